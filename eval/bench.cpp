// The run-time-against-error sweep (runBench): each cell of the study composed, timed and scored.
#include "eval/bench.h"
#include "eval/bench_internal.h"
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

using namespace detail;

CompositorConfig compositorConfig(const BenchOptions& o) {
    CompositorConfig c;
    c.seed = o.seed;
    c.change = o.change;
    c.skipTiles = o.skipTiles;
    c.sparseRetention = o.sparseRetention;
    c.landedSamples = o.landedSamples;
    c.phaseMerge = o.phaseMerge;
    c.landedWeights = o.landedWeights;
    c.landedFootprint = o.landedFootprint;
    c.floorMerge = o.floorMerge;
    c.steadyFloor = o.steadyFloor;
    c.steadyDisplay = o.steadyDisplay;
    c.steadyDisplaySpeed = o.steadyDisplaySpeed;
    c.taau = o.taau;
    c.taauSimple = o.taauSimple;
    c.motionReachDeg = o.motionReachDeg;
    return c;
}

namespace {

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
        gaze::GazeSource* gazeSource = setup->gaze.get();
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
                    CompositorConfig cc = compositorConfig(o);
                    cc.method = i < 0 || sweep ? Method::Fov : o.methods[i];
                    cc.foveation = i < 0 ? FoveationMode::None : mode;
                    cc.foveaDeg = sweep ? sweepFoveas[size_t(i - methodRuns)] : fovea;
                    cc.measureCopy = i >= 0 && !sweep;
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
                        run.acc.addFrameStats(st, copyFrame);
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

}  // namespace wrsfov::eval
