#include "preview/strip.h"

#include <opencv2/imgproc.hpp>

namespace wrsfov::preview {

namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kScale = 0.36;
constexpr int kMargin = 4, kGap = 14;

// Places the items left to right, wrapping; calls draw(item, x, line) for each.
template <typename Draw>
uint32_t place(uint32_t width, const std::vector<std::string>& items, Draw draw) {
    int line = 0, x = kMargin;
    for (const std::string& item : items) {
        const cv::Size size = cv::getTextSize(item, kFont, kScale, 1, nullptr);
        if (x > kMargin && x + size.width > int(width) - kMargin) {
            ++line;
            x = kMargin;
        }
        draw(item, x, line);
        x += size.width + kGap;
    }
    return uint32_t(line + 1);
}

}  // namespace

cv::Mat drawStrip(const Layout& layout, const std::vector<std::string>& items) {
    cv::Mat m(int(layout.stripHeight), int(layout.width), CV_8UC4, cv::Scalar(0, 0, 0, 0));
    place(layout.width, items, [&](const std::string& item, int x, int line) {
        if (line >= int(layout.stripLines)) return;
        const int y = 2 + line * int(kStripLineHeight) + int(kStripLineHeight) - 4;
        cv::putText(m, item, {x, y}, kFont, kScale, cv::Scalar(235, 235, 235, 255), 1, cv::LINE_AA);
    });
    return m;
}

uint32_t stripLinesNeeded(uint32_t width, const std::vector<std::string>& items) {
    return place(width, items, [](const std::string&, int, int) {});
}

}  // namespace wrsfov::preview
