// The evaluation's study, shared by its parts (not installed): bench.cpp runs the sweep's cells,
// bench_scenes.cpp opens the scenes and their gaze (and the cost model's cell geometry),
// device_sweep.cpp runs the scaling sweep's cells and writes scene sequences, bench_report.cpp writes the reports.
#ifndef WRSFOV_EVAL_BENCH_INTERNAL_H
#define WRSFOV_EVAL_BENCH_INTERNAL_H

#include <array>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "compositor/host_app.h"
#include "eval/bench.h"
#include "eval/metrics.h"
#include "gaze/source.h"
#include "scenes/text.h"

namespace wrsfov::eval::detail {

inline constexpr double kFps = 90.0;
Error benchError(const std::string& m);

// The part of fov's MSE a bound (oracle, oracle-q) removes, or 0 where it removes less than 1 % of it
// (a band where every candidate is equally blurred: there a ratio against it is noise, e.g. 388 for a
// 0.2 % gain). η and η_q are n/a against no gain.
double boundGain(double fovMse, double boundMse);

// The result of method m in the cell (scene, mode, fovea) among `results`, or nullptr.
const CellResult* findCell(std::span<const CellResult> results, SceneKind scene, FoveationMode mode, float fovea,
                           Method m);

// Whether a device name is Mesa's CPU renderer (the report says its times are a CPU's).
bool isCpuRenderer(const std::string& deviceName);

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

/// The swapchain options of an application that renders the atrium with these options.
HostStereoApp::Options atriumAppOptions(const scenes::AtriumOptions& o);

// A scene's frames and the synthetic gaze that goes with it (reading for text, free viewing else).
struct SceneSetup {
    std::unique_ptr<SceneFrames> frames;
    std::unique_ptr<gaze::GazeSource> gaze;
};

/// The sweep's gaze source from the generator configuration `gc` (o.seed): the generator's gaze, or on
/// the atrium's and dynamic's look-around path (scenes::CameraPath::LookAround) the generator's free
/// viewing kept within 6° of each target, turned to where that path's eye looks in the head.
Result<std::unique_ptr<gaze::GazeSource>> sweepGazeSource(const BenchOptions& o, SceneKind scene,
                                                          gaze::GeneratorConfig gc);

/// Opens a scene of the sweep: its frames and its synthetic gaze (o.seed).
Result<SceneSetup> openScene(vk::Context& ctx, SceneKind scene, const BenchOptions& o);

// The sweep's synthetic gaze: reading over the text scene's layout, free viewing elsewhere.
gaze::GeneratorConfig sweepGaze(const BenchOptions& o, const scenes::TextLayout* text);

/// Whether a method has a birth colour to track (the stale-pixel statistics).
inline bool tracksBirth(Method m) { return m == Method::WrsPaper || usesRetainPass(m); }

double median(std::vector<double> v);
double mseFromPsnr(double p);
double psnrFromMse(double m);

// Fraction of full-rate shading: each pixel costs the quality of its blended pyramid levels
// (wrs_level_quality: 1/4^level, blended).
double shadingFraction(FoveationMode mode, const cv::Mat& ecc, float rf, float rm);

/// A cell's sums over its frames, as the sweep and the device sweep gather them.
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

    /// Adds a counted frame's statistics: the retention shares and the GPU times (the copy kernels'
    /// on a frame that ran them, copyFrame).
    void addFrameStats(const FrameStats& st, bool copyFrame) {
        mono = st.monoViews;
        if (st.retained) {
            retainShare += st.retainShare();
            motionShare += st.motionShare();
            shareFrames++;
        }
        if (st.gpu.valid) {
            pyramid.push_back(st.gpu.pyramid);
            foveate.push_back(st.gpu.foveate);
            temporal.push_back(st.gpu.temporal);
            total.push_back(st.gpu.total);
            if (copyFrame) {
                copy.push_back(st.gpu.copy);
                copyFloor.push_back(st.gpu.copyFloor);
            }
        }
    }
};

}  // namespace wrsfov::eval::detail

#endif  // WRSFOV_EVAL_BENCH_INTERNAL_H
