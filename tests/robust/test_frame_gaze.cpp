// docs/bad-input.md, "Gaze": what gaze::to_eye_gaze makes of every kind of bad sample. An invalid
// result is what the compositor turns into its fallback (view centre, fallback fovea).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gaze/frame_gaze.h"

namespace wrsfov::gaze {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const double kNaNd = std::numeric_limits<double>::quiet_NaN();

struct Row {
    std::string name;
    std::function<void(GazeSample&, double& frame_t)> bad;  ///< changes a good sample at t = 2 s
    bool valid;
    float confidence = 1.0f;  ///< expected when valid
};
void PrintTo(const Row& r, std::ostream* os) { *os << r.name; }

std::vector<Row> rows() {
    auto dir = [](glm::vec3 d) { return [d](GazeSample& s, double&) { s.eye[0].dir = d; }; };
    return {
        {"good", [](GazeSample&, double&) {}, true},
        {"not_valid", [](GazeSample& s, double&) { s.eye[0].valid = false; }, false},
        {"direction_nan", dir({kNaN, 0, -1}), false},
        {"direction_pos_inf", dir({0, kInf, -1}), false},
        {"direction_neg_inf", dir({0, 0, -kInf}), false},
        {"direction_zero", dir({0, 0, 0}), false},
        {"direction_length_overflows", dir({3e38f, 3e38f, -3e38f}), false},
        {"direction_length_underflows", dir({1e-30f, 0, -1e-30f}), false},
        {"direction_not_unit_is_normalised", dir({0, 0, -7}), true},
        {"direction_behind_is_kept", dir({0, 0, 1}), true},
        {"confidence_nan", [](GazeSample& s, double&) { s.eye[0].confidence = kNaN; }, true, 0.0f},
        {"confidence_negative", [](GazeSample& s, double&) { s.eye[0].confidence = -2.0f; }, true, 0.0f},
        {"confidence_above_one", [](GazeSample& s, double&) { s.eye[0].confidence = 5.0f; }, true, 1.0f},
        {"confidence_pos_inf", [](GazeSample& s, double&) { s.eye[0].confidence = kInf; }, true, 1.0f},
        {"time_nan", [](GazeSample& s, double&) { s.t_s = kNaNd; }, false},
        {"time_pos_inf", [](GazeSample& s, double&) { s.t_s = std::numeric_limits<double>::infinity(); }, false},
        {"frame_time_nan", [](GazeSample&, double& t) { t = kNaNd; }, false},
        {"time_99ms_old", [](GazeSample& s, double&) { s.t_s -= 0.099; }, true},
        {"time_101ms_old", [](GazeSample& s, double&) { s.t_s -= 0.101; }, false},
        {"time_huge_old", [](GazeSample& s, double&) { s.t_s = -1e300; }, false},
        {"time_101ms_ahead", [](GazeSample& s, double&) { s.t_s += 0.101; }, false},
        {"time_negative_but_current", [](GazeSample& s, double& t) { s.t_s = t = -3.0; }, true},
    };
}

class ToEyeGaze : public ::testing::TestWithParam<Row> {};

TEST_P(ToEyeGaze, Row) {
    const Row& row = GetParam();
    GazeSample s;
    s.t_s = 2.0;
    for (auto& e : s.eye) e = {glm::normalize(glm::vec3(0.1f, -0.2f, -1.0f)), true, 1.0f};
    double frame_t = 2.0;
    row.bad(s, frame_t);
    const layers::EyeGaze g = to_eye_gaze(s, 0, frame_t);
    EXPECT_EQ(g.valid, row.valid);
    if (row.valid) {
        EXPECT_NEAR(glm::length(g.dir), 1.0f, 1e-6f);
        EXPECT_LT(glm::length(g.dir - glm::normalize(s.eye[0].dir)), 1e-6f);
        EXPECT_EQ(g.confidence, row.confidence);
    } else {
        // The invalid default: nothing of the bad sample gets through.
        EXPECT_EQ(g.dir, glm::vec3(0, 0, -1));
        EXPECT_EQ(g.confidence, 0.0f);
    }
    // The other eye is converted on its own.
    const auto both = to_frame_gaze(s, frame_t);
    EXPECT_EQ(both[0].valid, row.valid);
    const bool timeOk = std::isfinite(s.t_s) && std::isfinite(frame_t) && std::abs(frame_t - s.t_s) <= 0.1;
    EXPECT_EQ(both[1].valid, timeOk);
}

INSTANTIATE_TEST_SUITE_P(FrameGaze, ToEyeGaze, ::testing::ValuesIn(rows()),
                         [](const ::testing::TestParamInfo<Row>& i) { return i.param.name; });

TEST(FrameGaze, EyeIndexOutOfRangeAndNoSource) {
    GazeSample s;
    s.eye[0] = s.eye[1] = {glm::vec3(0, 0, -1), true, 1.0f};
    EXPECT_FALSE(to_eye_gaze(s, 2, 0.0).valid);
    EXPECT_FALSE(to_eye_gaze(s, -1, 0.0).valid);
    const auto none = frame_gaze(nullptr, 1.0);
    EXPECT_FALSE(none[0].valid);
    EXPECT_FALSE(none[1].valid);
}

TEST(FrameGaze, HoldTimeComesFromThePolicy) {
    GazeSample s;
    s.t_s = 1.0;
    s.eye[0] = s.eye[1] = {glm::vec3(0, 0, -1), true, 1.0f};
    DropoutPolicy p;
    p.hold_s = 0.02;
    EXPECT_TRUE(to_eye_gaze(s, 0, 1.019, p).valid);
    EXPECT_FALSE(to_eye_gaze(s, 0, 1.03, p).valid);
}

TEST(FrameGaze, ReplayGapIsADropoutNotAnInterpolation) {
    // Two valid samples 300 ms apart (a recording with a hole): the first is held for the hold time,
    // then the eye is invalid until the next sample; nothing in between is interpolated.
    std::vector<GazeSample> v(2);
    v[0].t_s = 0.0;
    v[1].t_s = 0.3;
    for (auto& e : v[0].eye) e = {glm::vec3(0, 0, -1), true, 1.0f};
    for (auto& e : v[1].eye) e = {glm::normalize(glm::vec3(1, 0, -1)), true, 1.0f};
    ReplaySource src(v);
    const auto held = frame_gaze(&src, 0.05);
    ASSERT_TRUE(held[0].valid);
    EXPECT_EQ(held[0].dir, glm::vec3(0, 0, -1));
    EXPECT_FALSE(frame_gaze(&src, 0.15)[0].valid);
    EXPECT_FALSE(frame_gaze(&src, 0.29)[1].valid);
    EXPECT_TRUE(frame_gaze(&src, 0.3)[0].valid);
    // Samples closer than max_gap_s still interpolate.
    DropoutPolicy p;
    p.max_gap_s = 0.5;
    ReplaySource close(v, p);
    const auto mid = frame_gaze(&close, 0.15, p);
    ASSERT_TRUE(mid[0].valid);
    EXPECT_NEAR(mid[0].dir.x, std::sin(3.14159265f / 8), 1e-5f);
}

}  // namespace
}  // namespace wrsfov::gaze
