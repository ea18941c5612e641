// The run-time-against-error benchmark: scenes x foveation modes x fovea sizes, every method
// through the same compositor path against the unfoveated reference of the same frames, with
// synthetic gaze (reading for `text`, free viewing for the others). The `sequence` scene evaluates
// external frames from a sequence directory (docs/sequence.md) the same way.
#pragma once

#include <array>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "compositor/vk_context.h"
#include "eval/fvvdp.h"
#include "layers/status.h"
#include "scenes/atrium.h"
#include "scenes/photo.h"

namespace wrsfov::eval {

/// Built-in scenes, and `Sequence`: the frames of BenchOptions::sequenceDir. `Thin`: the atrium with
/// thin high-contrast geometry (railings, wires, cut-out foliage) and specular shading
/// (scenes::AtriumOptions::thin).
enum class SceneKind : uint8_t { Text, Atrium, Dynamic, Sequence, Photo, Thin };
std::string_view toString(SceneKind s);
std::optional<SceneKind> parseScene(std::string_view name);
/// The scenes the atrium renderer draws (atrium, dynamic, thin): depth, motion, a camera path.
constexpr bool isAtriumScene(SceneKind s) {
    return s == SceneKind::Atrium || s == SceneKind::Dynamic || s == SceneKind::Thin;
}

struct BenchOptions {
    std::vector<SceneKind> scenes{SceneKind::Text, SceneKind::Atrium, SceneKind::Dynamic};
    std::vector<Method> methods{Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::Oracle, Method::OracleQ};
    std::vector<float> foveas{5.0f, 7.5f, 10.0f};  ///< diameters in degrees
    std::vector<FoveationMode> modes{FoveationMode::Mip, FoveationMode::Gauss};
    uint32_t width = 320, height = 288;  ///< per eye
    int frames = 90;                     ///< per cell, at 90 Hz
    int warmup = 10;                     ///< frames before timings and metrics count
    int heavyEvery = 10;                 ///< SSIM, FLIP and stale pixels on every n-th counted frame
    int copyEvery = 1;                   ///< the copy kernels on every n-th counted frame
    /// Stale-pixel statistics: wrs-paper, wrs and the oracle keep birth colours (trackBirth, 32 B/px
    /// more traffic and the time it takes). Off for timing runs: the passes as an application gets them.
    bool staleStats = true;
    /// Error metrics (PSNR, near-gaze PSNR, SSIM, FLIP, temporal instability, bands, stale pixels).
    /// Off (the scaling sweep, which reports time and bytes): no output is read back and the quality
    /// fields of the results are NaN; times, bytes and the shading fraction are measured as before.
    bool qualityMetrics = true;
    /// CompositorConfig::skipTiles (--no-skip turns it off: the same output, the per-pixel path).
    bool skipTiles = true;
    /// CompositorConfig::sparseRetention (--dense-retention turns it off: the same output, retention in
    /// every tile).
    bool sparseRetention = true;
    /// CompositorConfig::landedSamples (--no-landed: retention of quad views keeps the composed
    /// candidates only).
    bool landedSamples = true;
    /// CompositorConfig::phaseMerge (--no-phase-merge: each phase's wide candidate taken fresh).
    bool phaseMerge = true;
    /// CompositorConfig::landedWeights (--landed-weights: landed samples weighed by their overlap).
    bool landedWeights = CompositorConfig{}.landedWeights;
    /// CompositorConfig::landedFootprint (--landed-footprint K, wide pixels; 0: one output pixel).
    float landedFootprint = CompositorConfig{}.landedFootprint;
    /// CompositorConfig::steadyDisplay (--steady-display A; 0: off).
    float steadyDisplay = CompositorConfig{}.steadyDisplay;
    /// CompositorConfig::steadyDisplaySpeed (--steady-display-speed V, output pixels a frame; 0: one weight at every speed).
    float steadyDisplaySpeed = CompositorConfig{}.steadyDisplaySpeed;
    /// CompositorConfig::taau (--taau K,W,B,V,L,T,S) and CompositorConfig::taauSimple (--taau-simple R,W,G).
    CompositorConfig::Taau taau;
    CompositorConfig::TaauSimple taauSimple;
    /// CompositorConfig::floorMerge (--floor-merge: equal-quality merging at the floor too, retention in
    /// every tile).
    bool floorMerge = false;
    /// CompositorConfig::steadyFloor (--steady-floor: the floor level filtered over time).
    bool steadyFloor = false;
    /// Scene `photo` (scenes/photo.h): the image (a file, or grass / wood generated), the head's motion
    /// and its speed in pixels per frame at the view's centre (--photo, --photo-motion, --photo-speed).
    std::string photoImage = "grass";
    scenes::PhotoMotion photoMotion = scenes::PhotoMotion::Pan;
    float photoSpeed = 0.37f;
    /// CompositorConfig::motionReachDeg (--motion-reach; 0: no limit).
    float motionReachDeg = CompositorConfig{}.motionReachDeg;
    uint32_t seed = 1;
    ChangeMetric change = ChangeMetric::LStar;  ///< the change term of the WRS history bias
    scenes::CameraPath path = scenes::CameraPath::Lateral;
    /// Built-in scenes in monitor mode: one symmetric 76° x 60° view (the paper's desktop setting)
    /// submitted as both views, instead of the HMD's stereo pair.
    bool monitor = false;
    /// HMD stereo of atrium and dynamic: > 0 uses a symmetric square field of view of this many
    /// degrees per eye instead of the HMD's own (AtriumOptions::fovDeg).
    float hmdFovDeg = 0.0f;
    /// Shading samples per pixel of atrium's and dynamic's procedural materials
    /// (AtriumOptions::materialSamples): 4 filtered, 1 point-sampled (aliased).
    uint32_t materialSamples = 4;
    /// SceneKind::Sequence: the sequence directory. Its frames are the reference as submitted (at
    /// full quality), its gaze comes from gaze.csv (synthetic free viewing without one), frame f is
    /// displayed at f / fps of the json. width/height must be the sequence's, frames <= its frame count.
    std::string sequenceDir;
    std::string cropDir;  ///< where to write side-by-side crops and error maps ("" = none)
    /// FovVideoVDP JOD (foveated, eval/fvvdp.h) per method beside the other error metrics; needs
    /// qualityMetrics. Display: monitor in monitor mode and for sequences, HMD otherwise; the view
    /// geometry from the submitted field of view; the run's per-frame gaze; the scene's frame rate.
    bool jod = true;
    /// JOD over the last `jodFrames` counted frames only (0: every counted frame), the same frames for
    /// every method of a cell, so that JOD costs less. CellResult::jodNearPsnr is near-gaze PSNR over them.
    int jodFrames = 0;
    /// The fovea a method is worth: `fov` at these extra fovea diameters (degrees) in the cell of the
    /// first fovea, fed the same frames and scored (JOD and near-gaze PSNR) over the JOD frames only
    /// (fov keeps nothing from frame to frame, so it is submitted only those frames). Empty: none.
    /// Foveas of `foveas` are not run twice. See foveaWorth and writeReport's fovea_worth.csv.
    std::vector<float> worthFoveas;
    /// Where to write every method's output frames and the reference as PNG, with the gaze in pixels
    /// ("" = nowhere): DIR/<scene>_<mode>_<fovea>/<method|reference>/{L,R}/NNNNNN.png over the counted
    /// frames (R only in HMD stereo), gaze.csv and view.csv (docs/metrics.md, "Outputs for other metrics").
    std::string outputsDir;
    std::function<void(const std::string&)> progress;
};

/// The compositor's configuration the options give: the seed, the change metric and every research
/// switch (tiles, sparse retention, landed samples, phase merge, the steady floor and display, taau's
/// parameters, the motion reach). The one mapping from the options to CompositorConfig: each study
/// sets its runs' method, foveation and fovea (and what it measures) on it.
CompositorConfig compositorConfig(const BenchOptions& o);

/// One cell of the sweep: means over the counted frames and both eyes.
/// Edges of the eccentricity bands of CellResult::bandMse, in degrees from the gaze: [0, 5), [5, 10),
/// [10, 20), [20, 30), [30, ∞).
inline constexpr std::array<double, 6> kEccBands{0.0, 5.0, 10.0, 20.0, 30.0, std::numeric_limits<double>::infinity()};

struct CellResult {
    SceneKind scene;
    Method method;
    FoveationMode mode;
    float foveaDeg;
    int frames = 0;
    PassTimes gpu;            ///< medians, ms per frame for both eyes
    double copyMs = 0;        ///< same-bytes copy kernel in the same submissions, median ms
    double copyFloorMs = 0;   ///< copy kernel moving the method's floor bytes, same submissions, median ms
    double trafficBytes = 0;  ///< bytes the passes read and write per frame (what the copy kernel moves)
    Traffic traffic;          ///< per pass, bytes per pixel of one view, and the method's floor
    double shadingFraction = 0;  ///< full-rate shading work the foveation represents (1 = none saved)
    double psnr = 0, ssim = 0, nearPsnr = 0, eccMse = 0, flip = 0, temporal = 0;
    /// FovVideoVDP JOD (foveated; 10 = no visible difference) over the JOD frames (BenchOptions::jodFrames),
    /// mean of the eyes in HMD stereo; NaN without it. jodNearPsnr: near-gaze PSNR over the same frames.
    double jod = std::numeric_limits<double>::quiet_NaN();
    double jodNearPsnr = std::numeric_limits<double>::quiet_NaN();
    int jodFrames = 0;  ///< frames the JOD is over
    /// A run of the fovea-worth sweep (BenchOptions::worthFoveas): fov at an extra fovea, submitted and
    /// scored over the JOD frames only; its times are medians over those frames.
    bool worthSweep = false;
    double mse = 0, nearMse = 0;  ///< mean squared error (sRGB, 0..1), full image and within 10° of gaze
    /// Retention efficiency (MSE_fov − MSE) / (MSE_fov − MSE_oracle) in the same cell, full image and
    /// near gaze; NaN without fov and oracle in the cell or where the oracle removes less than 1 % of
    /// fov's MSE.
    double eta = std::numeric_limits<double>::quiet_NaN(), etaNear = std::numeric_limits<double>::quiet_NaN();
    /// The same against the retention oracle (`oracle-q`: history kept only when closer and of higher
    /// quality than the candidate), whole image and near gaze; NaN without fov and oracle-q in the cell
    /// or where oracle-q removes less than 1 % of fov's MSE.
    double etaQ = std::numeric_limits<double>::quiet_NaN(), etaQNear = std::numeric_limits<double>::quiet_NaN();
    /// Stale pixels (wrs-paper, wrs, oracle; NaN otherwise): pixels showing a sample whose submitted
    /// colour when taken lies more than 4/255 outside the 3x3 neighbourhood of the submitted colour
    /// now. Their share of all pixels, the method's MSE over them and fov's MSE over the same pixels.
    double staleFraction = std::numeric_limits<double>::quiet_NaN();
    double staleMse = std::numeric_limits<double>::quiet_NaN(), staleFovMse = std::numeric_limits<double>::quiet_NaN();
    double fovTotalMs = 0;    ///< the `fov` method's median total in the same cell (for ratios)
    /// Methods with the retain pass: mean share of tiles that ran retention (FrameStats::retainShare);
    /// NaN for the others.
    double retainShare = std::numeric_limits<double>::quiet_NaN();
    /// Sparse retention: mean share of tiles whose motion the classification read
    /// (FrameStats::motionShare); NaN for methods without it.
    double motionShare = std::numeric_limits<double>::quiet_NaN();
    /// MSE (sRGB, 0..1) per eccentricity band (kEccBands), and the share of pixels in each band.
    std::array<double, kEccBands.size() - 1> bandMse{}, bandShare{};
};

/// The atrium's options (AtriumOptions) for `scene` (atrium or dynamic) in a sweep with `options`.
scenes::AtriumOptions atriumOptions(const BenchOptions& options, SceneKind scene);
/// The photo scene's options (PhotoOptions) in a sweep with `options`.
scenes::PhotoOptions photoOptions(const BenchOptions& options);

/// Runs the sweep. Fails with a message when a scene, compositor or frame cannot be made.
Result<std::vector<CellResult>> runBench(vk::Context& ctx, const BenchOptions& options);

/// What forEachSceneFrame shows its visitor with each frame: the application's swapchain options and
/// the scene's frame rate.
struct SceneFrameInfo {
    HostStereoApp::Options app;
    double fps = 90.0;
};
/// Frames of `scene` as the sweep submits them (size, camera path, seed, gaze of the sweep), one at a
/// time: `visit(info, index, time, eyes)` gets each frame's images and gaze; a failing visit stops the
/// walk with its error.
Status forEachSceneFrame(vk::Context& ctx, SceneKind scene, const BenchOptions& options,
                         const std::function<Status(const SceneFrameInfo&, int, double,
                                                    std::array<EyeSubmission, 2>&)>& visit);

/// Writes `options.frames` frames of `scene` (at options.width x options.height, camera path and
/// seed as in the sweep) with the sweep's gaze for that scene as a sequence directory `dir`:
/// colour PNG, depth and motion EXR where the scene has them, gaze.csv. runBench on the written
/// sequence then sees the same images and gaze as runBench on the scene.
Status writeSceneSequence(vk::Context& ctx, SceneKind scene, const BenchOptions& options, const std::string& dir);

/// What the bench needs of a FovVideoVDP implementation: frames in, JOD out. fvvdp::Metric (the C++
/// reference) is one; a GPU version with the same push/jod stands in through makeJodMetric.
class JodMetric {
public:
    virtual ~JodMetric() = default;
    /// `test`, `reference`: CV_32FC3 sRGB-encoded RGB of the metric's size; `gazePx` the pixel looked at
    /// (fvvdp::Metric::push's convention: pixel (x, y) spans [x, x + 1), its centre at x + 0.5).
    virtual Status push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gazePx) = 0;
    virtual Result<double> jod() const = 0;
};

/// The JOD implementation the bench scores with. `ctx`: the bench's device, for a GPU version.
Result<std::unique_ptr<JodMetric>> makeJodMetric(vk::Context& ctx, const fvvdp::Options& options);

/// The metric's options for one eye of a bench cell: display preset (monitor in monitor mode and for
/// sequences, HMD otherwise), view geometry from the eye's fov tangents, foveated, at `fps`.
fvvdp::Options jodOptions(const BenchOptions& options, SceneKind scene, uint32_t width, uint32_t height,
                          glm::vec4 fovTan, double fps);

/// The fovea a method is worth: the smallest fovea at which a curve of (fovea diameter, score) of
/// `fov` reaches `target` (the method's score; higher is better), interpolated linearly in the score
/// between the sweep's foveas. Points need not be sorted; non-finite scores are ignored.
struct FoveaWorth {
    enum class Bound : uint8_t {
        Exact,     ///< deg lies within the sweep
        AtMost,    ///< fov at the smallest fovea already reaches the target: deg is that fovea (or less)
        MoreThan,  ///< no fovea of the sweep reaches the target: more than deg, the largest
        Unknown,   ///< no finite target or no points
    };
    double deg = std::numeric_limits<double>::quiet_NaN();
    Bound bound = Bound::Unknown;
};
FoveaWorth foveaWorth(std::vector<std::pair<double, double>> curve, double target);
/// "7.9°", "5.0° or less", "more than 15.0°", "n/a".
std::string toString(const FoveaWorth& w);

/// The smallest WRS fovea whose near-gaze PSNR is at least FOV's at 10° (same scene and mode);
/// 0 when none is (or the sweep lacks the cells).
float equalQualityFovea(const std::vector<CellResult>& results, SceneKind scene, FoveationMode mode);

/// What runDeviceSweep did on the host.
struct DeviceSweepStats {
    int rendered = 0;   ///< frames the scene rendered on the device (atrium, dynamic)
    int uploads = 0;    ///< frames uploaded from the host (other scenes): once per distinct frame
    int submitted = 0;  ///< frame ends, all methods together
};
/// The scaling sweep's run (wrsfov-bench --scaling): the cells of `options` timed with the scene's
/// frames kept on the device. The scene writes one set of input images per frame (the atrium renders
/// into them on the device; another scene uploads a frame only when it differs from the one uploaded
/// last, a still image once) and every method's compositor reads those very images through imported
/// swapchains (HostStereoApp::share). Nothing is read back and there is no reference run: the quality
/// fields and shadingFraction are NaN. Times (PassTimes medians over the counted frames), the copy
/// kernels (CompositorConfig::measureCopy, every copyEvery-th counted frame), bytes and the retention
/// shares are measured as runBench measures them, with the same synthetic gaze driving every frame.
Result<std::vector<CellResult>> runDeviceSweep(vk::Context& ctx, const BenchOptions& options,
                                               DeviceSweepStats* stats = nullptr);

/// One size of a scaling sweep (wrsfov-bench --scaling): its cells.
struct ScalingStep {
    uint32_t width = 0, height = 0;
    std::vector<CellResult> cells;
};
/// Writes scaling.csv, scaling.md and scaling.png (time and bytes against pixels per method) into `dir`.
/// `costModel`: a section on the static cost model (cost_model.md in `dir`) appended to scaling.md ("" = none).
Status writeScalingReport(const std::vector<ScalingStep>& steps, const BenchOptions& options, const std::string& dir,
                          const std::string& deviceName, const std::string& costModel = "");

/// What the cost model (eval/cost_model.h) needs of a cell without running it: the bytes per texel of
/// its views and the share of all 8x8 tiles (both eyes, counted frames) in each tile class
/// (gpu::WRS_TILE_*), from the sweep's own gaze and views for `scene` at width x height per eye,
/// classified as the compositor's classify pass does (makeFrameParams, wrs_tile_class). Built-in
/// scenes only; nothing is rendered.
struct CellGeometry {
    TrafficInputs inputs;
    std::array<double, gpu::WRS_TILE_LISTS> tileShare{};  ///< classes only: the skip list's share is 0
};
Result<CellGeometry> cellGeometry(const BenchOptions& options, SceneKind scene, FoveationMode mode, float fovea,
                                  uint32_t width, uint32_t height);

/// The same for frames submitted as quad views (wrsfov-bench --cost-model --cost-quad): the atrium's views
/// as the saving study renders them (eval/saving.cpp), wide views at `wideScale` of the display's pixels
/// and an inset `insetDeg` across at the display's density, `width` x `height` the output per eye. The
/// inputs are trafficInputs() of that layer (the compose pass's bytes, the composed images' formats). The
/// tiles: of class far (every pixel at the wide views' quality) outside the inset, placed at the view's
/// centre, and any where it lies; `allTilesAny`: every tile any (a frame of `wrs` that merges every phase
/// of jittered views has no floor rule). No skip share: sparse retention's is not measured here.
Result<CellGeometry> quadCellGeometry(const BenchOptions& options, SceneKind scene, uint32_t width, uint32_t height,
                                      float wideScale, float insetDeg, bool allTilesAny);

/// Writes results.csv, table.md, error_vs_time.png and error_vs_fovea.png into `dir`.
Status writeReport(const std::vector<CellResult>& results, const BenchOptions& options, const std::string& dir,
                   const std::string& deviceName);

}  // namespace wrsfov::eval
