// Sequence directories: external stereo frames in and out (the format is specified in
// docs/sequence.md).
//
//   DIR/sequence.json                  size, per-eye field of view, frame count, fps, colour file
//                                      type, depth range (optional), motion units (optional)
//   DIR/NNNNNN_{L,R}_color.png         sRGB, 8 bits, RGB or RGBA         (or color.exr: linear float)
//   DIR/NNNNNN_{L,R}_depth.exr         one float channel, as submitted   (only with "depth")
//   DIR/NNNNNN_{L,R}_motion.exr        2 or 3 float channels             (only with "motion")
//   DIR/gaze.csv                       t_s,frame,valid,left_x,...,right_z (optional)
//
// Every failure is a Result error whose message names the file (and the field, line or pixel).
// sequence.json is read and written with nlohmann-json, EXR files with OpenEXR, PNG with OpenCV.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "compositor/host_app.h"
#include "layers/frame.h"
#include "layers/status.h"

namespace wrsfov::eval {

/// Error::code of the sequence functions.
enum class SequenceError : int {
    MissingFile = 1,  ///< the directory, sequence.json or a frame file the json implies is not there
    BadJson,          ///< sequence.json is not valid JSON (syntax errors: file:line:column), or has a key twice
    BadField,         ///< a field is missing, unknown, of the wrong type, not finite or out of range
    FrameCount,       ///< frame files beyond frame_count, or a frame index outside the sequence
    ImageSize,        ///< an image is not width x height
    ImageChannels,    ///< wrong channel count or names, or not 8-bit for PNG
    BadImage,         ///< a file that cannot be decoded (truncated, corrupt, not EXR/PNG)
    BadGaze,          ///< a malformed gaze.csv row (message: file line N)
    BadInput,         ///< the writer was given images or an info it cannot write
    WriteFailed,      ///< a file could not be written
};

/// How the colour of every frame is stored.
enum class ColorFile : uint8_t {
    Png,  ///< NNNNNN_E_color.png: sRGB-encoded, 8 bits per channel -> RGBA8_SRGB
    Exr,  ///< NNNNNN_E_color.exr: linear float R, G, B (A ignored) -> RGBA16F
};

/// Units of the first two motion channels in the files (the reader converts to pixels).
enum class MotionUnits : uint8_t {
    Pixels,  ///< pixels of this image
    Ndc,     ///< normalized device coordinates, [-1, 1] across the image, y down: px = ndc * size / 2
    Uv,      ///< texture coordinates, [0, 1] across the image, v down: px = uv * size
};

std::string_view toString(ColorFile c);
std::string_view toString(MotionUnits u);

/// Depth range of the depth files (like XrCompositionLayerDepthInfoKHR).
struct SequenceDepth {
    float nearZ = 0.1f;
    float farZ = 100.0f;  ///< may be +infinity ("far": "inf" in the json)
    bool reversedZ = false;
};

/// What sequence.json says.
struct SequenceInfo {
    uint32_t width = 0, height = 0;  ///< per eye, pixels
    uint32_t frameCount = 0;
    double fps = 90.0;  ///< frame i is displayed at t = i / fps seconds
    ColorFile color = ColorFile::Png;
    std::array<layers::Fov, 2> fov{};    ///< [0] left, [1] right; angles in radians
    std::optional<SequenceDepth> depth;  ///< depth files present for every frame and eye
    std::optional<MotionUnits> motion;   ///< motion files present for every frame and eye
    std::string description;             ///< free text, optional
};

/// Reads and validates DIR/sequence.json (not the frame files).
Result<SequenceInfo> readSequenceInfo(const std::string& dir);
/// Parses the text of a sequence.json; `name` is used in messages.
Result<SequenceInfo> parseSequenceInfo(std::string_view json, const std::string& name = "sequence.json");
/// The json text for `info` (what SequenceWriter writes; round-trips through parseSequenceInfo).
std::string formatSequenceInfo(const SequenceInfo& info);

/// Name of a frame file: frameFileName(3, 1, "depth.exr") = "000003_R_depth.exr".
std::string frameFileName(uint32_t frame, int eye, std::string_view kind);

/// Why a frame's gaze is invalid although gaze.csv has a row for it (the documented fallback:
/// the compositor uses the view centre with its fallback fovea).
struct GazeNote {
    std::size_t line = 0;  ///< 1-based line in gaze.csv
    uint32_t frame = 0;
    std::string message;
};

/// One frame as the application submits it.
struct SequenceFrame {
    uint32_t index = 0;
    double time_s = 0.0;
    /// Colour (RGBA8_SRGB or RGBA16F), depth (R32F, as in the file), motion (RGBA16F: pixels,
    /// third channel z_prev - z_cur or 0, fourth 0), field of view and gaze per eye.
    std::array<EyeSubmission, 2> eyes;
};

/// Reads a sequence directory frame by frame.
class SequenceReader {
public:
    /// Reads sequence.json and gaze.csv, and checks that every frame file the json implies exists
    /// and that none lies beyond frame_count. Pixel data is read by frame().
    static Result<std::unique_ptr<SequenceReader>> open(const std::string& dir);

    const SequenceInfo& info() const { return info_; }
    const std::string& dir() const { return dir_; }

    /// Frame `index` < frameCount: decodes and checks its files (size, channels) and converts
    /// motion to pixels. Gaze: from gaze.csv (the last row for this frame); invalid (fallback) when
    /// the frame has no row or its row's direction is not finite or not a unit vector (see
    /// gazeNotes()). Without gaze.csv the gaze is left invalid for the caller to fill in.
    Result<SequenceFrame> frame(uint32_t index) const;

    /// Whether the directory has gaze.csv.
    bool hasGaze() const { return hasGaze_; }
    /// Gaze of frame `index` from gaze.csv (both eyes invalid without a file or a row).
    const std::array<layers::EyeGaze, 2>& gaze(uint32_t index) const { return gaze_.at(index); }
    /// Rows of gaze.csv that made a frame's gaze invalid, and frames without any row.
    const std::vector<GazeNote>& gazeNotes() const { return gazeNotes_; }

    /// Swapchain formats and depth range that fit what frame() returns.
    HostStereoApp::Options appOptions() const;

private:
    SequenceReader() = default;
    std::string dir_;
    SequenceInfo info_;
    bool hasGaze_ = false;
    std::vector<std::array<layers::EyeGaze, 2>> gaze_;
    std::vector<GazeNote> gazeNotes_;
};

/// Parses gaze.csv text for a sequence of `frameCount` frames (what SequenceReader::open does with
/// the file). Malformed rows (wrong number of fields, a field that is not a number, valid not 0/1,
/// a frame outside [0, frameCount), a missing column) fail with the line number; a non-finite or
/// non-unit direction (length off by more than 1 %) makes that frame's gaze invalid and adds a note.
struct SequenceGaze {
    std::vector<std::array<layers::EyeGaze, 2>> frames;
    std::vector<GazeNote> notes;
};
Result<SequenceGaze> parseSequenceGaze(std::string_view csv, uint32_t frameCount, const std::string& name = "gaze.csv");

/// Writes a sequence directory: sequence.json on create(), the frame files on writeFrame(), and
/// gaze.csv (the eyes' gaze of every frame) on finish().
class SequenceWriter {
public:
    /// Creates `dir` if needed and writes sequence.json. Fails on an invalid `info`.
    static Result<std::unique_ptr<SequenceWriter>> create(const std::string& dir, const SequenceInfo& info);

    /// Writes frame `index` (frames in order from 0). Colour must be RGBA8_SRGB for PNG and RGBA8,
    /// RGBA8_SRGB (decoded to linear) or RGBA16F for EXR; depth R32F or D32F; motion RG16F or
    /// RGBA16F in pixels (converted to the json's units). Depth and motion must be present exactly
    /// when the json declares them. Images must be width x height.
    Status writeFrame(uint32_t index, const std::array<EyeSubmission, 2>& eyes);

    /// Writes gaze.csv (t_s = index / fps). Fails unless frameCount frames were written.
    Status finish();
    /// Ends a recording whose length was not known in advance (created with frameCount as an upper
    /// bound): rewrites sequence.json with frame_count = the frames written, then finish(). Fails when
    /// no frame was written.
    Status close();
    uint32_t written() const { return written_; }

    const SequenceInfo& info() const { return info_; }

private:
    SequenceWriter() = default;
    std::string dir_;
    SequenceInfo info_;
    uint32_t written_ = 0;
    std::vector<std::array<layers::EyeGaze, 2>> gaze_;
};

}  // namespace wrsfov::eval
