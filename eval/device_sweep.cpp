// The scaling sweep's cells (runDeviceSweep: every method timed on the scene's frames kept on the
// device, nothing read back) and the scenes' frames as sequence directories (writeSceneSequence).
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
        const bool rendered = isAtriumScene(scene);
        const scenes::AtriumOptions ao = atriumOptions(o, scene);
        std::unique_ptr<scenes::AtriumRenderer> renderer;
        std::unique_ptr<SceneFrames> hostFrames;
        std::unique_ptr<gaze::GazeSource> gazeSource;
        HostStereoApp::Options appOpt;
        double fps = kFps;
        if (rendered) {
            auto r = scenes::AtriumRenderer::create(ctx, ao);
            if (!r) return r.error();
            renderer = std::move(*r);
            appOpt = atriumAppOptions(ao);
            gaze::GeneratorConfig gc = sweepGaze(o, nullptr);
            gc.seconds = o.frames / fps + 2.0;
            auto g = sweepGazeSource(o, scene, gc);
            if (!g) return g.error();
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
                    CompositorConfig cc = compositorConfig(o);
                    cc.method = m;
                    cc.foveation = mode;
                    cc.foveaDeg = fovea;
                    cc.measureCopy = true;
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
                        run.acc.addFrameStats(fs, copyFrame);
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

}  // namespace wrsfov::eval
