#include "gaze/hid_eyetracker.h"

#include <cmath>
#include <glm/geometric.hpp>
#include <string>

namespace wrsfov::gaze::hid {

namespace {

int nibble(uint32_t unit, int i) {
    const int v = static_cast<int>((unit >> (4 * i)) & 0xF);
    return v >= 8 ? v - 16 : v;
}

// Walks the collection chain of a field, innermost first, for the first usage on page 0x12
// that is one of `wanted`.
uint16_t enclosing(const ReportDescriptor& d, const Field& f, std::initializer_list<uint16_t> wanted) {
    for (uint32_t u : d.collection_path(f)) {
        if (usage_page(u) != eye::kPage) continue;
        for (uint16_t w : wanted)
            if (usage_id(u) == w) return w;
    }
    return 0;
}

// Number of consecutive elements from `i` with the same usage (a multi-byte value).
uint32_t run_length(const Field& f, uint32_t i) {
    uint32_t n = 1;
    while (i + n < f.count && f.usage_at(i + n) == f.usage_at(i)) ++n;
    return n;
}

// A value outside the logical range is HID's "null" (no measurement, e.g. eyes not found).
Result<double> read_value(const ReportDescriptor& d, const ValueRef& r, std::span<const uint8_t> payload,
                          bool* null_value = nullptr) {
    const Field& f = d.fields[static_cast<size_t>(r.field)];
    if (r.elements == 1) {
        auto raw = read_raw(f, r.index, payload);
        if (!raw) return raw.error();
        if (null_value && f.logical_min < f.logical_max && (*raw < f.logical_min || *raw > f.logical_max))
            *null_value = true;
        return to_physical(f, *raw);
    }
    // Several elements of one usage: a little-endian integer made of the elements.
    if (uint64_t{f.bit_size} * r.elements > 64) return fail("multi-element value wider than 64 bits");
    uint64_t v = 0;
    for (uint32_t k = 0; k < r.elements; ++k) {
        Field part = f;
        part.logical_min = 0;  // the parts are unsigned digits
        auto raw = read_raw(part, r.index + k, payload);
        if (!raw) return raw.error();
        v |= (static_cast<uint64_t>(*raw) & ((f.bit_size >= 64) ? ~uint64_t{0} : ((uint64_t{1} << f.bit_size) - 1)))
             << (f.bit_size * k);
    }
    return static_cast<double>(v);
}

}  // namespace

Result<double> length_to_um(const Field& f) {
    const double e = std::pow(10.0, f.unit_exponent);
    if (f.unit == 0) return e;
    const uint32_t sys = f.unit & 0xF;
    bool only_length = nibble(f.unit, 1) == 1;
    for (int i = 2; i < 8; ++i) only_length = only_length && nibble(f.unit, i) == 0;
    if (only_length && sys == 1) return 1e4 * e;     // centimetres
    if (only_length && sys == 3) return 25'400 * e;  // inches
    return fail("field " + usage_name(f.usage_at(0)) + " has unit " + unit_name(f.unit) + ", which is not a length");
}

Result<double> time_to_us(const Field& f) {
    const double e = std::pow(10.0, f.unit_exponent);
    if (f.unit == 0) return e;
    const uint32_t sys = f.unit & 0xF;
    bool only_time = nibble(f.unit, 3) == 1;
    for (int i : {1, 2, 4, 5, 6, 7}) only_time = only_time && nibble(f.unit, i) == 0;
    if (only_time && sys >= 1 && sys <= 4) return 1e6 * e;  // seconds in every system
    return fail("field " + usage_name(f.usage_at(0)) + " has unit " + unit_name(f.unit) + ", which is not a time");
}

Result<EyeTrackerLayout> find_eye_tracker(const ReportDescriptor& d) {
    EyeTrackerLayout L;
    bool have_report = false;
    // Pass 1: the input report with a gaze point.
    for (size_t fi = 0; fi < d.fields.size() && !have_report; ++fi) {
        const Field& f = d.fields[fi];
        if (f.type != ReportType::Input || !f.is_variable()) continue;
        for (uint32_t i = 0; i < f.count; ++i) {
            const uint32_t u = f.usage_at(i);
            if (usage_page(u) != eye::kPage) continue;
            const bool in_gaze = enclosing(d, f, {eye::kGazePoint}) == eye::kGazePoint;
            if ((usage_id(u) == eye::kPositionX && in_gaze) || (usage_id(u) == eye::kGazePoint && f.count - i >= 2)) {
                have_report = true;
                L.tracking_report_id = f.report_id;
                break;
            }
        }
    }
    if (!have_report)
        return fail(
            "no input report with a Gaze Point (usage page 0x12: Position X/Y in a Gaze Point collection, "
            "or Gaze Point itself) in the descriptor: not an eye tracker");
    for (size_t fi = 0; fi < d.fields.size(); ++fi) {
        const Field& f = d.fields[fi];
        if (!f.is_variable()) continue;
        const int idx = static_cast<int>(fi);
        if (f.type == ReportType::Feature) {
            for (uint32_t i = 0; i < f.count; ++i) {
                const uint32_t u = f.usage_at(i);
                if (usage_page(u) != eye::kPage) continue;
                if (usage_id(u) == eye::kCalibratedScreenWidth && !L.screen_width.found()) {
                    L.screen_width = {idx, i, 1};
                    L.screen_report_id = f.report_id;
                } else if (usage_id(u) == eye::kCalibratedScreenHeight && !L.screen_height.found()) {
                    L.screen_height = {idx, i, 1};
                }
            }
            continue;
        }
        if (f.type != ReportType::Input || f.report_id != L.tracking_report_id) continue;
        const uint16_t group = enclosing(d, f, {eye::kGazePoint, eye::kLeftEyePosition, eye::kRightEyePosition});
        for (uint32_t i = 0; i < f.count; ++i) {
            const uint32_t u = f.usage_at(i);
            if (usage_page(u) != eye::kPage) continue;
            const uint16_t id = usage_id(u);
            if (id == eye::kSensorTimestamp && !L.timestamp.found()) {
                const uint32_t n = run_length(f, i);
                L.timestamp = {idx, i, n};
                i += n - 1;
            } else if (id == eye::kTrackerQuality && !L.quality.found()) {
                L.quality = {idx, i, 1};
            } else if (id >= eye::kPositionX && id <= eye::kPositionZ) {
                const int axis = id - eye::kPositionX;
                if (group == eye::kGazePoint && axis < 2 && !L.gaze[axis].found()) L.gaze[axis] = {idx, i, 1};
                if (group == eye::kLeftEyePosition && !L.eye_pos[0][axis].found()) L.eye_pos[0][axis] = {idx, i, 1};
                if (group == eye::kRightEyePosition && !L.eye_pos[1][axis].found()) L.eye_pos[1][axis] = {idx, i, 1};
            } else if (id == eye::kGazePoint && f.count - i >= 2 && !L.gaze[0].found()) {
                L.gaze[0] = {idx, i, 1};
                L.gaze[1] = {idx, i + 1, 1};
                i += 1;
            } else if ((id == eye::kLeftEyePosition || id == eye::kRightEyePosition) && f.count - i >= 3) {
                const int e = id == eye::kLeftEyePosition ? 0 : 1;
                if (!L.eye_pos[e][0].found())
                    for (uint32_t k = 0; k < 3; ++k) L.eye_pos[e][k] = {idx, i + k, 1};
                i += 2;
            }
        }
    }
    if (!L.gaze[0].found() || !L.gaze[1].found())
        return fail("the Gaze Point of input report " + std::to_string(L.tracking_report_id) +
                    " lacks Position X or Y");
    // Check units once here so that decoding cannot meet a non-length gaze point.
    for (const ValueRef& r : L.gaze)
        if (auto s = length_to_um(d.fields[static_cast<size_t>(r.field)]); !s) return s.error();
    for (auto& eye : L.eye_pos) {
        const bool complete = eye[0].found() && eye[1].found() && eye[2].found();
        if (!complete) eye[0] = eye[1] = eye[2] = ValueRef{};
        for (const ValueRef& r : eye)
            if (r.found())
                if (auto s = length_to_um(d.fields[static_cast<size_t>(r.field)]); !s) return s.error();
    }
    if (L.timestamp.found())
        if (auto s = time_to_us(d.fields[static_cast<size_t>(L.timestamp.field)]); !s) return s.error();
    if (L.screen_width.found() != L.screen_height.found()) L.screen_width = L.screen_height = ValueRef{};
    if (L.screen_width.found() && d.fields[static_cast<size_t>(L.screen_height.field)].report_id != L.screen_report_id)
        L.screen_width = L.screen_height = ValueRef{};
    return L;
}

Result<TrackingData> decode_tracking(const ReportDescriptor& d, const EyeTrackerLayout& L,
                                     std::span<const uint8_t> report) {
    auto view = view_report(d, ReportType::Input, report);
    if (!view) return view.error();
    TrackingData t;
    t.report_id = view->id;
    if (view->id != L.tracking_report_id)
        return fail("input report " + std::to_string(view->id) + " is not the tracking report (" +
                    std::to_string(L.tracking_report_id) + ")");
    bool null_value = false;
    auto length = [&](const ValueRef& r) -> Result<double> {
        auto v = read_value(d, r, view->payload, &null_value);
        if (!v) return v.error();
        auto s = length_to_um(d.fields[static_cast<size_t>(r.field)]);
        if (!s) return s.error();
        return *v * *s;
    };
    for (int a = 0; a < 2; ++a) {
        auto v = length(L.gaze[a]);
        if (!v) return v.error();
        t.gaze_um[a] = *v;
    }
    t.gaze_valid = !null_value;
    for (int e = 0; e < 2; ++e) {
        if (!L.eye_pos[e][0].found()) continue;
        glm::dvec3 p;
        null_value = false;
        for (int a = 0; a < 3; ++a) {
            auto v = length(L.eye_pos[e][a]);
            if (!v) return v.error();
            p[a] = *v;
        }
        if (!null_value) t.eye_um[e] = p;
    }
    if (L.timestamp.found()) {
        auto v = read_value(d, L.timestamp, view->payload);
        if (!v) return v.error();
        auto s = time_to_us(d.fields[static_cast<size_t>(L.timestamp.field)]);
        if (!s) return s.error();
        t.timestamp_us = *v * *s;
    }
    if (L.quality.found()) {
        auto v = read_value(d, L.quality, view->payload);
        if (!v) return v.error();
        t.quality = *v;
    }
    return t;
}

Result<ScreenSize> decode_screen(const ReportDescriptor& d, const EyeTrackerLayout& L,
                                 std::span<const uint8_t> report) {
    if (!L.screen_width.found()) return fail("the descriptor has no Calibrated Screen Width/Height feature");
    auto view = view_report(d, ReportType::Feature, report);
    if (!view) return view.error();
    if (view->id != L.screen_report_id)
        return fail("feature report " + std::to_string(view->id) + " is not the screen report (" +
                    std::to_string(L.screen_report_id) + ")");
    ScreenSize s;
    for (int k = 0; k < 2; ++k) {
        const ValueRef& r = k == 0 ? L.screen_width : L.screen_height;
        auto v = read_value(d, r, view->payload);
        if (!v) return v.error();
        auto scale = length_to_um(d.fields[static_cast<size_t>(r.field)]);
        if (!scale) return scale.error();
        (k == 0 ? s.width_um : s.height_um) = *v * *scale;
    }
    if (!(s.width_um > 0 && s.height_um > 0))
        return fail("calibrated screen size " + std::to_string(s.width_um) + " x " + std::to_string(s.height_um) +
                    " um is not positive (tracker not calibrated?)");
    return s;
}

std::array<EyeGaze, 2> eyes_from_gaze_point(const TrackingData& t, const ScreenSize& screen,
                                            const ViewerDefaults& viewer) {
    std::array<EyeGaze, 2> out{};
    if (!t.gaze_valid) return out;
    const glm::dvec3 p(t.gaze_um.x, t.gaze_um.y, 0);
    for (int e = 0; e < 2; ++e) {
        glm::dvec3 eye;
        if (t.eye_um[e]) {
            eye = *t.eye_um[e];
        } else {
            const double side = e == 0 ? -0.5 : 0.5;
            eye = {0.5 * screen.width_um + side * viewer.ipd_um, 0.5 * screen.height_um, viewer.distance_um};
        }
        const glm::dvec3 v = p - eye;  // screen frame: x right, y down, z towards the user
        if (!(eye.z > 0) || !std::isfinite(glm::length(v)) || !(glm::length(v) > 0)) continue;
        const glm::dvec3 dir = glm::normalize(glm::dvec3(v.x, -v.y, v.z));
        out[static_cast<size_t>(e)].dir = glm::vec3(dir);
        out[static_cast<size_t>(e)].valid = true;
        out[static_cast<size_t>(e)].confidence = 1.f;
    }
    return out;
}

}  // namespace wrsfov::gaze::hid
