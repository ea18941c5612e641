// Pictures of gaze: a scanpath and a velocity-over-time plot, drawn with OpenCV and written as PNG.
#pragma once

#include <span>
#include <string>

#include "gaze/result.h"
#include "gaze/sample.h"

namespace wrsfov::gaze {

struct PlotOptions {
    int width = 1200, height = 800;
    double max_seconds = 0;       ///< velocity plot: only the first seconds (0: all)
    double threshold_deg_s = 30;  ///< drawn as a dashed line on the velocity plot
};

/// Azimuth/elevation of the cyclopean gaze, coloured by each sample's label, with a degree grid.
Status write_scanpath_png(const std::string& path, std::span<const GazeSample> samples, const PlotOptions& o = {});

/// Speed (5-sample velocity, deg/s) over time, coloured by label, with the I-VT threshold.
Status write_velocity_png(const std::string& path, std::span<const GazeSample> samples, const PlotOptions& o = {});

}  // namespace wrsfov::gaze
