// wrsfov-example: what an HMD compositor does with the installed wrsfov library.
//
//  1. It owns its Vulkan instance, device and queue, and hands them to wrsfov (StereoCompositor::create).
//  2. It creates stereo swapchains (colour, depth, motion; one array layer per eye) on the compositor.
//  3. Every frame it fills them (here from the CPU: a scene panning sideways, so motion vectors are
//     non-zero and the history has to follow), takes the gaze from a synthetic eye-movement source,
//     and ends the frame. The compositor's work is submitted with a semaphore the example's own
//     "present" submission waits for: nothing on the CPU waits for the compositor's fence.
//  4. It reads both eyes' output back, prints the frame statistics and writes the outputs as PPM.
//
// usage: wrsfov-example [FRAMES] [OUT_PREFIX]   (default 60 frames, no files)
#include <vulkan/vulkan.h>

#include <wrsfov/gaze/frame_gaze.h>
#include <wrsfov/gaze/source.h>
#include <wrsfov/layers/frame.h>
#include <wrsfov/stereo_compositor.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

using namespace wrsfov;

namespace {

constexpr uint32_t kWidth = 256, kHeight = 224;

// A GPU before a CPU device (Mesa lavapipe on a machine without one).
int typeScore(VkPhysicalDeviceType t) {
    if (t == VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU) return 3;
    return t == VK_PHYSICAL_DEVICE_TYPE_CPU ? 1 : 2;
}

int fail(const std::string& what) {
    std::fprintf(stderr, "wrsfov-example: %s\n", what.c_str());
    return 1;
}

// The application's own Vulkan objects: an instance, the best device with a compute queue, a
// device with one queue, and what it needs to present (here: a command pool and a semaphore).
struct AppVulkan {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    uint32_t family = 0;
    VkQueue queue = VK_NULL_HANDLE;
    VkCommandPool pool = VK_NULL_HANDLE;
    VkSemaphore composited = VK_NULL_HANDLE;
    VkFence presented = VK_NULL_HANDLE;

    bool create(std::string& error) {
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "wrsfov-example";
        app.apiVersion = VK_API_VERSION_1_0;
        VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ici.pApplicationInfo = &app;
        if (vkCreateInstance(&ici, nullptr, &instance) != VK_SUCCESS) return error = "no Vulkan instance", false;
        uint32_t n = 0;
        vkEnumeratePhysicalDevices(instance, &n, nullptr);
        std::vector<VkPhysicalDevice> devices(n);
        vkEnumeratePhysicalDevices(instance, &n, devices.data());
        int best = -1;
        for (VkPhysicalDevice d : devices) {
            uint32_t qn = 0;
            vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, nullptr);
            std::vector<VkQueueFamilyProperties> families(qn);
            vkGetPhysicalDeviceQueueFamilyProperties(d, &qn, families.data());
            VkPhysicalDeviceProperties props;
            vkGetPhysicalDeviceProperties(d, &props);
            for (uint32_t f = 0; f < qn; ++f)
                if ((families[f].queueFlags & VK_QUEUE_COMPUTE_BIT) && typeScore(props.deviceType) > best) {
                    best = typeScore(props.deviceType);
                    physical = d;
                    family = f;
                    break;
                }
        }
        if (!physical) return error = "no Vulkan device with a compute queue", false;
        const float priority = 1.0f;
        VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qci.queueFamilyIndex = family;
        qci.queueCount = 1;
        qci.pQueuePriorities = &priority;
        VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
        dci.queueCreateInfoCount = 1;
        dci.pQueueCreateInfos = &qci;
        if (vkCreateDevice(physical, &dci, nullptr, &device) != VK_SUCCESS) return error = "no Vulkan device", false;
        vkGetDeviceQueue(device, family, 0, &queue);
        VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        pci.queueFamilyIndex = family;
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        if (vkCreateCommandPool(device, &pci, nullptr, &pool) != VK_SUCCESS ||
            vkCreateSemaphore(device, &sci, nullptr, &composited) != VK_SUCCESS ||
            vkCreateFence(device, &fci, nullptr, &presented) != VK_SUCCESS)
            return error = "no command pool, semaphore or fence", false;
        return true;
    }
    ~AppVulkan() {
        if (device) {
            vkDeviceWaitIdle(device);
            vkDestroyFence(device, presented, nullptr);
            vkDestroySemaphore(device, composited, nullptr);
            vkDestroyCommandPool(device, pool, nullptr);
            vkDestroyDevice(device, nullptr);
        }
        if (instance) vkDestroyInstance(instance, nullptr);
    }
};

// A scene the CPU can draw: stripes and a checkerboard, panning right by `speed` pixels a frame, at
// a depth that grows from the bottom of the image to the top.
struct PanningScene {
    float speed = 1.5f;
    float colour(float x, float y, int c) const {
        const float stripes = 0.5f + 0.5f * std::sin(x * 0.35f + c);
        const bool check = (int(std::floor(x / 16)) + int(std::floor(y / 16))) & 1;
        return check ? stripes : 0.25f * stripes + 0.1f * c;
    }
    void draw(uint64_t frame, HostImage& color, HostImage& depth, HostImage& motion) const {
        const float shift = speed * float(frame);
        for (uint32_t y = 0; y < kHeight; ++y)
            for (uint32_t x = 0; x < kWidth; ++x) {
                const float sx = float(x) - shift;  // scene coordinates: content moves right
                color.store(x, y, {colour(sx, float(y), 0), colour(sx, float(y), 1), colour(sx, float(y), 2), 1.0f});
                depth.store(x, y, glm::vec4(0.90f + 0.09f * float(y) / kHeight));
                // previous position = current + motion: a point now at x was at x - speed.
                motion.store(x, y, {-speed, 0.0f, 0.0f, 0.0f});
            }
    }
};

// Acquire, wait, write one layer per eye (both eyes see the same image here), release.
Status upload(layers::Swapchain& sc, const HostImage& image) {
    auto index = sc.acquire();
    if (!index) return index.error();
    if (Status s = sc.wait(); !s) return s;
    for (uint32_t eye = 0; eye < 2; ++eye)
        if (Status s = sc.write(*index, eye, image.bytes()); !s) return s;
    return sc.release();
}

bool writePpm(const HostImage& rgba, const std::string& path) {
    std::ofstream out(path, std::ios::binary);
    out << "P6\n" << rgba.width << " " << rgba.height << "\n255\n";
    for (std::size_t i = 0; i < rgba.data.size(); i += 4) out.write(reinterpret_cast<const char*>(&rgba.data[i]), 3);
    return bool(out);
}

}  // namespace

int main(int argc, char** argv) {
    const int frames = argc > 1 ? std::atoi(argv[1]) : 60;
    const std::string outPrefix = argc > 2 ? argv[2] : "";
    if (frames < 2 || frames > 100000) return fail("FRAMES must be 2..100000");

    AppVulkan app;
    std::string error;
    if (!app.create(error)) return fail(error);
    Settings settings;  // wrs, mip foveation, 5° fovea: the defaults
    auto compositor = StereoCompositor::create({app.instance, app.physical, app.device, app.family, 0}, settings);
    if (!compositor) return fail(compositor.error().message);
    StereoCompositor& comp = **compositor;
    std::printf("device: %s\n", comp.deviceName().c_str());

    auto swapchain = [&](layers::Usage usage, layers::Format format) {
        layers::SwapchainCreateInfo info;
        info.usage = usage;
        info.format = format;
        info.width = kWidth;
        info.height = kHeight;
        info.arraySize = 2;  // layer = eye
        return comp.createSwapchain(info);
    };
    auto color = swapchain(layers::Usage::Color, layers::Format::RGBA8_SRGB);
    auto depth = swapchain(layers::Usage::Depth, layers::Format::R32F);
    auto motion = swapchain(layers::Usage::Motion, layers::Format::RG16F);
    if (!color || !depth || !motion) return fail("swapchain: " + (!color ? color.error() : !depth ? depth.error() : motion.error()).message);

    gaze::GeneratorConfig gazeConfig;
    gazeConfig.mode = gaze::Mode::Scene;  // free viewing: fixations and saccades
    gazeConfig.seconds = 10;
    gazeConfig.seed = 7;
    auto gazeSource = gaze::SyntheticSource::create(gazeConfig);
    if (!gazeSource) return fail("gaze: " + gazeSource.error().message);

    HostImage colorImage = HostImage::make(layers::Format::RGBA8_SRGB, kWidth, kHeight);
    HostImage depthImage = HostImage::make(layers::Format::R32F, kWidth, kHeight);
    HostImage motionImage = HostImage::make(layers::Format::RG16F, kWidth, kHeight);
    PanningScene scene;
    VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    cai.commandPool = app.pool;
    cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    cai.commandBufferCount = 1;
    VkCommandBuffer present = VK_NULL_HANDLE;
    if (vkAllocateCommandBuffers(app.device, &cai, &present) != VK_SUCCESS) return fail("no command buffer");

    const double fps = 90.0;
    std::printf("%6s %9s %8s %6s %6s %8s\n", "frame", "gaze", "gpu ms", "depth", "motion", "history");
    for (int i = 0; i < frames; ++i) {
        const double t = i / fps;
        scene.draw(uint64_t(i), colorImage, depthImage, motionImage);
        if (Status s = upload(**color, colorImage); !s) return fail("colour: " + s.message());
        if (Status s = upload(**depth, depthImage); !s) return fail("depth: " + s.message());
        if (Status s = upload(**motion, motionImage); !s) return fail("motion: " + s.message());

        layers::FrameEndInfo frame;
        frame.frameIndex = uint64_t(i) + 1;
        frame.time_s = t;
        layers::ProjectionLayer layer;
        for (uint32_t eye = 0; eye < 2; ++eye) {
            layers::ProjectionView v;
            v.fov = {-0.80f, 0.80f, 0.72f, -0.72f};  // about 92° x 82°
            v.color = {color->get(), {0, 0, kWidth, kHeight}, eye};
            v.depth = layers::DepthInfo{{depth->get(), {0, 0, kWidth, kHeight}, eye}, 0.1f, 100.0f, false};
            v.motion = layers::MotionInfo{{motion->get(), {0, 0, kWidth, kHeight}, eye}};
            layer.views.push_back(v);
        }
        frame.layers.push_back(layer);
        const auto eyes = gaze::frame_gaze(gazeSource->get(), t);
        frame.gaze[0] = eyes[0];
        frame.gaze[1] = eyes[1];

        // The compositor submits and signals `composited`; the application's present submission
        // waits for it (here it only transitions nothing and signals the fence the CPU waits on
        // before the next frame, as a real compositor's swapchain present would).
        const VkSemaphore signal[] = {app.composited};
        FrameSubmission submission;
        submission.mode = FrameSubmission::Mode::Submit;
        submission.signalSemaphores = signal;
        if (Status s = comp.endFrame(frame, submission); !s) return fail("frame " + std::to_string(i) + ": " + s.message());

        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        vkResetCommandBuffer(present, 0);
        vkBeginCommandBuffer(present, &bi);
        vkEndCommandBuffer(present);
        const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.waitSemaphoreCount = 1;
        si.pWaitSemaphores = &app.composited;
        si.pWaitDstStageMask = &stage;
        si.commandBufferCount = 1;
        si.pCommandBuffers = &present;
        if (vkQueueSubmit(app.queue, 1, &si, app.presented) != VK_SUCCESS) return fail("present submission");
        vkWaitForFences(app.device, 1, &app.presented, VK_TRUE, UINT64_MAX);
        vkResetFences(app.device, 1, &app.presented);

        // What the frame did: waitFrame() collects its GPU time (already finished here).
        if (Status s = comp.waitFrame(); !s) return fail(s.message());
        const FrameReport st = comp.lastFrame();
        if (i % 10 == 0 || i == frames - 1)
            std::printf("%6d %9s %8.2f %6s %6s %8s\n", i + 1, st.gazeFallback[0] ? "fallback" : "tracked",
                        st.gpuMs, st.usedDepth ? "yes" : "no", st.usedMotion ? "yes" : "no",
                        st.historyReset ? "reset" : "kept");
    }

    for (uint32_t eye = 0; eye < 2; ++eye) {
        auto out = comp.readOutput(eye);
        if (!out) return fail("read back: " + out.error().message);
        double mean = 0;
        for (std::byte b : out->data) mean += double(b);
        mean /= double(out->data.size());
        std::printf("%s eye: %ux%u RGBA8 sRGB, mean %.1f\n", eye == 0 ? "left" : "right", out->width, out->height, mean);
        if (!outPrefix.empty()) {
            const std::string path = outPrefix + (eye == 0 ? "_left.ppm" : "_right.ppm");
            if (!writePpm(*out, path)) return fail("cannot write " + path);
            std::printf("wrote %s\n", path.c_str());
        }
    }
    std::printf("wrsfov-example: %d frames composited\n", frames);
    return 0;
}
