// libFuzzer target: the text files a user hands the tools, through the parsers that read them:
// sequence.json (parseSequenceInfo), a sequence's gaze.csv (parseSequenceGaze) and gaze recordings
// in every format (read_gaze_text: the project CSV, Pupil Labs and Tobii Pro Lab exports).
//
// Input: one selector byte, then the file's text. Its low two bits choose the parser (0
// sequence.json, 1 gaze.csv, 2 and 3 a recording); the upper six bits are the parser's parameter
// (gaze.csv: frame count - 1; a recording: its format, GazeFormat modulo 4, 0 = auto). Any input must end in a result or an error, never a crash, a hang
// or undefined behaviour; what a parser accepts must satisfy what its callers rely on.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "eval/sequence.h"
#include "gaze/gaze_file.h"

namespace {

void require(bool ok) {
    if (!ok) std::abort();
}

// A direction a consumer may use: a valid eye's is a unit vector within the readers' 1 % (the
// compositor normalises); an invalid eye's is finite (a caller that ignores the flag sees no NaN).
template <class Eye>
bool usableDirection(const Eye& e) {
    if (!(std::isfinite(e.dir.x) && std::isfinite(e.dir.y) && std::isfinite(e.dir.z))) return false;
    const double n = std::sqrt(double(e.dir.x) * e.dir.x + double(e.dir.y) * e.dir.y + double(e.dir.z) * e.dir.z);
    return !e.valid || std::abs(n - 1.0) <= 0.0101;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const uint8_t sel = data[0];
    const std::string_view text(reinterpret_cast<const char*>(data + 1), size - 1);
    switch (sel & 3u) {
    case 0: {
        auto info = wrsfov::eval::parseSequenceInfo(text);
        if (!info) return 0;
        // What the reader relies on: a size, frames, a positive finite rate; a json written back
        // from it parses to the same description.
        require(info->width > 0 && info->height > 0 && info->frameCount > 0);
        require(std::isfinite(info->fps) && info->fps > 0);
        auto again = wrsfov::eval::parseSequenceInfo(wrsfov::eval::formatSequenceInfo(*info));
        require(again.ok());
        require(again->width == info->width && again->height == info->height &&
                again->frameCount == info->frameCount && again->fps == info->fps);
        break;
    }
    case 1: {
        const uint32_t frames = 1u + (sel >> 2u);
        auto g = wrsfov::eval::parseSequenceGaze(text, frames);
        if (!g) return 0;
        require(g->frames.size() == frames);  // one gaze per frame, whatever the file held
        for (const auto& f : g->frames)
            for (const auto& e : f) require(usableDirection(e) && std::isfinite(e.confidence));
        break;
    }
    default: {
        wrsfov::gaze::ReadOptions o;
        o.format = static_cast<wrsfov::gaze::GazeFormat>((sel >> 2u) % 4u);
        auto r = wrsfov::gaze::read_gaze_text(text, o);
        if (!r) return 0;
        for (const auto& s : r->samples) {
            require(std::isfinite(s.t_s));
            for (const auto& e : s.eye) require(usableDirection(e) && std::isfinite(e.confidence));
        }
        break;
    }
    }
    return 0;
}
