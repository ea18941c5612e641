// Pipelines shared on the context (vk::Context::sharedPipeline): a compositor made after another with
// the same configuration compiles nothing and composes the same bits, one of another method compiles
// its own variants, and the pipelines outlive the compositor (and the layouts and modules) that made
// them, under the validation layer (on a context of the test's own).
#include <array>
#include <memory>
#include <string>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class SharedPipelines : public GpuTest {};

TEST_F(SharedPipelines, MadeOncePerContextAndUsedByEveryCompositor) {
    constexpr uint32_t W = 64, H = 48;
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    cfg.foveation = FoveationMode::Mip;
    cfg.seed = 5;
    RandomScene scene(31);
    auto frame = [&] { return scene.stereoFrame(W, H); };
    // A context of its own, so that the counts start at zero whatever ran before in this program.
    auto own = vk::Context::create();
    ASSERT_TRUE(own.ok()) << own.error().message;
    vk::Context& ctx = **own;
    ASSERT_EQ(ctx.sharedPipelineCount(), 0u);
    const auto formats = std::array{layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F};
    const auto first = frame();
    size_t made = 0;
    {
        auto a = Compositor::create(ctx, cfg);
        ASSERT_TRUE(a.ok()) << a.error().message;
        StereoApp appA(**a, W, H, formats[0], formats[1], formats[2]);
        ASSERT_TRUE(appA.submit(1, first).ok());
        const size_t afterA = ctx.sharedPipelineCount();
        EXPECT_GT(afterA, 0u) << "the first wrs frame makes its pipelines";
        // The frame's stats count them (the fp16 probe's, made at create, is not the frame's) and the
        // time they took: the first frame's hitch.
        EXPECT_EQ((*a)->stats().pipelinesMade, afterA - (ctx.halfProbe() ? 1u : 0u));
        EXPECT_GT((*a)->stats().pipelineMs, 0.0);

        // The same configuration: nothing new, the same bits.
        auto b = Compositor::create(ctx, cfg);
        ASSERT_TRUE(b.ok()) << b.error().message;
        StereoApp appB(**b, W, H, formats[0], formats[1], formats[2]);
        ASSERT_TRUE(appB.submit(1, first).ok());
        EXPECT_EQ(ctx.sharedPipelineCount(), afterA);
        EXPECT_EQ((*b)->stats().pipelinesMade, 0u) << "b's first frame found a's pipelines";
        EXPECT_EQ((*b)->stats().pipelineMs, 0.0);
        expectSameOutputs(**a, **b, "frame 1");
        for (uint64_t n = 2; n <= 3; ++n) {
            const auto eyes = frame();
            ASSERT_TRUE(appA.submit(n, eyes).ok());
            ASSERT_TRUE(appB.submit(n, eyes).ok());
            expectSameOutputs(**a, **b, "frame " + std::to_string(n));
            expectSameReservoirs(**a, **b, "frame " + std::to_string(n));
            EXPECT_EQ((*a)->stats().pipelinesMade, 0u) << "frame " << n;
        }
        const size_t afterB = ctx.sharedPipelineCount();

        // Another method uses variants wrs did not (foveate): it makes those.
        CompositorConfig fovCfg = cfg;
        fovCfg.method = Method::Fov;
        auto c = Compositor::create(ctx, fovCfg);
        ASSERT_TRUE(c.ok()) << c.error().message;
        StereoApp appC(**c, W, H, formats[0], formats[1], formats[2]);
        ASSERT_TRUE(appC.submit(1, first).ok());
        EXPECT_GT(ctx.sharedPipelineCount(), afterB);
        EXPECT_EQ((*c)->stats().pipelinesMade, ctx.sharedPipelineCount() - afterB);

        made = ctx.sharedPipelineCount();
    }
    // The compositors that made the pipelines gone (with their layouts and shader modules), new ones
    // bind them: nothing is made, the validation layer stays silent, and two of them agree.
    auto again = Compositor::create(ctx, cfg);
    ASSERT_TRUE(again.ok()) << again.error().message;
    StereoApp appAgain(**again, W, H, formats[0], formats[1], formats[2]);
    ASSERT_TRUE(appAgain.submit(1, first).ok());
    EXPECT_EQ(ctx.sharedPipelineCount(), made);
    auto d = Compositor::create(ctx, cfg);
    ASSERT_TRUE(d.ok()) << d.error().message;
    StereoApp appD(**d, W, H, formats[0], formats[1], formats[2]);
    ASSERT_TRUE(appD.submit(1, first).ok());
    expectSameOutputs(**again, **d, "a new compositor's first frame");
    EXPECT_EQ(ctx.validationErrors(), 0u) << "validation errors on the test's own context";
}

}  // namespace
}  // namespace wrsfov::test
