// The stability study of method `wrs` (quality-aware retention, the tracked 16-byte layout): the
// adversarial streams of stress/streams.h through load, the depth test and wrs_retain with
// wrs_pack_tracked storage, per equal-quality rule. The stream's weight is the candidate's quality
// (as with foveation `none`), its fingerprint the L* of the sanitized colour (a uniform image).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "shaders/wrs_common.h"

namespace wrsfov::stress {

struct RetainStats {
    std::string stream, domain, rule;
    uint64_t pixelFrames = 0;
    uint64_t outcomes[gpu::WRS_OUTCOMES] = {};  ///< WRS_OUT_* counts
    uint64_t nonFiniteStored = 0;     ///< a stored field not finite
    uint64_t validWithoutQuality = 0; ///< stored usable (valid) with q <= 0
    uint64_t zeroQualityReplaced = 0; ///< a q = 0 candidate replaced usable history
    uint64_t nonFiniteOutput = 0;
    double wsumMax = 0, wsumOverQMax = 0;  ///< largest stored w_sum, and w_sum / q
    double wall_s = 0;
    /// Pipeline and Extreme streams must meet every invariant.
    bool mustHold = true;
    bool pass() const {
        return !mustHold || (nonFiniteStored == 0 && validWithoutQuality == 0 && zeroQualityReplaced == 0 &&
                             nonFiniteOutput == 0);
    }
};

/// Runs every stream for `frames` frames x `pixels` pixels with both equal-quality rules.
std::vector<RetainStats> runRetainStress(uint64_t frames, uint32_t pixels, uint32_t seed);
/// A Markdown section (table and verdict) and a CSV of the results.
std::string retainMarkdown(const std::vector<RetainStats>& stats);
std::string retainCsv(const std::vector<RetainStats>& stats);

}  // namespace wrsfov::stress
