// The frames the runtime received from hello_xr without the API layer, with it, and with it disabled
// (tests/xr/layer_test.sh): with the layer they are the application's frames at the gaze and
// foveated away from it; disabled, they are the application's frames exactly.
// usage: wrsfov_xr_layer_frames_tests PLAIN_DIR LAYER_DIR DISABLED_DIR LOST_DIR
#include <gtest/gtest.h>

#include <cmath>

#include "eval/sequence.h"

namespace {

std::string g_plain, g_layer, g_disabled, g_lost;
constexpr double kPi = 3.14159265358979;

std::unique_ptr<wrsfov::eval::SequenceReader> open(const std::string& dir) {
    auto r = wrsfov::eval::SequenceReader::open(dir);
    if (!r) ADD_FAILURE() << r.error().message;
    return r ? std::move(*r) : nullptr;
}

double eccentricity(const glm::vec3& gaze, const wrsfov::layers::Fov& f, uint32_t w, uint32_t h, int x, int y) {
    const double l = std::tan(f.angleLeft), r = std::tan(f.angleRight);
    const double u = std::tan(f.angleUp), dn = std::tan(f.angleDown);
    const glm::vec3 p =
        glm::normalize(glm::vec3(float(l + (x + 0.5) / w * (r - l)), float(u - (y + 0.5) / h * (u - dn)), -1.0f));
    return std::acos(std::clamp(double(glm::dot(p, glm::normalize(gaze))), -1.0, 1.0)) * 180.0 / kPi;
}

// hello_xr draws the same frames in every run (a still head, still cubes), so the runs compare
// frame by frame.
TEST(XrLayerFrames, DisabledLayerChangesNothing) {
    auto a = open(g_plain), b = open(g_disabled);
    ASSERT_TRUE(a && b);
    ASSERT_EQ(a->info().frameCount, b->info().frameCount);
    for (uint32_t i : {10u, 59u}) {
        auto fa = a->frame(i), fb = b->frame(i);
        ASSERT_TRUE(fa && fb);
        for (int e = 0; e < 2; ++e) EXPECT_EQ(fa->eyes[e].color.data, fb->eyes[e].color.data) << "frame " << i;
    }
}

// After the layer disabled itself (device lost inside it), the frames pass through untouched.
TEST(XrLayerFrames, LayerLostItsDeviceAndPassesFramesThrough) {
    auto a = open(g_plain), b = open(g_lost);
    ASSERT_TRUE(a && b);
    auto fa = a->frame(59), fb = b->frame(59);
    ASSERT_TRUE(fa && fb);
    for (int e = 0; e < 2; ++e) EXPECT_EQ(fa->eyes[e].color.data, fb->eyes[e].color.data) << "eye " << e;
}

// The layer used the runtime's cyclopean eye gaze; the recorded per-eye gaze verges by about 1.2 deg
// either side of it, so "at the gaze" is within 1 deg of the recorded direction (inside the 2.5 deg
// fovea radius of both).
TEST(XrLayerFrames, LayerFoveatesAwayFromTheGazeAndKeepsTheGaze) {
    auto a = open(g_plain), b = open(g_layer);
    ASSERT_TRUE(a && b);
    const uint32_t w = a->info().width, h = a->info().height;
    double nearMax = 0, farSum = 0;
    uint64_t nearN = 0, farN = 0;
    for (uint32_t i = 10; i < b->info().frameCount; ++i) {  // every frame: blinks leave some without gaze
        auto fa = a->frame(i), fb = b->frame(i);
        ASSERT_TRUE(fa && fb);
        for (int e = 0; e < 2; ++e) {
            const auto& g = b->gaze(i)[e];
            if (!g.valid) continue;
            const auto& in = fa->eyes[e].color;
            const auto& out = fb->eyes[e].color;
            for (int y = 1; y + 1 < int(h); ++y)
                for (int x = 1; x + 1 < int(w); ++x) {
                    const double ecc = eccentricity(g.dir, a->info().fov[e], w, h, x, y);
                    double diff = 0, grad = 0;
                    auto at = [&](const wrsfov::HostImage& im, int px, int py, int c) {
                        return double(im.data[(size_t(py) * w + px) * 4 + c]) / 255.0;
                    };
                    for (int c = 0; c < 3; ++c) {
                        diff = std::max(diff, std::abs(at(out, x, y, c) - at(in, x, y, c)));
                        grad = std::max({grad, std::abs(at(in, x + 1, y, c) - at(in, x - 1, y, c)),
                                         std::abs(at(in, x, y + 1, c) - at(in, x, y - 1, c))});
                    }
                    if (ecc < 1.0) {
                        nearMax = std::max(nearMax, diff);
                        ++nearN;
                    } else if (ecc > 20.0 && grad > 0.2) {
                        farSum += diff;
                        ++farN;
                    }
                }
        }
    }
    std::printf("near gaze: %llu px, max |layer - app| %.4f; periphery edges: %llu px, mean %.4f\n",
                (unsigned long long)nearN, nearMax, (unsigned long long)farN, farN ? farSum / double(farN) : 0.0);
    ASSERT_GT(nearN, 20u);
    ASSERT_GT(farN, 100u);
    EXPECT_LE(nearMax, 2.0 / 255.0);
    EXPECT_GT(farSum / double(farN), 0.05);
}

}  // namespace

int main(int argc, char** argv) {
    ::testing::InitGoogleTest(&argc, argv);
    if (argc < 5) {
        std::fprintf(stderr, "usage: %s PLAIN_DIR LAYER_DIR DISABLED_DIR LOST_DIR\n", argv[0]);
        return 2;
    }
    g_plain = argv[1];
    g_layer = argv[2];
    g_disabled = argv[3];
    g_lost = argv[4];
    return RUN_ALL_TESTS();
}
