// Our own OpenXR client against the runtime, through the Khronos loader: what hello_xr does not
// do. Every call the runtime refuses, with its XrResult; the session state machine and frame
// order; array swapchains with depth, recorded and checked; the eye-gaze action.
// Environment (tests/xr/CMakeLists.txt): XR_RUNTIME_JSON, WRSFOV_XR_PACE=free, a small view size.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <unistd.h>
#include <glm/gtc/packing.hpp>
#include <opencv2/imgcodecs.hpp>

#include "eval/sequence.h"
#include "tests/xr/xr_client.h"

namespace wrsfov::xrtest {
namespace {

const std::vector<const char*> kExtensions = {XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME,
                                              XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME,
                                              XR_EXT_EYE_GAZE_INTERACTION_EXTENSION_NAME,
                                              XR_FB_SPACE_WARP_EXTENSION_NAME};
constexpr int64_t kSrgb = VK_FORMAT_R8G8B8A8_SRGB;
constexpr XrSwapchainUsageFlags kColorUsage =
    XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;

// A recording directory of this process's own, emptied first and removed afterwards: ctest runs the
// same test binary in several entries at once (plain, under core validation, through the layer), and
// a shared name let one entry delete the directory another was writing.
struct RecordDir {
    std::string path;
    explicit RecordDir(const std::string& name)
        : path(std::string(::testing::TempDir()) + name + "_" + std::to_string(::getpid())) {
        std::filesystem::remove_all(path);
    }
    ~RecordDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

XrPath path(XrInstance i, const char* s) {
    XrPath p = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(i, s, &p), XR_SUCCESS) << s;
    return p;
}

/// A checkerboard of `cell` pixels in two colours, RGBA8.
std::vector<uint8_t> checker(uint32_t w, uint32_t h, uint32_t cell, uint8_t a, uint8_t b) {
    std::vector<uint8_t> t(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const uint8_t v = ((x / cell + y / cell) % 2) ? a : b;
            uint8_t* p = &t[(size_t(y) * w + x) * 4];
            p[0] = v, p[1] = uint8_t(255 - v), p[2] = uint8_t(x * 255 / w), p[3] = 255;
        }
    return t;
}

/// Runs frames until the session is FOCUSED (READY -> begin -> first frames).
void runToFocused(Client& c, const Swapchain& color) {
    ASSERT_EQ(c.begin(), XR_SUCCESS);
    for (int i = 0; i < 3; ++i) {
        XrResult r = c.frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(c, fs.predictedDisplayTime, color);
            std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c.session, &fe);
        });
        ASSERT_EQ(r, XR_SUCCESS);
    }
}

TEST(XrClient, InstanceAndSystemRefusals) {
    // An extension the runtime does not have.
    XrInstanceCreateInfo ici{XR_TYPE_INSTANCE_CREATE_INFO};
    std::snprintf(ici.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "refusals");
    ici.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    const char* bogus[] = {"XR_WRSFOV_no_such_extension"};
    ici.enabledExtensionCount = 1;
    ici.enabledExtensionNames = bogus;
    XrInstance inst = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateInstance(&ici, &inst), XR_ERROR_EXTENSION_NOT_PRESENT);

    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    XrSystemGetInfo sgi{XR_TYPE_SYSTEM_GET_INFO};
    sgi.formFactor = XR_FORM_FACTOR_HANDHELD_DISPLAY;
    XrSystemId sys = 0;
    EXPECT_EQ(xrGetSystem(c->instance, &sgi, &sys), XR_ERROR_FORM_FACTOR_UNSUPPORTED);
    XrSystemProperties props{XR_TYPE_SYSTEM_PROPERTIES};
    EXPECT_EQ(xrGetSystemProperties(c->instance, 42, &props), XR_ERROR_SYSTEM_INVALID);
    XrSystemEyeGazeInteractionPropertiesEXT eye{XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
    props.next = &eye;
    ASSERT_EQ(xrGetSystemProperties(c->instance, c->system, &props), XR_SUCCESS);
    EXPECT_EQ(eye.supportsEyeGazeInteraction, XR_TRUE);
    EXPECT_EQ(props.graphicsProperties.maxLayerCount, 16u);

    uint32_t n = 0;
    XrViewConfigurationView one[1] = {{XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    EXPECT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 1,
                                                &n, one),
              XR_ERROR_SIZE_INSUFFICIENT);
    EXPECT_EQ(n, 2u);
    EXPECT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO, 0,
                                                &n, nullptr),
              XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
    EXPECT_EQ(c->viewWidth, 64u);  // WRSFOV_XR_WIDTH in the test's environment

    XrPath p = XR_NULL_PATH;
    EXPECT_EQ(xrStringToPath(c->instance, "/user/hand//left", &p), XR_ERROR_PATH_FORMAT_INVALID);
    EXPECT_EQ(xrStringToPath(c->instance, "user/hand/left", &p), XR_ERROR_PATH_FORMAT_INVALID);
    EXPECT_EQ(xrStringToPath(c->instance, "/User/hand", &p), XR_ERROR_PATH_FORMAT_INVALID);
    char buf[64];
    EXPECT_EQ(xrPathToString(c->instance, 987654, 64, &n, buf), XR_ERROR_PATH_INVALID);
    const XrPath left = path(c->instance, "/user/hand/left");
    EXPECT_EQ(path(c->instance, "/user/hand/left"), left);  // interned once
    ASSERT_EQ(xrPathToString(c->instance, left, 64, &n, buf), XR_SUCCESS);
    EXPECT_STREQ(buf, "/user/hand/left");
    EXPECT_EQ(n, 16u);
    EXPECT_EQ(xrPathToString(c->instance, left, 4, &n, buf), XR_ERROR_SIZE_INSUFFICIENT);

    // Handles that are not live.
    XrSession dead = reinterpret_cast<XrSession>(uintptr_t(0x1234));
    EXPECT_EQ(xrBeginSession(dead, nullptr), XR_ERROR_HANDLE_INVALID);
    XrSessionCreateInfo sci{XR_TYPE_SESSION_CREATE_INFO};
    sci.systemId = c->system;
    XrSession second = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateSession(c->instance, &sci, &second), XR_ERROR_GRAPHICS_DEVICE_INVALID);  // no binding
}

TEST(XrClient, SessionStateMachineAndFrameOrder) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    EXPECT_EQ(Client::states(c->poll()),
              (std::vector<XrSessionState>{XR_SESSION_STATE_IDLE, XR_SESSION_STATE_READY}));
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    EXPECT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_ERROR_SESSION_NOT_RUNNING);
    XrSessionBeginInfo mono{XR_TYPE_SESSION_BEGIN_INFO};
    mono.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO;
    EXPECT_EQ(xrBeginSession(c->session, &mono), XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    EXPECT_EQ(c->begin(), XR_ERROR_SESSION_RUNNING);

    EXPECT_EQ(xrBeginFrame(c->session, nullptr), XR_ERROR_CALL_ORDER_INVALID);  // no xrWaitFrame
    XrFrameEndInfo empty = frameEnd(1, {});
    EXPECT_EQ(xrEndFrame(c->session, &empty), XR_ERROR_CALL_ORDER_INVALID);  // no xrBeginFrame
    ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
    EXPECT_GT(fs.predictedDisplayTime, 0);
    EXPECT_EQ(fs.predictedDisplayPeriod, XrDuration(11111111));  // 90 Hz
    EXPECT_EQ(Client::states(c->poll()),
              (std::vector<XrSessionState>{XR_SESSION_STATE_SYNCHRONIZED, XR_SESSION_STATE_VISIBLE,
                                           XR_SESSION_STATE_FOCUSED}));
    EXPECT_EQ(fs.shouldRender, XR_TRUE);
    ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
    XrFrameState fs2{XR_TYPE_FRAME_STATE};
    ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs2), XR_SUCCESS);
    EXPECT_EQ(fs2.predictedDisplayTime - fs.predictedDisplayTime, fs.predictedDisplayPeriod);
    EXPECT_EQ(xrBeginFrame(c->session, nullptr), XR_FRAME_DISCARDED);  // the first was never ended
    XrFrameEndInfo none = frameEnd(fs2.predictedDisplayTime, {});
    EXPECT_EQ(xrEndFrame(c->session, &none), XR_SUCCESS);  // zero layers is a valid frame

    EXPECT_EQ(xrEndSession(c->session), XR_ERROR_SESSION_NOT_STOPPING);
    ASSERT_EQ(xrRequestExitSession(c->session), XR_SUCCESS);
    EXPECT_EQ(Client::states(c->poll()),
              (std::vector<XrSessionState>{XR_SESSION_STATE_VISIBLE, XR_SESSION_STATE_SYNCHRONIZED,
                                           XR_SESSION_STATE_STOPPING}));
    ASSERT_EQ(xrEndSession(c->session), XR_SUCCESS);
    EXPECT_EQ(Client::states(c->poll()),
              (std::vector<XrSessionState>{XR_SESSION_STATE_IDLE, XR_SESSION_STATE_EXITING}));
    EXPECT_EQ(xrEndSession(c->session), XR_ERROR_SESSION_NOT_RUNNING);
    EXPECT_EQ(xrRequestExitSession(c->session), XR_ERROR_SESSION_NOT_RUNNING);
}

TEST(XrClient, SwapchainRefusals) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    Swapchain sc;
    EXPECT_EQ(c->createSwapchain(VK_FORMAT_B5G6R5_UNORM_PACK16, 64, 64, 1, kColorUsage, sc),
              XR_ERROR_SWAPCHAIN_FORMAT_UNSUPPORTED);
    EXPECT_EQ(c->createSwapchain(kSrgb, 0, 64, 1, kColorUsage, sc), XR_ERROR_VALIDATION_FAILURE);
    EXPECT_EQ(c->createSwapchain(kSrgb, 64, 64, 0, kColorUsage, sc), XR_ERROR_VALIDATION_FAILURE);
    EXPECT_EQ(c->createSwapchain(kSrgb, 64, 64, 1, kColorUsage, sc, XR_SWAPCHAIN_CREATE_PROTECTED_CONTENT_BIT),
              XR_ERROR_FEATURE_UNSUPPORTED);
    EXPECT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, 64, 64, 1, XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT, sc),
              XR_ERROR_FEATURE_UNSUPPORTED);  // a depth format as colour attachment
    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.format = kSrgb, ci.width = ci.height = 64, ci.faceCount = ci.arraySize = ci.mipCount = 1;
    ci.sampleCount = 4;
    ci.usageFlags = kColorUsage;
    XrSwapchain h = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateSwapchain(c->session, &ci, &h), XR_ERROR_FEATURE_UNSUPPORTED);
    ci.sampleCount = 1;
    ci.type = XR_TYPE_SESSION_CREATE_INFO;  // wrong structure type
    EXPECT_EQ(xrCreateSwapchain(c->session, &ci, &h), XR_ERROR_VALIDATION_FAILURE);

    ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 1, kColorUsage, sc), XR_SUCCESS);
    // Three images; four in the runtime's strict setting (WRSFOV_XR_SWAPCHAINS=strict), as another
    // runtime may make.
    const char* mode = std::getenv("WRSFOV_XR_SWAPCHAINS");
    const uint32_t count = mode && std::string(mode) == "strict" ? 4u : 3u;
    ASSERT_EQ(sc.images.size(), count);
    XrSwapchainImageBaseHeader wrong[4] = {{XR_TYPE_SWAPCHAIN_IMAGE_OPENGL_KHR}};
    uint32_t n = 0;
    EXPECT_EQ(xrEnumerateSwapchainImages(sc.handle, count, &n, wrong), XR_ERROR_VALIDATION_FAILURE);
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    EXPECT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_ERROR_CALL_ORDER_INVALID);       // nothing acquired
    EXPECT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_ERROR_CALL_ORDER_INVALID);  // nothing waited
    uint32_t idx[5];
    for (uint32_t i = 0; i < count; ++i) ASSERT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &idx[i]), XR_SUCCESS);
    EXPECT_EQ(idx[0], 0u);
    EXPECT_EQ(idx[count - 1], count - 1);
    EXPECT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &idx[count]), XR_ERROR_CALL_ORDER_INVALID);  // all acquired
    EXPECT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_ERROR_CALL_ORDER_INVALID);  // acquired, not waited
    ASSERT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_SUCCESS);
    ASSERT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_SUCCESS);
    EXPECT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_ERROR_CALL_ORDER_INVALID);  // released twice

    // A static swapchain is acquired once in its life.
    Swapchain st;
    ASSERT_EQ(c->createSwapchain(kSrgb, 32, 32, 1, kColorUsage, st, XR_SWAPCHAIN_CREATE_STATIC_IMAGE_BIT),
              XR_SUCCESS);
    EXPECT_EQ(st.images.size(), 1u);
    c->writeSwapchain(st, 4, VK_IMAGE_ASPECT_COLOR_BIT, [](uint32_t) { return checker(32, 32, 4, 0, 255); });
    EXPECT_EQ(xrAcquireSwapchainImage(st.handle, nullptr, &idx[0]), XR_ERROR_CALL_ORDER_INVALID);

    ASSERT_EQ(xrDestroySwapchain(sc.handle), XR_SUCCESS);
    EXPECT_EQ(xrDestroySwapchain(sc.handle), XR_ERROR_HANDLE_INVALID);
    EXPECT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &idx[0]), XR_ERROR_HANDLE_INVALID);
}

TEST(XrClient, FrameEndRefusalsChangeNothing) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    Swapchain color, unreleased, depth;
    ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 2, kColorUsage, color), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 1, kColorUsage, unreleased), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, 64, 64, 2,
                                 XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                 depth),
              XR_SUCCESS);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [](uint32_t) { return checker(64, 64, 4, 0, 255); });
    c->writeSwapchain(depth, 4, VK_IMAGE_ASPECT_DEPTH_BIT, [](uint32_t) { return std::vector<uint8_t>(64 * 64 * 4); });
    runToFocused(*c, color);

    // Each case: a broken copy of a good frame end, its expected result.
    struct Case {
        const char* what;
        std::function<void(StereoLayer&, XrFrameEndInfo&)> spoil;
        XrResult want;
    };
    XrCompositionLayerCylinderKHR cylinder{XR_TYPE_COMPOSITION_LAYER_CYLINDER_KHR};
    std::vector<const XrCompositionLayerBaseHeader*> tooMany(17);
    const XrCompositionLayerBaseHeader* nullLayer[1] = {nullptr};
    const XrCompositionLayerBaseHeader* cylinderLayer[1] = {
        reinterpret_cast<const XrCompositionLayerBaseHeader*>(&cylinder)};
    const std::vector<Case> cases = {
        {"rect beyond the image", [](StereoLayer& s, XrFrameEndInfo&) { s.views[1].subImage.imageRect.extent.width = 65; },
         XR_ERROR_SWAPCHAIN_RECT_INVALID},
        {"negative rect offset", [](StereoLayer& s, XrFrameEndInfo&) { s.views[0].subImage.imageRect.offset.y = -1; },
         XR_ERROR_SWAPCHAIN_RECT_INVALID},
        {"array index out of range", [](StereoLayer& s, XrFrameEndInfo&) { s.views[1].subImage.imageArrayIndex = 2; },
         XR_ERROR_VALIDATION_FAILURE},
        {"one view", [](StereoLayer& s, XrFrameEndInfo&) { s.layer.viewCount = 1; }, XR_ERROR_VALIDATION_FAILURE},
        {"wrong view type", [](StereoLayer& s, XrFrameEndInfo&) { s.views[0].type = XR_TYPE_VIEW; },
         XR_ERROR_VALIDATION_FAILURE},
        {"unnormalised pose", [](StereoLayer& s, XrFrameEndInfo&) { s.views[0].pose.orientation.w = 2.0f; },
         XR_ERROR_POSE_INVALID},
        {"NaN field of view", [](StereoLayer& s, XrFrameEndInfo&) { s.views[1].fov.angleUp = std::nanf(""); },
         XR_ERROR_VALIDATION_FAILURE},
        {"swapchain never released",
         [&](StereoLayer& s, XrFrameEndInfo&) { s.views[1].subImage.swapchain = unreleased.handle; },
         XR_ERROR_LAYER_INVALID},
        {"destroyed space", [](StereoLayer& s, XrFrameEndInfo&) { s.layer.space = reinterpret_cast<XrSpace>(uintptr_t(8)); },
         XR_ERROR_HANDLE_INVALID},
        {"depth near == far",
         [&](StereoLayer& s, XrFrameEndInfo&) {
             s.depth[0].farZ = s.depth[0].nearZ;
         },
         XR_ERROR_VALIDATION_FAILURE},
        {"depth range inverted", [&](StereoLayer& s, XrFrameEndInfo&) { s.depth[1].minDepth = 1.0f; },
         XR_ERROR_VALIDATION_FAILURE},
        {"additive blend", [](StereoLayer&, XrFrameEndInfo& f) { f.environmentBlendMode = XR_ENVIRONMENT_BLEND_MODE_ADDITIVE; },
         XR_ERROR_ENVIRONMENT_BLEND_MODE_UNSUPPORTED},
        {"display time 0", [](StereoLayer&, XrFrameEndInfo& f) { f.displayTime = 0; }, XR_ERROR_TIME_INVALID},
        {"17 layers", [&](StereoLayer&, XrFrameEndInfo& f) { f.layerCount = 17, f.layers = tooMany.data(); },
         XR_ERROR_LAYER_LIMIT_EXCEEDED},
        {"null layer", [&](StereoLayer&, XrFrameEndInfo& f) { f.layers = nullLayer; }, XR_ERROR_LAYER_INVALID},
        {"cylinder layer", [&](StereoLayer&, XrFrameEndInfo& f) { f.layers = cylinderLayer; }, XR_ERROR_LAYER_INVALID},
        {"wrong frame end type", [](StereoLayer&, XrFrameEndInfo& f) { f.type = XR_TYPE_FRAME_STATE; },
         XR_ERROR_VALIDATION_FAILURE},
    };
    for (const Case& k : cases) {
        XrResult r = c->frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(*c, fs.predictedDisplayTime, color, nullptr, &depth);
            cylinder.space = c->local;
            std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            k.spoil(sl, fe);
            EXPECT_EQ(xrEndFrame(c->session, &fe), k.want) << k.what;
            // The refused frame is still open: a good frame end closes it.
            StereoLayer good;
            good.build(*c, fs.predictedDisplayTime, color, nullptr, &depth);
            std::vector<const XrCompositionLayerBaseHeader*> gl{good.header()};
            XrFrameEndInfo gf = frameEnd(fs.predictedDisplayTime, gl);
            return xrEndFrame(c->session, &gf);
        });
        EXPECT_EQ(r, XR_SUCCESS) << "good frame after: " << k.what;
    }
}

// Both eyes in one array swapchain (layer = eye), depth in another, recorded by the runtime: the
// recording holds the right eye's own layer and the depth, and the output is the input at the gaze.
TEST(XrClient, ArraySwapchainsWithDepthAreCompositedAndRecorded) {
    const RecordDir rec("wrsfov_xr_client_rec");
    const std::string& dir = rec.path;
    setenv("WRSFOV_XR_RECORD", dir.c_str(), 1);
    auto c = Client::create(kExtensions);
    unsetenv("WRSFOV_XR_RECORD");
    ASSERT_TRUE(c);
    const uint32_t w = c->viewWidth, h = c->viewHeight;
    Swapchain color, depth;
    ASSERT_EQ(c->createSwapchain(kSrgb, w, h, 2, kColorUsage, color), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, w, h, 2,
                                 XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                 depth),
              XR_SUCCESS);
    const auto left = checker(w, h, 2, 20, 230), right = checker(w, h, 3, 90, 160);
    std::vector<uint8_t> z(size_t(w) * h * 4);
    for (uint32_t i = 0; i < w * h; ++i) {
        const float d = 0.5f + 0.4f * float(i % w) / float(w);
        std::memcpy(&z[i * 4], &d, 4);
    }
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    const int frames = 6;
    for (int f = 0; f < frames; ++f) {
        c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t l) { return l ? right : left; });
        c->writeSwapchain(depth, 4, VK_IMAGE_ASPECT_DEPTH_BIT, [&](uint32_t) { return z; });
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(*c, fs.predictedDisplayTime, color, nullptr, &depth);
            std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS);
    }
    c.reset();  // destroying the session closes the recording

    auto opened = eval::SequenceReader::open(dir);
    ASSERT_TRUE(opened) << opened.error().message;
    auto& r = *opened;
    EXPECT_EQ(r->info().frameCount, uint32_t(frames));
    ASSERT_TRUE(r->info().depth.has_value());
    EXPECT_FLOAT_EQ(r->info().depth->nearZ, 0.1f);
    EXPECT_FALSE(r->info().depth->reversedZ);
    auto last = r->frame(frames - 1);
    ASSERT_TRUE(last) << last.error().message;
    for (int e = 0; e < 2; ++e) {
        const auto& want = e ? right : left;
        const auto& got = last->eyes[e].color.data;
        ASSERT_EQ(got.size(), want.size());
        EXPECT_EQ(0, std::memcmp(got.data(), want.data(), want.size())) << "eye " << e << " is not its array layer";
        ASSERT_TRUE(last->eyes[e].depth.has_value());
        float d;
        std::memcpy(&d, last->eyes[e].depth->data.data() + 4 * (w / 2), 4);
        EXPECT_NEAR(d, 0.5f + 0.4f * float(w / 2) / float(w), 1e-6f);
        // The fine checkerboard is blurred away from the gaze: the output differs from the input.
        cv::Mat out = cv::imread(dir + "/" + eval::frameFileName(frames - 1, e, "output.png"));
        ASSERT_FALSE(out.empty());
        double diff = 0;
        for (uint32_t y = 0; y < h; ++y)
            for (uint32_t x = 0; x < w; ++x) diff += std::abs(double(out.at<cv::Vec3b>(y, x)[2]) - want[(y * w + x) * 4]);
        EXPECT_GT(diff / (w * h), 10.0) << "eye " << e << " looks unfoveated";
    }
}

// XR_FB_space_warp: motion in NDC (current - previous) and its depth, converted to the compositor's
// pixels (previous = current + mv); recorded in pixels. Refusals of a bad space-warp info.
TEST(XrClient, SpaceWarpMotionReachesTheCompositorInPixels) {
    const RecordDir rec("wrsfov_xr_client_warp");
    const std::string& dir = rec.path;
    setenv("WRSFOV_XR_RECORD", dir.c_str(), 1);
    auto c = Client::create(kExtensions);
    unsetenv("WRSFOV_XR_RECORD");
    ASSERT_TRUE(c);
    const uint32_t w = c->viewWidth, h = c->viewHeight;
    Swapchain color, motion, depth;
    ASSERT_EQ(c->createSwapchain(kSrgb, w, h, 2, kColorUsage, color), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_R16G16B16A16_SFLOAT, w, h, 2, kColorUsage, motion), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, w, h, 2,
                                 XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT,
                                 depth),
              XR_SUCCESS);
    // Everything moved 3 px right and 2 px up since the last frame: NDC (+6/w, -4/h); z is an NDC
    // depth change the runtime must ignore.
    std::vector<uint8_t> mv(size_t(w) * h * 8);
    const uint16_t texel[4] = {glm::packHalf1x16(6.0f / float(w)), glm::packHalf1x16(-4.0f / float(h)),
                               glm::packHalf1x16(0.25f), 0};
    for (size_t i = 0; i < size_t(w) * h; ++i) std::memcpy(&mv[i * 8], texel, 8);
    std::vector<uint8_t> z(size_t(w) * h * 4);
    const float half = 0.5f;
    for (size_t i = 0; i < size_t(w) * h; ++i) std::memcpy(&z[i * 4], &half, 4);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return checker(w, h, 4, 10, 240); });
    c->writeSwapchain(motion, 8, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return mv; });
    c->writeSwapchain(depth, 4, VK_IMAGE_ASPECT_DEPTH_BIT, [&](uint32_t) { return z; });
    ASSERT_EQ(c->begin(), XR_SUCCESS);

    struct Case {
        const char* what;
        std::function<void(XrCompositionLayerSpaceWarpInfoFB&)> spoil;
        XrResult want;
    };
    const std::vector<Case> cases = {
        {"good", [](XrCompositionLayerSpaceWarpInfoFB&) {}, XR_SUCCESS},
        {"near == far", [](XrCompositionLayerSpaceWarpInfoFB& s) { s.farZ = s.nearZ; }, XR_ERROR_VALIDATION_FAILURE},
        {"empty depth range", [](XrCompositionLayerSpaceWarpInfoFB& s) { s.minDepth = s.maxDepth; },
         XR_ERROR_VALIDATION_FAILURE},
        {"unknown flag", [](XrCompositionLayerSpaceWarpInfoFB& s) { s.layerFlags = 0x80; },
         XR_ERROR_VALIDATION_FAILURE},
        {"bad delta pose", [](XrCompositionLayerSpaceWarpInfoFB& s) { s.appSpaceDeltaPose.orientation.w = 0.5f; },
         XR_ERROR_POSE_INVALID},
        // XrPosef{} (a zero quaternion): what an application without locomotion leaves there; read as
        // the identity.
        {"zero-initialised delta pose", [](XrCompositionLayerSpaceWarpInfoFB& s) { s.appSpaceDeltaPose = XrPosef{}; },
         XR_SUCCESS},
        {"motion rect outside",
         [](XrCompositionLayerSpaceWarpInfoFB& s) { s.motionVectorSubImage.imageRect.offset.x = 1; },
         XR_ERROR_SWAPCHAIN_RECT_INVALID},
        {"good again", [](XrCompositionLayerSpaceWarpInfoFB&) {}, XR_SUCCESS},
    };
    for (const Case& k : cases) {
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(*c, fs.predictedDisplayTime, color);
            XrCompositionLayerSpaceWarpInfoFB warp[2];
            for (int e = 0; e < 2; ++e) {
                warp[e] = {XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB};
                warp[e].motionVectorSubImage = {motion.handle, {{0, 0}, {int32_t(w), int32_t(h)}}, uint32_t(e)};
                warp[e].depthSubImage = {depth.handle, {{0, 0}, {int32_t(w), int32_t(h)}}, uint32_t(e)};
                warp[e].appSpaceDeltaPose.orientation.w = 1.0f;
                warp[e].minDepth = 0.0f, warp[e].maxDepth = 1.0f, warp[e].nearZ = 0.1f, warp[e].farZ = 100.0f;
                sl.views[e].next = &warp[e];
            }
            k.spoil(warp[1]);
            std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            EXPECT_EQ(xrEndFrame(c->session, &fe), k.want) << k.what;
            if (k.want == XR_SUCCESS) return XR_SUCCESS;
            XrFrameEndInfo none = frameEnd(fs.predictedDisplayTime, {});
            return xrEndFrame(c->session, &none);
        }),
                  XR_SUCCESS);
    }
    c.reset();

    auto opened = eval::SequenceReader::open(dir);
    ASSERT_TRUE(opened) << opened.error().message;
    auto& r = *opened;
    EXPECT_EQ(r->info().frameCount, 3u);  // the three good frames
    ASSERT_TRUE(r->info().motion.has_value());
    EXPECT_EQ(*r->info().motion, eval::MotionUnits::Pixels);
    ASSERT_TRUE(r->info().depth.has_value());  // from the space-warp info
    auto f = r->frame(1);
    ASSERT_TRUE(f) << f.error().message;
    for (int e = 0; e < 2; ++e) {
        ASSERT_TRUE(f->eyes[e].motion.has_value());
        const glm::vec4 m = f->eyes[e].motion->fetch(w / 2, h / 3);
        EXPECT_NEAR(m.x, -3.0f, 0.01f) << "eye " << e;  // previous position is 3 px to the left
        EXPECT_NEAR(m.y, 2.0f, 0.01f) << "eye " << e;   // and 2 px lower (y down)
        EXPECT_EQ(m.z, 0.0f) << "eye " << e;            // the NDC depth change is not a linear dz
    }
    // With depth submitted, both eyes verge on the surface under the gaze: depth 0.5 everywhere with
    // near 0.1 m, far 100 m is 0.1 * 100 / (100 - 0.5 * 99.9) = 0.1998 m. The eyes' rays (from
    // -/+ IPD/2) meet there.
    uint32_t valid = 0;
    for (uint32_t i = 0; i < r->info().frameCount; ++i) {
        const auto& g = r->gaze(i);
        if (!g[0].valid || !g[1].valid) continue;
        ++valid;
        const glm::vec3 eL(-0.0315f, 0, 0), eR(0.0315f, 0, 0), l = g[0].dir, rr = g[1].dir;
        // Closest approach of the two rays (they intersect up to rounding).
        const glm::vec3 w0 = eL - eR;
        const float a = glm::dot(l, l), b = glm::dot(l, rr), cc = glm::dot(rr, rr), d = glm::dot(l, w0),
                    e2 = glm::dot(rr, w0);
        const float s = (b * e2 - cc * d) / (a * cc - b * b);
        const glm::vec3 p = eL + s * l;
        EXPECT_NEAR(-p.z, 0.1998f, 0.002f) << "frame " << i;
    }
    EXPECT_GT(valid, 0u) << "no frame with valid gaze to check the vergence on";
}

// Quad layers after the projection layer are drawn over the composited output: an opaque quad 1 m
// ahead in VIEW space shows its colour where each eye looks straight ahead; a left-eye-only quad
// shows in the left eye only.
TEST(XrClient, QuadLayersAreDrawnOverTheProjection) {
    const RecordDir rec("wrsfov_xr_client_quad");
    const std::string& dir = rec.path;
    setenv("WRSFOV_XR_RECORD", dir.c_str(), 1);
    auto c = Client::create(kExtensions);
    unsetenv("WRSFOV_XR_RECORD");
    ASSERT_TRUE(c);
    const uint32_t w = c->viewWidth, h = c->viewHeight;
    Swapchain color, red, green;
    ASSERT_EQ(c->createSwapchain(kSrgb, w, h, 2, kColorUsage, color), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(kSrgb, 16, 16, 1, kColorUsage, red), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(kSrgb, 16, 16, 1, kColorUsage, green), XR_SUCCESS);
    auto solid = [](uint8_t r, uint8_t g, uint8_t b) {
        std::vector<uint8_t> t(16 * 16 * 4);
        for (size_t i = 0; i < 16 * 16; ++i) t[i * 4] = r, t[i * 4 + 1] = g, t[i * 4 + 2] = b, t[i * 4 + 3] = 255;
        return t;
    };
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return checker(w, h, 2, 0, 255); });
    c->writeSwapchain(red, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return solid(200, 40, 40); });
    c->writeSwapchain(green, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return solid(30, 220, 60); });
    XrReferenceSpaceCreateInfo rci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    rci.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace view;
    ASSERT_EQ(xrCreateReferenceSpace(c->session, &rci, &view), XR_SUCCESS);
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    for (int f = 0; f < 2; ++f)
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(*c, fs.predictedDisplayTime, color);
            XrCompositionLayerQuad q[3] = {
                {XR_TYPE_COMPOSITION_LAYER_QUAD}, {XR_TYPE_COMPOSITION_LAYER_QUAD}, {XR_TYPE_COMPOSITION_LAYER_QUAD}};
            for (int k = 0; k < 3; ++k) {
                q[k].space = view;
                q[k].pose.orientation.w = 1.0f;
                q[k].subImage.swapchain = k ? green.handle : red.handle;
                q[k].subImage.imageRect = {{0, 0}, {16, 16}};
            }
            q[0].eyeVisibility = XR_EYE_VISIBILITY_BOTH;
            q[0].pose.position = {0.0f, 0.0f, -1.0f};
            q[0].size = {0.4f, 0.4f};
            q[1].eyeVisibility = XR_EYE_VISIBILITY_LEFT;
            q[1].pose.position = {0.0f, -0.35f, -1.0f};  // below the red one
            q[1].size = {0.2f, 0.2f};
            // A quad of size {0, 0} is valid and covers nothing (the red one stays visible through it).
            q[2].eyeVisibility = XR_EYE_VISIBILITY_BOTH;
            q[2].pose.position = {0.0f, 0.0f, -0.5f};
            q[2].size = {0.0f, 0.0f};
            std::vector<const XrCompositionLayerBaseHeader*> ls{
                sl.header(), reinterpret_cast<const XrCompositionLayerBaseHeader*>(&q[0]),
                reinterpret_cast<const XrCompositionLayerBaseHeader*>(&q[1]),
                reinterpret_cast<const XrCompositionLayerBaseHeader*>(&q[2])};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS);
    c.reset();
    auto opened = eval::SequenceReader::open(dir);
    ASSERT_TRUE(opened) << opened.error().message;
    auto& r = *opened;
    for (int e = 0; e < 2; ++e) {
        cv::Mat out = cv::imread(dir + "/" + eval::frameFileName(1, e, "output.png"));  // BGR
        ASSERT_FALSE(out.empty());
        const layers::Fov& fov = r->info().fov[e];
        // Pixel of an eye-space direction (x right, y down).
        auto pixel = [&](float dx, float dy) {
            const float px = (dx - std::tan(fov.angleLeft)) / (std::tan(fov.angleRight) - std::tan(fov.angleLeft));
            const float py = (std::tan(fov.angleUp) - dy) / (std::tan(fov.angleUp) - std::tan(fov.angleDown));
            return cv::Point(int(px * float(w)), int(py * float(h)));
        };
        const float eyeX = e == 0 ? -0.0315f : 0.0315f;  // the quad's centre seen from each eye
        const cv::Vec3b ahead = out.at<cv::Vec3b>(pixel(-eyeX, 0.0f));
        EXPECT_NEAR(ahead[2], 200, 1) << "eye " << e;
        EXPECT_NEAR(ahead[1], 40, 1) << "eye " << e;
        EXPECT_NEAR(ahead[0], 40, 1) << "eye " << e;
        const cv::Vec3b below = out.at<cv::Vec3b>(pixel(-eyeX, -0.35f));
        const bool isGreen = below[1] > 200 && below[2] < 50;
        EXPECT_EQ(isGreen, e == 0) << "eye " << e << ": the left-only quad";
        const cv::Vec3b corner = out.at<cv::Vec3b>(0, 0);
        EXPECT_FALSE(corner[2] == 200 && corner[1] == 40) << "eye " << e << ": the quad covers everything";
    }
}

// The simulated head follows the configured path (here `turn`: +-25 deg yaw, 6 s period), with the
// eyes IPD apart, and xrWaitFrame paces the frames at the display rate (realtime).
TEST(XrClient, HeadPathAndRealtimePacing) {
    setenv("WRSFOV_XR_HEAD", "turn", 1);
    setenv("WRSFOV_XR_PACE", "realtime", 1);
    auto c = Client::create(kExtensions);
    unsetenv("WRSFOV_XR_HEAD");
    setenv("WRSFOV_XR_PACE", "free", 1);  // as the rest of the suite runs
    ASSERT_TRUE(c);
    XrReferenceSpaceCreateInfo rci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    rci.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace view;
    ASSERT_EQ(xrCreateReferenceSpace(c->session, &rci, &view), XR_SUCCESS);
    ASSERT_EQ(c->begin(), XR_SUCCESS);

    XrTime last = 0;
    for (int i = 0; i < 12; ++i) {
        XrFrameState fs{XR_TYPE_FRAME_STATE};
        ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
        timespec now;
        clock_gettime(CLOCK_MONOTONIC, &now);
        const XrTime t = XrTime(now.tv_sec) * 1000000000 + now.tv_nsec;
        // Returned no earlier than one period before the frame's display (the runtime's clock is
        // CLOCK_MONOTONIC), and display times are whole periods apart.
        EXPECT_GE(t, fs.predictedDisplayTime - fs.predictedDisplayPeriod) << "frame " << i;
        if (last) {
            EXPECT_GT(fs.predictedDisplayTime, last);
            EXPECT_EQ((fs.predictedDisplayTime - last) % fs.predictedDisplayPeriod, 0) << "frame " << i;
        }
        last = fs.predictedDisplayTime;
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        XrFrameEndInfo none = frameEnd(fs.predictedDisplayTime, {});
        ASSERT_EQ(xrEndFrame(c->session, &none), XR_SUCCESS);
    }

    // Yaw of the head in LOCAL at four times 0.75 s apart: it turns, by up to 25 deg.
    auto yawAt = [&](XrTime t) {
        XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
        EXPECT_EQ(xrLocateSpace(view, c->local, t, &loc), XR_SUCCESS);
        EXPECT_TRUE(loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT);
        const XrQuaternionf q = loc.pose.orientation;
        return 2.0f * std::atan2(q.y, q.w) * 180.0f / 3.14159265f;
    };
    // Over 2.25 s, more than a third of the 6 s period, the yaw moves by at least 25 (1 - cos 67.5°)
    // = 15.4°, and four samples 45° of phase apart span at least 13.5°, wherever they fall on the path
    // (`last` follows the wall clock under realtime pacing: it depends on the set-up time).
    float lo = 1e9f, hi = -1e9f;
    for (int k = 0; k < 4; ++k) {
        const float y = yawAt(last + XrTime(k) * 750000000);
        EXPECT_LE(std::abs(y), 25.01f);
        lo = std::min(lo, y);
        hi = std::max(hi, y);
    }
    EXPECT_GT(hi - lo, 10.0f);
    // The eyes: IPD apart, at the head.
    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO;
    li.displayTime = last;
    li.space = view;
    XrViewState vs{XR_TYPE_VIEW_STATE};
    XrView v[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
    uint32_t n = 0;
    ASSERT_EQ(xrLocateViews(c->session, &li, &vs, 2, &n, v), XR_SUCCESS);
    EXPECT_NEAR(v[1].pose.position.x - v[0].pose.position.x, 0.063f, 1e-5f);
    EXPECT_NEAR(v[0].pose.position.y, 0.0f, 1e-5f);
    EXPECT_TRUE(vs.viewStateFlags & XR_VIEW_STATE_POSITION_TRACKED_BIT);
    li.displayTime = 0;
    EXPECT_EQ(xrLocateViews(c->session, &li, &vs, 2, &n, v), XR_ERROR_TIME_INVALID);
}

// A long run with swapchains re-created (new sizes) every 100 frames: every frame end succeeds and
// nothing is left behind (under the validation layer, objects the runtime or a layer leaked on the
// device are reported when the client destroys it: tests/xr/CMakeLists.txt fails on that).
// Under the sanitizers (tools/run-tests.sh, stage 2), which check the host paths, 300 frames: three
// re-creations of each size.
TEST(XrClient, ThousandFramesWithSwapchainRecreation) {
#ifdef WRSFOV_SANITIZED
    constexpr int kFrames = 300;
#else
    constexpr int kFrames = 1000;
#endif
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    ASSERT_EQ(c->begin(), XR_SUCCESS);
    Swapchain color;
    for (int f = 0; f < kFrames; ++f) {
        if (f % 100 == 0) {
            if (color.handle) {
                ASSERT_EQ(xrDestroySwapchain(color.handle), XR_SUCCESS);
            }
            color = {};
            const uint32_t size = (f / 100) % 2 ? 48 : 64;
            ASSERT_EQ(c->createSwapchain(kSrgb, size, size, 2, kColorUsage, color), XR_SUCCESS) << "frame " << f;
        }
        if (f % 10 == 0)
            c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                              [&](uint32_t l) { return checker(color.width, color.height, 2 + l, 0, 255); });
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            StereoLayer sl;
            sl.build(*c, fs.predictedDisplayTime, color);
            std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS)
            << "frame " << f;
    }
}

TEST(XrClient, EyeGazeActionFollowsTheGenerator) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asci.actionSetName, "gameplay");
    std::strcpy(asci.localizedActionSetName, "Gameplay");
    XrActionSet set;
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_SUCCESS);
    EXPECT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_ERROR_NAME_DUPLICATED);
    std::strcpy(asci.actionSetName, "Bad Name");
    XrActionSet bad;
    EXPECT_EQ(xrCreateActionSet(c->instance, &asci, &bad), XR_ERROR_PATH_FORMAT_INVALID);

    XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
    aci.actionType = XR_ACTION_TYPE_POSE_INPUT;
    std::strcpy(aci.actionName, "gaze");
    std::strcpy(aci.localizedActionName, "Gaze");
    XrAction gaze;
    ASSERT_EQ(xrCreateAction(set, &aci, &gaze), XR_SUCCESS);
    aci.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    std::strcpy(aci.actionName, "select");
    std::strcpy(aci.localizedActionName, "Select");
    XrAction select;
    ASSERT_EQ(xrCreateAction(set, &aci, &select), XR_SUCCESS);

    XrActionSuggestedBinding b{gaze, path(c->instance, "/user/eyes_ext/input/gaze_ext/pose")};
    XrInteractionProfileSuggestedBinding s{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    s.interactionProfile = path(c->instance, "/interaction_profiles/ext/eye_gaze_interaction");
    s.countSuggestedBindings = 1;
    s.suggestedBindings = &b;
    ASSERT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_SUCCESS);
    // An unknown profile is refused; a source of another type than the action's is a valid
    // suggestion (never bound): a boolean on the gaze pose, a pose on a click.
    XrActionSuggestedBinding both[2] = {{gaze, b.binding}, {select, b.binding}};
    s.suggestedBindings = both;
    s.countSuggestedBindings = 2;
    EXPECT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_SUCCESS);
    s.countSuggestedBindings = 1;
    s.suggestedBindings = &b;
    s.interactionProfile = path(c->instance, "/interaction_profiles/acme/teapot");
    EXPECT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_ERROR_PATH_UNSUPPORTED);
    XrActionSuggestedBinding click{gaze, path(c->instance, "/user/hand/left/input/select/click")};
    s.interactionProfile = path(c->instance, "/interaction_profiles/khr/simple_controller");
    s.suggestedBindings = &click;
    EXPECT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_SUCCESS);
    XrActionSuggestedBinding okClick{select, click.binding};
    s.suggestedBindings = &okClick;
    EXPECT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_SUCCESS);

    XrActionSpaceCreateInfo spi{XR_TYPE_ACTION_SPACE_CREATE_INFO};
    spi.action = gaze;
    spi.poseInActionSpace.orientation.w = 1.0f;
    XrSpace gazeSpace;
    ASSERT_EQ(xrCreateActionSpace(c->session, &spi, &gazeSpace), XR_SUCCESS);
    spi.action = select;
    EXPECT_EQ(xrCreateActionSpace(c->session, &spi, &gazeSpace + 0), XR_ERROR_ACTION_TYPE_MISMATCH);

    XrInteractionProfileState ips{XR_TYPE_INTERACTION_PROFILE_STATE};
    EXPECT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/eyes_ext"), &ips),
              XR_ERROR_ACTIONSET_NOT_ATTACHED);
    XrSessionActionSetsAttachInfo att{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    att.countActionSets = 1;
    att.actionSets = &set;
    ASSERT_EQ(xrAttachSessionActionSets(c->session, &att), XR_SUCCESS);
    EXPECT_EQ(xrAttachSessionActionSets(c->session, &att), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    EXPECT_EQ(xrCreateAction(set, &aci, &select), XR_ERROR_ACTIONSETS_ALREADY_ATTACHED);
    // Interaction profiles change only in xrSyncActions: nothing yet after the attach.
    auto profileChanged = [&] {
        bool changed = false;
        for (const auto& e : c->poll()) changed |= e.type == XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED;
        return changed;
    };
    EXPECT_FALSE(profileChanged()) << "queued by xrAttachSessionActionSets";
    ASSERT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/eyes_ext"), &ips), XR_SUCCESS);
    EXPECT_EQ(ips.interactionProfile, XrPath(XR_NULL_PATH));

    XrActiveActionSet active{set, XR_NULL_PATH};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    EXPECT_EQ(xrSyncActions(c->session, &sync), XR_SESSION_NOT_FOCUSED);
    EXPECT_TRUE(profileChanged()) << "not queued by the first xrSyncActions";
    EXPECT_FALSE(profileChanged());
    ASSERT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/eyes_ext"), &ips), XR_SUCCESS);
    EXPECT_EQ(ips.interactionProfile, path(c->instance, "/interaction_profiles/ext/eye_gaze_interaction"));
    ASSERT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/hand/left"), &ips), XR_SUCCESS);
    EXPECT_EQ(ips.interactionProfile, XrPath(XR_NULL_PATH));  // no controllers on this HMD
    EXPECT_EQ(xrSyncActions(c->session, &sync), XR_SESSION_NOT_FOCUSED);
    EXPECT_FALSE(profileChanged()) << "a second change event without a change";

    Swapchain color;
    ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 2, kColorUsage, color), XR_SUCCESS);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                      [&](uint32_t) { return checker(c->viewWidth, c->viewHeight, 4, 0, 255); });
    runToFocused(*c, color);
    ASSERT_EQ(xrSyncActions(c->session, &sync), XR_SUCCESS);

    XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
    gi.action = gaze;
    XrActionStatePose pose{XR_TYPE_ACTION_STATE_POSE};
    ASSERT_EQ(xrGetActionStatePose(c->session, &gi, &pose), XR_SUCCESS);
    EXPECT_EQ(pose.isActive, XR_TRUE);
    XrActionStateBoolean boolean{XR_TYPE_ACTION_STATE_BOOLEAN};
    EXPECT_EQ(xrGetActionStateBoolean(c->session, &gi, &boolean), XR_ERROR_ACTION_TYPE_MISMATCH);
    gi.action = select;
    ASSERT_EQ(xrGetActionStateBoolean(c->session, &gi, &boolean), XR_SUCCESS);
    EXPECT_EQ(boolean.isActive, XR_FALSE);

    XrReferenceSpaceCreateInfo rci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_VIEW;
    rci.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace view;
    ASSERT_EQ(xrCreateReferenceSpace(c->session, &rci, &view), XR_SUCCESS);
    XrFrameState fs{XR_TYPE_FRAME_STATE};
    ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
    XrEyeGazeSampleTimeEXT sampleTime{XR_TYPE_EYE_GAZE_SAMPLE_TIME_EXT};
    XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
    loc.next = &sampleTime;
    ASSERT_EQ(xrLocateSpace(gazeSpace, view, fs.predictedDisplayTime, &loc), XR_SUCCESS);
    // Valid unless the generator blinks right then; its scene mode keeps the gaze within 20 deg x 12 deg.
    if (loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT) {
        const XrQuaternionf q = loc.pose.orientation;
        // -Z rotated by q: the gaze direction in the view.
        const float fz = -(1.0f - 2.0f * (q.x * q.x + q.y * q.y));
        EXPECT_LT(std::acos(-fz) * 180.0f / 3.14159265f, 25.0f);
        EXPECT_GT(sampleTime.time, 0);
        EXPECT_LE(sampleTime.time, fs.predictedDisplayTime);
    }
    EXPECT_EQ(xrLocateSpace(gazeSpace, view, 0, &loc), XR_ERROR_TIME_INVALID);
    uint32_t n = 0;
    XrBoundSourcesForActionEnumerateInfo bsi{XR_TYPE_BOUND_SOURCES_FOR_ACTION_ENUMERATE_INFO};
    bsi.action = gaze;
    XrPath src[2];
    ASSERT_EQ(xrEnumerateBoundSourcesForAction(c->session, &bsi, 2, &n, src), XR_SUCCESS);
    ASSERT_EQ(n, 1u);
    EXPECT_EQ(src[0], b.binding);
}

/// An instance of its own (no session) with these extensions; XR_NULL_HANDLE on failure.
XrInstance bareInstance(const std::vector<const char*>& extensions, const std::vector<const char*>& layers = {}) {
    XrInstanceCreateInfo ici{XR_TYPE_INSTANCE_CREATE_INFO};
    std::snprintf(ici.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "wrsfov-xr-bare");
    ici.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ici.enabledExtensionCount = uint32_t(extensions.size());
    ici.enabledExtensionNames = extensions.data();
    ici.enabledApiLayerCount = uint32_t(layers.size());
    ici.enabledApiLayerNames = layers.data();
    XrInstance inst = XR_NULL_HANDLE;
    const XrResult r = xrCreateInstance(&ici, &inst);
    EXPECT_EQ(r, XR_SUCCESS);
    return r == XR_SUCCESS ? inst : XR_NULL_HANDLE;
}

// The loader hands the application's XrInstanceCreateInfo to the runtime unchanged, so the names of
// the API layers the application enabled reach the runtime, which must accept them. Here the OpenXR
// core validation layer (installed with the system's OpenXR packages) is enabled by name, through the
// real loader; where XR_API_LAYER_PATH hides it (the run through our own layer), our layer is.
TEST(XrClient, InstanceWithApiLayersEnabledByName) {
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateApiLayerProperties(0, &n, nullptr), XR_SUCCESS);
    std::vector<XrApiLayerProperties> props(n, {XR_TYPE_API_LAYER_PROPERTIES});
    ASSERT_EQ(xrEnumerateApiLayerProperties(n, &n, props.data()), XR_SUCCESS);
    const char* env = std::getenv("XR_ENABLE_API_LAYERS");
    const std::string enabledByEnv = env ? env : "";
    std::string chosen;
    for (const char* want : {"XR_APILAYER_LUNARG_core_validation", "XR_APILAYER_WRSFOV_foveation"})
        for (const auto& p : props)
            if (chosen.empty() && std::strcmp(p.layerName, want) == 0 && enabledByEnv.find(want) == std::string::npos)
                chosen = want;
    if (chosen.empty()) {
        // Only where the environment enabled the layers already, or XR_API_LAYER_PATH hides the rest.
        ASSERT_TRUE(!enabledByEnv.empty() || std::getenv("XR_API_LAYER_PATH"))
            << "XR_APILAYER_LUNARG_core_validation is not installed";
        GTEST_SKIP() << "no API layer left to enable by name";
    }
    const char* name = chosen.c_str();
    XrInstance inst = bareInstance({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME}, {name});
    ASSERT_NE(inst, XR_NULL_HANDLE) << "with " << name << " enabled";
    XrSystemGetInfo sgi{XR_TYPE_SYSTEM_GET_INFO};
    sgi.formFactor = XR_FORM_FACTOR_HEAD_MOUNTED_DISPLAY;
    XrSystemId sys = XR_NULL_SYSTEM_ID;
    EXPECT_EQ(xrGetSystem(inst, &sgi, &sys), XR_SUCCESS);
    EXPECT_EQ(xrDestroyInstance(inst), XR_SUCCESS);
}

// One image at a time is waited for: a second xrWaitSwapchainImage before the release is out of
// order and changes nothing, so the waits that follow the release still work.
TEST(XrClient, SecondWaitBeforeReleaseIsRefused) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    Swapchain sc;
    ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 1, kColorUsage, sc), XR_SUCCESS);
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    uint32_t idx[2];
    ASSERT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &idx[0]), XR_SUCCESS);
    ASSERT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &idx[1]), XR_SUCCESS);
    ASSERT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_SUCCESS);
    EXPECT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_ERROR_CALL_ORDER_INVALID);
    ASSERT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_SUCCESS);
    EXPECT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_SUCCESS);  // the second acquired image
    EXPECT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_SUCCESS);
    EXPECT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_ERROR_CALL_ORDER_INVALID);  // nothing acquired
    // The ring goes on as before.
    for (int f = 0; f < 3; ++f) {
        uint32_t i = 0;
        ASSERT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &i), XR_SUCCESS);
        ASSERT_EQ(xrWaitSwapchainImage(sc.handle, &wi), XR_SUCCESS);
        ASSERT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_SUCCESS);
    }
}

// Action and action-set names: an empty name is NAME_INVALID (a malformed one PATH_FORMAT_INVALID),
// and destroying an action or a set, attached or not, frees its name and localized name.
TEST(XrClient, ActionNamesAreCheckedAndFreedOnDestroy) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asci.localizedActionSetName, "Set");
    XrActionSet set = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_ERROR_NAME_INVALID);
    std::strcpy(asci.actionSetName, "Bad Name");
    EXPECT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_ERROR_PATH_FORMAT_INVALID);
    std::strcpy(asci.actionSetName, "set");
    asci.localizedActionSetName[0] = '\0';
    EXPECT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_ERROR_LOCALIZED_NAME_INVALID);
    std::strcpy(asci.localizedActionSetName, "Set");
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_SUCCESS);

    XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
    aci.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    std::strcpy(aci.localizedActionName, "Action");
    XrAction action = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateAction(set, &aci, &action), XR_ERROR_NAME_INVALID);
    std::strcpy(aci.actionName, "Bad Name");
    EXPECT_EQ(xrCreateAction(set, &aci, &action), XR_ERROR_PATH_FORMAT_INVALID);
    std::strcpy(aci.actionName, "action");
    ASSERT_EQ(xrCreateAction(set, &aci, &action), XR_SUCCESS);
    XrAction again = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateAction(set, &aci, &again), XR_ERROR_NAME_DUPLICATED);
    std::strcpy(aci.actionName, "other");
    EXPECT_EQ(xrCreateAction(set, &aci, &again), XR_ERROR_LOCALIZED_NAME_DUPLICATED);
    ASSERT_EQ(xrDestroyAction(action), XR_SUCCESS);
    std::strcpy(aci.actionName, "action");
    ASSERT_EQ(xrCreateAction(set, &aci, &action), XR_SUCCESS) << "the destroyed action's names";

    // A set destroyed while attached lives on in the session, its names do not.
    XrSessionActionSetsAttachInfo att{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    att.countActionSets = 1;
    att.actionSets = &set;
    ASSERT_EQ(xrAttachSessionActionSets(c->session, &att), XR_SUCCESS);
    ASSERT_EQ(xrDestroyActionSet(set), XR_SUCCESS);
    EXPECT_EQ(xrDestroyAction(action), XR_ERROR_HANDLE_INVALID);  // went with its set
    XrActionSet set2 = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set2), XR_SUCCESS) << "the destroyed attached set's names";
    ASSERT_EQ(xrCreateAction(set2, &aci, &action), XR_SUCCESS);
    ASSERT_EQ(xrDestroyActionSet(set2), XR_SUCCESS);
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set2), XR_SUCCESS) << "the destroyed set's names";
}

// xrSuggestInteractionProfileBindings against the interaction profiles of OpenXR 1.0: every
// component of each profile, for an action of any type; paths that later versions or extensions add,
// paths below a component and components of the other hand are PATH_UNSUPPORTED; so is the eye-gaze
// profile on an instance without XR_EXT_eye_gaze_interaction.
TEST(XrClient, SuggestedBindingsFollowTheOpenXR10Profiles) {
    XrInstance inst = bareInstance({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME});
    ASSERT_NE(inst, XR_NULL_HANDLE);
    XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asci.actionSetName, "bindings");
    std::strcpy(asci.localizedActionSetName, "Bindings");
    XrActionSet set = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateActionSet(inst, &asci, &set), XR_SUCCESS);
    const XrActionType types[] = {XR_ACTION_TYPE_BOOLEAN_INPUT, XR_ACTION_TYPE_FLOAT_INPUT,
                                  XR_ACTION_TYPE_VECTOR2F_INPUT, XR_ACTION_TYPE_POSE_INPUT,
                                  XR_ACTION_TYPE_VIBRATION_OUTPUT};
    std::vector<XrAction> actions;
    for (XrActionType t : types) {
        XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
        aci.actionType = t;
        std::snprintf(aci.actionName, XR_MAX_ACTION_NAME_SIZE, "a%d", int(t));
        std::snprintf(aci.localizedActionName, XR_MAX_LOCALIZED_ACTION_NAME_SIZE, "A %d", int(t));
        XrAction a = XR_NULL_HANDLE;
        ASSERT_EQ(xrCreateAction(set, &aci, &a), XR_SUCCESS);
        actions.push_back(a);
    }
    auto suggest = [&](const std::string& profile, const std::string& binding, XrAction a) {
        XrActionSuggestedBinding b{a, path(inst, binding.c_str())};
        XrInteractionProfileSuggestedBinding s{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
        s.interactionProfile = path(inst, profile.c_str());
        s.countSuggestedBindings = 1;
        s.suggestedBindings = &b;
        return xrSuggestInteractionProfileBindings(inst, &s);
    };
    struct Case {
        const char* profile;
        const char* user;
        std::vector<const char*> valid;    // 1.0 components
        std::vector<const char*> invalid;  // not 1.0 (later versions, extensions), or not this profile's
    };
    const std::vector<Case> cases = {
        {"khr/simple_controller",
         "/user/hand/left",
         {"/input/select/click", "/input/menu/click", "/input/grip/pose", "/input/aim/pose", "/output/haptic"},
         {"/input/grip_surface/pose", "/input/palm_ext/pose", "/input/trigger/value", "/input/select/click/invalid"}},
        {"google/daydream_controller",
         "/user/hand/right",
         {"/input/select/click", "/input/trackpad", "/input/trackpad/x", "/input/trackpad/touch", "/input/aim/pose"},
         {"/output/haptic", "/input/grip_surface/pose", "/input/trackpad/dpad_up"}},
        {"htc/vive_controller",
         "/user/hand/left",
         {"/input/system/click", "/input/squeeze/click", "/input/trigger/value", "/input/trackpad/y", "/output/haptic"},
         {"/input/squeeze/value", "/input/grip_surface/pose", "/input/trackpad/dpad_center"}},
        {"htc/vive_pro",
         "/user/head",
         {"/input/system/click", "/input/volume_up/click", "/input/volume_down/click", "/input/mute_mic/click"},
         {"/input/menu/click", "/output/haptic"}},
        {"microsoft/motion_controller",
         "/user/hand/right",
         {"/input/menu/click", "/input/thumbstick", "/input/thumbstick/click", "/input/trackpad/touch",
          "/input/grip/pose", "/output/haptic"},
         {"/input/system/click", "/input/thumbstick/dpad_left", "/input/grip_surface/pose"}},
        {"microsoft/xbox_controller",
         "/user/gamepad",
         {"/input/menu/click", "/input/a/click", "/input/dpad_up/click", "/input/trigger_left/value",
          "/input/thumbstick_right", "/output/haptic_left_trigger"},
         {"/input/trigger/value", "/output/haptic", "/input/thumbstick_left/dpad_up"}},
        {"oculus/go_controller",
         "/user/hand/left",
         {"/input/system/click", "/input/trigger/click", "/input/back/click", "/input/trackpad", "/input/grip/pose"},
         {"/output/haptic", "/input/grip_surface/pose"}},
        {"oculus/touch_controller",
         "/user/hand/left",
         {"/input/x/click", "/input/y/touch", "/input/menu/click", "/input/squeeze/value", "/input/thumbrest/touch",
          "/input/aim/pose", "/output/haptic"},
         {"/input/a/click", "/input/system/click", "/input/thumb_resting_surfaces/proximity",
          "/input/trigger/proximity_fb", "/input/grip_surface/pose"}},
        {"oculus/touch_controller",
         "/user/hand/right",
         {"/input/a/click", "/input/b/touch", "/input/system/click", "/input/trigger/touch"},
         {"/input/x/click", "/input/menu/click"}},
        {"valve/index_controller",
         "/user/hand/right",
         {"/input/system/touch", "/input/squeeze/force", "/input/trackpad/force", "/input/thumbstick/touch",
          "/output/haptic"},
         {"/input/grip_surface/pose", "/input/thumbstick/dpad_down", "/input/trigger/proximity"}},
    };
    for (const Case& k : cases) {
        const std::string profile = std::string("/interaction_profiles/") + k.profile;
        for (const char* v : k.valid)
            for (XrAction a : actions)  // any action type may be suggested for any source
                EXPECT_EQ(suggest(profile, k.user + std::string(v), a), XR_SUCCESS) << profile << " " << k.user << v;
        for (const char* v : k.invalid)
            EXPECT_EQ(suggest(profile, k.user + std::string(v), actions[0]), XR_ERROR_PATH_UNSUPPORTED)
                << profile << " " << k.user << v;
    }
    // An identifier alone names its component ("/input/trigger" is the trigger's value or click).
    EXPECT_EQ(suggest("/interaction_profiles/valve/index_controller", "/user/hand/left/input/trigger", actions[1]),
              XR_SUCCESS);
    // The conformance suite's malformed sources and profiles.
    for (const char* bad : {"/invalid", "/user/invalid", "/user/hand/invalid", "/user/hand/right",
                            "/user/hand/right/invalid", "/user/hand/right/input", "/user/hand/invalid/input",
                            "/user/invalid/right/input", "/invalid/hand/right/input",
                            "/user/hand/left/input_bad/menu/click", "/user/hand/right/input/select/click/invalid"})
        EXPECT_EQ(suggest("/interaction_profiles/khr/simple_controller", bad, actions[0]), XR_ERROR_PATH_UNSUPPORTED)
            << bad;
    for (const char* bad : {"/invalid", "/interaction_profiles", "/interaction_profiles/invalid",
                            "/interaction_profiles/khr/simple_controller/invalid",
                            "/interaction_profiles/ext/eye_gaze_interaction"})  // extension not enabled
        EXPECT_EQ(suggest(bad, "/user/hand/left/input/select/click", actions[0]), XR_ERROR_PATH_UNSUPPORTED) << bad;
    EXPECT_EQ(
        suggest("/interaction_profiles/ext/eye_gaze_interaction", "/user/eyes_ext/input/gaze_ext/pose", actions[3]),
        XR_ERROR_PATH_UNSUPPORTED);
    // /user/eyes_ext is no top-level user path without the extension.
    XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
    aci.actionType = XR_ACTION_TYPE_POSE_INPUT;
    std::strcpy(aci.actionName, "eyes");
    std::strcpy(aci.localizedActionName, "Eyes");
    XrPath eyes = path(inst, "/user/eyes_ext");
    aci.countSubactionPaths = 1;
    aci.subactionPaths = &eyes;
    XrAction a = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateAction(set, &aci, &a), XR_ERROR_PATH_UNSUPPORTED);
    EXPECT_EQ(xrDestroyInstance(inst), XR_SUCCESS);
}

// Values outside an enumeration and paths never made: the specification's (and the conformance
// suite's) results.
TEST(XrClient, InvalidEnumValuesAndPaths) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    XrSystemGetInfo sgi{XR_TYPE_SYSTEM_GET_INFO};
    sgi.formFactor = XR_FORM_FACTOR_MAX_ENUM;
    XrSystemId sys = 0;
    EXPECT_EQ(xrGetSystem(c->instance, &sgi, &sys), XR_ERROR_FORM_FACTOR_UNSUPPORTED);

    XrReferenceSpaceCreateInfo rci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    rci.referenceSpaceType = XR_REFERENCE_SPACE_TYPE_MAX_ENUM;
    rci.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace space = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateReferenceSpace(c->session, &rci, &space), XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
    EXPECT_EQ(space, XrSpace(XR_NULL_HANDLE));
    rci.referenceSpaceType = XrReferenceSpaceType(1000038000);  // XR_MSFT_unbounded_reference_space's
    EXPECT_EQ(xrCreateReferenceSpace(c->session, &rci, &space), XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
    XrExtent2Df bounds;
    EXPECT_EQ(xrGetReferenceSpaceBoundsRect(c->session, XR_REFERENCE_SPACE_TYPE_MAX_ENUM, &bounds),
              XR_ERROR_VALIDATION_FAILURE);

    // A view configuration that is no valid enum for this application (none at all, or one of an
    // extension it has not enabled) is a validation failure, a valid one this system lacks is
    // unsupported.
    XrViewConfigurationProperties vcp{XR_TYPE_VIEW_CONFIGURATION_PROPERTIES};
    EXPECT_EQ(xrGetViewConfigurationProperties(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_MAX_ENUM, &vcp),
              XR_ERROR_VALIDATION_FAILURE);
    EXPECT_EQ(xrGetViewConfigurationProperties(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_MONO, &vcp),
              XR_ERROR_VIEW_CONFIGURATION_TYPE_UNSUPPORTED);
    uint32_t n = 0;
    EXPECT_EQ(
        xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_MAX_ENUM, 0, &n, nullptr),
        XR_ERROR_VALIDATION_FAILURE);
    EXPECT_EQ(
        xrEnumerateEnvironmentBlendModes(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_MAX_ENUM, 0, &n, nullptr),
        XR_ERROR_VALIDATION_FAILURE);
    for (int ext : {1000037000, 1000054000}) {  // XR_VARJO_quad_views', XR_MSFT_first_person_observer's
        EXPECT_EQ(
            xrEnumerateEnvironmentBlendModes(c->instance, c->system, XrViewConfigurationType(ext), 0, &n, nullptr),
            XR_ERROR_VALIDATION_FAILURE);
        EXPECT_EQ(
            xrEnumerateViewConfigurationViews(c->instance, c->system, XrViewConfigurationType(ext), 0, &n, nullptr),
            XR_ERROR_VALIDATION_FAILURE);
    }
    XrSessionBeginInfo sbi{XR_TYPE_SESSION_BEGIN_INFO};
    sbi.primaryViewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_MAX_ENUM;
    EXPECT_EQ(xrBeginSession(c->session, &sbi), XR_ERROR_VALIDATION_FAILURE);

    // A subaction path that no xrStringToPath made is PATH_INVALID; a path the action was not made
    // with is PATH_UNSUPPORTED.
    XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asci.actionSetName, "enums");
    std::strcpy(asci.localizedActionSetName, "Enums");
    XrActionSet set = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_SUCCESS);
    XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
    aci.actionType = XR_ACTION_TYPE_BOOLEAN_INPUT;
    std::strcpy(aci.actionName, "click");
    std::strcpy(aci.localizedActionName, "Click");
    const XrPath left = path(c->instance, "/user/hand/left");
    aci.countSubactionPaths = 1;
    aci.subactionPaths = &left;
    XrAction action = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateAction(set, &aci, &action), XR_SUCCESS);
    XrSessionActionSetsAttachInfo att{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    att.countActionSets = 1;
    att.actionSets = &set;
    ASSERT_EQ(xrAttachSessionActionSets(c->session, &att), XR_SUCCESS);
    const XrPath never = XrPath(0x7ffff0);
    char buf[64];
    ASSERT_EQ(xrPathToString(c->instance, never, 64, &n, buf), XR_ERROR_PATH_INVALID);
    XrActionStateGetInfo gi{XR_TYPE_ACTION_STATE_GET_INFO};
    gi.action = action;
    gi.subactionPath = never;
    XrActionStateBoolean st{XR_TYPE_ACTION_STATE_BOOLEAN};
    EXPECT_EQ(xrGetActionStateBoolean(c->session, &gi, &st), XR_ERROR_PATH_INVALID);
    gi.subactionPath = path(c->instance, "/user/hand/right");
    EXPECT_EQ(xrGetActionStateBoolean(c->session, &gi, &st), XR_ERROR_PATH_UNSUPPORTED);
    XrActiveActionSet active{set, never};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    EXPECT_EQ(xrSyncActions(c->session, &sync), XR_ERROR_PATH_INVALID);
    XrInteractionProfileState ips{XR_TYPE_INTERACTION_PROFILE_STATE};
    EXPECT_EQ(xrGetCurrentInteractionProfile(c->session, never, &ips), XR_ERROR_PATH_INVALID);
}

// xrResultToString and xrStructureTypeToString name every value: unknown ones as the specification
// spells them, with the value in decimal.
TEST(XrClient, UnknownEnumValuesToString) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    char buf[XR_MAX_RESULT_STRING_SIZE];
    ASSERT_EQ(xrResultToString(c->instance, XR_ERROR_CALL_ORDER_INVALID, buf), XR_SUCCESS);
    EXPECT_STREQ(buf, "XR_ERROR_CALL_ORDER_INVALID");
    ASSERT_EQ(xrResultToString(c->instance, XrResult(0x7ffffffe), buf), XR_SUCCESS);
    EXPECT_STREQ(buf, "XR_UNKNOWN_SUCCESS_2147483646");
    ASSERT_EQ(xrResultToString(c->instance, XrResult(int32_t(0x80000000)), buf), XR_SUCCESS);
    EXPECT_STREQ(buf, "XR_UNKNOWN_FAILURE_-2147483648");
    ASSERT_EQ(xrResultToString(c->instance, XrResult(-999), buf), XR_SUCCESS);
    EXPECT_STREQ(buf, "XR_UNKNOWN_FAILURE_-999");
    char type[XR_MAX_STRUCTURE_NAME_SIZE];
    ASSERT_EQ(xrStructureTypeToString(c->instance, XR_TYPE_FRAME_STATE, type), XR_SUCCESS);
    EXPECT_STREQ(type, "XR_TYPE_FRAME_STATE");
    ASSERT_EQ(xrStructureTypeToString(c->instance, XrStructureType(0x7ffffffe), type), XR_SUCCESS);
    EXPECT_STREQ(type, "XR_UNKNOWN_STRUCTURE_TYPE_2147483646");
}

// Destroying a session drops the events it still had queued: none names a destroyed handle.
TEST(XrClient, DestroyedSessionLeavesNoEvents) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    const XrSession gone = c->session;  // IDLE and READY are queued, not yet polled
    ASSERT_EQ(xrDestroySession(gone), XR_SUCCESS);
    c->session = XR_NULL_HANDLE;
    for (const XrEventDataBuffer& e : c->poll()) {
        ASSERT_NE(e.type, XR_TYPE_EVENT_DATA_SESSION_STATE_CHANGED)
            << "state " << reinterpret_cast<const XrEventDataSessionStateChanged&>(e).state
            << " of a destroyed session";
    }
}

// An instance without XR_EXT_eye_gaze_interaction sees none of it, whatever runs below (through the
// API layer, which enables the extension for itself, this is the layer's invisibility); an attach
// of no action sets is refused whatever a layer adds.
TEST(XrClient, EyeGazeNotEnabledIsNotVisible) {
    auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME});
    ASSERT_TRUE(c);
    XrSystemEyeGazeInteractionPropertiesEXT eye{XR_TYPE_SYSTEM_EYE_GAZE_INTERACTION_PROPERTIES_EXT};
    XrSystemProperties props{XR_TYPE_SYSTEM_PROPERTIES};
    props.next = &eye;
    ASSERT_EQ(xrGetSystemProperties(c->instance, c->system, &props), XR_SUCCESS);
    EXPECT_EQ(eye.supportsEyeGazeInteraction, XR_FALSE);

    XrActionSetCreateInfo asci{XR_TYPE_ACTION_SET_CREATE_INFO};
    std::strcpy(asci.actionSetName, "app");
    std::strcpy(asci.localizedActionSetName, "App");
    XrActionSet set = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateActionSet(c->instance, &asci, &set), XR_SUCCESS);
    XrActionCreateInfo aci{XR_TYPE_ACTION_CREATE_INFO};
    aci.actionType = XR_ACTION_TYPE_POSE_INPUT;
    std::strcpy(aci.actionName, "pose");
    std::strcpy(aci.localizedActionName, "Pose");
    XrAction pose = XR_NULL_HANDLE;
    ASSERT_EQ(xrCreateAction(set, &aci, &pose), XR_SUCCESS);
    XrActionSuggestedBinding b{pose, path(c->instance, "/user/eyes_ext/input/gaze_ext/pose")};
    XrInteractionProfileSuggestedBinding s{XR_TYPE_INTERACTION_PROFILE_SUGGESTED_BINDING};
    s.interactionProfile = path(c->instance, "/interaction_profiles/ext/eye_gaze_interaction");
    s.countSuggestedBindings = 1;
    s.suggestedBindings = &b;
    EXPECT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_ERROR_PATH_UNSUPPORTED);
    b.binding = path(c->instance, "/user/hand/left/input/aim/pose");
    s.interactionProfile = path(c->instance, "/interaction_profiles/khr/simple_controller");
    ASSERT_EQ(xrSuggestInteractionProfileBindings(c->instance, &s), XR_SUCCESS);

    XrSessionActionSetsAttachInfo att{XR_TYPE_SESSION_ACTION_SETS_ATTACH_INFO};
    att.countActionSets = 0;
    att.actionSets = &set;
    EXPECT_EQ(xrAttachSessionActionSets(c->session, &att), XR_ERROR_VALIDATION_FAILURE);
    att.countActionSets = 1;
    ASSERT_EQ(xrAttachSessionActionSets(c->session, &att), XR_SUCCESS);
    XrActiveActionSet active{set, XR_NULL_PATH};
    XrActionsSyncInfo sync{XR_TYPE_ACTIONS_SYNC_INFO};
    sync.countActiveActionSets = 1;
    sync.activeActionSets = &active;
    Swapchain color;
    ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 2, kColorUsage, color), XR_SUCCESS);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                      [&](uint32_t) { return checker(c->viewWidth, c->viewHeight, 4, 0, 255); });
    runToFocused(*c, color);
    ASSERT_EQ(xrSyncActions(c->session, &sync), XR_SUCCESS);
    ASSERT_EQ(xrSyncActions(c->session, &sync), XR_SUCCESS);
    for (const auto& e : c->poll())
        EXPECT_NE(e.type, XR_TYPE_EVENT_DATA_INTERACTION_PROFILE_CHANGED) << "no profile of the application's changed";
    XrInteractionProfileState ips{XR_TYPE_INTERACTION_PROFILE_STATE};
    EXPECT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/eyes_ext"), &ips),
              XR_ERROR_PATH_UNSUPPORTED);
    ASSERT_EQ(xrGetCurrentInteractionProfile(c->session, path(c->instance, "/user/hand/left"), &ips), XR_SUCCESS);
    EXPECT_EQ(ips.interactionProfile, XrPath(XR_NULL_PATH));
}

// ---- Composition off the API's critical path ----------------------------------------------------

/// A hand-made frame end of one stereo layer reading `color` (both eyes from layer 0).
XrResult endWith(Client& c, const XrFrameState& fs, const Swapchain& color) {
    StereoLayer sl;
    sl.build(c, fs.predictedDisplayTime, color);
    std::vector<const XrCompositionLayerBaseHeader*> ls{sl.header()};
    XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
    return xrEndFrame(c.session, &fe);
}

/// Acquires the next image of `sc` and waits for it with `timeout`; releases it when the wait
/// succeeded. Returns the wait's result and the image's index.
std::pair<XrResult, uint32_t> cycleImage(const Swapchain& sc, XrDuration timeout) {
    uint32_t index = 0;
    EXPECT_EQ(xrAcquireSwapchainImage(sc.handle, nullptr, &index), XR_SUCCESS);
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = timeout;
    const XrResult r = xrWaitSwapchainImage(sc.handle, &wi);
    if (r == XR_SUCCESS) {
        EXPECT_EQ(xrReleaseSwapchainImage(sc.handle, nullptr), XR_SUCCESS);
    }
    return {r, index};
}

// xrEndFrame hands the frame to the compositor thread and returns; the frame's images stay the
// compositor's until it is complete. Deterministic: with WRSFOV_XR_TEST_HOLD_FRAMES=1 the runtime
// completes a frame only once a call waits for it (a wait with no timeout only looks), so an
// xrEndFrame that waited for its frame would never return, and the image it read is refused to a
// zero-timeout wait until a blocking wait lets the frame complete.
TEST(XrClient, FrameEndReturnsBeforeTheFrameIsComplete) {
    setenv("WRSFOV_XR_TEST_HOLD_FRAMES", "1", 1);
    auto c = Client::create(kExtensions);
    unsetenv("WRSFOV_XR_TEST_HOLD_FRAMES");
    ASSERT_TRUE(c);
    Swapchain color;
    ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 1, kColorUsage, color), XR_SUCCESS);
    const auto texels = checker(c->viewWidth, c->viewHeight, 4, 30, 220);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });  // image 0
    runToFocused(*c, color);  // three frames reading image 0, each completed at the next xrEndFrame

    XrFrameState fs{XR_TYPE_FRAME_STATE};
    ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
    ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });  // image 1
    ASSERT_EQ(endWith(*c, fs, color), XR_SUCCESS);  // returns with the frame held in flight

    // Images 2 and 0 are not read by the frame in flight; image 1 is.
    EXPECT_EQ(cycleImage(color, 0), std::make_pair(XR_SUCCESS, 2u));
    EXPECT_EQ(cycleImage(color, 0), std::make_pair(XR_SUCCESS, 0u));
    EXPECT_EQ(cycleImage(color, 0), std::make_pair(XR_TIMEOUT_EXPIRED, 1u));
    // Still acquired: a blocking wait lets the frame complete and hands the image over.
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    EXPECT_EQ(xrWaitSwapchainImage(color.handle, &wi), XR_SUCCESS);
    EXPECT_EQ(xrReleaseSwapchainImage(color.handle, nullptr), XR_SUCCESS);

    // The loop goes on: each xrEndFrame waits for the frame before (and so completes it).
    for (int i = 0; i < 3; ++i) {
        ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        ASSERT_EQ(endWith(*c, fs, color), XR_SUCCESS);
    }
}

// Destroying a swapchain or the session while a frame that reads it is in flight waits for the
// frame (no image goes while the GPU reads it: the validation layer would say so) and leaves the
// runtime ready for a new session.
TEST(XrClient, SessionDestroyedWithAFrameInFlight) {
    for (int round = 0; round < 2; ++round) {
        setenv("WRSFOV_XR_TEST_HOLD_FRAMES", "1", 1);
        auto c = Client::create(kExtensions);
        unsetenv("WRSFOV_XR_TEST_HOLD_FRAMES");
        ASSERT_TRUE(c);
        Swapchain color, other;
        ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 1, kColorUsage, color), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 1, kColorUsage, other), XR_SUCCESS);
        const auto texels = checker(c->viewWidth, c->viewHeight, 4, 30, 220);
        c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
        c->writeSwapchain(other, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
        ASSERT_EQ(c->begin(), XR_SUCCESS);
        XrFrameState fs{XR_TYPE_FRAME_STATE};
        ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
        ASSERT_EQ(endWith(*c, fs, color), XR_SUCCESS);  // in flight, held
        if (round == 0) {
            ASSERT_EQ(xrDestroySwapchain(color.handle), XR_SUCCESS);  // waits for the frame
            ASSERT_EQ(xrWaitFrame(c->session, nullptr, &fs), XR_SUCCESS);
            ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS);
            ASSERT_EQ(endWith(*c, fs, other), XR_SUCCESS);  // in flight, held
        }
        ASSERT_EQ(xrDestroySession(c->session), XR_SUCCESS);  // with the frame in flight
        c->session = XR_NULL_HANDLE;
    }
    // A new session runs frames.
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    Swapchain color;
    ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 1, kColorUsage, color), XR_SUCCESS);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                      [&](uint32_t) { return checker(c->viewWidth, c->viewHeight, 4, 30, 220); });
    runToFocused(*c, color);
}

// The CTS's pipelined loop: xrWaitFrame on one thread, xrBeginFrame / xrEndFrame (with the
// swapchain work, views and events) on another. Display times increase by whole periods, a second
// xrWaitFrame waits for the frame before to be begun, and every frame ends.
TEST(XrClient, PipelinedFrameSubmissionFromTwoThreads) {
    auto c = Client::create(kExtensions);
    ASSERT_TRUE(c);
    Swapchain color;
    ASSERT_EQ(c->createSwapchain(kSrgb, c->viewWidth, c->viewHeight, 1, kColorUsage, color), XR_SUCCESS);
    const auto texels = checker(c->viewWidth, c->viewHeight, 4, 30, 220);
    c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
    ASSERT_EQ(c->begin(), XR_SUCCESS);

    constexpr int kFrames = 40;
    std::mutex m;
    std::condition_variable cv;
    std::deque<XrFrameState> queued;
    std::atomic<int> waitedAhead{0}, maxAhead{0};
    XrResult waitResult = XR_SUCCESS;
    std::thread waiter([&] {
        for (int i = 0; i < kFrames; ++i) {
            XrFrameState fs{XR_TYPE_FRAME_STATE};
            const XrResult r = xrWaitFrame(c->session, nullptr, &fs);
            std::lock_guard lock(m);
            if (r != XR_SUCCESS) {
                waitResult = r;
                cv.notify_one();
                return;
            }
            maxAhead = std::max(maxAhead.load(), ++waitedAhead);
            queued.push_back(fs);
            cv.notify_one();
        }
    });
    XrTime last = 0;
    int ended = 0;
    for (int i = 0; i < kFrames; ++i) {
        XrFrameState fs;
        {
            std::unique_lock lock(m);
            cv.wait(lock, [&] { return !queued.empty() || waitResult != XR_SUCCESS; });
            if (queued.empty()) break;
            fs = queued.front();
            queued.pop_front();
        }
        --waitedAhead;  // before the begin: the waiter's next xrWaitFrame returns only after it
        ASSERT_EQ(xrBeginFrame(c->session, nullptr), XR_SUCCESS) << "frame " << i;
        if (last) {
            EXPECT_GT(fs.predictedDisplayTime, last);
            EXPECT_EQ((fs.predictedDisplayTime - last) % fs.predictedDisplayPeriod, 0) << "frame " << i;
        }
        last = fs.predictedDisplayTime;
        c->writeSwapchain(color, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t) { return texels; });
        c->poll();
        ASSERT_EQ(endWith(*c, fs, color), XR_SUCCESS) << "frame " << i;
        ++ended;
    }
    waiter.join();
    EXPECT_EQ(waitResult, XR_SUCCESS);
    EXPECT_EQ(ended, kFrames);
    EXPECT_LE(maxAhead.load(), 1) << "xrWaitFrame returned twice before an xrBeginFrame";
}

}  // namespace
}  // namespace wrsfov::xrtest
