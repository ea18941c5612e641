// The stress streams through the real compositor (Compositor::endFrame with swapchain images written
// from the host), with the CPU reference (compositor/reference.h) stepping the same frames in
// lockstep on its own history. Every frame both eyes' packed reservoirs and outputs are read back
// and compared word by word.
//
// Exact: the kept colour (the selection), z and M. Within tolerance: the kept weight w (one fp16 step:
// the device's exp rounds the weight differently) and w_sum (kWsumTolerance). A pixel-frame outside
// that is counted and the reference takes the GPU's history of that eye for the next frame (a resync);
// otherwise the reference runs on its own history all the way (full lockstep).
//
// Layout: one image row per stream, `width` pixels per row (the row's independent samples), both eyes
// (the eye's pixel index is x + eye * width in the stream). The foveate pass computes the weights from
// the gaze, so each eye has a gaze programme instead of the CPU streams' weights:
//   eye 0: gaze alternates between the view centre (whole view inside the fovea: w = 1 exactly) and
//          90° off axis (w ≈ 1.3e-3); every 16th frame the gaze is invalid (fallback fovea, w = 1);
//   eye 1: saccades: fixations of 20 frames anywhere within ±30°, with drift.
// The views are 3° wide, foveation `none` (the candidate is the submitted colour), colour RGBA16F,
// depth R32F, motion RGBA16F (zero except in the rows that stress reprojection).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "compositor/vk_context.h"
#include "layers/status.h"
#include "stress/cpu_stress.h"

namespace wrsfov::stress {

/// What a row does besides its stream's colour and depth.
enum class RowMotion : uint8_t {
    Zero,       ///< motion 0: the history stays in place
    NonFinite,  ///< every other frame (NaN, +Inf, NaN): taken as zero motion
    OffScreen,  ///< every 3rd frame the previous position is off-screen: history dropped
};

struct GpuRow {
    std::string stream;
    RowMotion motion = RowMotion::Zero;
    /// After frame 1 the row's reservoirs are aged (both sides alike): M = 65500 and w_sum = 4095.5,
    /// the fp32 fixed point of a w = 1 pixel after ~9 million frames (docs/stability.md "Safe horizon").
    bool aged = false;
};
std::vector<GpuRow> defaultGpuRows();

struct GpuOptions {
    uint64_t frames = 10000;
    uint32_t width = 16;
    uint32_t seed = 1;
    std::vector<GpuRow> rows;  ///< empty: defaultGpuRows()
    /// Test hook: the reference draws its random numbers with seed + this, which must make the
    /// comparison fail (tests show that it can).
    uint32_t referenceSeedOffset = 0;
    ProgressFn progress;
};

struct GpuRowStats {
    GpuRow row;
    uint64_t pixelFrames = 0;
    uint64_t decisions = 0, kept = 0;  ///< reference combines with history, and how many kept it
    // GPU against the lockstep reference, per pixel-frame.
    uint64_t selectionMismatch = 0;  ///< the GPU kept the history and the reference did not, or the reverse
    uint64_t nearThreshold = 0;      ///< ... of which the random number was within 1e-5 of the keep threshold
    uint64_t weightRounding = 0;     ///< same decision, but the kept w is one fp16 step apart (weight rounding)
    uint64_t zmMismatch = 0;         ///< word 3 (z, M)
    uint64_t wsumMismatch = 0;       ///< word 2 (w_sum) not bit-identical
    uint32_t wsumMaxUlp = 0;
    double wsumMaxRel = 0;     ///< largest relative w_sum difference
    uint64_t outputDiffs = 0;  ///< output bytes that differ
    int outputMaxDiff = 0;
    uint64_t stepMismatch = 0;  ///< stress/step.h on the reference's inputs differs from the reference
    uint64_t nonFinite = 0;     ///< GPU reservoirs with a non-finite field or w_sum <= 0
    double wsumMax = 0;
    uint32_t mMax = 0;
};

/// Relative w_sum difference the lockstep comparison accepts: the weight (exp) and the change term
/// (pow) are built-in functions whose last bits differ between devices; w_sum accumulates them.
inline constexpr double kWsumTolerance = 1e-4;

struct GpuResult {
    std::string device;
    uint32_t width = 0, height = 0;
    uint64_t frames = 0;
    std::vector<GpuRowStats> rows;
    uint64_t resyncs = 0;         ///< frames after which an eye's reference history was replaced by the GPU's
    uint64_t finalIdentical = 0;  ///< pixels whose last packed reservoir is bit-identical on both sides
    uint64_t finalAgree = 0;      ///< ... equal except w_sum within kWsumTolerance
    uint64_t finalPixels = 0;
    uint32_t validationErrors = 0;  ///< Khronos validation errors during the run (when enabled)
    bool validation = false;
    double wall_s = 0;
};

/// Runs the GPU stress on `context`. Fails on unknown row streams or when the compositor refuses.
Result<GpuResult> runGpu(vk::Context& context, const GpuOptions& options);

}  // namespace wrsfov::stress
