// Sparse retention on the GPU (docs/retention.md "Sparse retention"): far tiles where no sample
// sharper than the floor can be held skip retention and run the foveating pass alone. A compositor
// that does so gives the same output, bit for bit, and the same reservoirs outside the skipped tiles
// as one that runs retention in every tile, for `wrs` (both equal-quality rules) and `oracle-q`, both
// foveation modes with classes, no motion, sub-pixel drift and random motion (large, off-screen),
// mono views, an invalid gaze and a saccade back into a visited area. And the tiles that run
// retention follow the gaze: where it has been, not the whole image.
#include <algorithm>
#include <cmath>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class Sparse : public GpuTest {};

constexpr uint32_t W = 160, H = 120;  // 20 x 15 tiles

layers::Fov wideFov() { return layers::Fov{std::atan(-0.8f), std::atan(0.8f), std::atan(0.6f), std::atan(-0.6f)}; }
glm::vec3 gazeAtPixel(double x, double y) { return test::gazeAtPixel(x, y, W, H, wideFov()); }
HostImage texture(float sx, float sy, float brightness) { return fineTexture(W, H, sx, sy, brightness); }
HostImage motionImage(float mx, float my) { return uniformMotion(W, H, mx, my); }

enum class Motion { None, Drift, Random };

// The gaze path: a fixation at A, a saccade to B, back to A (visited), an invalid sample, then C.
glm::vec3 gazeAt(uint64_t f) {
    if (f <= 8) return gazeAtPixel(40, 40);
    if (f <= 16) return gazeAtPixel(120, 80);
    if (f <= 22) return gazeAtPixel(42, 41);
    return gazeAtPixel(90, 30);
}

TEST_F(Sparse, SameOutputAsRetentionInEveryTile) {
    struct Case {
        Method method;
        EqualQuality rule;
        FoveationMode mode;
        Motion motion;
    };
    std::vector<Case> cases;
    // The two modes differ in shader variants and tile levels only: one host path.
    for (FoveationMode mode : sanitizedSweep({FoveationMode::Mip, FoveationMode::Gauss}))
        for (Motion motion : {Motion::None, Motion::Drift, Motion::Random}) {
            cases.push_back({Method::Wrs, EqualQuality::Merge, mode, motion});
            cases.push_back({Method::OracleQ, EqualQuality::Merge, mode, motion});
        }
    cases.push_back({Method::Wrs, EqualQuality::Reservoir, FoveationMode::Mip, Motion::Drift});
    double minShare = 1.0;
    for (const Case& c : cases) {
        const std::string name = std::string(toString(c.method)) + " " + std::string(toString(c.rule)) + " " +
                                 std::string(toString(c.mode)) + " motion " + std::to_string(int(c.motion));
        SCOPED_TRACE(name);
        CompositorConfig cfg;
        cfg.method = c.method;
        cfg.equalQuality = c.rule;
        cfg.foveation = c.mode;
        cfg.foveaDeg = 5.0f;
        cfg.seed = 7;
        CompositorConfig dense = cfg;
        dense.sparseRetention = false;
        auto a = Compositor::create(context(), cfg);
        auto b = Compositor::create(context(), dense);
        ASSERT_TRUE(a.ok() && b.ok());
        const std::optional<layers::Format> mf =
            c.motion == Motion::None ? std::nullopt : std::optional<layers::Format>(layers::Format::RGBA16F);
        StereoApp appA(**a, W, H, layers::Format::RGBA16F, layers::Format::D32F, mf);
        StereoApp appB(**b, W, H, layers::Format::RGBA16F, layers::Format::D32F, mf);
        RandomScene scene(11);
        const HostImage depth = scene.depth(layers::Format::D32F, W, H);
        for (uint64_t f = 1; f <= 26; ++f) {
            std::array<EyeFrame, 2> eyes;
            const glm::vec2 s = c.motion == Motion::Drift ? glm::vec2(0.37f, 0.21f) * float(f) : glm::vec2(0.0f);
            for (int e = 0; e < 2; ++e) {
                eyes[e].fov = wideFov();
                // A light change at frame 20 flushes what A's second visit kept.
                eyes[e].color = c.motion == Motion::Random ? scene.color(layers::Format::RGBA16F, W, H)
                                                           : texture(s.x, s.y, f == 20 ? 0.7f : 1.0f);
                eyes[e].depth = depth;
                if (c.motion == Motion::Drift) {
                    HostImage m = motionImage(-0.37f, -0.21f);
                    HostImage m16 = HostImage::make(layers::Format::RGBA16F, W, H);
                    for (uint32_t y = 0; y < H; ++y)
                        for (uint32_t x = 0; x < W; ++x) m16.store(x, y, m.fetch(x, y));
                    eyes[e].motion = m16;
                } else if (c.motion == Motion::Random) {
                    eyes[e].motion = scene.motion(layers::Format::RGBA16F, W, H);
                }
                eyes[e].gaze = {gazeAt(f) + glm::vec3(0.0f, 0.002f * float(e), 0.0f), f != 23, 1.0f};
            }
            ASSERT_TRUE(appA.submit(f, eyes).ok());
            ASSERT_TRUE(appB.submit(f, eyes).ok());
            EXPECT_TRUE((*a)->stats().sparse);
            EXPECT_FALSE((*b)->stats().sparse);
            EXPECT_EQ((*b)->stats().retainShare(), 1.0);
            const std::string what = "frame " + std::to_string(f);
            expectSameOutputs(**a, **b, what);
            expectSameReservoirs(**a, **b, what);
            if (HasFailure()) return;
            if (f > 1) minShare = std::min(minShare, (*a)->stats().retainShare());
        }
    }
    // The comparison means something only where tiles were skipped.
    EXPECT_LT(minShare, 0.5);
}

TEST_F(Sparse, MonoViewsMatchStereo) {
    for (Motion motion : {Motion::None, Motion::Drift}) {
        CompositorConfig cfg;
        cfg.method = Method::Wrs;
        CompositorConfig dense = cfg;
        dense.sparseRetention = false;
        auto a = Compositor::create(context(), cfg);
        auto b = Compositor::create(context(), dense);
        ASSERT_TRUE(a.ok() && b.ok());
        HostStereoApp::Options o;
        o.width = W;
        o.height = H;
        o.color = layers::Format::RGBA16F;
        if (motion == Motion::Drift) o.motion = layers::Format::RG16F;
        o.monoView = true;
        auto appA = HostStereoApp::create(**a, o);
        auto appB = HostStereoApp::create(**b, o);
        ASSERT_TRUE(appA.ok() && appB.ok());
        for (uint64_t f = 1; f <= 20; ++f) {
            const glm::vec2 s = motion == Motion::Drift ? glm::vec2(0.37f, 0.21f) * float(f) : glm::vec2(0.0f);
            std::array<EyeSubmission, 2> eyes;
            eyes[0].fov = wideFov();
            eyes[0].color = texture(s.x, s.y, 1.0f);
            if (motion == Motion::Drift) eyes[0].motion = motionImage(-0.37f, -0.21f);
            eyes[0].gaze = {gazeAt(f), true, 1.0f};
            eyes[1] = eyes[0];
            ASSERT_TRUE((*appA)->submit(f, f / 90.0, eyes).ok());
            ASSERT_TRUE((*appB)->submit(f, f / 90.0, eyes).ok());
            EXPECT_TRUE((*a)->stats().monoViews && (*a)->stats().sparse);
            const std::string what = "frame " + std::to_string(f);
            expectSameOutputs(**a, **b, what);
            expectSameReservoirs(**a, **b, what);
            // The right eye's held qualities are the left eye's.
            EXPECT_EQ(*(*a)->readTileHeld(0), *(*a)->readTileHeld(1)) << what;
            if (HasFailure()) return;
        }
    }
}

TEST_F(Sparse, RetentionFollowsTheVisitedArea) {
    // A still scene: fixate A, then B. The tiles around A keep their sharp samples and keep running
    // retention after the gaze left; far tiles neither fixation reached skip; a light change flushes
    // A's samples and its tiles go back to skipping.
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok());
    HostStereoApp::Options o;
    o.width = W;
    o.height = H;
    o.color = layers::Format::RGBA16F;
    auto app = HostStereoApp::create(**comp, o);
    ASSERT_TRUE(app.ok());
    const uint32_t tx = W / gpu::WRS_TILE;
    const float floorQ = gpu::wrs_floor_quality(gpu::WRS_FOV_MIP);
    auto run = [&](uint64_t from, uint64_t to, glm::vec3 gaze, float brightness) {
        for (uint64_t f = from; f <= to; ++f) {
            std::array<EyeSubmission, 2> eyes;
            for (int e = 0; e < 2; ++e) {
                eyes[e].fov = wideFov();
                eyes[e].color = texture(0, 0, brightness);
                eyes[e].gaze = {gaze, true, 1.0f};
            }
            EXPECT_TRUE((*app)->submit(f, f / 90.0, eyes).ok());
        }
        return (*comp)->stats().retainShare();
    };
    const double atA = run(1, 10, gazeAtPixel(40, 40), 1.0f);
    const std::vector<float> heldA = *(*comp)->readTileHeld(0);
    const double atB = run(11, 20, gazeAtPixel(120, 80), 1.0f);
    const std::vector<float> heldB = *(*comp)->readTileHeld(0);
    std::printf("retain share: at A %.3f, then at B %.3f\n", atA, atB);
    const std::size_t tileA = (40 / gpu::WRS_TILE) * tx + 40 / gpu::WRS_TILE, tileB = (80 / gpu::WRS_TILE) * tx + 120 / gpu::WRS_TILE;
    const std::size_t corner = (H / gpu::WRS_TILE - 1) * tx;  // bottom left: far from both
    EXPECT_EQ(heldA[tileA], 1.0f) << "the fixated tile holds full-rate samples";
    EXPECT_EQ(heldB[tileA], 1.0f) << "and keeps them after the gaze left";
    EXPECT_EQ(heldB[tileB], 1.0f);
    EXPECT_EQ(heldB[corner], 0.0f) << "a far tile the gaze never reached stores nothing";
    EXPECT_GT(atB, atA) << "both visited areas run retention";
    EXPECT_LT(atB, 0.6) << "but not the whole image";
    // The light change flushes A's samples (change test): A's tiles hold the floor, then nothing.
    run(21, 23, gazeAtPixel(120, 80), 0.6f);
    const std::vector<float> heldC = *(*comp)->readTileHeld(0);
    EXPECT_LE(heldC[tileA], floorQ) << "A's samples were flushed by the light change";
    const double after = (*comp)->stats().retainShare();
    EXPECT_LT(after, atB);
    std::printf("after the light change: %.3f\n", after);
}

TEST_F(Sparse, FloorMergeKeepsTheRuleBeforeIt) {
    // CompositorConfig::floorMerge: equal-quality samples merge at the floor quality too, retention runs
    // in every tile, and the GPU still agrees with the CPU reference; the default's floor rule takes
    // the candidate there instead, which changes the far periphery's output under motion.
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    CompositorConfig merge = cfg;
    merge.floorMerge = true;
    auto a = Compositor::create(context(), cfg);
    auto b = Compositor::create(context(), merge);
    ASSERT_TRUE(a.ok() && b.ok());
    StereoApp appA(**a, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
    StereoApp appB(**b, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
    Reference ref(merge);
    uint64_t merged = 0, floorRule = 0, differ = 0;
    int maxDiff = 0;
    for (uint64_t f = 1; f <= 12; ++f) {
        std::array<EyeFrame, 2> eyes;
        const glm::vec2 s = glm::vec2(0.37f, 0.21f) * float(f);
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = wideFov();
            eyes[e].color = texture(s.x, s.y, 1.0f);
            eyes[e].motion = motionImage(-0.37f, -0.21f);
            eyes[e].gaze = {gazeAtPixel(60, 50), true, 1.0f};
        }
        if (f > 1)
            for (uint32_t e = 0; e < 2; ++e) {
                ref.setHistory(e, *(*b)->readReservoirs(e));
                ref.setSteadyFloor(e, *(*b)->readSteadyFloor(e));
            }
        ASSERT_TRUE(appA.submit(f, eyes).ok());
        ASSERT_TRUE(appB.submit(f, eyes).ok());
        ref.step((*b)->lastParams(), referenceInputs(eyes));
        EXPECT_FALSE((*b)->stats().sparse);
        EXPECT_EQ((*b)->stats().retainShare(), 1.0);
        EXPECT_EQ((*b)->lastParams().tuning.w, 0.0f) << "no floor rule";
        for (uint32_t e = 0; e < 2; ++e) {
            for (const Reference::Trace& t : ref.trace(e)) {
                merged += t.outcome == gpu::WRS_OUT_MERGED;
                floorRule += t.outcome == gpu::WRS_OUT_FLOOR;
            }
            auto og = (*b)->readOutput(e), od = (*a)->readOutput(e);
            ASSERT_TRUE(og.ok() && od.ok());
            for (std::size_t i = 0; i < og->data.size(); ++i) {
                maxDiff = std::max(maxDiff, std::abs(int(uint8_t(og->data[i])) - int(uint8_t(ref.output(e).data[i]))));
                differ += og->data[i] != od->data[i];
            }
        }
    }
    std::printf("floor merge: merged %llu, floor rule %llu, output bytes differing from the default %llu\n",
                (unsigned long long)merged, (unsigned long long)floorRule, (unsigned long long)differ);
    EXPECT_LE(maxDiff, 1) << "GPU against the CPU reference";
    EXPECT_EQ(floorRule, 0u);
    EXPECT_GT(merged, uint64_t(W) * H) << "the far periphery merges";
    EXPECT_GT(differ, 1000u) << "and that changes its output under motion";
}

TEST_F(Sparse, MotionReachBoundsWhereTheMotionIsRead) {
    // docs/retention.md "Motion reach". A still fixation at A under a slow drift: the classification
    // reads the motion only of far tiles with a sample sharper than the floor within the reach (A's
    // superblocks and their neighbours), as the CPU reference counts them, and with no limit it reads
    // every far tile's. A drift beyond the reach tracks no history at all (every pixel takes its
    // candidate), one just within it does; the GPU agrees with the reference throughout.
    constexpr uint32_t BW = 256, BH = 192;  // 32 x 24 tiles, 4 x 3 superblocks
    const layers::Fov fov{std::atan(-0.8f), std::atan(0.8f), std::atan(0.6f), std::atan(-0.6f)};
    // The reach in pixels: 8 degrees at the centre, 256 px over 1.6 in tangent: 35.7 px.
    const float reachPx = glm::radians(8.0f) * float(BW) / 1.6f;
    struct Case {
        float reachDeg;
        glm::vec2 drift;  // pixels per frame
        const char* what;
    };
    for (const Case& c : {Case{8.0f, {0.37f, 0.21f}, "slow drift"}, Case{0.0f, {0.37f, 0.21f}, "no limit"},
                          Case{8.0f, {reachPx + 1.0f, 0.0f}, "beyond the reach"},
                          Case{8.0f, {reachPx - 1.0f, 0.0f}, "within the reach"}}) {
        SCOPED_TRACE(c.what);
        CompositorConfig cfg;
        cfg.method = Method::Wrs;
        cfg.motionReachDeg = c.reachDeg;
        auto comp = Compositor::create(context(), cfg);
        ASSERT_TRUE(comp.ok());
        StereoApp app(**comp, BW, BH, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
        Reference ref(cfg);
        uint64_t read = 0, far = 0, withHistory = 0, pixels = 0;
        int maxDiff = 0;
        for (uint64_t f = 1; f <= 10; ++f) {
            std::array<EyeFrame, 2> eyes;
            const glm::vec2 s = c.drift * float(f);
            for (int e = 0; e < 2; ++e) {
                eyes[e].fov = fov;
                eyes[e].color = fineTexture(BW, BH, s.x, s.y, 1.0f);
                eyes[e].motion = uniformMotion(BW, BH, -c.drift.x, -c.drift.y);
                eyes[e].gaze = {test::gazeAtPixel(50, 50, BW, BH, fov) + glm::vec3(0.0f, 0.002f * float(e), 0.0f), true, 1.0f};
            }
            if (f > 1)
                for (uint32_t e = 0; e < 2; ++e) {
                    ref.setHistory(e, *(*comp)->readReservoirs(e), *(*comp)->readTileHeld(e));
                    ref.setSteadyFloor(e, *(*comp)->readSteadyFloor(e));
                }
            ASSERT_TRUE(app.submit(f, eyes).ok());
            ref.step((*comp)->lastParams(), referenceInputs(eyes));
            const FrameStats& st = (*comp)->stats();
            ASSERT_TRUE(st.sparse);
            EXPECT_FLOAT_EQ((*comp)->lastParams().eye[0].motion_scale.w,
                            c.reachDeg > 0.0f ? reachPx : std::numeric_limits<float>::infinity());
            EXPECT_EQ(st.motionTiles, ref.motionTiles()) << "frame " << f;
            if (f > 1) {
                read += st.motionTiles;
                far += st.tiles[gpu::WRS_TILE_FAR] + st.tiles[gpu::WRS_TILE_SKIP];
                for (uint32_t e = 0; e < 2; ++e)
                    for (const Reference::Trace& t : ref.trace(e)) withHistory += t.hadHistory, ++pixels;
            }
            for (uint32_t e = 0; e < 2; ++e) {
                auto out = (*comp)->readOutput(e);
                ASSERT_TRUE(out.ok());
                for (std::size_t i = 0; i < out->data.size(); ++i)
                    maxDiff = std::max(maxDiff, std::abs(int(uint8_t(out->data[i])) - int(uint8_t(ref.output(e).data[i]))));
            }
        }
        std::printf("%s: motion read in %llu of %llu far tiles; %llu of %llu pixels ran retention with history\n",
                    c.what, (unsigned long long)read, (unsigned long long)far, (unsigned long long)withHistory,
                    (unsigned long long)pixels);
        EXPECT_LE(maxDiff, 1) << "GPU against the CPU reference";
        const std::string what = c.what;
        if (what == "slow drift") {
            EXPECT_GT(read, 0u);
            EXPECT_LT(read, far / 2) << "the motion of far tiles beyond the reach of A is not read";
        } else if (what == "no limit") {
            EXPECT_EQ(read, far) << "every far tile's motion is read";
        } else if (what == "beyond the reach") {
            EXPECT_EQ(withHistory, 0u) << "no pixel tracks a kept sample";
        } else {
            EXPECT_GT(withHistory, 2000u) << "pixels track kept samples";
        }
    }
}

}  // namespace
}  // namespace wrsfov::test
