// Descriptor set 0, shared by the per-eye passes (pyramid, foveate, wrs, taa, retain). Each eye's
// images are bound as element [eye] of an array and indexed with gl_WorkGroupID.z (dynamically
// uniform). Level 0 and linear depth are never stored: every pass decodes the submitted images
// where it reads them (load_color, load_depth), which costs 4 B/px per reading pass instead of a
// 16 B/px write and read of a level-0 buffer.
#ifndef WRSFOV_BINDINGS_GLSL
#define WRSFOV_BINDINGS_GLSL

// Every pass: the device's fp16 conversion for storage, of values rounded to fp16's grid by hand, where
// the compositor found it exact on them (wrs_store_f16, Compositor::hardwareHalf).
layout(constant_id = 7) const bool HARDWARE_HALF = false;
#define WRS_HARDWARE_HALF HARDWARE_HALF
// Every pass: the birth colours of the stale-pixel evaluation are tracked (CompositorConfig::trackBirth,
// bindings 10 and 11). A constant rather than a uniform branch, so that passes without it carry none of
// its code or registers (the retain pass: 72 -> 60 VGPRs on ACO).
layout(constant_id = 8) const bool TRACK_BIRTH = false;
// Every pass that reads the submitted colour (load_color): how it is encoded (WRS_INPUT_*, the same for
// both eyes: EyeParams::color_rect.z), so that a pass carries the decoding of that encoding only, no sRGB
// table where the colour is linear or composed; WRS_INPUT_ANY where the eyes differ (each eye's own,
// read at run time).
layout(constant_id = 9) const uint INPUT_ENCODING = 4u;
#include "wrs_common.h"
#include "wrs_submitted.h"
#include "wrs_params.h"
#include "compose_params.h"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = 1) uniform sampler2D colorIn[2];   // RGBA8 (sRGB viewed as UNORM or sRGB), RGBA16F
layout(set = 0, binding = 2) uniform sampler2D depthIn[2];   // D32F / R32F, [0, 1]
layout(set = 0, binding = 3) uniform sampler2D motionIn[2];  // RG16F / RGBA16F, pixels (+ dz)
// Colour pyramid levels 1..WRS_LEVELS-1, linear RGB + alpha (wrs_pyramid_texel) as fp16 RGBA
// (wrs_f32_to_f16 each), eye-major then level-major (wrs_level_offset less level 0).
layout(std430, set = 0, binding = 4) buffer Pyramid { uvec2 pyramid[]; };
// Foveated candidate: linear RGB and its weight p̂ (0 when the input pixel was not finite).
layout(std430, set = 0, binding = 6) buffer Candidate { vec4 candidate[]; };
layout(std430, set = 0, binding = 7) readonly buffer ReservoirPrev { uvec4 res_prev[]; };
layout(std430, set = 0, binding = 8) writeonly buffer ReservoirCur { uvec4 res_cur[]; };
// Evaluation only (TRACK_BIRTH): the submitted linear colour when the shown sample was taken.
layout(std430, set = 0, binding = 10) readonly buffer BirthPrev { vec4 birth_prev[]; };
layout(std430, set = 0, binding = 11) writeonly buffer BirthCur { vec4 birth_cur[]; };
// Linear value of each 8-bit sRGB code (wrs_srgb8_table), written once by the compositor.
layout(std430, set = 0, binding = 12) readonly buffer SrgbTable { float srgb_table[256]; };
// Tiles (classify.comp): per class an indirect dispatch (x = its tiles, y = z = 1), then the
// classes' tile lists, class k at k * tile_capacity(): eye << 30 | ty << 15 | tx.
layout(std430, set = 0, binding = 13) buffer Tiles { uvec4 tile_args[WRS_TILE_LISTS]; uint tile_list[]; };
// Sparse retention: per tile and eye the best quality the tile stored (float bits; 0: nothing), the
// previous frame's at frame.held.x, this frame's at frame.held.y; from frame.held.w, per superblock
// (WRS_SUPERBLOCK^2 tiles) and eye the largest of the previous frame's (classify.comp, phase 1).
layout(std430, set = 0, binding = 14) buffer TileHeld { uint tile_held[]; };
// Submitted foveation (FOV_MODE WRS_FOV_SUBMITTED), written by the compose pass (compose.comp) as
// words: each pixel's rendered quality (float bits, eye-major like the reservoirs), each tile's
// largest, then each pixel's landed wide sample (wrs_pack_landed, two words) where EyeParams says so.
layout(std430, set = 0, binding = 15) readonly buffer Quality { uint submitted_words[]; };
// Evaluation only: the full-resolution reference of a frame submitted foveated, which the oracles
// compare with (EyeParams::ref_rect; a placeholder otherwise).
layout(set = 0, binding = 16) uniform sampler2D referenceIn[2];
// Method wrs, the steady display (wrs_display_fold_step, retain.comp): two slots of every pixel's displayed linear
// colour (wrs_pack_shown: fp16, 1 where written), slot-major then as the reservoirs; a placeholder where it
// does not run.
layout(std430, set = 0, binding = 17) buffer Display { uvec2 display_history[]; };
// Quad views: the compose pass's parameters (compose.comp) and the submitted wide views, from which the
// retain pass takes each pixel's landed wide sample (landed_sample); placeholders otherwise.
layout(std140, set = 0, binding = 18) uniform ComposeBlock { ComposeParams compose; };
layout(set = 0, binding = 19) uniform sampler2D wideIn[2];
// Output per eye (layer = eye), sRGB-encoded 8-bit.
layout(set = 0, binding = 9, rgba8) uniform writeonly image2DArray outImage;

uint eye_index(uint eye) { return eye; }
uvec2 tile_count() { return (frame.size.xy + uvec2(WRS_TILE - 1u)) / WRS_TILE; }
uint tile_capacity() { uvec2 t = tile_count(); return t.x * t.y * 2u; }
// Index of tile t of an eye among the tiles of both eyes (TileHeld).
uint tile_index(uint eye, uvec2 t) { uvec2 n = tile_count(); return (eye * n.y + t.y) * n.x + t.x; }
// Submitted foveation: the largest rendered quality of tile t's pixels, which the compose pass writes
// after the pixels' (at 2 W H, tile_index order).
float submitted_tile_quality(uint eye, uvec2 t) {
    return uintBitsToFloat(submitted_words[2u * frame.size.x * frame.size.y + tile_index(eye, t)]);
}
// Submitted foveation: the rendered quality of pixel p (index idx) of an eye: quad views carry it in the
// composed colour's alpha (wrs_composed_alpha), a rate map's compose pass writes it to the buffer.
float submitted_quality(uint eye, uvec2 p, uint idx) {
    EyeParams ep = frame.eye[eye];
    uint encoding = INPUT_ENCODING == WRS_INPUT_ANY ? ep.color_rect.z : INPUT_ENCODING;
    if (encoding == WRS_INPUT_COMPOSED) return texelFetch(colorIn[eye], ivec2(p + ep.color_rect.xy), 0).a;
    return uintBitsToFloat(submitted_words[idx]);
}
// Quad views with landed samples (EyeParams::motion_rect.z): the wide sample that landed in pixel idx,
// colour and quality (0: none).
vec4 submitted_landed(uint idx) {
    uint at = 2u * (frame.size.x * frame.size.y + tile_capacity() / 2u) + 2u * idx;
    return wrs_unpack_landed(uvec2(submitted_words[at], submitted_words[at + 1u]));
}
// The held quality of tile t in the previous frame.
float held_prev(uint eye, uvec2 t) { return uintBitsToFloat(tile_held[frame.held.x + tile_index(eye, t)]); }
uvec2 superblock_count() { return (tile_count() + uvec2(WRS_SUPERBLOCK - 1u)) / WRS_SUPERBLOCK; }
// Word of superblock b of an eye in TileHeld.
uint superblock_word(uint eye, uvec2 b) { uvec2 n = superblock_count(); return frame.held.w + (eye * n.y + b.y) * n.x + b.x; }
// The pixel and eye of this invocation: over the whole image (tile == 0: groups of
// WRS_GROUP_X x WRS_GROUP_Y pixels, z = eye), or in the gl_WorkGroupID.x-th tile of class tile - 1
// (an indirect dispatch of one group per tile; the eye is the same for the whole group).
void invocation_pixel(uint tile, out uint eye, out uvec2 p) {
    if (tile == 0u) {
        eye = gl_WorkGroupID.z;
        p = gl_GlobalInvocationID.xy;
    } else {
        uint t = tile_list[(tile - 1u) * tile_capacity() + gl_WorkGroupID.x];
        eye = t >> 30u;
        p = uvec2(t & 0x7fffu, (t >> 15u) & 0x7fffu) * WRS_TILE + gl_LocalInvocationID.xy;
    }
}
// The levels pixel p is foveated with (wrs_foveation_levels of its eccentricity, returned in `e`),
// or, in a tiled dispatch of a class with constant levels (tile > 1), that class's levels without
// any eccentricity (e = 0: only mode none reads it, and it has no tile classes).
vec3 pixel_levels(uint tile, uint mode, uint eye, uvec2 p, out float e) {
    e = 0.0;
    if (tile > 1u) return wrs_mode_simulated(mode) ? wrs_tile_levels(tile - 1u) : vec3(0.0);
    EyeParams ep = frame.eye[eye];
    e = wrs_eccentricity_deg(wrs_pixel_ray(p.x, p.y, frame.size.x, frame.size.y, ep.fov_tan), ep.gaze.xyz);
    return wrs_foveation_levels(mode, e, ep.gaze.w, frame.tuning.x);
}
uint pixel_index(uint eye, uvec2 p) { return (eye * frame.size.y + p.y) * frame.size.x + p.x; }
// Pixel p of an eye in slot `slot` of the steady display's history.
uint display_index(uint slot, uint eye, uvec2 p) { return slot * 2u * frame.size.x * frame.size.y + pixel_index(eye, p); }
// Size of a pyramid level (wrs_level_size of the frame, from the parameter block).
uvec2 level_size(uint level) { return frame.levels[level].xy; }
uint pyramid_index(uint eye, uint level, uvec2 q) {
    uvec4 l = frame.levels[level];
    return eye * l.w + l.z + q.y * l.x + q.x;
}
// Rounds to nearest even on every device (wrs_store_f16).
uvec2 pyr_pack(vec4 v) { return uvec2(wrs_store_f16x2(v.x, v.y), wrs_store_f16x2(v.z, v.w)); }
// fp16 to fp32 is exact, so unpackHalf2x16 agrees with wrs_f16_to_f32 on the CPU.
vec4 pyr_unpack(uvec2 h) { return vec4(unpackHalf2x16(h.x), unpackHalf2x16(h.y)); }
// A stored texel of level >= 1.
vec4 pyr_read(uint eye, uint level, uvec2 q) { return pyr_unpack(pyramid[pyramid_index(eye, level, q)]); }
void pyr_write(uint eye, uint level, uvec2 q, uvec2 packed_texel) { pyramid[pyramid_index(eye, level, q)] = packed_texel; }

// The candidate stage's bridge (wrs_candidate.h): an eye's pyramid is the pyramid buffer's levels of it.
struct WrsPyramid {
    uint eye;
};
WrsPyramid eye_pyramid(uint eye) { return WrsPyramid(eye); }
vec4 wrs_pyr_texel(WrsPyramid s, uint level, uvec2 q) { return pyr_read(s.eye, level, q); }
uvec2 wrs_pyr_level_size(WrsPyramid s, uint level) { return level_size(level); }
vec2 wrs_pyr_level_scale(WrsPyramid s, uint level) { return frame.level_scale[level].xy; }
#include "wrs_candidate.h"

// Level 0 at pixel p of the eye's rectangle: linear RGB, sanitized, validity (1 or 0) in alpha.
// The sRGB table it decodes with: the buffer, or a pass's copy of it in shared memory (a pass that
// defines WRS_SRGB_TABLE before including this file fills that copy before its first load_color).
#ifndef WRS_SRGB_TABLE
#define WRS_SRGB_TABLE srgb_table
#endif
#include "wrs_input.h"
// Quad views: the colour is the compose pass's, whose alpha says whether any source tap was valid
// (colour_rect.z == WRS_INPUT_COMPOSED).
vec4 load_color(uint eye, uvec2 p) {
    EyeParams ep = frame.eye[eye];
    uint encoding = INPUT_ENCODING == WRS_INPUT_ANY ? ep.color_rect.z : INPUT_ENCODING;
    return wrs_decode_input(texelFetch(colorIn[eye], ivec2(p + ep.color_rect.xy), 0), encoding);
}
// The full-resolution reference at pixel p (submitted foveation, the oracles only), decoded as load_color.
vec3 load_reference(uint eye, uvec2 p) {
    EyeParams ep = frame.eye[eye];
    return wrs_decode_input(texelFetch(referenceIn[eye], ivec2(p + ep.ref_rect.xy), 0), ep.ref_rect.z).rgb;
}
// Linear view depth at pixel p (only where the view has depth).
float load_depth(uint eye, uvec2 p) {
    EyeParams ep = frame.eye[eye];
    float d = texelFetch(depthIn[eye], ivec2(p + ep.depth_rect.xy), 0).r;
    return wrs_linear_depth(d, ep.depth_range.x, ep.depth_range.y, ep.depth_rect.z != 0u);
}
// Whether load_color reads the sRGB table (a pass that copies it into shared memory does so only then).
bool input_reads_srgb_table() { return INPUT_ENCODING == WRS_INPUT_ANY || wrs_input_srgb8(INPUT_ENCODING); }
// Whether the steady display filters pixel idx of an eye (retain.comp DISPLAY): a wide view's pixel of quad
// views with landed samples; the inset's are shown as retention shows them.
bool display_filters(uint eye, uvec2 p, uint idx) {
    return frame.eye[eye].motion_rect.z != 0u && wrs_is_wide_quality(submitted_quality(eye, p, idx), frame.eye[eye].tile.w);
}
// What a pass shows at pixel p, into the output image (sRGB-encoded 8-bit).
void store_output(uint eye, uvec2 p, vec3 linear_rgb) {
    imageStore(outImage, ivec3(ivec2(p), int(eye)), vec4(wrs_output_value(linear_rgb), 1.0));
}

#endif
