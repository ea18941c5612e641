// How the compositor hands a frame's GPU work over (FrameSubmission), and how it makes or takes the
// images an application renders into (SwapchainImageOptions).
#pragma once

#include <cstdint>
#include <span>

#include <vulkan/vulkan.h>

namespace wrsfov {

/// How a swapchain's images are made when an application renders into them with Vulkan (an OpenXR
/// runtime handing them out): extra usage and create flags, and the layout the application leaves
/// them in. The compositor moves the images it reads to GENERAL and back inside its own submission.
struct SwapchainImageOptions {
    VkImageUsageFlags usage = 0;  ///< added to what the compositor needs (sampled, transfer, attachment)
    VkImageCreateFlags flags = 0;
    VkImageLayout restingLayout = VK_IMAGE_LAYOUT_GENERAL;
    /// Leave the images uninitialised until VulkanSwapchain::prepare() (an OpenXR runtime may use the
    /// application's queue only in some calls: xrCreateSwapchain is not one of them).
    bool deferInitialization = false;
    /// createSwapchain: make the images with `flags` alone. By default the compositor adds
    /// VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT to sRGB images and reads them through UNORM views; without
    /// it they are read through sRGB views (the device decodes, shaders/wrs_input.h), as imported
    /// images are unless `flags` says they were made MUTABLE_FORMAT.
    bool exactFlags = false;
};

/// How a frame end hands its GPU work over. The output image (2 layers, layer = eye, RGBA8 holding
/// sRGB-encoded values, VK_IMAGE_LAYOUT_GENERAL) is complete when the work is.
struct FrameSubmission {
    enum class Mode : uint8_t {
        /// Submit to the context's queue and wait for it (the default): the frame's statistics carry GPU times.
        Wait,
        /// Submit to the context's queue with the caller's semaphores and return without waiting:
        /// the caller's compositor never blocks on the compositor's fence. The next call that needs
        /// the frame finished (endFrame, waitFrame, read*, writeReservoirs, a swapchain write through
        /// this compositor, destruction) waits for it; waitFrame() also fills the GPU times.
        Submit,
        /// Record into the caller's primary command buffer (recording, from a pool of the context's
        /// queue family) and return; the caller submits it on that queue family, after its own
        /// writes of the inputs and before its reads of the output (the recorded work starts with a
        /// barrier against all earlier work on the queue and ends with one making the output
        /// visible to all later commands), and must see that submission complete before its next
        /// call into this compositor or its swapchains. No GPU times, no copy kernels.
        Record,
    };
    Mode mode = Mode::Wait;
    /// Submit: semaphores the compositor's submission waits for, each with the stages that wait
    /// (VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT covers every pass), and semaphores it signals.
    std::span<const VkSemaphore> waitSemaphores;
    std::span<const VkPipelineStageFlags> waitStages;
    std::span<const VkSemaphore> signalSemaphores;
    /// Record: the command buffer.
    VkCommandBuffer commandBuffer = VK_NULL_HANDLE;
};

}  // namespace wrsfov
