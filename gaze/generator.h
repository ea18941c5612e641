// Synthetic eye movements: seeded, deterministic gaze that moves like real eyes.
//
// The generator simulates a cyclopean gaze angle on a 4 kHz grid (drift, microsaccades, saccades
// on the main sequence with landing error and post-saccadic settling, smooth pursuit, blinks),
// then samples it like a tracker would (rate, latency, noise, dropouts). Both eyes get the same
// direction: vergence is not modelled. All randomness comes from cv::RNG streams derived from
// the seed, one per component, so changing the tracker model leaves the eye trajectory as it was.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "gaze/angles.h"
#include "gaze/result.h"
#include "gaze/sample.h"

namespace wrsfov::gaze {

/// What the simulated observer does.
enum class Mode { Fixation, Scene, Reading, Pursuit };

std::string_view mode_name(Mode m);
std::optional<Mode> parse_mode(std::string_view name);

/// Saccade kinematics (Dai et al. 2016 peak velocity; Carpenter duration).
struct MainSequence {
    double eta_deg_s = 600;  ///< asymptotic peak velocity
    double c_deg = 6;        ///< amplitude constant
    double duration_slope_ms = 2.2;
    double duration_intercept_ms = 21;

    /// Vp = eta (1 - exp(-A / c)).
    double peak_velocity(double amplitude_deg) const;
    /// D = slope A + intercept, in seconds.
    double duration_s(double amplitude_deg) const;
};

/// How saccades are executed.
struct SaccadeModel {
    MainSequence main;
    double landing_gain = 0.97;      ///< mean gain (undershoot), Kowler & Blaser 1995
    double landing_sd = 0.07;        ///< landing error SD as a fraction of the amplitude
    double velocity_jitter = 0.08;   ///< log-normal SD of eta between saccades
    double settle_fraction = 0.015;  ///< post-saccadic oscillation amplitude as a fraction of A
    double settle_max_deg = 0.2;
    double settle_freq_hz = 15;
    double settle_tau_s = 0.02;
};

/// Fixational eye movements: drift and microsaccades (Engbert; Martinez-Conde 2009).
struct FixationalModel {
    double microsaccade_interval_mean_s = 0.45;
    double microsaccade_interval_shape = 5;
    double microsaccade_amplitude_mean_arcmin = 8;
    double microsaccade_amplitude_shape = 4;
    double microsaccade_amplitude_max_deg = 1;
    double drift_speed_deg_s = 0.35;   ///< RMS drift velocity per axis (Ornstein-Uhlenbeck velocity)
    double drift_tau_s = 0.04;         ///< drift velocity correlation time
    double drift_restore_per_s = 0.5;  ///< weak pull back to the fixated point
};

/// Free viewing of a scene (Rayner 1998; Bahill 1975).
struct SceneModel {
    double fixation_mean_s = 0.35;
    double fixation_shape = 5;
    double fixation_min_s = 0.08;
    double saccade_mean_deg = 4;
    double saccade_shape = 2;
    double saccade_min_deg = 0.5;
    double saccade_max_deg = 30;
    double half_width_deg = 20;  ///< the scene spans +-half_width in azimuth
    double half_height_deg = 12;
};

/// Reading lines of text (Rayner 1998).
struct ReadingModel {
    double char_deg = 0.3;          ///< width of one character
    double line_spacing_deg = 1.0;  ///< distance between lines
    int line_chars = 70;            ///< characters per line
    int lines_per_page = 8;
    double fixation_mean_s = 0.245;
    double fixation_shape = 8;
    double fixation_min_s = 0.1;
    double fixation_max_s = 0.5;
    double forward_mean_chars = 8.8;
    double forward_shape = 6;
    double regression_prob = 0.11;
    double regression_mean_chars = 4.5;
    double line_start_mean_chars = 4;  ///< where the first fixation of a line lands
};

/// Step-ramp smooth pursuit trials (Rashbass 1961).
struct PursuitModel {
    double speed_min_deg_s = 5;
    double speed_max_deg_s = 20;
    double ramp_s = 1.5;
    double rest_s = 0.6;
    double latency_s = 0.15;
    double gain = 0.92;
    double tau_s = 0.08;             ///< eye velocity follows the target with this lag
    double catchup_error_deg = 1.0;  ///< position error that triggers a catch-up saccade
};

/// Blinks: samples are invalid while the lid is closed.
struct BlinkModel {
    double per_minute = 17;
    double min_s = 0.1;
    double max_s = 0.4;
};

/// The tracker that samples the eye (Niehorster et al.).
struct TrackerModel {
    double rate_hz = 1000;         ///< 90..1000 Hz
    double latency_s = 0;          ///< a sample at t shows the eye at t - latency
    double noise_deg = 0.005;      ///< RMS white noise per axis
    double dropout_per_s = 0.2;    ///< rate of tracking losses
    double dropout_mean_s = 0.01;  ///< mean length of one loss (exponential)
    double loss_probability = 0;   ///< independent per-sample loss
};

/// Everything the generator needs.
struct GeneratorConfig {
    Mode mode = Mode::Fixation;
    double seconds = 10;
    uint64_t seed = 1;
    bool blinks_enabled = true;
    SaccadeModel saccade;
    FixationalModel fixational;
    SceneModel scene;
    ReadingModel reading;
    PursuitModel pursuit;
    BlinkModel blinks;
    TrackerModel tracker;

    /// Checks ranges (rate 90..1000 Hz, at most an hour, positive durations, ...); the message names the field.
    Status validate() const;
};

/// An event as the generator executed it (ground truth).
struct TrueEvent {
    Event type = Event::Unknown;
    double t0_s = 0, t1_s = 0;
    double amplitude_deg = 0;
    double peak_velocity_deg_s = 0;
    GazeAngle from, to;
};

/// Generator output: tracker samples plus the truth behind them.
struct GeneratedGaze {
    std::vector<GazeSample> samples;  ///< labelled with the true event
    std::vector<TrueEvent> events;    ///< saccades, microsaccades, blinks, pursuit ramps
    int line_changes = 0;             ///< reading: return sweeps executed
    int pages = 0;                    ///< reading: page turns executed
};

/// Generates `config.seconds` of gaze. Deterministic for a given config.
Result<GeneratedGaze> generate(const GeneratorConfig& config);

}  // namespace wrsfov::gaze
