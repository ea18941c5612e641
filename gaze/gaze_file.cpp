#include "gaze/gaze_file.h"

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <glm/geometric.hpp>
#include <map>
#include <optional>
#include <sstream>

namespace wrsfov::gaze {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\r' || s.front() == '\t' || s.front() == '\xEF' ||
                          s.front() == '\xBB' || s.front() == '\xBF'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\r' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

// Splits one line on `delim`, honouring double quotes.
std::vector<std::string> split(std::string_view line, char delim) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (c == '"') {
            if (quoted && i + 1 < line.size() && line[i + 1] == '"') {
                cur += '"';
                ++i;
            } else {
                quoted = !quoted;
            }
        } else if (c == delim && !quoted) {
            out.push_back(std::move(cur));
            cur.clear();
        } else if (c != '\r' || quoted) {
            cur += c;
        }
    }
    out.push_back(std::move(cur));
    return out;
}

std::optional<double> to_number(std::string_view s, bool decimal_comma = false) {
    s = trim(s);
    if (s.empty()) return std::nullopt;
    std::string tmp;
    if (decimal_comma && s.find(',') != std::string_view::npos) {
        tmp.assign(s);
        for (char& c : tmp)
            if (c == ',') c = '.';
        s = tmp;
    }
    if (s.front() == '+') s.remove_prefix(1);
    double v = 0;
    const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (ec != std::errc() || p != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

struct Columns {
    std::map<std::string, size_t, std::less<>> index;
    size_t count = 0;

    explicit Columns(const std::vector<std::string>& header) : count(header.size()) {
        for (size_t i = 0; i < header.size(); ++i) index.emplace(std::string(trim(header[i])), i);
    }
    std::optional<size_t> find(std::string_view name) const {
        auto it = index.find(name);
        if (it == index.end()) return std::nullopt;
        return it->second;
    }
    // A column whose name starts with `prefix` (Tobii adds unit suffixes such as " [μs]").
    std::optional<std::pair<size_t, std::string>> find_prefix(std::string_view prefix) const {
        for (const auto& [name, i] : index)
            if (name.rfind(prefix, 0) == 0) return std::make_pair(i, name);
        return std::nullopt;
    }
};

struct Lines {
    std::string_view text;
    size_t pos = 0, number = 0;
    bool next(std::string_view& line) {
        if (pos >= text.size()) return false;
        const size_t end = text.find('\n', pos);
        line = text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
        pos = end == std::string_view::npos ? text.size() : end + 1;
        ++number;
        return true;
    }
};

std::string fmt(const char* f, double a) {
    char b[96];
    std::snprintf(b, sizeof b, f, a);
    return b;
}

// A direction from a file: finite, not near zero, and unit length within 1 % (then normalised).
std::optional<std::string> check_unit(glm::vec3& d) {
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z)) return "direction is not finite";
    const float len = glm::length(d);
    if (std::abs(len - 1.f) > 0.01f) return fmt("direction is not a unit vector (length %.4g)", len);
    d /= len;
    return std::nullopt;
}

class Reader {
public:
    Reader(std::string_view text, const ReadOptions& o) : o_(o) { lines_.text = text; }

    Result<GazeRecording> run() {
        std::string_view line;
        std::string_view header;
        while (lines_.next(line)) {
            const std::string_view t = trim(line);
            if (t.empty() || t.front() == '#') continue;
            header = line;
            break;
        }
        if (header.empty()) return fail("the file has no header line (empty file?)");
        GazeFormat f = o_.format;
        if (f == GazeFormat::Auto) {
            if (header.find('\t') != std::string_view::npos &&
                header.find("Recording timestamp") != std::string_view::npos)
                f = GazeFormat::TobiiProLab;
            else if (header.find("gaze_timestamp") != std::string_view::npos)
                f = GazeFormat::PupilLabs;
            else if (header.find("t_s") != std::string_view::npos)
                f = GazeFormat::Project;
            else
                return fail("unrecognised header '" + std::string(header.substr(0, 80)) +
                            "': expected the project CSV (t_s,frame,valid,...), Pupil Labs gaze_positions.csv "
                            "(gaze_timestamp,...) or a Tobii Pro Lab TSV (Recording timestamp ...)");
        }
        rec_.format = f;
        switch (f) {
            case GazeFormat::Project:
                return project(header);
            case GazeFormat::PupilLabs:
                return pupil(header);
            case GazeFormat::TobiiProLab:
                return tobii(header);
            case GazeFormat::Auto:
                break;
        }
        return fail("no format");
    }

private:
    void issue(std::string msg) { rec_.issues.push_back({lines_.number, std::move(msg)}); }

    // Adds a sample if its time is after the previous one.
    bool push(GazeSample s, long long frame) {
        if (!rec_.samples.empty() && !(s.t_s > rec_.samples.back().t_s)) {
            issue(fmt("time %.6f s is not after the previous sample's", s.t_s));
            return false;
        }
        rec_.samples.push_back(s);
        rec_.frames.push_back(frame);
        return true;
    }

    // Next data row split on `delim`; false at the end. Blank and comment lines are skipped.
    bool row(char delim, size_t expected, std::vector<std::string>& f) {
        std::string_view line;
        while (lines_.next(line)) {
            const std::string_view t = trim(line);
            if (t.empty() || t.front() == '#') continue;
            f = split(line, delim);
            if (f.size() != expected) {
                issue("expected " + std::to_string(expected) + " fields, got " + std::to_string(f.size()));
                continue;
            }
            return true;
        }
        return false;
    }

    Result<GazeRecording> project(std::string_view header) {
        const Columns c(split(header, ','));
        const char* names[] = {"t_s", "frame", "valid", "left_x", "left_y", "left_z", "right_x", "right_y", "right_z"};
        size_t idx[9];
        for (int i = 0; i < 9; ++i) {
            auto k = c.find(names[i]);
            if (!k)
                return fail(std::string("project CSV header lacks column '") + names[i] +
                            "' (expected t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z)");
            idx[i] = *k;
        }
        const auto label_col = c.find("label");
        const auto conf_col = c.find("confidence");
        rec_.has_labels = label_col.has_value();
        std::vector<std::string> f;
        while (row(',', c.count, f)) {
            const auto t = to_number(f[idx[0]]);
            if (!t) {
                issue("t_s '" + f[idx[0]] + "' is not a number");
                continue;
            }
            const auto frame = to_number(f[idx[1]]);
            // Below 2^53: every integer there is exact in a double and fits the frame index.
            if (!frame || *frame < 0 || *frame != std::floor(*frame) || *frame >= 9007199254740992.0) {
                issue("frame '" + f[idx[1]] + "' is not a non-negative integer below 2^53");
                continue;
            }
            const std::string_view v = trim(f[idx[2]]);
            if (v != "0" && v != "1") {
                issue("valid '" + f[idx[2]] + "' is not 0 or 1");
                continue;
            }
            GazeSample s;
            s.t_s = *t;
            const bool valid = v == "1";
            float conf = valid ? 1.f : 0.f;
            if (conf_col) {
                const auto cv = to_number(f[*conf_col]);
                if (!cv || *cv < 0 || *cv > 1) {
                    issue("confidence '" + f[*conf_col] + "' is not in [0, 1]");
                    continue;
                }
                conf = static_cast<float>(*cv);
            }
            bool ok = true;
            for (int e = 0; e < 2 && ok; ++e) {
                glm::vec3 d(0, 0, -1);
                bool have = true;
                for (int k = 0; k < 3; ++k) {
                    const auto x = to_number(f[idx[3 + 3 * e + k]]);
                    if (!x) {
                        have = false;
                        if (valid || !trim(f[idx[3 + 3 * e + k]]).empty()) {
                            issue(std::string(names[3 + 3 * e + k]) + " '" + f[idx[3 + 3 * e + k]] +
                                  "' is not a number");
                            ok = false;
                        }
                        break;
                    }
                    d[k] = static_cast<float>(*x);
                }
                if (!ok) break;
                if (valid) {
                    if (auto err = check_unit(d)) {
                        issue(std::string(e == 0 ? "left " : "right ") + *err);
                        ok = false;
                        break;
                    }
                } else if (const float len = glm::length(d); !have || !(len > 0) || !std::isfinite(len)) {
                    d = glm::vec3(0, 0, -1);  // no usable direction (also infinite or too long to normalise)
                } else {
                    d /= len;
                }
                s.eye[e] = {d, valid, conf};
            }
            if (!ok) continue;
            if (label_col) {
                const std::string_view ln = trim(f[*label_col]);
                const auto ev = ln.empty() ? std::optional<Event>(Event::Unknown) : parse_event(ln);
                if (!ev) {
                    issue("label '" + f[*label_col] + "' is not an event name");
                    continue;
                }
                s.label = *ev;
            }
            push(s, static_cast<long long>(*frame));
        }
        return std::move(rec_);
    }

    // Pupil Core: 3D camera space of the world camera, x right, y down, z forward; eye0 is the
    // right eye, eye1 the left.
    Result<GazeRecording> pupil(std::string_view header) {
        const Columns c(split(header, ','));
        const auto ts = c.find("gaze_timestamp"), conf = c.find("confidence");
        if (!ts || !conf) return fail("Pupil Labs gaze_positions.csv lacks gaze_timestamp or confidence");
        auto triple = [&](const char* p) -> std::optional<std::array<size_t, 3>> {
            const std::string b = p;
            auto x = c.find(b + "_x"), y = c.find(b + "_y"), z = c.find(b + "_z");
            if (!x || !y || !z) return std::nullopt;
            return std::array<size_t, 3>{*x, *y, *z};
        };
        const auto n0 = triple("gaze_normal0"), n1 = triple("gaze_normal1"), p3 = triple("gaze_point_3d");
        if (!n0 && !n1 && !p3)
            return fail("Pupil Labs gaze_positions.csv has neither gaze_normal0/1_{x,y,z} nor gaze_point_3d_{x,y,z}");
        std::optional<double> t_first;
        std::vector<std::string> f;
        while (row(',', c.count, f)) {
            const auto t = to_number(f[*ts]);
            if (!t) {
                issue("gaze_timestamp '" + f[*ts] + "' is not a number");
                continue;
            }
            const auto cf = to_number(f[*conf]);
            if (!cf || *cf < 0 || *cf > 1) {
                issue("confidence '" + f[*conf] + "' is not in [0, 1]");
                continue;
            }
            enum class Got { Missing, Ok, Bad };
            auto read_dir = [&](const std::optional<std::array<size_t, 3>>& cols, glm::vec3& d) {
                if (!cols) return Got::Missing;
                double v[3];
                int empty = 0;
                for (int k = 0; k < 3; ++k) {
                    if (trim(f[(*cols)[k]]).empty()) {
                        ++empty;
                        continue;
                    }
                    const auto x = to_number(f[(*cols)[k]]);
                    if (!x) return Got::Bad;
                    v[k] = *x;
                }
                if (empty == 3) return Got::Missing;
                if (empty > 0) return Got::Bad;
                const glm::dvec3 dv(v[0], -v[1], -v[2]);
                const double len = glm::length(dv);
                if (!(len > 0) || !std::isfinite(len)) return Got::Bad;  // zero, or too long to normalise
                d = glm::vec3(glm::normalize(dv));
                return Got::Ok;
            };
            glm::vec3 right, left, point;
            const Got gr = read_dir(n0, right), gl = read_dir(n1, left), gp = read_dir(p3, point);
            if (gr == Got::Bad || gl == Got::Bad || gp == Got::Bad) {
                issue("gaze direction fields are not three numbers");
                continue;
            }
            const bool valid = *cf >= o_.min_confidence;
            const float conf_f = static_cast<float>(*cf);
            GazeSample s;
            if (!t_first) t_first = *t;
            s.t_s = *t - *t_first;
            if (gr == Got::Ok) s.eye[kRight] = {right, valid, conf_f};
            if (gl == Got::Ok) s.eye[kLeft] = {left, valid, conf_f};
            // Monocular rows: the other eye follows the cyclopean gaze point if there is one.
            for (int e = 0; e < 2; ++e)
                if (!s.eye[e].valid && (e == kRight ? gr : gl) != Got::Ok && gp == Got::Ok)
                    s.eye[e] = {point, valid, conf_f};
            push(s, -1);
        }
        return std::move(rec_);
    }

    // Tobii Pro Lab (Pro Glasses): gaze direction per eye, x left, y up, z forward.
    Result<GazeRecording> tobii(std::string_view header) {
        const Columns c(split(header, '\t'));
        const auto ts = c.find_prefix("Recording timestamp");
        if (!ts) return fail("Tobii Pro Lab TSV lacks the 'Recording timestamp' column");
        double to_seconds = 1e-6;  // Pro Lab's default export unit is microseconds
        if (ts->second.find("[ms]") != std::string::npos) to_seconds = 1e-3;
        if (ts->second.find("[ns]") != std::string::npos) to_seconds = 1e-9;
        std::optional<size_t> dir[2][3];
        const char* side[2] = {"left", "right"};
        const char* axis[3] = {"X", "Y", "Z"};
        for (int e = 0; e < 2; ++e)
            for (int k = 0; k < 3; ++k) {
                auto col = c.find_prefix(std::string("Gaze direction ") + side[e] + " " + axis[k]);
                if (col) dir[e][k] = col->first;
            }
        for (int e = 0; e < 2; ++e)
            for (int k = 0; k < 3; ++k)
                if (!dir[e][k])
                    return fail(std::string("Tobii Pro Lab TSV lacks 'Gaze direction ") + side[e] + " " + axis[k] +
                                "': export the gaze direction columns (screen-based recordings without them are "
                                "not supported)");
        const auto validity_l = c.find("Validity left"), validity_r = c.find("Validity right");
        const auto sensor = c.find("Sensor");
        const auto movement = c.find("Eye movement type");
        std::optional<double> t_first;
        std::vector<std::string> f;
        while (row('\t', c.count, f)) {
            if (sensor && !trim(f[*sensor]).empty() && trim(f[*sensor]) != "Eye Tracker") {
                ++rec_.ignored_rows;
                continue;
            }
            const auto t = to_number(f[ts->first], true);
            if (!t) {
                issue("Recording timestamp '" + f[ts->first] + "' is not a number");
                continue;
            }
            GazeSample s;
            if (!t_first) t_first = *t;
            s.t_s = (*t - *t_first) * to_seconds;
            bool bad = false;
            for (int e = 0; e < 2; ++e) {
                const auto vcol = e == 0 ? validity_l : validity_r;
                bool valid = true;
                if (vcol) {
                    const std::string_view v = trim(f[*vcol]);
                    if (v == "Invalid" || v.empty()) {
                        valid = false;
                    } else if (v != "Valid") {
                        issue(std::string("Validity ") + side[e] + " '" + f[*vcol] + "' is not Valid or Invalid");
                        bad = true;
                        break;
                    }
                }
                double v[3];
                int empty = 0;
                for (int k = 0; k < 3; ++k) {
                    const std::string& field = f[*dir[e][k]];
                    if (trim(field).empty()) {
                        ++empty;
                        continue;
                    }
                    const auto x = to_number(field, true);
                    if (!x) {
                        issue(std::string("Gaze direction ") + side[e] + " " + axis[k] + " '" + field +
                              "' is not a number");
                        bad = true;
                        break;
                    }
                    v[k] = *x;
                }
                if (bad) break;
                if (empty == 3 || !valid) {
                    s.eye[e] = {};
                    continue;
                }
                if (empty > 0) {
                    issue(std::string("Gaze direction ") + side[e] + " has missing components");
                    bad = true;
                    break;
                }
                glm::vec3 d(static_cast<float>(-v[0]), static_cast<float>(v[1]), static_cast<float>(-v[2]));
                if (auto err = check_unit(d)) {
                    issue(std::string("Gaze direction ") + side[e] + ": " + *err);
                    bad = true;
                    break;
                }
                s.eye[e] = {d, true, 1.f};
            }
            if (bad) continue;
            if (movement) {
                const std::string_view m = trim(f[*movement]);
                if (m == "Fixation")
                    s.label = Event::Fixation;
                else if (m == "Saccade")
                    s.label = Event::Saccade;
                else if (m == "EyesNotFound")
                    s.label = Event::Blink;
            }
            push(s, -1);
        }
        return std::move(rec_);
    }

    ReadOptions o_;
    Lines lines_;
    GazeRecording rec_;
};

}  // namespace

std::string_view format_name(GazeFormat f) {
    switch (f) {
        case GazeFormat::Auto:
            return "auto";
        case GazeFormat::Project:
            return "project CSV";
        case GazeFormat::PupilLabs:
            return "Pupil Labs gaze_positions.csv";
        case GazeFormat::TobiiProLab:
            return "Tobii Pro Lab TSV";
    }
    return "?";
}

Result<GazeRecording> read_gaze_text(std::string_view text, const ReadOptions& options) {
    return Reader(text, options).run();
}

Result<GazeRecording> read_gaze_file(const std::string& path, const ReadOptions& options) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return fail("cannot open gaze file '" + path + "'");
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) return fail("cannot read gaze file '" + path + "'");
    auto r = read_gaze_text(ss.str(), options);
    if (!r) return fail(path + ": " + r.error().message);
    return r;
}

std::string format_gaze_csv(std::span<const GazeSample> samples, bool labels, std::span<const long long> frames) {
    std::string out = "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z";
    out += labels ? ",label\n" : "\n";
    char buf[320];
    for (size_t i = 0; i < samples.size(); ++i) {
        const GazeSample& s = samples[i];
        glm::vec3 d[2] = {s.eye[0].dir, s.eye[1].dir};
        const bool valid = s.eye[0].valid || s.eye[1].valid;
        if (valid && !s.eye[0].valid) d[0] = d[1];
        if (valid && !s.eye[1].valid) d[1] = d[0];
        const long long frame = i < frames.size() && frames[i] >= 0 ? frames[i] : static_cast<long long>(i);
        int n = std::snprintf(buf, sizeof buf, "%.6f,%lld,%d,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g", s.t_s, frame,
                              valid ? 1 : 0, d[0].x, d[0].y, d[0].z, d[1].x, d[1].y, d[1].z);
        out.append(buf, static_cast<size_t>(n));
        if (labels) {
            out += ',';
            out += event_name(s.label);
        }
        out += '\n';
    }
    return out;
}

Status write_gaze_csv(const std::string& path, std::span<const GazeSample> samples, bool labels,
                      std::span<const long long> frames) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) return fail("cannot create '" + path + "' (does the directory exist and is it writable?)");
    const std::string text = format_gaze_csv(samples, labels, frames);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) return fail("cannot write '" + path + "' (disk full?)");
    return Ok{};
}

}  // namespace wrsfov::gaze
