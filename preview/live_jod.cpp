#include "preview/live_jod.h"

#include <cmath>
#include <opencv2/core/utility.hpp>
#include <string>

namespace wrsfov::preview {

namespace fvvdp = eval::fvvdp;

Result<std::unique_ptr<LiveJod>> LiveJod::create(const LiveJodOptions& o) {
    if (o.window == 0) return Error{2, "live JOD: the pooling window must hold at least one frame"};
    std::array<std::optional<fvvdp::Metric>, 2> m;
    for (int e = 0; e < 2; ++e) {
        fvvdp::Options fo;
        fo.photometry = o.photometry;
        fo.geometry = fvvdp::ViewGeometry::view(o.width, o.height, o.fovTan[e]);
        fo.fps = o.fps;
        fo.foveated = true;
        fo.distortion_map = o.map;
        auto made = fvvdp::Metric::create(fo);
        if (!made) return Error{made.error().code, "live JOD, eye " + std::to_string(e) + ": " + made.error().message};
        m[e].emplace(std::move(*made));
    }
    return std::unique_ptr<LiveJod>(new LiveJod(o, {std::move(*m[0]), std::move(*m[1])}));
}

Status LiveJod::push(const std::array<cv::Mat, 2>& test, const std::array<cv::Mat, 2>& reference,
                     const std::array<glm::vec2, 2>& gazePx) {
    // Check both eyes before either metric takes a frame, so that a bad frame leaves both as they were.
    for (int e = 0; e < 2; ++e)
        if (Status s = fvvdp::detail::checkInputFrame(test[e], reference[e], gazePx[e], metric_[e].options().geometry);
            !s)
            return Error{s.error().code, "live JOD, eye " + std::to_string(e) + ": " + s.error().message};
    std::array<Status, 2> st;
    cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& r) {
        for (int e = r.start; e < r.end; ++e) st[e] = metric_[e].push(test[e], reference[e], gazePx[e]);
    });
    for (int e = 0; e < 2; ++e)
        if (!st[e]) {
            // The other eye took the frame: start both anew rather than leave them a frame apart.
            reset();
            return Error{st[e].error().code, "live JOD, eye " + std::to_string(e) + ": " + st[e].error().message};
        }
    std::array<double, 2> q{};
    for (int e = 0; e < 2; ++e) {
        const std::array<double, 2> pooled = fvvdp::detail::poolFrame(metric_[e].lastFrame());
        if (frames_ == 0) imageQuality_[e] = pooled[0];
        q[e] = pooled[1];
    }
    quality_.push_back(q);
    if (quality_.size() > options_.window) quality_.pop_front();
    ++frames_;
    return {};
}

std::optional<std::array<double, 2>> LiveJod::jod() const {
    if (frames_ == 0) return std::nullopt;
    const fvvdp::Parameters& p = fvvdp::kParameters;
    std::array<double, 2> out{};
    for (int e = 0; e < 2; ++e) {
        // One frame is scored as an image, more as a video: Metric::jod's rule.
        double q = imageQuality_[e];
        if (frames_ > 1) {
            double sum = 0.0;
            for (const auto& f : quality_) sum += std::pow(f[e], p.beta_t);
            q = std::pow(sum / double(quality_.size()), 1.0 / p.beta_t);
        }
        out[e] = fvvdp::detail::jodFromQuality(q);
    }
    return out;
}

const cv::Mat& LiveJod::map(int eye) const { return metric_[eye == 0 ? 0 : 1].distortionMap(); }

void LiveJod::reset() {
    for (auto& m : metric_) m.reset();
    quality_.clear();
    imageQuality_ = {};
    frames_ = 0;
}

}  // namespace wrsfov::preview
