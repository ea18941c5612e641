// Gaze for a frame end: what a GazeSource reports, turned into the per-eye layers::EyeGaze that a
// FrameEndInfo carries, so that every caller treats a dead, stale or broken source the same way.
// An eye reported invalid here makes the compositor fall back to the view centre with the fallback
// fovea (FrameStats::gazeFallback); it follows gaze again as soon as valid samples return.
#pragma once

#include <array>

#include "gaze/sample.h"
#include "gaze/source.h"
#include "layers/frame.h"

namespace wrsfov::gaze {

/// One eye of `sample` for a frame shown at `frame_t_s` (in the source's time line). The eye is
/// invalid when the sample says so, when its direction is not finite or has no length (it is
/// normalised otherwise), or when the sample's time is not finite or lies more than
/// `policy.hold_s` away from `frame_t_s` (a sample kept from a source that stopped answering).
/// Confidence is clamped to [0, 1]; a confidence that is not a number becomes 0. Invalid eyes keep
/// the default direction (0, 0, -1) and confidence 0.
layers::EyeGaze to_eye_gaze(const GazeSample& sample, int eye, double frame_t_s, const DropoutPolicy& policy = {});

/// Both eyes of `sample` (index 0 left, 1 right), as to_eye_gaze.
std::array<layers::EyeGaze, 2> to_frame_gaze(const GazeSample& sample, double frame_t_s,
                                             const DropoutPolicy& policy = {});

/// Polls `source` at `frame_t_s` and converts the result; no source (none opened, or it was
/// dropped after an error) gives two invalid eyes.
std::array<layers::EyeGaze, 2> frame_gaze(GazeSource* source, double frame_t_s, const DropoutPolicy& policy = {});

}  // namespace wrsfov::gaze
