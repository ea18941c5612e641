#include "stress/gpu_stress.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "compositor/compositor.h"
#include "compositor/host_app.h"
#include "compositor/reference.h"
#include "stress/step.h"

namespace wrsfov::stress {

using namespace gpu;

namespace {

constexpr float kDeg = 3.14159265f / 180.0f;
constexpr uint32_t kAgedM = 65500;
constexpr float kAgedWsum = 4095.5f;
// A selection that differs where the random number lies this close to the keep threshold comes from
// the device's exp/pow rounding of the weight or the change term (docs/conventions.md, "GPU and CPU
// agreement": the GPU and the reference differ only in built-in functions).
constexpr float kNearThreshold = 1e-5f;

glm::vec3 direction(float azimuthDeg, float elevationDeg) {
    const float az = azimuthDeg * kDeg, el = elevationDeg * kDeg;
    return glm::vec3(std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el));
}

layers::EyeGaze gazeOf(uint32_t eye, uint64_t n, uint32_t seed) {
    layers::EyeGaze g;
    g.valid = true;
    g.confidence = 1.0f;
    if (eye == 0) {
        if (n % 16 == 0) {
            g.valid = false;  // fallback: view centre with the 20° fallback fovea
            g.confidence = 0.0f;
        }
        g.dir = n % 2 ? glm::vec3(0.0f, 0.0f, -1.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
        return g;
    }
    const uint64_t k = n / 20;
    const float az = 60.0f * (unitFloat(streamHash(seed, 1000, k, 0)) - 0.5f) +
                     0.2f * (unitFloat(streamHash(seed, 1001, n, 0)) - 0.5f);
    const float el = 60.0f * (unitFloat(streamHash(seed, 1000, k, 1)) - 0.5f) +
                     0.2f * (unitFloat(streamHash(seed, 1001, n, 1)) - 0.5f);
    g.dir = direction(az, el);
    return g;
}

glm::vec4 motionOf(RowMotion m, uint64_t n) {
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
    switch (m) {
        case RowMotion::NonFinite:
            return n % 2 ? glm::vec4(0.0f) : glm::vec4(nan, inf, nan, 0.0f);
        case RowMotion::OffScreen:
            return n % 3 ? glm::vec4(0.0f) : glm::vec4(-1000.0f, 0.0f, 0.0f, 0.0f);
        case RowMotion::Zero:
            break;
    }
    return glm::vec4(0.0f);
}

uint32_t ulpDistance(uint32_t a, uint32_t b) {
    // Both are w_sum bit patterns of positive floats: ordered like integers.
    return a > b ? a - b : b - a;
}

bool reservoirSane(const glm::uvec4& p) {
    const Reservoir r = wrs_unpack(p);
    return wrs_finite3(r.color) && wrs_finite(r.w) && wrs_finite(r.w_sum) && wrs_finite(r.z) && r.w_sum > 0.0f;
}

}  // namespace

std::vector<GpuRow> defaultGpuRows() {
    return {{"constant"},
            {"constant", RowMotion::Zero, true},
            {"constant-q"},
            {"binary"},
            {"spikes"},
            {"nonfinite"},
            {"invalid"},
            {"depth-jumps"},
            {"static"},
            {"random"},
            {"constant", RowMotion::NonFinite},
            {"binary", RowMotion::OffScreen},
            {"random", RowMotion::Zero, true},
            {"depth-jumps", RowMotion::NonFinite},
            {"spikes", RowMotion::Zero, true},
            {"nonfinite", RowMotion::OffScreen}};
}

Result<GpuResult> runGpu(vk::Context& ctx, const GpuOptions& options) {
    GpuOptions o = options;
    if (o.rows.empty()) o.rows = defaultGpuRows();
    if (o.frames < 1) return Error{1, "--gpu-frames must be at least 1"};
    if (o.frames > 0xffffffffull) return Error{1, "--gpu-frames must fit the 32-bit frame index of wrs_rand"};
    if (o.width < 1 || o.width > 1024) return Error{1, "GPU width must be in 1..1024"};
    if (o.rows.size() > 1024) return Error{1, "at most 1024 GPU rows"};

    const std::vector<Stream> all = makeStreams(o.frames, o.seed);
    std::vector<const Stream*> rowStream;
    for (const GpuRow& r : o.rows) {
        auto it = std::find_if(all.begin(), all.end(), [&](const Stream& s) { return s.name == r.stream; });
        if (it == all.end()) return Error{1, "unknown GPU row stream '" + r.stream + "'"};
        if (!it->bernoulli)
            return Error{1, "stream '" + r.stream + "' needs the eq. 6 bias off; the GPU run has one configuration"};
        if (it->domain == Domain::Outside)
            return Error{1, "stream '" + r.stream + "' has weights the foveate pass cannot produce"};
        rowStream.push_back(&*it);
    }

    GpuResult res;
    res.device = ctx.deviceName();
    res.validation = ctx.validationEnabled();
    res.width = o.width;
    res.height = uint32_t(o.rows.size());
    res.frames = o.frames;
    const uint32_t W = res.width, H = res.height;

    CompositorConfig cfg;
    cfg.method = Method::WrsPaper;
    cfg.foveation = FoveationMode::None;
    cfg.foveaDeg = 5.0f;
    cfg.change = ChangeMetric::LStar;
    cfg.bernoulli = true;
    cfg.depthTau = kDepthTau;
    cfg.seed = o.seed;
    auto comp = Compositor::create(ctx, cfg);
    if (!comp) return comp.error();
    HostStereoApp::Options ao;
    ao.width = W;
    ao.height = H;
    ao.color = layers::Format::RGBA16F;
    ao.depth = layers::Format::R32F;
    ao.motion = layers::Format::RGBA16F;
    ao.nearZ = kNearZ;
    ao.farZ = kFarZ;
    auto app = HostStereoApp::create(**comp, ao);
    if (!app) return app.error();
    Reference ref(cfg);
    layers::Fov fov;  // 3° x 3°: every pixel within 2.1° of the centre, inside the 2.5° fovea radius
    fov.angleLeft = fov.angleDown = -1.5f * kDeg;
    fov.angleRight = fov.angleUp = 1.5f * kDeg;

    res.rows.resize(H);
    for (uint32_t r = 0; r < H; ++r) res.rows[r].row = o.rows[r];
    const uint32_t errorsBefore = ctx.validationErrors();
    const auto t0 = std::chrono::steady_clock::now();
    int reported = 0;
    std::array<std::vector<glm::uvec4>, 2> prev;

    for (uint64_t n = 1; n <= o.frames; ++n) {
        std::array<EyeSubmission, 2> eyes;
        for (uint32_t e = 0; e < 2; ++e) {
            EyeSubmission& s = eyes[e];
            s.fov = fov;
            s.color = HostImage::make(layers::Format::RGBA16F, W, H);
            s.depth = HostImage::make(layers::Format::R32F, W, H);
            s.motion = HostImage::make(layers::Format::RGBA16F, W, H);
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const StreamSample smp = rowStream[y]->sample(n, x + e * W);
                    s.color.store(x, y, glm::vec4(smp.color, 1.0f));
                    s.depth->store(x, y, glm::vec4(smp.depth));
                    s.motion->store(x, y, motionOf(o.rows[y].motion, n));
                }
            s.gaze = gazeOf(e, n, o.seed);
        }

        if (n == 2) {
            // Age the marked rows on both sides alike, from the GPU's first frame.
            for (uint32_t e = 0; e < 2; ++e) {
                auto g = (*comp)->readReservoirs(e);
                if (!g) return g.error();
                for (uint32_t y = 0; y < H; ++y) {
                    if (!o.rows[y].aged) continue;
                    for (uint32_t x = 0; x < W; ++x) {
                        Reservoir rv = wrs_unpack((*g)[y * W + x]);
                        rv.M = kAgedM;
                        rv.w_sum = kAgedWsum;
                        (*g)[y * W + x] = wrs_pack(rv);
                    }
                }
                if (Status s = (*comp)->writeReservoirs(e, *g); !s) return s.error();
                ref.setHistory(e, *g);
            }
        }

        for (uint32_t e = 0; e < 2; ++e)
            prev[e] = n > 1 ? ref.reservoirs(e) : std::vector<glm::uvec4>(std::size_t(W) * H, glm::uvec4(0u));
        if (Status s = (*app)->submit(n, double(n) / 90.0, eyes); !s)
            return Error{s.error().code, "frame " + std::to_string(n) + ": " + s.message()};
        FrameParams params = (*comp)->lastParams();
        params.size.w += o.referenceSeedOffset;
        std::array<Reference::EyeInput, 2> in;
        for (uint32_t e = 0; e < 2; ++e) in[e] = {eyes[e].color, eyes[e].depth, eyes[e].motion};
        ref.step(params, in);

        for (uint32_t e = 0; e < 2; ++e) {
            auto gres = (*comp)->readReservoirs(e);
            if (!gres) return gres.error();
            auto gout = (*comp)->readOutput(e);
            if (!gout) return gout.error();
            const std::vector<glm::uvec4>& cres = ref.reservoirs(e);
            const HostImage& cout = ref.output(e);
            const auto& trace = ref.trace(e);
            const auto& cand = ref.candidates(e);
            const EyeParams& ep = params.eye[e];
            bool resync = false;
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x;
                    GpuRowStats& st = res.rows[y];
                    const glm::uvec4 g = (*gres)[i], c = cres[i];
                    st.pixelFrames++;
                    st.decisions += trace[i].hadHistory;
                    st.kept += trace[i].hadHistory && trace[i].keep;
                    // Selection: the GPU kept the history iff its colour words are the history's. Where the
                    // candidate's colour packs like the history's, only the w field could tell, and that
                    // depends on the rounding of the weight: such decisions are not compared.
                    const Reference::Trace& tr = trace[i];
                    const glm::uvec4 h = prev[e][tr.source];
                    const uint32_t candX = wrs_f32_to_f16(cand[i].x) | (wrs_f32_to_f16(cand[i].y) << 16u);
                    const uint32_t candB = wrs_f32_to_f16(cand[i].z);
                    const bool ambiguous = candX == h.x && candB == (h.y & 0xffffu);
                    const bool gpuKeep = g.x == h.x && (g.y & 0xffffu) == (h.y & 0xffffu);
                    if (tr.hadHistory && gpuKeep != tr.keep && !ambiguous) {
                        st.selectionMismatch++;
                        st.nearThreshold += std::fabs(tr.rnd - tr.threshold) < kNearThreshold;
                        resync = true;
                    } else if (g.x != c.x || (g.y & 0xffffu) != (c.y & 0xffffu)) {
                        st.selectionMismatch++;  // a different colour kept: cannot happen with the same decision
                        resync = true;
                    } else if (g.y != c.y) {
                        // Same decision, the kept weight differs: one fp16 step is the device's exp rounding
                        // landing on the other side of an fp16 rounding boundary; more is a mismatch.
                        st.weightRounding++;
                        if (ulpDistance(g.y >> 16u, c.y >> 16u) > 1u) {
                            st.selectionMismatch++;
                            resync = true;
                        }
                    }
                    if (g.w != c.w) {
                        st.zmMismatch++;
                        resync = true;
                    }
                    if (g.z != c.z) {
                        st.wsumMismatch++;
                        st.wsumMaxUlp = std::max(st.wsumMaxUlp, ulpDistance(g.z, c.z));
                        const float a = uintBitsToFloat(g.z), b = uintBitsToFloat(c.z);
                        const double rel = std::fabs(double(a) - double(b)) / std::max(double(std::fabs(b)), 1e-30);
                        st.wsumMaxRel = std::max(st.wsumMaxRel, rel);
                        if (!(rel <= kWsumTolerance)) resync = true;
                    }
                    if (!reservoirSane(g)) st.nonFinite++;
                    const Reservoir gr = wrs_unpack(g);
                    if (wrs_finite(gr.w_sum)) st.wsumMax = std::max(st.wsumMax, double(gr.w_sum));
                    st.mMax = std::max(st.mMax, gr.M);
                    for (int k = 0; k < 4; ++k) {
                        const int d =
                            std::abs(int(uint8_t(gout->data[i * 4 + k])) - int(uint8_t(cout.data[i * 4 + k])));
                        st.outputDiffs += d != 0;
                        st.outputMaxDiff = std::max(st.outputMaxDiff, d);
                    }
                    // The stress step on the reference's own inputs must give the reference's result.
                    glm::uvec2 q;
                    float dz;
                    const bool onScreen = wrs_reproject(glm::uvec2(x, y), glm::uvec2(W, H),
                                                        glm::vec3(eyes[e].motion->fetch(x, y)), q, dz);
                    const Reservoir hist = wrs_unpack(prev[e][std::size_t(q.y) * W + q.x]);
                    Candidate cd;
                    cd.color = glm::vec3(cand[i]);
                    cd.weight = cand[i].w;
                    cd.z = wrs_linear_depth(eyes[e].depth->fetch(x, y).x, ep.depth_range.x, ep.depth_range.y,
                                            ep.depth_rect.z != 0u);
                    const StepOut so =
                        temporalStep(hist, onScreen, true, cd, dz, params.tuning.y,
                                     wrs_rand(x, y, e, params.size.z, params.size.w), uint(cfg.change), cfg.bernoulli);
                    if (wrs_pack(so.r) != c) st.stepMismatch++;
                    if (n == o.frames) {
                        res.finalPixels++;
                        res.finalIdentical += g == c;
                        const float a = uintBitsToFloat(g.z), b = uintBitsToFloat(c.z);
                        res.finalAgree += g.x == c.x && (g.y & 0xffffu) == (c.y & 0xffffu) &&
                                          ulpDistance(g.y >> 16u, c.y >> 16u) <= 1u && g.w == c.w &&
                                          std::fabs(double(a) - double(b)) <= kWsumTolerance * std::fabs(double(b));
                    }
                }
            if (resync) {
                res.resyncs++;
                ref.setHistory(e, *gres);
            }
        }

        const double frac = double(n) / double(o.frames);
        if (o.progress && (int(frac * 20.0) > reported || n == o.frames)) {
            reported = int(frac * 20.0);
            const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            o.progress(Progress{"gpu", frac, el, el > 0 ? double(n) / el : 0});
        }
    }
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    res.validationErrors = ctx.validationErrors() - errorsBefore;
    return res;
}

}  // namespace wrsfov::stress
