// Summary statistics of a gaze recording from the independent detectors, next to published values.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "gaze/detect.h"
#include "gaze/sample.h"

namespace wrsfov::gaze {

/// Fit of Vp = eta (1 - exp(-A / c)) to detected events, in log space, plus how the events sit
/// against a reference main sequence.
struct MainSequenceFit {
    size_t n = 0;
    double eta_deg_s = 0, c_deg = 0;
    double log_rmse = 0;                   ///< RMS of log(Vp / fit)
    double median_ratio_to_reference = 0;  ///< median of Vp / (eta_ref (1 - exp(-A / c_ref)))
    double log_correlation = 0;            ///< Pearson r of log A vs log Vp
};

/// Fits the main sequence to the `clean` events with amplitude > 0 and peak velocity > 0.
MainSequenceFit fit_main_sequence(std::span<const DetectedEvent> events, double ref_eta = 600, double ref_c = 6);

/// Text layout for the reading analysis.
struct ReadingLayout {
    double char_deg = 0.3;
    double line_spacing_deg = 1.0;
};

/// Reading measures from I-VT saccades: forward saccades and regressions stay on a line (vertical
/// change below half a line), return sweeps go down a line and to the left, page turns go up.
struct ReadingStats {
    size_t forward = 0, regressions = 0, return_sweeps = 0, page_turns = 0;
    double median_forward_chars = 0;
    double median_regression_chars = 0;
    double regression_fraction = 0;     ///< regressions / (forward + regressions)
    size_t line_changes = 0;            ///< consecutive fixations one line lower, no blink between
    double sweeps_per_line_change = 0;  ///< return sweeps between the fixations of a line change
};

ReadingStats analyse_reading(const IvtResult& ivt, const ReadingLayout& layout);

/// Options for `compute_stats`.
struct StatsOptions {
    EngbertKlieglParams ek;
    IvtParams ivt;
    std::optional<ReadingLayout> reading;  ///< set to get reading measures
};

/// Everything `wrsfov-gaze stats` prints.
struct GazeStats {
    size_t samples = 0;
    double duration_s = 0, rate_hz = 0, valid_fraction = 0, valid_s = 0;
    // Blinks.
    size_t blinks = 0, dropouts = 0;
    double blinks_per_minute = 0, median_blink_ms = 0;
    // Microsaccades (Engbert & Kliegl), counted inside I-VT fixations.
    size_t microsaccades = 0;
    double microsaccade_rate_hz = 0, median_microsaccade_arcmin = 0, median_microsaccade_ms = 0;
    double ek_sigma_x = 0, ek_sigma_y = 0;
    MainSequenceFit microsaccade_fit;
    // Saccades (I-VT).
    size_t saccades = 0;
    double saccade_rate_hz = 0, median_saccade_deg = 0, median_saccade_ms = 0, fraction_saccades_le_15 = 0;
    MainSequenceFit saccade_fit;
    // Fixations and pursuit.
    size_t fixations = 0;
    double median_fixation_ms = 0, mean_fixation_ms = 0;
    size_t pursuits = 0;
    double median_pursuit_speed_deg_s = 0;
    std::optional<ReadingStats> reading;

    IvtResult ivt;  ///< the detected events, for plots
    EngbertKlieglResult ek;
};

GazeStats compute_stats(std::span<const GazeSample> samples, const StatsOptions& options = {});

/// Human-readable table with the published values beside the measured ones.
std::string format_stats(const GazeStats& s);

/// Median of a list (0 for an empty one).
double median(std::vector<double> v);

}  // namespace wrsfov::gaze
