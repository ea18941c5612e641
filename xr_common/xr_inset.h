// Quad views (XR_VARJO_quad_views, XR_VARJO_foveated_rendering) as the simulated HMD offers them: the
// recommended sizes of the wide views and the insets, and where an inset goes in its wide view. Pure
// functions of the configuration, shared by the runtime and the API layer.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "layers/frame.h"
#include "xr_common/xr_config.h"

namespace wrsfov::xr {

/// The wide views' pixel density against the display's: 1 / 2.5 on each axis (the Varjo example's
/// context-to-focus ratio), so a wide view has 1 / 6.25 of the display's pixels.
constexpr float kWideDensity = 1.0f / 2.5f;

struct QuadViewSizes {
    glm::uvec2 wide{0, 0};   ///< views 0, 1: the display's size x kWideDensity, rounded
    glm::uvec2 inset{0, 0};  ///< views 2, 3: the inset's field of view at the display's density, rounded
};
/// Recommended image sizes of the four views for the display `config` describes (eye 0's field of
/// view sets the density; both eyes' insets have the same size).
QuadViewSizes quadViewSizes(const RuntimeConfig& config);

/// The inset's half extent in tangent units on each axis: tan(insetDeg / 2), at most half the view's.
glm::vec2 insetHalfTangent(const layers::Fov& view, float insetDeg);

/// The inset's field of view inside `view`: centred on `gaze` (a direction in the eye's space, -Z
/// forward) or, without one (nullopt, or a direction not in front of the eye), on the view's centre
/// in tangent space, which is where the compositor's fallback fovea goes; shifted at the view's edges
/// so that it never leaves the view. Its extent in tangent units is the same wherever it goes, so an
/// image of the recommended inset size has the display's density everywhere.
layers::Fov insetFov(const layers::Fov& view, float insetDeg, std::optional<glm::vec3> gaze);

}  // namespace wrsfov::xr
