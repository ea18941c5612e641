// The FOV+TAA baseline: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_TAA_H
#define WRSFOV_WRS_TAA_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// FOV+TAA baseline (docs/conventions.md "Evaluation"): Karis 2014 YCoCg neighbourhood clip with Salvi 2016
// variance clipping, exponential blend with the reprojected history
// ---------------------------------------------------------------------------------------------

const float WRS_TAA_ALPHA = 0.1f;  // weight of the current frame
const float WRS_TAA_GAMMA = 1.0f;  // variance clip box: mean ± gamma·sigma

WRS_FN vec3 wrs_rgb_to_ycocg(vec3 c) {
    return vec3(0.25f * c.x + 0.5f * c.y + 0.25f * c.z, 0.5f * c.x - 0.5f * c.z, -0.25f * c.x + 0.5f * c.y - 0.25f * c.z);
}
WRS_FN vec3 wrs_ycocg_to_rgb(vec3 c) { return vec3(c.x + c.y - c.z, c.x + c.z, c.x - c.y - c.z); }

// Clips `h` towards the centre of the box (centre ± extent) along the line to the centre, so that
// the result lies in the box (Karis: clip rather than clamp keeps the hue of the history). The box
// is at least one 8-bit step wide per axis: a flat channel would otherwise let rounding noise in
// the history decide how far all three channels are pulled.
WRS_FN vec3 wrs_clip_box(vec3 h, vec3 centre, vec3 extent) {
    vec3 d = h - centre;
    vec3 e = max(extent, vec3(1.0f / 255.0f, 1.0f / 255.0f, 1.0f / 255.0f));
    vec3 r = wrs_div(abs(d), e);
    float m = max(r.x, max(r.y, r.z));
    return m > 1.0f ? centre + wrs_div(d, m) : h;
}

// The moments of nine values, one added at a time (m1: their sum, m2: the sum of their squares), and the
// mean and standard deviation of the nine, per channel.
WRS_FN void wrs_moments_add(WRS_INOUT(vec3) m1, WRS_INOUT(vec3) m2, vec3 v) {
    WRS_PRECISE vec3 s1 = m1 + v;
    WRS_PRECISE vec3 sq = v * v;
    WRS_PRECISE vec3 s2 = m2 + sq;
    m1 = s1;
    m2 = s2;
}
WRS_FN void wrs_moments_of_nine(vec3 m1, vec3 m2, WRS_OUT(vec3) mu, WRS_OUT(vec3) sigma) {
    // The variance cancels (m2 / 9 - mu^2): its terms multiply by a literal 1/9 and stay unfused, so that
    // every device computes the same box before the square root.
    WRS_PRECISE vec3 m = m1 * 0.111111112f;
    WRS_PRECISE vec3 var = m2 * 0.111111112f - m * m;
    mu = m;
    sigma = wrs_sqrt(max(var, vec3(0.0f, 0.0f, 0.0f)));
}
// The mean and standard deviation of the 3x3 neighbourhood `nb` (YCoCg), per channel.
WRS_FN void wrs_taa_moments(vec3 nb[9], WRS_OUT(vec3) mu, WRS_OUT(vec3) sigma) {
    vec3 m1 = vec3(0.0f, 0.0f, 0.0f);
    vec3 m2 = vec3(0.0f, 0.0f, 0.0f);
    for (int i = 0; i < 9; ++i) wrs_moments_add(m1, m2, nb[i]);
    wrs_moments_of_nine(m1, m2, mu, sigma);
}
// The history `hist` (linear RGB) clipped to the variance box (mean ± gamma sigma) of the 3x3
// neighbourhood `nb` (YCoCg, centre at 4), in YCoCg.
WRS_FN vec3 wrs_taa_clip(vec3 nb[9], vec3 hist, float gamma) {
    vec3 mu, sigma;
    wrs_taa_moments(nb, mu, sigma);
    return wrs_clip_box(wrs_rgb_to_ycocg(hist), mu, gamma * sigma);
}
// One TAA step: `nb` holds the 3x3 neighbourhood of the current (foveated) colour in YCoCg, the
// centre at index 4; `hist` the reprojected history in linear RGB, `has_history` whether it exists.
WRS_FN vec3 wrs_taa_step(vec3 nb[9], vec3 hist, bool has_history, float alpha) {
    vec3 cur = wrs_ycocg_to_rgb(nb[4]);
    if (!has_history) return cur;
    vec3 h = wrs_taa_clip(nb, hist, WRS_TAA_GAMMA);
    WRS_PRECISE vec3 out_ycocg = h + (nb[4] - h) * alpha;
    return max(wrs_ycocg_to_rgb(out_ycocg), vec3(0.0f, 0.0f, 0.0f));
}
WRS_FN vec3 wrs_taa(vec3 nb[9], vec3 hist, bool has_history) { return wrs_taa_step(nb, hist, has_history, WRS_TAA_ALPHA); }

// Neighbourhood tap of the TAA pass, clamped to the image.
WRS_FN uvec2 wrs_taa_tap(uvec2 p, ivec2 o, uvec2 size) {
    return uvec2(clamp(ivec2(p) + o, ivec2(0, 0), ivec2(size) - ivec2(1, 1)));
}

// Bilinear reprojection of the TAA history: previous position = pixel centre + mv. False when it is
// off-screen (or the motion is not finite, then zero motion is used as in wrs_reproject).
WRS_FN bool wrs_taa_reproject(uvec2 p, uvec2 size, vec3 mv, WRS_OUT(uvec2) i0, WRS_OUT(uvec2) i1, WRS_OUT(vec2) f) {
    bool finite_xy = wrs_finite(mv.x) && wrs_finite(mv.y);
    vec2 m = finite_xy ? vec2(mv.x, mv.y) : vec2(0.0f, 0.0f);
    vec2 pos = vec2(p) + vec2(0.5f, 0.5f) + m;
    i0 = p;
    i1 = p;
    f = vec2(0.0f, 0.0f);
    if (!(pos.x >= 0.0f && pos.y >= 0.0f && pos.x < float(size.x) && pos.y < float(size.y))) return false;
    vec2 t = clamp(pos - vec2(0.5f, 0.5f), vec2(0.0f, 0.0f), vec2(size) - vec2(1.0f, 1.0f));
    vec2 fl = floor(t);
    i0 = uvec2(fl);
    i1 = min(i0 + uvec2(1u, 1u), size - uvec2(1u, 1u));
    f = t - fl;
    return true;
}

WRS_END

#endif
