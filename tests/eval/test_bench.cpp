// Regression guard of the benchmark's headline: at a 5° fovea, WRS keeps more near-gaze quality
// than FOV on the reading page (reading gaze) and in the atrium (free viewing, static camera).
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <gtest/gtest.h>

#include "../core/gpu_rig.h"
#include "eval/bench.h"
#include "eval/flicker.h"

namespace wrsfov::test {
namespace {

class Bench : public GpuTest {};

TEST_F(Bench, WrsBeatsFovNearGazeAtFiveDegrees) {
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Text, eval::SceneKind::Atrium};
    o.methods = {Method::Fov, Method::WrsPaper};
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.width = 160;
    o.height = 144;
    o.frames = 120;  // long enough for the reading gaze to revisit words
    o.warmup = 10;
    o.heavyEvery = 1000;
    o.path = scenes::CameraPath::Static;
    auto r = eval::runBench(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    ASSERT_EQ(r->size(), 4u);
    for (eval::SceneKind scene : o.scenes) {
        double fov = NAN, wrs = NAN;
        for (const auto& c : *r) {
            if (c.scene != scene) continue;
            (c.method == Method::Fov ? fov : wrs) = c.nearPsnr;
            EXPECT_TRUE(c.gpu.valid);
            EXPECT_GT(c.copyMs, 0.0);
            EXPECT_GT(c.shadingFraction, 0.0);
            EXPECT_LT(c.shadingFraction, 0.2);  // a 5° fovea shades a small part of a 92° view at full rate
            // The eccentricity bands partition the pixels: their shares sum to 1 and their MSEs,
            // weighted by the shares, give the whole image's MSE.
            double share = 0.0, mse = 0.0;
            for (std::size_t b = 0; b < c.bandMse.size(); ++b) {
                share += c.bandShare[b];
                mse += c.bandShare[b] * c.bandMse[b];
            }
            EXPECT_NEAR(share, 1.0, 1e-12);
            EXPECT_NEAR(mse, c.mse, 1e-9 * c.mse);
            EXPECT_GT(c.bandShare.back(), 0.3);  // most of a 92° view lies beyond 30° of a gaze near its centre
        }
        std::printf("%s: near-gaze PSNR fov %.3f dB, wrs %.3f dB\n", std::string(eval::toString(scene)).c_str(), fov,
                    wrs);
        EXPECT_GT(wrs, fov) << eval::toString(scene);
    }
}

TEST_F(Bench, FlickerAnalysisAccountsForEveryStablePixelPair) {
    // wrsfov-bench --flicker on the photo scene: its classes partition the stable pixel pairs and
    // their sums are the methods' temporal instabilities; a still head gives `wrs` nothing to flicker
    // with (kept samples do not move: steadier than fov), a slow pan does, and the files are written.
    eval::BenchOptions o;
    o.scenes = {eval::SceneKind::Photo};
    o.monitor = true;
    o.foveas = {5.0f};
    o.modes = {FoveationMode::Mip};
    o.width = 128;
    o.height = 96;
    o.frames = 24;
    o.warmup = 4;
    for (scenes::PhotoMotion m : {scenes::PhotoMotion::Static, scenes::PhotoMotion::Pan}) {
        SCOPED_TRACE(std::string(scenes::toString(m)));
        o.photoMotion = m;
        const std::string dir = ::testing::TempDir() + "flicker_" + std::string(scenes::toString(m));
        auto r = eval::analyseFlicker(context(), o, dir);
        ASSERT_TRUE(r.ok()) << r.error().message;
        uint64_t pairs = 0;
        double w = 0, f = 0;
        for (const eval::FlickerClass& c : r->classes) {
            pairs += c.pairs;
            w += c.wrsChange;
            f += c.fovChange;
            EXPECT_GT(c.pairs, 0u) << c.name;
        }
        ASSERT_GT(r->stablePairs, 1000u);
        EXPECT_EQ(pairs, r->stablePairs);
        EXPECT_NEAR(r->wrsInstability, w / double(pairs), 1e-12);
        EXPECT_NEAR(r->fovInstability, f / double(pairs), 1e-12);
        std::printf("%s: wrs %.6f fov %.6f reference %.6f over %llu pairs, %zu classes\n",
                    std::string(scenes::toString(m)).c_str(), r->wrsInstability, r->fovInstability, r->refInstability,
                    (unsigned long long)r->stablePairs, r->classes.size());
        if (m == scenes::PhotoMotion::Static) {
            EXPECT_LE(r->wrsInstability, r->fovInstability);
            EXPECT_EQ(r->refInstability, 0.0) << "a still scene: the reference never changes";
        } else {
            EXPECT_GT(r->refInstability, 0.0);
        }
        for (const char* file : {"/flicker.md", "/flicker.csv", "/flicker.png"})
            EXPECT_TRUE(std::filesystem::exists(dir + file)) << file;
    }
}

TEST(BenchOptions, RefusesBadSweeps) {
    eval::BenchOptions o;
    o.frames = 5;
    o.warmup = 10;
    auto r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("warm-up"), std::string::npos) << r.error().message;
    o = {};
    o.width = 8;
    r = eval::runBench(context(), o);
    ASSERT_FALSE(r.ok());
}

}  // namespace
}  // namespace wrsfov::test
