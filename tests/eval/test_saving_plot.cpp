// JOD against pixels across saving studies (eval/saving_plot.cpp): saving.csv read back by its
// columns, every malformed file refused with its line and field, the curves' best points, the fewest
// pixels reaching a target, and the report of two studies of one cell.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "eval/saving.h"

namespace wrsfov::eval {
namespace {

namespace fs = std::filesystem;

const char* kHeader =
    "scene,input,method,inset_deg,pixels_rendered,render_ms,compose_ms,jod,near_gaze_psnr,wide_density,jitter,"
    "temporal_instability\n";

// A scratch directory of its own per test, removed after.
class SavingPlot : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("wrsfov_saving_plot_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const std::string p = (dir_ / name).string();
        std::ofstream(p) << text;
        return p;
    }
    static std::string read(const fs::path& p) {
        std::ifstream in(p);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    }
    fs::path dir_;
};

// The headset cell's shape: a target study (unjittered fov at 0.4/30°) and a jittered one (0.3 and 0.2 at 10°).
const std::string kTarget = std::string(kHeader) +
                            "atrium,full,fov,0,1000000,80,10,10,inf,0,0,1e-05\n"
                            "atrium,quad,fov,30,210000,20,5,8.0,30.5,0.4,0,0.009\n";
const std::string kJittered = std::string(kHeader) +
                              "atrium,full,fov,0,1000000,80,10,10,inf,0,0,1e-05\n"
                              "atrium,quad,fov,10,95000,11,5,7.4,29,0.3,8,0.015\n"
                              "atrium,quad,taau,10,95000,11,6,7.9,29.5,0.3,8,0.013\n"
                              "atrium,quad,wrs,10,95000,11,7,8.4,30,0.3,8,0.008\n"
                              "atrium,quad,fov,10,50000,8,5,7.0,28,0.2,8,0.016\n"
                              "atrium,quad,taau,10,50000,8,6,7.7,29,0.2,8,0.012\n"
                              "atrium,quad,wrs,10,50000,8,7,7.9,29.2,0.2,8,0.011\n";

TEST_F(SavingPlot, ReadsASavingCsvByItsColumns) {
    auto rows = readSavingCsv(write("a.csv", kJittered));
    ASSERT_TRUE(rows) << rows.error().message;
    ASSERT_EQ(rows->size(), 7u);
    const SavingRow& full = (*rows)[0];
    EXPECT_EQ(full.input, SavingInput::Full);
    EXPECT_TRUE(std::isinf(full.nearGazePsnr));
    const SavingRow& wrs = (*rows)[3];
    EXPECT_EQ(wrs.scene, SceneKind::Atrium);
    EXPECT_EQ(wrs.input, SavingInput::Quad);
    EXPECT_EQ(wrs.method, Method::Wrs);
    EXPECT_EQ(wrs.insetDeg, 10.0f);
    EXPECT_EQ(wrs.pixelsRendered, 95000.0);
    EXPECT_EQ(wrs.renderMs, 11.0);
    EXPECT_EQ(wrs.composeMs, 7.0);
    EXPECT_EQ(wrs.jod, 8.4);
    EXPECT_EQ(wrs.wideScale, 0.3f);
    EXPECT_EQ(wrs.jitterPhases, 8u);
    EXPECT_EQ(wrs.temporalInstability, 0.008);
    EXPECT_EQ(curveName(wrs), "wrs (jittered)");
    EXPECT_EQ(curveName((*rows)[1]), "fov (jittered)");
    // Columns in another order, and a study from before the jittered views (no wide_density, jitter,
    // temporal_instability): read by name, the missing ones as 0, 0 and NaN; a NaN score stays NaN.
    auto old = readSavingCsv(write("old.csv",
                                   "method,scene,input,inset_deg,pixels_rendered,render_ms,compose_ms,jod,near_gaze_psnr\n"
                                   "wrs,text,quad,20,5000,nan,3,nan,31\n"));
    ASSERT_TRUE(old) << old.error().message;
    ASSERT_EQ(old->size(), 1u);
    EXPECT_EQ((*old)[0].scene, SceneKind::Text);
    EXPECT_EQ((*old)[0].method, Method::Wrs);
    EXPECT_TRUE(std::isnan((*old)[0].jod));
    EXPECT_TRUE(std::isnan((*old)[0].temporalInstability));
    EXPECT_EQ((*old)[0].jitterPhases, 0u);
    EXPECT_EQ(curveName((*old)[0]), "wrs");
}

TEST_F(SavingPlot, RefusesAMalformedFileNamingLineAndField) {
    struct Case {
        const char* what;
        std::string text;
        const char* expect;
    };
    const std::string row = "atrium,quad,wrs,10,95000,11,7,8.4,30,0.3,8,0.008\n";
    const Case cases[] = {
        {"missing", "", "cannot read"},
        {"empty", "", "is empty"},
        {"no jod column", "scene,input,method,inset_deg,pixels_rendered,render_ms,compose_ms,near_gaze_psnr\n",
         "no column \"jod\""},
        {"short line", std::string(kHeader) + "atrium,quad,wrs,10\n", ":2: 4 fields where the header has 12"},
        {"text for a number", std::string(kHeader) + "atrium,quad,wrs,10,95000,11,7,eight,30,0.3,8,0.008\n",
         ":2: column jod is not a number: \"eight\""},
        {"empty number", std::string(kHeader) + row + "atrium,quad,wrs,10,95000,,7,8,30,0.3,8,0.008\n",
         ":3: column render_ms is not a number"},
        {"unknown method", std::string(kHeader) + "atrium,quad,dlss,10,95000,11,7,8.4,30,0.3,8,0.008\n",
         "unknown method \"dlss\""},
        {"unknown scene", std::string(kHeader) + "moon,quad,wrs,10,95000,11,7,8.4,30,0.3,8,0.008\n", "unknown scene"},
        {"unknown input", std::string(kHeader) + "atrium,vrs,wrs,10,95000,11,7,8.4,30,0.3,8,0.008\n",
         "unknown input \"vrs\""},
        {"zero pixels", std::string(kHeader) + "atrium,quad,wrs,10,0,11,7,8.4,30,0.3,8,0.008\n",
         "pixels_rendered must be a positive count"},
        {"NaN pixels", std::string(kHeader) + "atrium,quad,wrs,10,nan,11,7,8.4,30,0.3,8,0.008\n",
         "pixels_rendered must be a positive count"},
        {"density above 1", std::string(kHeader) + "atrium,quad,wrs,10,95000,11,7,8.4,30,1.5,8,0.008\n", "out of range"},
        {"fractional jitter", std::string(kHeader) + "atrium,quad,wrs,10,95000,11,7,8.4,30,0.3,2.5,0.008\n",
         "out of range"},
    };
    for (const Case& c : cases) {
        const std::string path =
            std::string(c.what) == "missing" ? (dir_ / "absent.csv").string() : write("bad.csv", c.text);
        auto r = readSavingCsv(path);
        ASSERT_FALSE(r) << c.what;
        EXPECT_NE(r.error().message.find(c.expect), std::string::npos) << c.what << ": " << r.error().message;
        EXPECT_NE(r.error().message.find(path), std::string::npos) << c.what << ": the message names the file";
    }
}

// The cell's columns the moving-content study reads (head_path, head_deg_per_s, seed, split): read where
// present, refused where malformed.
TEST_F(SavingPlot, ReadsTheCellColumnsAndRefusesMalformedOnes) {
    const std::string header = std::string(kHeader).substr(0, std::string(kHeader).size() - 1) +
                               ",head_path,head_deg_per_s,seed,split\n";
    const std::string row = "dynamic,quad,wrs,10,95000,11,7,8.4,30,0.3,8,0.008,";
    auto rows = readSavingCsv(write("cell.csv", header + row + "look-around,183.9,3,train\n"));
    ASSERT_TRUE(rows) << rows.error().message;
    ASSERT_EQ(rows->size(), 1u);
    EXPECT_EQ((*rows)[0].headPath, "look-around");
    EXPECT_DOUBLE_EQ((*rows)[0].headDegPerS, 183.9);
    EXPECT_EQ((*rows)[0].seed, 3u);
    EXPECT_EQ((*rows)[0].split, "train");
    for (auto [tail, expect] : {std::pair{"yaw60,60,1,dev\n", "split must be train or test, not \"dev\""},
                                std::pair{"yaw60,60,0,test\n", "seed must be a whole number from 1"},
                                std::pair{"yaw60,60,1.5,test\n", "seed must be a whole number from 1"},
                                std::pair{"yaw60,fast,1,test\n", "column head_deg_per_s is not a number"}}) {
        auto bad = readSavingCsv(write("bad.csv", header + row + tail));
        ASSERT_FALSE(bad) << tail;
        EXPECT_NE(bad.error().message.find(expect), std::string::npos) << bad.error().message;
        EXPECT_NE(bad.error().message.find("bad.csv:2"), std::string::npos) << bad.error().message;
    }
}

TEST_F(SavingPlot, ParsesATargetAndRefusesAMalformedOne) {
    auto t = parseSavingTarget("fov,0.4,30");
    ASSERT_TRUE(t) << t.error().message;
    EXPECT_EQ(t->method, Method::Fov);
    EXPECT_EQ(t->wideScale, 0.4f);
    EXPECT_EQ(t->insetDeg, 30.0f);
    EXPECT_EQ(t->jitterPhases, 0u);
    auto j = parseSavingTarget("wrs,0.3,10,8");
    ASSERT_TRUE(j);
    EXPECT_EQ(j->jitterPhases, 8u);
    for (const char* bad : {"fov", "fov,0.4", "fov,0.4,30,8,1", "dlss,0.4,30", "fov,0,30", "fov,1.5,30", "fov,nan,30",
                            "fov,0.4,-5", "fov,0.4,inf", "fov,0.4,30,2.5", "fov,0.4,30,-1"})
        EXPECT_FALSE(parseSavingTarget(bad)) << bad;
}

TEST_F(SavingPlot, TheFrontKeepsWhatNoCheaperPointBeatsAndReachIsInterpolated) {
    auto row = [](double px, double ms, double jod) {
        SavingRow r;
        r.input = SavingInput::Quad;
        r.pixelsRendered = px;
        r.renderMs = ms;
        r.jod = jod;
        return r;
    };
    // 0.25/30° (133 k) scores below 0.3/10° (112 k): a user would not pick it; NaN JOD is left out.
    const std::vector<SavingRow> curve{row(165658, 16, 8.78), row(53704, 8, 7.98), row(133586, 14, 8.30),
                                       row(112072, 12, 8.45), row(80000, 10, 8.32), row(90000, 11, std::nan(""))};
    const auto front = savingFront(curve);
    ASSERT_EQ(front.size(), 4u);
    EXPECT_EQ(front[0].pixels, 53704);
    EXPECT_EQ(front[1].pixels, 80000);
    EXPECT_EQ(front[2].pixels, 112072);
    EXPECT_EQ(front[3].pixels, 165658);
    // 8.0 between 53704 (7.98) and 80000 (8.32): 2/34 of the way, render time likewise.
    const SavingReach r = savingReach(front, 8.0);
    EXPECT_EQ(r.bound, FoveaWorth::Bound::Exact);
    EXPECT_NEAR(r.pixels, 53704 + (80000 - 53704) * 0.02 / 0.34, 1e-6);
    EXPECT_NEAR(r.renderMs, 8 + 2 * 0.02 / 0.34, 1e-9);
    // On a point exactly: its own render time.
    const SavingReach on = savingReach(front, 8.45);
    EXPECT_EQ(on.bound, FoveaWorth::Bound::Exact);
    EXPECT_EQ(on.pixels, 112072);
    EXPECT_EQ(on.renderMs, 12);
    EXPECT_EQ(savingReach(front, 7.0).bound, FoveaWorth::Bound::AtMost);
    EXPECT_EQ(savingReach(front, 7.0).pixels, 53704);
    EXPECT_EQ(savingReach(front, 9.0).bound, FoveaWorth::Bound::MoreThan);
    EXPECT_EQ(savingReach({}, 8.0).bound, FoveaWorth::Bound::Unknown);
    EXPECT_EQ(savingReach(front, std::nan("")).bound, FoveaWorth::Bound::Unknown);
}

TEST_F(SavingPlot, TwoStudiesOfOneCellMakeOnePlot) {
    std::vector<SavingRow> rows;
    for (const std::string& text : {kTarget, kJittered}) {
        auto r = readSavingCsv(write("s.csv", text));
        ASSERT_TRUE(r) << r.error().message;
        rows.insert(rows.end(), r->begin(), r->end());
    }
    std::string summary;
    ASSERT_TRUE(writeJodAgainstPixels(rows, SavingTarget{Method::Fov, 0.4f, 30.0f, 0}, dir_.string(), &summary));
    ASSERT_TRUE(fs::exists(dir_ / "jod_vs_pixels.png"));
    EXPECT_GT(fs::file_size(dir_ / "jod_vs_pixels.png"), 1000u);
    const std::string md = read(dir_ / "jod_vs_pixels.md");
    // The target's JOD 8.0 at 21 %; wrs reaches it between 0.2/10° (5 %, 7.9) and 0.3/10° (9.5 %, 8.4):
    // 5 + 4.5 x 0.1/0.5 = 5.9 %; taau at 9.5 % only with 7.9 < 8.0: not reached; fov (unjittered), its own
    // target, at 21 %.
    EXPECT_NE(summary.find("JOD **8.00** with 21.0 %"), std::string::npos) << summary;
    EXPECT_NE(summary.find("| wrs (jittered) | 5.9 % | 8.60 | 0.30 / 10°: 9.5 %, JOD 8.40 |"), std::string::npos) << summary;
    EXPECT_NE(summary.find("| taau (jittered) | not reached (9.5 % measured) | n/a | none |"), std::string::npos) << summary;
    EXPECT_NE(summary.find("| fov | 21.0 % or less |"), std::string::npos) << summary;
    // At equal pixels: the jittered views' rows side by side, the target's own configuration left out.
    EXPECT_NE(summary.find("| 0.30 / 10°, jittered | 9.5 % | 7.40 / 0.0150 | 7.90 / 0.0130 | 8.40 / 0.0080 |"),
              std::string::npos)
        << summary;
    EXPECT_EQ(summary.find("| 0.40 / 30° |"), std::string::npos) << summary;
    EXPECT_NE(md.find(summary), std::string::npos);
    EXPECT_NE(md.find("| wrs (jittered) | 0.20 | 10° | 8 | 5.0 % |"), std::string::npos) << md;
    // Without a target: the plot and the rows, no reach table.
    std::string none;
    ASSERT_TRUE(writeJodAgainstPixels(rows, std::nullopt, dir_.string(), &none));
    EXPECT_EQ(none.find("The target"), std::string::npos);
}

TEST_F(SavingPlot, RefusesStudiesOfDifferentCellsAndATargetNoRowMatches) {
    std::vector<SavingRow> rows;
    for (const std::string& text : {kTarget, kJittered}) {
        auto r = readSavingCsv(write("s.csv", text));
        ASSERT_TRUE(r) << r.error().message;
        rows.insert(rows.end(), r->begin(), r->end());
    }
    // Another size: its full-resolution row renders other pixels.
    auto other = readSavingCsv(write("o.csv", std::string(kHeader) + "atrium,full,fov,0,2000000,80,10,10,inf,0,0,1e-05\n"));
    ASSERT_TRUE(other);
    std::vector<SavingRow> mixed = rows;
    mixed.insert(mixed.end(), other->begin(), other->end());
    auto s = writeJodAgainstPixels(mixed, std::nullopt, dir_.string());
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("different cells"), std::string::npos) << s.message();
    // No full-resolution row.
    std::vector<SavingRow> noFull(rows.begin() + 1, rows.begin() + 2);
    EXPECT_FALSE(writeJodAgainstPixels(noFull, std::nullopt, dir_.string()));
    // A target no row matches: jittered fov at 0.4/30° was not run.
    auto t = writeJodAgainstPixels(rows, SavingTarget{Method::Fov, 0.4f, 30.0f, 8}, dir_.string());
    ASSERT_FALSE(t);
    EXPECT_NE(t.message().find("for the target"), std::string::npos) << t.message();
    // A study without JOD (--no-jod) has no target to reach.
    std::vector<SavingRow> noJod = rows;
    for (SavingRow& r : noJod) r.jod = std::nan("");
    auto n = writeJodAgainstPixels(noJod, SavingTarget{Method::Fov, 0.4f, 30.0f, 0}, dir_.string());
    ASSERT_FALSE(n);
    EXPECT_NE(n.message().find("no JOD"), std::string::npos) << n.message();
    EXPECT_FALSE(fs::exists(dir_ / "jod_vs_pixels.md"));
}

}  // namespace
}  // namespace wrsfov::eval
