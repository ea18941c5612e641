#include "preview/preview_app.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <opencv2/imgcodecs.hpp>

#include "compositor/compositor.h"
#include "compositor/vk_context.h"
#include "eval/metrics.h"
#include "preview/gaze_input.h"
#include "preview/layout.h"
#include "preview/live_jod.h"
#include "preview/presenter.h"
#include "preview/scene_feed.h"
#include "preview/strip.h"

namespace wrsfov::preview {

namespace {

constexpr double kFrameStep_s = 1.0 / 90.0;  // the scene clock advances one 90 Hz frame per composited frame

std::string g_glfwError;  // the last GLFW error, for messages (GLFW reports through a C callback)

void onGlfwError(int code, const char* text) {
    g_glfwError = std::string(text ? text : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

std::string fmt(const char* f, double a) {
    char buf[64];
    std::snprintf(buf, sizeof(buf), f, a);
    return buf;
}

const char* formatName(VkFormat f) {
    switch (f) {
        case VK_FORMAT_B8G8R8A8_UNORM:
            return "B8G8R8A8_UNORM";
        case VK_FORMAT_R8G8B8A8_UNORM:
            return "R8G8B8A8_UNORM";
        case VK_FORMAT_B8G8R8A8_SRGB:
            return "B8G8R8A8_SRGB";
        case VK_FORMAT_R8G8B8A8_SRGB:
            return "R8G8B8A8_SRGB";
        default:
            return "other";
    }
}

// GLFW key of a --keys name (validated by parseArguments).
int keyCode(const std::string& name) {
    if (name == "space") return GLFW_KEY_SPACE;
    if (name == "right") return GLFW_KEY_RIGHT;
    if (name == "escape") return GLFW_KEY_ESCAPE;
    const char c = name[0];
    return c >= '0' && c <= '9' ? GLFW_KEY_0 + (c - '0') : GLFW_KEY_A + (c - 'a');
}

// glfwInit / glfwTerminate.
struct GlfwLibrary {
    bool ok = false;
    GlfwLibrary() {
        glfwSetErrorCallback(onGlfwError);
        ok = glfwInit() == GLFW_TRUE;
    }
    ~GlfwLibrary() {
        if (ok) glfwTerminate();
    }
};

struct WindowDeleter {
    void operator()(GLFWwindow* w) const { glfwDestroyWindow(w); }
};

class Session {
public:
    explicit Session(const PreviewOptions& o)
        : o_(o),
          method_(o.method),
          fovea_(o.foveaDeg),
          mode_(o.mode),
          scene_(o.scene),
          path_(o.path),
          photoImage_(o.photoImage),
          photoMotion_(o.photoMotion),
          photoSpeed_(o.photoSpeed),
          view_(o.view),
          overlay_(o.overlay),
          gazeSpec_(o.gaze) {}
    int run();

private:
    Status open();
    Status makeScene();
    Status makeGaze(const GazeSpec& spec);
    Status applyConfig();
    Status composite(bool advance);
    Status scoreJod(double t);
    std::string jodText() const;
    void handleKey(int key);
    void fitWindow();
    std::vector<std::string> statsItems() const;
    ComposeFrame composeFrame(const cv::Mat& strip) const;
    std::optional<std::array<float, 2>> cursorInEye() const;
    Status saveScreenshot(const std::string& path);
    std::string summary() const;

    static void onKey(GLFWwindow* w, int key, int, int action, int) {
        if (action == GLFW_PRESS || (action == GLFW_REPEAT && (key == GLFW_KEY_RIGHT || key == GLFW_KEY_PERIOD)))
            static_cast<Session*>(glfwGetWindowUserPointer(w))->keys_.push_back(key);
    }
    static void onFramebufferSize(GLFWwindow* w, int, int) {
        auto* s = static_cast<Session*>(glfwGetWindowUserPointer(w));
        if (s->presenter_) s->presenter_->framebufferResized();
    }

    PreviewOptions o_;
    // Settings the keys change.
    PreviewMethod method_;
    float fovea_;
    FoveationMode mode_;
    SceneKind scene_;
    scenes::CameraPath path_;
    std::string photoImage_;
    scenes::PhotoMotion photoMotion_;
    float photoSpeed_;
    View view_;
    bool overlay_;
    GazeSpec gazeSpec_;
    bool paused_ = false, step_ = false, dirty_ = false;

    // Destroyed in reverse order: the presenter (surface) before the window and the context.
    GlfwLibrary glfw_;
    std::unique_ptr<GLFWwindow, WindowDeleter> window_;
    std::unique_ptr<vk::Context> ctx_;
    std::unique_ptr<Compositor> main_, reference_;
    std::unique_ptr<SceneFeed> feed_;
    std::unique_ptr<GazeInput> gaze_;
    std::unique_ptr<Presenter> presenter_;
    // Live FovVideoVDP of the output against the reference (views that run the reference).
    std::unique_ptr<LiveJod> jod_;
    uint64_t jodFrame_ = 0;                  // frame index of the last frame scored
    double jodT_ = 0;                        // its scene time
    uint64_t settingsGen_ = 0, jodGen_ = 0;  // settings changed since the video began: a new video

    Layout layout_;
    std::vector<int> keys_;
    uint64_t frameIndex_ = 0;  // frame index of the last composited frame (every compositor)
    uint64_t referenceFrame_ = 0;
    double sceneT_ = 0;  // scene time of the last composited frame
    bool haveFrame_ = false;
    std::array<layers::EyeGaze, 2> lastGaze_{};
    std::string gazeNote_;
    double lastPresent_ = -1, frameMs_ = 0;
    int composited_ = 0;
    uint32_t shots_ = 0;
    uint32_t reportedRecreations_ = 0;
    int iteration_ = 0;
    bool resizeDone_ = false;
};

Status Session::open() {
    if (!glfw_.ok)
        return Error{kExitFailure, "cannot open a display: " + g_glfwError +
                                       ". The preview needs an X11 display (DISPLAY); without one, run it under "
                                       "xvfb-run, e.g. xvfb-run -a -s \"-screen 0 1280x1024x24\" wrsfov-preview"};
    if (glfwVulkanSupported() != GLFW_TRUE)
        return Error{kExitFailure, "GLFW finds no Vulkan loader with surface support: " + g_glfwError +
                                       " (Debian: libvulkan1 mesa-vulkan-drivers)"};
    uint32_t n = 0;
    const char** exts = glfwGetRequiredInstanceExtensions(&n);
    if (!exts) return Error{kExitFailure, "the Vulkan loader lacks the window-surface extensions: " + g_glfwError};

    layout_ = makeLayout(view_, o_.width, o_.height);
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_.reset(glfwCreateWindow(int(layout_.width), int(layout_.height), "wrsfov-preview", nullptr, nullptr));
    if (!window_) return Error{kExitFailure, "cannot create a window: " + g_glfwError};
    glfwSetWindowUserPointer(window_.get(), this);
    glfwSetKeyCallback(window_.get(), &Session::onKey);
    glfwSetFramebufferSizeCallback(window_.get(), &Session::onFramebufferSize);
    fitWindow();

    vk::ContextOptions co = vk::ContextOptions::fromEnvironment();
    co.instanceExtensions.assign(exts, exts + n);
    co.deviceExtensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    co.queueFilter = [](VkInstance instance, VkPhysicalDevice device, uint32_t family) {
        return glfwGetPhysicalDevicePresentationSupport(instance, device, family) == GLFW_TRUE;
    };
    auto ctx = vk::Context::create(co);
    if (!ctx) return Error{kExitFailure, ctx.error().message};
    ctx_ = std::move(*ctx);

    auto comp = Compositor::create(*ctx_, compositorConfig(method_, mode_, fovea_, o_.seed, o_.skipTiles));
    if (!comp) return comp.error();
    main_ = std::move(*comp);
    if (Status s = makeScene(); !s) return s;
    if (Status s = makeGaze(gazeSpec_); !s) return s;
    auto p = Presenter::create(*ctx_, window_.get());
    if (!p) return p.error();
    presenter_ = std::move(*p);
    if (o_.cursor) glfwSetCursorPos(window_.get(), (*o_.cursor)[0], (*o_.cursor)[1]);
    std::printf("wrsfov-preview: %s, %ux%u per eye, swapchain %ux%u %s\n", ctx_->deviceName().c_str(), o_.width,
                o_.height, presenter_->extent().width, presenter_->extent().height,
                formatName(presenter_->surfaceFormat()));
    return {};
}

// Scales the window to the preview image, shrunk to fit the screen.
void Session::fitWindow() {
    double w = layout_.width, h = layout_.height;
    if (GLFWmonitor* m = glfwGetPrimaryMonitor())
        if (const GLFWvidmode* mode = glfwGetVideoMode(m)) {
            const double s = std::min({1.0, 0.9 * mode->width / w, 0.9 * mode->height / h});
            w *= s;
            h *= s;
        }
    glfwSetWindowSize(window_.get(), std::max(1, int(w)), std::max(1, int(h)));
}

Status Session::makeScene() {
    SceneFeedOptions fo;
    fo.scene = scene_;
    fo.path = path_;
    fo.photoImage = photoImage_;
    fo.photoMotion = photoMotion_;
    fo.photoSpeed = photoSpeed_;
    fo.width = o_.width;
    fo.height = o_.height;
    fo.seed = o_.seed;
    auto f = SceneFeed::create(*ctx_, fo);
    if (!f) return f.error();
    feed_ = std::move(*f);  // the old scene's swapchains go with the old feed
    jod_.reset();           // the new scene's views may have another field of view
    ++settingsGen_;
    main_->resetHistory();
    if (reference_) reference_->resetHistory();
    referenceFrame_ = 0;
    return {};
}

Status Session::makeGaze(const GazeSpec& spec) {
    GazeSetting gs;
    gs.scene = scene_;
    gs.text = feed_->textLayout();
    gs.seed = o_.seed;
    auto g = createGazeInput(spec, gs);
    if (!g) return g.error();
    gaze_ = std::move(*g);
    gazeSpec_ = spec;
    ++settingsGen_;
    return {};
}

Status Session::applyConfig() {
    if (Status s = main_->setConfig(compositorConfig(method_, mode_, fovea_, o_.seed, o_.skipTiles)); !s) return s;
    ++settingsGen_;
    dirty_ = true;
    return {};
}

std::optional<std::array<float, 2>> Session::cursorInEye() const {
    double cx = 0, cy = 0;
    glfwGetCursorPos(window_.get(), &cx, &cy);
    int ww = 0, wh = 0, fw = 0, fh = 0;
    glfwGetWindowSize(window_.get(), &ww, &wh);
    glfwGetFramebufferSize(window_.get(), &fw, &fh);
    if (ww <= 0 || wh <= 0) return std::nullopt;
    // Window coordinates -> framebuffer pixels (they differ on HiDPI screens).
    const double fx = cx * fw / ww, fy = cy * fh / wh;
    Placement p = presenter_ && presenter_->placement().width ? presenter_->placement()
                                                              : placeInWindow(layout_.width, layout_.height, fw, fh);
    auto hit = hitTest(layout_, p, fx, fy);
    if (!hit) return std::nullopt;
    return std::array<float, 2>{hit->x, hit->y};
}

// Makes and composites one frame: the next scene time (advance) or the current one again (a
// setting changed while paused). Every compositor sees the same frame index, time and gaze.
Status Session::composite(bool advance) {
    const double t = haveFrame_ && advance ? sceneT_ + kFrameStep_s : sceneT_;
    const double prevT = haveFrame_ ? sceneT_ : t;
    GazeQuery q;
    q.t = t;
    q.fov[0] = feed_->fov(0);
    q.fov[1] = feed_->fov(1);
    q.width = o_.width;
    q.height = o_.height;
    if (gazeSpec_.kind == GazeKind::Mouse) q.cursor = cursorInEye();
    GazeReading g = gaze_->sample(q);

    std::vector<Compositor*> targets{main_.get()};
    if (needsReference(view_) && method_ != PreviewMethod::Reference) {
        if (!reference_) {
            auto r = Compositor::create(
                *ctx_, compositorConfig(PreviewMethod::Reference, mode_, fovea_, o_.seed, o_.skipTiles));
            if (!r) return r.error();
            reference_ = std::move(*r);
        }
        targets.push_back(reference_.get());
    }
    ++frameIndex_;
    if (Status s = feed_->submit(targets, frameIndex_, t, prevT, g.eye); !s) return s;
    if (targets.size() > 1) {
        referenceFrame_ = frameIndex_;
        if (Status s = scoreJod(t); !s) return s;
    }
    sceneT_ = t;
    haveFrame_ = true;
    lastGaze_ = g.eye;
    gazeNote_ = g.note;
    ++composited_;
    return {};
}

// Scores the frame just composited, each eye's output against the reference's, with the gaze the
// compositor used. The frames of one setting at consecutive 90 Hz times are one video; anything
// else (a setting changed, frames without the reference, a still frame composited again) starts a
// new one.
Status Session::scoreJod(double t) {
    const bool wantMap = view_ == View::Visible;
    const gpu::FrameParams& params = main_->lastParams();
    if (!jod_ || jod_->options().map != wantMap) {
        LiveJodOptions lo;
        lo.width = o_.width;
        lo.height = o_.height;
        for (int e = 0; e < 2; ++e) lo.fovTan[e] = params.eye[e].fov_tan;
        lo.fps = 1.0 / kFrameStep_s;
        lo.map = wantMap;
        auto made = LiveJod::create(lo);
        if (!made) return made.error();
        jod_ = std::move(*made);
    }
    const bool continues =
        jodGen_ == settingsGen_ && jodFrame_ + 1 == frameIndex_ && std::abs(t - (jodT_ + kFrameStep_s)) < 1e-6;
    if (jod_->frames() > 0 && !continues) jod_->reset();
    std::array<cv::Mat, 2> out, ref;
    std::array<glm::vec2, 2> gaze;
    for (int e = 0; e < 2; ++e) {
        auto o = main_->readOutput(uint32_t(e));
        if (!o) return o.error();
        auto r = reference_->readOutput(uint32_t(e));
        if (!r) return r.error();
        out[e] = eval::toMat(*o);
        ref[e] = eval::toMat(*r);
        gaze[e] = eval::gazePixelF(params.eye[e], o_.width, o_.height);
    }
    if (Status s = jod_->push(out, ref, gaze); !s) return s;
    jodFrame_ = frameIndex_;
    jodT_ = t;
    jodGen_ = settingsGen_;
    return {};
}

// The JOD readout: each eye's JOD over the last second of frames scored; empty where nothing is scored.
std::string Session::jodText() const {
    if (!needsReference(view_)) return {};
    if (method_ == PreviewMethod::Reference) return "JOD 10 (the reference itself)";
    if (!jod_ || jodFrame_ != frameIndex_) return {};
    const auto j = jod_->jod();
    if (!j) return {};
    return "JOD L " + fmt("%.2f", (*j)[0]) + " R " + fmt("%.2f", (*j)[1]) + " (FovVideoVDP, last " +
           std::to_string(jod_->pooled()) + (jod_->pooled() == 1 ? " frame)" : " frames)");
}

void Session::handleKey(int key) {
    Status s;
    std::string what;  // what changed, for the console
    switch (key) {
        case GLFW_KEY_ESCAPE:
        case GLFW_KEY_Q:
            glfwSetWindowShouldClose(window_.get(), GLFW_TRUE);
            what = "quit";
            break;
        case GLFW_KEY_1:
        case GLFW_KEY_2:
        case GLFW_KEY_3:
        case GLFW_KEY_4:
        case GLFW_KEY_5:
        case GLFW_KEY_M:
            method_ = key == GLFW_KEY_M ? nextMethod(method_) : PreviewMethod(key - GLFW_KEY_1);
            s = applyConfig();
            what = "method " + std::string(toString(method_));
            break;
        case GLFW_KEY_F:
            fovea_ = nextFovea(fovea_);
            s = applyConfig();
            what = "fovea " + fmt("%g", fovea_) + " deg";
            break;
        case GLFW_KEY_G:
            mode_ = mode_ == FoveationMode::Mip ? FoveationMode::Gauss : FoveationMode::Mip;
            s = applyConfig();
            what = "foveation " + std::string(toString(mode_));
            break;
        case GLFW_KEY_N: {
            const SceneKind before = scene_;
            scene_ = nextScene(scene_);
            s = makeScene();
            if (s && gazeSpec_.kind == GazeKind::Generator) s = makeGaze(gazeSpec_);  // it reads text or views a room
            if (!s) scene_ = before;
            dirty_ = true;
            what = "scene " + std::string(toString(scene_));
            break;
        }
        case GLFW_KEY_P: {
            const scenes::CameraPath before = path_;
            path_ = nextPath(path_);
            if (scene_ != SceneKind::Text && scene_ != SceneKind::Photo) s = makeScene();
            if (!s) path_ = before;
            dirty_ = true;
            what = "camera path " + std::string(toString(path_)) +
                   (scene_ == SceneKind::Text    ? " (text: none)"
                    : scene_ == SceneKind::Photo ? " (photo: --photo-motion)"
                                                 : "");
            break;
        }
        case GLFW_KEY_V:
            view_ = nextView(view_);
            layout_ = makeLayout(view_, o_.width, o_.height);
            fitWindow();  // the strip may still grow at the next image: the window then letterboxes it
            if (needsReference(view_)) dirty_ = true;  // the reference needs this frame too
            what = "view " + std::string(toString(view_));
            break;
        case GLFW_KEY_I: {
            // mouse -> generator -> the source from the command line (if another one) -> mouse
            std::vector<GazeSpec> cycle{GazeSpec{GazeKind::Mouse}, GazeSpec{GazeKind::Generator}};
            if (o_.gaze.kind != GazeKind::Mouse && o_.gaze.kind != GazeKind::Generator) cycle.push_back(o_.gaze);
            size_t i = 0;
            while (i < cycle.size() && toString(cycle[i]) != toString(gazeSpec_)) ++i;
            s = makeGaze(cycle[(i + 1) % cycle.size()]);
            dirty_ = true;
            what = "gaze " + toString(gazeSpec_);
            break;
        }
        case GLFW_KEY_O:
            overlay_ = !overlay_;
            what = std::string("overlay ") + (overlay_ ? "on" : "off");
            break;
        case GLFW_KEY_SPACE:
            paused_ = !paused_;
            what = paused_ ? "paused" : "resumed";
            break;
        case GLFW_KEY_RIGHT:
        case GLFW_KEY_PERIOD:
            if (!paused_) return;
            step_ = true;
            what = "step";
            break;
        case GLFW_KEY_S: {
            char name[64];
            std::snprintf(name, sizeof(name), "wrsfov-preview-%06llu-%u.png", (unsigned long long)frameIndex_,
                          shots_++);
            s = saveScreenshot(name);
            what = std::string("screenshot ") + name;
            break;
        }
        case GLFW_KEY_H:
            std::printf("%s", keyHelp().c_str());
            break;
        default:
            return;
    }
    if (!s)
        std::fprintf(stderr, "wrsfov-preview: %s\n", s.message().c_str());
    else if (!what.empty())
        std::printf("[#%llu] %s\n", (unsigned long long)frameIndex_, what.c_str());
    std::fflush(stdout);
}

std::vector<std::string> Session::statsItems() const {
    std::vector<std::string> items;
    const FrameStats& st = main_->stats();
    std::string method(toString(method_));
    std::transform(method.begin(), method.end(), method.begin(), ::toupper);
    items.push_back(method);
    items.push_back("fovea " + fmt("%.1f", fovea_) + " deg");
    items.push_back(std::string(toString(mode_)));
    std::string scene(toString(scene_));
    if (scene_ == SceneKind::Photo)
        scene += " / " + std::string(scenes::toString(photoMotion_));
    else if (scene_ != SceneKind::Text)
        scene += " / " + std::string(toString(path_));
    items.push_back(scene);
    std::string view = "view " + std::string(toString(view_));
    if (view_ == View::Compare) view += " (top: output, bottom: reference)";
    if (view_ == View::Error) view += " (|output - reference| x4)";
    if (view_ == View::Visible) view += " (FovVideoVDP visible distortion, ramp 0 - 5 JOD)";
    items.push_back(view);
    std::string gz = "gaze " + toString(gazeSpec_) + ":";
    for (int e = 0; e < 2; ++e)
        gz += std::string(e ? " R " : " L ") + (st.gazeFallback[e] ? "invalid (centre, 20 deg)" : "valid");
    items.push_back(gz);
    if (!gazeNote_.empty()) items.push_back("(" + gazeNote_ + ")");
    if (std::string jod = jodText(); !jod.empty()) items.push_back(jod);
    if (st.gpu.valid) {
        // One dispatch per pass covers both eyes (z = eye): the per-eye share is half of it.
        items.push_back("GPU ms (both eyes | per eye):");
        auto pass = [&](const char* name, double ms) {
            items.push_back(std::string(name) + " " + fmt("%.3f", ms) + " | " + fmt("%.3f", ms / 2));
        };
        if (method_ != PreviewMethod::Reference) pass("pyramid", st.gpu.pyramid);
        if (method_ != PreviewMethod::Wrs) pass("foveate", st.gpu.foveate);
        if (method_ == PreviewMethod::WrsPaper) pass("wrs-paper", st.gpu.temporal);
        if (method_ == PreviewMethod::Wrs) pass("retain", st.gpu.temporal);
        if (method_ == PreviewMethod::FovTaa) pass("taa", st.gpu.temporal);
        pass("total", st.gpu.total);
    } else {
        items.push_back("GPU time: no timestamps on this queue");
    }
    // Sparse retention: where the gaze has been, the share of tiles that ran retention.
    if (st.sparse) items.push_back("retention in " + fmt("%.1f", 100.0 * st.retainShare()) + " % of tiles");
    items.push_back("frame " + fmt("%.1f", frameMs_) + " ms");
    items.push_back("#" + std::to_string(frameIndex_) + (paused_ ? "  PAUSED" : ""));
    items.push_back("H: keys");
    return items;
}

ComposeFrame Session::composeFrame(const cv::Mat& strip) const {
    ComposeFrame f;
    f.layout = &layout_;
    f.output = &main_->outputImage();
    const bool refCurrent = reference_ && referenceFrame_ == frameIndex_ && referenceFrame_ != 0;
    f.reference = method_ == PreviewMethod::Reference ? &main_->outputImage()
                  : refCurrent                        ? &reference_->outputImage()
                                                      : nullptr;
    f.eyes = eyeOverlays(*main_);
    if (view_ == View::Visible && jod_ && jodFrame_ == frameIndex_ && jod_->options().map)
        f.visible = {&jod_->map(0), &jod_->map(1)};
    f.circles = f.marker = overlay_;
    f.strip = &strip;
    return f;
}

Status Session::saveScreenshot(const std::string& path) {
    auto img = presenter_->lastImage();
    if (!img) return img.error();
    try {
        if (!cv::imwrite(path, *img)) return Error{kExitFailure, "cannot write screenshot '" + path + "'"};
    } catch (const cv::Exception& e) {
        return Error{kExitFailure, "cannot write screenshot '" + path + "': " + e.what()};
    }
    return {};
}

std::string Session::summary() const {
    const FrameStats& st = main_->stats();
    std::string s = "wrsfov-preview: " + std::to_string(composited_) + " frames (" + std::string(toString(scene_)) +
                    ", " + std::string(toString(method_)) + ", fovea " + fmt("%g", fovea_) + " deg, " +
                    std::string(toString(mode_)) + ", gaze " + toString(gazeSpec_) + ")";
    if (st.gpu.valid)
        s += "; GPU ms (both eyes) pyramid " + fmt("%.3f", st.gpu.pyramid) + " foveate " + fmt("%.3f", st.gpu.foveate) +
             " temporal " + fmt("%.3f", st.gpu.temporal) + " total " + fmt("%.3f", st.gpu.total);
    if (st.sparse) s += "; retention in " + fmt("%.1f", 100.0 * st.retainShare()) + " % of tiles";
    if (std::string jod = jodText(); !jod.empty()) s += "; " + jod;
    s += "; swapchain " + std::to_string(presenter_->extent().width) + "x" +
         std::to_string(presenter_->extent().height) + ", recreated " +
         std::to_string(presenter_->swapchainRecreations()) + " times";
    return s;
}

int Session::run() {
    if (Status s = open(); !s) {
        std::fprintf(stderr, "wrsfov-preview: %s\n", s.message().c_str());
        return kExitFailure;
    }
    if (o_.frames == 0) std::printf("%s", keyHelp().c_str());
    std::fflush(stdout);
    uint64_t presentedFrame = 0;
    while (!glfwWindowShouldClose(window_.get())) {
        if (paused_ && !step_ && !dirty_ && keys_.empty())
            glfwWaitEventsTimeout(1.0 / 30.0);  // nothing changes while paused: no need to spin
        else
            glfwPollEvents();
        for (const auto& [at, name] : o_.keys)
            if (at == iteration_) keys_.push_back(keyCode(name));
        ++iteration_;
        std::vector<int> keys;
        keys.swap(keys_);
        for (int k : keys) handleKey(k);
        if (glfwWindowShouldClose(window_.get())) break;
        int fw = 0, fh = 0;
        glfwGetFramebufferSize(window_.get(), &fw, &fh);
        if (fw == 0 || fh == 0) {  // minimised: nothing to present to; wait for the next event
            glfwWaitEvents();
            continue;
        }
        const bool budgetLeft = o_.frames == 0 || composited_ < o_.frames;
        if (budgetLeft && (!paused_ || step_ || dirty_ || !haveFrame_)) {
            if (Status s = composite(!paused_ || step_); !s) {
                std::fprintf(stderr, "wrsfov-preview: frame %llu: %s\n", (unsigned long long)frameIndex_ + 1,
                             s.message().c_str());
                return kExitFailure;
            }
            step_ = dirty_ = false;
        }
        const std::vector<std::string> items = statsItems();
        const uint32_t lines = stripLinesNeeded(layout_.width, items);
        // More stats than the strip holds: it grows (the window letterboxes the taller image).
        if (lines > layout_.stripLines) layout_ = makeLayout(view_, o_.width, o_.height, lines);
        const cv::Mat strip = drawStrip(layout_, items);
        auto r = presenter_->present(composeFrame(strip));
        if (!r) {
            std::fprintf(stderr, "wrsfov-preview: %s\n", r.error().message.c_str());
            return kExitFailure;
        }
        if (*r == PresentOutcome::Presented) {
            presentedFrame = frameIndex_;
            const double now = glfwGetTime();
            if (lastPresent_ >= 0) {
                const double ms = (now - lastPresent_) * 1000.0;
                frameMs_ = frameMs_ == 0 ? ms : 0.9 * frameMs_ + 0.1 * ms;
            }
            lastPresent_ = now;
            if (presenter_->swapchainRecreations() != reportedRecreations_) {
                reportedRecreations_ = presenter_->swapchainRecreations();
                std::printf("swapchain recreated: %ux%u (%s)\n", presenter_->extent().width,
                            presenter_->extent().height, presenter_->recreationReason());
            }
        }
        if (!resizeDone_ && o_.resizeFrame >= 0 && composited_ >= o_.resizeFrame && presentedFrame == frameIndex_) {
            glfwSetWindowSize(window_.get(), int(o_.resizeWidth), int(o_.resizeHeight));
            resizeDone_ = true;
        }
        // --frames: stop once the last frame has been presented.
        if (o_.frames > 0 && composited_ >= o_.frames && presentedFrame == frameIndex_) break;
    }
    std::printf("%s\n", summary().c_str());
    int status = kExitOk;
    if (!o_.screenshot.empty()) {
        if (Status s = saveScreenshot(o_.screenshot); !s) {
            std::fprintf(stderr, "wrsfov-preview: %s\n", s.message().c_str());
            status = kExitFailure;
        } else {
            std::printf("screenshot: %s\n", o_.screenshot.c_str());
        }
    }
    if (ctx_->validationEnabled()) {
        std::printf("validation: %u errors, %u warnings\n", ctx_->validationErrors(), ctx_->validationWarnings());
        if (ctx_->validationErrors() > 0 && status == kExitOk) status = kExitValidation;
    }
    std::fflush(stdout);
    return status;
}

}  // namespace

int runPreview(const PreviewOptions& options) {
    Session s(options);
    return s.run();
}

}  // namespace wrsfov::preview
