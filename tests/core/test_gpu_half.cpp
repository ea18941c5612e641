// fp16 storage with the device's own conversion (CompositorConfig::hardwareHalf): where the probe
// found it exact on the values the passes give it (already on fp16's grid, wrs_store_f16), every pass
// stores the same bits with it as without it, for every method, mode and input kind.
#include <cstdlib>
#include <string>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class HardwareHalf : public GpuTest {};

TEST_F(HardwareHalf, SameBitsAsTheHandConversion) {
    constexpr uint32_t W = 96, H = 64;
    int compared = 0;
    // Under the sanitizers Mip only: Tiles.* and Retain.* run the other modes' host paths there.
    const std::vector<FoveationMode> modes = sanitizedSweep({FoveationMode::Mip, FoveationMode::Gauss, FoveationMode::None});
    for (Method method : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::OracleQ})
        for (FoveationMode mode : modes) {
            SCOPED_TRACE(std::string(toString(method)) + " " + std::string(toString(mode)));
            CompositorConfig cfg;
            cfg.method = method;
            cfg.foveation = mode;
            cfg.seed = 9;
            CompositorConfig byHand = cfg;
            byHand.hardwareHalf = false;
            auto a = Compositor::create(context(), cfg);
            auto b = Compositor::create(context(), byHand);
            ASSERT_TRUE(a.ok() && b.ok());
            EXPECT_FALSE((*b)->usesHardwareHalf());
            if (handHalfForced()) GTEST_SKIP() << "WRSFOV_HARDWARE_HALF=0: the hand conversion only";
            if (!(*a)->usesHardwareHalf()) {
                // LLVM (lavapipe) converts with round to nearest even: the probe must find it exact there.
                ASSERT_FALSE(context().isCpuDevice()) << "the probe refused lavapipe's fp16 conversion";
                GTEST_SKIP() << context().deviceName() << ": fp16 conversion differs from the hand one, not used";
            }
            StereoApp appA(**a, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
            StereoApp appB(**b, W, H, layers::Format::RGBA8_SRGB, layers::Format::R32F, layers::Format::RGBA16F);
            RandomScene scene(77);
            for (uint64_t n = 1; n <= 4; ++n) {
                const std::array<EyeFrame, 2> eyes = scene.stereoFrame(W, H, n != 3);
                ASSERT_TRUE(appA.submit(n, eyes).ok());
                ASSERT_TRUE(appB.submit(n, eyes).ok());
                const std::string what = "frame " + std::to_string(n);
                expectSameOutputs(**a, **b, what);
                if (method != Method::Fov) expectSameReservoirs(**a, **b, what);
                if (HasFailure()) return;
                ++compared;
            }
        }
    EXPECT_EQ(compared, 5 * int(modes.size()) * 4);
}

// WRSFOV_HARDWARE_HALF=0 keeps the hand conversion whatever the probe found; unset, the probe decides.
TEST_F(HardwareHalf, EnvironmentCanForceTheHandConversion) {
    const char* before = std::getenv("WRSFOV_HARDWARE_HALF");
    const std::string saved = before ? before : "";
    setenv("WRSFOV_HARDWARE_HALF", "0", 1);
    EXPECT_TRUE(handHalfForced());
    auto forced = Compositor::create(context(), CompositorConfig{});
    unsetenv("WRSFOV_HARDWARE_HALF");
    EXPECT_FALSE(handHalfForced());
    auto free = Compositor::create(context(), CompositorConfig{});
    if (before) setenv("WRSFOV_HARDWARE_HALF", saved.c_str(), 1);
    ASSERT_TRUE(forced.ok() && free.ok());
    EXPECT_FALSE((*forced)->usesHardwareHalf());
    ASSERT_TRUE(context().halfProbe().has_value());
    EXPECT_EQ((*free)->usesHardwareHalf(), *context().halfProbe());
    if (context().isCpuDevice()) {
        EXPECT_TRUE((*free)->usesHardwareHalf()) << "lavapipe's conversion passes the probe";
    }
}

}  // namespace
}  // namespace wrsfov::test
