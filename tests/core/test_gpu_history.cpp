// Temporal behaviour of the reservoirs on the GPU, with the change term and the Bernoulli bias off
// and foveation `none` so that every expectation is exact: the first frame initialises, motion
// vectors carry a pixel's kept sample with the content, history whose source is off-screen is
// dropped, and a depth jump beyond tau flushes (unless the motion's dz explains it).
#include <cmath>
#include <cstdio>
#include <functional>
#include <sstream>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

using gpu::Reservoir;
using gpu::wrs_unpack;

class History : public GpuTest {
protected:
    static constexpr uint32_t W = 64, H = 48;

    CompositorConfig exactConfig() const {
        CompositorConfig cfg;
        cfg.method = Method::WrsPaper;
        cfg.foveation = FoveationMode::None;  // candidate = input colour
        cfg.change = ChangeMetric::Off;
        cfg.bernoulli = false;
        cfg.foveaDeg = 10.0f;
        cfg.seed = 3;
        return cfg;
    }
    static layers::Fov fov() { return layers::Fov{std::atan(-0.5f), std::atan(0.5f), std::atan(0.4f), std::atan(-0.4f)}; }
    // The direction of pixel (x, y)'s centre for fov(): gaze "at" a pixel.
    static glm::vec3 gazeAt(double x, double y) {
        double tx = -0.5 + (x + 0.5) / W, ty = 0.4 - (y + 0.5) / H * 0.8;
        return glm::vec3(glm::normalize(glm::dvec3(tx, ty, -1.0)));
    }
    // Content column cx, row y and a frame marker, exact in fp16: the colour names where it came from.
    static glm::vec4 code(int cx, int y, float marker) {
        return glm::vec4(float(cx + 16) / 128.0f, float(y + 1) / 128.0f, marker, 1.0f);
    }
    // The candidate weight the GPU gives pixel (x, y) of eye e in the last frame.
    static float weight(const Compositor& c, uint32_t e, uint32_t x, uint32_t y) {
        const gpu::EyeParams& ep = c.lastParams().eye[e];
        glm::vec3 ray = gpu::wrs_pixel_ray(x, y, W, H, ep.fov_tan);
        return gpu::wrs_sample_weight(gpu::wrs_eccentricity_deg(ray, glm::vec3(ep.gaze)), ep.gaze.w);
    }

    struct Counts {
        uint64_t moved = 0, kept = 0, replaced = 0, fresh = 0, nearThreshold = 0;
    };

    // Checks one frame: for each pixel, `source(x, y, q)` says where its history comes from (false:
    // off-screen). On-screen: M = M_prev + 1, w_sum = w_sum_prev + w_cur, and the decision follows
    // rand * (w_sum_prev + w_cur) <= w_sum_prev (no bias terms) with the history's sample words copied
    // unchanged when kept. Off-screen: {candidate, w_cur, w_cur, 1}.
    Counts checkStep(Compositor& comp, const Reservoirs& prev, const Reservoirs& cur,
                     const std::array<EyeFrame, 2>& eyes, uint32_t frame,
                     const std::function<bool(uint32_t, uint32_t, glm::uvec2&)>& source) {
        Counts c;
        int bad = 0;
        std::ostringstream log, sink;
        auto fail = [&](uint32_t e, uint32_t x, uint32_t y) -> std::ostream& {
            if (bad++ >= 8) return sink;
            return log << "\n  eye " << e << " pixel " << x << "," << y << ": ";
        };
        for (uint32_t e = 0; e < 2; ++e)
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x;
                    const Reservoir r = wrs_unpack(cur[e][i]);
                    const glm::vec3 cand = glm::vec3(eyes[e].color.fetch(x, y));
                    const float wc = weight(comp, e, x, y);
                    glm::uvec2 q;
                    if (!source(x, y, q)) {
                        c.fresh++;
                        bool ok = r.M == 1u && r.color == cand && std::fabs(r.w_sum - wc) <= 1e-5f * wc &&
                                  r.w == gpu::wrs_round_f16(r.w_sum);
                        if (!ok)
                            fail(e, x, y) << "no history expected: M " << r.M << " w_sum " << r.w_sum << " (w_cur "
                                          << wc << ")";
                        continue;
                    }
                    const glm::uvec4 hp = prev[e][std::size_t(q.y) * W + q.x];
                    const Reservoir h = wrs_unpack(hp);
                    if (r.M != h.M + 1u) fail(e, x, y) << "M " << r.M << ", history at " << q.x << "," << q.y << " had " << h.M;
                    if (std::fabs(r.w_sum - (h.w_sum + wc)) > 1e-5f * (h.w_sum + wc))
                        fail(e, x, y) << "w_sum " << r.w_sum << " != " << h.w_sum << " + " << wc;
                    const float rnd = gpu::wrs_rand(x, y, e, frame, 3u);
                    const float thr = h.w_sum / (h.w_sum + wc);
                    const bool gotKeep = cur[e][i].x == hp.x && cur[e][i].y == hp.y;
                    const bool gotCand = r.color == cand;
                    if (std::fabs(rnd - thr) < 1e-5f) {
                        c.nearThreshold++;
                        if (!gotKeep && !gotCand) fail(e, x, y) << "neither history nor candidate";
                        continue;
                    }
                    const bool keep = rnd * (h.w_sum + wc) <= h.w_sum;
                    if (keep) {
                        c.kept++;
                        if (!gotKeep) fail(e, x, y) << "history expected (rnd " << rnd << " <= " << thr << ")";
                        if (q != glm::uvec2(x, y)) c.moved++;
                    } else {
                        c.replaced++;
                        if (!gotCand || std::fabs(r.w - wc) > wc / 1024.0f)
                            fail(e, x, y) << "candidate expected (rnd " << rnd << " > " << thr << ")";
                    }
                }
        EXPECT_EQ(bad, 0) << "frame " << frame << ": " << bad << " checks differ from the expectation" << log.str();
        return c;
    }
};

TEST_F(History, FirstFrameInitialisesAndTranslationCarriesHistory) {
    auto comp = Compositor::create(context(), exactConfig());
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    Compositor& c = **comp;
    StereoApp app(c, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RGBA16F);
    auto frameWith = [&](int shift, float marker, glm::vec2 mv, glm::vec3 gaze) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = fov();
            eyes[e].color = HostImage::make(layers::Format::RGBA16F, W, H);
            eyes[e].motion = HostImage::make(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    eyes[e].color.store(x, y, code(int(x) - shift, int(y), marker));
                    eyes[e].motion->store(x, y, glm::vec4(mv, 0.0f, 0.0f));
                }
            eyes[e].gaze = {gaze, true, 1.0f};
        }
        return eyes;
    };

    // Frame 1: gaze at pixel (20, 24): the fovea there weighs 1. Every reservoir starts from its candidate.
    auto f1 = frameWith(0, 0.25f, glm::vec2(0.0f), gazeAt(20, 24));
    ASSERT_TRUE(app.submit(1, f1).ok());
    EXPECT_TRUE(c.stats().historyReset);
    Reservoirs r1 = readReservoirs(c);
    uint64_t foveal = 0;
    for (uint32_t e = 0; e < 2; ++e)
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                const Reservoir r = wrs_unpack(r1[e][std::size_t(y) * W + x]);
                const float wc = weight(c, e, x, y);
                ASSERT_EQ(r.M, 1u) << x << "," << y;
                ASSERT_EQ(r.color, glm::vec3(f1[e].color.fetch(x, y))) << x << "," << y;
                ASSERT_NEAR(r.w_sum, wc, 3e-6f * wc) << x << "," << y;  // w_sum = w (device exp within 2e-6)
                ASSERT_EQ(r.w, gpu::wrs_round_f16(r.w_sum)) << x << "," << y;
                ASSERT_EQ(r.z, 0.0f);  // no depth submitted
                foveal += r.w_sum == 1.0f;
            }
    EXPECT_GT(foveal, 2u * 60u);  // r_f = 5° is about 5.5 px here

    // Frame 2: the content moves 3 px right; previous position = p + (-3, 0). The gaze moves far away,
    // so the old foveal samples weigh much more than the new candidates and are mostly kept.
    auto f2 = frameWith(3, 0.75f, glm::vec2(-3.0f, 0.0f), gazeAt(56, 6));
    ASSERT_TRUE(app.submit(2, f2).ok());
    EXPECT_FALSE(c.stats().historyReset);
    EXPECT_TRUE(c.stats().usedMotion);
    Reservoirs r2 = readReservoirs(c);
    Counts k2 = checkStep(c, r1, r2, f2, 2, [](uint32_t x, uint32_t y, glm::uvec2& q) {
        if (x < 3) return false;  // x + 0.5 - 3 < 0
        q = glm::uvec2(x - 3, y);
        return true;
    });
    // In the old fovea the kept sample is the old frame's (marker 0.25) of the same content.
    uint64_t oldFovea = 0, oldFoveaKept = 0;
    for (uint32_t e = 0; e < 2; ++e)
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 3; x < W; ++x) {
                const Reservoir h = wrs_unpack(r1[e][std::size_t(y) * W + x - 3]);
                const Reservoir r = wrs_unpack(r2[e][std::size_t(y) * W + x]);
                // Whichever sample is kept, it shows the content that is at (x, y) now.
                ASSERT_EQ(glm::vec2(r.color), glm::vec2(code(int(x) - 3, int(y), 0.0f))) << x << "," << y;
                if (h.w_sum == 1.0f) {
                    oldFovea++;
                    if (r.color.z == 0.25f) {
                        oldFoveaKept++;
                        EXPECT_EQ(r.M, 2u);
                    }
                }
            }
    std::printf("  frame 2: %llu kept (%llu moved with the content), %llu replaced, %llu without history, "
                "%llu near the threshold; old fovea kept %llu of %llu\n",
                (unsigned long long)k2.kept, (unsigned long long)k2.moved, (unsigned long long)k2.replaced,
                (unsigned long long)k2.fresh, (unsigned long long)k2.nearThreshold, (unsigned long long)oldFoveaKept,
                (unsigned long long)oldFovea);
    EXPECT_EQ(k2.fresh, 2u * 3u * H);
    EXPECT_GT(k2.moved, 0u);
    EXPECT_GT(k2.replaced, 0u);
    EXPECT_GT(oldFovea, 2u * 60u);
    EXPECT_GT(oldFoveaKept, oldFovea * 8 / 10);
    EXPECT_LT(k2.nearThreshold, 10u);

    // Frame 3: motion (+3, -2) reads from the right and above: the last 3 columns and first 2 rows
    // have no history, all others continue from (x + 3, y - 2).
    auto f3 = frameWith(3, 0.5f, glm::vec2(3.0f, -2.0f), gazeAt(10, 40));
    ASSERT_TRUE(app.submit(3, f3).ok());
    Reservoirs r3 = readReservoirs(c);
    Counts k3 = checkStep(c, r2, r3, f3, 3, [](uint32_t x, uint32_t y, glm::uvec2& q) {
        if (x + 3 >= W || y < 2) return false;
        q = glm::uvec2(x + 3, y - 2);
        return true;
    });
    EXPECT_EQ(k3.fresh, 2u * (3u * H + 2u * (W - 3u)));
    uint64_t m3 = 0;
    for (const auto& r : r3[0]) m3 += wrs_unpack(r).M == 3u;
    EXPECT_GT(m3, 0u);

    // Frame 4: fractional motion (-2.6, 0.4): the previous position x - 2.1, y + 0.9 is read at the
    // nearest pixel, i.e. the one containing it: (x - 3, y); x <= 2 is off-screen.
    auto f4 = frameWith(3, 0.125f, glm::vec2(-2.6f, 0.4f), gazeAt(40, 30));
    ASSERT_TRUE(app.submit(4, f4).ok());
    Reservoirs r4 = readReservoirs(c);
    Counts k4 = checkStep(c, r3, r4, f4, 4, [](uint32_t x, uint32_t y, glm::uvec2& q) {
        if (x < 3) return false;
        q = glm::uvec2(x - 3, y);
        return true;
    });
    EXPECT_EQ(k4.fresh, 2u * 3u * H);

    // Frame 5: no motion image at all: no reprojection, every pixel continues from itself.
    StereoApp still(c, W, H, layers::Format::RGBA16F, std::nullopt, std::nullopt);
    auto f5 = frameWith(3, 0.375f, glm::vec2(0.0f), gazeAt(30, 20));
    for (auto& e : f5) e.motion.reset();
    ASSERT_TRUE(still.submit(5, f5).ok());
    EXPECT_FALSE(c.stats().usedMotion);
    Reservoirs r5 = readReservoirs(c);
    Counts k5 = checkStep(c, r4, r5, f5, 5, [](uint32_t x, uint32_t y, glm::uvec2& q) {
        q = glm::uvec2(x, y);
        return true;
    });
    EXPECT_EQ(k5.fresh, 0u);
    EXPECT_GT(k5.kept, 0u);
}

TEST_F(History, DepthJumpBeyondTauFlushes) {
    CompositorConfig cfg = exactConfig();
    cfg.depthTau = 0.05f;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    Compositor& c = **comp;
    StereoApp app(c, W, H, layers::Format::RGBA16F, layers::Format::R32F, layers::Format::RGBA16F);
    const float n = app.nearZ, f = app.farZ;
    // Depth buffer value of linear depth z (standard Z): d = f (1 - n / z) / (f - n).
    auto depthOf = [&](float z) { return f * (1.0f - n / z) / (f - n); };
    RandomScene rs(8);
    auto frameWith = [&](const std::function<float(uint32_t, uint32_t)>& z,
                         const std::function<float(uint32_t, uint32_t)>& dz) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = fov();
            eyes[e].color = rs.color(layers::Format::RGBA16F, W, H);
            eyes[e].depth = HostImage::make(layers::Format::R32F, W, H);
            eyes[e].motion = HostImage::make(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    eyes[e].depth->store(x, y, glm::vec4(depthOf(z(x, y))));
                    eyes[e].motion->store(x, y, glm::vec4(0.0f, 0.0f, dz(x, y), 0.0f));
                }
            eyes[e].gaze = {gazeAt(32, 24), true, 1.0f};
        }
        return eyes;
    };
    auto zero = [](uint32_t, uint32_t) { return 0.0f; };
    auto f1 = frameWith([](uint32_t, uint32_t) { return 2.0f; }, zero);
    ASSERT_TRUE(app.submit(1, f1).ok());
    EXPECT_TRUE(c.stats().usedDepth);
    Reservoirs r1 = readReservoirs(c);
    for (uint32_t e = 0; e < 2; ++e)
        for (const auto& p : r1[e]) {
            const Reservoir r = wrs_unpack(p);
            ASSERT_EQ(r.M, 1u);
            ASSERT_NEAR(r.z, 2.0f, 2e-3f);  // linear depth of the frame, fp16
        }

    // Frame 2, by column band: [0,16) jumps to 3 (50 % > tau), except the lower half where the motion's
    // dz = z_prev - z_cur = -1 explains the jump; [16,32) moves to 2.06 (3 % < tau); [32,48) to 2.14
    // (|2 - 2.14| = 0.14 > 0.05 * 2.14 = 0.107); [48,64) stays at 2.
    auto z2 = [](uint32_t x, uint32_t) { return x < 16 ? 3.0f : x < 32 ? 2.06f : x < 48 ? 2.14f : 2.0f; };
    auto dz2 = [](uint32_t x, uint32_t y) { return x < 16 && y >= 24 ? -1.0f : 0.0f; };
    auto f2 = frameWith(z2, dz2);
    ASSERT_TRUE(app.submit(2, f2).ok());
    Reservoirs r2 = readReservoirs(c);
    auto flushed = [](uint32_t x, uint32_t y) { return (x < 16 && y < 24) || (x >= 32 && x < 48); };
    Counts k = checkStep(c, r1, r2, f2, 2, [&](uint32_t x, uint32_t y, glm::uvec2& q) {
        q = glm::uvec2(x, y);
        return !flushed(x, y);
    });
    EXPECT_EQ(k.fresh, 2u * (16u * 24u + 16u * H));
    for (uint32_t e = 0; e < 2; ++e)
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                const Reservoir r = wrs_unpack(r2[e][std::size_t(y) * W + x]);
                ASSERT_EQ(r.M, flushed(x, y) ? 1u : 2u) << x << "," << y;
                ASSERT_NEAR(r.z, z2(x, y), 4e-3f) << "z is this frame's depth, whichever sample is kept";
            }

    // After an explicit reset every reservoir starts again from its candidate.
    c.resetHistory();
    auto f3 = frameWith(z2, zero);
    ASSERT_TRUE(app.submit(3, f3).ok());
    EXPECT_TRUE(c.stats().historyReset);
    Reservoirs r3 = readReservoirs(c);
    for (uint32_t e = 0; e < 2; ++e)
        for (std::size_t i = 0; i < r3[e].size(); ++i) {
            const Reservoir r = wrs_unpack(r3[e][i]);
            ASSERT_EQ(r.M, 1u);
            ASSERT_EQ(r.color, glm::vec3(f3[e].color.fetch(uint32_t(i % W), uint32_t(i / W))));
        }
}

// MotionInfo::scale: the same motion given in other units (NDC, current - previous, as OpenXR's
// XR_FB_space_warp submits it) with the scale that converts it gives the output and the reservoirs,
// bit for bit, of the motion in pixels; the NDC values read as pixels (scale 1) do not. A scale that
// is not finite is refused.
TEST_F(History, MotionScaleEqualsMotionInPixels) {
    CompositorConfig cfg;  // the default method (wrs), mip foveation
    cfg.seed = 5;
    std::unique_ptr<Compositor> comps[3];
    std::unique_ptr<StereoApp> apps[3];
    for (int k = 0; k < 3; ++k) {
        auto c = Compositor::create(context(), cfg);
        ASSERT_TRUE(c.ok()) << c.error().message;
        comps[k] = std::move(*c);
        apps[k] = std::make_unique<StereoApp>(*comps[k], W, H, layers::Format::RGBA16F, std::nullopt,
                                              layers::Format::RGBA16F);
    }
    // Motion in pixels whose NDC form -m * 2 / size is exact in fp16 (x: halves over 32; y: multiples
    // of 3 over 24), so the two submissions carry the same numbers.
    auto pixels = [](uint32_t x, uint32_t y, int frame) {
        return glm::vec2(float(int(x + frame) % 5 - 2) + 0.5f * float(y % 2), float((int(y) % 3 - 1) * 3));
    };
    const glm::vec3 toPixels(-0.5f * float(W), -0.5f * float(H), 1.0f);
    for (int frame = 1; frame <= 4; ++frame) {
        std::array<EyeFrame, 2> px, ndc;
        for (int e = 0; e < 2; ++e) {
            px[e].fov = fov();
            px[e].color = HostImage::make(layers::Format::RGBA16F, W, H);
            px[e].motion = HostImage::make(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    px[e].color.store(x, y, code(int(x) - frame, int(y) + e, 0.25f));
                    const glm::vec2 m = pixels(x, y, frame);
                    px[e].motion->store(x, y, glm::vec4(m, 0.0f, 0.0f));
                }
            px[e].gaze = {gazeAt(20 + 3 * frame, 24), true, 1.0f};
            ndc[e] = px[e];
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x)
                    ndc[e].motion->store(x, y, glm::vec4(pixels(x, y, frame) / glm::vec2(toPixels), 0.0f, 0.0f));
        }
        ASSERT_TRUE(apps[0]->submit(frame, px).ok());
        apps[1]->write(ndc);
        layers::FrameEndInfo fe = apps[1]->frameEnd(frame, ndc);
        for (auto& v : fe.layers[0].views) v.motion->scale = toPixels;
        ASSERT_TRUE(comps[1]->endFrame(fe).ok());
        ASSERT_TRUE(apps[2]->submit(frame, ndc).ok());  // NDC taken for pixels
        EXPECT_TRUE(comps[1]->stats().usedMotion);
    }
    const Reservoirs want = readReservoirs(*comps[0]), got = readReservoirs(*comps[1]),
                     wrong = readReservoirs(*comps[2]);
    for (int e = 0; e < 2; ++e) {
        // Samples above the floor quality are the ones whose history the motion decides (at the floor
        // every pixel takes its candidate, whatever the motion).
        const float floorQ = gpu::wrs_floor_quality(gpu::WRS_FOV_MIP);
        size_t differ = 0, differWrong = 0, aboveFloor = 0;
        for (size_t i = 0; i < want[e].size(); ++i) {
            differ += want[e][i] != got[e][i];
            if (!(gpu::wrs_packed_quality(want[e][i]) > floorQ)) continue;
            aboveFloor++;
            differWrong += want[e][i] != wrong[e][i];
        }
        EXPECT_EQ(differ, 0u) << "eye " << e << ": reservoirs differ from the motion in pixels";
        EXPECT_GT(aboveFloor, want[e].size() / 8) << "eye " << e;
        EXPECT_GT(differWrong, aboveFloor / 4) << "eye " << e << ": the motion never mattered (" << differWrong
                                               << " of " << aboveFloor << ")";
        auto a = comps[0]->readOutput(uint32_t(e)), b = comps[1]->readOutput(uint32_t(e));
        ASSERT_TRUE(a.ok() && b.ok());
        EXPECT_EQ(a->data, b->data) << "eye " << e;
    }

    // Not finite: refused with its own code, nothing changes.
    std::array<EyeFrame, 2> again;
    for (int e = 0; e < 2; ++e) {
        again[e].fov = fov();
        again[e].color = HostImage::make(layers::Format::RGBA16F, W, H);
        again[e].motion = HostImage::make(layers::Format::RGBA16F, W, H);
    }
    apps[1]->write(again);
    layers::FrameEndInfo bad = apps[1]->frameEnd(9, again);
    bad.layers[0].views[1].motion->scale.y = std::nanf("");
    Status s = comps[1]->endFrame(bad);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(layers::SubmitError::InvalidMotionScale));
    EXPECT_EQ(readReservoirs(*comps[1])[0], got[0]);
}

}  // namespace
}  // namespace wrsfov::test
