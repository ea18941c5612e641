// Depth: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_DEPTH_H
#define WRSFOV_WRS_DEPTH_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Depth (docs/conventions.md "Depth")
// ---------------------------------------------------------------------------------------------

// Linear view depth from a [0, 1] depth value; far may be +inf (infinite projection). Returns 0
// ("unknown") for anything that does not give a positive finite depth; the depth test is then
// skipped for that pixel.
WRS_FN float wrs_linear_depth(float d, float near_z, float far_z, bool reversed) {
    if (!wrs_finite(d) || d < 0.0f || d > 1.0f) return 0.0f;
    float z;
    bool inf_far = !wrs_finite(far_z);
    if (reversed) {
        z = inf_far ? wrs_div(near_z, d) : wrs_div(near_z * far_z, near_z + d * (far_z - near_z));
    } else {
        z = inf_far ? wrs_div(near_z, 1.0f - d) : wrs_div(near_z * far_z, far_z - d * (far_z - near_z));
    }
    return (wrs_finite(z) && z > 0.0f) ? min(z, WRS_HALF_MAX) : 0.0f;
}

// The inverse: the [0, 1] depth value of a planar view depth z (same units as near and far). A z
// outside [near, far] (in front of the near plane, beyond a finite far plane), not positive or NaN
// gives -1, which wrs_linear_depth reads as "unknown"; z = +inf is the far plane of an infinite
// projection (1, reversed 0) and unknown for a finite one.
WRS_FN float wrs_depth_from_linear(float z, float near_z, float far_z, bool reversed) {
    if (!(z > 0.0f)) return -1.0f;  // also NaN
    bool inf_far = !wrs_finite(far_z);
    float d;
    if (!wrs_finite(z)) {
        d = inf_far ? (reversed ? 0.0f : 1.0f) : -1.0f;
    } else if (reversed) {
        d = inf_far ? near_z / z : near_z * (far_z - z) / (z * (far_z - near_z));
    } else {
        d = inf_far ? 1.0f - near_z / z : far_z * (z - near_z) / (z * (far_z - near_z));
    }
    return (d >= 0.0f && d <= 1.0f) ? d : -1.0f;
}

// True when the history at a reprojected pixel belongs to another surface: the depth test of docs/conventions.md "Reservoirs".
// z_hist: depth stored with the history; z_cur: this pixel now; dz: z_prev − z_cur from the
// motion vector's third channel (0 without one).
WRS_FN bool wrs_depth_flush(float z_hist, float z_cur, float dz, float tau) {
    if (z_hist <= 0.0f || z_cur <= 0.0f) return false;  // unknown on either side: nothing to test
    return abs(z_hist - (z_cur + dz)) > tau * z_cur;
}

// Reprojection (docs/conventions.md "Motion"): the previous position of pixel p is its centre + mv.xy, read at the
// nearest pixel q. Non-finite motion is taken as zero motion and a non-finite dz as 0 (documented
// fallback: the history stays, the depth and change tests still guard it). Returns false when the
// previous position is off-screen: that pixel has no history.
WRS_FN bool wrs_reproject(uvec2 p, uvec2 size, vec3 mv, WRS_OUT(uvec2) q, WRS_OUT(float) dz) {
    bool finite_xy = wrs_finite(mv.x) && wrs_finite(mv.y);
    vec2 m = finite_xy ? vec2(mv.x, mv.y) : vec2(0.0f, 0.0f);
    dz = wrs_finite(mv.z) ? mv.z : 0.0f;
    vec2 pos = vec2(p) + vec2(0.5f, 0.5f) + m;
    q = p;
    if (!(pos.x >= 0.0f && pos.y >= 0.0f && pos.x < float(size.x) && pos.y < float(size.y))) return false;
    q = uvec2(floor(pos));
    return true;
}

WRS_END

#endif
