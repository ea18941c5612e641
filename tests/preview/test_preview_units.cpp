// The preview's parts that need no window: command line, gaze sources, layout and cursor mapping,
// the stats strip, the live JOD.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compositor/host_app.h"
#include "preview/panel_params.h"
#include "preview/gaze_input.h"
#include "preview/layout.h"
#include "preview/live_jod.h"
#include "preview/options.h"
#include "preview/strip.h"
#include "shaders/wrs_common.h"

using namespace wrsfov;
using namespace wrsfov::preview;

namespace {

Result<PreviewOptions> parse(std::vector<std::string> args) {
    std::vector<const char*> argv{"wrsfov-preview"};
    for (const auto& a : args) argv.push_back(a.c_str());
    return parseArguments(int(argv.size()), argv.data());
}

void expectRefused(std::vector<std::string> args, const std::string& mention) {
    auto r = parse(args);
    ASSERT_FALSE(r.ok()) << "accepted: " << args.front();
    EXPECT_EQ(r.error().code, 2);
    EXPECT_NE(r.error().message.find(mention), std::string::npos) << r.error().message;
}

}  // namespace

TEST(PreviewOptions, DefaultsAndValues) {
    auto d = parse({});
    ASSERT_TRUE(d.ok());
    EXPECT_EQ(d->width, 320u);
    EXPECT_EQ(d->scene, SceneKind::Atrium);
    EXPECT_EQ(d->method, PreviewMethod::Wrs);
    EXPECT_EQ(d->gaze.kind, GazeKind::Mouse);
    EXPECT_EQ(d->frames, 0);

    auto o =
        parse({"--size",      "192x176", "--scene",   "dynamic",  "--path",   "turn",       "--method",     "fov+taa",
               "--fovea",     "7.5",     "--mode",    "gauss",    "--gaze",   "fixed:8,-4", "--seed",       "9",
               "--view",      "error",   "--overlay", "off",      "--frames", "12",         "--screenshot", "x.png",
               "--resize-at", "3",       "640x360",   "--cursor", "10.5,20"});
    ASSERT_TRUE(o.ok()) << o.error().message;
    EXPECT_EQ(o->width, 192u);
    EXPECT_EQ(o->height, 176u);
    EXPECT_EQ(o->scene, SceneKind::Dynamic);
    EXPECT_EQ(o->path, scenes::CameraPath::Turn);
    EXPECT_EQ(o->method, PreviewMethod::FovTaa);
    EXPECT_FLOAT_EQ(o->foveaDeg, 7.5f);
    EXPECT_EQ(o->mode, FoveationMode::Gauss);
    EXPECT_EQ(o->gaze.kind, GazeKind::Fixed);
    EXPECT_DOUBLE_EQ(o->gaze.fixed.az_deg, 8.0);
    EXPECT_DOUBLE_EQ(o->gaze.fixed.el_deg, -4.0);
    EXPECT_EQ(o->seed, 9u);
    EXPECT_EQ(o->view, View::Error);
    EXPECT_FALSE(o->overlay);
    EXPECT_EQ(o->frames, 12);
    EXPECT_EQ(o->screenshot, "x.png");
    EXPECT_EQ(o->resizeFrame, 3);
    EXPECT_EQ(o->resizeWidth, 640u);
    EXPECT_EQ(o->resizeHeight, 360u);
    ASSERT_TRUE(o->cursor.has_value());
    EXPECT_DOUBLE_EQ((*o->cursor)[0], 10.5);

    // Tile classes: on unless --no-skip, and handed to the compositor's configuration.
    EXPECT_TRUE(d->skipTiles);
    auto ns = parse({"--no-skip"});
    ASSERT_TRUE(ns.ok()) << ns.error().message;
    EXPECT_FALSE(ns->skipTiles);
    EXPECT_TRUE(o->skipTiles);
    EXPECT_FALSE(compositorConfig(PreviewMethod::Wrs, FoveationMode::Mip, 5.0f, 1, ns->skipTiles).skipTiles);
    EXPECT_TRUE(compositorConfig(PreviewMethod::Wrs, FoveationMode::Mip, 5.0f, 1).skipTiles);

    auto h = parse({"--size", "10x10", "--help"});
    EXPECT_FALSE(h.ok());  // arguments are read in order: the bad size comes first
    auto h2 = parse({"--help"});
    ASSERT_TRUE(h2.ok());
    EXPECT_TRUE(h2->help);
}

TEST(PreviewOptions, BadArgumentsNameTheOption) {
    expectRefused({"--size", "16x16"}, "--size");
    expectRefused({"--size", "200"}, "--size");
    expectRefused({"--size", "200x100x3"}, "--size");
    expectRefused({"--scene", "sequence"}, "--scene");
    expectRefused({"--path", "orbit"}, "--path");
    expectRefused({"--method", "dlss"}, "--method");
    expectRefused({"--fovea", "0"}, "--fovea");
    expectRefused({"--fovea", "nan"}, "--fovea");
    expectRefused({"--fovea", "5deg"}, "--fovea");
    expectRefused({"--mode", "none"}, "--mode");
    expectRefused({"--gaze", "eyes"}, "--gaze");
    expectRefused({"--gaze", "fixed:95,0"}, "fixed:AZ,EL");
    expectRefused({"--gaze", "file:"}, "file:PATH");
    expectRefused({"--seed", "-1"}, "--seed");
    expectRefused({"--view", "mono"}, "--view");
    expectRefused({"--overlay", "yes"}, "--overlay");
    expectRefused({"--frames", "0"}, "--frames");
    expectRefused({"--resize-at", "3"}, "--resize-at");
    expectRefused({"--cursor", "3"}, "--cursor");
    expectRefused({"--screenshot", "a.png"}, "--frames");
    expectRefused({"--frames"}, "missing value");
    expectRefused({"--bogus", "1"}, "unknown option");
}

TEST(PreviewOptions, HelpVersionAndMessages) {
    auto h = parse({"--help"});
    ASSERT_TRUE(h.ok());
    EXPECT_NE(h->text.find("Default: 320x288."), std::string::npos) << h->text;  // every option with its default
    EXPECT_NE(h->text.find("Space"), std::string::npos);                         // and the keys
    auto v = parse({"--version"});
    ASSERT_TRUE(v.ok());
    EXPECT_TRUE(v->version);
    EXPECT_EQ(v->text.rfind("wrsfov-preview ", 0), 0u) << v->text;
    // Messages name the option and the value.
    auto r = parse({"--frames", "0"});
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "--frames: '0' is not an integer in 1..10000000");
    auto g = parse({"--gaze", "eyes"});
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.error().message.rfind("--gaze: wants mouse, generator", 0), 0u) << g.error().message;
    // Given twice, the last one counts.
    auto t = parse({"--seed", "3", "--seed", "4"});
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->seed, 4u);
}

TEST(PreviewOptions, ConfigFile) {
    const std::string path = ::testing::TempDir() + "wrsfov_preview_options.toml";
    {
        std::ofstream f(path);
        f << "# preview settings\nsize = \"192x176\"\nmethod = \"fov+taa\"\noverlay = \"off\"\nseed = 9\n"
             "gaze = \"fixed:8,-4\"\n";
    }
    auto o = parse({"--config", path, "--seed", "5"});
    ASSERT_TRUE(o.ok()) << o.error().message;
    EXPECT_EQ(o->width, 192u);
    EXPECT_EQ(o->height, 176u);
    EXPECT_EQ(o->method, PreviewMethod::FovTaa);
    EXPECT_FALSE(o->overlay);
    EXPECT_EQ(o->gaze.kind, GazeKind::Fixed);
    EXPECT_EQ(o->seed, 5u);  // the command line wins over the file
    {
        std::ofstream f(path);
        f << "frames = 0\n";
    }
    expectRefused({"--config", path}, "--frames: '0'");
    {
        std::ofstream f(path);
        f << "colour = \"red\"\n";
    }
    expectRefused({"--config", path}, "--config: unknown key 'colour'");
    std::remove(path.c_str());
    auto missing = parse({"--config", path});
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().code, 1);  // a file that cannot be read is a run-time error
}

TEST(PreviewOptions, GazeSpecsReadBackTheirText) {
    for (const char* text :
         {"mouse", "generator", "hid", "hid:046d:c52b", "hid:/dev/hidraw3", "file:/tmp/g.csv", "fixed:8,-4"}) {
        auto s = parseGazeSpec(text);
        ASSERT_TRUE(s.ok()) << text << ": " << s.error().message;
        EXPECT_EQ(toString(*s), text);
    }
    auto h = parseGazeSpec("hid:046d:c52b");
    ASSERT_TRUE(h.ok());
    EXPECT_EQ(h->kind, GazeKind::Hid);
    EXPECT_EQ(h->argument, "046d:c52b");
    EXPECT_FALSE(parseGazeSpec("mouse:1").ok());
    EXPECT_FALSE(parseGazeSpec("fixed:1").ok());
}

TEST(PreviewOptions, KeyCyclesAndConfigs) {
    EXPECT_FLOAT_EQ(nextFovea(5.0f), 7.5f);
    EXPECT_FLOAT_EQ(nextFovea(7.5f), 10.0f);
    EXPECT_FLOAT_EQ(nextFovea(10.0f), 5.0f);
    EXPECT_FLOAT_EQ(nextFovea(6.0f), 7.5f);
    EXPECT_EQ(nextMethod(PreviewMethod::Wrs), PreviewMethod::Reference);
    EXPECT_EQ(nextScene(SceneKind::Dynamic), SceneKind::Photo);
    EXPECT_EQ(nextScene(SceneKind::Photo), SceneKind::Text);
    EXPECT_EQ(nextView(View::Error), View::Visible);
    EXPECT_EQ(nextView(View::Visible), View::Stereo);

    CompositorConfig ref = compositorConfig(PreviewMethod::Reference, FoveationMode::Gauss, 7.5f, 3);
    EXPECT_EQ(ref.method, Method::Fov);
    EXPECT_EQ(ref.foveation, FoveationMode::None);
    CompositorConfig taa = compositorConfig(PreviewMethod::FovTaa, FoveationMode::Gauss, 7.5f, 3);
    EXPECT_EQ(taa.method, Method::FovTaa);
    EXPECT_EQ(taa.foveation, FoveationMode::Gauss);
    EXPECT_FLOAT_EQ(taa.foveaDeg, 7.5f);
    EXPECT_EQ(taa.seed, 3u);
}

TEST(PreviewLayout, PanelsAndStrip) {
    const Layout s = makeLayout(View::Stereo, 192, 176);
    EXPECT_EQ(s.width, 384u);
    EXPECT_EQ(s.stripY, 176u);
    EXPECT_EQ(s.height, 176u + s.stripHeight);
    ASSERT_EQ(s.panels.size(), 2u);
    EXPECT_EQ(s.panels[1].x, 192u);
    EXPECT_EQ(s.panels[1].eye, 1u);

    const Layout c = makeLayout(View::Compare, 192, 176);
    ASSERT_EQ(c.panels.size(), 4u);
    EXPECT_EQ(c.stripY, 352u);
    EXPECT_EQ(c.panels[3].kind, PanelKind::Reference);
    EXPECT_EQ(c.panels[3].y, 176u);

    const Layout r = makeLayout(View::Right, 192, 176);
    ASSERT_EQ(r.panels.size(), 1u);
    EXPECT_EQ(r.panels[0].eye, 1u);
    EXPECT_EQ(r.width, 192u);
    EXPECT_GT(r.stripLines, s.stripLines);  // a narrower strip needs more lines

    const Layout v = makeLayout(View::Visible, 192, 176);
    ASSERT_EQ(v.panels.size(), 2u);
    EXPECT_EQ(v.panels[0].kind, PanelKind::Visible);
    EXPECT_EQ(v.panels[1].eye, 1u);
    EXPECT_EQ(uint32_t(PanelKind::Visible), WRS_PANEL_VISIBLE);
    EXPECT_EQ(uint32_t(PanelKind::Error), WRS_PANEL_ERROR);

    EXPECT_TRUE(needsReference(View::Error));
    EXPECT_TRUE(needsReference(View::Visible));
    EXPECT_FALSE(needsReference(View::Stereo));
}

TEST(PreviewLayout, CursorMapsThroughTheLetterbox) {
    const Layout l = makeLayout(View::Stereo, 192, 176);
    // Same size: identity.
    Placement same = placeInWindow(l.width, l.height, l.width, l.height);
    EXPECT_EQ(same.x, 0);
    EXPECT_EQ(same.width, l.width);
    auto h = hitTest(l, same, 292.25, 60.5);
    ASSERT_TRUE(h.has_value());
    EXPECT_EQ(h->eye, 1u);
    EXPECT_FLOAT_EQ(h->x, 100.25f);
    EXPECT_FLOAT_EQ(h->y, 60.5f);
    EXPECT_FALSE(hitTest(l, same, 10, l.stripY + 3.0).has_value());  // the strip is no eye
    EXPECT_FALSE(hitTest(l, same, -1, 10).has_value());

    // A window twice as wide as needed: the image is centred with bars left and right.
    Placement wide = placeInWindow(l.width, l.height, l.width * 4, l.height * 2);
    EXPECT_EQ(wide.width, l.width * 2);
    EXPECT_EQ(wide.height, l.height * 2);
    EXPECT_EQ(wide.x, int32_t(l.width));
    EXPECT_EQ(wide.y, 0);
    auto w = hitTest(l, wide, wide.x + 2 * 50.5, 2 * 30.0);
    ASSERT_TRUE(w.has_value());
    EXPECT_EQ(w->eye, 0u);
    EXPECT_NEAR(w->x, 50.5f, 1e-4);
    EXPECT_NEAR(w->y, 30.0f, 1e-4);
    EXPECT_FALSE(hitTest(l, wide, 5, 5).has_value());  // on the bar
}

// The mouse gaze at a pixel's centre is that pixel's ray as the compositor computes it (docs/conventions.md,
// "Views"): eccentricity 0 there, and the pixel's own angular size one pixel away.
TEST(PreviewGaze, CursorRayIsThePixelRayOfEachEye) {
    const uint32_t w = 192, h = 176;
    const layers::Fov fov[2] = {hmdFov(0), hmdFov(1)};
    for (auto [px, py] : {std::pair{0u, 0u}, std::pair{100u, 60u}, std::pair{191u, 175u}}) {
        auto g = gazeFromCursor(fov, w, h, std::array<float, 2>{px + 0.5f, py + 0.5f});
        for (int e = 0; e < 2; ++e) {
            ASSERT_TRUE(g[e].valid);
            const glm::vec4 tan(std::tan(fov[e].angleLeft), std::tan(fov[e].angleRight), std::tan(fov[e].angleUp),
                                std::tan(fov[e].angleDown));
            const glm::vec3 ray = gpu::wrs_pixel_ray(px, py, w, h, tan);
            EXPECT_LT(gpu::wrs_eccentricity_deg(ray, g[e].dir), 0.01f) << "eye " << e << " pixel " << px << "," << py;
            const glm::vec3 next = gpu::wrs_pixel_ray(std::min(px + 1, w - 1), py, w, h, tan);
            if (px + 1 < w) {
                EXPECT_GT(gpu::wrs_eccentricity_deg(next, g[e].dir), 0.2f);
            }
        }
        // The eyes' fields of view differ, so the same pixel is a different direction per eye.
        EXPECT_GT(gpu::wrs_eccentricity_deg(g[0].dir, g[1].dir), 1.0f);
    }
    auto none = gazeFromCursor(fov, w, h, std::nullopt);
    EXPECT_FALSE(none[0].valid);
    EXPECT_FALSE(none[1].valid);
}

TEST(PreviewGaze, FixedAndMissingSources) {
    GazeSetting setting;
    auto fixed = createGazeInput(*parseGazeSpec("fixed:10,-5"), setting);
    ASSERT_TRUE(fixed.ok());
    GazeQuery q;
    GazeReading r = (*fixed)->sample(q);
    EXPECT_TRUE(r.eye[0].valid && r.eye[1].valid);
    EXPECT_NEAR(r.eye[0].dir.x, std::sin(10 * M_PI / 180) * std::cos(5 * M_PI / 180), 1e-5);
    EXPECT_NEAR(r.eye[0].dir.y, -std::sin(5 * M_PI / 180), 1e-5);

    auto file = createGazeInput(*parseGazeSpec("file:/nonexistent/gaze.csv"), setting);
    ASSERT_FALSE(file.ok());
    EXPECT_NE(file.error().message.find("/nonexistent/gaze.csv"), std::string::npos);

    auto gen = createGazeInput(*parseGazeSpec("generator"), setting);
    ASSERT_TRUE(gen.ok());
    // Reading the text: over a few seconds the gaze moves along the lines (several degrees).
    float minX = 1, maxX = -1;
    for (int i = 0; i < 300; ++i) {
        q.t = i / 90.0;
        GazeReading g = (*gen)->sample(q);
        if (!g.eye[0].valid) continue;
        minX = std::min(minX, g.eye[0].dir.x);
        maxX = std::max(maxX, g.eye[0].dir.x);
    }
    EXPECT_GT(maxX - minX, 0.05f);
}

TEST(PreviewStrip, WrapsItemsOntoLines) {
    const Layout l = makeLayout(View::Left, 192, 176);
    auto inkInLine = [&](const cv::Mat& m, uint32_t line) {
        int n = 0;
        for (int y = int(2 + line * kStripLineHeight); y < int(2 + (line + 1) * kStripLineHeight); ++y)
            for (int x = 0; x < m.cols; ++x) n += m.at<cv::Vec4b>(y, x)[3] > 0;
        return n;
    };
    cv::Mat one = drawStrip(l, {"WRS"});
    ASSERT_EQ(one.rows, int(l.stripHeight));
    ASSERT_EQ(one.cols, int(l.width));
    EXPECT_GT(inkInLine(one, 0), 10);
    EXPECT_EQ(inkInLine(one, 1), 0);
    cv::Mat many = drawStrip(l, {"fovea 5.0 deg", "mip", "atrium / lateral", "view stereo", "gaze mouse"});
    EXPECT_GT(inkInLine(many, 0), 10);
    EXPECT_GT(inkInLine(many, 1), 10);
    EXPECT_EQ(stripLinesNeeded(l.width, {"WRS"}), 1u);
    EXPECT_GE(stripLinesNeeded(l.width, {"fovea 5.0 deg", "mip", "atrium / lateral", "view stereo", "gaze mouse"}), 2u);
}

// ---------------------------------------------------------------------------------------------
// Live JOD (preview/live_jod.h)
// ---------------------------------------------------------------------------------------------

namespace {

constexpr uint32_t kJodW = 64, kJodH = 48;

LiveJodOptions jodOptions(std::size_t window, bool map, double fps = 90.0) {
    LiveJodOptions o;
    o.fps = fps;
    o.width = kJodW;
    o.height = kJodH;
    o.fovTan = {glm::vec4(-0.8f, 0.7f, 0.6f, -0.65f), glm::vec4(-0.7f, 0.8f, 0.6f, -0.65f)};
    o.window = window;
    o.map = map;
    return o;
}

// Fine random texture (fixed seed) in sRGB-encoded [0, 1], and a copy blurred inside a disc.
cv::Mat texture(uint64_t seed) {
    cv::Mat m(int(kJodH), int(kJodW), CV_32FC3);
    cv::RNG rng(seed);
    rng.fill(m, cv::RNG::UNIFORM, 0.1, 0.9);
    return m;
}

cv::Mat blurredDisc(const cv::Mat& m, cv::Point centre, int radius, double sigma) {
    cv::Mat b, out = m.clone();
    cv::GaussianBlur(m, b, {0, 0}, sigma);
    cv::Mat mask = cv::Mat::zeros(m.size(), CV_8U);
    cv::circle(mask, centre, radius, 255, cv::FILLED);
    b.copyTo(out, mask);
    return out;
}

}  // namespace

TEST(PreviewLiveJod, IdenticalFramesScoreTenWithAnEmptyMap) {
    auto j = LiveJod::create(jodOptions(90, true));
    ASSERT_TRUE(j.ok()) << j.error().message;
    EXPECT_FALSE((*j)->jod().has_value());
    for (int f = 0; f < 3; ++f) {
        const cv::Mat a = texture(10 + f), b = texture(20 + f);
        ASSERT_TRUE((*j)->push({a, b}, {a, b}, {glm::vec2(30, 20), glm::vec2(34, 20)}).ok());
    }
    const auto jod = (*j)->jod();
    ASSERT_TRUE(jod.has_value());
    for (int e = 0; e < 2; ++e) {
        EXPECT_NEAR((*jod)[e], 10.0, 1e-9) << "eye " << e;
        ASSERT_FALSE((*j)->map(e).empty());
        EXPECT_EQ(cv::countNonZero((*j)->map(e) > 1e-6f), 0) << "eye " << e;
    }
}

// Up to the window the readout is the metric's own JOD of the frames pushed (an image for one
// frame, a video after); past it, the frames before the window no longer count. At 8 Hz the
// temporal filters are two frames long, so a change of the blur leaves the transient channel at once.
TEST(PreviewLiveJod, PoolsTheLastWindowAsTheMetricPoolsAVideo) {
    constexpr std::size_t kWindow = 4;
    constexpr double kFps = 8.0;
    auto live = LiveJod::create(jodOptions(kWindow, false, kFps));
    ASSERT_TRUE(live.ok()) << live.error().message;
    std::array<std::optional<eval::fvvdp::Metric>, 2> whole;
    for (int e = 0; e < 2; ++e) {
        eval::fvvdp::Options fo;
        fo.photometry = eval::fvvdp::DisplayPhotometry::hmd();
        fo.geometry = eval::fvvdp::ViewGeometry::view(kJodW, kJodH, jodOptions(kWindow, false).fovTan[e]);
        fo.fps = kFps;
        auto m = eval::fvvdp::Metric::create(fo);
        ASSERT_TRUE(m.ok());
        whole[e].emplace(std::move(*m));
    }
    std::vector<std::array<double, 2>> frameQuality;
    const glm::vec2 gaze(20, 24);
    const cv::Mat ref = texture(100);
    constexpr int kFrames = 9;
    for (int f = 0; f < kFrames; ++f) {
        // Heavily blurred at the gaze for the first three frames, lightly after.
        const cv::Mat test = blurredDisc(ref, {20, 24}, 14, f < 3 ? 2.5 : 0.6);
        ASSERT_TRUE((*live)->push({test, test}, {ref, ref}, {gaze, gaze}).ok());
        std::array<double, 2> q{};
        for (int e = 0; e < 2; ++e) {
            ASSERT_TRUE(whole[e]->push(test, ref, gaze).ok());
            q[e] = eval::fvvdp::detail::poolFrame(whole[e]->lastFrame())[1];
        }
        frameQuality.push_back(q);
        const auto j = (*live)->jod();
        ASSERT_TRUE(j.has_value());
        EXPECT_EQ((*live)->pooled(), std::min<std::size_t>(f + 1, kWindow));
        for (int e = 0; e < 2; ++e) {
            if (std::size_t(f) < kWindow) {
                EXPECT_NEAR((*j)[e], *whole[e]->jod(), 1e-9) << "frame " << f << " eye " << e;
            } else {
                double sum = 0;
                for (std::size_t k = frameQuality.size() - kWindow; k < frameQuality.size(); ++k)
                    sum += frameQuality[k][e];
                EXPECT_NEAR((*j)[e], eval::fvvdp::detail::jodFromQuality(sum / kWindow), 1e-9) << "frame " << f;
            }
            // The heavily blurred frames and the change have left the window: better than the whole video.
            if (f == kFrames - 1) {
                EXPECT_GT((*j)[e], *whole[e]->jod() + 0.05) << "eye " << e;
            }
        }
    }
    (*live)->reset();
    EXPECT_FALSE((*live)->jod().has_value());
    EXPECT_EQ((*live)->frames(), 0u);
}

// The map shows where the difference is: inside the blurred disc, not away from it.
TEST(PreviewLiveJod, MapIsWhereTheBlurIs) {
    auto j = LiveJod::create(jodOptions(90, true));
    ASSERT_TRUE(j.ok());
    const cv::Mat ref = texture(7);
    const cv::Mat test = blurredDisc(ref, {16, 24}, 10, 2.0);
    ASSERT_TRUE((*j)->push({test, test}, {ref, ref}, {glm::vec2(16, 24), glm::vec2(16, 24)}).ok());
    for (int e = 0; e < 2; ++e) {
        const cv::Mat& m = (*j)->map(e);
        ASSERT_EQ(m.size(), cv::Size(int(kJodW), int(kJodH)));
        const double inside = cv::mean(m(cv::Rect(10, 18, 12, 12)))[0];
        const double away = cv::mean(m(cv::Rect(44, 4, 16, 12)))[0];
        EXPECT_GT(inside, 0.1) << "eye " << e;
        EXPECT_GT(inside, 10 * away) << "eye " << e;
        EXPECT_LT((*(*j)->jod())[e], 9.9);
    }
    auto noMap = LiveJod::create(jodOptions(90, false));
    ASSERT_TRUE(noMap.ok());
    ASSERT_TRUE((*noMap)->push({test, test}, {ref, ref}, {glm::vec2(16, 24), glm::vec2(16, 24)}).ok());
    EXPECT_TRUE((*noMap)->map(0).empty());
}

// A NaN, a wrong size or a non-finite gaze is an error naming the eye; what was pooled stays.
TEST(PreviewLiveJod, BadFramesAreRefusedAndChangeNothing) {
    auto j = LiveJod::create(jodOptions(90, false));
    ASSERT_TRUE(j.ok());
    const cv::Mat ref = texture(3), test = blurredDisc(ref, {30, 20}, 12, 1.5);
    const std::array<glm::vec2, 2> gaze{glm::vec2(30, 20), glm::vec2(30, 20)};
    ASSERT_TRUE((*j)->push({test, test}, {ref, ref}, gaze).ok());
    const auto before = *(*j)->jod();

    cv::Mat nan = test.clone();
    nan.at<cv::Vec3f>(5, 7)[1] = std::numeric_limits<float>::quiet_NaN();
    Status s = (*j)->push({test, nan}, {ref, ref}, gaze);
    ASSERT_FALSE(s.ok());
    EXPECT_NE(s.message().find("eye 1"), std::string::npos) << s.message();
    cv::Mat small(10, 10, CV_32FC3, cv::Scalar::all(0.5));
    EXPECT_FALSE((*j)->push({test, test}, {small, ref}, gaze).ok());
    EXPECT_FALSE((*j)->push({test, test}, {ref, ref}, {glm::vec2(NAN, 1), gaze[1]}).ok());
    EXPECT_EQ((*j)->frames(), 1u);
    EXPECT_EQ(*(*j)->jod(), before);

    LiveJodOptions bad = jodOptions(90, false);
    bad.width = 4;
    auto refused = LiveJod::create(bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("live JOD"), std::string::npos);
    EXPECT_FALSE(LiveJod::create(jodOptions(0, false)).ok());
}
