#include "scenes/png.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace wrsfov {

Status writePng(const HostImage& image, const std::string& path) {
    if (image.format != layers::Format::RGBA8 && image.format != layers::Format::RGBA8_SRGB)
        return Error{1, "writePng needs an 8-bit RGBA image, got " + std::string(layers::toString(image.format))};
    cv::Mat rgba(int(image.height), int(image.width), CV_8UC4, const_cast<std::byte*>(image.data.data()));
    cv::Mat bgr;
    cv::cvtColor(rgba, bgr, cv::COLOR_RGBA2BGR);
    try {
        if (!cv::imwrite(path, bgr)) return Error{1, "could not write " + path};
    } catch (const cv::Exception& e) {
        return Error{1, "could not write " + path + ": " + e.what()};
    }
    return {};
}

}  // namespace wrsfov
