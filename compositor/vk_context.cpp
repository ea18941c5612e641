#include "compositor/vk_context.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace wrsfov::vk {

const char* resultString(VkResult r) {
    switch (r) {
#define WRS_CASE(x) \
    case x:         \
        return #x;
        WRS_CASE(VK_SUCCESS)
        WRS_CASE(VK_NOT_READY)
        WRS_CASE(VK_TIMEOUT)
        WRS_CASE(VK_INCOMPLETE)
        WRS_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
        WRS_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        WRS_CASE(VK_ERROR_INITIALIZATION_FAILED)
        WRS_CASE(VK_ERROR_DEVICE_LOST)
        WRS_CASE(VK_ERROR_MEMORY_MAP_FAILED)
        WRS_CASE(VK_ERROR_LAYER_NOT_PRESENT)
        WRS_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
        WRS_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
        WRS_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
        WRS_CASE(VK_ERROR_TOO_MANY_OBJECTS)
        WRS_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
        WRS_CASE(VK_ERROR_SURFACE_LOST_KHR)
        WRS_CASE(VK_ERROR_OUT_OF_DATE_KHR)
        WRS_CASE(VK_SUBOPTIMAL_KHR)
#undef WRS_CASE
        default:
            return "VK_ERROR_(unknown)";
    }
}

void fatal(const char* file, int line, const char* call, VkResult r) {
    std::fprintf(stderr, "%s:%d: %s failed with %s\n", file, line, call, resultString(r));
    std::abort();
}

namespace {

// How long a wait on a device already lost may take (a never-submitted fence must not hang).
constexpr uint64_t kLostWaitNs = 5'000'000'000ull;

Error vkError(const std::string& what, VkResult r) {
    return Error{static_cast<int>(r), what + " failed: " + resultString(r)};
}

}  // namespace

int deviceTypeScore(VkPhysicalDeviceType t) {
    switch (t) {
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return 4;
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return 3;
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return 2;
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return 1;
        default:
            return 0;
    }
}

namespace {

bool hasLayer(const char* name) {
    uint32_t n = 0;
    vkEnumerateInstanceLayerProperties(&n, nullptr);
    std::vector<VkLayerProperties> layers(n);
    vkEnumerateInstanceLayerProperties(&n, layers.data());
    for (auto& l : layers)
        if (std::strcmp(l.layerName, name) == 0) return true;
    return false;
}

}  // namespace

ContextOptions ContextOptions::fromEnvironment() {
    ContextOptions o;
    if (const char* v = std::getenv("WRSFOV_VALIDATION")) o.validation = std::strcmp(v, "0") != 0 && *v;
    if (const char* d = std::getenv("WRSFOV_DEVICE")) o.deviceName = d;
    return o;
}

void memoryBarrier(VkCommandBuffer cb, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess) {
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = srcAccess;
    mb.dstAccessMask = dstAccess;
    vkCmdPipelineBarrier(cb, srcStage, dstStage, 0, 1, &mb, 0, nullptr, 0, nullptr);
}

VkWriteDescriptorSet bufferWrite(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                                 const VkDescriptorBufferInfo* infos, uint32_t count) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = binding;
    w.descriptorCount = count;
    w.descriptorType = type;
    w.pBufferInfo = infos;
    return w;
}

VkWriteDescriptorSet imageWrite(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                                const VkDescriptorImageInfo* infos, uint32_t count) {
    VkWriteDescriptorSet w{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    w.dstSet = set;
    w.dstBinding = binding;
    w.descriptorCount = count;
    w.descriptorType = type;
    w.pImageInfo = infos;
    return w;
}

// ---- Buffer / Image ------------------------------------------------------------------------------

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        reset();
        std::swap(device_, o.device_);
        std::swap(buffer_, o.buffer_);
        std::swap(memory_, o.memory_);
        std::swap(size_, o.size_);
        std::swap(mapped_, o.mapped_);
    }
    return *this;
}

void Buffer::reset() {
    if (buffer_) vkDestroyBuffer(device_, buffer_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
}

Image& Image::operator=(Image&& o) noexcept {
    if (this != &o) {
        reset();
        std::swap(device_, o.device_);
        std::swap(image_, o.image_);
        std::swap(memory_, o.memory_);
        std::swap(layerViews_, o.layerViews_);
        std::swap(arrayView_, o.arrayView_);
        std::swap(info_, o.info_);
        std::swap(aspect_, o.aspect_);
        std::swap(ownsImage_, o.ownsImage_);
    }
    return *this;
}

void Image::reset() {
    for (VkImageView v : layerViews_) vkDestroyImageView(device_, v, nullptr);
    layerViews_.clear();
    if (arrayView_) vkDestroyImageView(device_, arrayView_, nullptr);
    if (image_ && ownsImage_) vkDestroyImage(device_, image_, nullptr);
    if (memory_) vkFreeMemory(device_, memory_, nullptr);
    arrayView_ = VK_NULL_HANDLE;
    image_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    ownsImage_ = true;
}

// ---- Context -------------------------------------------------------------------------------------

VKAPI_ATTR VkBool32 VKAPI_CALL Context::debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                      VkDebugUtilsMessageTypeFlagsEXT,
                                                      const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* self = static_cast<Context*>(user);
    const char* kind = "info";
    if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        self->validationErrors_++;
        kind = "error";
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        self->validationWarnings_++;
        kind = "warning";
    } else {
        return VK_FALSE;
    }
    std::string msg = std::string("[validation ") + kind + "] " + (data->pMessage ? data->pMessage : "");
    std::fprintf(stderr, "%s\n", msg.c_str());
    std::lock_guard<std::mutex> lock(self->messagesMutex_);
    self->messages_.push_back(std::move(msg));
    return VK_FALSE;
}

std::vector<std::string> Context::validationMessages() const {
    std::lock_guard<std::mutex> lock(messagesMutex_);
    return messages_;
}

Result<std::unique_ptr<Context>> Context::create(const ContextOptions& options) {
    std::unique_ptr<Context> ctx(new Context());
    Context& c = *ctx;

    std::vector<const char*> layers;
    std::vector<const char*> extensions = options.instanceExtensions;
    if (options.validation) {
        if (!hasLayer("VK_LAYER_KHRONOS_validation"))
            return Error{static_cast<int>(VK_ERROR_LAYER_NOT_PRESENT),
                         "validation was requested but VK_LAYER_KHRONOS_validation is not installed "
                         "(Debian package vulkan-validationlayers)"};
        layers.push_back("VK_LAYER_KHRONOS_validation");
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
        c.validation_ = true;
    }

    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "wrsfov";
    app.pEngineName = "wrsfov";
    app.apiVersion = VK_API_VERSION_1_2;

    VkDebugUtilsMessengerCreateInfoEXT dbg{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
    dbg.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    // Performance hints are left out: images stay in GENERAL layout on purpose (see swapchain.h).
    dbg.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT;
    dbg.pfnUserCallback = &Context::debugCallback;
    dbg.pUserData = &c;

    VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ici.pApplicationInfo = &app;
    ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
    ici.ppEnabledLayerNames = layers.data();
    ici.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
    ici.ppEnabledExtensionNames = extensions.data();
    if (c.validation_) ici.pNext = &dbg;
    if (VkResult r = vkCreateInstance(&ici, nullptr, &c.instance_); r != VK_SUCCESS)
        return Error{static_cast<int>(r), std::string("vkCreateInstance failed: ") + resultString(r) +
                                              " (is a Vulkan driver installed? Debian: mesa-vulkan-drivers)"};
    if (c.validation_) {
        auto fn = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(c.instance_, "vkCreateDebugUtilsMessengerEXT"));
        if (fn) fn(c.instance_, &dbg, nullptr, &c.messenger_);
    }

    uint32_t n = 0;
    vkEnumeratePhysicalDevices(c.instance_, &n, nullptr);
    std::vector<VkPhysicalDevice> devices(n);
    vkEnumeratePhysicalDevices(c.instance_, &n, devices.data());
    std::string available;
    int best = -1;
    for (VkPhysicalDevice d : devices) {
        VkPhysicalDeviceProperties p;
        vkGetPhysicalDeviceProperties(d, &p);
        available += std::string(available.empty() ? "" : ", ") + p.deviceName;
        if (p.apiVersion < VK_API_VERSION_1_2) continue;
        if (!options.deviceName.empty() && std::string(p.deviceName).find(options.deviceName) == std::string::npos)
            continue;
        uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> qf(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, qf.data());
        for (uint32_t i = 0; i < qn; ++i) {
            VkQueueFlags need = VK_QUEUE_COMPUTE_BIT | VK_QUEUE_GRAPHICS_BIT;
            if ((qf[i].queueFlags & need) != need) continue;
            if (options.queueFilter && !options.queueFilter(c.instance_, d, i)) continue;
            int score = deviceTypeScore(p.deviceType);
            if (score > best) {
                best = score;
                c.physical_ = d;
                c.queueFamily_ = i;
                c.timestampValidBits_ = qf[i].timestampValidBits;
            }
            break;
        }
    }
    if (!c.physical_)
        return Error{static_cast<int>(VK_ERROR_INITIALIZATION_FAILED),
                     (options.deviceName.empty() ? std::string("no Vulkan 1.2 device with a graphics+compute queue") +
                                                       (options.queueFilter ? " that can present" : "")
                                                 : "no Vulkan 1.2 device named like '" + options.deviceName + "'") +
                         "; available: " + (available.empty() ? "none" : available)};
    vkGetPhysicalDeviceProperties(c.physical_, &c.props_);
    vkGetPhysicalDeviceMemoryProperties(c.physical_, &c.memProps_);

    float prio = 1.0f;
    VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qci.queueFamilyIndex = c.queueFamily_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &prio;
    VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    dci.enabledExtensionCount = static_cast<uint32_t>(options.deviceExtensions.size());
    dci.ppEnabledExtensionNames = options.deviceExtensions.data();
    if (VkResult r = vkCreateDevice(c.physical_, &dci, nullptr, &c.device_); r != VK_SUCCESS)
        return vkError("vkCreateDevice", r);
    vkGetDeviceQueue(c.device_, c.queueFamily_, 0, &c.queue_);

    if (Status s = c.initQueueObjects(); !s) return s.error();
    return ctx;
}

Status Context::initQueueObjects() {
    VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pci.queueFamilyIndex = queueFamily_;
    if (VkResult r = vkCreateCommandPool(device_, &pci, nullptr, &pool_); r != VK_SUCCESS)
        return vkError("vkCreateCommandPool", r);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (VkResult r = vkCreateFence(device_, &fci, nullptr, &fence_); r != VK_SUCCESS)
        return vkError("vkCreateFence", r);
    if (const char* spec = std::getenv("WRSFOV_FAULT"); spec && *spec) {
        auto faults = FaultInjection::parse(spec);
        if (!faults) return faults.error();
        injectFaults(*faults);
    }
    return {};
}

Result<std::unique_ptr<Context>> Context::adopt(const AdoptedDevice& d) {
    if (!d.instance || !d.physicalDevice || !d.device)
        return Error{static_cast<int>(VK_ERROR_INITIALIZATION_FAILED),
                     "adopting a device needs its VkInstance, VkPhysicalDevice and VkDevice"};
    std::unique_ptr<Context> ctx(new Context());
    Context& c = *ctx;
    c.adopted_ = true;
    c.instance_ = d.instance;
    c.physical_ = d.physicalDevice;
    c.device_ = d.device;
    c.queueFamily_ = d.queueFamily;
    vkGetPhysicalDeviceProperties(c.physical_, &c.props_);
    vkGetPhysicalDeviceMemoryProperties(c.physical_, &c.memProps_);
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical_, &qn, nullptr);
    std::vector<VkQueueFamilyProperties> qf(qn);
    vkGetPhysicalDeviceQueueFamilyProperties(c.physical_, &qn, qf.data());
    if (d.queueFamily >= qn || d.queueIndex >= qf[d.queueFamily].queueCount ||
        !(qf[d.queueFamily].queueFlags & VK_QUEUE_COMPUTE_BIT))
        return Error{static_cast<int>(VK_ERROR_INITIALIZATION_FAILED),
                     "queue family " + std::to_string(d.queueFamily) + " index " + std::to_string(d.queueIndex) +
                         " is not a compute queue of the adopted device"};
    c.timestampValidBits_ = qf[d.queueFamily].timestampValidBits;
    vkGetDeviceQueue(c.device_, c.queueFamily_, d.queueIndex, &c.queue_);
    if (Status s = c.initQueueObjects(); !s) return s.error();
    return ctx;
}

Context::~Context() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        for (auto& [key, p] : pipelines_) vkDestroyPipeline(device_, p, nullptr);
        if (fence_) vkDestroyFence(device_, fence_, nullptr);
        if (pool_) vkDestroyCommandPool(device_, pool_, nullptr);
        if (!adopted_) vkDestroyDevice(device_, nullptr);
    }
    if (messenger_) {
        auto fn = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
        if (fn) fn(instance_, messenger_, nullptr);
    }
    if (instance_ && !adopted_) vkDestroyInstance(instance_, nullptr);
}

Result<uint32_t> Context::memoryType(uint32_t typeBits, VkMemoryPropertyFlags props) const {
    for (uint32_t i = 0; i < memProps_.memoryTypeCount; ++i)
        if ((typeBits & (1u << i)) && (memProps_.memoryTypes[i].propertyFlags & props) == props) return i;
    return Error{static_cast<int>(VK_ERROR_OUT_OF_DEVICE_MEMORY), "no memory type with the needed properties"};
}

Result<Buffer> Context::createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible) {
    Buffer b;
    b.device_ = device_;
    b.size_ = size;
    VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bci.size = size;
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    if (VkResult r = vkCreateBuffer(device_, &bci, nullptr, &b.buffer_); r != VK_SUCCESS)
        return vkError("vkCreateBuffer (" + std::to_string(size) + " bytes)", r);
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(device_, b.buffer_, &req);
    auto type = memoryType(req.memoryTypeBits,
                           hostVisible ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                       : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!type) return type.error();
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = *type;
    if (VkResult r = allocateMemory(mai, &b.memory_); r != VK_SUCCESS)
        return vkError("vkAllocateMemory (" + std::to_string(req.size) + " bytes)", r);
    if (VkResult r = vkBindBufferMemory(device_, b.buffer_, b.memory_, 0); r != VK_SUCCESS)
        return vkError("vkBindBufferMemory", r);
    if (hostVisible)
        if (VkResult r = vkMapMemory(device_, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_); r != VK_SUCCESS)
            return vkError("vkMapMemory (" + std::to_string(req.size) + " bytes)", r);
    return b;
}

Result<Image> Context::createImage(const ImageCreateInfo& info, VkFormat viewFormat) {
    Image img;
    img.device_ = device_;
    img.info_ = info;
    bool depth = info.format == VK_FORMAT_D32_SFLOAT;
    img.aspect_ = depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
    ici.flags = info.flags;
    ici.imageType = VK_IMAGE_TYPE_2D;
    ici.format = info.format;
    ici.extent = {info.width, info.height, 1};
    ici.mipLevels = info.mipLevels;
    ici.arrayLayers = info.layers;
    ici.samples = VK_SAMPLE_COUNT_1_BIT;
    ici.tiling = VK_IMAGE_TILING_OPTIMAL;
    ici.usage = info.usage;
    ici.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    ici.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    if (VkResult r = vkCreateImage(device_, &ici, nullptr, &img.image_); r != VK_SUCCESS)
        return vkError("vkCreateImage (" + std::to_string(info.width) + "x" + std::to_string(info.height) + ")", r);
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(device_, img.image_, &req);
    auto type = memoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (!type) return type.error();
    VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    mai.allocationSize = req.size;
    mai.memoryTypeIndex = *type;
    if (VkResult r = allocateMemory(mai, &img.memory_); r != VK_SUCCESS)
        return vkError("vkAllocateMemory (image, " + std::to_string(req.size) + " bytes)", r);
    if (VkResult r = vkBindImageMemory(device_, img.image_, img.memory_, 0); r != VK_SUCCESS)
        return vkError("vkBindImageMemory", r);
    if (Status s = createViews(img, viewFormat); !s) return s.error();
    return img;
}

Result<Image> Context::wrapImage(VkImage image, const ImageCreateInfo& info, VkFormat viewFormat) {
    if (!image) return Error{static_cast<int>(VK_ERROR_INITIALIZATION_FAILED), "wrapping a null VkImage"};
    Image img;
    img.device_ = device_;
    img.info_ = info;
    img.aspect_ = info.format == VK_FORMAT_D32_SFLOAT ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT;
    img.image_ = image;
    img.ownsImage_ = false;
    if (Status s = createViews(img, viewFormat); !s) return s.error();
    return img;
}

Status Context::createViews(Image& img, VkFormat viewFormat) {
    const ImageCreateInfo& info = img.info_;
    VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
    vci.image = img.image_;
    vci.format = viewFormat == VK_FORMAT_UNDEFINED ? info.format : viewFormat;
    // An sRGB view cannot be a storage view: a view of an image of ours made with STORAGE (for a UNORM
    // alias of it) asks for the image's other usage only. VkImageViewUsageCreateInfo is Vulkan 1.1's: on
    // a device of our own (1.2) only, not an adopted one, whose application may have enabled 1.0 (an
    // sRGB image with STORAGE is then not viewed as sRGB: the API layer leaves such swapchains alone).
    VkImageViewUsageCreateInfo viewUsage{VK_STRUCTURE_TYPE_IMAGE_VIEW_USAGE_CREATE_INFO};
    if (!adopted_ && img.ownsImage_ && vci.format == VK_FORMAT_R8G8B8A8_SRGB &&
        (info.usage & VK_IMAGE_USAGE_STORAGE_BIT)) {
        viewUsage.usage = info.usage & ~VkImageUsageFlags(VK_IMAGE_USAGE_STORAGE_BIT);
        vci.pNext = &viewUsage;
    }
    vci.subresourceRange = {img.aspect_, 0, info.mipLevels, 0, 1};
    for (uint32_t l = 0; l < info.layers; ++l) {
        vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
        vci.subresourceRange.baseArrayLayer = l;
        VkImageView v;
        if (VkResult r = vkCreateImageView(device_, &vci, nullptr, &v); r != VK_SUCCESS)
            return vkError("vkCreateImageView", r);
        img.layerViews_.push_back(v);
    }
    vci.viewType = VK_IMAGE_VIEW_TYPE_2D_ARRAY;
    vci.subresourceRange.baseArrayLayer = 0;
    vci.subresourceRange.layerCount = info.layers;
    if (VkResult r = vkCreateImageView(device_, &vci, nullptr, &img.arrayView_); r != VK_SUCCESS)
        return vkError("vkCreateImageView", r);
    return {};
}

Result<VkPipeline> Context::sharedPipeline(const std::vector<uint32_t>& key,
                                           const std::function<Result<VkPipeline>()>& make, PipelineTally* tally) {
    std::lock_guard lock(pipelinesMutex_);
    auto it = pipelines_.find(key);
    if (it != pipelines_.end()) return it->second;
    const auto start = std::chrono::steady_clock::now();
    Result<VkPipeline> made = make();
    if (!made) return made;
    pipelines_.emplace(key, *made);
    if (tally) {
        ++tally->made;
        tally->ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
    return made;
}

Result<VkPipeline> Context::createComputePipeline(VkShaderModule module, VkPipelineLayout layout,
                                                  std::span<const uint32_t> constants) {
    std::vector<VkSpecializationMapEntry> entries(constants.size());
    for (uint32_t i = 0; i < entries.size(); ++i) entries[i] = {i, uint32_t(i * sizeof(uint32_t)), sizeof(uint32_t)};
    VkSpecializationInfo spec{uint32_t(entries.size()), entries.data(), constants.size_bytes(), constants.data()};
    VkComputePipelineCreateInfo ci{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    ci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    ci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    ci.stage.module = module;
    ci.stage.pName = "main";
    ci.stage.pSpecializationInfo = &spec;
    ci.layout = layout;
    if (faults_.failPipeline && ++faultPipelines_ == faults_.failPipeline) {
        faults_.failPipeline = 0;
        return vkError("vkCreateComputePipelines", VK_ERROR_OUT_OF_DEVICE_MEMORY);
    }
    VkPipeline p = VK_NULL_HANDLE;
    if (VkResult r = vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &ci, nullptr, &p); r != VK_SUCCESS)
        return vkError("vkCreateComputePipelines", r);
    return p;
}

size_t Context::sharedPipelineCount() const {
    std::lock_guard lock(pipelinesMutex_);
    return pipelines_.size();
}

Status Context::createObject(const char* call, const std::function<VkResult()>& create) {
    if (faults_.failObject && ++faultObjects_ == faults_.failObject) {
        faults_.failObject = 0;
        return vkError(call, VK_ERROR_OUT_OF_HOST_MEMORY);
    }
    if (VkResult r = create(); r != VK_SUCCESS) return vkError(call, r);
    return {};
}

Result<ShaderModule> Context::createShaderModule(const uint32_t* code, size_t bytes) {
    VkShaderModuleCreateInfo sci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    sci.codeSize = bytes;
    sci.pCode = code;
    VkShaderModule m = VK_NULL_HANDLE;
    if (Status s = createObject("vkCreateShaderModule", [&] { return vkCreateShaderModule(device_, &sci, nullptr, &m); });
        !s)
        return s.error();
    return ShaderModule(device_, m);
}

Result<DescriptorSetLayout> Context::createSetLayout(std::initializer_list<VkDescriptorSetLayoutBinding> bindings) {
    return createSetLayout(std::span<const VkDescriptorSetLayoutBinding>(bindings.begin(), bindings.size()));
}

Result<DescriptorSetLayout> Context::createSetLayout(std::span<const VkDescriptorSetLayoutBinding> bindings) {
    VkDescriptorSetLayoutCreateInfo lci{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
    lci.bindingCount = static_cast<uint32_t>(bindings.size());
    lci.pBindings = bindings.data();
    VkDescriptorSetLayout sl = VK_NULL_HANDLE;
    if (Status s = createObject("vkCreateDescriptorSetLayout",
                                [&] { return vkCreateDescriptorSetLayout(device_, &lci, nullptr, &sl); });
        !s)
        return s.error();
    return DescriptorSetLayout(device_, sl);
}

Result<PipelineLayout> Context::createPipelineLayout(VkDescriptorSetLayout set, uint32_t pushBytes,
                                                     VkShaderStageFlags pushStages) {
    VkPushConstantRange pcr{pushStages, 0, pushBytes};
    VkPipelineLayoutCreateInfo plci{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &set;
    plci.pushConstantRangeCount = pushBytes ? 1 : 0;
    plci.pPushConstantRanges = pushBytes ? &pcr : nullptr;
    VkPipelineLayout pl = VK_NULL_HANDLE;
    if (Status s = createObject("vkCreatePipelineLayout",
                                [&] { return vkCreatePipelineLayout(device_, &plci, nullptr, &pl); });
        !s)
        return s.error();
    return PipelineLayout(device_, pl);
}

void layoutTransition(VkCommandBuffer cb, VkImage image, VkImageAspectFlags aspect, uint32_t layers,
                      VkImageLayout from, VkImageLayout to, uint32_t baseLayer) {
    if (from == to) return;
    VkImageMemoryBarrier b{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
    b.srcAccessMask = VK_ACCESS_MEMORY_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
    b.oldLayout = from;
    b.newLayout = to;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = image;
    b.subresourceRange = {aspect, 0, 1, baseLayer, layers};
    vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &b);
}

Result<std::vector<std::byte>> Context::readImageLayer(VkImage image, VkImageAspectFlags aspect, uint32_t layer,
                                                       uint32_t width, uint32_t height, size_t bytes,
                                                       VkImageLayout layout) {
    return readImageRegion(image, aspect, layer, {0, 0}, {width, height}, bytes, layout);
}

Result<std::vector<std::byte>> Context::readImageRegion(VkImage image, VkImageAspectFlags aspect, uint32_t layer,
                                                        VkOffset2D offset, VkExtent2D extent, size_t bytes,
                                                        VkImageLayout layout) {
    auto staging = createBuffer(bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    if (!staging) return staging.error();
    Status s = submitAndWait([&](VkCommandBuffer cb) {
        memoryBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        // Copied from TRANSFER_SRC_OPTIMAL, the layout a copy source is meant to be in (from GENERAL a
        // device may read it slower; the validation layer's best practices say so).
        // (The layer read alone: callers may pass a layout that holds for it only.)
        layoutTransition(cb, image, aspect, 1, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layer);
        VkBufferImageCopy region{};
        region.imageSubresource = {aspect, 0, layer, 1};
        region.imageOffset = {offset.x, offset.y, 0};
        region.imageExtent = {extent.width, extent.height, 1};
        vkCmdCopyImageToBuffer(cb, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, staging->handle(), 1, &region);
        layoutTransition(cb, image, aspect, 1, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout, layer);
        memoryBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
    });
    if (!s) return s.error();
    std::vector<std::byte> out(bytes);
    std::memcpy(out.data(), staging->mapped(), bytes);
    return out;
}

Result<VkCommandBuffer> Context::allocateCommandBuffer() {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    VkCommandBuffer cb = VK_NULL_HANDLE;
    if (Status s = createObject("vkAllocateCommandBuffers", [&] { return vkAllocateCommandBuffers(device_, &ai, &cb); });
        !s)
        return s.error();
    return cb;
}

void Context::freeCommandBuffer(VkCommandBuffer cb) { vkFreeCommandBuffers(device_, pool_, 1, &cb); }

Status Context::submitAndWait(const std::function<void(VkCommandBuffer)>& record) {
    Result<VkCommandBuffer> made = allocateCommandBuffer();
    if (!made) return made.error();
    VkCommandBuffer cb = *made;
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (VkResult r = vkBeginCommandBuffer(cb, &bi); r != VK_SUCCESS) {
        freeCommandBuffer(cb);
        return vkError("vkBeginCommandBuffer", r);
    }
    record(cb);
    if (VkResult r = vkEndCommandBuffer(cb); r != VK_SUCCESS) {
        freeCommandBuffer(cb);
        return vkError("vkEndCommandBuffer", r);
    }
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    VkResult r = submitBatch(si, fence_);
    vkResetFences(device_, 1, &fence_);
    freeCommandBuffer(cb);
    if (r != VK_SUCCESS) return vkError("queue submission", r);
    return {};
}

// ---- Device faults (FaultInjection) ---------------------------------------------------------------

Result<FaultInjection> FaultInjection::parse(const std::string& spec) {
    FaultInjection f;
    auto bad = [&] {
        return Error{static_cast<int>(VK_ERROR_INITIALIZATION_FAILED),
                     "WRSFOV_FAULT='" + spec + "' is not alloc:N, lost:N, pipeline:N and/or object:N (N >= 1, comma-separated)"};
    };
    std::size_t pos = 0;
    while (pos <= spec.size()) {
        const std::size_t end = std::min(spec.find(',', pos), spec.size());
        const std::string item = spec.substr(pos, end - pos);
        const std::size_t colon = item.find(':');
        if (colon == std::string::npos) return bad();
        const std::string kind = item.substr(0, colon), count = item.substr(colon + 1);
        char* stop = nullptr;
        const unsigned long n = count.empty() ? 0 : std::strtoul(count.c_str(), &stop, 10);
        if (count.empty() || *stop || n < 1 || n > 0xffffffffUL || count[0] == '-' || count[0] == '+') return bad();
        if (kind == "alloc")
            f.failAllocation = static_cast<uint32_t>(n);
        else if (kind == "lost")
            f.loseDevice = static_cast<uint32_t>(n);
        else if (kind == "pipeline")
            f.failPipeline = static_cast<uint32_t>(n);
        else if (kind == "object")
            f.failObject = static_cast<uint32_t>(n);
        else
            return bad();
        pos = end + 1;
    }
    return f;
}

void Context::injectFaults(const FaultInjection& faults) {
    faults_ = faults;
    faultAllocations_ = faultSubmissions_ = faultPipelines_ = faultObjects_ = 0;
}

VkResult Context::allocateMemory(const VkMemoryAllocateInfo& info, VkDeviceMemory* memory) {
    if (faults_.failAllocation && ++faultAllocations_ == faults_.failAllocation) {
        faults_.failAllocation = 0;
        *memory = VK_NULL_HANDLE;
        return VK_ERROR_OUT_OF_DEVICE_MEMORY;
    }
    return vkAllocateMemory(device_, &info, nullptr, memory);
}

VkResult Context::submitBatch(const VkSubmitInfo& submit, VkFence fence) {
    VkResult r = submitNoWait(submit, fence);
    return r == VK_SUCCESS ? waitSubmission(fence) : r;
}

VkResult Context::submitNoWait(const VkSubmitInfo& submit, VkFence fence) {
    if (deviceLost_) return VK_ERROR_DEVICE_LOST;
    VkResult r = vkQueueSubmit(queue_, 1, &submit, fence);
    if (r == VK_ERROR_DEVICE_LOST) deviceLost_ = true;
    return r;
}

VkResult Context::waitSubmission(VkFence fence) {
    if (deviceLost_) {
        // Still waited for, a bounded time: on a lost device the wait returns at once, and after an
        // injected loss the work really runs, so the caller may reset the fence and destroy the
        // semaphores the batch used once this returns (no object in use is torn down).
        vkWaitForFences(device_, 1, &fence, VK_TRUE, kLostWaitNs);
        return VK_ERROR_DEVICE_LOST;
    }
    VkResult r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX);
    // An injected loss lets the batch finish first, so that the device stays consistent for teardown.
    if (r == VK_SUCCESS && faults_.loseDevice && ++faultSubmissions_ == faults_.loseDevice) {
        faults_.loseDevice = 0;
        r = VK_ERROR_DEVICE_LOST;
    }
    if (r == VK_ERROR_DEVICE_LOST) deviceLost_ = true;
    return r;
}

}  // namespace wrsfov::vk
