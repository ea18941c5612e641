// The traffic model (compositor.h: traffic, trafficBytes, floorBytes): what each pass reads and
// writes per pixel of one view, from its bindings and formats, and the floor a method cannot avoid.
#include <gtest/gtest.h>

#include "compositor/compositor.h"

namespace wrsfov {
namespace {

// The report's inputs: RGBA8 sRGB colour, D32F depth, RGBA16F motion.
TrafficInputs inputs(uint32_t w, uint32_t h, bool depth, bool motion) {
    return TrafficInputs{w, h, 4, depth ? 4u : 0u, motion ? 8u : 0u};
}

double passBytes(const Traffic& t, const std::string& name) {
    for (const PassTraffic& p : t.passes)
        if (p.pass == name) return p.read + p.write;
    return -1;
}

TEST(Traffic, WithinTheBudgetsAt1024x768) {
    CompositorConfig wrs;
    CompositorConfig fov;
    fov.method = Method::Fov;
    for (FoveationMode mode : {FoveationMode::Mip, FoveationMode::Gauss}) {
        wrs.foveation = fov.foveation = mode;
        const Traffic tw = traffic(wrs, inputs(1024, 768, true, true));
        const Traffic tf = traffic(fov, inputs(1024, 768, true, true));
        // The budgets, and for wrs the three words a tile its classification moves (reach, held, list entry).
        EXPECT_LE(tw.perPixel(), 64.0 + 3 * 4.0 / 64.0) << toString(mode);
        EXPECT_LE(tf.perPixel(), 24.0) << toString(mode);
        // Floors: colour 4 + output 4, plus reservoir 2 x 16 + depth 4 + motion 8 with history.
        EXPECT_DOUBLE_EQ(tw.floor, 52.0);
        EXPECT_DOUBLE_EQ(tf.floor, 8.0);
        // Sparse retention with every tile retaining (the default shares): the classification moves a word a
        // tile (its list entry and the held quality it reads), its reach phase the superblocks' tiles' held
        // words, and the skipped tiles' pass nothing.
        constexpr double kTileWord = 4.0 / 64.0;
        ASSERT_EQ(tw.passes.size(), 5u);
        EXPECT_EQ(tw.passes[0].pass, "reach");
        EXPECT_EQ(tw.passes[1].pass, "classify");
        EXPECT_EQ(tw.passes[2].pass, "pyramid");
        EXPECT_EQ(tw.passes[3].pass, "retain");
        EXPECT_EQ(tw.passes[4].pass, "skip");
        EXPECT_DOUBLE_EQ(passBytes(tw, "reach"), kTileWord);
        EXPECT_DOUBLE_EQ(passBytes(tw, "classify"), 2 * kTileWord);
        EXPECT_EQ(passBytes(tw, "skip"), 0.0);
        // The steady floor, where asked for, per level-4 texel (1/256 of the pixels at 1024x768): level
        // 4 and the history in, a motion texel (8 bytes), the filtered texel out; then two texels in,
        // one out. Its two passes follow the pyramid.
        CompositorConfig steady = wrs;
        steady.steadyFloor = true;
        const Traffic ts = traffic(steady, inputs(1024, 768, true, true));
        ASSERT_EQ(ts.passes.size(), 7u);
        EXPECT_EQ(ts.passes[3].pass, "steady");
        EXPECT_EQ(ts.passes[4].pass, "steady-copy");
        EXPECT_DOUBLE_EQ(passBytes(ts, "steady"), (8.0 + 8.0 + 8.0 + 8.0) / 256.0);
        EXPECT_DOUBLE_EQ(passBytes(ts, "steady-copy"), 24.0 / 256.0);
        EXPECT_DOUBLE_EQ(ts.perPixel() - tw.perPixel(), 56.0 / 256.0);
        // Not for fov, nor for wrs where the floor rule does not apply (merging at the floor).
        CompositorConfig fovSteady = fov, mergeSteady = steady;
        fovSteady.steadyFloor = true;
        mergeSteady.floorMerge = true;
        EXPECT_EQ(traffic(fovSteady, inputs(1024, 768, true, true)).passes.size(), 3u);
        EXPECT_EQ(traffic(mergeSteady, inputs(1024, 768, true, true)).passes.size(), 3u);
        // Without sparse retention: no reach phase and no held qualities read, the same retention.
        CompositorConfig dense = wrs;
        dense.sparseRetention = false;
        const Traffic td = traffic(dense, inputs(1024, 768, true, true));
        ASSERT_EQ(td.passes.size(), 3u);
        EXPECT_DOUBLE_EQ(td.perPixel(), tw.perPixel() - 2 * kTileWord);
        ASSERT_EQ(tf.passes.size(), 3u);
        EXPECT_EQ(tf.passes[2].pass, "foveate");
    }
}

TEST(Traffic, SparseRetentionWeighsTheTilesByTheirShare) {
    CompositorConfig wrs;
    TrafficInputs in = inputs(1024, 768, true, true);
    const Traffic all = traffic(wrs, in);
    in.retainShare = 0.1;
    in.motionShare = 0.3;
    const Traffic t = traffic(wrs, in);
    // Retention's bytes in a tenth of the tiles, the foveating pass's (colour, levels, output) in the
    // rest, and the motion of the tiles whose motion the classification read.
    EXPECT_DOUBLE_EQ(passBytes(t, "retain"), 0.1 * passBytes(all, "retain"));
    EXPECT_DOUBLE_EQ(passBytes(t, "classify"), 0.3 * in.motionBytes + 2 * 4.0 / 64.0);
    CompositorConfig fov;
    fov.method = Method::Fov;
    EXPECT_NEAR(passBytes(t, "skip"), 0.9 * passBytes(traffic(fov, in), "foveate"), 1e-9);
    // The floor: colour and output everywhere, history, depth and motion where retention ran.
    EXPECT_DOUBLE_EQ(t.floor, 8.0 + 0.1 * (32.0 + in.depthBytes + in.motionBytes));
    EXPECT_LT(t.perPixel(), 0.5 * all.perPixel());
}

TEST(Traffic, EveryMethodMovesAtLeastItsFloorAndTheFrameBytesFollow) {
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::Oracle, Method::OracleQ})
        for (FoveationMode mode : {FoveationMode::None, FoveationMode::Mip, FoveationMode::Gauss})
            for (int inputsMask = 0; inputsMask < 4; ++inputsMask) {
                CompositorConfig c;
                c.method = m;
                c.foveation = mode;
                const TrafficInputs in = inputs(300, 200, inputsMask & 1, inputsMask & 2);
                const Traffic t = traffic(c, in);
                const std::string what = std::string(toString(m)) + "/" + std::string(toString(mode));
                EXPECT_GE(t.perPixel(), t.floor) << what;
                EXPECT_GT(t.floor, 0.0) << what;
                EXPECT_NEAR(double(trafficBytes(c, in)), t.perPixel() * 300 * 200 * 2, 1.0) << what;
                EXPECT_NEAR(double(floorBytes(c, in)), t.floor * 300 * 200 * 2, 1.0) << what;
                // `none` builds no pyramid, except the fingerprint level of wrs and the oracles.
                const bool retain = usesRetainPass(m);
                EXPECT_EQ(passBytes(t, "pyramid") > 0, mode != FoveationMode::None || retain) << what;
            }
}

TEST(Traffic, DepthAndMotionCountOnlyWhereAMethodReadsThem) {
    CompositorConfig c;
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs}) {
        c.method = m;
        const double bare = traffic(c, inputs(256, 256, false, false)).perPixel();
        const double depth = traffic(c, inputs(256, 256, true, false)).perPixel() - bare;
        const double motion = traffic(c, inputs(256, 256, false, true)).perPixel() - bare;
        EXPECT_DOUBLE_EQ(depth, m == Method::WrsPaper || m == Method::Wrs ? 4.0 : 0.0) << toString(m);
        // wrs: the motion, and sparse retention's reach phase that motion brings (a word per tile).
        EXPECT_DOUBLE_EQ(motion, m == Method::Fov ? 0.0 : m == Method::Wrs ? 8.0 + 4.0 / 64.0 : 8.0) << toString(m);
    }
}

TEST(Traffic, GaussReadsTheLevelsItIsBuiltFromAndBirthTrackingCosts32Bytes) {
    CompositorConfig c;
    c.foveation = FoveationMode::Mip;
    const Traffic mip = traffic(c, inputs(512, 512, true, true));
    c.foveation = FoveationMode::Gauss;
    const Traffic gauss = traffic(c, inputs(512, 512, true, true));
    // Levels 1, 2, 3 of 512^2 hold 1/4, 1/16, 1/64 of the pixels, 8 bytes a texel. gauss reads levels
    // 1..3 to build the next and stores all four; mip stores only 3 and 4 (the levels it samples).
    const double l1 = 0.25, l2 = 0.0625, l3 = 0.015625;
    EXPECT_NEAR(passBytes(gauss, "pyramid") - passBytes(mip, "pyramid"), 8.0 * (l1 + l2 + l3) + 8.0 * (l1 + l2), 1e-9);
    // What the foveating pass reads follows what was stored.
    EXPECT_NEAR(passBytes(gauss, "retain") - passBytes(mip, "retain"), 8.0 * (l1 + l2), 1e-9);
    c.trackBirth = true;
    EXPECT_DOUBLE_EQ(traffic(c, inputs(512, 512, true, true)).perPixel() - gauss.perPixel(), 32.0);
}

}  // namespace
}  // namespace wrsfov
