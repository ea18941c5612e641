#include "compositor/swapchain_vk.h"

#include "compositor/compositor.h"

#include <cstring>
#include <string>

namespace wrsfov {

using layers::Format;
using layers::SwapchainError;
using layers::Usage;

namespace {
Error err(SwapchainError code, std::string msg) { return Error{static_cast<int>(code), std::move(msg)}; }
}  // namespace

Result<std::unique_ptr<VulkanSwapchain>> VulkanSwapchain::create(vk::Context& ctx, const Compositor* owner,
                                                                 const layers::SwapchainCreateInfo& info,
                                                                 const SwapchainImageOptions& options) {
    if (Status s = layers::validateCreateInfo(info); !s) return s.error();
    std::unique_ptr<VulkanSwapchain> sc(new VulkanSwapchain(ctx, owner, info));
    sc->restingLayout_ = options.restingLayout;

    vk::ImageCreateInfo ici;
    ici.format = layers::toVkFormat(info.format);
    ici.width = info.width;
    ici.height = info.height;
    ici.layers = info.arraySize;
    ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
    ici.usage |=
        info.format == Format::D32F ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT;
    VkFormat viewFormat = VK_FORMAT_UNDEFINED;
    ici.usage |= options.usage;
    ici.flags = options.flags;
    // The compositor's own sRGB images are MUTABLE_FORMAT, read through UNORM views, unless the maker
    // asks for its flags alone (a runtime's strict setting: as Monado 21 makes them).
    if (info.format == Format::RGBA8_SRGB && !options.exactFlags) ici.flags |= VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT;
    sc->chooseViews(ici.flags, viewFormat);
    for (uint32_t i = 0; i < info.imageCount; ++i) {
        auto img = ctx.createImage(ici, viewFormat);
        if (!img) return err(SwapchainError::DeviceFailure, img.error().message);
        sc->images_.push_back(std::move(*img));
    }
    if (!options.deferInitialization)
        if (Status s = sc->prepare(); !s) return s.error();
    return sc;
}

Result<std::unique_ptr<VulkanSwapchain>> VulkanSwapchain::import(vk::Context& ctx, const Compositor* owner,
                                                                 const layers::SwapchainCreateInfo& info,
                                                                 std::span<const VkImage> images,
                                                                 const SwapchainImageOptions& options) {
    if (Status s = layers::validateCreateInfo(info); !s) return s.error();
    if (images.size() != info.imageCount)
        return err(SwapchainError::InvalidCreateInfo, std::to_string(images.size()) + " images imported for a swapchain of " +
                                                          std::to_string(info.imageCount));
    std::unique_ptr<VulkanSwapchain> sc(new VulkanSwapchain(ctx, owner, info));
    sc->restingLayout_ = options.restingLayout;
    sc->prepared_ = true;  // the owner keeps them initialised, in the resting layout
    vk::ImageCreateInfo ici;
    ici.format = layers::toVkFormat(info.format);
    ici.width = info.width;
    ici.height = info.height;
    ici.layers = info.arraySize;
    // The compositor samples them: its views ask for no other usage. An sRGB image is read through a
    // UNORM view only where its owner says it made it MUTABLE_FORMAT.
    ici.usage = VK_IMAGE_USAGE_SAMPLED_BIT;
    ici.flags = options.flags;
    VkFormat viewFormat = VK_FORMAT_UNDEFINED;
    sc->chooseViews(options.flags, viewFormat);
    for (VkImage image : images) {
        auto img = ctx.wrapImage(image, ici, viewFormat);
        if (!img) return err(SwapchainError::DeviceFailure, img.error().message);
        sc->images_.push_back(std::move(*img));
    }
    return sc;
}

void VulkanSwapchain::chooseViews(VkImageCreateFlags flags, VkFormat& viewFormat) {
    viewFormat = VK_FORMAT_UNDEFINED;
    encoding_ = gpu::WRS_INPUT_LINEAR;
    if (info().format != Format::RGBA8_SRGB) return;
    // A UNORM view of an sRGB image is valid only if the image was made MUTABLE_FORMAT
    // (VUID-VkImageViewCreateInfo-image-01019); a runtime may ignore XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT
    // (Monado 21 does). Without it the image is read through an sRGB view and the device decodes.
    const bool mutableFormat = (flags & VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT) != 0;
    viewFormat = mutableFormat ? VK_FORMAT_R8G8B8A8_UNORM : VK_FORMAT_R8G8B8A8_SRGB;
    encoding_ = mutableFormat ? gpu::WRS_INPUT_SRGB : gpu::WRS_INPUT_SRGB_VIEW;
}

Status VulkanSwapchain::prepare() {
    if (prepared_) return {};
    const layers::SwapchainCreateInfo& info = this->info();
    VulkanSwapchain* sc = this;
    // Start the images cleared to zero, in their resting layout.
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        for (auto& img : sc->images_) {
            VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
            b.srcAccessMask = 0;
            b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
            b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
            b.newLayout = VK_IMAGE_LAYOUT_GENERAL;
            b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
            b.image = img.handle();
            b.subresourceRange = {img.aspect(), 0, 1, 0, info.arraySize};
            vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr,
                                 0, nullptr, 1, &b);
            if (img.aspect() == VK_IMAGE_ASPECT_DEPTH_BIT) {
                VkClearDepthStencilValue z{0.0f, 0};
                vkCmdClearDepthStencilImage(cb, img.handle(), VK_IMAGE_LAYOUT_GENERAL, &z, 1, &b.subresourceRange);
            } else {
                VkClearColorValue c{};
                vkCmdClearColorImage(cb, img.handle(), VK_IMAGE_LAYOUT_GENERAL, &c, 1, &b.subresourceRange);
            }
            if (sc->restingLayout_ != VK_IMAGE_LAYOUT_GENERAL) {
                b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
                b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
                b.oldLayout = VK_IMAGE_LAYOUT_GENERAL;
                b.newLayout = sc->restingLayout_;
                vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0,
                                     nullptr, 0, nullptr, 1, &b);
            }
        }
    });
    if (!s) return err(SwapchainError::DeviceFailure, s.message());
    prepared_ = true;
    return {};
}

Status VulkanSwapchain::write(uint32_t index, uint32_t arrayLayer, std::span<const std::byte> texels) {
    const auto& in = info();
    if (index >= in.imageCount || arrayLayer >= in.arraySize)
        return err(SwapchainError::WriteOutOfRange, "write to image " + std::to_string(index) + " layer " +
                                                        std::to_string(arrayLayer) + " of a swapchain with " +
                                                        std::to_string(in.imageCount) + " images of " +
                                                        std::to_string(in.arraySize) + " layers");
    std::size_t expect = std::size_t(in.width) * in.height * layers::bytesPerTexel(in.format);
    if (texels.size() != expect)
        return err(SwapchainError::WriteOutOfRange, "write of " + std::to_string(texels.size()) + " bytes to a " +
                                                        std::to_string(in.width) + "x" + std::to_string(in.height) +
                                                        " " + std::string(layers::toString(in.format)) +
                                                        " image that takes " + std::to_string(expect));
    if (!isWaited(index))
        return err(SwapchainError::CallOrder,
                   "write to image " + std::to_string(index) + ", which is not acquired and waited for");
    auto staging = ctx_.createBuffer(expect, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!staging) return err(SwapchainError::DeviceFailure, staging.error().message);
    std::memcpy(staging->mapped(), texels.data(), expect);
    const vk::Image& img = images_[index];
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_TRANSFER_WRITE_BIT);
        vk::layoutTransition(cb, img.handle(), img.aspect(), in.arraySize, restingLayout_, VK_IMAGE_LAYOUT_GENERAL);
        VkBufferImageCopy region{};
        region.imageSubresource = {img.aspect(), 0, arrayLayer, 1};
        region.imageExtent = {in.width, in.height, 1};
        vkCmdCopyBufferToImage(cb, staging->handle(), img.handle(), VK_IMAGE_LAYOUT_GENERAL, 1, &region);
        vk::layoutTransition(cb, img.handle(), img.aspect(), in.arraySize, VK_IMAGE_LAYOUT_GENERAL, restingLayout_);
    });
    if (!s) return err(SwapchainError::DeviceFailure, s.message());
    return {};
}

Result<std::vector<std::byte>> VulkanSwapchain::read(uint32_t index, uint32_t arrayLayer) {
    const auto& in = info();
    if (index >= in.imageCount || arrayLayer >= in.arraySize)
        return err(SwapchainError::WriteOutOfRange, "read of image " + std::to_string(index) + " layer " +
                                                        std::to_string(arrayLayer) + " is out of range");
    std::size_t bytes = std::size_t(in.width) * in.height * layers::bytesPerTexel(in.format);
    const vk::Image& img = images_[index];
    auto r = ctx_.readImageLayer(img.handle(), img.aspect(), arrayLayer, in.width, in.height, bytes, restingLayout_);
    if (!r) return err(SwapchainError::DeviceFailure, r.error().message);
    return std::move(*r);
}

Result<std::vector<std::byte>> VulkanSwapchain::readTexel(uint32_t index, uint32_t arrayLayer, uint32_t x,
                                                          uint32_t y) {
    const auto& in = info();
    if (index >= in.imageCount || arrayLayer >= in.arraySize || x >= in.width || y >= in.height)
        return err(SwapchainError::WriteOutOfRange, "read of texel (" + std::to_string(x) + ", " + std::to_string(y) +
                                                        ") of image " + std::to_string(index) + " is out of range");
    const vk::Image& img = images_[index];
    auto r = ctx_.readImageRegion(img.handle(), img.aspect(), arrayLayer, {int32_t(x), int32_t(y)}, {1, 1},
                                  layers::bytesPerTexel(in.format), restingLayout_);
    if (!r) return err(SwapchainError::DeviceFailure, r.error().message);
    return std::move(*r);
}

}  // namespace wrsfov
