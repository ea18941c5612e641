// The moving-content study's summary (eval/study.cpp): Student's t quantiles, paired intervals against
// hand-computed ones, rows grouped into cells and paired by seed, the target's reach, the goals'
// verdicts, and the rows it refuses.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "eval/study.h"

namespace wrsfov::eval {
namespace {

namespace fs = std::filesystem;

TEST(Study, StudentQuantilesFromTheTable) {
    EXPECT_NEAR(tQuantile975(1), 12.706, 1e-3);
    EXPECT_NEAR(tQuantile975(2), 4.303, 1e-3);
    EXPECT_NEAR(tQuantile975(10), 2.228, 1e-3);
    EXPECT_NEAR(tQuantile975(30), 2.042, 1e-3);
    EXPECT_NEAR(tQuantile975(200), 1.960, 1e-3);
    EXPECT_TRUE(std::isnan(tQuantile975(0)));
}

TEST(Study, PairedIntervalAsComputedByHand) {
    // d = 0.1, 0.2, 0.3: mean 0.2, s = 0.1, half-width 4.303 * 0.1 / sqrt(3) = 0.24843.
    const PairedInterval p = pairedInterval({0.1, 0.2, 0.3});
    EXPECT_EQ(p.n, 3);
    EXPECT_NEAR(p.mean, 0.2, 1e-12);
    EXPECT_NEAR(p.lo, 0.2 - 0.248434, 1e-5);
    EXPECT_NEAR(p.hi, 0.2 + 0.248434, 1e-5);
    EXPECT_STREQ(p.verdict(), "tie");
    EXPECT_STREQ(pairedInterval({0.10, 0.11, 0.12}).verdict(), "beats");
    EXPECT_STREQ(pairedInterval({-0.10, -0.11, -0.12}).verdict(), "loses");
    EXPECT_STREQ(pairedInterval({0.5}).verdict(), "n/a");  // one pair: no interval
    EXPECT_TRUE(std::isnan(pairedInterval({0.5}).lo));
    EXPECT_EQ(pairedInterval({}).n, 0);
}

// One seed's rows of a cell: full resolution, the target, and two jittered configurations (0.3 at 9.5 %
// and 0.2 at 5 % of the pixels) with fov, taau and wrs, offset by the seed so the seeds differ.
std::vector<SavingRow> cellRows(SceneKind scene, const std::string& path, const std::string& split, uint32_t seed,
                                double wrsGain) {
    std::vector<SavingRow> rows;
    auto row = [&](SavingInput in, Method m, float wide, float inset, uint32_t jitter, double pixels, double jod,
                   double inst) {
        SavingRow r;
        r.scene = scene;
        r.input = in;
        r.method = m;
        r.wideScale = wide;
        r.insetDeg = inset;
        r.jitterPhases = jitter;
        r.pixelsRendered = pixels;
        r.jod = jod;
        r.temporalInstability = inst;
        r.headPath = path;
        r.headDegPerS = 60;
        r.seed = seed;
        r.split = split;
        rows.push_back(r);
    };
    const double s = 0.01 * seed;
    row(SavingInput::Full, Method::Fov, 0, 0, 0, 1e6, 10, 0.001);
    row(SavingInput::Quad, Method::Fov, 0.4f, 30, 0, 211000, 8.0 + s, 0.010);
    row(SavingInput::Quad, Method::Fov, 0.3f, 10, 8, 95000, 7.4 + s, 0.015);
    row(SavingInput::Quad, Method::Taau, 0.3f, 10, 8, 95000, 7.9 + s, 0.010);
    row(SavingInput::Quad, Method::Wrs, 0.3f, 10, 8, 95000, 7.9 + s + wrsGain + 0.002 * seed, 0.0101);
    row(SavingInput::Quad, Method::Fov, 0.2f, 10, 8, 50000, 7.0 + s, 0.016);
    row(SavingInput::Quad, Method::Taau, 0.2f, 10, 8, 50000, 7.7 + s, 0.012);
    row(SavingInput::Quad, Method::Wrs, 0.2f, 10, 8, 50000, 7.7 + s + wrsGain + 0.002 * seed, 0.0150);
    return rows;
}

TEST(Study, GroupsCellsPairsSeedsAndFindsTheReach) {
    std::vector<SavingRow> rows;
    for (uint32_t seed : {1u, 2u, 3u}) {
        for (const SavingRow& r : cellRows(SceneKind::Dynamic, "yaw60", "test", seed, 0.2)) rows.push_back(r);
        for (const SavingRow& r : cellRows(SceneKind::Atrium, "lateral", "train", seed, -0.1)) rows.push_back(r);
    }
    auto study = summarizeStudy(rows);
    ASSERT_TRUE(study) << study.error().message;
    ASSERT_EQ(study->cells.size(), 2u);
    const StudyCell& test = study->cells[0];
    EXPECT_EQ(test.scene, SceneKind::Dynamic);
    EXPECT_EQ(test.split, "test");
    EXPECT_EQ(test.seeds, (std::vector<uint32_t>{1, 2, 3}));
    EXPECT_NEAR(test.targetJod, 8.02, 1e-9);  // 8 + 0.01 * mean seed
    // wrs: 7.9 + 0.02 + 0.2 + 0.004 = 8.124 at 9.5 %, 7.924 at 5 %: it reaches 8.02 between them, linearly
    // at 5 % + 4.5 % * (8.02 - 7.924) / 0.2.
    EXPECT_EQ(test.wrsReach.bound, FoveaWorth::Bound::Exact);
    EXPECT_NEAR(test.wrsReach.pixels, 0.05 + 0.045 * (8.02 - 7.924) / 0.2, 1e-9);
    EXPECT_EQ(test.taauReach.bound, FoveaWorth::Bound::MoreThan);  // 7.92 at best
    // wrs against taau, fov and (absent) taau-simple: two comparisons per configuration and cell.
    int n = 0;
    for (const StudyComparison& c : study->comparisons) {
        if (c.cell != 0 || c.b != Method::Taau || c.wideScale != 0.3f) continue;
        ++n;
        EXPECT_EQ(c.jod.n, 3);
        EXPECT_NEAR(c.jod.mean, 0.204, 1e-9);  // 0.2 + 0.002 * mean seed
        EXPECT_STREQ(c.jod.verdict(), "beats");
        EXPECT_NEAR(c.pixelShare, 0.095, 1e-12);
        EXPECT_NEAR(c.instabilityExcess(), 0.01, 1e-9);
    }
    EXPECT_EQ(n, 1);
    EXPECT_EQ(study->comparisons.size(), 8u);
}

TEST(Study, ReportJudgesTheGoalsOnTheTestCellsOnly) {
    std::vector<SavingRow> rows;
    for (uint32_t seed : {1u, 2u, 3u}) {
        for (const SavingRow& r : cellRows(SceneKind::Dynamic, "yaw60", "test", seed, 0.2)) rows.push_back(r);
        // A training cell where wrs loses: it must not count against the goals.
        for (const SavingRow& r : cellRows(SceneKind::Atrium, "lateral", "train", seed, -0.3)) rows.push_back(r);
    }
    auto study = summarizeStudy(rows);
    ASSERT_TRUE(study);
    const fs::path dir = fs::temp_directory_path() / "wrsfov_study_report";
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::string summary;
    ASSERT_TRUE(writeStudyReport(*study, dir.string(), &summary));
    // Reach 7.2 % (within 10 %, not within 6.7 %); beats taau at both configurations; instability +1 % at
    // 0.3 but +25 % at 0.2.
    EXPECT_NE(summary.find("with at most 10 % of full resolution's pixels: **met**, 1 of 1 cells"), std::string::npos)
        << summary;
    EXPECT_NE(summary.find("at most 6.7 %: **not met**, the median 7.2 %"), std::string::npos) << summary;
    EXPECT_NE(summary.find("at least 80 % of the test cells and configurations: **met**, 2 of 2"), std::string::npos)
        << summary;
    EXPECT_NE(summary.find("never below `fov` on the same views: **met**"), std::string::npos) << summary;
    EXPECT_NE(summary.find("above `taau`'s: **not met**, 1 of 2 within it, the worst +25.0 %"), std::string::npos)
        << summary;
    for (const char* f : {"study.md", "study.csv", "study.png"}) EXPECT_TRUE(fs::exists(dir / f)) << f;
    std::ifstream csv(dir / "study.csv");
    std::string header, line;
    std::getline(csv, header);
    int lines = 0, losses = 0;
    while (std::getline(csv, line)) {
        ++lines;
        losses += line.rfind("train,atrium,lateral", 0) == 0 && line.find(",taau,3,") != std::string::npos &&
                  line.find(",loses,") != std::string::npos;
    }
    EXPECT_EQ(lines, 8);
    EXPECT_EQ(losses, 2);  // the training cell's losses are in the table, under train
    fs::remove_all(dir);
}

TEST(Study, RefusesDuplicateRowsDisagreeingSeedsAndNoWrs) {
    std::vector<SavingRow> rows = cellRows(SceneKind::Dynamic, "yaw60", "test", 1, 0.2);
    std::vector<SavingRow> twice = rows;
    twice.push_back(rows[4]);
    auto a = summarizeStudy(twice);
    ASSERT_FALSE(a);
    EXPECT_NE(a.error().message.find("two rows of wrs at 0.30 / 10° for dynamic yaw60 seed 1"), std::string::npos)
        << a.error().message;
    std::vector<SavingRow> other = cellRows(SceneKind::Dynamic, "yaw60", "test", 2, 0.2);
    for (SavingRow& r : other) r.pixelsRendered *= 1.1;
    std::vector<SavingRow> both = rows;
    both.insert(both.end(), other.begin(), other.end());
    auto b = summarizeStudy(both);
    ASSERT_FALSE(b);
    EXPECT_NE(b.error().message.find("seeds differ in the pixels"), std::string::npos) << b.error().message;
    std::vector<SavingRow> noWrs;
    for (const SavingRow& r : rows)
        if (r.method != Method::Wrs) noWrs.push_back(r);
    auto c = summarizeStudy(noWrs);
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("no jittered quad views composed with wrs"), std::string::npos);
}

}  // namespace
}  // namespace wrsfov::eval
