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

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gaze/gaze_file.h"
#include "shaders/wrs_common.h"

#include "eval/sequence_internal.h"

namespace wrsfov::eval {

using namespace seqfile;
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
