// The steady floor: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_FLOOR_H
#define WRSFOV_WRS_FLOOR_H

#include "glsl_cpp.h"
#include "config.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// The steady floor (docs/retention.md "The steady floor"): the floor level's texels (level 4, one
// per 16x16 pixels), filtered over time as TAA filters pixels, for the retention methods whose floor
// rule takes the candidate there. Without it the far periphery shows each frame's 16x16 box averages,
// which crawl as content moves under them; the merge at the floor smoothed that at the price of
// retention in every far tile. Filtering 1/256 of the pixels steadies it as much; FovVideoVDP scores
// both smoothings lower than neither, so it is an option (CompositorConfig::steadyFloor).
// ---------------------------------------------------------------------------------------------

const uint WRS_STEADY_LEVEL = 4u;  // the floor level of `mip` and `gauss` (quality 1/256)
// Weight of the current texel. Atrium lateral at 512x384 (150 frames, fovea 5 deg, `mip`): temporal
// instability 0.00116 unfiltered, 0.00082 / 0.00074 / 0.00066 / 0.00060 at 0.4 / 0.25 / 0.15 / 0.1,
// near-gaze PSNR -0.013 / -0.018 / -0.022 / -0.026 dB (with bilinear resampling of the history, where
// level 4 is seen within 10 deg of the gaze); 0.25 keeps that within 0.02 dB.
const float WRS_STEADY_ALPHA = 0.25f;

// First texel of an eye's level 4 in slot `slot` (0 or 1) of the steady history, which follows both
// eyes' stored pyramids in the pyramid buffer; `l4` is level 4's row of FrameParams::levels.
WRS_FN uint wrs_steady_offset(uvec4 l4, uint slot, uint eye) { return 2u * l4.w + (slot * 2u + eye) * (l4.x * l4.y); }
// The pixel whose motion moves level-4 texel d: the centre of its 16x16 block, clamped to the image.
WRS_FN uvec2 wrs_steady_motion_pixel(uvec2 d, uvec2 size0) {
    uint s = 1u << WRS_STEADY_LEVEL;
    return min(d * s + uvec2(s / 2u, s / 2u), size0 - uvec2(1u, 1u));
}
// Catmull-Rom weights of the taps at -1, 0, 1, 2 for a sample at fraction f in [0, 1) past tap 0:
// the history's resampling. A bilinear one blurs by f(1 - f) texels^2 each frame (0.02 at a slow
// pan's 0.02 texels a frame), which the filter accumulates over its ~1/alpha frames into a blur of a
// quarter texel (4 pixels) on top of the 16x16 box; Catmull-Rom's blur at that f is ~30 times less.
WRS_FN vec4 wrs_catmull_rom(float f) {
    WRS_PRECISE float f2 = f * f, f3 = f2 * f;
    WRS_PRECISE vec4 w = vec4(-0.5f * f3 + f2 - 0.5f * f, 1.5f * f3 - 2.5f * f2 + 1.0f,
                              -1.5f * f3 + 2.0f * f2 + 0.5f * f, 0.5f * f3 - 0.5f * f2);
    return w;
}
// Tap k (each axis 0..3, for -1..2) of the 4x4 Catmull-Rom footprint at i0, clamped to the image.
WRS_FN uvec2 wrs_cubic_tap(uvec2 i0, ivec2 k, uvec2 size) {
    return uvec2(clamp(ivec2(i0) + k - ivec2(1, 1), ivec2(0, 0), ivec2(size) - ivec2(1, 1)));
}
// A pixel's motion in level-4 texels (the depth change is not used).
WRS_FN vec3 wrs_steady_motion(vec3 mv) {
    const float s = 0.0625f;  // 1 / 2^WRS_STEADY_LEVEL
    return vec3(mv.x * s, mv.y * s, 0.0f);
}

WRS_END

#endif
