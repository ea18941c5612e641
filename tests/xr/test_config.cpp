// The runtime's configuration: file, then environment over it; every bad value named with its key
// and where it came from (tests run without a GPU).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>

#include "compositor/host_app.h"
#include "xr_common/xr_config.h"
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"

namespace wrsfov::xr {
namespace {

struct Env {
    std::map<std::string, std::string> vars;
    std::function<const char*(const char*)> fn() const {
        return [this](const char* name) -> const char* {
            auto it = vars.find(name);
            return it == vars.end() ? nullptr : it->second.c_str();
        };
    }
};

std::string writeFile(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path) << text;
    return path;
}

TEST(XrConfig, DefaultsWithoutFileOrEnvironment) {
    Env env;
    auto c = loadRuntimeConfig(env.fn());
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->compositor.method, Method::Wrs);
    EXPECT_EQ(c->width, 1024u);
    EXPECT_EQ(c->displayHz, 90.0);
    EXPECT_TRUE(c->pace);
    EXPECT_EQ(c->gaze, GazeKind::Generator);
    EXPECT_EQ(c->gazeMode, gaze::Mode::Scene);
    EXPECT_EQ(c->output, Output::Auto);
    EXPECT_FLOAT_EQ(c->vergenceDistance_m, 1.5f);
    EXPECT_LT(c->fov[0].angleLeft, -c->fov[0].angleRight);  // the HMD's asymmetric field: wider temporally
}

TEST(XrConfig, FileThenEnvironment) {
    Env env;
    env.vars["WRSFOV_XR_CONFIG"] = writeFile("xr_ok.conf",
                                             "# a comment\n"
                                             "method = fov+taa   # trailing comment\n"
                                             "fovea=7.5\n\n"
                                             "width = 640\nheight = 480\n"
                                             "fov = 90\n"
                                             "pace = free\n"
                                             "head = turn\n"
                                             "gaze = file\ngaze_file = /tmp/g.csv\n"
                                             "output = headless\n");
    env.vars["WRSFOV_XR_WIDTH"] = "320";  // the environment wins
    env.vars["WRSFOV_XR_GAZE_MODE"] = "reading";
    auto c = loadRuntimeConfig(env.fn());
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_EQ(c->compositor.method, Method::FovTaa);
    EXPECT_FLOAT_EQ(c->compositor.foveaDeg, 7.5f);
    EXPECT_EQ(c->width, 320u);
    EXPECT_EQ(c->height, 480u);
    EXPECT_NEAR(c->fov[1].angleRight, 0.785398f, 1e-5f);
    EXPECT_FLOAT_EQ(c->fov[1].angleLeft, -c->fov[1].angleRight);
    EXPECT_FALSE(c->pace);
    EXPECT_EQ(c->head, scenes::CameraPath::Turn);
    EXPECT_EQ(c->gaze, GazeKind::File);
    EXPECT_EQ(c->gazeFile, "/tmp/g.csv");
    EXPECT_EQ(c->gazeMode, gaze::Mode::Reading);
    EXPECT_EQ(c->output, Output::Headless);
}

TEST(XrConfig, EveryBadValueNamesItsKeyAndSource) {
    struct Case {
        std::string key, value, expect;
    };
    const std::vector<Case> cases = {
        {"method", "oracle", "fov, fov+taa, wrs-paper, wrs or off"},
        {"method", "oracle-q", "fov, fov+taa, wrs-paper, wrs or off"},
        {"method", "magic", "'method' = 'magic'"},
        {"fovea", "0", "[0.5, 60]"},
        {"fovea", "nan", "[0.5, 60]"},
        {"foveation", "box", "none, mip or gauss"},
        {"width", "100.5", "integer in [16, 8192]"},
        {"height", "9000", "integer in [16, 8192]"},
        {"fov", "200", "hmd or"},
        {"ipd", "0.2", "metres"},
        {"display_hz", "inf", "[10, 240]"},
        {"pace", "fast", "realtime or free"},
        {"frames", "-1", "0: until the application exits"},
        {"head", "spin", "static, lateral, turn, yaw30, yaw60, yaw120 or look-around"},
        {"gaze", "eyes", "generator, file, hid, mouse or none"},
        {"gaze_mode", "stare", "fixation, scene, reading or pursuit"},
        {"gaze_seed", "x", "integer >= 0"},
        {"vergence_distance", "0", "metres"},
        {"output", "vr", "auto, window or headless"},
        {"validation", "maybe", "0 or 1"},
    };
    for (const Case& k : cases) {
        Env env;
        std::string var = "WRSFOV_XR_";
        for (char ch : k.key) var += char(std::toupper(static_cast<unsigned char>(ch)));
        env.vars[var] = k.value;
        auto c = loadRuntimeConfig(env.fn());
        ASSERT_FALSE(c) << k.key << " = " << k.value << " was accepted";
        EXPECT_NE(c.error().message.find(var), std::string::npos) << c.error().message;
        EXPECT_NE(c.error().message.find(k.expect), std::string::npos) << c.error().message;
    }
    Env file;
    file.vars["WRSFOV_XR_CONFIG"] = writeFile("xr_bad.conf", "method = wrs\n\nfoveation = box\n");
    auto c = loadRuntimeConfig(file.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("xr_bad.conf:3: 'foveation'"), std::string::npos) << c.error().message;
    file.vars["WRSFOV_XR_CONFIG"] = writeFile("xr_noeq.conf", "method wrs\n");
    c = loadRuntimeConfig(file.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("xr_noeq.conf:1: expected key = value"), std::string::npos);
    file.vars["WRSFOV_XR_CONFIG"] = writeFile("xr_unknown.conf", "colour = blue\n");
    c = loadRuntimeConfig(file.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("unknown key 'colour'"), std::string::npos);
    file.vars["WRSFOV_XR_CONFIG"] = ::testing::TempDir() + "no_such_dir/xr.conf";
    c = loadRuntimeConfig(file.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("cannot read"), std::string::npos);
    Env noFile;
    noFile.vars["WRSFOV_XR_GAZE"] = "file";
    c = loadRuntimeConfig(noFile.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("gaze_file"), std::string::npos);
}

// Quad views: on by default, withdrawn by quad_views = 0; the inset's size in degrees checked.
TEST(XrConfig, QuadViewKeys) {
    Env env;
    auto c = loadRuntimeConfig(env.fn());
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_TRUE(c->quadViews);
    EXPECT_FLOAT_EQ(c->insetDeg, 30.0f);
    env.vars["WRSFOV_XR_QUAD_VIEWS"] = "0";
    env.vars["WRSFOV_XR_INSET_DEG"] = "20";
    c = loadRuntimeConfig(env.fn());
    ASSERT_TRUE(c) << c.error().message;
    EXPECT_FALSE(c->quadViews);
    EXPECT_FLOAT_EQ(c->insetDeg, 20.0f);
    env.vars["WRSFOV_XR_INSET_DEG"] = "4";
    c = loadRuntimeConfig(env.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("WRSFOV_XR_INSET_DEG: 'inset_deg' = '4'"), std::string::npos) << c.error().message;
    env.vars["WRSFOV_XR_INSET_DEG"] = "30";
    env.vars["WRSFOV_XR_QUAD_VIEWS"] = "maybe";
    c = loadRuntimeConfig(env.fn());
    ASSERT_FALSE(c);
    EXPECT_NE(c.error().message.find("'quad_views' = 'maybe': expected 0 or 1"), std::string::npos)
        << c.error().message;
}

// The recommended sizes at the default 1024 x 1024 display over the HMD's 92 x 93 degrees: wide views
// at 1 / 2.5 of its density, a 30-degree inset at its density.
TEST(XrInset, RecommendedSizes) {
    RuntimeConfig c;
    c.fov[0] = hmdFov(0);
    c.fov[1] = hmdFov(1);
    const QuadViewSizes s = quadViewSizes(c);
    EXPECT_EQ(s.wide, glm::uvec2(410, 410));
    // 2 tan 15 deg = 0.5359 tangent units at 1024 / (tan 42 + tan 50) = 489.4 (across) and
    // 1024 / (tan 45 + tan 48) = 485.2 (down) pixels per unit.
    EXPECT_EQ(s.inset, glm::uvec2(262, 260));
    // Pixels per frame: both eyes' four views against stereo at the display's density.
    const double quad = 2.0 * (s.wide.x * s.wide.y + s.inset.x * s.inset.y), stereo = 2.0 * 1024 * 1024;
    EXPECT_NEAR(quad / stereo, 0.2253, 1e-3);
}

// The inset follows the gaze, stays inside its view at the edges, keeps its extent in tangent units
// (so its density), and is centred on the view (the compositor's fallback) without a gaze.
TEST(XrInset, PlacedOnTheGazeInsideTheView) {
    const layers::Fov view = hmdFov(0);
    const float tl = std::tan(view.angleLeft), tr = std::tan(view.angleRight), tu = std::tan(view.angleUp),
                td = std::tan(view.angleDown);
    const float h = std::tan(15.0f * 3.14159265f / 180.0f);
    auto check = [&](const layers::Fov& f, glm::vec2 centre) {
        EXPECT_GE(f.angleLeft, view.angleLeft);
        EXPECT_LE(f.angleRight, view.angleRight);
        EXPECT_LE(f.angleUp, view.angleUp);
        EXPECT_GE(f.angleDown, view.angleDown);
        EXPECT_NEAR(std::tan(f.angleRight) - std::tan(f.angleLeft), 2 * h, 1e-5);
        EXPECT_NEAR(std::tan(f.angleUp) - std::tan(f.angleDown), 2 * h, 1e-5);
        EXPECT_NEAR(0.5f * (std::tan(f.angleRight) + std::tan(f.angleLeft)), centre.x, 1e-5);
        EXPECT_NEAR(0.5f * (std::tan(f.angleUp) + std::tan(f.angleDown)), centre.y, 1e-5);
    };
    check(insetFov(view, 30.0f, std::nullopt), {0.5f * (tl + tr), 0.5f * (tu + td)});
    check(insetFov(view, 30.0f, glm::vec3(0.1f, -0.2f, -1.0f)), {0.1f, -0.2f});
    // Far right and up: shifted back inside, touching the edges.
    check(insetFov(view, 30.0f, glm::normalize(glm::vec3(3.0f, 2.0f, -1.0f))), {tr - h, tu - h});
    // Behind the eye: centred.
    check(insetFov(view, 30.0f, glm::vec3(0.0f, 0.0f, 1.0f)), {0.5f * (tl + tr), 0.5f * (tu + td)});
    // An inset wider than the view is the view.
    const layers::Fov all = insetFov(view, 120.0f, glm::vec3(0.3f, 0.0f, -1.0f));
    EXPECT_NEAR(std::tan(all.angleRight) - std::tan(all.angleLeft), tr - tl, 1e-5);
}

}  // namespace
}  // namespace wrsfov::xr

namespace wrsfov::xr {
namespace {

// xr::jitterOf: a submitted field of view that is the located one shifted by at most half a pixel is a
// jittered render (its shift is the sample offset); any other is composed as submitted.
TEST(XrJitter, ASubPixelShiftIsTheSampleOffsetAndNothingElseIs) {
    const layers::Fov located{-0.8f, 0.7f, 0.75f, -0.82f};
    constexpr uint32_t W = 640, H = 720;
    auto shifted = [&](double ox, double oy, double scaleX = 1.0) {
        const double l = std::tan(double(located.angleLeft)), r = std::tan(double(located.angleRight));
        const double u = std::tan(double(located.angleUp)), d = std::tan(double(located.angleDown));
        const double px = (r - l) / W, py = (u - d) / H;
        return layers::Fov{float(std::atan(l + ox * px)), float(std::atan(l + (r - l) * scaleX + ox * px)),
                           float(std::atan(u - oy * py)), float(std::atan(d - oy * py))};
    };
    for (auto [ox, oy] : {std::pair{0.25, -0.375}, std::pair{-0.5, 0.5}, std::pair{0.0, 0.1}, std::pair{0.4999, -0.0625}}) {
        const auto o = jitterOf(shifted(ox, oy), located, W, H);
        ASSERT_TRUE(o) << ox << ", " << oy;
        EXPECT_NEAR(o->x, ox, 2e-3) << "float angles: a few thousandths of a pixel at 640 px";
        EXPECT_NEAR(o->y, oy, 2e-3);
    }
    EXPECT_FALSE(jitterOf(located, located, W, H)) << "not jittered";
    EXPECT_FALSE(jitterOf(shifted(0.6, 0.0), located, W, H)) << "more than half a pixel";
    EXPECT_FALSE(jitterOf(shifted(0.0, -3.0), located, W, H)) << "a different view";
    EXPECT_FALSE(jitterOf(shifted(0.2, 0.0, 1.01), located, W, H)) << "a different size";
    layers::Fov bad = shifted(0.2, 0.1);
    bad.angleUp = std::numeric_limits<float>::quiet_NaN();
    EXPECT_FALSE(jitterOf(bad, located, W, H)) << "not finite";
    EXPECT_FALSE(jitterOf(shifted(0.2, 0.1), located, 0, H)) << "no image";
    // placeJitter: the located grid with the offset, or the view untouched.
    layers::ProjectionView v;
    v.fov = shifted(-0.3, 0.2);
    v.color.rect = {0, 0, W, H};
    EXPECT_TRUE(placeJitter(v, located));
    EXPECT_EQ(v.fov.angleLeft, located.angleLeft);
    EXPECT_NEAR(v.sampleOffset.x, -0.3f, 2e-3f);
    EXPECT_NEAR(v.sampleOffset.y, 0.2f, 2e-3f);
    layers::ProjectionView w;
    w.fov = shifted(0.0, 2.0);
    w.color.rect = {0, 0, W, H};
    const layers::Fov before = w.fov;
    EXPECT_FALSE(placeJitter(w, located));
    EXPECT_EQ(w.fov.angleUp, before.angleUp);
    EXPECT_EQ(w.sampleOffset, glm::vec2(0.0f));
}

}  // namespace
}  // namespace wrsfov::xr
