// Conversions between gaze angles and eye-space directions.
#pragma once

#include <glm/vec3.hpp>

#include "gaze/sample.h"

namespace wrsfov::gaze {

/// A gaze angle in degrees: azimuth positive to the right, elevation positive up, (0, 0) straight
/// ahead. Rotation order: azimuth about +Y, then elevation (Fick gimbal), so that
/// `dir = (sin az cos el, sin el, -cos az cos el)` in OpenXR eye space.
struct GazeAngle {
    double az_deg = 0;
    double el_deg = 0;
};

/// Unit eye-space direction of a gaze angle.
glm::vec3 direction_from_angle(GazeAngle a);

/// Gaze angle of a direction (need not be unit length; the zero vector gives (0, 0)).
GazeAngle angle_from_direction(const glm::vec3& dir);

/// Angle between two directions in degrees, robust for tiny angles.
double angle_between_deg(const glm::vec3& a, const glm::vec3& b);

/// The cyclopean direction of a sample: the normalised mean of the valid eyes. False if neither
/// eye is valid.
bool cyclopean_direction(const GazeSample& s, glm::vec3& out);

/// A sample with both eyes looking along `a` (the generator's and screen trackers' mapping).
GazeSample sample_from_angle(double t_s, GazeAngle a, bool valid, Event label = Event::Unknown);

}  // namespace wrsfov::gaze
