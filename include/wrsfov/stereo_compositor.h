// The compositor as an integrator uses it: one front class over the application's Vulkan device.
//
//   auto comp = wrsfov::StereoCompositor::create({instance, physicalDevice, device, queueFamily, 0});
//   auto color = (*comp)->createSwapchain({layers::Usage::Color, layers::Format::RGBA8_SRGB, w, h, 2});
//   ... each frame: fill the swapchains, then
//   (*comp)->endFrame(frame);                  // layers::FrameEndInfo: the views, their images, the gaze
//   VkImage shown = (*comp)->outputImage();    // 2 layers (eye), RGBA8 sRGB-encoded, GENERAL layout
//
// examples/stereo_frame.cpp is a whole program; docs/integrating.md says what each call does and
// which thread may make it. The passes, their buffers and the research switches stay behind this class
// (compositor/compositor.h, which the project's own tools and studies use).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include <vulkan/vulkan.h>

#include "layers/frame.h"
#include "layers/status.h"
#include "layers/swapchain.h"
#include "wrsfov/image.h"
#include "wrsfov/settings.h"
#include "wrsfov/submission.h"

namespace wrsfov {

/// The application's Vulkan objects, which it keeps owning: the compositor submits to the queue
/// (queueIndex of queueFamily, a family with compute), which the application must not use from another
/// thread while a StereoCompositor call runs.
struct VulkanDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    uint32_t queueIndex = 0;
};

/// What the last frame did.
struct FrameReport {
    uint64_t frameIndex = 0;
    /// GPU time of the frame's passes, both eyes, in milliseconds; gpuTimed false where it was not
    /// measured (FrameSubmission::Mode::Record, or Submit before waitFrame()).
    double gpuMs = 0.0;
    bool gpuTimed = false;
    /// The eye's gaze was invalid (or missing): its fovea was put at the view's centre, at the fallback size.
    std::array<bool, 2> gazeFallback{};
    bool usedDepth = false;   ///< the frame's depth flushed history where it changed
    bool usedMotion = false;  ///< the history followed the frame's motion vectors
    /// The frame started without the history its method keeps (the first frame, a new size or method,
    /// resetHistory); never for `fov`, which keeps none.
    bool historyReset = false;
    /// How the frame came: full-resolution views, quad views or views with a rate map.
    layers::SubmittedFoveation submitted = layers::SubmittedFoveation::Full;
    /// Pipelines the frame had to make (their first use on the device) and the host time that took.
    uint32_t pipelinesMade = 0;
    double pipelineMs = 0.0;
};

class StereoCompositor {
public:
    /// On the application's device. Refused with ConfigError-coded Errors where a setting is out of
    /// range or evaluation-only (the oracles), and with the device's error where it lacks what the
    /// passes need.
    static Result<std::unique_ptr<StereoCompositor>> create(const VulkanDevice& device, const Settings& settings = {});
    /// On a device of its own (the best one the loader offers; WRSFOV_DEVICE picks by name): for a
    /// program with no Vulkan of its own, such as a test or a preview.
    static Result<std::unique_ptr<StereoCompositor>> createOnOwnDevice(const Settings& settings = {});
    ~StereoCompositor();
    StereoCompositor(const StereoCompositor&) = delete;
    StereoCompositor& operator=(const StereoCompositor&) = delete;

    /// A swapchain whose images the compositor makes on the device (layers/swapchain.h: acquire,
    /// wait, write or render, release).
    Result<std::unique_ptr<layers::Swapchain>> createSwapchain(const layers::SwapchainCreateInfo& info,
                                                               const SwapchainImageOptions& options = {});
    /// A swapchain over images the application made on the device and keeps owning: info.imageCount
    /// images of info's format, size and array size, with SAMPLED usage, in options.restingLayout
    /// whenever the compositor may read them.
    Result<std::unique_ptr<layers::Swapchain>> importSwapchain(const layers::SwapchainCreateInfo& info,
                                                               std::span<const VkImage> images,
                                                               const SwapchainImageOptions& options = {});

    /// Validates and composites one frame. A refused frame changes nothing; the error code is a
    /// layers::SubmitError that names what was wrong (docs/bad-input.md).
    Status endFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission = {});
    /// Waits for the last frame submitted with FrameSubmission::Mode::Submit and fills its GPU time.
    Status waitFrame();
    FrameReport lastFrame() const;

    /// The output image: 2 layers (layer = eye), VK_FORMAT_R8G8B8A8_UNORM holding sRGB-encoded values
    /// (present it through an sRGB view or copy it as is to an sRGB swapchain), in VK_IMAGE_LAYOUT_GENERAL.
    /// It is remade when the output's size changes (a frame of another size); VK_NULL_HANDLE before the first frame.
    VkImage outputImage() const;
    uint32_t width() const;
    uint32_t height() const;
    /// One eye's output of the last frame, read back: RGBA8, sRGB-encoded.
    Result<HostImage> readOutput(uint32_t eye);

    Settings settings() const;
    /// Takes effect at the next frame; a change of method or foveation starts without history. Refused,
    /// changing nothing, as create refuses.
    Status setSettings(const Settings& settings);
    /// The next frame starts without history (a scene cut, a teleport).
    void resetHistory();
    std::string deviceName() const;

private:
    struct Impl;
    /// On `device`, or on a device of its own where it is null.
    static Result<std::unique_ptr<StereoCompositor>> make(const Settings& settings, const VulkanDevice* device);
    explicit StereoCompositor(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wrsfov
