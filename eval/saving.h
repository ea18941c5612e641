// What rendering foveated saves, end to end (wrsfov-bench --saving, docs/metrics.md "Rendering saved"):
// a scene rendered as an application would submit it, at full resolution, as quad views (a wide view at
// a low density and an inset on the gaze at the display's density) and at gaze-centred shading rates,
// each composed without and with WRS and scored against the full-resolution render: pixels rendered,
// render and composition time, FovVideoVDP JOD, near-gaze PSNR and retention efficiency.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "compositor/compositor.h"
#include "eval/bench.h"

namespace wrsfov::eval {

/// How the frames were rendered: full resolution, quad views, or at shading rates.
enum class SavingInput : uint8_t { Full, Quad, Rate };
/// "full", "quad", "rate".
std::string_view toString(SavingInput input);

struct SavingOptions {
    /// The scene's frames and gaze as the sweep makes them: scene size per eye (the display), frames,
    /// warm-up, seed, monitor mode or the HMD field of view, camera path, JOD frames, progress.
    BenchOptions bench;
    /// Quad views: the inset's size across, degrees. Rate maps: the diameter of the 1x1 region around the
    /// gaze (a 2x2 ring out to twice it, 4x4 beyond).
    std::vector<float> insetDegs{5.0f, 10.0f, 15.0f, 20.0f, 30.0f};
    /// The wide views' pixel density relative to the display's (the OpenXR specification's Varjo example:
    /// 14 px/deg against 35, 1 / 2.5).
    float wideScale = 0.4f;
    /// The wide views rendered as an engine renders for temporal upsampling: each frame's projection
    /// shifted by a sub-pixel jitter, Halton (2, 3) over this many phases (layers::haltonJitter; 0 or 1:
    /// none), submitted as ProjectionView::sampleOffset; the atrium's materials and the text page then
    /// filtered over the display's pixel rather than the wide view's (a texture LOD bias of log2
    /// wideScale), so each wide pixel is a sharp point sample; the photo is point-sampled at the
    /// texture's density in every view already (`wrsfov-bench --saving --jitter N`).
    uint32_t jitterPhases = 0;
    /// Composed with each of these (fov: composition alone; the oracle bounds any retention rule, the
    /// retention oracle `oracle-q` any rule that keeps only sharper samples).
    std::vector<Method> methods{Method::Fov, Method::Wrs, Method::Oracle, Method::OracleQ};
    /// Shading-rate rows too (fov and wrs only), at these 1x1-region diameters (empty: insetDegs).
    bool rate = true;
    std::vector<float> rateDegs;
    /// Pixels per rate-map texel (VK_KHR_fragment_shading_rate's attachment texel size).
    uint32_t rateTexel = 16;
    /// FovVideoVDP JOD per row (on the CPU, the study's largest cost at a headset's size). Without it
    /// (`wrsfov-bench --saving --no-jod`) the rows keep pixels, times and near-gaze PSNR, and there is no
    /// headline or plot: a cell for the render and composition times at sizes where JOD costs too much.
    bool jod = true;
    /// Retention outcomes (`wrsfov-bench --saving --outcomes`): the CPU reference steps beside each quad-view
    /// composition of `wrs` and the oracle on the same composed frames, and counts over the scored frames
    /// what the rule did at each pixel (WRS_OUT_*), split by whether the pixel's history held a sample
    /// sharper than the frame's floor quality (the inset's, once the inset moved on). outcomes.csv and a
    /// table in saving.md. The CPU reference costs about as much as the study at the main job's sizes.
    bool outcomes = false;
    /// Which part of a study this run is (saving.csv's `split` column): "train" where a method's
    /// parameters are chosen, "test" where the figures are reported (`wrsfov-bench --saving --split`).
    std::string split = "test";
};

/// Retention outcomes of one composition (SavingOptions::outcomes): pixel counts over the scored frames
/// (evaluated eyes), per class of pixel and per outcome: WRS_OUT_FRESH .. WRS_OUT_FLOOR, then `skipped`
/// (a far tile that sparse retention skipped: the candidate, nothing stored).
struct SavingOutcomes {
    static constexpr int kOutcomes = 8;
    /// Classes: the history was at the wide views' quality or none (0); sharper, and the candidate is
    /// sharper than the wide views too: the inset is still there (1); sharper, and the candidate is the
    /// wide views': the inset has left the pixel (2); a landed wide sample (WRS_FLAG_LANDED) sharper
    /// than the wide views, of an earlier frame, so of another phase of a jittered view or another
    /// position of a moving one (3). Classes 2 and 3 are where retention can gain.
    static constexpr int kClasses = 4;
    std::array<std::array<uint64_t, kOutcomes>, kClasses> count{};
    uint64_t gapShown = 0;        ///< pixels where a gap's kept sample was shown (wrs_track_gap)
    uint64_t differing = 0;       ///< reservoirs where the reference and the GPU disagree
    uint64_t reservoirs = 0;      ///< reservoirs compared
    /// Pixels of class `cls`, and the share of them with outcome k (NaN for an empty class).
    uint64_t pixels(int cls) const {
        uint64_t n = 0;
        for (uint64_t c : count[cls]) n += c;
        return n;
    }
    double share(int cls, int k) const {
        const uint64_t n = pixels(cls);
        return n ? double(count[cls][k]) / double(n) : std::numeric_limits<double>::quiet_NaN();
    }
};

struct SavingRow {
    SceneKind scene = SceneKind::Atrium;
    SavingInput input = SavingInput::Full;
    Method method = Method::Fov;
    float insetDeg = 0.0f;       ///< 0 for the full-resolution row
    double pixelsRendered = 0;   ///< per frame, both eyes: pixels (quad: wide + inset) or shaded samples (rate)
    /// Median per frame of the application's rendering of both eyes, device time from timestamps around
    /// its render passes (GPU scenes; NaN for a scene rendered on the CPU or emulated: the text page,
    /// shading rates on a device without them).
    double renderMs = std::numeric_limits<double>::quiet_NaN();
    double composeMs = 0;  ///< median compositor time per frame, both eyes (PassTimes::total)
    /// Over the JOD frames: FovVideoVDP JOD and near-gaze PSNR against the full-resolution render, MSE
    /// (sRGB, 0..1), and the retention efficiency against the oracle of the same input and inset,
    /// (MSE_fov - MSE) / (MSE_fov - MSE_oracle) (NaN without both or where the oracle removes < 1 %).
    double jod = std::numeric_limits<double>::quiet_NaN();
    double nearGazePsnr = std::numeric_limits<double>::quiet_NaN();
    double mse = std::numeric_limits<double>::quiet_NaN();
    double eta = std::numeric_limits<double>::quiet_NaN();
    /// The same against the retention oracle (`oracle-q`: a sharper sample kept only where it is nearer the
    /// full-resolution render, the bound of a rule that keeps only sharper samples), where the study ran it.
    double etaQ = std::numeric_limits<double>::quiet_NaN();
    /// SavingOptions::outcomes, quad views with `wrs` or the oracle only.
    std::optional<SavingOutcomes> outcomes;
    /// Temporal instability over the scored frames (eval/metrics.h: the output's frame-to-frame change where
    /// the full-resolution render does not change), evaluated eyes averaged.
    double temporalInstability = std::numeric_limits<double>::quiet_NaN();
    /// Mean over the timed frames of the share of tiles that ran the retain pass (FrameStats::retainShare;
    /// the rest took sparse retention's skip list); NaN for a method without the pass. Every other pass
    /// of a frame (compose, classification, pyramid, steady display) runs in every tile.
    double retainShare = std::numeric_limits<double>::quiet_NaN();
    float wideScale = 0.0f;     ///< the wide views' density (quad views; 0 otherwise)
    uint32_t jitterPhases = 0;  ///< SavingOptions::jitterPhases of quad views (0 otherwise)
    /// The cell: the head's path (the atrium's and dynamic's camera path; the photo's motion as
    /// "photo-<motion>"; "static" for the text page), its largest angular speed in degrees per second
    /// (NaN for the photo, whose speed is in pixels a frame), the seed (gaze, jitter start, the compositor's
    /// random choices) and the split the run was made for (SavingOptions::split).
    std::string headPath = "static";
    double headDegPerS = 0.0;
    uint32_t seed = 1;
    std::string split = "test";
};

/// The sizes of a quad view as the study renders it, which the cost model's quad cell
/// (eval::quadCellGeometry) takes too: the wide view at `wideScale` of the display's W x H pixels, the
/// inset `insetDeg` across at the display's density over `fov` (pixels per tangent unit), each side at
/// least one pixel and the inset's at most the display's.
struct QuadViewSizes {
    uint32_t wideW = 0, wideH = 0, insetW = 0, insetH = 0;
};
QuadViewSizes quadViewSizes(uint32_t W, uint32_t H, const layers::Fov& fov, float wideScale, float insetDeg);

/// Runs the study on one scene (text or atrium). Fails with a message when a scene, compositor or frame
/// cannot be made.
Result<std::vector<SavingRow>> runSaving(vk::Context& ctx, SceneKind scene, const SavingOptions& options);

/// The inset a method needs to match a target JOD: the smallest inset (interpolated between the study's)
/// at which `method`'s quad-view JOD reaches `targetJod` (FoveaWorth semantics).
FoveaWorth insetForJod(const std::vector<SavingRow>& rows, SceneKind scene, Method method, double targetJod);

/// Writes saving.csv, saving.md and saving.png (JOD against render time, or against pixels where the
/// scene has no render time, one curve per method) into `dir`; `headline` (optional) gets the study's
/// headline in one paragraph of Markdown.
Status writeSavingReport(const std::vector<SavingRow>& rows, const SavingOptions& options, const std::string& dir,
                         const std::string& deviceName, std::string* headline = nullptr);

// --- JOD against pixels across studies (eval/saving_plot.cpp, wrsfov-bench --saving-plot) ---

/// Reads a saving.csv that writeSavingReport wrote (columns by name; a file of a study before the
/// jittered views, without wide_density, jitter or temporal_instability, reads them as 0, 0 and NaN).
/// A missing column, a field that is not a number, an unknown scene, method or input, a count of
/// pixels that is not positive: an error naming the file, the line and the field.
Result<std::vector<SavingRow>> readSavingCsv(const std::string& path);

/// The row whose JOD the curves are asked to reach: a method's quad views at a wide density and inset,
/// jittered (more than one phase) or not. Text form "METHOD,DENSITY,INSET[,JITTER]" ("fov,0.4,30").
struct SavingTarget {
    Method method = Method::Fov;
    float wideScale = 0.4f, insetDeg = 30.0f;
    uint32_t jitterPhases = 0;
};
Result<SavingTarget> parseSavingTarget(std::string_view text);

/// A figure of the study's tables: `printfFormat` (one double) applied to v; "∞" for +infinity (a
/// fovea that never reaches a target), "n/a" for any other value that is not finite.
std::string savingNumber(const char* printfFormat, double v);

/// A row's curve: the method, "(jittered)" for quad views over more than one phase, "(rate)" for
/// shading rates ("wrs (jittered)", "fov").
std::string curveName(const SavingRow& r);

/// A curve's best points: its rows with a JOD, by pixels, each kept only where it scores above every
/// cheaper one (what a user picking the fewest pixels for a JOD would choose among).
struct SavingFrontPoint {
    double pixels = 0, renderMs = 0, jod = 0;
};
std::vector<SavingFrontPoint> savingFront(const std::vector<SavingRow>& curve);
/// The fewest pixels at which a front reaches `targetJod`, linear between its points (FoveaWorth's
/// bounds: AtMost where its cheapest point already reaches it, MoreThan where none does), and the
/// render time linear in the pixels there.
struct SavingReach {
    double pixels = std::numeric_limits<double>::quiet_NaN(), renderMs = std::numeric_limits<double>::quiet_NaN();
    FoveaWorth::Bound bound = FoveaWorth::Bound::Unknown;
};
SavingReach savingReach(const std::vector<SavingFrontPoint>& front, double targetJod);

/// Writes jod_vs_pixels.png (JOD against the share of full resolution's pixels, one curve per
/// curveName, the target's JOD as a line) and jod_vs_pixels.md (the fewest pixels at which each curve
/// reaches the target, the curves at equal pixels, every row) into `dir`; `summary` gets the first two
/// tables. The rows may come from several studies, which must share the scene and its full-resolution
/// row (one cell): otherwise an error, as for a target no row matches or a study without JOD.
Status writeJodAgainstPixels(const std::vector<SavingRow>& rows, const std::optional<SavingTarget>& target,
                             const std::string& dir, std::string* summary = nullptr);

}  // namespace wrsfov::eval
