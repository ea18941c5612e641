#include "xr_common/xr_config.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "compositor/host_app.h"
#include "gaze/hid_device.h"

namespace wrsfov::xr {

namespace {

constexpr float kDeg = 3.14159265358979f / 180.0f;

Error bad(std::string_view key, std::string_view value, std::string_view expected) {
    return Error{1, "'" + std::string(key) + "' = '" + std::string(value) + "': expected " + std::string(expected)};
}

std::optional<double> number(std::string_view v) {
    std::string s(v);
    char* end = nullptr;
    double d = std::strtod(s.c_str(), &end);
    if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(d)) return std::nullopt;
    return d;
}

std::optional<bool> boolean(std::string_view v) {
    if (v == "1" || v == "true" || v == "on" || v == "yes") return true;
    if (v == "0" || v == "false" || v == "off" || v == "no") return false;
    return std::nullopt;
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

// Every key the runtime reads; also the environment variables WRSFOV_XR_<KEY>.
constexpr const char* kKeys[] = {"method", "fovea", "foveation", "width", "height", "fov", "ipd",
                                 "display_hz", "pace", "frames", "record", "head", "gaze", "gaze_mode",
                                 "gaze_seed", "gaze_file", "vergence_distance", "validation", "verbose",
                                 "output", "screenshot", "quad_views", "inset_deg", "swapchains"};

}  // namespace

Status applyConfigKey(RuntimeConfig& c, std::string_view key, std::string_view v) {
    auto num = [&](double lo, double hi) -> std::optional<double> {
        auto d = number(v);
        if (!d || *d < lo || *d > hi) return std::nullopt;
        return d;
    };
    auto range = [&](double lo, double hi) {
        std::ostringstream o;
        o << "a number in [" << lo << ", " << hi << "]";
        return o.str();
    };
    if (key == "method") {
        auto m = parseMethod(v);
        if (v == "off") {
            c.compose = false;
            return {};
        }
        if (!m || isOracle(*m)) return bad(key, v, "fov, fov+taa, wrs-paper, wrs or off");
        c.compositor.method = *m;
        c.compose = true;
    } else if (key == "fovea") {
        auto d = num(0.5, 60);
        if (!d) return bad(key, v, range(0.5, 60) + " (fovea diameter in degrees)");
        c.compositor.foveaDeg = float(*d);
    } else if (key == "foveation") {
        auto m = parseFoveationMode(v);
        if (!m) return bad(key, v, "none, mip or gauss");
        c.compositor.foveation = *m;
    } else if (key == "width" || key == "height") {
        auto d = num(16, 8192);
        if (!d || *d != std::floor(*d)) return bad(key, v, "an integer in [16, 8192]");
        (key == "width" ? c.width : c.height) = uint32_t(*d);
    } else if (key == "fov") {
        if (v == "hmd") {
            c.fov[0] = hmdFov(0);
            c.fov[1] = hmdFov(1);
        } else {
            auto d = num(10, 170);
            if (!d) return bad(key, v, "hmd or " + range(10, 170) + " (symmetric square field of view in degrees)");
            const float h = float(*d) * 0.5f * kDeg;
            for (auto& f : c.fov) f = layers::Fov{-h, h, h, -h};
        }
    } else if (key == "ipd") {
        auto d = num(0.04, 0.08);
        if (!d) return bad(key, v, range(0.04, 0.08) + " (metres)");
        c.ipd_m = float(*d);
    } else if (key == "display_hz") {
        auto d = num(10, 240);
        if (!d) return bad(key, v, range(10, 240));
        c.displayHz = *d;
    } else if (key == "pace") {
        if (v == "realtime") c.pace = true;
        else if (v == "free") c.pace = false;
        else return bad(key, v, "realtime or free");
    } else if (key == "frames") {
        auto d = num(0, 1e9);
        if (!d || *d != std::floor(*d)) return bad(key, v, "an integer >= 0 (0: until the application exits)");
        c.frames = uint64_t(*d);
    } else if (key == "record") {
        c.record = std::string(v);
    } else if (key == "head") {
        auto p = scenes::parseCameraPath(v);
        if (!p) return bad(key, v, "static, lateral, turn, yaw30, yaw60, yaw120 or look-around");
        c.head = *p;
    } else if (key == "gaze") {
        if (v == "generator") c.gaze = GazeKind::Generator;
        else if (v == "file") c.gaze = GazeKind::File;
        else if (v == "hid") c.gaze = GazeKind::Hid;
        else if (v == "mouse") c.gaze = GazeKind::Mouse;
        else if (v == "none") c.gaze = GazeKind::None;
        else return bad(key, v, "generator, file, hid, mouse or none");
    } else if (key == "gaze_mode") {
        auto m = gaze::parse_mode(v);
        if (!m) return bad(key, v, "fixation, scene, reading or pursuit");
        c.gazeMode = *m;
    } else if (key == "gaze_seed") {
        auto d = num(0, 4294967295.0);
        if (!d || *d != std::floor(*d)) return bad(key, v, "an integer >= 0");
        c.gazeSeed = uint64_t(*d);
    } else if (key == "gaze_file") {
        c.gazeFile = std::string(v);
    } else if (key == "vergence_distance") {
        auto d = num(0.1, 1000);
        if (!d) return bad(key, v, range(0.1, 1000) + " (metres)");
        c.vergenceDistance_m = float(*d);
    } else if (key == "output") {
        if (v == "auto") c.output = Output::Auto;
        else if (v == "window") c.output = Output::Window;
        else if (v == "headless") c.output = Output::Headless;
        else return bad(key, v, "auto, window or headless");
    } else if (key == "screenshot") {
        c.screenshot = std::string(v);
    } else if (key == "quad_views") {
        auto b = boolean(v);
        if (!b) return bad(key, v, "0 or 1");
        c.quadViews = *b;
    } else if (key == "inset_deg") {
        auto d = num(5, 120);
        if (!d) return bad(key, v, range(5, 120) + " (the inset's size across in degrees)");
        c.insetDeg = float(*d);
    } else if (key == "swapchains") {
        if (v == "own") c.strictSwapchains = false;
        else if (v == "strict") c.strictSwapchains = true;
        else return bad(key, v, "own or strict");
    } else if (key == "validation" || key == "verbose") {
        auto b = boolean(v);
        if (!b) return bad(key, v, "0 or 1");
        (key == "validation" ? c.validation : c.verbose) = *b;
    } else {
        std::string keys;
        for (const char* k : kKeys) keys += std::string(keys.empty() ? "" : ", ") + k;
        return Error{1, "unknown key '" + std::string(key) + "' (keys: " + keys + ")"};
    }
    return {};
}

Result<std::unique_ptr<gaze::GazeSource>> openGazeSource(const RuntimeConfig& c) {
    if (c.gaze == GazeKind::Generator) {
        gaze::GeneratorConfig g;
        g.mode = c.gazeMode;
        g.seed = c.gazeSeed;
        g.seconds = 60;  // replayed in a loop
        auto src = gaze::SyntheticSource::create(g);
        if (!src) return Error{1, "gaze generator: " + src.error().message};
        return std::unique_ptr<gaze::GazeSource>(std::move(*src));
    }
    if (c.gaze == GazeKind::File) {
        auto src = gaze::ReplaySource::open(c.gazeFile);
        if (!src) return Error{1, "gaze file: " + src.error().message};
        return std::unique_ptr<gaze::GazeSource>(std::move(*src));
    }
    if (c.gaze == GazeKind::Hid) {
        auto path = gaze::hid::resolve_device("0");
        if (!path) return Error{1, "HID eye tracker: " + path.error().message};
        return std::unique_ptr<gaze::GazeSource>(
            std::make_unique<gaze::hid::HidTrackerSource>(gaze::hid::hidapi_connector(*path)));
    }
    return std::unique_ptr<gaze::GazeSource>();  // mouse (the runtime's window) or none
}

Result<RuntimeConfig> loadRuntimeConfig(const std::function<const char*(const char*)>& getenvFn) {
    return loadConfig("WRSFOV_XR_", getenvFn);
}

Result<RuntimeConfig> loadConfig(const std::string& prefix, const std::function<const char*(const char*)>& getenvFn) {
    auto env = [&](const char* name) -> const char* { return getenvFn ? getenvFn(name) : std::getenv(name); };
    RuntimeConfig c;
    c.fov[0] = hmdFov(0);
    c.fov[1] = hmdFov(1);
    if (const char* v = env("WRSFOV_VALIDATION")) c.validation = std::string(v) == "1";
    if (const char* path = env((prefix + "CONFIG").c_str()); path && *path) {
        std::ifstream in(path);
        if (!in) return Error{1, prefix + "CONFIG: cannot read " + path};
        std::string line;
        for (int n = 1; std::getline(in, line); ++n) {
            std::string_view l = line;
            if (auto hash = l.find('#'); hash != std::string_view::npos) l = l.substr(0, hash);
            l = trim(l);
            if (l.empty()) continue;
            const auto eq = l.find('=');
            if (eq == std::string_view::npos)
                return Error{1, std::string(path) + ":" + std::to_string(n) + ": expected key = value"};
            if (Status s = applyConfigKey(c, trim(l.substr(0, eq)), trim(l.substr(eq + 1))); !s)
                return Error{1, std::string(path) + ":" + std::to_string(n) + ": " + s.message()};
        }
    }
    for (const char* key : kKeys) {
        std::string name = prefix;
        for (const char* k = key; *k; ++k) name += char(std::toupper(static_cast<unsigned char>(*k)));
        if (const char* v = env(name.c_str()))
            if (Status s = applyConfigKey(c, key, trim(v)); !s) return Error{1, name + ": " + s.message()};
    }
    if (c.gaze == GazeKind::File && c.gazeFile.empty())
        return Error{1, "gaze = file needs gaze_file (" + prefix + "GAZE_FILE)"};
    return c;
}

}  // namespace wrsfov::xr
