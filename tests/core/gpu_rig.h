// Shared test scaffolding for GPU tests: one Vulkan context per test program (validation on when
// WRSFOV_VALIDATION=1, and every test fails on any validation error), a stereo "application" that
// submits colour/depth/motion through real swapchains, and random input generators.
#pragma once

#include <array>
#include <initializer_list>
#include <memory>
#include <optional>
#include <random>
#include <span>
#include <vector>
#include <string>

#include <gtest/gtest.h>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "compositor/reference.h"
#include "compositor/vk_context.h"
#include "layers/frame.h"

namespace wrsfov::test {

/// Built with the sanitizers (tests/CMakeLists.txt). There the host code is what is checked, and a
/// sweep over shader variants that share one host path keeps its first variant (sanitizedSweep); the
/// release build runs them all against the reference.
#ifdef WRSFOV_SANITIZED
inline constexpr bool kSanitized = true;
#else
inline constexpr bool kSanitized = false;
#endif
/// The values a sweep runs: all of them, or in a sanitizer build only the first.
template <typename T>
std::vector<T> sanitizedSweep(std::initializer_list<T> values) {
    std::vector<T> v(values);
    if (kSanitized && v.size() > 1) v.resize(1);
    return v;
}

/// The test program's Vulkan context (created on first use; aborts the test if none).
vk::Context& context();

/// Base fixture of GPU tests: checks that the validation layer stayed silent during the test.
class GpuTest : public ::testing::Test {
protected:
    void SetUp() override;
    void TearDown() override;

private:
    uint32_t errorsBefore_ = 0;
};

/// What one eye submits in a frame.
using EyeFrame = EyeSubmission;

/// A stereo application on HostStereoApp: one swapchain per kind with two array layers (layer = eye).
class StereoApp {
public:
    StereoApp(Compositor& compositor, uint32_t width, uint32_t height, layers::Format colorFormat,
              std::optional<layers::Format> depthFormat, std::optional<layers::Format> motionFormat);

    /// Writes the images and ends the frame (time = frameIndex / 90 s).
    Status submit(uint64_t frameIndex, const std::array<EyeFrame, 2>& eyes, bool reversed = false);
    /// Builds (without submitting) the frame end for the images last written.
    layers::FrameEndInfo frameEnd(uint64_t frameIndex, const std::array<EyeFrame, 2>& eyes, bool reversed = false);
    /// Writes both eyes' images through acquire/wait/write/release.
    void write(const std::array<EyeFrame, 2>& eyes);

    layers::Swapchain& color() { return app_->color(); }
    layers::Swapchain* depth() { return app_->depth(); }
    layers::Swapchain* motion() { return app_->motion(); }
    const float nearZ = 0.1f, farZ = 100.0f;

private:
    Compositor& comp_;
    std::unique_ptr<HostStereoApp> app_;
};

/// Reference inputs from the same images.
std::array<Reference::EyeInput, 2> referenceInputs(const std::array<EyeFrame, 2>& eyes);

using wrsfov::hmdFov;
/// A gaze direction at (azimuth, elevation) degrees, -Z forward.
glm::vec3 gazeDir(float azimuthDeg, float elevationDeg);

/// A gaze direction through the centre of pixel (x, y) of a w x h view with field of view `fov`.
glm::vec3 gazeAtPixel(double x, double y, uint32_t w, uint32_t h, const layers::Fov& fov);
/// Fine deterministic texture (a 1-2 px pattern with a smooth ramp), RGBA16F, shifted by (sx, sy)
/// pixels (the continuous pattern sampled at the shifted centres) and scaled in brightness.
HostImage fineTexture(uint32_t w, uint32_t h, float sx, float sy, float brightness);
/// The same motion (pixels) at every pixel, RG16F.
HostImage uniformMotion(uint32_t w, uint32_t h, float mx, float my);

/// Random test content.
struct RandomScene {
    explicit RandomScene(uint32_t seed) : rng(seed) {}
    std::mt19937 rng;
    /// Blocky colour with fine noise (exercises every pyramid level).
    HostImage color(layers::Format f, uint32_t w, uint32_t h);
    /// Depth in (0, 1) made of patches, so flushes happen at patch edges.
    HostImage depth(layers::Format f, uint32_t w, uint32_t h);
    /// Motion: a random global shift (integer and fractional) plus per-patch jitter, some off-screen.
    HostImage motion(layers::Format f, uint32_t w, uint32_t h);
    glm::vec3 gaze(const layers::Fov& fov);
    /// Both eyes of an HMD frame (hmdFov): sRGB colour, R32F depth, RGBA16F motion and this scene's
    /// gaze, valid or not.
    std::array<EyeFrame, 2> stereoFrame(uint32_t w, uint32_t h, bool gazeValid = true) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            eyes[e].color = color(layers::Format::RGBA8_SRGB, w, h);
            eyes[e].depth = depth(layers::Format::R32F, w, h);
            eyes[e].motion = motion(layers::Format::RGBA16F, w, h);
            eyes[e].gaze = {gaze(eyes[e].fov), gazeValid, 1.0f};
        }
        return eyes;
    }
};

}  // namespace wrsfov::test

namespace wrsfov::test {
/// Runs a compute shader with binding 0 = input SSBO, binding 1 = output SSBO and a uint push
/// constant `count` (local size 64 in x), and returns the output bytes.
std::vector<std::byte> runBufferKernel(const uint32_t* spirv, size_t spirvBytes, std::span<const std::byte> input,
                                       size_t outputBytes, uint32_t count);
}  // namespace wrsfov::test
