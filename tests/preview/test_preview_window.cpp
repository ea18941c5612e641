// wrsfov-preview in a real window (Xvfb, lavapipe presenting through a Vulkan swapchain): runs the
// program, reads its screenshots with OpenCV and checks them against the scene's geometry: both
// eyes show the scene, the gaze marker sits where the gaze points, the fovea is sharp exactly
// there, the circles lie at their eccentricities, and resizing, views and gaze sources work.
// Run by preview_window_test.sh, which starts Xvfb and sets WRSFOV_PREVIEW_BIN / _OUT.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "compositor/host_app.h"
#include "gaze/angles.h"
#include "scenes/atrium.h"

using namespace wrsfov;

namespace {

constexpr uint32_t kW = 192, kH = 176;
// The scene of most cases: the atrium from a still camera (detail everywhere, no motion).
const std::string kScene = " --size 192x176 --scene atrium --path static --seed 1";

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

std::string outPath(const std::string& name) { return env("WRSFOV_PREVIEW_OUT") + "/" + name; }

struct ProgramRun {
    int status = -1;
    std::string output;
};

// Runs the preview with `args` (stdout and stderr together).
ProgramRun runPreview(const std::string& args, const std::string& prefix = "") {
    const std::string cmd = prefix + "'" + env("WRSFOV_PREVIEW_BIN") + "' " + args + " 2>&1";
    ProgramRun r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) r.output.append(buf, n);
    const int st = pclose(p);
    r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
    return r;
}

// With the validation layer on (WRSFOV_VALIDATION=1), a run must report no error.
void expectClean(const ProgramRun& r) {
    if (!env("WRSFOV_VALIDATION").empty() && env("WRSFOV_VALIDATION") != "0") {
        EXPECT_NE(r.output.find("validation: 0 errors"), std::string::npos) << r.output;
    }
}

// Runs and expects success, and no validation error when the layer is on.
cv::Mat shoot(const std::string& args, const std::string& file) {
    const std::string path = outPath(file);
    std::remove(path.c_str());
    ProgramRun r = runPreview(args + " --screenshot '" + path + "'");
    EXPECT_EQ(r.status, 0) << args << "\n" << r.output;
    expectClean(r);
    cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
    EXPECT_FALSE(img.empty()) << "no screenshot " << path << "\n" << r.output;
    return img;
}

cv::Mat panel(const cv::Mat& img, int col, int row = 0) {
    return img(cv::Rect(col * int(kW), row * int(kH), int(kW), int(kH)));
}

// Marker pixels: the exact marker colour (BGR 255, 0, 255); centroid in pixel indices.
bool findMarker(const cv::Mat& p, cv::Point2d& centre, int& count) {
    double sx = 0, sy = 0;
    count = 0;
    for (int y = 0; y < p.rows; ++y)
        for (int x = 0; x < p.cols; ++x)
            if (p.at<cv::Vec3b>(y, x) == cv::Vec3b(255, 0, 255)) {
                sx += x;
                sy += y;
                ++count;
            }
    if (count == 0) return false;
    centre = {sx / count, sy / count};
    return true;
}

// Where a direction lands in an eye's image, in pixel indices (centre of pixel i at i).
cv::Point2d project(const layers::Fov& fov, const glm::vec3& d) {
    const double tl = std::tan(fov.angleLeft), tr = std::tan(fov.angleRight);
    const double tu = std::tan(fov.angleUp), td = std::tan(fov.angleDown);
    const double tx = d.x / -d.z, ty = d.y / -d.z;
    return {(tx - tl) / (tr - tl) * kW - 0.5, (tu - ty) / (tu - td) * kH - 0.5};
}

double eccentricityDeg(const layers::Fov& fov, double x, double y, const glm::vec3& gaze) {
    return gaze::angle_between_deg(pixelDirection(fov, kW, kH, float(x), float(y)), gaze);
}

// Eccentricities of the pixels of one exact colour (BGR), relative to `gaze`.
std::vector<double> colourEccentricities(const cv::Mat& p, cv::Vec3b bgr, const layers::Fov& fov,
                                         const glm::vec3& gaze) {
    std::vector<double> e;
    for (int y = 0; y < p.rows; ++y)
        for (int x = 0; x < p.cols; ++x)
            if (p.at<cv::Vec3b>(y, x) == bgr) e.push_back(eccentricityDeg(fov, x, y, gaze));
    std::sort(e.begin(), e.end());
    return e;
}

double median(const std::vector<double>& v) { return v.empty() ? NAN : v[v.size() / 2]; }

// Mean absolute difference (8-bit, all channels) over pixels whose eccentricity from `gaze` is in [lo, hi).
double meanDiff(const cv::Mat& a, const cv::Mat& b, const layers::Fov& fov, const glm::vec3& gaze, double lo, double hi,
                int& n) {
    double sum = 0;
    n = 0;
    for (int y = 0; y < a.rows; ++y)
        for (int x = 0; x < a.cols; ++x) {
            const double e = eccentricityDeg(fov, x, y, gaze);
            if (e < lo || e >= hi) continue;
            const cv::Vec3b pa = a.at<cv::Vec3b>(y, x), pb = b.at<cv::Vec3b>(y, x);
            for (int c = 0; c < 3; ++c) sum += std::abs(int(pa[c]) - int(pb[c]));
            ++n;
        }
    return n ? sum / (3.0 * n) : NAN;
}

void expectSceneVisible(const cv::Mat& p, const std::string& what) {
    cv::Scalar mean, sd;
    cv::meanStdDev(p, mean, sd);
    EXPECT_GT(sd[0] + sd[1] + sd[2], 3 * 8.0) << what << ": uniform";
    EXPECT_GT(mean[0] + mean[1] + mean[2], 3 * 30.0) << what << ": black";
}

class PreviewWindow : public ::testing::Test {
protected:
    void SetUp() override {
        if (env("WRSFOV_PREVIEW_BIN").empty() || env("WRSFOV_PREVIEW_OUT").empty() || env("DISPLAY").empty())
            GTEST_FAIL() << "run through preview_window_test.sh (needs WRSFOV_PREVIEW_BIN, WRSFOV_PREVIEW_OUT and an "
                            "X display)";
    }
};

}  // namespace

// Synthetic gaze: both eyes show the scene; FOV equals the reference inside the fovea around the
// marker and differs from it in the periphery.
TEST_F(PreviewWindow, FoveaIsSharpWhereTheMarkerIs) {
    const std::string common = kScene + " --gaze generator --frames 5";
    cv::Mat marked = shoot(common + " --method fov --overlay on", "gen_fov_marked.png");
    cv::Mat fov = shoot(common + " --method fov --overlay off", "gen_fov.png");
    cv::Mat ref = shoot(common + " --method reference --overlay off", "gen_reference.png");
    ASSERT_FALSE(marked.empty() || fov.empty() || ref.empty());
    ASSERT_EQ(fov.cols, int(2 * kW));
    ASSERT_GT(fov.rows, int(kH));
    for (int e = 0; e < 2; ++e) {
        const std::string eye = e ? "right" : "left";
        expectSceneVisible(panel(fov, e), eye + " fov");
        expectSceneVisible(panel(ref, e), eye + " reference");
        cv::Point2d c;
        int count = 0;
        ASSERT_TRUE(findMarker(panel(marked, e), c, count)) << eye << ": no gaze marker";
        EXPECT_GE(count, 12) << eye;
        const layers::Fov f = scenes::atriumFov(e);
        const glm::vec3 g = pixelDirection(f, kW, kH, float(c.x), float(c.y));
        int nNear = 0, nFar = 0;
        const double near = meanDiff(panel(fov, e), panel(ref, e), f, g, 0.0, 2.0, nNear);
        const double far = meanDiff(panel(fov, e), panel(ref, e), f, g, 15.0, 180.0, nFar);
        ASSERT_GT(nNear, 10) << eye;
        ASSERT_GT(nFar, 1000) << eye;
        EXPECT_LT(near, 1.0) << eye << ": the fovea around the marker is not the reference";
        EXPECT_GT(far, 6.0) << eye << ": the periphery is not foveated";
        EXPECT_GT(far, 10 * near + 3) << eye;
    }
}

// A fixed gaze direction: the marker lands where the direction projects in each eye's (different,
// asymmetric) view, and the circles lie at r_f and r_m = 7.5° of eccentricity.
TEST_F(PreviewWindow, MarkerAndCirclesAtTheirAngles) {
    const gaze::GazeAngle a{8, -4};
    const glm::vec3 g = gaze::direction_from_angle(a);
    cv::Mat img = shoot(kScene + " --gaze fixed:8,-4 --fovea 10 --method wrs --frames 3", "fixed_circles.png");
    ASSERT_FALSE(img.empty());
    for (int e = 0; e < 2; ++e) {
        const std::string eye = e ? "right" : "left";
        const layers::Fov f = scenes::atriumFov(e);
        cv::Point2d c;
        int count = 0;
        ASSERT_TRUE(findMarker(panel(img, e), c, count)) << eye;
        const cv::Point2d want = project(f, g);
        EXPECT_NEAR(c.x, want.x, 0.75) << eye;
        EXPECT_NEAR(c.y, want.y, 0.75) << eye;
        const auto fovea = colourEccentricities(panel(img, e), {255, 255, 0}, f, g);  // cyan
        const auto mid = colourEccentricities(panel(img, e), {0, 200, 255}, f, g);    // orange-yellow
        ASSERT_GT(fovea.size(), 20u) << eye;
        ASSERT_GT(mid.size(), 30u) << eye;
        EXPECT_NEAR(median(fovea), 5.0, 0.3) << eye;
        EXPECT_NEAR(fovea.front(), 5.0, 1.0) << eye;
        EXPECT_NEAR(fovea.back(), 5.0, 1.0) << eye;
        EXPECT_NEAR(median(mid), 7.5, 0.3) << eye;
        EXPECT_NEAR(mid.front(), 7.5, 1.0) << eye;
        EXPECT_NEAR(mid.back(), 7.5, 1.0) << eye;
    }
}

// Mouse gaze: the pointer over the right eye's pixel (100, 60) puts the gaze through pixel (100, 60)
// of both eyes (the window is the preview image's size, so window = image coordinates).
TEST_F(PreviewWindow, MouseGazeFollowsThePointer) {
    cv::Mat img = shoot(kScene + " --gaze mouse --cursor 292,60 --method fov --frames 3", "mouse.png");
    ASSERT_FALSE(img.empty());
    for (int e = 0; e < 2; ++e) {
        cv::Point2d c;
        int count = 0;
        ASSERT_TRUE(findMarker(panel(img, e), c, count)) << "eye " << e;
        // The pointer sits at the corner between pixels 99 and 100: the marker is centred there.
        EXPECT_NEAR(c.x, 99.5, 0.75) << "eye " << e;
        EXPECT_NEAR(c.y, 59.5, 0.75) << "eye " << e;
    }
}

// A gaze file replayed on the scene clock.
TEST_F(PreviewWindow, GazeFileDrivesTheFovea) {
    const gaze::GazeAngle a{-6, 3};
    const glm::vec3 d = gaze::direction_from_angle(a);
    const std::string csv = outPath("gaze.csv");
    {
        std::ofstream f(csv);
        f << "t_s,frame,valid,left_x,left_y,left_z,right_x,right_y,right_z\n";
        for (int i = 0; i < 3; ++i)
            f << i * 0.5 << ',' << i << ",1," << d.x << ',' << d.y << ',' << d.z << ',' << d.x << ',' << d.y << ','
              << d.z << '\n';
    }
    cv::Mat img = shoot(kScene + " --gaze file:" + csv + " --method fov --frames 3", "file.png");
    ASSERT_FALSE(img.empty());
    for (int e = 0; e < 2; ++e) {
        cv::Point2d c;
        int count = 0;
        ASSERT_TRUE(findMarker(panel(img, e), c, count)) << "eye " << e;
        const cv::Point2d want = project(scenes::atriumFov(e), d);
        EXPECT_NEAR(c.x, want.x, 0.75) << "eye " << e;
        EXPECT_NEAR(c.y, want.y, 0.75) << "eye " << e;
    }
}

// A tracker that is not there: the gaze is invalid, no marker, and the fallback fovea (20°
// diameter) is drawn around the view centre.
TEST_F(PreviewWindow, InvalidGazeShowsTheFallbackFovea) {
    cv::Mat img = shoot(kScene + " --gaze hid:/nonexistent/hidraw --method fov --frames 2", "fallback.png");
    ASSERT_FALSE(img.empty());
    for (int e = 0; e < 2; ++e) {
        cv::Point2d c;
        int count = 0;
        EXPECT_FALSE(findMarker(panel(img, e), c, count)) << "eye " << e;
        const layers::Fov f = scenes::atriumFov(e);
        const glm::vec3 centre = glm::normalize(glm::vec3((std::tan(f.angleLeft) + std::tan(f.angleRight)) / 2,
                                                          (std::tan(f.angleUp) + std::tan(f.angleDown)) / 2, -1));
        const auto fovea = colourEccentricities(panel(img, e), {255, 255, 0}, f, centre);
        ASSERT_GT(fovea.size(), 50u) << "eye " << e;
        EXPECT_NEAR(median(fovea), 10.0, 0.3) << "eye " << e;
    }
}

// Compare and error views: the layout, and the error map is black in the fovea only.
TEST_F(PreviewWindow, CompareAndErrorViews) {
    const std::string common = kScene + " --gaze fixed:5,2 --method fov --frames 3";
    cv::Mat cmp = shoot(common + " --view compare --overlay off", "compare.png");
    cv::Mat err = shoot(common + " --view error --overlay off", "error.png");
    ASSERT_FALSE(cmp.empty() || err.empty());
    EXPECT_EQ(cmp.cols, int(2 * kW));
    EXPECT_GT(cmp.rows, int(2 * kH));
    const glm::vec3 g = gaze::direction_from_angle({5, 2});
    for (int e = 0; e < 2; ++e) {
        const layers::Fov f = scenes::atriumFov(e);
        expectSceneVisible(panel(cmp, e, 1), "reference panel");
        int nNear = 0, nFar = 0;
        const double near = meanDiff(panel(cmp, e, 0), panel(cmp, e, 1), f, g, 0.0, 2.0, nNear);
        const double far = meanDiff(panel(cmp, e, 0), panel(cmp, e, 1), f, g, 15.0, 180.0, nFar);
        EXPECT_LT(near, 1.0) << "eye " << e;
        EXPECT_GT(far, 6.0) << "eye " << e;
        const cv::Mat black = cv::Mat::zeros(int(kH), int(kW), CV_8UC3);
        const double errNear = meanDiff(panel(err, e), black, f, g, 0.0, 2.0, nNear);
        const double errFar = meanDiff(panel(err, e), black, f, g, 15.0, 180.0, nFar);
        EXPECT_LT(errNear, 1.0) << "eye " << e;
        EXPECT_GT(errFar, 10.0) << "eye " << e;
    }
}

// Visible-difference view: FovVideoVDP's distortion map of `fov` against the reference is darker
// at the gaze (the fovea is the reference; the coarse bands' distortion still reaches it) than in
// the blurred periphery; the JOD readout is in
// the stats and the exit summary, below 10 for `fov` and 10 for the reference itself.
TEST_F(PreviewWindow, VisibleDifferenceViewAndJodReadout) {
    const std::string common = kScene + " --gaze fixed:5,2 --frames 3 --view visible --overlay off";
    const std::string path = outPath("visible.png");
    std::remove(path.c_str());
    ProgramRun r = runPreview(common + " --method fov --screenshot '" + path + "'");
    ASSERT_EQ(r.status, 0) << r.output;
    expectClean(r);
    const size_t at = r.output.find("JOD L ");
    ASSERT_NE(at, std::string::npos) << r.output;
    double left = NAN, right = NAN;
    int frames = 0;
    ASSERT_EQ(
        std::sscanf(r.output.c_str() + at, "JOD L %lf R %lf (FovVideoVDP, last %d frames)", &left, &right, &frames), 3)
        << r.output.substr(at, 80);
    EXPECT_EQ(frames, 3);
    for (double j : {left, right}) {
        EXPECT_GT(j, 3.0);
        EXPECT_LT(j, 9.9);
    }
    cv::Mat vis = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(vis.empty());
    EXPECT_EQ(vis.cols, int(2 * kW));
    const glm::vec3 g = gaze::direction_from_angle({5, 2});
    const cv::Mat black = cv::Mat::zeros(int(kH), int(kW), CV_8UC3);
    for (int e = 0; e < 2; ++e) {
        const layers::Fov f = scenes::atriumFov(e);
        int nNear = 0, nFar = 0;
        const double near = meanDiff(panel(vis, e), black, f, g, 0.0, 2.0, nNear);
        const double far = meanDiff(panel(vis, e), black, f, g, 15.0, 180.0, nFar);
        EXPECT_GT(far, 40.0) << "eye " << e;
        EXPECT_LT(near, 0.5 * far) << "eye " << e;
    }
    ProgramRun self = runPreview(common + " --method reference");
    ASSERT_EQ(self.status, 0) << self.output;
    EXPECT_NE(self.output.find("JOD 10 (the reference itself)"), std::string::npos) << self.output;
}

// The window is resized while frames are presented: the swapchain is recreated at the new size
// and the run finishes normally (a moving scene with TAA history, for good measure).
TEST_F(PreviewWindow, ResizeRecreatesTheSwapchain) {
    const std::string path = outPath("resized.png");
    std::remove(path.c_str());
    ProgramRun r = runPreview(
        " --size 192x176 --scene dynamic --path turn --method fov+taa --gaze generator --frames 8 --resize-at 3 "
        "500x320 --screenshot '" +
        path + "'");
    ASSERT_EQ(r.status, 0) << r.output;
    expectClean(r);
    EXPECT_NE(r.output.find("swapchain recreated: 500x320"), std::string::npos) << r.output;
    cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.cols, int(2 * kW));  // the screenshot is the preview image, not the window
    expectSceneVisible(panel(img, 0), "left after resize");
    expectSceneVisible(panel(img, 1), "right after resize");
}

// Keys at run time (injected at loop iterations): text -> atrium, reference -> FOV, three views on
// to `compare`, then pause with two single steps and resume. Each step composites exactly one frame,
// a paused loop none; the last image is the compare view with FOV above the reference.
TEST_F(PreviewWindow, KeysSwitchAtRunTime) {
    const std::string path = outPath("keys.png");
    std::remove(path.c_str());
    ProgramRun r = runPreview(
        " --size 192x176 --scene text --path static --method reference --gaze fixed:5,2 --overlay off --frames 8 "
        "--keys 1:n,2:2,3:v,3:v,3:v,4:space,6:right,9:right,12:space --screenshot '" +
        path + "'");
    ASSERT_EQ(r.status, 0) << r.output;
    expectClean(r);
    size_t at = 0;
    for (const char* line :
         {"[#1] scene atrium", "[#2] method fov", "[#3] view left", "[#3] view right", "[#3] view compare",
          "[#4] paused", "[#4] step", "[#5] step", "[#6] resumed", "8 frames (atrium, fov,"}) {
        const size_t found = r.output.find(line, at);
        ASSERT_NE(found, std::string::npos) << "missing or out of order: " << line << "\n" << r.output;
        at = found;
    }
    cv::Mat img = cv::imread(path, cv::IMREAD_COLOR);
    ASSERT_FALSE(img.empty());
    EXPECT_EQ(img.cols, int(2 * kW));
    EXPECT_GT(img.rows, int(2 * kH));
    const glm::vec3 g = gaze::direction_from_angle({5, 2});
    for (int e = 0; e < 2; ++e) {
        const layers::Fov f = scenes::atriumFov(e);
        expectSceneVisible(panel(img, e, 1), "reference");
        int nNear = 0, nFar = 0;
        EXPECT_LT(meanDiff(panel(img, e, 0), panel(img, e, 1), f, g, 0.0, 2.0, nNear), 1.0) << "eye " << e;
        EXPECT_GT(meanDiff(panel(img, e, 0), panel(img, e, 1), f, g, 15.0, 180.0, nFar), 6.0) << "eye " << e;
    }
}

TEST_F(PreviewWindow, ClearErrorsAndExitStatus) {
    ProgramRun noDisplay = runPreview(kScene + " --frames 1", "env -u DISPLAY ");
    EXPECT_EQ(noDisplay.status, 1) << noDisplay.output;
    EXPECT_NE(noDisplay.output.find("display"), std::string::npos) << noDisplay.output;

    ProgramRun badSize = runPreview("--size 8x8 --frames 1");
    EXPECT_EQ(badSize.status, 2) << badSize.output;
    EXPECT_NE(badSize.output.find("--size"), std::string::npos) << badSize.output;
    ProgramRun badGaze = runPreview("--gaze eyes --frames 1");
    EXPECT_EQ(badGaze.status, 2) << badGaze.output;
    EXPECT_NE(badGaze.output.find("--gaze"), std::string::npos) << badGaze.output;
    ProgramRun noFile = runPreview(kScene + " --gaze file:/nonexistent/gaze.csv --frames 1");
    EXPECT_EQ(noFile.status, 1) << noFile.output;
    EXPECT_NE(noFile.output.find("/nonexistent/gaze.csv"), std::string::npos) << noFile.output;
    ProgramRun help = runPreview("--help");
    EXPECT_EQ(help.status, 0);
    EXPECT_NE(help.output.find("--gaze"), std::string::npos);
    EXPECT_NE(help.output.find("Space"), std::string::npos);
}

// Without --frames the preview runs until the window is closed; Escape closes it like the window's
// close button (glfwWindowShouldClose), and the program ends normally after that frame.
TEST_F(PreviewWindow, EscapeClosesTheWindow) {
    ProgramRun r = runPreview(kScene + " --gaze generator --keys 3:escape");
    ASSERT_EQ(r.status, 0) << r.output;
    expectClean(r);
    EXPECT_NE(r.output.find("[#3] quit"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("wrsfov-preview: 3 frames"), std::string::npos) << r.output;
}
