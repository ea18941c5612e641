// The integrator's front class (wrsfov/stereo_compositor.h) over the compositor and its Vulkan context.
#include "wrsfov/stereo_compositor.h"

#include "compositor/compositor.h"
#include "compositor/vk_context.h"

namespace wrsfov {

Result<CompositorConfig> compositorConfig(const Settings& s) {
    if (isOracle(s.method))
        return Error{static_cast<int>(ConfigError::InvalidValue),
                     "method " + std::string(toString(s.method)) +
                         " is for evaluation only (it needs the full-rate image); choose fov, fov+taa, wrs-paper, "
                         "wrs or taau"};
    CompositorConfig c;
    c.method = s.method;
    c.foveation = s.foveation;
    c.foveaDeg = s.foveaDeg;
    c.seed = s.seed;
    c.landedSamples = s.landedSamples;
    return c;
}

struct StereoCompositor::Impl {
    std::unique_ptr<vk::Context> context;
    std::unique_ptr<Compositor> compositor;
    Settings settings;
};

StereoCompositor::StereoCompositor(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
StereoCompositor::~StereoCompositor() {
    impl_->compositor.reset();  // before the context it runs on
}

// The settings are checked before the device is touched: a refused one makes nothing.
Result<std::unique_ptr<StereoCompositor>> StereoCompositor::make(const Settings& settings, const VulkanDevice* device) {
    auto config = compositorConfig(settings);
    if (!config) return config.error();
    auto context = device ? vk::Context::adopt({device->instance, device->physicalDevice, device->device,
                                                device->queueFamily, device->queueIndex})
                          : vk::Context::create();
    if (!context) return context.error();
    auto compositor = Compositor::create(**context, *config);
    if (!compositor) return compositor.error();
    auto impl = std::make_unique<Impl>(Impl{std::move(*context), std::move(*compositor), settings});
    return std::unique_ptr<StereoCompositor>(new StereoCompositor(std::move(impl)));
}

Result<std::unique_ptr<StereoCompositor>> StereoCompositor::create(const VulkanDevice& device, const Settings& settings) {
    return make(settings, &device);
}

Result<std::unique_ptr<StereoCompositor>> StereoCompositor::createOnOwnDevice(const Settings& settings) {
    return make(settings, nullptr);
}

Result<std::unique_ptr<layers::Swapchain>> StereoCompositor::createSwapchain(const layers::SwapchainCreateInfo& info,
                                                                             const SwapchainImageOptions& options) {
    return impl_->compositor->createSwapchain(info, options);
}

Result<std::unique_ptr<layers::Swapchain>> StereoCompositor::importSwapchain(const layers::SwapchainCreateInfo& info,
                                                                             std::span<const VkImage> images,
                                                                             const SwapchainImageOptions& options) {
    return impl_->compositor->importSwapchain(info, images, options);
}

Status StereoCompositor::endFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission) {
    return impl_->compositor->endFrame(frame, submission);
}

Status StereoCompositor::waitFrame() { return impl_->compositor->waitFrame(); }

FrameReport StereoCompositor::lastFrame() const {
    const Compositor& c = *impl_->compositor;
    const FrameStats& s = c.stats();
    FrameReport r;
    r.frameIndex = s.frameIndex;
    r.gpuMs = s.gpu.total;
    r.gpuTimed = s.gpu.valid;
    r.gazeFallback = {s.gazeFallback[0], s.gazeFallback[1]};
    r.usedDepth = s.usedDepth;
    r.usedMotion = s.usedMotion;
    r.historyReset = s.historyReset;
    r.submitted = c.lastSubmitted();
    r.pipelinesMade = s.pipelinesMade;
    r.pipelineMs = s.pipelineMs;
    return r;
}

VkImage StereoCompositor::outputImage() const { return impl_->compositor->outputImage().handle(); }
uint32_t StereoCompositor::width() const { return impl_->compositor->width(); }
uint32_t StereoCompositor::height() const { return impl_->compositor->height(); }
Result<HostImage> StereoCompositor::readOutput(uint32_t eye) { return impl_->compositor->readOutput(eye); }

Settings StereoCompositor::settings() const { return impl_->settings; }

Status StereoCompositor::setSettings(const Settings& settings) {
    auto config = compositorConfig(settings);
    if (!config) return config.error();
    if (Status s = impl_->compositor->setConfig(*config); !s) return s;
    impl_->settings = settings;
    return {};
}

void StereoCompositor::resetHistory() { impl_->compositor->resetHistory(); }

std::string StereoCompositor::deviceName() const { return impl_->context->deviceName(); }

}  // namespace wrsfov
