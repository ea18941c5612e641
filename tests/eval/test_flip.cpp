// LDR-FLIP (Andersson et al. 2020): hand-computed values on uniform images (no features, so FLIP is
// the remapped Hunt-adjusted HyAB colour difference), the extremes, symmetry, monotonicity, locality
// and the viewing-distance parameter.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <utility>
#include <vector>

#include "eval/metrics.h"

namespace wrsfov::eval {
namespace {

constexpr double kPi = 3.14159265358979323846;

cv::Mat uniform(int w, int h, cv::Vec3f c) { return cv::Mat(h, w, CV_32FC3, cv::Scalar(c[0], c[1], c[2])); }

// A textured test scene: smoothed noise with hard-edged rectangles, sRGB in [0, 1], fixed seed.
cv::Mat texture(int w, int h, uint64_t seed) {
    cv::Mat n(h, w, CV_32FC3);
    cv::RNG(seed).fill(n, cv::RNG::UNIFORM, 0.0, 1.0);
    cv::Mat t;
    cv::GaussianBlur(n, t, cv::Size(0, 0), 1.5);
    t = (t - cv::Scalar::all(0.5)) * 3.0 + cv::Scalar::all(0.5);
    cv::rectangle(t, cv::Rect(w / 8, h / 8, w / 4, h / 3), cv::Scalar(0.9, 0.8, 0.1), cv::FILLED);
    cv::rectangle(t, cv::Rect(w / 2, h / 2, w / 3, h / 5), cv::Scalar(0.05, 0.1, 0.6), cv::FILLED);
    cv::min(t, 1.0, t);
    cv::max(t, 0.0, t);
    return t;
}

cv::Mat gaussianNoise(int w, int h, uint64_t seed) {
    cv::Mat n(h, w, CV_32FC3);
    cv::RNG(seed).fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    return n;
}

cv::Mat clamp01(cv::Mat m) {
    cv::min(m, 1.0, m);
    cv::max(m, 0.0, m);
    return m;
}

// --- FLIP by hand, from the paper's formulas ----------------------------------------------------

double linear(double c) { return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4); }
double srgb(double c) { return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055; }

// Linear sRGB -> XYZ (D65), the rational form used with FLIP.
const cv::Matx33d kM(10135552.0 / 24577794.0, 8788810.0 / 24577794.0, 4435075.0 / 24577794.0,  //
                     2613072.0 / 12288897.0, 8788810.0 / 12288897.0, 887015.0 / 12288897.0,    //
                     1425312.0 / 73733382.0, 8788810.0 / 73733382.0, 70074185.0 / 73733382.0);
const cv::Vec3d kWhite = kM * cv::Vec3d(1, 1, 1);

double labF(double t) {
    const double d = 6.0 / 29.0;
    return t > d * d * d ? std::cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

// Hunt-adjusted L*a*b* of white-normalised XYZ (x/x_n, y/y_n, z/z_n).
cv::Vec3d huntLabOfNormalisedXyz(cv::Vec3d n) {
    double fx = labF(n[0]), fy = labF(n[1]), fz = labF(n[2]);
    double L = 116.0 * fy - 16.0;
    return {L, 0.01 * L * 500.0 * (fx - fy), 0.01 * L * 200.0 * (fy - fz)};
}

cv::Vec3d huntLabByHand(cv::Vec3d rgb_linear) {
    cv::Vec3d xyz = kM * rgb_linear;
    return huntLabOfNormalisedXyz({xyz[0] / kWhite[0], xyz[1] / kWhite[1], xyz[2] / kWhite[2]});
}

// sRGB pixel of a YCxCz colour.
cv::Vec3f srgbOfYCxCz(double Y, double Cx, double Cz) {
    double ny = (Y + 16.0) / 116.0;
    cv::Vec3d xyz((ny + Cx / 500.0) * kWhite[0], ny * kWhite[1], (ny - Cz / 200.0) * kWhite[2]);
    cv::Vec3d rgb = kM.inv() * xyz;
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(rgb[c] >= 0.0 && rgb[c] <= 1.0) << "test colour out of gamut";
    return cv::Vec3f(float(srgb(rgb[0])), float(srgb(rgb[1])), float(srgb(rgb[2])));
}

double hyabByHand(cv::Vec3d p, cv::Vec3d q) { return std::abs(p[0] - q[0]) + std::hypot(p[1] - q[1], p[2] - q[2]); }

// Remapped colour term of a HyAB distance (p_c = 0.4, p_t = 0.95, q_c = 0.7).
double colourTermByHand(double hyab) {
    double cmax = std::pow(hyabByHand(huntLabByHand({0, 1, 0}), huntLabByHand({0, 0, 1})), 0.7);
    double e = std::pow(hyab, 0.7);
    double pc = 0.4 * cmax, pt = 0.95;
    return e < pc ? pt / pc * e : pt + (e - pc) / (cmax - pc) * (1.0 - pt);
}

// The paper's 2D kernels, written out in full (not factored): K[(y + r)·(2r + 1) + (x + r)].
struct Kernel2D {
    int r = 0;
    std::vector<double> k;
    double at(int x, int y) const { return k[std::size_t((y + r) * (2 * r + 1) + (x + r))]; }
};

// CSF filter: a1·sqrt(π/b1)·exp(−π²d²/b1) + a2·sqrt(π/b2)·exp(−π²d²/b2), d in degrees, sum 1.
Kernel2D csfKernel(double a1, double b1, double a2, double b2, double ppd) {
    Kernel2D K;
    K.r = int(std::ceil(3.0 * std::sqrt(0.04 / (2.0 * kPi * kPi)) * ppd));
    double sum = 0.0;
    for (int y = -K.r; y <= K.r; ++y)
        for (int x = -K.r; x <= K.r; ++x) {
            double d2 = (x * x + y * y) / (ppd * ppd);
            double v = a1 * std::sqrt(kPi / b1) * std::exp(-kPi * kPi * d2 / b1) +
                       a2 * std::sqrt(kPi / b2) * std::exp(-kPi * kPi * d2 / b2);
            K.k.push_back(v);
            sum += v;
        }
    for (double& v : K.k) v /= sum;
    return K;
}

// x-direction edge (−x·g) or point ((x²/σ² − 1)·g) detector, σ = 0.5·0.082·ppd, positive weights
// scaled to sum 1 and negative weights to sum −1.
Kernel2D featureKernel(bool point, double ppd) {
    Kernel2D K;
    double sd = 0.5 * 0.082 * ppd;
    K.r = int(std::ceil(3.0 * sd));
    double pos = 0.0, neg = 0.0;
    for (int y = -K.r; y <= K.r; ++y)
        for (int x = -K.r; x <= K.r; ++x) {
            double g = std::exp(-(x * x + y * y) / (2.0 * sd * sd));
            double v = point ? (x * x / (sd * sd) - 1.0) * g : -x * g;
            K.k.push_back(v);
            (v > 0 ? pos : neg) += std::abs(v);
        }
    for (double& v : K.k) v = v > 0 ? v / pos : v / neg;
    return K;
}

// Response at column x0 of an image that varies only along x (value phi(x)), to K and to K
// transposed (the y-direction detector).
template <typename Phi>
std::pair<double, double> respond(const Kernel2D& K, int x0, Phi phi) {
    double rx = 0.0, ry = 0.0;
    for (int y = -K.r; y <= K.r; ++y)
        for (int x = -K.r; x <= K.r; ++x) {
            rx += K.at(x, y) * phi(x0 + x);
            ry += K.at(y, x) * phi(x0 + x);
        }
    return {rx, ry};
}

// FLIP of two uniform sRGB colours: no edges or points, so ΔE = ΔE_c, the remapped HyAB^0.7.
double uniformFlipByHand(cv::Vec3d srgb_a, cv::Vec3d srgb_b) {
    auto lab = [](cv::Vec3d s) { return huntLabByHand({linear(s[0]), linear(s[1]), linear(s[2])}); };
    return colourTermByHand(hyabByHand(lab(srgb_a), lab(srgb_b)));
}

void expectUniformMap(const FlipResult& r, double value, double tol) {
    double lo, hi;
    cv::minMaxLoc(r.map, &lo, &hi);
    EXPECT_NEAR(lo, value, tol);
    EXPECT_NEAR(hi, value, tol);
    EXPECT_NEAR(r.mean, value, tol);
}

// ---------------------------------------------------------------------------------------------

TEST(EvalFlip, ViewingConditions) {
    EXPECT_NEAR(pixelsPerDegree(0.7, 0.7, 3840.0), 3840.0 * kPi / 180.0, 1e-9);  // ≈ 67.02
    EXPECT_NEAR(FlipOptions{}.pixels_per_degree, 67.0206, 1e-4);
    EXPECT_NEAR(FlipOptions::monitor(0.7, 0.7, 3840.0).pixels_per_degree, FlipOptions{}.pixels_per_degree, 1e-9);
    EXPECT_NEAR(pixelsPerDegree(1.4, 0.7, 3840.0), 2.0 * FlipOptions{}.pixels_per_degree, 1e-9);
    EXPECT_NEAR(pixelsPerDegreeAtCentre(1000, glm::vec4(-1, 1, 1, -1)), 500.0 * kPi / 180.0, 1e-9);
    EXPECT_THROW(pixelsPerDegree(0.0, 0.7, 3840.0), std::invalid_argument);
    EXPECT_THROW(pixelsPerDegreeAtCentre(0, glm::vec4(-1, 1, 1, -1)), std::invalid_argument);
    cv::Mat a = uniform(4, 4, {0.5f, 0.5f, 0.5f});
    EXPECT_THROW(flip(a, a, FlipOptions{0.0}), std::invalid_argument);
    EXPECT_THROW(flip(a, a, FlipOptions{std::nan("")}), std::invalid_argument);
}

TEST(EvalFlip, IdenticalImagesAreZeroEverywhere) {
    cv::Mat a = texture(96, 80, 21);
    FlipResult r = flip(a, a.clone());
    ASSERT_EQ(r.map.type(), CV_32FC1);
    ASSERT_EQ(r.map.size(), a.size());
    EXPECT_EQ(r.mean, 0.0);
    EXPECT_EQ(cv::norm(r.map, cv::NORM_INF), 0.0);
}

TEST(EvalFlip, UniformGreysMatchTheHandComputedColourTerm) {
    // Greys: a* = b* = 0, HyAB = |ΔL*|, in the lower (linear) part of the remapping.
    double expected = uniformFlipByHand({0.5, 0.5, 0.5}, {0.6, 0.6, 0.6});
    EXPECT_NEAR(expected, 0.285, 1e-3);  // |ΔL*| ≈ 9.84, 9.84^0.7 ≈ 4.95, · 0.95 / (0.4·c_max)
    expectUniformMap(flip(uniform(48, 40, {0.5f, 0.5f, 0.5f}), uniform(48, 40, {0.6f, 0.6f, 0.6f})), expected, 1e-5);
}

TEST(EvalFlip, UniformColoursMatchTheHandComputedColourTerm) {
    // Red against green: Hunt-adjusted chroma and L* both count, upper part of the remapping.
    double rg = uniformFlipByHand({1, 0, 0}, {0, 1, 0});
    EXPECT_GT(rg, 0.95);
    expectUniformMap(flip(uniform(40, 40, {1, 0, 0}), uniform(40, 40, {0, 1, 0})), rg, 1e-5);
    double mixed = uniformFlipByHand({0.8, 0.4, 0.2}, {0.7, 0.45, 0.3});
    expectUniformMap(flip(uniform(40, 40, {0.8f, 0.4f, 0.2f}), uniform(40, 40, {0.7f, 0.45f, 0.3f})), mixed, 1e-5);
    // Green against blue is the normalising maximum: exactly 1.
    expectUniformMap(flip(uniform(32, 32, {0, 1, 0}), uniform(32, 32, {0, 0, 1})), 1.0, 1e-5);
}

// Grey luminance profiles along x (no chroma): the CSF blurs Y, the detectors see the profile's slope
// and curvature. Checked at one pixel against the paper's kernels summed in full.
struct GreyCase {
    const char* name;
    double (*lum)(int x);  // linear luminance y/y_n of column x
    double test_lum;       // the uniform test image
};

double greyFlipByHand(const GreyCase& c, int x0, double ppd) {
    Kernel2D csf_a = csfKernel(1.0, 0.0047, 0.0, 1e-5, ppd);
    auto Y = [&](int x) { return 116.0 * c.lum(x) - 16.0; };
    double y_f = respond(csf_a, x0, Y).first;  // filtered Y; Cx = Cz = 0 for greys
    double L_ref = 116.0 * labF((y_f + 16.0) / 116.0) - 16.0;
    double L_test = 116.0 * labF(c.test_lum) - 16.0;
    double dc = colourTermByHand(std::abs(L_ref - L_test));
    auto [ex, ey] = respond(featureKernel(false, ppd), x0, c.lum);
    auto [px, py] = respond(featureKernel(true, ppd), x0, c.lum);
    double df = std::max(std::hypot(ex, ey), std::hypot(px, py));  // the uniform test has no features
    df = std::pow(df / std::sqrt(2.0), 0.5);
    return std::pow(dc, 1.0 - df);
}

cv::Mat greyImage(const GreyCase& c, int w, int h) {
    cv::Mat m(h, w, CV_32FC3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) m.at<cv::Vec3f>(y, x) = cv::Vec3f::all(float(srgb(c.lum(x))));
    return m;
}

TEST(EvalFlip, EdgeAndPointFeaturesMatchThePaperKernelsAtOnePixel) {
    const GreyCase cases[] = {
        // Ramp: an edge response (slope × first moment of the edge detector), no point response.
        {"ramp", [](int x) { return 0.1 + 0.01 * x; }, 0.5},
        // Parabola, read at its vertex: a point response and no edge response; the test image is
        // the vertex value, so the colour difference is only the CSF's blur of the curvature.
        {"parabola", [](int x) { return 0.2 + 0.5 / 1024.0 * (x - 32) * (x - 32); }, 0.2},
    };
    for (double ppd : {FlipOptions{}.pixels_per_degree, 40.0}) {
        for (const GreyCase& c : cases) {
            cv::Mat ref = greyImage(c, 65, 9);
            cv::Mat test = uniform(65, 9, cv::Vec3f::all(float(srgb(c.test_lum))));
            double expected = greyFlipByHand(c, 32, ppd);
            double got = flip(ref, test, FlipOptions{ppd}).map.at<float>(4, 32);
            EXPECT_NEAR(got / expected, 1.0, 1e-4) << c.name << " at " << ppd << " ppd: " << got << " vs " << expected;
            EXPECT_NEAR(flip(test, ref, FlipOptions{ppd}).map.at<float>(4, 32), got, 1e-6);
        }
    }
}

TEST(EvalFlip, ChromaticCsfsMatchThePaperKernelsAtOnePixel) {
    // Constant Y, a parabola in Cx (or Cz) read at its vertex against uniform grey of the same Y:
    // the difference there is only the red-green (blue-yellow) CSF's blur of the curvature.
    const double ppd = FlipOptions{}.pixels_per_degree;
    const double Y0 = 116.0 * 0.3 - 16.0, q = 30.0 / 1024.0;
    auto chroma = [&](int x) { return q * (x - 32) * (x - 32); };
    struct {
        const char* name;
        bool cz;
        Kernel2D csf;
    } cases[] = {{"red-green", false, csfKernel(1.0, 0.0053, 0.0, 1e-5, ppd)},
                 {"blue-yellow", true, csfKernel(34.1, 0.04, 13.5, 0.025, ppd)}};
    for (auto& c : cases) {
        cv::Mat ref(9, 65, CV_32FC3);
        for (int y = 0; y < 9; ++y)
            for (int x = 0; x < 65; ++x)
                ref.at<cv::Vec3f>(y, x) = srgbOfYCxCz(Y0, c.cz ? 0.0 : chroma(x), c.cz ? chroma(x) : 0.0);
        cv::Mat test = uniform(65, 9, cv::Vec3f::all(float(srgb(0.3))));
        double filtered = respond(c.csf, 32, chroma).first;
        cv::Vec3d n(0.3 + (c.cz ? 0.0 : filtered / 500.0), 0.3, 0.3 - (c.cz ? filtered / 200.0 : 0.0));
        double expected = colourTermByHand(hyabByHand(huntLabOfNormalisedXyz(n), huntLabByHand({0.3, 0.3, 0.3})));
        double got = flip(ref, test).map.at<float>(4, 32);
        EXPECT_NEAR(got / expected, 1.0, 2e-3) << c.name << ": " << got << " vs " << expected;
    }
}

TEST(EvalFlip, BlackAgainstWhiteIsNearOne) {
    FlipResult r = flip(uniform(64, 64, {0, 0, 0}), uniform(64, 64, {1, 1, 1}));
    EXPECT_GT(r.mean, 0.9);
    expectUniformMap(r, uniformFlipByHand({0, 0, 0}, {1, 1, 1}), 1e-5);
    // A black/white checkerboard against its inverse: every pixel maximally different; the same edges.
    cv::Mat c(128, 128, CV_32FC3), inv;
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) c.at<cv::Vec3f>(y, x) = cv::Vec3f::all(((x / 32 + y / 32) % 2) ? 1.0f : 0.0f);
    cv::subtract(cv::Scalar::all(1.0), c, inv);
    EXPECT_GT(flip(c, inv).mean, 0.9);
}

// Coarse viewing: at 0.5 pixels per degree no edge or point can be resolved; the error is finite
// and reduces to the colour term (checked against a fine viewing of uniform images, where the
// features vanish as well).
TEST(EvalFlip, CoarseViewingStaysFinite) {
    cv::Mat a(48, 64, CV_32FC3, cv::Scalar(0.2, 0.4, 0.6)), b = a.clone();
    cv::randu(b, cv::Scalar::all(0.0), cv::Scalar::all(1.0));
    for (double ppd : {0.02, 0.3, 0.5, 0.65, 1.0}) {
        const FlipResult r = flip(a, b, FlipOptions{ppd});
        EXPECT_TRUE(std::isfinite(r.mean)) << ppd;
        EXPECT_GT(r.mean, 0.0) << ppd;
        EXPECT_LE(r.mean, 1.0) << ppd;
    }
    const cv::Mat grey(16, 16, CV_32FC3, cv::Scalar::all(0.5)), white(16, 16, CV_32FC3, cv::Scalar::all(1.0));
    EXPECT_NEAR(flip(grey, white, FlipOptions{0.5}).mean, flip(grey, white, FlipOptions{67.0}).mean, 1e-6);
}

TEST(EvalFlip, IsSymmetric) {
    cv::Mat a = texture(80, 64, 22);
    cv::Mat b = clamp01(a + 0.1 * gaussianNoise(80, 64, 23));
    FlipResult ab = flip(a, b), ba = flip(b, a);
    EXPECT_NEAR(ab.mean, ba.mean, 1e-9);
    EXPECT_LE(cv::norm(ab.map, ba.map, cv::NORM_INF), 1e-6);
}

TEST(EvalFlip, GrowsWithTheErrorAndStaysInRange) {
    cv::Mat a = texture(96, 96, 24);
    cv::Mat n = gaussianNoise(96, 96, 25);
    double prev = 0.0;
    for (double k : {0.003, 0.01, 0.03, 0.1, 0.3}) {
        FlipResult r = flip(a, clamp01(a + k * n));
        EXPECT_GT(r.mean, prev) << "noise sigma " << k;
        double lo, hi;
        cv::minMaxLoc(r.map, &lo, &hi);
        EXPECT_GE(lo, 0.0);
        EXPECT_LE(hi, 1.0);
        prev = r.mean;
    }
}

TEST(EvalFlip, SmallNoiseIsSmallLargeNoiseIsLarge) {
    cv::Mat a = texture(96, 96, 26);
    cv::Mat n = gaussianNoise(96, 96, 27);
    double small = flip(a, clamp01(a + 0.003 * n)).mean;
    double large = flip(a, clamp01(a + 0.3 * n)).mean;
    EXPECT_LT(small, 0.05);
    EXPECT_GT(large, 0.3);
}

TEST(EvalFlip, ErrorStaysNearTheDifference) {
    // Vertical step edges at x = 40 and x = 43: beyond the largest filter radius (10 px at 67 ppd)
    // from both edges the images agree and have no features, so FLIP is exactly 0 there.
    cv::Mat a = uniform(96, 32, {0.2f, 0.2f, 0.2f}), b = a.clone();
    a(cv::Rect(40, 0, 56, 32)).setTo(cv::Scalar::all(0.8));
    b(cv::Rect(43, 0, 53, 32)).setTo(cv::Scalar::all(0.8));
    FlipResult r = flip(a, b);
    for (int x = 0; x < 96; ++x) {
        float v = r.map.at<float>(16, x);
        if (x < 40 - 11 || x > 43 + 11) {
            EXPECT_EQ(v, 0.0f) << "x " << x;
        }
        if (x >= 40 && x < 43) {
            EXPECT_GT(v, 0.5f) << "x " << x;
        }
    }
}

TEST(EvalFlip, FinerViewingHidesFineDetail) {
    // A one-pixel checkerboard against flat grey: seen at 67 ppd the eye blurs it away; at 10 ppd not.
    cv::Mat c(64, 64, CV_32FC3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) c.at<cv::Vec3f>(y, x) = cv::Vec3f::all(((x + y) % 2) ? 0.8f : 0.2f);
    cv::Mat grey = uniform(64, 64, {0.55f, 0.55f, 0.55f});
    double fine = flip(c, grey).mean;
    double coarse = flip(c, grey, FlipOptions{10.0}).mean;
    EXPECT_LT(fine + 0.1, coarse);
}

TEST(EvalFlip, HostImageMatchesMat) {
    HostImage a = HostImage::make(layers::Format::RGBA8_SRGB, 24, 24);
    HostImage b = a;
    for (uint32_t y = 0; y < 24; ++y)
        for (uint32_t x = 0; x < 24; ++x) {
            a.store(x, y, glm::vec4(float(x) / 23.0f, float(y) / 23.0f, 0.5f, 1.0f));
            b.store(x, y, glm::vec4(float(x) / 23.0f, 0.5f, float(y) / 23.0f, 1.0f));
        }
    FlipResult h = flip(a, b);
    FlipResult m = flip(toMat(a), toMat(b));
    EXPECT_EQ(h.mean, m.mean);
    EXPECT_GT(h.mean, 0.0);
}

}  // namespace
}  // namespace wrsfov::eval
