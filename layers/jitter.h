// Sub-pixel jitter as engines render for temporal upsampling (TAAU, FSR 2): a per-frame offset of the
// projection from a low-discrepancy sequence, which a view reports as ProjectionView::sampleOffset.
#pragma once

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "layers/frame.h"

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

/// `fov` of a w x h view shifted by `o` of its pixels (+x right, +y down): the field of view a view
/// jittered by `o` is rendered through and, in OpenXR, submitted with (the inverse of xr::jitterOf).
inline Fov jitteredFov(const Fov& fov, glm::vec2 o, uint32_t w, uint32_t h) {
    const double l = std::tan(double(fov.angleLeft)), r = std::tan(double(fov.angleRight));
    const double u = std::tan(double(fov.angleUp)), d = std::tan(double(fov.angleDown));
    const double px = (r - l) / w, py = (u - d) / h;
    return {float(std::atan(l + o.x * px)), float(std::atan(r + o.x * px)), float(std::atan(u - o.y * py)),
            float(std::atan(d - o.y * py))};
}

}  // namespace wrsfov::layers
