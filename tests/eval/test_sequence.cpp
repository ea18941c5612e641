// Sequence directories on the CPU: sequence.json round trip and its errors, frame files written and
// read back bit for bit, motion units converted to pixels, gaze.csv rows and their fallbacks, and a
// clear error for every kind of malformed input. EXR files made "by another tool" come from OpenCV
// (as most tools name channels) or from OpenEXR directly (any channel layout, pixel type, window).
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfOutputPart.h>
#include <OpenEXR/ImfPartType.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "compositor/host_app.h"
#include "eval/sequence.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// A fresh empty directory per test, removed afterwards.
class TempDir {
public:
    explicit TempDir(const std::string& name) {
        path_ = fs::path(::testing::TempDir()) / ("wrsfov_seq_" + name + "_" + std::to_string(::getpid()));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() { fs::remove_all(path_); }
    std::string str() const { return path_.string(); }
    std::string file(const std::string& n) const { return (path_ / n).string(); }

private:
    fs::path path_;
};

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}

void replaceInFile(const std::string& path, const std::string& from, const std::string& to) {
    std::string t = readText(path);
    auto p = t.find(from);
    ASSERT_NE(p, std::string::npos) << from;
    t.replace(p, from.size(), to);
    writeText(path, t);
}

// An EXR written with OpenEXR: `channels` (name, pixel type in the file), value(c, x, y) of channel c
// at pixel (x, y) of the data window, which starts at `origin`; `sampling` for every channel.
struct ExrChannel {
    std::string name;
    Imf::PixelType type = Imf::FLOAT;
};
void writeTestExr(const std::string& path, int w, int h, const std::vector<ExrChannel>& channels,
                  const std::function<float(int, int, int)>& value, Imath::V2i origin = {0, 0}, int sampling = 1) {
    const Imath::Box2i window(origin, origin + Imath::V2i(w - 1, h - 1));
    Imf::Header header(window, window);
    header.compression() = Imf::ZIP_COMPRESSION;
    const int sw = w / sampling, sh = h / sampling;
    // One plane per channel in the file's type (OpenEXR does not convert when writing).
    std::vector<std::vector<char>> planes(channels.size());
    Imf::FrameBuffer fb;
    for (std::size_t c = 0; c < channels.size(); ++c) {
        const Imf::PixelType type = channels[c].type;
        const std::size_t size = type == Imf::HALF ? 2 : 4;
        planes[c].resize(size * std::size_t(sw) * std::size_t(sh));
        for (int y = 0; y < sh; ++y)
            for (int x = 0; x < sw; ++x) {
                const float v = value(int(c), x, y);
                char* p = planes[c].data() + size * (std::size_t(y) * std::size_t(sw) + std::size_t(x));
                // Converted only for a UINT channel: a float channel may hold NaN or values beyond uint32.
                const uint32_t u = type == Imf::UINT ? uint32_t(v) : 0u;
                const half hv(v);
                std::memcpy(p, type == Imf::FLOAT ? static_cast<const void*>(&v)
                               : type == Imf::UINT ? static_cast<const void*>(&u)
                                                   : static_cast<const void*>(&hv),
                            size);
            }
        header.channels().insert(channels[c].name, Imf::Channel(type, sampling, sampling));
        fb.insert(channels[c].name, Imf::Slice::Make(type, planes[c].data(), window, size, size * std::size_t(sw),
                                                     sampling, sampling));
    }
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
}

// Channel names of an EXR file and one channel's values (row by row).
std::vector<std::string> exrChannels(const std::string& path) {
    Imf::InputFile in(path.c_str());
    std::vector<std::string> names;
    for (auto it = in.header().channels().begin(); it != in.header().channels().end(); ++it) names.push_back(it.name());
    return names;
}
std::vector<float> exrChannel(const std::string& path, const std::string& name) {
    Imf::InputFile in(path.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    const std::size_t w = std::size_t(dw.max.x - dw.min.x + 1), h = std::size_t(dw.max.y - dw.min.y + 1);
    std::vector<float> v(w * h);
    Imf::FrameBuffer fb;
    fb.insert(name, Imf::Slice::Make(Imf::FLOAT, v.data(), dw, sizeof(float), sizeof(float) * w));
    in.setFrameBuffer(fb);
    in.readPixels(dw.min.y, dw.max.y);
    return v;
}

SequenceInfo smallInfo(uint32_t w, uint32_t h, uint32_t frames) {
    SequenceInfo info;
    info.width = w;
    info.height = h;
    info.frameCount = frames;
    info.fps = 90.0;
    info.fov = {hmdFov(0), hmdFov(1)};
    info.depth = SequenceDepth{0.05f, 100.0f, false};
    info.motion = MotionUnits::Pixels;
    return info;
}

// Random frames with the formats an application submits (the atrium's), and special values.
std::array<EyeSubmission, 2> randomFrame(std::mt19937& rng, const SequenceInfo& info, uint32_t index) {
    std::uniform_int_distribution<int> byte(0, 255);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), mv(-40.0f, 40.0f);
    std::array<EyeSubmission, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        EyeSubmission& s = eyes[e];
        s.color = HostImage::make(info.color == ColorFile::Png ? layers::Format::RGBA8_SRGB : layers::Format::RGBA16F,
                                  info.width, info.height);
        for (uint32_t y = 0; y < info.height; ++y)
            for (uint32_t x = 0; x < info.width; ++x) {
                if (info.color == ColorFile::Png) {
                    std::byte* p = s.color.data.data() + (std::size_t(y) * info.width + x) * 4;
                    for (int c = 0; c < 3; ++c) p[c] = std::byte(byte(rng));
                    p[3] = std::byte(255);
                } else {
                    s.color.store(x, y, glm::vec4(u(rng) * 4.0f, u(rng), u(rng) * 0.01f, 1.0f));
                }
            }
        if (info.depth) {
            s.depth = HostImage::make(layers::Format::R32F, info.width, info.height);
            for (uint32_t y = 0; y < info.height; ++y)
                for (uint32_t x = 0; x < info.width; ++x) s.depth->store(x, y, glm::vec4(u(rng)));
            s.depth->store(0, 0, glm::vec4(0.0f));
            s.depth->store(1, 0, glm::vec4(1.0f));
            s.depth->store(2, 0, glm::vec4(1e-30f));
        }
        if (info.motion) {
            s.motion = HostImage::make(layers::Format::RGBA16F, info.width, info.height);
            for (uint32_t y = 0; y < info.height; ++y)
                for (uint32_t x = 0; x < info.width; ++x)
                    s.motion->store(x, y, glm::vec4(mv(rng), mv(rng), mv(rng) * 0.01f, 0.0f));
        }
        s.fov = info.fov[e];
        s.gaze = {glm::normalize(glm::vec3(0.1f * float(index), -0.05f, -1.0f)), true, 1.0f};
    }
    return eyes;
}

std::vector<std::array<EyeSubmission, 2>> writeRandom(const std::string& dir, const SequenceInfo& info,
                                                      uint32_t seed = 7) {
    std::mt19937 rng(seed);
    auto w = SequenceWriter::create(dir, info);
    EXPECT_TRUE(w.ok()) << w.error().message;
    std::vector<std::array<EyeSubmission, 2>> frames;
    for (uint32_t i = 0; i < info.frameCount; ++i) {
        frames.push_back(randomFrame(rng, info, i));
        Status s = (*w)->writeFrame(i, frames.back());
        EXPECT_TRUE(s.ok()) << s.message();
    }
    Status s = (*w)->finish();
    EXPECT_TRUE(s.ok()) << s.message();
    return frames;
}

// Motion as read: the first three channels (the fourth is not part of the format).
void expectSameMotion(const HostImage& a, const HostImage& b) {
    ASSERT_EQ(a.width, b.width);
    for (uint32_t y = 0; y < a.height; ++y)
        for (uint32_t x = 0; x < a.width; ++x) {
            glm::vec4 p = a.fetch(x, y), q = b.fetch(x, y);
            ASSERT_EQ(p.x, q.x) << x << "," << y;
            ASSERT_EQ(p.y, q.y) << x << "," << y;
            ASSERT_EQ(p.z, q.z) << x << "," << y;
        }
}

// ---------------------------------------------------------------------------------------------
// sequence.json
// ---------------------------------------------------------------------------------------------

TEST(SequenceJson, RoundTripsEveryField) {
    SequenceInfo a = smallInfo(64, 48, 4);
    a.fps = 72.5;
    a.color = ColorFile::Exr;
    a.depth = SequenceDepth{0.0625f, INFINITY, true};
    a.motion = MotionUnits::Ndc;
    a.description = "quotes \" and \\ and\nnewline";
    const std::string text = formatSequenceInfo(a);
    auto b = parseSequenceInfo(text);
    ASSERT_TRUE(b.ok()) << b.error().message << "\n" << text;
    EXPECT_EQ(b->width, 64u);
    EXPECT_EQ(b->height, 48u);
    EXPECT_EQ(b->frameCount, 4u);
    EXPECT_EQ(b->fps, 72.5);
    EXPECT_EQ(b->color, ColorFile::Exr);
    for (int e = 0; e < 2; ++e) {  // bit for bit: floats are written in their shortest exact form
        EXPECT_EQ(b->fov[e].angleLeft, a.fov[e].angleLeft);
        EXPECT_EQ(b->fov[e].angleRight, a.fov[e].angleRight);
        EXPECT_EQ(b->fov[e].angleUp, a.fov[e].angleUp);
        EXPECT_EQ(b->fov[e].angleDown, a.fov[e].angleDown);
    }
    ASSERT_TRUE(b->depth.has_value());
    EXPECT_EQ(b->depth->nearZ, 0.0625f);
    EXPECT_TRUE(std::isinf(b->depth->farZ));
    EXPECT_TRUE(b->depth->reversedZ);
    ASSERT_TRUE(b->motion.has_value());
    EXPECT_EQ(*b->motion, MotionUnits::Ndc);
    EXPECT_EQ(b->description, a.description);
    EXPECT_EQ(formatSequenceInfo(*b), text);

    // Without depth and motion neither comes back.
    a.depth.reset();
    a.motion.reset();
    auto c = parseSequenceInfo(formatSequenceInfo(a));
    ASSERT_TRUE(c.ok()) << c.error().message;
    EXPECT_FALSE(c->depth.has_value());
    EXPECT_FALSE(c->motion.has_value());
}

TEST(SequenceJson, HandWrittenFileWithNullsAndComments) {
    const char* text = R"({
  "width": 32, "height": 16, "frame_count": 2, "fps": 30, "color": "png",
  "description": "caf\u00e9",
  "fov": {"left":  {"angle_left": -0.8, "angle_right": 0.7, "angle_up": 0.75, "angle_down": -0.8},
          "right": {"angle_left": -0.7, "angle_right": 0.8, "angle_up": 0.75, "angle_down": -0.8}},
  "depth": null,
  "motion": {"units": "uv"}
})";
    auto i = parseSequenceInfo(text);
    ASSERT_TRUE(i.ok()) << i.error().message;
    EXPECT_EQ(i->description, "caf\xC3\xA9");
    EXPECT_FALSE(i->depth.has_value());
    EXPECT_EQ(*i->motion, MotionUnits::Uv);
    EXPECT_EQ(i->fov[0].angleLeft, -0.8f);
    EXPECT_EQ(i->fps, 30.0);
}

struct JsonCase {
    const char* what;
    std::string from, to;  // replacement in a valid file
    SequenceError code;
    std::vector<std::string> mentions;
};

// Field errors name the file and the field's path; syntax errors the line and column.
TEST(SequenceJson, EveryBadFieldNamesTheField) {
    const std::string good = formatSequenceInfo(smallInfo(64, 48, 4));
    ASSERT_TRUE(parseSequenceInfo(good).ok());
    const std::vector<JsonCase> cases = {
        {"syntax",
         "\"width\": 64,",
         "\"width\": 64,,",
         SequenceError::BadJson,
         {"sequence.json:4:15:", "not valid JSON"}},
        {"truncated", "", "", SequenceError::BadJson, {"truncated"}},
        {"NaN",
         "\"fps\": 90",
         "\"fps\": NaN",
         SequenceError::BadField,
         {"sequence.json: \"fps\" is NaN, not a finite number"}},
        {"Infinity", "\"fps\": 90", "\"fps\": Infinity", SequenceError::BadField, {"\"fps\"", "not a finite"}},
        {"NaN angle",
         "\"angle_up\": 0.7853982",
         "\"angle_up\": NaN",
         SequenceError::BadField,
         {"fov.left.angle_up", "NaN"}},
        {"missing", "\"height\": 48,\n", "", SequenceError::BadField, {"missing field \"height\""}},
        {"wrong type", "\"width\": 64", "\"width\": \"64\"", SequenceError::BadField, {"\"width\" must be a number"}},
        {"not integer", "\"width\": 64", "\"width\": 64.5", SequenceError::BadField, {"\"width\" must be an integer"}},
        {"zero frames", "\"frame_count\": 4", "\"frame_count\": 0", SequenceError::BadField, {"frame_count"}},
        {"unknown",
         "\"fps\": 90",
         "\"fps\": 90, \"motion_units\": \"px\"",
         SequenceError::BadField,
         {"unknown field \"motion_units\""}},
        {"colour", "\"color\": \"png\"", "\"color\": \"jpg\"", SequenceError::BadField, {"\"color\" is \"jpg\""}},
        {"fov order",
         "\"angle_up\": 0.7853982",
         "\"angle_up\": -0.9",
         SequenceError::BadField,
         {"fov.left", "angle_down must be less than angle_up"}},
        {"fov range", "\"angle_up\": 0.7853982", "\"angle_up\": 1.6", SequenceError::BadField, {"fov.left"}},
        {"near", "\"near\": 0.05", "\"near\": 0", SequenceError::BadField, {"depth.near"}},
        {"far", "\"far\": 100", "\"far\": 0.01", SequenceError::BadField, {"depth.far"}},
        {"reversed", "\"reversed\": false", "\"reversed\": 0", SequenceError::BadField, {"depth.reversed"}},
        {"units", "\"units\": \"pixels\"", "\"units\": \"metres\"", SequenceError::BadField, {"motion.units"}},
        {"duplicate", "\"fps\": 90", "\"fps\": 90, \"fps\": 60", SequenceError::BadJson, {"appears twice"}},
        {"version", "\"version\": 1", "\"version\": 2", SequenceError::BadField, {"version"}},
        {"huge", "\"fps\": 90", "\"fps\": 1e400", SequenceError::BadField, {"\"fps\" is 1e400, not a finite number"}},
        {"huge integer",
         "\"width\": 64",
         "\"width\": 99999999999999999999999",
         SequenceError::BadField,
         {"\"width\" must be an integer in [1, 16384]"}},
        {"huge width", "\"width\": 64", "\"width\": 1e400", SequenceError::BadField, {"\"width\" is 1e400"}},
        {"negative", "\"height\": 48", "\"height\": -48", SequenceError::BadField, {"\"height\"", "-48"}},
        {"negative fps", "\"fps\": 90", "\"fps\": -90", SequenceError::BadField, {"\"fps\" must be positive"}},
        {"beyond float", "\"near\": 0.05", "\"near\": 1e39", SequenceError::BadField, {"\"depth.near\" is 1e+39"}},
        {"-Infinity far",
         "\"far\": 100",
         "\"far\": -Infinity",
         SequenceError::BadField,
         {"\"depth.far\" is -Infinity, not a finite number"}},
        {"NaN string", "\"color\": \"png\"", "\"color\": NaN", SequenceError::BadField, {"\"color\" must be a string"}},
        {"NaN key", "\"fps\": 90", "NaN: 90", SequenceError::BadJson, {"field name must be a quoted string"}},
        {"nested duplicate",
         "\"angle_up\": 0.7853982",
         "\"angle_up\": 0.7853982, \"angle_up\": 0.7",
         SequenceError::BadJson,
         {"field \"fov.left.angle_up\" appears twice"}},
        {"nested too deeply",
         "\"fps\": 90",
         "\"fps\": 90, \"description\": " + std::string(40, '[') + std::string(40, ']'),
         SequenceError::BadJson,
         {"nested more than 32 levels deep"}},
        {"non-UTF-8 string",
         "\"fps\": 90",
         "\"fps\": 90, \"description\": \"caf\xE9\"",
         SequenceError::BadJson,
         {"sequence.json:7:", "ill-formed UTF-8", "\\xE9"}},
        {"non-UTF-8 byte", "\"fps\": 90", "\"fps\": 90\xFF", SequenceError::BadJson, {"sequence.json:7:12:"}},
        {"trailing comma", "\"reversed\": false", "\"reversed\": false,", SequenceError::BadJson, {"not valid JSON"}},
        {"comment", "\"fps\": 90", "\"fps\": 90 // ninety", SequenceError::BadJson, {"sequence.json:7:13:"}},
    };
    for (const JsonCase& c : cases) {
        std::string text = good;
        if (std::string(c.what) == "truncated") {
            text = good.substr(0, good.size() / 2);
        } else {
            auto p = text.find(c.from);
            ASSERT_NE(p, std::string::npos) << c.what << ": " << c.from << " in\n" << good;
            text.replace(p, c.from.size(), c.to);
        }
        auto r = parseSequenceInfo(text);
        ASSERT_FALSE(r.ok()) << c.what;
        EXPECT_EQ(r.error().code, int(c.code)) << c.what << ": " << r.error().message;
        for (const auto& m : c.mentions)
            EXPECT_TRUE(contains(r.error().message, m))
                << c.what << ": '" << r.error().message << "' lacks '" << m << "'";
    }
    EXPECT_EQ(parseSequenceInfo("").error().code, int(SequenceError::BadJson));
    EXPECT_TRUE(contains(parseSequenceInfo("\xEF\xBB\xBF \n").error().message, "the file is empty"));
    EXPECT_EQ(parseSequenceInfo("[1, 2]").error().code, int(SequenceError::BadField));
    EXPECT_EQ(parseSequenceInfo("1e400").error().code, int(SequenceError::BadField));
    // Objects where objects belong; Infinity (Python's json writes it) is an infinite far plane.
    std::string text = good;
    text.replace(text.find("\"motion\": {"), std::string("\"motion\": {\n    \"units\": \"pixels\"\n  }").size(),
                 "\"motion\": [\"pixels\"]");
    auto m = parseSequenceInfo(text);
    ASSERT_FALSE(m.ok()) << text;
    EXPECT_TRUE(contains(m.error().message, "\"motion\" must be an object")) << m.error().message;
    text = good;
    text.replace(text.find("\"far\": 100"), std::string("\"far\": 100").size(), "\"far\": Infinity");
    auto inf = parseSequenceInfo(text);
    ASSERT_TRUE(inf.ok()) << inf.error().message;
    EXPECT_TRUE(std::isinf(inf->depth->farZ));
}

// Syntax errors give the position in the file as written: line and column (bytes from 1), counted
// past a byte-order mark, CR LF line ends and the NaN / Infinity tokens the reader accepts.
TEST(SequenceJson, SyntaxErrorsNameLineAndColumn) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"{\"fps\": NaN, \"x\": 1,, }", "f.json:1:21: not valid JSON: "},
        {"{\"fps\": -Infinity, \"far\": Infinity, \"x\": 1,, }", "f.json:1:44: "},
        {"\xEF\xBB\xBF{,}", "f.json:1:5: "},
        {"{\r\n  \"a\": 1,,\r\n}", "f.json:2:10: "},
        {"{\n\n  \"a\": tru }", "f.json:3:11: "},
        {"{\"a\": 1", "f.json:1:8: not valid JSON: "},  // one past the end
        {"{\"a\": \"abc", "(truncated?)"},
        {"{\"a\": 1", "(truncated?)"},
        {"{\"a\": 1}}", "f.json:1:9: "},
        {"{\"a\": \"\x01\"}", "control character"},
        {"{\"a\": \"\\ud800\"}", "surrogate"},
    };
    for (const auto& [text, mention] : cases) {
        auto r = parseSequenceInfo(text, "f.json");
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_EQ(r.error().code, int(SequenceError::BadJson)) << text << ": " << r.error().message;
        EXPECT_TRUE(contains(r.error().message, mention))
            << text << ": '" << r.error().message << "' lacks '" << mention << "'";
    }
}

// The writer writes JSON any reader can take: the description escaped, bytes that are not UTF-8
// replaced by U+FFFD (the reader would refuse them), pretty printed one field per line.
TEST(SequenceJson, WriterEscapesTheDescription) {
    SequenceInfo a = smallInfo(8, 8, 1);
    a.description = std::string("tab\t, NUL ") + '\0' + ", caf\xC3\xA9, bad \xFF byte";
    const std::string text = formatSequenceInfo(a);
    EXPECT_TRUE(contains(text, "\n  \"fps\": 90,\n")) << text;
    EXPECT_TRUE(contains(text, "\"far\": 100,")) << text;
    auto b = parseSequenceInfo(text);
    ASSERT_TRUE(b.ok()) << b.error().message << "\n" << text;
    EXPECT_EQ(b->description, std::string("tab\t, NUL ") + '\0' + ", caf\xC3\xA9, bad \xEF\xBF\xBD byte");
}

TEST(SequenceJson, MissingDirectoryOrFile) {
    TempDir dir("nojson");
    auto r = readSequenceInfo(dir.str());
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().code, int(SequenceError::MissingFile));
    EXPECT_TRUE(contains(r.error().message, dir.file("sequence.json"))) << r.error().message;
    auto o = SequenceReader::open(dir.str() + "/absent");
    ASSERT_FALSE(o.ok());
    EXPECT_EQ(o.error().code, int(SequenceError::MissingFile));
    EXPECT_TRUE(contains(o.error().message, "does not exist")) << o.error().message;
}

// ---------------------------------------------------------------------------------------------
// Frames written and read back
// ---------------------------------------------------------------------------------------------

TEST(Sequence, PngColourAndFloatDepthMotionReadBackExactly) {
    TempDir dir("roundtrip");
    const SequenceInfo info = smallInfo(40, 24, 3);
    auto written = writeRandom(dir.str(), info);
    auto r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE((*r)->hasGaze());
    EXPECT_TRUE((*r)->gazeNotes().empty());
    const HostStereoApp::Options app = (*r)->appOptions();
    EXPECT_EQ(app.color, layers::Format::RGBA8_SRGB);
    EXPECT_EQ(app.depth, layers::Format::R32F);
    EXPECT_EQ(app.motion, layers::Format::RGBA16F);
    EXPECT_EQ(app.nearZ, 0.05f);
    for (uint32_t i = 0; i < info.frameCount; ++i) {
        auto f = (*r)->frame(i);
        ASSERT_TRUE(f.ok()) << f.error().message;
        EXPECT_DOUBLE_EQ(f->time_s, i / 90.0);
        for (int e = 0; e < 2; ++e) {
            const EyeSubmission &a = written[i][e], &b = f->eyes[e];
            EXPECT_EQ(b.color.format, layers::Format::RGBA8_SRGB);
            EXPECT_EQ(a.color.data, b.color.data) << "frame " << i << " eye " << e;
            ASSERT_TRUE(b.depth.has_value());
            EXPECT_EQ(a.depth->data, b.depth->data) << "frame " << i << " eye " << e;
            ASSERT_TRUE(b.motion.has_value());
            expectSameMotion(*a.motion, *b.motion);
            EXPECT_EQ(b.fov.angleLeft, info.fov[e].angleLeft);
            EXPECT_TRUE(b.gaze.valid);
            EXPECT_EQ(b.gaze.dir, a.gaze.dir);  // %.9g in gaze.csv reads back as the same float
        }
    }
    EXPECT_EQ(exrChannels(dir.file("000001_R_depth.exr")), std::vector<std::string>{"Y"});
    auto beyond = (*r)->frame(info.frameCount);
    ASSERT_FALSE(beyond.ok());
    EXPECT_EQ(beyond.error().code, int(SequenceError::FrameCount));
}

TEST(Sequence, ExrColourReadsBackAsHalfFloats) {
    TempDir dir("exrcolour");
    SequenceInfo info = smallInfo(16, 8, 2);
    info.color = ColorFile::Exr;
    info.depth.reset();
    info.motion.reset();
    auto written = writeRandom(dir.str(), info);
    auto r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ((*r)->appOptions().color, layers::Format::RGBA16F);
    EXPECT_FALSE((*r)->appOptions().depth.has_value());
    EXPECT_FALSE((*r)->appOptions().motion.has_value());
    auto f = (*r)->frame(1);
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_EQ(f->eyes[0].color.data, written[1][0].color.data);  // fp16 -> float EXR -> fp16
    EXPECT_EQ(exrChannels(dir.file("000001_L_color.exr")), (std::vector<std::string>{"B", "G", "R"}));
    EXPECT_FALSE(f->eyes[0].depth.has_value());
    EXPECT_FALSE(fs::exists(dir.file("000000_L_depth.exr")));
}

// A sequence made by hand with OpenCV (not by the writer): motion in pixels, ndc and uv units,
// colour PNG with alpha, infinite reversed depth, gaze with a comment, a confidence column and a NaN.
TEST(Sequence, HandMadeSequenceMotionUnitsBecomePixels) {
    ::setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 0);
    const int W = 32, H = 16;
    for (const std::string units : {"pixels", "ndc", "uv"}) {
        TempDir dir("handmade_" + units);
        writeText(dir.file("sequence.json"),
                  R"({"width": 32, "height": 16, "frame_count": 2, "fps": 60, "color": "png",
 "fov": {"left": {"angle_left": -0.7, "angle_right": 0.7, "angle_up": 0.6, "angle_down": -0.6},
         "right": {"angle_left": -0.7, "angle_right": 0.7, "angle_up": 0.6, "angle_down": -0.6}},
 "depth": {"near": 0.1, "far": "inf", "reversed": true},
 "motion": {"units": ")" + units + R"("}})");
        // Every pixel moves by (+4, -2) pixels and its depth changes by 0.25; written in the units.
        const float sx = units == "ndc" ? 2.0f / W : units == "uv" ? 1.0f / W : 1.0f;
        const float sy = units == "ndc" ? 2.0f / H : units == "uv" ? 1.0f / H : 1.0f;
        for (int i = 0; i < 2; ++i)
            for (int e = 0; e < 2; ++e) {
                cv::Mat color(H, W, CV_8UC4, cv::Scalar(10, 20, 30 + e, 128));  // B, G, R, A
                ASSERT_TRUE(cv::imwrite(dir.file(frameFileName(i, e, "color.png")), color));
                cv::Mat mv(H, W, CV_32FC3, cv::Scalar(0.25, -2.0 * sy, 4.0 * sx));
                ASSERT_TRUE(cv::imwrite(dir.file(frameFileName(i, e, "motion.exr")), mv,
                                        {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
                cv::Mat d1(H, W, CV_32FC1);
                d1.forEach<float>(
                    [&](float& p, const int* pos) { p = 0.001f * float(pos[0]) + float(i); });  // pos: row, column
                ASSERT_TRUE(cv::imwrite(dir.file(frameFileName(i, e, "depth.exr")), d1,
                                        {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
            }
        writeText(dir.file("gaze.csv"),
                  "# a comment line\n"
                  "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z,confidence\n"
                  "0.0,0,1,0,0,-1,0,0,-1,0.9\n"
                  "0.0167,1,1,nan,0,-1,0,0,-1,0.9\n");
        auto r = SequenceReader::open(dir.str());
        ASSERT_TRUE(r.ok()) << r.error().message;
        EXPECT_TRUE((*r)->info().depth->reversedZ);
        EXPECT_TRUE(std::isinf((*r)->info().depth->farZ));
        auto f = (*r)->frame(1);
        ASSERT_TRUE(f.ok()) << f.error().message;
        EXPECT_DOUBLE_EQ(f->time_s, 1.0 / 60.0);
        const EyeSubmission& s = f->eyes[1];
        glm::vec4 c = s.color.fetch(3, 5);
        EXPECT_EQ(glm::ivec4(glm::round(c * 255.0f)), glm::ivec4(31, 20, 10, 128)) << units;
        for (uint32_t y : {0u, 7u, 15u}) {
            glm::vec4 m = s.motion->fetch(9, y);
            EXPECT_EQ(m.x, 4.0f) << units;
            EXPECT_EQ(m.y, -2.0f) << units;
            EXPECT_EQ(m.z, 0.25f) << units;
            EXPECT_EQ(s.depth->fetch(9, y).x, 0.001f * float(y) + 1.0f) << units;
        }
        // Gaze: frame 0 valid with its confidence, frame 1 has a NaN -> invalid (fallback) with a note.
        EXPECT_TRUE((*r)->gaze(0)[0].valid);
        EXPECT_FLOAT_EQ((*r)->gaze(0)[1].confidence, 0.9f);
        EXPECT_FALSE(f->eyes[0].gaze.valid);
        EXPECT_FALSE(f->eyes[1].gaze.valid);
        ASSERT_EQ((*r)->gazeNotes().size(), 1u);
        EXPECT_EQ((*r)->gazeNotes()[0].line, 4u);
        EXPECT_EQ((*r)->gazeNotes()[0].frame, 1u);
        EXPECT_TRUE(contains((*r)->gazeNotes()[0].message, "not finite")) << (*r)->gazeNotes()[0].message;
    }
}

TEST(Sequence, WriterConvertsMotionUnitsBack) {
    for (MotionUnits units : {MotionUnits::Ndc, MotionUnits::Uv}) {
        TempDir dir("units_" + std::string(toString(units)));
        SequenceInfo info = smallInfo(32, 16, 1);
        info.motion = units;
        std::array<EyeSubmission, 2> eyes;
        std::mt19937 rng(3);
        eyes = randomFrame(rng, info, 0);
        for (int e = 0; e < 2; ++e)  // values with few bits, exact through the unit scaling
            for (uint32_t y = 0; y < 16; ++y)
                for (uint32_t x = 0; x < 32; ++x)
                    eyes[e].motion->store(x, y, glm::vec4(float(x) - 8.5f, 3.0f - float(y), 0.125f, 0.0f));
        auto w = SequenceWriter::create(dir.str(), info);
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE((*w)->writeFrame(0, eyes).ok());
        ASSERT_TRUE((*w)->finish().ok());
        // In the file: R, G, B, in the declared units.
        const std::string file = dir.file("000000_L_motion.exr");
        EXPECT_EQ(exrChannels(file), (std::vector<std::string>{"B", "G", "R"}));
        const float sx = units == MotionUnits::Ndc ? 2.0f / 32 : 1.0f / 32;
        EXPECT_FLOAT_EQ(exrChannel(file, "R")[20], (20 - 8.5f) * sx);
        EXPECT_FLOAT_EQ(exrChannel(file, "B")[20], 0.125f);
        auto r = SequenceReader::open(dir.str());
        ASSERT_TRUE(r.ok()) << r.error().message;
        auto f = (*r)->frame(0);
        ASSERT_TRUE(f.ok()) << f.error().message;
        expectSameMotion(*eyes[0].motion, *f->eyes[0].motion);
    }
}

// ---------------------------------------------------------------------------------------------
// Malformed input: one clear error per kind
// ---------------------------------------------------------------------------------------------

class BrokenSequence : public ::testing::Test {
protected:
    void SetUp() override {
        ::setenv("OPENCV_IO_ENABLE_OPENEXR", "1", 0);
        writeRandom(dir.str(), smallInfo(W, H, 3));
        ASSERT_TRUE(SequenceReader::open(dir.str()).ok());
    }
    // open() then frame(i); the first error of either.
    Error firstError(uint32_t frame = 1) {
        auto r = SequenceReader::open(dir.str());
        if (!r) return r.error();
        auto f = (*r)->frame(frame);
        if (!f) return f.error();
        return Error{0, "no error"};
    }
    void expectError(SequenceError code, std::initializer_list<std::string> mentions, uint32_t frame = 1) {
        Error e = firstError(frame);
        EXPECT_EQ(e.code, int(code)) << e.message;
        for (const auto& m : mentions)
            EXPECT_TRUE(contains(e.message, m)) << "'" << e.message << "' lacks '" << m << "'";
    }
    static constexpr int W = 24, H = 12;
    TempDir dir{"broken_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name())};
};

TEST_F(BrokenSequence, MissingFrameFile) {
    fs::remove(dir.file("000002_R_motion.exr"));
    expectError(SequenceError::MissingFile, {"000002_R_motion.exr", "frame 2 of frame_count 3"});
}

TEST_F(BrokenSequence, ColourOfTheOtherType) {
    fs::rename(dir.file("000001_L_color.png"), dir.file("000001_L_color.exr"));
    expectError(SequenceError::MissingFile, {"000001_L_color.png", "there is 000001_L_color.exr"});
}

TEST_F(BrokenSequence, FrameCountTooSmall) {
    replaceInFile(dir.file("sequence.json"), "\"frame_count\": 3", "\"frame_count\": 2");
    expectError(SequenceError::FrameCount, {"frame_count 2", "000002_"});
}

TEST_F(BrokenSequence, FrameCountTooLarge) {
    replaceInFile(dir.file("sequence.json"), "\"frame_count\": 3", "\"frame_count\": 4");
    expectError(SequenceError::MissingFile, {"000003_L_color.png", "frame_count 4"});
}

TEST_F(BrokenSequence, WrongSize) {
    cv::Mat d(H + 1, W, CV_32FC1, cv::Scalar(0.5));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_L_depth.exr"), d, {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
    expectError(SequenceError::ImageSize, {"000001_L_depth.exr", "24x13", "says 24x12"});
    cv::Mat c(H, W / 2, CV_8UC3, cv::Scalar(1, 2, 3));
    ASSERT_TRUE(cv::imwrite(dir.file("000000_R_color.png"), c));
    expectError(SequenceError::ImageSize, {"000000_R_color.png", "12x12"}, 0);
}

TEST_F(BrokenSequence, WrongChannels) {
    cv::Mat grey(H, W, CV_8UC1, cv::Scalar(7));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_L_color.png"), grey));
    expectError(SequenceError::ImageChannels, {"000001_L_color.png", "1 channel", "RGB"});
    writeRandom(dir.str(), smallInfo(W, H, 3));

    cv::Mat d3(H, W, CV_32FC3, cv::Scalar(0.5, 0.5, 0.5));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_L_depth.exr"), d3, {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
    expectError(SequenceError::ImageChannels, {"000001_L_depth.exr", "3 channels (B, G, R)", "exactly one"});
    writeRandom(dir.str(), smallInfo(W, H, 3));

    cv::Mat m1(H, W, CV_32FC1, cv::Scalar(1.0));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_R_motion.exr"), m1, {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
    expectError(SequenceError::ImageChannels, {"000001_R_motion.exr", "1 channel (Y)", "R, G"});
    cv::Mat m4(H, W, CV_32FC4, cv::Scalar(1, 1, 1, 1));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_R_motion.exr"), m4, {cv::IMWRITE_EXR_TYPE, cv::IMWRITE_EXR_TYPE_FLOAT}));
    expectError(SequenceError::ImageChannels, {"000001_R_motion.exr", "4 channels"});
    writeRandom(dir.str(), smallInfo(W, H, 3));

    cv::Mat c16(H, W, CV_16UC3, cv::Scalar(1000, 2000, 3000));
    ASSERT_TRUE(cv::imwrite(dir.file("000001_L_color.png"), c16));
    expectError(SequenceError::ImageChannels, {"000001_L_color.png", "8 bits"});
}

TEST_F(BrokenSequence, TruncatedFiles) {
    for (const std::string name : {"000001_L_color.png", "000001_R_depth.exr", "000001_L_motion.exr"}) {
        writeRandom(dir.str(), smallInfo(W, H, 3));
        const std::string bytes = readText(dir.file(name));
        writeText(dir.file(name), bytes.substr(0, bytes.size() * 2 / 3));
        expectError(SequenceError::BadImage, {name});
        writeText(dir.file(name), bytes.substr(0, 20));  // inside the header
        expectError(SequenceError::BadImage, {name});
        writeText(dir.file(name), "");
        expectError(SequenceError::BadImage, {name});
    }
}

// EXR files another tool may write: half, float or uint channels, a data window that does not
// start at (0, 0), other channel names, subsampled channels, several parts, or not EXR at all.
TEST_F(BrokenSequence, ExrLayouts) {
    const std::string depth = "000001_L_depth.exr";
    auto depthAt = [&](uint32_t x, uint32_t y) {
        auto r = SequenceReader::open(dir.str());
        EXPECT_TRUE(r.ok());
        auto f = (*r)->frame(1);
        EXPECT_TRUE(f.ok()) << f.error().message;
        return f.ok() ? f->eyes[0].depth->fetch(x, y).x : NAN;
    };
    // Half and uint channels are read as float; the data window's origin does not matter.
    writeTestExr(dir.file(depth), W, H, {{"Y", Imf::HALF}},
                 [](int, int x, int y) { return 0.25f * float(x) + 0.5f * float(y); });
    EXPECT_EQ(depthAt(3, 2), 1.75f);
    writeTestExr(dir.file(depth), W, H, {{"R", Imf::UINT}}, [](int, int x, int) { return float(x); });
    EXPECT_EQ(depthAt(7, 5), 7.0f);
    writeTestExr(dir.file(depth), W, H, {{"G"}}, [](int, int x, int y) { return float(x + 100 * y); }, {-5, 40});
    EXPECT_EQ(depthAt(2, 3), 302.0f);
    writeRandom(dir.str(), smallInfo(W, H, 3));

    // A channel Z is planar view depth in the json's units (near 0.05, far 100, not reversed), alone
    // or beside colour (a single-layer EXR with R, G, B, A and Z), converted to the submitted
    // convention; outside [near, far] it is unknown (-1).
    auto planarZ = [](int x, int y) { return x == 0 ? 0.01f : 0.5f + 0.25f * float(x) + 2.0f * float(y); };
    for (bool beside : {false, true}) {
        if (beside)
            writeTestExr(dir.file(depth), W, H, {{"R"}, {"G"}, {"B"}, {"A"}, {"Z", Imf::HALF}},
                         [&](int c, int x, int y) { return c == 4 ? planarZ(x, y) : 0.75f; });
        else
            writeTestExr(dir.file(depth), W, H, {{"Z"}}, [&](int, int x, int y) { return planarZ(x, y); });
        for (auto [x, y] : {std::pair{3u, 2u}, std::pair{7u, 0u}, std::pair{23u, 11u}}) {
            const float z = beside ? float(half(planarZ(x, y))) : planarZ(x, y);
            const float d = depthAt(x, y);
            EXPECT_EQ(d, gpu::wrs_depth_from_linear(z, 0.05f, 100.0f, false)) << x << "," << y;
            EXPECT_NEAR(gpu::wrs_linear_depth(d, 0.05f, 100.0f, false), z, 1e-4f * z) << x << "," << y;
        }
        EXPECT_EQ(depthAt(0, 4), -1.0f) << "in front of the near plane";
    }
    writeRandom(dir.str(), smallInfo(W, H, 3));
    writeTestExr(dir.file(depth), W, H, {{"depth.V"}}, [](int, int, int) { return 0.5f; });
    expectError(SequenceError::ImageChannels, {depth, "1 channel (depth.V)", "named Z"});
    writeTestExr(dir.file(depth), W, H, {{"R"}, {"G"}}, [](int, int, int) { return 0.5f; });
    expectError(SequenceError::ImageChannels, {depth, "2 channels (G, R)", "exactly one channel"});
    writeTestExr(dir.file(depth), W, H + 2, {{"Y"}}, [](int, int, int) { return 0.5f; }, {3, 3});
    expectError(SequenceError::ImageSize, {depth, "24x14", "says 24x12"});
    writeRandom(dir.str(), smallInfo(W, H, 3));
    writeTestExr(dir.file("000001_R_motion.exr"), W, H, {{"R"}, {"G"}}, [](int, int, int) { return 1.0f; }, {0, 0}, 2);
    expectError(SequenceError::ImageChannels, {"000001_R_motion.exr", "subsampled"});
    writeTestExr(dir.file("000001_R_motion.exr"), W, H, {{"R"}, {"G"}, {"Z"}}, [](int, int, int) { return 1.0f; });
    expectError(SequenceError::ImageChannels, {"000001_R_motion.exr", "3 channels (G, R, Z)"});
    writeRandom(dir.str(), smallInfo(W, H, 3));

    // Two parts.
    {
        std::vector<Imf::Header> headers(2, Imf::Header(W, H));
        for (int p = 0; p < 2; ++p) {
            headers[p].setName(p ? "right" : "left");
            headers[p].setType(Imf::SCANLINEIMAGE);
            headers[p].channels().insert("Y", Imf::Channel(Imf::FLOAT));
        }
        std::vector<float> px(W * H, 0.5f);
        Imf::MultiPartOutputFile out(dir.file(depth).c_str(), headers.data(), 2);
        for (int p = 0; p < 2; ++p) {
            Imf::OutputPart part(out, p);
            Imf::FrameBuffer fb;
            auto* base = reinterpret_cast<char*>(px.data());
            fb.insert("Y", Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * W));
            part.setFrameBuffer(fb);
            part.writePixels(H);
        }
    }
    expectError(SequenceError::BadImage, {depth, "multi-part"});
    // Not EXR: a PNG under the EXR name; garbage after a valid signature.
    fs::copy_file(dir.file("000001_L_color.png"), dir.file(depth), fs::copy_options::overwrite_existing);
    expectError(SequenceError::BadImage, {depth, "no EXR signature"});
    writeText(dir.file(depth), std::string("\x76\x2f\x31\x01\x02\x00\x00\x00", 8) + std::string(200, '\x7f'));
    expectError(SequenceError::BadImage, {depth, "not a readable EXR file"});
}

// Colour with alpha (ignored), and values beyond half floats: finite ones clamp to +-65504, NaN and
// infinities pass through (the compositor's bad-input rules handle them); depth is bit for bit.
TEST(Sequence, ExrValuesBeyondHalfAndNonFinite) {
    TempDir dir("exrvalues");
    SequenceInfo info = smallInfo(8, 4, 1);
    info.color = ColorFile::Exr;
    writeRandom(dir.str(), info);
    const float special[] = {NAN, INFINITY, -INFINITY, 1e6f, -1e6f, 70000.0f, 1e-30f, 0.5f};
    auto value = [&](int c, int x, int) { return c == 3 ? 0.25f : special[(x + c) % 8]; };
    writeTestExr(dir.file("000000_L_color.exr"), 8, 4, {{"R"}, {"G"}, {"B"}, {"A"}}, value);
    writeTestExr(dir.file("000000_L_depth.exr"), 8, 4, {{"Y"}}, value);
    writeTestExr(dir.file("000000_L_motion.exr"), 8, 4, {{"R"}, {"G"}}, value);
    auto r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    auto f = (*r)->frame(0);
    ASSERT_TRUE(f.ok()) << f.error().message;
    const EyeSubmission& s = f->eyes[0];
    // Every finite value here is a half float after clamping, except 1e-30 (which rounds to 0).
    auto half = [](float v) {
        return std::abs(v) < 1e-3f ? 0.0f : std::isfinite(v) ? std::clamp(v, -65504.0f, 65504.0f) : v;
    };
    auto same = [](float a, float b) { return std::isnan(b) ? std::isnan(a) : a == b; };
    for (uint32_t x = 0; x < 8; ++x) {
        const glm::vec4 c = s.color.fetch(x, 1), m = s.motion->fetch(x, 1);
        const float d = s.depth->fetch(x, 1).x;
        for (int k = 0; k < 3; ++k)
            EXPECT_TRUE(same(c[k], half(special[(x + uint32_t(k)) % 8]))) << x << " " << k << ": " << c[k];
        EXPECT_EQ(c.w, 1.0f);
        EXPECT_TRUE(same(m.x, half(special[x % 8]))) << x << ": " << m.x;
        EXPECT_TRUE(same(m.y, half(special[(x + 1) % 8]))) << x << ": " << m.y;
        EXPECT_EQ(m.z, 0.0f);  // no B channel
        const float wantD = special[x % 8];
        EXPECT_TRUE(std::isnan(wantD) ? std::isnan(d) : d == wantD) << x << ": " << d;
    }
}

TEST_F(BrokenSequence, BadJsonAndMissingJson) {
    replaceInFile(dir.file("sequence.json"), "\"fps\": 90", "\"fps\": NaN");
    expectError(SequenceError::BadField, {"sequence.json:", "\"fps\" is NaN"});
    fs::remove(dir.file("sequence.json"));
    expectError(SequenceError::MissingFile, {"sequence.json"});
}

TEST_F(BrokenSequence, GazeRows) {
    const std::string header = "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\n";
    // NaN and non-unit directions: that frame's gaze is invalid (fallback), not an error.
    writeText(dir.file("gaze.csv"), header +
                                        "0,0,1,0,0,-1,0,0,-1\n"
                                        "0.011,1,1,0,0,-1,NaN,0,-1\n"
                                        "0.022,2,1,0,0,-2,0,0,-1\n");
    auto r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE((*r)->gaze(0)[0].valid);
    EXPECT_FALSE((*r)->gaze(1)[0].valid);
    EXPECT_FALSE((*r)->gaze(1)[1].valid);
    EXPECT_FALSE((*r)->gaze(2)[0].valid);
    ASSERT_EQ((*r)->gazeNotes().size(), 2u);
    EXPECT_EQ((*r)->gazeNotes()[0].line, 3u);
    EXPECT_TRUE(contains((*r)->gazeNotes()[1].message, "not a unit vector")) << (*r)->gazeNotes()[1].message;
    auto f = (*r)->frame(1);
    ASSERT_TRUE(f.ok());
    EXPECT_FALSE(f->eyes[1].gaze.valid);
    // The invalid eye's NaN direction is replaced: no NaN leaves the reader, whatever the flag says.
    EXPECT_EQ((*r)->gaze(1)[1].dir, glm::vec3(0.0f, 0.0f, -1.0f));

    // An invalid eye's infinite direction is replaced by straight ahead, a finite one kept.
    writeText(dir.file("gaze.csv"), header + "0,0,1,0,0,-1,0,0,-1\n0.011,1,0,inf,0,-1,0.6,0,-0.8\n");
    r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ((*r)->gaze(1)[0].dir, glm::vec3(0.0f, 0.0f, -1.0f));
    EXPECT_EQ((*r)->gaze(1)[1].dir, glm::vec3(0.6f, 0.0f, -0.8f));

    // A frame without a row is invalid too; a blink row (valid 0) may leave the directions empty.
    writeText(dir.file("gaze.csv"), header + "0,0,0,,,,,,\n0.022,2,1,0,0,-1,0,0,-1\n");
    r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_FALSE((*r)->gaze(0)[0].valid);
    EXPECT_FALSE((*r)->gaze(1)[0].valid);
    EXPECT_TRUE((*r)->gaze(2)[1].valid);
    ASSERT_EQ((*r)->gazeNotes().size(), 1u);
    EXPECT_TRUE(contains((*r)->gazeNotes()[0].message, "no row for frame 1"));

    // Malformed rows are errors with the line number.
    const std::vector<std::pair<std::string, std::string>> bad = {
        {"0,0,1,0,0,-1,0,0\n", "expected 9 fields, got 8"},
        {"0,0,1,0,0,-1,0,zero,-1\n", "right_y 'zero' is not a number"},
        {"0,0,yes,0,0,-1,0,0,-1\n", "valid 'yes'"},
        {"0,1.5,1,0,0,-1,0,0,-1\n", "frame '1.5'"},
        {"0,3,1,0,0,-1,0,0,-1\n", "frame 3 is beyond the sequence"},
        {"nan,0,1,0,0,-1,0,0,-1\n", "t_s 'nan'"},
        {"0,0,1,,0,-1,0,0,-1\n", "left_x '' is not a number"},
    };
    for (const auto& [row, message] : bad) {
        writeText(dir.file("gaze.csv"), header + "0,0,1,0,0,-1,0,0,-1\n" + row);
        Error e = firstError();
        EXPECT_EQ(e.code, int(SequenceError::BadGaze)) << row << e.message;
        EXPECT_TRUE(contains(e.message, "gaze.csv line 3: " + message)) << row << ": " << e.message;
    }
    writeText(dir.file("gaze.csv"), "t_s,frame,valid,left_x,left_y,left_z\n");
    Error e = firstError();
    EXPECT_EQ(e.code, int(SequenceError::BadGaze));
    EXPECT_TRUE(contains(e.message, "line 1: header lacks column 'right_x'")) << e.message;

    // Without gaze.csv: no gaze (the benchmark fills in synthetic gaze).
    fs::remove(dir.file("gaze.csv"));
    r = SequenceReader::open(dir.str());
    ASSERT_TRUE(r.ok());
    EXPECT_FALSE((*r)->hasGaze());
    EXPECT_FALSE((*r)->gaze(0)[0].valid);
}

TEST(SequenceWriter, RefusesWhatItCannotWrite) {
    TempDir dir("writer");
    SequenceInfo info = smallInfo(16, 8, 2);
    info.fov[0].angleLeft = NAN;
    auto bad = SequenceWriter::create(dir.str(), info);
    ASSERT_FALSE(bad.ok());
    EXPECT_TRUE(contains(bad.error().message, "fov.left")) << bad.error().message;

    info = smallInfo(16, 8, 2);
    auto w = SequenceWriter::create(dir.str(), info);
    ASSERT_TRUE(w.ok());
    std::mt19937 rng(1);
    auto eyes = randomFrame(rng, info, 0);
    eyes[1].depth.reset();
    Status s = (*w)->writeFrame(0, eyes);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.message(), "right eye: no depth")) << s.message();
    eyes = randomFrame(rng, info, 0);
    eyes[0].color = HostImage::make(layers::Format::RGBA8_SRGB, 8, 8);
    s = (*w)->writeFrame(0, eyes);
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.message(), "8x8")) << s.message();
    eyes = randomFrame(rng, info, 0);
    ASSERT_TRUE((*w)->writeFrame(0, eyes).ok());
    EXPECT_FALSE((*w)->writeFrame(2, eyes).ok());  // out of order
    s = (*w)->finish();
    ASSERT_FALSE(s.ok());
    EXPECT_TRUE(contains(s.message(), "1 frames written, frame_count is 2")) << s.message();
}

}  // namespace
}  // namespace wrsfov::eval
