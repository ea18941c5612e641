// Eye tracker reports (HID usage page 0x12): where the fields are, what they mean in µm and µs,
// and how a gaze point on the calibrated screen becomes a direction per eye.
#pragma once

#include <array>
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <optional>
#include <span>

#include "gaze/hid_descriptor.h"
#include "gaze/result.h"
#include "gaze/sample.h"

namespace wrsfov::gaze::hid {

/// One value in a report: a field and its element. `elements` > 1 for a value sent as several
/// consecutive elements of the same usage (e.g. a 64-bit timestamp as 8 one-byte elements,
/// little-endian).
struct ValueRef {
    int field = -1;
    uint32_t index = 0;
    uint32_t elements = 1;
    bool found() const { return field >= 0; }
};

/// Where an eye tracker's values are.
struct EyeTrackerLayout {
    uint8_t tracking_report_id = 0;  ///< input report carrying the gaze point
    ValueRef timestamp;              ///< Sensor Timestamp (optional)
    ValueRef gaze[2];                ///< Gaze Point X, Y
    ValueRef eye_pos[2][3];          ///< [left/right][X, Y, Z] (optional)
    ValueRef quality;                ///< Tracker Quality (optional)
    uint8_t screen_report_id = 0;    ///< feature report with the calibrated screen size
    ValueRef screen_width, screen_height;
};

/// Finds the Tracking Data input report with a Gaze Point (Position X/Y inside a Gaze Point
/// collection, or a Gaze Point field of at least two elements), and the optional timestamp, eye
/// positions, quality and Calibrated Screen Width/Height feature.
Result<EyeTrackerLayout> find_eye_tracker(const ReportDescriptor& d);

/// A decoded Tracking Data report.
struct TrackingData {
    uint8_t report_id = 0;
    std::optional<double> timestamp_us;
    glm::dvec2 gaze_um{0};                ///< from the top-left of the calibrated screen, y down
    bool gaze_valid = true;               ///< false when a value is outside its logical range (HID null)
    std::optional<glm::dvec3> eye_um[2];  ///< left, right; same frame, z towards the user; empty if null
    std::optional<double> quality;
};

/// Decodes one input report as read from hidraw (with the ID byte when the descriptor uses IDs).
Result<TrackingData> decode_tracking(const ReportDescriptor& d, const EyeTrackerLayout& layout,
                                     std::span<const uint8_t> report);

/// Calibrated screen size in micrometres.
struct ScreenSize {
    double width_um = 0, height_um = 0;
};

/// Decodes the Calibrated Screen Width/Height feature report.
Result<ScreenSize> decode_screen(const ReportDescriptor& d, const EyeTrackerLayout& layout,
                                 std::span<const uint8_t> report);

/// The viewer when the tracker sends no eye positions: eyes this far from the screen, centred on
/// it, this far apart.
struct ViewerDefaults {
    double distance_um = 650'000;
    double ipd_um = 63'000;
};

/// Per-eye directions towards a gaze point, with eye-space axes parallel to the screen (+X right,
/// +Y up, -Z into the screen). Invalid eyes where the geometry is impossible (eye on or behind the
/// screen plane, non-finite values).
std::array<EyeGaze, 2> eyes_from_gaze_point(const TrackingData& t, const ScreenSize& screen,
                                            const ViewerDefaults& viewer = {});

/// Multiplier that turns a field's physical value into micrometres (or an error if its unit is
/// not a length). Fields without a unit are micrometres, as the usage table defines them.
Result<double> length_to_um(const Field& f);
/// Multiplier to microseconds (or an error if the unit is not a time). No unit: microseconds.
Result<double> time_to_us(const Field& f);

}  // namespace wrsfov::gaze::hid
