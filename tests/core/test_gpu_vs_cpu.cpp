// The GPU pipeline against the CPU reference built from the same shared header, over many frames of
// random colour, depth, motion and gaze. Each frame the reference starts from the GPU's own history,
// so every frame checks one step of every pixel: the selection must be identical except where the
// random number lies within 1e-6 of the keep threshold, output colours within 1/255.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "gpu_rig.h"

namespace wrsfov::test {
namespace {

struct Case {
    const char* name;
    Method method;
    FoveationMode mode;
    layers::Format color;
    std::optional<layers::Format> depth;
    std::optional<layers::Format> motion;
    ChangeMetric change;
    bool reversed;
    EqualQuality rule = EqualQuality::Merge;
};

struct Tally {
    uint64_t decisions = 0, kept = 0, mismatches = 0, nearThreshold = 0, outputOff = 0, maxOutputDiff = 0;
};

void compareFrame(const Compositor& comp, Compositor& gpu, Reference& ref, const std::vector<glm::uvec4> prev[2],
                  Tally& t, bool wrs, int frame, const std::vector<bool>* preset = nullptr) {
    const uint32_t W = comp.width(), H = comp.height();
    for (uint32_t eye = 0; eye < 2; ++eye) {
        // Pixels whose selection legitimately differed (rand within 1e-6 of the threshold) show
        // different samples; their output is not compared.
        std::vector<bool> skip = preset ? preset[eye] : std::vector<bool>(std::size_t(W) * H, false);
        if (wrs) {
            auto res = gpu.readReservoirs(eye);
            ASSERT_TRUE(res.ok());
            const auto& cpuRes = ref.reservoirs(eye);
            const auto& trace = ref.trace(eye);
            for (uint32_t i = 0; i < W * H; ++i) {
                const Reference::Trace& tr = trace[i];
                const glm::uvec4 g = (*res)[i], c = cpuRes[i];
                const gpu::Reservoir gr = gpu::wrs_unpack(g), cr = gpu::wrs_unpack(c);
                // Both start from the same history, so M must agree everywhere; w_sum to float rounding.
                EXPECT_EQ(gr.M, cr.M) << "frame " << frame << " pixel " << i;
                EXPECT_NEAR(gr.w_sum, cr.w_sum, 1e-5f * std::max(1.0f, cr.w_sum))
                    << "frame " << frame << " pixel " << i;
                if (!tr.hadHistory) continue;  // initialisation: the candidate, checked through the output
                t.decisions++;
                t.kept += tr.keep;
                // The GPU kept the history iff its sample words are the history's words.
                const glm::uvec4 h = prev[eye][tr.source];
                const bool gpuKeep = g.x == h.x && g.y == h.y;
                const bool cpuKeep = tr.keep;
                const bool ambiguous = c.x == h.x && c.y == h.y && !cpuKeep;  // candidate packs like the history
                if (gpuKeep == cpuKeep || ambiguous) continue;
                t.mismatches++;
                if (std::fabs(tr.rnd - tr.threshold) < 1e-6f) {
                    t.nearThreshold++;
                    skip[i] = true;
                    std::printf(
                        "  near-threshold selection difference: frame %d eye %u pixel %u,%u (rand %.9f, "
                        "threshold %.9f)\n",
                        frame, eye, i % W, i / W, tr.rnd, tr.threshold);
                } else if (t.mismatches - t.nearThreshold <= 5) {
                    ADD_FAILURE() << "frame " << frame << " eye " << eye << " pixel " << i % W << "," << i / W
                                  << ": selection differs, cpu keep=" << cpuKeep << " rnd=" << tr.rnd
                                  << " threshold=" << tr.threshold;
                }
            }
        }
        auto out = gpu.readOutput(eye);
        ASSERT_TRUE(out.ok());
        const HostImage& cpuOut = ref.output(eye);
        for (std::size_t i = 0; i < out->data.size(); ++i) {
            if (skip[i / 4]) continue;
            int d = std::abs(int(uint8_t(out->data[i])) - int(uint8_t(cpuOut.data[i])));
            t.maxOutputDiff = std::max<uint64_t>(t.maxOutputDiff, d);
            if (d > 1) {
                if (t.outputOff++ < 5)
                    ADD_FAILURE() << "frame " << frame << " eye " << eye << " pixel " << (i / 4) % W << ","
                                  << (i / 4) / W << " channel " << i % 4 << ": gpu " << int(uint8_t(out->data[i]))
                                  << " cpu " << int(uint8_t(cpuOut.data[i]));
            }
        }
    }
}

// Methods wrs and oracle: the reservoirs must agree field by field (colour to fp16 rounding,
// fingerprint and offset codes to one code: both are quantised measurements). A pixel that
// disagrees beyond that made a different decision; that is allowed only where the reference's
// deciding comparison was within 1e-5 (relative) of its threshold.
struct RetainTally {
    uint64_t decisions = 0, outcomes[gpu::WRS_OUTCOMES] = {}, mismatches = 0, nearThreshold = 0;
};

bool sameReservoir(const glm::uvec4& g, const glm::uvec4& c) {
    const gpu::Tracked a = gpu::wrs_unpack_tracked(g), b = gpu::wrs_unpack_tracked(c);
    auto close = [](float x, float y, float rel) { return std::fabs(x - y) <= rel * std::max(std::fabs(y), 1e-3f); };
    for (int k = 0; k < 3; ++k)
        if (!close(a.color[k], b.color[k], 2e-3f)) return false;
    const int fpA = int((g.z >> 16) & 0xff), fpB = int((c.z >> 16) & 0xff);
    const int dxA = int(int8_t(g.w >> 16)), dxB = int(int8_t(c.w >> 16)), dyA = int(int8_t(g.w >> 24)),
              dyB = int(int8_t(c.w >> 24));
    return close(a.q, b.q, 2e-3f) && close(a.w_sum, b.w_sum, 2e-3f) && std::abs(fpA - fpB) <= 1 && a.flags == b.flags &&
           (g.w & 0xffffu) == (c.w & 0xffffu) && std::abs(dxA - dxB) <= 1 && std::abs(dyA - dyB) <= 1;
}

void compareRetain(Compositor& gpu, const Reference& ref, RetainTally& t, std::vector<bool> skip[2], int frame) {
    const uint32_t W = gpu.width(), H = gpu.height();
    for (uint32_t eye = 0; eye < 2; ++eye) {
        skip[eye].assign(std::size_t(W) * H, false);
        auto res = gpu.readReservoirs(eye);
        ASSERT_TRUE(res.ok());
        for (uint32_t i = 0; i < W * H; ++i) {
            const Reference::Trace& tr = ref.trace(eye)[i];
            if (tr.hadHistory) {
                t.decisions++;
                t.outcomes[tr.outcome]++;
            }
            if (sameReservoir((*res)[i], ref.reservoirs(eye)[i])) continue;
            t.mismatches++;
            if (tr.margin < 1e-5f) {
                t.nearThreshold++;
                skip[eye][i] = true;
                std::printf("  near-threshold decision difference: frame %d eye %u pixel %u,%u (margin %.3g)\n", frame,
                            eye, i % W, i / W, tr.margin);
            } else if (t.mismatches - t.nearThreshold <= 5) {
                const gpu::Tracked a = gpu::wrs_unpack_tracked((*res)[i]),
                                   b = gpu::wrs_unpack_tracked(ref.reservoirs(eye)[i]);
                ADD_FAILURE() << "frame " << frame << " eye " << eye << " pixel " << i % W << "," << i / W
                              << ": reservoirs differ, cpu outcome " << tr.outcome << " margin " << tr.margin
                              << " gpu colour " << a.color.x << "," << a.color.y << "," << a.color.z << " q " << a.q
                              << " w_sum " << a.w_sum << " fp " << a.fp << " | cpu colour " << b.color.x << ","
                              << b.color.y << "," << b.color.z << " q " << b.q << " w_sum " << b.w_sum << " fp "
                              << b.fp;
            }
        }
    }
}

class GpuVsCpu : public GpuTest, public ::testing::WithParamInterface<Case> {};

// Runs `frames` random frames of case `c` at W x H through the compositor and the CPU reference and
// compares every decision and output. `counts`: also require every branch of the rule to be exercised
// (the full-length run).
void runAgainstReference(const Case& c, uint32_t W, uint32_t H, int frames, bool counts) {
    CompositorConfig cfg;
    cfg.method = c.method;
    cfg.foveation = c.mode;
    cfg.change = c.change;
    cfg.foveaDeg = 10.0f;
    cfg.seed = 7;
    cfg.equalQuality = c.rule;
    const bool retain = usesRetainPass(c.method);
    RetainTally rt;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    StereoApp app(**comp, W, H, c.color, c.depth, c.motion);
    Reference ref(cfg);
    RandomScene rs(1234);
    Tally t;
    // Temporally coherent content: colour changes a little every frame and anew every 5th frame,
    // depth anew every 10th, so history survives often enough to exercise the combine.
    std::array<HostImage, 2> baseColor, baseDepth;
    std::mt19937 noise(99);
    std::uniform_real_distribution<float> jitter(-0.04f, 0.04f);
    for (int f = 0; f < frames; ++f) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            if (f % 5 == 0) baseColor[e] = rs.color(c.color, W, H);
            eyes[e].color = baseColor[e];
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x)
                    eyes[e].color.store(
                        x, y, eyes[e].color.fetch(x, y) + glm::vec4(jitter(noise), jitter(noise), jitter(noise), 0.0f));
            if (c.depth) {
                if (f % 10 == 0) baseDepth[e] = rs.depth(*c.depth, W, H);
                eyes[e].depth = baseDepth[e];
            }
            if (c.motion) eyes[e].motion = rs.motion(*c.motion, W, H);
            eyes[e].gaze = {rs.gaze(eyes[e].fov), true, 1.0f};
        }
        std::vector<glm::uvec4> prev[2];
        if (c.method != Method::Fov && f > 0) {  // every temporal method: start from the GPU history
            for (uint32_t e = 0; e < 2; ++e) {
                auto r = (*comp)->readReservoirs(e);
                ASSERT_TRUE(r.ok());
                prev[e] = *r;
                ref.setHistory(e, prev[e], *(*comp)->readTileHeld(e));
                ref.setSteadyFloor(e, *(*comp)->readSteadyFloor(e));
            }
        }
        Status s = app.submit(uint64_t(f + 1), eyes, c.reversed);
        ASSERT_TRUE(s.ok()) << s.message();
        gpu::FrameParams params = (*comp)->lastParams();
        if (std::getenv("WRSFOV_TEST_MUTATE_SEED")) params.size.w += 1;  // shows the comparison can fail
        ref.step(params, referenceInputs(eyes));
        if (retain) {
            std::vector<bool> skip[2];
            compareRetain(**comp, ref, rt, skip, f);
            compareFrame(**comp, **comp, ref, prev, t, false, f, skip);
        } else {
            compareFrame(**comp, **comp, ref, prev, t, c.method == Method::WrsPaper, f);
        }
        if (::testing::Test::HasFailure()) break;
    }
    std::printf("[%s at %ux%u, %d frames]\n", c.name, W, H, frames);
    if (retain) {
        std::printf(
            "[%s] decisions with history: %llu (fresh %llu, changed %llu, better %llu, kept %llu, merged %llu, "
            "outside %llu, floor %llu), mismatches: %llu (near threshold: %llu)\n",
            c.name, (unsigned long long)rt.decisions, (unsigned long long)rt.outcomes[0],
            (unsigned long long)rt.outcomes[1], (unsigned long long)rt.outcomes[2], (unsigned long long)rt.outcomes[3],
            (unsigned long long)rt.outcomes[4], (unsigned long long)rt.outcomes[5], (unsigned long long)rt.outcomes[6],
            (unsigned long long)rt.mismatches, (unsigned long long)rt.nearThreshold);
        EXPECT_EQ(rt.mismatches, rt.nearThreshold);
        EXPECT_LE(rt.nearThreshold, rt.decisions / 10000 + 5);
        if (!counts) return;
        EXPECT_GT(rt.decisions, 50000u);
        // Every branch of the rule must be exercised for the comparison to mean anything.
        const std::vector<uint32_t> branches = isOracle(c.method)
                                                   ? std::vector<uint32_t>{gpu::WRS_OUT_KEPT, gpu::WRS_OUT_BETTER}
                                                   : std::vector<uint32_t>{gpu::WRS_OUT_CHANGED, gpu::WRS_OUT_BETTER,
                                                                           gpu::WRS_OUT_KEPT, gpu::WRS_OUT_KEPT};
        for (uint32_t b : branches) EXPECT_GT(rt.outcomes[b], rt.decisions / 200) << "outcome " << b;
        // The floor rule takes the far periphery's equal-quality decisions (mip and gauss), so merges
        // happen only above it (the fovea and the mid-periphery): fewer, but still exercised.
        if (!isOracle(c.method) && c.mode != FoveationMode::None) {
            EXPECT_GT(rt.outcomes[gpu::WRS_OUT_FLOOR], rt.decisions / 200) << "floor rule";
            if (c.rule == EqualQuality::Merge) {
                EXPECT_GE(rt.outcomes[gpu::WRS_OUT_MERGED], 20u) << "merges above the floor";
            }
        }
    }
    std::printf(
        "[%s] decisions with history: %llu (history kept in %llu), selection mismatches: %llu (all within 1e-6 of the "
        "threshold: "
        "%llu), max output difference: %llu/255\n",
        c.name, (unsigned long long)t.decisions, (unsigned long long)t.kept, (unsigned long long)t.mismatches,
        (unsigned long long)t.nearThreshold, (unsigned long long)t.maxOutputDiff);
    EXPECT_EQ(t.mismatches, t.nearThreshold);
    EXPECT_LE(t.maxOutputDiff, 1u);
    if (counts && c.method == Method::WrsPaper) {
        // Both outcomes of the combine must be well represented for the comparison to mean anything.
        EXPECT_GT(t.decisions, 100000u);
        EXPECT_GT(t.kept, t.decisions / 20);
        EXPECT_GT(t.decisions - t.kept, t.decisions / 20);
    }
}

TEST_P(GpuVsCpu, SixtyRandomFramesMatchReference) {
    // 88 x 72: not multiples of the 8x8 workgroup: exercises bounds checks.
    runAgainstReference(GetParam(), 88, 72, 60, true);
}

// Sizes whose levels are odd where the mip pyramid's groups clamp their taps: level 0 (87, 69, 33),
// level 1 (45, 37, 35, 17, 9), and images narrower than one 32x32 group (17, 9).
TEST_P(GpuVsCpu, OddSizesMatchReference) {
    for (auto [w, h] : {std::pair{87u, 69u}, std::pair{90u, 74u}, std::pair{33u, 17u}}) {
        runAgainstReference(GetParam(), w, h, 6, false);
        if (HasFailure()) break;
    }
}

using layers::Format;
INSTANTIATE_TEST_SUITE_P(
    Pipelines, GpuVsCpu,
    ::testing::Values(Case{"wrs_mip_depth_motion", Method::WrsPaper, FoveationMode::Mip, Format::RGBA8_SRGB,
                           Format::D32F, Format::RGBA16F, ChangeMetric::LStar, false},
                      Case{"wrs_gauss_r32f_rg16f_reversed", Method::WrsPaper, FoveationMode::Gauss, Format::RGBA16F,
                           Format::R32F, Format::RG16F, ChangeMetric::DeltaE94, true},
                      Case{"wrs_none_nodepth_nomotion", Method::WrsPaper, FoveationMode::None, Format::RGBA8,
                           std::nullopt, std::nullopt, ChangeMetric::Off, false},
                      Case{"retain_mip_depth_motion", Method::Wrs, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                           Format::RGBA16F, ChangeMetric::LStar, false},
                      Case{"retain_gauss_reservoir_reversed", Method::Wrs, FoveationMode::Gauss, Format::RGBA16F,
                           Format::R32F, Format::RG16F, ChangeMetric::LStar, true, EqualQuality::Reservoir},
                      Case{"retain_none_nodepth_nomotion", Method::Wrs, FoveationMode::None, Format::RGBA8,
                           std::nullopt, std::nullopt, ChangeMetric::LStar, false},
                      Case{"oracle_mip_motion", Method::Oracle, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                           Format::RG16F, ChangeMetric::LStar, false},
                      Case{"oracle_q_gauss_depth_motion", Method::OracleQ, FoveationMode::Gauss, Format::RGBA8_SRGB,
                           Format::D32F, Format::RGBA16F, ChangeMetric::LStar, false},
                      Case{"taa_mip_motion", Method::FovTaa, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                           Format::RG16F, ChangeMetric::LStar, false},
                      Case{"fov_mip", Method::Fov, FoveationMode::Mip, Format::RGBA8_SRGB, std::nullopt, std::nullopt,
                           ChangeMetric::LStar, false}),
    [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

}  // namespace
}  // namespace wrsfov::test
