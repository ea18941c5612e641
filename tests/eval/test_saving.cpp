// The rendering-saved study (eval/saving.h) on a small atrium: what each row counts (pixels of the wide
// views and insets, shaded samples under the rate pattern), that the full-resolution row is the
// reference, that the oracle bounds every method of its input and inset, and the report's files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "../core/gpu_rig.h"
#include "eval/metrics.h"
#include "eval/saving.h"

namespace wrsfov::test {
namespace {

class Saving : public GpuTest {};

TEST_F(Saving, RowsCountWhatWasRenderedAndTheOracleBoundsEachInput) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 128;
    o.height = 128;
    o.hmdFovDeg = 40.0f;  // 3.2 px/deg: small, but the inset and wide views differ as at any density
    o.frames = 16;
    o.warmup = 4;
    o.jodFrames = 6;
    o.path = scenes::CameraPath::Lateral;
    so.insetDegs = {10.0f, 20.0f};
    so.rateDegs = {10.0f};
    so.methods = {Method::Fov, Method::Wrs, Method::Oracle, Method::OracleQ};
    auto rows = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 1u + 2u * 4u + 1u * 2u);

    const eval::SavingRow& full = rows->front();
    EXPECT_EQ(full.input, eval::SavingInput::Full);
    EXPECT_EQ(full.pixelsRendered, 2.0 * 128 * 128);
    EXPECT_GT(full.jod, 9.9) << "the full-resolution row is the reference itself";
    EXPECT_TRUE(std::isinf(full.nearGazePsnr));
    EXPECT_GT(full.renderMs, 0.0);
    // The reference against itself: only the changes within the metric's threshold (one 8-bit step).
    EXPECT_LT(full.temporalInstability, 1.0 / 255.0);
    EXPECT_EQ(full.wideScale, 0.0f);
    // Quad views: 51x51 wide views (0.4 of 128) and an inset of 2 tan(deg / 2) tangent units at the
    // display's 128 / (2 tan 20°) pixels per tangent unit, both eyes.
    const double density = 128.0 / (2.0 * std::tan(20.0 * M_PI / 180.0));
    for (const eval::SavingRow& r : *rows) {
        if (r.input == eval::SavingInput::Quad) {
            const double inset = std::round(2.0 * std::tan(0.5 * r.insetDeg * M_PI / 180.0) * density);
            EXPECT_EQ(r.pixelsRendered, 2.0 * (51.0 * 51.0 + inset * inset)) << r.insetDeg;
            EXPECT_GT(r.renderMs, 0.0);
            EXPECT_LT(r.pixelsRendered, full.pixelsRendered);
            EXPECT_GT(r.temporalInstability, 0.0);
            EXPECT_EQ(r.wideScale, 0.4f);
            EXPECT_EQ(r.jitterPhases, 0u);
        }
        // The retain pass's share of the tiles: methods with it only, at most every tile.
        if (r.method == Method::Fov) {
            EXPECT_TRUE(std::isnan(r.retainShare)) << r.retainShare;
        } else {
            EXPECT_GT(r.retainShare, 0.0) << toString(r.method) << " " << r.insetDeg;
            EXPECT_LE(r.retainShare, 1.0) << toString(r.method) << " " << r.insetDeg;
        }
        if (r.input == eval::SavingInput::Rate) {
            // Between a 4x4 rate everywhere and full rate: the 1x1 region and its 2x2 ring around the gaze.
            EXPECT_GT(r.pixelsRendered, full.pixelsRendered / 16.0);
            EXPECT_LT(r.pixelsRendered, full.pixelsRendered / 2.0);
            EXPECT_TRUE(std::isnan(r.renderMs)) << "no variable-rate shading on this device: no render time";
        }
        EXPECT_TRUE(std::isfinite(r.jod) && r.jod <= full.jod + 1e-9);
        EXPECT_GT(r.composeMs, 0.0);
        // The oracle keeps whichever sample is nearer the reference: no method of its input and inset has
        // a lower MSE.
        for (const eval::SavingRow& x : *rows) {
            if (x.input == r.input && x.insetDeg == r.insetDeg && x.method == Method::Oracle) {
                EXPECT_LE(x.mse, r.mse * (1.0 + 1e-9)) << toString(r.method) << " at " << r.insetDeg;
            }
        }
    }
    // Larger insets render more pixels.
    EXPECT_LT((*rows)[1].pixelsRendered, (*rows)[5].pixelsRendered);
    // η_q is against the retention oracle of the same input and inset (none for the full-resolution row and
    // the rate rows, which have no oracle-q), n/a where it removes under 1 % of fov's error.
    for (const eval::SavingRow& r : *rows) {
        const eval::SavingRow *fov = nullptr, *oq = nullptr;
        for (const eval::SavingRow& x : *rows) {
            if (x.input != r.input || x.insetDeg != r.insetDeg) continue;
            if (x.method == Method::Fov) fov = &x;
            if (x.method == Method::OracleQ) oq = &x;
        }
        SCOPED_TRACE(std::string(toString(r.input)) + " " + std::string(toString(r.method)));
        if (!fov || !oq || !(fov->mse - oq->mse > 0.01 * fov->mse)) {
            EXPECT_TRUE(std::isnan(r.etaQ));
        } else {
            EXPECT_DOUBLE_EQ(r.etaQ, (fov->mse - r.mse) / (fov->mse - oq->mse));
        }
        if (r.input == eval::SavingInput::Quad) {
            EXPECT_NE(oq, nullptr);
        }
    }

    const std::string dir = std::filesystem::temp_directory_path() / "wrsfov_saving_test";
    std::string headline;
    Status s = eval::writeSavingReport(*rows, so, dir, context().deviceName(), &headline);
    ASSERT_TRUE(s.ok()) << s.message();
    std::ifstream csv(dir + "/saving.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header, "scene,input,method,inset_deg,pixels_rendered,render_ms,compose_ms,jod,near_gaze_psnr,"
                      "wide_density,jitter,temporal_instability,head_path,head_deg_per_s,seed,split");
    int n = 0;
    while (std::getline(csv, line)) {
        n++;
        // The cell's columns: the atrium's lateral path (no rotation), the options' seed, the default split.
        EXPECT_TRUE(line.ends_with(",lateral,0," + std::to_string(so.bench.seed) + ",test")) << line;
    }
    EXPECT_EQ(n, int(rows->size()));
    EXPECT_GT(std::filesystem::file_size(dir + "/saving.png"), 5000u);
    EXPECT_NE(headline.find("matches composition alone at a 20° inset"), std::string::npos) << headline;
}

// Jittered wide views (SavingOptions::jitterPhases): the same pixels rendered, each frame's wide views
// shifted by a new Halton phase with their textures sampled at the display's density and placed where
// they were taken. Composed without temporal reuse (fov), the sharper point samples flicker: the
// temporal instability rises against the same views without jitter, which is what temporal upsampling and
// WRS over the jittered history must take back (docs/metrics.md, "Jittered wide views").
TEST_F(Saving, JitteredWideViewsRenderTheSamePixelsAndFlickerWithoutReuse) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 128;
    o.height = 128;
    o.hmdFovDeg = 40.0f;
    o.frames = 16;
    o.warmup = 4;
    o.jodFrames = 8;
    o.path = scenes::CameraPath::Static;
    so.insetDegs = {10.0f};
    so.rate = false;
    so.methods = {Method::Fov};
    auto still = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_TRUE(still.ok()) << still.error().message;
    so.jitterPhases = 8;
    auto jittered = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_TRUE(jittered.ok()) << jittered.error().message;
    ASSERT_EQ(still->size(), 2u);
    ASSERT_EQ(jittered->size(), 2u);
    const eval::SavingRow &a = (*still)[1], &b = (*jittered)[1];
    EXPECT_EQ(b.jitterPhases, 8u);
    EXPECT_EQ(a.pixelsRendered, b.pixelsRendered);
    std::printf("[saving] fov on still wide views: instability %.5f, JOD %.2f; jittered: %.5f, JOD %.2f\n",
                a.temporalInstability, a.jod, b.temporalInstability, b.jod);
    // A still camera: the unjittered views do not change at all, the jittered ones every frame.
    EXPECT_LT(a.temporalInstability, 1e-4);
    EXPECT_GT(b.temporalInstability, 10.0 * std::max(a.temporalInstability, 1e-4));
}

// The photo (natural texture, a head panning) as quad views, without JOD: pixels and times only, no
// headline or plot; wrs keeps more of what the inset rendered than composition alone.
TEST_F(Saving, PhotoQuadViewsWithoutJod) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 128;
    o.height = 96;
    o.monitor = true;
    o.frames = 12;
    o.warmup = 3;
    o.jodFrames = 4;
    o.photoMotion = scenes::PhotoMotion::Pan;
    so.insetDegs = {20.0f};
    so.rate = false;
    so.jod = false;
    so.methods = {Method::Fov, Method::Wrs};
    auto rows = eval::runSaving(context(), eval::SceneKind::Photo, so);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 3u);
    const eval::SavingRow &full = (*rows)[0], &fov = (*rows)[1], &wrs = (*rows)[2];
    EXPECT_EQ(full.pixelsRendered, 128.0 * 96.0) << "monitor mode: one view";
    for (const eval::SavingRow& r : *rows) {
        EXPECT_TRUE(std::isnan(r.jod));
        EXPECT_TRUE(std::isnan(r.renderMs)) << "rendered on the CPU";
        EXPECT_GT(r.composeMs, 0.0);
    }
    EXPECT_LT(fov.pixelsRendered, 0.5 * full.pixelsRendered);
    EXPECT_TRUE(std::isfinite(fov.nearGazePsnr) && std::isfinite(wrs.nearGazePsnr));
    EXPECT_LE(wrs.mse, fov.mse * 1.02) << "retention must not lose to composition alone";
    const std::string dir = std::filesystem::temp_directory_path() / "wrsfov_saving_photo_test";
    std::filesystem::remove_all(dir);
    std::string headline;
    ASSERT_TRUE(eval::writeSavingReport(*rows, so, dir, context().deviceName(), &headline).ok());
    EXPECT_NE(headline.find("no JOD"), std::string::npos) << headline;
    EXPECT_TRUE(std::filesystem::exists(dir + "/saving.csv"));
    // Every composition's row says the share of tiles that ran the retain pass (– for fov).
    std::ifstream mdFile(dir + "/saving.md");
    const std::string md((std::istreambuf_iterator<char>(mdFile)), std::istreambuf_iterator<char>());
    EXPECT_NE(md.find("| retain tiles |"), std::string::npos);
    EXPECT_NE(md.find(eval::savingNumber("%.1f %%", 100.0 * wrs.retainShare) + " |"), std::string::npos) << md;
    EXPECT_FALSE(std::filesystem::exists(dir + "/saving.png"));
}

// A cell of the moving-content study: `dynamic` (moving boxes) with the head turning at 60 °/s, jittered
// quad views. Its rows name the cell (path, speed, seed, split), and another seed is another gaze path and
// jitter start: the same cell, different frames.
TEST_F(Saving, DynamicSceneUnderFastYawNamesItsCell) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 96;
    o.height = 96;
    o.hmdFovDeg = 40.0f;
    o.frames = 10;
    o.warmup = 3;
    o.jodFrames = 4;
    o.path = scenes::CameraPath::Yaw60;
    so.insetDegs = {15.0f};
    so.rate = false;
    so.jod = false;
    so.jitterPhases = 4;
    so.methods = {Method::Fov, Method::Wrs};
    so.split = "train";
    std::array<std::vector<eval::SavingRow>, 2> bySeed;
    for (uint32_t seed : {2u, 3u}) {
        o.seed = seed;
        auto rows = eval::runSaving(context(), eval::SceneKind::Dynamic, so);
        ASSERT_TRUE(rows.ok()) << rows.error().message;
        ASSERT_EQ(rows->size(), 3u);
        for (const eval::SavingRow& r : *rows) {
            EXPECT_EQ(r.scene, eval::SceneKind::Dynamic);
            EXPECT_EQ(r.headPath, "yaw60");
            EXPECT_EQ(r.headDegPerS, 60.0);
            EXPECT_EQ(r.seed, seed);
            EXPECT_EQ(r.split, "train");
            EXPECT_FALSE(std::isnan(r.nearGazePsnr));  // +inf for the full-resolution row, its own reference
        }
        bySeed[seed - 2] = std::move(*rows);
    }
    EXPECT_NE(bySeed[0][2].mse, bySeed[1][2].mse) << "seeds 2 and 3 gave wrs the same frames";
}

// The thin scene on the look-around path: the study names the cell, and the sweep's gaze is the path's:
// each valid eye's azimuth in the head within the local exploration's 6° (and its small saccades'
// overshoot) of scenes::lookAroundGaze, so the inset follows the big gaze shifts the head follows.
// A headset's 100° per eye at 96², 8 frames with the last 4 scored, a 10° inset over wide views jittered
// over 4 phases, fov, taau and wrs, no JOD and no rate rows: the smallest study run of a head path.
eval::SavingOptions smallJitteredHeadset(scenes::CameraPath path) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 96;
    o.height = 96;
    o.hmdFovDeg = 100.0f;
    o.frames = 8;
    o.warmup = 3;
    o.jodFrames = 4;
    o.path = path;
    so.insetDegs = {10.0f};
    so.rate = false;
    so.jod = false;
    so.jitterPhases = 4;
    so.methods = {Method::Fov, Method::Taau, Method::Wrs};
    return so;
}

// --write-outputs with --saving: every composition's scored frames as PNG, from which the row's temporal
// instability comes back, and the gaze of each scored frame; a directory that cannot be made is an error.
TEST_F(Saving, WriteOutputsWritesWhatTheInstabilityScored) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "wrsfov_saving_outputs";
    std::filesystem::remove_all(dir);
    eval::SavingOptions so = smallJitteredHeadset(scenes::CameraPath::Yaw60);
    so.bench.outputsDir = dir.string();
    auto rows = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 4u);
    const std::filesystem::path scene = dir / "atrium";
    const char* names[] = {"full_fov", "quad_fov_10", "quad_taau_10", "quad_wrs_10"};
    auto frame = [&](const std::string& run, const char* eye, int k) {
        char file[16];
        std::snprintf(file, sizeof file, "%06d.png", k);
        cv::Mat bgr = cv::imread((scene / run / eye / file).string(), cv::IMREAD_COLOR);
        EXPECT_FALSE(bgr.empty()) << run << "/" << eye << "/" << file;
        cv::Mat rgb, f;
        if (bgr.empty()) return f;
        cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
        f.create(rgb.rows, rgb.cols, CV_32FC3);  // code / 255 in float, as eval::toMat reads the output
        for (int y = 0; y < rgb.rows; ++y)
            for (int x = 0; x < rgb.cols; ++x)
                for (int c = 0; c < 3; ++c) f.at<cv::Vec3f>(y, x)[c] = float(rgb.at<cv::Vec3b>(y, x)[c]) / 255.0f;
        return f;
    };
    for (std::size_t r = 0; r < 4; ++r) {
        double ti = 0;
        for (const char* eye : {"L", "R"}) {
            eval::TemporalInstability m;
            for (int k = 0; k < 4; ++k) {
                const cv::Mat ref = frame("full_fov", eye, k), out = frame(names[r], eye, k);
                if (ref.empty() || out.empty()) return;
                m.addFrame(ref, out);
            }
            EXPECT_FALSE(std::filesystem::exists(scene / names[r] / eye / "000004.png")) << "the scored frames only";
            ti += m.mean() / 2.0;
        }
        EXPECT_NEAR(ti, (*rows)[r].temporalInstability, 1e-9) << names[r];
    }
    EXPECT_GT((*rows)[3].temporalInstability, 0.0) << "the jittered turn changes the output";
    std::ifstream gaze(scene / "gaze.csv");
    std::string line;
    int lines = 0;
    std::getline(gaze, line);
    EXPECT_EQ(line, "frame,left_x,left_y");
    while (std::getline(gaze, line)) {
        EXPECT_EQ(line.rfind(std::to_string(lines) + ",", 0), 0u) << line;
        ++lines;
    }
    EXPECT_EQ(lines, 4);
    // A path that cannot be a directory: a clear error, not a crash.
    std::filesystem::remove_all(dir);
    std::ofstream(dir.string()) << "a file";
    auto bad = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("cannot create"), std::string::npos) << bad.error().message;
    std::filesystem::remove_all(dir);
}

TEST_F(Saving, ThinSceneOnTheLookAroundPathFollowsItsGaze) {
    eval::SavingOptions so = smallJitteredHeadset(scenes::CameraPath::LookAround);
    eval::BenchOptions& o = so.bench;
    auto rows = eval::runSaving(context(), eval::SceneKind::Thin, so);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 4u);
    for (const eval::SavingRow& r : *rows) {
        EXPECT_EQ(r.scene, eval::SceneKind::Thin);
        EXPECT_EQ(r.headPath, "look-around");
        EXPECT_NEAR(r.headDegPerS, scenes::headDegPerS(scenes::CameraPath::LookAround), 1e-9);
        EXPECT_TRUE(std::isfinite(r.mse));
    }
    o.frames = 40;  // to 0.44 s: the first shift (to 30° at 0.2 s) and the head's turn after it
    double lo = 1e9, hi = -1e9;
    int valid = 0;
    Status s = eval::forEachSceneFrame(context(), eval::SceneKind::Thin, o,
                                       [&](const eval::SceneFrameInfo&, int, double t, std::array<EyeSubmission, 2>& eyes) {
                                           for (const EyeSubmission& e : eyes) {
                                               if (!e.gaze.valid) continue;
                                               ++valid;
                                               const double az = std::atan2(-e.gaze.dir.x, -e.gaze.dir.z) * 180.0 / 3.14159265358979;
                                               const double expect = scenes::lookAroundGaze(t).azimuthDeg;
                                               EXPECT_NEAR(az, expect, 9.0) << "t " << t;
                                               lo = std::min(lo, expect), hi = std::max(hi, expect);
                                           }
                                           return Status{};
                                       });
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_GT(valid, 60);  // of 80 eye-frames (two eyes, 40 frames), a blink allowed
    EXPECT_GT(hi - lo, 25.0);  // the eye led the 30° shift before the head caught up
}

// The retention outcomes (--outcomes): the CPU reference stepped beside `wrs` and the oracle on quad views
// counts every evaluated pixel of every scored frame once, agrees with the compositor's reservoirs, and
// finds the inset's samples (a history sharper than the floor) among them; the report lists them.
TEST_F(Saving, OutcomesCountEveryScoredPixelAndTheReferenceAgrees) {
    eval::SavingOptions so;
    eval::BenchOptions& o = so.bench;
    o.width = 96;
    o.height = 96;
    o.hmdFovDeg = 40.0f;
    o.frames = 10;
    o.warmup = 3;
    o.jodFrames = 4;
    o.path = scenes::CameraPath::Lateral;  // depth and motion in both sources
    so.insetDegs = {10.0f};
    so.rate = false;
    so.jod = false;
    so.outcomes = true;
    so.methods = {Method::Fov, Method::Wrs, Method::Oracle};
    auto rows = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_TRUE(rows.ok()) << rows.error().message;
    ASSERT_EQ(rows->size(), 4u);
    const uint64_t pixels = 4ull * 2 * 96 * 96;  // scored frames x eyes x pixels
    for (const eval::SavingRow& r : *rows) {
        SCOPED_TRACE(std::string(toString(r.input)) + " " + std::string(toString(r.method)));
        if (r.method == Method::Fov) {
            EXPECT_FALSE(r.outcomes.has_value()) << "only retention has outcomes";
            continue;
        }
        ASSERT_TRUE(r.outcomes.has_value());
        const eval::SavingOutcomes& oc = *r.outcomes;
        EXPECT_EQ(oc.pixels(0) + oc.pixels(1) + oc.pixels(2) + oc.pixels(3), pixels);
        EXPECT_EQ(oc.reservoirs, pixels);
        EXPECT_GT(oc.pixels(1), 0u) << "the inset's samples where the inset still is";
        EXPECT_GT(oc.pixels(2), 0u) << "and where it has left: the head moves";
        EXPECT_GT(oc.pixels(0) + oc.pixels(3), oc.pixels(1) + oc.pixels(2)) << "most of a 40° view is the wide views'";
        // Where the inset still is, its candidate has the history's quality: never dropped as a change of
        // quality, and under sparse retention never skipped (such a tile is not rendered at the floor only).
        EXPECT_EQ(oc.count[1][7], 0u);
        if (r.method == Method::Wrs) {
            EXPECT_EQ(oc.differing, 0u) << "the reference is the compositor's, decision for decision";
            // Landed wide samples (docs/retention.md): held by many wide pixels, and kept there against
            // the bilinear wide view's candidate. (Sparse retention's skips of tiles rendered at the
            // floor only, which landed samples leave few of: Submitted.SparseRetentionSkipsWideOnlyTiles….)
            EXPECT_GT(oc.pixels(3), pixels / 20) << "landed wide samples held";
            EXPECT_GT(oc.count[3][int(gpu::WRS_OUT_KEPT)], 0u) << "and kept";
        } else {
            EXPECT_EQ(oc.pixels(3), 0u) << "the oracles are not offered landed samples";
            // The oracle's comparisons of distances to the full-resolution reference flip near ties
            // (Submitted.OraclesCompareWithTheFullResolutionReference).
            EXPECT_LE(oc.differing, pixels / 100);
        }
    }
    const std::string dir = std::filesystem::temp_directory_path() / "wrsfov_saving_outcomes_test";
    std::filesystem::remove_all(dir);
    ASSERT_TRUE(eval::writeSavingReport(*rows, so, dir, context().deviceName()).ok());
    std::ifstream csv(dir + "/outcomes.csv");
    std::string header, line;
    std::getline(csv, header);
    EXPECT_EQ(header, "scene,input,method,inset_deg,class,outcome,pixels");
    int n = 0;
    while (std::getline(csv, line)) n++;
    EXPECT_EQ(n, 2 * 4 * 8) << "wrs and the oracle, four classes, eight outcomes";
    std::ifstream md(dir + "/saving.md");
    const std::string text((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find("## Retention outcomes"), std::string::npos);
}

TEST_F(Saving, BadOptionsAreRefusedWithAMessage) {
    eval::SavingOptions so;
    so.bench.width = so.bench.height = 64;
    so.bench.frames = 4;
    so.bench.warmup = 1;
    auto seq = eval::runSaving(context(), eval::SceneKind::Sequence, so);
    ASSERT_FALSE(seq.ok());
    EXPECT_NE(seq.error().message.find("the atrium, dynamic, thin, the text page or the photo"), std::string::npos);
    so.split = "validation";
    auto split = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_FALSE(split.ok());
    EXPECT_NE(split.error().message.find("train or test"), std::string::npos);
    so.split = "test";
    so.insetDegs = {0.0f};
    auto zero = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_FALSE(zero.ok());
    EXPECT_NE(zero.error().message.find("inset sizes"), std::string::npos);
    so.insetDegs = {10.0f};
    so.rateTexel = 12;
    auto texel = eval::runSaving(context(), eval::SceneKind::Atrium, so);
    ASSERT_FALSE(texel.ok());
    EXPECT_NE(texel.error().message.find("power of two"), std::string::npos);
}

}  // namespace
}  // namespace wrsfov::test
