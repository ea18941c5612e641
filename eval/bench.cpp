#include "eval/bench.h"
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
    }
    return "?";
}

std::optional<SceneKind> parseScene(std::string_view name) {
    for (SceneKind s : {SceneKind::Text, SceneKind::Atrium, SceneKind::Dynamic, SceneKind::Sequence, SceneKind::Photo})
        if (toString(s) == name) return s;
    return std::nullopt;
}

namespace {

constexpr double kFps = 90.0;
Error benchError(const std::string& m) { return Error{1, m}; }

// The part of fov's MSE a bound (oracle, oracle-q) removes, or 0 where it removes less than 1 % of it
// (a band where every candidate is equally blurred: there a ratio against it is noise, e.g. 388 for a
// 0.2 % gain). η and η_q are n/a against no gain.
double boundGain(double fovMse, double boundMse) {
    const double gain = fovMse - boundMse;
    return gain > 0.01 * fovMse ? gain : 0.0;
}

// The result of method m in the cell (scene, mode, fovea) among `results`, or nullptr.
const CellResult* findCell(std::span<const CellResult> results, SceneKind scene, FoveationMode mode, float fovea,
                           Method m) {
    for (const CellResult& c : results)
        if (c.scene == scene && c.mode == mode && c.foveaDeg == fovea && c.method == m) return &c;
    return nullptr;
}

// Whether a device name is Mesa's CPU renderer (the report says its times are a CPU's).
bool isCpuRenderer(const std::string& deviceName) {
    return deviceName.find("llvmpipe") != std::string::npos || deviceName.find("lavapipe") != std::string::npos;
}

// Frames of one scene as the application submits them (CPU images, both eyes).
class SceneFrames {
public:
    virtual ~SceneFrames() = default;
    virtual Status frame(int index, double t, double prevT, std::array<EyeSubmission, 2>& eyes) = 0;
    virtual HostStereoApp::Options appOptions() const = 0;
    /// Whether frame() fills in the gaze (a sequence with gaze.csv); else the synthetic gaze is used.
    virtual bool providesGaze() const { return false; }
    virtual double fps() const { return kFps; }
};

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
HostStereoApp::Options atriumAppOptions(const scenes::AtriumOptions& o) {
    return depthMotionAppOptions(o.width, o.height, o.nearZ, o.farZ, o.reversedZ, o.monitor);
}

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

// A scene's frames and the synthetic gaze that goes with it (reading for text, free viewing else).
struct SceneSetup {
    std::unique_ptr<SceneFrames> frames;
    std::unique_ptr<gaze::SyntheticSource> gaze;
};

// The sweep's synthetic gaze: reading over the text scene's layout, free viewing elsewhere.
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

}  // namespace

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
    ao.path = o.path;
    ao.monitor = o.monitor;
    ao.fovDeg = o.hmdFovDeg;
    ao.materialSamples = o.materialSamples;
    return ao;
}

namespace {

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
    auto gazeSource = gaze::SyntheticSource::create(gc);
    if (!gazeSource) return benchError("bench: gaze generator: " + gazeSource.error().message);
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

// Fraction of full-rate shading: each pixel costs the quality of its blended pyramid levels
// (wrs_level_quality: 1/4^level, blended).
double shadingFraction(FoveationMode mode, const cv::Mat& ecc, float rf, float rm) {
    double sum = 0;
    for (int y = 0; y < ecc.rows; ++y)
        for (int x = 0; x < ecc.cols; ++x)
            sum += gpu::wrs_level_quality(gpu::wrs_foveation_levels(uint32_t(mode), ecc.at<float>(y, x), rf, rm));
    return sum / double(ecc.total());
}

struct Accum {
    double mse = 0, nearMse = 0, eccMse = 0, ssim = 0, flip = 0, shading = 0;
    double staleSe = 0, staleFovSe = 0, stalePx = 0, stalePxTotal = 0;
    int n = 0, heavy = 0;
    std::vector<double> pyramid, foveate, temporal, total, copy, copyFloor;
    bool mono = false;  ///< the passes ran once for both views (FrameStats::monoViews)
    double retainShare = 0, motionShare = 0;  ///< sums over counted frames (FrameStats::retainShare, motionShare)
    int shareFrames = 0;
    TemporalInstability instab[2];
    std::array<double, kEccBands.size() - 1> bandSe{}, bandPx{};  ///< squared error and pixels per band
    double jodNearMse = 0;  ///< near-gaze MSE summed over the JOD frames' eye-frames
    int jodN = 0;
};

// Adds each pixel's squared error (sRGB, mean over channels, as psnr) to its eccentricity band.
void addBandErrors(const cv::Mat& r, const cv::Mat& t, const cv::Mat& ecc, Accum& a) {
    for (int y = 0; y < r.rows; ++y) {
        const float* pr = r.ptr<float>(y);
        const float* pt = t.ptr<float>(y);
        const float* pe = ecc.ptr<float>(y);
        for (int x = 0; x < r.cols; ++x) {
            std::size_t b = 0;
            while (b + 2 < kEccBands.size() && double(pe[x]) >= kEccBands[b + 1]) ++b;
            double se = 0.0;
            for (int c = 0; c < 3; ++c) {
                const double d = double(pr[3 * x + c]) - double(pt[3 * x + c]);
                se += d * d;
            }
            a.bandSe[b] += se / 3.0;
            a.bandPx[b] += 1.0;
        }
    }
}

cv::Mat toBgr8(const HostImage& img) {
    cv::Mat rgba(int(img.height), int(img.width), CV_8UC4, const_cast<std::byte*>(img.data.data()));
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    return bgr;
}

bool tracksBirth(Method m) { return m == Method::WrsPaper || usesRetainPass(m); }

// Stale pixels of one eye: the colour submitted when the shown sample was taken (birth, linear) is
// more than 4/255 outside the range of the 3x3 neighbourhood of the submitted colour now (ref,
// sRGB 8-bit; the neighbourhood covers the sample's sub-pixel offset). Adds the squared errors of
// the method's output and of fov's output over those pixels.
void addStale(const std::vector<glm::vec4>& birth, const HostImage& ref, const HostImage& out, const HostImage& fovOut,
              Accum& a) {
    const int W = int(ref.width), H = int(ref.height);
    const auto* r = reinterpret_cast<const uint8_t*>(ref.data.data());
    const auto* o = reinterpret_cast<const uint8_t*>(out.data.data());
    const auto* fo = reinterpret_cast<const uint8_t*>(fovOut.data.data());
    const float tol = 4.0f / 255.0f;
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const std::size_t i = std::size_t(y) * W + x;
            const glm::vec3 b = gpu::wrs_linear_to_srgb3(glm::vec3(birth[i]));
            bool stale = false;
            for (int c = 0; c < 3 && !stale; ++c) {
                float lo = 1.0f, hi = 0.0f;
                for (int j = -1; j <= 1; ++j)
                    for (int k = -1; k <= 1; ++k) {
                        const int xx = std::clamp(x + k, 0, W - 1), yy = std::clamp(y + j, 0, H - 1);
                        const float v = r[(std::size_t(yy) * W + xx) * 4 + c] / 255.0f;
                        lo = std::min(lo, v);
                        hi = std::max(hi, v);
                    }
                stale = b[c] < lo - tol || b[c] > hi + tol;
            }
            a.stalePxTotal += 1;
            if (!stale) continue;
            a.stalePx += 1;
            for (int c = 0; c < 3; ++c) {
                const double ref8 = r[i * 4 + c] / 255.0, d = o[i * 4 + c] / 255.0 - ref8, df = fo[i * 4 + c] / 255.0 - ref8;
                a.staleSe += d * d / 3.0;
                a.staleFovSe += df * df / 3.0;
            }
        }
}

// Where the gaze of an eye meets the image, in pixels (may lie outside).
cv::Point gazePixel(const gpu::EyeParams& ep, uint32_t w, uint32_t h) {
    const glm::vec3 g(ep.gaze);
    if (!(g.z < 0.0f)) return {int(w) / 2, int(h) / 2};
    const float tx = g.x / -g.z, ty = g.y / -g.z;
    const float u = (tx - ep.fov_tan.x) / (ep.fov_tan.y - ep.fov_tan.x), v = (ep.fov_tan.z - ty) / (ep.fov_tan.z - ep.fov_tan.w);
    return {int(std::lround(u * w)), int(std::lround(v * h))};
}

// The C++ reference behind the bench's JodMetric interface.
class CpuJodMetric final : public JodMetric {
public:
    explicit CpuJodMetric(fvvdp::Metric m) : m_(std::move(m)) {}
    Status push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gazePx) override {
        return m_.push(test, reference, gazePx);
    }
    Result<double> jod() const override { return m_.jod(); }

private:
    fvvdp::Metric m_;
};

constexpr int kCropW = 96, kCropH = 72, kZoom = 3;  // crops are magnified 3x, nearest neighbour

// A kCropW x kCropH crop around `centre` (clamped into the image), magnified, with markers for the
// gaze now (white cross) and a second ago (yellow circle) and a label.
cv::Mat cropTile(const cv::Mat& img, cv::Point centre, cv::Point then, cv::Point now, const std::string& label) {
    const int cw = std::min(kCropW, img.cols), ch = std::min(kCropH, img.rows);
    const cv::Rect roi(std::clamp(centre.x - cw / 2, 0, img.cols - cw), std::clamp(centre.y - ch / 2, 0, img.rows - ch), cw, ch);
    cv::Mat big;
    cv::resize(img(roi), big, {cw * kZoom, ch * kZoom}, 0, 0, cv::INTER_NEAREST);
    auto at = [&](cv::Point p) { return (p - roi.tl()) * kZoom + cv::Point(kZoom / 2, kZoom / 2); };
    cv::circle(big, at(then), 9, {0, 230, 255}, 1, cv::LINE_AA);
    cv::drawMarker(big, at(now), {255, 255, 255}, cv::MARKER_CROSS, 14, 1, cv::LINE_AA);
    if (!label.empty()) {
        cv::rectangle(big, {0, 0}, {big.cols, 18}, {0, 0, 0}, cv::FILLED);
        cv::putText(big, label, {4, 13}, cv::FONT_HERSHEY_SIMPLEX, 0.42, {255, 255, 255}, 1, cv::LINE_AA);
    }
    return big;
}

cv::Mat flipColour(const cv::Mat& map) {
    cv::Mat m8, c;
    map.convertTo(m8, CV_8U, 255.0);
    cv::applyColorMap(m8, c, cv::COLORMAP_MAGMA);
    return c;
}

// The FLIP colour scale as a tile of crop size: 0 at the bottom, 1 at the top.
cv::Mat flipColourBar(int w, int h) {
    cv::Mat ramp(h, 1, CV_32F);
    for (int y = 0; y < h; ++y) ramp.at<float>(y, 0) = 1.0f - float(y) / float(h - 1);
    cv::Mat bar = flipColour(ramp), tile(h, w, CV_8UC3, cv::Scalar(0, 0, 0));
    const int bw = std::min(40, w / 4);
    cv::resize(bar, bar, {bw, h}, 0, 0, cv::INTER_NEAREST);
    bar.copyTo(tile(cv::Rect(bw / 2, 0, bw, h)));
    const int tx = bw * 2 - bw / 2 + 6;
    auto text = [&](const char* t, int y, double scale) {
        cv::putText(tile, t, {tx, y}, cv::FONT_HERSHEY_SIMPLEX, scale, {255, 255, 255}, 1, cv::LINE_AA);
    };
    text("FLIP 1", 14, 0.45);
    text("0.5", h / 2 + 5, 0.45);
    text("0", h - 4, 0.45);
    if (h >= 200) {  // the key, where it fits
        text("error maps below the images", h / 2 + 40, 0.38);
        text("+ gaze now, o 1 s ago", h / 2 + 58, 0.38);
    }
    return tile;
}

}  // namespace

Result<std::unique_ptr<JodMetric>> makeJodMetric(vk::Context&, const fvvdp::Options& options) {
    auto m = fvvdp::Metric::create(options);
    if (!m) return m.error();
    return std::unique_ptr<JodMetric>(std::make_unique<CpuJodMetric>(std::move(*m)));
}

fvvdp::Options jodOptions(const BenchOptions& o, SceneKind scene, uint32_t width, uint32_t height, glm::vec4 fovTan,
                          double fps) {
    fvvdp::Options fo;
    const bool hmd = !o.monitor && scene != SceneKind::Sequence;
    fo.photometry = hmd ? fvvdp::DisplayPhotometry::hmd() : fvvdp::DisplayPhotometry::monitor();
    fo.geometry = fvvdp::ViewGeometry::view(width, height, fovTan);
    fo.fps = fps;
    fo.foveated = true;
    return fo;
}

FoveaWorth foveaWorth(std::vector<std::pair<double, double>> curve, double target) {
    std::erase_if(curve, [](const auto& p) { return !std::isfinite(p.first) || !std::isfinite(p.second); });
    if (curve.empty() || !std::isfinite(target)) return {};
    std::sort(curve.begin(), curve.end());
    if (curve.front().second >= target) return {curve.front().first, FoveaWorth::Bound::AtMost};
    // The first segment that climbs to the target (a curve that is not monotonic: its first crossing).
    for (std::size_t i = 1; i < curve.size(); ++i) {
        const auto [f0, s0] = curve[i - 1];
        const auto [f1, s1] = curve[i];
        if (s0 < target && s1 >= target) return {f0 + (f1 - f0) * (target - s0) / (s1 - s0), FoveaWorth::Bound::Exact};
    }
    return {curve.back().first, FoveaWorth::Bound::MoreThan};
}

std::string toString(const FoveaWorth& w) {
    char buf[48];
    switch (w.bound) {
    case FoveaWorth::Bound::Exact: std::snprintf(buf, sizeof buf, "%.1f°", w.deg); return buf;
    case FoveaWorth::Bound::AtMost: std::snprintf(buf, sizeof buf, "%.1f° or less", w.deg); return buf;
    case FoveaWorth::Bound::MoreThan: std::snprintf(buf, sizeof buf, "more than %.1f°", w.deg); return buf;
    case FoveaWorth::Bound::Unknown: break;
    }
    return "n/a";
}

Result<std::vector<CellResult>> runBench(vk::Context& ctx, const BenchOptions& o) {
    auto say = [&](const std::string& s) {
        if (o.progress) o.progress(s);
    };
    if (o.width < 32 || o.height < 32) return benchError("bench: images must be at least 32x32 per eye");
    if (o.frames <= o.warmup) return benchError("bench: frames must exceed the warm-up frames");
    std::vector<CellResult> results;
    const int cellsTotal = int(o.scenes.size() * o.modes.size() * o.foveas.size());
    int cellNo = 0;
    for (SceneKind scene : o.scenes) {
        auto setup = openScene(ctx, scene, o);
        if (!setup) return setup.error();
        SceneFrames* frames = setup->frames.get();
        gaze::SyntheticSource* gazeSource = setup->gaze.get();
        const HostStereoApp::Options appOpt = frames->appOptions();
        auto texel = [](std::optional<layers::Format> f) { return f ? uint32_t(layers::bytesPerTexel(*f)) : 0u; };
        const TrafficInputs trafficIn{o.width, o.height, texel(appOpt.color), texel(appOpt.depth), texel(appOpt.motion)};

        for (FoveationMode mode : o.modes) {
            for (float fovea : o.foveas) {
                ++cellNo;
                say("cell " + std::to_string(cellNo) + "/" + std::to_string(cellsTotal) + ": " +
                    std::string(toString(scene)) + ", " + std::string(toString(mode)) + ", fovea " +
                    std::to_string(fovea).substr(0, 4) + "°");
                // Reference + one compositor per method, all fed the same frames.
                struct Run {
                    Method method;
                    std::unique_ptr<Compositor> comp;
                    std::unique_ptr<HostStereoApp> app;
                    Accum acc;
                    HostImage last[2];
                    float fovea = 0;
                    bool sweep = false;  // a fovea-worth run: fov at an extra fovea, JOD frames only
                    std::array<std::unique_ptr<JodMetric>, 2> jod;
                    cv::Mat out[2];  // this frame's output as the metrics read it
                };
                // The fovea-worth sweep: fov at the extra foveas, in the first fovea's cell (not without foveation).
                std::vector<float> sweepFoveas;
                if (o.qualityMetrics && o.jod && fovea == o.foveas.front() && mode != FoveationMode::None)
                    for (float wf : o.worthFoveas)
                        if (std::find(o.foveas.begin(), o.foveas.end(), wf) == o.foveas.end() &&
                            std::find(sweepFoveas.begin(), sweepFoveas.end(), wf) == sweepFoveas.end())
                            sweepFoveas.push_back(wf);
                const int methodRuns = int(o.methods.size());
                std::vector<Run> runs;
                for (int i = -1; i < methodRuns + int(sweepFoveas.size()); ++i) {
                    const bool sweep = i >= methodRuns;
                    CompositorConfig cc;
                    cc.method = i < 0 || sweep ? Method::Fov : o.methods[i];
                    cc.foveation = i < 0 ? FoveationMode::None : mode;
                    cc.foveaDeg = sweep ? sweepFoveas[size_t(i - methodRuns)] : fovea;
                    cc.seed = o.seed;
                    cc.change = o.change;
                    cc.measureCopy = i >= 0 && !sweep;
                    cc.skipTiles = o.skipTiles;
                    cc.sparseRetention = o.sparseRetention;
                    cc.floorMerge = o.floorMerge;
                    cc.steadyFloor = o.steadyFloor;
                    cc.motionReachDeg = o.motionReachDeg;
                    cc.trackBirth = i >= 0 && o.staleStats && tracksBirth(cc.method);
                    auto c = Compositor::create(ctx, cc);
                    if (!c) return c.error();
                    auto a = HostStereoApp::create(**c, appOpt);
                    if (!a) return a.error();
                    Run run;
                    run.method = cc.method;
                    run.fovea = cc.foveaDeg;
                    run.sweep = sweep;
                    run.comp = std::move(*c);
                    run.app = std::move(*a);
                    runs.push_back(std::move(run));
                }
                double prevT = 0;
                std::vector<cv::Point> gazePx;  // the left eye's gaze in pixels, per frame (crops)
                // Monitor mode submits one view as both eyes: the left eye's metrics stand for both.
                const int evalEyes = o.monitor ? 1 : 2;
                int fovRun = -1;  // fov's run, for the stale-pixel comparison
                for (std::size_t r = 1; r < runs.size(); ++r)
                    if (runs[r].method == Method::Fov && !runs[r].sweep) fovRun = int(r);
                // JOD (and the sweep) over the last jodFrames counted frames, or all of them.
                const bool scoreJod = o.qualityMetrics && o.jod;
                const int jodStart = o.jodFrames > 0 ? std::max(o.warmup, o.frames - o.jodFrames) : o.warmup;
                // --write-outputs: this cell's directory, one folder per method and eye, the gaze.
                std::string outDir;
                std::ofstream gazeCsv, viewCsv;
                if (!o.outputsDir.empty() && o.qualityMetrics) {  // without metrics nothing is read back
                    std::ostringstream name;
                    name << o.outputsDir << "/" << toString(scene) << "_" << toString(mode) << "_" << fovea;
                    outDir = name.str();
                    std::error_code ec;
                    for (std::size_t r = 0; r < runs.size() && !ec; ++r)
                        for (int e = 0; e < evalEyes && !runs[r].sweep && !ec; ++e)
                            std::filesystem::create_directories(
                                outDir + "/" + (r == 0 ? std::string("reference") : std::string(toString(runs[r].method))) +
                                    (e == 0 ? "/L" : "/R"),
                                ec);
                    if (ec) return benchError("bench: cannot create " + outDir + ": " + ec.message());
                    gazeCsv.open(outDir + "/gaze.csv");
                    if (!gazeCsv) return benchError("bench: cannot write " + outDir + "/gaze.csv");
                    gazeCsv << (evalEyes == 2 ? "frame,left_x,left_y,right_x,right_y,bench_frame,t_s\n"
                                              : "frame,left_x,left_y,bench_frame,t_s\n");
                    viewCsv.open(outDir + "/view.csv");
                    if (!viewCsv) return benchError("bench: cannot write " + outDir + "/view.csv");
                    viewCsv << "eye,tan_left,tan_right,tan_up,tan_down,width,height,fps,display,first_frame,jod_first_frame\n";
                }
                for (int f = 0; f < o.frames; ++f) {
                    const double t = f / frames->fps();
                    std::array<EyeSubmission, 2> eyes;
                    if (Status s = frames->frame(f, t, f == 0 ? t : prevT, eyes); !s) return s.error();
                    prevT = t;
                    if (!frames->providesGaze()) {
                        gaze::GazeSample g = gazeSource->sample(t);
                        for (int e = 0; e < 2; ++e) eyes[e].gaze = {g.eye[e].dir, g.eye[e].valid, g.eye[e].confidence};
                    }
                    HostImage ref[2];
                    // The reference as the metrics read it (sRGB floats), its eccentricity and the
                    // eccentricity weights: once per frame, shared by every method of the cell.
                    cv::Mat refMat[2], ecc[2], eccWeights[2];
                    double shading[2] = {0, 0};
                    // The copy kernel doubles a frame's GPU work: it runs on every copyEvery-th counted frame.
                    const bool copyFrame = f >= o.warmup && (f - o.warmup) % std::max(1, o.copyEvery) == 0;
                    const bool jodFrame = scoreJod && f >= jodStart;
                    glm::vec2 gazeF[2];
                    for (std::size_t r = 0; r < runs.size(); ++r) {
                        Run& run = runs[r];
                        run.out[0] = run.out[1] = cv::Mat();
                        // fov keeps nothing between frames: the sweep's runs see only the frames they score.
                        if (run.sweep && f < jodStart) continue;
                        if (r > 0 && !run.sweep && run.comp->config().measureCopy != copyFrame) {
                            CompositorConfig cc = run.comp->config();
                            cc.measureCopy = copyFrame;
                            if (Status s = run.comp->setConfig(cc); !s) return s.error();
                        }
                        if (Status s = run.app->submit(uint64_t(f + 1), t, eyes); !s)
                            return benchError("bench: frame " + std::to_string(f) + " refused: " + s.message());
                        for (uint32_t e = 0; e < 2 && (o.qualityMetrics || !o.cropDir.empty()); ++e) {
                            auto out = run.comp->readOutput(e);
                            if (!out) return out.error();
                            run.last[e] = std::move(*out);
                        }
                        if (r == 0) {
                            ref[0] = run.last[0];
                            ref[1] = run.last[1];
                            gazePx.push_back(gazePixel(run.comp->lastParams().eye[0], o.width, o.height));
                            for (int e = 0; e < 2; ++e) gazeF[e] = gazePixelF(run.comp->lastParams().eye[e], o.width, o.height);
                            // Eccentricity and shading work are the same for every method of the cell.
                            for (int e = 0; e < evalEyes; ++e) {
                                const gpu::EyeParams& ep = run.comp->lastParams().eye[e];
                                ecc[e] = eccentricityMap(o.width, o.height, ep);
                                if (o.qualityMetrics) {
                                    eccWeights[e] = eccentricityWeights(ecc[e]);
                                    refMat[e] = toMat(ref[e]);
                                }
                                if (f >= o.warmup)
                                    shading[e] = shadingFraction(mode, ecc[e], ep.gaze.w, run.comp->lastParams().tuning.x);
                            }
                            continue;
                        }
                        cv::Mat* outMat = run.out;
                        for (int e = 0; e < evalEyes && o.qualityMetrics; ++e) {
                            outMat[e] = toMat(run.last[e]);
                            run.acc.instab[e].addFrame(refMat[e], outMat[e]);
                        }
                        if (f < o.warmup) continue;
                        const FrameStats& st = run.comp->stats();
                        run.acc.mono = st.monoViews;
                        if (st.retained) {
                            run.acc.retainShare += st.retainShare();
                            run.acc.motionShare += st.motionShare();
                            run.acc.shareFrames++;
                        }
                        if (st.gpu.valid) {
                            run.acc.pyramid.push_back(st.gpu.pyramid);
                            run.acc.foveate.push_back(st.gpu.foveate);
                            run.acc.temporal.push_back(st.gpu.temporal);
                            run.acc.total.push_back(st.gpu.total);
                            if (copyFrame) {
                                run.acc.copy.push_back(st.gpu.copy);
                                run.acc.copyFloor.push_back(st.gpu.copyFloor);
                            }
                        }
                        if (!o.qualityMetrics) {
                            for (int e = 0; e < evalEyes; ++e) run.acc.shading += shading[e];
                            run.acc.n += evalEyes;
                            continue;
                        }
                        const bool heavy = (f - o.warmup) % std::max(1, o.heavyEvery) == 0;
                        for (int e = 0; e < evalEyes; ++e) {
                            const gpu::EyeParams& ep = run.comp->lastParams().eye[e];
                            run.acc.mse += meanSquaredError(refMat[e], outMat[e]);
                            // Near-gaze PSNR is NaN only when no pixel lies within 10° (gaze far outside the
                            // view); such an eye-frame adds nothing there (counted as zero error).
                            double np = nearGazePsnr(refMat[e], outMat[e], ecc[e]);
                            run.acc.nearMse += std::isnan(np) ? 0.0 : mseFromPsnr(np);
                            if (jodFrame) {
                                run.acc.jodNearMse += std::isnan(np) ? 0.0 : mseFromPsnr(np);
                                run.acc.jodN++;
                            }
                            run.acc.eccMse += weightedMse(refMat[e], outMat[e], eccWeights[e]);
                            run.acc.shading += shading[e];
                            addBandErrors(refMat[e], outMat[e], ecc[e], run.acc);
                            if (heavy) {
                                run.acc.ssim += ssim(refMat[e], outMat[e]);
                                FlipOptions fo{pixelsPerDegreeAtCentre(o.width, ep.fov_tan)};
                                run.acc.flip += flip(refMat[e], outMat[e], fo).mean;
                                // fov runs before the temporal methods (methods in option order), so its
                                // output of this frame is there when fov is listed first.
                                if (o.staleStats && tracksBirth(run.method) && fovRun >= 0 && fovRun < int(r)) {
                                    auto birth = run.comp->readBirth(uint32_t(e));
                                    if (!birth) return birth.error();
                                    addStale(*birth, ref[e], run.last[e], runs[fovRun].last[e], run.acc);
                                }
                            }
                        }
                        run.acc.n += evalEyes;
                        if (heavy) run.acc.heavy += evalEyes;
                    }
                    // --write-outputs: the counted frames, numbered from 0, and where the gaze was.
                    if (!outDir.empty() && f >= o.warmup) {
                        const int k = f - o.warmup;
                        char file[32];
                        std::snprintf(file, sizeof file, "%06d.png", k);
                        for (std::size_t r = 0; r < runs.size(); ++r) {
                            if (runs[r].sweep) continue;
                            const std::string name = r == 0 ? std::string("reference") : std::string(toString(runs[r].method));
                            for (int e = 0; e < evalEyes; ++e)
                                if (!cv::imwrite(outDir + "/" + name + (e == 0 ? "/L/" : "/R/") + file, toBgr8(runs[r].last[e])))
                                    return benchError("bench: cannot write " + outDir + "/" + name + "/" + file);
                        }
                        gazeCsv.precision(7);
                        gazeCsv << k;
                        for (int e = 0; e < evalEyes; ++e) gazeCsv << ',' << gazeF[e].x << ',' << gazeF[e].y;
                        gazeCsv << ',' << f << ',' << f / frames->fps() << '\n';
                        if (k == 0)
                            for (int e = 0; e < evalEyes; ++e) {
                                const glm::vec4 ft = runs[0].comp->lastParams().eye[e].fov_tan;
                                viewCsv.precision(9);
                                viewCsv << (e == 0 ? "L" : "R") << ',' << ft.x << ',' << ft.y << ',' << ft.z << ',' << ft.w
                                        << ',' << o.width << ',' << o.height << ',' << frames->fps() << ','
                                        << (!o.monitor && scene != SceneKind::Sequence ? "hmd" : "monitor") << ','
                                        << o.warmup << ',' << jodStart - o.warmup << '\n';
                            }
                    }
                    // JOD: every method's (and eye's) metric takes the frame; independent, so in parallel.
                    if (jodFrame) {
                        std::vector<std::pair<int, int>> jobs;  // (run, eye)
                        for (std::size_t r = 1; r < runs.size(); ++r)
                            for (int e = 0; e < evalEyes; ++e) {
                                if (runs[r].out[e].empty()) continue;
                                if (!runs[r].jod[e]) {
                                    const glm::vec4 ft = runs[0].comp->lastParams().eye[e].fov_tan;
                                    auto m = makeJodMetric(ctx, jodOptions(o, scene, o.width, o.height, ft, frames->fps()));
                                    if (!m) return benchError("bench: JOD: " + m.error().message);
                                    runs[r].jod[e] = std::move(*m);
                                }
                                jobs.emplace_back(int(r), e);
                            }
                        std::vector<std::string> failed(jobs.size());
                        cv::parallel_for_(cv::Range(0, int(jobs.size())), [&](const cv::Range& range) {
                            for (int j = range.start; j < range.end; ++j) {
                                const auto [r, e] = jobs[size_t(j)];
                                if (Status st = runs[size_t(r)].jod[size_t(e)]->push(runs[size_t(r)].out[e], refMat[e], gazeF[e]); !st)
                                    failed[size_t(j)] = st.message();
                            }
                        });
                        for (std::size_t j = 0; j < jobs.size(); ++j)
                            if (!failed[j].empty())
                                return benchError("bench: JOD of " + std::string(toString(runs[size_t(jobs[j].first)].method)) +
                                                  ", frame " + std::to_string(f) + ": " + failed[j]);
                    }
                }
                double fovTotal = 0;
                for (std::size_t r = 1; r < runs.size(); ++r)
                    if (runs[r].method == Method::Fov && !runs[r].sweep) fovTotal = median(runs[r].acc.total);
                for (std::size_t r = 1; r < runs.size(); ++r) {
                    Run& run = runs[r];
                    Accum& a = run.acc;
                    CellResult c{scene, run.method, mode, run.fovea};
                    c.worthSweep = run.sweep;
                    c.frames = run.sweep ? o.frames - jodStart : o.frames - o.warmup;
                    if (run.jod[0]) {
                        double sum = 0;
                        int eyes = 0;
                        for (int e = 0; e < evalEyes; ++e) {
                            if (!run.jod[e]) continue;
                            auto j = run.jod[e]->jod();
                            if (!j) return benchError("bench: JOD of " + std::string(toString(run.method)) + ": " + j.error().message);
                            sum += *j;
                            ++eyes;
                        }
                        c.jod = sum / eyes;
                        c.jodFrames = o.frames - jodStart;
                        c.jodNearPsnr = psnrFromMse(a.jodNearMse / std::max(1, a.jodN));
                    }
                    c.gpu = {median(a.pyramid), median(a.foveate), median(a.temporal), median(a.total),
                             median(a.copy),    median(a.copyFloor), !a.total.empty()};
                    // Sparse retention: the bytes of the tiles that ran retention and of those that did not.
                    TrafficInputs cellIn = trafficIn;
                    if (a.shareFrames > 0) {
                        c.retainShare = a.retainShare / a.shareFrames;
                        cellIn.retainShare = c.retainShare;
                        c.motionShare = a.motionShare / a.shareFrames;
                        cellIn.motionShare = c.motionShare;
                    }
                    c.traffic = traffic(run.comp->config(), cellIn);
                    // Identical views run the passes once (monitor mode, FrameStats::monoViews); so does the copy.
                    c.trafficBytes = double(trafficBytes(run.comp->config(), cellIn)) / (a.mono ? 2 : 1);
                    c.copyMs = median(a.copy);
                    c.copyFloorMs = median(a.copyFloor);
                    c.shadingFraction = a.shading / std::max(1, a.n);
                    c.psnr = psnrFromMse(a.mse / std::max(1, a.n));
                    c.nearPsnr = psnrFromMse(a.nearMse / std::max(1, a.n));
                    c.eccMse = a.eccMse / std::max(1, a.n);
                    c.ssim = a.ssim / std::max(1, a.heavy);
                    c.flip = a.flip / std::max(1, a.heavy);
                    c.temporal = o.monitor ? a.instab[0].mean() : 0.5 * (a.instab[0].mean() + a.instab[1].mean());
                    c.fovTotalMs = fovTotal;
                    c.mse = a.mse / std::max(1, a.n);
                    double px = 0.0;
                    for (double n : a.bandPx) px += n;
                    for (std::size_t b = 0; b < c.bandMse.size(); ++b) {
                        c.bandMse[b] = a.bandPx[b] > 0 ? a.bandSe[b] / a.bandPx[b] : 0.0;
                        c.bandShare[b] = px > 0 ? a.bandPx[b] / px : 0.0;
                    }
                    c.nearMse = a.nearMse / std::max(1, a.n);
                    if (!o.qualityMetrics) {
                        const double nan = std::numeric_limits<double>::quiet_NaN();
                        c.psnr = c.nearPsnr = c.eccMse = c.ssim = c.flip = c.temporal = c.mse = c.nearMse = nan;
                        c.bandMse.fill(nan);
                    }
                    if (a.stalePxTotal > 0) {
                        c.staleFraction = a.stalePx / a.stalePxTotal;
                        c.staleMse = a.stalePx > 0 ? a.staleSe / a.stalePx : 0.0;
                        c.staleFovMse = a.stalePx > 0 ? a.staleFovSe / a.stalePx : 0.0;
                    }
                    results.push_back(c);
                }
                // Retention efficiency against fov and each oracle of this cell.
                const std::size_t first = results.size() - (runs.size() - 1);
                const auto cell = std::span<const CellResult>(results).subspan(first);
                const CellResult* fovCell = findCell(cell, scene, mode, fovea, Method::Fov);
                const CellResult* oracleCell = findCell(cell, scene, mode, fovea, Method::Oracle);
                const CellResult* oracleQCell = findCell(cell, scene, mode, fovea, Method::OracleQ);
                auto efficiency = [&](const CellResult* bound, double CellResult::*whole, double CellResult::*near) {
                    if (!fovCell || !bound) return;
                    const double gain = boundGain(fovCell->mse, bound->mse),
                                 gainNear = boundGain(fovCell->nearMse, bound->nearMse);
                    for (std::size_t k = first; k < results.size(); ++k) {
                        if (results[k].worthSweep) continue;
                        if (gain > 0) results[k].*whole = (fovCell->mse - results[k].mse) / gain;
                        if (gainNear > 0) results[k].*near = (fovCell->nearMse - results[k].nearMse) / gainNear;
                    }
                };
                efficiency(oracleCell, &CellResult::eta, &CellResult::etaNear);
                efficiency(oracleQCell, &CellResult::etaQ, &CellResult::etaQNear);
                // Crops of the left eye's last frame for the smallest fovea: around the point the gaze
                // left about a second ago (where kept samples make the difference) and at the gaze.
                if (!o.cropDir.empty() && fovea == o.foveas.front() && !gazePx.empty()) {
                    const int back = std::min<int>(int(gazePx.size()) - 1, int(std::lround(frames->fps())));
                    const cv::Point then = gazePx[gazePx.size() - 1 - back], now = gazePx.back();
                    FlipOptions fo{pixelsPerDegreeAtCentre(o.width, runs[0].comp->lastParams().eye[0].fov_tan)};
                    std::vector<cv::Mat> flipMaps(runs.size());
                    for (std::size_t r = 1; r < runs.size(); ++r)
                        if (!runs[r].sweep) flipMaps[r] = flip(runs[0].last[0], runs[r].last[0], fo).map;
                    std::vector<cv::Mat> rows;
                    for (const auto& [centre, what] : {std::pair{then, std::string("1 s ago")}, std::pair{now, std::string("now")}}) {
                        std::vector<cv::Mat> images, maps;
                        for (std::size_t r = 0; r < runs.size(); ++r) {
                            if (runs[r].sweep) continue;
                            const std::string label = r == 0 ? "reference" : std::string(toString(runs[r].method));
                            images.push_back(cropTile(toBgr8(runs[r].last[0]), centre, then, now, label + " (" + what + ")"));
                            maps.push_back(r == 0 ? flipColourBar(images[0].cols, images[0].rows)
                                                  : cropTile(flipColour(flipMaps[r]), centre, then, now, ""));
                        }
                        cv::Mat top, bottom;
                        cv::hconcat(images, top);
                        cv::hconcat(maps, bottom);
                        rows.push_back(top);
                        rows.push_back(bottom);
                    }
                    cv::Mat all;
                    cv::vconcat(rows, all);
                    std::ostringstream name;
                    name << o.cropDir << "/crops_" << toString(scene) << "_" << toString(mode) << "_" << fovea
                         << ".png";
                    cv::imwrite(name.str(), all);
                }
            }
        }
    }
    return results;
}

Result<std::vector<CellResult>> runDeviceSweep(vk::Context& ctx, const BenchOptions& o, DeviceSweepStats* stats) {
    auto say = [&](const std::string& s) {
        if (o.progress) o.progress(s);
    };
    if (o.width < 32 || o.height < 32) return benchError("bench: images must be at least 32x32 per eye");
    if (o.frames <= o.warmup) return benchError("bench: frames must exceed the warm-up frames");
    DeviceSweepStats local;
    DeviceSweepStats& st = stats ? *stats : local;
    st = {};
    std::vector<CellResult> results;
    for (SceneKind scene : o.scenes) {
        // The scene's inputs: one image per swapchain (every frame end waits for its work), owned by a
        // compositor that never composites; the atrium renders into them, the other scenes upload.
        const bool rendered = scene == SceneKind::Atrium || scene == SceneKind::Dynamic;
        const scenes::AtriumOptions ao = atriumOptions(o, scene);
        std::unique_ptr<scenes::AtriumRenderer> renderer;
        std::unique_ptr<SceneFrames> hostFrames;
        std::unique_ptr<gaze::SyntheticSource> gazeSource;
        HostStereoApp::Options appOpt;
        double fps = kFps;
        if (rendered) {
            auto r = scenes::AtriumRenderer::create(ctx, ao);
            if (!r) return r.error();
            renderer = std::move(*r);
            appOpt = atriumAppOptions(ao);
            gaze::GeneratorConfig gc = sweepGaze(o, nullptr);
            gc.seconds = o.frames / fps + 2.0;
            auto g = gaze::SyntheticSource::create(gc);
            if (!g) return benchError("bench: gaze generator: " + g.error().message);
            gazeSource = std::move(*g);
        } else {
            auto setup = openScene(ctx, scene, o);
            if (!setup) return setup.error();
            hostFrames = std::move(setup->frames);
            gazeSource = std::move(setup->gaze);
            appOpt = hostFrames->appOptions();
            fps = hostFrames->fps();
        }
        appOpt.imageCount = 1;
        auto owner = Compositor::create(ctx);
        if (!owner) return owner.error();
        auto source = HostStereoApp::create(**owner, appOpt);
        if (!source) return source.error();
        auto texel = [](std::optional<layers::Format> f) { return f ? uint32_t(layers::bytesPerTexel(*f)) : 0u; };
        const TrafficInputs trafficIn{o.width, o.height, texel(appOpt.color), texel(appOpt.depth),
                                      texel(appOpt.motion)};
        // The host images last uploaded: a frame equal to them is not uploaded again (a still image once).
        std::array<EyeSubmission, 2> uploaded;
        bool anyUploaded = false;
        auto sameImages = [&](const std::array<EyeSubmission, 2>& eyes) {
            if (!anyUploaded) return false;
            for (int e = 0; e < (appOpt.monoView ? 1 : 2); ++e) {
                const EyeSubmission &a = eyes[e], &b = uploaded[e];
                if (a.color.data != b.color.data || a.depth.has_value() != b.depth.has_value() ||
                    a.motion.has_value() != b.motion.has_value() || (a.depth && a.depth->data != b.depth->data) ||
                    (a.motion && a.motion->data != b.motion->data))
                    return false;
            }
            return true;
        };
        for (FoveationMode mode : o.modes) {
            for (float fovea : o.foveas) {
                say("cell: " + std::string(toString(scene)) + ", " + std::string(toString(mode)) + ", fovea " +
                    std::to_string(fovea).substr(0, 4) + "°, " + std::to_string(o.width) + "x" +
                    std::to_string(o.height) + " per eye, frames kept on the device");
                struct Run {
                    Method method;
                    std::unique_ptr<Compositor> comp;
                    std::unique_ptr<HostStereoApp> app;
                    Accum acc;
                };
                std::vector<Run> runs;
                for (Method m : o.methods) {
                    CompositorConfig cc;
                    cc.method = m;
                    cc.foveation = mode;
                    cc.foveaDeg = fovea;
                    cc.seed = o.seed;
                    cc.change = o.change;
                    cc.measureCopy = true;
                    cc.skipTiles = o.skipTiles;
                    cc.sparseRetention = o.sparseRetention;
                    cc.floorMerge = o.floorMerge;
                    cc.steadyFloor = o.steadyFloor;
                    cc.motionReachDeg = o.motionReachDeg;
                    cc.trackBirth = o.staleStats && tracksBirth(m);
                    auto c = Compositor::create(ctx, cc);
                    if (!c) return c.error();
                    auto a = HostStereoApp::share(**c, **source);
                    if (!a) return a.error();
                    runs.push_back(Run{m, std::move(*c), std::move(*a), Accum()});
                }
                double prevT = 0;
                for (int f = 0; f < o.frames; ++f) {
                    const double t = f / fps;
                    std::array<EyeSubmission, 2> eyes;
                    if (rendered) {
                        HostStereoApp& app = **source;
                        Status s = app.drawInPlace([&](const HostStereoApp::Images& im) {
                            return renderer->render(t, f == 0 ? t : prevT, app.color(), im.color, *app.depth(),
                                                    im.depth, *app.motion(), im.motion);
                        });
                        if (!s) return s.error();
                        ++st.rendered;
                        for (int e = 0; e < 2; ++e) eyes[e].fov = scenes::atriumFov(ao, e);
                    } else {
                        if (Status s = hostFrames->frame(f, t, f == 0 ? t : prevT, eyes); !s) return s.error();
                        if (!sameImages(eyes)) {
                            if (Status s = (*source)->write(eyes); !s) return s.error();
                            uploaded = eyes;
                            anyUploaded = true;
                            ++st.uploads;
                        }
                    }
                    prevT = t;
                    if (!hostFrames || !hostFrames->providesGaze()) {
                        gaze::GazeSample g = gazeSource->sample(t);
                        for (int e = 0; e < 2; ++e) eyes[e].gaze = {g.eye[e].dir, g.eye[e].valid, g.eye[e].confidence};
                    }
                    // The copy kernels double a frame's GPU work: on every copyEvery-th counted frame.
                    const bool copyFrame = f >= o.warmup && (f - o.warmup) % std::max(1, o.copyEvery) == 0;
                    for (Run& run : runs) {
                        if (run.comp->config().measureCopy != copyFrame) {
                            CompositorConfig cc = run.comp->config();
                            cc.measureCopy = copyFrame;
                            if (Status s = run.comp->setConfig(cc); !s) return s.error();
                        }
                        if (Status s = run.app->submitShared(uint64_t(f + 1), t, eyes); !s)
                            return benchError("bench: frame " + std::to_string(f) + " refused: " + s.message());
                        ++st.submitted;
                        if (f < o.warmup) continue;
                        const FrameStats& fs = run.comp->stats();
                        run.acc.mono = fs.monoViews;
                        if (fs.retained) {
                            run.acc.retainShare += fs.retainShare();
                            run.acc.motionShare += fs.motionShare();
                            run.acc.shareFrames++;
                        }
                        if (fs.gpu.valid) {
                            run.acc.pyramid.push_back(fs.gpu.pyramid);
                            run.acc.foveate.push_back(fs.gpu.foveate);
                            run.acc.temporal.push_back(fs.gpu.temporal);
                            run.acc.total.push_back(fs.gpu.total);
                            if (copyFrame) {
                                run.acc.copy.push_back(fs.gpu.copy);
                                run.acc.copyFloor.push_back(fs.gpu.copyFloor);
                            }
                        }
                    }
                }
                double fovTotal = 0;
                for (const Run& run : runs)
                    if (run.method == Method::Fov) fovTotal = median(run.acc.total);
                const double nan = std::numeric_limits<double>::quiet_NaN();
                for (Run& run : runs) {
                    const Accum& a = run.acc;
                    CellResult c{scene, run.method, mode, fovea};
                    c.frames = o.frames - o.warmup;
                    c.gpu = {median(a.pyramid), median(a.foveate), median(a.temporal), median(a.total),
                             median(a.copy),    median(a.copyFloor), !a.total.empty()};
                    TrafficInputs cellIn = trafficIn;
                    if (a.shareFrames > 0) {
                        c.retainShare = cellIn.retainShare = a.retainShare / a.shareFrames;
                        c.motionShare = cellIn.motionShare = a.motionShare / a.shareFrames;
                    }
                    c.traffic = traffic(run.comp->config(), cellIn);
                    c.trafficBytes = double(trafficBytes(run.comp->config(), cellIn)) / (a.mono ? 2 : 1);
                    c.copyMs = median(a.copy);
                    c.copyFloorMs = median(a.copyFloor);
                    c.fovTotalMs = fovTotal;
                    // Nothing was read back: no error metric, and no eccentricity map for the shading share.
                    c.shadingFraction = c.psnr = c.nearPsnr = c.eccMse = c.ssim = c.flip = c.temporal = c.mse =
                        c.nearMse = nan;
                    c.bandMse.fill(nan);
                    results.push_back(c);
                }
            }
        }
    }
    return results;
}

Status forEachSceneFrame(vk::Context& ctx, SceneKind scene, const BenchOptions& o,
                         const std::function<Status(const SceneFrameInfo&, int, double,
                                                    std::array<EyeSubmission, 2>&)>& visit) {
    auto setup = openScene(ctx, scene, o);
    if (!setup) return setup.error();
    SceneFrames& frames = *setup->frames;
    const SceneFrameInfo app{frames.appOptions(), frames.fps()};
    double prevT = 0;
    for (int f = 0; f < o.frames; ++f) {
        const double t = f / frames.fps();
        std::array<EyeSubmission, 2> eyes;
        if (Status s = frames.frame(f, t, f == 0 ? t : prevT, eyes); !s) return s;
        prevT = t;
        if (!frames.providesGaze()) {
            gaze::GazeSample g = setup->gaze->sample(t);
            for (int e = 0; e < 2; ++e) eyes[e].gaze = {g.eye[e].dir, g.eye[e].valid, g.eye[e].confidence};
        }
        if (Status s = visit(app, f, t, eyes); !s) return s;
    }
    return {};
}

Status writeSceneSequence(vk::Context& ctx, SceneKind scene, const BenchOptions& o, const std::string& dir) {
    if (o.frames < 1) return benchError("write sequence: frames must be at least 1");
    std::unique_ptr<SequenceWriter> writer;
    SequenceInfo info;
    auto write = [&](const SceneFrameInfo& si, int f, double, std::array<EyeSubmission, 2>& eyes) -> Status {
        if (!writer) {  // the json needs the field of view, which the first frame brings
            const HostStereoApp::Options& app = si.app;
            info.width = app.width;
            info.height = app.height;
            info.frameCount = uint32_t(o.frames);
            info.fps = si.fps;
            info.color = app.color == layers::Format::RGBA8_SRGB ? ColorFile::Png : ColorFile::Exr;
            if (app.depth) info.depth = SequenceDepth{app.nearZ, app.farZ, app.reversedZ};
            if (app.motion) info.motion = MotionUnits::Pixels;
            std::ostringstream d;
            d << "scene " << toString(scene) << ", seed " << o.seed << ", written by wrsfov-bench --write-sequence";
            info.description = d.str();
            info.fov = {eyes[0].fov, eyes[1].fov};
            auto w = SequenceWriter::create(dir, info);
            if (!w) return w.error();
            writer = std::move(*w);
        }
        for (int e = 0; e < 2; ++e)
            if (std::memcmp(&eyes[e].fov, &info.fov[e], sizeof(layers::Fov)) != 0)
                return benchError("write sequence: the field of view of scene " + std::string(toString(scene)) +
                                  " changes at frame " + std::to_string(f) + "; a sequence has one per eye");
        if (Status s = writer->writeFrame(uint32_t(f), eyes); !s) return s;
        if (o.progress && ((f + 1) % 30 == 0 || f + 1 == o.frames))
            o.progress("wrote frame " + std::to_string(f + 1) + "/" + std::to_string(o.frames));
        return {};
    };
    if (Status s = forEachSceneFrame(ctx, scene, o, write); !s) return s;
    return writer->finish();
}

float equalQualityFovea(const std::vector<CellResult>& results, SceneKind scene, FoveationMode mode) {
    double target = std::numeric_limits<double>::quiet_NaN();
    for (const auto& c : results)
        if (c.scene == scene && c.mode == mode && c.method == Method::Fov && c.foveaDeg == 10.0f && !c.worthSweep)
            target = c.nearPsnr;
    if (std::isnan(target)) return 0.0f;
    float best = 0.0f;
    for (const auto& c : results)
        if (c.scene == scene && c.mode == mode && c.method == Method::Wrs && c.foveaDeg < 10.0f && c.nearPsnr >= target &&
            (best == 0.0f || c.foveaDeg < best))
            best = c.foveaDeg;
    return best;
}

namespace {


// Pixel density at the view centre of the atrium scenes for these options.
double centrePixelsPerDegree(const BenchOptions& o) {
    scenes::AtriumOptions ao;
    ao.monitor = o.monitor;
    ao.fovDeg = o.hmdFovDeg;
    const layers::Fov f = scenes::atriumFov(ao, 0);
    return pixelsPerDegreeAtCentre(o.width, glm::vec4(std::tan(f.angleLeft), std::tan(f.angleRight),
                                                      std::tan(f.angleUp), std::tan(f.angleDown)));
}

std::string fmt(double v, int prec = 2) {
    if (std::isinf(v)) return "inf";
    if (std::isnan(v)) return "n/a";
    std::ostringstream s;
    s.setf(std::ios::fixed);
    s.precision(prec);
    s << v;
    return s.str();
}

// Bytes per pass per method (they depend on the method, the mode and the inputs, not the scene
// content), the floor, and the times against both copy kernels.
void writeTrafficSection(std::ostream& md, const std::vector<CellResult>& results) {
    md << "\n## Traffic\n\n"
          "Bytes each pass reads and writes per pixel of one view, from its bindings and formats (shaders/), "
          "every texel of every binding counted once (the memory traffic with caches that hold a bilinear or 3×3 "
          "neighbourhood). The *floor* is what the method cannot avoid: the colour in and the output out, and for "
          "methods with history the 16-byte reservoir read and written and the depth and motion they use. Times "
          "are medians over the same cells as above; *copy* moves the method's bytes, *copy floor* the floor's, "
          "in the same submissions.\n\n"
          "| scene | mode | method | passes (read + write, B/px) | B/px | floor B/px | ×floor | GPU ms | ×copy | "
          "×copy floor |\n|---|---|---|---|---|---|---|---|---|---|\n";
    for (const CellResult& c : results) {
        std::string passes;
        for (const PassTraffic& p : c.traffic.passes)
            passes += (passes.empty() ? "" : ", ") + p.pass + " " + fmt(p.read, 1) + " + " + fmt(p.write, 1);
        md << "| " << toString(c.scene) << " | " << toString(c.mode) << " | " << toString(c.method) << " | " << passes
           << " | " << fmt(c.traffic.perPixel(), 1) << " | " << fmt(c.traffic.floor, 1) << " | "
           << fmt(c.traffic.perPixel() / c.traffic.floor) << " | " << fmt(c.gpu.total, 3) << " | "
           << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.gpu.total / c.copyFloorMs) << " |\n";
    }
}

std::string bandName(std::size_t b) {
    return std::isinf(kEccBands[b + 1]) ? "≥ " + fmt(kEccBands[b], 0) + "°"
                                   : fmt(kEccBands[b], 0) + "–" + fmt(kEccBands[b + 1], 0) + "°";
}

// Where the error and the oracles' gains lie: MSE per eccentricity band, η per band, and each band's
// share of each oracle's gain over the whole image (band MSE gain × the band's share of pixels).
void writeBandSection(std::ostream& md, const std::vector<CellResult>& results) {
    md << "\n## Error by eccentricity\n\n"
          "MSE (sRGB, ×1000) per band of eccentricity from the gaze, over all counted frames; *px* the band's "
          "share of the pixels; *η* per band against fov and the oracle of the same cell, *η_q* against the "
          "retention oracle (oracle-q), n/a where that oracle removes less than 1 % of fov's MSE in the band; "
          "*gain share*: the band's part of that oracle's whole-image MSE gain over "
          "fov (where a keep-or-replace rule could gain, and how much of it lies where every candidate is "
          "equally blurred).\n";
    auto same = [](const CellResult& a, const CellResult& b) {
        return a.scene == b.scene && a.mode == b.mode && a.foveaDeg == b.foveaDeg;
    };
    for (std::size_t i = 0; i < results.size(); ++i) {
        const CellResult& first = results[i];
        bool seen = false;
        for (std::size_t j = 0; j < i; ++j) seen = seen || same(results[j], first);
        if (seen) continue;
        const CellResult* fov = findCell(results, first.scene, first.mode, first.foveaDeg, Method::Fov);
        const CellResult* oracle = findCell(results, first.scene, first.mode, first.foveaDeg, Method::Oracle);
        const CellResult* oracleQ = findCell(results, first.scene, first.mode, first.foveaDeg, Method::OracleQ);
        md << "\n" << toString(first.scene) << ", " << toString(first.mode) << ", fovea " << fmt(first.foveaDeg, 1)
           << "°\n\n| method |";
        for (std::size_t b = 0; b < first.bandMse.size(); ++b) md << " " << bandName(b) << " |";
        md << "\n|---|";
        for (std::size_t b = 0; b < first.bandMse.size(); ++b) md << "---|";
        md << "\n| px |";
        for (double v : first.bandShare) md << " " << fmt(100 * v, 1) << " % |";
        md << "\n";
        for (const CellResult& c : results) {
            if (!same(c, first)) continue;
            md << "| " << toString(c.method) << " |";
            for (double v : c.bandMse) md << " " << fmt(1000 * v, 2) << " |";
            md << "\n";
        }
        if (!fov) continue;
        for (const CellResult* bound : {oracle, oracleQ}) {
            if (!bound) continue;
            double total = 0.0;
            for (std::size_t b = 0; b < first.bandMse.size(); ++b)
                total += (fov->bandMse[b] - bound->bandMse[b]) * fov->bandShare[b];
            md << "| " << toString(bound->method) << " gain share |";
            for (std::size_t b = 0; b < first.bandMse.size(); ++b)
                md << " "
                   << fmt(total > 0 ? 100 * (fov->bandMse[b] - bound->bandMse[b]) * fov->bandShare[b] / total : 0.0, 0)
                   << " % |";
            md << "\n";
            for (const CellResult& c : results) {
                if (!same(c, first) || c.method == Method::Fov || isOracle(c.method)) continue;
                md << "| " << (bound == oracle ? "η " : "η_q ") << toString(c.method) << " |";
                for (std::size_t b = 0; b < first.bandMse.size(); ++b) {
                    const double g = boundGain(fov->bandMse[b], bound->bandMse[b]);
                    md << " " << (g > 0 ? fmt((fov->bandMse[b] - c.bandMse[b]) / g) : std::string("n/a")) << " |";
                }
                md << "\n";
            }
        }
    }
}

}  // namespace

Status writeReport(const std::vector<CellResult>& results, const BenchOptions& o, const std::string& dir,
                   const std::string& deviceName) {
    std::ofstream csv(dir + "/results.csv");
    if (!csv) return Error{1, "cannot write " + dir + "/results.csv"};
    csv.precision(7);
    csv << "scene,method,mode,fovea_deg,frames,pyramid_ms,foveate_ms,temporal_ms,total_ms,per_eye_ms,"
           "copy_ms,copy_floor_ms,traffic_bytes,bytes_per_px,floor_bytes_per_px,ratio_to_floor_bytes,ratio_to_copy,"
           "ratio_to_copy_floor,ratio_to_fov,shading_fraction,psnr,jod,ssim,near_gaze_psnr,ecc_mse,flip,"
           "temporal_instability,mse,near_gaze_mse,eta,eta_near_gaze,stale_fraction,stale_mse,stale_fov_mse,eta_q,"
           "eta_q_near_gaze,retain_share,jod_frames,jod_near_gaze_psnr,worth_sweep\n";
    for (const auto& c : results)
        csv << toString(c.scene) << ',' << toString(c.method) << ',' << toString(c.mode) << ',' << c.foveaDeg << ','
            << c.frames << ',' << c.gpu.pyramid << ',' << c.gpu.foveate << ',' << c.gpu.temporal << ',' << c.gpu.total
            << ',' << c.gpu.total / 2 << ',' << c.copyMs << ',' << c.copyFloorMs << ',' << c.trafficBytes << ','
            << c.traffic.perPixel() << ',' << c.traffic.floor << ',' << c.traffic.perPixel() / c.traffic.floor << ','
            << c.gpu.total / c.copyMs << ',' << c.gpu.total / c.copyFloorMs << ',' << c.gpu.total / c.fovTotalMs << ','
            << c.shadingFraction << ',' << c.psnr << ',' << c.jod << ',' << c.ssim << ',' << c.nearPsnr << ',' << c.eccMse << ',' << c.flip << ',' << c.temporal
            << ',' << c.mse << ',' << c.nearMse << ',' << c.eta << ',' << c.etaNear << ',' << c.staleFraction << ','
            << c.staleMse << ',' << c.staleFovMse << ',' << c.etaQ << ',' << c.etaQNear << ',' << c.retainShare << ','
            << c.jodFrames << ',' << c.jodNearPsnr << ',' << (c.worthSweep ? 1 : 0) << '\n';

    // The fovea each method at the first fovea is worth: fov's fovea of equal JOD, and of equal near-gaze
    // PSNR over the same frames.
    struct Worth {
        SceneKind scene;
        FoveationMode mode;
        Method method;
        const CellResult* cell;
        FoveaWorth byJod, byPsnr;
        double fovMin = 0, fovMax = 0;
    };
    std::vector<Worth> worth;
    const float fovea0 = o.foveas.front();
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            std::vector<std::pair<double, double>> byJod, byPsnr;
            for (const CellResult& c : results)
                if (c.scene == scene && c.mode == mode && c.method == Method::Fov && c.foveaDeg >= fovea0) {
                    byJod.emplace_back(c.foveaDeg, c.jod);
                    byPsnr.emplace_back(c.foveaDeg, c.jodNearPsnr);
                }
            if (byJod.size() < 2) continue;
            double lo = 1e9, hi = 0;
            for (auto [f, v] : byJod) lo = std::min(lo, f), hi = std::max(hi, f);
            for (Method m : o.methods) {
                if (m == Method::Fov) continue;
                const CellResult* c = findCell(results, scene, mode, fovea0, m);
                if (!c || std::isnan(c->jod)) continue;
                worth.push_back({scene, mode, m, c, foveaWorth(byJod, c->jod), foveaWorth(byPsnr, c->jodNearPsnr), lo, hi});
            }
        }
    if (!worth.empty()) {
        std::ofstream wc(dir + "/fovea_worth.csv");
        if (!wc) return Error{1, "cannot write " + dir + "/fovea_worth.csv"};
        wc.precision(7);
        wc << "scene,mode,method,fovea_deg,jod,worth_jod_deg,worth_jod_bound,near_gaze_psnr,worth_psnr_deg,"
              "worth_psnr_bound,fov_min_deg,fov_max_deg,jod_frames\n";
        auto bound = [](FoveaWorth::Bound b) {
            return b == FoveaWorth::Bound::Exact      ? "exact"
                   : b == FoveaWorth::Bound::AtMost   ? "at_most"
                   : b == FoveaWorth::Bound::MoreThan ? "more_than"
                                                      : "unknown";
        };
        for (const Worth& w : worth)
            wc << toString(w.scene) << ',' << toString(w.mode) << ',' << toString(w.method) << ',' << fovea0 << ','
               << w.cell->jod << ',' << w.byJod.deg << ',' << bound(w.byJod.bound) << ',' << w.cell->jodNearPsnr << ','
               << w.byPsnr.deg << ',' << bound(w.byPsnr.bound) << ',' << w.fovMin << ',' << w.fovMax << ','
               << w.cell->jodFrames << '\n';
    }

    auto find = [&](SceneKind scene, FoveationMode mode, Method m, float fovea) {
        return findCell(results, scene, mode, fovea, m);
    };
    const bool cpuDevice = isCpuRenderer(deviceName);

    std::ofstream md(dir + "/table.md");
    if (!md) return Error{1, "cannot write " + dir + "/table.md"};
    md << "# wrsfov benchmark\n\n" << o.width << "x" << o.height
       << (o.monitor ? " (monitor mode: one 76x60 degree view as both eyes)"
                     : o.hmdFovDeg > 0 ? " per eye (HMD stereo, the central " + fmt(o.hmdFovDeg, 0) + "°x" +
                                            fmt(o.hmdFovDeg, 0) + "° of each eye's view)"
                                      : std::string(" per eye (HMD stereo)"))
       << ", " << fmt(centrePixelsPerDegree(o), 1)
       << " px/deg at the view centre (atrium, dynamic; text has its own layout; their procedural materials "
       << (o.materialSamples > 1 ? "filtered over each pixel, " + std::to_string(o.materialSamples) + " shading samples"
                                 : std::string("point-sampled, aliased"))
       << "), " << o.frames << " frames at 90 Hz (" << o.warmup << " warm-up). Times measured on **" << deviceName << "**"
       << (cpuDevice ? " — Mesa lavapipe, a CPU renderer: absolute times say little about a GPU, ratios in the same "
                       "run (×copy, ×fov) say more"
                     : "")
       << ".\n";
    if (o.monitor)
        md << "\nIn monitor mode both views are one image: every method but `wrs-paper` runs the passes (and the "
              "copy kernels) once and copies the result to the right eye; `wrs-paper` draws different random "
              "numbers per eye and runs both, so its GPU time is not comparable with the others' here (compare in "
              "HMD stereo).\n";
    if (std::find(o.scenes.begin(), o.scenes.end(), SceneKind::Sequence) != o.scenes.end())
        md << "\nScene `sequence`: the frames of " << o.sequenceDir
           << " at the fps of its sequence.json, gaze from its gaze.csv (synthetic free viewing without one).\n";
    if (std::find(o.scenes.begin(), o.scenes.end(), SceneKind::Photo) != o.scenes.end())
        md << "\nScene `photo`: " << o.photoImage << " on a plane 1 m away, one texel per pixel at the view's centre, "
           << "head " << scenes::toString(o.photoMotion)
           << (o.photoMotion == scenes::PhotoMotion::Static ? std::string()
                                                            : " at " + fmt(o.photoSpeed, 2) + " px/frame at the view's centre")
           << ", free-viewing gaze.\n";

    // Summary first: per scene and mode, each method against fov at the smallest fovea.
    md << "\n## Summary\n\n";
    const float f0 = o.foveas.front();
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            const CellResult* fov = find(scene, mode, Method::Fov, f0);
            if (!fov) continue;
            md << "- **" << toString(scene) << ", " << toString(mode) << ", fovea " << fmt(f0, 1) << "°**: ";
            const CellResult* oracle = find(scene, mode, Method::Oracle, f0);
            const CellResult* oracleQ = find(scene, mode, Method::OracleQ, f0);
            if (oracle)
                md << "the oracle bound gains " << fmt(oracle->psnr - fov->psnr) << " dB full / "
                   << fmt(oracle->nearPsnr - fov->nearPsnr) << " dB near gaze over fov"
                   << (std::isnan(oracle->jod) ? std::string() : " (JOD " + fmt(oracle->jod) + ")");
            if (oracleQ)
                md << (oracle ? ", the retention bound (oracle-q) " : "the retention bound (oracle-q) gains ")
                   << fmt(oracleQ->psnr - fov->psnr) << " dB full / " << fmt(oracleQ->nearPsnr - fov->nearPsnr)
                   << " dB near gaze" << (std::isnan(oracleQ->jod) ? std::string() : " (JOD " + fmt(oracleQ->jod) + ")");
            if (oracle || oracleQ) md << ". ";
            bool firstM = true;
            for (Method m : o.methods) {
                if (m == Method::Fov || isOracle(m)) continue;
                const CellResult* c = find(scene, mode, m, f0);
                if (!c) continue;
                const double dFull = c->psnr - fov->psnr, dNear = c->nearPsnr - fov->nearPsnr;
                md << (firstM ? "" : "; ") << "`" << toString(m) << "` ";
                if (!std::isnan(dNear) || !std::isnan(dFull))  // NaN: a run without error metrics (--scaling)
                    md << (dNear > 0.05 ? "beats fov by " : dNear < -0.05 ? "loses to fov by " : "ties with fov, ")
                       << fmt(dFull) << " dB full / " << fmt(dNear) << " dB near gaze";
                else
                    md << "runs";
                const bool eta = !std::isnan(c->eta) || !std::isnan(c->etaNear);
                const bool etaQ = !std::isnan(c->etaQ) || !std::isnan(c->etaQNear);
                if (eta || etaQ) {
                    md << " (";
                    if (eta) md << "η " << fmt(c->eta) << " / " << fmt(c->etaNear);
                    if (etaQ) md << (eta ? ", " : "") << "η_q " << fmt(c->etaQ) << " / " << fmt(c->etaQNear);
                    md << ")";
                }
                if (!std::isnan(c->jod)) md << ", JOD " << fmt(c->jod) << " vs fov " << fmt(fov->jod);
                md << " at " << fmt(c->gpu.total / fov->gpu.total) << "× fov's GPU time";
                if (!std::isnan(c->staleMse) && c->staleFraction > 0)
                    md << ", stale-pixel MSE " << fmt(c->staleMse, 5) << " vs fov " << fmt(c->staleFovMse, 5);
                firstM = false;
            }
            md << ".\n";
            for (const Worth& w : worth) {
                if (w.scene != scene || w.mode != mode || w.method != Method::Wrs) continue;
                md << "- **The fovea `wrs` at " << fmt(fovea0, 1) << "° is worth** (the `fov` fovea of equal score, fov "
                   << "swept over " << fmt(w.fovMin, 1) << "–" << fmt(w.fovMax, 1) << "°, linear in the score, over the "
                   << w.cell->jodFrames << " JOD frames): **" << toString(w.byJod) << " by FovVideoVDP** (JOD "
                   << fmt(w.cell->jod) << "), " << toString(w.byPsnr) << " by near-gaze PSNR ("
                   << fmt(w.cell->jodNearPsnr) << " dB). The paper's user study preferred WRS at 5° over FOV at 5° "
                   << "(64 %) and over FOV at 7.5° (62 %): WRS 5° judged about as good as FOV 7.5° or better; by JOD "
                   << "here it is "
                   << (w.byJod.bound == FoveaWorth::Bound::MoreThan || (w.byJod.bound == FoveaWorth::Bound::Exact && w.byJod.deg >= 7.5)
                           ? "as good as fov at 7.5° or better, as the study found"
                       : w.byJod.bound == FoveaWorth::Bound::Unknown ? "not known"
                                                                      : "worth less than fov at 7.5°, less than the study found")
                   << ".\n";
            }
        }

    md << "\n## Columns\n\n"
          "- *near PSNR*: PSNR (dB, sRGB 8-bit) over pixels within 10° of the gaze; *PSNR* over the whole image.\n"
          "- *JOD*: FovVideoVDP v1.2 (our implementation, eval/fvvdp.h, docs/metrics.md), foveated with the run's "
          "gaze, 10 = no visible difference, against the unfoveated reference; display "
       << (o.monitor ? "monitor (200 cd/m², 1000:1, 250 lux)" : "HMD (100 cd/m², black 0.1 cd/m²) for built-in scenes, monitor for sequences")
       << ", geometry from the submitted field of view, "
       << (o.jodFrames > 0 ? "over the last " + std::to_string(std::min(o.jodFrames, o.frames - o.warmup)) + " counted frames"
                           : std::string("over every counted frame"))
       << (o.monitor ? "" : ", mean of the two eyes") << ". *fov (sweep)* rows: fov at the fovea-worth sweep's extra "
          "foveas, submitted and scored over the JOD frames only (fov keeps nothing between frames); their near "
          "PSNR and PSNR are over those frames.\n"
          "- *η* / *η near*: retention efficiency (MSE_fov − MSE) / (MSE_fov − MSE_oracle) in the same cell, "
          "whole image / within 10°: 0 = no better than fov, 1 = as good as the oracle (which keeps, per pixel, "
          "whichever of history and candidate is closer to the reference). n/a without fov and oracle, or when "
          "the oracle removes less than 1 % of fov's MSE there. *η_q* / *η_q near*: the same against the "
          "retention oracle `oracle-q`, which "
          "keeps the history only where it is closer to the reference *and* of higher quality than the candidate: "
          "the ceiling of keeping what foveation throws away, without the oracle's choice among equally or less "
          "sharp samples (which needs the reference to see which of two blurred values happens to be closer).\n"
          "- *SSIM*, *FLIP* (NVIDIA FLIP, 0..1, lower is better): every "
       << o.heavyEvery
       << "th counted frame. *ecc-MSE*: MSE weighted by the cone-density falloff of eccentricity.\n"
          "- *temporal*: temporal instability, the mean absolute frame-to-frame change of the output where the "
          "reference did not change (0..1; lower is steadier).\n"
          "- *stale*: share of pixels showing a sample whose submitted colour when taken is more than 4/255 "
          "outside the 3×3 neighbourhood of the submitted colour now (methods that keep samples); *stale MSE* "
          "the method's MSE over those pixels, *fov there* fov's MSE over the same pixels (every "
       << o.heavyEvery
       << "th frame).\n"
          "- *GPU ms*: median GPU time per frame, both eyes; *×copy*: against a copy kernel moving the same "
          "bytes in the same submission; *×copy floor*: against a copy kernel moving only the method's floor "
          "bytes (see Traffic); *×fov*: against fov in the same cell; *B/px*: bytes the passes read and write per "
          "pixel of one view; *shading*: the fraction of full-rate shading the foveation represents; *retain*: "
          "the share of 8×8 tiles that ran retention (sparse retention skips far tiles that can hold nothing "
          "sharper than their candidates), mean over the counted frames.\n";

    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            md << "\n## " << toString(scene) << ", foveation " << toString(mode) << "\n\n"
               << "| method | fovea | near PSNR | PSNR | JOD | η | η near | η_q | η_q near | SSIM | FLIP | ecc-MSE | temporal "
                  "| stale | stale MSE | fov there | GPU ms | ×copy | ×copy floor | ×fov | B/px | shading | retain |\n"
                  "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
            for (const auto& c : results) {
                if (c.scene != scene || c.mode != mode) continue;
                md << "| " << toString(c.method) << (c.worthSweep ? " (sweep)" : "") << " | " << fmt(c.foveaDeg, 1) << "° | "
                   << fmt(c.nearPsnr) << " | " << fmt(c.psnr) << " | " << fmt(c.jod) << " | " << fmt(c.eta) << " | " << fmt(c.etaNear) << " | " << fmt(c.etaQ) << " | "
                   << fmt(c.etaQNear) << " | " << fmt(c.ssim, 4)
                   << " | " << fmt(c.flip, 4) << " | " << fmt(c.eccMse, 5) << " | " << fmt(c.temporal, 5) << " | "
                   << (std::isnan(c.staleFraction) ? std::string("n/a") : fmt(100 * c.staleFraction, 3) + " %")
                   << " | " << fmt(c.staleMse, 5) << " | " << fmt(c.staleFovMse, 5) << " | " << fmt(c.gpu.total, 3)
                   << " | " << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.gpu.total / c.copyFloorMs) << " | "
                   << fmt(c.gpu.total / c.fovTotalMs) << " | " << fmt(c.traffic.perPixel(), 1) << " | "
                   << fmt(c.shadingFraction, 3) << " | "
                   << (std::isnan(c.retainShare) ? std::string("n/a") : fmt(100 * c.retainShare, 1) + " %") << " |\n";
            }
            float eq = equalQualityFovea(results, scene, mode);
            md << "\nEqual-quality fovea (smallest wrs fovea below 10° with near-gaze PSNR ≥ fov at 10°): "
               << (eq > 0 ? fmt(eq, 1) + "°" : std::string("none in this sweep")) << "\n";
        }

    if (!worth.empty()) {
        md << "\n## The fovea a method is worth\n\n"
              "For each method at "
           << fmt(fovea0, 1)
           << "°, the `fov` fovea that scores the same: fov's JOD (and near-gaze PSNR) against its fovea "
              "diameter, interpolated linearly in the score between the swept foveas; the smallest fovea that "
              "reaches the method's score (\"or less\": fov at the smallest fovea already does; \"more than\": no "
              "swept fovea does). Both scores over the same JOD frames. The paper's user study: WRS at 5° "
              "preferred over FOV at 5° by 64 % and over FOV at 7.5° by 62 % of the answers. fovea_worth.csv "
              "has the figures.\n\n"
              "| scene | mode | method | JOD | worth by JOD | near PSNR (JOD frames) | worth by near PSNR | fov swept |\n"
              "|---|---|---|---|---|---|---|---|\n";
        for (const Worth& w : worth)
            md << "| " << toString(w.scene) << " | " << toString(w.mode) << " | " << toString(w.method) << " | "
               << fmt(w.cell->jod) << " | " << toString(w.byJod) << " | " << fmt(w.cell->jodNearPsnr) << " dB | "
               << toString(w.byPsnr) << " | " << fmt(w.fovMin, 1) << "–" << fmt(w.fovMax, 1) << "° |\n";
    }

    writeTrafficSection(md, results);
    writeBandSection(md, results);

    std::ofstream bands(dir + "/ecc_bands.csv");
    if (!bands) return Error{1, "cannot write " + dir + "/ecc_bands.csv"};
    bands.precision(7);
    bands << "scene,method,mode,fovea_deg,band_lo_deg,band_hi_deg,pixel_share,mse\n";
    for (const auto& c : results)
        for (std::size_t b = 0; b < c.bandMse.size(); ++b)
            bands << toString(c.scene) << ',' << toString(c.method) << ',' << toString(c.mode) << ',' << c.foveaDeg
                  << ',' << kEccBands[b] << ',' << kEccBands[b + 1] << ',' << c.bandShare[b] << ',' << c.bandMse[b]
                  << '\n';

    // Per scene and mode: error against run time, against fovea size, and η per method.
    for (SceneKind scene : o.scenes)
        for (FoveationMode mode : o.modes) {
            std::vector<Series> vsTime, vsFovea, eta, jodTime;
            bool anyJod = false;
            for (Method m : o.methods) {
                Series st{std::string(toString(m)), methodColour(m)}, sf{std::string(toString(m)), methodColour(m)};
                Series se{std::string(toString(m)), methodColour(m)}, sj{std::string(toString(m)), methodColour(m)};
                sf.line = true;
                // Near-gaze PSNR against fovea size: with a fovea-worth sweep, fov's whole curve (5-15°) and
                // every method's point, all over the JOD frames the sweep is scored on (jodNearPsnr).
                const bool worthCurve = std::any_of(results.begin(), results.end(), [&](const CellResult& c) {
                    return c.scene == scene && c.mode == mode && c.worthSweep;
                });
                for (const auto& c : results) {
                    if (c.scene != scene || c.method != m || c.mode != mode) continue;
                    if (worthCurve && std::isfinite(c.jodNearPsnr)) sf.points.push_back({c.foveaDeg, c.jodNearPsnr});
                    // JOD against time: the sweep's fov points too (fov's whole curve).
                    if (!std::isnan(c.jod)) {
                        sj.points.push_back({c.gpu.total, c.jod});
                        sj.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                        anyJod = true;
                    }
                    if (c.worthSweep) continue;
                    st.points.push_back({c.gpu.total, c.nearPsnr});
                    st.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                    if (!worthCurve) sf.points.push_back({c.foveaDeg, c.nearPsnr});
                    se.points.push_back({c.eta, c.etaNear});
                    se.labels.push_back(fmt(c.foveaDeg, 1) + " deg");
                }
                vsTime.push_back(st);
                std::sort(sf.points.begin(), sf.points.end(), [](auto a, auto b) { return a.x < b.x; });
                vsFovea.push_back(sf);
                eta.push_back(se);
                jodTime.push_back(sj);
            }
            const std::string s(toString(scene)), m(toString(mode)), tag = s + "_" + m;
            if (anyJod)
                cv::imwrite(dir + "/jod_vs_time_" + tag + ".png",
                            chart(s + " (" + m + "): FovVideoVDP JOD against GPU time", "GPU ms per frame (both eyes)",
                                  "JOD (10 = no visible difference)", jodTime));
            cv::imwrite(dir + "/error_vs_time_" + tag + ".png",
                        chart(s + " (" + m + "): near-gaze PSNR against GPU time", "GPU ms per frame (both eyes)",
                              "near-gaze PSNR (dB)", vsTime));
            cv::imwrite(dir + "/error_vs_fovea_" + tag + ".png",
                        chart(s + " (" + m + "): near-gaze PSNR against fovea size", "fovea diameter (deg)",
                              "near-gaze PSNR (dB)", vsFovea));
            cv::imwrite(dir + "/eta_" + tag + ".png",
                        chart(s + " (" + m + "): retention efficiency (1 = oracle, 0 = fov)", "eta, whole image",
                              "eta, within 10 deg", eta));
        }
    return {};
}

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
    auto gazeSource = gaze::SyntheticSource::create(gc);
    if (!gazeSource) return benchError("bench: gaze generator: " + gazeSource.error().message);

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

Status writeScalingReport(const std::vector<ScalingStep>& steps, const BenchOptions& o, const std::string& dir,
                          const std::string& deviceName, const std::string& costModel) {
    std::ofstream csv(dir + "/scaling.csv");
    std::ofstream md(dir + "/scaling.md");
    if (!csv || !md) return Error{1, "cannot write " + dir + "/scaling.{csv,md}"};
    csv.precision(7);
    csv << "width,height,scene,method,mode,megapixels_per_frame,total_ms,copy_ms,copy_floor_ms,bytes_per_px,"
           "floor_bytes_per_px,ratio_to_fov,ratio_to_copy,ratio_to_copy_floor,ns_per_px,retain_share\n";
    const bool cpuDevice = isCpuRenderer(deviceName);
    md << "# wrsfov scaling\n\nTime and bytes per frame at " << steps.size() << " sizes, "
       << (o.monitor ? "monitor mode" : "HMD stereo (both eyes)") << ", fovea " << fmt(o.foveas.front(), 1)
       << "°, foveation " << toString(o.modes.front()) << ", " << o.frames - o.warmup << " counted frames per cell, "
       << "stale-pixel tracking off (the passes as an application gets them). Measured on **" << deviceName << "**"
       << (cpuDevice ? " — Mesa lavapipe, a CPU renderer: its timestamps do not bracket dispatches, so times are the "
                       "host's wall clock from submission to completion (PassTimes::hostTimed), and a CPU computes "
                       "rather than moves bytes; ratios in the same run say more than absolute times"
                     : "")
       << ".\n\n*ns/px*: time per pixel of both views: flat when the cost grows linearly with pixels. *×copy*: "
          "against a copy kernel moving the method's bytes, *×copy floor*: the floor's; each size's table.md "
          "(in its WxH directory) has the bytes per pass under Traffic. *retain*: the share of 8×8 tiles that "
          "ran retention over the timed frames (sparse retention: where the gaze has been).\n\n"
          "| size per eye | method | GPU ms | ns/px | ×fov | B/px | floor B/px | copy ms | ×copy | copy floor ms | "
          "×copy floor | retain |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<Method, Series> series;
    for (const ScalingStep& st : steps)
        for (const CellResult& c : st.cells) {
            const double px = double(st.width) * st.height * 2;  // both views
            const double nsPx = c.gpu.total * 1e6 / px;
            csv << st.width << ',' << st.height << ',' << toString(c.scene) << ',' << toString(c.method) << ','
                << toString(c.mode) << ',' << px / 1e6 << ',' << c.gpu.total << ',' << c.copyMs << ',' << c.copyFloorMs
                << ',' << c.traffic.perPixel() << ',' << c.traffic.floor << ',' << c.gpu.total / c.fovTotalMs << ','
                << c.gpu.total / c.copyMs << ',' << c.gpu.total / c.copyFloorMs << ',' << nsPx << ',' << c.retainShare
                << '\n';
            md << "| " << st.width << "×" << st.height << " | " << toString(c.method) << " | " << fmt(c.gpu.total, 2)
               << " | " << fmt(nsPx, 1) << " | " << fmt(c.gpu.total / c.fovTotalMs) << " | "
               << fmt(c.traffic.perPixel(), 1) << " | " << fmt(c.traffic.floor, 1) << " | " << fmt(c.copyMs, 2)
               << " | " << fmt(c.gpu.total / c.copyMs) << " | " << fmt(c.copyFloorMs, 2) << " | "
               << fmt(c.gpu.total / c.copyFloorMs) << " | "
               << (std::isnan(c.retainShare) ? std::string("n/a") : fmt(100 * c.retainShare, 1) + " %") << " |\n";
            auto it = series.find(c.method);
            if (it == series.end())
                it = series.emplace(c.method, Series{std::string(toString(c.method)), methodColour(c.method)}).first;
            it->second.line = true;
            it->second.points.push_back({px / 1e6, c.gpu.total});
        }
    if (!costModel.empty()) md << "\n" << costModel;
    std::vector<Series> all;
    for (auto& [m, s] : series) all.push_back(s);
    cv::imwrite(dir + "/scaling.png", chart("GPU time per frame against pixels (both views)", "megapixels per frame",
                                            "GPU ms per frame", all));
    return {};
}

}  // namespace wrsfov::eval
