// sequence.json: its parser (nlohmann-json with what the format adds) and its fields.
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

#include <nlohmann/json.hpp>
#include "eval/sequence_internal.h"

namespace wrsfov::eval {

using namespace seqfile;
namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------------
// sequence.json through nlohmann-json (RFC 8259, UTF-8 checked, a byte-order mark skipped), with
// what the format adds on top:
//  - the non-standard tokens NaN, Infinity and -Infinity (Python's json module writes them) are
//    read, so that the field check can name the field (and "far" may be Infinity): before parsing,
//    each such bare token becomes a marker string, a NUL followed by the token's text;
//  - a key that appears twice in an object is an error (nlohmann keeps the last one);
//  - nesting deeper than kMaxJsonDepth is an error (the format needs 3 levels).
// Numbers are read as the nearest double; the float fields are that double rounded to float.
// ---------------------------------------------------------------------------------------------

using Json = nlohmann::ordered_json;  // ordered: fields are checked and written in file order

constexpr int kMaxJsonDepth = 32;
constexpr std::string_view kNonFinite[] = {"-Infinity", "Infinity", "NaN"};

// The json text with every bare NaN / Infinity / -Infinity turned into a marker string, and where
// those tokens were (to give syntax errors the position in the original text).
struct MarkedJson {
    struct Swap {
        std::size_t at, len;  // in `text`
        std::size_t origAt, origLen;
    };
    std::string text;
    std::vector<Swap> swaps;

    // The offset in the original text of offset `pos` in `text`.
    std::size_t originalOffset(std::size_t pos) const {
        std::size_t orig = pos;
        for (const Swap& s : swaps) {
            if (pos < s.at) break;
            if (pos < s.at + s.len) return s.origAt;
            orig = s.origAt + s.origLen + (pos - s.at - s.len);
        }
        return orig;
    }
};

MarkedJson markNonFinite(std::string_view in) {
    MarkedJson out;
    out.text.reserve(in.size());
    bool inString = false;
    auto identChar = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    for (std::size_t i = 0; i < in.size(); ++i) {
        const char c = in[i];
        if (inString) {
            out.text += c;
            if (c == '\\' && i + 1 < in.size()) out.text += in[++i];
            else if (c == '"') inString = false;
            continue;
        }
        if (c == '"') inString = true;
        bool swapped = false;
        for (std::string_view tok : kNonFinite) {
            if (in.substr(i, tok.size()) != tok || (i > 0 && identChar(in[i - 1])) ||
                (i + tok.size() < in.size() && identChar(in[i + tok.size()])))
                continue;
            const std::string marker = "\"\\u0000" + std::string(tok) + "\"";
            out.swaps.push_back({out.text.size(), marker.size(), i, tok.size()});
            out.text += marker;
            i += tok.size() - 1;
            swapped = true;
            break;
        }
        if (!swapped) out.text += c;
    }
    return out;
}

// The token's text ("NaN", "Infinity", "-Infinity") when `v` is the marker string of one.
std::optional<std::string_view> nonFiniteToken(const Json& v) {
    if (!v.is_string()) return std::nullopt;
    const std::string& s = v.get_ref<const std::string&>();
    if (s.empty() || s[0] != '\0') return std::nullopt;
    for (std::string_view tok : kNonFinite)
        if (std::string_view(s).substr(1) == tok) return tok;
    return std::nullopt;
}

std::string numberText(double v) {
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back as v
    return ec == std::errc() ? std::string(buf, p) : std::string("?");
}

std::string joinPath(const std::string& path, std::string_view key) {
    return path.empty() ? std::string(key) : path + "." + std::string(key);
}

// Follows the parser through the objects and arrays (nlohmann's parser callback) to refuse
// duplicate keys and deep nesting, and to name the field a number overflow happens in.
class JsonTracker {
public:
    struct Refused {
        std::string what;
    };

    bool operator()(int depth, Json::parse_event_t event, Json& parsed) {
        using E = Json::parse_event_t;
        switch (event) {
        case E::object_start:
        case E::array_start:
            if (depth >= kMaxJsonDepth)
                throw Refused{"nested more than " + std::to_string(kMaxJsonDepth) + " levels deep"};
            open_.push_back({here(), event == E::object_start, {}, {}});
            break;
        case E::key: {
            if (auto tok = nonFiniteToken(parsed))
                throw Refused{"a field name must be a quoted string, not " + std::string(*tok)};
            Open& o = open_.back();
            o.lastKey = parsed.get<std::string>();
            if (!o.keys.insert(o.lastKey).second)
                throw Refused{"field \"" + joinPath(o.path, o.lastKey) + "\" appears twice"};
            break;
        }
        case E::object_end:
        case E::array_end: open_.pop_back(); break;
        case E::value: break;
        }
        return true;
    }

    // The field whose value is being read ("fov.left.angle_up", "fps"; "" at the top level).
    std::string here() const {
        if (open_.empty()) return "";
        const Open& o = open_.back();
        return o.object ? joinPath(o.path, o.lastKey) : o.path + "[]";
    }

private:
    struct Open {
        std::string path;
        bool object;
        std::string lastKey;
        std::unordered_set<std::string> keys;
    };
    std::vector<Open> open_;
};

// "file:line:column" of a byte offset (0-based; columns count bytes from 1).
std::string textPosition(const std::string& name, std::string_view text, std::size_t pos) {
    pos = std::min(pos, text.size());
    const std::size_t line = 1 + std::size_t(std::count(text.begin(), text.begin() + std::ptrdiff_t(pos), '\n'));
    const std::size_t lineStart = pos == 0 ? 0 : text.rfind('\n', pos - 1);
    const std::size_t column = lineStart == std::string_view::npos || pos == 0 ? pos + 1 : pos - lineStart;
    return name + ":" + std::to_string(line) + ":" + std::to_string(column);
}

// nlohmann's message without its "[json.exception...] parse error at line L, column C: " prefix,
// bytes outside ASCII written as \xNN (the text it quotes may hold the offending bytes).
std::string parseErrorReason(const std::string& what) {
    std::string_view s = what;
    if (auto col = s.find(", column "); col != std::string_view::npos)
        if (auto colon = s.find(": ", col); colon != std::string_view::npos) s.remove_prefix(colon + 2);
    std::string out;
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x80) {
            out += c;
        } else {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\x%02X", unsigned(u));
            out += buf;
        }
    }
    return out;
}

Result<Json> parseJson(std::string_view text, const std::string& name) {
    const std::string_view body = text.substr(text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0);
    if (body.find_first_not_of(" \t\r\n") == std::string_view::npos)
        return seqError(SequenceError::BadJson, name + ": not valid JSON: the file is empty");
    const MarkedJson marked = markNonFinite(text);
    JsonTracker tracker;
    try {
        return Json::parse(marked.text, std::ref(tracker));
    } catch (const Json::parse_error& e) {
        // e.byte: 1-based index of the last byte read (one past the end after reading the end).
        const std::size_t pos =
            e.byte > marked.text.size() ? text.size() : marked.originalOffset(e.byte == 0 ? 0 : e.byte - 1);
        const std::string reason = parseErrorReason(e.what());
        const bool ranOut = reason.find("end of input") != std::string::npos ||
                            reason.find("missing closing quote") != std::string::npos;
        return seqError(SequenceError::BadJson, textPosition(name, text, pos) + ": not valid JSON: " + reason +
                                                    (ranOut ? " (truncated?)" : ""));
    } catch (const Json::out_of_range& e) {
        if (e.id == 406) {  // "number overflow parsing '1e400'": beyond double
            const std::string w = e.what();
            const auto a = w.find('\''), b = w.rfind('\'');
            const std::string num = a != std::string::npos && b > a ? w.substr(a + 1, b - a - 1) : "a number";
            const std::string field = tracker.here();
            const std::string what = field.empty() ? "the top level" : "\"" + field + "\"";
            return seqError(SequenceError::BadField, name + ": " + what + " is " + num + ", not a finite number");
        }
        return seqError(SequenceError::BadJson, name + ": not valid JSON: " + parseErrorReason(e.what()));
    } catch (const JsonTracker::Refused& r) {
        return seqError(SequenceError::BadJson, name + ": not valid JSON: " + r.what);
    } catch (const Json::exception& e) {
        return seqError(SequenceError::BadJson, name + ": not valid JSON: " + parseErrorReason(e.what()));
    }
}

// Typed access to the fields of one object of sequence.json; messages name the file and field.
class Fields {
public:
    Fields(const Json& v, std::string path, std::string file, Error* error)
        : v_(v), path_(std::move(path)), file_(std::move(file)), error_(error) {}

    // Fails on fields other than `known`.
    bool onlyKnown(std::initializer_list<std::string_view> known) {
        for (const auto& [k, v] : v_.items()) {
            if (std::find(known.begin(), known.end(), k) != known.end()) continue;
            std::string list;
            for (auto n : known) list += (list.empty() ? "" : ", ") + std::string(n);
            return fail("unknown field \"" + name(k) + "\" (known here: " + list + ")");
        }
        return true;
    }

    const Json* find(std::string_view key) const {
        auto it = v_.find(std::string(key));
        return it == v_.end() ? nullptr : &*it;
    }

    const Json* require(std::string_view key) {
        const Json* v = find(key);
        if (!v) fail("missing field \"" + name(key) + "\"");
        return v;
    }

    bool number(std::string_view key, double& out, bool required = true) {
        const Json* v = required ? require(key) : find(key);
        if (!v) return !required;
        if (auto tok = nonFiniteToken(*v))
            return fail("\"" + name(key) + "\" is " + std::string(*tok) + ", not a finite number");
        if (!v->is_number()) return fail("\"" + name(key) + "\" must be a number");
        out = v->get<double>();
        return true;
    }

    // A float (the double rounded to float); "inf" / Infinity only where allowed.
    bool floatValue(std::string_view key, float& out, bool allowInf = false) {
        const Json* v = require(key);
        if (!v) return false;
        const auto tok = nonFiniteToken(*v);
        if (allowInf && (tok == "Infinity" || (v->is_string() && (*v == "inf" || *v == "infinity")))) {
            out = HUGE_VALF;
            return true;
        }
        if (tok) return fail("\"" + name(key) + "\" is " + std::string(*tok) + ", not a finite number");
        if (!v->is_number()) return fail("\"" + name(key) + "\" must be a number" + (allowInf ? " or \"inf\"" : ""));
        const double d = v->get<double>();
        // Beyond the largest float (rounding included) the float would be infinite.
        constexpr double kFloatLimit = 3.4028235677973366e38;  // FLT_MAX + half its ulp
        if (!(std::abs(d) < kFloatLimit))
            return fail("\"" + name(key) + "\" is " + numberText(d) + ", not a finite number");
        out = static_cast<float>(d);
        return true;
    }

    bool integer(std::string_view key, uint64_t lo, uint64_t hi, uint32_t& out) {
        double d = 0;
        if (!number(key, d)) return false;
        if (d != std::floor(d) || d < double(lo) || d > double(hi))
            return fail("\"" + name(key) + "\" must be an integer in [" + std::to_string(lo) + ", " +
                        std::to_string(hi) + "], not " + find(key)->dump());
        out = uint32_t(d);
        return true;
    }

    bool string(std::string_view key, std::string& out, bool required = true) {
        const Json* v = required ? require(key) : find(key);
        if (!v) return !required;
        if (!v->is_string() || nonFiniteToken(*v)) return fail("\"" + name(key) + "\" must be a string");
        out = v->get<std::string>();
        return true;
    }

    bool boolean(std::string_view key, bool& out) {
        const Json* v = find(key);
        if (!v) return true;
        if (!v->is_boolean()) return fail("\"" + name(key) + "\" must be true or false");
        out = v->get<bool>();
        return true;
    }

    // A child object; nullopt with no error when absent or null and !required.
    std::optional<Fields> child(std::string_view key, bool required) {
        const Json* v = required ? require(key) : find(key);
        if (!v || (!required && v->is_null())) return std::nullopt;
        if (!v->is_object()) {
            fail("\"" + name(key) + "\" must be an object {...}");
            return std::nullopt;
        }
        return Fields(*v, name(key), file_, error_);
    }

    bool fail(const std::string& what) {
        *error_ = seqError(SequenceError::BadField, file_ + ": " + what);
        return false;
    }
    std::string name(std::string_view key) const { return joinPath(path_, key); }

private:
    const Json& v_;
    std::string path_, file_;
    Error* error_;
};

// The json number for a value: an integer when it is one (fps 90, far 100), else the double.
Json jsonNumber(double v) {
    if (v == std::trunc(v) && std::abs(v) < 9007199254740992.0) return Json(static_cast<int64_t>(v));
    return Json(v);
}

// A float as json: its shortest decimal text as a double, which the reader rounds back to the
// same float (checked; the float's exact double otherwise); "inf" for an infinite far plane.
Json jsonFloat(float f) {
    if (std::isinf(f)) return Json(f > 0 ? "inf" : "-inf");
    char buf[64];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, f);
    double d = double(f);
    if (ec == std::errc()) {
        double shortest = 0;
        std::from_chars(buf, p, shortest);
        if (static_cast<float>(shortest) == f) d = shortest;
    }
    return jsonNumber(d);
}

// The same rules as the frame validation of layers/ (SubmitError::InvalidFov).
std::optional<std::string> checkFov(const layers::Fov& f) {
    const float lim = 1.5707963f;
    for (float a : {f.angleLeft, f.angleRight, f.angleUp, f.angleDown})
        if (!(std::abs(a) < lim)) return "angles must lie inside (-pi/2, pi/2) radians";
    if (!(f.angleLeft < f.angleRight)) return "angle_left must be less than angle_right";
    if (!(f.angleDown < f.angleUp)) return "angle_down must be less than angle_up";
    return std::nullopt;
}

}  // namespace

namespace seqfile {

std::optional<std::string> checkInfo(const SequenceInfo& info) {
    if (info.width < 1 || info.height < 1 || info.width > kMaxSize || info.height > kMaxSize)
        return "width and height must be in [1, " + std::to_string(kMaxSize) + "]";
    if (info.frameCount < 1 || info.frameCount > kMaxFrames)
        return "frame_count must be in [1, " + std::to_string(kMaxFrames) + "]";
    if (!(std::isfinite(info.fps) && info.fps > 0)) return "fps must be a positive finite number";
    for (int e = 0; e < 2; ++e)
        if (auto m = checkFov(info.fov[e])) return std::string("fov.") + (e ? "right" : "left") + ": " + *m;
    if (info.depth) {
        const SequenceDepth& d = *info.depth;
        if (!(std::isfinite(d.nearZ) && d.nearZ > 0)) return "depth.near must be a positive finite number";
        if (!(d.farZ > d.nearZ) || std::isnan(d.farZ)) return "depth.far must be greater than depth.near (or \"inf\")";
    }
    return std::nullopt;
}

Result<std::string> readText(const std::string& path, SequenceError missingCode) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) return seqError(missingCode, "missing file " + path);
    std::ifstream in(path, std::ios::binary);
    if (!in) return seqError(missingCode, "cannot open " + path);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

}  // namespace seqfile

Result<SequenceInfo> parseSequenceInfo(std::string_view json, const std::string& name) {
    auto root = parseJson(json, name);
    if (!root) return root.error();
    if (!root->is_object())
        return seqError(SequenceError::BadField, name + ": the top level must be an object {...}");
    Error err;
    Fields top(*root, "", name, &err);
    if (!top.onlyKnown({"format", "version", "description", "width", "height", "frame_count", "fps", "color", "fov",
                        "depth", "motion"}))
        return err;
    SequenceInfo info;
    std::string format;
    if (!top.string("format", format, false)) return err;
    if (top.find("format") && format != "wrsfov-sequence")
        return seqError(SequenceError::BadField,
                        name + ": \"format\" is \"" + format + "\", expected \"wrsfov-sequence\"");
    double version = 1;
    if (!top.number("version", version, false)) return err;
    if (version != 1)
        return seqError(SequenceError::BadField,
                        name + ": \"version\" " + numberText(version) + " is not supported (1)");
    if (!top.string("description", info.description, false)) return err;
    if (!top.integer("width", 1, kMaxSize, info.width) || !top.integer("height", 1, kMaxSize, info.height) ||
        !top.integer("frame_count", 1, kMaxFrames, info.frameCount) || !top.number("fps", info.fps))
        return err;
    if (!(info.fps > 0)) return seqError(SequenceError::BadField, name + ": \"fps\" must be positive");
    std::string color;
    if (!top.string("color", color)) return err;
    if (color == "png") info.color = ColorFile::Png;
    else if (color == "exr") info.color = ColorFile::Exr;
    else
        return seqError(SequenceError::BadField,
                        name + ": \"color\" is \"" + color + "\", expected \"png\" or \"exr\"");

    auto fov = top.child("fov", true);
    if (!fov) return err;
    if (!fov->onlyKnown({"left", "right"})) return err;
    for (int e = 0; e < 2; ++e) {
        auto eye = fov->child(e == 0 ? "left" : "right", true);
        if (!eye) return err;
        layers::Fov& f = info.fov[e];
        if (!eye->onlyKnown({"angle_left", "angle_right", "angle_up", "angle_down"}) ||
            !eye->floatValue("angle_left", f.angleLeft) || !eye->floatValue("angle_right", f.angleRight) ||
            !eye->floatValue("angle_up", f.angleUp) || !eye->floatValue("angle_down", f.angleDown))
            return err;
        if (auto m = checkFov(f))
            return seqError(SequenceError::BadField, name + ": fov." + (e ? "right" : "left") + ": " + *m);
    }
    if (auto d = top.child("depth", false)) {
        SequenceDepth depth;
        if (!d->onlyKnown({"near", "far", "reversed"}) || !d->floatValue("near", depth.nearZ) ||
            !d->floatValue("far", depth.farZ, true) || !d->boolean("reversed", depth.reversedZ))
            return err;
        if (!(depth.nearZ > 0)) return seqError(SequenceError::BadField, name + ": depth.near must be > 0");
        if (!(depth.farZ > depth.nearZ))
            return seqError(SequenceError::BadField, name + ": depth.far must be greater than depth.near");
        info.depth = depth;
    } else if (!err.message.empty()) {
        return err;
    }
    if (auto m = top.child("motion", false)) {
        std::string units;
        if (!m->onlyKnown({"units"}) || !m->string("units", units)) return err;
        if (units == "pixels") info.motion = MotionUnits::Pixels;
        else if (units == "ndc") info.motion = MotionUnits::Ndc;
        else if (units == "uv") info.motion = MotionUnits::Uv;
        else
            return seqError(SequenceError::BadField, name + ": motion.units is \"" + units +
                                                         "\", expected \"pixels\", \"ndc\" or \"uv\"");
    } else if (!err.message.empty()) {
        return err;
    }
    return info;
}

Result<SequenceInfo> readSequenceInfo(const std::string& dir) {
    const std::string path = dir + "/sequence.json";
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        return seqError(SequenceError::MissingFile, "sequence directory " + dir + " does not exist");
    auto text = readText(path, SequenceError::MissingFile);
    if (!text) return text.error();
    return parseSequenceInfo(*text, path);
}

std::string formatSequenceInfo(const SequenceInfo& info) {
    Json j;
    j["format"] = "wrsfov-sequence";
    j["version"] = 1;
    if (!info.description.empty()) j["description"] = info.description;
    j["width"] = info.width;
    j["height"] = info.height;
    j["frame_count"] = info.frameCount;
    j["fps"] = jsonNumber(info.fps);
    j["color"] = std::string(toString(info.color));
    for (int e = 0; e < 2; ++e) {
        const layers::Fov& f = info.fov[e];
        Json& eye = j["fov"][e ? "right" : "left"];
        eye["angle_left"] = jsonFloat(f.angleLeft);
        eye["angle_right"] = jsonFloat(f.angleRight);
        eye["angle_up"] = jsonFloat(f.angleUp);
        eye["angle_down"] = jsonFloat(f.angleDown);
    }
    if (info.depth) {
        Json& d = j["depth"];
        d["near"] = jsonFloat(info.depth->nearZ);
        d["far"] = jsonFloat(info.depth->farZ);
        d["reversed"] = info.depth->reversedZ;
    }
    if (info.motion) j["motion"]["units"] = std::string(toString(*info.motion));
    // Pretty printed; bytes of the description that are not UTF-8 become U+FFFD.
    return j.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

}  // namespace wrsfov::eval
