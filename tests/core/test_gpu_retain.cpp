// Behaviour of method `wrs` (quality-aware retention) on the GPU, on scenes where the right answer
// is known: after the gaze leaves a textured spot, wrs keeps the sharp samples there while fov and
// the published rule (wrs-paper) show the blurred periphery; a real change (lighting) replaces them
// at once; kept samples follow sub-pixel motion; poisoned inputs never reach a reservoir; and the
// birth colours the bench uses to find stale pixels say "not stale" on a static scene and "stale"
// where a shown sample's scene changed. Every frame is also checked against the CPU reference.
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

constexpr uint32_t W = 160, H = 120;

layers::Fov fov() { return layers::Fov{std::atan(-0.8f), std::atan(0.8f), std::atan(0.6f), std::atan(-0.6f)}; }
glm::vec3 gazeAtPixel(double x, double y) { return test::gazeAtPixel(x, y, W, H, fov()); }
HostImage texture(float sx, float sy, float brightness) { return fineTexture(W, H, sx, sy, brightness); }

// A W x H app with RGBA16F colour and the given depth and motion formats.
HostStereoApp::Options appOptions(layers::Format depth, std::optional<layers::Format> motion) {
    HostStereoApp::Options o;
    o.width = W;
    o.height = H;
    o.color = layers::Format::RGBA16F;
    o.depth = depth;
    o.motion = motion;
    return o;
}

HostImage motionImage(float mx, float my) { return uniformMotion(W, H, mx, my); }

// sRGB MSE of an output against the reference over a disc (radius r pixels) around (cx, cy).
double discMse(const HostImage& a, const HostImage& b, float cx, float cy, float r) {
    double se = 0;
    int n = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            if ((x + 0.5f - cx) * (x + 0.5f - cx) + (y + 0.5f - cy) * (y + 0.5f - cy) > r * r) continue;
            for (int c = 0; c < 3; ++c) {
                double d = (int(uint8_t(a.data[(y * W + x) * 4 + c])) - int(uint8_t(b.data[(y * W + x) * 4 + c]))) / 255.0;
                se += d * d;
            }
            n += 3;
        }
    return se / std::max(1, n);
}

class Retain : public GpuTest {
protected:
    struct Lane {
        std::unique_ptr<Compositor> comp;
        std::unique_ptr<StereoApp> app;
        std::unique_ptr<Reference> ref;  // stepped from the GPU history every frame (wrs only)
        StepTally tally;
    };
    Lane lane(Method m, FoveationMode mode = FoveationMode::Mip, bool motion = false, bool birth = false) {
        CompositorConfig cfg;
        cfg.method = m;
        cfg.foveation = mode;
        cfg.foveaDeg = 5.0f;
        cfg.seed = 21;
        cfg.trackBirth = birth;
        Lane l;
        auto c = Compositor::create(context(), cfg);
        EXPECT_TRUE(c.ok());
        l.comp = std::move(*c);
        l.app = std::make_unique<StereoApp>(*l.comp, W, H, layers::Format::RGBA16F, std::nullopt,
                                            motion ? std::optional(layers::Format::RG16F) : std::nullopt);
        l.ref = std::make_unique<Reference>(cfg);
        return l;
    }
    std::array<EyeFrame, 2> frame(const HostImage& color, glm::vec3 gaze, const std::optional<HostImage>& motion = {}) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = fov();
            eyes[e].color = color;
            eyes[e].motion = motion;
            eyes[e].gaze = {gaze, true, 1.0f};
        }
        return eyes;
    }
    // One frame on every lane; the retention lanes are compared with the CPU reference.
    void step(std::vector<Lane*> lanes, uint64_t index, const std::array<EyeFrame, 2>& eyes) {
        for (Lane* l : lanes) {
            const Method m = l->comp->config().method;
            if (usesRetainPass(m)) {
                std::vector<glm::uvec4> prev[2];
                if (index > 1)
                    for (uint32_t e = 0; e < 2; ++e) {
                        prev[e] = *l->comp->readReservoirs(e);
                        l->ref->setHistory(e, prev[e], *l->comp->readTileHeld(e));
                        l->ref->setSteadyFloor(e, *l->comp->readSteadyFloor(e));
                    }
                ASSERT_TRUE(l->app->submit(index, eyes).ok());
                l->ref->step(l->comp->lastParams(), referenceInputs(eyes));
                for (uint32_t e = 0; e < 2; ++e) {
                    auto out = l->comp->readOutput(e);
                    ASSERT_TRUE(out.ok());
                    for (std::size_t i = 0; i < out->data.size(); ++i)
                        ASSERT_LE(std::abs(int(uint8_t(out->data[i])) - int(uint8_t(l->ref->output(e).data[i]))), 1)
                            << "frame " << index << " eye " << e << " byte " << i;
                }
            } else {
                ASSERT_TRUE(l->app->submit(index, eyes).ok());
            }
        }
    }
    HostImage out(Lane& l) { return *l.comp->readOutput(0); }
};

TEST_F(Retain, KeepsFovealSamplesAfterTheGazeLeavesAndDropsThemOnALightChange) {
    Lane fov = lane(Method::Fov), paper = lane(Method::WrsPaper), wrs = lane(Method::Wrs), reference = lane(Method::Fov, FoveationMode::None);
    std::vector<Lane*> all{&reference, &fov, &paper, &wrs};
    const HostImage tex = texture(0, 0, 1.0f);
    const float ax = 50, ay = 60, bx = 120, by = 60;  // fixate A (30 frames), then B, 35° apart
    uint64_t f = 1;
    for (; f <= 30; ++f) step(all, f, frame(tex, gazeAtPixel(ax, ay)));
    for (; f <= 60; ++f) step(all, f, frame(tex, gazeAtPixel(bx, by)));
    const HostImage r = out(reference);
    // Within 4 px (2°) of A: inside the 5° fovea during the fixation.
    const double eFov = discMse(out(fov), r, ax, ay, 4), ePaper = discMse(out(paper), r, ax, ay, 4),
                 eWrs = discMse(out(wrs), r, ax, ay, 4);
    std::printf("around the point left 30 frames ago: MSE fov %.5f, wrs-paper %.5f, wrs %.5f\n", eFov, ePaper, eWrs);
    // The spot is 40° in the periphery now: fov shows 16x16 blur there, wrs the samples from the fixation.
    EXPECT_GT(eFov, 0.005);
    EXPECT_LT(eWrs, eFov * 0.05);
    // The published rule keeps them only by chance (eq. 6 alone gives up a sample within ~0.25 s).
    EXPECT_GT(ePaper, eWrs * 2.0);

    // The light dims to 60 %: a change, not a shading-rate reduction, so the kept samples go.
    const HostImage dim = texture(0, 0, 0.6f);
    step(all, f++, frame(dim, gazeAtPixel(bx, by)));
    const HostImage rd = out(reference);
    const double eFovDim = discMse(out(fov), rd, ax, ay, 4), eWrsDim = discMse(out(wrs), rd, ax, ay, 4);
    std::printf("after the light change: MSE fov %.5f, wrs %.5f\n", eFovDim, eWrsDim);
    EXPECT_LE(eWrsDim, eFovDim * 1.05);  // no stale bright samples
}

TEST_F(Retain, KeptSamplesFollowSubPixelMotion) {
    // The texture drifts by (0.37, 0.21) px per frame with exact motion vectors. With nearest-pixel
    // reprojection a kept sample would slide by up to half a pixel per frame; tracked, it stays on
    // its content and the spot left behind stays sharp.
    Lane fov = lane(Method::Fov, FoveationMode::Mip, true), wrs = lane(Method::Wrs, FoveationMode::Mip, true),
         reference = lane(Method::Fov, FoveationMode::None, true);
    std::vector<Lane*> all{&reference, &fov, &wrs};
    const glm::vec2 v(0.37f, 0.21f);
    const float ax = 50, ay = 60;
    uint64_t f = 1;
    for (; f <= 60; ++f) {
        const glm::vec2 s = v * float(f);
        const glm::vec3 g = f <= 30 ? gazeAtPixel(ax + s.x, ay + s.y) : gazeAtPixel(130, 60);
        step(all, f, frame(texture(s.x, s.y, 1.0f), g, motionImage(-v.x, -v.y)));
    }
    const glm::vec2 s = v * 60.0f;
    const HostImage r = out(reference);
    const double eFov = discMse(out(fov), r, ax + s.x, ay + s.y, 3), eWrs = discMse(out(wrs), r, ax + s.x, ay + s.y, 3);
    std::printf("moving texture, spot left 30 frames ago: MSE fov %.5f, wrs %.5f\n", eFov, eWrs);
    // Measured 0.42x (0.39x before gaps between kept samples showed the kept neighbourhood rather than
    // the blurred candidate, wrs_track_gap; 0.42x before kept samples were shown as the tent mean of
    // their neighbours, wrs_shown_add): tracking keeps most samples, but where neighbouring samples'
    // offsets differ (left behind by the fovea's merges and refreshes) a footprint can receive two
    // samples and its neighbour none; the gap shows an interpolation across it, which on this 1-2 px
    // pattern is no closer than the blurred candidate (docs/retention.md, "Limits").
    EXPECT_LT(eWrs, eFov * 0.5);
}

TEST_F(Retain, AGapBetweenKeptSamplesShowsThemNotTheCandidate) {
    // Kept full-rate samples in every pixel of a band, all at their pixel centres but for column 20,
    // whose sample sits half a pixel left, and column 21, whose sits 0.13 px right: under a uniform
    // pan of 0.37 px the centre of column 20 falls between the two, 0.87 and 0.76 px from them, and its
    // lookup finds nothing within reach (docs/retention.md "Natural texture in motion"). It shows the
    // tent mean of the two kept samples, not its blurred candidate (which it stores), on the GPU as
    // in the CPU reference.
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok());
    StereoApp app(**comp, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
    const float grey = 0.4f;
    HostImage flat = HostImage::make(layers::Format::RGBA16F, W, H);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) flat.store(x, y, glm::vec4(grey, grey, grey, 1.0f));
    auto frameWith = [&](const HostImage& motion) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = fov();
            eyes[e].color = flat;
            eyes[e].motion = motion;
            eyes[e].gaze = {gazeAtPixel(140, 100), true, 1.0f};  // far from the band: blurred candidates
        }
        return eyes;
    };
    ASSERT_TRUE(app.submit(1, frameWith(motionImage(0.0f, 0.0f))).ok());
    // The band's kept samples: full rate, alternating 0.1 / 0.7 by column, the fingerprint of the grey.
    const float lstar = gpu::wrs_linear_to_lab(glm::vec3(grey)).x;
    std::vector<glm::uvec4> packed = *(*comp)->readReservoirs(0);
    for (uint32_t y = 10; y < 40; ++y)
        for (uint32_t x = 4; x < 60; ++x) {
            gpu::Tracked t;
            t.color = glm::vec3(x % 2 == 0 ? 0.1f : 0.7f);
            t.q = 1.0f;
            t.w_sum = 1.0f;
            t.fp = gpu::wrs_fp_value(gpu::wrs_fp_code(lstar));
            t.flags = gpu::WRS_FLAG_MOVED;
            t.z = 0.0f;
            t.d = x == 20 ? glm::vec2(-0.5f, 0.0f) : x == 21 ? glm::vec2(0.13f, 0.0f) : glm::vec2(0.0f);
            packed[std::size_t(y) * W + x] = gpu::wrs_pack_tracked(t, glm::vec2(0.5f));
        }
    Reference ref(cfg);
    for (uint32_t e = 0; e < 2; ++e) {
        ASSERT_TRUE((*comp)->writeReservoirs(e, packed).ok());
        ref.setHistory(e, packed);
        ref.setSteadyFloor(e, *(*comp)->readSteadyFloor(e));
    }
    const auto eyes = frameWith(motionImage(0.37f, 0.0f));
    ASSERT_TRUE(app.submit(2, eyes).ok());
    ref.step((*comp)->lastParams(), referenceInputs(eyes));
    auto outGpu = (*comp)->readOutput(0);
    ASSERT_TRUE(outGpu.ok());
    const HostImage& outCpu = ref.output(0);
    int maxDiff = 0, gaps = 0;
    for (std::size_t i = 0; i < outGpu->data.size(); ++i)
        maxDiff = std::max(maxDiff, std::abs(int(uint8_t(outGpu->data[i])) - int(uint8_t(outCpu.data[i]))));
    EXPECT_LE(maxDiff, 1) << "GPU against the CPU reference";
    const uint8_t candidate = uint8_t(std::lround(255.0f * gpu::wrs_linear_to_srgb(grey)));
    // Tent weights 1 - 0.87 and 1 - 0.76 of the samples either side (0.1 and 0.7).
    const float w0 = 1.0f - 0.8701172f, w1 = 1.0f - 0.7599f;
    const uint8_t expected = uint8_t(std::lround(255.0f * gpu::wrs_linear_to_srgb((0.1f * w0 + 0.7f * w1) / (w0 + w1))));
    for (uint32_t y = 12; y < 38; ++y) {
        const uint8_t shown = uint8_t(outGpu->data[(std::size_t(y) * W + 20) * 4]);
        EXPECT_NE(shown, candidate) << "row " << y << ": the gap shows its blurred candidate";
        EXPECT_NEAR(shown, expected, 2) << "row " << y;
        gaps += ref.trace(0)[std::size_t(y) * W + 20].gapShown;
    }
    EXPECT_EQ(gaps, 26);
    // And stores its candidate: no kept sample is made up.
    const gpu::Tracked stored = gpu::wrs_unpack_tracked((*(*comp)->readReservoirs(0))[20u * W + 20u]);
    EXPECT_LT(stored.q, 1.0f);
}

TEST_F(Retain, PoisonedInputsNeverReachReservoirsOrOutputs) {
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    cfg.foveaDeg = 10.0f;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok());
    StereoApp app(**comp, W, H, layers::Format::RGBA16F, layers::Format::R32F, layers::Format::RGBA16F);
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    RandomScene rs(5);
    for (uint64_t f = 1; f <= 12; ++f) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = fov();
            eyes[e].color = texture(0, 0, 1.0f);
            eyes[e].depth = rs.depth(layers::Format::R32F, W, H);
            eyes[e].motion = rs.motion(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 20; y < 60; ++y)
                for (uint32_t x = 20; x < 80; ++x) {
                    const float bad = (x + y + f) % 3 == 0 ? nan : (x + y + f) % 3 == 1 ? inf : -inf;
                    if (x < 40) eyes[e].color.store(x, y, glm::vec4(bad, 0.5f, bad, 1.0f));
                    else if (x < 60) eyes[e].depth->store(x, y, glm::vec4(bad));
                    else eyes[e].motion->store(x, y, glm::vec4(bad, bad, bad, 0.0f));
                }
            // Gaze poisoned every third frame: the documented fallback (view centre, larger fovea).
            eyes[e].gaze = {f % 3 == 0 ? glm::vec3(nan, 0, -1) : gazeAtPixel(40, 40), true, 1.0f};
        }
        ASSERT_TRUE(app.submit(f, eyes).ok());
        for (uint32_t e = 0; e < 2; ++e) {
            auto res = (*comp)->readReservoirs(e);
            ASSERT_TRUE(res.ok());
            uint64_t bad = 0;
            for (const glm::uvec4& w : *res) {
                const gpu::Tracked t = gpu::wrs_unpack_tracked(w);
                bad += !(gpu::wrs_finite3(t.color) && std::isfinite(t.q) && std::isfinite(t.w_sum) && std::isfinite(t.z) &&
                         t.q >= 0.0f && t.w_sum >= 0.0f);
            }
            EXPECT_EQ(bad, 0u) << "frame " << f << " eye " << e;
            EXPECT_TRUE((*comp)->stats().gazeFallback[e] == (f % 3 == 0));
        }
    }
}

TEST_F(Retain, BirthColoursFindStaleSamples) {
    // Static scene: every shown sample was taken from the colour still there. After a light change
    // the published rule keeps samples (eq. 7 with L* at 40 % darker flushes most, not all), and the
    // birth colours of those it kept are the old, brighter ones.
    for (Method m : {Method::Wrs, Method::WrsPaper}) {
        Lane l = lane(m, FoveationMode::Mip, false, true);
        const HostImage tex = texture(0, 0, 1.0f);
        uint64_t f = 1;
        for (; f <= 20; ++f) ASSERT_TRUE(l.app->submit(f, frame(tex, gazeAtPixel(60 + f, 60))).ok());
        auto birth = l.comp->readBirth(0);
        ASSERT_TRUE(birth.ok());
        double maxDiff = 0;
        for (uint32_t i = 0; i < W * H; ++i)
            maxDiff = std::max<double>(maxDiff, glm::length(glm::vec3((*birth)[i]) - glm::vec3(tex.fetch(i % W, i / W))));
        EXPECT_LT(maxDiff, 1e-3) << toString(m) << ": static scene, every birth colour is the colour now";
        ASSERT_TRUE(l.app->submit(f, frame(texture(0, 0, 0.6f), gazeAtPixel(60 + f, 60))).ok());
        birth = l.comp->readBirth(0);
        auto res = l.comp->readReservoirs(0);
        uint64_t old = 0;
        for (uint32_t i = 0; i < W * H; ++i)
            old += glm::length(glm::vec3((*birth)[i]) - glm::vec3(tex.fetch(i % W, i / W))) < 1e-3;
        std::printf("%s: %llu of %u pixels show a sample taken before the light change\n", std::string(toString(m)).c_str(),
                    (unsigned long long)old, W * H);
        if (m == Method::Wrs) {
            EXPECT_EQ(old, 0u);
        }
    }
    Lane off = lane(Method::Wrs);  // trackBirth off: refused after a frame, not garbage
    ASSERT_TRUE(off.app->submit(1, frame(texture(0, 0, 1.0f), gazeAtPixel(60, 60))).ok());
    EXPECT_FALSE(off.comp->readBirth(0).ok());
}

TEST_F(Retain, MonoViewsRunOnceAndMatchStereo) {
    // One view shown to both eyes (monitor mode): the compositor runs the passes for the left eye and
    // copies output and history; the result must be what two identical stereo views give, byte for
    // byte, and a stereo frame afterwards must continue from the copied history as from its own.
    for (Method m : {Method::Wrs, Method::Oracle, Method::WrsPaper, Method::FovTaa, Method::Fov}) {
        CompositorConfig cfg;
        cfg.method = m;
        cfg.foveaDeg = 5.0f;
        cfg.seed = 9;
        cfg.trackBirth = m != Method::FovTaa && m != Method::Fov;
        auto mono = Compositor::create(context(), cfg), stereo = Compositor::create(context(), cfg);
        ASSERT_TRUE(mono.ok() && stereo.ok());
        HostStereoApp::Options o = appOptions(layers::Format::R32F, layers::Format::RG16F);
        auto stereoApp = HostStereoApp::create(**stereo, o);
        auto stereoOnMono = HostStereoApp::create(**mono, o);
        o.monoView = true;
        auto monoApp = HostStereoApp::create(**mono, o);
        ASSERT_TRUE(stereoApp.ok() && monoApp.ok() && stereoOnMono.ok());
        RandomScene rs(31);
        for (uint64_t f = 1; f <= 12; ++f) {
            std::array<EyeFrame, 2> eyes;
            eyes[0].fov = fov();
            eyes[0].color = texture(0.3f * f, 0.1f * f, 1.0f);
            eyes[0].depth = rs.depth(layers::Format::R32F, W, H);
            eyes[0].motion = motionImage(-0.3f, -0.1f);
            eyes[0].gaze = {gazeAtPixel(40 + 3 * f, 50), true, 1.0f};
            eyes[1] = eyes[0];
            const bool lastStereo = f == 12;  // the mono compositor gets a stereo frame at the end
            ASSERT_TRUE((lastStereo ? **stereoOnMono : **monoApp).submit(f, f / 90.0, eyes).ok());
            ASSERT_TRUE((*stereoApp)->submit(f, f / 90.0, eyes).ok());
            // wrs-paper draws per-eye random numbers: identical views are still run per eye.
            EXPECT_EQ((*mono)->stats().monoViews, !lastStereo && m != Method::WrsPaper) << toString(m) << " frame " << f;
            EXPECT_FALSE((*stereo)->stats().monoViews);
            for (uint32_t e = 0; e < 2; ++e) {
                const auto a = (*mono)->readOutput(e)->data, b = (*stereo)->readOutput(e)->data;
                std::size_t diff = 0, first = 0;
                for (std::size_t i = 0; i < a.size(); ++i)
                    if (a[i] != b[i] && diff++ == 0) first = i;
                EXPECT_EQ(diff, 0u) << toString(m) << " frame " << f << " eye " << e << ": output bytes differ, first at pixel "
                                    << (first / 4) % W << "," << (first / 4) / W;
                if (m != Method::Fov) {  // fov keeps no history
                    EXPECT_TRUE(*(*mono)->readReservoirs(e) == *(*stereo)->readReservoirs(e))
                        << toString(m) << " frame " << f << " eye " << e << ": reservoirs differ";
                }
                if (cfg.trackBirth) {
                    EXPECT_TRUE(*(*mono)->readBirth(e) == *(*stereo)->readBirth(e)) << "births differ";
                }
            }
            if (HasFailure()) return;
        }
    }
}

TEST_F(Retain, InPlaceWithoutMotionMatchesPingPong) {
    // Without a motion image, `wrs` and the oracle update the reservoirs in place and skip the store
    // of unchanged ones; with an all-zero motion image they ping-pong and store every pixel. The rule
    // reads the same pixels either way, so outputs and reservoirs must agree byte for byte: static
    // frames (kept samples, skipped stores), a gaze that moves (better samples), a light change and a
    // depth change (flushes).
    for (Method m : {Method::Wrs, Method::Oracle}) {
        CompositorConfig cfg;
        cfg.method = m;
        cfg.foveaDeg = 5.0f;
        cfg.seed = 3;
        auto inPlace = Compositor::create(context(), cfg), pingPong = Compositor::create(context(), cfg);
        ASSERT_TRUE(inPlace.ok() && pingPong.ok());
        auto appA = HostStereoApp::create(**inPlace, appOptions(layers::Format::D32F, std::nullopt));
        auto appB = HostStereoApp::create(**pingPong, appOptions(layers::Format::D32F, layers::Format::RG16F));
        ASSERT_TRUE(appA.ok() && appB.ok());
        RandomScene rs(5);
        HostImage depth = rs.depth(layers::Format::D32F, W, H);
        for (uint64_t f = 1; f <= 16; ++f) {
            if (f == 12) depth = rs.depth(layers::Format::D32F, W, H);
            std::array<EyeFrame, 2> a;
            for (uint32_t e = 0; e < 2; ++e) {
                a[e].fov = fov();
                a[e].color = texture(0.4f, 0.2f, f >= 9 && f < 11 ? 0.6f : 1.0f);
                a[e].depth = depth;
                a[e].gaze = {gazeAtPixel(f < 6 ? 40 + 2 * f : 110, 60 + e), true, 1.0f};
            }
            std::array<EyeFrame, 2> b = a;
            for (uint32_t e = 0; e < 2; ++e) b[e].motion = motionImage(0.0f, 0.0f);
            ASSERT_TRUE((*appA)->submit(f, f / 90.0, a).ok());
            ASSERT_TRUE((*appB)->submit(f, f / 90.0, b).ok());
            EXPECT_TRUE((*inPlace)->stats().inPlace);
            EXPECT_FALSE((*pingPong)->stats().inPlace);
            for (uint32_t e = 0; e < 2; ++e) {
                EXPECT_TRUE((*inPlace)->readOutput(e)->data == (*pingPong)->readOutput(e)->data)
                    << toString(m) << " frame " << f << " eye " << e << ": outputs differ";
                EXPECT_TRUE(*(*inPlace)->readReservoirs(e) == *(*pingPong)->readReservoirs(e))
                    << toString(m) << " frame " << f << " eye " << e << ": reservoirs differ";
            }
            if (HasFailure()) return;
        }
    }
}

}  // namespace
}  // namespace wrsfov::test
