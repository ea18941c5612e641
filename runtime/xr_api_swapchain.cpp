// The runtime's swapchains, on the application's Vulkan device.
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/quaternion.hpp>

#include "compositor/host_app.h"
#include "compositor/input.h"
#include "compositor/reference.h"
#include "compositor/swapchain_vk.h"
#include "gaze/frame_gaze.h"
#include "preview/gaze_input.h"
#include "scenes/png.h"

#include <opencv2/imgcodecs.hpp>
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"
#include "runtime/xr_session.h"

namespace wrsfov::xr {

namespace {
constexpr uint32_t kMaxSize = 8192;
}  // namespace

// ---------------------------------------------------------------------------------------------
// Swapchains

namespace {

struct FormatEntry {
    VkFormat vk;
    layers::Format format;
    layers::Usage usage;
};
// In order of preference (applications take the first they know).
constexpr FormatEntry kFormats[] = {
    {VK_FORMAT_R8G8B8A8_SRGB, layers::Format::RGBA8_SRGB, layers::Usage::Color},
    {VK_FORMAT_R8G8B8A8_UNORM, layers::Format::RGBA8, layers::Usage::Color},
    {VK_FORMAT_R16G16B16A16_SFLOAT, layers::Format::RGBA16F, layers::Usage::Color},
    {VK_FORMAT_D32_SFLOAT, layers::Format::D32F, layers::Usage::Depth},
    {VK_FORMAT_R32_SFLOAT, layers::Format::R32F, layers::Usage::Depth},
    {VK_FORMAT_R16G16_SFLOAT, layers::Format::RG16F, layers::Usage::Motion},
};

// The strict setting offers 8-bit colour as sRGB only (RuntimeConfig::strictSwapchains).
bool offered(const Session& s, const FormatEntry& f) {
    return !(s.instance->config.strictSwapchains && f.format == layers::Format::RGBA8);
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainFormats(XrSession h, uint32_t capacity, uint32_t* countOutput,
                                                           int64_t* formats) {
    if (!getSession(h)) return XR_ERROR_HANDLE_INVALID;
    std::vector<int64_t> v;
    for (const auto& f : kFormats)
        if (offered(*getSession(h), f)) v.push_back(int64_t(f.vk));
    return fillArray(capacity, countOutput, formats, v);
}

XRAPI_ATTR XrResult XRAPI_CALL xrCreateSwapchain(XrSession h, const XrSwapchainCreateInfo* info, XrSwapchain* out) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard gpu(s->gpuMutex);
    if (!info || !out || info->type != XR_TYPE_SWAPCHAIN_CREATE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    const XrSwapchainCreateFlags knownFlags =
        XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT | XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT;
    if (info->createFlags & ~knownFlags) return XR_ERROR_VALIDATION_FAILURE;
    if (info->createFlags & XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT) return XR_ERROR_FEATURE_UNSUPPORTED;
    const FormatEntry* fmt = nullptr;
    for (const auto& f : kFormats)
        if (int64_t(f.vk) == info->format && offered(*s, f)) fmt = &f;
    if (!fmt) return XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED;
    if (info->width == 0 || info->height == 0 || info->width > kMaxSize || info->height > kMaxSize ||
        info->arraySize == 0 || info->faceCount == 0 || info->mipCount == 0 || info->sampleCount == 0)
        return XR_ERROR_VALIDATION_FAILURE;
    if (info->sampleCount != 1 || info->mipCount != 1 || info->faceCount != 1 || info->arraySize > 16)
        return XR_ERROR_FEATURE_UNSUPPORTED;  // single-sampled, one mip level, 2D (array) images
    const bool depth = fmt->format == layers::Format::D32F;
    if ((depth && (info->usageFlags & XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT)) ||
        (!depth && (info->usageFlags & XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT)))
        return XR_ERROR_FEATURE_UNSUPPORTED;

    SwapchainImageOptions options;
    if (info->usageFlags & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT) options.usage |= VK_IMAGE_USAGE_STORAGE_BIT;
    // The strict setting ignores MUTABLE_FORMAT, as Monado 21 does: its sRGB images are read through
    // sRGB views (the compositor adds MUTABLE_FORMAT to its own otherwise).
    const bool strict = s->instance->config.strictSwapchains;
    if ((info->usageFlags & XR_SWAPCHAIN_USAGE_MUTABLE_FORMAT_BIT) && !strict)
        options.flags |= VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT;
    options.exactFlags = strict;
    options.restingLayout =
        depth ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    options.deferInitialization = true;  // cleared at the first acquire: xrCreateSwapchain may not use the queue
    // What the images will be made with (swapchain_vk.cpp adds sampled, transfer and the attachment).
    VkImageUsageFlags usage = options.usage | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                              VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                              (depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT);
    VkImageCreateFlags flags =
        options.flags |
        (fmt->format == layers::Format::RGBA8_SRGB && !strict ? VK_IMAGE_CREATE_MUTABLE_FORMAT_BIT : 0);
    VkImageFormatProperties props;
    if (vkGetPhysicalDeviceImageFormatProperties(s->context->physicalDevice(), fmt->vk, VK_IMAGE_TYPE_2D,
                                                 VK_IMAGE_TILING_OPTIMAL, usage, flags, &props) != VK_SUCCESS ||
        props.maxArrayLayers < info->arraySize || props.maxExtent.width < info->width ||
        props.maxExtent.height < info->height)
        return XR_ERROR_FEATURE_UNSUPPORTED;

    layers::SwapchainCreateInfo ci;
    ci.usage = fmt->usage;
    ci.format = fmt->format;
    ci.width = info->width;
    ci.height = info->height;
    ci.arraySize = info->arraySize;
    ci.imageCount = (info->createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) ? 1 : strict ? 4 : 3;
    ci.anyUse = true;  // an RGBA16F swapchain may carry colour or space-warp motion
    auto images = s->compositor->createSwapchain(ci, options);
    if (!images) {
        logLine("xrCreateSwapchain: " + images.error().message);
        return images.error().code == int(layers::SwapchainError::DeviceFailure) ? XR_ERROR_OUT_OF_MEMORY
                                                                                  : XR_ERROR_VALIDATION_FAILURE;
    }
    auto sc = std::make_unique<Swapchain>();
    sc->session = s;
    sc->info = *info;
    sc->info.next = nullptr;
    sc->format = fmt->format;
    sc->images = std::move(*images);
    sc->readByFrame.assign(ci.imageCount, 0);
    registerObject(sc.get());
    *out = reinterpret_cast<XrSwapchain>(sc.get());
    s->swapchains.push_back(std::move(sc));
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrDestroySwapchain(XrSwapchain h) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    Session* s = sc->session;
    // A frame handed to the compositor may still read the images: they go once it is complete.
    uint64_t lastReader = 0;
    {
        std::lock_guard lock(sc->mutex);
        for (uint64_t f : sc->readByFrame) lastReader = std::max(lastReader, f);
    }
    {
        std::unique_lock frame(s->frameMutex);
        waitForFrame(s, frame, lastReader, XR_INFINITE_DURATION);
    }
    std::lock_guard gpu(s->gpuMutex);
    unregisterObject(sc);
    auto& v = s->swapchains;
    for (auto it = v.begin(); it != v.end(); ++it)
        if (it->get() == sc) {
            v.erase(it);
            break;
        }
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrEnumerateSwapchainImages(XrSwapchain h, uint32_t capacity, uint32_t* countOutput,
                                                          XrSwapchainImageBaseHeader* images) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard lock(sc->mutex);
    if (!countOutput) return XR_ERROR_VALIDATION_FAILURE;
    const uint32_t n = sc->images->info().imageCount;
    *countOutput = n;
    if (capacity == 0) return XR_SUCCESS;
    if (capacity < n) return XR_ERROR_SIZE_INSUFFICIENT;
    if (!images) return XR_ERROR_VALIDATION_FAILURE;
    auto* vkImages = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
    for (uint32_t i = 0; i < n; ++i)
        if (vkImages[i].type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR) return XR_ERROR_VALIDATION_FAILURE;
    for (uint32_t i = 0; i < n; ++i) vkImages[i].image = sc->images->image(i);
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrAcquireSwapchainImage(XrSwapchain h, const XrSwapchainImageAcquireInfo* info,
                                                       uint32_t* index) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!index || (info && info->type != XR_TYPE_SWAPCHAIN_IMAGE_ACQUIRE_INFO)) return XR_ERROR_VALIDATION_FAILURE;
    std::lock_guard gpu(sc->session->gpuMutex);  // prepare() may use the queue (allowed in this call)
    std::lock_guard lock(sc->mutex);
    if ((sc->info.createFlags & XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT) && sc->acquiredEver > 0)
        return XR_ERROR_CALL_ORDER_INVALID;
    // First use: clear the images and put them in the layout the application expects (the queue may
    // be used here).
    if (Status p = static_cast<VulkanSwapchain*>(sc->images.get())->prepare(); !p) {
        logLine("xrAcquireSwapchainImage: " + p.message());
        return XR_ERROR_RUNTIME_FAILURE;
    }
    auto r = sc->images->acquire();
    if (!r) return XR_ERROR_CALL_ORDER_INVALID;  // every image acquired and not released
    ++sc->acquiredEver;
    sc->acquiredOrder.push_back(*r);
    *index = *r;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrWaitSwapchainImage(XrSwapchain h, const XrSwapchainImageWaitInfo* info) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO) return XR_ERROR_VALIDATION_FAILURE;
    uint64_t reader = 0;
    {
        std::lock_guard lock(sc->mutex);
        // One image at a time is waited for: a second wait before its release is out of order, and
        // changes nothing (the images stay acquired for later legitimate waits).
        for (uint32_t i = 0; i < sc->images->info().imageCount; ++i)
            if (sc->images->isWaited(i)) return XR_ERROR_CALL_ORDER_INVALID;
        if (sc->acquiredOrder.empty()) return XR_ERROR_CALL_ORDER_INVALID;  // nothing acquired
        reader = sc->readByFrame[sc->acquiredOrder.front()];
    }
    // The image is the application's again once the last frame that reads it is complete (its GPU
    // work done: the compositor thread saw its fence). Usually long ago: three images rotate.
    {
        Session* s = sc->session;
        std::unique_lock frame(s->frameMutex);
        if (!waitForFrame(s, frame, reader, info->timeout)) return XR_TIMEOUT_EXPIRED;
    }
    std::lock_guard lock(sc->mutex);
    if (!sc->images->wait()) return XR_ERROR_CALL_ORDER_INVALID;
    sc->acquiredOrder.pop_front();
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrReleaseSwapchainImage(XrSwapchain h, const XrSwapchainImageReleaseInfo* info) {
    Swapchain* sc = getSwapchain(h);
    if (!sc) return XR_ERROR_HANDLE_INVALID;
    std::lock_guard lock(sc->mutex);
    if (info && info->type != XR_TYPE_SWAPCHAIN_IMAGE_RELEASE_INFO) return XR_ERROR_VALIDATION_FAILURE;
    return sc->images->release() ? XR_SUCCESS : XR_ERROR_CALL_ORDER_INVALID;  // released twice, or not waited
}

}  // namespace wrsfov::xr
