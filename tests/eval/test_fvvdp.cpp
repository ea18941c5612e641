// FovVideoVDP (eval/fvvdp.h) on small synthetic videos: the properties the metric must have, and
// the input rules. Agreement with the reference implementation is measured apart (docs/metrics.md).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "eval/fvvdp.h"

namespace wrsfov::eval::fvvdp {
namespace {

constexpr int kSize = 128;
constexpr double kPi = 3.14159265358979323846;

// A textured frame: sine gratings of a few frequencies and smooth noise around mid grey, in [0.1, 0.9].
cv::Mat texture(int w = kSize, int h = kSize, uint64_t seed = 7) {
    cv::Mat noise(h, w, CV_32F);
    cv::RNG rng(seed);
    rng.fill(noise, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::GaussianBlur(noise, noise, cv::Size(0, 0), 1.5);
    cv::Mat img(h, w, CV_32FC3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float g = 0.5f + 0.12f * std::sin(0.35f * x) * std::cos(0.22f * y) + 0.1f * std::sin(0.9f * (x + y)) +
                            0.5f * noise.at<float>(y, x);
            const float v = std::clamp(g, 0.1f, 0.9f);
            img.at<cv::Vec3f>(y, x) = {v, 0.9f * v + 0.05f, 0.8f * v + 0.1f};
        }
    return img;
}

cv::Mat blurred(const cv::Mat& img, double sigma) {
    cv::Mat out;
    cv::GaussianBlur(img, out, cv::Size(0, 0), sigma, sigma, cv::BORDER_REFLECT);
    return out;
}

// `img` with the pixels within `radius` of `centre` taken from `other`.
cv::Mat disc(const cv::Mat& img, const cv::Mat& other, cv::Point2f centre, float radius) {
    cv::Mat mask = cv::Mat::zeros(img.size(), CV_8U);
    cv::circle(mask, cv::Point(int(centre.x), int(centre.y)), int(radius), cv::Scalar(255), cv::FILLED);
    cv::Mat out = img.clone();
    other.copyTo(out, mask);
    return out;
}

Options options(bool foveated, int w = kSize, int h = kSize, double fov_deg = 40.0) {
    Options o;
    o.geometry = ViewGeometry::symmetric(uint32_t(w), uint32_t(h), fov_deg);
    o.foveated = foveated;
    o.fps = 60.0;
    return o;
}

// JOD of `frames` frames of the same test and reference images, gaze at `gaze`.
double videoJod(const cv::Mat& test, const cv::Mat& ref, const Options& o, int frames = 3,
                glm::vec2 gaze = {kSize / 2, kSize / 2}) {
    auto m = Metric::create(o);
    EXPECT_TRUE(m.ok()) << m.error().message;
    for (int f = 0; f < frames; ++f) EXPECT_TRUE(m->push(test, ref, gaze).ok());
    auto j = m->jod();
    EXPECT_TRUE(j.ok());
    return j.value();
}

TEST(Fvvdp, IdenticalVideosScoreTen) {
    const cv::Mat a = texture(), b = texture(kSize, kSize, 11);
    for (bool fov : {false, true}) {
        auto m = Metric::create(options(fov));
        ASSERT_TRUE(m.ok()) << m.error().message;
        ASSERT_TRUE(m->push(a, a, {20.0f, 100.0f}).ok());
        EXPECT_DOUBLE_EQ(m->jod().value(), 10.0) << "image, foveated " << fov;
        // A changing video, the test equal to the reference in every frame.
        for (int f = 0; f < 6; ++f) ASSERT_TRUE(m->push(f % 2 ? a : b, f % 2 ? a : b, {64.0f, 64.0f}).ok());
        EXPECT_DOUBLE_EQ(m->jod().value(), 10.0) << "video, foveated " << fov;
    }
}

TEST(Fvvdp, JodFallsWithBlurStrength) {
    const cv::Mat ref = texture();
    for (bool fov : {false, true}) {
        double prev = 10.0;
        for (double sigma : {0.5, 1.0, 2.0, 4.0}) {
            const double jod = videoJod(blurred(ref, sigma), ref, options(fov));
            EXPECT_LT(jod, prev) << "sigma " << sigma << ", foveated " << fov;
            prev = jod;
        }
        EXPECT_LT(prev, 9.0) << "a strong blur is clearly visible";
    }
}

TEST(Fvvdp, JodFallsAsTheBlurredAreaNearsTheGaze) {
    // A 256-pixel view 16° wide (16 pixels per degree) with one blurred disc; the gaze moves away
    // from it (0° to 12°), so that only the eccentricity of the same error changes.
    const int w = 256, h = 128;
    const cv::Mat ref = texture(w, h), test = disc(ref, blurred(ref, 3.0), {200.0f, 64.0f}, 14.0f);
    double prev = 0.0;
    for (float gx : {200.0f, 168.0f, 136.0f, 104.0f, 72.0f, 40.0f, 8.0f}) {
        const double jod = videoJod(test, ref, options(true, w, h, 16.0), 3, {gx, 64.0f});
        EXPECT_GT(jod, prev) << "gaze at x = " << gx;
        prev = jod;
    }
}

TEST(Fvvdp, FlickerCostsMoreThanAStaticErrorOfTheSamePsnr) {
    // The same smooth error pattern, either added in every frame (static) or with its sign
    // alternating every 4 frames at 60 Hz (7.5 Hz flicker, constant mean). Every frame has the same
    // squared error in both, so the same PSNR.
    const cv::Mat ref = texture();
    cv::Mat pattern(ref.size(), CV_32F);
    cv::RNG rng(3);
    rng.fill(pattern, cv::RNG::UNIFORM, -1.0, 1.0);
    cv::GaussianBlur(pattern, pattern, cv::Size(0, 0), 2.0);
    cv::normalize(pattern, pattern, -0.04, 0.04, cv::NORM_MINMAX);
    cv::Mat p3;
    cv::merge(std::vector<cv::Mat>{pattern, pattern, pattern}, p3);
    const cv::Mat plus = ref + p3, minus = ref - p3;  // stays within [0.06, 0.94]: no clamping

    auto run = [&](bool flicker) {
        auto m = Metric::create(options(false));
        EXPECT_TRUE(m.ok());
        for (int f = 0; f < 24; ++f) EXPECT_TRUE(m->push(flicker && (f / 4) % 2 ? minus : plus, ref).ok());
        return m->jod().value();
    };
    const double still = run(false), flicker = run(true);
    EXPECT_LT(flicker, still - 0.1) << "static " << still << ", flicker " << flicker;
    EXPECT_LT(still, 10.0);
}

TEST(Fvvdp, FoveatedModePenalisesPeripheralBlurLess) {
    const int w = 256, h = 128;
    const cv::Mat ref = texture(w, h);
    // Blur everywhere but a 20-pixel disc around the gaze at the centre.
    const cv::Mat test = disc(blurred(ref, 2.0), ref, {128.0f, 64.0f}, 20.0f);
    const double fov = videoJod(test, ref, options(true, w, h, 60.0), 3, {128.0f, 64.0f});
    const double flat = videoJod(test, ref, options(false, w, h, 60.0), 3, {128.0f, 64.0f});
    EXPECT_GT(fov, flat + 0.2) << "foveated " << fov << ", non-foveated " << flat;
}

TEST(Fvvdp, NonFiniteInputIsAnErrorNotAScore) {
    const cv::Mat ref = texture();
    for (float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                      -std::numeric_limits<float>::infinity()}) {
        auto m = Metric::create(options(true));
        ASSERT_TRUE(m.ok());
        cv::Mat test = ref.clone();
        test.at<cv::Vec3f>(5, 9)[1] = bad;
        Status s = m->push(test, ref, {64.0f, 64.0f});
        ASSERT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, int(FvvdpError::NonFinite));
        EXPECT_NE(s.message().find("test image has a non-finite value at pixel (9, 5)"), std::string::npos)
            << s.message();
        s = m->push(ref, test, {64.0f, 64.0f});
        ASSERT_FALSE(s.ok());
        EXPECT_NE(s.message().find("reference"), std::string::npos) << s.message();
        // Nothing was added: no score yet, and a good frame after the bad ones scores as usual.
        EXPECT_EQ(m->frames(), 0u);
        EXPECT_EQ(m->jod().error().code, int(FvvdpError::NoFrames));
        ASSERT_TRUE(m->push(ref, ref, {64.0f, 64.0f}).ok());
        EXPECT_DOUBLE_EQ(m->jod().value(), 10.0);
    }
    auto m = Metric::create(options(true));
    Status s = m->push(ref, ref, {std::numeric_limits<float>::quiet_NaN(), 3.0f});
    EXPECT_EQ(s.error().code, int(FvvdpError::InvalidInput));
}

TEST(Fvvdp, WrongSizesAndTypesAreErrors) {
    auto m = Metric::create(options(true));
    ASSERT_TRUE(m.ok());
    const cv::Mat ref = texture();
    Status s = m->push(texture(kSize, kSize - 2), ref);
    ASSERT_FALSE(s.ok());
    EXPECT_EQ(s.error().code, int(FvvdpError::InvalidInput));
    EXPECT_NE(s.message().find("128x126"), std::string::npos) << s.message();
    cv::Mat u8;
    ref.convertTo(u8, CV_8UC3, 255.0);
    EXPECT_FALSE(m->push(u8, ref).ok());
    EXPECT_FALSE(m->push(cv::Mat(), ref).ok());
    EXPECT_EQ(m->frames(), 0u);

    Options o = options(true);
    o.geometry.width = 4;
    EXPECT_EQ(Metric::create(o).error().code, int(FvvdpError::InvalidOptions));
    o = options(true);
    o.fps = 0.0;
    EXPECT_FALSE(Metric::create(o).ok());
    o = options(true);
    o.geometry.fov_tan = {0.5f, -0.5f, 0.5f, -0.5f};
    EXPECT_FALSE(Metric::create(o).ok());
    o = options(true);
    o.photometry.contrast = 0.5;
    EXPECT_FALSE(Metric::create(o).ok());

    // score(): frame counts must match.
    EXPECT_FALSE(score({ref, ref}, {ref}, {}, options(true)).ok());
}

TEST(Fvvdp, StreamingKeepsOnlyTheFilterWindow) {
    Options o = options(false);
    o.fps = 90.0;
    auto m = Metric::create(o);
    ASSERT_TRUE(m.ok());
    EXPECT_EQ(m->filterLength(), 23);  // ceil(90 / 4): 250 ms
    o.fps = 60.0;
    EXPECT_EQ(Metric::create(o)->filterLength(), 15);
    // Frame by frame equals the whole video at once, and reset() starts a new video.
    const cv::Mat ref = texture(), test = blurred(ref, 1.0);
    std::vector<cv::Mat> t{test, ref, test, test}, r{ref, ref, ref, ref};
    const double whole = score(t, r, {}, o).value();
    auto s = Metric::create(o);
    for (int f = 0; f < 4; ++f) ASSERT_TRUE(s->push(ref, ref).ok());
    s->reset();
    for (int f = 0; f < 4; ++f) ASSERT_TRUE(s->push(t[size_t(f)], r[size_t(f)], {kSize / 2, kSize / 2}).ok());
    EXPECT_DOUBLE_EQ(s->jod().value(), whole);
}

TEST(Fvvdp, DistortionMapShowsWhereTheErrorIs) {
    const int w = 256, h = 128;
    const cv::Mat ref = texture(w, h), test = disc(ref, blurred(ref, 3.0), {200.0f, 64.0f}, 16.0f);
    Options o = options(true, w, h, 16.0);
    auto plain = Metric::create(o);
    ASSERT_TRUE(plain->push(test, ref).ok());
    EXPECT_TRUE(plain->distortionMap().empty());
    o.distortion_map = true;
    auto m = Metric::create(o);
    ASSERT_TRUE(m->push(ref, ref, {200.0f, 64.0f}).ok());
    ASSERT_EQ(m->distortionMap().size(), cv::Size(w, h));
    EXPECT_EQ(cv::countNonZero(m->distortionMap()), 0);
    ASSERT_TRUE(m->push(test, ref, {200.0f, 64.0f}).ok());
    const cv::Mat& d = m->distortionMap();
    EXPECT_TRUE(cv::checkRange(d, true, nullptr, 0.0, 100.0));
    const double inside = cv::mean(d(cv::Rect(190, 54, 20, 20)))[0], outside = cv::mean(d(cv::Rect(20, 20, 60, 80)))[0];
    EXPECT_GT(inside, 0.05);
    EXPECT_GT(inside, 20.0 * outside) << "inside " << inside << ", outside " << outside;
}

TEST(Fvvdp, ViewAndFlatScreenGeometry) {
    using Model = ViewGeometry::Model;
    // On an axis both models give the true angle; off the axes the flat-screen norm of per-axis
    // angles is larger (45°, 45° from the axis: 63.6° against 54.7°).
    EXPECT_NEAR(detail::eccentricityDeg(Model::View, std::tan(0.5), 0.0, 0.0, 0.0), 0.5 * 180.0 / kPi, 1e-9);
    EXPECT_NEAR(detail::eccentricityDeg(Model::FlatScreen, 0.0, std::tan(0.5), 0.0, 0.0), 0.5 * 180.0 / kPi, 1e-9);
    EXPECT_NEAR(detail::eccentricityDeg(Model::View, 1.0, 1.0, 0.0, 0.0), 54.7356, 1e-3);
    EXPECT_NEAR(detail::eccentricityDeg(Model::FlatScreen, 1.0, 1.0, 0.0, 0.0), 63.6396, 1e-3);
    EXPECT_NEAR(detail::eccentricityDeg(Model::View, 0.3, -0.2, 0.3, -0.2), 0.0, 1e-9);
    // Symmetric in pixel and gaze.
    EXPECT_NEAR(detail::eccentricityDeg(Model::View, 0.7, 0.1, -0.2, 0.4),
                detail::eccentricityDeg(Model::View, -0.2, 0.4, 0.7, 0.1), 1e-9);
    // Pixels per degree: the central pixel's subtense, and the flat screen made from it.
    const ViewGeometry g = ViewGeometry::flatScreenPpd(512, 256, 30.0);
    EXPECT_NEAR(g.ppdCentre(), 30.0, 1e-4);
    EXPECT_NEAR(ViewGeometry::symmetric(1000, 500, 90.0).ppdCentre(), 1.0 / (2.0 * std::atan(0.001) * 180.0 / kPi),
                1e-3);
    // More pixels per degree off-axis on a flat screen; 1 at the axis.
    EXPECT_NEAR(detail::resolutionMagnification(0.0, 30.0), 1.0, 1e-3);
    EXPECT_NEAR(detail::resolutionMagnification(40.0, 30.0), 1.0 / std::pow(std::cos(40.0 * kPi / 180.0), 2.0), 0.01);
}

TEST(Fvvdp, ContrastSensitivityFunction) {
    using namespace detail;
    // Band-pass in frequency, its peak near 1 cpd for the metric's stimuli of 1.5 cycles at office
    // luminance.
    const double s_low = csfSensitivity(0.125, 0.0, 100.0, 0.0), s1 = csfSensitivity(1.0, 0.0, 100.0, 0.0),
                 s3 = csfSensitivity(3.0, 0.0, 100.0, 0.0), s20 = csfSensitivity(20.0, 0.0, 100.0, 0.0);
    EXPECT_GT(s1, s_low);
    EXPECT_GT(s1, s3);
    EXPECT_GT(s3, s20);
    EXPECT_GT(s1, 50.0);
    EXPECT_LT(s1, 500.0);
    // Less sensitive in the dark and in the periphery.
    EXPECT_LT(csfSensitivity(3.0, 0.0, 0.1, 0.0), s3);
    EXPECT_LT(csfSensitivity(8.0, 0.0, 100.0, 20.0), csfSensitivity(8.0, 0.0, 100.0, 0.0));
    // The table reproduces the model at its nodes and between them closely.
    const auto table = csfTable(0.0);
    EXPECT_NEAR(csfLookup(table, 4.0f, 100.0f, 0.0f) / csfSensitivity(4.0, 0.0, 100.0, 0.0), 1.0, 0.02);
    EXPECT_NEAR(csfLookup(table, 7.0f, 30.0f, 10.0f) / csfSensitivity(7.0, 0.0, 30.0, 10.0), 1.0, 0.03);
    // Photometry: the presets' black levels.
    EXPECT_NEAR(DisplayPhotometry::monitor().black(), 0.2 + 250.0 * 0.005 / 3.14159265358979, 1e-9);
    EXPECT_NEAR(DisplayPhotometry::hmd().black(), 0.1, 1e-12);
    EXPECT_NEAR(displayLuminance(1.0f, 1.0f, 1.0f, 200.0f, 0.5f), 200.0f, 1e-3f);
}

}  // namespace
}  // namespace wrsfov::eval::fvvdp
