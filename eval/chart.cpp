#include "eval/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace wrsfov::eval {

cv::Mat chart(const std::string& title, const std::string& xLabel, const std::string& yLabel,
              const std::vector<Series>& series) {
    const int W = 720, H = 500, L = 70, R = 20, T = 80, B = 60;
    cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const auto& s : series)
        for (const auto& p : s.points)
            if (std::isfinite(p.x) && std::isfinite(p.y)) {
                x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
            }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    // A range of one value (one fovea, one time) gets a margin of its own size, not of a rounding error.
    auto margin = [](double lo, double hi, double share) {
        return hi - lo > 1e-9 * std::max(1.0, std::fabs(hi)) ? (hi - lo) * share : std::max(0.5, 0.05 * std::fabs(hi));
    };
    const double px = margin(x0, x1, 0.08), py = margin(y0, y1, 0.1);
    x0 -= px, x1 += px, y0 -= py, y1 += py;
    auto map = [&](cv::Point2d p) {
        return cv::Point(int(L + (p.x - x0) / (x1 - x0) * (W - L - R)), int(H - B - (p.y - y0) / (y1 - y0) * (H - T - B)));
    };
    cv::rectangle(img, {L, T}, {W - R, H - B}, {0, 0, 0}, 1);
    // Ticks at round values: a step of 1, 2 or 5 times a power of ten, about five per axis.
    auto niceStep = [](double range) {
        const double raw = range / 5.0, p = std::pow(10.0, std::floor(std::log10(raw))), m = raw / p;
        return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * p;
    };
    auto label = [](double v, double step) {
        char buf[32];
        const int decimals = std::max(0, int(-std::floor(std::log10(step) + 1e-9)));
        std::snprintf(buf, sizeof buf, "%.*f", decimals, std::fabs(v) < step * 1e-6 ? 0.0 : v);
        return std::string(buf);
    };
    const double sx = niceStep(x1 - x0), sy = niceStep(y1 - y0);
    for (double xv = std::ceil(x0 / sx) * sx; xv <= x1; xv += sx) {
        cv::line(img, map({xv, y0}), map({xv, y0}) + cv::Point(0, 5), {0, 0, 0}, 1);
        cv::putText(img, label(xv, sx), map({xv, y0}) + cv::Point(-12, 20), cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0}, 1,
                    cv::LINE_AA);
    }
    for (double yv = std::ceil(y0 / sy) * sy; yv <= y1; yv += sy) {
        cv::putText(img, label(yv, sy), {8, map({x0, yv}).y + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, {0, 0, 0}, 1, cv::LINE_AA);
        cv::line(img, map({x0, yv}), map({x1, yv}), {225, 225, 225}, 1);
    }
    cv::putText(img, title, {L, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(img, xLabel, {W / 2 - 80, H - 15}, cv::FONT_HERSHEY_SIMPLEX, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
    cv::putText(img, yLabel, {5, T - 8}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
    int lx = L, ly = 42;  // legend: a row in the top margin, two where one is too narrow
    std::vector<cv::Rect> labelBoxes;  // every point and every label drawn: labels go where they overlap none
    for (const auto& s : series)
        for (const auto& p : s.points)
            if (s.markers && std::isfinite(p.x) && std::isfinite(p.y))
                labelBoxes.push_back(cv::Rect(map(p) - cv::Point(5, 5), cv::Size(11, 11)));
    for (const auto& s : series) {
        for (std::size_t i = 0; i < s.points.size(); ++i) {
            if (!std::isfinite(s.points[i].y)) continue;
            if (s.markers) cv::circle(img, map(s.points[i]), 5, s.colour, -1, cv::LINE_AA);
            if (s.line && i > 0) cv::line(img, map(s.points[i - 1]), map(s.points[i]), s.colour, 2, cv::LINE_AA);
            // A point label is drawn only where it overlaps no label drawn before it.
            if (i < s.labels.size()) {
                int base = 0;
                const cv::Size ts = cv::getTextSize(s.labels[i], cv::FONT_HERSHEY_SIMPLEX, 0.38, 1, &base);
                cv::Point at = map(s.points[i]) + cv::Point(7, -7);
                if (at.x + ts.width > W - R) at.x = map(s.points[i]).x - 7 - ts.width;  // keep it inside the plot
                const cv::Rect box(at.x, at.y - ts.height, ts.width, ts.height + base);
                bool free = true;
                for (const cv::Rect& r : labelBoxes) free = free && (r & box).area() == 0;
                if (free) {
                    labelBoxes.push_back(box);
                    cv::putText(img, s.labels[i], at, cv::FONT_HERSHEY_SIMPLEX, 0.38, s.colour, 1, cv::LINE_AA);
                }
            }
        }
        // The legend wraps to a second row where an entry would leave the image; a series without a name
        // (an error bar) has no entry.
        if (s.name.empty()) continue;
        int base = 0;
        const int tw = cv::getTextSize(s.name, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, &base).width;
        if (lx > L && lx + 10 + tw > W - 5) lx = L, ly += 18;
        if (s.markers)
            cv::circle(img, {lx, ly}, 5, s.colour, -1, cv::LINE_AA);
        else
            cv::line(img, {lx - 6, ly}, {lx + 6, ly}, s.colour, 2, cv::LINE_AA);
        cv::putText(img, s.name, {lx + 10, ly + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 0, 0}, 1, cv::LINE_AA);
        lx += 10 + tw + 24;
    }
    return img;
}

cv::Scalar methodColour(Method m) {
    switch (m) {
    case Method::Fov: return {40, 40, 220};
    case Method::FovTaa: return {40, 160, 40};
    case Method::WrsPaper: return {150, 150, 150};
    case Method::Wrs: return {200, 90, 20};
    case Method::Oracle: return {170, 40, 170};
    case Method::OracleQ: return {120, 170, 230};
    case Method::Taau: return {20, 200, 200};
    case Method::TaauSimple: return {120, 200, 240};
    }
    return {0, 0, 0};
}

}  // namespace wrsfov::eval
