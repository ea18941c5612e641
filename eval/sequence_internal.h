// What the sequence format's sources share (sequence.cpp: the reader and the writer;
// sequence_json.cpp: sequence.json; sequence_images.cpp: the PNG and EXR images; sequence_gaze.cpp: gaze.csv).
// Not installed; the format's API is eval/sequence.h.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "eval/sequence.h"

namespace wrsfov::eval::seqfile {

constexpr uint32_t kMaxFrames = 999999;  // six digits in the file names
constexpr uint32_t kMaxSize = 16384;

inline Error seqError(SequenceError code, std::string message) { return Error{int(code), std::move(message)}; }

/// Why `info` is not a sequence the format can hold, or nullopt.
std::optional<std::string> checkInfo(const SequenceInfo& info);
/// The whole file at `path`; `missingCode` where it cannot be opened.
Result<std::string> readText(const std::string& path, SequenceError missingCode);

/// Writes float channels `names` from interleaved `px` (width x height x names.size()), ZIP.
Status writeExr(const std::string& path, int width, int height, const std::vector<std::string>& names,
                const float* px);
/// Frame `i`'s colour, depth or motion of eye `e` from the sequence in `dir`, checked against `info`.
Result<HostImage> readColor(const std::string& dir, uint32_t i, int e, const SequenceInfo& info);
Result<HostImage> readDepth(const std::string& dir, uint32_t i, int e, const SequenceInfo& info);
Result<HostImage> readMotion(const std::string& dir, uint32_t i, int e, const SequenceInfo& info);

}  // namespace wrsfov::eval::seqfile
