// Where the fovea lands on the GPU: with method `fov` and `mip` foveation on a one-pixel
// checkerboard, the output is the input exactly inside r_f of each eye's gaze and the flat average
// outside r_f + 1°, for asymmetric, mirrored fields of view and a different gaze per eye. The two
// eyes also keep independent reservoirs.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class Foveation : public GpuTest {};

layers::Fov fovFromTangents(float l, float r, float u, float d) {
    return layers::Fov{std::atan(l), std::atan(r), std::atan(u), std::atan(d)};
}

HostImage checkerboard(uint32_t w, uint32_t h) {
    HostImage img = HostImage::make(layers::Format::RGBA8, w, h);
    for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) img.store(x, y, glm::vec4(glm::vec3(float((x + y) & 1u)), 1.0f));
    return img;
}

struct FoveaFound {
    glm::dvec2 centroid{0};
    uint32_t sharp = 0;
};

// Checks one eye's output against the checkerboard and returns the centroid of the exact pixels.
FoveaFound checkFovea(const HostImage& out, const HostImage& in, const gpu::EyeParams& ep, uint32_t W, uint32_t H,
                      const char* what) {
    const double r_f = ep.gaze.w;
    // Every level of the box pyramid averages a 1-px checkerboard to 0.5 (W, H multiples of 16).
    const int flat = encodeOutput(glm::vec3(0.5f)).x;
    FoveaFound f;
    int bad = 0;
    uint32_t inside = 0, outside = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const double e = eccentricity(ep, x, y, W, H);
            const std::size_t o = (std::size_t(y) * W + x) * 4;
            const int got = int(uint8_t(out.data[o])), src = int(uint8_t(in.data[o]));
            if (got == src) {
                f.sharp++;
                f.centroid += glm::dvec2(x, y);
            }
            if (e < r_f - 0.02) {
                inside++;
                if (std::abs(got - src) > 1 && bad++ < 5)
                    ADD_FAILURE() << what << ": pixel " << x << "," << y << " at " << e << "° is inside the fovea but "
                                  << got << " != input " << src;
            } else if (e > r_f + 1.02) {
                outside++;
                if ((std::abs(got - flat) > 1 || std::abs(got - src) < 60) && bad++ < 5)
                    ADD_FAILURE() << what << ": pixel " << x << "," << y << " at " << e << "° should be blurred, got "
                                  << got << " (input " << src << ")";
            }
        }
    EXPECT_GT(inside, 100u) << what << ": the fovea must cover enough pixels for the test to mean something";
    EXPECT_GT(outside, W * H / 2) << what;
    if (f.sharp) f.centroid /= double(f.sharp);
    return f;
}

// Pixel position (continuous, pixel centres at integers) where a direction meets the image.
glm::dvec2 pixelOf(const gpu::EyeParams& ep, glm::dvec3 dir, uint32_t W, uint32_t H) {
    const double tx = dir.x / -dir.z, ty = dir.y / -dir.z;
    return {(tx - ep.fov_tan.x) / (double(ep.fov_tan.y) - ep.fov_tan.x) * W - 0.5,
            (ep.fov_tan.z - ty) / (double(ep.fov_tan.z) - ep.fov_tan.w) * H - 0.5};
}

TEST_F(Foveation, SharpRegionSitsAtEachEyesGazeWithAsymmetricViews) {
    const uint32_t W = 96, H = 80;
    CompositorConfig cfg;
    cfg.method = Method::Fov;
    cfg.foveation = FoveationMode::Mip;
    cfg.foveaDeg = 10.0f;  // r_f = 5°, about 8 px here
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    StereoApp app(**comp, W, H, layers::Format::RGBA8, std::nullopt, std::nullopt);
    std::array<EyeFrame, 2> eyes;
    // Mirrored asymmetric views: tan left/right/up/down = -0.6/0.4/0.45/-0.35 and -0.4/0.6/0.45/-0.35.
    eyes[0].fov = fovFromTangents(-0.6f, 0.4f, 0.45f, -0.35f);
    eyes[1].fov = fovFromTangents(-0.4f, 0.6f, 0.45f, -0.35f);
    // Left eye looks at tan (-0.25, 0.15), pixel (33.1, 29.5); right at (0.2, -0.1), pixel (57.1, 54.5).
    const glm::dvec3 gaze[2] = {glm::normalize(glm::dvec3(-0.25, 0.15, -1)), glm::normalize(glm::dvec3(0.2, -0.1, -1))};
    const glm::dvec2 expectPixel[2] = {{33.1, 29.5}, {57.1, 54.5}};
    for (int e = 0; e < 2; ++e) {
        eyes[e].color = checkerboard(W, H);
        eyes[e].gaze = {glm::vec3(gaze[e]), true, 1.0f};
    }
    Status s = app.submit(1, eyes);
    ASSERT_TRUE(s.ok()) << s.message();
    EXPECT_FALSE((*comp)->stats().gazeFallback[0]);
    EXPECT_FALSE((*comp)->stats().gazeFallback[1]);
    FoveaFound found[2];
    for (uint32_t e = 0; e < 2; ++e) {
        auto out = (*comp)->readOutput(e);
        ASSERT_TRUE(out.ok());
        const gpu::EyeParams& ep = (*comp)->lastParams().eye[e];
        const glm::dvec2 at = pixelOf(ep, gaze[e], W, H);
        EXPECT_NEAR(at.x, expectPixel[e].x, 1e-3);
        EXPECT_NEAR(at.y, expectPixel[e].y, 1e-3);
        found[e] = checkFovea(*out, eyes[e].color, ep, W, H, e == 0 ? "left" : "right");
        std::printf("  eye %u: %u exact pixels centred at (%.2f, %.2f), gaze at (%.2f, %.2f)\n", e, found[e].sharp,
                    found[e].centroid.x, found[e].centroid.y, at.x, at.y);
        EXPECT_NEAR(found[e].centroid.x, at.x, 0.75);
        EXPECT_NEAR(found[e].centroid.y, at.y, 0.75);
        // The other eye's gaze point is blurred in this eye.
        const glm::ivec2 other = glm::ivec2(glm::round(pixelOf(ep, gaze[1 - e], W, H)));
        ASSERT_TRUE(other.x >= 0 && other.y >= 0 && other.x < int(W) && other.y < int(H));
        EXPECT_EQ(int(uint8_t(out->data[(std::size_t(other.y) * W + other.x) * 4])), encodeOutput(glm::vec3(0.5f)).x);
    }
    EXPECT_GT(glm::length(found[0].centroid - found[1].centroid), 20.0);
}

TEST_F(Foveation, InvalidGazeFallsBackToTheOffAxisViewCentre) {
    // With an asymmetric view the view centre is off the optical axis; the fallback fovea sits there.
    const uint32_t W = 96, H = 80;
    CompositorConfig cfg;
    cfg.method = Method::Fov;
    cfg.foveation = FoveationMode::Mip;
    cfg.foveaDeg = 4.0f;
    cfg.fallbackFoveaDeg = 12.0f;  // r = 6°
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    StereoApp app(**comp, W, H, layers::Format::RGBA8, std::nullopt, std::nullopt);
    std::array<EyeFrame, 2> eyes;
    eyes[0].fov = fovFromTangents(-0.7f, 0.3f, 0.5f, -0.3f);  // centre at tan (-0.2, 0.1)
    eyes[1].fov = fovFromTangents(-0.3f, 0.7f, 0.3f, -0.5f);  // centre at tan (0.2, -0.1)
    for (int e = 0; e < 2; ++e) eyes[e].color = checkerboard(W, H);
    eyes[0].gaze = {glm::vec3(0.1f, 0.0f, -1.0f), false, 0.0f};                              // not valid
    eyes[1].gaze = {glm::vec3(std::numeric_limits<float>::quiet_NaN(), 0, -1), true, 1.0f};  // not finite
    ASSERT_TRUE(app.submit(1, eyes).ok());
    for (uint32_t e = 0; e < 2; ++e) {
        EXPECT_TRUE((*comp)->stats().gazeFallback[e]);
        const gpu::EyeParams& ep = (*comp)->lastParams().eye[e];
        EXPECT_FLOAT_EQ(ep.gaze.w, 6.0f);
        const glm::dvec3 centre = glm::normalize(glm::dvec3(e == 0 ? -0.2 : 0.2, e == 0 ? 0.1 : -0.1, -1.0));
        EXPECT_NEAR(glm::dot(glm::dvec3(ep.gaze), centre), 1.0, 1e-6);
        auto out = (*comp)->readOutput(e);
        ASSERT_TRUE(out.ok());
        FoveaFound f = checkFovea(*out, eyes[e].color, ep, W, H, e == 0 ? "left fallback" : "right fallback");
        EXPECT_NEAR(f.centroid.x, (W - 1) / 2.0, 0.75);
        EXPECT_NEAR(f.centroid.y, (H - 1) / 2.0, 0.75);
    }
}

TEST_F(Foveation, EyesKeepIndependentReservoirs) {
    // Two runs that differ only in the right eye (colour, depth, motion and gaze): the left eye's
    // reservoirs and output must be bit-identical in every frame, the right eye's must differ.
    const uint32_t W = 64, H = 48;
    CompositorConfig cfg;
    cfg.foveaDeg = 10.0f;
    cfg.seed = 21;
    auto a = Compositor::create(context(), cfg);
    auto b = Compositor::create(context(), cfg);
    ASSERT_TRUE(a.ok() && b.ok());
    StereoApp appA(**a, W, H, layers::Format::RGBA8_SRGB, layers::Format::D32F, layers::Format::RGBA16F);
    StereoApp appB(**b, W, H, layers::Format::RGBA8_SRGB, layers::Format::D32F, layers::Format::RGBA16F);
    RandomScene left(11), rightA(12), rightB(13);
    uint64_t rightDiffers = 0, rightOutputDiffers = 0;
    for (int f = 0; f < 12; ++f) {
        std::array<EyeFrame, 2> ea, eb;
        ea[0].fov = eb[0].fov = hmdFov(0);
        ea[1].fov = eb[1].fov = hmdFov(1);
        ea[0].color = left.color(layers::Format::RGBA8_SRGB, W, H);
        ea[0].depth = left.depth(layers::Format::D32F, W, H);
        ea[0].motion = left.motion(layers::Format::RGBA16F, W, H);
        ea[0].gaze = {left.gaze(ea[0].fov), true, 1.0f};
        eb[0] = ea[0];
        for (auto [rs, e] : {std::pair{&rightA, &ea[1]}, std::pair{&rightB, &eb[1]}}) {
            e->color = rs->color(layers::Format::RGBA8_SRGB, W, H);
            e->depth = rs->depth(layers::Format::D32F, W, H);
            e->motion = rs->motion(layers::Format::RGBA16F, W, H);
            e->gaze = {rs->gaze(e->fov), true, 1.0f};
        }
        ASSERT_TRUE(appA.submit(f + 1, ea).ok());
        ASSERT_TRUE(appB.submit(f + 1, eb).ok());
        auto ra = readReservoirs(**a), rb = readReservoirs(**b);
        ASSERT_EQ(ra[0].size(), std::size_t(W) * H);
        uint64_t leftDiffers = 0;
        for (std::size_t i = 0; i < ra[0].size(); ++i) {
            leftDiffers += ra[0][i] != rb[0][i];
            rightDiffers += ra[1][i] != rb[1][i];
        }
        EXPECT_EQ(leftDiffers, 0u) << "frame " << f + 1 << ": the right eye's input changed left reservoirs";
        auto oa = (*a)->readOutput(0), ob = (*b)->readOutput(0);
        ASSERT_TRUE(oa.ok() && ob.ok());
        EXPECT_TRUE(oa->data == ob->data) << "frame " << f + 1 << ": left output differs";
        auto ra1 = (*a)->readOutput(1), rb1 = (*b)->readOutput(1);
        ASSERT_TRUE(ra1.ok() && rb1.ok());
        for (std::size_t i = 0; i < std::size_t(W) * H; ++i)
            rightOutputDiffers += std::memcmp(ra1->data.data() + 4 * i, rb1->data.data() + 4 * i, 4) != 0;
        EXPECT_NE(glm::vec3((*a)->lastParams().eye[1].gaze), glm::vec3((*b)->lastParams().eye[1].gaze));
        if (HasFailure()) break;
    }
    // Far tiles that hold nothing sharper than the floor skip retention (sparse retention) and leave
    // their reservoirs as they were in both runs, so not every right reservoir differs; the output does.
    EXPECT_GT(rightDiffers, 12u * W * H / 4) << "the right eye's input must matter for its own reservoirs";
    EXPECT_GT(rightOutputDiffers, 12u * W * H * 9 / 10) << "the right eye's input must matter for its own output";
}

}  // namespace
}  // namespace wrsfov::test
