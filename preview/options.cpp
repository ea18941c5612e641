#include "preview/options.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace wrsfov::preview {

namespace {

constexpr PreviewMethod kMethods[] = {PreviewMethod::Reference, PreviewMethod::Fov, PreviewMethod::FovTaa,
                                      PreviewMethod::WrsPaper, PreviewMethod::Wrs};
constexpr scenes::CameraPath kPaths[] = {scenes::CameraPath::Static, scenes::CameraPath::Lateral,
                                         scenes::CameraPath::Turn};

template <typename T, size_t N>
T nextOf(const T (&all)[N], T v) {
    for (size_t i = 0; i < N; ++i)
        if (all[i] == v) return all[(i + 1) % N];
    return all[0];
}

Error argError(std::string m) { return Error{2, std::move(m)}; }

bool parseSize(std::string_view v, uint32_t& w, uint32_t& h, uint32_t lo, uint32_t hi) {
    unsigned a = 0, b = 0;
    char tail = 0;
    std::string s(v);
    if (std::sscanf(s.c_str(), "%ux%u%c", &a, &b, &tail) != 2) return false;
    if (a < lo || b < lo || a > hi || b > hi) return false;
    w = a;
    h = b;
    return true;
}

bool parseInt(std::string_view v, long lo, long hi, long& out) {
    std::string s(v);
    char* end = nullptr;
    out = std::strtol(s.c_str(), &end, 10);
    return !s.empty() && *end == '\0' && out >= lo && out <= hi;
}

}  // namespace

std::string_view toString(PreviewMethod m) {
    switch (m) {
        case PreviewMethod::Reference:
            return "reference";
        case PreviewMethod::Fov:
            return "fov";
        case PreviewMethod::FovTaa:
            return "fov+taa";
        case PreviewMethod::WrsPaper:
            return "wrs-paper";
        case PreviewMethod::Wrs:
            return "wrs";
    }
    return "?";
}

std::optional<PreviewMethod> parseMethod(std::string_view name) {
    for (PreviewMethod m : kMethods)
        if (toString(m) == name) return m;
    if (name == "taa") return PreviewMethod::FovTaa;
    return std::nullopt;
}

PreviewMethod nextMethod(PreviewMethod m) { return nextOf(kMethods, m); }

scenes::CameraPath nextPath(scenes::CameraPath p) { return nextOf(kPaths, p); }

float nextFovea(float deg) {
    for (float f : kFoveaSteps)
        if (f > deg + 1e-3f) return f;
    return kFoveaSteps[0];
}

CompositorConfig compositorConfig(PreviewMethod method, FoveationMode mode, float foveaDeg, uint32_t seed) {
    CompositorConfig c;
    c.method = method == PreviewMethod::Wrs        ? Method::Wrs
               : method == PreviewMethod::WrsPaper ? Method::WrsPaper
               : method == PreviewMethod::FovTaa   ? Method::FovTaa
                                                   : Method::Fov;
    c.foveation = method == PreviewMethod::Reference ? FoveationMode::None : mode;
    c.foveaDeg = foveaDeg;
    c.seed = seed;
    return c;
}

Result<PreviewOptions> parseArguments(int argc, const char* const* argv) {
    PreviewOptions o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--help" || a == "-h") {
            o.help = true;
            return o;
        }
        auto value = [&]() -> const char* { return i + 1 < argc ? argv[++i] : nullptr; };
        const char* v = value();
        if (!v) return argError("missing value after " + a);
        long n = 0;
        if (a == "--size") {
            if (!parseSize(v, o.width, o.height, 32, 4096))
                return argError("--size wants WxH per eye, each 32..4096, got '" + std::string(v) + "'");
        } else if (a == "--scene") {
            auto s = parseScene(v);
            if (!s) return argError("--scene wants text, atrium or dynamic, got '" + std::string(v) + "'");
            o.scene = *s;
        } else if (a == "--path") {
            auto p = scenes::parseCameraPath(v);
            if (!p) return argError("--path wants static, lateral or turn, got '" + std::string(v) + "'");
            o.path = *p;
        } else if (a == "--method") {
            auto m = parseMethod(v);
            if (!m) return argError("--method wants reference, fov, fov+taa, wrs-paper or wrs, got '" + std::string(v) + "'");
            o.method = *m;
        } else if (a == "--fovea") {
            char* end = nullptr;
            float f = std::strtof(v, &end);
            if (*v == '\0' || *end || !std::isfinite(f) || f <= 0 || f > 60)
                return argError("--fovea wants a diameter in (0, 60] degrees (keys step 5, 7.5, 10), got '" +
                                std::string(v) + "'");
            o.foveaDeg = f;
        } else if (a == "--mode") {
            std::string m = v;
            if (m == "mip")
                o.mode = FoveationMode::Mip;
            else if (m == "gauss")
                o.mode = FoveationMode::Gauss;
            else
                return argError("--mode wants mip or gauss, got '" + m + "'");
        } else if (a == "--gaze") {
            auto g = parseGazeSpec(v);
            if (!g) return argError(g.error().message);
            o.gaze = *g;
        } else if (a == "--seed") {
            if (!parseInt(v, 0, 0xffffffffL, n)) return argError("--seed wants an integer 0..4294967295");
            o.seed = uint32_t(n);
        } else if (a == "--view") {
            auto w = parseView(v);
            if (!w) return argError("--view wants stereo, left, right, compare or error, got '" + std::string(v) + "'");
            o.view = *w;
        } else if (a == "--overlay") {
            std::string s = v;
            if (s == "on")
                o.overlay = true;
            else if (s == "off")
                o.overlay = false;
            else
                return argError("--overlay wants on or off, got '" + s + "'");
        } else if (a == "--frames") {
            if (!parseInt(v, 1, 10000000, n))
                return argError("--frames wants 1..10000000, got '" + std::string(v) + "'");
            o.frames = int(n);
        } else if (a == "--screenshot") {
            o.screenshot = v;
            if (o.screenshot.empty()) return argError("--screenshot wants a file name");
        } else if (a == "--resize-at") {
            const char* size = value();
            if (!parseInt(v, 1, 10000000, n) || !size || !parseSize(size, o.resizeWidth, o.resizeHeight, 1, 16384))
                return argError("--resize-at wants a frame number and WxH, e.g. --resize-at 3 640x360");
            o.resizeFrame = int(n);
        } else if (a == "--keys") {
            // ITERATION:KEY[,ITERATION:KEY...]
            std::string list = v;
            size_t start = 0;
            while (start <= list.size()) {
                const size_t end = std::min(list.find(',', start), list.size());
                const std::string item = list.substr(start, end - start);
                const size_t colon = item.find(':');
                const std::string key = colon == std::string::npos ? "" : item.substr(colon + 1);
                const bool known = (key.size() == 1 && std::isalnum(static_cast<unsigned char>(key[0]))) ||
                                   key == "space" || key == "right" || key == "escape";
                if (colon == std::string::npos || !parseInt(item.substr(0, colon), 0, 10000000, n) || !known)
                    return argError(
                        "--keys wants ITERATION:KEY[,...] with KEY a letter, a digit, space, right or "
                        "escape, got '" +
                        item + "'");
                std::string lower = key;
                for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
                o.keys.emplace_back(int(n), lower);
                start = end + 1;
            }
        } else if (a == "--cursor") {
            double x = 0, y = 0;
            char tail = 0;
            if (std::sscanf(v, "%lf,%lf%c", &x, &y, &tail) != 2 || !std::isfinite(x) || !std::isfinite(y) || x < 0 ||
                y < 0)
                return argError("--cursor wants X,Y in window pixels, got '" + std::string(v) + "'");
            o.cursor = std::array<double, 2>{x, y};
        } else {
            return argError("unknown option " + a + " (see --help)");
        }
    }
    if (!o.screenshot.empty() && o.frames == 0)
        return argError("--screenshot FILE needs --frames N (interactive screenshots: the S key)");
    return o;
}

std::string usage() {
    return "usage: wrsfov-preview [options]\n"
           "A window showing the compositor's output for both eyes, with the gaze, the fovea and the stats.\n"
           "  --size WxH            per-eye image size (default 320x288)\n"
           "  --scene NAME          atrium | dynamic | text (default atrium)\n"
           "  --path NAME           camera path of atrium/dynamic: static | lateral | turn (default lateral)\n"
           "  --method NAME         reference | fov | fov+taa | wrs-paper | wrs (default wrs)\n"
           "  --fovea DEG           fovea diameter in degrees (default 5; the F key steps 5, 7.5, 10)\n"
           "  --mode NAME           foveation: mip | gauss (default mip)\n"
           "  --gaze SOURCE         mouse | generator | hid[:DEVICE] | file:PATH | fixed:AZ,EL (default mouse)\n"
           "  --seed N              seed of the scene, the generator and WRS (default 1)\n"
           "  --view NAME           stereo | left | right | compare | error (default stereo)\n"
           "  --overlay on|off      gaze marker and fovea / mid-periphery circles (default on)\n"
           "  --frames N            composite N frames, then exit\n"
           "  --screenshot FILE     with --frames: save the preview image (PNG) after the last frame\n"
           "  --resize-at N WxH     resize the window after frame N (tests)\n"
           "  --cursor X,Y          move the pointer to window position X,Y at start (tests, scripted shots)\n"
           "  --keys I:K[,I:K...]   press key K (letter, digit, space, right, escape) at loop iteration I (tests)\n"
           "  --help                this text and the keys\n"
           "Environment: WRSFOV_DEVICE=<name part> picks the Vulkan device, WRSFOV_VALIDATION=1 runs under the\n"
           "Khronos validation layer (the exit status is 3 if it reported errors).\n";
}

std::string keyHelp() {
    return "keys:\n"
           "  1 2 3 4 5 method: reference, FOV, FOV+TAA, WRS-paper, WRS   M  next method\n"
           "  F         fovea size 5 -> 7.5 -> 10 degrees         G  foveation mip <-> gauss\n"
           "  N         scene text -> atrium -> dynamic           P  camera path static -> lateral -> turn\n"
           "  V         view stereo -> left -> right -> compare -> error\n"
           "  I         gaze source (mouse, generator, and the one given with --gaze)\n"
           "  O         gaze marker and circles on/off\n"
           "  Space     pause / resume     Right or .  one frame while paused\n"
           "  S         screenshot (wrsfov-preview-NNNNNN.png in the current directory)\n"
           "  H         print this help    Esc or Q  quit\n";
}

}  // namespace wrsfov::preview
