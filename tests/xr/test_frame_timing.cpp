// Frame timing through the loader: how long xrWaitFrame, xrBeginFrame and xrEndFrame take and how far
// the frame loop falls behind the display period (the overhead the Khronos CTS test
// Timed_Pipelined_Frame_Submission scores), in the simple loop and in the CTS's pipelined loop. It
// prints the figures (docs/openxr-runtime.md quotes them); CI checks only that the loops run.
// Environment: XR_RUNTIME_JSON, and the runtime's own WRSFOV_XR_* (size, method, pace); the loops
// need WRSFOV_XR_PACE=realtime to mean anything. WRSFOV_XR_TIMING_FRAMES: measured frames (200).
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <mutex>
#include <thread>

#include "tests/xr/xr_client.h"

namespace wrsfov::xrtest {
namespace {

using Clock = std::chrono::steady_clock;
double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

int frameCount() {
    const char* v = std::getenv("WRSFOV_XR_TIMING_FRAMES");
    return v ? std::max(1, std::atoi(v)) : 200;
}

/// What the application's rendering would be: a whole-image stereo layer of a swapchain it acquires,
/// waits for and releases each frame (no GPU work of its own: the loop measures the runtime).
struct Scene {
    Client& c;
    Swapchain color;
    explicit Scene(Client& client) : c(client) {
        EXPECT_EQ(c.createSwapchain(VK_FORMAT_R8G8B8A8_SRGB, c.viewWidth, c.viewHeight, 1,
                                    XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                    color),
                  XR_SUCCESS);
        std::vector<uint8_t> texels(size_t(c.viewWidth) * c.viewHeight * 4);
        for (size_t i = 0; i < texels.size(); ++i) texels[i] = uint8_t((i * 37) ^ (i >> 7));
        c.writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
    }
    void render() {
        uint32_t index = 0;
        EXPECT_EQ(xrAcquireSwapchainImage(color.handle, nullptr, &index), XR_SUCCESS);
        XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
        wi.timeout = XR_INFINITE_DURATION;
        EXPECT_EQ(xrWaitSwapchainImage(color.handle, &wi), XR_SUCCESS);
        EXPECT_EQ(xrReleaseSwapchainImage(color.handle, nullptr), XR_SUCCESS);
    }
    XrResult end(const XrFrameState& fs) {
        StereoLayer sl;
        sl.build(c, fs.predictedDisplayTime, color);
        std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
        XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
        return xrEndFrame(c.session, &fe);
    }
};

struct Totals {
    Clock::duration wait{}, begin{}, end{}, loop{};
    XrDuration period = 0;
    int frames = 0;
    void report(const char* name) const {
        const double p = double(period) * 1e-6, frame = ms(loop) / frames;
        std::printf("[timing] %s: %d frames, period %.3f ms: xrWaitFrame %.3f ms, xrBeginFrame %.3f ms, "
                    "xrEndFrame %.3f ms, frame %.3f ms, overhead %.1f %%\n",
                    name, frames, p, ms(wait) / frames, ms(begin) / frames, ms(end) / frames, frame,
                    100.0 * (frame - p) / p);
        std::fflush(stdout);
    }
};

// wait, begin, render, end on one thread, no time of its own.
TEST(XrFrameTiming, SimpleLoop) {
    auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME});
    ASSERT_TRUE(c);
    Scene scene(*c);
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    const int warmup = 30, frames = frameCount();
    Totals t;
    Clock::time_point loopStart;
    for (int i = 0; i < warmup + frames; ++i) {
        if (i == warmup) loopStart = Clock::now();
        const bool measured = i >= warmup;
        XrFrameState fs{XR_TYPE_FRAME_STATE};
        auto t0 = Clock::now();
        ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
        auto t1 = Clock::now();
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        auto t2 = Clock::now();
        scene.render();
        auto t3 = Clock::now();
        ASSERT_EQ(scene.end(fs), XR_SUCCESS);
        auto t4 = Clock::now();
        if (measured) {
            t.wait += t1 - t0, t.begin += t2 - t1, t.end += t4 - t3;
            t.period = fs.predictedDisplayPeriod;
        }
    }
    t.loop = Clock::now() - loopStart;
    t.frames = frames;
    t.report("simple loop");
}

// The simple loop with quad views (XR_VARJO_quad_views): wide views and insets at the recommended sizes,
// the insets on the gaze (XrViewLocateFoveatedRenderingVARJO); the runtime composes them at the display's
// size (its session-end line gives the compositor's time per frame, to set beside the stereo loop's).
TEST(XrFrameTiming, QuadViewsLoop) {
    auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME,
                             XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME});
    ASSERT_TRUE(c);
    XrViewConfigurationView cv[4];
    for (auto& v : cv) v = {XR_TYPE_VIEW_CONFIGURATION_VIEW};
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO,
                                                4, &n, cv),
              XR_SUCCESS);
    Swapchain sc[2];  // wide, inset; layer = eye
    for (int i = 0; i < 2; ++i) {
        const uint32_t w = cv[2 * i].recommendedImageRectWidth, h = cv[2 * i].recommendedImageRectHeight;
        ASSERT_EQ(
            c->createSwapchain(VK_FORMAT_R8G8B8A8_SRGB, w, h, 2,
                               XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT, sc[i]),
            XR_SUCCESS);
        std::vector<uint8_t> texels(size_t(w) * h * 4);
        for (size_t k = 0; k < texels.size(); ++k) texels[k] = uint8_t((k * 37) ^ (k >> 7));
        c->writeSwapchain(sc[i], 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
    }
    ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
    const int warmup = 30, frames = frameCount();
    Totals t;
    Clock::time_point loopStart;
    for (int i = 0; i < warmup + frames; ++i) {
        if (i == warmup) loopStart = Clock::now();
        const bool measured = i >= warmup;
        XrFrameState fs{XR_TYPE_FRAME_STATE};
        auto t0 = Clock::now();
        ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
        auto t1 = Clock::now();
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        auto t2 = Clock::now();
        XrViewLocateFoveatedRenderingVARJO fr{XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO, nullptr, XR_TRUE};
        XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO, &fr};
        li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
        li.displayTime = fs.predictedDisplayTime;
        li.space = c->local;
        XrViewState vs{XR_TYPE_VIEW_STATE};
        XrView v[4];
        for (auto& x : v) x = {XR_TYPE_VIEW};
        ASSERT_EQ(xrLocateViews(c->session, &li, &vs, 4, &n, v), XR_SUCCESS);
        for (auto& s : sc) {
            uint32_t index = 0;
            ASSERT_EQ(xrAcquireSwapchainImage(s.handle, nullptr, &index), XR_SUCCESS);
            XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
            wi.timeout = XR_INFINITE_DURATION;
            ASSERT_EQ(xrWaitSwapchainImage(s.handle, &wi), XR_SUCCESS);
            ASSERT_EQ(xrReleaseSwapchainImage(s.handle, nullptr), XR_SUCCESS);
        }
        auto t3 = Clock::now();
        QuadLayer ql;
        ql.build(c->local, v, sc[0], sc[1]);
        std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
        XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
        ASSERT_EQ(xrEndFrame(c->session, &fe), XR_SUCCESS);
        auto t4 = Clock::now();
        if (measured) {
            t.wait += t1 - t0, t.begin += t2 - t1, t.end += t4 - t3;
            t.period = fs.predictedDisplayPeriod;
        }
    }
    t.loop = Clock::now() - loopStart;
    t.frames = frames;
    t.report("quad views loop");
}

// The CTS's Timed_Pipelined_Frame_Submission: xrWaitFrame on one thread, which then spends 90 % of
// the period ("simulation"); xrBeginFrame, 70 % of the period ("rendering") and xrEndFrame on another.
// Here the two threads sleep rather than spin (the CTS spins), so that on a CPU device the passes get
// the cores.
TEST(XrFrameTiming, PipelinedLoop) {
    auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME});
    ASSERT_TRUE(c);
    Scene scene(*c);
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    const int warmup = 60, frames = frameCount();
    std::mutex m;
    std::condition_variable cv;
    std::deque<XrFrameState> queued;
    bool done = false;
    XrResult waitResult = XR_SUCCESS;
    Totals t;
    Clock::time_point loopStart;
    std::thread app([&] {
        for (int i = 0; i < warmup + frames; ++i) {
            if (i == warmup) loopStart = Clock::now();
            XrFrameState fs{XR_TYPE_FRAME_STATE};
            auto t0 = Clock::now();
            const XrResult r = xrWaitFrame(c->session, nullptr, &fs);
            if (i >= warmup) t.wait += Clock::now() - t0;
            if (r != XR_SUCCESS) {
                std::lock_guard lock(m);
                waitResult = r;
                break;
            }
            t.period = fs.predictedDisplayPeriod;
            std::this_thread::sleep_for(std::chrono::nanoseconds(fs.predictedDisplayPeriod * 9 / 10));
            std::lock_guard lock(m);
            queued.push_back(fs);
            cv.notify_one();
        }
        std::lock_guard lock(m);
        done = true;
        cv.notify_one();
    });
    for (int i = 0;; ++i) {
        XrFrameState fs;
        {
            std::unique_lock lock(m);
            cv.wait(lock, [&] { return !queued.empty() || done; });
            if (queued.empty()) break;
            fs = queued.front();
            queued.pop_front();
        }
        const bool measured = i >= warmup;
        auto t0 = Clock::now();
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        if (measured) t.begin += Clock::now() - t0;
        auto renderStart = Clock::now();
        scene.render();
        std::this_thread::sleep_until(renderStart + std::chrono::nanoseconds(fs.predictedDisplayPeriod * 7 / 10));
        auto t1 = Clock::now();
        ASSERT_EQ(scene.end(fs), XR_SUCCESS);
        if (measured) t.end += Clock::now() - t1;
    }
    t.loop = Clock::now() - loopStart;
    app.join();
    ASSERT_EQ(waitResult, XR_SUCCESS);
    t.frames = frames;
    t.report("pipelined loop");
}

}  // namespace
}  // namespace wrsfov::xrtest
