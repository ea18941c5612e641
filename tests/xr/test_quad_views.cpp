// Quad views on the runtime (XR_VARJO_quad_views, XR_VARJO_foveated_rendering) through the loader: the
// view configuration and its recommended sizes, insets that follow the gaze, 300 frames rendered with a
// gaze-following inset whose composed output equals the library's composition of the same frames (a
// second Compositor fed the same images and the gaze the runtime recorded), and every refusal class.
// Environment (tests/xr/CMakeLists.txt): XR_RUNTIME_JSON, WRSFOV_XR_PACE=free.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <functional>
#include <glm/gtc/packing.hpp>
#include <glm/gtc/quaternion.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <span>
#include <string>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "eval/sequence.h"
#include "gaze/gaze_file.h"
#include "xr_common/xr_config.h"
#include "layers/jitter.h"
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"
#include "tests/xr/xr_client.h"

namespace wrsfov::xrtest {
namespace {

const std::vector<const char*> kQuadExtensions = {
    XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME,
    XR_VARJO_QUAD_VIEWS_EXTENSION_NAME, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME};
constexpr int64_t kSrgb = VK_FORMAT_R8G8B8A8_SRGB;
constexpr XrSwapchainUsageFlags kColorUsage =
    XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
constexpr XrSwapchainUsageFlags kDepthUsage =
    XR_SWAPCHAIN_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;

// Sets environment variables for the scope (the runtime reads them at xrCreateInstance), restoring them.
struct ScopedEnv {
    std::vector<std::pair<std::string, std::optional<std::string>>> saved;
    ScopedEnv(std::initializer_list<std::pair<const char*, const char*>> vars) {
        for (const auto& [k, v] : vars) {
            const char* old = std::getenv(k);
            saved.emplace_back(k, old ? std::optional<std::string>(old) : std::nullopt);
            if (v)
                setenv(k, v, 1);
            else
                unsetenv(k);
        }
    }
    ~ScopedEnv() {
        for (const auto& [k, v] : saved)
            if (v)
                setenv(k.c_str(), v->c_str(), 1);
            else
                unsetenv(k.c_str());
    }
};

struct TempDir {
    std::string path;
    explicit TempDir(const std::string& name)
        : path(std::string(::testing::TempDir()) + name + "_" + std::to_string(::getpid())) {
        std::filesystem::remove_all(path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
};

// The API layer XR_APILAYER_WRSFOV_foveation is enabled (the ctest entries through the layer).
bool throughLayer() {
    const char* layers = std::getenv("XR_ENABLE_API_LAYERS");
    return layers && std::strstr(layers, "XR_APILAYER_WRSFOV_foveation");
}

glm::vec4 tangents(const XrFovf& f) {
    return {std::tan(f.angleLeft), std::tan(f.angleRight), std::tan(f.angleUp), std::tan(f.angleDown)};
}

// The scene in an eye's tangent space at frame `f`: a fine pattern (a few display pixels per period,
// which the wide views cannot carry) drifting slowly over a ramp; sRGB bytes.
std::vector<uint8_t> render(uint32_t w, uint32_t h, const XrFovf& fov, int f) {
    const glm::vec4 t = tangents(fov);
    std::vector<uint8_t> out(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float tx = t.x + (x + 0.5f) / w * (t.y - t.x), ty = t.z - (y + 0.5f) / h * (t.z - t.w);
            const float u = tx * 80.0f + 0.05f * f, v = ty * 80.0f;
            const float c = 0.5f + 0.35f * std::sin(u * 1.9f) * std::sin(v * 1.6f) + 0.1f * std::sin(tx * 3.0f);
            uint8_t* p = &out[(size_t(y) * w + x) * 4];
            p[0] = uint8_t(std::clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f);
            p[1] = uint8_t(std::clamp(1.0f - c, 0.0f, 1.0f) * 200.0f + 0.5f);
            p[2] = uint8_t(std::clamp(0.5f + 0.5f * ty, 0.0f, 1.0f) * 255.0f + 0.5f);
            p[3] = 255;
        }
    return out;
}

// Depth in [0, 1] (near 0.1, far 100): two planes split at tx = 0, so the vergence lands on either.
std::vector<uint8_t> depthImage(uint32_t w, uint32_t h, const XrFovf& fov) {
    const glm::vec4 t = tangents(fov);
    std::vector<uint8_t> out(size_t(w) * h * 4);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
            const float tx = t.x + (x + 0.5f) / w * (t.y - t.x);
            const float d = tx < 0.0f ? 0.95f : 0.98f;
            std::memcpy(&out[(size_t(y) * w + x) * 4], &d, 4);
        }
    return out;
}

XrSpace referenceSpace(Client& c, XrReferenceSpaceType type, XrResult* result = nullptr) {
    XrReferenceSpaceCreateInfo ci{XR_TYPE_REFERENCE_SPACE_CREATE_INFO};
    ci.referenceSpaceType = type;
    ci.poseInReferenceSpace.orientation.w = 1.0f;
    XrSpace s = XR_NULL_HANDLE;
    XrResult r = xrCreateReferenceSpace(c.session, &ci, &s);
    if (result)
        *result = r;
    else
        EXPECT_EQ(r, XR_SUCCESS);
    return s;
}

XrResult locate(Client& c, XrTime t, bool foveated, XrView (&views)[4], XrViewState* state = nullptr) {
    XrViewLocateFoveatedRenderingVARJO fr{XR_TYPE_VIEW_LOCATE_FOVEATED_RENDERING_VARJO};
    fr.foveatedRenderingActive = foveated ? XR_TRUE : XR_FALSE;
    XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO, &fr};
    li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
    li.displayTime = t;
    li.space = c.local;
    XrViewState vs{XR_TYPE_VIEW_STATE};
    for (auto& v : views) v = {XR_TYPE_VIEW};
    uint32_t n = 0;
    XrResult r = xrLocateViews(c.session, &li, state ? state : &vs, 4, &n, views);
    if (r == XR_SUCCESS) {
        EXPECT_EQ(n, 4u);
    }
    return r;
}

layers::Fov toFov(const XrFovf& f) { return {f.angleLeft, f.angleRight, f.angleUp, f.angleDown}; }

// The field of view `f` of a w x h view shifted by `o` of its pixels (+y down): what an engine that
// jitters for temporal upsampling renders with and submits.
XrFovf jittered(const XrFovf& f, glm::vec2 o, uint32_t w, uint32_t h) {
    const layers::Fov j = layers::jitteredFov(toFov(f), o, w, h);
    return {j.angleLeft, j.angleRight, j.angleUp, j.angleDown};
}

void expectFovNear(const XrFovf& got, const layers::Fov& want, float tol, const std::string& what) {
    EXPECT_NEAR(got.angleLeft, want.angleLeft, tol) << what;
    EXPECT_NEAR(got.angleRight, want.angleRight, tol) << what;
    EXPECT_NEAR(got.angleUp, want.angleUp, tol) << what;
    EXPECT_NEAR(got.angleDown, want.angleDown, tol) << what;
}

// The view configuration, its sizes (with and without XrFoveatedViewConfigurationViewVARJO), the
// system's foveated-rendering property, and the combined-eye space listed.
TEST(XrQuadViews, ViewConfigurationAndRecommendedSizes) {
    ScopedEnv env{{"WRSFOV_XR_WIDTH", "1024"}, {"WRSFOV_XR_HEIGHT", "1024"}};
    auto c = Client::create(kQuadExtensions);
    ASSERT_TRUE(c);
    XrSystemFoveatedRenderingPropertiesVARJO fr{XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO};
    XrSystemProperties props{XR_TYPE_SYSTEM_PROPERTIES, &fr};
    ASSERT_EQ(xrGetSystemProperties(c->instance, c->system, &props), XR_SUCCESS);
    EXPECT_EQ(fr.supportsFoveatedRendering, XR_TRUE);
    XrViewConfigurationType types[4];
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateViewConfigurations(c->instance, c->system, 4, &n, types), XR_SUCCESS);
    ASSERT_EQ(n, 2u);
    EXPECT_EQ(types[0], XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO);
    EXPECT_EQ(types[1], XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO);
    for (bool chained : {false, true}) {
        XrFoveatedViewConfigurationViewVARJO fv[4];
        XrViewConfigurationView v[4];
        for (int i = 0; i < 4; ++i) {
            fv[i] = {XR_TYPE_FOVEATED_VIEW_CONFIGURATION_VIEW_VARJO, nullptr, XR_TRUE};
            v[i] = {XR_TYPE_VIEW_CONFIGURATION_VIEW, chained ? &fv[i] : nullptr};
        }
        ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system,
                                                    XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, 0, &n, nullptr),
                  XR_SUCCESS);
        ASSERT_EQ(n, 4u);
        ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system,
                                                    XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, 4, &n, v),
                  XR_SUCCESS);
        // 1024 / 2.5 = 409.6; 30 degrees at 1024 px over tan 42 + tan 50 (across), tan 45 + tan 48 (down).
        for (int i = 0; i < 2; ++i) {
            EXPECT_EQ(v[i].recommendedImageRectWidth, 410u);
            EXPECT_EQ(v[i].recommendedImageRectHeight, 410u);
            EXPECT_EQ(v[2 + i].recommendedImageRectWidth, 262u);
            EXPECT_EQ(v[2 + i].recommendedImageRectHeight, 260u);
        }
        const double quad = 2.0 * (410 * 410 + 262 * 260), stereo = 2.0 * 1024 * 1024;
        std::printf("[quad views] per frame: %.0f pixels against %.0f stereo at the display's density (%.1f %%)\n",
                    quad, stereo, 100.0 * quad / stereo);
    }
    XrViewConfigurationView sv[2] = {{XR_TYPE_VIEW_CONFIGURATION_VIEW}, {XR_TYPE_VIEW_CONFIGURATION_VIEW}};
    ASSERT_EQ(
        xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO, 2, &n, sv),
        XR_SUCCESS);
    EXPECT_EQ(sv[0].recommendedImageRectWidth, 1024u);
    XrViewConfigurationProperties vp{XR_TYPE_VIEW_CONFIGURATION_PROPERTIES};
    EXPECT_EQ(
        xrGetViewConfigurationProperties(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, &vp),
        XR_SUCCESS);
    EXPECT_EQ(vp.viewConfigurationType, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO);
    XrEnvironmentBlendMode mode;
    EXPECT_EQ(xrEnumerateEnvironmentBlendModes(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, 1,
                                               &n, &mode),
              XR_SUCCESS);
    XrReferenceSpaceType spaces[8];
    ASSERT_EQ(xrEnumerateReferenceSpaces(c->session, 8, &n, spaces), XR_SUCCESS);
    EXPECT_NE(std::find(spaces, spaces + n, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO), spaces + n);
}

// 100 frames of quad views with the inset on the gaze (1.1 s of the generator's gaze, the 8 jitter
// phases 12 times over), under whatever validation the environment turns on. Each frame: the combined-eye space says whether the gaze is valid, xrLocateViews puts the insets
// there (checked against the gaze the space gives), the four views are rendered and submitted with
// depth. Then the runtime's recorded output of every frame is compared with a second Compositor's,
// fed the same images, fields of view and the gaze the runtime recorded.
TEST(XrQuadViews, GazeFollowingInsetMatchesTheLibrary) {
    const TempDir rec("wrsfov_xr_quad_rec");
    constexpr uint32_t kDisplay = 160;
    ScopedEnv env{{"WRSFOV_XR_WIDTH", "160"},
                  {"WRSFOV_XR_HEIGHT", "160"},
                  {"WRSFOV_XR_RECORD", rec.path.c_str()},
                  {"WRSFOV_XR_OUTPUT", "headless"}};
    auto config = xr::loadRuntimeConfig();
    ASSERT_TRUE(config) << config.error().message;
    auto c = Client::create(kQuadExtensions);
    ASSERT_TRUE(c);
    const xr::QuadViewSizes sizes = xr::quadViewSizes(*config);
    EXPECT_EQ(sizes.wide, glm::uvec2(64, 64));
    Swapchain wide, inset, wideDepth, insetDepth;
    ASSERT_EQ(c->createSwapchain(kSrgb, sizes.wide.x, sizes.wide.y, 2, kColorUsage, wide), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(kSrgb, sizes.inset.x, sizes.inset.y, 2, kColorUsage, inset), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, sizes.wide.x, sizes.wide.y, 2, kDepthUsage, wideDepth),
              XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, sizes.inset.x, sizes.inset.y, 2, kDepthUsage, insetDepth),
              XR_SUCCESS);
    const XrSpace eyes = referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO);
    const XrSpace view = referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_VIEW);
    ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);

    struct Submitted {
        std::array<std::vector<uint8_t>, 4> color, depth;  // wide L, R, inset L, R
        std::array<XrFovf, 4> fov;                         // as submitted (the wide views jittered)
        std::array<XrFovf, 2> located;                     // the wide views as located
    };
    // 100 frames: every phase of the jitter twelve times over, the gaze lost for a quarter of them (the inset
    // centred, as XrQuadViews.InsetStaysInsideTheViewAndCentresWithoutGaze checks). Under the sanitizers
    // (tools/run-tests.sh, stage 2), which check the host paths, 24: every phase three times, the gaze
    // valid throughout.
#ifdef WRSFOV_SANITIZED
    constexpr int kFrames = 24;
#else
    constexpr int kFrames = 100;
#endif
    std::vector<Submitted> frames;
    int tracked = 0, shifted = 0, edge = 0;
    for (int f = 0; f < kFrames; ++f) {
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            XrSpaceLocation gazeLoc{XR_TYPE_SPACE_LOCATION};
            EXPECT_EQ(xrLocateSpace(eyes, view, fs.predictedDisplayTime, &gazeLoc), XR_SUCCESS);
            const bool valid = gazeLoc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
            tracked += valid;
            XrView v[4];
            EXPECT_EQ(locate(*c, fs.predictedDisplayTime, valid, v), XR_SUCCESS);
            for (int e = 0; e < 2; ++e) {
                const std::string what = "frame " + std::to_string(f) + " eye " + std::to_string(e);
                EXPECT_EQ(std::memcmp(&v[e].pose, &v[e + 2].pose, sizeof(XrPosef)), 0) << what;
                // The inset where the eye looks: the combined gaze verged at 1.5 m (no depth yet when the
                // views are located), shifted inside the view.
                std::optional<glm::vec3> dir;
                if (valid) {
                    const XrQuaternionf& q = gazeLoc.pose.orientation;
                    const glm::vec3 g = glm::quat(q.w, q.x, q.y, q.z) * glm::vec3(0, 0, -1);
                    const glm::vec3 eyePos((e == 0 ? -0.5f : 0.5f) * config->ipd_m, 0, 0);
                    dir = glm::normalize(g * config->vergenceDistance_m - eyePos);
                }
                const layers::Fov want = xr::insetFov(toFov(v[e].fov), config->insetDeg, dir);
                expectFovNear(v[e + 2].fov, want, 2e-3f, what);
                const layers::Fov centred = xr::insetFov(toFov(v[e].fov), config->insetDeg, std::nullopt);
                shifted += std::abs(v[e + 2].fov.angleLeft - centred.angleLeft) > 0.01f;
                edge += v[e + 2].fov.angleLeft <= v[e].fov.angleLeft + 1e-6f ||
                        v[e + 2].fov.angleRight >= v[e].fov.angleRight - 1e-6f;
            }
            Submitted s;
            // The wide views rendered jittered as an engine does for temporal upsampling (Halton 2, 3
            // over 8 phases), submitted with the shifted field of view; the insets where located.
            for (int e = 0; e < 2; ++e) {
                s.located[e] = v[e].fov;
                v[e].fov = jittered(v[e].fov, layers::haltonJitter(uint64_t(f), 8), sizes.wide.x, sizes.wide.y);
            }
            for (int i = 0; i < 4; ++i) {
                const glm::uvec2 size = i < 2 ? sizes.wide : sizes.inset;
                s.fov[i] = v[i].fov;
                s.color[i] = render(size.x, size.y, v[i].fov, f);
                s.depth[i] = depthImage(size.x, size.y, v[i].fov);
            }
            c->writeSwapchain(wide, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t l) { return s.color[l]; });
            c->writeSwapchain(inset, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t l) { return s.color[2 + l]; });
            c->writeSwapchain(wideDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT, [&](uint32_t l) { return s.depth[l]; });
            c->writeSwapchain(insetDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT, [&](uint32_t l) { return s.depth[2 + l]; });
            frames.push_back(std::move(s));
            QuadLayer ql;
            ql.build(c->local, v, wide, inset, &wideDepth, &insetDepth);
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS)
            << "frame " << f;
    }
    c.reset();  // destroying the session closes the recording
    std::printf(
        "[quad views] %d of %d frames with a valid gaze; insets off the centre in %d of %d, at the view's "
        "edge in %d\n",
        tracked, kFrames, shifted, 2 * kFrames, edge);
    EXPECT_GT(tracked, kFrames / 2);
    EXPECT_GT(shifted, kFrames / 2) << "the insets do not follow the gaze";

    auto opened = eval::SequenceReader::open(rec.path);
    ASSERT_TRUE(opened) << opened.error().message;
    const auto& reader = *opened;
    ASSERT_EQ(reader->info().frameCount, uint32_t(kFrames));
    EXPECT_EQ(reader->info().width, kDisplay);
    ASSERT_TRUE(std::filesystem::exists(rec.path + "/" + eval::frameFileName(0, 1, "inset.png")));

    // The library: a compositor of the runtime's configuration on a device of our own.
    auto ctx = vk::Context::create();
    ASSERT_TRUE(ctx) << ctx.error().message;
    auto comp = Compositor::create(**ctx, config->compositor);
    ASSERT_TRUE(comp) << comp.error().message;
    auto make = [&](layers::Usage u, layers::Format fmt, glm::uvec2 size) {
        layers::SwapchainCreateInfo ci;
        ci.usage = u;
        ci.format = fmt;
        ci.width = size.x;
        ci.height = size.y;
        ci.arraySize = 2;
        auto sc = (*comp)->createSwapchain(ci);
        EXPECT_TRUE(sc) << (sc ? "" : sc.error().message);
        return sc ? std::move(*sc) : nullptr;
    };
    auto lw = make(layers::Usage::Color, layers::Format::RGBA8_SRGB, sizes.wide);
    auto li = make(layers::Usage::Color, layers::Format::RGBA8_SRGB, sizes.inset);
    auto lwd = make(layers::Usage::Depth, layers::Format::D32F, sizes.wide);
    auto lid = make(layers::Usage::Depth, layers::Format::D32F, sizes.inset);
    ASSERT_TRUE(lw && li && lwd && lid);
    uint64_t differing = 0, pixels = 0;
    int maxDiff = 0, jitteredViews = 0;
    for (int f = 0; f < kFrames; ++f) {
        const Submitted& s = frames[f];
        auto put = [&](layers::Swapchain& sc, int first, const std::array<std::vector<uint8_t>, 4>& imgs) {
            auto index = sc.acquire();
            ASSERT_TRUE(index);
            ASSERT_TRUE(sc.wait());
            for (uint32_t e = 0; e < 2; ++e)
                ASSERT_TRUE(sc.write(*index, e, std::as_bytes(std::span(imgs[first + e]))));
            ASSERT_TRUE(sc.release());
        };
        put(*lw, 0, s.color);
        put(*li, 2, s.color);
        put(*lwd, 0, s.depth);
        put(*lid, 2, s.depth);
        layers::FrameEndInfo fe;
        fe.frameIndex = uint64_t(f) + 1;  // the runtime numbers the session's frames from 1
        fe.time_s = f / 90.0;
        layers::ProjectionLayer layer;
        for (uint32_t e = 0; e < 2; ++e) {
            layers::ProjectionView pv;
            pv.fov = toFov(s.fov[e]);
            pv.color = {lw.get(), {0, 0, sizes.wide.x, sizes.wide.y}, e};
            pv.depth = layers::DepthInfo{{lwd.get(), {0, 0, sizes.wide.x, sizes.wide.y}, e}, 0.1f, 100.0f, false};
            // The library is told where the samples were taken: the located grid and the jitter.
            jitteredViews += xr::placeJitter(pv, toFov(s.located[e]));
            layers::InsetView in;
            in.fov = toFov(s.fov[2 + e]);
            in.color = {li.get(), {0, 0, sizes.inset.x, sizes.inset.y}, e};
            in.depth = layers::DepthInfo{{lid.get(), {0, 0, sizes.inset.x, sizes.inset.y}, e}, 0.1f, 100.0f, false};
            pv.inset = in;
            layer.views.push_back(pv);
            fe.gaze[e] = reader->gaze(uint32_t(f))[e];
        }
        layer.outputWidth = layer.outputHeight = kDisplay;
        fe.layers.push_back(layer);
        Status st = (*comp)->endFrame(fe);
        ASSERT_TRUE(st) << "frame " << f << ": " << st.message();
        for (uint32_t e = 0; e < 2; ++e) {
            auto out = (*comp)->readOutput(e);
            ASSERT_TRUE(out);
            cv::Mat got = cv::imread(rec.path + "/" + eval::frameFileName(uint32_t(f), int(e), "output.png"));
            ASSERT_EQ(uint32_t(got.cols), out->width);
            ASSERT_EQ(uint32_t(got.rows), out->height);
            for (uint32_t y = 0; y < out->height; ++y)
                for (uint32_t x = 0; x < out->width; ++x) {
                    const auto* o = reinterpret_cast<const uint8_t*>(&out->data[(size_t(y) * out->width + x) * 4]);
                    const cv::Vec3b r = got.at<cv::Vec3b>(int(y), int(x));  // BGR
                    int d = 0;
                    for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(o[k]) - int(r[2 - k])));
                    differing += d != 0;
                    maxDiff = std::max(maxDiff, d);
                    ++pixels;
                }
        }
    }
    std::printf("[quad views] jittered wide views, runtime output against the library's: %llu of %llu pixels "
                "differ, max %d / 255\n",
                (unsigned long long)differing, (unsigned long long)pixels, maxDiff);
    EXPECT_EQ(differing, 0u);
    EXPECT_EQ(jitteredViews, 2 * kFrames) << "every wide view was submitted jittered";
    EXPECT_EQ((*ctx)->validationErrors() + (*ctx)->validationWarnings(), 0u);
}

// A quad-view session with whole-image swapchains written once: colour for the wide views and the
// insets (layer = eye), depth for both.
struct QuadSession {
    std::unique_ptr<Client> c;
    Swapchain wide, inset, wideDepth, insetDepth;
    glm::uvec2 wideSize{0, 0}, insetSize{0, 0};
    void open(XrViewConfigurationType type = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO) {
        c = Client::create(kQuadExtensions);
        ASSERT_TRUE(c);
        XrViewConfigurationView v[4];
        for (auto& x : v) x = {XR_TYPE_VIEW_CONFIGURATION_VIEW};
        uint32_t n = 0;
        ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system,
                                                    XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, 4, &n, v),
                  XR_SUCCESS);
        wideSize = {v[0].recommendedImageRectWidth, v[0].recommendedImageRectHeight};
        insetSize = {v[2].recommendedImageRectWidth, v[2].recommendedImageRectHeight};
        ASSERT_EQ(c->createSwapchain(kSrgb, wideSize.x, wideSize.y, 2, kColorUsage, wide), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(kSrgb, insetSize.x, insetSize.y, 2, kColorUsage, inset), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, wideSize.x, wideSize.y, 2, kDepthUsage, wideDepth),
                  XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, insetSize.x, insetSize.y, 2, kDepthUsage, insetDepth),
                  XR_SUCCESS);
        const XrFovf fov{-0.5f, 0.5f, 0.5f, -0.5f};
        c->writeSwapchain(wide, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                          [&](uint32_t) { return render(wideSize.x, wideSize.y, fov, 0); });
        c->writeSwapchain(inset, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                          [&](uint32_t) { return render(insetSize.x, insetSize.y, fov, 0); });
        c->writeSwapchain(wideDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT,
                          [&](uint32_t) { return depthImage(wideSize.x, wideSize.y, fov); });
        c->writeSwapchain(insetDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT,
                          [&](uint32_t) { return depthImage(insetSize.x, insetSize.y, fov); });
        ASSERT_EQ(c->begin(type), XR_SUCCESS);
    }
    /// One frame: the layer built from the located quad views, spoilt by `spoil`, ended; the result of
    /// that xrEndFrame, and what the runtime wrote to stderr meanwhile. A refused frame stays open: a
    /// good frame end then closes it (`goodAfter`: its result).
    XrResult frame(const std::function<void(QuadLayer&)>& spoil, std::string* log = nullptr,
                   XrResult* goodAfter = nullptr) {
        XrResult spoilt = XR_SUCCESS;
        XrResult r = c->frame([&](const XrFrameState& fs) {
            XrView v[4];
            EXPECT_EQ(locate(*c, fs.predictedDisplayTime, true, v), XR_SUCCESS);
            QuadLayer ql;
            ql.build(c->local, v, wide, inset, &wideDepth, &insetDepth);
            spoil(ql);
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            ::testing::internal::CaptureStderr();
            spoilt = xrEndFrame(c->session, &fe);
            const std::string err = ::testing::internal::GetCapturedStderr();
            if (log) *log = err;
            if (spoilt == XR_SUCCESS) return XR_SUCCESS;
            QuadLayer good;
            good.build(c->local, v, wide, inset, &wideDepth, &insetDepth);
            std::vector<const XrCompositionLayerBaseHeader*> gl{good.header()};
            XrFrameEndInfo gf = frameEnd(fs.predictedDisplayTime, gl);
            return xrEndFrame(c->session, &gf);
        });
        if (goodAfter) *goodAfter = r;
        return r == XR_SUCCESS ? spoilt : r;
    }
};

// Every refusal class of a quad-view frame end, with the specification's XrResult and a log line naming
// the field and its value; each refused frame changes nothing (a good frame end follows it).
TEST(XrQuadViews, FrameEndRefusalsNameTheField) {
    QuadSession q;
    q.open();
    if (::testing::Test::HasFatalFailure()) return;
    ASSERT_EQ(q.frame([](QuadLayer&) {}), XR_SUCCESS);
    struct Case {
        const char* what;
        std::function<void(QuadLayer&)> spoil;
        XrResult want;
        const char* field;  // in the runtime's log line
    };
    const float nan = std::nanf("");
    const std::vector<Case> cases = {
        {"two views in a quad session", [](QuadLayer& l) { l.layer.viewCount = 2; }, XR_ERROR_VALIDATION_FAILURE,
         "(frameEndInfo->layers[0]->viewCount == 2) is not the 4 views"},
        {"left inset beyond its view's left edge",
         [](QuadLayer& l) { l.views[2].fov.angleLeft = l.views[0].fov.angleLeft - 0.01f; }, XR_ERROR_VALIDATION_FAILURE,
         "views[2].fov.angleLeft == "},
        {"right inset above its view", [](QuadLayer& l) { l.views[3].fov.angleUp = l.views[1].fov.angleUp + 0.05f; },
         XR_ERROR_VALIDATION_FAILURE, "views[3].fov.angleUp == "},
        {"right inset moved 1 cm", [](QuadLayer& l) { l.views[3].pose.position.x += 0.01f; }, XR_ERROR_POSE_INVALID,
         "views[3].pose == "},
        {"left inset turned 5 degrees",
         [](QuadLayer& l) {
             const glm::quat q = glm::angleAxis(0.0873f, glm::vec3(0, 1, 0));
             l.views[2].pose.orientation = {q.x, q.y, q.z, q.w};
         },
         XR_ERROR_POSE_INVALID, "views[2].pose == "},
        {"inset pose not a unit quaternion", [](QuadLayer& l) { l.views[2].pose.orientation.w = 2.0f; },
         XR_ERROR_POSE_INVALID, "views[2].pose == "},
        {"inset NaN angle", [=](QuadLayer& l) { l.views[2].fov.angleRight = nan; }, XR_ERROR_VALIDATION_FAILURE,
         "views[2].fov.angleRight == nan"},
        {"inset rectangle beyond its image", [](QuadLayer& l) { l.views[3].subImage.imageRect.extent.width += 1; },
         XR_ERROR_SWAPCHAIN_RECT_INVALID, "views[3].subImage.imageRect == "},
        {"inset array index", [](QuadLayer& l) { l.views[3].subImage.imageArrayIndex = 2; },
         XR_ERROR_VALIDATION_FAILURE, "views[3].subImage.imageArrayIndex == 2"},
        {"inset view type", [](QuadLayer& l) { l.views[2].type = XR_TYPE_VIEW; }, XR_ERROR_VALIDATION_FAILURE,
         "views[2].type == "},
        {"inset depth range", [](QuadLayer& l) { l.depth[3].minDepth = 1.0f; }, XR_ERROR_VALIDATION_FAILURE,
         "views[3].next<XrCompositionLayerDepthInfoKHR>.minDepth == 1"},
        {"inset depth near == far", [](QuadLayer& l) { l.depth[2].farZ = l.depth[2].nearZ; },
         XR_ERROR_VALIDATION_FAILURE, "views[2].next<XrCompositionLayerDepthInfoKHR>.nearZ == 0.1, farZ == 0.1"},
    };
    for (const Case& k : cases) {
        std::string log;
        XrResult good = XR_ERROR_RUNTIME_FAILURE;
        EXPECT_EQ(q.frame(k.spoil, &log, &good), k.want) << k.what;
        EXPECT_EQ(good, XR_SUCCESS) << "good frame after: " << k.what;
        EXPECT_NE(log.find(k.field), std::string::npos) << k.what << ": " << log;
    }
    // Depth on the wide views only: not refused (the specification lets any view go without), composited
    // without depth.
    EXPECT_EQ(q.frame([](QuadLayer& l) { l.views[2].next = l.views[3].next = nullptr; }), XR_SUCCESS);
    q.c.reset();

    // Four views in a stereo session.
    QuadSession s;
    s.open(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO);
    if (::testing::Test::HasFatalFailure()) return;
    std::string log;
    EXPECT_EQ(s.frame([](QuadLayer&) {}, &log), XR_ERROR_VALIDATION_FAILURE);
    EXPECT_NE(log.find("(frameEndInfo->layers[0]->viewCount == 4) is not the 2 views of the session's view "
                       "configuration XR_VIEW_CONFIGURATION_TYPE_PRIMARY_STEREO"),
              std::string::npos)
        << log;
}

// Without the extensions enabled, quad views and the combined-eye space do not exist for the application;
// with quad_views = 0 the runtime does not offer them at all.
TEST(XrQuadViews, OnlyWhereEnabledAndOffered) {
    {
        auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME});
        ASSERT_TRUE(c);
        const XrViewConfigurationType quad = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
        uint32_t n = 0;
        XrViewConfigurationType types[4];
        ASSERT_EQ(xrEnumerateViewConfigurations(c->instance, c->system, 4, &n, types), XR_SUCCESS);
        EXPECT_EQ(n, 1u);
        EXPECT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system, quad, 0, &n, nullptr),
                  XR_ERROR_VALIDATION_FAILURE);
        XrViewConfigurationProperties vp{XR_TYPE_VIEW_CONFIGURATION_PROPERTIES};
        EXPECT_EQ(xrGetViewConfigurationProperties(c->instance, c->system, quad, &vp), XR_ERROR_VALIDATION_FAILURE);
        XrResult r;
        referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO, &r);
        EXPECT_EQ(r, XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
        EXPECT_EQ(c->begin(quad), XR_ERROR_VALIDATION_FAILURE);
        ASSERT_EQ(c->begin(), XR_SUCCESS);
        XrView v[4];
        EXPECT_EQ(locate(*c, 1000, true, v), XR_ERROR_VALIDATION_FAILURE);
    }
    {
        // Quad views without foveated rendering: the insets stay centred even when asked to follow.
        auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME});
        ASSERT_TRUE(c);
        XrResult r;
        referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO, &r);
        EXPECT_EQ(r, XR_ERROR_REFERENCE_SPACE_UNSUPPORTED);
        ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
        XrView v[4];
        ASSERT_EQ(locate(*c, 1000000000, true, v), XR_SUCCESS);
        auto config = xr::loadRuntimeConfig();
        ASSERT_TRUE(config);
        for (int e = 0; e < 2; ++e)
            expectFovNear(v[2 + e].fov, xr::insetFov(toFov(v[e].fov), config->insetDeg, std::nullopt), 1e-6f,
                          "centred inset");
    }
    // The runtime with quad_views = 0. Through the API layer the layer offers them instead
    // (OfferedByTheLayerOnAStereoRuntime).
    if (throughLayer()) return;
    ScopedEnv env{{"WRSFOV_XR_QUAD_VIEWS", "0"}};
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateInstanceExtensionProperties(nullptr, 0, &n, nullptr), XR_SUCCESS);
    std::vector<XrExtensionProperties> props(n, {XR_TYPE_EXTENSION_PROPERTIES});
    ASSERT_EQ(xrEnumerateInstanceExtensionProperties(nullptr, n, &n, props.data()), XR_SUCCESS);
    for (const auto& p : props) {
        EXPECT_STRNE(p.extensionName, XR_VARJO_QUAD_VIEWS_EXTENSION_NAME);
        EXPECT_STRNE(p.extensionName, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME);
    }
    const char* ext[] = {XR_VARJO_QUAD_VIEWS_EXTENSION_NAME};
    XrInstanceCreateInfo ici{XR_TYPE_INSTANCE_CREATE_INFO};
    std::snprintf(ici.applicationInfo.applicationName, XR_MAX_APPLICATION_NAME_SIZE, "wrsfov-xr-quad-off");
    ici.applicationInfo.apiVersion = XR_MAKE_VERSION(1, 0, 0);
    ici.enabledExtensionCount = 1;
    ici.enabledExtensionNames = ext;
    XrInstance inst = XR_NULL_HANDLE;
    EXPECT_EQ(xrCreateInstance(&ici, &inst), XR_ERROR_EXTENSION_NOT_PRESENT);
    if (inst) xrDestroyInstance(inst);
}

// A gaze far up and to the right (a gaze file): each inset is shifted back inside its view, touching its
// edges, and keeps its size; once the file's gaze turns invalid the combined-eye space is no longer
// tracked and the insets are centred.
TEST(XrQuadViews, InsetStaysInsideTheViewAndCentresWithoutGaze) {
    const TempDir dir("wrsfov_xr_quad_gaze");
    std::filesystem::create_directories(dir.path);
    std::vector<gaze::GazeSample> samples;
    for (int i = 0; i <= 200; ++i) {
        gaze::GazeSample g;
        g.t_s = i * 0.01;
        for (auto& e : g.eye) e = {glm::normalize(glm::vec3(1.5f, 0.9f, -1.0f)), i * 0.01 < 0.3, 1.0f};
        samples.push_back(g);
    }
    const std::string file = dir.path + "/gaze.csv";
    ASSERT_TRUE(gaze::write_gaze_csv(file, samples, false));
    ScopedEnv env{{"WRSFOV_XR_GAZE", "file"}, {"WRSFOV_XR_GAZE_FILE", file.c_str()}};
    QuadSession q;
    q.open();
    if (::testing::Test::HasFatalFailure()) return;
    const XrSpace eyes = referenceSpace(*q.c, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO);
    auto config = xr::loadRuntimeConfig();
    ASSERT_TRUE(config);
    int atEdge = 0, centred = 0;
    for (int f = 0; f < 60; ++f) {
        ASSERT_EQ(q.c->frame([&](const XrFrameState& fs) {
            XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
            EXPECT_EQ(xrLocateSpace(eyes, q.c->local, fs.predictedDisplayTime, &loc), XR_SUCCESS);
            const bool tracked = loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
            EXPECT_TRUE(loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_VALID_BIT);
            XrView v[4];
            EXPECT_EQ(locate(*q.c, fs.predictedDisplayTime, true, v), XR_SUCCESS);
            for (int e = 0; e < 2; ++e) {
                const XrFovf& w = v[e].fov;
                const XrFovf& in = v[2 + e].fov;
                if (tracked) {
                    EXPECT_NEAR(in.angleRight, w.angleRight, 1e-6f) << "frame " << f;
                    EXPECT_NEAR(in.angleUp, w.angleUp, 1e-6f) << "frame " << f;
                    ++atEdge;
                } else {
                    expectFovNear(in, xr::insetFov(toFov(w), config->insetDeg, std::nullopt), 1e-6f, "centred");
                    ++centred;
                }
                // The same extent in tangent units wherever it is: the display's density.
                const float h = std::tan(0.5f * config->insetDeg * 3.14159265f / 180.0f);
                EXPECT_NEAR(std::tan(in.angleRight) - std::tan(in.angleLeft), 2 * h, 1e-4f);
                EXPECT_NEAR(std::tan(in.angleUp) - std::tan(in.angleDown), 2 * h, 1e-4f);
            }
            QuadLayer ql;
            ql.build(q.c->local, v, q.wide, q.inset, &q.wideDepth, &q.insetDepth);
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(q.c->session, &fe);
        }),
                  XR_SUCCESS);
    }
    EXPECT_GT(atEdge, 20);
    EXPECT_GT(centred, 20);
}

// XR_FB_space_warp on all four views: each view's motion is in its own NDC, so one scene motion gives
// the wide views and the insets different texels; composed, both are the same motion in output pixels
// (recorded in pixels: previous = current + mv).
TEST(XrQuadViews, SpaceWarpMotionOfEachViewInOutputPixels) {
    const TempDir rec("wrsfov_xr_quad_warp");
    ScopedEnv env{{"WRSFOV_XR_WIDTH", "160"}, {"WRSFOV_XR_HEIGHT", "160"}, {"WRSFOV_XR_RECORD", rec.path.c_str()}};
    auto c = Client::create({XR_KHR_VULKAN_ENABLE2_EXTENSION_NAME, XR_FB_SPACE_WARP_EXTENSION_NAME,
                             XR_VARJO_QUAD_VIEWS_EXTENSION_NAME, XR_VARJO_FOVEATED_RENDERING_EXTENSION_NAME});
    ASSERT_TRUE(c);
    auto config = xr::loadRuntimeConfig();
    ASSERT_TRUE(config);
    const xr::QuadViewSizes sizes = xr::quadViewSizes(*config);
    Swapchain color[2], motion[2], depth[2];  // wide, inset; layer = eye
    const glm::uvec2 size[2] = {sizes.wide, sizes.inset};
    for (int i = 0; i < 2; ++i) {
        ASSERT_EQ(c->createSwapchain(kSrgb, size[i].x, size[i].y, 2, kColorUsage, color[i]), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_R16G16B16A16_SFLOAT, size[i].x, size[i].y, 2, kColorUsage, motion[i]),
                  XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, size[i].x, size[i].y, 2, kDepthUsage, depth[i]), XR_SUCCESS);
    }
    ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
    // The scene moved right by 0.01 tangent units since the last frame: in a view spanning s tangent
    // units across that is 2 * 0.01 / s of NDC (current - previous).
    constexpr float kShift = 0.01f;
    for (int f = 0; f < 3; ++f) {
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            XrView v[4];
            EXPECT_EQ(locate(*c, fs.predictedDisplayTime, true, v), XR_SUCCESS);
            XrCompositionLayerSpaceWarpInfoFB warp[4];
            QuadLayer ql;
            ql.build(c->local, v, color[0], color[1]);
            for (int i = 0; i < 2; ++i) {
                const glm::uvec2 sz = size[i];
                c->writeSwapchain(color[i], 4, VK_IMAGE_ASPECT_COLOR_BIT,
                                  [&](uint32_t e) { return render(sz.x, sz.y, v[2 * i + e].fov, f); });
                c->writeSwapchain(depth[i], 4, VK_IMAGE_ASPECT_DEPTH_BIT,
                                  [&](uint32_t e) { return depthImage(sz.x, sz.y, v[2 * i + e].fov); });
                c->writeSwapchain(motion[i], 8, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t e) {
                    const glm::vec4 t = tangents(v[2 * i + e].fov);
                    const uint16_t texel[4] = {glm::packHalf1x16(2.0f * kShift / (t.y - t.x)), 0, 0, 0};
                    std::vector<uint8_t> mv(size_t(sz.x) * sz.y * 8);
                    for (size_t k = 0; k < size_t(sz.x) * sz.y; ++k) std::memcpy(&mv[k * 8], texel, 8);
                    return mv;
                });
            }
            for (uint32_t i = 0; i < 4; ++i) {
                const Swapchain& m = motion[i / 2];
                warp[i] = {XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB};
                warp[i].motionVectorSubImage = {m.handle, {{0, 0}, {int32_t(m.width), int32_t(m.height)}}, i % 2};
                warp[i].depthSubImage = {depth[i / 2].handle, warp[i].motionVectorSubImage.imageRect, i % 2};
                warp[i].appSpaceDeltaPose.orientation.w = 1.0f;
                warp[i].minDepth = 0.0f;
                warp[i].maxDepth = 1.0f;
                warp[i].nearZ = 0.1f;
                warp[i].farZ = 100.0f;
                ql.views[i].next = &warp[i];
            }
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS);
    }
    c.reset();
    auto opened = eval::SequenceReader::open(rec.path);
    ASSERT_TRUE(opened) << opened.error().message;
    ASSERT_TRUE((*opened)->info().motion.has_value());
    auto last = (*opened)->frame(2);
    ASSERT_TRUE(last) << last.error().message;
    for (int e = 0; e < 2; ++e) {
        const XrFovf fov{config->fov[e].angleLeft, config->fov[e].angleRight, config->fov[e].angleUp,
                         config->fov[e].angleDown};
        const glm::vec4 t = tangents(fov);
        const float want = -kShift * 160.0f / (t.y - t.x);  // output pixels to the previous position
        ASSERT_TRUE(last->eyes[e].motion.has_value());
        const HostImage& m = *last->eyes[e].motion;
        float lo = 1e9f, hi = -1e9f;
        for (uint32_t y = 0; y < m.height; ++y)
            for (uint32_t x = 0; x < m.width; ++x) {
                lo = std::min(lo, m.fetch(x, y).x);
                hi = std::max(hi, m.fetch(x, y).x);
            }
        EXPECT_NEAR(lo, want, 0.01f) << "eye " << e;
        EXPECT_NEAR(hi, want, 0.01f) << "eye " << e;
    }
}

// The API layer (XR_APILAYER_WRSFOV_foveation) offering quad views on a runtime without them (the
// ctest entry xr_quad_through_layer: WRSFOV_XR_QUAD_VIEWS=0, the runtime showing and recording what
// it receives, WRSFOV_XR_METHOD=off). First the layer's answers: the quad configuration over the
// runtime's stereo one, its sizes, the combined-eye space, insets on the layer's gaze. Then, with the
// layer's gaze off (a deterministic centred inset and fallback fovea), 60 frames whose stereo frames
// as the runtime received them equal a Compositor of the layer's configuration fed the same four views.
TEST(XrQuadViews, OfferedByTheLayerOnAStereoRuntime) {
    const char* quadOff = std::getenv("WRSFOV_XR_QUAD_VIEWS");
    if (!throughLayer() || !quadOff || std::string(quadOff) != "0")
        GTEST_SKIP() << "runs through the API layer on a runtime without quad views (xr_quad_through_layer)";
    constexpr uint32_t kDisplay = 160;
    {
        ScopedEnv env{{"WRSFOV_XR_WIDTH", "160"}, {"WRSFOV_XR_HEIGHT", "160"}};
        auto c = Client::create(kQuadExtensions);
        ASSERT_TRUE(c);
        XrViewConfigurationType types[4];
        uint32_t n = 0;
        ASSERT_EQ(xrEnumerateViewConfigurations(c->instance, c->system, 4, &n, types), XR_SUCCESS);
        ASSERT_EQ(n, 2u);
        EXPECT_EQ(types[0], XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO);
        XrViewConfigurationView v[4];
        for (auto& x : v) x = {XR_TYPE_VIEW_CONFIGURATION_VIEW};
        ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system,
                                                    XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO, 4, &n, v),
                  XR_SUCCESS);
        ASSERT_EQ(n, 4u);
        EXPECT_EQ(v[0].recommendedImageRectWidth, 64u);  // 160 / 2.5
        EXPECT_EQ(v[2].recommendedImageRectWidth, 43u);  // 2 tan 15 deg over 90 degrees at 160 px
        XrSystemFoveatedRenderingPropertiesVARJO fr{XR_TYPE_SYSTEM_FOVEATED_RENDERING_PROPERTIES_VARJO};
        XrSystemProperties props{XR_TYPE_SYSTEM_PROPERTIES, &fr};
        ASSERT_EQ(xrGetSystemProperties(c->instance, c->system, &props), XR_SUCCESS);
        EXPECT_EQ(fr.supportsFoveatedRendering, XR_TRUE);
        const XrSpace eyes = referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_COMBINED_EYE_VARJO);
        const XrSpace view = referenceSpace(*c, XR_REFERENCE_SPACE_TYPE_VIEW);
        Swapchain wide, inset;
        ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 2, kColorUsage, wide), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(kSrgb, 43, 43, 2, kColorUsage, inset), XR_SUCCESS);
        ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
        int tracked = 0, shifted = 0;
        for (int f = 0; f < 30; ++f) {
            ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
                XrSpaceLocation loc{XR_TYPE_SPACE_LOCATION};
                EXPECT_EQ(xrLocateSpace(eyes, view, fs.predictedDisplayTime, &loc), XR_SUCCESS);
                const bool valid = loc.locationFlags & XR_SPACE_LOCATION_ORIENTATION_TRACKED_BIT;
                tracked += valid;
                XrView lv[4];
                EXPECT_EQ(locate(*c, fs.predictedDisplayTime, valid, lv), XR_SUCCESS);
                for (int e = 0; e < 2; ++e) {
                    EXPECT_EQ(std::memcmp(&lv[e].pose, &lv[e + 2].pose, sizeof(XrPosef)), 0);
                    EXPECT_GE(lv[e + 2].fov.angleLeft, lv[e].fov.angleLeft);
                    EXPECT_LE(lv[e + 2].fov.angleRight, lv[e].fov.angleRight);
                    EXPECT_LE(lv[e + 2].fov.angleUp, lv[e].fov.angleUp);
                    EXPECT_GE(lv[e + 2].fov.angleDown, lv[e].fov.angleDown);
                    if (valid) {
                        // On the rendering gaze: the combined-eye direction, in the inset's centre.
                        const XrQuaternionf& q = loc.pose.orientation;
                        const glm::vec3 g = glm::quat(q.w, q.x, q.y, q.z) * glm::vec3(0, 0, -1);
                        const glm::vec4 t = tangents(lv[e + 2].fov);
                        EXPECT_NEAR(0.5f * (t.x + t.y), g.x / -g.z, 2e-3f) << "frame " << f;
                        EXPECT_NEAR(0.5f * (t.z + t.w), g.y / -g.z, 2e-3f) << "frame " << f;
                    }
                    const layers::Fov centred = xr::insetFov(toFov(lv[e].fov), 30.0f, std::nullopt);
                    shifted += std::abs(lv[e + 2].fov.angleLeft - centred.angleLeft) > 0.01f;
                }
                c->writeSwapchain(wide, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                                  [&](uint32_t e) { return render(64, 64, lv[e].fov, f); });
                c->writeSwapchain(inset, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                                  [&](uint32_t e) { return render(43, 43, lv[2 + e].fov, f); });
                QuadLayer ql;
                ql.build(c->local, lv, wide, inset);
                std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
                XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
                return xrEndFrame(c->session, &fe);
            }),
                      XR_SUCCESS);
        }
        EXPECT_GT(tracked, 15);
        EXPECT_GT(shifted, 15) << "the layer's insets do not follow its gaze";
        // The count alone, with no views and a view state whose flags a previous call set: 4, and the
        // state as it was (the layer locates the stereo views into its own; docs/openxr-layer.md).
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
            li.viewConfigurationType = XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO;
            li.displayTime = fs.predictedDisplayTime;
            li.space = c->local;
            XrViewState vs{XR_TYPE_VIEW_STATE};
            vs.viewStateFlags = XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT;
            uint32_t count = 0;
            EXPECT_EQ(xrLocateViews(c->session, &li, &vs, 0, &count, nullptr), XR_SUCCESS);
            EXPECT_EQ(count, 4u);
            EXPECT_EQ(vs.viewStateFlags, XR_VIEW_STATE_ORIENTATION_VALID_BIT | XR_VIEW_STATE_POSITION_VALID_BIT);
            XrView lv[4];
            for (auto& v : lv) v = {XR_TYPE_VIEW};
            EXPECT_EQ(xrLocateViews(c->session, &li, &vs, 2, &count, lv), XR_ERROR_SIZE_INSUFFICIENT);
            const std::vector<const XrCompositionLayerBaseHeader*> none;
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, none);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS);
        // Two views in the quad session the layer offers: refused, as the runtime would.
        XrResult r = c->frame([&](const XrFrameState& fs) {
            XrView lv[4];
            EXPECT_EQ(locate(*c, fs.predictedDisplayTime, false, lv), XR_SUCCESS);
            QuadLayer ql;
            ql.build(c->local, lv, wide, inset);
            ql.layer.viewCount = 2;
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            EXPECT_EQ(xrEndFrame(c->session, &fe), XR_ERROR_VALIDATION_FAILURE);
            ql.layer.viewCount = 4;
            return xrEndFrame(c->session, &fe);
        });
        EXPECT_EQ(r, XR_SUCCESS);
    }

    // The composition, bit for bit: the layer's gaze off, so the inset is centred and the fovea the
    // compositor's fallback, both known here.
    const TempDir rec("wrsfov_xr_quad_layer_rec");
    ScopedEnv env{{"WRSFOV_XR_WIDTH", "160"},
                  {"WRSFOV_XR_HEIGHT", "160"},
                  {"WRSFOV_XR_RECORD", rec.path.c_str()},
                  {"WRSFOV_LAYER_GAZE", "none"}};
    auto layerConfig = xr::loadConfig("WRSFOV_LAYER_");
    ASSERT_TRUE(layerConfig) << layerConfig.error().message;
    auto c = Client::create(kQuadExtensions);
    ASSERT_TRUE(c);
    Swapchain wide, inset;
    ASSERT_EQ(c->createSwapchain(kSrgb, 64, 64, 2, kColorUsage, wide), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(kSrgb, 43, 43, 2, kColorUsage, inset), XR_SUCCESS);
    ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
    struct Submitted {
        std::array<std::vector<uint8_t>, 4> color;
        std::array<XrFovf, 4> fov;      // as submitted (the wide views jittered)
        std::array<XrFovf, 2> located;  // the wide views as located
    };
    std::vector<Submitted> frames;
    constexpr int kFrames = 60;
    for (int f = 0; f < kFrames; ++f) {
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            XrView lv[4];
            EXPECT_EQ(locate(*c, fs.predictedDisplayTime, true, lv), XR_SUCCESS);
            Submitted s;
            // Wide views jittered (Halton 2, 3 over 8 phases) and submitted with the shifted field of view.
            for (int e = 0; e < 2; ++e) {
                s.located[e] = lv[e].fov;
                lv[e].fov = jittered(lv[e].fov, layers::haltonJitter(uint64_t(f), 8), 64, 64);
            }
            for (int i = 0; i < 4; ++i) {
                s.fov[i] = lv[i].fov;
                s.color[i] = i < 2 ? render(64, 64, lv[i].fov, f) : render(43, 43, lv[i].fov, f);
            }
            c->writeSwapchain(wide, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t e) { return s.color[e]; });
            c->writeSwapchain(inset, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t e) { return s.color[2 + e]; });
            frames.push_back(std::move(s));
            QuadLayer ql;
            ql.build(c->local, lv, wide, inset);
            std::vector<const XrCompositionLayerBaseHeader*> ls{ql.header()};
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS);
    }
    c.reset();
    auto opened = eval::SequenceReader::open(rec.path);
    ASSERT_TRUE(opened) << opened.error().message;
    const auto& reader = *opened;
    ASSERT_EQ(reader->info().frameCount, uint32_t(kFrames));
    ASSERT_EQ(reader->info().width, kDisplay);  // stereo at the runtime's size

    auto ctx = vk::Context::create();
    ASSERT_TRUE(ctx) << ctx.error().message;
    auto comp = Compositor::create(**ctx, layerConfig->compositor);
    ASSERT_TRUE(comp) << comp.error().message;
    auto make = [&](uint32_t size) {
        layers::SwapchainCreateInfo ci;
        ci.format = layers::Format::RGBA8_SRGB;
        ci.width = ci.height = size;
        ci.arraySize = 2;
        auto sc = (*comp)->createSwapchain(ci);
        EXPECT_TRUE(sc);
        return sc ? std::move(*sc) : nullptr;
    };
    auto lw = make(64), li = make(43);
    ASSERT_TRUE(lw && li);
    uint64_t differing = 0, pixels = 0;
    for (int f = 0; f < kFrames; ++f) {
        const Submitted& s = frames[f];
        for (auto [sc, first] : {std::pair{lw.get(), 0}, std::pair{li.get(), 2}}) {
            auto index = sc->acquire();
            ASSERT_TRUE(index);
            ASSERT_TRUE(sc->wait());
            for (uint32_t e = 0; e < 2; ++e)
                ASSERT_TRUE(sc->write(*index, e, std::as_bytes(std::span(s.color[first + e]))));
            ASSERT_TRUE(sc->release());
        }
        layers::FrameEndInfo fe;
        fe.frameIndex = uint64_t(f) + 1;
        fe.time_s = f / 90.0;
        layers::ProjectionLayer layer;
        for (uint32_t e = 0; e < 2; ++e) {
            layers::ProjectionView pv;
            pv.fov = toFov(s.fov[e]);
            pv.color = {lw.get(), {0, 0, 64, 64}, e};
            EXPECT_TRUE(xr::placeJitter(pv, toFov(s.located[e]))) << "frame " << f;
            layers::InsetView in;
            in.fov = toFov(s.fov[2 + e]);
            in.color = {li.get(), {0, 0, 43, 43}, e};
            pv.inset = in;
            layer.views.push_back(pv);
        }
        layer.outputWidth = layer.outputHeight = kDisplay;
        fe.layers.push_back(layer);
        Status st = (*comp)->endFrame(fe);
        ASSERT_TRUE(st) << st.message();
        auto got = reader->frame(uint32_t(f));
        ASSERT_TRUE(got) << got.error().message;
        for (uint32_t e = 0; e < 2; ++e) {
            auto out = (*comp)->readOutput(e);
            ASSERT_TRUE(out);
            const HostImage& r = got->eyes[e].color;
            ASSERT_EQ(r.data.size(), out->data.size());
            for (std::size_t i = 0; i < out->data.size(); i += 4) {
                differing += std::memcmp(&out->data[i], &r.data[i], 3) != 0;
                ++pixels;
            }
        }
    }
    std::printf(
        "[quad views] through the layer: the runtime's received frames against the library's: %llu of %llu "
        "pixels differ\n",
        (unsigned long long)differing, (unsigned long long)pixels);
    EXPECT_EQ(differing, 0u);
    // The layer hands the runtime the field of view it composed over: the located one, not the jittered
    // one the application submitted (the runtime places the image by it).
    for (int e = 0; e < 2; ++e) expectFovNear(frames[0].located[e], reader->info().fov[e], 1e-6f, "recorded field of view");
}

}  // namespace
}  // namespace wrsfov::xrtest

namespace wrsfov::xrtest {
namespace {

// Quad views through the API layer on any stereo runtime (our own with quad_views = 0 in the
// xr_quad_through_layer test, in its strict swapchain setting; Monado, pointed at with
// WRSFOV_TEST_ANY_RUNTIME=1): what an application sees and submits, with no assumption about the
// runtime's sizes, formats or image counts. The configuration (four views, the insets inside their
// wide views at the same poses), swapchains of a colour format the runtime offers with depth, and 60
// frames of four rendered views ended with XR_SUCCESS. What the runtime shows is its own: the layer's
// log line "N of N frames foveated" is what the harness checks (tests/xr/CMakeLists.txt).
TEST(XrQuadViews, SubmittedThroughTheLayerOnAnyStereoRuntime) {
    const char* quadOff = std::getenv("WRSFOV_XR_QUAD_VIEWS");
    const char* any = std::getenv("WRSFOV_TEST_ANY_RUNTIME");
    if (!throughLayer() || !((quadOff && std::string(quadOff) == "0") || (any && std::string(any) == "1")))
        GTEST_SKIP() << "runs through the API layer on a runtime without quad views (xr_quad_through_layer)";
    auto c = Client::create(kQuadExtensions);
    ASSERT_TRUE(c);
    XrViewConfigurationType types[8];
    uint32_t n = 0;
    ASSERT_EQ(xrEnumerateViewConfigurations(c->instance, c->system, 8, &n, types), XR_SUCCESS);
    ASSERT_GE(n, 2u);
    EXPECT_EQ(types[0], XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO);
    XrViewConfigurationView v[4];
    for (auto& x : v) x = {XR_TYPE_VIEW_CONFIGURATION_VIEW};
    ASSERT_EQ(xrEnumerateViewConfigurationViews(c->instance, c->system, XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO,
                                                4, &n, v),
              XR_SUCCESS);
    ASSERT_EQ(n, 4u);
    const uint32_t ww = v[0].recommendedImageRectWidth, wh = v[0].recommendedImageRectHeight;
    const uint32_t iw = v[2].recommendedImageRectWidth, ih = v[2].recommendedImageRectHeight;
    EXPECT_GT(ww * wh, 0u);
    EXPECT_GT(iw * ih, 0u);
    EXPECT_LT(ww, c->viewWidth);  // wide views below the display's density
    // A colour format the runtime offers that the layer composes (8-bit RGBA, sRGB first), and depth.
    uint32_t fc = 0;
    ASSERT_EQ(xrEnumerateSwapchainFormats(c->session, 0, &fc, nullptr), XR_SUCCESS);
    std::vector<int64_t> formats(fc);
    ASSERT_EQ(xrEnumerateSwapchainFormats(c->session, fc, &fc, formats.data()), XR_SUCCESS);
    auto offered = [&](int64_t f) { return std::find(formats.begin(), formats.end(), f) != formats.end(); };
    const int64_t color = offered(kSrgb) ? kSrgb : int64_t(VK_FORMAT_R8G8B8A8_UNORM);
    ASSERT_TRUE(offered(color)) << "the runtime offers no 8-bit RGBA colour format";
    const bool withDepth = offered(VK_FORMAT_D32_SFLOAT);
    Swapchain wide, inset, wideDepth, insetDepth;
    ASSERT_EQ(c->createSwapchain(color, ww, wh, 2, kColorUsage, wide), XR_SUCCESS);
    ASSERT_EQ(c->createSwapchain(color, iw, ih, 2, kColorUsage, inset), XR_SUCCESS);
    if (withDepth) {
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, ww, wh, 2, kDepthUsage, wideDepth), XR_SUCCESS);
        ASSERT_EQ(c->createSwapchain(VK_FORMAT_D32_SFLOAT, iw, ih, 2, kDepthUsage, insetDepth), XR_SUCCESS);
    }
    // READY before xrBeginSession (another runtime need not be ready at once).
    bool ready = false;
    for (int i = 0; i < 500 && !ready; ++i) {
        for (XrSessionState s : Client::states(c->poll())) ready = ready || s == XR_SESSION_STATE_READY;
        if (!ready) usleep(10000);
    }
    ASSERT_TRUE(ready) << "the session never became READY";
    ASSERT_EQ(c->begin(XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO), XR_SUCCESS);
    int rendered = 0;
    for (int f = 0; f < 60; ++f) {
        ASSERT_EQ(c->frame([&](const XrFrameState& fs) {
            c->poll();
            std::vector<const XrCompositionLayerBaseHeader*> ls;
            QuadLayer ql;
            if (fs.shouldRender) {
                XrView lv[4];
                EXPECT_EQ(locate(*c, fs.predictedDisplayTime, true, lv), XR_SUCCESS);
                for (int e = 0; e < 2; ++e) {
                    EXPECT_EQ(std::memcmp(&lv[e].pose, &lv[e + 2].pose, sizeof(XrPosef)), 0) << "frame " << f;
                    EXPECT_GE(lv[e + 2].fov.angleLeft, lv[e].fov.angleLeft) << "frame " << f;
                    EXPECT_LE(lv[e + 2].fov.angleRight, lv[e].fov.angleRight) << "frame " << f;
                    EXPECT_LE(lv[e + 2].fov.angleUp, lv[e].fov.angleUp) << "frame " << f;
                    EXPECT_GE(lv[e + 2].fov.angleDown, lv[e].fov.angleDown) << "frame " << f;
                }
                c->writeSwapchain(wide, 4, VK_IMAGE_ASPECT_COLOR_BIT, [&](uint32_t e) { return render(ww, wh, lv[e].fov, f); });
                c->writeSwapchain(inset, 4, VK_IMAGE_ASPECT_COLOR_BIT,
                                  [&](uint32_t e) { return render(iw, ih, lv[2 + e].fov, f); });
                if (withDepth) {
                    c->writeSwapchain(wideDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT,
                                      [&](uint32_t e) { return depthImage(ww, wh, lv[e].fov); });
                    c->writeSwapchain(insetDepth, 4, VK_IMAGE_ASPECT_DEPTH_BIT,
                                      [&](uint32_t e) { return depthImage(iw, ih, lv[2 + e].fov); });
                }
                ql.build(c->local, lv, wide, inset, withDepth ? &wideDepth : nullptr, withDepth ? &insetDepth : nullptr);
                ls.push_back(ql.header());
                ++rendered;
            }
            XrFrameEndInfo fe = frameEnd(fs.predictedDisplayTime, ls);
            return xrEndFrame(c->session, &fe);
        }),
                  XR_SUCCESS)
            << "frame " << f;
    }
    EXPECT_GT(rendered, 30) << "the runtime asked for few frames to be rendered";
    std::printf("[quad views, any runtime] %d of 60 frames rendered as four views (wide %ux%u, inset %ux%u, %s%s)\n",
                rendered, ww, wh, iw, ih, color == kSrgb ? "R8G8B8A8_SRGB" : "R8G8B8A8_UNORM", withDepth ? ", D32 depth" : "");
}

}  // namespace
}  // namespace wrsfov::xrtest
