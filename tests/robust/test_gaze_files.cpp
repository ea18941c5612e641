// docs/bad-input.md, "Gaze files": malformed project CSV, Pupil Labs and Tobii Pro Lab files. A
// file that cannot be read as its format fails with a message; a bad row is skipped and reported
// with its line number and reason, and never becomes a sample.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <glm/geometric.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gaze/gaze_file.h"
#include "gaze/source.h"

namespace wrsfov::gaze {
namespace {

const std::string P = "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\n";
const std::string Good = "0.000,0,1,0,0,-1,0,0,-1\n";
const std::string PC = "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z,confidence,label\n";
const std::string Pupil =
    "gaze_timestamp,confidence,gaze_normal0_x,gaze_normal0_y,gaze_normal0_z,gaze_normal1_x,gaze_normal1_y,"
    "gaze_normal1_z\n";
const std::string PupilGood = "100.0,0.9,0,0,1,0,0,1\n";
const std::string Tobii =
    "Recording timestamp\tGaze direction left X\tGaze direction left Y\tGaze direction left Z\tGaze direction right "
    "X\tGaze direction right Y\tGaze direction right Z\tValidity left\tValidity right\tSensor\n";
const std::string TobiiGood = "0\t0\t0\t1\t0\t0\t1\tValid\tValid\tEye Tracker\n";

struct Row {
    std::string name;
    std::string text;
    std::optional<std::string> fails;  ///< the whole file is refused with this in the message
    std::vector<size_t> issueLines;    ///< else: the rows reported and skipped...
    std::string issue;                 ///< ...the first one's reason contains this...
    size_t samples = 0;                ///< ...and the samples that remain
    std::function<void(const GazeRecording&)> check = nullptr;
    GazeFormat format = GazeFormat::Auto;
};
void PrintTo(const Row& r, std::ostream* os) { *os << r.name; }

Row fails(std::string name, std::string text, std::string message, GazeFormat f = GazeFormat::Auto) {
    Row r{std::move(name), std::move(text), std::move(message)};
    r.format = f;
    return r;
}
Row skipped(std::string name, std::string text, std::vector<size_t> lines, std::string issue, size_t samples) {
    return Row{std::move(name), std::move(text), std::nullopt, std::move(lines), std::move(issue), samples};
}
Row taken(std::string name, std::string text, size_t samples, std::function<void(const GazeRecording&)> check) {
    return Row{std::move(name), std::move(text), std::nullopt, {}, "", samples, std::move(check)};
}

std::vector<Row> rows() {
    std::vector<Row> r;
    // Project CSV: whole-file problems.
    r.push_back(fails("project_empty", "", "no header line"));
    r.push_back(fails("project_only_comments_and_blanks", "# nothing\n\n   \n# more\n", "no header line"));
    r.push_back(fails("project_binary_garbage", std::string("\x01\x02\xff\xfe\x00\x10 junk", 10) + "\n",
                      "unrecognised header"));
    r.push_back(fails("project_missing_column", "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y\n" + Good,
                      "lacks column 'right_z'"));
    r.push_back(fails("project_wrong_delimiter", "t_s;frame;valid;left_x;left_y;left_z;right_x;right_y;right_z\n",
                      "lacks column 't_s'"));
    r.push_back(taken("project_header_only", P, 0, nullptr));
    // Rows cut short or too long.
    r.push_back(skipped("project_row_truncated", P + Good + "0.01,1,1,0,0\n", {3}, "expected 9 fields, got 5", 1));
    r.push_back(skipped("project_file_truncated_mid_number", P + Good + "0.01,1,1,0,0,-1,0,0,-", {3},
                        "right_z '-' is not a number", 1));
    r.push_back(skipped("project_row_extra_field", P + Good + "0.01,1,1,0,0,-1,0,0,-1,7\n", {3},
                        "expected 9 fields, got 10", 1));
    // Time.
    using Kind = std::pair<const char*, const char*>;  // value, row name
    for (auto [v, kind] : {Kind{"nan", "nan"}, Kind{"inf", "pos_inf"}, Kind{"-inf", "neg_inf"}, Kind{"1e400", "huge"},
                           Kind{"abc", "text"}, Kind{"", "empty"}})
        r.push_back(skipped(std::string("project_time_") + kind, P + Good + v + ",1,1,0,0,-1,0,0,-1\n", {3},
                            "t_s '" + std::string(v) + "' is not a number", 1));
    r.push_back(skipped("project_time_backwards", P + "0.02,0,1,0,0,-1,0,0,-1\n0.01,1,1,0,0,-1,0,0,-1\n", {3},
                        "not after the previous sample", 1));
    r.push_back(skipped("project_time_repeated", P + Good + Good, {3}, "not after the previous sample", 1));
    r.push_back(taken("project_time_negative", P + "-5,0,1,0,0,-1,0,0,-1\n", 1,
                      [](const GazeRecording& g) { EXPECT_EQ(g.samples[0].t_s, -5.0); }));
    // Frame and validity.
    // 6.44444e71 and 2^53 are finite integers in a double but not frame indices (found by fuzz_text:
    // converting the first to an integer was undefined behaviour).
    for (auto [v, kind] : {Kind{"-1", "negative"}, Kind{"1.5", "fraction"}, Kind{"nan", "nan"}, Kind{"1e400", "huge"},
                           Kind{"6.44444e71", "beyond_integers"}, Kind{"9007199254740992", "two_to_the_53"}})
        r.push_back(skipped(std::string("project_frame_") + kind, P + "0," + v + ",1,0,0,-1,0,0,-1\n", {2},
                            "is not a non-negative integer", 0));
    for (auto [v, kind] :
         {Kind{"2", "two"}, Kind{"", "empty"}, Kind{"nan", "nan"}, Kind{"-1", "negative"}, Kind{"true", "text"}})
        r.push_back(skipped(std::string("project_valid_") + kind, P + "0,0," + v + ",0,0,-1,0,0,-1\n", {2},
                            "is not 0 or 1", 0));
    // Directions.
    r.push_back(
        skipped("project_direction_nan", P + "0,0,1,nan,0,-1,0,0,-1\n", {2}, "left_x 'nan' is not a number", 0));
    r.push_back(
        skipped("project_direction_inf", P + "0,0,1,0,0,-1,0,-inf,-1\n", {2}, "right_y '-inf' is not a number", 0));
    r.push_back(skipped("project_direction_huge", P + "0,0,1,1e30,0,-1,0,0,-1\n", {2},
                        "left direction is not a unit vector", 0));
    r.push_back(skipped("project_direction_zero", P + "0,0,1,0,0,-1,0,0,0\n", {2}, "not a unit vector (length 0)", 0));
    r.push_back(
        skipped("project_direction_2_percent_long", P + "0,0,1,0,0,-1.02,0,0,-1\n", {2}, "not a unit vector", 0));
    r.push_back(
        skipped("project_direction_empty_but_valid", P + "0,0,1,,,,0,0,-1\n", {2}, "left_x '' is not a number", 0));
    r.push_back(
        skipped("project_direction_nan_in_invalid_row", P + "0,0,0,nan,0,-1,0,0,-1\n", {2}, "is not a number", 0));
    r.push_back(taken("project_direction_empty_and_invalid", P + "0,0,0,,,,,,\n", 1, [](const GazeRecording& g) {
        EXPECT_FALSE(g.samples[0].eye[0].valid);
        EXPECT_FALSE(g.samples[0].eye[1].valid);
    }));
    r.push_back(taken("project_direction_behind_the_viewer", P + "0,0,1,0,0,1,0,0,1\n", 1,
                      [](const GazeRecording& g) { EXPECT_EQ(g.samples[0].eye[0].dir, glm::vec3(0, 0, 1)); }));
    r.push_back(taken("project_direction_within_1_percent_is_normalised", P + "0,0,1,0,0,-1.005,0,0,-1\n", 1,
                      [](const GazeRecording& g) { EXPECT_FLOAT_EQ(glm::length(g.samples[0].eye[0].dir), 1.0f); }));
    // Confidence and label columns.
    for (auto [v, kind] : {Kind{"nan", "nan"}, Kind{"-0.1", "negative"}, Kind{"1.5", "above_one"},
                           Kind{"inf", "pos_inf"}, Kind{"", "empty"}})
        r.push_back(skipped(std::string("project_confidence_") + kind, PC + "0,0,1,0,0,-1,0,0,-1," + v + ",fixation\n",
                            {2}, "is not in [0, 1]", 0));
    r.push_back(skipped("project_label_unknown", PC + "0,0,1,0,0,-1,0,0,-1,1,wink\n", {2},
                        "label 'wink' is not an event name", 0));
    // Huge: a 1 MB field, and a row of 100000 fields.
    r.push_back(skipped("project_huge_field", P + Good + std::string(1 << 20, '7') + ",1,1,0,0,-1,0,0,-1\n", {3},
                        "is not a number", 1));
    {
        std::string wide = "1";
        for (int i = 0; i < 100000; ++i) wide += ",0";
        r.push_back(skipped("project_huge_row", P + Good + wide + "\n", {3}, "expected 9 fields, got 100001", 1));
    }
    r.push_back(taken("project_crlf_line_ends",
                      "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\r\n"
                      "0,0,1,0,0,-1,0,0,-1\r\n",
                      1, nullptr));

    // Pupil Labs gaze_positions.csv.
    r.push_back(
        fails("pupil_missing_confidence", "gaze_timestamp,norm_pos_x\n1,2\n", "lacks gaze_timestamp or confidence"));
    r.push_back(fails("pupil_no_direction_columns", "gaze_timestamp,confidence,norm_pos_x\n1,1,0.5\n",
                      "neither gaze_normal0/1"));
    r.push_back(skipped("pupil_timestamp_nan", Pupil + PupilGood + "nan,0.9,0,0,1,0,0,1\n", {3},
                        "gaze_timestamp 'nan' is not a number", 1));
    for (auto [v, kind] : {Kind{"nan", "nan"}, Kind{"-0.5", "negative"}, Kind{"1.7", "above_one"}, Kind{"", "empty"}})
        r.push_back(skipped(std::string("pupil_confidence_") + kind, Pupil + "100.0," + v + ",0,0,1,0,0,1\n", {2},
                            "is not in [0, 1]", 0));
    r.push_back(skipped("pupil_normal_nan", Pupil + "100.0,0.9,nan,0,1,0,0,1\n", {2}, "not three numbers", 0));
    r.push_back(skipped("pupil_normal_partial", Pupil + "100.0,0.9,0,,1,0,0,1\n", {2}, "not three numbers", 0));
    r.push_back(skipped("pupil_normal_zero", Pupil + "100.0,0.9,0,0,0,0,0,1\n", {2}, "not three numbers", 0));
    r.push_back(skipped("pupil_normal_huge", Pupil + "100.0,0.9,0,0,1e300,0,0,1\n", {2}, "not three numbers", 0));
    r.push_back(taken("pupil_normal_long_is_normalised", Pupil + "100.0,0.9,0,3e10,4e10,0,0,1\n", 1,
                      [](const GazeRecording& g) {
                          EXPECT_EQ(g.samples[0].eye[1].dir, glm::vec3(0.0f, -0.6f, -0.8f));
                          EXPECT_TRUE(g.samples[0].eye[1].valid);
                      }));
    r.push_back(
        taken("pupil_low_confidence_is_invalid", Pupil + "100.0,0.3,0,0,1,0,0,1\n", 1,
              [](const GazeRecording& g) { EXPECT_FALSE(g.samples[0].eye[0].valid || g.samples[0].eye[1].valid); }));
    r.push_back(
        skipped("pupil_row_truncated", Pupil + PupilGood + "100.1,0.9,0\n", {3}, "expected 8 fields, got 3", 1));

    // Tobii Pro Lab TSV.
    r.push_back(fails("tobii_missing_direction_columns", "Recording timestamp\tGaze point X\tGaze point Y\n1\t2\t3\n",
                      "lacks 'Gaze direction left X'"));
    r.push_back(fails("tobii_missing_timestamp_column", "Gaze direction left X\tSensor\n1\t2\n",
                      "lacks the 'Recording timestamp' column", GazeFormat::TobiiProLab));
    r.push_back(skipped("tobii_timestamp_nan", Tobii + TobiiGood + "nan\t0\t0\t1\t0\t0\t1\tValid\tValid\tEye Tracker\n",
                        {3}, "Recording timestamp 'nan' is not a number", 1));
    r.push_back(skipped("tobii_direction_nan", Tobii + "0\tnan\t0\t1\t0\t0\t1\tValid\tValid\tEye Tracker\n", {2},
                        "Gaze direction left X 'nan' is not a number", 0));
    r.push_back(skipped("tobii_direction_inf", Tobii + "0\t0\t0\t1\t0\t0\tinf\tValid\tValid\tEye Tracker\n", {2},
                        "Gaze direction right Z 'inf' is not a number", 0));
    r.push_back(skipped("tobii_direction_huge", Tobii + "0\t0\t0\t1e30\t0\t0\t1\tValid\tValid\tEye Tracker\n", {2},
                        "not a unit vector", 0));
    r.push_back(skipped("tobii_direction_partial", Tobii + "0\t0\t\t1\t0\t0\t1\tValid\tValid\tEye Tracker\n", {2},
                        "missing components", 0));
    r.push_back(skipped("tobii_validity_unknown", Tobii + "0\t0\t0\t1\t0\t0\t1\tMaybe\tValid\tEye Tracker\n", {2},
                        "Validity left 'Maybe' is not Valid or Invalid", 0));
    r.push_back(skipped("tobii_row_truncated", Tobii + TobiiGood + "10\t0\t0\n", {3}, "expected 10 fields, got 3", 1));
    r.push_back(taken("tobii_decimal_commas", Tobii + "0\t0,1\t0,2\t0,974679434\t0\t0\t1\tValid\tValid\tEye Tracker\n",
                      1, [](const GazeRecording& g) { EXPECT_NEAR(g.samples[0].eye[0].dir.x, -0.1f, 1e-6f); }));
    r.push_back(taken("tobii_other_sensor_rows_ignored",
                      Tobii + TobiiGood + "5\tnan\tnan\tnan\t\t\t\t\t\tAccelerometer\n", 1,
                      [](const GazeRecording& g) { EXPECT_EQ(g.ignored_rows, 1u); }));
    return r;
}

class Malformed : public ::testing::TestWithParam<Row> {};

TEST_P(Malformed, Row) {
    const Row& row = GetParam();
    ReadOptions o;
    o.format = row.format;
    auto rec = read_gaze_text(row.text, o);
    if (row.fails) {
        ASSERT_FALSE(rec.ok()) << "the file was read";
        EXPECT_NE(rec.error().message.find(*row.fails), std::string::npos) << rec.error().message;
        return;
    }
    ASSERT_TRUE(rec.ok()) << rec.error().message;
    std::vector<size_t> lines;
    for (const FileIssue& i : rec->issues) lines.push_back(i.line);
    EXPECT_EQ(lines, row.issueLines);
    if (!row.issue.empty()) {
        ASSERT_FALSE(rec->issues.empty());
        EXPECT_NE(rec->issues[0].message.find(row.issue), std::string::npos) << rec->issues[0].message.substr(0, 200);
    }
    ASSERT_EQ(rec->samples.size(), row.samples);
    // Whatever was taken is usable: finite times, unit directions for valid eyes, confidence in [0, 1].
    for (const GazeSample& s : rec->samples) {
        EXPECT_TRUE(std::isfinite(s.t_s));
        for (const EyeGaze& e : s.eye) {
            EXPECT_TRUE(std::isfinite(e.dir.x) && std::isfinite(e.dir.y) && std::isfinite(e.dir.z));
            if (e.valid) {
                EXPECT_NEAR(glm::length(e.dir), 1.0f, 1e-5f);
            }
            EXPECT_TRUE(e.confidence >= 0.0f && e.confidence <= 1.0f);
        }
    }
    if (row.check) row.check(*rec);
}

INSTANTIATE_TEST_SUITE_P(GazeFile, Malformed, ::testing::ValuesIn(rows()), [](const ::testing::TestParamInfo<Row>& i) {
    std::string n = i.param.name;
    for (char& c : n)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return n;
});

std::string tempPath(const std::string& name) {
    // One name per process: two builds may run this test at the same time.
    return (std::filesystem::temp_directory_path() / ("wrsfov_robust_" + std::to_string(::getpid()) + "_" + name))
        .string();
}

TEST(GazeFileOnDisk, MissingFileDirectoryAndNoSamples) {
    auto missing = read_gaze_file(tempPath("does_not_exist.csv"));
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("cannot open gaze file"), std::string::npos) << missing.error().message;
    EXPECT_NE(missing.error().message.find("does_not_exist.csv"), std::string::npos);

    const std::string dir = tempPath("a_directory");
    std::filesystem::create_directories(dir);
    auto isDir = read_gaze_file(dir);
    ASSERT_FALSE(isDir.ok());
    EXPECT_NE(isDir.error().message.find(dir), std::string::npos) << isDir.error().message;

    // A file whose every row is bad opens as a recording, but not as a source.
    const std::string bad = tempPath("all_bad.csv");
    {
        std::ofstream f(bad);
        f << P << "nan,0,1,0,0,-1,0,0,-1\n0,0,7,0,0,-1,0,0,-1\n";
    }
    auto rec = read_gaze_file(bad);
    ASSERT_TRUE(rec.ok());
    EXPECT_EQ(rec->issues.size(), 2u);
    auto src = ReplaySource::open(bad);
    ASSERT_FALSE(src.ok());
    EXPECT_NE(src.error().message.find("no usable gaze samples"), std::string::npos) << src.error().message;
    std::filesystem::remove(bad);
    std::filesystem::remove(dir);
}

}  // namespace
}  // namespace wrsfov::gaze
