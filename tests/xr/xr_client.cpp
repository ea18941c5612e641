#include "tests/xr/xr_client.h"

#include <gtest/gtest.h>

#include <cstring>

namespace wrsfov::xrtest {

#define XR_OK(call) ASSERT_EQ((call), XR_SUCCESS) << #call

namespace {

void createAll(Client& c, const std::vector<const char*>& extensions) {
    XrInstanceCreateInfo ici{XR_TYPE_INSTANCE_CREATE_INFO};
    std::snprintf(ici.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "wrsfov-xr-client-test");
    ici.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ici.enabledExtensionCount = uint32_t(extensions.size());
    ici.enabledExtensionNames = extensions.data();
    XR_OK(xrCreateInstance(&ici, &c.instance));
    XrSystemGetInfo sgi{XR_TYPE_SYSTEM_GET_INFO};
    sgi.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XR_OK(xrGetSystem(c.instance, &sgi, &c.system));
    uint32_t n = 0;
    XrViewConfigurationView views[2] = {{XR_TYPE_VIEW_CONFIGURATION_VIEW}, {XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    XR_OK(xrEnumerateViewConfigurationViews(c.instance, c.system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &n,
                                            views));
    c.viewWidth = views[0].recommendedImageRectWidth;
    c.viewHeight = views[0].recommendedImageRectHeight;

    auto requirements =
        proc<PFN_xrGetVulkanGraphicsRequirements2KHR>(c.instance, "xrGetVulkanGraphicsRequirements2KHR");
    auto createInstance = proc<PFN_xrCreateVulkanInstanceKHR>(c.instance, "xrCreateVulkanInstanceKHR");
    auto graphicsDevice = proc<PFN_xrGetVulkanGraphicsDevice2KHR>(c.instance, "xrGetVulkanGraphicsDevice2KHR");
    auto createDevice = proc<PFN_xrCreateVulkanDeviceKHR>(c.instance, "xrCreateVulkanDeviceKHR");
    ASSERT_TRUE(requirements && createInstance && graphicsDevice && createDevice);
    XrGraphicsRequirementsVulkan2KHR req{XR_TYPE_GRAPHICS_REQUIREMENTS_VULKAN2_KHR};
    XR_OK(requirements(c.instance, c.system, &req));

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "wrsfov-xr-client-test";
    app.apiVersion = VK_API_VERSION_1_0;
    VkInstanceCreateInfo vci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    vci.pApplicationInfo = &app;
    XrVulkanInstanceCreateInfoKHR xvi{XR_TYPE_VULKAN_INSTANCE_CREATE_INFO_KHR};
    xvi.systemId = c.system;
    xvi.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    xvi.vulkanCreateInfo = &vci;
    VkResult vr = VK_ERROR_UNKNOWN;
    XR_OK(createInstance(c.instance, &xvi, &c.vkInstance, &vr));
    ASSERT_EQ(vr, VK_SUCCESS);
    XrVulkanGraphicsDeviceGetInfoKHR gdi{XR_TYPE_VULKAN_GRAPHICS_DEVICE_GET_INFO_KHR};
    gdi.systemId = c.system;
    gdi.vulkanInstance = c.vkInstance;
    XR_OK(graphicsDevice(c.instance, &gdi, &c.physical));

    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical, &qn, qf.data());
    for (uint32_t i = 0; i < qn; ++i)
        if (qf[i].queueFlags & VK_QUEUE_GRAPHICS_BIT) {
            c.queueFamily = i;
            break;
        }
    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = c.queueFamily;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    XrVulkanDeviceCreateInfoKHR xdi{XR_TYPE_VULKAN_DEVICE_CREATE_INFO_KHR};
    xdi.systemId = c.system;
    xdi.pfnGetInstanceProcAddr = &vkGetInstanceProcAddr;
    xdi.vulkanPhysicalDevice = c.physical;
    xdi.vulkanCreateInfo = &dci;
    XR_OK(createDevice(c.instance, &xdi, &c.device, &vr));
    ASSERT_EQ(vr, VK_SUCCESS);
    vkGetDeviceQueue(c.device, c.queueFamily, 0, &c.queue);
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.queueFamilyIndex = c.queueFamily;
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    ASSERT_EQ(vkCreateCommandPool(c.device, &pci, nullptr, &c.pool), VK_SUCCESS);

    XrGraphicsBindingVulkan2KHR binding{XR_TYPE_GRAPHICS_BINDING_VULKAN2_KHR};
    binding.instance = c.vkInstance;
    binding.physicalDevice = c.physical;
    binding.device = c.device;
    binding.queueFamilyIndex = c.queueFamily;
    binding.queueIndex = 0;
    XrSessionCreateInfo sci{XR_TYPE_SESSION_CREATE_INFO};
    sci.next = &binding;
    sci.systemId = c.system;
    XR_OK(xrCreateSession(c.instance, &sci, &c.session));
    XrReferenceSpaceCreateInfo rci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_LOCAL;
    rci.poseInReferenceSpace.orientation.w = 1.0f;
    XR_OK(xrCreateReferenceSpace(c.session, &rci, &c.local));
}

}  // namespace

std::unique_ptr<Client> Client::create(const std::vector<const char*>& extensions) {
    std::unique_ptr<Client> c(new Client());
    createAll(*c, extensions);
    if (::testing::Test::HasFatalFailure() || !c->session) return nullptr;
    return c;
}

Client::~Client() {
    if (session) xrDestroySession(session);  // spaces and swapchains go with it
    if (instance) xrDestroyInstance(instance);
    if (device) {
        vkDeviceWaitIdle(device);
        if (pool) vkDestroyCommandPool(device, pool, nullptr);
        vkDestroyDevice(device, nullptr);
    }
    if (vkInstance) vkDestroyInstance(vkInstance, nullptr);
}

std::vector<XrEventDataBuffer> Client::poll() {
    std::vector<XrEventDataBuffer> out;
    for (;;) {
        XrEventDataBuffer e{XR_TYPE_EVENT_DATA_BUFFER};
        if (xrPollEvent(instance, &e) != XR_SUCCESS) break;
        out.push_back(e);
    }
    return out;
}

std::vector<XrSessionState> Client::states(const std::vector<XrEventDataBuffer>& events) {
    std::vector<XrSessionState> s;
    for (const auto& e : events)
        if (e.type == XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
            s.push_back(reinterpret_cast<const XrEventDataSessionStateChanged&>(e).state);
    return s;
}

XrResult Client::createSwapchain(int64_t format, uint32_t w, uint32_t h, uint32_t arraySize,
                                 XrSwapchainUsageFlags usage, Swapchain& out, XrSwapchainCreateFlags flags) {
    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.createFlags = flags;
    ci.usageFlags = usage;
    ci.format = format;
    ci.sampleCount = 1;
    ci.width = w;
    ci.height = h;
    ci.faceCount = 1;
    ci.arraySize = arraySize;
    ci.mipCount = 1;
    XrResult r = xrCreateSwapchain(session, &ci, &out.handle);
    if (r != XR_SUCCESS) return r;
    uint32_t n = 0;
    xrEnumerateSwapchainImages(out.handle, 0, &n, nullptr);
    std::vector<XrSwapchainImageVulkan2KHR> imgs(n, {XR_TYPE_SWAPCHAIN_IMAGE_VULKAN2_KHR});
    r = xrEnumerateSwapchainImages(out.handle, n, &n, reinterpret_cast<XrSwapchainImageBaseHeader*>(imgs.data()));
    for (auto& i : imgs) out.images.push_back(i.image);
    out.width = w;
    out.height = h;
    out.arraySize = arraySize;
    out.format = format;
    return r;
}

void Client::writeSwapchain(Swapchain& sc, uint32_t texelBytes, VkImageAspectFlags aspect,
                            const std::function<std::vector<uint8_t>(uint32_t layer)>& fill) {
    uint32_t index = 0;
    XR_OK(xrAcquireSwapchainImage(sc.handle, nullptr, &index));
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    XR_OK(xrWaitSwapchainImage(sc.handle, &wi));

    const VkDeviceSize layerBytes = VkDeviceSize(sc.width) * sc.height * texelBytes;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = layerBytes * sc.arraySize;
    bci.usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    VkBuffer buf;
    ASSERT_EQ(vkCreateBuffer(device, &bci, nullptr, &buf), VK_SUCCESS);
    VkMemoryRequirements mr;
    vkGetBufferMemoryRequirements(device, buf, &mr);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(physical, &mp);
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = mr.size;
    const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    for (uint32_t i = 0; i < mp.memoryTypeCount; ++i)
        if ((mr.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) {
            mai.memoryTypeIndex = i;
            break;
        }
    VkDeviceMemory mem;
    ASSERT_EQ(vkAllocateMemory(device, &mai, nullptr, &mem), VK_SUCCESS);
    vkBindBufferMemory(device, buf, mem, 0);
    void* mapped = nullptr;
    vkMapMemory(device, mem, 0, VK_WHOLE_SIZE, 0, &mapped);
    for (uint32_t l = 0; l < sc.arraySize; ++l) {
        std::vector<uint8_t> texels = fill(l);
        ASSERT_EQ(texels.size(), layerBytes);
        std::memcpy(static_cast<uint8_t*>(mapped) + l * layerBytes, texels.data(), layerBytes);
    }

    // The image is in the attachment layout the spec promises after a wait; back there before release.
    const VkImageLayout rest = aspect == VK_IMAGE_ASPECT_DEPTH_BIT ? VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL
                                                                   : VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    VkCommandBuffer cb;
    vkAllocateCommandBuffers(device, &cai, &cb);
    VkCommandBufferBeginInfo cbi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    vkBeginCommandBuffer(cb, &cbi);
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.oldLayout = rest;
    b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = sc.images[index];
    b.subresourceRange = {aspect, 0, 1, 0, sc.arraySize};
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &b);
    std::vector<VkBufferImageCopy> regions(sc.arraySize);
    for (uint32_t l = 0; l < sc.arraySize; ++l) {
        regions[l] = {};
        regions[l].bufferOffset = l * layerBytes;
        regions[l].imageSubresource = {aspect, 0, l, 1};
        regions[l].imageExtent = {sc.width, sc.height, 1};
    }
    vkCmdCopyBufferToImage(cb, buf, sc.images[index], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, sc.arraySize,
                           regions.data());
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = rest;
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &b);
    vkEndCommandBuffer(cb);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    ASSERT_EQ(vkQueueSubmit(queue, 1, &si, VK_NULL_HANDLE), VK_SUCCESS);
    vkQueueWaitIdle(queue);
    vkFreeCommandBuffers(device, pool, 1, &cb);
    vkDestroyBuffer(device, buf, nullptr);
    vkFreeMemory(device, mem, nullptr);
    XR_OK(xrReleaseSwapchainImage(sc.handle, nullptr));
}

XrResult Client::begin(XrViewConfigurationType type) {
    XrSessionBeginInfo bi{XR_TYPE_SESSION_BEGIN_INFO};
    bi.primaryViewConfigurationType = type;
    return xrBeginSession(session, &bi);
}

XrResult Client::frame(const std::function<XrResult(const XrFrameState&)>& submit) {
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    if (XrResult r = xrWaitFrame(session, nullptr, &fs); r != XR_SUCCESS) return r;
    if (XrResult r = xrBeginFrame(session, nullptr); r != XR_SUCCESS) return r;
    return submit(fs);
}

void StereoLayer::build(Client& c, XrTime time, const Swapchain& color, const Swapchain* colorRight,
                        const Swapchain* depthSc) {
    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = time;
    li.space = c.local;
    XrViewState vs{XR_TYPE_VIEW_STATE};
    XrView xv[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
    uint32_t n = 0;
    xrLocateViews(c.session, &li, &vs, 2, &n, xv);
    for (int e = 0; e < 2; ++e) {
        const Swapchain& sc = (e == 1 && colorRight) ? *colorRight : color;
        views[e] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
        views[e].pose = xv[e].pose;
        views[e].fov = xv[e].fov;
        views[e].subImage.swapchain = sc.handle;
        views[e].subImage.imageRect = {{0, 0}, {int32_t(sc.width), int32_t(sc.height)}};
        views[e].subImage.imageArrayIndex = (sc.arraySize > 1) ? uint32_t(e) : 0u;
        if (depthSc) {
            depth[e] = {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR};
            depth[e].subImage.swapchain = depthSc->handle;
            depth[e].subImage.imageRect = views[e].subImage.imageRect;
            depth[e].subImage.imageArrayIndex = depthSc->arraySize > 1 ? uint32_t(e) : 0u;
            depth[e].minDepth = 0.0f;
            depth[e].maxDepth = 1.0f;
            depth[e].nearZ = 0.1f;
            depth[e].farZ = 100.0f;
            views[e].next = &depth[e];
        }
    }
    layer = {XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    layer.space = c.local;
    layer.viewCount = 2;
    layer.views = views;
}

void QuadLayer::build(XrSpace space, const XrView (&located)[4], const Swapchain& wide, const Swapchain& inset,
                      const Swapchain* wideDepth, const Swapchain* insetDepth) {
    for (uint32_t v = 0; v < 4; ++v) {
        const Swapchain& sc = v < 2 ? wide : inset;
        const Swapchain* dsc = v < 2 ? wideDepth : insetDepth;
        views[v] = {XR_TYPE_COMPOSITION_LAYER_PROJECTION_VIEW};
        views[v].pose = located[v].pose;
        views[v].fov = located[v].fov;
        views[v].subImage.swapchain = sc.handle;
        views[v].subImage.imageRect = {{0, 0}, {int32_t(sc.width), int32_t(sc.height)}};
        views[v].subImage.imageArrayIndex = v % 2;
        if (dsc) {
            depth[v] = {XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR};
            depth[v].subImage = views[v].subImage;
            depth[v].subImage.swapchain = dsc->handle;
            depth[v].minDepth = 0.0f;
            depth[v].maxDepth = 1.0f;
            depth[v].nearZ = 0.1f;
            depth[v].farZ = 100.0f;
            views[v].next = &depth[v];
        }
    }
    layer = {XR_TYPE_COMPOSITION_LAYER_PROJECTION};
    layer.space = space;
    layer.viewCount = 4;
    layer.views = views;
}

XrFrameEndInfo frameEnd(XrTime time, const std::vector<const XrCompositionLayerBaseHeader*>& layers) {
    XrFrameEndInfo fe{XR_TYPE_FRAME_END_INFO};
    fe.displayTime = time;
    fe.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_OPAQUE;
    fe.layerCount = uint32_t(layers.size());
    fe.layers = layers.empty() ? nullptr : layers.data();
    return fe;
}

}  // namespace wrsfov::xrtest
