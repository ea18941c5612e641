#include <gtest/gtest.h>

#include <cmath>

#include "gaze/angles.h"
#include "gaze/source.h"

namespace wg = wrsfov::gaze;

TEST(GazeAngles, AxesFollowOpenXr) {
    const glm::vec3 ahead = wg::direction_from_angle({0, 0});
    EXPECT_NEAR(ahead.z, -1, 1e-6);
    const glm::vec3 right = wg::direction_from_angle({90, 0});
    EXPECT_NEAR(right.x, 1, 1e-6);
    const glm::vec3 up = wg::direction_from_angle({0, 90});
    EXPECT_NEAR(up.y, 1, 1e-6);
}

TEST(GazeAngles, RoundTrip) {
    for (double az = -80; az <= 80; az += 7.3)
        for (double el = -60; el <= 60; el += 5.9) {
            const wg::GazeAngle a = wg::angle_from_direction(wg::direction_from_angle({az, el}));
            EXPECT_NEAR(a.az_deg, az, 1e-4);
            EXPECT_NEAR(a.el_deg, el, 1e-4);
        }
    EXPECT_NEAR(wg::angle_between_deg(wg::direction_from_angle({0, 0}), wg::direction_from_angle({0, 1.0 / 60})),
                1.0 / 60, 1e-5);
}

TEST(GazeAngles, EventNames) {
    for (int i = 0; i <= static_cast<int>(wg::Event::Unknown); ++i) {
        const auto e = static_cast<wg::Event>(i);
        EXPECT_EQ(wg::parse_event(wg::event_name(e)), e);
    }
    EXPECT_EQ(wg::parse_event("Saccade"), wg::Event::Saccade);
    EXPECT_FALSE(wg::parse_event("wink").has_value());
}

namespace {
std::vector<wg::GazeSample> ramp() {
    // 100 Hz, azimuth = t degrees per 10 ms; invalid from 0.10 s to 0.30 s.
    std::vector<wg::GazeSample> v;
    for (int i = 0; i <= 40; ++i) {
        const double t = i * 0.01;
        v.push_back(wg::sample_from_angle(t, {static_cast<double>(i), 0}, !(t > 0.095 && t < 0.305)));
    }
    return v;
}
}  // namespace

TEST(GazeSource, InterpolatesBetweenValidSamples) {
    const auto v = ramp();
    const wg::GazeSample s = wg::interpolate_samples(v, 0.055, {});
    ASSERT_TRUE(s.eye[0].valid && s.eye[1].valid);
    EXPECT_NEAR(wg::angle_from_direction(s.eye[0].dir).az_deg, 5.5, 1e-3);
    EXPECT_DOUBLE_EQ(s.t_s, 0.055);
}

TEST(GazeSource, HoldsLastValidUpToLimitThenInvalid) {
    const auto v = ramp();
    wg::DropoutPolicy p;
    p.hold_s = 0.1;
    const wg::GazeSample held = wg::interpolate_samples(v, 0.15, p);  // last valid at 0.09: 60 ms old
    ASSERT_TRUE(held.eye[0].valid);
    EXPECT_NEAR(wg::angle_from_direction(held.eye[0].dir).az_deg, 9, 1e-3);
    const wg::GazeSample lost = wg::interpolate_samples(v, 0.25, p);  // 160 ms old
    EXPECT_FALSE(lost.eye[0].valid);
    EXPECT_FALSE(lost.eye[1].valid);
    // After the end of the data the same policy applies.
    EXPECT_TRUE(wg::interpolate_samples(v, 0.45, p).eye[0].valid);
    EXPECT_FALSE(wg::interpolate_samples(v, 0.55, p).eye[0].valid);
    // Before the first sample, and garbage times.
    EXPECT_FALSE(wg::interpolate_samples(v, -1, p).eye[0].valid);
    EXPECT_FALSE(wg::interpolate_samples(v, std::nan(""), p).eye[0].valid);
    EXPECT_FALSE(wg::interpolate_samples({}, 0, p).eye[0].valid);
}

TEST(GazeSource, PerEyeValidity) {
    std::vector<wg::GazeSample> v = {wg::sample_from_angle(0, {1, 0}, true), wg::sample_from_angle(0.01, {2, 0}, true)};
    v[1].eye[wg::kRight].valid = false;
    wg::DropoutPolicy p;
    p.hold_s = 0.001;
    const wg::GazeSample s = wg::interpolate_samples(v, 0.008, p);
    EXPECT_TRUE(s.eye[wg::kLeft].valid);
    EXPECT_FALSE(s.eye[wg::kRight].valid);  // right held sample is 8 ms old, limit 1 ms
}

TEST(GazeSource, SyntheticSourceIsDeterministicAndLoops) {
    wg::GeneratorConfig c;
    c.mode = wg::Mode::Scene;
    c.seconds = 2;
    c.seed = 5;
    auto a = wg::SyntheticSource::create(c);
    auto b = wg::SyntheticSource::create(c);
    ASSERT_TRUE(a.ok()) << a.error().message;
    ASSERT_TRUE(b.ok());
    for (double t = 0; t < 5; t += 0.0111) {
        const wg::GazeSample x = (*a)->sample(t), y = (*b)->sample(t);
        EXPECT_EQ(x.eye[0].valid, y.eye[0].valid);
        EXPECT_EQ(x.eye[0].dir, y.eye[0].dir);
    }
    const wg::GazeSample s0 = (*a)->sample(0.5), s1 = (*a)->sample(2.5);
    EXPECT_EQ(s0.eye[0].dir, s1.eye[0].dir);
    EXPECT_DOUBLE_EQ(s1.t_s, 2.5);
    c.tracker.rate_hz = 20;
    EXPECT_FALSE(wg::SyntheticSource::create(c).ok());
}
