#include "gaze/angles.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <numbers>

namespace wrsfov::gaze {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}

std::string_view event_name(Event e) {
    switch (e) {
        case Event::Fixation:
            return "fixation";
        case Event::Saccade:
            return "saccade";
        case Event::Microsaccade:
            return "microsaccade";
        case Event::Drift:
            return "drift";
        case Event::Blink:
            return "blink";
        case Event::Pursuit:
            return "pursuit";
        case Event::Unknown:
            break;
    }
    return "unknown";
}

std::optional<Event> parse_event(std::string_view name) {
    for (int i = 0; i <= static_cast<int>(Event::Unknown); ++i) {
        Event e = static_cast<Event>(i);
        std::string_view n = event_name(e);
        if (name.size() != n.size()) continue;
        bool same = true;
        for (size_t k = 0; k < n.size(); ++k) {
            char c = name[k];
            if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
            if (c != n[k]) same = false;
        }
        if (same) return e;
    }
    return std::nullopt;
}

glm::vec3 direction_from_angle(GazeAngle a) {
    const double az = a.az_deg * kDeg, el = a.el_deg * kDeg;
    return glm::vec3(static_cast<float>(std::sin(az) * std::cos(el)), static_cast<float>(std::sin(el)),
                     static_cast<float>(-std::cos(az) * std::cos(el)));
}

GazeAngle angle_from_direction(const glm::vec3& dir) {
    const double x = dir.x, y = dir.y, z = dir.z;
    const double horiz = std::sqrt(x * x + z * z);
    if (horiz == 0 && y == 0) return {};
    return {std::atan2(x, -z) / kDeg, std::atan2(y, horiz) / kDeg};
}

double angle_between_deg(const glm::vec3& a, const glm::vec3& b) {
    // atan2 of |a x b| and a.b keeps precision for the arc-minute angles microsaccades need.
    const glm::dvec3 da(a), db(b);
    return std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db)) / kDeg;
}

bool cyclopean_direction(const GazeSample& s, glm::vec3& out) {
    glm::dvec3 sum(0);
    int n = 0;
    for (const EyeGaze& e : s.eye) {
        if (!e.valid) continue;
        sum += glm::dvec3(e.dir);
        ++n;
    }
    const double len = glm::length(sum);
    if (n == 0 || !(len > 0)) return false;
    out = glm::vec3(sum / len);
    return true;
}

GazeSample sample_from_angle(double t_s, GazeAngle a, bool valid, Event label) {
    GazeSample s;
    s.t_s = t_s;
    s.label = label;
    const glm::vec3 d = direction_from_angle(a);
    for (EyeGaze& e : s.eye) {
        e.dir = d;
        e.valid = valid;
        e.confidence = valid ? 1.f : 0.f;
    }
    return s;
}

}  // namespace wrsfov::gaze
