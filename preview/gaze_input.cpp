#include "preview/gaze_input.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "compositor/host_app.h"
#include "gaze/hid_device.h"
#include "gaze/source.h"

namespace wrsfov::preview {

namespace {

Error gazeError(std::string message) { return Error{1, std::move(message)}; }

layers::EyeGaze toLayers(const gaze::EyeGaze& g) { return {g.dir, g.valid, g.confidence}; }

class MouseInput final : public GazeInput {
public:
    explicit MouseInput(GazeSpec s) : GazeInput(std::move(s)) {}
    GazeReading sample(const GazeQuery& q) override {
        GazeReading r;
        r.eye = gazeFromCursor(q.fov, q.width, q.height, q.cursor);
        if (!q.cursor) r.note = "cursor outside the eye images";
        return r;
    }
};

class FixedInput final : public GazeInput {
public:
    explicit FixedInput(GazeSpec s) : GazeInput(std::move(s)) {}
    GazeReading sample(const GazeQuery&) override {
        GazeReading r;
        const glm::vec3 d = gaze::direction_from_angle(spec().fixed);
        for (auto& e : r.eye) e = {d, true, 1.0f};
        return r;
    }
};

// Generator and file: sampled on the scene clock; a file is replayed in a loop.
class ReplayInput final : public GazeInput {
public:
    ReplayInput(GazeSpec s, std::unique_ptr<gaze::GazeSource> source, double loop_s)
        : GazeInput(std::move(s)), source_(std::move(source)), loop_s_(loop_s) {}
    GazeReading sample(const GazeQuery& q) override {
        double t = q.t;
        if (loop_s_ > 0) t = std::fmod(t, loop_s_);
        const gaze::GazeSample g = source_->sample(t);
        GazeReading r;
        for (int e = 0; e < 2; ++e) r.eye[e] = toLayers(g.eye[e]);
        if (!g.eye[0].valid && !g.eye[1].valid) r.note = g.label == gaze::Event::Blink ? "blink" : "no valid sample";
        return r;
    }

private:
    std::unique_ptr<gaze::GazeSource> source_;
    double loop_s_;
};

// HID: live, on the tracker source's own clock.
class HidInput final : public GazeInput {
public:
    HidInput(GazeSpec s, std::unique_ptr<gaze::hid::HidTrackerSource> source)
        : GazeInput(std::move(s)), source_(std::move(source)) {}
    GazeReading sample(const GazeQuery&) override {
        source_->poll();
        const gaze::GazeSample g = source_->sample(gaze::hid::HidTrackerSource::steady_seconds());
        GazeReading r;
        for (int e = 0; e < 2; ++e) r.eye[e] = toLayers(g.eye[e]);
        if (!source_->connected())
            r.note = "tracker not connected" + (source_->last_error().empty() ? "" : ": " + source_->last_error());
        return r;
    }

private:
    std::unique_ptr<gaze::hid::HidTrackerSource> source_;
};

bool parseNumber(std::string_view s, double& out) {
    std::string str(s);
    char* end = nullptr;
    out = std::strtod(str.c_str(), &end);
    return !str.empty() && end && *end == '\0' && std::isfinite(out);
}

}  // namespace

Result<GazeSpec> parseGazeSpec(std::string_view text) {
    GazeSpec s;
    const size_t colon = text.find(':');
    const std::string_view head = text.substr(0, colon);
    const std::string_view arg = colon == std::string_view::npos ? std::string_view() : text.substr(colon + 1);
    const bool hasArg = colon != std::string_view::npos;
    if (head == "mouse" && !hasArg) {
        s.kind = GazeKind::Mouse;
    } else if (head == "generator" && !hasArg) {
        s.kind = GazeKind::Generator;
    } else if (head == "hid") {
        s.kind = GazeKind::Hid;
        s.argument = std::string(arg);
        if (hasArg && arg.empty()) return gazeError("--gaze hid: wants a device after the colon (or plain 'hid')");
    } else if (head == "file") {
        s.kind = GazeKind::File;
        s.argument = std::string(arg);
        if (arg.empty()) return gazeError("--gaze file:PATH wants a path");
    } else if (head == "fixed") {
        s.kind = GazeKind::Fixed;
        const size_t comma = arg.find(',');
        if (comma == std::string_view::npos || !parseNumber(arg.substr(0, comma), s.fixed.az_deg) ||
            !parseNumber(arg.substr(comma + 1), s.fixed.el_deg) || std::abs(s.fixed.az_deg) >= 90 ||
            std::abs(s.fixed.el_deg) >= 90)
            return gazeError("--gaze fixed:AZ,EL wants azimuth and elevation in degrees in (-90, 90), got '" +
                             std::string(text) + "'");
    } else {
        return gazeError("--gaze wants mouse, generator, hid[:DEVICE], file:PATH or fixed:AZ,EL, got '" +
                         std::string(text) + "'");
    }
    return s;
}

std::string toString(const GazeSpec& s) {
    switch (s.kind) {
        case GazeKind::Mouse:
            return "mouse";
        case GazeKind::Generator:
            return "generator";
        case GazeKind::Hid:
            return s.argument.empty() ? "hid" : "hid:" + s.argument;
        case GazeKind::File:
            return "file:" + s.argument;
        case GazeKind::Fixed: {
            char buf[64];
            std::snprintf(buf, sizeof(buf), "fixed:%g,%g", s.fixed.az_deg, s.fixed.el_deg);
            return buf;
        }
    }
    return "?";
}

std::array<layers::EyeGaze, 2> gazeFromCursor(const layers::Fov fov[2], uint32_t width, uint32_t height,
                                              std::optional<std::array<float, 2>> cursor) {
    std::array<layers::EyeGaze, 2> g{};
    if (!cursor || width == 0 || height == 0) return g;
    // pixelDirection takes a pixel index (centre at +0.5); the cursor is a continuous position.
    for (int e = 0; e < 2; ++e)
        g[e] = {pixelDirection(fov[e], width, height, (*cursor)[0] - 0.5f, (*cursor)[1] - 0.5f), true, 1.0f};
    return g;
}

Result<std::unique_ptr<GazeInput>> createGazeInput(const GazeSpec& spec, const GazeSetting& setting) {
    switch (spec.kind) {
        case GazeKind::Mouse:
            return std::unique_ptr<GazeInput>(new MouseInput(spec));
        case GazeKind::Fixed:
            return std::unique_ptr<GazeInput>(new FixedInput(spec));
        case GazeKind::Generator: {
            gaze::GeneratorConfig gc;
            gc.seed = setting.seed;
            gc.seconds = 60;
            if (setting.scene == SceneKind::Text) {
                // Read the lines of the text scene (as the benchmark does).
                gc.mode = gaze::Mode::Reading;
                gc.reading.char_deg = setting.text.charDeg;
                gc.reading.line_spacing_deg = setting.text.lineSpacingDeg;
                gc.reading.line_chars = setting.text.lineChars;
                gc.reading.lines_per_page = setting.text.lines;
            } else {
                gc.mode = gaze::Mode::Scene;
            }
            auto src = gaze::SyntheticSource::create(gc);
            if (!src) return gazeError("gaze generator: " + src.error().message);
            return std::unique_ptr<GazeInput>(new ReplayInput(spec, std::move(*src), 0.0));
        }
        case GazeKind::File: {
            auto src = gaze::ReplaySource::open(spec.argument);
            if (!src) return gazeError("gaze file '" + spec.argument + "': " + src.error().message);
            const double loop = (*src)->duration_s();
            return std::unique_ptr<GazeInput>(new ReplayInput(spec, std::move(*src), loop));
        }
        case GazeKind::Hid: {
            std::string path;
            if (spec.argument.empty()) {
                auto devices = gaze::hid::enumerate_devices();
                if (!devices) return gazeError("HID: " + devices.error().message);
                for (const auto& d : *devices)
                    if (d.is_eye_tracker()) {
                        path = d.path;
                        break;
                    }
                if (path.empty())
                    return gazeError(
                        "no HID eye tracker (usage page 0x12) found; `wrsfov-gaze list` shows the HID devices "
                        "(hidraw nodes need read permission)");
            } else {
                auto p = gaze::hid::resolve_device(spec.argument);
                if (!p) return gazeError("HID: " + p.error().message);
                path = *p;
            }
            auto src = std::make_unique<gaze::hid::HidTrackerSource>(gaze::hid::hidapi_connector(path));
            return std::unique_ptr<GazeInput>(new HidInput(spec, std::move(src)));
        }
    }
    return gazeError("unknown gaze source");
}

}  // namespace wrsfov::preview
