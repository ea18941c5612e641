#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "gaze/generator.h"
#include "gaze/plot.h"

namespace wg = wrsfov::gaze;

TEST(GazePlot, ScanpathAndVelocityPngs) {
    wg::GeneratorConfig c;
    c.mode = wg::Mode::Scene;
    c.seconds = 4;
    c.seed = 3;
    auto g = wg::generate(c);
    ASSERT_TRUE(g.ok());
    const auto dir = std::filesystem::temp_directory_path();
    const std::string scan = (dir / "wrsfov_gaze_scan.png").string(), vel = (dir / "wrsfov_gaze_vel.png").string();
    wg::PlotOptions o;
    o.width = 640;
    o.height = 480;
    ASSERT_TRUE(wg::write_scanpath_png(scan, g->samples, o).ok());
    ASSERT_TRUE(wg::write_velocity_png(vel, g->samples, o).ok());
    for (const std::string& p : {scan, vel}) {
        const cv::Mat img = cv::imread(p);
        ASSERT_FALSE(img.empty()) << p;
        EXPECT_EQ(img.cols, 640);
        EXPECT_EQ(img.rows, 480);
        // Saccades are drawn in red (BGR 40, 40, 220).
        cv::Mat red;
        cv::inRange(img, cv::Scalar(0, 0, 180), cv::Scalar(90, 90, 255), red);
        EXPECT_GT(cv::countNonZero(red), 50) << p;
        std::filesystem::remove(p);
    }
    EXPECT_FALSE(wg::write_scanpath_png(scan, {}, o).ok());
    EXPECT_FALSE(wg::write_velocity_png("/nonexistent-dir/v.png", g->samples, o).ok());
}
