// Parameters of the compose pass (shaders/compose.comp), shared by C++ and GLSL (std140 uniform
// buffer): per eye, where the submitted quad views or rate map are and how they map to the output.
// 16-byte rows only, explicit padding; the C++ side checks the size.
#ifndef WRSFOV_COMPOSE_PARAMS_H
#define WRSFOV_COMPOSE_PARAMS_H

#include "glsl_cpp.h"

WRS_BEGIN

struct ComposeEye {
    vec4 wide_map;      // output pixel -> wide view pixel: xy scale, zw offset (wrs_source_pos)
    vec4 inset_map;     // output pixel -> inset pixel, likewise
    uvec4 sizes;        // xy: the wide view's colour size; zw: the inset's
    uvec4 wide_color;   // xy: offset of the wide view in its colour image; z: how it is read (WRS_INPUT_*); w: pad
    uvec4 inset_color;  // the same for the inset
    uvec4 offsets;      // xy: wide depth offset, zw: wide motion offset
    uvec4 inset_offsets;  // xy: inset depth offset, zw: inset motion offset
    vec4 wide_motion;   // xyz: a wide motion texel to output pixels (MotionInfo::scale times output px per
                        // wide px on x, y); w: q_wide, the wide view's quality (density ratio squared)
    vec4 inset_motion;  // xyz: the same for the inset; w: 1 / the blend width in inset pixels (0: hard edge)
    uvec4 rate;         // rate map: xy offset of the map in its image; zw: pixels per texel
    vec4 landed;        // landed wide samples (wrs_landed_offset): xy: output pixels per wide pixel
                        // (1 / wide_map.xy); z: 1 where they are offered to retention, 2 where the
                        // wide samples are gathered for method taau instead; w: taau's 1 / r^2
};

struct ComposeParams {
    ComposeEye eye[2];
    uvec4 size;  // xy: output size per eye; zw: pad
};

WRS_END

#ifdef __cplusplus
static_assert(sizeof(wrsfov::gpu::ComposeEye) == 176);
static_assert(sizeof(wrsfov::gpu::ComposeParams) == 2 * 176 + 16);
#endif

#endif
