// Image-quality metrics of the evaluation (docs/conventions.md, "Evaluation").
//
// Every metric compares a *reference* (the unfoveated render of a frame) with a *test* image (a
// method's output of the same frame). Images are sRGB-encoded values in [0, 1]:
//   - cv::Mat of type CV_32FC3, channels in R, G, B order (not OpenCV's usual BGR), or
//   - HostImage: RGBA8 / RGBA8_SRGB texels are taken as sRGB-encoded c / 255 (the compositor's
//     output), RGBA16F texels as linear values that are sRGB-encoded first; alpha is dropped.
//
// Input rules, the same for every function:
//   - wrong type, empty images or mismatched sizes throw std::invalid_argument with a message;
//   - a non-finite value (NaN, ±inf) anywhere in an image or an eccentricity map throws
//     std::invalid_argument naming the first such pixel: a NaN is a bug upstream, never averaged in;
//   - finite values outside [0, 1] are clamped to [0, 1] (what a display shows).
// The PNG writers report failures (bad input included) as a Status instead of throwing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>

#include "wrsfov/image.h"
#include "layers/status.h"
#include "shaders/wrs_params.h"

namespace wrsfov::eval {

// ---------------------------------------------------------------------------------------------
// Conversion
// ---------------------------------------------------------------------------------------------

/// HostImage -> CV_32FC3 (R, G, B), sRGB-encoded values in [0, 1]. RGBA8 and RGBA8_SRGB: c / 255;
/// RGBA16F: linear values, clamped and sRGB-encoded (non-finite texels stay non-finite, so that
/// the metrics reject them). Throws std::invalid_argument for other formats, an empty image, or a data
/// buffer whose size does not match width × height × texel size.
cv::Mat toMat(const HostImage& image);

// ---------------------------------------------------------------------------------------------
// Full-image error
// ---------------------------------------------------------------------------------------------

/// Mean squared error over all pixels and the three channels.
double meanSquaredError(const cv::Mat& reference, const cv::Mat& test);

/// Per-pixel squared error, averaged over the three channels (CV_32F, same size): the map that
/// meanSquaredError averages and that the error-map PNGs show.
cv::Mat squaredErrorMap(const cv::Mat& reference, const cv::Mat& test);

/// PSNR in dB with peak 1: 10·log10(1 / MSE). Identical images give +infinity.
double psnr(const cv::Mat& reference, const cv::Mat& test);
/// PSNR of two HostImages (see toMat).
double psnr(const HostImage& reference, const HostImage& test);

/// SSIM from cv::quality::QualitySSIM (Gaussian 11×11 window, σ = 1.5, Wang et al. 2004 constants)
/// on the images scaled to 0–255, averaged over the three channels. Identical images give 1.
double ssim(const cv::Mat& reference, const cv::Mat& test);
/// SSIM of two HostImages (see toMat).
double ssim(const HostImage& reference, const HostImage& test);

// ---------------------------------------------------------------------------------------------
// Eccentricity-aware error
// ---------------------------------------------------------------------------------------------

/// Per-pixel eccentricity in degrees (CV_32F, height × width) of a view with the given field of
/// view tangents (XrFovf order: left, right, up, down) seen with the given gaze direction (eye
/// space, -Z forward; normalised here), computed exactly as the compositor does
/// (gpu::wrs_pixel_ray, gpu::wrs_eccentricity_deg). Throws std::invalid_argument for a zero size,
/// non-finite tangents, an empty field of view, or a zero or non-finite gaze.
cv::Mat eccentricityMap(uint32_t width, uint32_t height, glm::vec4 fov_tan, glm::vec3 gaze);
/// Same, from one eye's compositor parameters (fov_tan and gaze.xyz).
cv::Mat eccentricityMap(uint32_t width, uint32_t height, const gpu::EyeParams& eye);

/// Where the gaze of `eye` meets its image as fvvdp::Metric::push wants it: continuous pixel
/// coordinates, pixel (x, y) centred at (x + 0.5, y + 0.5), possibly outside the image; the image's
/// central pixel (w / 2, h / 2) when the gaze does not point forwards.
glm::vec2 gazePixelF(const gpu::EyeParams& eye, uint32_t width, uint32_t height);

/// Radius of the near-gaze region of docs/conventions.md, "Evaluation", in degrees.
inline constexpr double kNearGazeDeg = 10.0;

/// PSNR (peak 1) over the pixels whose eccentricity is <= max_deg. `eccentricity` is a CV_32F map
/// of the images' size (eccentricityMap). +infinity when those pixels are identical; NaN when no
/// pixel lies within max_deg (nothing to measure).
double nearGazePsnr(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity,
                    double max_deg = kNearGazeDeg);
/// Near-gaze PSNR of two HostImages (see toMat).
double nearGazePsnr(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity,
                    double max_deg = kNearGazeDeg);

/// Fovea radius of the eccentricity weighting, in degrees. Fixed, independent of the fovea size of
/// the method under test, so that methods with different foveae are weighted alike: 2.5° is the
/// radius of the anatomical fovea (5° across), the region of full acuity.
inline constexpr double kWeightFoveaDeg = 2.5;

/// Per-pixel weight of the eccentricity-weighted MSE (CV_32F): the compositor's Watson sample
/// weight gpu::wrs_sample_weight(e, fovea_deg), i.e. 1 within fovea_deg and the relative cone
/// density d(e) / d(fovea_deg) outside. fovea_deg must be finite and > 0.
cv::Mat eccentricityWeights(const cv::Mat& eccentricity, double fovea_deg = kWeightFoveaDeg);

/// Eccentricity-weighted MSE: sum_i w_i·mse_i / sum_i w_i with w from eccentricityWeights and mse_i
/// the pixel's squared error averaged over channels. A uniform error gives the plain MSE; an error
/// far in the periphery counts only as much as the eye resolves there.
double eccentricityWeightedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity,
                               double fovea_deg = kWeightFoveaDeg);
/// Eccentricity-weighted MSE of two HostImages (see toMat).
double eccentricityWeightedMse(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity,
                               double fovea_deg = kWeightFoveaDeg);
/// The same with weights already computed (eccentricityWeights; CV_32FC1 of the images' size, finite,
/// >= 0): for callers that score several images against one reference and gaze.
double weightedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& weights);

// ---------------------------------------------------------------------------------------------
// FLIP (LDR), Andersson et al. 2020
// ---------------------------------------------------------------------------------------------

/// Pixels per degree of a monitor seen head-on from `distance_m`: distance · (resolution / width) ·
/// π / 180, the FLIP paper's viewing-condition parameter. Throws for non-positive arguments.
double pixelsPerDegree(double distance_m, double width_m, double resolution_px);

/// Pixels per degree on the optical axis (tan = 0) of a view `width_px` wide with the given fov
/// tangents: width / (tan right − tan left) · π / 180, the viewing condition of a headset's per-eye
/// image for FLIP. Throws for a zero width, non-finite tangents or an empty field of view.
double pixelsPerDegreeAtCentre(uint32_t width_px, glm::vec4 fov_tan);

/// Viewing conditions of FLIP.
struct FlipOptions {
    /// The FLIP paper's default: a 0.7 m wide 3840-pixel monitor seen from 0.7 m (≈ 67.0 ppd).
    double pixels_per_degree = 0.7 * (3840.0 / 0.7) * (3.14159265358979323846 / 180.0);

    /// Options for a monitor of the given width and horizontal resolution seen from distance_m.
    static FlipOptions monitor(double distance_m, double width_m, double resolution_px) {
        return FlipOptions{pixelsPerDegree(distance_m, width_m, resolution_px)};
    }
};

/// Result of flip(): the mean over pixels and the per-pixel error.
struct FlipResult {
    double mean = 0.0;
    cv::Mat map;  ///< CV_32F, the images' size, values in [0, 1]
};

/// LDR-FLIP of Andersson et al. 2020 ("FLIP: A Difference Evaluator for Alternating Images", HPG
/// 2020): CSF-filtered colour difference (YCxCz, Hunt-adjusted HyAB in L*a*b*, remapped) raised to
/// 1 − the feature difference (edges and points of the luminance). 0 for identical images, close to
/// 1 for the largest differences. Symmetric in its two arguments. Image borders are extended by
/// replication. Throws std::invalid_argument for a pixels_per_degree that is not finite and > 0.
FlipResult flip(const cv::Mat& reference, const cv::Mat& test, const FlipOptions& options = {});
/// FLIP of two HostImages (see toMat).
FlipResult flip(const HostImage& reference, const HostImage& test, const FlipOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Temporal instability
// ---------------------------------------------------------------------------------------------

/// Mean absolute frame-to-frame change of the output over the pixels where the reference does not
/// change: a pixel counts for the pair of frames (t−1, t) when max over channels of
/// |ref_t − ref_{t−1}| <= threshold, and contributes the mean over channels of |out_t − out_{t−1}|.
/// Feed the frames of one sequence (one eye) in order; all frames must have one size.
class TemporalInstability {
public:
    /// Default threshold: one 8-bit step, so re-encoding noise of a static reference still counts
    /// as "not changing".
    static constexpr double kDefaultThreshold = 1.0 / 255.0;

    /// Throws std::invalid_argument for a threshold that is negative or not finite.
    explicit TemporalInstability(double threshold = kDefaultThreshold);

    /// Adds frame t. Returns this frame pair's instability (mean over its stable pixels), or NaN for
    /// the first frame or when no pixel of the reference stayed unchanged. Throws
    /// std::invalid_argument for bad images or a size different from the previous frame's; the
    /// accumulated state is then left as it was.
    double addFrame(const cv::Mat& reference, const cv::Mat& output);
    /// Adds frame t from HostImages (see toMat).
    double addFrame(const HostImage& reference, const HostImage& output);

    /// Instability over all frame pairs so far: sum of the changes over all stable pixel pairs
    /// divided by their number (pairs with more stable pixels weigh more). NaN when there are none.
    double mean() const;
    /// Frames added so far.
    std::size_t frames() const { return frames_; }
    /// Stable pixel pairs counted so far.
    uint64_t stablePixels() const { return stable_; }
    /// Forgets all frames (a new sequence); the threshold is kept.
    void reset();

private:
    double threshold_;
    cv::Mat prev_ref_;
    cv::Mat prev_out_;
    std::size_t frames_ = 0;
    uint64_t stable_ = 0;
    double sum_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
// All metrics of one frame
// ---------------------------------------------------------------------------------------------

/// Parameters of evaluateFrame.
struct MetricOptions {
    double near_gaze_deg = kNearGazeDeg;
    double weight_fovea_deg = kWeightFoveaDeg;
    FlipOptions flip;
};

/// Every per-frame metric of one image pair.
struct FrameMetrics {
    double psnr = 0.0;
    double ssim = 0.0;
    double near_gaze_psnr = 0.0;
    double ecc_weighted_mse = 0.0;
    double flip = 0.0;
    cv::Mat flip_map;  ///< CV_32F per-pixel FLIP
};

/// Computes all per-frame metrics (temporal instability needs a sequence: TemporalInstability).
FrameMetrics evaluateFrame(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity,
                           const MetricOptions& options = {});
/// All per-frame metrics of two HostImages (see toMat).
FrameMetrics evaluateFrame(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity,
                           const MetricOptions& options = {});

// ---------------------------------------------------------------------------------------------
// Error maps as PNG
// ---------------------------------------------------------------------------------------------

/// Error::code of the Status the PNG writers return.
enum class EvalError : int {
    InvalidInput = 1,  ///< empty map, wrong type, non-finite or negative values
    WriteFailed = 2,   ///< the PNG could not be encoded or written
};

/// How an error map is drawn.
struct ErrorMapStyle {
    /// Value drawn with the top colour; values above are clamped. <= 0: the map's maximum (1 when
    /// the map is all zero).
    double max_value = 0.0;
    /// OpenCV colour map (cv::ColormapTypes).
    int colormap = cv::COLORMAP_MAGMA;
    /// Text above the legend bar (e.g. "MSE", "FLIP"); empty for none.
    std::string label;
};

/// Writes a per-pixel error map (CV_32F, finite, >= 0) as a colour-mapped PNG with a legend bar on
/// the right (colour scale from 0 at the bottom to max_value at the top, with tick labels). Fails
/// with a message for an empty map, a wrong type, non-finite or negative values, or an unwritable
/// path.
Status writeErrorMapPng(const cv::Mat& error, const std::string& path, const ErrorMapStyle& style = {});

/// Writes a FLIP map (FlipResult::map) the same way on FLIP's fixed [0, 1] scale with magma.
Status writeFlipMapPng(const cv::Mat& flip_map, const std::string& path);

}  // namespace wrsfov::eval
