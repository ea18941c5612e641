#include "eval/metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/quality/qualityssim.hpp>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include "shaders/wrs_common.h"

namespace wrsfov::eval {

namespace {

constexpr double kPi = 3.14159265358979323846;

[[noreturn]] void fail(const std::string& message) { throw std::invalid_argument("eval: " + message); }

std::string sizeText(const cv::Mat& m) { return std::to_string(m.cols) + "x" + std::to_string(m.rows); }

// First non-finite value of a float Mat (any channel count), as "(x, y)"; empty when all are finite.
std::string firstNonFinite(const cv::Mat& m) {
    const int cn = m.channels();
    for (int y = 0; y < m.rows; ++y) {
        const float* p = m.ptr<float>(y);
        // A row is tested whole first (exponent bits all ones: NaN or infinity), a loop the compiler
        // vectorises; only a row that fails is searched for the first such value.
        uint32_t any = 0;
        for (int i = 0; i < m.cols * cn; ++i) {
            uint32_t bits;
            std::memcpy(&bits, p + i, 4);
            any |= uint32_t((bits & 0x7f800000u) == 0x7f800000u);
        }
        if (!any) continue;
        for (int i = 0; i < m.cols * cn; ++i)
            if (!std::isfinite(p[i])) return "(" + std::to_string(i / cn) + ", " + std::to_string(y) + ")";
    }
    return {};
}

// Validates one image and returns a continuous copy clamped to [0, 1].
cv::Mat prepare(const cv::Mat& image, const char* what) {
    if (image.empty()) fail(std::string(what) + " image is empty");
    if (image.type() != CV_32FC3)
        fail(std::string(what) + " image must be CV_32FC3 (sRGB-encoded RGB in [0, 1]), got type " +
             std::to_string(image.type()));
    if (std::string at = firstNonFinite(image); !at.empty())
        fail(std::string(what) + " image has a non-finite value at pixel " + at);
    cv::Mat out;
    cv::min(image, 1.0, out);
    cv::max(out, 0.0, out);
    return out.isContinuous() ? out : out.clone();
}

struct Pair {
    cv::Mat ref;
    cv::Mat test;
};

Pair preparePair(const cv::Mat& reference, const cv::Mat& test) {
    Pair p{prepare(reference, "reference"), prepare(test, "test")};
    if (p.ref.size() != p.test.size())
        fail("image sizes differ: reference " + sizeText(p.ref) + ", test " + sizeText(p.test));
    return p;
}

void checkEccentricity(const cv::Mat& ecc, cv::Size size) {
    if (ecc.empty()) fail("eccentricity map is empty");
    if (ecc.type() != CV_32FC1)
        fail("eccentricity map must be CV_32FC1 (degrees), got type " + std::to_string(ecc.type()));
    if (ecc.size() != size)
        fail("eccentricity map is " + sizeText(ecc) + ", images are " + sizeText(cv::Mat(size, CV_8U)));
    if (std::string at = firstNonFinite(ecc); !at.empty())
        fail("eccentricity map has a non-finite value at pixel " + at);
}

double psnrFromMse(double mse) {
    if (mse <= 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(1.0 / mse);
}

// Calls f(x, y, e) for every pixel with e the squared difference averaged over channels, in double
// (inputs prepared).
template <typename F>
void forEachSqErr(const Pair& p, F&& f) {
    for (int y = 0; y < p.ref.rows; ++y) {
        const float* a = p.ref.ptr<float>(y);
        const float* b = p.test.ptr<float>(y);
        for (int x = 0; x < p.ref.cols; ++x) {
            double s = 0.0;
            for (int c = 0; c < 3; ++c) {
                double d = double(a[3 * x + c]) - double(b[3 * x + c]);
                s += d * d;
            }
            f(x, y, s / 3.0);
        }
    }
}

void checkFovTan(glm::vec4 fov_tan) {
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(fov_tan[i])) fail("field-of-view tangents must be finite");
    if (!(fov_tan.y > fov_tan.x) || !(fov_tan.z > fov_tan.w))
        fail("field of view is empty: need tan right > tan left and tan up > tan down");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Conversion
// ---------------------------------------------------------------------------------------------

cv::Mat toMat(const HostImage& image) {
    using layers::Format;
    if (image.width == 0 || image.height == 0) fail("HostImage is empty");
    if (image.format != Format::RGBA8 && image.format != Format::RGBA8_SRGB && image.format != Format::RGBA16F)
        fail("HostImage format " + std::string(layers::toString(image.format)) +
             " is not a colour format (need rgba8, rgba8_srgb or rgba16f)");
    std::size_t expected = std::size_t(image.width) * image.height * image.texelBytes();
    if (image.data.size() != expected)
        fail("HostImage holds " + std::to_string(image.data.size()) + " bytes, " + std::to_string(image.width) + "x" +
             std::to_string(image.height) + " " + std::string(layers::toString(image.format)) + " needs " +
             std::to_string(expected));
    cv::Mat out(int(image.height), int(image.width), CV_32FC3);
    if (image.format != Format::RGBA16F) {
        // 8-bit: the values HostImage::fetch gives (code / 255), from a table, without its per-texel dispatch.
        std::array<float, 256> unorm;
        for (int i = 0; i < 256; ++i) unorm[i] = float(i) / 255.0f;
        const auto* in = reinterpret_cast<const uint8_t*>(image.data.data());
        for (uint32_t y = 0; y < image.height; ++y) {
            float* o = out.ptr<float>(int(y));
            const uint8_t* p = in + std::size_t(y) * image.width * 4;
            for (uint32_t x = 0; x < image.width; ++x)
                for (int c = 0; c < 3; ++c) o[3 * x + c] = unorm[p[4 * x + c]];
        }
        return out;
    }
    for (uint32_t y = 0; y < image.height; ++y) {  // RGBA16F: linear, encoded to sRGB here
        float* o = out.ptr<float>(int(y));
        for (uint32_t x = 0; x < image.width; ++x) {
            glm::vec4 t = image.fetch(x, y);
            for (int c = 0; c < 3; ++c) {
                float v = t[c];
                if (std::isfinite(v)) v = gpu::wrs_linear_to_srgb(v);
                o[3 * x + c] = v;
            }
        }
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// Full-image error
// ---------------------------------------------------------------------------------------------

cv::Mat squaredErrorMap(const cv::Mat& reference, const cv::Mat& test) {
    Pair p = preparePair(reference, test);
    cv::Mat out(p.ref.size(), CV_32F);
    forEachSqErr(p, [&](int x, int y, double e) { out.at<float>(y, x) = float(e); });
    return out;
}

double meanSquaredError(const cv::Mat& reference, const cv::Mat& test) {
    Pair p = preparePair(reference, test);
    double sum = 0.0;
    forEachSqErr(p, [&](int, int, double e) { sum += e; });
    return sum / double(p.ref.total());
}

double psnr(const cv::Mat& reference, const cv::Mat& test) { return psnrFromMse(meanSquaredError(reference, test)); }
double psnr(const HostImage& reference, const HostImage& test) { return psnr(toMat(reference), toMat(test)); }

double ssim(const cv::Mat& reference, const cv::Mat& test) {
    Pair p = preparePair(reference, test);
    cv::Mat a, b;
    p.ref.convertTo(a, CV_32F, 255.0);
    p.test.convertTo(b, CV_32F, 255.0);
    cv::Scalar s = cv::quality::QualitySSIM::compute(a, b, cv::noArray());
    return (s[0] + s[1] + s[2]) / 3.0;
}
double ssim(const HostImage& reference, const HostImage& test) { return ssim(toMat(reference), toMat(test)); }

// ---------------------------------------------------------------------------------------------
// Eccentricity-aware error
// ---------------------------------------------------------------------------------------------

cv::Mat eccentricityMap(uint32_t width, uint32_t height, glm::vec4 fov_tan, glm::vec3 gaze) {
    if (width == 0 || height == 0) fail("eccentricity map size must be non-zero");
    checkFovTan(fov_tan);
    float len = glm::length(gaze);
    if (!std::isfinite(len) || len <= 0.0f) fail("gaze direction must be finite and non-zero");
    glm::vec3 g = gaze / len;
    cv::Mat out(int(height), int(width), CV_32F);
    for (uint32_t y = 0; y < height; ++y) {
        float* o = out.ptr<float>(int(y));
        for (uint32_t x = 0; x < width; ++x)
            o[x] = gpu::wrs_eccentricity_deg(gpu::wrs_pixel_ray(x, y, width, height, fov_tan), g);
    }
    return out;
}

cv::Mat eccentricityMap(uint32_t width, uint32_t height, const gpu::EyeParams& eye) {
    return eccentricityMap(width, height, eye.fov_tan, glm::vec3(eye.gaze));
}

glm::vec2 gazePixelF(const gpu::EyeParams& ep, uint32_t w, uint32_t h) {
    const glm::vec3 g(ep.gaze);
    if (!(g.z < 0.0f)) return {float(w / 2), float(h / 2)};
    const float tx = g.x / -g.z, ty = g.y / -g.z;
    const float u = (tx - ep.fov_tan.x) / (ep.fov_tan.y - ep.fov_tan.x),
                v = (ep.fov_tan.z - ty) / (ep.fov_tan.z - ep.fov_tan.w);
    return {u * float(w) - 0.5f, v * float(h) - 0.5f};
}

double nearGazePsnr(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity, double max_deg) {
    Pair p = preparePair(reference, test);
    checkEccentricity(eccentricity, p.ref.size());
    if (std::isnan(max_deg)) fail("near-gaze radius is NaN");
    double sum = 0.0;
    std::size_t n = 0;
    forEachSqErr(p, [&](int x, int y, double e) {
        if (double(eccentricity.at<float>(y, x)) <= max_deg) {
            sum += e;
            ++n;
        }
    });
    if (n == 0) return std::numeric_limits<double>::quiet_NaN();
    return psnrFromMse(sum / double(n));
}
double nearGazePsnr(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity, double max_deg) {
    return nearGazePsnr(toMat(reference), toMat(test), eccentricity, max_deg);
}

cv::Mat eccentricityWeights(const cv::Mat& eccentricity, double fovea_deg) {
    if (!std::isfinite(fovea_deg) || fovea_deg <= 0.0) fail("weighting fovea radius must be finite and > 0");
    checkEccentricity(eccentricity, eccentricity.size());
    cv::Mat w(eccentricity.size(), CV_32F);
    for (int y = 0; y < w.rows; ++y) {
        const float* pd = eccentricity.ptr<float>(y);
        float* pw = w.ptr<float>(y);
        for (int x = 0; x < w.cols; ++x) pw[x] = gpu::wrs_sample_weight(std::max(pd[x], 0.0f), float(fovea_deg));
    }
    return w;
}

double eccentricityWeightedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity,
                               double fovea_deg) {
    checkEccentricity(eccentricity, reference.size());
    return weightedMse(reference, test, eccentricityWeights(eccentricity, fovea_deg));
}
double weightedMse(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& weights) {
    Pair p = preparePair(reference, test);
    if (weights.type() != CV_32FC1 || weights.size() != p.ref.size())
        fail("weights must be CV_32FC1 of the images' size (" + sizeText(p.ref) + ")");
    if (std::string at = firstNonFinite(weights); !at.empty()) fail("weight at pixel " + at + " is not finite");
    double lo = 0.0;
    cv::minMaxLoc(weights, &lo);
    if (lo < 0.0) fail("weights must not be negative");
    double num = 0.0, den = 0.0;
    forEachSqErr(p, [&](int x, int y, double e) {
        double wi = weights.at<float>(y, x);
        num += wi * e;
        den += wi;
    });
    return den > 0.0 ? num / den : 0.0;  // eccentricity weights are > 0 for any finite eccentricity
}
double eccentricityWeightedMse(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity,
                               double fovea_deg) {
    return eccentricityWeightedMse(toMat(reference), toMat(test), eccentricity, fovea_deg);
}

// ---------------------------------------------------------------------------------------------
// FLIP
// ---------------------------------------------------------------------------------------------

double pixelsPerDegree(double distance_m, double width_m, double resolution_px) {
    if (!(distance_m > 0.0) || !(width_m > 0.0) || !(resolution_px > 0.0) || !std::isfinite(distance_m) ||
        !std::isfinite(width_m) || !std::isfinite(resolution_px))
        fail("viewing distance, monitor width and resolution must be finite and > 0");
    return distance_m * (resolution_px / width_m) * (kPi / 180.0);
}

double pixelsPerDegreeAtCentre(uint32_t width_px, glm::vec4 fov_tan) {
    if (width_px == 0) fail("view width must be non-zero");
    checkFovTan(fov_tan);
    return double(width_px) / (double(fov_tan.y) - double(fov_tan.x)) * (kPi / 180.0);
}

namespace {

// LDR-FLIP, Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström, Fairchild 2020, "FLIP: A
// Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2) (HPG 2020).
// From the paper:
//   - colour pipeline: YCxCz opponent space, one spatial CSF filter per channel, each a sum of two
//     Gaussians S(x) = a1·sqrt(π/b1)·exp(−π²x²/b1) + a2·sqrt(π/b2)·exp(−π²x²/b2), x in degrees:
//       achromatic (Y):   a1 = 1,    b1 = 0.0047, a2 = 0,    b2 = 1e-5
//       red-green (Cx):   a1 = 1,    b1 = 0.0053, a2 = 0,    b2 = 1e-5
//       blue-yellow (Cz): a1 = 34.1, b1 = 0.04,   a2 = 13.5, b2 = 0.025
//     then linear RGB clamped to [0, 1], CIELAB, Hunt adjustment a* ← 0.01·L*·a*, b* ← 0.01·L*·b*,
//     HyAB distance |ΔL*| + ||(Δa*, Δb*)||, raised to q_c = 0.7 and remapped: [0, p_c·c_max) linearly
//     to [0, p_t), [p_c·c_max, c_max] linearly to [p_t, 1], with p_c = 0.4, p_t = 0.95 and
//     c_max = HyAB(Hunt(green), Hunt(blue))^q_c for linear RGB (0, 1, 0) and (0, 0, 1);
//   - feature pipeline on the unfiltered luminance y/y_n: first (edge) and second (point) x- and
//     y-derivatives of a Gaussian with σ = 0.5·w·ppd pixels, w = 0.082° (the detector's
//     peak-to-trough width), positive weights scaled to sum 1 and negative weights to −1;
//     ΔE_f = (max(|‖edge_r‖ − ‖edge_t‖|, |‖point_r‖ − ‖point_t‖|) / √2)^q_f with q_f = 0.5;
//   - ΔE = ΔE_c^(1 − ΔE_f); pixels per degree = distance · (resolution / width) · π / 180.
// From the authors' reference code rather than the paper's text: the CSF kernel radius
// ceil(3·sqrt(b_max / (2π²))·ppd) pixels with b_max = 0.04 (the largest b), kernels normalised to sum
// 1; detector radius ceil(3σ); the rational sRGB-to-XYZ matrix below with white = matrix · (1, 1, 1);
// YCxCz as linearised CIELAB: Y = 116·y/y_n − 16, Cx = 500·(x/x_n − y/y_n), Cz = 200·(y/y_n − z/z_n).
// Choices of this implementation: borders replicated (a uniform image stays uniform through every
// filter); the colour term clamped to 1 so that the map stays in [0, 1] for any input. The values have
// not been compared with the reference code's output on shared images.
constexpr double kQc = 0.7;
constexpr double kPc = 0.4;
constexpr double kPt = 0.95;
constexpr double kQf = 0.5;
constexpr double kEdgeWidthDeg = 0.082;

struct Csf {
    double a1, b1, a2, b2;
};
constexpr Csf kCsfA{1.0, 0.0047, 0.0, 1e-5};
constexpr Csf kCsfRG{1.0, 0.0053, 0.0, 1e-5};
constexpr Csf kCsfBY{34.1, 0.04, 13.5, 0.025};
constexpr double kCsfBMax = 0.04;

const cv::Matx33d kRgbToXyz(10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0,  //
                            2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0,    //
                            1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0);
const cv::Matx33d kXyzToRgb = kRgbToXyz.inv();
const cv::Vec3d kWhite = kRgbToXyz * cv::Vec3d(1.0, 1.0, 1.0);

// Runs f(y) for every row, rows split over OpenCV's worker threads. Rows are independent.
template <typename F>
void forRows(int rows, F&& f) {
    cv::parallel_for_(cv::Range(0, rows), [&](const cv::Range& r) {
        for (int y = r.start; y < r.end; ++y) f(y);
    });
}

double srgbToLinear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }

double labF(double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// Linear RGB -> Hunt-adjusted CIELAB.
cv::Vec3d huntLab(cv::Vec3d rgb) {
    cv::Vec3d xyz = kRgbToXyz * rgb;
    double fx = labF(xyz[0] / kWhite[0]), fy = labF(xyz[1] / kWhite[1]), fz = labF(xyz[2] / kWhite[2]);
    double L = 116.0 * fy - 16.0;
    double a = 500.0 * (fx - fy), b = 200.0 * (fy - fz);
    return {L, 0.01 * L * a, 0.01 * L * b};
}

double hyab(cv::Vec3d p, cv::Vec3d q) {
    double da = p[1] - q[1], db = p[2] - q[2];
    return std::abs(p[0] - q[0]) + std::sqrt(da * da + db * db);
}

// sRGB-encoded RGB (prepared) -> YCxCz planes (CV_64F: the detectors' square root magnifies rounding).
std::array<cv::Mat, 3> toYCxCz(const cv::Mat& srgb) {
    std::array<cv::Mat, 3> out;
    for (auto& m : out) m.create(srgb.size(), CV_64F);
    forRows(srgb.rows, [&](int y) {
        const float* p = srgb.ptr<float>(y);
        double* o0 = out[0].ptr<double>(y);
        double* o1 = out[1].ptr<double>(y);
        double* o2 = out[2].ptr<double>(y);
        for (int x = 0; x < srgb.cols; ++x) {
            cv::Vec3d lin(srgbToLinear(p[3 * x]), srgbToLinear(p[3 * x + 1]), srgbToLinear(p[3 * x + 2]));
            cv::Vec3d xyz = kRgbToXyz * lin;
            double nx = xyz[0] / kWhite[0], ny = xyz[1] / kWhite[1], nz = xyz[2] / kWhite[2];
            o0[x] = 116.0 * ny - 16.0;
            o1[x] = 500.0 * (nx - ny);
            o2[x] = 200.0 * (ny - nz);
        }
    });
    return out;
}

// Convolves one plane with the normalised 2D CSF filter, as a sum of separable Gaussian terms.
cv::Mat csfFilter(const cv::Mat& plane, const Csf& csf, double ppd) {
    const int r = int(std::ceil(3.0 * std::sqrt(kCsfBMax / (2.0 * kPi * kPi)) * ppd));
    const double dx = 1.0 / ppd;
    struct Term {
        double scale;  // a·sqrt(π/b)·(Σ g)²: the term's share of the 2D kernel's sum
        cv::Mat g;     // 1D Gaussian normalised to sum 1
    };
    std::vector<Term> terms;
    for (auto [a, b] : {std::pair{csf.a1, csf.b1}, std::pair{csf.a2, csf.b2}}) {
        if (a == 0.0) continue;
        cv::Mat g(2 * r + 1, 1, CV_64F);
        double s = 0.0;
        for (int i = -r; i <= r; ++i) {
            double xd = i * dx;
            g.at<double>(i + r) = std::exp(-kPi * kPi * xd * xd / b);
            s += g.at<double>(i + r);
        }
        g /= s;
        terms.push_back({a * std::sqrt(kPi / b) * s * s, g});
    }
    double total = 0.0;
    for (const Term& t : terms) total += t.scale;
    cv::Mat out = cv::Mat::zeros(plane.size(), CV_64F);
    for (const Term& t : terms) {
        cv::Mat f;
        cv::sepFilter2D(plane, f, CV_64F, t.g, t.g, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
        cv::scaleAdd(f, t.scale / total, out, out);
    }
    return out;
}

// Filtered YCxCz -> linear RGB clamped to [0, 1] -> Hunt-adjusted L*a*b*, as a CV_64FC3 image.
cv::Mat filteredToHuntLab(const std::array<cv::Mat, 3>& f) {
    cv::Mat out(f[0].size(), CV_64FC3);
    forRows(out.rows, [&](int y) {
        const double* p0 = f[0].ptr<double>(y);
        const double* p1 = f[1].ptr<double>(y);
        const double* p2 = f[2].ptr<double>(y);
        cv::Vec3d* o = out.ptr<cv::Vec3d>(y);
        for (int x = 0; x < out.cols; ++x) {
            double ny = (p0[x] + 16.0) / 116.0;
            double nx = p1[x] / 500.0 + ny;
            double nz = ny - p2[x] / 200.0;
            cv::Vec3d rgb = kXyzToRgb * cv::Vec3d(nx * kWhite[0], ny * kWhite[1], nz * kWhite[2]);
            for (int c = 0; c < 3; ++c) rgb[c] = std::clamp(rgb[c], 0.0, 1.0);
            o[x] = huntLab(rgb);
        }
    });
    return out;
}

// 1D edge (first derivative) or point (second derivative) profile of the feature detectors, with
// positive weights normalised to sum 1 and negative weights to sum −1, and the matching 1D Gaussian
// (sum 1) for the other axis. The 2D kernels of the paper factor into these two.
struct FeatureKernels {
    cv::Mat edge;
    cv::Mat point;
    cv::Mat gauss;
};

FeatureKernels featureKernels(double ppd) {
    const double sd = 0.5 * kEdgeWidthDeg * ppd;
    const int r = int(std::ceil(3.0 * sd));
    FeatureKernels k{cv::Mat(2 * r + 1, 1, CV_64F), cv::Mat(2 * r + 1, 1, CV_64F), cv::Mat(2 * r + 1, 1, CV_64F)};
    double gs = 0.0;
    double pos[2] = {0.0, 0.0}, neg[2] = {0.0, 0.0};
    for (int i = -r; i <= r; ++i) {
        double g = std::exp(-double(i) * i / (2.0 * sd * sd));
        double e = -double(i) * g;
        double p = (double(i) * i / (sd * sd) - 1.0) * g;
        k.gauss.at<double>(i + r) = g;
        k.edge.at<double>(i + r) = e;
        k.point.at<double>(i + r) = p;
        gs += g;
        (e > 0 ? pos[0] : neg[0]) += std::abs(e);
        (p > 0 ? pos[1] : neg[1]) += std::abs(p);
    }
    k.gauss /= gs;
    // At very coarse viewing (below about 1 pixel per degree) the edge Gaussian is narrower than a
    // pixel and its off-centre taps underflow to 0: no feature can be resolved there. A kernel
    // with an empty lobe would no longer sum to zero, so it becomes 0 (feature term 0) instead of
    // dividing 0 by 0 or responding to flat regions.
    auto normalise = [](double v, double positive, double negative) {
        if (!(positive > 0) || !(negative > 0)) return 0.0;
        return v > 0 ? v / positive : v / negative;
    };
    for (int i = 0; i <= 2 * r; ++i) {
        double& e = k.edge.at<double>(i);
        e = normalise(e, pos[0], neg[0]);
        double& p = k.point.at<double>(i);
        p = normalise(p, pos[1], neg[1]);
    }
    return k;
}

// Magnitudes of the edge and point responses of a luminance plane.
std::pair<cv::Mat, cv::Mat> features(const cv::Mat& lum, const FeatureKernels& k) {
    auto filt = [&](const cv::Mat& kx, const cv::Mat& ky) {
        cv::Mat f;
        cv::sepFilter2D(lum, f, CV_64F, kx, ky, cv::Point(-1, -1), 0.0, cv::BORDER_REPLICATE);
        return f;
    };
    cv::Mat edges, points;
    cv::magnitude(filt(k.edge, k.gauss), filt(k.gauss, k.edge), edges);
    cv::magnitude(filt(k.point, k.gauss), filt(k.gauss, k.point), points);
    return {edges, points};
}

}  // namespace

FlipResult flip(const cv::Mat& reference, const cv::Mat& test, const FlipOptions& options) {
    const double ppd = options.pixels_per_degree;
    if (!std::isfinite(ppd) || ppd <= 0.0) fail("FLIP pixels per degree must be finite and > 0");
    Pair p = preparePair(reference, test);

    std::array<cv::Mat, 3> ref = toYCxCz(p.ref);
    std::array<cv::Mat, 3> tst = toYCxCz(p.test);

    // Colour pipeline.
    const Csf* csfs[3] = {&kCsfA, &kCsfRG, &kCsfBY};
    std::array<cv::Mat, 3> fref, ftst;
    for (int c = 0; c < 3; ++c) {
        fref[c] = csfFilter(ref[c], *csfs[c], ppd);
        ftst[c] = csfFilter(tst[c], *csfs[c], ppd);
    }
    cv::Mat lab_ref = filteredToHuntLab(fref);
    cv::Mat lab_tst = filteredToHuntLab(ftst);
    const double cmax = std::pow(hyab(huntLab({0.0, 1.0, 0.0}), huntLab({0.0, 0.0, 1.0})), kQc);
    const double pccmax = kPc * cmax;

    // Feature pipeline on the unfiltered, normalised luminance y/y_n = (Y + 16) / 116.
    FeatureKernels k = featureKernels(ppd);
    cv::Mat lum_ref, lum_tst;
    ref[0].convertTo(lum_ref, CV_64F, 1.0 / 116.0, 16.0 / 116.0);
    tst[0].convertTo(lum_tst, CV_64F, 1.0 / 116.0, 16.0 / 116.0);
    // Named matrices rather than structured bindings: the row lambda below captures them, which
    // clang before 16 refuses for bindings.
    cv::Mat edge_ref, point_ref, edge_tst, point_tst;
    std::tie(edge_ref, point_ref) = features(lum_ref, k);
    std::tie(edge_tst, point_tst) = features(lum_tst, k);

    FlipResult result;
    result.map.create(p.ref.size(), CV_32F);
    std::vector<double> row_sums(std::size_t(p.ref.rows), 0.0);
    forRows(p.ref.rows, [&](int y) {
        double sum = 0.0;
        const cv::Vec3d* lr = lab_ref.ptr<cv::Vec3d>(y);
        const cv::Vec3d* lt = lab_tst.ptr<cv::Vec3d>(y);
        const double* er = edge_ref.ptr<double>(y);
        const double* et = edge_tst.ptr<double>(y);
        const double* pr = point_ref.ptr<double>(y);
        const double* pt = point_tst.ptr<double>(y);
        float* o = result.map.ptr<float>(y);
        for (int x = 0; x < p.ref.cols; ++x) {
            double dc = std::pow(hyab(lr[x], lt[x]), kQc);
            dc = dc < pccmax ? (kPt / pccmax) * dc : kPt + (dc - pccmax) / (cmax - pccmax) * (1.0 - kPt);
            dc = std::min(dc, 1.0);
            double df = std::max(std::abs(er[x] - et[x]), std::abs(pr[x] - pt[x]));
            df = std::pow(df / std::sqrt(2.0), kQf);
            double v = std::pow(dc, 1.0 - df);
            o[x] = float(v);
            sum += v;
        }
        row_sums[std::size_t(y)] = sum;
    });
    double sum = 0.0;
    for (double r : row_sums) sum += r;  // in row order: the mean does not depend on the thread count
    result.mean = sum / double(result.map.total());
    return result;
}

FlipResult flip(const HostImage& reference, const HostImage& test, const FlipOptions& options) {
    return flip(toMat(reference), toMat(test), options);
}

// ---------------------------------------------------------------------------------------------
// Temporal instability
// ---------------------------------------------------------------------------------------------

TemporalInstability::TemporalInstability(double threshold) : threshold_(threshold) {
    if (!std::isfinite(threshold) || threshold < 0.0) fail("temporal instability threshold must be finite and >= 0");
}

double TemporalInstability::addFrame(const cv::Mat& reference, const cv::Mat& output) {
    Pair p = preparePair(reference, output);
    if (frames_ > 0 && p.ref.size() != prev_ref_.size())
        fail("frame size changed within a sequence: was " + sizeText(prev_ref_) + ", now " + sizeText(p.ref));
    double frame_value = std::numeric_limits<double>::quiet_NaN();
    if (frames_ > 0) {
        double sum = 0.0;
        uint64_t n = 0;
        for (int y = 0; y < p.ref.rows; ++y) {
            const float* r0 = prev_ref_.ptr<float>(y);
            const float* r1 = p.ref.ptr<float>(y);
            const float* o0 = prev_out_.ptr<float>(y);
            const float* o1 = p.test.ptr<float>(y);
            for (int x = 0; x < p.ref.cols; ++x) {
                double dr = 0.0, dout = 0.0;
                for (int c = 0; c < 3; ++c) {
                    dr = std::max(dr, std::abs(double(r1[3 * x + c]) - double(r0[3 * x + c])));
                    dout += std::abs(double(o1[3 * x + c]) - double(o0[3 * x + c]));
                }
                if (dr <= threshold_) {
                    sum += dout / 3.0;
                    ++n;
                }
            }
        }
        if (n > 0) frame_value = sum / double(n);
        sum_ += sum;
        stable_ += n;
    }
    prev_ref_ = p.ref;
    prev_out_ = p.test;
    ++frames_;
    return frame_value;
}

double TemporalInstability::addFrame(const HostImage& reference, const HostImage& output) {
    return addFrame(toMat(reference), toMat(output));
}

double TemporalInstability::mean() const {
    return stable_ > 0 ? sum_ / double(stable_) : std::numeric_limits<double>::quiet_NaN();
}

void TemporalInstability::reset() {
    prev_ref_.release();
    prev_out_.release();
    frames_ = 0;
    stable_ = 0;
    sum_ = 0.0;
}

// ---------------------------------------------------------------------------------------------
// All metrics of one frame
// ---------------------------------------------------------------------------------------------

FrameMetrics evaluateFrame(const cv::Mat& reference, const cv::Mat& test, const cv::Mat& eccentricity,
                           const MetricOptions& options) {
    FrameMetrics m;
    m.psnr = psnr(reference, test);
    m.ssim = ssim(reference, test);
    m.near_gaze_psnr = nearGazePsnr(reference, test, eccentricity, options.near_gaze_deg);
    m.ecc_weighted_mse = eccentricityWeightedMse(reference, test, eccentricity, options.weight_fovea_deg);
    FlipResult f = flip(reference, test, options.flip);
    m.flip = f.mean;
    m.flip_map = f.map;
    return m;
}

FrameMetrics evaluateFrame(const HostImage& reference, const HostImage& test, const cv::Mat& eccentricity,
                           const MetricOptions& options) {
    return evaluateFrame(toMat(reference), toMat(test), eccentricity, options);
}

// ---------------------------------------------------------------------------------------------
// Error maps as PNG
// ---------------------------------------------------------------------------------------------

namespace {

Status invalid(const std::string& message) { return Status(Error{int(EvalError::InvalidInput), "eval: " + message}); }

std::string tickText(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", v);
    return buf;
}

}  // namespace

Status writeErrorMapPng(const cv::Mat& error, const std::string& path, const ErrorMapStyle& style) {
    if (error.empty()) return invalid("error map is empty (" + path + ")");
    if (error.type() != CV_32FC1)
        return invalid("error map must be CV_32FC1, got type " + std::to_string(error.type()));
    if (std::string at = firstNonFinite(error); !at.empty())
        return invalid("error map has a non-finite value at pixel " + at + " (" + path + ")");
    double lo = 0.0, hi = 0.0;
    cv::minMaxLoc(error, &lo, &hi);
    if (lo < 0.0) return invalid("error map has negative values (" + path + ")");
    if (!std::isfinite(style.max_value)) return invalid("error map max_value is not finite");
    const double top = style.max_value > 0.0 ? style.max_value : (hi > 0.0 ? hi : 1.0);

    try {
        cv::Mat u8, coloured;
        error.convertTo(u8, CV_8U, 255.0 / top);
        cv::applyColorMap(u8, coloured, style.colormap);

        // Legend: a panel to the right with a vertical colour bar from 0 (bottom) to top, and ticks.
        const int legend_w = 84;
        const int h = std::max(error.rows, 96);
        cv::Mat canvas(h, error.cols + legend_w, CV_8UC3, cv::Scalar(32, 32, 32));
        coloured.copyTo(canvas(cv::Rect(0, 0, error.cols, error.rows)));
        const int bar_x = error.cols + 8, bar_w = 14, bar_top = 22, bar_bottom = h - 10;
        const int bar_h = bar_bottom - bar_top;
        cv::Mat ramp(bar_h, 1, CV_8U);
        for (int i = 0; i < bar_h; ++i)
            ramp.at<uint8_t>(i) = uint8_t(std::lround(255.0 * (bar_h - 1 - i) / (bar_h - 1)));
        cv::Mat ramp_c;
        cv::applyColorMap(ramp, ramp_c, style.colormap);
        cv::resize(ramp_c, ramp_c, cv::Size(bar_w, bar_h), 0, 0, cv::INTER_NEAREST);
        ramp_c.copyTo(canvas(cv::Rect(bar_x, bar_top, bar_w, bar_h)));
        const cv::Scalar text(230, 230, 230);
        const int font = cv::FONT_HERSHEY_SIMPLEX;
        for (int i = 0; i <= 4; ++i) {
            double v = top * (4 - i) / 4.0;
            int y = bar_top + int(std::lround((bar_h - 1) * i / 4.0));
            cv::line(canvas, {bar_x + bar_w, y}, {bar_x + bar_w + 4, y}, text);
            std::string t = (i == 0 && hi > top && style.max_value > 0.0 ? ">" : "") + tickText(v);
            cv::putText(canvas, t, {bar_x + bar_w + 7, y + 4}, font, 0.35, text, 1, cv::LINE_AA);
        }
        if (!style.label.empty()) cv::putText(canvas, style.label, {bar_x, 14}, font, 0.4, text, 1, cv::LINE_AA);
        if (!cv::imwrite(path, canvas))
            return Status(Error{int(EvalError::WriteFailed), "eval: could not write PNG " + path});
    } catch (const cv::Exception& e) {
        return Status(Error{int(EvalError::WriteFailed), "eval: could not write PNG " + path + ": " + e.what()});
    }
    return Status::success();
}

Status writeFlipMapPng(const cv::Mat& flip_map, const std::string& path) {
    return writeErrorMapPng(flip_map, path, ErrorMapStyle{1.0, cv::COLORMAP_MAGMA, "FLIP"});
}

}  // namespace wrsfov::eval
