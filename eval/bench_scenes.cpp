// The study's scenes: the frames each scene submits, its synthetic gaze, the options a cell
// opens it with, and the geometry of a cell as the cost model replays it (cellGeometry).
#include "eval/bench.h"
#include "eval/bench_internal.h"
#include "eval/saving.h"
#include "eval/chart.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <span>
#include <sstream>

#include <filesystem>

#include <glm/gtc/matrix_transform.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "compositor/host_app.h"
#include "eval/metrics.h"
#include "eval/sequence.h"
#include "gaze/source.h"
#include "scenes/text.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {

std::string_view toString(SceneKind s) {
    switch (s) {
    case SceneKind::Text: return "text";
    case SceneKind::Atrium: return "atrium";
    case SceneKind::Dynamic: return "dynamic";
    case SceneKind::Sequence: return "sequence";
    case SceneKind::Photo: return "photo";
    case SceneKind::Thin: return "thin";
    }
    return "?";
}

std::optional<SceneKind> parseScene(std::string_view name) {
    for (SceneKind s : {SceneKind::Text, SceneKind::Atrium, SceneKind::Dynamic, SceneKind::Sequence, SceneKind::Photo,
                        SceneKind::Thin})
        if (toString(s) == name) return s;
    return std::nullopt;
}

namespace detail {

Error benchError(const std::string& m) { return Error{1, m}; }
double boundGain(double fovMse, double boundMse) {
    const double gain = fovMse - boundMse;
    return gain > 0.01 * fovMse ? gain : 0.0;
}
const CellResult* findCell(std::span<const CellResult> results, SceneKind scene, FoveationMode mode, float fovea,
                           Method m) {
    for (const CellResult& c : results)
        if (c.scene == scene && c.mode == mode && c.foveaDeg == fovea && c.method == m) return &c;
    return nullptr;
}
bool isCpuRenderer(const std::string& deviceName) {
    return deviceName.find("llvmpipe") != std::string::npos || deviceName.find("lavapipe") != std::string::npos;
}

}  // namespace detail

using namespace detail;

namespace {

class TextFrames final : public SceneFrames {
public:
    TextFrames(uint32_t w, uint32_t h, uint32_t seed, bool monitor) {
        scenes::TextOptions o;
        o.width = w;
        o.height = h;
        o.seed = seed;
        o.monitor = monitor;
        scene_ = std::make_unique<scenes::TextScene>(o);
    }
    Status frame(int, double, double, std::array<EyeSubmission, 2>& eyes) override {
        for (int e = 0; e < 2; ++e) {
            eyes[e].color = scene_->color(e);
            eyes[e].depth = scene_->depth(e);
            eyes[e].motion.reset();
            eyes[e].fov = fov(e);
        }
        return {};
    }
    HostStereoApp::Options appOptions() const override {
        HostStereoApp::Options a;
        a.width = scene_->options().width;
        a.height = scene_->options().height;
        a.depth = layers::Format::R32F;
        a.nearZ = scene_->options().nearZ;
        a.farZ = scene_->options().farZ;
        a.monoView = scene_->options().monitor;  // one view as both eyes: the compositor works once
        return a;
    }
    const scenes::TextLayout& layout() const { return scene_->options().layout; }
    layers::Fov fov(int eye) const { return scenes::textFov(scene_->options(), eye); }

private:
    std::unique_ptr<scenes::TextScene> scene_;
};

// What a scene with depth and motion submits (atrium, dynamic, photo): sRGB colour, D32F depth,
// RGBA16F motion.
HostStereoApp::Options depthMotionAppOptions(uint32_t width, uint32_t height, float nearZ, float farZ, bool reversedZ,
                                             bool monoView) {
    HostStereoApp::Options a;
    a.width = width;
    a.height = height;
    a.depth = layers::Format::D32F;
    a.motion = layers::Format::RGBA16F;
    a.nearZ = nearZ;
    a.farZ = farZ;
    a.reversedZ = reversedZ;
    a.monoView = monoView;
    return a;
}

}  // namespace

namespace detail {

HostStereoApp::Options atriumAppOptions(const scenes::AtriumOptions& o) {
    return depthMotionAppOptions(o.width, o.height, o.nearZ, o.farZ, o.reversedZ, o.monitor);
}

}  // namespace detail

namespace {


// The atrium is rendered with Vulkan into an application's swapchains, then read back so that
// every compositor of the cell gets the very same images.
class AtriumFrames final : public SceneFrames {
public:
    static Result<std::unique_ptr<AtriumFrames>> create(vk::Context& ctx, const scenes::AtriumOptions& o) {
        std::unique_ptr<AtriumFrames> f(new AtriumFrames());
        auto comp = Compositor::create(ctx);
        if (!comp) return comp.error();
        f->owner_ = std::move(*comp);
        f->options_ = o;
        auto app = HostStereoApp::create(*f->owner_, f->appOptions());
        if (!app) return app.error();
        f->app_ = std::move(*app);
        auto r = scenes::AtriumRenderer::create(ctx, o);
        if (!r) return r.error();
        f->renderer_ = std::move(*r);
        return f;
    }
    Status frame(int, double t, double prevT, std::array<EyeSubmission, 2>& eyes) override {
        HostStereoApp& app = *app_;
        return app.drawInPlace([&](const HostStereoApp::Images& im) {
            Status s = renderer_->render(t, prevT, app.color(), im.color, *app.depth(), im.depth, *app.motion(), im.motion);
            for (uint32_t e = 0; e < 2 && s; ++e) {
                s = app.readBack(im, e, eyes[e].color, &eyes[e].depth.emplace(), &eyes[e].motion.emplace());
                eyes[e].fov = scenes::atriumFov(options_, int(e));
            }
            return s;
        });
    }
    HostStereoApp::Options appOptions() const override { return atriumAppOptions(options_); }

private:
    AtriumFrames() = default;
    scenes::AtriumOptions options_;
    std::unique_ptr<Compositor> owner_;
    std::unique_ptr<HostStereoApp> app_;
    std::unique_ptr<scenes::AtriumRenderer> renderer_;
};

// Natural texture on a plane (scenes/photo.h): sRGB colour, D32F depth, RGBA16F motion, rendered on
// the CPU; in monitor mode one view, copied to both eyes.
class PhotoFrames final : public SceneFrames {
public:
    explicit PhotoFrames(std::unique_ptr<scenes::PhotoScene> scene) : scene_(std::move(scene)) {}
    Status frame(int index, double, double, std::array<EyeSubmission, 2>& eyes) override {
        const scenes::PhotoOptions& o = scene_->options();
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = scenes::photoFov(o, e);
            if (o.monitor && e == 1) {
                eyes[1].color = eyes[0].color;
                eyes[1].depth = eyes[0].depth;
                eyes[1].motion = eyes[0].motion;
                break;
            }
            HostImage c, d, m;
            if (Status s = scene_->render(uint32_t(index), e, c, d, m); !s) return s;
            eyes[e].color = std::move(c);
            eyes[e].depth = std::move(d);
            eyes[e].motion = std::move(m);
        }
        return {};
    }
    HostStereoApp::Options appOptions() const override {
        const scenes::PhotoOptions& o = scene_->options();
        return depthMotionAppOptions(o.width, o.height, o.nearZ, o.farZ, false, o.monitor);
    }

private:
    std::unique_ptr<scenes::PhotoScene> scene_;
};


// External frames from a sequence directory, read from disk frame by frame.
class SequenceFrames final : public SceneFrames {
public:
    explicit SequenceFrames(std::unique_ptr<SequenceReader> reader) : reader_(std::move(reader)) {}
    Status frame(int index, double, double, std::array<EyeSubmission, 2>& eyes) override {
        auto f = reader_->frame(uint32_t(index));
        if (!f) return f.error();
        eyes = std::move(f->eyes);
        return {};
    }
    HostStereoApp::Options appOptions() const override { return reader_->appOptions(); }
    bool providesGaze() const override { return reader_->hasGaze(); }
    double fps() const override { return reader_->info().fps; }

private:
    std::unique_ptr<SequenceReader> reader_;
};


}  // namespace

namespace detail {

gaze::GeneratorConfig sweepGaze(const BenchOptions& o, const scenes::TextLayout* text) {
    gaze::GeneratorConfig gc;
    gc.seed = o.seed;
    gc.mode = gaze::Mode::Scene;
    if (text) {
        gc.mode = gaze::Mode::Reading;
        gc.reading.char_deg = text->charDeg;
        gc.reading.line_spacing_deg = text->lineSpacingDeg;
        gc.reading.line_chars = text->lineChars;
        gc.reading.lines_per_page = text->lines;
    }
    return gc;
}

}  // namespace detail

namespace {

// The look-around path's gaze (detail::sweepGazeSource): each eye's direction of the local free viewing
// turned by scenes::lookAroundGaze, azimuth about the head's +Y (left-positive), elevation about +X.
class LookAroundGaze final : public gaze::GazeSource {
public:
    explicit LookAroundGaze(std::unique_ptr<gaze::GazeSource> local) : local_(std::move(local)) {}
    gaze::GazeSample sample(double t) override {
        gaze::GazeSample s = local_->sample(t);
        const scenes::GazeInHead g = scenes::lookAroundGaze(t);
        constexpr float kRad = 3.14159265358979f / 180.0f;
        const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), g.azimuthDeg * kRad, glm::vec3(0, 1, 0)) *
                             glm::rotate(glm::mat4(1.0f), g.elevationDeg * kRad, glm::vec3(1, 0, 0)));
        for (gaze::EyeGaze& e : s.eye)
            if (e.valid) e.dir = glm::normalize(turn * e.dir);
        return s;
    }

private:
    std::unique_ptr<gaze::GazeSource> local_;
};

}  // namespace

namespace detail {

Result<std::unique_ptr<gaze::GazeSource>> sweepGazeSource(const BenchOptions& o, SceneKind scene,
                                                          gaze::GeneratorConfig gc) {
    const bool lookAround = o.path == scenes::CameraPath::LookAround &&
                            isAtriumScene(scene);
    if (lookAround) {
        // Looking around within ±6° of where the path's gaze shift landed, saccades up to 10°.
        gc.scene.half_width_deg = 6.0;
        gc.scene.half_height_deg = 6.0;
        gc.scene.saccade_max_deg = 10.0;
    }
    auto g = gaze::SyntheticSource::create(gc);
    if (!g) return benchError("bench: gaze generator: " + g.error().message);
    if (!lookAround) return std::unique_ptr<gaze::GazeSource>(std::move(*g));
    return std::unique_ptr<gaze::GazeSource>(std::make_unique<LookAroundGaze>(std::move(*g)));
}

}  // namespace detail

// The photo scene's options for a cell of the sweep.
scenes::PhotoOptions photoOptions(const BenchOptions& o) {
    scenes::PhotoOptions po;
    po.width = o.width;
    po.height = o.height;
    po.monitor = o.monitor;
    po.fovDeg = o.hmdFovDeg;
    po.image = o.photoImage;
    po.motion = o.photoMotion;
    po.speed = o.photoSpeed;
    po.frames = uint32_t(o.frames);
    po.seed = o.seed;
    return po;
}

scenes::AtriumOptions atriumOptions(const BenchOptions& o, SceneKind scene) {
    scenes::AtriumOptions ao;
    ao.width = o.width;
    ao.height = o.height;
    ao.dynamic = scene == SceneKind::Dynamic;
    ao.thin = scene == SceneKind::Thin;
    ao.path = o.path;
    ao.monitor = o.monitor;
    ao.fovDeg = o.hmdFovDeg;
    ao.materialSamples = o.materialSamples;
    return ao;
}

namespace detail {

Result<SceneSetup> openScene(vk::Context& ctx, SceneKind scene, const BenchOptions& o) {
    SceneSetup setup;
    gaze::GeneratorConfig gc = sweepGaze(o, nullptr);
    if (scene == SceneKind::Text) {
        auto tf = std::make_unique<TextFrames>(o.width, o.height, o.seed, o.monitor);
        gc = sweepGaze(o, &tf->layout());
        setup.frames = std::move(tf);
    } else if (scene == SceneKind::Sequence) {
        if (o.sequenceDir.empty()) return benchError("bench: scene 'sequence' needs a sequence directory");
        auto r = SequenceReader::open(o.sequenceDir);
        if (!r) return r.error();
        const SequenceInfo& si = (*r)->info();
        if (si.width != o.width || si.height != o.height)
            return benchError("bench: sequence " + o.sequenceDir + " is " + std::to_string(si.width) + "x" +
                              std::to_string(si.height) + " per eye, the sweep " + std::to_string(o.width) + "x" +
                              std::to_string(o.height));
        if (uint32_t(o.frames) > si.frameCount)
            return benchError("bench: sequence " + o.sequenceDir + " has " + std::to_string(si.frameCount) +
                              " frames, fewer than the " + std::to_string(o.frames) + " asked for");
        setup.frames = std::make_unique<SequenceFrames>(std::move(*r));
    } else if (scene == SceneKind::Photo) {
        auto ps = scenes::PhotoScene::create(photoOptions(o));
        if (!ps) return benchError("bench: " + ps.error().message);
        setup.frames = std::make_unique<PhotoFrames>(std::move(*ps));
    } else {
        auto af = AtriumFrames::create(ctx, atriumOptions(o, scene));
        if (!af) return af.error();
        setup.frames = std::move(*af);
    }
    gc.seconds = o.frames / setup.frames->fps() + 2.0;
    auto gazeSource = sweepGazeSource(o, scene, gc);
    if (!gazeSource) return gazeSource.error();
    setup.gaze = std::move(*gazeSource);
    return setup;
}

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

double mseFromPsnr(double p) { return std::isinf(p) ? 0.0 : std::pow(10.0, -p / 10.0); }
double psnrFromMse(double m) { return m <= 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / m); }

double shadingFraction(FoveationMode mode, const cv::Mat& ecc, float rf, float rm) {
    double sum = 0;
    for (int y = 0; y < ecc.rows; ++y)
        for (int x = 0; x < ecc.cols; ++x)
            sum += gpu::wrs_level_quality(gpu::wrs_foveation_levels(uint32_t(mode), ecc.at<float>(y, x), rf, rm));
    return sum / double(ecc.total());
}

}  // namespace detail

namespace {

// A swapchain that only describes its images: what makeFrameParams reads of a view (its format).
class DescribedSwapchain final : public layers::Swapchain {
public:
    explicit DescribedSwapchain(const layers::SwapchainCreateInfo& info) : Swapchain(info) {}
    Status write(uint32_t, uint32_t, std::span<const std::byte>) override { return Error{1, "no images"}; }
    VkImage image(uint32_t) const override { return VK_NULL_HANDLE; }
};

}  // namespace

Result<CellGeometry> cellGeometry(const BenchOptions& options, SceneKind scene, FoveationMode mode, float fovea,
                                  uint32_t width, uint32_t height) {
    if (scene == SceneKind::Sequence)
        return benchError("bench: the cost model replays the gaze of a built-in scene (text, atrium, dynamic), not of "
                          "a sequence directory");
    if (width < 32 || height < 32) return benchError("bench: images must be at least 32x32 per eye");
    BenchOptions o = options;
    o.width = width;
    o.height = height;
    HostStereoApp::Options app;
    layers::Fov fov[2];
    gaze::GeneratorConfig gc;
    if (scene == SceneKind::Text) {
        TextFrames text(width, height, o.seed, o.monitor);
        app = text.appOptions();
        fov[0] = text.fov(0), fov[1] = text.fov(1);
        gc = sweepGaze(o, &text.layout());
    } else if (scene == SceneKind::Photo) {
        const scenes::PhotoOptions po = photoOptions(o);
        app = depthMotionAppOptions(width, height, po.nearZ, po.farZ, false, po.monitor);
        fov[0] = scenes::photoFov(po, 0), fov[1] = scenes::photoFov(po, 1);
        gc = sweepGaze(o, nullptr);
    } else {
        const scenes::AtriumOptions ao = atriumOptions(o, scene);
        app = atriumAppOptions(ao);
        fov[0] = scenes::atriumFov(ao, 0), fov[1] = scenes::atriumFov(ao, 1);
        gc = sweepGaze(o, nullptr);
    }
    gc.seconds = o.frames / kFps + 2.0;
    auto gazeSource = detail::sweepGazeSource(o, scene, gc);
    if (!gazeSource) return gazeSource.error();

    auto texel = [](std::optional<layers::Format> f) { return f ? uint32_t(layers::bytesPerTexel(*f)) : 0u; };
    CellGeometry g;
    g.inputs = {width, height, texel(app.color), texel(app.depth), texel(app.motion)};
    // The frame ends the sweep submits (HostStereoApp::frameEnd), through the compositor's own
    // parameters (makeFrameParams: gaze fallback, fovea radius) and its classification (wrs_tile_class).
    layers::SwapchainCreateInfo sci;
    sci.format = app.color;
    sci.width = width;
    sci.height = height;
    DescribedSwapchain colour(sci);
    layers::FrameEndInfo frame;
    frame.layers.resize(1);
    frame.layers[0].views.resize(2);
    CompositorConfig cc;
    cc.foveation = mode;
    cc.foveaDeg = fovea;
    const glm::uvec2 size(width, height), tiles((width + gpu::WRS_TILE - 1) / gpu::WRS_TILE,
                                                (height + gpu::WRS_TILE - 1) / gpu::WRS_TILE);
    std::array<double, gpu::WRS_TILE_CLASSES> count{};
    for (int f = o.warmup; f < o.frames; ++f) {
        const gaze::GazeSample s = (*gazeSource)->sample(f / kFps);
        for (int e = 0; e < 2; ++e) {
            const int src = app.monoView ? 0 : e;
            layers::ProjectionView& v = frame.layers[0].views[e];
            v.fov = fov[src];
            v.color = {&colour, {0, 0, width, height}, uint32_t(src)};
            frame.gaze[e] = {s.eye[src].dir, s.eye[src].valid, s.eye[src].confidence};
        }
        bool fallback[2];
        const gpu::FrameParams p = makeFrameParams(cc, frame, width, height, fallback);
        for (int e = 0; e < 2; ++e) {
            const gpu::EyeParams& ep = p.eye[e];
            for (uint32_t ty = 0; ty < tiles.y; ++ty)
                for (uint32_t tx = 0; tx < tiles.x; ++tx)
                    count[gpu::wrs_tile_class(uint32_t(mode), glm::uvec2(tx, ty), size, ep.fov_tan, ep.tile,
                                              glm::vec3(ep.gaze), ep.gaze.w, p.tuning.x)] += 1;
        }
    }
    double all = 0;
    for (double c : count) all += c;
    for (std::size_t k = 0; k < count.size(); ++k) g.tileShare[k] = all > 0 ? count[k] / all : 0.0;
    return g;
}

Result<CellGeometry> quadCellGeometry(const BenchOptions& options, SceneKind scene, uint32_t width, uint32_t height,
                                      float wideScale, float insetDeg, bool allTilesAny) {
    if (!isAtriumScene(scene))
        return benchError("bench: the cost model's quad views are the atrium's (HMD stereo), not scene " +
                          std::string(toString(scene)));
    if (width < 32 || height < 32) return benchError("bench: images must be at least 32x32 per eye");
    if (!(wideScale > 0.0f && wideScale <= 1.0f) || !(insetDeg > 0.0f && insetDeg < 170.0f))
        return benchError("bench: quad views need a wide density in (0, 1] and an inset in (0, 170) degrees");
    BenchOptions o = options;
    o.width = width;
    o.height = height;
    const scenes::AtriumOptions ao = atriumOptions(o, scene);
    const HostStereoApp::Options app = atriumAppOptions(ao);
    const layers::Fov fov = scenes::atriumFov(ao, 0);
    // The study's views (eval/saving.cpp).
    const auto [wideW, wideH, insetW, insetH] = quadViewSizes(width, height, fov, wideScale, insetDeg);
    auto described = [](std::optional<layers::Format> f, uint32_t w, uint32_t h) {
        layers::SwapchainCreateInfo sci;
        sci.format = *f;
        sci.width = w;
        sci.height = h;
        return std::make_unique<DescribedSwapchain>(sci);
    };
    std::vector<std::unique_ptr<DescribedSwapchain>> images;
    auto sub = [&](std::optional<layers::Format> f, uint32_t w, uint32_t h) {
        images.push_back(described(f, w, h));
        return layers::SubImage{images.back().get(), {0, 0, w, h}, 0};
    };
    layers::ProjectionLayer layer;
    layer.views.resize(2);
    layer.outputWidth = width;
    layer.outputHeight = height;
    layers::ProjectionView& v = layer.views[0];
    v.fov = fov;
    v.color = sub(app.color, wideW, wideH);
    layers::InsetView inset;
    inset.color = sub(app.color, insetW, insetH);
    // The inset at the view's centre, at the display's density (as the study places it without gaze).
    {
        const double l = std::tan(fov.angleLeft), r = std::tan(fov.angleRight), u = std::tan(fov.angleUp),
                     d = std::tan(fov.angleDown);
        const double hx = 0.5 * insetW * (r - l) / width, hy = 0.5 * insetH * (u - d) / height;
        const double cx = 0.5 * (l + r), cy = 0.5 * (u + d);
        inset.fov = {float(std::atan(cx - hx)), float(std::atan(cx + hx)), float(std::atan(cy + hy)),
                     float(std::atan(cy - hy))};
    }
    if (app.depth) {
        v.depth = layers::DepthInfo{};
        v.depth->subImage = sub(app.depth, wideW, wideH);
        inset.depth = layers::DepthInfo{};
        inset.depth->subImage = sub(app.depth, insetW, insetH);
    }
    if (app.motion) {
        v.motion = layers::MotionInfo{};
        v.motion->subImage = sub(app.motion, wideW, wideH);
        inset.motion = layers::MotionInfo{};
        inset.motion->subImage = sub(app.motion, insetW, insetH);
    }
    v.inset = inset;
    layer.views[1] = v;
    CellGeometry g;
    g.inputs = trafficInputs(layer);
    // The tile classes of a frame submitted foveated (wrs_submitted_tile_class): far where every pixel
    // was rendered at the wide views' quality, any elsewhere; the inset at the view's centre. A frame
    // that merges every phase of jittered views has no floor rule: every tile is of class any.
    const uint32_t tx = (width + gpu::WRS_TILE - 1) / gpu::WRS_TILE, ty = (height + gpu::WRS_TILE - 1) / gpu::WRS_TILE;
    const uint32_t x0 = (width - insetW) / 2, y0 = (height - insetH) / 2;
    const uint32_t touchedX = (x0 + insetW - 1) / gpu::WRS_TILE - x0 / gpu::WRS_TILE + 1,
                   touchedY = (y0 + insetH - 1) / gpu::WRS_TILE - y0 / gpu::WRS_TILE + 1;
    const double any = allTilesAny ? 1.0 : double(touchedX) * touchedY / (double(tx) * ty);
    g.tileShare[gpu::WRS_TILE_ANY] = any;
    g.tileShare[gpu::WRS_TILE_FAR] = 1.0 - any;
    return g;
}

}  // namespace wrsfov::eval
