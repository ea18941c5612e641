#include "stress/streams.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>
#include <memory>

#include "shaders/wrs_common.h"

namespace wrsfov::stress {

namespace {

// Stream content randomness (not the combine's rand, which is wrs_rand): splitmix64 of the inputs.
uint64_t mix(uint64_t x) {
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}
uint64_t hash(uint32_t seed, uint32_t stream, uint64_t a, uint64_t b = 0) { return streamHash(seed, stream, a, b); }
float unit(uint64_t h) { return unitFloat(h); }

constexpr float kGrey = 0.5f;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// ΔL of eq. 7 between two colours, from the shared function (the exact model needs its value, not a
// second implementation of CIELAB).
double lstarChange(glm::vec3 a, glm::vec3 b) { return gpu::wrs_change(gpu::WRS_CHANGE_LSTAR, a, b); }

// ΔL between a colour and its fp16-stored self: what the change term sees when the candidate equals
// the kept sample before storage.
double quantizationChange(glm::vec3 c) {
    return lstarChange(c, glm::vec3(gpu::wrs_round_f16(c.x), gpu::wrs_round_f16(c.y), gpu::wrs_round_f16(c.z)));
}

// Depth values that the load pass maps to "unknown" (docs/conventions.md, "Depth").
constexpr float kBadDepth[4] = {kNaN, -0.5f, 1.5f, kInf};

}  // namespace

uint64_t streamHash(uint32_t seed, uint32_t stream, uint64_t a, uint64_t b) {
    return mix(mix(mix(uint64_t(seed) << 32 | stream) ^ a) ^ b);
}
float unitFloat(uint64_t h) { return float(h >> 40) * (1.0f / 16777216.0f); }

std::string_view toString(Domain d) {
    switch (d) {
        case Domain::Pipeline:
            return "pipeline";
        case Domain::Extreme:
            return "extreme";
        case Domain::Outside:
            return "outside";
    }
    return "?";
}

float minPipelineWeight() { return gpu::wrs_watson_density(180.0f) / gpu::wrs_watson_density(0.0f); }

std::vector<std::string> streamNames() {
    std::vector<std::string> names;
    for (const Stream& s : makeStreams(1000, 1)) names.push_back(s.name);
    return names;
}

std::vector<Stream> makeStreams(uint64_t frames, uint32_t seed) {
    std::vector<Stream> v;
    uint32_t id = 0;
    auto add = [&](Stream s) {
        ++id;
        v.push_back(std::move(s));
    };

    {
        Stream s{"constant", "grey, w = 1, fixed depth: the longest possible static history"};
        s.sample = [](uint64_t, uint32_t) { return StreamSample{}; };
        s.model = [](uint64_t, bool) { return ModelStep{}; };
        add(std::move(s));
    }
    {
        // 0.3 is not an fp16 value: the kept sample (stored in fp16) and the identical next candidate
        // differ by |ΔL| = 4.2e-5, and w_sum settles where the bias balances the growth.
        Stream s{"constant-q", "as constant with grey 0.3, which fp16 storage rounds: a small |ΔL| every frame"};
        s.sample = [](uint64_t, uint32_t) {
            StreamSample x;
            x.color = glm::vec3(0.3f);
            return x;
        };
        const double c = quantizationChange(glm::vec3(0.3f));
        s.model = [c](uint64_t, bool f16) { return ModelStep{1.0, f16 ? c : 0.0, false}; };
        add(std::move(s));
    }
    {
        Stream s{"unbiased", "as constant with the eq. 6 bias off (CompositorConfig::bernoulli = false): w_sum = n"};
        s.bernoulli = false;
        s.sample = [](uint64_t, uint32_t) { return StreamSample{}; };
        s.model = [](uint64_t, bool) { return ModelStep{}; };
        add(std::move(s));
    }
    {
        Stream s{"alternating", "w alternates 1 (odd frames) and 1e-6 (even frames), grey"};
        s.domain = Domain::Extreme;
        s.classes = {"w=1", "w=1e-6"};
        s.sample = [](uint64_t n, uint32_t) {
            StreamSample x;
            x.weight = n % 2 ? 1.0f : 1e-6f;
            x.cls = n % 2 ? 0u : 1u;
            return x;
        };
        s.model = [](uint64_t n, bool) { return ModelStep{n % 2 ? 1.0 : double(1e-6f), 0.0, false}; };
        add(std::move(s));
    }
    {
        Stream s{"zero", "zero-weight candidates with a valid colour in 3 of 4 frames, w = 1 in the 4th"};
        s.domain = Domain::Extreme;
        s.classes = {"w=1", "w=0"};
        s.sample = [](uint64_t n, uint32_t) {
            StreamSample x;
            x.weight = n % 4 == 1 ? 1.0f : 0.0f;
            x.cls = n % 4 == 1 ? 0u : 1u;
            return x;
        };
        s.model = [](uint64_t n, bool) { return ModelStep{n % 4 == 1 ? 1.0 : 0.0, 0.0, false}; };
        add(std::move(s));
    }
    {
        // 1, 1/2, ..., 2^-126 = FLT_MIN, the denormals down to 2^-149, then 0 and FLT_MIN again.
        Stream s{"tiny", "w sweeps 2^-k for k = 0..149 (FLT_MIN at 126, denormals after), then 0, FLT_MIN; grey"};
        s.domain = Domain::Extreme;
        s.classes = {"w>=2^-24", "2^-24>w>=FLT_MIN", "denormal", "w=0"};
        auto w = [](uint64_t n) {
            const uint64_t k = (n - 1) % 152;
            return k < 150 ? std::ldexp(1.0f, -int(k)) : k == 150 ? 0.0f : FLT_MIN;
        };
        s.sample = [w](uint64_t n, uint32_t) {
            StreamSample x;
            x.weight = w(n);
            x.cls = x.weight >= std::ldexp(1.0f, -24) ? 0u : x.weight >= FLT_MIN ? 1u : x.weight > 0.0f ? 2u : 3u;
            return x;
        };
        s.model = [w](uint64_t n, bool) { return ModelStep{double(w(n)), 0.0, false}; };
        add(std::move(s));
    }
    {
        Stream s{"min-normal", "w = FLT_MIN (1.2e-38) every frame, grey"};
        s.domain = Domain::Extreme;
        s.knownDeviation =
            "w_sum is floored at WRS_WSUM_MIN = 1e-30: weights below 2^-24 * 1e-30 can never replace the first "
            "sample (the exact model is scale-free and replaces as for w = 1)";
        s.sample = [](uint64_t, uint32_t) {
            StreamSample x;
            x.weight = FLT_MIN;
            return x;
        };
        s.model = [](uint64_t, bool) { return ModelStep{double(FLT_MIN), 0.0, false}; };
        add(std::move(s));
    }
    {
        // Invalid candidates get weight 0 and the sanitized colour (black) enters the change term.
        Stream s{"invalid", "colour NaN in 3 of 4 frames (weight 0 after the load pass), grey in the 4th"};
        s.classes = {"grey", "NaN"};
        const double c = lstarChange(glm::vec3(0.0f), glm::vec3(gpu::wrs_round_f16(kGrey)));
        s.sample = [](uint64_t n, uint32_t) {
            StreamSample x;
            if (n % 4 != 1) {
                x.color = glm::vec3(kNaN);
                x.cls = 1;
            }
            return x;
        };
        s.model = [c](uint64_t n, bool) { return n % 4 == 1 ? ModelStep{} : ModelStep{0.0, c, false}; };
        add(std::move(s));
    }
    {
        Stream s{"nonfinite",
                 "each channel cycles through NaN, +Inf, -Inf, 0, 1, 65504, 1e30, -1, 1e-40, 0.5 (phase per pixel "
                 "and channel); w = 1"};
        s.classes = {"valid", "invalid"};
        s.sample = [](uint64_t n, uint32_t i) {
            static constexpr float vals[10] = {kNaN, kInf, -kInf, 0.0f, 1.0f, 65504.0f, 1e30f, -1.0f, 1e-40f, 0.5f};
            StreamSample x;
            x.color = glm::vec3(vals[(n + i) % 10], vals[(n + 3 * i + 3) % 10], vals[(n + 7 * i + 7) % 10]);
            bool valid;
            (void)gpu::wrs_sanitize_color(x.color, valid);
            x.cls = valid ? 0u : 1u;
            return x;
        };
        add(std::move(s));
    }
    {
        Stream s{"binary", "colour 0 or 1 at random every frame (|ΔL| = 1 at each change), w = 1"};
        s.classes = {"black", "white"};
        const uint32_t sid = id;
        s.sample = [seed, sid](uint64_t n, uint32_t i) {
            StreamSample x;
            const bool white = hash(seed, sid, n, i) & 1u;
            x.color = glm::vec3(white ? 1.0f : 0.0f);
            x.cls = white;
            return x;
        };
        add(std::move(s));
    }
    {
        Stream s{"spikes", "black with a white frame every 50th frame (|ΔL| = 1 spikes), w = 1"};
        s.classes = {"black", "spike"};
        s.sample = [](uint64_t n, uint32_t) {
            StreamSample x;
            const bool spike = n % 50 == 0;
            x.color = glm::vec3(spike ? 1.0f : 0.0f);
            x.cls = spike;
            return x;
        };
        add(std::move(s));
    }
    {
        // Every frame the depth jumps between 0.25 and 0.75 (linear 0.133 and 0.399: a flush); every 7th
        // frame it is unknown (NaN, -0.5, 1.5, +Inf), which skips the depth test in that frame and the next.
        Stream s{"depth-jumps",
                 "depth alternates 0.25 / 0.75 every frame, unknown (NaN, <0, >1, Inf) every 7th; w = 1"};
        auto bad = [](uint64_t n) { return n % 7 == 0; };
        s.sample = [bad](uint64_t n, uint32_t) {
            StreamSample x;
            x.depth = bad(n) ? kBadDepth[(n / 7) % 4] : n % 2 ? 0.25f : 0.75f;
            return x;
        };
        s.model = [bad](uint64_t n, bool) {
            ModelStep m;
            m.flush = !bad(n) && !bad(n - 1);
            return m;
        };
        add(std::move(s));
    }
    {
        // Static periods of random length (1/50 to 1/5 of the run), each with its own grey level, weight
        // and depth; consecutive periods differ in depth by far more than tau, so each starts afresh.
        Stream s{"static", "long static periods (2% to 20% of the run each), then colour, weight and depth change"};
        const uint32_t sid = id;
        auto starts = std::make_shared<std::vector<uint64_t>>();
        const uint64_t lo = std::max<uint64_t>(frames / 50, 2), hi = std::max<uint64_t>(frames / 5, lo + 1);
        for (uint64_t n = 1, k = 0; n <= frames + 1; ++k) {
            starts->push_back(n);
            n += lo + hash(seed, sid, k, 1) % (hi - lo);
        }
        auto period = [starts](uint64_t n) {
            return uint64_t(std::upper_bound(starts->begin(), starts->end(), n) - starts->begin()) - 1;
        };
        auto weight = [seed, sid](uint64_t k) {
            return gpu::wrs_sample_weight(20.0f * unit(hash(seed, sid, k, 2)), 2.5f);
        };
        s.sample = [seed, sid, period, weight](uint64_t n, uint32_t) {
            const uint64_t k = period(n);
            StreamSample x;
            x.color = glm::vec3(0.2f + 0.6f * unit(hash(seed, sid, k, 3)));
            x.weight = weight(k);
            x.depth = k % 2 ? 0.8f : 0.3f;
            x.cls = uint32_t(k % 2);
            return x;
        };
        s.classes = {"even period", "odd period"};
        s.model = [seed, sid, starts, period, weight](uint64_t n, bool f16) {
            const uint64_t k = period(n);
            const float g = 0.2f + 0.6f * unit(hash(seed, sid, k, 3));
            return ModelStep{double(weight(k)), f16 ? quantizationChange(glm::vec3(g)) : 0.0,
                             k > 0 && (*starts)[k] == n};
        };
        add(std::move(s));
    }
    {
        // Gaze fixations of 25 frames at a random eccentricity up to 40°; the stream's pixels lie on a
        // line 0.5° apart, so each pixel sees a different weight sequence. Colour noise gives small ΔL.
        Stream s{"random",
                 "weights of a saccading gaze (p̂ of the pipeline, r_f = 2.5°), colour noise ±0.02, depth noise"};
        const uint32_t sid = id;
        s.sample = [seed, sid](uint64_t n, uint32_t i) {
            StreamSample x;
            const float gazeEcc = 40.0f * unit(hash(seed, sid, n / 25, 0));
            const float drift = 0.3f * unit(hash(seed, sid, n, 1));
            x.weight = gpu::wrs_sample_weight(std::fabs(gazeEcc - 0.5f * float(i % 80)) + drift, 2.5f);
            x.color = glm::vec3(kGrey + 0.04f * (unit(hash(seed, sid, n, i + 2)) - 0.5f));
            x.depth = 0.5f + 0.001f * (unit(hash(seed, sid, n, i + 1000003)) - 0.5f);
            return x;
        };
        add(std::move(s));
    }
    {
        Stream s{"out-of-range", "weights no foveate pass produces: 1e5, 1e30, FLT_MAX, +Inf, NaN, -1, 2 (cycling)"};
        s.domain = Domain::Outside;
        s.sample = [](uint64_t n, uint32_t i) {
            static constexpr float ws[7] = {1e5f, 1e30f, FLT_MAX, kInf, kNaN, -1.0f, 2.0f};
            StreamSample x;
            x.weight = ws[(n + i) % 7];
            return x;
        };
        add(std::move(s));
    }
    return v;
}

}  // namespace wrsfov::stress
