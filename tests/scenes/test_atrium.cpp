// The atrium scene: deterministic, and its motion vectors agree with the camera: reprojecting the
// previous frame's colour with them reproduces the current frame.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "scenes/atrium.h"
#include "scenes/png.h"
#include "scenes/text.h"
#include "../core/gpu_rig.h"

namespace wrsfov::test {
namespace {

struct Frame {
    HostImage color, depth, motion;
};

class Atrium : public GpuTest {
protected:
    void SetUp() override {
        GpuTest::SetUp();
        auto c = Compositor::create(context());
        ASSERT_TRUE(c.ok());
        comp = std::move(*c);
        HostStereoApp::Options o;
        o.width = W;
        o.height = H;
        o.depth = layers::Format::D32F;
        o.motion = layers::Format::RGBA16F;
        auto a = HostStereoApp::create(*comp, o);
        ASSERT_TRUE(a.ok());
        app = std::move(*a);
    }
    // Renders eye `eye` at t (previous time prevT) and reads the three images back.
    // footprint != 1: renderViews through the renderer's own views with that material footprint.
    Frame render(scenes::AtriumRenderer& r, double t, double prevT, uint32_t eye, float footprint = 1.0f) {
        layers::Swapchain* sc[3] = {&app->color(), app->depth(), app->motion()};
        uint32_t idx[3];
        for (int i = 0; i < 3; ++i) {
            idx[i] = *sc[i]->acquire();
            EXPECT_TRUE(sc[i]->wait().ok());
        }
        Status s = footprint == 1.0f
                       ? r.render(t, prevT, *sc[0], idx[0], *sc[1], idx[1], *sc[2], idx[2])
                       : r.renderViews(t, prevT, {scenes::atriumFov(r.options(), 0), scenes::atriumFov(r.options(), 1)},
                                       *sc[0], idx[0], *sc[1], idx[1], *sc[2], idx[2], footprint);
        EXPECT_TRUE(s.ok()) << s.message();
        Frame f;
        HostImage* out[3] = {&f.color, &f.depth, &f.motion};
        layers::Format fmt[3] = {layers::Format::RGBA8_SRGB, layers::Format::D32F, layers::Format::RGBA16F};
        for (int i = 0; i < 3; ++i) {
            *out[i] = HostImage::make(fmt[i], W, H);
            auto bytes = sc[i]->read(idx[i], eye);
            EXPECT_TRUE(bytes.ok());
            if (bytes.ok()) out[i]->data = *bytes;
            EXPECT_TRUE(sc[i]->release().ok());
        }
        return f;
    }
    static constexpr uint32_t W = 160, H = 144;
    std::unique_ptr<Compositor> comp;
    std::unique_ptr<HostStereoApp> app;
};

TEST_F(Atrium, Deterministic) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.dynamic = true;
    auto r = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    Frame a = render(**r, 0.4, 0.4 - 1 / 90.0, 0);
    Frame b = render(**r, 0.4, 0.4 - 1 / 90.0, 0);
    EXPECT_EQ(a.color.data, b.color.data);
    if (const char* dir = std::getenv("WRSFOV_TEST_PNG")) (void)writePng(a.color, std::string(dir) + "/atrium.png");
    EXPECT_EQ(a.motion.data, b.motion.data);
    // Something is drawn everywhere (no clear colour left), depth inside (0, 1).
    uint64_t cleared = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            float d = a.depth.fetch(x, y).x;
            cleared += d >= 1.0f;
            EXPECT_GT(d, 0.0f);
        }
    EXPECT_EQ(cleared, 0u);
}

float cur_depth(const HostImage& depth, uint32_t x, uint32_t y) { return depth.fetch(x, y).x; }

// Reprojection error: mean |current - previous(p + mv)| over pixels, in sRGB 8-bit units.
double reprojectionError(const Frame& prev, const Frame& cur, bool useMotion) {
    double sum = 0;
    uint64_t n = 0;
    for (uint32_t y = 2; y + 2 < cur.color.height; ++y)
        for (uint32_t x = 2; x + 2 < cur.color.width; ++x) {
            glm::vec4 mv = useMotion ? cur.motion.fetch(x, y) : glm::vec4(0.0f);
            float px = float(x) + mv.x, py = float(y) + mv.y;
            int qx = int(std::lround(px)), qy = int(std::lround(py));
            if (qx < 0 || qy < 0 || qx >= int(cur.color.width) || qy >= int(cur.color.height)) continue;
            glm::vec4 a = cur.color.fetch(x, y), b = prev.color.fetch(uint32_t(qx), uint32_t(qy));
            sum += (std::fabs(a.x - b.x) + std::fabs(a.y - b.y) + std::fabs(a.z - b.z)) / 3.0 * 255.0;
            n++;
        }
    return sum / double(std::max<uint64_t>(n, 1));
}

TEST_F(Atrium, MotionVectorsMatchCameraReprojection) {
    struct Case {
        scenes::CameraPath path;
        bool monitor;
        bool thin = false;
    };
    for (Case c : {Case{scenes::CameraPath::Lateral, false}, Case{scenes::CameraPath::Turn, false},
                   Case{scenes::CameraPath::Yaw120, false}, Case{scenes::CameraPath::Lateral, true},
                   Case{scenes::CameraPath::Yaw30, false, true}}) {
        const scenes::CameraPath path = c.path;
        scenes::AtriumOptions o;
        o.width = W;
        o.height = H;
        o.path = path;
        o.monitor = c.monitor;
        o.thin = c.thin;
        auto r = scenes::AtriumRenderer::create(context(), o);
        ASSERT_TRUE(r.ok());
        const double dt = 4.0 / 90.0;  // a few frames apart, so the motion is several pixels
        const double t1 = 0.05;  // both paths move fastest around t = 0
        for (uint32_t eye = 0; eye < 2; ++eye) {
            Frame prev = render(**r, t1 - dt, t1 - 2 * dt, eye);
            Frame cur = render(**r, t1, t1 - dt, eye);
            double withMv = reprojectionError(prev, cur, true);
            double without = reprojectionError(prev, cur, false);
            // Largest motion in the frame, to be sure it is not trivially small.
            float maxMv = 0;
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) maxMv = std::max(maxMv, glm::length(glm::vec2(cur.motion.fetch(x, y))));
            std::printf("path %d%s%s eye %u: max |mv| %.2f px, reprojection error %.2f with motion, %.2f without\n",
                        int(path), c.monitor ? " (monitor)" : "", c.thin ? " (thin)" : "", eye, maxMv, withMv, without);
            EXPECT_GT(maxMv, c.monitor ? 1.0f : 1.5f);  // the monitor view sees less of the near walls
            // Colour reprojection is limited by the aliasing of the high-frequency materials; it must
            // still be clearly better with the motion vectors than without.
            EXPECT_LT(withMv, 0.8 * without);

            // Geometric check: unproject each pixel with its depth through this frame's camera,
            // project it with the previous frame's camera: that displacement is the motion vector.
            glm::mat4 proj = scenes::projection(scenes::atriumFov(o, int(eye)), o.nearZ, o.farZ, o.reversedZ);
            glm::mat4 curVp = proj * scenes::atriumView(o, int(eye), t1);
            glm::mat4 prevVp = proj * scenes::atriumView(o, int(eye), t1 - dt);
            glm::mat4 inv = glm::inverse(curVp);
            float worst = 0;
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    glm::vec2 ndc((float(x) + 0.5f) / W * 2 - 1, (float(y) + 0.5f) / H * 2 - 1);
                    glm::vec4 world = inv * glm::vec4(ndc, cur_depth(cur.depth, x, y), 1.0f);
                    world /= world.w;
                    glm::vec4 pc = prevVp * world;
                    glm::vec2 prevPx = (glm::vec2(pc) / pc.w * 0.5f + 0.5f) * glm::vec2(W, H);
                    glm::vec2 expect = prevPx - glm::vec2(float(x) + 0.5f, float(y) + 0.5f);
                    worst = std::max(worst, glm::length(expect - glm::vec2(cur.motion.fetch(x, y))));
                }
            std::printf("  worst |mv - camera reprojection| = %.4f px\n", worst);
            EXPECT_LT(worst, 0.05f);
        }
    }
}

// Monitor mode: one symmetric 76° x 60° view submitted as both eyes, so both images are the same.
TEST_F(Atrium, MonitorModeShowsOneViewToBothEyes) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.monitor = true;
    const layers::Fov f = scenes::atriumFov(o, 0);
    EXPECT_NEAR((f.angleRight - f.angleLeft) * 180.0 / 3.14159265358979, 76.0, 1e-4);
    EXPECT_NEAR((f.angleUp - f.angleDown) * 180.0 / 3.14159265358979, 60.0, 1e-4);
    EXPECT_FLOAT_EQ(f.angleLeft, -f.angleRight);
    auto r = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(r.ok());
    Frame left = render(**r, 0.5, 0.5 - 1 / 90.0, 0);
    Frame right = render(**r, 0.5, 0.5 - 1 / 90.0, 1);
    EXPECT_EQ(left.color.data, right.color.data);
    EXPECT_EQ(left.depth.data, right.depth.data);
    // The stereo camera, by contrast, sees the room from two places.
    o.monitor = false;
    auto rs = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(rs.ok());
    EXPECT_NE(render(**rs, 0.5, 0.5 - 1 / 90.0, 0).color.data, render(**rs, 0.5, 0.5 - 1 / 90.0, 1).color.data);
}

// The `thin` scene: the room with railings, cables and cut-out foliage in front of it, and highlights on
// the glossy floor. Where it shows the room (the same depth as the atrium's), the floor is lit as in the
// atrium plus a specular term, never darker; the thin geometry covers a part of the view and the cut-outs
// leave holes (the foliage's panels show both leaves and the room through them).
TEST_F(Atrium, ThinSceneAddsThinGeometryAndHighlights) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.path = scenes::CameraPath::Static;
    auto plain = scenes::AtriumRenderer::create(context(), o);
    o.thin = true;
    auto thin = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(plain.ok() && thin.ok());
    const Frame a = render(**plain, 0.5, 0.5, 0), b = render(**thin, 0.5, 0.5, 0);
    uint64_t nearer = 0, same = 0, brighter = 0, darker = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const float da = a.depth.fetch(x, y).x, db = b.depth.fetch(x, y).x;
            if (db < da - 1e-6f) {
                ++nearer;
                continue;
            }
            ASSERT_LE(std::fabs(db - da), 1e-6f) << "the thin scene hides nothing behind the room: " << x << "," << y;
            ++same;
            const glm::vec4 ca = a.color.fetch(x, y), cb = b.color.fetch(x, y);
            const float d = (cb.x + cb.y + cb.z - ca.x - ca.y - ca.z) / 3.0f;
            darker += d < -1.5f / 255.0f;
            brighter += d > 0.1f;
        }
    std::printf("thin: %.1f %% of the pixels nearer (thin geometry), %.1f %% of the room brighter by > 0.1 (highlights)\n",
                100.0 * double(nearer) / double(W * H), 100.0 * double(brighter) / double(same));
    EXPECT_GT(nearer, W * H / 50);   // railings, cables and leaves cover more than 2 % of the view
    EXPECT_LT(nearer, W * H / 2);    // and the cut-outs let the room through
    EXPECT_EQ(darker, 0u);           // the specular term only adds light
    EXPECT_GT(brighter, same / 500);  // highlights on the floor
}

// The look-around path: the gaze in the world (the head's yaw plus where the eye looks in the head)
// lands on each target after its saccade and stays there while the head turns (the eye counter-rotates),
// the head turns through 85 % of each shift at up to headDegPerS, and the eye stays within ±35°.
TEST(CameraPaths, LookAroundHeadFollowsTheGazeShifts) {
    const scenes::CameraPath p = scenes::CameraPath::LookAround;
    EXPECT_EQ(scenes::parseCameraPath("look-around"), p);
    EXPECT_EQ(scenes::toString(p), "look-around");
    const double peak = scenes::headDegPerS(p);
    EXPECT_NEAR(peak, 1.875 * 42.5 / (0.15 + 42.5 / 150.0), 1e-6);  // the 50° shift's turn
    constexpr double kDeg = 180.0 / 3.14159265358979;
    auto worldGaze = [&](double t) { return scenes::headPose(p, t).yaw * kDeg + scenes::lookAroundGaze(t).azimuthDeg; };
    double fastest = 0, widest = 0;
    for (double t = 0; t < 6.0; t += 0.001) {
        const double v = std::abs(scenes::headPose(p, t + 0.001).yaw - scenes::headPose(p, t).yaw) * kDeg / 0.001;
        fastest = std::max(fastest, v);
        widest = std::max(widest, double(std::abs(scenes::lookAroundGaze(t).azimuthDeg)));
    }
    EXPECT_NEAR(fastest, peak, 0.01 * peak);
    EXPECT_LE(widest, 35.0 + 1e-4);
    EXPECT_GT(widest, 20.0);  // the eye leads each large shift
    // Each shift: from 0.2 s every 0.6 s. 0.2 s after its onset the saccade has landed and the head is
    // still turning, yet the gaze in the world holds the target; by the next shift the head has arrived.
    const double targets[] = {30, -15, 25, -25, 5, -10, 30};
    for (int k = 0; k < 7; ++k) {
        const double t0 = 0.2 + 0.6 * k;
        EXPECT_NEAR(worldGaze(t0 + 0.2), targets[k], 1e-3) << "shift " << k;
        EXPECT_NEAR(worldGaze(t0 + 0.4), targets[k], 1e-3) << "shift " << k;
        const double headMid = scenes::headPose(p, t0 + 0.2).yaw * kDeg;
        const double from = k == 0 ? 0.0 : 0.85 * targets[k - 1];
        EXPECT_GT(std::abs(headMid - from), 1.0) << "the head is turning at shift " << k;
        EXPECT_LT(std::abs(headMid - 0.85 * targets[k]), std::abs(from - 0.85 * targets[k])) << "shift " << k;
        EXPECT_NEAR(scenes::headPose(p, t0 + 0.59).yaw * kDeg, 0.85 * targets[k], 1e-3) << "shift " << k;
    }
}

TEST_F(Atrium, StaticCameraHasZeroMotion) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.path = scenes::CameraPath::Static;
    auto r = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(r.ok());
    Frame f = render(**r, 1.0, 1.0 - 1 / 90.0, 1);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            glm::vec4 mv = f.motion.fetch(x, y);
            // Exactly zero: a retention rule takes any non-zero vector as motion.
            ASSERT_EQ(mv.x, 0.0f) << x << "," << y;
            ASSERT_EQ(mv.y, 0.0f) << x << "," << y;
            ASSERT_LT(std::fabs(mv.z), 1e-3f);
        }
}

// Filtered materials (four shading samples per pixel, the default) against point-sampled ones: the
// same geometry (depth and motion bit for bit), about the same mean colour, much less contrast between
// neighbouring pixels (the stripes and checker edges alias when point-sampled); 2 samples is refused.
TEST_F(Atrium, FilteredMaterialsRemovePixelScaleAliasing) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.monitor = true;
    Frame f[2];
    for (int i = 0; i < 2; ++i) {
        o.materialSamples = i == 0 ? 1u : 4u;
        auto r = scenes::AtriumRenderer::create(context(), o);
        ASSERT_TRUE(r.ok()) << r.error().message;
        f[i] = render(**r, 0.5, 0.5 - 1 / 90.0, 0);
    }
    EXPECT_EQ(f[0].depth.data, f[1].depth.data);
    EXPECT_EQ(f[0].motion.data, f[1].motion.data);
    double mean[2] = {0, 0}, step[2] = {0, 0};
    for (int i = 0; i < 2; ++i) {
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                glm::vec4 c = f[i].color.fetch(x, y);
                mean[i] += (c.x + c.y + c.z) / 3.0;
                if (x + 1 < W) {
                    glm::vec4 n = f[i].color.fetch(x + 1, y);
                    step[i] += (std::fabs(c.x - n.x) + std::fabs(c.y - n.y) + std::fabs(c.z - n.z)) / 3.0;
                }
            }
        mean[i] /= double(W) * H;
        step[i] /= double(W - 1) * H;
    }
    std::printf("mean sRGB %.4f point-sampled, %.4f filtered; mean |step| %.4f, %.4f\n", mean[0], mean[1], step[0],
                step[1]);
    // sRGB means: averaging in linear colour brightens mixed pixels a little.
    EXPECT_NEAR(mean[1], mean[0], 0.03);
    EXPECT_LT(step[1], 0.8 * step[0]);
    o.materialSamples = 2;
    auto bad = scenes::AtriumRenderer::create(context(), o);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("material samples"), std::string::npos) << bad.error().message;
}

// Mean |difference| of horizontally adjacent pixels of an sRGB image (its pixel-scale contrast).
double meanStep(const HostImage& img) {
    double step = 0;
    for (uint32_t y = 0; y < img.height; ++y)
        for (uint32_t x = 0; x + 1 < img.width; ++x) {
            const glm::vec4 c = img.fetch(x, y), n = img.fetch(x + 1, y);
            step += (std::fabs(c.x - n.x) + std::fabs(c.y - n.y) + std::fabs(c.z - n.z)) / 3.0;
        }
    return step / (double(img.width - 1) * img.height);
}

// A view rendered for temporal upsampling samples its materials at the display's density (renderViews'
// footprint, the wide view's density over the display's): the same geometry, sharper materials (more
// pixel-scale contrast, towards the point-sampled scene's) than the same view filtered over its own
// pixels.
TEST_F(Atrium, AFootprintBelowOneSamplesMaterialsAtTheDisplaysDensity) {
    scenes::AtriumOptions o;
    o.width = W;
    o.height = H;
    o.monitor = true;
    auto r = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Frame own = render(**r, 0.5, 0.5 - 1 / 90.0, 0);
    const Frame display = render(**r, 0.5, 0.5 - 1 / 90.0, 0, 0.4f);
    EXPECT_EQ(own.depth.data, display.depth.data);
    EXPECT_EQ(own.motion.data, display.motion.data);
    const double a = meanStep(own.color), b = meanStep(display.color);
    std::printf("mean |step| %.4f over the view's pixel, %.4f over 0.4 of it\n", a, b);
    EXPECT_GT(b, 1.1 * a);
}

// The text page's footprint likewise: 1 is the page as before, bit for bit; 0.4 is sharper.
TEST(TextScene, AFootprintBelowOneSamplesThePageAtTheDisplaysDensity) {
    scenes::TextOptions o;
    o.width = 384;
    o.height = 320;
    scenes::TextScene page(o);
    const std::array<layers::Fov, 2> fovs{scenes::textFov(o, 0), scenes::textFov(o, 1)};
    std::array<HostImage, 2> c1, d1, c4, d4;
    page.renderViews(fovs, 154, 128, c1, d1);  // a wide view at 0.4 of the display's density
    std::array<HostImage, 2> same, sameDepth;
    page.renderViews(fovs, 154, 128, same, sameDepth, 1.0f);
    EXPECT_EQ(c1[0].data, same[0].data);
    page.renderViews(fovs, 154, 128, c4, d4, 0.4f);
    EXPECT_EQ(d1[0].data, d4[0].data);
    const double a = meanStep(c1[0]), b = meanStep(c4[0]);
    std::printf("text: mean |step| %.4f over the view's pixel, %.4f over 0.4 of it\n", a, b);
    // The page is drawn bilinearly from a texture at about the display's density: its four subsamples
    // over 0.4 of the pixel add less contrast than the atrium's procedural materials (0.0240 against 0.0225).
    EXPECT_GT(b, 1.04 * a);
}

TEST_F(Atrium, RejectsWrongSwapchains) {
    scenes::AtriumOptions o;
    o.width = W + 1;  // does not match the swapchains
    o.height = H;
    auto r = scenes::AtriumRenderer::create(context(), o);
    ASSERT_TRUE(r.ok());
    layers::Swapchain* sc[3] = {&app->color(), app->depth(), app->motion()};
    uint32_t idx[3];
    for (int i = 0; i < 3; ++i) {
        idx[i] = *sc[i]->acquire();
        ASSERT_TRUE(sc[i]->wait().ok());
    }
    Status s = (*r)->render(0.0, 0.0, *sc[0], idx[0], *sc[1], idx[1], *sc[2], idx[2]);
    EXPECT_FALSE(s.ok());
    EXPECT_NE(s.message().find("swapchains must be"), std::string::npos) << s.message();
    s = (*r)->render(0.0, 0.0, *sc[1], idx[1], *sc[0], idx[0], *sc[2], idx[2]);
    EXPECT_FALSE(s.ok());
    for (int i = 0; i < 3; ++i) EXPECT_TRUE(sc[i]->release().ok());
}

}  // namespace
}  // namespace wrsfov::test


namespace wrsfov::test {
namespace {

TEST(TextScene, DeterministicStereoPageWithTextAtTheStatedSize) {
    scenes::TextOptions o;
    o.width = 384;
    o.height = 320;
    scenes::TextScene a(o), b(o);
    scenes::TextOptions m = o;  // monitor mode at ~10 px/deg: glyphs resolved
    m.monitor = true;
    m.width = 768;
    m.height = 608;
    scenes::TextScene mon(m);
    EXPECT_EQ(a.color(0).data, b.color(0).data);
    EXPECT_EQ(a.color(1).data, b.color(1).data);
    // Stereo: the eyes see the page from different places.
    EXPECT_NE(a.color(0).data, a.color(1).data);
    if (const char* dir = std::getenv("WRSFOV_TEST_PNG")) {
        (void)writePng(a.color(0), std::string(dir) + "/text_L.png");
        (void)writePng(mon.color(0), std::string(dir) + "/text_monitor.png");
    }
    EXPECT_EQ(mon.color(0).data, mon.color(1).data);  // monitor mode: one view for both eyes
    // The reading block (black glyphs) is darker on average than the grey nonsense text beside it
    // at the same elevations, and it ends at the stated ±20°.
    const scenes::TextLayout& L = o.layout;
    auto darkFraction = [&](float azFrom, float azTo, float el0, float el1) {
        double dark = 0;
        uint64_t n = 0;
        layers::Fov f = scenes::textFov(m, 0);
        for (uint32_t y = 0; y < m.height; ++y)
            for (uint32_t x = 0; x < m.width; ++x) {
                glm::vec3 r = pixelDirection(f, m.width, m.height, float(x), float(y));
                float az = std::atan2(r.x, -r.z) * 57.29578f, el = std::atan2(r.y, -r.z) * 57.29578f;
                if (az < azFrom || az > azTo || el < el0 || el > el1) continue;
                n++;
                dark += 1.0 - mon.color(0).fetch(x, y).x;
            }
        return n ? double(dark) / double(n) : 0.0;
    };
    float top = float(L.lineCentreDeg(0)), bottom = float(L.lineCentreDeg(L.lines - 1));
    double inside = darkFraction(-18, 18, bottom, top);
    double outside = darkFraction(22, 36, bottom, top);
    // Darkness the ink adds over the blank page (sRGB 238/255).
    const double paper = 1.0 - 238.0 / 255.0;
    std::printf("ink darkness: %.4f inside the reading block, %.4f beside it (freetype %d)\n", inside - paper,
                outside - paper, mon.usedFreeType());
    EXPECT_GT(inside - paper, 0.02);
    EXPECT_GT(inside - paper, 1.5 * (outside - paper));
    // Depth is the page plane: constant, inside (0, 1).
    float d0 = a.depth(0).fetch(0, 0).x;
    EXPECT_GT(d0, 0.0f);
    EXPECT_LT(d0, 1.0f);
    EXPECT_EQ(a.depth(1).fetch(o.width - 1, o.height - 1).x, d0);
}

}  // namespace
}  // namespace wrsfov::test
