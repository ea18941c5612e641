#include "gaze/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gaze/detect.h"

namespace wrsfov::gaze {

namespace {

cv::Scalar colour(Event e) {  // BGR
    switch (e) {
        case Event::Fixation:
            return {180, 120, 40};
        case Event::Saccade:
            return {40, 40, 220};
        case Event::Microsaccade:
            return {0, 160, 255};
        case Event::Drift:
            return {140, 140, 40};
        case Event::Blink:
            return {160, 160, 160};
        case Event::Pursuit:
            return {60, 170, 60};
        case Event::Unknown:
            break;
    }
    return {90, 90, 90};
}

// A "nice" grid step for a span.
double grid_step(double span) {
    const double raw = span / 8;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * p >= raw) return m * p;
    return 10 * p;
}

struct Frame {
    cv::Rect area;
    double x0, x1, y0, y1;
    cv::Point map(double x, double y) const {
        const double fx = (x - x0) / (x1 - x0), fy = (y - y0) / (y1 - y0);
        return {area.x + static_cast<int>(std::lround(fx * area.width)),
                area.y + area.height - static_cast<int>(std::lround(fy * area.height))};
    }
};

void axes(cv::Mat& img, const Frame& f, const std::string& xlabel, const std::string& ylabel,
          const std::string& title) {
    const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);
    char b[32];
    const double sx = grid_step(f.x1 - f.x0), sy = grid_step(f.y1 - f.y0);
    for (double x = std::ceil(f.x0 / sx) * sx; x <= f.x1 + 1e-9; x += sx) {
        cv::line(img, f.map(x, f.y0), f.map(x, f.y1), grid, 1);
        std::snprintf(b, sizeof b, "%g", std::abs(x) < 1e-12 ? 0.0 : x);
        cv::putText(img, b, f.map(x, f.y0) + cv::Point(-10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    }
    for (double y = std::ceil(f.y0 / sy) * sy; y <= f.y1 + 1e-9; y += sy) {
        cv::line(img, f.map(f.x0, y), f.map(f.x1, y), grid, 1);
        std::snprintf(b, sizeof b, "%g", std::abs(y) < 1e-12 ? 0.0 : y);
        cv::putText(img, b, f.map(f.x0, y) + cv::Point(-45, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, ink, 1, cv::LINE_AA);
    }
    cv::rectangle(img, f.area, ink, 1);
    cv::putText(img, xlabel, {f.area.x + f.area.width / 2 - 60, f.area.y + f.area.height + 40},
                cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
    cv::putText(img, ylabel, {8, f.area.y - 10}, cv::FONT_HERSHEY_SIMPLEX, 0.5, ink, 1, cv::LINE_AA);
    cv::putText(img, title, {f.area.x + f.area.width / 2 - 150, 24}, cv::FONT_HERSHEY_SIMPLEX, 0.6, ink, 1,
                cv::LINE_AA);
}

void legend(cv::Mat& img, cv::Point at) {
    for (Event e : {Event::Fixation, Event::Drift, Event::Microsaccade, Event::Saccade, Event::Pursuit, Event::Blink,
                    Event::Unknown}) {
        cv::line(img, at, at + cv::Point(18, 0), colour(e), 3);
        cv::putText(img, std::string(event_name(e)), at + cv::Point(24, 5), cv::FONT_HERSHEY_SIMPLEX, 0.4, {40, 40, 40},
                    1, cv::LINE_AA);
        at.x += 135;
    }
}

Status save(const std::string& path, const cv::Mat& img) {
    try {
        if (!cv::imwrite(path, img)) return fail("cannot write PNG '" + path + "'");
    } catch (const cv::Exception& e) {
        return fail("cannot write PNG '" + path + "': " + e.what());
    }
    return Ok{};
}

Status check(std::span<const GazeSample> samples, const PlotOptions& o) {
    if (samples.empty()) return fail("nothing to plot: no samples");
    if (o.width < 200 || o.height < 150 || o.width > 10000 || o.height > 10000)
        return fail("plot size must be 200x150 .. 10000x10000");
    return Ok{};
}

}  // namespace

Status write_scanpath_png(const std::string& path, std::span<const GazeSample> samples, const PlotOptions& o) {
    if (Status s = check(samples, o); !s) return s;
    const AngleTrace tr = to_angle_trace(samples);
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (size_t i = 0; i < tr.size(); ++i) {
        if (!tr.valid[i]) continue;
        x0 = std::min(x0, tr.az_deg[i]);
        x1 = std::max(x1, tr.az_deg[i]);
        y0 = std::min(y0, tr.el_deg[i]);
        y1 = std::max(y1, tr.el_deg[i]);
    }
    if (x0 > x1) return fail("nothing to plot: no valid samples");
    // Square degrees and a margin; at least 1 degree across so fixational movements show.
    const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    const cv::Rect area(70, 40, o.width - 100, o.height - 110);
    double half_w = std::max(0.5, 0.55 * (x1 - x0)), half_h = std::max(0.5, 0.55 * (y1 - y0));
    const double aspect = static_cast<double>(area.width) / area.height;
    if (half_w / half_h < aspect)
        half_w = half_h * aspect;
    else
        half_h = half_w / aspect;
    const Frame f{area, cx - half_w, cx + half_w, cy - half_h, cy + half_h};
    cv::Mat img(o.height, o.width, CV_8UC3, cv::Scalar(255, 255, 255));
    axes(img, f, "azimuth (deg)", "elevation (deg)", "scanpath (" + std::to_string(samples.size()) + " samples)");
    for (size_t i = 1; i < tr.size(); ++i) {
        if (!tr.valid[i] || !tr.valid[i - 1]) continue;
        cv::line(img, f.map(tr.az_deg[i - 1], tr.el_deg[i - 1]), f.map(tr.az_deg[i], tr.el_deg[i]),
                 colour(samples[i].label), 1, cv::LINE_AA);
    }
    legend(img, {area.x, o.height - 20});
    return save(path, img);
}

Status write_velocity_png(const std::string& path, std::span<const GazeSample> samples, const PlotOptions& o) {
    if (Status s = check(samples, o); !s) return s;
    const AngleTrace tr = to_angle_trace(samples);
    const Velocity v = velocity_5pt(tr);
    const double t_begin = tr.t_s.front();
    double t_end = tr.t_s.back();
    if (o.max_seconds > 0) t_end = std::min(t_end, t_begin + o.max_seconds);
    if (!(t_end > t_begin)) t_end = t_begin + 1;
    double vmax = o.threshold_deg_s * 1.5;
    for (size_t i = 0; i < tr.size() && tr.t_s[i] <= t_end; ++i)
        if (v.vvalid[i]) vmax = std::max(vmax, std::hypot(v.vx[i], v.vy[i]));
    const cv::Rect area(70, 40, o.width - 100, o.height - 110);
    const Frame f{area, 0, t_end - t_begin, 0, vmax * 1.05};
    cv::Mat img(o.height, o.width, CV_8UC3, cv::Scalar(255, 255, 255));
    axes(img, f, "time (s)", "speed (deg/s)", "gaze speed, 5-sample velocity");
    cv::Point prev;
    bool have_prev = false;
    for (size_t i = 0; i < tr.size() && tr.t_s[i] <= t_end; ++i) {
        if (!v.vvalid[i]) {
            have_prev = false;
            continue;
        }
        const cv::Point p = f.map(tr.t_s[i] - t_begin, std::hypot(v.vx[i], v.vy[i]));
        if (have_prev) cv::line(img, prev, p, colour(samples[i].label), 1, cv::LINE_AA);
        prev = p;
        have_prev = true;
    }
    // Dashed threshold line.
    for (double t = 0; t < t_end - t_begin; t += (t_end - t_begin) / 120)
        cv::line(img, f.map(t, o.threshold_deg_s),
                 f.map(std::min(t + (t_end - t_begin) / 240, t_end - t_begin), o.threshold_deg_s), {0, 0, 0}, 1);
    legend(img, {area.x, o.height - 20});
    return save(path, img);
}

}  // namespace wrsfov::gaze
