// Gaze samples: what every gaze source produces and every consumer reads.
#pragma once

#include <cstdint>
#include <glm/vec3.hpp>
#include <optional>
#include <string_view>

namespace wrsfov::gaze {

/// Eye-movement event a sample belongs to. Synthetic data carries the true label; recorded data
/// is `Unknown` unless the file says otherwise.
enum class Event : uint8_t { Fixation, Saccade, Microsaccade, Drift, Blink, Pursuit, Unknown };

/// One eye's gaze: a unit direction in that eye's space (OpenXR: -Z forward, +Y up, +X right).
struct EyeGaze {
    glm::vec3 dir{0, 0, -1};
    bool valid = false;
    float confidence = 0;  ///< 0..1, as reported by the tracker (1 for synthetic valid samples)
};

/// Both eyes at one instant. `t_s` is in the source's own time line (seconds).
struct GazeSample {
    double t_s = 0;
    EyeGaze eye[2];  ///< [0] left, [1] right
    Event label = Event::Unknown;
};

/// Index of the left and right eye in `GazeSample::eye`.
inline constexpr int kLeft = 0;
inline constexpr int kRight = 1;

/// Lower-case name of an event ("fixation", "saccade", ...), as written in gaze files.
std::string_view event_name(Event e);

/// Inverse of `event_name`; also accepts the first letter's upper-case form. Empty on unknown text.
std::optional<Event> parse_event(std::string_view name);

}  // namespace wrsfov::gaze
