// A small scatter/line chart drawn with OpenCV, for the reports' PNG plots.
#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "compositor/compositor.h"

namespace wrsfov::eval {

/// One series: its points (non-finite ones are skipped), optional per-point labels (drawn where they
/// overlap no other label), whether consecutive points are joined, and whether each has a dot. A series
/// with an empty name has no legend entry (an error bar beside its series).
struct Series {
    std::string name;
    cv::Scalar colour;
    std::vector<cv::Point2d> points;
    std::vector<std::string> labels;
    bool line = false;
    bool markers = true;  ///< a dot at each point (false: the line alone, e.g. a target level)
};

/// A 720 x 500 chart with round-valued ticks and a legend row above the plot.
cv::Mat chart(const std::string& title, const std::string& xLabel, const std::string& yLabel,
              const std::vector<Series>& series);

/// Each method's colour in every plot (BGR).
cv::Scalar methodColour(Method m);

}  // namespace wrsfov::eval
