// What an application submitted, normalised for the passes: how the frame was foveated before it was
// submitted (a full-resolution frame, quad views, a shading-rate map), the size of the output, the
// compose pass's parameters and the floor quality of the frame's candidates. Pure functions of a
// validated frame (layers::FrameValidator), shared by the compositor and the CPU reference.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "layers/frame.h"
#include "shaders/compose_params.h"

namespace wrsfov {

/// How the passes read the colour of `s` (gpu::WRS_INPUT_LINEAR, WRS_INPUT_SRGB: a UNORM view of sRGB
/// codes, or WRS_INPUT_SRGB_VIEW: an sRGB view, decoded by the device): the compositor's swapchain
/// says which views it made (VulkanSwapchain::colorEncoding); any other swapchain is read by format.
uint32_t colorEncoding(const layers::SubImage& s);

/// The compose pass's parameters for a validated layer with quad views or rate maps (zero for a full
/// frame). `out`: the output size (layers::outputSize); `blendPx`: CompositorConfig::insetBlendPx.
gpu::ComposeParams makeComposeParams(const layers::ProjectionLayer& layer, glm::uvec2 out, float blendPx);

/// Quad views: the 8x8 groups of output pixels (compose.comp's) where the inset of `eye` may show, as
/// [x0, x1) x [y0, y1) in (x0, y0, x1, y1): every group with a pixel whose inset position is inside the
/// inset (wrs_inset_weight > 0), one pixel to spare on each side; empty (x0 == x1) where the inset is
/// off the output. The compose pass reads the inset in these groups only.
glm::uvec4 insetGroups(const gpu::ComposeEye& eye, glm::uvec2 out);

/// Quad views: the wide view's quality, (wide px/deg / inset px/deg)^2 over both axes (at the view's
/// centre, in tangent units), clamped to (0, 1].
float wideQuality(const layers::ProjectionView& view);

/// The lowest quality a submitted frame's candidates can have, which the floor rule treats as the
/// far periphery (wrs_retain): the smaller wide quality of the two eyes for quad views, a 4x4 rate
/// (WRS_RATE_FLOOR) for rate maps; 0 for a full frame.
float submittedFloor(const layers::ProjectionLayer& layer);

}  // namespace wrsfov
