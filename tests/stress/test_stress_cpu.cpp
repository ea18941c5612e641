// Short versions of the wrsfov-stress CPU runs: every stream through the shipping reservoir layout
// with its invariants and selection statistics, the precision study's fp16-w_sum variant breaking
// where docs/stability.md says, the safe horizon, and the stress step against the CPU reference.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "compositor/reference.h"
#include "stress/cpu_stress.h"
#include "stress/report.h"
#include "stress/step.h"

namespace wrsfov::stress {
namespace {

using namespace gpu;

const StreamResult& find(const CpuResult& r, const std::string& name) {
    for (const StreamResult& s : r.streams)
        if (s.stream.name == name) return s;
    ADD_FAILURE() << "no stream " << name;
    return r.streams.front();
}

const FormatStats& statsFor(const StreamResult& s, FormatId f) {
    for (const FormatStats& x : s.formats)
        if (x.format == f) return x;
    ADD_FAILURE() << "no format " << formatInfo(f).name;
    return s.formats.front();
}

// The short run: 10^5 frames of every stream, 16 pixels each, in the shipping layout. CTest runs
// each test in its own process, so the checks of this one run are the parts of one test.
void everyStreamKeepsTheInvariants(const CpuResult& r) {
    ASSERT_EQ(r.streams.size(), streamNames().size());
    for (const StreamResult& s : r.streams) {
        const FormatStats& f = statsFor(s, FormatId::Chosen);
        SCOPED_TRACE(s.stream.name);
        // Even weights no foveate pass produces never put NaN into the output colour.
        EXPECT_EQ(f.nonFiniteOutput, 0u);
        if (s.stream.domain == Domain::Outside) continue;
        EXPECT_EQ(f.nonFiniteStored, 0u) << "NaN/Inf field or w_sum <= 0 stored";
        EXPECT_LE(f.boundRatioMax, 1.0) << "w_sum above sqrt(1 + 2.25 (n - 1)) (bias on) or n (bias off)";
        EXPECT_GT(f.wsumMin, 0.0);
        EXPECT_EQ(f.mWraps, 0u);
        EXPECT_EQ(f.lost, 0u) << "a stored reservoir loaded as invalid";
        EXPECT_EQ(f.identityViolations, 0u) << "kept sample's words differ from its candidate's";
        EXPECT_EQ(f.zeroWeightSelected, 0u) << "a weight-0 candidate replaced existing history";
        EXPECT_LE(f.mMax, WRS_M_MAX);
    }
    // The checks the command's exit status uses: all pass for the shipping layout.
    for (const Check& c : evaluate(&r, nullptr)) EXPECT_TRUE(c.pass) << c.what << ": " << c.detail;
}

void selectionFrequenciesMatchTheExactModel(const CpuResult& r) {
    int modelled = 0;
    for (const StreamResult& s : r.streams) {
        if (!selectionAsserted(s.stream)) continue;
        SCOPED_TRACE(s.stream.name);
        for (FormatId fid : {FormatId::Chosen}) {
            const FormatStats& f = statsFor(s, fid);
            EXPECT_LT(std::fabs(f.conditional.z()), kZLimit) << formatInfo(fid).name;
            EXPECT_LT(std::fabs(f.conditionalAfterCap.z()), kZLimit) << formatInfo(fid).name;
            if (s.modelWsum.empty()) continue;
            ++modelled;
            EXPECT_LT(std::fabs(f.unconditional.z()), kZLimit) << formatInfo(fid).name;
            if (f.chiMid.valid) {
                EXPECT_GT(f.chiMid.p, kChiLimit) << formatInfo(fid).name;
            }
            if (f.chiFinal.valid) {
                EXPECT_GT(f.chiFinal.p, kChiLimit) << formatInfo(fid).name;
            }
        }
    }
    EXPECT_GE(modelled, 8);
    // The tests have power: enough decisions and replacements to see a 5 % bias.
    const FormatStats& c = statsFor(find(r, "constant"), FormatId::Chosen);
    EXPECT_GT(c.unconditional.expected, 5000.0);
    EXPECT_LT(std::sqrt(c.unconditional.variance), 0.02 * c.unconditional.expected);
}

void wsumGrowsAsTheSquareRootOrSettlesWhereTheChangeTermBalancesIt(const CpuResult& r) {
    // |ΔL| = 0 (grey 0.5 is an fp16 value): s_n ~ sqrt(2n), as the exact model, to 0.5 %.
    const StreamResult& c = find(r, "constant");
    const FormatStats& cf = statsFor(c, FormatId::Chosen);
    EXPECT_NEAR(cf.wsumFinalMean, c.modelWsum.back(), 0.005 * c.modelWsum.back());
    EXPECT_NEAR(cf.wsumFinalMean, std::sqrt(2.0 * 100000), 0.01 * std::sqrt(2.0 * 100000));
    // Grey 0.3 is rounded by fp16 storage: the change term sees |ΔL| = c > 0 every frame and w_sum
    // settles at w / sqrt(c) = 154 (s (1 - c) s / (s + w) + w = s  <=>  s = w / sqrt(c)).
    const StreamResult& q = find(r, "constant-q");
    const double cq = gpu::wrs_change(gpu::WRS_CHANGE_LSTAR, gpu::vec3(0.3f), gpu::vec3(gpu::wrs_round_f16(0.3f)));
    const FormatStats& qf = statsFor(q, FormatId::Chosen);
    EXPECT_NEAR(qf.wsumFinalMean, 1.0 / std::sqrt(cq), 0.01 / std::sqrt(cq));
    EXPECT_GT(qf.wsumFrozenFrom, 0u) << "reached its fixed point";
    // The fp32 baseline does not round the colour: no change term, square-root growth.
    CpuOptions o;
    o.frames = 100000;
    o.pixels = 4;
    o.streams = {"constant-q"};
    o.formats = {FormatId::F32};
    auto f32 = runCpu(o);
    ASSERT_TRUE(f32.ok());
    EXPECT_NEAR(f32->streams[0].formats[0].wsumFinalMean, std::sqrt(2.0 * 100000), 0.01 * std::sqrt(2.0 * 100000));
    // Without the eq. 6 bias w_sum counts the frames.
    EXPECT_EQ(statsFor(find(r, "unbiased"), FormatId::Chosen).wsumFinalMean, 100000.0);
}

void mSaturatesAt65535AndNothingChangesAfter(const CpuResult& r) {
    const FormatStats& f = statsFor(find(r, "constant"), FormatId::Chosen);
    EXPECT_EQ(f.mMax, 65535u);
    EXPECT_EQ(f.firstCapFrame, 65535u) << "M = n without flushes";
    EXPECT_EQ(f.mAtCap, 16u * (100000 - 65535 + 1));
    EXPECT_GT(f.conditionalAfterCap.expected, 500.0);
    EXPECT_LT(std::fabs(f.conditionalAfterCap.z()), kZLimit);
}

void knownDeviationOfTinyWeightsIsWhereTheDocSaysIt(const CpuResult& r) {
    // w = FLT_MIN every frame: w_sum is floored at WRS_WSUM_MIN = 1e-30, the increment 1.2e-38 is far
    // below half an ulp, and the first sample is never replaced. The scale-free model replaces it.
    const StreamResult& s = find(r, "min-normal");
    const FormatStats& f = statsFor(s, FormatId::Chosen);
    EXPECT_FALSE(s.stream.knownDeviation.empty());
    EXPECT_EQ(f.replaced, 0u);
    EXPECT_EQ(f.wsumMin, double(gpu::WRS_WSUM_MIN));
    EXPECT_EQ(f.wsumMax, double(gpu::WRS_WSUM_MIN));
    EXPECT_LT(f.unconditional.z(), -kZLimit) << "the unconditional test sees the deviation";
    EXPECT_EQ(f.nonFiniteStored, 0u);
}

TEST(StressCpu, ShortRunOfEveryStream) {
    CpuOptions o;
    o.frames = 100000;
    o.pixels = 16;
    o.seed = 1;
    o.formats = {FormatId::Chosen};
    auto r = runCpu(o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    std::printf("  10^5 frames x 16 pixels x %zu streams: %.1f s\n", r->streams.size(), r->wall_s);
    {
        SCOPED_TRACE("invariants");
        everyStreamKeepsTheInvariants(*r);
    }
    {
        SCOPED_TRACE("selection frequencies");
        selectionFrequenciesMatchTheExactModel(*r);
    }
    {
        SCOPED_TRACE("w_sum growth");
        wsumGrowsAsTheSquareRootOrSettlesWhereTheChangeTermBalancesIt(*r);
    }
    {
        SCOPED_TRACE("M saturation");
        mSaturatesAt65535AndNothingChangesAfter(*r);
    }
    {
        SCOPED_TRACE("known deviation");
        knownDeviationOfTinyWeightsIsWhereTheDocSaysIt(*r);
    }
}

TEST(StressCpu, Fp16WsumVariantBreaksWhereTheStudySays) {
    CpuOptions o;
    o.frames = 10000;
    o.pixels = 16;
    o.streams = {"constant", "min-normal"};
    o.formats = {FormatId::Chosen, FormatId::WsumF16};
    auto r = runCpu(o);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const Horizon h = horizon(FormatId::WsumF16, 1.0f, true, 100000);
    std::printf("  fp16 w_sum, w = 1: frozen at frame %llu, w_sum %.6g (exact %.6g)\n", (unsigned long long)h.frame,
                h.wsum, h.exactWsum);
    // Predicted: the increment 1/(s + 1) falls below half an fp16 ulp (1/64 in [32, 64)) at s = 63.
    EXPECT_EQ(h.wsum, 63.0);
    EXPECT_GT(h.frame, 1000u);
    EXPECT_LT(h.frame, 2000u);

    const StreamResult& c = find(*r, "constant");
    const FormatStats& shipping = statsFor(c, FormatId::Chosen);
    const FormatStats& f16 = statsFor(c, FormatId::WsumF16);
    EXPECT_EQ(f16.wsumFrozenFrom, h.frame) << "the run freezes exactly where the horizon study says";
    EXPECT_EQ(f16.wsumMax, 63.0);
    EXPECT_GT(c.modelWsum.back(), 140.0);  // exact: sqrt(2 * 10^4)
    // The selection statistics catch it: far more new candidates taken than the exact model allows.
    EXPECT_GT(f16.unconditional.z(), 10.0);
    EXPECT_LT(std::fabs(shipping.unconditional.z()), kZLimit);

    // Weights below 2^-25 round w_sum to fp16 0: every stored reservoir is discarded on load.
    const FormatStats& tiny = statsFor(find(*r, "min-normal"), FormatId::WsumF16);
    EXPECT_EQ(tiny.lost, 16u * (10000 - 1));
    EXPECT_EQ(tiny.nonFiniteStored, 16u * 10000);
    EXPECT_EQ(statsFor(find(*r, "min-normal"), FormatId::Chosen).lost, 0u);
}

TEST(StressCpu, SafeHorizonOfTheShippingLayout) {
    // A constant-weight pixel's w_sum stops growing when w^2/(s + w) < half an ulp of s. With s ~ w sqrt(2n)
    // that is n ~ 2^23 whatever w (docs/stability.md); the fp32 rounding of the bias makes it earlier.
    for (float w : {1.0f, 0.37f, 7.07e-6f}) {
        const Horizon h = horizon(FormatId::Chosen, w, true, uint64_t(1) << 25);
        SCOPED_TRACE(w);
        EXPECT_FALSE(h.lost);
        EXPECT_GT(h.frame, uint64_t(1) << 22);
        EXPECT_LT(h.frame, uint64_t(1) << 24);
        EXPECT_GT(h.wsum / w, 3000.0);
        EXPECT_LT(h.wsum / w, 5793.0);  // 4096 sqrt(2)
    }
    // The horizon loop uses the change metric `off`, claiming the same bits as L* for identical colours.
    Reservoir a = wrs_unpack(wrs_pack(wrs_reservoir(gpu::vec3(0.5f), 1.0f, 1.0f, 1u, 1.0f))), b = a;
    for (int n = 0; n < 3000; ++n) {
        bool k;
        a = wrs_unpack(wrs_pack(wrs_combine(true, a, gpu::vec3(0.5f), 0.7f, 1.0f, 0.3f, WRS_CHANGE_OFF, true, k)));
        b = wrs_unpack(wrs_pack(wrs_combine(true, b, gpu::vec3(0.5f), 0.7f, 1.0f, 0.3f, WRS_CHANGE_LSTAR, true, k)));
        ASSERT_EQ(wrs_pack(a), wrs_pack(b)) << n;
    }
}

TEST(StressCpu, StressStepIsTheReferenceStep) {
    // The CPU reference (all passes, foveation none, depth and motion) against stress/step.h on the
    // reference's own candidates: bit-identical reservoirs, so the long CPU runs use the pipeline's step.
    const uint32_t W = 24, H = 20;
    CompositorConfig cfg;
    cfg.method = Method::WrsPaper;
    cfg.foveation = FoveationMode::None;
    cfg.seed = 5;
    Reference ref(cfg);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const float nan = std::nanf("");
    gpu::FrameParams params{};
    for (int e = 0; e < 2; ++e) {
        params.eye[e].fov_tan = gpu::vec4(-0.5f, 0.5f, 0.4f, -0.4f);
        params.eye[e].depth_range = gpu::vec4(kNearZ, kFarZ, 0.0f, 0.0f);
        // Motion in pixels, no reach limit.
        params.eye[e].motion_scale = gpu::vec4(1.0f, 1.0f, 1.0f, std::numeric_limits<float>::infinity());
    }
    params.tuning = gpu::vec4(7.5f, kDepthTau, 0.0f, 0.0f);
    uint64_t compared = 0, kept = 0;
    std::array<std::vector<glm::uvec4>, 2> prev;
    for (uint32_t n = 1; n <= 60; ++n) {
        params.size = gpu::uvec4(W, H, n, cfg.seed);
        std::array<Reference::EyeInput, 2> in;
        for (int e = 0; e < 2; ++e) {
            params.eye[e].gaze = gpu::vec4(glm::normalize(glm::vec3(u(rng) - 0.5f, u(rng) - 0.5f, -1.0f)), 2.5f);
            in[e].color = HostImage::make(layers::Format::RGBA16F, W, H);
            in[e].depth = HostImage::make(layers::Format::R32F, W, H);
            in[e].motion = HostImage::make(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const float g = (x / 4 + y / 4 + n / 7) % 3 * 0.3f;
                    in[e].color.store(x, y, glm::vec4(u(rng) < 0.02f ? nan : g, g, g, 1.0f));
                    in[e].depth->store(x, y, glm::vec4(u(rng) < 0.1f ? 0.9f : 0.5f));
                    const float m = u(rng);
                    in[e].motion->store(x, y,
                                        m < 0.1f   ? glm::vec4(nan)
                                        : m < 0.2f ? glm::vec4(-30.0f, 1.0f, 0, 0)
                                                   : glm::vec4(0.0f));
                }
            prev[e] = n > 1 ? ref.reservoirs(e) : std::vector<glm::uvec4>(std::size_t(W) * H, glm::uvec4(0u));
        }
        ref.step(params, in);
        for (uint32_t e = 0; e < 2; ++e)
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x;
                    glm::uvec2 q;
                    float dz;
                    const bool on =
                        wrs_reproject(glm::uvec2(x, y), glm::uvec2(W, H), glm::vec3(in[e].motion->fetch(x, y)), q, dz);
                    const glm::vec4 c = ref.candidates(e)[i];
                    Candidate cd;
                    cd.color = glm::vec3(c);
                    cd.weight = c.w;
                    cd.z = wrs_linear_depth(in[e].depth->fetch(x, y).x, kNearZ, kFarZ, false);
                    const StepOut so = temporalStep(wrs_unpack(prev[e][std::size_t(q.y) * W + q.x]), on, true, cd, dz,
                                                    kDepthTau, wrs_rand(x, y, e, n, cfg.seed), WRS_CHANGE_LSTAR, true);
                    ASSERT_EQ(wrs_pack(so.r), ref.reservoirs(e)[i])
                        << "frame " << n << " eye " << e << " " << x << "," << y;
                    compared++;
                    kept += so.hadHistory && so.keep;
                }
    }
    EXPECT_EQ(compared, 60u * 2 * W * H);
    EXPECT_GT(kept, compared / 4);
}

TEST(StressFormats, StudyVariantsRoundTripAsDescribed) {
    const Reservoir r = wrs_reservoir(gpu::vec3(0.3f, 1.0f, 70000.0f), 0.1f, 0.3f, 300u, 2.0f);
    EXPECT_EQ(wrs_pack(roundTrip(FormatId::Chosen, r)), wrs_pack(r));
    const Reservoir f = roundTrip(FormatId::F32, r);
    EXPECT_EQ(f.color.x, 0.3f);
    EXPECT_EQ(f.w_sum, 0.3f);
    EXPECT_EQ(roundTrip(FormatId::WsumF16, r).w_sum, gpu::wrs_round_f16(0.3f));
    EXPECT_EQ(roundTrip(FormatId::MU8, r).M, 255u);
    EXPECT_EQ(roundTrip(FormatId::MU8Wrap, wrs_reservoir(gpu::vec3(0.0f), 1, 1, 256u, 1)).M, 0u);
    EXPECT_EQ(roundTrip(FormatId::MF16, wrs_reservoir(gpu::vec3(0.0f), 1, 1, 2049u, 1)).M, 2048u);
    EXPECT_EQ(roundTrip(FormatId::MF16, wrs_reservoir(gpu::vec3(0.0f), 1, 1, 2047u, 1)).M, 2047u);
    for (const FormatInfo& fi : formats()) EXPECT_EQ(parseFormat(fi.name), fi.id);
    EXPECT_FALSE(parseFormat("fp8").has_value());
}

TEST(StressStatistics, TailsAndChiSquare) {
    EXPECT_NEAR(chiSquareUpperTail(3.841459, 1), 0.05, 1e-6);
    EXPECT_NEAR(chiSquareUpperTail(18.307038, 10), 0.05, 1e-6);
    EXPECT_NEAR(chiSquareUpperTail(10.0, 2), std::exp(-5.0), 1e-12);  // dof 2: exactly exp(-x/2)
    EXPECT_NEAR(chiSquareUpperTail(200.0, 150), 0.00398, 1e-4);       // Wilson-Hilferty: 0.00398
    EXPECT_NEAR(normalTwoSided(1.959964), 0.05, 1e-6);
    // Observed far from expected fails; on target passes.
    std::map<BucketKey, double> e{{{0, 0}, 0.5}, {{1, 0}, 0.5}};
    EXPECT_LT(chiSquare(e, {{{0, 0}, 700}, {{1, 0}, 300}}, 1000).p, 1e-10);
    EXPECT_GT(chiSquare(e, {{{0, 0}, 505}, {{1, 0}, 495}}, 1000).p, 0.5);
    ZTest z;
    for (int i = 0; i < 1000; ++i) z.add(0.5);
    z.observed = 500;
    EXPECT_EQ(z.z(), 0.0);
    z.observed = 600;
    EXPECT_NEAR(z.z(), 100.0 / std::sqrt(250.0), 1e-9);
}

TEST(StressCpu, RefusesBadOptions) {
    CpuOptions o;
    o.frames = 1;
    EXPECT_FALSE(runCpu(o).ok());
    o.frames = 10;
    o.streams = {"no-such-stream"};
    auto r = runCpu(o);
    ASSERT_FALSE(r.ok());
    EXPECT_NE(r.error().message.find("no-such-stream"), std::string::npos);
}

}  // namespace
}  // namespace wrsfov::stress
