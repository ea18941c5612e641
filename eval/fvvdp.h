// FovVideoVDP (Mantiuk et al. 2021, "FovVideoVDP: A visible difference predictor for wide
// field-of-view video", ACM TOG 40(4)), our own implementation of its calibration v1.2 (parameter
// file version 1.2.3 of the reference, docs/metrics.md "FovVideoVDP"). Quality in JOD: 10 = no
// visible difference, each unit less is one just-objectionable difference more.
//
// The model, frame by frame (docs/metrics.md names every equation and parameter):
//   display model (sRGB-encoded RGB -> absolute luminance, cd/m²) -> sustained and transient
//   temporal channels (FIR filters over the last 250 ms) -> Laplacian pyramid, band contrast
//   against the expanded next Gaussian level of the reference's sustained channel -> contrast
//   sensitivity of frequency, temporal channel, luminance and eccentricity -> mutual masking ->
//   pooling over pixels (per band), bands, channels and frames -> JOD regression.
//
// Streaming: push(test, reference, gaze) per frame, jod() at any time. Memory: the temporal
// filter's window (ceil(fps / 4) luminance frames of test and reference) and one frame's
// pyramids; pooled sums only for the frames already seen.
//
// Every per-pixel or per-band step is a small free function below (fvvdp::detail), so that a
// compute-shader version can mirror the C++ reference pass by pass.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <glm/glm.hpp>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "layers/status.h"

namespace wrsfov::eval::fvvdp {

/// Error::code of the Results and Statuses of this header.
enum class FvvdpError : int {
    InvalidOptions = 1,  ///< a display, geometry or frame-rate parameter out of range
    InvalidInput = 2,    ///< empty image, wrong type, wrong size, non-finite gaze
    NonFinite = 3,       ///< NaN or ±inf in an input image
    NoFrames = 4,        ///< jod() before any push()
};

// ---------------------------------------------------------------------------------------------
// Display model
// ---------------------------------------------------------------------------------------------

/// Photometry of the display: sRGB-encoded values V in [0, 1] per channel become
/// L = (peak − black) · srgb_to_linear(V) + black in cd/m², and the luminance
/// Y = 0.2126729 L_R + 0.7151522 L_G + 0.0721750 L_B (the sRGB primaries' Y row).
struct DisplayPhotometry {
    double peak = 200.0;          ///< cd/m²
    double contrast = 1000.0;     ///< peak / emitted black, the panel's own contrast
    double ambient_lux = 250.0;   ///< illuminance on the screen
    double reflectivity = 0.005;  ///< share of the ambient light the panel reflects (k_refl)

    /// Effective black level: peak / contrast + ambient_lux · reflectivity / π.
    double black() const;

    /// Desktop monitor, the reference's `standard_4k`: 200 cd/m², 1000:1, 250 lux.
    static DisplayPhotometry monitor() { return {}; }
    /// Head-mounted display, the reference's `standard_hmd`: 100 cd/m², black 0.1 cd/m², no
    /// ambient light reaching the panel.
    static DisplayPhotometry hmd() { return {100.0, 1000.0, 0.0, 0.005}; }
};

/// Geometry of the image seen: its size and its field of view as tangents (XrFovf order: left,
/// right, up, down; left < 0 < right, down < 0 < up; asymmetric allowed). Pixel (x, y) has its
/// centre at tangents tx = left + (x + 0.5) / W · (right − left), ty = up − (y + 0.5) / H · (up −
/// down) (docs/conventions.md), so the image is a flat screen one unit in front of the eye.
struct ViewGeometry {
    /// How eccentricity and the local angular resolution are taken from the tangents.
    enum class Model : uint8_t {
        /// wrsfov's views: eccentricity is the angle between the pixel's ray and the gaze ray;
        /// the local resolution follows the pixel's angle from the optical axis (tangent 0, not
        /// necessarily the image centre).
        View,
        /// The reference's flat-screen model, for agreement measurements: the optical axis at the
        /// image centre (the view must be symmetric), eccentricity as the norm of the horizontal
        /// and vertical angle differences, the local resolution from their norm.
        FlatScreen,
    };

    uint32_t width = 0, height = 0;
    glm::vec4 fov_tan{-1.0f, 1.0f, 1.0f, -1.0f};
    Model model = Model::View;

    /// A view of wrsfov (the compositor's fov tangents).
    static ViewGeometry view(uint32_t width, uint32_t height, glm::vec4 fov_tan);
    /// A symmetric view `fov_h_deg` wide, square pixels.
    static ViewGeometry symmetric(uint32_t width, uint32_t height, double fov_h_deg, Model model = Model::View);
    /// The reference's flat screen: a display width_m × height_m seen from distance_m, the image
    /// filling it (Model::FlatScreen).
    static ViewGeometry flatScreen(uint32_t width, uint32_t height, double width_m, double height_m, double distance_m);
    /// The reference's flat screen with the given pixels per degree at its centre
    /// (Model::FlatScreen): the display width whose central pixel subtends 1 / ppd degrees.
    static ViewGeometry flatScreenPpd(uint32_t width, uint32_t height, double ppd);

    /// Pixels per degree at the optical axis: 1 / (2 · atan(pitch / 2)) in degrees, pitch the
    /// tangent span of one pixel (the reference's ppd of a display's centre).
    double ppdCentre() const;
};

/// Options of the metric.
struct Options {
    DisplayPhotometry photometry = DisplayPhotometry::monitor();
    ViewGeometry geometry;
    double fps = 90.0;     ///< frame rate of the video; sets the temporal filters' sampling
    bool foveated = true;  ///< false: foveal sensitivity everywhere (gaze ignored)
    /// Keep each frame's per-pixel distortion (Metric::distortionMap): one more pyramid per frame.
    bool distortion_map = false;
};

/// The calibrated parameters (the reference's fvvdp_parameters.json, version 1.2.3, calibration
/// "fvvdp_1_20" of 20/11/2021). Exposed for the documentation and the tests; not meant to be tuned.
struct Parameters {
    double mask_p = 2.4;
    double mask_c = -0.973838;
    double w_transient = 0.25;
    double beta = 1.52134;       ///< spatial pooling (p-norm over the pixels of a band)
    double beta_t = 1.0;         ///< pooling over frames
    double beta_tch = 0.666092;  ///< pooling over the two temporal channels
    double beta_sch = 1.0;       ///< pooling over the bands
    double sustained_sigma = 0.5;
    double sustained_beta = 0.06;
    double csf_sigma = -1.5;                  ///< stimulus size in wavelengths (negative: fixed number of cycles)
    double sensitivity_correction = 16.2596;  ///< dB
    double jod_a = -0.0161713;
    double log_jod_exp = -0.2280;
    double mask_q_sust = 2.43685;
    double mask_q_trans = 4.946;
    double k_cm = 0.604562;  ///< exponent of the cortical magnification
};
inline constexpr Parameters kParameters{};
inline constexpr const char* kVersion = "1.2.3";

// ---------------------------------------------------------------------------------------------
// The metric
// ---------------------------------------------------------------------------------------------

/// Pooled quality of one frame, per band (finest first) and temporal channel (0 sustained,
/// 1 transient), before the weights of the channels: the p-norm mean of the masked differences.
struct FrameQuality {
    std::vector<std::array<double, 2>> band;
};

/// Streaming FovVideoVDP of one video pair.
class Metric {
public:
    /// Checks the options (geometry size ≥ 8 × 8 pixels, finite positive tangent span, fps > 0,
    /// peak > black ≥ 0) and precomputes the filters, the pyramid layout and the CSF table.
    static Result<Metric> create(const Options& options);

    /// Adds one frame: `test` and `reference` CV_32FC3 (R, G, B), sRGB-encoded, the geometry's
    /// size; finite values outside [0, 1] are clamped (what a display shows). `gaze_px` is the
    /// pixel looked at (its centre (x + 0.5, y + 0.5); fractional and off-image values allowed),
    /// used in foveated mode. Fails (the state left as it was) for an empty image, a wrong type or
    /// size, a NaN or infinite value (naming the first pixel) or a non-finite gaze.
    Status push(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px);
    /// The same with the gaze at the image's central pixel (W / 2, H / 2), the reference's default.
    Status push(const cv::Mat& test, const cv::Mat& reference);

    /// JOD of the frames pushed so far. One frame is scored as an image (the sustained channel
    /// alone, as the reference scores images); more as a video whose first frame is replicated
    /// into the temporal filters' past. Fails before the first frame.
    Result<double> jod() const;

    /// Per-pixel visible distortion of the last frame in JOD units (the reference's "raw" heat map:
    /// the masked differences of all bands collapsed like a Laplacian pyramid, sustained plus 0.25 ·
    /// transient, then |jod_a| · D^(10^log_jod_exp)); CV_32F of the image's size, 0 where nothing
    /// is visible. Empty unless Options::distortion_map is set.
    const cv::Mat& distortionMap() const { return distortion_; }
    /// Quality of the last frame pushed (empty before the first).
    const FrameQuality& lastFrame() const { return last_; }
    std::size_t frames() const { return frames_; }
    /// Bands of the pyramid scored (the base band excluded) and their frequencies in cycles per
    /// degree at the optical axis.
    const std::vector<double>& bandFrequencies() const { return band_freq_; }
    /// Length of the temporal filters in frames: ceil(fps / 4).
    int filterLength() const { return filter_len_; }
    const Options& options() const { return options_; }

    /// Forgets all frames (a new video); the options are kept.
    void reset();

private:
    struct Plane {
        int w = 0, h = 0;
        std::vector<float> v;
    };
    struct BandGeometry {
        int w = 0, h = 0;
        std::vector<float> tx, ty;   ///< tangent of each column and row
        std::vector<float> res_mag;  ///< local resolution / resolution at the optical axis
    };

    Metric() = default;
    void processFrame(glm::vec2 gaze_px);

    Options options_;
    int filter_len_ = 0;
    std::array<std::vector<float>, 2> filters_;  ///< sustained, transient; [0] applies to the newest frame
    std::vector<double> band_freq_;
    std::vector<BandGeometry> bands_;
    std::vector<float> csf_table_[2];  ///< log2 S over (Y, rho, ecc), per temporal channel

    std::vector<Plane> window_test_, window_ref_;  ///< ring of luminance frames
    int window_next_ = 0;
    std::size_t frames_ = 0;
    double sum_video_ = 0.0;  ///< sum over frames of (pooled quality)^beta_t
    double q_image_ = 0.0;    ///< first frame's sustained-only quality (the image score)
    FrameQuality last_;
    cv::Mat distortion_;
    /// A frame's working buffers, kept from frame to frame so that processing a frame allocates
    /// nothing after the first.
    struct Scratch {
        std::array<std::vector<float>, 4> a, b, band;
        std::vector<float> expanded, ecc, rho, l_bkg;
    };
    Scratch scratch_;
};

/// JOD of a whole video pair (frames in order, one gaze per frame or none for the image centre).
Result<double> score(const std::vector<cv::Mat>& test, const std::vector<cv::Mat>& reference,
                     const std::vector<glm::vec2>& gaze_px, const Options& options);

// ---------------------------------------------------------------------------------------------
// The steps, one pixel or one value at a time (the GPU version mirrors these)
// ---------------------------------------------------------------------------------------------
namespace detail {

/// sRGB decoding (IEC 61966-2-1).
float srgbToLinear(float v);
/// Absolute luminance in cd/m² of one sRGB-encoded pixel (values clamped to [0, 1]).
float displayLuminance(float r, float g, float b, float peak, float black);

/// The temporal filters at `fps` (length ceil(250 ms · fps)): sustained, a log-normal impulse
/// response in time normalised to sum 1; transient, its derivative scaled by k2 = 0.0621705 (the
/// reference's calibration). Element k applies to the frame k frames before the newest.
std::array<std::vector<float>, 2> temporalFilters(double fps, const Parameters& p = kParameters);

/// Temporal frequency (Hz) at which each channel's CSF is taken: 0 sustained, 5 transient.
inline constexpr std::array<double, 2> kChannelOmega{0.0, 5.0};

/// Cortical magnification (Dougherty et al. 2003) relative to the fovea's: (3.67 / (e + 3.67))^k_cm.
double corticalMagnificationRel(double ecc_deg, double k_cm);
/// Spatio-velocity CSF of Laird et al. 2006 (Daly's model refit), velocity clamped to ≥ 0.1 °/s.
double csfSpatioVelocity(double rho_cpd, double velocity_deg_s);
/// Achromatic sensitivity of Mantiuk et al. 2020's cone-contrast CSF (log-parabola in frequency,
/// Rovamo's area summation, luminance-dependent peak) for a Gabor of frequency rho (cpd) and area
/// (deg²) on a D65 background of luminance Y (cd/m²).
double csfAchromatic(double rho_cpd, double area_deg2, double luminance);
/// The metric's CSF of frequency, temporal frequency, luminance and eccentricity (before the
/// sensitivity correction): spatial sensitivity of the cortically scaled frequency and area times
/// the relative spatio-temporal sensitivity at omega. Floored at 1e-4.
double csfSensitivity(double rho_cpd, double omega_hz, double luminance, double ecc_deg,
                      const Parameters& p = kParameters);

/// Grid of the CSF table: kCsfN samples per axis, log-spaced luminance (cd/m²) and frequency
/// (cpd), eccentricity spaced in its square root; linear interpolation in log2 Y, log2 rho, √ecc.
inline constexpr int kCsfN = 32;
inline constexpr double kCsfYMin = 0.001, kCsfYMax = 10000.0;
inline constexpr double kCsfRhoMin = 0.0625, kCsfRhoMax = 64.0;
inline constexpr double kCsfEccMax = 120.0;
/// The table of log2 csfSensitivity for one omega, index (iY · N + iRho) · N + iEcc.
std::vector<float> csfTable(double omega_hz, const Parameters& p = kParameters);
/// Sensitivity from the table (clamped to its range), without the sensitivity correction.
float csfLookup(const std::vector<float>& table, float rho_cpd, float luminance, float ecc_deg);

/// Masked, perceptually normalised difference of one pixel of one band: test and reference band
/// contrasts already multiplied by the sensitivity; p = mask_p, q the channel's masking exponent,
/// mask_gain = 10^mask_c. D = |t − r|^p / (1 + (mask_gain · min(|t|, |r|))^q), capped at 1e4.
float maskedDifference(float t, float r, float p, float q, float mask_gain);

/// Eccentricity in degrees of the pixel at tangents (tx, ty) for the gaze at (gtx, gty): the angle
/// between their rays (Model::View) or the norm of the horizontal and vertical angle differences
/// (Model::FlatScreen, the reference's). With gaze (0, 0): the angle from the optical axis that
/// sets the local resolution.
double eccentricityDeg(ViewGeometry::Model model, double tx, double ty, double gtx, double gty);

/// Local resolution of a flat screen at angle `angle_deg` from its axis relative to its centre's,
/// with ppd_centre its central pixels per degree: (tan(a + δ) − tan a) / tan δ, δ = half a pixel.
double resolutionMagnification(double angle_deg, double ppd_centre);

/// Pools one frame's band qualities: {the sustained channel alone (an image's quality), both
/// channels (a video frame's quality)}; frames are then pooled by the beta_t-mean.
std::array<double, 2> poolFrame(const FrameQuality& frame, const Parameters& p = kParameters);

/// JOD of a pooled quality Q: 10 − |jod_a| · Q^(10^log_jod_exp).
double jodFromQuality(double q, const Parameters& p = kParameters);

/// Pyramid steps (the reference's 5-tap kernel a = 0.4, mirrored borders): one Gaussian
/// reduction (ceil halves) and one expansion to (w, h).
void pyramidReduce(const float* src, int w, int h, float* dst);
void pyramidExpand(const float* src, int sw, int sh, float* dst, int w, int h);

/// The checks every push makes on an input frame, with their codes and messages: empty, not CV_32FC3,
/// not the geometry's size (InvalidInput), a non-finite value (NonFinite, naming the first pixel).
Status checkInputImage(const cv::Mat& m, const char* what, const ViewGeometry& g);
/// The checks of one push: the test image, the reference image (checkInputImage) and a finite gaze
/// (InvalidInput).
Status checkInputFrame(const cv::Mat& test, const cv::Mat& reference, glm::vec2 gaze_px, const ViewGeometry& g);

}  // namespace detail

}  // namespace wrsfov::eval::fvvdp
