// gaze.csv: the per-frame gaze of a sequence.
#include "eval/sequence.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>
#include <unordered_set>

#include "gaze/gaze_file.h"
#include "eval/sequence_internal.h"

namespace wrsfov::eval {

using namespace seqfile;
namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// gaze.csv
// ---------------------------------------------------------------------------------------------

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\r')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

std::vector<std::string_view> splitCsv(std::string_view line) {
    std::vector<std::string_view> out;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= line.size(); ++i)
        if (i == line.size() || line[i] == ',') {
            out.push_back(trim(line.substr(start, i - start)));
            start = i + 1;
        }
    return out;
}

// A number as text: finite or not ("nan", "inf" are numbers here); nullopt for anything else.
std::optional<double> csvNumber(std::string_view s) {
    if (s.empty()) return std::nullopt;
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0;
    auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (p != s.data() + s.size()) return std::nullopt;
    if (ec == std::errc::result_out_of_range) return s.front() == '-' ? -HUGE_VAL : HUGE_VAL;
    if (ec != std::errc()) return std::nullopt;
    return v;
}

}  // namespace

Result<SequenceGaze> parseSequenceGaze(std::string_view csv, uint32_t frameCount, const std::string& name) {
    SequenceGaze out;
    out.frames.assign(frameCount, {});
    std::vector<std::size_t> rowLine(frameCount, 0);
    auto bad = [&](std::size_t line, const std::string& what) {
        return seqError(SequenceError::BadGaze, name + " line " + std::to_string(line) + ": " + what);
    };
    std::size_t lineNo = 0, pos = 0;
    std::vector<std::string_view> header;
    std::size_t idx[9] = {};
    std::optional<std::size_t> confCol;
    const char* names[] = {"t_s", "frame", "valid", "left_x", "left_y", "left_z", "right_x", "right_y", "right_z"};
    if (csv.substr(0, 3) == "\xEF\xBB\xBF") pos = 3;
    while (pos < csv.size()) {
        std::size_t end = csv.find('\n', pos);
        if (end == std::string_view::npos) end = csv.size();
        const std::string_view line = trim(csv.substr(pos, end - pos));
        pos = end + 1;
        ++lineNo;
        if (line.empty() || line.front() == '#') continue;
        auto f = splitCsv(line);
        if (header.empty()) {
            header = f;
            for (int k = 0; k < 9; ++k) {
                auto it = std::find(header.begin(), header.end(), names[k]);
                if (it == header.end())
                    return bad(lineNo, std::string("header lacks column '") + names[k] +
                                           "' (expected t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z)");
                idx[k] = std::size_t(it - header.begin());
            }
            auto c = std::find(header.begin(), header.end(), "confidence");
            if (c != header.end()) confCol = std::size_t(c - header.begin());
            continue;
        }
        if (f.size() != header.size())
            return bad(lineNo,
                       "expected " + std::to_string(header.size()) + " fields, got " + std::to_string(f.size()));
        auto t = csvNumber(f[idx[0]]);
        if (!t || !std::isfinite(*t)) return bad(lineNo, "t_s '" + std::string(f[idx[0]]) + "' is not a finite number");
        auto fr = csvNumber(f[idx[1]]);
        if (!fr || !(*fr >= 0) || *fr != std::floor(*fr))
            return bad(lineNo, "frame '" + std::string(f[idx[1]]) + "' is not a non-negative integer");
        if (*fr >= double(frameCount))
            return bad(lineNo, "frame " + std::string(f[idx[1]]) + " is beyond the sequence (frame_count " +
                                   std::to_string(frameCount) + ")");
        const std::string_view v = f[idx[2]];
        if (v != "0" && v != "1") return bad(lineNo, "valid '" + std::string(v) + "' is not 0 or 1");
        const uint32_t frame = uint32_t(*fr);
        float conf = v == "1" ? 1.0f : 0.0f;
        if (confCol) {
            auto c = csvNumber(f[*confCol]);
            if (!c || !(*c >= 0 && *c <= 1))
                return bad(lineNo, "confidence '" + std::string(f[*confCol]) + "' is not in [0, 1]");
            conf = float(*c);
        }
        std::array<layers::EyeGaze, 2> g{};
        std::string note;
        for (int e = 0; e < 2; ++e) {
            glm::vec3 d(0.0f, 0.0f, -1.0f);
            bool finite = true;
            for (int k = 0; k < 3; ++k) {
                const std::string_view s = f[idx[3 + 3 * e + k]];
                if (v == "0" && s.empty()) continue;  // no direction during a dropout is fine
                auto x = csvNumber(s);
                if (!x)
                    return bad(lineNo, std::string(names[3 + 3 * e + k]) + " '" + std::string(s) + "' is not a number");
                d[k] = float(*x);
                finite = finite && std::isfinite(d[k]);
            }
            g[e].dir = d;
            g[e].confidence = conf;
            g[e].valid = v == "1";
            if (!g[e].valid) continue;
            const float len = finite ? glm::length(d) : NAN;
            char buf[96];
            if (!finite) {
                std::snprintf(buf, sizeof buf, "%s direction is not finite", e ? "right" : "left");
            } else if (!(std::abs(len - 1.0f) <= 0.01f)) {
                std::snprintf(buf, sizeof buf, "%s direction is not a unit vector (length %.4g)", e ? "right" : "left",
                              double(len));
            } else {
                continue;  // unit within 1 %: passed as written, bit for bit (the compositor normalises)
            }
            // The documented fallback: the frame's gaze becomes invalid (view centre, fallback fovea).
            note += (note.empty() ? "" : "; ") + std::string(buf);
        }
        for (auto& eg : g)  // an invalid eye's direction is never used; it is still never NaN or infinite
            if (!(std::isfinite(eg.dir.x) && std::isfinite(eg.dir.y) && std::isfinite(eg.dir.z)))
                eg.dir = glm::vec3(0.0f, 0.0f, -1.0f);
        if (!note.empty()) {
            for (auto& eg : g) eg.valid = false, eg.confidence = 0.0f;
            out.notes.push_back({lineNo, frame, note + ": gaze of frame " + std::to_string(frame) + " is invalid"});
        }
        out.frames[frame] = g;  // the last row of a frame wins
        rowLine[frame] = lineNo;
    }
    if (header.empty()) return bad(lineNo == 0 ? 1 : lineNo, "no header line (empty file?)");
    for (uint32_t i = 0; i < frameCount; ++i)
        if (rowLine[i] == 0) out.notes.push_back({0, i, "no row for frame " + std::to_string(i) + ": gaze invalid"});
    // Notes in frame order, rows before "no row".
    std::stable_sort(out.notes.begin(), out.notes.end(),
                     [](const GazeNote& a, const GazeNote& b) { return a.frame < b.frame; });
    return out;
}

}  // namespace wrsfov::eval
