// The preview's live FovVideoVDP: each eye's output scored against the unfoveated reference as the
// frames go by (eval/fvvdp.h, the C++ metric), for the JOD readout in the stats strip and the
// visible-difference view (the metric's per-pixel distortion map). docs/preview.md, "Live JOD".
#pragma once

#include <array>
#include <cstdint>
#include <deque>
#include <glm/glm.hpp>
#include <memory>
#include <opencv2/core.hpp>
#include <optional>

#include "eval/fvvdp.h"
#include "layers/status.h"

namespace wrsfov::preview {

struct LiveJodOptions {
    uint32_t width = 0, height = 0;  ///< per eye
    /// Each eye's field of view as tangents (left, right, up, down), as the compositor used it.
    std::array<glm::vec4, 2> fovTan{};
    /// The preview shows an HMD's views: the metric's HMD display (100 cd/m², docs/metrics.md).
    eval::fvvdp::DisplayPhotometry photometry = eval::fvvdp::DisplayPhotometry::hmd();
    double fps = 90.0;        ///< the preview's scene clock: one 90 Hz frame per composited frame
    bool map = false;         ///< keep each frame's distortion map (the visible-difference view)
    std::size_t window = 90;  ///< frames the readout pools over (1 s at 90 Hz)
};

/// Two streaming metrics, one per eye (each eye is a video of its own), fed the same frames as
/// the screen shows. The readout pools the last `window` frames as the metric pools a video (the
/// beta_t-mean of the frames' qualities, then the JOD regression); up to `window` frames it is
/// exactly Metric::jod() of the frames pushed.
class LiveJod {
public:
    /// Fails for options the metric refuses (a size under 8 × 8, a bad field of view), naming them.
    static Result<std::unique_ptr<LiveJod>> create(const LiveJodOptions& options);

    /// Adds one frame per eye: `test` (the method's output) and `reference`, CV_32FC3 sRGB-encoded
    /// RGB of the options' size, `gazePx` each eye's gaze in continuous pixels (eval::gazePixelF).
    /// The two eyes run in parallel. A bad frame (NaN, a wrong size) is an error naming the eye; the
    /// frames pushed before stay as they were.
    Status push(const std::array<cv::Mat, 2>& test, const std::array<cv::Mat, 2>& reference,
                const std::array<glm::vec2, 2>& gazePx);

    /// JOD of each eye over the last min(frames(), window) frames; nullopt before the first frame.
    std::optional<std::array<double, 2>> jod() const;
    /// Frames the readout pools now (at most the window).
    std::size_t pooled() const { return quality_.size(); }
    /// Frames pushed since creation or the last reset.
    std::size_t frames() const { return frames_; }
    /// The last frame's visible distortion of `eye` in JOD units (CV_32F, the image's size; 0 where
    /// nothing is visible). Empty without LiveJodOptions::map or before the first frame.
    const cv::Mat& map(int eye) const;
    const LiveJodOptions& options() const { return options_; }
    /// Forgets every frame: the next push starts a new video (a setting changed, a frame was skipped).
    void reset();

private:
    LiveJod(const LiveJodOptions& o, std::array<eval::fvvdp::Metric, 2> m) : options_(o), metric_(std::move(m)) {}

    LiveJodOptions options_;
    std::array<eval::fvvdp::Metric, 2> metric_;
    std::deque<std::array<double, 2>> quality_;  ///< per frame, each eye's pooled quality (video)
    std::array<double, 2> imageQuality_{};       ///< the first frame's sustained-only quality (an image)
    std::size_t frames_ = 0;
};

}  // namespace wrsfov::preview
