// The per-frame parameter block of every pass, shared by C++ and GLSL (std140 uniform buffer).
// 16-byte rows only, explicit padding; the C++ side checks the size.
#ifndef WRSFOV_WRS_PARAMS_H
#define WRSFOV_WRS_PARAMS_H

#include "glsl_cpp.h"
#include "config.h"

WRS_BEGIN

struct EyeParams {
    vec4 fov_tan;       // tan(angleLeft), tan(angleRight), tan(angleUp), tan(angleDown)
    vec4 gaze;          // xyz: unit gaze direction in eye space; w: fovea radius r_f in degrees
    uvec4 color_rect;   // x, y offset of the view in the colour image; z: 1 if sRGB-encoded; w: image layer
    uvec4 depth_rect;   // x, y offset in the depth image; z: 1 if reversed-Z; w: `wrs` merging every phase:
                        // the wide box's tap spacing (wrs_wide_box_steps); 0 otherwise
    uvec4 motion_rect;  // x, y offset in the motion image; z: WRS_LANDED_ON where the compose pass wrote
                        // landed samples (or taau's gathered ones), | WRS_LANDED_WEIGHTED where `wrs` weighs
                        // them by their overlap (landed weights); w: 1 where the views' sample offsets moved
    vec4 depth_range;   // near, far (may be +inf), zw: the weight cap and, for method taau-simple, the clip
                        // box (sigmas), for method taau the luma stability
    vec4 motion_scale;  // xyz: multiplies the motion texel (MotionInfo::scale; 1 without motion);
                        // w: the motion reach in pixels (wrs_within_reach; +inf: no limit)
    vec4 tile;          // the classification's view constants (wrs_tile_geometry): xy: a pixel's width
                        // and height on the image plane (tangent units); z: rho (degrees); w: quad views:
                        // the wide views' quality (taau: above it the inset shows; wrs merging every
                        // phase: up to it a candidate takes the wide box); 0 otherwise
    uvec4 ref_rect;     // evaluation only (the oracles with submitted foveation): x, y offset of the
                        // full-resolution reference in its image; z: its encoding (WRS_INPUT_*); w: layer
    uvec4 display;      // the steady display (frame.tuning.z > 0), and method taau's box: x, the spacing of
                        // the neighbourhood's taps (wrs_wide_box_steps: one wide pixel); y, the steady
                        // display's full speed (wrs_display_weight; a float's bits); zw: pad
    vec4 taau;          // method taau (wrs_taau_step): x, the still box in sigmas; y, the velocity (output pixels
                        // a frame) at which it is one sigma; z, the lock's frames; w, the lock's threshold
};

struct FrameParams {
    EyeParams eye[2];
    uvec4 size;    // x: width, y: height (both eyes), z: frame index, w: seed
    vec4 tuning;   // x: r_m (degrees), y: tau_depth (relative), z: the steady display's weight
                   // (wrs_display_fold_step; 0 where it does not run), w: the floor rule's quality (floorQuality)
    // Per pyramid level (wrs_level_size, wrs_level_offset, once per frame rather than per tap):
    // xy: size; z: first texel of the level in an eye's stored pyramid (levels 1.. only, so level 1
    // starts at 0); w: texels of an eye's stored pyramid.
    uvec4 levels[WRS_LEVELS];
    // Per pyramid level, xy: its size over level 0's (wrs_level_scale, worked out on the host so that the
    // bilinear weights are the same on every device); zw: pad.
    vec4 level_scale[WRS_LEVELS];
    // Sparse retention (wrs_common.h): x, y: first word of the previous and of this frame's held
    // qualities in TileHeld (one word per tile, eye-major); z: 1 when far tiles may skip retention;
    // w: first word of the superblocks' held qualities (wrs_reach_blocks; one word per superblock, eye-major).
    uvec4 held;
};

// Push constants of the pyramid pass: which level is being written.
struct LevelPush {
    uint level;
    uint pad0;
    uint pad1;
    uint pad2;
};

WRS_END

#ifdef __cplusplus
static_assert(sizeof(wrsfov::gpu::EyeParams) == 176);
static_assert(sizeof(wrsfov::gpu::FrameParams) == 2 * 176 + 32 + 2 * 16 * WRS_LEVELS + 16);
static_assert(sizeof(wrsfov::gpu::LevelPush) == 16);
#endif

#endif
