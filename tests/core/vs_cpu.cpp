#include "vs_cpu.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace wrsfov::test {
namespace {

// `wrs-paper` (selections, w_sum, M) and every method's output against one reference. A selection may
// differ only where the random number lies within 1e-6 of the keep threshold w1 / (w1 + w_cur): that
// quotient and w_cur = p-hat (exp: 3 + 2|x| ULP, OpFDiv: 2.5 ULP, the eccentricity through length and
// normalize) are within a few tens of ULP of the reference's on any conformant device, far under 1e-6.
void compareFrame(Compositor& gpu, const Reference& ref, const std::vector<glm::uvec4> prev[2], Tally& t, bool wrs,
                  int frame, const std::vector<bool>* preset = nullptr) {
    const uint32_t W = gpu.width(), H = gpu.height();
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
                // Both start from the same history, so M must agree everywhere; w_sum to the error of
                // its float arithmetic (the same few tens of ULP as the threshold's: under 1e-5).
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
        // The output: each channel is the 8-bit code of an sRGB value that pow (inherited from
        // exp2(y log2 x): ~10 ULP, about 1e-6) computes: one within that of a code boundary may be
        // quantised to the code on either side of it. One step, no more.
        auto out = gpu.readOutput(eye);
        ASSERT_TRUE(out.ok());
        const HostImage& cpuOut = ref.output(eye);
        for (std::size_t i = 0; i < out->data.size(); ++i) {
            if (skip[i / 4]) continue;
            int d = std::abs(int(uint8_t(out->data[i])) - int(uint8_t(cpuOut.data[i])));
            t.maxOutputDiff = std::max<uint64_t>(t.maxOutputDiff, d);
            t.channels++;
            t.channelsOneStep += d == 1;
            if (d > 1) {
                if (t.outputOff++ < 5)
                    ADD_FAILURE() << "frame " << frame << " eye " << eye << " pixel " << (i / 4) % W << ","
                                  << (i / 4) / W << " channel " << i % 4 << ": gpu " << int(uint8_t(out->data[i]))
                                  << " cpu " << int(uint8_t(cpuOut.data[i]));
            }
        }
    }
}

// Methods wrs and oracle: the reservoirs must agree field by field. Colour, quality and weight to fp16
// rounding of values computed with quotients (merge weights: OpFDiv 2.5 ULP), the colour also to the
// error of a blend's weight (t = e - r_f: the eccentricity through normalize, length and quotients is
// within ~1e-6 of the reference's, so t within 1e-5 at the blends' e <= 10 deg: 2e-5 of a colour step
// of at most 1); the fingerprint and
// offset codes to one code (quantised measurements: a value within rounding of a code boundary may
// take either code); the linear depth to one fp16 step (a quotient: OpFDiv, 2.5 ULP, then rounded to
// fp16). A pixel that disagrees beyond that made a different decision; that is allowed only where the
// reference's deciding comparison was within 1e-5 (relative) of its threshold: every quantity compared
// there (quality from the eccentricity, oracle distances through pow, fingerprints through the
// bilinear lookup) is within a few ULP (under 1e-6) of the reference's on any conformant device.
bool sameReservoir(const glm::uvec4& g, const glm::uvec4& c) {
    const gpu::Tracked a = gpu::wrs_unpack_tracked(g), b = gpu::wrs_unpack_tracked(c);
    auto close = [](float x, float y, float rel, float least) {
        return std::fabs(x - y) <= rel * std::max(std::fabs(y), least);
    };
    for (int k = 0; k < 3; ++k)
        if (!close(a.color[k], b.color[k], 2e-3f, 1e-2f)) return false;
    const int fpA = int((g.z >> 16) & 0xff), fpB = int((c.z >> 16) & 0xff);
    const int dxA = int(int8_t(g.w >> 16)), dxB = int(int8_t(c.w >> 16)), dyA = int(int8_t(g.w >> 24)),
              dyB = int(int8_t(c.w >> 24));
    const int zA = int(g.w & 0x7fffu), zB = int(c.w & 0x7fffu);  // z >= 0: consecutive fp16 codes are one step apart
    return close(a.q, b.q, 2e-3f, 1e-3f) && close(a.w_sum, b.w_sum, 2e-3f, 1e-3f) && std::abs(fpA - fpB) <= 1 &&
           a.flags == b.flags && std::abs(zA - zB) <= 1 && std::abs(dxA - dxB) <= 1 && std::abs(dyA - dyB) <= 1;
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

// The steady floor's texels: a TAA step (quotients, a square root) rounded to fp16, so one fp16 step
// apart at most where the float arithmetic before the rounding differs by a few ULP.
void compareSteady(Compositor& gpu, const Reference& ref, SteadyTally& t, int frame) {
    for (uint32_t e = 0; e < 2; ++e) {
        auto g = gpu.readSteadyFloor(e);
        ASSERT_TRUE(g.ok());
        const std::vector<glm::vec4>& cpu = ref.steadyFloor(e);
        ASSERT_EQ(g->size(), cpu.size());
        for (std::size_t i = 0; i < cpu.size(); ++i) {
            ++t.texels;
            const glm::vec4 d = glm::abs((*g)[i] - cpu[i]);
            if (!glm::any(glm::greaterThan(d, glm::abs(cpu[i]) * (1.0f / 1024.0f) + 1e-6f))) continue;
            if (t.differ++ < 5)
                ADD_FAILURE() << "frame " << frame << " eye " << e << " steady floor texel " << i << ": gpu "
                              << (*g)[i].x << "," << (*g)[i].y << "," << (*g)[i].z << " cpu " << cpu[i].x << ","
                              << cpu[i].y << "," << cpu[i].z;
        }
    }
}

}  // namespace

void runAgainstReferences(const Case& c, uint32_t W, uint32_t H, int frames, std::vector<Variant>& variants) {
    CompositorConfig cfg;
    cfg.method = c.method;
    cfg.foveation = c.mode;
    cfg.change = c.change;
    cfg.foveaDeg = 10.0f;
    cfg.seed = 7;
    cfg.equalQuality = c.rule;
    cfg.steadyFloor = c.steadyFloor;
    const bool retain = usesRetainPass(c.method);
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    StereoApp app(**comp, W, H, c.color, c.depth, c.motion);
    std::vector<Reference> refs;
    for (std::size_t k = 0; k < variants.size(); ++k) refs.emplace_back(cfg);
    RandomScene rs(1234);
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
        std::vector<float> held[2];
        std::vector<glm::vec4> steady[2];
        if (c.method != Method::Fov && f > 0) {  // every temporal method: start from the GPU history
            for (uint32_t e = 0; e < 2; ++e) {
                auto r = (*comp)->readReservoirs(e);
                ASSERT_TRUE(r.ok());
                prev[e] = *r;
                held[e] = *(*comp)->readTileHeld(e);
                steady[e] = *(*comp)->readSteadyFloor(e);
            }
        }
        Status s = app.submit(uint64_t(f + 1), eyes, c.reversed);
        ASSERT_TRUE(s.ok()) << s.message();
        gpu::FrameParams params = (*comp)->lastParams();
        if (std::getenv("WRSFOV_TEST_MUTATE_SEED")) params.size.w += 1;  // shows the comparison can fail
        const auto inputs = referenceInputs(eyes);
        for (std::size_t k = 0; k < variants.size(); ++k) {
            Variant& v = variants[k];
            SCOPED_TRACE("reference rounding as " + v.name);
            Reference& ref = refs[k];
            if (!prev[0].empty())
                for (uint32_t e = 0; e < 2; ++e) {
                    ref.setHistory(e, prev[e], held[e]);
                    ref.setSteadyFloor(e, steady[e]);
                }
            {
                gpu::ScopedDeviceRounding model(v.model);
                ref.step(params, inputs);
            }
            if (retain) {
                std::vector<bool> skip[2];
                compareRetain(**comp, ref, v.rt, skip, f);
                compareFrame(**comp, ref, prev, v.t, false, f, skip);
            } else {
                compareFrame(**comp, ref, prev, v.t, c.method == Method::WrsPaper, f);
            }
            if (c.steadyFloor) compareSteady(**comp, ref, v.st, f);
        }
        // One reference: stop at the first frame that fails. Several: run on, so each one's tally is whole.
        if (variants.size() == 1 && ::testing::Test::HasFailure()) break;
    }
    std::printf("[%s at %ux%u, %d frames]\n", c.name, W, H, frames);
    for (const Variant& v : variants) {
        const char* n = v.name.c_str();
        if (retain)
            std::printf(
                "[%s%s%s] decisions with history: %llu (fresh %llu, changed %llu, better %llu, kept %llu, merged %llu, "
                "outside %llu, floor %llu), mismatches: %llu (near threshold: %llu)\n",
                c.name, *n ? ", " : "", n, (unsigned long long)v.rt.decisions, (unsigned long long)v.rt.outcomes[0],
                (unsigned long long)v.rt.outcomes[1], (unsigned long long)v.rt.outcomes[2],
                (unsigned long long)v.rt.outcomes[3], (unsigned long long)v.rt.outcomes[4],
                (unsigned long long)v.rt.outcomes[5], (unsigned long long)v.rt.outcomes[6],
                (unsigned long long)v.rt.mismatches, (unsigned long long)v.rt.nearThreshold);
        std::printf(
            "[%s%s%s] decisions with history: %llu (history kept in %llu), selection mismatches: %llu (all within 1e-6 "
            "of the threshold: %llu), max output difference: %llu/255 (one step: %llu of %llu channels)%s\n",
            c.name, *n ? ", " : "", n, (unsigned long long)v.t.decisions, (unsigned long long)v.t.kept,
            (unsigned long long)v.t.mismatches, (unsigned long long)v.t.nearThreshold,
            (unsigned long long)v.t.maxOutputDiff, (unsigned long long)v.t.channelsOneStep,
            (unsigned long long)v.t.channels,
            c.steadyFloor ? (", steady floor texels beyond one fp16 step: " + std::to_string(v.st.differ) + " of " +
                             std::to_string(v.st.texels))
                                .c_str()
                          : "");
    }
}

void expectAgreement(const Case& c, const Variant& v) {
    SCOPED_TRACE("reference rounding as " + v.name);
    if (usesRetainPass(c.method)) {
        EXPECT_EQ(v.rt.mismatches, v.rt.nearThreshold);
        EXPECT_LE(v.rt.nearThreshold, v.rt.decisions / 10000 + 5);
    }
    EXPECT_EQ(v.t.mismatches, v.t.nearThreshold);
    EXPECT_LE(v.t.maxOutputDiff, 1u);
    // A channel is a step apart only where its sRGB value lies within the two sides' pow errors of a
    // code boundary: ~15 ULP each (inherited from exp2(y log2 x)), 2.5e-4 of a code, so a fraction of
    // about 1e-3 of the channels at most. A UNORM store given a value that is not a whole code may round
    // it to either neighbour (fundamentals-fpfixedconv), which would put half of them a step apart.
    EXPECT_LE(v.t.channelsOneStep, v.t.channels / 1000);
    EXPECT_EQ(v.st.differ, 0u);
}

std::vector<Case> comparedPipelines() {
    using layers::Format;
    return {Case{"wrs_mip_depth_motion", Method::WrsPaper, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                 Format::RGBA16F, ChangeMetric::LStar, false},
            Case{"wrs_gauss_r32f_rg16f_reversed", Method::WrsPaper, FoveationMode::Gauss, Format::RGBA16F, Format::R32F,
                 Format::RG16F, ChangeMetric::DeltaE94, true},
            Case{"wrs_none_nodepth_nomotion", Method::WrsPaper, FoveationMode::None, Format::RGBA8, std::nullopt,
                 std::nullopt, ChangeMetric::Off, false},
            Case{"retain_mip_depth_motion", Method::Wrs, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                 Format::RGBA16F, ChangeMetric::LStar, false},
            Case{"retain_gauss_reservoir_reversed", Method::Wrs, FoveationMode::Gauss, Format::RGBA16F, Format::R32F,
                 Format::RG16F, ChangeMetric::LStar, true, EqualQuality::Reservoir},
            Case{"retain_none_nodepth_nomotion", Method::Wrs, FoveationMode::None, Format::RGBA8, std::nullopt,
                 std::nullopt, ChangeMetric::LStar, false},
            Case{"oracle_mip_motion", Method::Oracle, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F,
                 Format::RG16F, ChangeMetric::LStar, false},
            Case{"oracle_q_gauss_depth_motion", Method::OracleQ, FoveationMode::Gauss, Format::RGBA8_SRGB, Format::D32F,
                 Format::RGBA16F, ChangeMetric::LStar, false},
            Case{"taa_mip_motion", Method::FovTaa, FoveationMode::Mip, Format::RGBA8_SRGB, Format::D32F, Format::RG16F,
                 ChangeMetric::LStar, false},
            Case{"fov_mip", Method::Fov, FoveationMode::Mip, Format::RGBA8_SRGB, std::nullopt, std::nullopt,
                 ChangeMetric::LStar, false}};
}

}  // namespace wrsfov::test
