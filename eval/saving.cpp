#include "eval/saving.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>
#include <cstring>
#include <tuple>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <cstdio>

#include "compositor/host_app.h"
#include "compositor/reference.h"
#include "layers/jitter.h"
#include "eval/chart.h"
#include "eval/metrics.h"
#include "scenes/atrium.h"
#include "scenes/photo.h"
#include "scenes/text.h"

namespace wrsfov::eval {

std::string_view toString(SavingInput input) {
    switch (input) {
    case SavingInput::Full: return "full";
    case SavingInput::Quad: return "quad";
    case SavingInput::Rate: return "rate";
    }
    return "?";
}

namespace {

constexpr double kPi = 3.14159265358979323846;

Error savingError(const std::string& msg) { return Error{1, "saving: " + msg}; }

glm::vec4 tangents(const layers::Fov& f) {
    return {std::tan(f.angleLeft), std::tan(f.angleRight), std::tan(f.angleUp), std::tan(f.angleDown)};
}
layers::Fov fovOfTangents(glm::dvec4 t) {
    return {float(std::atan(t.x)), float(std::atan(t.y)), float(std::atan(t.z)), float(std::atan(t.w))};
}

// The inset of a quad view: w x h pixels at the display's density (`density`, pixels per tangent unit),
// about `deg` across at the view's centre, centred on the gaze's tangent point (the view's centre
// without a valid gaze), shifted to stay inside the wide view, and placed on whole display pixels, so
// that its pixels are the display's (a compositor resamples it without blurring it).
glm::dvec4 insetTangents(const layers::Fov& wide, const layers::EyeGaze& g, uint32_t w_px, uint32_t h_px,
                         glm::dvec2 density) {
    const glm::dvec4 w = glm::dvec4(tangents(wide));
    const double halfX = 0.5 * w_px / density.x, halfY = 0.5 * h_px / density.y;
    double cx = 0.5 * (w.x + w.y), cy = 0.5 * (w.z + w.w);
    const double len = glm::length(glm::dvec3(g.dir));
    if (g.valid && std::isfinite(len) && len > 1e-6 && g.dir.z < -1e-6f) cx = g.dir.x / -g.dir.z, cy = g.dir.y / -g.dir.z;
    auto place = [](double c, double h, double lo, double hi) {
        if (2 * h >= hi - lo) return std::pair(lo, hi);
        c = std::clamp(c, lo + h, hi - h);
        return std::pair(c - h, c + h);
    };
    auto [l, r] = place(cx, halfX, w.x, w.y);
    auto [d, u] = place(cy, halfY, w.w, w.z);
    // On the display's pixel grid: the left and top edges on whole pixels, the extent exactly w x h.
    l = w.x + std::round((l - w.x) * density.x) / density.x;
    u = w.z - std::round((w.z - u) * density.y) / density.y;
    r = std::min(l + w_px / density.x, w.y);
    d = std::max(u - h_px / density.y, w.w);
    return {l, r, u, d};
}

// Pixels of a view spanning `span` tangent units at `density` pixels per tangent unit (at least 1).
uint32_t pixelsOver(double span, double density) { return uint32_t(std::max(1.0, std::round(span * density))); }

// Pixels per tangent unit of a W x H view over `fov`, across and down.
glm::dvec2 densityOver(uint32_t W, uint32_t H, const layers::Fov& fov) {
    const glm::vec4 t = tangents(fov);
    return {W / (double(t.y) - t.x), H / (double(t.z) - t.w)};
}

double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

// Both eyes' images of one view kind as an application renders them (depth always; motion for the atrium).
struct Views {
    std::array<HostImage, 2> color, depth;
    std::array<std::optional<HostImage>, 2> motion;
};

// A swapchain of two layers (layer = eye) on a compositor.
std::unique_ptr<layers::Swapchain> swapchain(Compositor& c, layers::Usage usage, layers::Format format, uint32_t w,
                                             uint32_t h, Status& status) {
    layers::SwapchainCreateInfo ci;
    ci.usage = usage;
    ci.format = format;
    ci.width = w;
    ci.height = h;
    ci.arraySize = 2;
    auto sc = c.createSwapchain(ci);
    if (!sc) {
        if (status) status = sc.error();
        return nullptr;
    }
    return std::move(*sc);
}
// Writes both layers of the next image (acquire, wait, write, release).
Status put(layers::Swapchain& sc, const HostImage& left, const HostImage& right) {
    auto index = sc.acquire();
    if (!index) return index.error();
    if (Status s = sc.wait(); !s) return s;
    Status s = sc.write(*index, 0, left.bytes());
    if (s) s = sc.write(*index, 1, right.bytes());
    Status r = sc.release();
    return s ? r : s;
}

// The atrium rendered through any views into an owner compositor's swapchains and read back.
class AtriumViews {
public:
    static Result<std::unique_ptr<AtriumViews>> create(vk::Context& ctx, const scenes::AtriumOptions& o) {
        std::unique_ptr<AtriumViews> a(new AtriumViews());
        auto owner = Compositor::create(ctx);
        if (!owner) return owner.error();
        a->owner_ = std::move(*owner);
        auto r = scenes::AtriumRenderer::create(ctx, o);
        if (!r) return r.error();
        a->renderer_ = std::move(*r);
        return a;
    }
    // Both eyes through `fovs` at w x h; `ms` gets the render's device time (timestamps around its render
    // passes), or where the queue has no timestamps its time from submission to completion.
    Status render(double t, double prevT, const std::array<layers::Fov, 2>& fovs, uint32_t w, uint32_t h, Views& out,
                  double* ms, float footprint = 1.0f) {
        auto it = apps_.find({w, h});
        if (it == apps_.end()) {
            HostStereoApp::Options ao;
            ao.width = w;
            ao.height = h;
            ao.color = layers::Format::RGBA8_SRGB;
            ao.depth = layers::Format::D32F;
            ao.motion = layers::Format::RGBA16F;
            auto app = HostStereoApp::create(*owner_, ao);
            if (!app) return app.error();
            it = apps_.emplace(std::pair(w, h), std::move(*app)).first;
        }
        HostStereoApp& app = *it->second;
        return app.drawInPlace([&](const HostStereoApp::Images& im) {
            const auto t0 = std::chrono::steady_clock::now();
            Status s = renderer_->renderViews(t, prevT, fovs, app.color(), im.color, *app.depth(), im.depth,
                                              *app.motion(), im.motion, footprint);
            if (ms) *ms = std::isfinite(renderer_->lastGpuMs()) ? renderer_->lastGpuMs() : msSince(t0);
            for (uint32_t e = 0; e < 2 && s; ++e)
                s = app.readBack(im, e, out.color[e], &out.depth[e], &out.motion[e].emplace());
            return s;
        });
    }

private:
    AtriumViews() = default;
    std::unique_ptr<Compositor> owner_;
    std::unique_ptr<scenes::AtriumRenderer> renderer_;
    std::map<std::pair<uint32_t, uint32_t>, std::unique_ptr<HostStereoApp>> apps_;
};

// One composition of the study: an input at an inset size, composed with one method.
struct Run {
    SavingInput input = SavingInput::Full;
    Method method = Method::Fov;
    float insetDeg = 0.0f;
    uint32_t insetW = 0, insetH = 0;
    std::unique_ptr<Compositor> comp;
    std::unique_ptr<layers::Swapchain> color, depth, motion, insetColor, insetDepth, insetMotion, rateMap, reference;
    std::vector<double> composeMs;
    double retainShareSum = 0;  // over the timed frames that ran the retain pass
    int retainFrames = 0;
    std::array<std::unique_ptr<JodMetric>, 2> jod;
    double mseSum = 0, nearMseSum = 0;
    int scored = 0;
    double pixelSum = 0;  // over the frames: pixels (or shaded samples) rendered
    int frames = 0;
    std::array<TemporalInstability, 2> instability;
    std::unique_ptr<Reference> ref;  // SavingOptions::outcomes
    SavingOutcomes outcomes;
    std::array<std::vector<glm::uvec4>, 2> history;  // the compositor's reservoirs after the last frame
    std::array<std::vector<float>, 2> held;          // and its held qualities
};

// SavingOptions::outcomes: steps the run's reference on the frame its compositor just composed (the same
// composed inputs: composeQuadViews of the same sources and parameters), from the compositor's own
// history of the frame before (its reservoirs and held qualities, read back before the frame), so that
// the outcomes counted are the compositor's decisions and a near-threshold difference does not carry
// into later frames. On a scored frame it counts each evaluated pixel's outcome by whether its history
// was sharper than the wide views' quality (the lowest a quad-view frame has), and the reservoirs where
// the reference and the compositor disagree.
Status tallyOutcomes(Run& r, const std::array<QuadSources, 2>& sources, const std::array<const HostImage*, 2>& full,
                     int evalEyes, bool scored) {
    std::array<Reference::EyeInput, 2> in;
    for (uint32_t e = 0; e < 2; ++e) {
        in[e] = composeQuadViews(r.comp->lastComposeParams(), e, sources[e]);
        if (isOracle(r.method)) in[e].reference = *full[e];
        if (r.frames > 1) r.ref->setHistory(e, r.history[e], r.held[e]);
    }
    r.ref->step(r.comp->lastParams(), in);
    for (uint32_t e = 0; e < 2; ++e) {
        auto res = r.comp->readReservoirs(e);
        if (!res) return res.error();
        auto held = r.comp->readTileHeld(e);
        if (!held) return held.error();
        const std::vector<glm::uvec4>& cpu = r.ref->reservoirs(e);
        if (scored && int(e) < evalEyes) {
            const float floorQ = r.comp->lastComposeParams().eye[e].wide_motion.w;
            const float sharper = floorQ * (1.0f + gpu::WRS_Q_EQUAL);
            const auto& trace = r.ref->trace(e);
            for (std::size_t i = 0; i < trace.size(); ++i) {
                const Reference::Trace& t = trace[i];
                const bool held = t.hadHistory && t.source < r.history[e].size();
                const gpu::Tracked h = held ? gpu::wrs_unpack_tracked(r.history[e][t.source]) : gpu::Tracked{};
                const bool sharp = held && h.q > sharper;
                const bool landed = sharp && (h.flags & gpu::WRS_FLAG_LANDED) != 0u;
                const int cls = !sharp ? 0 : landed ? 3 : in[e].quality[i] > sharper ? 1 : 2;
                const uint32_t k = t.skipped ? SavingOutcomes::kOutcomes - 1 : t.outcome;
                if (k < uint32_t(SavingOutcomes::kOutcomes)) ++r.outcomes.count[cls][k];
                if (t.gapShown) ++r.outcomes.gapShown;
            }
            for (std::size_t i = 0; i < cpu.size() && i < res->size(); ++i)
                if (cpu[i] != (*res)[i]) ++r.outcomes.differing;
            r.outcomes.reservoirs += cpu.size();
        }
        r.history[e] = std::move(*res);
        r.held[e] = std::move(*held);
    }
    return {};
}

double mseFromPsnr(double p) { return std::isinf(p) ? 0.0 : std::pow(10.0, -p / 10.0); }
double psnrFromMse(double m) { return m <= 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(1.0 / m); }

// VK_KHR_fragment_shading_rate values of the study's rates: 1x1, 2x2, 4x4.
constexpr uint8_t kRate1x1 = 0, kRate2x2 = 5, kRate4x4 = 10;

// A gaze-centred rate map: 1x1 within deg / 2 of the gaze, 2x2 out to deg, 4x4 beyond (texel centres).
HostImage rateMapFor(const layers::Fov& fov, uint32_t W, uint32_t H, uint32_t T, const layers::EyeGaze& g, float deg) {
    const uint32_t mw = (W + T - 1) / T, mh = (H + T - 1) / T;
    HostImage map = HostImage::make(layers::Format::R8UI, mw, mh);
    glm::vec3 gaze = g.dir;
    const glm::vec4 t = tangents(fov);
    if (!(g.valid && glm::length(gaze) > 1e-6f)) gaze = glm::vec3(0.5f * (t.x + t.y), 0.5f * (t.z + t.w), -1.0f);
    gaze = glm::normalize(gaze);
    for (uint32_t y = 0; y < mh; ++y)
        for (uint32_t x = 0; x < mw; ++x) {
            const float cx = std::min(float(x * T) + 0.5f * T, float(W)), cy = std::min(float(y * T) + 0.5f * T, float(H));
            const glm::vec3 ray = pixelDirection(fov, W, H, cx - 0.5f, cy - 0.5f);
            const double e = std::acos(std::clamp(double(glm::dot(ray, gaze)), -1.0, 1.0)) * 180.0 / kPi;
            map.store(x, y, glm::vec4(e < 0.5 * deg ? kRate1x1 : e < deg ? kRate2x2 : kRate4x4, 0, 0, 0));
        }
    return map;
}

}  // namespace

Result<std::vector<SavingRow>> runSaving(vk::Context& ctx, SceneKind scene, const SavingOptions& so) {
    if (!isAtriumScene(scene) && scene != SceneKind::Text && scene != SceneKind::Photo)
        return savingError("the study renders the atrium, dynamic, thin, the text page or the photo, not scene " +
                           std::string(toString(scene)));
    if (so.split != "train" && so.split != "test") return savingError("the split must be train or test, not " + so.split);
    if (so.insetDegs.empty()) return savingError("no inset sizes");
    for (float d : so.insetDegs)
        if (!(d > 0.0f && d < 170.0f)) return savingError("inset sizes must be in (0°, 170°)");
    if (!(so.wideScale > 0.0f && so.wideScale <= 1.0f)) return savingError("the wide views' density must be in (0, 1]");
    if (so.rateTexel < 4 || so.rateTexel > 64 || (so.rateTexel & (so.rateTexel - 1)))
        return savingError("the rate-map texel must be a power of two from 4 to 64");
    if (so.methods.empty()) return savingError("no methods");
    const BenchOptions& o = so.bench;
    if (o.frames < 1 || o.warmup < 0 || o.warmup >= o.frames) return savingError("needs 0 <= warmup < frames");
    const uint32_t W = o.width, H = o.height;
    const int evalEyes = o.monitor ? 1 : 2;  // monitor mode: one view, shown to both eyes
    const int jodFrames = std::clamp(o.jodFrames > 0 ? o.jodFrames : o.frames - o.warmup, 1, o.frames - o.warmup);
    const int firstScored = o.frames - jodFrames;

    std::unique_ptr<AtriumViews> atriumViews;
    std::unique_ptr<scenes::TextScene> text;
    std::unique_ptr<scenes::PhotoScene> photo;
    if (isAtriumScene(scene)) {
        auto a = AtriumViews::create(ctx, atriumOptions(o, scene));
        if (!a) return a.error();
        atriumViews = std::move(*a);
    } else if (scene == SceneKind::Photo) {
        auto p = scenes::PhotoScene::create(photoOptions(o));
        if (!p) return p.error();
        photo = std::move(*p);
    } else {
        scenes::TextOptions to;
        to.width = W;
        to.height = H;
        to.seed = o.seed;
        to.monitor = o.monitor;
        text = std::make_unique<scenes::TextScene>(to);
    }
    // The scene through any views; the text page is static, so its views depend on the views alone.
    std::map<std::tuple<float, float, float, float, uint32_t, uint32_t, float>, Views> textCache;
    int frameIndex = 0;  // the photo's frame (its motion is per frame)
    auto render = [&](const std::array<layers::Fov, 2>& fovs, uint32_t w, uint32_t h, double t, double prevT,
                      Views& out, double* ms, float footprint = 1.0f) -> Status {
        if (ms) *ms = std::numeric_limits<double>::quiet_NaN();
        if (atriumViews) return atriumViews->render(t, prevT, fovs, w, h, out, ms, footprint);
        if (photo) {
            const double f = frameIndex, pf = frameIndex > 0 ? frameIndex - 1 : 0;
            for (int e = 0; e < 2; ++e) {
                if (e == 1 && o.monitor && std::memcmp(&fovs[0], &fovs[1], sizeof(layers::Fov)) == 0) {
                    out.color[1] = out.color[0];
                    out.depth[1] = out.depth[0];
                    out.motion[1] = out.motion[0];
                    break;
                }
                HostImage m;
                if (Status s = photo->renderViewAt(f, pf, e, fovs[e], w, h, out.color[e], out.depth[e], m); !s) return s;
                out.motion[e] = std::move(m);
            }
            return {};
        }
        const auto key =
            std::make_tuple(fovs[0].angleLeft, fovs[0].angleUp, fovs[1].angleLeft, fovs[1].angleUp, w, h, footprint);
        if (auto it = textCache.find(key); it != textCache.end()) {
            out = it->second;
            return {};
        }
        text->renderViews(fovs, w, h, out.color, out.depth, footprint);
        if (textCache.size() > 64) textCache.clear();  // the insets move with the gaze: keep a few
        textCache.emplace(key, out);
        return {};
    };

    std::vector<Run> runs;
    std::array<layers::Fov, 2> fullFov{};
    glm::dvec2 density{0, 0};
    uint32_t wideW = 0, wideH = 0;
    std::vector<double> fullRenderMs, wideRenderMs;
    std::map<float, std::vector<double>> insetRenderMs;
    HostStereoApp::Options app;
    double prevT = 0;

    auto setUp = [&](const SceneFrameInfo& info, const std::array<EyeSubmission, 2>& eyes) -> Status {
        app = info.app;
        for (int e = 0; e < 2; ++e) fullFov[e] = eyes[e].fov;
        density = densityOver(W, H, fullFov[0]);
        const QuadViewSizes wideSizes = quadViewSizes(W, H, fullFov[0], so.wideScale, so.insetDegs.front());
        wideW = wideSizes.wideW;
        wideH = wideSizes.wideH;
        const bool hasDepth = eyes[0].depth.has_value(), hasMotion = eyes[0].motion.has_value();
        const layers::Format depthFmt = hasDepth ? eyes[0].depth->format : layers::Format::R32F;
        auto add = [&](SavingInput in, Method m, float deg) -> Status {
            Run r;
            r.input = in;
            r.method = m;
            r.insetDeg = deg;
            CompositorConfig cfg = compositorConfig(o);
            cfg.method = m;
            cfg.foveation = FoveationMode::None;  // the full-resolution row: composed as submitted
            auto c = Compositor::create(ctx, cfg);
            if (!c) return c.error();
            r.comp = std::move(*c);
            Status st;
            Compositor& comp = *r.comp;
            const bool quad = in == SavingInput::Quad;
            const uint32_t cw = quad ? wideW : W, ch = quad ? wideH : H;
            r.color = swapchain(comp, layers::Usage::Color, layers::Format::RGBA8_SRGB, cw, ch, st);
            if (hasDepth) r.depth = swapchain(comp, layers::Usage::Depth, depthFmt, cw, ch, st);
            if (hasMotion) r.motion = swapchain(comp, layers::Usage::Motion, layers::Format::RGBA16F, cw, ch, st);
            if (quad) {
                const QuadViewSizes sizes = quadViewSizes(W, H, fullFov[0], so.wideScale, deg);
                r.insetW = sizes.insetW;
                r.insetH = sizes.insetH;
                r.insetColor = swapchain(comp, layers::Usage::Color, layers::Format::RGBA8_SRGB, r.insetW, r.insetH, st);
                if (hasDepth) r.insetDepth = swapchain(comp, layers::Usage::Depth, depthFmt, r.insetW, r.insetH, st);
                if (hasMotion)
                    r.insetMotion = swapchain(comp, layers::Usage::Motion, layers::Format::RGBA16F, r.insetW, r.insetH, st);
            } else if (in == SavingInput::Rate) {
                const uint32_t T = so.rateTexel;
                r.rateMap = swapchain(comp, layers::Usage::ShadingRate, layers::Format::R8UI, (W + T - 1) / T,
                                      (H + T - 1) / T, st);
            }
            if (in != SavingInput::Full && isOracle(m))
                r.reference = swapchain(comp, layers::Usage::Color, layers::Format::RGBA8_SRGB, W, H, st);
            if (so.outcomes && quad && (m == Method::Wrs || m == Method::Oracle)) r.ref = std::make_unique<Reference>(cfg);
            if (!st) return st;
            for (int e = 0; e < evalEyes && so.jod; ++e) {
                auto j = makeJodMetric(ctx, jodOptions(o, scene, W, H, tangents(fullFov[e]), info.fps));
                if (!j) return j.error();
                r.jod[e] = std::move(*j);
            }
            runs.push_back(std::move(r));
            return {};
        };
        if (Status s = add(SavingInput::Full, Method::Fov, 0.0f); !s) return s;
        for (float deg : so.insetDegs)
            for (Method m : so.methods)
                if (Status s = add(SavingInput::Quad, m, deg); !s) return s;
        if (so.rate)
            for (float deg : so.rateDegs.empty() ? so.insetDegs : so.rateDegs)
                for (Method m : so.methods)
                    if (m == Method::Fov || m == Method::Wrs)
                        if (Status s = add(SavingInput::Rate, m, deg); !s) return s;
        return {};
    };

    // --write-outputs (BenchOptions::outputsDir): what the metrics score, every run's output of each scored
    // frame as PNG, DIR/SCENE/RUN/{L,R}/NNNNNN.png (RUN: full_fov, the reference, or INPUT_METHOD[_INSET]),
    // numbered from the first scored frame, and the left eye's gaze in pixels (gaze.csv).
    const std::string outDir = o.outputsDir.empty() ? std::string() : o.outputsDir + "/" + std::string(toString(scene));
    std::ofstream gazeCsv;
    auto runName = [&](const Run& r) {
        std::ostringstream n;
        n << toString(r.input) << "_" << toString(r.method);
        if (r.input != SavingInput::Full) n << "_" << r.insetDeg;
        return n.str();
    };
    auto writeOutput = [&](const Run& r, int e, int k, const cv::Mat& rgb) -> Status {
        const std::string dir = outDir + "/" + runName(r) + (e == 0 ? "/L" : "/R");
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (ec) return savingError("cannot create " + dir + ": " + ec.message());
        cv::Mat bgr8;
        rgb.convertTo(bgr8, CV_8UC3, 255.0);
        cv::cvtColor(bgr8, bgr8, cv::COLOR_RGB2BGR);
        char file[32];
        std::snprintf(file, sizeof file, "/%06d.png", k);
        if (!cv::imwrite(dir + file, bgr8)) return savingError("cannot write " + dir + file);
        return {};
    };
    auto visit = [&](const SceneFrameInfo& info, int f, double t, std::array<EyeSubmission, 2>& eyes) -> Status {
        if (runs.empty())
            if (Status s = setUp(info, eyes); !s) return s;
        const double pt = f == 0 ? t : prevT;
        prevT = t;
        frameIndex = f;
        const bool scored = f >= firstScored;
        // What the application renders this frame: the full-resolution views (the scene's own frame;
        // rendered again on the scored frames only to time them), the wide views, each inset on the gaze,
        // and for the shading rates the views at half and a quarter of the resolution (a 2x2 or 4x4 block's
        // one sample is the centre of the block, as a pixel of those views is).
        if (scored && atriumViews) {
            Views scratch;
            double ms = 0;
            if (Status s = render(fullFov, W, H, t, pt, scratch, &ms); !s) return s;
            fullRenderMs.push_back(ms);
        }
        Views wide, half, quarter;
        double ms = 0;
        // Jittered wide views (SavingOptions::jitterPhases): the projection shifted by this frame's phase,
        // materials filtered over the display's pixel; submitted with the shift as their sample offset. The
        // sequence starts at phase seed - 1 (seed 1: at its start), so seeds differ in the jitter too.
        const glm::vec2 jitter = layers::haltonJitter(uint64_t(f) + (o.seed - 1), so.jitterPhases);
        std::array<layers::Fov, 2> wideFov = fullFov;
        if (so.jitterPhases > 1)
            for (int e = 0; e < 2; ++e) wideFov[e] = layers::jitteredFov(fullFov[e], jitter, wideW, wideH);
        const float footprint = so.jitterPhases > 1 ? so.wideScale : 1.0f;
        if (Status s = render(wideFov, wideW, wideH, t, pt, wide, &ms, footprint); !s) return s;
        if (scored) wideRenderMs.push_back(ms);
        if (so.rate) {
            if (Status s = render(fullFov, (W + 1) / 2, (H + 1) / 2, t, pt, half, nullptr); !s) return s;
            if (Status s = render(fullFov, (W + 3) / 4, (H + 3) / 4, t, pt, quarter, nullptr); !s) return s;
        }
        std::map<float, std::pair<Views, std::array<glm::dvec4, 2>>> insets;
        struct Rated {
            std::array<HostImage, 2> maps, colour;
            double samples = 0;  // shaded samples of the views the application renders
        };
        std::map<float, Rated> rates;
        std::array<cv::Mat, 2> reference;
        for (Run& r : runs) {
            layers::FrameEndInfo fe;
            fe.frameIndex = uint64_t(f) + 1;
            fe.time_s = t;
            layers::ProjectionLayer layer;
            Status s;
            std::array<layers::Fov, 2> insetFov{};
            if (r.input == SavingInput::Full) {
                s = put(*r.color, eyes[0].color, eyes[1].color);
                if (s && r.depth) s = put(*r.depth, *eyes[0].depth, *eyes[1].depth);
                if (s && r.motion) s = put(*r.motion, *eyes[0].motion, *eyes[1].motion);
            } else if (r.input == SavingInput::Quad) {
                auto it = insets.find(r.insetDeg);
                if (it == insets.end()) {
                    std::array<glm::dvec4, 2> tan;
                    for (int e = 0; e < 2; ++e) tan[e] = insetTangents(fullFov[e], eyes[e].gaze, r.insetW, r.insetH, density);
                    Views v;
                    double ims = 0;
                    if (Status rs = render({fovOfTangents(tan[0]), fovOfTangents(tan[1])}, r.insetW, r.insetH, t, pt, v,
                                           &ims);
                        !rs)
                        return rs;
                    if (scored) insetRenderMs[r.insetDeg].push_back(ims);
                    it = insets.emplace(r.insetDeg, std::pair(std::move(v), tan)).first;
                }
                const Views& in = it->second.first;
                for (int e = 0; e < 2; ++e) insetFov[e] = fovOfTangents(it->second.second[e]);
                s = put(*r.color, wide.color[0], wide.color[1]);
                if (s) s = put(*r.insetColor, in.color[0], in.color[1]);
                if (s && r.depth) s = put(*r.depth, wide.depth[0], wide.depth[1]);
                if (s && r.insetDepth) s = put(*r.insetDepth, in.depth[0], in.depth[1]);
                if (s && r.motion) s = put(*r.motion, *wide.motion[0], *wide.motion[1]);
                if (s && r.insetMotion) s = put(*r.insetMotion, *in.motion[0], *in.motion[1]);
                r.pixelSum += evalEyes * (double(wideW) * wideH + double(r.insetW) * r.insetH);
            } else {
                auto it = rates.find(r.insetDeg);
                if (it == rates.end()) {
                    Rated rated;
                    std::array<HostImage, 2>&maps = rated.maps, &colour = rated.colour;
                    double& samples = rated.samples;
                    for (int e = 0; e < 2; ++e) {
                        maps[e] = rateMapFor(fullFov[e], W, H, so.rateTexel, eyes[e].gaze, r.insetDeg);
                        colour[e] = HostImage::make(layers::Format::RGBA8_SRGB, W, H);
                        const std::size_t tb = colour[e].texelBytes();
                        for (uint32_t y = 0; y < H; ++y)
                            for (uint32_t x = 0; x < W; ++x) {
                                const uint8_t v = uint8_t(maps[e].data[(y / so.rateTexel) * maps[e].width + x / so.rateTexel]);
                                const HostImage& src = v == kRate1x1 ? eyes[e].color : v == kRate2x2 ? half.color[e] : quarter.color[e];
                                const uint32_t k = v == kRate1x1 ? 1 : v == kRate2x2 ? 2 : 4;
                                std::memcpy(colour[e].data.data() + (std::size_t(y) * W + x) * tb,
                                            src.data.data() + (std::size_t(y / k) * src.width + x / k) * tb, tb);
                                if (e < evalEyes) samples += 1.0 / double(k * k);
                            }
                    }
                    it = rates.emplace(r.insetDeg, std::move(rated)).first;
                }
                r.pixelSum += it->second.samples;
                s = put(*r.rateMap, it->second.maps[0], it->second.maps[1]);
                if (s) s = put(*r.color, it->second.colour[0], it->second.colour[1]);
                if (s && r.depth) s = put(*r.depth, *eyes[0].depth, *eyes[1].depth);
                if (s && r.motion) s = put(*r.motion, *eyes[0].motion, *eyes[1].motion);
            }
            if (s && r.reference) s = put(*r.reference, eyes[0].color, eyes[1].color);
            if (!s) return s;
            const uint32_t cw = r.input == SavingInput::Quad ? wideW : W, ch = r.input == SavingInput::Quad ? wideH : H;
            for (uint32_t eye = 0; eye < 2; ++eye) {
                // Monitor mode: one view as both eyes, so the compositor works once (FrameStats::monoViews).
                const uint32_t e = o.monitor ? 0u : eye;
                layers::ProjectionView v;
                v.fov = fullFov[e];
                v.color = {r.color.get(), {0, 0, cw, ch}, e};
                if (r.input == SavingInput::Quad) v.sampleOffset = jitter;
                if (r.depth) v.depth = layers::DepthInfo{{r.depth.get(), {0, 0, cw, ch}, e}, app.nearZ, app.farZ, app.reversedZ};
                if (r.motion) v.motion = layers::MotionInfo{{r.motion.get(), {0, 0, cw, ch}, e}};
                if (r.input == SavingInput::Quad) {
                    layers::InsetView in;
                    in.fov = insetFov[e];
                    in.color = {r.insetColor.get(), {0, 0, r.insetW, r.insetH}, e};
                    if (r.insetDepth)
                        in.depth = layers::DepthInfo{{r.insetDepth.get(), {0, 0, r.insetW, r.insetH}, e}, app.nearZ,
                                                     app.farZ, app.reversedZ};
                    if (r.insetMotion) in.motion = layers::MotionInfo{{r.insetMotion.get(), {0, 0, r.insetW, r.insetH}, e}};
                    v.inset = in;
                }
                if (r.rateMap) {
                    const uint32_t T = so.rateTexel;
                    v.rateMap = layers::RateMapInfo{{r.rateMap.get(), {0, 0, (W + T - 1) / T, (H + T - 1) / T}, e}, T, T};
                }
                if (r.reference) v.reference = layers::SubImage{r.reference.get(), {0, 0, W, H}, e};
                layer.views.push_back(v);
                fe.gaze[eye] = eyes[e].gaze;
            }
            if (r.input == SavingInput::Quad) layer.outputWidth = W, layer.outputHeight = H;
            fe.layers.push_back(std::move(layer));
            if (Status es = r.comp->endFrame(fe); !es)
                return savingError(std::string(toString(r.input)) + " " + std::string(toString(r.method)) + " at " +
                                   std::to_string(r.insetDeg) + "°, frame " + std::to_string(f) + ": " + es.message());
            r.frames++;
            if (r.ref) {
                const Views& in = insets.at(r.insetDeg).first;
                std::array<QuadSources, 2> src;
                for (uint32_t eye = 0; eye < 2; ++eye) {
                    const uint32_t e = o.monitor ? 0u : eye;
                    src[eye] = {wide.color[e], std::nullopt, std::nullopt, in.color[e], std::nullopt, std::nullopt};
                    if (r.depth) src[eye].wideDepth = wide.depth[e], src[eye].insetDepth = in.depth[e];
                    if (r.motion) src[eye].wideMotion = wide.motion[e], src[eye].insetMotion = in.motion[e];
                }
                const uint32_t e1 = o.monitor ? 0u : 1u;
                if (Status ts = tallyOutcomes(r, src, {&eyes[0].color, &eyes[e1].color}, evalEyes, scored); !ts) return ts;
            }
            if (r.input == SavingInput::Full) r.pixelSum += evalEyes * double(W) * H;
            if (f >= o.warmup) r.composeMs.push_back(r.comp->stats().gpu.total);
            if (f >= o.warmup && r.comp->stats().retained)
                r.retainShareSum += r.comp->stats().retainShare(), r.retainFrames++;
            if (!scored) continue;
            for (int e = 0; e < evalEyes; ++e) {
                auto out = r.comp->readOutput(uint32_t(e));
                if (!out) return out.error();
                const cv::Mat test = toMat(*out);
                // The reference: the full-resolution frame as the first run (composed as submitted) shows it.
                if (r.input == SavingInput::Full) reference[e] = test;
                const gpu::EyeParams& ep = r.comp->lastParams().eye[e];
                r.mseSum += meanSquaredError(reference[e], test);
                r.nearMseSum += mseFromPsnr(nearGazePsnr(reference[e], test, eccentricityMap(W, H, ep)));
                r.instability[e].addFrame(reference[e], test);
                if (!outDir.empty()) {
                    const int k = f - firstScored;
                    if (Status ws = writeOutput(r, e, k, test); !ws) return ws;
                    if (r.input == SavingInput::Full && e == 0) {
                        if (!gazeCsv.is_open()) {
                            gazeCsv.open(outDir + "/gaze.csv");
                            if (!gazeCsv) return savingError("cannot write " + outDir + "/gaze.csv");
                            gazeCsv << "frame,left_x,left_y\n";
                        }
                        const glm::vec2 g = gazePixelF(ep, W, H);
                        gazeCsv << k << ',' << g.x << ',' << g.y << '\n';
                    }
                }
                if (!r.jod[e]) continue;
                if (Status js = r.jod[e]->push(test, reference[e], gazePixelF(ep, W, H)); !js) return js;
            }
            r.scored++;
        }
        if (o.progress && ((f + 1) % 30 == 0 || f + 1 == o.frames))
            o.progress("saving " + std::string(toString(scene)) + ": frame " + std::to_string(f + 1) + "/" +
                       std::to_string(o.frames) + ", " + std::to_string(runs.size()) + " compositions");
        return {};
    };
    if (Status s = forEachSceneFrame(ctx, scene, o, visit); !s) return s.error();

    std::vector<SavingRow> rows;
    for (Run& r : runs) {
        SavingRow row;
        row.scene = scene;
        row.input = r.input;
        row.method = r.method;
        row.insetDeg = r.insetDeg;
        row.pixelsRendered = r.frames ? r.pixelSum / r.frames : 0.0;
        row.composeMs = median(r.composeMs);
        if (r.retainFrames) row.retainShare = r.retainShareSum / r.retainFrames;
        if (r.ref) row.outcomes = r.outcomes;
        if (atriumViews && r.input == SavingInput::Full) row.renderMs = median(fullRenderMs);
        if (atriumViews && r.input == SavingInput::Quad) row.renderMs = median(wideRenderMs) + median(insetRenderMs[r.insetDeg]);
        const double n = double(std::max(1, r.scored * evalEyes));
        row.mse = r.mseSum / n;
        double ti = 0;
        for (int e = 0; e < evalEyes; ++e) ti += r.instability[e].mean();
        row.temporalInstability = ti / evalEyes;
        if (r.input == SavingInput::Quad) row.wideScale = so.wideScale, row.jitterPhases = so.jitterPhases;
        if (atriumViews) {
            row.headPath = std::string(scenes::toString(o.path));
            row.headDegPerS = scenes::headDegPerS(o.path);
        } else if (photo) {
            row.headPath = "photo-" + std::string(scenes::toString(o.photoMotion));
            row.headDegPerS = std::numeric_limits<double>::quiet_NaN();
        }
        row.seed = o.seed;
        row.split = so.split;
        row.nearGazePsnr = psnrFromMse(r.nearMseSum / n);
        if (so.jod) {
            double jod = 0;
            for (int e = 0; e < evalEyes; ++e) {
                auto j = r.jod[e]->jod();
                if (!j) return j.error();
                jod += *j;
            }
            row.jod = jod / evalEyes;
        }
        rows.push_back(row);
    }
    // Retention efficiency against the oracle of the same input and inset, and against the retention oracle
    // (n/a without both rows, or where the bound removes under 1 % of fov's error).
    for (SavingRow& row : rows) {
        auto mseOf = [&](Method m) {
            for (const SavingRow& x : rows)
                if (x.input == row.input && x.insetDeg == row.insetDeg && x.method == m) return x.mse;
            return std::numeric_limits<double>::quiet_NaN();
        };
        const double fov = mseOf(Method::Fov);
        auto against = [&](Method bound) {
            const double b = mseOf(bound);
            return fov - b > 0.01 * fov ? (fov - row.mse) / (fov - b) : std::numeric_limits<double>::quiet_NaN();
        };
        row.eta = against(Method::Oracle);
        row.etaQ = against(Method::OracleQ);
    }
    return rows;
}

QuadViewSizes quadViewSizes(uint32_t W, uint32_t H, const layers::Fov& fov, float wideScale, float insetDeg) {
    const glm::dvec2 density = densityOver(W, H, fov);
    const double span = 2.0 * std::tan(0.5 * insetDeg * kPi / 180.0);
    return {std::max(1u, uint32_t(std::lround(W * double(wideScale)))),
            std::max(1u, uint32_t(std::lround(H * double(wideScale)))), std::min(pixelsOver(span, density.x), W),
            std::min(pixelsOver(span, density.y), H)};
}

FoveaWorth insetForJod(const std::vector<SavingRow>& rows, SceneKind scene, Method method, double targetJod) {
    std::vector<std::pair<double, double>> curve;
    for (const SavingRow& r : rows)
        if (r.scene == scene && r.input == SavingInput::Quad && r.method == method) curve.push_back({r.insetDeg, r.jod});
    return foveaWorth(std::move(curve), targetJod);
}

std::string savingNumber(const char* printfFormat, double v) {
    if (!std::isfinite(v)) return std::isinf(v) && v > 0 ? "∞" : "n/a";
    char buf[64];
    std::snprintf(buf, sizeof buf, printfFormat, v);
    return buf;
}

namespace {

std::string fmt(const char* f, double v) { return savingNumber(f, v); }

// Pixels and render time of quad views at an inset of `deg` (between the study's sizes): the pixels
// grow as a + b tan^2(deg / 2) (the inset's square), fitted through the smallest and the largest inset;
// the render time linearly in the pixels between the two insets around `deg`.
struct QuadCost {
    double pixels = std::numeric_limits<double>::quiet_NaN(), renderMs = std::numeric_limits<double>::quiet_NaN();
};
QuadCost quadCost(const std::vector<const SavingRow*>& quad, double deg) {
    QuadCost c;
    if (quad.size() < 2 || !std::isfinite(deg)) return c;
    auto t2 = [](double d) { const double t = std::tan(0.5 * d * kPi / 180.0); return t * t; };
    const SavingRow &lo = *quad.front(), &hi = *quad.back();
    const double b = (hi.pixelsRendered - lo.pixelsRendered) / (t2(hi.insetDeg) - t2(lo.insetDeg));
    c.pixels = lo.pixelsRendered + b * (t2(deg) - t2(lo.insetDeg));
    for (std::size_t i = 1; i < quad.size(); ++i)
        if (deg <= quad[i]->insetDeg || i + 1 == quad.size()) {
            const SavingRow &a = *quad[i - 1], &z = *quad[i];
            const double f = (c.pixels - a.pixelsRendered) / (z.pixelsRendered - a.pixelsRendered);
            c.renderMs = a.renderMs + (z.renderMs - a.renderMs) * f;
            break;
        }
    return c;
}

}  // namespace

Status writeSavingReport(const std::vector<SavingRow>& rows, const SavingOptions& so, const std::string& dir,
                         const std::string& deviceName, std::string* headline) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (rows.empty()) return savingError("no rows to report");
    const SceneKind scene = rows.front().scene;
    const BenchOptions& o = so.bench;
    {
        std::ofstream csv(dir + "/saving.csv");
        if (!csv) return savingError("cannot write " + dir + "/saving.csv");
        csv << "scene,input,method,inset_deg,pixels_rendered,render_ms,compose_ms,jod,near_gaze_psnr,wide_density,jitter,"
               "temporal_instability,head_path,head_deg_per_s,seed,split\n";
        csv << std::setprecision(6);
        for (const SavingRow& r : rows)
            csv << toString(r.scene) << ',' << toString(r.input) << ',' << toString(r.method) << ',' << r.insetDeg << ','
                << std::llround(r.pixelsRendered) << ',' << r.renderMs << ',' << r.composeMs << ',' << r.jod << ','
                << r.nearGazePsnr << ',' << r.wideScale << ',' << r.jitterPhases << ',' << r.temporalInstability << ','
                << r.headPath << ',' << r.headDegPerS << ',' << r.seed << ',' << r.split << '\n';
    }
    const SavingRow* full = nullptr;
    for (const SavingRow& r : rows)
        if (r.input == SavingInput::Full) full = &r;
    auto quadOf = [&](Method m) {
        std::vector<const SavingRow*> q;
        for (const SavingRow& r : rows)
            if (r.input == SavingInput::Quad && r.method == m) q.push_back(&r);
        std::sort(q.begin(), q.end(), [](auto* a, auto* b) { return a->insetDeg < b->insetDeg; });
        return q;
    };
    auto row = [&](SavingInput in, Method m, float deg) -> const SavingRow* {
        for (const SavingRow& r : rows)
            if (r.input == in && r.method == m && r.insetDeg == deg) return &r;
        return nullptr;
    };
    const bool cpu = deviceName.find("llvmpipe") != std::string::npos || deviceName.find("lavapipe") != std::string::npos;
    const bool hasRender = full && std::isfinite(full->renderMs);

    // The headline: the inset with WRS (and the oracle's) that matches composition alone at 30° and 20°.
    std::ostringstream head;
    const std::vector<const SavingRow*> quadWrs = quadOf(Method::Wrs);
    if (!so.jod) {
        head << "- " << toString(scene) << ": no JOD (`--no-jod`); pixels, render and composition times only.";
        if (hasRender) {
            head << " Render time per frame: " << fmt("%.3f", full->renderMs) << " ms at full resolution";
            for (const SavingRow* q : quadOf(Method::Fov))
                head << "; quad views with a " << fmt("%.0f", q->insetDeg) << "° inset " << fmt("%.3f", q->renderMs)
                     << " ms (×" << fmt("%.2f", q->renderMs / full->renderMs) << ", " << fmt("%.1f", 100.0 * q->pixelsRendered / full->pixelsRendered)
                     << " % of the pixels)";
        }
        head << ".\n";
    }
    for (float target : {30.0f, 20.0f}) {
        const SavingRow* base = so.jod ? row(SavingInput::Quad, Method::Fov, target) : nullptr;
        if (!base) continue;
        const FoveaWorth wrs = insetForJod(rows, scene, Method::Wrs, base->jod);
        const FoveaWorth oracle = insetForJod(rows, scene, Method::Oracle, base->jod);
        head << "- **" << toString(scene) << ", quad views: `wrs` matches composition alone at a " << target << "° inset ("
             << fmt("%.2f", base->jod) << " JOD) with an inset of " << toString(wrs) << "** (the oracle: "
             << toString(oracle);
        if (!quadOf(Method::OracleQ).empty())
            head << "; the retention oracle: " << toString(insetForJod(rows, scene, Method::OracleQ, base->jod));
        head << ").";
        const QuadCost c = quadCost(quadWrs, wrs.deg);
        if (wrs.bound == FoveaWorth::Bound::Exact || wrs.bound == FoveaWorth::Bound::AtMost) {
            head << " Pixels rendered per frame: " << fmt("%.3f", c.pixels / 1e6) << " M against "
                 << fmt("%.3f", base->pixelsRendered / 1e6) << " M at " << target << "° ("
                 << fmt("%.1f", 100.0 * (1.0 - c.pixels / base->pixelsRendered)) << " % fewer) and "
                 << fmt("%.3f", full ? full->pixelsRendered / 1e6 : NAN) << " M at full resolution ("
                 << fmt("%.1f", full ? 100.0 * (1.0 - c.pixels / full->pixelsRendered) : NAN) << " % fewer)";
            if (hasRender && std::isfinite(c.renderMs))
                head << "; render time " << fmt("%.2f", c.renderMs) << " ms against " << fmt("%.2f", base->renderMs)
                     << " ms (×" << fmt("%.2f", c.renderMs / base->renderMs) << ") and " << fmt("%.2f", full->renderMs)
                     << " ms at full resolution (×" << fmt("%.2f", c.renderMs / full->renderMs) << ")"
                     << (cpu ? ", on the CPU renderer (ratios)" : "");
            head << ".";
        } else {
            head << " No inset of the study reaches it with `wrs`.";
        }
        head << "\n";
    }
    // Where the inset left a pixel, how often `wrs` kept the inset's sample; and how often the oracle kept
    // an older sample of the wide views (a pick among aliased samples that a quality-respecting rule
    // does not make): at the largest inset with outcomes.
    const SavingRow *wrsOc = nullptr, *oracleOc = nullptr;
    for (const SavingRow& r : rows) {
        if (!r.outcomes || r.input != SavingInput::Quad) continue;
        if (r.method == Method::Wrs && (!wrsOc || r.insetDeg >= wrsOc->insetDeg)) wrsOc = &r;
        if (r.method == Method::Oracle && (!oracleOc || r.insetDeg >= oracleOc->insetDeg)) oracleOc = &r;
    }
    if (wrsOc) {
        const SavingOutcomes& w = *wrsOc->outcomes;
        head << "- Retention outcomes at " << fmt("%.0f", wrsOc->insetDeg) << "° (`--outcomes`): where the inset has left a "
             << "pixel, `wrs` keeps the inset's sample at " << fmt("%.1f", 100.0 * w.share(2, int(gpu::WRS_OUT_KEPT)))
             << " % of them (the change test drops " << fmt("%.1f", 100.0 * w.share(2, int(gpu::WRS_OUT_CHANGED))) << " %)";
        if (oracleOc && oracleOc->insetDeg == wrsOc->insetDeg)
            head << "; the oracle keeps " << fmt("%.1f", 100.0 * oracleOc->outcomes->share(2, int(gpu::WRS_OUT_KEPT)))
                 << " % there, and also keeps an older sample of the wide views at "
                 << fmt("%.1f", 100.0 * oracleOc->outcomes->share(0, int(gpu::WRS_OUT_KEPT)))
                 << " % of the pixels whose history is the wide views' own: a pick among the wide views' samples "
                    "of other frames by their distance to the full-resolution render, which a rule that keeps only "
                    "sharper samples does not make";
        if (w.pixels(3) > 0)
            head << "; `wrs` holds a landed wide sample of an earlier frame at "
                 << fmt("%.1f", 100.0 * double(w.pixels(3)) / double(w.pixels(0) + w.pixels(1) + w.pixels(2) + w.pixels(3)))
                 << " % of the pixels and keeps it at " << fmt("%.1f", 100.0 * w.share(3, int(gpu::WRS_OUT_KEPT)))
                 << " % of those (" << fmt("%.1f", 100.0 * w.share(3, int(gpu::WRS_OUT_CHANGED))) << " % read as a change)";
        head << ".\n";
    }
    if (headline) *headline = head.str();

    std::ofstream md(dir + "/saving.md");
    if (!md) return savingError("cannot write " + dir + "/saving.md");
    md << "# Rendering saved: " << toString(scene) << "\n\n";
    md << "The scene rendered as an application would submit it — at full resolution, as quad views (wide views at "
       << fmt("%.2f", so.wideScale) << " of the display's pixel density"
       << (so.jitterPhases > 1 ? ", jittered over " + std::to_string(so.jitterPhases) +
                                     " Halton (2, 3) phases with textures sampled at the display's density"
                               : std::string())
       << ", an inset on the gaze at the display's density), "
       << "and at gaze-centred shading rates (1×1 within half the inset size of the gaze, 2×2 out to the inset size, "
       << "4×4 beyond, " << so.rateTexel << "-pixel rate texels) — composed without (`fov`) and with retention (`wrs`), "
       << "with the oracle as the bound of any retention rule, against the full-resolution render. "
       << o.width << "×" << o.height << (o.monitor ? " (monitor mode, one view)" : " per eye (HMD stereo)") << ", "
       << o.frames << " frames of synthetic gaze; JOD (FovVideoVDP, foveated), near-gaze PSNR (within 10°) and η over "
       << "the last " << std::max(1, o.jodFrames) << " frames; times are medians per frame after " << o.warmup
       << " frames of warm-up. Device: " << deviceName
       << (cpu ? " (a CPU: its times are the CPU's work, worth reading as ratios only)" : "") << ". Command: `wrsfov-bench --saving`"
       << " (docs/metrics.md, \"Rendering saved\").\n\n";
    md << "## Headline\n\n" << head.str() << "\n";
    if (so.jod && scene == SceneKind::Atrium) {
        md << "Goal: on the atrium at 12 px/deg or more, the inset `wrs` needs to match 30° without it is at most 10° (a "
              "ninth of the inset's pixels).";
        if (const SavingRow* base = row(SavingInput::Quad, Method::Fov, 30.0f)) {
            // The verdict on this cell, and what bounds it: the oracle bounds any retention rule on these frames.
            const FoveaWorth wrs = insetForJod(rows, scene, Method::Wrs, base->jod);
            const FoveaWorth oracle = insetForJod(rows, scene, Method::Oracle, base->jod);
            const bool reached = wrs.bound == FoveaWorth::Bound::Exact || wrs.bound == FoveaWorth::Bound::AtMost;
            if (reached && wrs.deg <= 10.0) {
                md << " **Met on this cell**: `wrs` needs " << toString(wrs) << ".";
            } else {
                md << " **Not met on this cell**: `wrs` needs " << toString(wrs);
                if (reached) md << ", " << fmt("%.1f", wrs.deg - 10.0) << "° more than the goal";
                if (!quadOf(Method::OracleQ).empty())
                    md << ". The retention oracle (`oracle-q`: a sharper sample kept exactly where it is nearer the "
                          "full-resolution render, the bound of a rule that keeps sharper samples) needs "
                       << toString(insetForJod(rows, scene, Method::OracleQ, base->jod));
                md << ". The oracle, which keeps at each pixel whichever sample is nearer the full-resolution render "
                      "and so bounds any retention rule on these frames, needs "
                   << toString(oracle) << ": ";
                const bool oracleReached =
                    oracle.bound == FoveaWorth::Bound::Exact || oracle.bound == FoveaWorth::Bound::AtMost;
                if (oracleReached && oracle.deg > 10.0)
                    md << "no retention rule reaches 10° here. What the inset rendered and the gaze comes back to within "
                       << o.frames << " frames (" << fmt("%.1f", o.frames / 90.0)
                       << " s of gaze) is too little; longer cells revisit more (docs/metrics.md, \"Rendering saved\").";
                else
                    md << "the rest of the gap is the retention rule's (`--outcomes` says where its decisions differ).";
            }
        }
        md << "\n\n";
    }
    md << "## Every composition\n\n";
    const bool hasEtaQ = !quadOf(Method::OracleQ).empty();
    md << "| input | method | inset | pixels rendered (M) | × full | render ms | × full | compose ms | JOD | "
          "near-gaze PSNR (dB) | temporal instability | η |"
       << (hasEtaQ ? " η_q |" : "") << " retain tiles |\n|---|---|---|---|---|---|---|---|---|---|---|---|"
       << (hasEtaQ ? "---|" : "") << "---|\n";
    for (const SavingRow& r : rows) {
        md << "| " << toString(r.input) << " | " << toString(r.method) << " | "
           << (r.input == SavingInput::Full ? std::string("–") : fmt("%.1f°", r.insetDeg)) << " | "
           << fmt("%.3f", r.pixelsRendered / 1e6) << " | " << fmt("%.3f", full ? r.pixelsRendered / full->pixelsRendered : NAN)
           << " | " << fmt("%.2f", r.renderMs) << " | " << fmt("%.2f", full ? r.renderMs / full->renderMs : NAN) << " | "
           << fmt("%.2f", r.composeMs) << " | " << fmt("%.2f", r.jod) << " | " << fmt("%.2f", r.nearGazePsnr) << " | "
           << fmt("%.5f", r.temporalInstability) << " | " << fmt("%.2f", r.eta) << " |";
        if (hasEtaQ) md << ' ' << fmt("%.2f", r.etaQ) << " |";
        md << ' ' << (std::isnan(r.retainShare) ? std::string("–") : fmt("%.1f %%", 100.0 * r.retainShare)) << " |\n";
    }
    md << "\nColumns: pixels rendered per frame by the application (both eyes; quad: wide + inset; rate: shaded "
          "samples, one per block); render ms: the application's rendering per frame ("
       << (hasRender ? "the atrium's raster on this device, both eyes, timed by the device's timestamps around its render passes; "
                       "rate maps: n/a, as this device has no variable-rate shading and the "
                       "study emulates it by rendering at half and a quarter of the resolution"
                     : "n/a: the scene is rendered on the CPU, and its cost is its pixels")
       << "); compose ms: the compositor's time per frame (PassTimes::total, with the compose pass); JOD and near-gaze "
          "PSNR against the full-resolution render; temporal instability: the output's mean frame-to-frame change (sRGB, "
          "0..1) where the full-resolution render does not change (docs/metrics.md); η: (MSE_fov − MSE) / (MSE_fov − MSE_oracle) for the same input and "
          "inset (n/a where the oracle removes less than 1 % of fov's MSE)"
       << (hasEtaQ ? "; η_q: the same against the retention oracle (`oracle-q`), the bound of a rule that keeps only "
                     "sharper samples"
                   : "")
       << "; retain tiles: the share of tiles that ran the retain pass, mean over the timed frames (the others took "
          "sparse retention's skip list; every other pass runs in every tile; – for a method without the pass)"
       << ".\n";

    // Retention outcomes (SavingOptions::outcomes).
    static constexpr const char* kOutcomeNames[SavingOutcomes::kOutcomes] = {
        "fresh", "changed", "better", "kept", "merged", "outside", "floor", "skipped"};
    static constexpr const char* kClassNames[SavingOutcomes::kClasses] = {"floor history", "inset still there",
                                                                          "inset left", "landed wide sample"};
    bool anyOutcomes = false;
    for (const SavingRow& r : rows) anyOutcomes = anyOutcomes || r.outcomes.has_value();
    if (anyOutcomes) {
        std::ofstream csv(dir + "/outcomes.csv");
        if (!csv) return savingError("cannot write " + dir + "/outcomes.csv");
        csv << "scene,input,method,inset_deg,class,outcome,pixels\n";
        md << "\n## Retention outcomes\n\n"
              "What the rule did at each pixel of the scored frames (the CPU reference stepped beside the compositor on "
              "the same composed frames from the compositor's own history, `--outcomes`), per class of pixel: its "
              "history at the wide views' quality or none (**floor history**); a history sharper than that where the "
              "candidate is sharper too (**inset still there**); a sharper history where the candidate is the wide "
              "views' (**inset left**: where retention can gain); a wide sample of an earlier frame that landed near "
              "the pixel, sharper than the wide views (**landed wide sample**: another phase of a jittered view, or "
              "another position of a moving one; docs/retention.md \"Landed wide samples\"). Outcomes (WRS_OUT_*, shaders/wrs_common.h): fresh "
              "(no usable history), changed (the change test dropped the history), better (the candidate is sharper), "
              "kept (the history is sharper, or the oracle kept it), merged and outside (equal quality: merged, "
              "clipped first), floor (a floor-quality history against a floor-quality candidate: the candidate, by the "
              "floor rule), skipped (a far tile sparse retention skipped: the candidate).\n\n";
        md << "| method | inset | class | pixels |";
        for (const char* n : kOutcomeNames) md << ' ' << n << " |";
        md << " reference ≠ GPU |\n|---|---|---|---|";
        for (int k = 0; k < SavingOutcomes::kOutcomes; ++k) md << "---|";
        md << "---|\n";
        for (const SavingRow& r : rows) {
            if (!r.outcomes) continue;
            const SavingOutcomes& oc = *r.outcomes;
            for (int h = 0; h < SavingOutcomes::kClasses; ++h) {
                md << "| " << toString(r.method) << " | " << fmt("%.1f°", r.insetDeg) << " | " << kClassNames[h] << " | "
                   << oc.pixels(h) << " |";
                for (int k = 0; k < SavingOutcomes::kOutcomes; ++k) {
                    md << ' ' << fmt("%.1f %%", 100.0 * oc.share(h, k)) << " |";
                    csv << toString(r.scene) << ',' << toString(r.input) << ',' << toString(r.method) << ',' << r.insetDeg
                        << ',' << kClassNames[h] << ',' << kOutcomeNames[k] << ',' << oc.count[h][k] << '\n';
                }
                md << ' ' << (h == 0 ? std::to_string(oc.differing) + " of " + std::to_string(oc.reservoirs) : std::string())
                   << " |\n";
            }
        }
    }

    // JOD against the cost, one curve per method: render time where the scene has it, else pixels.
    std::vector<Series> series;
    for (Method m : so.methods) {
        for (SavingInput in : {SavingInput::Quad, SavingInput::Rate}) {
            Series sr;
            sr.name = std::string(toString(m)) + (in == SavingInput::Rate ? " (rate)" : "");
            sr.colour = methodColour(m);
            if (in == SavingInput::Rate) sr.colour *= 0.6;
            sr.line = true;
            for (const SavingRow& r : rows)
                if (r.input == in && r.method == m) {
                    sr.points.push_back({hasRender && in == SavingInput::Quad ? r.renderMs : r.pixelsRendered / 1e6, r.jod});
                    sr.labels.push_back(fmt("%.0f deg", r.insetDeg));
                }
            if (!sr.points.empty() && !(hasRender && in == SavingInput::Rate)) series.push_back(sr);
        }
    }
    if (full) series.push_back({"full resolution", {0, 0, 0}, {{hasRender ? full->renderMs : full->pixelsRendered / 1e6, full->jod}}, {}, false});
    if (!so.jod) return {};  // no JOD to plot
    const std::string title = std::string(toString(scene)) + ": FovVideoVDP JOD against the rendering it costs";
    cv::imwrite(dir + "/saving.png",
                chart(title, hasRender ? "render ms per frame (both eyes)" : "megapixels rendered per frame", "JOD", series));
    return {};
}

}  // namespace wrsfov::eval
