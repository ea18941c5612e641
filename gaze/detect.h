// Event detectors that validate gaze: Engbert & Kliegl microsaccades and I-VT saccades.
//
// They work on any gaze file and share no code with the generator: they see only timestamps,
// directions and validity.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "gaze/sample.h"

namespace wrsfov::gaze {

/// A gaze recording as angle time series (cyclopean azimuth/elevation in degrees).
struct AngleTrace {
    std::vector<double> t_s;
    std::vector<double> az_deg, el_deg;
    std::vector<uint8_t> valid;
    double dt_s = 0;  ///< median sample interval

    size_t size() const { return t_s.size(); }
};

/// Converts samples to angles (cyclopean direction of the valid eyes).
AngleTrace to_angle_trace(std::span<const GazeSample> samples);

/// Velocity from a 5-sample window (Engbert & Kliegl 2003):
/// v_n = (x_{n+2} + x_{n+1} - x_{n-1} - x_{n-2}) / (6 dt). Samples whose window is not entirely
/// valid get `vvalid = 0`.
struct Velocity {
    std::vector<double> vx, vy;  ///< deg/s
    std::vector<uint8_t> vvalid;
};
Velocity velocity_5pt(const AngleTrace& trace);

/// A detected movement.
struct DetectedEvent {
    Event type = Event::Unknown;
    size_t begin = 0, end = 0;  ///< sample indices, end exclusive
    double t0_s = 0, t1_s = 0;
    double amplitude_deg = 0;
    double peak_velocity_deg_s = 0;
    double dx_deg = 0, dy_deg = 0;  ///< displacement from first to last sample
    double cx_deg = 0, cy_deg = 0;  ///< mean position (azimuth, elevation)
    bool clean = true;              ///< no invalid sample next to it (safe for main-sequence fits)

    double duration_s() const { return t1_s - t0_s; }
};

/// Engbert & Kliegl (2003) parameters.
struct EngbertKlieglParams {
    double lambda = 6;               ///< threshold multiplier of the median-based SD
    size_t min_samples = 3;          ///< minimum duration in samples
    double min_duration_s = 0.006;   ///< and in time (whichever is longer)
    double merge_gap_s = 0.01;       ///< events closer than this merge (overshoots)
    double max_amplitude_deg = 1.0;  ///< larger events are saccades, not microsaccades
};

/// Result of the Engbert & Kliegl detector.
struct EngbertKlieglResult {
    std::vector<DetectedEvent> microsaccades;
    double sigma_x = 0, sigma_y = 0;  ///< median-based velocity SD (deg/s)
    double eta_x = 0, eta_y = 0;      ///< thresholds (deg/s)
};

/// Detects microsaccades: samples outside the ellipse (vx/eta_x)^2 + (vy/eta_y)^2 = 1 with
/// eta = lambda * sqrt(median(v^2) - median(v)^2), runs of at least `min_samples`.
EngbertKlieglResult detect_microsaccades(const AngleTrace& trace, const EngbertKlieglParams& p = {});

/// I-VT parameters (Salvucci & Goldberg 2000), with an optional I-VVT pursuit band.
struct IvtParams {
    double saccade_threshold_deg_s = 30;
    double pursuit_threshold_deg_s = 0;  ///< > 0: slow segments moving faster than this are pursuit
    double min_fixation_s = 0.05;        ///< shorter inter-saccadic segments are dropped
    double blink_min_s = 0.05;           ///< invalid runs at least this long count as blinks
    double blink_max_s = 0.6;
};

/// Result of I-VT: saccades, fixations (or pursuit segments) and blinks, each in time order.
struct IvtResult {
    std::vector<DetectedEvent> saccades;
    std::vector<DetectedEvent> fixations;
    std::vector<DetectedEvent> pursuits;
    std::vector<DetectedEvent> blinks;
    size_t dropouts = 0;  ///< invalid runs too short or too long to be blinks
};

/// Velocity-threshold identification. Saccade bounds are extended outward while the speed keeps
/// falling, so that amplitudes include the slow start and end of the movement.
IvtResult detect_ivt(const AngleTrace& trace, const IvtParams& p = {});

}  // namespace wrsfov::gaze
