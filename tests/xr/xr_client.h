// A small OpenXR client for the runtime's tests: instance, system, Vulkan through
// XR_KHR_vulkan_enable2, session, a LOCAL space, swapchains it fills with Vulkan copies, and
// frame loops. It goes through the Khronos loader (XR_RUNTIME_JSON names the runtime).
#pragma once

#define XR_USE_GRAPHICS_API_VULKAN
#include <vulkan/vulkan.h>
#include <openxr/openxr.h>
#include <openxr/openxr_platform.h>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace wrsfov::xrtest {

/// An extension function of the instance (nullptr if missing).
template <typename F>
F proc(XrInstance instance, const char* name) {
    PFN_xrVoidFunction f = nullptr;
    if (xrGetInstanceProcAddr(instance, name, &f) != XR_SUCCESS) return nullptr;
    return reinterpret_cast<F>(f);
}

struct Swapchain {
    XrSwapchain handle = XR_NULL_HANDLE;
    std::vector<VkImage> images;
    uint32_t width = 0, height = 0, arraySize = 1;
    int64_t format = 0;
};

class Client {
public:
    /// Instance (with these extensions), system, Vulkan instance and device, session, LOCAL space.
    /// Fails the calling test (gtest assertion) on any error.
    static std::unique_ptr<Client> create(const std::vector<const char*>& extensions);
    ~Client();

    XrInstance instance = XR_NULL_HANDLE;
    XrSystemId system = XR_NULL_SYSTEM_ID;
    XrSession session = XR_NULL_HANDLE;
    XrSpace local = XR_NULL_HANDLE;
    VkInstance vkInstance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    VkQueue queue = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;
    VkCommandPool pool = VK_NULL_HANDLE;
    uint32_t viewWidth = 0, viewHeight = 0;  // recommended per-eye size

    /// All pending events.
    std::vector<XrEventDataBuffer> poll();
    /// The session states announced by `events`, in order.
    static std::vector<XrSessionState> states(const std::vector<XrEventDataBuffer>& events);

    XrResult createSwapchain(int64_t format, uint32_t w, uint32_t h, uint32_t arraySize, XrSwapchainUsageFlags usage,
                             Swapchain& out, XrSwapchainCreateFlags flags = 0);
    /// acquire, wait, fill every layer (fill(layer) gives tightly packed texels), release.
    void writeSwapchain(Swapchain& sc, uint32_t texelBytes, VkImageAspectFlags aspect,
                        const std::function<std::vector<uint8_t>(uint32_t layer)>& fill);
    /// Begins the session (after READY) and runs wait/begin/end with the layers `layers(frameState)`
    /// gives, `frames` times. Returns the first failing xrEndFrame result, XR_SUCCESS otherwise.
    XrResult begin(XrViewConfigurationType type = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO);
    XrResult frame(const std::function<XrResult(const XrFrameState&)>& submit);

private:
    Client() = default;
};

/// Two projection views covering whole images, at the views the runtime locates.
struct StereoLayer {
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    XrCompositionLayerProjectionView views[2] = {{XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                 {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW}};
    XrCompositionLayerDepthInfoKHR depth[2] = {{XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR},
                                               {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR}};
    /// Views located at `time` in `space`; colour from `color` (layer = eye if it is an array, else
    /// `colorRight` for the right eye); depth chained when `depthSc` is given.
    void build(Client& c, XrTime time, const Swapchain& color, const Swapchain* colorRight = nullptr,
               const Swapchain* depthSc = nullptr);
    const XrCompositionLayerBaseHeader* header() const {
        return reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer);
    }
};

/// Quad views (XR_VARJO_quad_views): views 0, 1 the wide views, 2, 3 the insets, each at the pose and
/// field of view xrLocateViews gave; colour (and depth, when given) from array swapchains, layer = eye,
/// whole images.
struct QuadLayer {
    XrCompositionLayerProjection layer{XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    XrCompositionLayerProjectionView views[4] = {{XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                 {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                 {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW},
                                                 {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW}};
    XrCompositionLayerDepthInfoKHR depth[4] = {{XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR},
                                               {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR},
                                               {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR},
                                               {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR}};
    void build(XrSpace space, const XrView (&located)[4], const Swapchain& wide, const Swapchain& inset,
               const Swapchain* wideDepth = nullptr, const Swapchain* insetDepth = nullptr);
    const XrCompositionLayerBaseHeader* header() const {
        return reinterpret_cast<const XrCompositionLayerBaseHeader*>(&layer);
    }
};

XrFrameEndInfo frameEnd(XrTime time, const std::vector<const XrCompositionLayerBaseHeader*>& layers);

}  // namespace wrsfov::xrtest
