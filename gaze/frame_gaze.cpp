#include "gaze/frame_gaze.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace wrsfov::gaze {

layers::EyeGaze to_eye_gaze(const GazeSample& sample, int eye, double frame_t_s, const DropoutPolicy& policy) {
    layers::EyeGaze out;  // invalid: the compositor's fallback
    if (eye < 0 || eye > 1) return out;
    const EyeGaze& g = sample.eye[eye];
    if (!g.valid) return out;
    if (!std::isfinite(sample.t_s) || !std::isfinite(frame_t_s) || !(std::abs(frame_t_s - sample.t_s) <= policy.hold_s))
        return out;
    if (!std::isfinite(g.dir.x) || !std::isfinite(g.dir.y) || !std::isfinite(g.dir.z)) return out;
    const float len = glm::length(g.dir);
    if (!std::isfinite(len) || !(len > 0.0f)) return out;
    out.dir = g.dir / len;
    out.valid = true;
    out.confidence = std::isnan(g.confidence) ? 0.0f : std::clamp(g.confidence, 0.0f, 1.0f);
    return out;
}

std::array<layers::EyeGaze, 2> to_frame_gaze(const GazeSample& sample, double frame_t_s, const DropoutPolicy& policy) {
    return {to_eye_gaze(sample, 0, frame_t_s, policy), to_eye_gaze(sample, 1, frame_t_s, policy)};
}

std::array<layers::EyeGaze, 2> frame_gaze(GazeSource* source, double frame_t_s, const DropoutPolicy& policy) {
    if (!source) return {};
    return to_frame_gaze(source->sample(frame_t_s), frame_t_s, policy);
}

}  // namespace wrsfov::gaze
