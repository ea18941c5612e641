// PSNR, SSIM, eccentricity maps, near-gaze PSNR, eccentricity-weighted MSE, temporal instability,
// HostImage conversion, input checks and the error-map PNGs, against hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>

#include "eval/metrics.h"
#include "shaders/wrs_common.h"

namespace wrsfov::eval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

cv::Mat uniform(int w, int h, cv::Vec3f c) { return cv::Mat(h, w, CV_32FC3, cv::Scalar(c[0], c[1], c[2])); }

// Uniform random values in [lo, hi), fixed seed.
cv::Mat randomImage(int w, int h, uint64_t seed, float lo = 0.0f, float hi = 1.0f) {
    cv::Mat m(h, w, CV_32FC3);
    cv::RNG rng(seed);
    rng.fill(m, cv::RNG::UNIFORM, lo, hi);
    return m;
}

const glm::vec4 kFov90(-1.0f, 1.0f, 1.0f, -1.0f);  // ±45° both ways
const glm::vec3 kAhead(0.0f, 0.0f, -1.0f);

// Watson 2014 density written out from the paper's formula, independent of the shader header.
double watson(double e) {
    const double a = 0.9851, r2 = 1.058, re = 22.14, dc0 = 14804.6, rm = 41.03;
    double q = 1.0 + e / r2;
    return 2.0 * dc0 / (1.0 + e / rm) * (a / (q * q) + (1.0 - a) * std::exp(-e / re));
}

template <typename F>
std::string thrownMessage(F&& f) {
    try {
        f();
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(nothing thrown)";
}

// ---------------------------------------------------------------------------------------------
// Conversion
// ---------------------------------------------------------------------------------------------

TEST(EvalConvert, Rgba8IsCodeOver255InRgbOrder) {
    HostImage h = HostImage::make(layers::Format::RGBA8_SRGB, 2, 1);
    h.store(0, 0, glm::vec4(1.0f, 0.0f, 51.0f / 255.0f, 1.0f));
    h.store(1, 0, glm::vec4(0.0f, 128.0f / 255.0f, 0.0f, 0.0f));
    cv::Mat m = toMat(h);
    ASSERT_EQ(m.type(), CV_32FC3);
    ASSERT_EQ(m.size(), cv::Size(2, 1));
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 0)[0], 1.0f);
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 0)[1], 0.0f);
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 0)[2], 0.2f);
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 1)[1], 128.0f / 255.0f);
}

TEST(EvalConvert, EveryRgba8CodeIsWhatFetchGives) {
    // toMat reads 8-bit texels through a table; HostImage::fetch is the definition it must equal.
    for (layers::Format f : {layers::Format::RGBA8, layers::Format::RGBA8_SRGB}) {
        HostImage h = HostImage::make(f, 256, 3);
        for (uint32_t i = 0; i < h.data.size(); ++i) h.data[i] = std::byte(uint8_t(i * 7 + i / 256));
        cv::Mat m = toMat(h);
        for (uint32_t y = 0; y < 3; ++y)
            for (uint32_t x = 0; x < 256; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(m.at<cv::Vec3f>(int(y), int(x))[c], h.fetch(x, y)[c]) << x << "," << y << "," << c;
    }
}

TEST(EvalConvert, Rgba16fIsLinearAndGetsSrgbEncoded) {
    HostImage h = HostImage::make(layers::Format::RGBA16F, 1, 1);
    h.store(0, 0, glm::vec4(0.5f, 0.0f, 1.0f, 1.0f));
    cv::Mat m = toMat(h);
    // sRGB encoding of 0.5: 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357
    EXPECT_NEAR(m.at<cv::Vec3f>(0, 0)[0], 0.735357, 1e-5);
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 0)[1], 0.0f);
    EXPECT_FLOAT_EQ(m.at<cv::Vec3f>(0, 0)[2], 1.0f);
}

TEST(EvalConvert, RejectsNonColourFormatsAndBadBuffers) {
    HostImage depth = HostImage::make(layers::Format::D32F, 4, 4);
    EXPECT_NE(thrownMessage([&] { toMat(depth); }).find("not a colour format"), std::string::npos);
    HostImage cut = HostImage::make(layers::Format::RGBA8, 4, 4);
    cut.data.resize(10);
    EXPECT_NE(thrownMessage([&] { toMat(cut); }).find("bytes"), std::string::npos);
    HostImage empty;
    EXPECT_THROW(toMat(empty), std::invalid_argument);
}

TEST(EvalConvert, NonFiniteHalfTexelIsRejectedByTheMetrics) {
    HostImage a = HostImage::make(layers::Format::RGBA16F, 3, 2);
    HostImage b = a;
    b.store(2, 1, glm::vec4(std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f, 1.0f));
    std::string msg = thrownMessage([&] { psnr(a, b); });
    EXPECT_NE(msg.find("test image has a non-finite value at pixel (2, 1)"), std::string::npos) << msg;
}

// ---------------------------------------------------------------------------------------------
// PSNR, SSIM, input rules
// ---------------------------------------------------------------------------------------------

TEST(EvalPsnr, IdenticalImagesAreInfinite) {
    cv::Mat a = randomImage(37, 23, 1);
    EXPECT_EQ(psnr(a, a.clone()), kInf);
    EXPECT_EQ(meanSquaredError(a, a), 0.0);
    HostImage h = HostImage::make(layers::Format::RGBA8, 5, 5);
    h.store(1, 1, glm::vec4(0.3f, 0.6f, 0.9f, 1.0f));
    EXPECT_EQ(psnr(h, h), kInf);
}

TEST(EvalPsnr, UniformOffsetOfOneTenthIs20dB) {
    cv::Mat a = randomImage(64, 48, 2, 0.0f, 0.9f);
    cv::Mat up = a + cv::Scalar::all(0.1);
    EXPECT_NEAR(psnr(a, up), 20.0, 1e-4);
    EXPECT_NEAR(psnr(up, a), 20.0, 1e-4);
    // 0.125 is exact in binary: MSE = 1/64, PSNR = 10·log10(64).
    cv::Mat b = uniform(16, 16, {0.25f, 0.5f, 0.75f});
    cv::Mat c = uniform(16, 16, {0.375f, 0.375f, 0.875f});
    EXPECT_NEAR(psnr(b, c), 10.0 * std::log10(64.0), 1e-9);
}

TEST(EvalPsnr, SinglePixelSingleChannel) {
    cv::Mat a = uniform(10, 10, {0.0f, 0.0f, 0.0f});
    cv::Mat b = a.clone();
    b.at<cv::Vec3f>(4, 7)[2] = 1.0f;  // MSE = 1 / 300
    EXPECT_NEAR(meanSquaredError(a, b), 1.0 / 300.0, 1e-12);
    EXPECT_NEAR(psnr(a, b), 10.0 * std::log10(300.0), 1e-9);
    cv::Mat map = squaredErrorMap(a, b);
    EXPECT_NEAR(map.at<float>(4, 7), 1.0 / 3.0, 1e-7);
    EXPECT_EQ(cv::countNonZero(map), 1);
}

TEST(EvalPsnr, HostImageMatchesMat) {
    HostImage a = HostImage::make(layers::Format::RGBA8_SRGB, 8, 8);
    HostImage b = a;
    for (uint32_t y = 0; y < 8; ++y)
        for (uint32_t x = 0; x < 8; ++x) b.store(x, y, glm::vec4(51.0f / 255.0f, 0.0f, 0.0f, 1.0f));
    // One channel off by 0.2 everywhere: MSE = 0.04 / 3.
    EXPECT_NEAR(psnr(a, b), 10.0 * std::log10(3.0 / 0.04), 1e-5);
    EXPECT_NEAR(psnr(a, b), psnr(toMat(a), toMat(b)), 1e-12);
}

TEST(EvalInput, MismatchesAndBadValuesThrowWithMessages) {
    cv::Mat a = randomImage(8, 8, 3);
    cv::Mat small = randomImage(8, 7, 3);
    EXPECT_NE(thrownMessage([&] { psnr(a, small); }).find("sizes differ"), std::string::npos);
    cv::Mat u8(8, 8, CV_8UC3, cv::Scalar::all(0));
    EXPECT_NE(thrownMessage([&] { ssim(a, u8); }).find("CV_32FC3"), std::string::npos);
    EXPECT_THROW(flip(cv::Mat(), a), std::invalid_argument);
    cv::Mat bad = a.clone();
    bad.at<cv::Vec3f>(5, 3)[1] = std::numeric_limits<float>::quiet_NaN();
    EXPECT_NE(thrownMessage([&] { meanSquaredError(a, bad); }).find("at pixel (3, 5)"), std::string::npos);
    bad.at<cv::Vec3f>(5, 3)[1] = std::numeric_limits<float>::infinity();
    EXPECT_THROW(flip(bad, a), std::invalid_argument);
}

TEST(EvalInput, OutOfRangeValuesAreClamped) {
    cv::Mat a = uniform(6, 6, {1.0f, 0.0f, 0.5f});
    cv::Mat b = uniform(6, 6, {1.5f, -0.25f, 0.5f});
    EXPECT_EQ(psnr(a, b), kInf);
    EXPECT_EQ(flip(a, b).mean, 0.0);
}

TEST(EvalSsim, IdenticalIsOneAndNoiseLowersIt) {
    cv::Mat a;
    cv::GaussianBlur(randomImage(64, 64, 4), a, cv::Size(0, 0), 2.0);
    EXPECT_NEAR(ssim(a, a.clone()), 1.0, 1e-6);
    cv::Mat n(64, 64, CV_32FC3);
    cv::RNG(5).fill(n, cv::RNG::NORMAL, 0.0, 1.0);
    double s_small = ssim(a, a + 0.01 * n);
    double s_large = ssim(a, a + 0.1 * n);
    EXPECT_LT(s_small, 1.0);
    EXPECT_GT(s_small, s_large);
    EXPECT_GT(s_large, -1.0);
    HostImage h = HostImage::make(layers::Format::RGBA8, 16, 16);
    EXPECT_NEAR(ssim(h, h), 1.0, 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Eccentricity
// ---------------------------------------------------------------------------------------------

TEST(EvalEccentricity, CornerAndCentreOfASymmetricView) {
    cv::Mat e = eccentricityMap(64, 64, kFov90, kAhead);
    ASSERT_EQ(e.type(), CV_32FC1);
    ASSERT_EQ(e.size(), cv::Size(64, 64));
    // Pixel (0, 0): ray (-63/64, 63/64, -1), angle atan(sqrt(2)·63/64).
    double corner = std::atan(std::sqrt(2.0) * 63.0 / 64.0) * 180.0 / kPi;
    EXPECT_NEAR(e.at<float>(0, 0), corner, 1e-3);
    EXPECT_NEAR(e.at<float>(63, 63), corner, 1e-3);
    double centre = std::atan(std::sqrt(2.0) * 0.5 / 32.0) * 180.0 / kPi;
    EXPECT_NEAR(e.at<float>(31, 32), centre, 1e-4);
    // The gaze need not be normalised; EyeParams gives the same map.
    gpu::EyeParams eye{};
    eye.fov_tan = kFov90;
    eye.gaze = glm::vec4(0.0f, 0.0f, -3.0f, 5.0f);
    cv::Mat e2 = eccentricityMap(64, 64, eye);
    EXPECT_EQ(cv::norm(e, e2, cv::NORM_INF), 0.0);
}

TEST(EvalEccentricity, FollowsTheGaze) {
    // Gaze through the centre of pixel (48, 16): tan x = -1 + 2·48.5/64, tan y = 1 - 2·16.5/64.
    glm::vec3 g(-1.0f + 2.0f * 48.5f / 64.0f, 1.0f - 2.0f * 16.5f / 64.0f, -1.0f);
    cv::Mat e = eccentricityMap(64, 64, kFov90, g);
    EXPECT_LT(e.at<float>(16, 48), 1e-3);
    cv::Point minLoc;
    cv::minMaxLoc(e, nullptr, nullptr, &minLoc);
    EXPECT_EQ(minLoc, cv::Point(48, 16));
}

TEST(EvalEccentricity, RejectsBadViews) {
    EXPECT_THROW(eccentricityMap(0, 4, kFov90, kAhead), std::invalid_argument);
    EXPECT_THROW(eccentricityMap(4, 4, kFov90, glm::vec3(0.0f)), std::invalid_argument);
    EXPECT_THROW(eccentricityMap(4, 4, glm::vec4(1.0f, -1.0f, 1.0f, -1.0f), kAhead), std::invalid_argument);
    EXPECT_THROW(eccentricityMap(4, 4, kFov90, glm::vec3(std::nanf(""), 0.0f, -1.0f)), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Near-gaze PSNR
// ---------------------------------------------------------------------------------------------

TEST(EvalNearGaze, ErrorOutsideTenDegreesIsNotCounted) {
    cv::Mat ecc = eccentricityMap(64, 64, kFov90, kAhead);
    cv::Mat ref = randomImage(64, 64, 6, 0.2f, 0.8f);
    cv::Mat test = ref.clone();
    int outside = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            if (ecc.at<float>(y, x) > 10.0f) {
                test.at<cv::Vec3f>(y, x) += cv::Vec3f(0.2f, -0.2f, 0.1f);
                ++outside;
            }
    ASSERT_GT(outside, 3000);
    EXPECT_EQ(nearGazePsnr(ref, test, ecc), kInf);
    EXPECT_LT(psnr(ref, test), 30.0);
    // A wider region takes the errors in.
    EXPECT_LT(nearGazePsnr(ref, test, ecc, 30.0), 40.0);
}

TEST(EvalNearGaze, ErrorInsideGivesTheKnownValue) {
    cv::Mat ecc = eccentricityMap(64, 64, kFov90, kAhead);
    cv::Mat ref = uniform(64, 64, {0.5f, 0.5f, 0.5f});
    cv::Mat test = ref.clone();
    int inside = 0, hit = 0;
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x) {
            float e = ecc.at<float>(y, x);
            if (e <= 10.0f) ++inside;
            if (e <= 5.0f) {
                test.at<cv::Vec3f>(y, x) = cv::Vec3f(0.75f, 0.75f, 0.75f);  // squared error 1/16
                ++hit;
            } else if (e > 10.0f) {
                test.at<cv::Vec3f>(y, x) = cv::Vec3f(0.0f, 1.0f, 0.0f);  // large, but outside
            }
        }
    ASSERT_GT(hit, 0);
    ASSERT_GT(inside, hit);
    double expected = 10.0 * std::log10(16.0 * inside / hit);
    EXPECT_NEAR(nearGazePsnr(ref, test, ecc), expected, 1e-9);
    HostImage hr = HostImage::make(layers::Format::RGBA8, 64, 64);
    EXPECT_EQ(nearGazePsnr(hr, hr, ecc), kInf);
}

TEST(EvalNearGaze, NoPixelWithinTheRadiusIsNaN) {
    cv::Mat ecc = eccentricityMap(16, 16, kFov90, glm::vec3(0.0f, 0.0f, 1.0f));  // looking backwards
    cv::Mat a = randomImage(16, 16, 7);
    EXPECT_TRUE(std::isnan(nearGazePsnr(a, a, ecc)));
    EXPECT_THROW(nearGazePsnr(a, a, cv::Mat(15, 16, CV_32F, cv::Scalar(0))), std::invalid_argument);
    cv::Mat bad = ecc.clone();
    bad.at<float>(2, 2) = std::nanf("");
    EXPECT_THROW(nearGazePsnr(a, a, bad), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// Eccentricity-weighted MSE
// ---------------------------------------------------------------------------------------------

TEST(EvalWeightedMse, WeightsAreWatsonNormalisedAtTheFovea) {
    cv::Mat ecc(1, 4, CV_32F);
    ecc.at<float>(0) = 0.0f;
    ecc.at<float>(1) = 2.5f;
    ecc.at<float>(2) = 10.0f;
    ecc.at<float>(3) = 40.0f;
    cv::Mat w = eccentricityWeights(ecc);
    EXPECT_FLOAT_EQ(w.at<float>(0), 1.0f);
    EXPECT_FLOAT_EQ(w.at<float>(1), 1.0f);
    EXPECT_NEAR(w.at<float>(2), watson(10.0) / watson(2.5), 1e-5);
    EXPECT_NEAR(w.at<float>(3), watson(40.0) / watson(2.5), 1e-6);
    EXPECT_LT(w.at<float>(3), 0.05f);
    EXPECT_THROW(eccentricityWeights(ecc, 0.0), std::invalid_argument);
}

TEST(EvalWeightedMse, UniformErrorEqualsThePlainMse) {
    cv::Mat ecc = eccentricityMap(48, 32, kFov90, kAhead);
    cv::Mat a = randomImage(48, 32, 8, 0.0f, 0.8f);
    cv::Mat b = a + cv::Scalar(0.2, 0.1, 0.0);
    double mse = (0.04 + 0.01) / 3.0;
    EXPECT_NEAR(eccentricityWeightedMse(a, b, ecc), mse, 1e-7);
    EXPECT_NEAR(meanSquaredError(a, b), mse, 1e-7);
    EXPECT_EQ(eccentricityWeightedMse(a, a, ecc), 0.0);
}

TEST(EvalWeightedMse, SinglePixelErrorIsWeightedByItsEccentricity) {
    cv::Mat ecc = eccentricityMap(64, 64, kFov90, kAhead);
    cv::Mat w = eccentricityWeights(ecc);
    double sum_w = 0.0;
    for (int i = 0; i < 64 * 64; ++i) sum_w += w.at<float>(i);
    cv::Mat ref = uniform(64, 64, {0.0f, 0.0f, 0.0f});
    auto withErrorAt = [&](int x, int y) {
        cv::Mat t = ref.clone();
        t.at<cv::Vec3f>(y, x) = cv::Vec3f(0.5f, 0.5f, 0.5f);  // squared error 0.25
        return t;
    };
    cv::Mat t_centre = withErrorAt(32, 32), t_corner = withErrorAt(0, 0);
    double centre = eccentricityWeightedMse(ref, t_centre, ecc);
    double corner = eccentricityWeightedMse(ref, t_corner, ecc);
    EXPECT_NEAR(centre, 0.25 / sum_w, 1e-9);
    double e_corner = std::atan(std::sqrt(2.0) * 63.0 / 64.0) * 180.0 / kPi;
    EXPECT_NEAR(corner, 0.25 * watson(e_corner) / watson(2.5) / sum_w, 1e-9);
    EXPECT_GT(centre, 20.0 * corner);
    // Plain MSE does not tell them apart.
    EXPECT_EQ(meanSquaredError(ref, t_centre), meanSquaredError(ref, t_corner));
}

TEST(EvalWeightedMse, PrecomputedWeightsGiveTheSameValueAndBadWeightsAreRefused) {
    cv::Mat ecc = eccentricityMap(40, 30, kFov90, kAhead);
    cv::Mat a = randomImage(40, 30, 3, 0.0f, 1.0f), b = randomImage(40, 30, 4, 0.0f, 1.0f);
    const cv::Mat w = eccentricityWeights(ecc);
    EXPECT_EQ(weightedMse(a, b, w), eccentricityWeightedMse(a, b, ecc));
    // Uniform weights: the plain MSE.
    EXPECT_NEAR(weightedMse(a, b, cv::Mat(30, 40, CV_32F, cv::Scalar(2.0))), meanSquaredError(a, b), 1e-12);
    EXPECT_NE(thrownMessage([&] { weightedMse(a, b, cv::Mat(30, 41, CV_32F, cv::Scalar(1.0))); }).find("weights must be"),
              std::string::npos);
    EXPECT_NE(thrownMessage([&] { weightedMse(a, b, cv::Mat(30, 40, CV_64F, cv::Scalar(1.0))); }).find("weights must be"),
              std::string::npos);
    cv::Mat bad = w.clone();
    bad.at<float>(7, 5) = std::numeric_limits<float>::infinity();
    EXPECT_NE(thrownMessage([&] { weightedMse(a, b, bad); }).find("weight at pixel (5, 7) is not finite"), std::string::npos);
    bad.at<float>(7, 5) = std::numeric_limits<float>::quiet_NaN();
    EXPECT_THROW(weightedMse(a, b, bad), std::invalid_argument);
    bad.at<float>(7, 5) = -0.5f;
    EXPECT_NE(thrownMessage([&] { weightedMse(a, b, bad); }).find("must not be negative"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Temporal instability
// ---------------------------------------------------------------------------------------------

TEST(EvalTemporal, StaticOutputIsZero) {
    TemporalInstability t;
    cv::Mat ref = randomImage(20, 10, 9);
    cv::Mat out = randomImage(20, 10, 10);
    EXPECT_TRUE(std::isnan(t.addFrame(ref, out)));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(t.addFrame(ref, out), 0.0);
    EXPECT_EQ(t.mean(), 0.0);
    EXPECT_EQ(t.frames(), 5u);
    EXPECT_EQ(t.stablePixels(), 4u * 200u);
}

TEST(EvalTemporal, FlickeringPixelGivesTheKnownValue) {
    TemporalInstability t;
    cv::Mat ref = uniform(4, 4, {0.3f, 0.3f, 0.3f});
    for (int f = 0; f < 6; ++f) {
        cv::Mat out = uniform(4, 4, {0.5f, 0.5f, 0.5f});
        float v = float(f % 2);
        out.at<cv::Vec3f>(2, 1) = cv::Vec3f(v, v, v);      // changes by 1 in every channel each frame
        out.at<cv::Vec3f>(0, 3)[1] = f % 2 ? 0.8f : 0.5f;  // changes by 0.3 in one channel
        double frame = t.addFrame(ref, out);
        if (f > 0) {
            EXPECT_NEAR(frame, (1.0 + 0.1) / 16.0, 1e-7);
        }
    }
    EXPECT_NEAR(t.mean(), 1.1 / 16.0, 1e-7);
    EXPECT_EQ(t.stablePixels(), 5u * 16u);
}

TEST(EvalTemporal, PixelsWhereTheReferenceChangesAreExcluded) {
    TemporalInstability t;
    for (int f = 0; f < 4; ++f) {
        float v = float(f % 2);
        cv::Mat ref = uniform(4, 4, {0.3f, 0.3f, 0.3f});
        ref.at<cv::Vec3f>(2, 1) = cv::Vec3f(v, 0.0f, 0.0f);
        // Within the threshold: still "not changing".
        ref.at<cv::Vec3f>(3, 3)[2] += f % 2 ? 0.5f / 255.0f : 0.0f;
        cv::Mat out = uniform(4, 4, {0.5f, 0.5f, 0.5f});
        out.at<cv::Vec3f>(2, 1) = cv::Vec3f(v, v, v);
        double frame = t.addFrame(ref, out);
        if (f > 0) {
            EXPECT_EQ(frame, 0.0);
        }
    }
    EXPECT_EQ(t.mean(), 0.0);
    EXPECT_EQ(t.stablePixels(), 3u * 15u);
}

TEST(EvalTemporal, NothingStableIsNaNAndBadFramesLeaveTheStateAlone) {
    TemporalInstability t;
    cv::Mat black = uniform(3, 3, {0.0f, 0.0f, 0.0f});
    cv::Mat white = uniform(3, 3, {1.0f, 1.0f, 1.0f});
    t.addFrame(black, black);
    EXPECT_TRUE(std::isnan(t.addFrame(white, white)));
    EXPECT_TRUE(std::isnan(t.mean()));
    EXPECT_THROW(t.addFrame(uniform(4, 3, {0, 0, 0}), uniform(4, 3, {0, 0, 0})), std::invalid_argument);
    EXPECT_THROW(t.addFrame(white, uniform(3, 4, {0, 0, 0})), std::invalid_argument);
    EXPECT_EQ(t.frames(), 2u);
    cv::Mat dim = uniform(3, 3, {0.9f, 1.0f, 1.0f});
    EXPECT_NEAR(t.addFrame(white, dim), 0.1 / 3.0, 1e-7);
    t.reset();
    EXPECT_EQ(t.frames(), 0u);
    EXPECT_TRUE(std::isnan(t.addFrame(uniform(4, 3, {0, 0, 0}), uniform(4, 3, {0, 0, 0}))));
    EXPECT_THROW(TemporalInstability(-1.0), std::invalid_argument);
}

TEST(EvalTemporal, HostImageFrames) {
    TemporalInstability t;
    HostImage ref = HostImage::make(layers::Format::RGBA8, 2, 2);
    HostImage out = ref;
    t.addFrame(ref, out);
    out.store(0, 0, glm::vec4(1.0f, 1.0f, 1.0f, 1.0f));
    EXPECT_NEAR(t.addFrame(ref, out), 0.25, 1e-7);
}

// ---------------------------------------------------------------------------------------------
// All metrics at once; error-map PNGs
// ---------------------------------------------------------------------------------------------

TEST(EvalFrame, EvaluateFrameMatchesTheSingleMetrics) {
    cv::Mat ecc = eccentricityMap(40, 30, kFov90, kAhead);
    cv::Mat a = randomImage(40, 30, 11);
    cv::Mat b = randomImage(40, 30, 12);
    FrameMetrics m = evaluateFrame(a, b, ecc);
    EXPECT_EQ(m.psnr, psnr(a, b));
    EXPECT_EQ(m.ssim, ssim(a, b));
    EXPECT_EQ(m.near_gaze_psnr, nearGazePsnr(a, b, ecc));
    EXPECT_EQ(m.ecc_weighted_mse, eccentricityWeightedMse(a, b, ecc));
    EXPECT_EQ(m.flip, flip(a, b).mean);
    EXPECT_EQ(m.flip_map.size(), a.size());
}

std::string tempPath(const std::string& name) {
    return (std::filesystem::path(testing::TempDir()) / ("wrsfov_eval_" + name)).string();
}

cv::Vec3b magma(int level) {
    cv::Mat one(1, 1, CV_8U, cv::Scalar(level)), c;
    cv::applyColorMap(one, c, cv::COLORMAP_MAGMA);
    return c.at<cv::Vec3b>(0, 0);
}

TEST(EvalPng, ErrorMapHasTheColourScaleAndALegend) {
    cv::Mat err(50, 60, CV_32F, cv::Scalar(0.0f));
    err.at<float>(10, 20) = 0.02f;
    err.at<float>(11, 20) = 0.015f;  // 0.75 of the maximum: level 191
    std::string path = tempPath("mse.png");
    Status s = writeErrorMapPng(err, path, ErrorMapStyle{0.0, cv::COLORMAP_MAGMA, "MSE"});
    ASSERT_TRUE(s.ok()) << s.message();
    cv::Mat png = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(png.empty());
    EXPECT_EQ(png.size(), cv::Size(60 + 84, 96));
    EXPECT_EQ(png.at<cv::Vec3b>(0, 0), magma(0));
    EXPECT_EQ(png.at<cv::Vec3b>(10, 20), magma(255));  // the maximum is the top of the scale
    EXPECT_EQ(png.at<cv::Vec3b>(11, 20), magma(191));
    // Legend bar: top colour near the top, bottom colour near the bottom.
    EXPECT_EQ(png.at<cv::Vec3b>(22, 60 + 8 + 7), magma(255));
    EXPECT_EQ(png.at<cv::Vec3b>(96 - 11, 60 + 8 + 7), magma(0));
    std::filesystem::remove(path);
}

TEST(EvalPng, FlipMapUsesTheFixedUnitScale) {
    cv::Mat f(120, 30, CV_32F, cv::Scalar(0.25f));
    std::string path = tempPath("flip.png");
    ASSERT_TRUE(writeFlipMapPng(f, path).ok());
    cv::Mat png = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_EQ(png.size(), cv::Size(30 + 84, 120));
    EXPECT_EQ(png.at<cv::Vec3b>(60, 15), magma(64));
    std::filesystem::remove(path);
}

TEST(EvalPng, BadInputAndPathsAreReported) {
    cv::Mat neg(4, 4, CV_32F, cv::Scalar(-1.0f));
    Status s = writeErrorMapPng(neg, tempPath("neg.png"));
    EXPECT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(EvalError::InvalidInput));
    cv::Mat nan(4, 4, CV_32F, cv::Scalar(std::nanf("")));
    EXPECT_EQ(writeFlipMapPng(nan, tempPath("nan.png")).error().code, int(EvalError::InvalidInput));
    EXPECT_FALSE(writeErrorMapPng(cv::Mat(), tempPath("empty.png")).ok());
    EXPECT_FALSE(writeErrorMapPng(cv::Mat(4, 4, CV_32FC3), tempPath("c3.png")).ok());
    Status w = writeErrorMapPng(cv::Mat(4, 4, CV_32F, cv::Scalar(0.1f)), "/nonexistent-dir/x/map.png");
    EXPECT_FALSE(w.ok());
    EXPECT_EQ(w.error().code, int(EvalError::WriteFailed));
    EXPECT_NE(w.message().find("/nonexistent-dir/x/map.png"), std::string::npos);
}

}  // namespace
}  // namespace wrsfov::eval
