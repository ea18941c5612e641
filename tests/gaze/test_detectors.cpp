// The detectors on hand-made signals (no generator involved).
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/core.hpp>

#include "gaze/angles.h"
#include "gaze/detect.h"
#include "gaze/stats.h"

namespace wg = wrsfov::gaze;

namespace {

// Minimum-jerk position profile: peak velocity is 1.875 A / D.
double min_jerk(double s) {
    s = std::clamp(s, 0.0, 1.0);
    return s * s * s * (10 - 15 * s + 6 * s * s);
}

struct Move {
    double t0, dur, dx, dy;
};

std::vector<wg::GazeSample> trace(double seconds, double rate, const std::vector<Move>& moves, double noise,
                                  uint64_t seed) {
    cv::RNG rng(seed);
    std::vector<wg::GazeSample> v;
    for (int i = 0; i < static_cast<int>(seconds * rate); ++i) {
        const double t = i / rate;
        double x = 0, y = 0;
        for (const Move& m : moves) {
            const double f = min_jerk((t - m.t0) / m.dur);
            x += m.dx * f;
            y += m.dy * f;
        }
        v.push_back(wg::sample_from_angle(t, {x + rng.gaussian(noise), y + rng.gaussian(noise)}, true));
    }
    return v;
}

}  // namespace

TEST(Ivt, FindsOneSaccadeWithItsAmplitudeAndPeak) {
    const auto v = trace(1.0, 1000, {{0.4, 0.045, 10, 0}}, 0.01, 1);
    const wg::IvtResult r = wg::detect_ivt(wg::to_angle_trace(v));
    ASSERT_EQ(r.saccades.size(), 1u);
    const wg::DetectedEvent& s = r.saccades[0];
    EXPECT_NEAR(s.amplitude_deg, 10, 0.5);
    EXPECT_NEAR(s.peak_velocity_deg_s, 1.875 * 10 / 0.045, 0.05 * 1.875 * 10 / 0.045);
    EXPECT_NEAR(s.t0_s, 0.4, 0.01);
    EXPECT_NEAR(s.duration_s(), 0.045, 0.015);
    ASSERT_EQ(r.fixations.size(), 2u);
    EXPECT_NEAR(r.fixations[0].duration_s(), 0.4, 0.02);
    EXPECT_NEAR(r.fixations[1].cx_deg, 10, 0.05);
}

TEST(Ivt, InvalidRunsAreBlinksOrDropouts) {
    auto v = trace(2.0, 500, {}, 0.01, 2);
    for (size_t i = 250; i < 350; ++i) v[i].eye[0].valid = v[i].eye[1].valid = false;  // 200 ms: blink
    for (size_t i = 600; i < 603; ++i) v[i].eye[0].valid = v[i].eye[1].valid = false;  // 6 ms: dropout
    const wg::IvtResult r = wg::detect_ivt(wg::to_angle_trace(v));
    ASSERT_EQ(r.blinks.size(), 1u);
    EXPECT_NEAR(r.blinks[0].duration_s(), 0.2, 0.005);
    EXPECT_EQ(r.dropouts, 1u);
    EXPECT_TRUE(r.saccades.empty());
    // No velocity is taken across a gap.
    const wg::Velocity vel = wg::velocity_5pt(wg::to_angle_trace(v));
    for (size_t i = 248; i < 352; ++i) EXPECT_FALSE(vel.vvalid[i]) << i;
}

TEST(EngbertKliegl, FindsMicrosaccadesAboveNoise) {
    // Three 15' microsaccades of 15 ms in 0.01 deg noise at 1000 Hz.
    const double a = 15.0 / 60;
    const auto v =
        trace(3.0, 1000, {{0.5, 0.015, a, 0}, {1.4, 0.015, 0, -a}, {2.3, 0.015, -a * 0.7, a * 0.7}}, 0.005, 3);
    const wg::EngbertKlieglResult r = wg::detect_microsaccades(wg::to_angle_trace(v));
    ASSERT_EQ(r.microsaccades.size(), 3u);
    for (const wg::DetectedEvent& m : r.microsaccades) {
        EXPECT_GT(m.amplitude_deg * 60, 9);
        EXPECT_LT(m.amplitude_deg * 60, 17);
    }
    EXPECT_NEAR(r.microsaccades[1].t0_s, 1.4, 0.01);
    // The 5-point velocity of white noise has SD sqrt(4) sigma / (6 dt); the median-based
    // estimator sqrt(median(v^2) - median(v)^2) gives 0.6745 of that for Gaussian data.
    EXPECT_NEAR(r.sigma_x, 0.6745 * 2 * 0.005 / 0.006, 0.15);
}

TEST(EngbertKliegl, QuietOnNoiseAlone) {
    const auto v = trace(5.0, 1000, {}, 0.005, 4);
    const wg::EngbertKlieglResult r = wg::detect_microsaccades(wg::to_angle_trace(v));
    // lambda = 6 with >= 3 samples: Gaussian noise almost never qualifies.
    EXPECT_LE(r.microsaccades.size(), 1u);
}

TEST(Detectors, DegenerateInputs) {
    EXPECT_TRUE(wg::detect_ivt(wg::to_angle_trace({})).saccades.empty());
    EXPECT_TRUE(wg::detect_microsaccades(wg::to_angle_trace({})).microsaccades.empty());
    std::vector<wg::GazeSample> invalid(100);
    for (size_t i = 0; i < invalid.size(); ++i) invalid[i].t_s = i * 0.001;
    const wg::GazeStats s = wg::compute_stats(invalid);
    EXPECT_EQ(s.saccades, 0u);
    EXPECT_EQ(s.valid_fraction, 0);
    // A noiseless constant signal.
    const auto still = trace(1.0, 1000, {}, 0, 5);
    EXPECT_TRUE(wg::detect_microsaccades(wg::to_angle_trace(still)).microsaccades.empty());
}

TEST(MainSequenceFit, RecoversDaiParameters) {
    std::vector<wg::DetectedEvent> ev;
    for (double a = 0.5; a < 25; a *= 1.15) {
        wg::DetectedEvent e;
        e.amplitude_deg = a;
        e.peak_velocity_deg_s = 500 * (1 - std::exp(-a / 5));
        ev.push_back(e);
    }
    const wg::MainSequenceFit f = wg::fit_main_sequence(ev, 500, 5);
    EXPECT_NEAR(f.eta_deg_s, 500, 10);
    EXPECT_NEAR(f.c_deg, 5, 0.15);
    EXPECT_NEAR(f.median_ratio_to_reference, 1, 1e-9);
    EXPECT_GT(f.log_correlation, 0.9);
}
