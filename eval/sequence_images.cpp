// The sequence's images: colour (PNG through OpenCV, or EXR), depth and motion (EXR through OpenEXR), read
// checked against sequence.json; EXR written as float.
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
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "shaders/wrs_common.h"
#include "eval/sequence_internal.h"

namespace wrsfov::eval {

using namespace seqfile;
namespace fs = std::filesystem;

namespace {

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

}  // namespace

namespace seqfile {

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

}  // namespace seqfile

}  // namespace wrsfov::eval
