// Views, eccentricity and the sample weight: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_VIEWS_H
#define WRSFOV_WRS_VIEWS_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Views and eccentricity (docs/conventions.md "Views", "Eccentricity")
// ---------------------------------------------------------------------------------------------

// fov_tan = (tan angleLeft, tan angleRight, tan angleUp, tan angleDown), the XrFovf order.
// Pixel (x, y), y down, centre (x + 0.5, y + 0.5); eye space is -Z forward, +Y up, +X right.
WRS_FN vec3 wrs_pixel_ray(uint x, uint y, uint width, uint height, vec4 fov_tan) {
    float u = wrs_div(float(x) + 0.5f, float(width));
    float v = wrs_div(float(y) + 0.5f, float(height));
    float tx = fov_tan.x + u * (fov_tan.y - fov_tan.x);
    float ty = fov_tan.z - v * (fov_tan.z - fov_tan.w);
    return wrs_normalize(vec3(tx, ty, -1.0f));
}

// atan(y / x) for y, x >= 0, in radians, written out (Cephes atanf: range reduction + odd
// polynomial, ~2e-7 relative) because built-in atan is as loose as 1e-5 on some devices, which
// would make CPU and GPU weights disagree near the fovea edge.
WRS_FN float wrs_atan2_pos(float y, float x) {
    if (y <= 0.0f) return 0.0f;
    if (x <= 0.0f) return 0.5f * WRS_PI;
    bool swap = y > x;
    float t = swap ? wrs_div(x, y) : wrs_div(y, x);  // in (0, 1]
    float base = 0.0f;
    if (t > 0.41421356f) {  // tan(pi/8)
        t = wrs_div(t - 1.0f, t + 1.0f);
        base = 0.25f * WRS_PI;
    }
    float z = t * t;
    WRS_PRECISE float p = ((8.05374449538e-2f * z - 1.38776856032e-1f) * z + 1.99777106478e-1f) * z - 3.33329491539e-1f;
    WRS_PRECISE float a = base + (p * z * t + t);
    return swap ? 0.5f * WRS_PI - a : a;
}

// Angle in degrees between two unit rays. 2·atan2(|a−b|, |a+b|) keeps full precision near 0°,
// where acos(dot) loses most of its digits.
WRS_FN float wrs_eccentricity_deg(vec3 ray, vec3 gaze) {
    float num = wrs_length(ray - gaze);
    float den = wrs_length(ray + gaze);
    return 2.0f * wrs_atan2_pos(num, den) * WRS_RAD_TO_DEG;
}

// ---------------------------------------------------------------------------------------------
// Sample weight p̂ (paper eq. 3–4): Watson 2014 cone density, normalised at the fovea edge
// ---------------------------------------------------------------------------------------------

const float WRS_WATSON_A = 0.9851f;
const float WRS_WATSON_R2 = 1.058f;
const float WRS_WATSON_RE = 22.14f;
const float WRS_WATSON_DC0 = 14804.6f;
const float WRS_WATSON_RM = 41.03f;

// Eq. 3, e in degrees.
WRS_FN float wrs_watson_density(float e) {
    float q = 1.0f + wrs_div(e, WRS_WATSON_R2);
    return wrs_div(2.0f * WRS_WATSON_DC0, 1.0f + wrs_div(e, WRS_WATSON_RM)) *
           (wrs_div(WRS_WATSON_A, q * q) + (1.0f - WRS_WATSON_A) * wrs_exp(wrs_div(-e, WRS_WATSON_RE)));
}

// Eq. 4: 1 inside the fovea (radius r_f in degrees), d(e)/d(r_f) outside.
WRS_FN float wrs_sample_weight(float e, float r_f) {
    if (e <= r_f) return 1.0f;
    return wrs_div(wrs_watson_density(e), wrs_watson_density(r_f));
}

WRS_END

#endif
