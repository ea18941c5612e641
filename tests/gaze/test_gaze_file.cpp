#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "gaze/angles.h"
#include "gaze/gaze_file.h"
#include "gaze/generator.h"
#include "gaze/source.h"

namespace wg = wrsfov::gaze;

namespace {
const std::string kData = WRSFOV_GAZE_TEST_DATA;

std::vector<size_t> issue_lines(const wg::GazeRecording& r) {
    std::vector<size_t> v;
    for (const wg::FileIssue& i : r.issues) v.push_back(i.line);
    return v;
}
}  // namespace

TEST(GazeFile, ProjectRoundTrip) {
    wg::GeneratorConfig c;
    c.mode = wg::Mode::Reading;
    c.seconds = 3;
    c.seed = 11;
    c.tracker.dropout_per_s = 3;
    auto g = wg::generate(c);
    ASSERT_TRUE(g.ok());
    const std::string path = (std::filesystem::temp_directory_path() / "wrsfov_gaze_roundtrip.csv").string();
    ASSERT_TRUE(wg::write_gaze_csv(path, g->samples, true).ok());
    auto r = wg::read_gaze_file(path);
    std::remove(path.c_str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, wg::GazeFormat::Project);
    EXPECT_TRUE(r->issues.empty());
    EXPECT_TRUE(r->has_labels);
    ASSERT_EQ(r->samples.size(), g->samples.size());
    for (size_t i = 0; i < r->samples.size(); ++i) {
        const wg::GazeSample &a = r->samples[i], &b = g->samples[i];
        EXPECT_NEAR(a.t_s, b.t_s, 1e-6);
        EXPECT_EQ(a.eye[0].valid, b.eye[0].valid);
        EXPECT_EQ(a.label, b.label);
        if (a.eye[0].valid) {
            EXPECT_LT(wg::angle_between_deg(a.eye[0].dir, b.eye[0].dir), 1e-4);
        }
        EXPECT_EQ(r->frames[i], static_cast<long long>(i));
    }
}

TEST(GazeFile, ProjectBadRowsAreReportedAndSkipped) {
    auto r = wg::read_gaze_file(kData + "/project_bad_rows.csv");
    ASSERT_TRUE(r.ok()) << r.error().message;
    // Lines: 5 too few fields, 6 valid=2, 7 not unit, 8 not a number, 9 time backwards,
    // 11 unknown label, 12 bad frame.
    EXPECT_EQ(issue_lines(*r), (std::vector<size_t>{5, 6, 7, 8, 9, 11, 12}));
    for (const wg::FileIssue& i : r->issues) EXPECT_FALSE(i.message.empty());
    ASSERT_EQ(r->samples.size(), 4u);
    EXPECT_NEAR(wg::angle_from_direction(r->samples[1].eye[0].dir).az_deg, 5.739, 1e-3);
    EXPECT_EQ(r->samples[1].label, wg::Event::Saccade);
    EXPECT_FALSE(r->samples[2].eye[0].valid);  // valid = 0 with empty directions is fine
    EXPECT_EQ(r->samples[2].label, wg::Event::Blink);
    EXPECT_EQ(r->samples[3].label, wg::Event::Unknown);
    EXPECT_EQ(r->frames[3], 9);
}

// An invalid eye's direction is carried (normalised) when it is usable, else straight ahead: an
// infinite one (a number beyond float's range) or one whose length overflows never becomes NaN
// (found by fuzz/fuzz_text.cpp).
TEST(GazeFile, InvalidEyeDirectionsAreNeverNaN) {
    auto r = wg::read_gaze_text("t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\n"
                                "0,0,0,1e39,0,-1,0,3e38,-3e38\n"
                                "0.01,1,0,0,0,-2,0,0.6,-0.8\n");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r->issues.empty());
    ASSERT_EQ(r->samples.size(), 2u);
    const glm::vec3 ahead(0, 0, -1);
    EXPECT_EQ(r->samples[0].eye[0].dir, ahead);
    EXPECT_EQ(r->samples[0].eye[1].dir, ahead);  // finite, but its length overflows
    EXPECT_EQ(r->samples[1].eye[0].dir, ahead);  // (0, 0, -2) normalised
    EXPECT_EQ(r->samples[1].eye[1].dir, glm::vec3(0, 0.6f, -0.8f));
    for (const auto& s : r->samples)
        for (const auto& e : s.eye) EXPECT_FALSE(e.valid);
}

TEST(GazeFile, PupilLabs) {
    auto r = wg::read_gaze_file(kData + "/pupil_gaze_positions.csv");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, wg::GazeFormat::PupilLabs);
    // Line 6: timestamp not a number, 7: confidence 1.7, 8: too few fields.
    EXPECT_EQ(issue_lines(*r), (std::vector<size_t>{6, 7, 8}));
    ASSERT_EQ(r->samples.size(), 4u);
    EXPECT_DOUBLE_EQ(r->samples[0].t_s, 0);
    EXPECT_NEAR(r->samples[1].t_s, 0.004, 1e-9);
    // Pupil camera space (y down, z forward) -> eye space (y up, -z forward).
    const glm::vec3 d = r->samples[1].eye[wg::kRight].dir;
    EXPECT_NEAR(d.x, 0.1, 1e-6);
    EXPECT_NEAR(d.y, 0.2, 1e-6);
    EXPECT_NEAR(d.z, -0.974679434, 1e-6);
    EXPECT_NEAR(r->samples[0].eye[wg::kLeft].dir.z, -1, 1e-6);
    // Confidence 0.3 < 0.6: invalid.
    EXPECT_FALSE(r->samples[2].eye[0].valid);
    EXPECT_FALSE(r->samples[2].eye[1].valid);
    // Monocular row: the left eye follows gaze_point_3d.
    ASSERT_TRUE(r->samples[3].eye[wg::kLeft].valid);
    const glm::vec3 p = r->samples[3].eye[wg::kLeft].dir;
    EXPECT_NEAR(p.x / -p.z, 50.0 / 500, 1e-5);
    EXPECT_NEAR(p.y / -p.z, 20.0 / 500, 1e-5);
}

TEST(GazeFile, TobiiProLab) {
    auto r = wg::read_gaze_file(kData + "/tobii_export.tsv");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r->format, wg::GazeFormat::TobiiProLab);
    EXPECT_EQ(r->ignored_rows, 1u);  // the accelerometer row
    // Line 6: "nope", 7: validity "Maybe", 8: too few fields.
    EXPECT_EQ(issue_lines(*r), (std::vector<size_t>{6, 7, 8}));
    ASSERT_EQ(r->samples.size(), 4u);
    EXPECT_NEAR(r->samples[1].t_s, 0.01, 1e-9);
    // Tobii glasses space (x left, y up, z forward), decimal commas.
    const glm::vec3 d = r->samples[1].eye[wg::kLeft].dir;
    EXPECT_NEAR(d.x, 0.1, 1e-6);
    EXPECT_NEAR(d.y, 0.2, 1e-6);
    EXPECT_NEAR(d.z, -0.974679434, 1e-6);
    EXPECT_EQ(r->samples[1].label, wg::Event::Saccade);
    EXPECT_FALSE(r->samples[2].eye[wg::kLeft].valid);
    EXPECT_TRUE(r->samples[2].eye[wg::kRight].valid);
    EXPECT_FALSE(r->samples[3].eye[0].valid);
    EXPECT_EQ(r->samples[3].label, wg::Event::Blink);
}

TEST(GazeFile, ReplaySourceFromEachFormat) {
    for (const char* f : {"/project_bad_rows.csv", "/pupil_gaze_positions.csv", "/tobii_export.tsv"}) {
        auto src = wg::ReplaySource::open(kData + f);
        ASSERT_TRUE(src.ok()) << f;
        EXPECT_FALSE((*src)->issues().empty()) << f;
        EXPECT_TRUE((*src)->sample(0.001).eye[0].valid) << f;
    }
}

TEST(GazeFile, ClearErrors) {
    auto missing = wg::read_gaze_file(kData + "/no_such_file.csv");
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("no_such_file.csv"), std::string::npos);
    auto unknown = wg::read_gaze_text("time,x,y\n1,2,3\n");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("unrecognised header"), std::string::npos);
    EXPECT_FALSE(wg::read_gaze_text("").ok());
    auto lacking = wg::read_gaze_text("t_s,frame,valid,left_x\n");
    ASSERT_FALSE(lacking.ok());
    EXPECT_NE(lacking.error().message.find("left_y"), std::string::npos);
    auto tobii = wg::read_gaze_text("Recording timestamp\tGaze point X\tGaze point Y\n1\t2\t3\n");
    ASSERT_FALSE(tobii.ok());
    EXPECT_NE(tobii.error().message.find("Gaze direction"), std::string::npos);
    EXPECT_FALSE(wg::write_gaze_csv("/nonexistent-dir/x.csv", {}, false).ok());
}
