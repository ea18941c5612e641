// Sub-pixel jitter as engines render for temporal upsampling (TAAU, FSR 2): a per-frame offset of the
// projection from a low-discrepancy sequence, which a view reports as ProjectionView::sampleOffset.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace wrsfov::layers {

/// The radical inverse of i in `base` (i >= 1): the Halton sequence's i-th value, in [0, 1).
inline double halton(uint64_t i, uint32_t base) {
    double f = 1.0, r = 0.0;
    for (; i > 0; i /= base) {
        f /= base;
        r += f * double(i % base);
    }
    return r;
}

/// The sample offset of frame `frame` (pixels, each component in [-0.5, 0.5)) in a cycle of `phases`
/// phases of the Halton (2, 3) sequence, from its first point; `phases` 0 or 1: no jitter.
inline glm::vec2 haltonJitter(uint64_t frame, uint32_t phases) {
    if (phases <= 1) return glm::vec2(0.0f);
    const uint64_t i = frame % phases + 1;
    return glm::vec2(float(halton(i, 2) - 0.5), float(halton(i, 3) - 0.5));
}

}  // namespace wrsfov::layers
