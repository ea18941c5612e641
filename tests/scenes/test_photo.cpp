// The photo scene (scenes/photo.h): generated textures are deterministic natural-looking texture
// with energy up to the pixel scale; every frame is the texture resampled through the exact
// screen-to-plane mapping, so the previous frame sampled at each pixel's motion vector reproduces
// the current frame; depth is the plane's; bad options and unreadable files are refused.
#include <cmath>
#include <cstdio>
#include <tuple>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scenes/photo.h"
#include "shaders/wrs_common.h"

namespace wrsfov::scenes {
namespace {

struct Frame {
    HostImage color, depth, motion;
};

Frame render(const PhotoScene& s, uint32_t index, int eye = 0) {
    Frame f;
    EXPECT_TRUE(s.render(index, eye, f.color, f.depth, f.motion).ok());
    return f;
}

// Linear luminance of a colour image.
cv::Mat luma(const HostImage& c) {
    cv::Mat m(int(c.height), int(c.width), CV_32F);
    for (uint32_t y = 0; y < c.height; ++y)
        for (uint32_t x = 0; x < c.width; ++x) {
            const glm::vec4 v = c.fetch(x, y);
            m.at<float>(int(y), int(x)) = 0.2126f * gpu::wrs_srgb_to_linear(v.x) + 0.7152f * gpu::wrs_srgb_to_linear(v.y) +
                                          0.0722f * gpu::wrs_srgb_to_linear(v.z);
        }
    return m;
}

TEST(Photo, GeneratedTexturesAreDeterministicAndDetailedToThePixel) {
    for (const char* kind : {"grass", "wood"}) {
        SCOPED_TRACE(kind);
        auto a = generatePhotoTexture(kind, 200, 150, 7), b = generatePhotoTexture(kind, 200, 150, 7),
             c = generatePhotoTexture(kind, 200, 150, 8);
        ASSERT_TRUE(a.ok() && b.ok() && c.ok());
        EXPECT_EQ(cv::norm(*a, *b, cv::NORM_INF), 0.0) << "the same seed gives the same texture";
        EXPECT_GT(cv::norm(*a, *c, cv::NORM_L1), 1.0) << "another seed another one";
        double lo, hi;
        cv::minMaxLoc(a->reshape(1), &lo, &hi);
        EXPECT_GE(lo, 0.0);
        EXPECT_LE(hi, 1.0);
        // Natural texture has detail at every scale: the finest (pixel-to-pixel differences) and a coarse
        // one (8-pixel block means) both vary.
        cv::Mat grey, dx, coarse;
        cv::cvtColor(*a, grey, cv::COLOR_RGB2GRAY);
        cv::Sobel(grey, dx, CV_32F, 1, 0, 1);
        cv::resize(grey, coarse, cv::Size(25, 19), 0, 0, cv::INTER_AREA);
        cv::Scalar m, sd, cm, csd;
        cv::meanStdDev(cv::abs(dx), m, sd);
        cv::meanStdDev(coarse, cm, csd);
        std::printf("%s: mean |dx| %.4f, coarse sd %.4f\n", kind, m[0], csd[0]);
        EXPECT_GT(m[0], 0.004);
        EXPECT_GT(csd[0], 0.004);
    }
    EXPECT_FALSE(generatePhotoTexture("marble", 64, 64, 1).ok());
    EXPECT_FALSE(generatePhotoTexture("grass", 4, 64, 1).ok());
}

TEST(Photo, MotionVectorsCarryThePreviousFrameOntoThisOne) {
    // Pan and turn, slow and fast, monitor and one HMD eye: the previous frame sampled where each pixel
    // was (its motion vector) matches this frame far better than the previous frame where the pixel
    // is, on the smooth wood texture (bilinear sampling of the previous frame is the test's only error).
    struct Case {
        PhotoMotion motion;
        float speed;
        bool monitor;
    };
    for (const Case& c : {Case{PhotoMotion::Pan, 0.37f, true}, Case{PhotoMotion::Pan, 2.3f, true},
                          Case{PhotoMotion::Turn, 1.5f, true}, Case{PhotoMotion::Pan, 1.0f, false}}) {
        SCOPED_TRACE(std::string(toString(c.motion)) + " " + std::to_string(c.speed));
        PhotoOptions o;
        o.width = 160, o.height = 120;
        o.image = "wood";
        o.monitor = c.monitor;
        o.motion = c.motion;
        o.speed = c.speed;
        o.frames = 12;
        auto s = PhotoScene::create(o);
        ASSERT_TRUE(s.ok()) << s.error().message;
        const Frame prev = render(**s, 9), cur = render(**s, 10);
        // The previous frame where each pixel was, resampled with the scene's own kernel.
        cv::Mat mapX(int(o.height), int(o.width), CV_32F), mapY(int(o.height), int(o.width), CV_32F), moved;
        for (uint32_t y = 0; y < o.height; ++y)
            for (uint32_t x = 0; x < o.width; ++x) {
                const glm::vec4 mv = cur.motion.fetch(x, y);
                mapX.at<float>(int(y), int(x)) = float(x) + mv.x;
                mapY.at<float>(int(y), int(x)) = float(y) + mv.y;
            }
        const cv::Mat lp = luma(prev.color), lc = luma(cur.color);
        // Mean error of the previous frame carried by the motion scaled by s and offset by (ox, oy).
        auto carried = [&](double sc, float ox, float oy) {
            cv::Mat mx = mapX.clone(), my = mapY.clone();
            for (uint32_t y = 0; y < o.height; ++y)
                for (uint32_t x = 0; x < o.width; ++x) {
                    mx.at<float>(int(y), int(x)) = float(x + (mapX.at<float>(int(y), int(x)) - x) * sc) + ox;
                    my.at<float>(int(y), int(x)) = float(y + (mapY.at<float>(int(y), int(x)) - y) * sc) + oy;
                }
            cv::remap(lp, moved, mx, my, cv::INTER_LANCZOS4, cv::BORDER_REPLICATE);
            double e = 0;
            int n = 0;
            for (int y = 8; y < int(o.height) - 8; ++y)
                for (int x = 8; x < int(o.width) - 8; ++x, ++n) e += std::abs(moved.at<float>(y, x) - lc.at<float>(y, x));
            return e / n;
        };
        const double errMoved = carried(1.0, 0, 0), errStill = carried(0.0, 0, 0);
        // The motion is exact: nudging it by a tenth of a pixel or scaling it by 10 % only adds error.
        for (auto [sc, ox, oy] : {std::tuple{0.9, 0.0f, 0.0f}, std::tuple{1.1, 0.0f, 0.0f}, std::tuple{1.0, 0.1f, 0.0f},
                                  std::tuple{1.0, -0.1f, 0.0f}, std::tuple{1.0, 0.0f, 0.1f}, std::tuple{1.0, 0.0f, -0.1f}})
            EXPECT_LT(errMoved, carried(sc, ox, oy)) << "scaled " << sc << ", offset " << ox << "," << oy;
        const double mvCentre = std::abs(cur.motion.fetch(o.width / 2, o.height / 2).x);
        const double mvEdge = std::abs(cur.motion.fetch(2, o.height / 2).x);
        std::printf("mean error moved %.5f, unmoved %.5f; motion at the centre %.4f, at the left edge %.4f\n",
                    errMoved, errStill, mvCentre, mvEdge);
        EXPECT_LT(errMoved, 0.5 * errStill);
        EXPECT_LT(errMoved, 0.0025);
        // The speed is given at the view's centre; a pan moves every pixel alike, a turn more off-axis.
        EXPECT_NEAR(mvCentre, c.speed, 0.01);
        if (c.motion == PhotoMotion::Pan) EXPECT_NEAR(mvEdge, c.speed, 0.01);
        else EXPECT_GT(mvEdge, c.speed * 1.2);
        // The first frame has no motion.
        const Frame first = render(**s, 0);
        EXPECT_EQ(first.motion.fetch(o.width / 2, o.height / 2), glm::vec4(0.0f));
    }
}

TEST(Photo, DepthIsThePlanes) {
    PhotoOptions o;
    o.width = 64, o.height = 48;
    o.distance = 2.5f;
    o.motion = PhotoMotion::Turn;
    o.speed = 0.3f;
    o.frames = 40;
    auto s = PhotoScene::create(o);
    ASSERT_TRUE(s.ok());
    const Frame f0 = render(**s, 0), f30 = render(**s, 30);
    auto linear = [&](const Frame& f, uint32_t x, uint32_t y) {
        return gpu::wrs_linear_depth(f.depth.fetch(x, y).x, o.nearZ, o.farZ, false);
    };
    EXPECT_NEAR(linear(f0, 32, 24), 2.5f, 2.5f * 1e-3f) << "facing the plane: its distance";
    // Turned by yaw, the ray of tangent tx meets the plane at distance / (cos(yaw) + sin(yaw) tx).
    const double yaw = 30.0 * 0.3 / (**s).pixelsPerTangent();
    const layers::Fov fov = photoFov(o, 0);
    const double tx = std::tan(fov.angleLeft) + 32.5 / 64.0 * (std::tan(fov.angleRight) - std::tan(fov.angleLeft));
    EXPECT_NEAR(linear(f30, 32, 24), 2.5 / (std::cos(yaw) + std::sin(yaw) * tx), 2.5 * 1e-3);
    // Depth's change along the motion is what the third motion channel says (view depth there - here).
    EXPECT_NE(f30.motion.fetch(5, 24).z, 0.0f);
}

TEST(Photo, BadOptionsAndFilesAreRefused) {
    PhotoOptions o;
    o.width = 64, o.height = 48;
    o.image = "/nonexistent/picture.png";
    auto a = PhotoScene::create(o);
    ASSERT_FALSE(a.ok());
    EXPECT_NE(a.error().message.find("/nonexistent/picture.png"), std::string::npos);
    o.image = "grass";
    o.distance = -1.0f;
    EXPECT_FALSE(PhotoScene::create(o).ok());
    o.distance = 1.0f;
    o.speed = std::nanf("");
    EXPECT_FALSE(PhotoScene::create(o).ok());
    o.speed = 1.0f;
    o.imageScale = 0.0f;
    EXPECT_FALSE(PhotoScene::create(o).ok());
    // A turn that would look away from the plane is refused, not rendered as garbage.
    o.imageScale = 1.0f;
    o.motion = PhotoMotion::Turn;
    o.speed = 60.0f;
    o.frames = 300;
    EXPECT_FALSE(PhotoScene::create(o).ok());
}

TEST(Photo, AnImageFileIsShownAtOneTexelPerPixel) {
    // A file written here, read back through the scene: along the central row each pixel shows the
    // texel of its column (random columns, constant down each, so the rows' density does not matter).
    cv::Mat img(40, 60, CV_8UC3), row(1, 60, CV_8UC3);
    cv::randu(row, cv::Scalar::all(0), cv::Scalar::all(255));
    for (int y = 0; y < 40; ++y) row.copyTo(img.row(y));
    const std::string path = ::testing::TempDir() + "photo_scene_test.png";
    ASSERT_TRUE(cv::imwrite(path, img));
    PhotoOptions o;
    o.width = 60, o.height = 40;
    o.image = path;
    o.motion = PhotoMotion::Static;
    auto s = PhotoScene::create(o);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const Frame f = render(**s, 0);
    int same = 0;
    for (uint32_t x = 10; x < 50; ++x) {
        const glm::vec4 c = f.color.fetch(x, 20);
        const cv::Vec3b t = img.at<cv::Vec3b>(20, int(x));
        same += std::abs(int(std::lround(c.x * 255)) - t[2]) <= 2;
    }
    EXPECT_EQ(same, 40) << "the texels land on the pixels";
}

// Other views of the same eye (quad views' wide view and inset): through the eye's own view at its
// size, the frame bit for bit; an inset on whole pixels of that view, the same pixels (to rounding);
// a view at 0.4 of the density, one sample per pixel, not a blur: it keeps the texture's contrast,
// and differs from the full frame filtered and decimated to its size (aliasing).
TEST(Photo, OtherViewsAreRenderedAtTheirOwnDensity) {
    PhotoOptions o;
    o.width = 120, o.height = 90;
    o.motion = PhotoMotion::Pan;
    auto s = PhotoScene::create(o);
    ASSERT_TRUE(s.ok()) << s.error().message;
    const PhotoScene& scene = **s;
    const Frame f = render(scene, 3);
    const layers::Fov fov = photoFov(o, 0);
    Frame v;
    ASSERT_TRUE(scene.renderViewAt(3, 2, 0, fov, 120, 90, v.color, v.depth, v.motion).ok());
    EXPECT_EQ(v.color.data, f.color.data);
    EXPECT_EQ(v.depth.data, f.depth.data);
    EXPECT_EQ(v.motion.data, f.motion.data);

    // An inset over pixels 40..79 x 30..59 of the view.
    const double tl = std::tan(fov.angleLeft), tr = std::tan(fov.angleRight), tu = std::tan(fov.angleUp),
                 td = std::tan(fov.angleDown);
    auto tanX = [&](double px) { return tl + px / 120.0 * (tr - tl); };
    auto tanY = [&](double py) { return tu - py / 90.0 * (tu - td); };
    const layers::Fov inset{float(std::atan(tanX(40))), float(std::atan(tanX(80))), float(std::atan(tanY(30))),
                            float(std::atan(tanY(60)))};
    Frame in;
    ASSERT_TRUE(scene.renderViewAt(3, 2, 0, inset, 40, 30, in.color, in.depth, in.motion).ok());
    int maxDiff = 0;
    for (uint32_t y = 0; y < 30; ++y)
        for (uint32_t x = 0; x < 40; ++x) {
            const glm::vec4 a = in.color.fetch(x, y), b = f.color.fetch(x + 40, y + 30);
            for (int k = 0; k < 3; ++k) maxDiff = std::max(maxDiff, int(std::lround(std::abs(a[k] - b[k]) * 255)));
            EXPECT_NEAR(in.motion.fetch(x, y).x, f.motion.fetch(x + 40, y + 30).x, 1e-3f);
        }
    EXPECT_LE(maxDiff, 1);

    // The wide view: 48 x 36 (0.4 of the density) over the whole view.
    Frame wide;
    ASSERT_TRUE(scene.renderViewAt(3, 2, 0, fov, 48, 36, wide.color, wide.depth, wide.motion).ok());
    cv::Mat full = luma(f.color), sparse = luma(wide.color), blurred;
    cv::resize(full, blurred, sparse.size(), 0, 0, cv::INTER_AREA);
    cv::Scalar mS, sS, mB, sB;
    cv::meanStdDev(sparse, mS, sS);
    cv::meanStdDev(blurred, mB, sB);
    std::printf("wide view: luminance sd %.4f, the full frame area-averaged to its size %.4f\n", sS[0], sB[0]);
    EXPECT_GT(sS[0], 1.15 * sB[0]) << "one sample per pixel keeps the texture's fine contrast (it aliases)";
    EXPECT_GT(cv::norm(sparse, blurred, cv::NORM_L2) / std::sqrt(double(sparse.total())), 0.01);
    // Motion in the wide view's own pixels: the pan's speed at 0.4 of the density.
    EXPECT_NEAR(wide.motion.fetch(24, 18).x, 0.4f * f.motion.fetch(60, 45).x, 0.02f);
}

}  // namespace
}  // namespace wrsfov::scenes
