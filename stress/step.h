// One pixel of one frame through the same shared functions the passes use, in the order the
// shaders call them: load.comp (sanitize, linear depth), foveate.comp with foveation `none`
// (candidate = level 0, weight 0 for an invalid colour) and wrs.comp (validity, depth test,
// combine). The stress runs and the GPU lockstep check use it; it holds no math of its own.
#pragma once

#include "shaders/wrs_common.h"

namespace wrsfov::stress {

/// The candidate of a pixel after the load and foveate passes.
struct Candidate {
    gpu::vec3 color{0.0f};
    float weight = 0.0f;  ///< p̂, 0 when the submitted colour was not finite
    float z = 0.0f;       ///< linear depth, 0 = unknown
};

/// load.comp + foveate.comp (`none`) for one pixel: `weight` is the p̂ the pixel has this frame.
static inline Candidate loadCandidate(gpu::vec3 submittedColor, float weight, float submittedDepth, float nearZ,
                                      float farZ, bool reversed) {
    Candidate c;
    bool valid;
    c.color = gpu::wrs_sanitize_color(submittedColor, valid);
    c.weight = valid ? weight : 0.0f;
    c.z = gpu::wrs_linear_depth(submittedDepth, nearZ, farZ, reversed);
    return c;
}

struct StepOut {
    gpu::Reservoir r;
    bool hadHistory = false;    ///< the combine ran with history
    bool keep = false;          ///< ... and kept the history's sample
    bool historyValid = false;  ///< the loaded history passed wrs_reservoir_valid
    bool flushed = false;       ///< the depth test dropped a valid history
};

/// wrs.comp for one pixel, from the history as loaded (already reprojected: `onScreen` false when the
/// previous position left the image). `hasDepth` is the HAS_DEPTH specialization constant.
static inline StepOut temporalStep(const gpu::Reservoir& hist, bool onScreen, bool hasDepth, const Candidate& cand,
                                   float dz, float tau, float rnd, gpu::uint changeMetric, bool bernoulli) {
    StepOut o;
    const float zCur = hasDepth ? cand.z : 0.0f;
    o.historyValid = gpu::wrs_reservoir_valid(hist);
    bool hasHistory = onScreen && o.historyValid;
    if (hasDepth && hasHistory && gpu::wrs_depth_flush(hist.z, zCur, dz, tau)) {
        hasHistory = false;
        o.flushed = true;
    }
    o.hadHistory = hasHistory;
    o.r = gpu::wrs_combine(hasHistory, hist, cand.color, cand.weight, zCur, rnd, changeMetric, bernoulli, o.keep);
    return o;
}

}  // namespace wrsfov::stress
