// The candidate stage: how one pixel's foveated colour, its weight, its quality, the range of the
// taps it came from and its fingerprint are built from the pyramid, for every input kind (simulated
// `mip`/`gauss`, `none`, and frames submitted foveated, whose quality the compose pass measured).
// The foveating pass (foveate.comp), the retain pass (retain.comp) and the CPU reference
// (compositor/reference.cpp) all build their candidates here and nowhere else.
//
// Shared by GLSL and C++ like wrs_common.h. The pyramid is read through bridge declarations that the
// includer provides before including this header (the model is RTXDI's bridge functions):
//   WrsPyramid                                          one eye's pyramid, as the side stores it
//   vec4  wrs_pyr_texel(WrsPyramid s, uint level, uvec2 q)  stored texel q of a level >= 1
//   uvec2 wrs_pyr_level_size(WrsPyramid s, uint level)      wrs_level_size of the frame
//   vec2  wrs_pyr_level_scale(WrsPyramid s, uint level)     wrs_level_scale of the frame
// The shaders' bridge is in bindings.glsl (the pyramid buffer); the reference's in reference.cpp.
#ifndef WRSFOV_WRS_CANDIDATE_H
#define WRSFOV_WRS_CANDIDATE_H

#include "wrs_common.h"

WRS_BEGIN

// Bilinear sample of `level` at the centre of pixel p. Widens [lo, hi] by the four taps' colours and
// returns their alpha range (the L* range at the fingerprint level) in `arange`. `level0` is the
// pixel's own decoded colour (level 0 is never stored: load_color on the GPU).
WRS_FN vec4 wrs_sample_level(WrsPyramid s, uint level, uvec2 p, vec4 level0, WRS_INOUT(vec3) lo,
                             WRS_INOUT(vec3) hi, WRS_OUT(float) arange) {
    if (level == 0u) {
        arange = wrs_taps_range(level0, level0, level0, level0, lo, hi);
        return level0;
    }
    uvec2 i0, i1;
    vec2 f = wrs_bilinear_setup(p, wrs_pyr_level_scale(s, level), wrs_pyr_level_size(s, level), i0, i1);
    vec4 c00 = wrs_pyr_texel(s, level, i0);
    vec4 c10 = wrs_pyr_texel(s, level, uvec2(i1.x, i0.y));
    vec4 c01 = wrs_pyr_texel(s, level, uvec2(i0.x, i1.y));
    vec4 c11 = wrs_pyr_texel(s, level, i1);
    arange = wrs_taps_range(c00, c10, c01, c11, lo, hi);
    return wrs_bilinear(c00, c10, c01, c11, f);
}

// One pixel's candidate: what the retention rule takes of it (RetainInput: colour, quality, tap range,
// fingerprint; its depth, motion and floor quality are the pixel's, left 0 and false for the caller to
// set; fp and fp_range only where asked for, with_fp) and the paper's sample weight p-hat.
struct WrsCandidate {
    RetainInput rule;
    float w;  // wrs_sample_weight; 0 for an invalid pixel
};

// The candidate at pixel p foveated with levels lv = (a, b, t) (wrs_foveation_levels of eccentricity e,
// or a tile class's constant levels), fovea radius r_f; q_sub is the rendered quality of a frame
// submitted foveated (compose pass), read only in that mode.
WRS_FN WrsCandidate wrs_candidate_at(WrsPyramid s, uint mode, uvec2 p, vec4 level0, vec3 lv, float e, float r_f,
                                     float q_sub, bool with_fp) {
    RetainInput c;
    c.lo = vec3(WRS_HALF_MAX, WRS_HALF_MAX, WRS_HALF_MAX);
    c.hi = vec3(0.0f, 0.0f, 0.0f);
    float range_a, range_b;
    vec4 col_a = wrs_sample_level(s, uint(lv.x), p, level0, c.lo, c.hi, range_a);
    vec4 col = col_a;
    if (lv.z > 0.0f) col = wrs_blend(col_a, wrs_sample_level(s, uint(lv.y), p, level0, c.lo, c.hi, range_b), lv.z);
    c.color = vec3(col);
    bool valid = level0.w > 0.5f;
    c.q = wrs_candidate_quality(mode, lv, e, r_f, q_sub, valid);
    c.fp = 0.0f;
    c.fp_range = 0.0f;
    if (with_fp) {
        if (uint(lv.x) == WRS_FP_LEVEL) {  // the far periphery samples the fingerprint level already
            c.fp = col_a.w;
            c.fp_range = range_a;
        } else {
            vec3 flo = vec3(0.0f, 0.0f, 0.0f), fhi = vec3(0.0f, 0.0f, 0.0f);
            c.fp = wrs_sample_level(s, WRS_FP_LEVEL, p, level0, flo, fhi, c.fp_range).w;
        }
    }
    c.moved = false;
    c.jittered = false;
    c.weight = 1.0f;
    c.d = vec2(0.0f, 0.0f);
    c.flags = 0u;
    c.z = 0.0f;
    c.q_floor = 0.0f;
    WrsCandidate r;
    r.rule = c;
    r.w = valid ? wrs_sample_weight(e, r_f) : 0.0f;
    return r;
}

WRS_END

#endif
