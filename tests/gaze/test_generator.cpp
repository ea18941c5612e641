// The generator against published statistics, measured by the independent detectors.
//
// Each statistical test uses one fixed seed, so it is deterministic. The acceptance ranges are
// the issue's. How safe a seed is was measured offline over seeds 1..20 (fixation 60 s, scene
// 120 s) and 1..12 (reading 600 s), mean +- SD across seeds:
//   microsaccade rate 1.63 +- 0.10 /s, median amplitude 6.9 +- 0.6', main-sequence r 0.93 +- 0.02;
//   scene median Vp/Dai 0.992 +- 0.005, median fixation 293 +- 9 ms;
//   reading forward 7.84 +- 0.07 chars, regressions 12.2 +- 0.8 %, sweeps per line change 0.98 +- 0.01.
// Every statistic's mean is at least 2.6 SDs inside its range (regressions are the tightest):
// under a normal approximation a seed fails with < 1 % probability, while a model change that
// shifts a statistic by a few SDs fails the test.
#include <gtest/gtest.h>

#include <cmath>

#include "gaze/angles.h"
#include "gaze/detect.h"
#include "gaze/gaze_file.h"
#include "gaze/generator.h"
#include "gaze/stats.h"

namespace wg = wrsfov::gaze;

namespace {

wg::GeneratedGaze make(wg::Mode mode, double seconds, uint64_t seed, double rate = 1000) {
    wg::GeneratorConfig c;
    c.mode = mode;
    c.seconds = seconds;
    c.seed = seed;
    c.tracker.rate_hz = rate;
    auto g = wg::generate(c);
    EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message);
    return std::move(g.value());
}

// The label column is there for plots and for comparing with the truth; a statistics run must
// not be able to lean on it.
std::vector<wg::GazeSample> unlabelled(std::vector<wg::GazeSample> v) {
    for (wg::GazeSample& s : v) s.label = wg::Event::Unknown;
    return v;
}

}  // namespace

TEST(GeneratorStats, FixationMicrosaccades) {
    const wg::GeneratedGaze g = make(wg::Mode::Fixation, 60, 1);
    ASSERT_EQ(g.samples.size(), 60000u);
    const wg::GazeStats s = wg::compute_stats(unlabelled(g.samples));
    RecordProperty("microsaccade_rate_hz", std::to_string(s.microsaccade_rate_hz));
    EXPECT_GE(s.microsaccade_rate_hz, 1.0);
    EXPECT_LE(s.microsaccade_rate_hz, 3.0);
    EXPECT_GE(s.median_microsaccade_arcmin, 5.0);
    EXPECT_LE(s.median_microsaccade_arcmin, 20.0);
    EXPECT_GE(s.microsaccade_fit.log_correlation, 0.8);
    EXPECT_GE(s.microsaccade_fit.n, 40u);
}

TEST(GeneratorStats, SceneMainSequenceAndFixations) {
    const wg::GeneratedGaze g = make(wg::Mode::Scene, 120, 1);
    const wg::GazeStats s = wg::compute_stats(unlabelled(g.samples));
    EXPECT_GE(s.saccades, 200u);
    EXPECT_NEAR(s.saccade_fit.median_ratio_to_reference, 1.0, 0.2);
    EXPECT_GE(s.median_fixation_ms, 250);
    EXPECT_LE(s.median_fixation_ms, 400);
    // The fitted curve lands inside Dai et al.'s published ranges too.
    EXPECT_GE(s.saccade_fit.eta_deg_s, 300);
    EXPECT_LE(s.saccade_fit.eta_deg_s, 900);
    EXPECT_GE(s.saccade_fit.c_deg, 4.5);
    EXPECT_LE(s.saccade_fit.c_deg, 7.5);
    EXPECT_GE(s.fraction_saccades_le_15, 0.9);  // "most <= 15 deg"
    EXPECT_GT(s.median_saccade_deg, 2);
    EXPECT_LT(s.median_saccade_deg, 6);
}

TEST(GeneratorStats, ReadingSaccadesRegressionsSweeps) {
    wg::GeneratorConfig c;
    c.mode = wg::Mode::Reading;
    c.seconds = 600;
    c.seed = 1;
    auto g = wg::generate(c);
    ASSERT_TRUE(g.ok());
    wg::StatsOptions o;
    o.reading = wg::ReadingLayout{c.reading.char_deg, c.reading.line_spacing_deg};
    const wg::GazeStats s = wg::compute_stats(unlabelled(g->samples), o);
    ASSERT_TRUE(s.reading.has_value());
    const wg::ReadingStats& r = *s.reading;
    EXPECT_GE(r.median_forward_chars, 7);
    EXPECT_LE(r.median_forward_chars, 9);
    EXPECT_GE(r.regression_fraction, 0.10);
    EXPECT_LE(r.regression_fraction, 0.15);
    EXPECT_NEAR(r.sweeps_per_line_change, 1.0, 0.05);
    // Sweeps hidden by blinks aside, every executed line change is seen as one return sweep.
    EXPECT_LE(r.return_sweeps, static_cast<size_t>(g->line_changes));
    EXPECT_GE(r.return_sweeps, static_cast<size_t>(0.85 * g->line_changes));
    EXPECT_GE(s.median_fixation_ms, 150);
    EXPECT_LE(s.median_fixation_ms, 300);
}

TEST(GeneratorStats, PursuitFollowsTheTarget) {
    const wg::GeneratedGaze g = make(wg::Mode::Pursuit, 60, 1);
    wg::StatsOptions o;
    o.ivt.pursuit_threshold_deg_s = 4;
    const wg::GazeStats s = wg::compute_stats(unlabelled(g.samples), o);
    EXPECT_GE(s.pursuits, 20u);
    // Targets move at 5..20 deg/s with gain 0.92: a typical pursuit speed near 11.5 deg/s.
    EXPECT_GT(s.median_pursuit_speed_deg_s, 8);
    EXPECT_LT(s.median_pursuit_speed_deg_s, 15);
    EXPECT_GT(s.saccades, 20u);  // catch-up and return saccades
}

TEST(Generator, SameSeedSameFileDifferentSeedDifferent) {
    for (wg::Mode m : {wg::Mode::Fixation, wg::Mode::Scene, wg::Mode::Reading, wg::Mode::Pursuit}) {
        const std::string a = wg::format_gaze_csv(make(m, 5, 42).samples, true);
        const std::string b = wg::format_gaze_csv(make(m, 5, 42).samples, true);
        const std::string c = wg::format_gaze_csv(make(m, 5, 43).samples, true);
        EXPECT_EQ(a, b) << wg::mode_name(m);
        EXPECT_NE(a, c) << wg::mode_name(m);
    }
}

TEST(Generator, TrackerRateLatencyNoiseDropouts) {
    wg::GeneratorConfig c;
    c.mode = wg::Mode::Scene;
    c.seconds = 20;
    c.seed = 9;
    c.blinks_enabled = false;
    c.tracker.noise_deg = 0;
    c.tracker.dropout_per_s = 0;
    const auto base = wg::generate(c);
    ASSERT_TRUE(base.ok());

    // Rate: 90 Hz gives 90 samples a second, evenly spaced.
    wg::GeneratorConfig r = c;
    r.tracker.rate_hz = 90;
    const auto slow = wg::generate(r);
    ASSERT_TRUE(slow.ok());
    EXPECT_EQ(slow->samples.size(), 1800u);
    EXPECT_NEAR(slow->samples[1].t_s - slow->samples[0].t_s, 1.0 / 90, 1e-12);

    // Latency: the same eye, shown 50 ms later.
    wg::GeneratorConfig l = c;
    l.tracker.latency_s = 0.05;
    const auto late = wg::generate(l);
    ASSERT_TRUE(late.ok());
    for (size_t i = 1000; i < 19000; i += 997)
        EXPECT_LT(wg::angle_between_deg(late->samples[i].eye[0].dir, base->samples[i - 50].eye[0].dir), 1e-4) << i;

    // Noise: RMS per axis as configured (within 5 %).
    wg::GeneratorConfig n = c;
    n.tracker.noise_deg = 0.05;
    const auto noisy = wg::generate(n);
    ASSERT_TRUE(noisy.ok());
    double sum = 0;
    for (size_t i = 0; i < noisy->samples.size(); ++i) {
        const wg::GazeAngle a = wg::angle_from_direction(noisy->samples[i].eye[0].dir);
        const wg::GazeAngle b = wg::angle_from_direction(base->samples[i].eye[0].dir);
        sum += (a.az_deg - b.az_deg) * (a.az_deg - b.az_deg);
    }
    EXPECT_NEAR(std::sqrt(sum / noisy->samples.size()), 0.05, 0.0025);

    // Dropouts: 5 losses a second of 20 ms mean -> about 9 % of the samples invalid.
    wg::GeneratorConfig d = c;
    d.tracker.dropout_per_s = 5;
    d.tracker.dropout_mean_s = 0.02;
    const auto lossy = wg::generate(d);
    ASSERT_TRUE(lossy.ok());
    size_t invalid = 0;
    for (const wg::GazeSample& s : lossy->samples) invalid += s.eye[0].valid ? 0 : 1;
    const double frac = static_cast<double>(invalid) / lossy->samples.size();
    EXPECT_GT(frac, 0.05);
    EXPECT_LT(frac, 0.14);
}

TEST(Generator, BlinksAtPublishedRate) {
    const wg::GeneratedGaze g = make(wg::Mode::Fixation, 300, 3, 250);
    const wg::GazeStats s = wg::compute_stats(g.samples);
    EXPECT_GE(s.blinks_per_minute, 12);
    EXPECT_LE(s.blinks_per_minute, 22);
    EXPECT_GE(s.median_blink_ms, 100);
    EXPECT_LE(s.median_blink_ms, 400);
    size_t blink_labels = 0;
    for (const wg::GazeSample& x : g.samples) blink_labels += x.label == wg::Event::Blink ? 1 : 0;
    EXPECT_GT(blink_labels, 0u);
}

TEST(Generator, RejectsBadConfig) {
    wg::GeneratorConfig c;
    c.tracker.rate_hz = 2000;
    auto g = wg::generate(c);
    ASSERT_FALSE(g.ok());
    EXPECT_NE(g.error().message.find("rate"), std::string::npos);
    c = {};
    c.seconds = -1;
    EXPECT_FALSE(wg::generate(c).ok());
    c = {};
    c.reading.char_deg = 0;
    EXPECT_FALSE(wg::generate(c).ok());
}

TEST(Generator, TruthLabelsMatchEvents) {
    const wg::GeneratedGaze g = make(wg::Mode::Scene, 10, 2);
    size_t saccade_events = 0;
    for (const wg::TrueEvent& e : g.events) saccade_events += e.type == wg::Event::Saccade ? 1 : 0;
    EXPECT_GT(saccade_events, 15u);
    size_t labelled = 0;
    for (const wg::GazeSample& s : g.samples) labelled += s.label == wg::Event::Saccade ? 1 : 0;
    EXPECT_GT(labelled, saccade_events * 15);  // >= 21 ms each at 1 kHz, minus blinks
}
