// The sequence the OpenXR runtime recorded from hello_xr (tests/xr/hello_xr_test.sh): it reads back
// as a sequence, the generator's gaze verges on one point, and the compositor's output (recorded
// beside the application's colour) is the application's image at the gaze and foveated away from it.
// usage: wrsfov_xr_recording_tests SEQUENCE_DIR
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <string>

#include "eval/sequence.h"

namespace {

std::string g_dir;
constexpr double kPi = 3.14159265358979;

std::unique_ptr<wrsfov::eval::SequenceReader> open() {
    auto r = wrsfov::eval::SequenceReader::open(g_dir);
    if (!r) ADD_FAILURE() << r.error().message;
    return r ? std::move(*r) : nullptr;
}

TEST(XrRecording, IsA300FrameStereoSequenceWithGaze) {
    auto r = open();
    ASSERT_TRUE(r);
    EXPECT_EQ(r->info().frameCount, 300u);
    EXPECT_EQ(r->info().width, 192u);
    EXPECT_EQ(r->info().height, 192u);
    EXPECT_DOUBLE_EQ(r->info().fps, 90.0);
    EXPECT_EQ(r->info().color, wrsfov::eval::ColorFile::Png);  // hello_xr picks R8G8B8A8_SRGB
    EXPECT_TRUE(r->hasGaze());
    auto f = r->frame(299);
    ASSERT_TRUE(f) << f.error().message;
    EXPECT_EQ(f->eyes[1].color.width, 192u);
}

// Both eyes fixate one point 1.5 m along the cyclopean gaze (the runtime's default vergence
// distance, IPD 63 mm): the angle between the eyes' directions is 2 atan(0.0315 / 1.5) = 2.41 deg
// straight ahead, a little less off axis (at most 20 deg in the generator's scene mode).
TEST(XrRecording, GeneratorGazeVergesOnOnePoint) {
    auto r = open();
    ASSERT_TRUE(r);
    uint32_t valid = 0;
    for (uint32_t i = 0; i < r->info().frameCount; ++i) {
        const auto& g = r->gaze(i);
        EXPECT_EQ(g[0].valid, g[1].valid) << "frame " << i;
        if (!g[0].valid) continue;
        ++valid;
        const double angle = std::acos(std::clamp(double(glm::dot(g[0].dir, g[1].dir)), -1.0, 1.0)) * 180.0 / kPi;
        EXPECT_GT(angle, 2.1) << "frame " << i;
        EXPECT_LT(angle, 2.45) << "frame " << i;
        EXPECT_GT(g[0].dir.x, g[1].dir.x) << "frame " << i << ": the eyes turn inwards";
    }
    // Blinks and simulated tracker dropouts make some frames invalid, not most.
    EXPECT_GT(valid, 240u);
}

// Eccentricity in degrees of pixel (x, y) from the gaze direction.
double eccentricity(const glm::vec3& gaze, const wrsfov::layers::Fov& f, uint32_t w, uint32_t h, int x, int y) {
    const double l = std::tan(f.angleLeft), r = std::tan(f.angleRight);
    const double u = std::tan(f.angleUp), dn = std::tan(f.angleDown);
    const glm::vec3 p = glm::normalize(glm::vec3(float(l + (x + 0.5) / w * (r - l)), float(u - (y + 0.5) / h * (u - dn)), -1.0f));
    return std::acos(std::clamp(double(glm::dot(p, glm::normalize(gaze))), -1.0, 1.0)) * 180.0 / kPi;
}

// Output vs the application's colour: within 1.5 deg of the gaze (inside the 5 deg fovea) they agree;
// on edges beyond 20 deg they differ by much more (the periphery is foveated).
TEST(XrRecording, OutputIsSharpAtTheGazeAndFoveatedAwayFromIt) {
    auto r = open();
    ASSERT_TRUE(r);
    const uint32_t w = r->info().width, h = r->info().height;
    double nearSum = 0, farSum = 0, nearMax = 0;
    uint64_t nearN = 0, farN = 0;
    for (uint32_t i = 10; i < r->info().frameCount; i += 10) {
        auto f = r->frame(i);
        ASSERT_TRUE(f) << f.error().message;
        for (int e = 0; e < 2; ++e) {
            const auto& gz = r->gaze(i)[e];
            if (!gz.valid) continue;
            const std::string out = g_dir + "/" + wrsfov::eval::frameFileName(i, e, "output.png");
            cv::Mat o = cv::imread(out, cv::IMREAD_COLOR);  // BGR
            ASSERT_FALSE(o.empty()) << out;
            const auto& in = f->eyes[e].color;  // RGBA8_SRGB, as submitted
            const auto& fov = r->info().fov[e];
            auto inAt = [&](int x, int y, int c) { return double(in.data[(size_t(y) * w + x) * 4 + c]) / 255.0; };
            for (int y = 1; y + 1 < int(h); ++y)
                for (int x = 1; x + 1 < int(w); ++x) {
                    const double ecc = eccentricity(gz.dir, fov, w, h, x, y);
                    double diff = 0, grad = 0;
                    for (int c = 0; c < 3; ++c) {
                        diff = std::max(diff, std::abs(double(o.at<cv::Vec3b>(y, x)[2 - c]) / 255.0 - inAt(x, y, c)));
                        grad = std::max({grad, std::abs(inAt(x + 1, y, c) - inAt(x - 1, y, c)),
                                         std::abs(inAt(x, y + 1, c) - inAt(x, y - 1, c))});
                    }
                    if (ecc < 1.5) {
                        nearSum += diff, ++nearN;
                        nearMax = std::max(nearMax, diff);
                    } else if (ecc > 20.0 && grad > 0.2) {
                        farSum += diff, ++farN;
                    }
                }
        }
    }
    ASSERT_GT(nearN, 300u);
    ASSERT_GT(farN, 200u) << "too few edges in the periphery to judge foveation";
    const double nearMean = nearSum / double(nearN), farMean = farSum / double(farN);
    std::printf("near gaze: %llu px, mean |out - in| %.4f, max %.4f; periphery edges: %llu px, mean %.4f\n",
                (unsigned long long)nearN, nearMean, nearMax, (unsigned long long)farN, farMean);
    EXPECT_LT(nearMean, 1.0 / 255.0);
    EXPECT_LE(nearMax, 3.0 / 255.0);
    EXPECT_GT(farMean, 0.05);
}

}  // namespace

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s SEQUENCE_DIR\n", argv[0]);
        return 2;
    }
    g_dir = argv[1];
    return RUN_ALL_TESTS();
}
