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

#include <Imath/ImathBox.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfTestFile.h>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gaze/gaze_file.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {

namespace fs = std::filesystem;

std::string_view toString(ColorFile c) { return c == ColorFile::Png ? "png" : "exr"; }

std::string_view toString(MotionUnits u) {
    switch (u) {
    case MotionUnits::Pixels: return "pixels";
    case MotionUnits::Ndc: return "ndc";
    case MotionUnits::Uv: return "uv";
    }
    return "?";
}

std::string frameFileName(uint32_t frame, int eye, std::string_view kind) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%06u_%c_", frame, eye == 0 ? 'L' : 'R');
    return std::string(buf) + std::string(kind);
}

namespace {

constexpr uint32_t kMaxFrames = 999999;  // six digits in the file names
constexpr uint32_t kMaxSize = 16384;

Error seqError(SequenceError code, std::string message) { return Error{int(code), std::move(message)}; }

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

// ---------------------------------------------------------------------------------------------
// EXR through OpenEXR: the header (channel names, data window) and the pixels, decoded as float
// whatever the channels' type (HALF, FLOAT or UINT). OpenEXR throws on truncated or corrupt files;
// every exception becomes BadImage naming the file. No reason to keep OpenCV's EXR codec (used
// before; it needs OPENCV_IO_ENABLE_OPENEXR and does not report channel names): it decodes through
// the same libOpenEXR and is no faster, cv::imread 6.6-6.8 ms against Imf::InputFile 6.7-6.8 ms for
// a 320x288 float RGB ZIP file, 155-157 ms against 154 ms at 1920x1080 (-O2, two shared cores).
// ---------------------------------------------------------------------------------------------

class ExrFile {
public:
    static Result<ExrFile> open(const std::string& path) {
        std::error_code ec;
        if (!fs::is_regular_file(path, ec)) return seqError(SequenceError::MissingFile, "missing file " + path);
        const std::string bad = path + " is not a readable EXR file: ";
        ExrFile f;
        f.path_ = path;
        try {
            bool tiled = false, deep = false, multiPart = false;
            if (!Imf::isOpenExrFile(path.c_str(), tiled, deep, multiPart))
                return seqError(SequenceError::BadImage, bad + "no EXR signature (empty, truncated or another format)");
            if (deep || multiPart)
                return seqError(SequenceError::BadImage, bad + "multi-part and deep EXR files are not supported");
            f.file_ = std::make_unique<Imf::InputFile>(path.c_str());
            const Imf::Header& h = f.file_->header();
            f.window_ = h.dataWindow();
            f.width_ = int64_t(f.window_.max.x) - f.window_.min.x + 1;
            f.height_ = int64_t(f.window_.max.y) - f.window_.min.y + 1;
            for (auto it = h.channels().begin(); it != h.channels().end(); ++it) {
                f.channels_.emplace_back(it.name());
                if (it.channel().xSampling != 1 || it.channel().ySampling != 1) f.subsampled_ = it.name();
            }
        } catch (const std::exception& e) {
            return seqError(SequenceError::BadImage, bad + e.what());
        }
        return f;
    }

    const std::vector<std::string>& channels() const { return channels_; }  // sorted by name
    int64_t width() const { return width_; }
    int64_t height() const { return height_; }
    const std::string& subsampled() const { return subsampled_; }  // a subsampled channel, if any

    // The channels `names` as float, interleaved, width x height; a channel the file lacks reads 0.
    Result<std::vector<float>> read(const std::vector<std::string>& names) {
        const std::size_t n = names.size(), w = std::size_t(width_), h = std::size_t(height_);
        std::vector<float> px(w * h * n);
        try {
            Imf::FrameBuffer fb;
            for (std::size_t c = 0; c < n; ++c)
                fb.insert(names[c], Imf::Slice::Make(Imf::FLOAT, px.data() + c, window_, sizeof(float) * n,
                                                     sizeof(float) * n * w));
            file_->setFrameBuffer(fb);
            file_->readPixels(window_.min.y, window_.max.y);
        } catch (const std::exception& e) {
            return seqError(SequenceError::BadImage, "cannot decode " + path_ + ": " + e.what());
        }
        return px;
    }

private:
    std::string path_;
    std::unique_ptr<Imf::InputFile> file_;
    Imath::Box2i window_;
    int64_t width_ = 0, height_ = 0;
    std::vector<std::string> channels_;
    std::string subsampled_;
};

// Writes float channels `names` from interleaved `px` (width x height x names.size()), ZIP.
Status writeExr(const std::string& path, int width, int height, const std::vector<std::string>& names,
                const float* px) {
    try {
        const std::size_t n = names.size();
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < n; ++c) {
            header.channels().insert(names[c], Imf::Channel(Imf::FLOAT));
            fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(px + c)),
                                           sizeof(float) * n, sizeof(float) * n * std::size_t(width)));
        }
        Imf::OutputFile out(path.c_str(), header);
        out.setFrameBuffer(fb);
        out.writePixels(height);
    } catch (const std::exception& e) {
        return seqError(SequenceError::WriteFailed, "cannot write " + path + ": " + e.what());
    }
    return {};
}

std::string channelList(const std::vector<std::string>& c) {
    std::string s;
    for (const auto& n : c) s += (s.empty() ? "" : ", ") + n;
    return std::to_string(c.size()) + " channel" + (c.size() == 1 ? "" : "s") + (c.empty() ? "" : " (" + s + ")");
}

bool sameSet(std::vector<std::string> a, std::vector<std::string> b) {
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    return a == b;
}

Status checkSize(const std::string& path, int64_t w, int64_t h, const SequenceInfo& info) {
    if (w != int64_t(info.width) || h != int64_t(info.height))
        return seqError(SequenceError::ImageSize, path + " is " + std::to_string(w) + "x" + std::to_string(h) +
                                                      ", sequence.json says " + std::to_string(info.width) + "x" +
                                                      std::to_string(info.height));
    return {};
}

// Opens an EXR whose channel set must be one of `allowed` (or contain `alsoWith`, when given) and
// whose size is the json's.
Result<ExrFile> openExr(const std::string& path, const SequenceInfo& info,
                        std::initializer_list<std::vector<std::string>> allowed, const std::string& what,
                        const std::string& alsoWith = {}) {
    auto f = ExrFile::open(path);
    if (!f) return f;
    bool ok = !alsoWith.empty() && std::count(f->channels().begin(), f->channels().end(), alsoWith) == 1;
    for (const auto& set : allowed) ok = ok || sameSet(f->channels(), set);
    if (!ok) return seqError(SequenceError::ImageChannels, path + " has " + channelList(f->channels()) + "; " + what);
    if (!f->subsampled().empty())
        return seqError(SequenceError::ImageChannels,
                        path + ": channel " + f->subsampled() + " is subsampled; every channel must be full size");
    if (Status s = checkSize(path, f->width(), f->height(), info); !s) return s.error();
    return f;
}

float clampHalf(float v) { return std::isfinite(v) ? std::clamp(v, -65504.0f, 65504.0f) : v; }

Result<HostImage> readColor(const std::string& dir, uint32_t i, int e, const SequenceInfo& info) {
    if (info.color == ColorFile::Png) {
        const std::string path = dir + "/" + frameFileName(i, e, "color.png");
        cv::Mat m;
        try {
            m = cv::imread(path, cv::IMREAD_UNCHANGED);
        } catch (const cv::Exception& ex) {
            return seqError(SequenceError::BadImage, "cannot decode " + path + ": " + ex.what());
        }
        if (m.empty())
            return seqError(SequenceError::BadImage, "cannot decode " + path + " (truncated or not a PNG file)");
        if (m.depth() != CV_8U)
            return seqError(SequenceError::ImageChannels,
                            path + " is not 8 bits per channel; colour PNGs are 8-bit sRGB (or use color.exr)");
        if (m.channels() != 3 && m.channels() != 4)
            return seqError(SequenceError::ImageChannels, path + " has " + std::to_string(m.channels()) + " channel" +
                                                              (m.channels() == 1 ? "" : "s") +
                                                              "; colour needs RGB or RGBA");
        if (Status s = checkSize(path, m.cols, m.rows, info); !s) return s.error();
        cv::Mat rgba;
        cv::cvtColor(m, rgba, m.channels() == 3 ? cv::COLOR_BGR2RGBA : cv::COLOR_BGRA2RGBA);
        HostImage img = HostImage::make(layers::Format::RGBA8_SRGB, info.width, info.height);
        for (int y = 0; y < rgba.rows; ++y)
            std::memcpy(img.data.data() + std::size_t(y) * info.width * 4, rgba.ptr(y), std::size_t(info.width) * 4);
        return img;
    }
    const std::string path = dir + "/" + frameFileName(i, e, "color.exr");
    auto f = openExr(path, info, {{"R", "G", "B"}, {"R", "G", "B", "A"}}, "colour needs R, G, B (and optionally A)");
    if (!f) return f.error();
    auto px = f->read({"R", "G", "B"});
    if (!px) return px.error();
    HostImage img = HostImage::make(layers::Format::RGBA16F, info.width, info.height);
    const float* p = px->data();
    for (uint32_t y = 0; y < info.height; ++y)
        for (uint32_t x = 0; x < info.width; ++x, p += 3)
            img.store(x, y, glm::vec4(clampHalf(p[0]), clampHalf(p[1]), clampHalf(p[2]), 1.0f));
    return img;
}

Result<HostImage> readDepth(const std::string& dir, uint32_t i, int e, const SequenceInfo& info) {
    const std::string path = dir + "/" + frameFileName(i, e, "depth.exr");
    auto f = openExr(path, info, {{"Y"}, {"R"}, {"G"}, {"B"}},
                     "depth needs exactly one channel, named Y (what OpenCV writes) or R, holding depth as "
                     "submitted, or a channel named Z holding planar view depth (OpenEXR's name)",
                     "Z");
    if (!f) return f.error();
    const auto& ch = f->channels();
    const bool planar = std::find(ch.begin(), ch.end(), "Z") != ch.end();
    auto px = f->read({planar ? std::string("Z") : ch[0]});
    if (!px) return px.error();
    // Z is the distance along the view axis in the json's units: converted to the submitted [0, 1]
    // convention with its near, far and reversed (wrs_depth_from_linear; outside [near, far]: unknown).
    if (planar)
        for (float& v : *px) v = gpu::wrs_depth_from_linear(v, info.depth->nearZ, info.depth->farZ, info.depth->reversedZ);
    HostImage img = HostImage::make(layers::Format::R32F, info.width, info.height);
    std::memcpy(img.data.data(), px->data(), px->size() * sizeof(float));
    return img;
}

Result<HostImage> readMotion(const std::string& dir, uint32_t i, int e, const SequenceInfo& info) {
    const std::string path = dir + "/" + frameFileName(i, e, "motion.exr");
    auto f = openExr(path, info, {{"R", "G"}, {"R", "G", "B"}},
                     "motion needs R, G (dx, dy) and optionally B (z_prev - z_cur)");
    if (!f) return f.error();
    auto px = f->read({"R", "G", "B"});  // a missing B reads 0
    if (!px) return px.error();
    float sx = 1, sy = 1;
    switch (*info.motion) {
    case MotionUnits::Pixels: break;
    case MotionUnits::Ndc: sx = 0.5f * float(info.width), sy = 0.5f * float(info.height); break;
    case MotionUnits::Uv: sx = float(info.width), sy = float(info.height); break;
    }
    HostImage img = HostImage::make(layers::Format::RGBA16F, info.width, info.height);
    const float* p = px->data();
    for (uint32_t y = 0; y < info.height; ++y)
        for (uint32_t x = 0; x < info.width; ++x, p += 3)
            img.store(x, y, glm::vec4(clampHalf(p[0] * sx), clampHalf(p[1] * sy), clampHalf(p[2]), 0.0f));
    return img;
}

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

Result<std::unique_ptr<SequenceReader>> SequenceReader::open(const std::string& dir) {
    auto info = readSequenceInfo(dir);
    if (!info) return info.error();
    std::unique_ptr<SequenceReader> r(new SequenceReader());
    r->dir_ = dir;
    r->info_ = *info;
    const SequenceInfo& si = r->info_;

    // Which frame files are there (one directory listing), then what the json implies.
    std::set<std::string> files;
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) files.insert(entry.path().filename().string());
    if (ec) return seqError(SequenceError::MissingFile, "cannot list " + dir + ": " + ec.message());
    const std::string colorKind = si.color == ColorFile::Png ? "color.png" : "color.exr";
    const std::string otherKind = si.color == ColorFile::Png ? "color.exr" : "color.png";
    for (uint32_t i = 0; i < si.frameCount; ++i)
        for (int e = 0; e < 2; ++e) {
            std::vector<std::string> kinds{colorKind};
            if (si.depth) kinds.push_back("depth.exr");
            if (si.motion) kinds.push_back("motion.exr");
            for (const auto& k : kinds) {
                const std::string n = frameFileName(i, e, k);
                if (files.count(n)) continue;
                std::string hint;
                if (k == colorKind && files.count(frameFileName(i, e, otherKind)))
                    hint = " (there is " + frameFileName(i, e, otherKind) + ": sequence.json says \"color\": \"" +
                           std::string(toString(si.color)) + "\")";
                return seqError(SequenceError::MissingFile, "missing file " + dir + "/" + n + hint + " (frame " +
                                                                std::to_string(i) + " of frame_count " +
                                                                std::to_string(si.frameCount) + ")");
            }
        }
    for (const auto& n : files) {
        unsigned idx = 0;
        char eye = 0;
        int used = 0;
        if (n.size() < 10 || std::sscanf(n.c_str(), "%6u_%c_%n", &idx, &eye, &used) != 2 || used != 9) continue;
        if ((eye != 'L' && eye != 'R') || idx < si.frameCount) continue;
        const std::string kind = n.substr(9);
        if (kind != "color.png" && kind != "color.exr" && kind != "depth.exr" && kind != "motion.exr") continue;
        return seqError(SequenceError::FrameCount, dir + "/sequence.json says frame_count " +
                                                       std::to_string(si.frameCount) + " but " + n +
                                                       " exists (frame " + std::to_string(idx) +
                                                       "): fix frame_count or remove the extra frames");
    }

    r->gaze_.assign(si.frameCount, {});
    const std::string gazePath = dir + "/gaze.csv";
    if (fs::exists(gazePath, ec)) {
        auto text = readText(gazePath, SequenceError::MissingFile);
        if (!text) return text.error();
        auto g = parseSequenceGaze(*text, si.frameCount, gazePath);
        if (!g) return g.error();
        r->hasGaze_ = true;
        r->gaze_ = std::move(g->frames);
        r->gazeNotes_ = std::move(g->notes);
    }
    return r;
}

Result<SequenceFrame> SequenceReader::frame(uint32_t index) const {
    if (index >= info_.frameCount)
        return seqError(SequenceError::FrameCount, "frame " + std::to_string(index) + " is beyond " + dir_ +
                                                       " (frame_count " + std::to_string(info_.frameCount) + ")");
    SequenceFrame f;
    f.index = index;
    f.time_s = index / info_.fps;
    for (int e = 0; e < 2; ++e) {
        EyeSubmission& eye = f.eyes[e];
        auto c = readColor(dir_, index, e, info_);
        if (!c) return c.error();
        eye.color = std::move(*c);
        if (info_.depth) {
            auto d = readDepth(dir_, index, e, info_);
            if (!d) return d.error();
            eye.depth = std::move(*d);
        }
        if (info_.motion) {
            auto m = readMotion(dir_, index, e, info_);
            if (!m) return m.error();
            eye.motion = std::move(*m);
        }
        eye.fov = info_.fov[e];
        eye.gaze = gaze_[index][e];
    }
    return f;
}

HostStereoApp::Options SequenceReader::appOptions() const {
    HostStereoApp::Options a;
    a.width = info_.width;
    a.height = info_.height;
    a.color = info_.color == ColorFile::Png ? layers::Format::RGBA8_SRGB : layers::Format::RGBA16F;
    if (info_.depth) {
        a.depth = layers::Format::R32F;
        a.nearZ = info_.depth->nearZ;
        a.farZ = info_.depth->farZ;
        a.reversedZ = info_.depth->reversedZ;
    }
    if (info_.motion) a.motion = layers::Format::RGBA16F;
    return a;
}

// ---------------------------------------------------------------------------------------------
// Writing
// ---------------------------------------------------------------------------------------------

namespace {

Status writePng(const std::string& path, const cv::Mat& m) {
    bool ok = false;
    std::string why;
    try {
        ok = cv::imwrite(path, m);
    } catch (const cv::Exception& e) {
        why = std::string(": ") + e.what();
    }
    if (!ok) return seqError(SequenceError::WriteFailed, "cannot write " + path + why);
    return {};
}

Status checkImage(const HostImage& img, const SequenceInfo& info, const std::string& what,
                  std::initializer_list<layers::Format> formats) {
    if (img.width != info.width || img.height != info.height)
        return seqError(SequenceError::BadInput, what + " is " + std::to_string(img.width) + "x" +
                                                     std::to_string(img.height) + ", the sequence is " +
                                                     std::to_string(info.width) + "x" + std::to_string(info.height));
    if (std::find(formats.begin(), formats.end(), img.format) == formats.end())
        return seqError(SequenceError::BadInput, what + " has format " + std::string(layers::toString(img.format)) +
                                                     ", which cannot be written here");
    if (img.data.size() != std::size_t(img.width) * img.height * img.texelBytes())
        return seqError(SequenceError::BadInput, what + " has the wrong number of bytes");
    return {};
}

Status writeSequenceJson(const std::string& dir, const SequenceInfo& info) {
    const std::string path = dir + "/sequence.json";
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    const std::string text = formatSequenceInfo(info);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    if (!out) return seqError(SequenceError::WriteFailed, "cannot write " + path);
    return {};
}

}  // namespace

Result<std::unique_ptr<SequenceWriter>> SequenceWriter::create(const std::string& dir, const SequenceInfo& info) {
    if (auto m = checkInfo(info)) return seqError(SequenceError::BadInput, "sequence for " + dir + ": " + *m);
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) return seqError(SequenceError::WriteFailed, "cannot create " + dir + ": " + ec.message());
    if (Status s = writeSequenceJson(dir, info); !s) return s.error();
    std::unique_ptr<SequenceWriter> w(new SequenceWriter());
    w->dir_ = dir;
    w->info_ = info;
    return w;
}

Status SequenceWriter::writeFrame(uint32_t index, const std::array<EyeSubmission, 2>& eyes) {
    using layers::Format;
    if (index != written_ || index >= info_.frameCount)
        return seqError(SequenceError::BadInput, "sequence " + dir_ + ": frame " + std::to_string(index) +
                                                     " written out of order or beyond frame_count " +
                                                     std::to_string(info_.frameCount));
    const int w = int(info_.width), h = int(info_.height);
    for (int e = 0; e < 2; ++e) {
        const EyeSubmission& eye = eyes[e];
        const std::string tag = "frame " + std::to_string(index) + (e ? " right" : " left") + " eye: ";
        if (info_.color == ColorFile::Png) {
            if (Status s = checkImage(eye.color, info_, tag + "colour", {Format::RGBA8_SRGB}); !s) return s;
            cv::Mat rgba(h, w, CV_8UC4, const_cast<std::byte*>(eye.color.data.data()));
            std::vector<cv::Mat> ch;
            cv::split(rgba, ch);
            const bool opaque = cv::countNonZero(ch[3] != 255) == 0;
            cv::Mat bgr;
            cv::cvtColor(rgba, bgr, opaque ? cv::COLOR_RGBA2BGR : cv::COLOR_RGBA2BGRA);
            if (Status s = writePng(dir_ + "/" + frameFileName(index, e, "color.png"), bgr); !s) return s;
        } else {
            if (Status s =
                    checkImage(eye.color, info_, tag + "colour", {Format::RGBA8, Format::RGBA8_SRGB, Format::RGBA16F});
                !s)
                return s;
            std::vector<float> rgb(std::size_t(w) * std::size_t(h) * 3);
            float* p = rgb.data();
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x, p += 3) {
                    glm::vec4 c = eye.color.fetch(uint32_t(x), uint32_t(y));
                    if (eye.color.format == Format::RGBA8_SRGB)
                        c = glm::vec4(gpu::wrs_srgb_to_linear3(glm::vec3(c)), c.w);
                    p[0] = c.x, p[1] = c.y, p[2] = c.z;
                }
            const std::string path = dir_ + "/" + frameFileName(index, e, "color.exr");
            if (Status s = writeExr(path, w, h, {"R", "G", "B"}, rgb.data()); !s) return s;
        }
        if (info_.depth.has_value() != eye.depth.has_value())
            return seqError(SequenceError::BadInput, tag + (info_.depth ? "no depth, but the sequence declares depth"
                                                                        : "depth, but the sequence declares none"));
        if (eye.depth) {
            if (Status s = checkImage(*eye.depth, info_, tag + "depth", {Format::R32F, Format::D32F}); !s) return s;
            // One channel named Y, as OpenCV and most tools write a single-channel image.
            const auto* depth = reinterpret_cast<const float*>(eye.depth->data.data());
            const std::string path = dir_ + "/" + frameFileName(index, e, "depth.exr");
            if (Status s = writeExr(path, w, h, {"Y"}, depth); !s) return s;
        }
        if (info_.motion.has_value() != eye.motion.has_value())
            return seqError(SequenceError::BadInput, tag + (info_.motion ? "no motion, but the sequence declares motion"
                                                                         : "motion, but the sequence declares none"));
        if (eye.motion) {
            if (Status s = checkImage(*eye.motion, info_, tag + "motion", {Format::RG16F, Format::RGBA16F}); !s)
                return s;
            float sx = 1, sy = 1;
            if (*info_.motion == MotionUnits::Ndc) sx = 2.0f / float(w), sy = 2.0f / float(h);
            if (*info_.motion == MotionUnits::Uv) sx = 1.0f / float(w), sy = 1.0f / float(h);
            // Always R, G, B (the files stay alike): B = z_prev - z_cur, 0 for RG16F.
            std::vector<float> rgb(std::size_t(w) * std::size_t(h) * 3);
            float* p = rgb.data();
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x, p += 3) {
                    glm::vec4 v = eye.motion->fetch(uint32_t(x), uint32_t(y));
                    p[0] = v.x * sx, p[1] = v.y * sy, p[2] = eye.motion->format == Format::RGBA16F ? v.z : 0.0f;
                }
            const std::string path = dir_ + "/" + frameFileName(index, e, "motion.exr");
            if (Status s = writeExr(path, w, h, {"R", "G", "B"}, rgb.data()); !s) return s;
        }
    }
    gaze_.push_back({eyes[0].gaze, eyes[1].gaze});
    ++written_;
    return {};
}

Status SequenceWriter::close() {
    if (written_ == 0) return seqError(SequenceError::FrameCount, "sequence " + dir_ + ": no frame was written");
    if (written_ != info_.frameCount) {
        info_.frameCount = written_;
        if (Status s = writeSequenceJson(dir_, info_); !s) return s;
    }
    return finish();
}

Status SequenceWriter::finish() {
    if (written_ != info_.frameCount)
        return seqError(SequenceError::FrameCount, "sequence " + dir_ + ": " + std::to_string(written_) +
                                                       " frames written, frame_count is " +
                                                       std::to_string(info_.frameCount));
    std::vector<gaze::GazeSample> samples(gaze_.size());
    std::vector<long long> frames(gaze_.size());
    for (std::size_t i = 0; i < gaze_.size(); ++i) {
        samples[i].t_s = double(i) / info_.fps;
        for (int e = 0; e < 2; ++e) samples[i].eye[e] = {gaze_[i][e].dir, gaze_[i][e].valid, gaze_[i][e].confidence};
        frames[i] = static_cast<long long>(i);
    }
    auto s = gaze::write_gaze_csv(dir_ + "/gaze.csv", samples, false, frames);
    if (!s) return seqError(SequenceError::WriteFailed, s.error().message);
    return {};
}

}  // namespace wrsfov::eval
