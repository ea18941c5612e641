#include "preview/options.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>

#include "cli/cli.h"

namespace wrsfov::preview {

namespace {

constexpr PreviewMethod kMethods[] = {PreviewMethod::Reference, PreviewMethod::Fov, PreviewMethod::FovTaa,
                                      PreviewMethod::WrsPaper, PreviewMethod::Wrs};
constexpr const auto& kPaths = scenes::kCameraPaths;

template <typename T, size_t N>
T nextOf(const T (&all)[N], T v) {
    for (size_t i = 0; i < N; ++i)
        if (all[i] == v) return all[(i + 1) % N];
    return all[0];
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

CompositorConfig compositorConfig(PreviewMethod method, FoveationMode mode, float foveaDeg, uint32_t seed,
                                  bool skipTiles) {
    CompositorConfig c;
    c.method = method == PreviewMethod::Wrs        ? Method::Wrs
               : method == PreviewMethod::WrsPaper ? Method::WrsPaper
               : method == PreviewMethod::FovTaa   ? Method::FovTaa
                                                   : Method::Fov;
    c.foveation = method == PreviewMethod::Reference ? FoveationMode::None : mode;
    c.foveaDeg = foveaDeg;
    c.seed = seed;
    c.skipTiles = skipTiles;
    return c;
}

namespace {

// ITERATION:KEY[,ITERATION:KEY...] with KEY a letter, a digit, space, right or escape.
std::optional<std::vector<std::pair<int, std::string>>> parseKeys(std::string_view list, std::string& why) {
    std::vector<std::pair<int, std::string>> keys;
    size_t start = 0;
    while (start <= list.size()) {
        const size_t end = std::min(list.find(',', start), list.size());
        const std::string item(list.substr(start, end - start));
        const size_t colon = item.find(':');
        const std::string key = colon == std::string::npos ? "" : item.substr(colon + 1);
        const bool known = (key.size() == 1 && std::isalnum(static_cast<unsigned char>(key[0]))) || key == "space" ||
                           key == "right" || key == "escape";
        const auto at = colon == std::string::npos ? std::nullopt : cli::parseWhole(item.substr(0, colon));
        if (!at || *at < 0 || *at > 10000000 || !known) {
            why = "'" + item + "' is not ITERATION:KEY with KEY a letter, a digit, space, right or escape";
            return std::nullopt;
        }
        std::string lower = key;
        for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
        keys.emplace_back(int(*at), lower);
        start = end + 1;
    }
    return keys;
}

std::optional<std::array<double, 2>> parseCursor(std::string_view v) {
    const size_t comma = v.find(',');
    if (comma == std::string_view::npos) return std::nullopt;
    const auto x = cli::parseFinite(v.substr(0, comma)), y = cli::parseFinite(v.substr(comma + 1));
    if (!x || !y || *x < 0 || *y < 0) return std::nullopt;
    return std::array<double, 2>{*x, *y};
}

template <typename T, size_t N>
std::vector<std::pair<std::string, T>> named(const T (&values)[N]) {
    std::vector<std::pair<std::string, T>> out;
    for (T v : values) out.emplace_back(std::string(toString(v)), v);
    return out;
}

constexpr SceneKind kScenes[] = {SceneKind::Atrium, SceneKind::Dynamic, SceneKind::Text, SceneKind::Photo};
constexpr scenes::PhotoMotion kPhotoMotions[] = {scenes::PhotoMotion::Static, scenes::PhotoMotion::Pan,
                                                 scenes::PhotoMotion::Turn};

// The command line over `o`: each option writes into it; `resize` and `cursor` are read after parsing.
struct CommandLine {
    CLI::App app{
        "A window showing the compositor's output for both eyes, with the gaze, the fovea and the stats "
        "(docs/preview.md).",
        "wrsfov-preview"};
    cli::Size size;
    std::array<std::string, 2> resize;
    std::array<double, 2> cursor{};
    bool noSkip = false;

    explicit CommandLine(PreviewOptions& o) : size{o.width, o.height} {
        cli::setup(app);
        cli::option(app, "--size", size, cli::size(32, 4096), "Image size per eye, W and H in 32..4096.");
        cli::option(app, "--scene", o.scene, cli::oneOf(named(kScenes)),
                    "Scene: atrium, dynamic, text (needs about 1400 pixels per eye to be legible) or photo (natural "
                    "texture on a plane: --photo, --photo-motion, --photo-speed).");
        cli::option(app, "--photo", o.photoImage, cli::text("an image file, grass or wood", "IMAGE"),
                    "Scene photo's image: a PNG or JPEG file, or a generated texture: grass (the default) or wood.");
        cli::option(app, "--photo-motion", o.photoMotion, cli::oneOf(named(kPhotoMotions)),
                    "Scene photo's head: static, pan (the default) or turn.");
        cli::option(app, "--photo-speed", o.photoSpeed, cli::number<float>(-64, 64),
                    "Scene photo's speed in pixels per frame at 90 Hz at the view's centre (default 0.37).")
            ->type_name("PX");
        cli::option(app, "--path", o.path, cli::oneOf(named(kPaths)),
                    "Camera path of atrium and dynamic: static, lateral, turn, yaw30, yaw60, yaw120 or look-around.");
        cli::option(app, "--method", o.method,
                    cli::parsedBy<PreviewMethod>(
                        parseMethod, [](const PreviewMethod& m) { return std::string(toString(m)); },
                        "one of reference, fov, fov+taa (or taa), wrs-paper, wrs"),
                    "What the compositor runs: reference (no foveation), fov, fov+taa, wrs-paper (WRS as published) "
                    "or wrs (quality-aware retention).");
        cli::option(app, "--fovea", o.foveaDeg, cli::number<float>(0, 60, cli::Ends::OpenLow),
                    "Fovea diameter in degrees, in (0, 60]; the F key steps 5, 7.5, 10.")
            ->type_name("DEG");
        cli::option(app, "--mode", o.mode,
                    cli::oneOf<FoveationMode>({{"mip", FoveationMode::Mip}, {"gauss", FoveationMode::Gauss}}),
                    "Foveation: mip or gauss.");
        cli::option(app, "--gaze", o.gaze,
                    cli::Reader<GazeSpec>{[](std::string_view text, std::string& why) -> std::optional<GazeSpec> {
                                              auto g = parseGazeSpec(text);
                                              if (g) return *g;
                                              why = g.error().message;  // "--gaze fixed:AZ,EL wants ..."
                                              if (why.rfind("--gaze ", 0) == 0) why.erase(0, 7);
                                              return std::nullopt;
                                          },
                                          [](const GazeSpec& g) { return toString(g); }, "SOURCE"},
                    "Gaze source: mouse, generator, hid[:DEVICE] (a hidraw path, an index of `wrsfov-gaze list` "
                    "or VID:PID), file:PATH (a gaze file replayed in a loop) or fixed:AZ,EL (degrees, right and "
                    "up positive).");
        cli::option(app, "--seed", o.seed, cli::integer<uint32_t>(0, 0xffffffffu),
                    "Seed of the scene, the gaze generator and WRS, 0..4294967295.");
        cli::option(
            app, "--view", o.view, cli::oneOf(named(kViews)),
            "View: stereo, left, right, compare (output above reference), error (|output - reference|) or visible "
            "(FovVideoVDP's visible distortion against the reference); the last three score the output's JOD "
            "live (docs/preview.md).");
        cli::option(app, "--overlay", o.overlay, cli::oneOf<bool>({{"on", true}, {"off", false}}),
                    "Gaze marker and fovea / mid-periphery circles: on or off.")
            ->type_name("on|off");
        app.add_flag("--no-skip", noSkip,
                     "Every pixel through the per-pixel path, no tile classes (docs/speed.md \"Tiles\"): the same "
                     "image, the GPU time without what the classes save.");
        cli::option(app, "--frames", o.frames, cli::integer(1, 10000000),
                    "Composite N frames (1..10000000), present the last one and exit.")
            ->default_str("until the window is closed");
        cli::option(app, "--screenshot", o.screenshot, cli::text("a file name", "FILE"),
                    "With --frames: save the preview image (PNG) after the last frame.");
        app.add_option("--resize-at", resize, "Resize the window to WxH after frame N, 1..10000000 (tests).")
            ->check(cli::check(cli::integer(1, 10000000)).application_index(0))
            ->check(cli::check(cli::size(1, 16384)).application_index(1))
            ->type_name("N WxH");
        cli::option(app, "--cursor", cursor,
                    cli::parsedBy<std::array<double, 2>>(
                        parseCursor, [](const std::array<double, 2>&) { return std::string(); },
                        "X,Y in window pixels (two numbers >= 0)", "X,Y"),
                    "Move the pointer to window position X,Y at start (tests, scripted shots).");
        cli::option(app, "--keys", o.keys,
                    cli::Reader<std::vector<std::pair<int, std::string>>>{
                        parseKeys, [](const std::vector<std::pair<int, std::string>>&) { return std::string(); },
                        "I:K[,I:K...]"},
                    "Press key K (a letter, a digit, space, right, escape) at loop iteration I (tests).");
        cli::addConfig(app);
        app.footer(
            "Environment: WRSFOV_DEVICE=<name part> picks the Vulkan device, WRSFOV_VALIDATION=1 runs under "
            "the\nKhronos validation layer (the exit status is 3 if it reported errors).\n\n" +
            keyHelp());
    }
};

}  // namespace

Result<PreviewOptions> parseArguments(int argc, const char* const* argv) {
    PreviewOptions o;
    CommandLine cl(o);
    const cli::Parsed p = cli::parse(cl.app, argc, argv);
    switch (p.kind) {
        case cli::Parsed::Kind::Run:
            break;
        case cli::Parsed::Kind::Help:
        case cli::Parsed::Kind::Version:
            o.help = p.kind == cli::Parsed::Kind::Help;
            o.version = !o.help;
            o.text = p.text;
            return o;
        case cli::Parsed::Kind::UsageError:
            return Error{2, p.text};
        case cli::Parsed::Kind::FileError:
            return Error{1, p.text};
    }
    o.width = cl.size.width;
    o.height = cl.size.height;
    if (cl.app.count("--resize-at")) {
        std::string why;
        o.resizeFrame = *cli::integer(1, 10000000).read(cl.resize[0], why);
        const cli::Size s = *cli::size(1, 16384).read(cl.resize[1], why);
        o.resizeWidth = s.width;
        o.resizeHeight = s.height;
    }
    if (cl.app.count("--cursor")) o.cursor = cl.cursor;
    o.skipTiles = !cl.noSkip;
    if (!o.screenshot.empty() && o.frames == 0)
        return Error{2, "--screenshot FILE needs --frames N (interactive screenshots: the S key)"};
    return o;
}

std::string usage() {
    PreviewOptions o;
    return CommandLine(o).app.help();
}

std::string keyHelp() {
    return "keys:\n"
           "  1 2 3 4 5 method: reference, FOV, FOV+TAA, WRS-paper, WRS   M  next method\n"
           "  F         fovea size 5 -> 7.5 -> 10 degrees         G  foveation mip <-> gauss\n"
           "  N         scene text -> atrium -> dynamic -> photo  P  camera path static -> lateral -> turn -> yaw30/60/120 -> look-around\n"
           "  V         view stereo -> left -> right -> compare -> error -> visible\n"
           "  I         gaze source (mouse, generator, and the one given with --gaze)\n"
           "  O         gaze marker and circles on/off\n"
           "  Space     pause / resume     Right or .  one frame while paused\n"
           "  S         screenshot (wrsfov-preview-NNNNNN.png in the current directory)\n"
           "  H         print this help    Esc or Q  quit\n";
}

}  // namespace wrsfov::preview
