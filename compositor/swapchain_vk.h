// Swapchain images on the compositor's device (internal to compositor/).
#pragma once

#include <span>
#include <vector>

#include "compositor/vk_context.h"
#include "layers/swapchain.h"

namespace wrsfov {

class Compositor;
struct SwapchainImageOptions;

class VulkanSwapchain final : public layers::Swapchain {
public:
    static Result<std::unique_ptr<VulkanSwapchain>> create(vk::Context& ctx, const Compositor* owner,
                                                           const layers::SwapchainCreateInfo& info,
                                                           const SwapchainImageOptions& options);
    /// A swapchain over images someone else made on ctx's device (see Compositor::importSwapchain).
    static Result<std::unique_ptr<VulkanSwapchain>> import(vk::Context& ctx, const Compositor* owner,
                                                           const layers::SwapchainCreateInfo& info,
                                                           std::span<const VkImage> images,
                                                           const SwapchainImageOptions& options);

    Status write(uint32_t index, uint32_t arrayLayer, std::span<const std::byte> texels) override;
    Result<std::vector<std::byte>> read(uint32_t index, uint32_t arrayLayer) override;
    /// One texel of one layer (bytesPerTexel(format) bytes), e.g. the depth under the gaze.
    Result<std::vector<std::byte>> readTexel(uint32_t index, uint32_t arrayLayer, uint32_t x, uint32_t y);
    VkImage image(uint32_t index) const override { return images_.at(index).handle(); }

    /// The view the compositor samples: sRGB images are viewed as UNORM (the load pass decodes
    /// with the shared sRGB function, so the GPU matches the CPU reference).
    VkImageView sampledView(uint32_t index, uint32_t layer) const { return images_.at(index).layerView(layer); }
    const Compositor* owner() const { return owner_; }
    /// The layout the images are in whenever the compositor is not reading them.
    VkImageLayout restingLayout() const { return restingLayout_; }
    VkImageAspectFlags aspect() const { return images_.front().aspect(); }
    /// Clears the images and moves them to their resting layout (once; create() does it unless
    /// SwapchainImageOptions::deferInitialization). Submits to the context's queue.
    Status prepare();

private:
    VulkanSwapchain(vk::Context& ctx, const Compositor* owner, const layers::SwapchainCreateInfo& info)
        : Swapchain(info), ctx_(ctx), owner_(owner) {}

    vk::Context& ctx_;
    const Compositor* owner_;
    std::vector<vk::Image> images_;
    VkImageLayout restingLayout_ = VK_IMAGE_LAYOUT_GENERAL;
    bool prepared_ = false;
};

}  // namespace wrsfov
