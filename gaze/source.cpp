#include "gaze/source.h"

#include <algorithm>
#include <cmath>
#include <glm/geometric.hpp>

namespace wrsfov::gaze {

GazeSample interpolate_samples(std::span<const GazeSample> samples, double t_s, const DropoutPolicy& policy) {
    GazeSample out;
    out.t_s = t_s;
    if (samples.empty() || !std::isfinite(t_s)) return out;
    // First sample after t_s.
    const auto it =
        std::upper_bound(samples.begin(), samples.end(), t_s, [](double t, const GazeSample& s) { return t < s.t_s; });
    const size_t hi = static_cast<size_t>(it - samples.begin());
    if (hi == 0) {
        // Before the first sample: it may stand in for the hold time, as if just measured.
        const GazeSample& f = samples.front();
        out.label = f.label;
        if (f.t_s - t_s <= policy.hold_s)
            for (int e = 0; e < 2; ++e) out.eye[e] = f.eye[e];
        return out;
    }
    const size_t lo = hi - 1;
    const GazeSample& a = samples[lo];
    const GazeSample* b = hi < samples.size() ? &samples[hi] : nullptr;
    const double w = b && b->t_s > a.t_s ? (t_s - a.t_s) / (b->t_s - a.t_s) : 0.0;
    out.label = b && w >= 0.5 ? b->label : a.label;
    for (int e = 0; e < 2; ++e) {
        if (b && a.eye[e].valid && b->eye[e].valid && b->t_s - a.t_s <= policy.max_gap_s) {
            const glm::vec3 d = glm::mix(a.eye[e].dir, b->eye[e].dir, static_cast<float>(w));
            const float len = glm::length(d);
            out.eye[e].dir = len > 0 ? d / len : a.eye[e].dir;
            out.eye[e].valid = true;
            out.eye[e].confidence = static_cast<float>(a.eye[e].confidence * (1 - w) + b->eye[e].confidence * w);
            continue;
        }
        // Hold the most recent valid sample; the walk is bounded by the hold time.
        for (size_t i = lo + 1; i-- > 0;) {
            if (t_s - samples[i].t_s > policy.hold_s) break;
            if (samples[i].eye[e].valid) {
                out.eye[e] = samples[i].eye[e];
                break;
            }
        }
    }
    return out;
}

ReplaySource::ReplaySource(std::vector<GazeSample> samples, DropoutPolicy policy)
    : samples_(std::move(samples)), policy_(policy) {
    std::stable_sort(samples_.begin(), samples_.end(),
                     [](const GazeSample& a, const GazeSample& b) { return a.t_s < b.t_s; });
}

Result<std::unique_ptr<ReplaySource>> ReplaySource::open(const std::string& path, DropoutPolicy policy,
                                                         const ReadOptions& options) {
    auto rec = read_gaze_file(path, options);
    if (!rec) return rec.error();
    if (rec->samples.empty()) return fail(path + ": no usable gaze samples");
    auto src = std::make_unique<ReplaySource>(std::move(rec->samples), policy);
    src->issues_ = std::move(rec->issues);
    return src;
}

GazeSample ReplaySource::sample(double t_s) { return interpolate_samples(samples_, t_s, policy_); }

double ReplaySource::duration_s() const { return samples_.empty() ? 0 : samples_.back().t_s - samples_.front().t_s; }

SyntheticSource::SyntheticSource(GeneratedGaze gen, double period, DropoutPolicy policy)
    : gen_(std::move(gen)), period_(period), policy_(policy) {}

Result<std::unique_ptr<SyntheticSource>> SyntheticSource::create(const GeneratorConfig& config, DropoutPolicy policy) {
    auto g = generate(config);
    if (!g) return g.error();
    if (g->samples.empty()) return fail("the generator produced no samples (seconds * rate < 1)");
    const double period = static_cast<double>(g->samples.size()) / config.tracker.rate_hz;
    return std::unique_ptr<SyntheticSource>(new SyntheticSource(std::move(*g), period, policy));
}

GazeSample SyntheticSource::sample(double t_s) {
    if (!std::isfinite(t_s)) return GazeSample{};
    const double local = t_s - std::floor(t_s / period_) * period_;
    GazeSample s = interpolate_samples(gen_.samples, local, policy_);
    s.t_s = t_s;
    return s;
}

}  // namespace wrsfov::gaze
