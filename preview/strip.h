// The stats strip under the panels: lines of text drawn on the CPU with OpenCV, premultiplied RGBA
// over transparent black, which the panel pass lays over a dark background.
#pragma once

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "preview/layout.h"

namespace wrsfov::preview {

/// Draws `items` left to right, wrapping to the next line when an item does not fit; items that
/// find no line are dropped. CV_8UC4, layout.width x layout.stripHeight.
cv::Mat drawStrip(const Layout& layout, const std::vector<std::string>& items);
/// How many lines drawStrip needs for `items` at this width.
uint32_t stripLinesNeeded(uint32_t width, const std::vector<std::string>& items);

}  // namespace wrsfov::preview
