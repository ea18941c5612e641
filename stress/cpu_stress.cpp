#include "stress/cpu_stress.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <set>
#include <thread>

#include "stress/step.h"

namespace wrsfov::stress {

using namespace gpu;

namespace {

uint32_t bits(float f) {
    uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
bool sameBits(vec3 a, vec3 b) { return bits(a.x) == bits(b.x) && bits(a.y) == bits(b.y) && bits(a.z) == bits(b.z); }

std::vector<uint64_t> seriesFrames(uint64_t frames, uint32_t points) {
    std::set<uint64_t> s{1, frames};
    const double l = std::log(double(frames));
    for (uint32_t k = 0; k < points; ++k) {
        s.insert(uint64_t(std::llround(std::exp(l * k / std::max(points - 1, 1u)))));
        s.insert(std::max<uint64_t>(1, frames * (k + 1) / points));  // a linear share for the late frames
    }
    std::vector<uint64_t> v;
    for (uint64_t f : s)
        if (f >= 1 && f <= frames) v.push_back(f);
    return v;
}

struct PixelState {
    Reservoir stored = wrs_reservoir(vec3(0.0f), 0.0f, 0.0f, 0u, 0.0f);  // all-zero memory: no history
    bool producedValid = false;  // what the combine produced last frame was valid before storage
    uint64_t birth = 0;          // frame of the kept sample's candidate
    vec3 birthColor{0.0f};       // its stored colour and weight
    float birthW = 0;
    uint32_t wsumBits = 0;
    uint64_t wsumLastChange = 0;  // pixel 0 only
};

void runStream(const Stream& st, uint32_t streamIndex, const CpuOptions& o, StreamResult& out,
               std::atomic<uint64_t>& done) {
    const uint64_t N = o.frames;
    const uint32_t P = o.pixels;
    const std::vector<FormatId>& fmts = o.formats;
    const size_t F = fmts.size();
    int baseline = -1;
    for (size_t f = 0; f < F; ++f)
        if (fmts[f] == FormatId::F32) baseline = int(f);

    // The model depends on the format only through the colour storage (fp16 everywhere but f32).
    std::vector<ModelFrame> modelF16, modelF32;
    if (st.model) {
        modelF16 = runModel(st, N, true);
        modelF32 = runModel(st, N, false);
    }
    auto modelOf = [&](FormatId f) -> const std::vector<ModelFrame>& {
        return f == FormatId::F32 ? modelF32 : modelF16;
    };
    const bool hasModel = !modelF16.empty();
    const std::vector<uint64_t> sf = seriesFrames(N, o.seriesPoints);
    out.formats.assign(F, FormatStats{});
    for (size_t f = 0; f < F; ++f) {
        out.formats[f].format = fmts[f];
        out.formats[f].series.frames = sf;
    }
    if (hasModel)
        for (uint64_t n : sf) out.modelWsum.push_back(modelF16[n].wsum);

    const uint64_t mid = N / 2;
    std::vector<std::map<BucketKey, uint64_t>> obsMid(F), obsFinal(F);
    std::vector<PixelState> state(size_t(P) * F);
    size_t nextSeries = 0;
    std::vector<double> sum(F), lo(F), hi(F);

    for (uint64_t n = 1; n <= N; ++n) {
        const bool sampleNow = nextSeries < sf.size() && sf[nextSeries] == n;
        if (sampleNow)
            for (size_t f = 0; f < F; ++f) {
                sum[f] = 0;
                lo[f] = INFINITY;
                hi[f] = -INFINITY;
            }
        const double bound = wsumBound(n, st.bernoulli);
        for (uint32_t i = 0; i < P; ++i) {
            const StreamSample s = st.sample(n, i);
            const Candidate cand = loadCandidate(s.color, s.weight, s.depth, kNearZ, kFarZ, false);
            const float rnd = wrs_rand(i, streamIndex, 0u, uint32_t(n), o.seed);
            for (size_t f = 0; f < F; ++f) {
                PixelState& ps = state[size_t(i) * F + f];
                FormatStats& fs = out.formats[f];
                const Reservoir hist = ps.stored;
                const StepOut so =
                    temporalStep(hist, true, true, cand, 0.0f, kDepthTau, rnd, WRS_CHANGE_LSTAR, st.bernoulli);
                const Reservoir stored = roundTrip(fmts[f], so.r);

                if (so.hadHistory) {
                    fs.decisions++;
                    const double change =
                        sameBits(cand.color, hist.color) ? 0.0 : wrs_change(WRS_CHANGE_LSTAR, cand.color, hist.color);
                    const double p = replaceProbability(hist.w_sum, cand.weight, change, st.bernoulli);
                    if (std::isfinite(p)) {  // not for weights outside [0, 1] (Domain::Outside)
                        fs.conditional.add(p);
                        fs.conditional.observed += !so.keep;
                    }
                    if (std::isfinite(p) && fs.firstCapFrame != 0 && n > fs.firstCapFrame) {
                        fs.conditionalAfterCap.add(p);
                        fs.conditionalAfterCap.observed += !so.keep;
                    }
                    fs.replaced += !so.keep;
                    if (!so.keep && cand.weight == 0.0f) fs.zeroWeightSelected++;
                    if (stored.M < hist.M) fs.mWraps++;
                } else {
                    fs.fresh++;
                    fs.flushes += so.flushed;
                    if (n > 1 && ps.producedValid && !so.historyValid) fs.lost++;
                }
                ps.producedValid = wrs_reservoir_valid(so.r);

                if (!so.hadHistory || !so.keep) {
                    ps.birth = n;
                    ps.birthColor = stored.color;
                    ps.birthW = stored.w;
                } else if (!sameBits(stored.color, ps.birthColor) || bits(stored.w) != bits(ps.birthW)) {
                    fs.identityViolations++;
                }
                if (hasModel) {
                    const ModelFrame* mf = &modelOf(fmts[f])[n];
                    if (mf->p < 1.0) {
                        fs.unconditional.add(mf->p);
                        fs.unconditional.observed += ps.birth == n;
                    }
                    if (n == mid) obsMid[f][bucketOf(st, ps.birth, n)]++;
                    if (n == N) obsFinal[f][bucketOf(st, ps.birth, n)]++;
                }

                if (!wrs_finite3(so.r.color)) fs.nonFiniteOutput++;
                const bool finite = wrs_finite3(stored.color) && wrs_finite(stored.w) && wrs_finite(stored.w_sum) &&
                                    wrs_finite(stored.z);
                if (!finite || !(stored.w_sum > 0.0f)) fs.nonFiniteStored++;
                if (wrs_finite(stored.w_sum)) {
                    fs.wsumMin = std::min(fs.wsumMin, double(stored.w_sum));
                    fs.wsumMax = std::max(fs.wsumMax, double(stored.w_sum));
                    if (st.domain != Domain::Outside)
                        fs.boundRatioMax = std::max(fs.boundRatioMax, double(stored.w_sum) / bound);
                }
                fs.mMax = std::max(fs.mMax, stored.M);
                if (stored.M == WRS_M_MAX) {
                    fs.mAtCap++;
                    if (fs.firstCapFrame == 0) fs.firstCapFrame = n;
                }
                if (i == 0 && bits(stored.w_sum) != ps.wsumBits) {
                    ps.wsumBits = bits(stored.w_sum);
                    ps.wsumLastChange = n;
                }
                if (sampleNow) {
                    sum[f] += stored.w_sum;
                    lo[f] = std::min(lo[f], double(stored.w_sum));
                    hi[f] = std::max(hi[f], double(stored.w_sum));
                }
                if (n == N) fs.wsumFinalMean += stored.w_sum / double(P);
                ps.stored = stored;
            }
            if (baseline >= 0) {
                const uint64_t b = state[size_t(i) * F + size_t(baseline)].birth;
                for (size_t f = 0; f < F; ++f) out.formats[f].divergentFrames += state[size_t(i) * F + f].birth != b;
            }
        }
        if (sampleNow) {
            for (size_t f = 0; f < F; ++f) {
                out.formats[f].series.mean.push_back(sum[f] / P);
                out.formats[f].series.min.push_back(lo[f]);
                out.formats[f].series.max.push_back(hi[f]);
            }
            ++nextSeries;
        }
        if ((n & 1023u) == 0 || n == N) done.store(n, std::memory_order_relaxed);
    }

    const uint64_t minFrozen = std::max<uint64_t>(100, N / 100);
    for (size_t f = 0; f < F; ++f) {
        FormatStats& fs = out.formats[f];
        const uint64_t last = state[f].wsumLastChange;
        fs.wsumFrozenFrom = N - last >= minFrozen ? last + 1 : 0;
        if (hasModel) {
            if (mid >= 2) fs.chiMid = chiSquare(birthBuckets(st, modelOf(fmts[f]), mid), obsMid[f], P);
            fs.chiFinal = chiSquare(birthBuckets(st, modelOf(fmts[f]), N), obsFinal[f], P);
        }
    }
}

}  // namespace

double wsumBound(uint64_t frame, bool bernoulli) {
    const double n = double(std::max<uint64_t>(frame, 1));
    return bernoulli ? std::sqrt(1.0 + 2.25 * (n - 1.0)) : n;
}

Result<CpuResult> runCpu(const CpuOptions& options) {
    CpuResult res;
    res.options = options;
    CpuOptions& o = res.options;
    if (o.frames < 2) return Error{1, "--frames must be at least 2"};
    if (o.frames > 0xffffffffull) return Error{1, "--frames must fit the 32-bit frame index of wrs_rand"};
    if (o.pixels < 1 || o.pixels > 1u << 16) return Error{1, "--pixels must be in 1..65536"};
    if (o.formats.empty())
        for (const FormatInfo& f : formats()) o.formats.push_back(f.id);

    std::vector<Stream> all = makeStreams(o.frames, o.seed);
    std::vector<std::pair<Stream, uint32_t>> chosen;
    if (o.streams.empty()) {
        for (uint32_t k = 0; k < all.size(); ++k) chosen.push_back({all[k], k});
    } else {
        for (const std::string& name : o.streams) {
            auto it = std::find_if(all.begin(), all.end(), [&](const Stream& s) { return s.name == name; });
            if (it == all.end()) return Error{1, "unknown stream '" + name + "'"};
            chosen.push_back({*it, uint32_t(it - all.begin())});
        }
    }

    res.streams.resize(chosen.size());
    std::vector<std::atomic<uint64_t>> done(chosen.size());
    for (auto& d : done) d.store(0);
    std::atomic<size_t> next{0};
    const unsigned threads = std::max(
        1u, std::min<unsigned>(o.threads ? o.threads : std::thread::hardware_concurrency(), unsigned(chosen.size())));
    const auto t0 = std::chrono::steady_clock::now();
    auto work = [&] {
        for (size_t k; (k = next.fetch_add(1)) < chosen.size();) {
            res.streams[k].stream = chosen[k].first;
            runStream(chosen[k].first, chosen[k].second, o, res.streams[k], done[k]);
        }
    };
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);

    const double total = double(o.frames) * double(chosen.size());
    int reported = 0;
    for (;;) {
        double sumDone = 0;
        for (auto& d : done) sumDone += double(d.load(std::memory_order_relaxed));
        const double frac = sumDone / total;
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (o.progress && (int(frac * 20.0) > reported || frac >= 1.0)) {
            reported = int(frac * 20.0);
            o.progress(Progress{"cpu", frac, el, el > 0 ? sumDone / el : 0});
        }
        if (frac >= 1.0) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    for (auto& t : pool) t.join();
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

Horizon horizon(FormatId format, float weight, bool bernoulli, uint64_t maxFrames) {
    Horizon h;
    h.format = format;
    h.weight = weight;
    h.bernoulli = bernoulli;
    // A grey pixel: the change term is exactly 0 (identical colours), so WRS_CHANGE_OFF gives the same
    // bits as the default L* metric at a fraction of the cost.
    const vec3 grey(0.5f);
    bool keep;
    Reservoir stored =
        roundTrip(format, wrs_combine(false, Reservoir{}, grey, weight, 1.0f, 0.0f, WRS_CHANGE_OFF, bernoulli, keep));
    double exact = weight;
    for (uint64_t n = 2; n <= maxFrames; ++n) {
        if (!wrs_reservoir_valid(stored)) {
            h.lost = true;
            h.frame = n;
            h.wsum = stored.w_sum;
            h.exactWsum = exact;
            return h;
        }
        const Reservoir r = wrs_combine(true, stored, grey, weight, 1.0f, 0.5f, WRS_CHANGE_OFF, bernoulli, keep);
        const Reservoir next = roundTrip(format, r);
        exact = bernoulli ? exact * exact / (exact + weight) + weight : exact + weight;
        if (h.drift1 == 0 && std::fabs(next.w_sum / exact - 1.0) > 0.01) h.drift1 = n;
        h.maxBoundRatio = std::max(h.maxBoundRatio, next.w_sum / (double(weight) * wsumBound(n, bernoulli)));
        if (bits(next.w_sum) == bits(stored.w_sum)) {
            h.frame = n;
            h.wsum = next.w_sum;
            h.exactWsum = exact;
            return h;
        }
        stored = next;
    }
    h.wsum = stored.w_sum;
    h.exactWsum = exact;
    return h;
}

}  // namespace wrsfov::stress
