// One frame's work as the stages of Compositor::endFrame hand it on (compositor.cpp: accept, allocate,
// plan, inputs, submit, keep; record.cpp: record), and what those stages read its images with.
// Internal to the compositor.
#pragma once

#include <array>
#include <string>
#include <utility>

#include "compositor/compositor.h"
#include "compositor/swapchain_vk.h"

namespace wrsfov {

/// One frame's work, as the stages of endFrame hand it on.
struct Compositor::FrameWork {
    bool record = false;  ///< FrameSubmission::Mode::Record: into the caller's command buffer
    layers::SubmittedFoveation kind = layers::SubmittedFoveation::Full;
    uint32_t w = 0, h = 0;  ///< the output's size per eye
    bool hasDepth = false, hasMotion = false;
    CompositorConfig next;  ///< the configuration the frame runs
    TrafficInputs trafficIn;
    /// Frames submitted foveated: the compose pass's sources (eye, or 2 + eye for the insets).
    std::array<VkImageView, 4> srcColor{}, srcDepth{}, srcMotion{};
    std::array<VkImageView, 2> srcRate{};
    PassPlan passes;
    VkDescriptorSet set = VK_NULL_HANDLE;  ///< the passes' set, the frame's images bound
    uint32_t eyes = WRS_EYES;              ///< the eyes the passes run for (1 with mono views)
    bool mono = false;
    bool inPlace = false, tiled = false, sparse = false, steady = false;
    uint32_t written = 0;  ///< the reservoir buffer the frame writes
    uint32_t tilesPerEye = 0;
    /// What planFrame and bindInputs change, as it was before them: restorePlan puts it back where the
    /// frame fails before the queue takes it (a pipeline the driver cannot make), so that the frame
    /// changes nothing a later one reads.
    struct Before {
        CompositorConfig config, pending, frame;
        bool configPending = false, historyValid = false, steadyValid = false;
        layers::SubmittedFoveation submitted = layers::SubmittedFoveation::Full;
        FoveationMode lastFoveation = FoveationMode::Mip;
        std::array<glm::vec4, 2> lastOffsets{};
        FrameStats stats;
        gpu::FrameParams params{};
        gpu::ComposeParams composeParams{};  ///< taken by allocateFrame, which sets the frame's
    } before;
    bool queued = false;  ///< the queue took the frame's submission (Record mode: the caller's buffer holds it)
};

namespace detail {

/// Every image a view reads, with its name for messages (nullptr where the view has none).
std::array<std::pair<const layers::SubImage*, const char*>, 8> subImagesOf(const layers::ProjectionView& v);

inline const VulkanSwapchain* vkSwapchain(const layers::SubImage& s) {
    return dynamic_cast<const VulkanSwapchain*>(s.swapchain);
}

/// The view the passes sample of a sub-image's last released image.
inline VkImageView sampledView(const layers::SubImage& s) {
    const VulkanSwapchain* vs = vkSwapchain(s);
    return vs->sampledView(uint32_t(vs->lastReleased()), s.arrayIndex);
}

inline Error submitError(layers::SubmitError code, std::string msg) {
    return Error{static_cast<int>(code), std::move(msg)};
}

}  // namespace detail
}  // namespace wrsfov
