// FovVideoVDP on the GPU (eval/fvvdp_gpu.h): the parameter block of its passes and their push
// constants, shared by C++ and GLSL (std140 uniform buffer; 16-byte rows, explicit padding; the C++
// side checks the sizes). The passes mirror the steps of fvvdp::detail (eval/fvvdp.h).
#ifndef WRSFOV_FVVDP_PARAMS_H
#define WRSFOV_FVVDP_PARAMS_H

#include "glsl_cpp.h"

// Gaussian levels stored: the image and one per band below it. 16 levels reach 2^16 pixels a side,
// beyond any view the metric is given (it stops at the first band at or below 0.5 cpd anyway).
#define FVVDP_MAX_LEVELS 16
// Samples per axis of the CSF table (fvvdp::detail::kCsfN).
#define FVVDP_CSF_N 32
// 8x8 invocations per group: one band pixel each; a group's 64 partial sums are reduced in shared
// memory to one value per temporal channel, which keeps the read-back to 1/32 of a float per pixel.
#define FVVDP_GROUP 8
// The per-quad passes (display, temporal; four pixels per invocation): 1-D groups of 64, the same
// lanes as an 8x8 group; laid out in x then y, x at most 32768 groups (the limit is 65535).
#define FVVDP_QUAD_GROUP 64
#define FVVDP_QUAD_GROUPS_X 32768

WRS_BEGIN

struct FvvdpParams {
    uvec4 image;    // x: width, y: height, z: filter length N (frames), w: quads (groups of 4 pixels, row-major)
    vec4 display;   // x: peak, y: black (cd/m²), z: sensitivity correction as a gain, w: pad
    vec4 fov_tan;   // tangents left, right, up, down (ViewGeometry::fov_tan)
    vec4 gaze;      // xy: gaze tangents of this frame, z: ppd at the optical axis, w: pad
    vec4 mask;      // x: mask_p, y: 10^mask_c, z: mask_q_sust, w: mask_q_trans
    vec4 pool;      // x: beta (spatial pooling), yzw: pad
    vec4 csf_axes;  // log2 of the CSF table's luminance range (x, y) and frequency range (z, w)
    vec4 csf_ecc;   // x: sqrt of the table's largest eccentricity, yzw: pad
    // Per Gaussian level l: x, y: size; z: first texel (vec4: test and reference, sustained and
    // transient) in the pyramid buffer; w: first float of band l's partial sums (2 per group).
    uvec4 level[FVVDP_MAX_LEVELS];
    // Per band l: x: frequency at the optical axis (cpd), y: contrast gain (1 finest, 2 others), zw: pad.
    vec4 band[FVVDP_MAX_LEVELS];
};

// Push constants of every pass: x: the level (reduce: the source level; band: the band), y: the
// window slot of the newest frame (display: the slot written), z: frames pushed including this one, w: pad.
struct FvvdpPush {
    uvec4 at;
};

WRS_END

#ifdef __cplusplus
static_assert(sizeof(wrsfov::gpu::FvvdpParams) == 8 * 16 + 2 * 16 * FVVDP_MAX_LEVELS);
static_assert(sizeof(wrsfov::gpu::FvvdpPush) == 16);
#endif

#endif
