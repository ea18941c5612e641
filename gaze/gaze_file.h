// Gaze files: the project's CSV (read and write), Pupil Labs and Tobii Pro Lab exports (read).
//
// Project CSV (docs/sequence.md, docs/gaze.md): a header line
// `t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z`, then one row per sample with
// unit directions in eye space. Columns are found by name; extra columns are accepted and
// ignored, except `label` (the true event, written by `wrsfov-gaze generate`) and `confidence`,
// which are read when present. Lines starting with '#' are comments.
//
// Bad rows never turn into samples: each is reported with its line number and skipped.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "gaze/result.h"
#include "gaze/sample.h"

namespace wrsfov::gaze {

enum class GazeFormat { Auto, Project, PupilLabs, TobiiProLab };

std::string_view format_name(GazeFormat f);

/// A row that was skipped, and why.
struct FileIssue {
    size_t line = 0;  ///< 1-based line number in the file
    std::string message;
};

struct ReadOptions {
    GazeFormat format = GazeFormat::Auto;
    float min_confidence = 0.6f;  ///< Pupil Labs: samples below this are invalid (Pupil's own default)
};

/// What a file held.
struct GazeRecording {
    GazeFormat format = GazeFormat::Auto;
    std::vector<GazeSample> samples;  ///< time-ordered; t_s of exports starts at 0
    std::vector<long long> frames;    ///< project CSV `frame` per sample (-1 where absent)
    std::vector<FileIssue> issues;    ///< skipped rows
    size_t ignored_rows = 0;          ///< rows that are not gaze (e.g. Tobii accelerometer rows)
    bool has_labels = false;
};

/// Reads a file in any supported format (`Auto` looks at the header). Fails only when the file
/// cannot be read or its header is not one of the formats; bad rows are in `issues`.
Result<GazeRecording> read_gaze_file(const std::string& path, const ReadOptions& options = {});

/// Same, from text already in memory.
Result<GazeRecording> read_gaze_text(std::string_view text, const ReadOptions& options = {});

/// Writes the project CSV. `frames` may be empty (then frame = sample index). With `labels`, a
/// `label` column holds each sample's event. A sample with one valid eye is written valid, with
/// the valid eye's direction in both columns (the format has a single validity flag).
Status write_gaze_csv(const std::string& path, std::span<const GazeSample> samples, bool labels,
                      std::span<const long long> frames = {});

/// The CSV text `write_gaze_csv` would write.
std::string format_gaze_csv(std::span<const GazeSample> samples, bool labels, std::span<const long long> frames = {});

}  // namespace wrsfov::gaze
