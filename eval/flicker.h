// Where kept samples flicker: per pixel and frame pair, the frame-to-frame change of `wrs`'s output
// against `fov`'s over the pixels where the reference does not change (the temporal instability's
// pixels, eval/metrics.h), split by what `wrs` showed at the pixel in the two frames: its candidate
// (the same output as `fov`) or something kept, by the kept sample's quality, and whether the pixel
// changed state. Written as flicker.md, flicker.csv and a map of where the excess is (flicker.png).
// `wrsfov-bench --flicker` runs it for the first scene, mode and fovea of the options.
#pragma once

#include <string>
#include <vector>

#include "compositor/vk_context.h"
#include "eval/bench.h"
#include "layers/status.h"

namespace wrsfov::eval {

/// One class of stable pixel pairs.
struct FlickerClass {
    std::string name;
    uint64_t pairs = 0;    ///< stable pixel pairs (left eye) in the class
    double wrsChange = 0;  ///< sum over them of the mean over channels of |Δ wrs|, sRGB 0..1
    double fovChange = 0;  ///< the same for `fov`
    double refChange = 0;  ///< the same for the reference (at most one 8-bit step per channel)
    /// Sums of the error's change, the mean over channels of |Δ (output - reference)|: what a viewer
    /// sees flicker against the scene's own motion.
    double wrsErrorChange = 0, fovErrorChange = 0;
    /// Sums of the error itself now, the mean over channels of |output - reference|.
    double wrsError = 0, fovError = 0;
    /// The change (as wrsChange) of `wrs` with every pixel that shows a full-rate kept sample showing the
    /// reference instead: a display of those samples with no error at all, where `wrs` keeps them.
    double exactKeptChange = 0;
    /// The same with every other pixel showing `fov`'s output: the excess over `fov` is then only the
    /// full-rate kept detail, shown without error, and its steps to and from `fov`'s output.
    double exactKeptFovChange = 0;
};

/// A connected patch (8-neighbourhood) of pixels that showed a sharper kept sample in one frame and
/// their candidate in the next, a candidate less sharp than the sample stored there in the first frame:
/// where a kept region loses a block at once (not where the gaze arrives with sharper candidates).
struct DropPatch {
    int frame = 0;                            ///< the frame the candidate was shown in
    int x = 0, y = 0, width = 0, height = 0;  ///< bounding box, left eye's pixels
    int area = 0;                             ///< pixels in the patch
    std::string reason;                       ///< the most frequent reason among them (FlickerReport::drops' names)
    double reasonShare = 0;                   ///< its share of the patch's pixels
};

struct FlickerReport {
    std::vector<FlickerClass> classes;
    uint64_t stablePairs = 0;  ///< all stable pixel pairs counted
    /// Temporal instability of each method over the same pairs (eval/metrics.h's definition).
    double wrsInstability = 0, fovInstability = 0, refInstability = 0;
    /// Mean over the same pairs of the error's change (FlickerClass::wrsErrorChange).
    double wrsErrorInstability = 0, fovErrorInstability = 0;
    /// Temporal instability over the same pairs of `wrs` with its full-rate kept samples shown exactly
    /// (FlickerClass::exactKeptChange), with `wrs`'s choice of where and what to keep: what a display of
    /// them without error gives; a steadier display of them must depart from the reference.
    double exactKeptInstability = 0;
    /// The same with every other pixel showing `fov`'s output (FlickerClass::exactKeptFovChange).
    double exactKeptFovInstability = 0;
    /// Pixels (all, not only stable ones) that showed a sharper kept sample in one frame and their
    /// candidate in the next, by the retention outcome of the CPU reference run on the GPU's history
    /// (WRS_OUT_*; "no history" where the tracked lookup found no sample).
    std::vector<std::pair<std::string, uint64_t>> drops;
    /// The losses among those drops (DropPatch) as patches of at least kMinDropPatch pixels, largest first.
    std::vector<DropPatch> patches;
    static constexpr int kMinDropPatch = 16;
};

/// Runs the reference, `fov` and `wrs` (CompositorConfig defaults with the options' mode, fovea, seed
/// and sparse-retention switches) on options.scenes.front() and classifies every stable pixel pair of
/// the left eye after the warm-up frames. Writes flicker.md, flicker.csv and flicker.png into `dir`
/// when it is not empty.
Result<FlickerReport> analyseFlicker(vk::Context& ctx, const BenchOptions& options, const std::string& dir);

}  // namespace wrsfov::eval
