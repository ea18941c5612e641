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

    /// The view the compositor samples: an sRGB image made MUTABLE_FORMAT (by the compositor, or by
    /// an owner that says so in SwapchainImageOptions::flags) is viewed as UNORM, any other through a
    /// view of its own sRGB format; the passes decode either to the same bits (shaders/wrs_input.h).
    VkImageView sampledView(uint32_t index, uint32_t layer) const { return images_.at(index).layerView(layer); }
    /// How the passes read the colour of sampledView(): gpu::WRS_INPUT_LINEAR, WRS_INPUT_SRGB (a UNORM
    /// view of sRGB codes) or WRS_INPUT_SRGB_VIEW (decoded by the device).
    uint32_t colorEncoding() const { return encoding_; }
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
    uint32_t encoding_ = 0;  // gpu::WRS_INPUT_LINEAR
    bool prepared_ = false;
    /// The format of the views made of images created with `flags`, and the encoding they are read as.
    void chooseViews(VkImageCreateFlags flags, VkFormat& viewFormat);
};

}  // namespace wrsfov
