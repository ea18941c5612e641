// XR_APILAYER_WRSFOV_foveation: swapchains (made with the usage the compositor needs, their images imported).
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

// ---- Swapchains -------------------------------------------------------------------------------

namespace {

const Next* nextOfSession(XrSession session) {
    auto it = g_sessions.find(session);
    return it == g_sessions.end() ? nullptr : &g_instances.at(it->second.instance).next;
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL layerCreateSwapchain(XrSession session, const XrSwapchainCreateInfo* info,
                                                    XrSwapchain* swapchain) {
    std::lock_guard lock(g_mutex);
    const Next* n = nextOfSession(session);
    if (!n) return XR_ERROR_HANDLE_INVALID;
    if (!info) return n->createSwapchain(session, info, swapchain);
    // The compositor samples the images, and does nothing else with them: SAMPLED added, on a copy; the
    // application's structure stays as it gave it. No MUTABLE_FORMAT: a runtime may ignore it (Monado
    // 21 does), so an sRGB image is read through a view of its own format (the device decodes,
    // shaders/wrs_input.h) and never reinterpreted.
    XrSwapchainCreateInfo ci = *info;
    const auto fmt = colorFormat(info->format);
    if (fmt) ci.usageFlags |= XR_SWAPCHAIN_USAGE_SAMPLED_BIT;
    XrResult r = n->createSwapchain(session, &ci, swapchain);
    if (XR_FAILED(r) && fmt && ci.usageFlags != info->usageFlags) {
        // The runtime refused the added usage: the images are made with the application's usage alone,
        // and the layer reads them only if that includes SAMPLED (layerEnumerateSwapchainImages).
        ci = *info;
        r = n->createSwapchain(session, &ci, swapchain);
        if (XR_SUCCEEDED(r))
            logLine("swapchain made without the SAMPLED usage the layer asked for (the runtime refused it): "
                    "frames that use it pass through");
    }
    if (XR_FAILED(r)) return r;
    SwapchainState& s = g_swapchains[*swapchain];
    s.session = session;
    s.info = ci;  // what the images were made with
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerDestroySwapchain(XrSwapchain swapchain) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    const Next* n = nextOfSession(it->second.session);
    // The compositor's last frame may still read it (the application waited for its own work only).
    if (it->second.imported) waitComposited(g_sessions.at(it->second.session));
    g_swapchains.erase(it);
    return n->destroySwapchain(swapchain);
}

XRAPI_ATTR XrResult XRAPI_CALL layerEnumerateSwapchainImages(XrSwapchain swapchain, uint32_t capacity,
                                                             uint32_t* countOutput, XrSwapchainImageBaseHeader* images) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    SwapchainState& sc = it->second;
    XrResult r = nextOfSession(sc.session)->enumerateSwapchainImages(swapchain, capacity, countOutput, images);
    if (r != XR_SUCCESS || capacity == 0 || !images || images->type != XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR ||
        !sc.images.empty())
        return r;
    auto* vkImages = reinterpret_cast<XrSwapchainImageVulkanKHR*>(images);
    for (uint32_t i = 0; i < *countOutput; ++i) sc.images.push_back(vkImages[i].image);
    SessionState& s = g_sessions.at(sc.session);
    const auto fmt = colorFormat(sc.info.format);
    // An sRGB swapchain with UNORDERED_ACCESS usage is not read: its images carry STORAGE usage, which an
    // sRGB view may not inherit, and narrowing a view's usage needs Vulkan 1.1, which the application's
    // device may not have enabled.
    const bool srgbStorage = fmt && *fmt == layers::Format::RGBA8_SRGB &&
                             (sc.info.usageFlags & XR_SWAPCHAIN_USAGE_UNORDERED_ACCESS_BIT);
    const bool usable = fmt && (sc.info.usageFlags & XR_SWAPCHAIN_USAGE_SAMPLED_BIT) && !srgbStorage &&
                        sc.info.faceCount == 1 && sc.info.mipCount == 1 && sc.info.sampleCount == 1 &&
                        sc.images.size() <= 8;
    if (s.comp && usable) {
        layers::SwapchainCreateInfo info;
        info.format = *fmt;
        info.usage = *fmt == layers::Format::D32F ? layers::Usage::Depth : layers::Usage::Color;
        info.anyUse = true;
        info.width = sc.info.width;
        info.height = sc.info.height;
        info.arraySize = sc.info.arraySize;
        info.imageCount = uint32_t(sc.images.size());
        SwapchainImageOptions o;
        o.restingLayout = *fmt == layers::Format::D32F ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                                                       : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
        auto imp = s.comp->importSwapchain(info, sc.images, o);
        if (imp) sc.imported = std::move(*imp);
        else logLine("swapchain not used: " + imp.error().message);
    }
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerAcquireSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageAcquireInfo* info,
                                                          uint32_t* index) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    XrResult r = nextOfSession(it->second.session)->acquireSwapchainImage(swapchain, info, index);
    if (XR_SUCCEEDED(r) && index) it->second.acquired.push_back(*index);
    return r;
}

// The runtime below knows only its own reads of the image; the compositor's reads of the last frame
// may still be running (the layer does not wait for them in xrEndFrame), and the application may
// render on a queue other than the one the compositor uses. Waiting here keeps the promise of
// xrWaitSwapchainImage: the image is free to write. By then the frame has normally long finished.
XRAPI_ATTR XrResult XRAPI_CALL layerWaitSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageWaitInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    XrResult r = nextOfSession(it->second.session)->waitSwapchainImage(swapchain, info);
    if (r == XR_SUCCESS && it->second.imported) waitComposited(g_sessions.at(it->second.session));
    return r;
}

XRAPI_ATTR XrResult XRAPI_CALL layerReleaseSwapchainImage(XrSwapchain swapchain, const XrSwapchainImageReleaseInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_swapchains.find(swapchain);
    if (it == g_swapchains.end()) return XR_ERROR_HANDLE_INVALID;
    SwapchainState& sc = it->second;
    XrResult r = nextOfSession(sc.session)->releaseSwapchainImage(swapchain, info);
    if (XR_SUCCEEDED(r) && !sc.acquired.empty()) {
        if (sc.imported) sc.imported->releasedElsewhere(sc.acquired.front());
        sc.acquired.erase(sc.acquired.begin());
    }
    return r;
}

}  // namespace wrsfov::xrlayer
