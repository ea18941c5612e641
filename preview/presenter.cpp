#include "preview/presenter.h"

#include <algorithm>
#include <cstring>
#include <string>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <opencv2/imgproc.hpp>

#include "panel_spv.h"
#include "shaders/config.h"

namespace wrsfov::preview {

std::array<EyeOverlay, 2> eyeOverlays(const Compositor& compositor) {
    std::array<EyeOverlay, 2> eyes;
    const gpu::FrameParams& p = compositor.lastParams();
    for (int e = 0; e < 2; ++e) {
        eyes[e].fovTan = p.eye[e].fov_tan;
        eyes[e].gaze = p.eye[e].gaze;
        eyes[e].midRadiusDeg = p.tuning.x;
        eyes[e].gazeValid = !compositor.stats().gazeFallback[e];
    }
    return eyes;
}

namespace {

Error presentError(const std::string& what, VkResult r) {
    return Error{static_cast<int>(r), what + " failed: " + vk::resultString(r)};
}

constexpr float kMarkerRadiusPx = 2.5f;  // the gaze marker's disc; a black ring 1.25 px wide around it

uint32_t groups(uint32_t n, uint32_t size) { return (n + size - 1) / size; }

bool isSrgb(VkFormat f) { return f == VK_FORMAT_B8G8R8A8_SRGB || f == VK_FORMAT_R8G8B8A8_SRGB; }

void imageBarrier(VkCommandBuffer cb, VkImage image, VkImageLayout from, VkImageLayout to,
                  VkPipelineStageFlags srcStage, VkAccessFlags srcAccess, VkPipelineStageFlags dstStage,
                  VkAccessFlags dstAccess) {
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = srcAccess;
    b.dstAccessMask = dstAccess;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cb, srcStage, dstStage, 0, 0, nullptr, 0, nullptr, 1, &b);
}

}  // namespace

Result<std::unique_ptr<Presenter>> Presenter::create(vk::Context& ctx, GLFWwindow* window) {
    std::unique_ptr<Presenter> p(new Presenter(ctx, window));
    if (Status s = p->init(); !s) return s.error();
    return p;
}

Status Presenter::init() {
    if (VkResult r = glfwCreateWindowSurface(ctx_.instance(), window_, nullptr, &surface_); r != VK_SUCCESS)
        return presentError("glfwCreateWindowSurface", r);
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(ctx_.physicalDevice(), ctx_.queueFamily(), surface_, &supported);
    if (!supported)
        return Error{1, "the Vulkan queue of " + ctx_.deviceName() + " cannot present to this window's surface"};

    auto setLayout = ctx_.createSetLayout({
        {0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
        {4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr},
    });
    if (!setLayout) return setLayout.error();
    setLayout_ = std::move(*setLayout);
    auto pipelineLayout =
        ctx_.createPipelineLayout(setLayout_.get(), sizeof(gpu::PanelPush), VK_SHADER_STAGE_COMPUTE_BIT);
    if (!pipelineLayout) return pipelineLayout.error();
    pipelineLayout_ = std::move(*pipelineLayout);
    auto module = ctx_.createShaderModule(panel_spv, sizeof(panel_spv));
    if (!module) return module.error();
    module_ = std::move(*module);
    VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpi.stage.module = module_.get();
    cpi.stage.pName = "main";
    cpi.layout = pipelineLayout_.get();
    VkPipeline pipe;
    VK_CHECK(vkCreateComputePipelines(ctx_.device(), VK_NULL_HANDLE, 1, &cpi, nullptr, &pipe));
    pipeline_ = vk::Pipeline(ctx_.device(), pipe);

    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler;
    VK_CHECK(vkCreateSampler(ctx_.device(), &sci, nullptr, &sampler));
    sampler_ = vk::Sampler(ctx_.device(), sampler);

    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2 * kFramesInFlight},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2 * kFramesInFlight},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kFramesInFlight}};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = kFramesInFlight;
    dpi.poolSizeCount = 3;
    dpi.pPoolSizes = sizes;
    VkDescriptorPool pool;
    VK_CHECK(vkCreateDescriptorPool(ctx_.device(), &dpi, nullptr, &pool));
    pool_ = vk::DescriptorPool(ctx_.device(), pool);

    for (Slot& s : slots_) {
        auto cmd = ctx_.allocateCommandBuffer();
        if (!cmd) return cmd.error();
        s.cmd = *cmd;
        VkSemaphoreCreateInfo smi{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VK_CHECK(vkCreateSemaphore(ctx_.device(), &smi, nullptr, &s.imageAvailable));
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        fci.flags = VK_FENCE_CREATE_SIGNALED_BIT;
        VK_CHECK(vkCreateFence(ctx_.device(), &fci, nullptr, &s.inFlight));
        VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        ai.descriptorPool = pool_.get();
        ai.descriptorSetCount = 1;
        VkDescriptorSetLayout sl = setLayout_.get();
        ai.pSetLayouts = &sl;
        VK_CHECK(vkAllocateDescriptorSets(ctx_.device(), &ai, &s.set));
    }
    auto made = createSwapchain();
    if (!made) return made.error();
    return {};
}

Presenter::~Presenter() {
    VkDevice d = ctx_.device();
    vkDeviceWaitIdle(d);
    for (Slot& s : slots_) {
        if (s.cmd) ctx_.freeCommandBuffer(s.cmd);
        if (s.imageAvailable) vkDestroySemaphore(d, s.imageAvailable, nullptr);
        if (s.inFlight) vkDestroyFence(d, s.inFlight, nullptr);
    }
    destroySwapchain();
    if (surface_) vkDestroySurfaceKHR(ctx_.instance(), surface_, nullptr);
}

void Presenter::destroySwapchain() {
    for (VkSemaphore s : renderFinished_) vkDestroySemaphore(ctx_.device(), s, nullptr);
    renderFinished_.clear();
    images_.clear();
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

Result<bool> Presenter::createSwapchain() {
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window_, &fbw, &fbh);
    VkPhysicalDevice pd = ctx_.physicalDevice();
    VkSurfaceCapabilitiesKHR caps;
    if (VkResult r = vkGetPhysicalDeviceSurfaceCapabilitiesKHR(pd, surface_, &caps); r != VK_SUCCESS)
        return presentError("vkGetPhysicalDeviceSurfaceCapabilitiesKHR", r);
    VkExtent2D extent = caps.currentExtent;
    if (extent.width == UINT32_MAX) {
        extent.width = std::clamp(uint32_t(std::max(fbw, 0)), caps.minImageExtent.width, caps.maxImageExtent.width);
        extent.height = std::clamp(uint32_t(std::max(fbh, 0)), caps.minImageExtent.height, caps.maxImageExtent.height);
    }
    if (extent.width == 0 || extent.height == 0 || fbw == 0 || fbh == 0) return false;  // minimised
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_DST_BIT))
        return Error{1, "the window surface's images cannot be written by a transfer (no TRANSFER_DST usage)"};

    if (!swapchain_) {
        // First creation: pick the format. The preview image holds sRGB-encoded values, so a UNORM
        // swapchain shows them as they are; an sRGB one is fed by an sRGB image (the blit decodes
        // and re-encodes).
        uint32_t n = 0;
        vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface_, &n, nullptr);
        std::vector<VkSurfaceFormatKHR> formats(n);
        vkGetPhysicalDeviceSurfaceFormatsKHR(pd, surface_, &n, formats.data());
        auto blitDst = [&](VkFormat f) {
            VkFormatProperties fp;
            vkGetPhysicalDeviceFormatProperties(pd, f, &fp);
            return (fp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_DST_BIT) != 0;
        };
        bool found = false;
        for (VkFormat want :
             {VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB}) {
            for (const VkSurfaceFormatKHR& f : formats)
                if (f.format == want && f.colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR && blitDst(want)) {
                    format_ = f;
                    found = true;
                    break;
                }
            if (found) break;
        }
        if (!found)
            return Error{1,
                         "the window surface offers no 8-bit RGBA/BGRA format in the sRGB colour space that a "
                         "blit can write"};
        targetFormat_ = isSrgb(format_.format) ? VK_FORMAT_R8G8B8A8_SRGB : VK_FORMAT_R8G8B8A8_UNORM;
        VkFormatProperties tp;
        vkGetPhysicalDeviceFormatProperties(pd, targetFormat_, &tp);
        if (!(tp.optimalTilingFeatures & VK_FORMAT_FEATURE_BLIT_SRC_BIT))
            return Error{1, "the device cannot blit from " + std::string(isSrgb(targetFormat_) ? "sRGB" : "UNORM") +
                                " RGBA8 images"};
        linearBlit_ = (tp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT) != 0;
    }

    uint32_t count = std::max(caps.minImageCount + 1, 2u);
    if (caps.maxImageCount > 0) count = std::min(count, caps.maxImageCount);
    VkSwapchainCreateInfoKHR sci{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    sci.surface = surface_;
    sci.minImageCount = count;
    sci.imageFormat = format_.format;
    sci.imageColorSpace = format_.colorSpace;
    sci.imageExtent = extent;
    sci.imageArrayLayers = 1;
    sci.imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    sci.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    sci.preTransform = caps.currentTransform;
    sci.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    for (VkCompositeAlphaFlagBitsKHR a :
         {VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR, VK_COMPOSITE_ALPHA_INHERIT_BIT_KHR,
          VK_COMPOSITE_ALPHA_PRE_MULTIPLIED_BIT_KHR, VK_COMPOSITE_ALPHA_POST_MULTIPLIED_BIT_KHR})
        if (caps.supportedCompositeAlpha & a) {
            sci.compositeAlpha = a;
            break;
        }
    sci.presentMode = VK_PRESENT_MODE_FIFO_KHR;  // always available; paces the loop to the display
    sci.clipped = VK_TRUE;
    VkSwapchainKHR old = swapchain_;
    sci.oldSwapchain = old;
    VkSwapchainKHR made = VK_NULL_HANDLE;
    VkResult r = vkCreateSwapchainKHR(ctx_.device(), &sci, nullptr, &made);
    // The old swapchain is retired either way; its images are no longer acquired by us.
    for (VkSemaphore s : renderFinished_) vkDestroySemaphore(ctx_.device(), s, nullptr);
    renderFinished_.clear();
    if (old) vkDestroySwapchainKHR(ctx_.device(), old, nullptr);
    swapchain_ = VK_NULL_HANDLE;
    if (r != VK_SUCCESS) return presentError("vkCreateSwapchainKHR", r);
    swapchain_ = made;
    extent_ = extent;

    uint32_t n = 0;
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, nullptr);
    images_.resize(n);
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, images_.data());
    renderFinished_.resize(n);
    for (VkSemaphore& s : renderFinished_) {
        VkSemaphoreCreateInfo smi{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VK_CHECK(vkCreateSemaphore(ctx_.device(), &smi, nullptr, &s));
    }
    return true;
}

Status Presenter::ensureTargets(const Layout& layout) {
    if (layout.width == targetWidth_ && layout.height == targetHeight_ && layout.stripHeight == stripHeight_ &&
        layout.eyeWidth == eyeWidth_ && layout.eyeHeight == eyeHeight_)
        return {};
    for (Slot& s : slots_)
        if (VkResult r = vkWaitForFences(ctx_.device(), 1, &s.inFlight, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
            return presentError("waiting for a frame in flight", r);
    vk::ImageCreateInfo ici;
    ici.format = targetFormat_;
    ici.width = layout.width;
    ici.height = layout.height;
    ici.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    // An sRGB image is written through a UNORM view (the shader stores encoded values).
    if (isSrgb(targetFormat_)) ici.flags = VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT | VK_IMAGE_CREATE_EXTENDED_USAGE_BIT;
    for (Slot& s : slots_) {
        s.target.reset();
        s.strip.reset();
        s.visible.reset();
        auto img = ctx_.createImage(ici, VK_FORMAT_R8G8B8A8_UNORM);
        if (!img) return img.error();
        s.target = std::move(*img);
        auto buf = ctx_.createBuffer(VkDeviceSize(layout.width) * layout.stripHeight * 4,
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        if (!buf) return buf.error();
        s.strip = std::move(*buf);
        auto vis = ctx_.createBuffer(VkDeviceSize(layout.eyeWidth) * layout.eyeHeight * 2 * sizeof(float),
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
        if (!vis) return vis.error();
        s.visible = std::move(*vis);
    }
    Status st = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        for (Slot& s : slots_) {
            imageBarrier(cb, s.target.handle(), VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_GENERAL,
                         VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_ACCESS_TRANSFER_WRITE_BIT);
            VkClearColorValue black{};
            VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(cb, s.target.handle(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &range);
        }
    });
    if (!st) return st;
    targetWidth_ = layout.width;
    targetHeight_ = layout.height;
    stripHeight_ = layout.stripHeight;
    eyeWidth_ = layout.eyeWidth;
    eyeHeight_ = layout.eyeHeight;
    lastSlot_ = -1;
    return {};
}

Result<PresentOutcome> Presenter::present(const ComposeFrame& f) {
    const Layout& layout = *f.layout;
    if (resized_ || needRecreate_ || !swapchain_) {
        VK_CHECK(vkDeviceWaitIdle(ctx_.device()));
        auto made = createSwapchain();
        if (!made) return made.error();
        if (!*made) return PresentOutcome::Skipped;  // no area (minimised): try again later
        reason_ = resized_ ? "window resized" : pendingReason_;
        resized_ = needRecreate_ = false;
        ++recreations_;
    }
    if (Status s = ensureTargets(layout); !s) return s.error();

    Slot& slot = slots_[frame_ % kFramesInFlight];
    if (VkResult r = vkWaitForFences(ctx_.device(), 1, &slot.inFlight, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
        return presentError("waiting for a frame in flight", r);
    uint32_t index = 0;
    VkResult acq =
        vkAcquireNextImageKHR(ctx_.device(), swapchain_, UINT64_MAX, slot.imageAvailable, VK_NULL_HANDLE, &index);
    if (acq == VK_ERROR_OUT_OF_DATE_KHR) {
        needRecreate_ = true;
        pendingReason_ =
            "VK_ERROR_OUT_OF_DATE_KHR";  // nothing was signalled; the fence stays signalled for the next try
        return PresentOutcome::Skipped;
    }
    if (acq != VK_SUCCESS && acq != VK_SUBOPTIMAL_KHR) return presentError("vkAcquireNextImageKHR", acq);
    if (acq == VK_SUBOPTIMAL_KHR) {  // still presentable: show this one, recreate after
        needRecreate_ = true;
        pendingReason_ = "VK_SUBOPTIMAL_KHR";
    }
    VK_CHECK(vkResetFences(ctx_.device(), 1, &slot.inFlight));

    // The stats strip, written by the CPU while nothing reads this slot.
    if (f.strip && f.strip->cols == int(layout.width) && f.strip->rows == int(layout.stripHeight) &&
        f.strip->type() == CV_8UC4 && f.strip->isContinuous())
        std::memcpy(slot.strip.mapped(), f.strip->data, size_t(layout.width) * layout.stripHeight * 4);
    else
        std::memset(slot.strip.mapped(), 0, size_t(layout.width) * layout.stripHeight * 4);

    // The visible distortion of each eye, likewise; black where there is none.
    const size_t eyePixels = size_t(layout.eyeWidth) * layout.eyeHeight;
    for (size_t e = 0; e < 2; ++e) {
        auto* dst = static_cast<float*>(slot.visible.mapped()) + e * eyePixels;
        const cv::Mat* m = f.visible[e];
        if (m && m->cols == int(layout.eyeWidth) && m->rows == int(layout.eyeHeight) && m->type() == CV_32F &&
            m->isContinuous())
            std::memcpy(dst, m->data, eyePixels * sizeof(float));
        else
            std::fill(dst, dst + eyePixels, 0.0f);
    }

    const vk::Image& ref = f.reference ? *f.reference : *f.output;
    VkDescriptorImageInfo ii[2] = {{sampler_.get(), f.output->arrayView(), VK_IMAGE_LAYOUT_GENERAL},
                                   {sampler_.get(), ref.arrayView(), VK_IMAGE_LAYOUT_GENERAL}};
    VkDescriptorBufferInfo bi{slot.strip.handle(), 0, VK_WHOLE_SIZE};
    VkDescriptorImageInfo ti{VK_NULL_HANDLE, slot.target.layerView(0), VK_IMAGE_LAYOUT_GENERAL};
    VkDescriptorBufferInfo vi{slot.visible.handle(), 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w[5] = {vk::imageWrite(slot.set, 0, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &ii[0]),
                                 vk::imageWrite(slot.set, 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &ii[1]),
                                 vk::bufferWrite(slot.set, 2, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi),
                                 vk::imageWrite(slot.set, 3, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &ti),
                                 vk::bufferWrite(slot.set, 4, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &vi)};
    vkUpdateDescriptorSets(ctx_.device(), 5, w, 0, nullptr);

    VkCommandBuffer cb = slot.cmd;
    VK_CHECK(vkResetCommandBuffer(cb, 0));
    VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VK_CHECK(vkBeginCommandBuffer(cb, &begin));
    // The compositors' passes (earlier submissions) wrote the outputs; earlier blits read this target.
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_.get(), 0, 1, &slot.set, 0, nullptr);
    auto dispatch = [&](const gpu::PanelPush& push, uint32_t w, uint32_t h) {
        vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cb, groups(w, WRS_GROUP_X), groups(h, WRS_GROUP_Y), 1);
    };
    for (const Panel& p : layout.panels) {
        const EyeOverlay& eo = f.eyes[p.eye];
        gpu::PanelPush push{};
        push.panel = glm::ivec4(int(p.x), int(p.y), int(p.kind), int(p.eye));
        uint32_t flags = (f.circles ? WRS_PANEL_CIRCLES : 0u) | (f.marker && eo.gazeValid ? WRS_PANEL_MARKER : 0u);
        push.size = glm::uvec4(layout.eyeWidth, layout.eyeHeight, layout.width, flags);
        push.fov_tan = eo.fovTan;
        push.gaze = eo.gaze;
        push.radii = glm::vec4(eo.midRadiusDeg, f.errorGain, kMarkerRadiusPx, f.visibleGain);
        dispatch(push, layout.eyeWidth, layout.eyeHeight);
    }
    // Panels that a view leaves empty (none today) and the strip.
    gpu::PanelPush strip{};
    strip.panel = glm::ivec4(0, int(layout.stripY), int(WRS_PANEL_STRIP), 0);
    strip.size = glm::uvec4(layout.width, layout.stripHeight, layout.width, 0);
    dispatch(strip, layout.width, layout.stripHeight);

    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    // The swapchain image: whatever it held is discarded (its wait is the acquire semaphore, at transfer).
    VkImage dst = images_[index];
    imageBarrier(cb, dst, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkClearColorValue black{};
    VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdClearColorImage(cb, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &black, 1, &range);
    imageBarrier(cb, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                 VK_ACCESS_TRANSFER_WRITE_BIT);
    placement_ = placeInWindow(layout.width, layout.height, extent_.width, extent_.height);
    VkImageBlit blit{};
    blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.srcOffsets[1] = {int32_t(layout.width), int32_t(layout.height), 1};
    blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    blit.dstOffsets[0] = {placement_.x, placement_.y, 0};
    blit.dstOffsets[1] = {placement_.x + int32_t(placement_.width), placement_.y + int32_t(placement_.height), 1};
    const bool scaled = placement_.width != layout.width || placement_.height != layout.height;
    vkCmdBlitImage(cb, slot.target.handle(), VK_IMAGE_LAYOUT_GENERAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                   &blit, scaled && linearBlit_ ? VK_FILTER_LINEAR : VK_FILTER_NEAREST);
    imageBarrier(cb, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
                 VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0);
    VK_CHECK(vkEndCommandBuffer(cb));

    VkPipelineStageFlags waitStage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.waitSemaphoreCount = 1;
    si.pWaitSemaphores = &slot.imageAvailable;
    si.pWaitDstStageMask = &waitStage;
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    si.signalSemaphoreCount = 1;
    si.pSignalSemaphores = &renderFinished_[index];
    if (VkResult r = vkQueueSubmit(ctx_.queue(), 1, &si, slot.inFlight); r != VK_SUCCESS)
        return presentError("vkQueueSubmit (preview)", r);
    lastSlot_ = int(frame_ % kFramesInFlight);
    ++frame_;

    VkPresentInfoKHR pi{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    pi.waitSemaphoreCount = 1;
    pi.pWaitSemaphores = &renderFinished_[index];
    pi.swapchainCount = 1;
    pi.pSwapchains = &swapchain_;
    pi.pImageIndices = &index;
    VkResult pr = vkQueuePresentKHR(ctx_.queue(), &pi);
    if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR) {
        needRecreate_ = true;
        pendingReason_ = vk::resultString(pr);
    } else if (pr != VK_SUCCESS) {
        return presentError("vkQueuePresentKHR", pr);
    }
    return PresentOutcome::Presented;
}

Result<cv::Mat> Presenter::lastImage() {
    if (lastSlot_ < 0) return Error{1, "no preview image has been composed yet"};
    const Slot& s = slots_[lastSlot_];
    const size_t bytes = size_t(targetWidth_) * targetHeight_ * 4;
    auto data =
        ctx_.readImageLayer(s.target.handle(), VK_IMAGE_ASPECT_COLOR_BIT, 0, targetWidth_, targetHeight_, bytes);
    if (!data) return data.error();
    cv::Mat rgba(int(targetHeight_), int(targetWidth_), CV_8UC4, data->data());
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    return bgr;
}

}  // namespace wrsfov::preview
