// Vulkan instance, device and queue, headless; move-only wrappers for the objects the compositor
// makes. Prefers a GPU, falls back to a CPU implementation (Mesa lavapipe), or takes a device by
// name. Optionally runs under the Khronos validation layer and counts what it reports.
#pragma once

#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <initializer_list>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "layers/status.h"

namespace wrsfov::vk {

/// Name of a VkResult, e.g. "VK_ERROR_DEVICE_LOST".
const char* resultString(VkResult r);

/// Prints file, line, call and result, then aborts: for the evaluation's scene renderer and metric, the
/// desktop preview's presentation and the tests, tools a failure may stop. The compositor, the runtime
/// and the layer return every failure of a Vulkan call as an error instead (docs/bad-input.md).
#define VK_CHECK(call)                                                                                        \
    do {                                                                                                      \
        VkResult vk_check_result_ = (call);                                                                   \
        if (vk_check_result_ != VK_SUCCESS) ::wrsfov::vk::fatal(__FILE__, __LINE__, #call, vk_check_result_); \
    } while (0)
[[noreturn]] void fatal(const char* file, int line, const char* call, VkResult r);

/// Preference of a device type when choosing a device: discrete > integrated > virtual > CPU > other.
int deviceTypeScore(VkPhysicalDeviceType type);

struct ContextOptions {
    /// Enable VK_LAYER_KHRONOS_validation (default: environment WRSFOV_VALIDATION=1).
    bool validation = false;
    /// Pick the first device whose name contains this (default: environment WRSFOV_DEVICE).
    std::string deviceName;
    /// Extra instance / device extensions (a windowed preview adds the surface ones).
    std::vector<const char*> instanceExtensions;
    std::vector<const char*> deviceExtensions;
    /// When set, a queue family is used only if this accepts it (a windowed preview asks for one
    /// that can present to its display); called with the new instance during device selection.
    std::function<bool(VkInstance, VkPhysicalDevice, uint32_t queueFamily)> queueFilter;
    /// Reads WRSFOV_VALIDATION and WRSFOV_DEVICE.
    static ContextOptions fromEnvironment();
};

/// Device faults on demand, for tests: a real device will not run out of memory or get lost when
/// asked to. Armed per Context with Context::injectFaults, or for a whole process with the
/// environment variable WRSFOV_FAULT (read by Context::create): "alloc:N", "lost:N", "pipeline:N",
/// "object:N", any of them comma-separated. Counting starts when the faults are armed; each fault fires once.
/// docs/bad-input.md ("Device faults") lists what each one leads to.
struct FaultInjection {
    /// The Nth device-memory allocation (1 = the next) fails with VK_ERROR_OUT_OF_DEVICE_MEMORY; 0: never.
    uint32_t failAllocation = 0;
    /// The Nth queue submission (1 = the next) runs, then its fence wait reports VK_ERROR_DEVICE_LOST
    /// and the context stays lost; 0: never.
    uint32_t loseDevice = 0;
    /// The Nth compute pipeline creation (1 = the next) fails with VK_ERROR_OUT_OF_DEVICE_MEMORY, one of
    /// vkCreateComputePipelines's results (a driver out of memory while compiling); 0: never.
    uint32_t failPipeline = 0;
    /// The Nth creation of an object without device memory through Context::createObject (shader
    /// modules, layouts, descriptor pools and sets, samplers, query pools, fences, command buffers;
    /// 1 = the next) fails with VK_ERROR_OUT_OF_HOST_MEMORY; 0: never.
    uint32_t failObject = 0;
    /// Parses a WRSFOV_FAULT value; fails with a message on anything else.
    static Result<FaultInjection> parse(const std::string& spec);
};

/// Pipelines made and the host time their creation took (Context::sharedPipeline), added up.
struct PipelineTally {
    uint32_t made = 0;
    double ms = 0.0;
};

/// A device made by someone else (an OpenXR application, a runtime, an engine) for Context::adopt.
struct AdoptedDevice {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physicalDevice = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t queueFamily = 0;  ///< a family with compute
    uint32_t queueIndex = 0;
};

class Context;

/// A buffer with its own memory. Host-visible buffers stay mapped.
class Buffer {
public:
    Buffer() = default;
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    ~Buffer() { reset(); }
    void reset();
    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    void* mapped() const { return mapped_; }
    explicit operator bool() const { return buffer_ != VK_NULL_HANDLE; }

private:
    friend class Context;
    VkDevice device_ = VK_NULL_HANDLE;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    void* mapped_ = nullptr;
};

struct ImageCreateInfo {
    VkFormat format = VK_FORMAT_R8G8B8A8_UNORM;
    uint32_t width = 1;
    uint32_t height = 1;
    uint32_t layers = 1;
    uint32_t mipLevels = 1;
    VkImageUsageFlags usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    VkImageCreateFlags flags = 0;
};

/// An image with its own memory and one 2D view per array layer (+ one 2D-array view).
class Image {
public:
    Image() = default;
    Image(Image&& o) noexcept { *this = std::move(o); }
    Image& operator=(Image&& o) noexcept;
    ~Image() { reset(); }
    void reset();
    VkImage handle() const { return image_; }
    /// 2D view of one layer, in `viewFormat` if given at creation, else the image format.
    VkImageView layerView(uint32_t layer) const { return layerViews_.at(layer); }
    VkImageView arrayView() const { return arrayView_; }
    const ImageCreateInfo& info() const { return info_; }
    VkImageAspectFlags aspect() const { return aspect_; }
    explicit operator bool() const { return image_ != VK_NULL_HANDLE; }

private:
    friend class Context;
    VkDevice device_ = VK_NULL_HANDLE;
    VkImage image_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    std::vector<VkImageView> layerViews_;
    VkImageView arrayView_ = VK_NULL_HANDLE;
    bool ownsImage_ = true;  // false for Context::wrapImage: only the views are ours
    ImageCreateInfo info_;
    VkImageAspectFlags aspect_ = VK_IMAGE_ASPECT_COLOR_BIT;
};

/// Generic move-only holder for a handle destroyed with vkDestroyX(device, handle, nullptr).
template <typename H, void (*Destroy)(VkDevice, H, const VkAllocationCallbacks*)>
class Handle {
public:
    Handle() = default;
    Handle(VkDevice d, H h) : device_(d), h_(h) {}
    Handle(Handle&& o) noexcept : device_(o.device_), h_(o.h_) { o.h_ = VK_NULL_HANDLE; }
    Handle& operator=(Handle&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            h_ = o.h_;
            o.h_ = VK_NULL_HANDLE;
        }
        return *this;
    }
    ~Handle() { reset(); }
    void reset() {
        if (h_ != VK_NULL_HANDLE) Destroy(device_, h_, nullptr);
        h_ = VK_NULL_HANDLE;
    }
    H get() const { return h_; }
    explicit operator bool() const { return h_ != VK_NULL_HANDLE; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    H h_ = VK_NULL_HANDLE;
};
using ShaderModule = Handle<VkShaderModule, vkDestroyShaderModule>;
using Pipeline = Handle<VkPipeline, vkDestroyPipeline>;
using PipelineLayout = Handle<VkPipelineLayout, vkDestroyPipelineLayout>;
using DescriptorSetLayout = Handle<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using DescriptorPool = Handle<VkDescriptorPool, vkDestroyDescriptorPool>;
using Sampler = Handle<VkSampler, vkDestroySampler>;
using QueryPool = Handle<VkQueryPool, vkDestroyQueryPool>;
using Fence = Handle<VkFence, vkDestroyFence>;
using Semaphore = Handle<VkSemaphore, vkDestroySemaphore>;
using CommandPool = Handle<VkCommandPool, vkDestroyCommandPool>;

/// A global memory barrier: everything in `srcStage` with `srcAccess` before, `dstStage` with
/// `dstAccess` after.
void memoryBarrier(VkCommandBuffer cb, VkPipelineStageFlags srcStage, VkAccessFlags srcAccess,
                   VkPipelineStageFlags dstStage, VkAccessFlags dstAccess);

/// Moves `layers` layers from `baseLayer` of an image's first mip level from one layout to another, after
/// all earlier work and before all later work (a full barrier: for hand-overs, not inner loops). No-op
/// if equal.
void layoutTransition(VkCommandBuffer cb, VkImage image, VkImageAspectFlags aspect, uint32_t layers,
                      VkImageLayout from, VkImageLayout to, uint32_t baseLayer = 0);

/// One descriptor write for `count` buffers or images at `binding` of `set`.
VkWriteDescriptorSet bufferWrite(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                                 const VkDescriptorBufferInfo* infos, uint32_t count = 1);
VkWriteDescriptorSet imageWrite(VkDescriptorSet set, uint32_t binding, VkDescriptorType type,
                                const VkDescriptorImageInfo* infos, uint32_t count = 1);

class Context {
public:
    /// Creates instance and device. Fails with a message naming the available devices when none
    /// fits (or the one asked for by name is not there).
    static Result<std::unique_ptr<Context>> create(const ContextOptions& options = ContextOptions::fromEnvironment());
    /// Uses a device someone else created and keeps owning: the context makes its own command pool
    /// and fence, never destroys the instance or device, and submits to the given queue, which the
    /// caller must not use from another thread while the context submits (as OpenXR's
    /// XR_KHR_vulkan_enable2 lets a runtime use the application's queue inside xrEndFrame). Instance and
    /// device may be Vulkan 1.0 (the shaders are SPIR-V 1.0) and need no extension or optional
    /// feature. Validation messages are not counted
    /// (the instance's owner installs the messenger).
    static Result<std::unique_ptr<Context>> adopt(const AdoptedDevice& device);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return props_; }
    std::string deviceName() const { return props_.deviceName; }
    bool isCpuDevice() const { return props_.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU; }
    /// Nanoseconds per timestamp tick; 0 when the queue cannot write timestamps.
    double timestampPeriodNs() const { return timestampValidBits_ ? props_.limits.timestampPeriod : 0.0; }

    /// Validation-layer messages of severity error / warning seen since creation.
    uint32_t validationErrors() const { return validationErrors_.load(); }
    uint32_t validationWarnings() const { return validationWarnings_.load(); }
    std::vector<std::string> validationMessages() const;
    bool validationEnabled() const { return validation_; }
    /// Whether the device's own fp16 conversion gave wrs_f32_to_f16's bits on every probe value
    /// (Compositor::hardwareHalf); unset until the first compositor on this context probed it.
    std::optional<bool> halfProbe() const { return halfProbe_; }
    void setHalfProbe(bool exact) { halfProbe_ = exact; }

    Result<Buffer> createBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible);
    /// viewFormat: format of the per-layer views (VK_FORMAT_UNDEFINED: the image's own format).
    Result<Image> createImage(const ImageCreateInfo& info, VkFormat viewFormat = VK_FORMAT_UNDEFINED);
    /// Views of an image someone else made on this device and keeps owning (it must match `info`):
    /// the Image destroys its views only.
    Result<Image> wrapImage(VkImage image, const ImageCreateInfo& info, VkFormat viewFormat = VK_FORMAT_UNDEFINED);
    /// Runs `create`, one vkCreate* or vkAllocate* call of an object without device memory, or fails it
    /// where FaultInjection::failObject says so: an error "<call> failed: <result>" (code = VkResult).
    Status createObject(const char* call, const std::function<VkResult()>& create);
    Result<ShaderModule> createShaderModule(const uint32_t* code, size_t bytes);
    /// A compute pipeline shared by everything on this context that makes the same one: `make` runs
    /// only on the first request for `key` (the maker's tag, shader and specialization constants; the
    /// maker must create it with a pipeline layout it always defines the same way, so that any of its
    /// instances can bind it), and the pipeline lives until the context is destroyed. A compositor
    /// made after another on the context then compiles only the variants none has used before (on
    /// lavapipe each takes ~70 ms, most of a short test's time). A failed `make` is returned and not
    /// kept: the next request tries again. Where this call made it, `tally` (if given) counts it and
    /// the host time the creation took. Thread-safe.
    Result<VkPipeline> sharedPipeline(const std::vector<uint32_t>& key, const std::function<Result<VkPipeline>()>& make,
                                      PipelineTally* tally = nullptr);
    /// A compute pipeline of `module`'s "main" with `constants` as specialization constants 0, 1, ...
    /// (32-bit each), for `layout`; the caller owns it. Fails (code = VkResult) where the driver does,
    /// or where FaultInjection::failPipeline says so.
    Result<VkPipeline> createComputePipeline(VkShaderModule module, VkPipelineLayout layout,
                                             std::span<const uint32_t> constants);
    /// How many pipelines sharedPipeline has made on this context.
    size_t sharedPipelineCount() const;
    Result<DescriptorSetLayout> createSetLayout(std::initializer_list<VkDescriptorSetLayoutBinding> bindings);
    Result<DescriptorSetLayout> createSetLayout(std::span<const VkDescriptorSetLayoutBinding> bindings);
    /// A layout with one descriptor set and `pushBytes` of push constants (none when 0).
    Result<PipelineLayout> createPipelineLayout(VkDescriptorSetLayout set, uint32_t pushBytes,
                                                VkShaderStageFlags pushStages);
    /// Copies one layer of an image to host memory, after all earlier writes. The layer, in `layout`,
    /// is copied from TRANSFER_SRC_OPTIMAL and left in `layout`.
    Result<std::vector<std::byte>> readImageLayer(VkImage image, VkImageAspectFlags aspect, uint32_t layer,
                                                  uint32_t width, uint32_t height, size_t bytes,
                                                  VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);
    /// The same for a rectangle of the layer (tightly packed rows of `bytes` in all).
    Result<std::vector<std::byte>> readImageRegion(VkImage image, VkImageAspectFlags aspect, uint32_t layer,
                                                   VkOffset2D offset, VkExtent2D extent, size_t bytes,
                                                   VkImageLayout layout = VK_IMAGE_LAYOUT_GENERAL);

    /// Records with `record`, submits, waits. Returns DeviceFailure-style errors (code = VkResult).
    Status submitAndWait(const std::function<void(VkCommandBuffer)>& record);
    /// Submits one batch to the queue and waits for `fence` (the caller resets it). Returns the
    /// result of vkQueueSubmit or vkWaitForFences. After VK_ERROR_DEVICE_LOST (real or injected) the
    /// context is lost: this and every later submission return it without touching the queue.
    VkResult submitBatch(const VkSubmitInfo& submit, VkFence fence);
    /// The two halves of submitBatch: submit without waiting, and wait for the fence of an earlier
    /// submitNoWait (injected device loss counts here, as in submitBatch).
    VkResult submitNoWait(const VkSubmitInfo& submit, VkFence fence);
    VkResult waitSubmission(VkFence fence);
    /// True once a submission reported VK_ERROR_DEVICE_LOST; only a new Context can be used then.
    bool deviceLost() const { return deviceLost_; }
    /// Test hook: arms `faults`, replacing what was armed before (see FaultInjection).
    void injectFaults(const FaultInjection& faults);
    /// Allocates a primary command buffer from the context's pool.
    Result<VkCommandBuffer> allocateCommandBuffer();
    void freeCommandBuffer(VkCommandBuffer cb);

private:
    Context() = default;
    /// Command pool, fence and the WRSFOV_FAULT faults, once the device and queue are known.
    Status initQueueObjects();
    /// One 2D view per layer and a 2D-array view of img (in viewFormat, or the image's format).
    Status createViews(Image& img, VkFormat viewFormat);
    static VKAPI_ATTR VkBool32 VKAPI_CALL debugCallback(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                        VkDebugUtilsMessageTypeFlagsEXT types,
                                                        const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
    Result<uint32_t> memoryType(uint32_t typeBits, VkMemoryPropertyFlags props) const;
    /// vkAllocateMemory, or the injected VK_ERROR_OUT_OF_DEVICE_MEMORY.
    VkResult allocateMemory(const VkMemoryAllocateInfo& info, VkDeviceMemory* memory);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    uint32_t timestampValidBits_ = 0;
    VkPhysicalDeviceProperties props_{};
    std::optional<bool> halfProbe_;
    VkPhysicalDeviceMemoryProperties memProps_{};
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    bool validation_ = false;
    bool adopted_ = false;  // instance and device belong to the caller of adopt()
    std::atomic<uint32_t> validationErrors_{0};
    std::atomic<uint32_t> validationWarnings_{0};
    mutable std::mutex pipelinesMutex_;
    std::map<std::vector<uint32_t>, VkPipeline> pipelines_;  // sharedPipeline's, destroyed with the context
    mutable std::mutex messagesMutex_;
    std::vector<std::string> messages_;
    FaultInjection faults_;
    uint32_t faultAllocations_ = 0, faultSubmissions_ = 0, faultPipelines_ = 0, faultObjects_ = 0;  // since armed
    bool deviceLost_ = false;
};

}  // namespace wrsfov::vk
