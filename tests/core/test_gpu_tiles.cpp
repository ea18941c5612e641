// Tile classes on the GPU (docs/speed.md "Tiles"): a compositor that runs its foveating pass per
// tile class gives the same outputs and reservoirs, bit for bit, as one that runs every pixel
// through the per-pixel path, for every method and foveation mode, narrow views (fovea and
// mid-periphery tiles) and HMD views (mostly far tiles), a size that is not a multiple of the tile,
// mono views and an invalid gaze.
#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class Tiles : public GpuTest {};

TEST_F(Tiles, SkippingGivesTheSameOutputBitForBit) {
    constexpr uint32_t W = 76, H = 52;
    const layers::Fov narrow{-0.21f, 0.19f, 0.15f, -0.17f};  // about 23 x 18 degrees: 3.3 px/deg
    int tiledRuns = 0;
    for (Method method : {Method::Fov, Method::Wrs, Method::Oracle, Method::WrsPaper}) {
        for (FoveationMode mode : {FoveationMode::Mip, FoveationMode::Gauss, FoveationMode::None}) {
            for (float fovea : sanitizedSweep({5.0f, 20.0f})) {  // a uniform: one host path
                for (bool hmd : sanitizedSweep({false, true})) {  // the views: a uniform too
                    SCOPED_TRACE(std::string(toString(method)) + " " + std::string(toString(mode)) + " fovea " +
                                 std::to_string(fovea) + (hmd ? " hmd" : " narrow"));
                    CompositorConfig cfg;
                    cfg.method = method;
                    cfg.foveation = mode;
                    cfg.foveaDeg = fovea;
                    cfg.seed = 3;
                    CompositorConfig off = cfg;
                    off.skipTiles = false;
                    auto a = Compositor::create(context(), cfg);
                    auto b = Compositor::create(context(), off);
                    ASSERT_TRUE(a.ok() && b.ok());
                    StereoApp appA(**a, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
                    StereoApp appB(**b, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
                    RandomScene scene(40);
                    for (uint64_t n = 1; n <= 2; ++n) {
                        std::array<EyeFrame, 2> eyes;
                        for (int e = 0; e < 2; ++e) {
                            eyes[e].fov = hmd ? hmdFov(e) : narrow;
                            eyes[e].color = scene.color(layers::Format::RGBA8_SRGB, W, H);
                            eyes[e].depth = scene.depth(layers::Format::R32F, W, H);
                            eyes[e].motion = scene.motion(layers::Format::RGBA16F, W, H);
                            // Frame 2: an invalid gaze (the view centre with the fallback fovea).
                            eyes[e].gaze = {scene.gaze(eyes[e].fov), n != 2, 1.0f};
                        }
                        ASSERT_TRUE(appA.submit(n, eyes).ok());
                        ASSERT_TRUE(appB.submit(n, eyes).ok());
                        const bool classes = mode != FoveationMode::None &&
                                             (method == Method::Fov || usesRetainPass(method));
                        EXPECT_EQ((*a)->stats().tiled, classes);
                        EXPECT_FALSE((*b)->stats().tiled);
                        tiledRuns += (*a)->stats().tiled;
                        const std::string what = "frame " + std::to_string(n);
                        expectSameOutputs(**a, **b, what);
                        if (method != Method::Fov) expectSameReservoirs(**a, **b, what);
                        if (HasFailure()) return;
                    }
                }
            }
        }
    }
    EXPECT_EQ(tiledRuns, 3 * 2 * (kSanitized ? 1 : 2) * (kSanitized ? 1 : 2) * 2);
}

TEST_F(Tiles, MonoViewsClassifyOneEye) {
    // The same images, view and gaze in both eyes: the passes run once (monoViews) over one eye's tiles.
    constexpr uint32_t W = 64, H = 40;
    for (Method method : {Method::Fov, Method::Wrs}) {
        CompositorConfig cfg;
        cfg.method = method;
        CompositorConfig off = cfg;
        off.skipTiles = false;
        auto a = Compositor::create(context(), cfg);
        auto b = Compositor::create(context(), off);
        ASSERT_TRUE(a.ok() && b.ok());
        HostStereoApp::Options o;
        o.width = W;
        o.height = H;
        o.monoView = true;
        auto appA = HostStereoApp::create(**a, o);
        auto appB = HostStereoApp::create(**b, o);
        ASSERT_TRUE(appA.ok() && appB.ok());
        RandomScene scene(41);
        for (uint64_t n = 1; n <= 3; ++n) {
            std::array<EyeSubmission, 2> eyes;
            eyes[0].fov = layers::Fov{-0.3f, 0.3f, 0.25f, -0.25f};
            eyes[0].color = scene.color(layers::Format::RGBA8_SRGB, W, H);
            eyes[0].gaze = {scene.gaze(eyes[0].fov), true, 1.0f};
            eyes[1] = eyes[0];
            ASSERT_TRUE((*appA)->submit(n, n / 90.0, eyes).ok());
            ASSERT_TRUE((*appB)->submit(n, n / 90.0, eyes).ok());
            EXPECT_TRUE((*a)->stats().monoViews && (*a)->stats().tiled);
            expectSameOutputs(**a, **b, std::string(toString(method)) + " frame " + std::to_string(n));
            if (HasFailure()) return;
        }
    }
}

}  // namespace
}  // namespace wrsfov::test
