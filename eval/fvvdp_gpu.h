// FovVideoVDP on the GPU: the metric of eval/fvvdp.h as Vulkan compute passes (shaders/fvvdp_*.comp),
// with the same streaming API as fvvdp::Metric, so that a caller switches by its create() line.
//
// Per frame, one submission: display model (pass 1, into the temporal filter's window on the
// device) -> temporal channels (pass 2, the FIR filters over the window) -> Gaussian pyramid of the
// four channels (pass 3, one dispatch per level) -> per band: Laplacian band, contrast, CSF
// (the table fvvdp::detail::csfTable computes, uploaded once), masking and per-group sums of D^beta
// (pass 4). The host reads the group sums back, adds them in double and pools bands, channels and
// frames with fvvdp::detail::poolFrame and jodFromQuality, as the C++ metric does.
// docs/metrics.md, "GPU implementation".
#pragma once

#include <array>
#include <memory>

#include "compositor/vk_context.h"
#include "eval/fvvdp.h"

namespace wrsfov::eval::fvvdp {

/// Streaming FovVideoVDP of one video pair on a Vulkan device. Same inputs, errors and scores as
/// Metric (within float rounding: the tests hold it within 0.01 JOD of it).
class GpuMetric {
public:
    /// Checks the options as Metric::create does, then makes the passes' pipelines and buffers on
    /// `ctx` (which must outlive the metric): the window (2 · filterLength() luminance frames),
    /// the pyramid of four float channels, the CSF tables. Options::distortion_map is refused
    /// (FvvdpError::InvalidOptions): the map is the C++ metric's only. Device memory that cannot be
    /// allocated is an error naming the buffer.
    static Result<GpuMetric> create(vk::Context& ctx, const Options& options);

    GpuMetric(GpuMetric&&) noexcept;
    GpuMetric& operator=(GpuMetric&&) noexcept;
    ~GpuMetric();

    /// As Metric::push: CV_32FC3 sRGB-encoded test and reference of the geometry's size, gaze in
    /// pixels. NaN or ±inf in an image, a wrong type or size, or a non-finite gaze are errors (the
    /// same codes and messages as Metric's), checked before anything reaches the device; the state
    /// is then left as it was. A failed submission (device lost) is an error too.
    Status push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px);
    /// The same with the gaze at the image's central pixel (W / 2, H / 2).
    Status push(const cv::Mat& test, const cv::Mat& reference);

    /// As Metric::jod: one frame scored as an image, more as a video. Fails before the first frame.
    Result<double> jod() const;

    /// Quality of the last frame pushed per band and channel (as Metric::lastFrame).
    const FrameQuality& lastFrame() const;
    std::size_t frames() const;
    const std::vector<double>& bandFrequencies() const;
    int filterLength() const;
    const Options& options() const;
    /// Device time of the last frame's passes in milliseconds (display, temporal, pyramid, bands),
    /// from timestamps; zeros where the queue has none.
    std::array<double, 4> passMilliseconds() const;
    /// Forgets all frames (a new video); options, pipelines and buffers are kept.
    void reset();

private:
    struct Impl;
    explicit GpuMetric(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

}  // namespace wrsfov::eval::fvvdp
