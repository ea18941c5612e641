// FovVideoVDP on the GPU (eval/fvvdp_gpu.h): descriptor set 0 of its passes and the per-pixel steps,
// each the mirror of its fvvdp::detail function (eval/fvvdp.cpp), in float.
#ifndef WRSFOV_FVVDP_COMMON_GLSL
#define WRSFOV_FVVDP_COMMON_GLSL

#include "fvvdp_params.h"

layout(std140, set = 0, binding = 0) uniform ParamsBlock { FvvdpParams params; };
// The per-pixel passes before the pyramid (display, temporal) take four consecutive pixels (a
// "quad", in row-major order) per invocation, so that each of their loads is a vec4: the images are
// padded to params.image.w quads (4 · quads pixels).
// This frame's images, sRGB-encoded RGB as the caller's CV_32FC3 (three vec4 per quad): the test
// image's quads, then the reference's. Finite (push() checks them on the host).
layout(std430, set = 0, binding = 1) readonly buffer Input { vec4 rgb[]; };
// The temporal filter's window: N slots of the test's then the reference's luminance (a vec4 per
// quad); frame f sits in slot f mod N.
layout(std430, set = 0, binding = 2) buffer Window { vec4 window_lum[]; };
// Gaussian pyramid of the four temporal channels, per texel (test sustained, reference sustained,
// test transient, reference transient); level l from params.level[l].z.
layout(std430, set = 0, binding = 3) buffer Pyramid { vec4 pyr[]; };
// The CSF tables (log2 S, fvvdp::detail::csfTable; per node the sustained and the transient
// channel's, which share their interpolation), then the temporal filters (sustained then transient,
// params.image.z each; element k for k frames back).
layout(std430, set = 0, binding = 4) readonly buffer Tables {
    vec2 csf_table[FVVDP_CSF_N * FVVDP_CSF_N * FVVDP_CSF_N];
    float filters[];
};
// Per band and group: the sums of D^beta over the group's pixels, sustained and transient.
layout(std430, set = 0, binding = 5) writeonly buffer Partial { float partial[]; };

layout(push_constant) uniform PushBlock { FvvdpPush push; };

const float FVVDP_A = 0.4;
const float FVVDP_KERNEL[5] = float[5](0.25 - FVVDP_A / 2.0, 0.25, FVVDP_A, 0.25, 0.25 - FVVDP_A / 2.0);

uint fvvdp_texel(uint level, uvec2 p) { return params.level[level].z + p.y * params.level[level].x + p.x; }

// The quad of an invocation of the per-quad passes (FVVDP_QUAD_GROUP-wide groups in x, then y).
uint fvvdp_quad() { return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * FVVDP_QUAD_GROUP + gl_GlobalInvocationID.x; }

// detail::srgbToLinear and detail::displayLuminance.
float fvvdp_srgb_to_linear(float v) { return v > 0.04045 ? pow((v + 0.055) / 1.055, 2.4) : v / 12.92; }
float fvvdp_display_luminance(vec3 rgb, float peak, float black) {
    vec3 l;
    for (int c = 0; c < 3; ++c) l[c] = (peak - black) * fvvdp_srgb_to_linear(clamp(rgb[c], 0.0, 1.0)) + black;
    return 0.2126729 * l.r + 0.7151522 * l.g + 0.0721750 * l.b;
}

// Source sample of tap k (0..4) of output i when reducing n samples (detail::pyramidReduce: the
// kernel at every second sample, borders mirrored).
int fvvdp_reduce_tap(int i, int k, int n) {
    int j = 2 * i + k - 2;
    if (j < 0) j = -j - 1;
    if (j >= n) j = 2 * n - 1 - j;
    return clamp(j, 0, n - 1);
}

// Expansion of m samples to n (detail::pyramidExpand: the samples at even positions, zeros between,
// the kernel times 2; beyond the ends the first and the last sample). Output i = 2h (even) takes
// samples h − 1, h, h + 1 with weights 2 · (K0, K2, K4), i = 2h + 1 (odd) samples h, h + 1 with
// 2 · (K1, K3); the taps past either end are exactly the clamped indices. As three taps: sources
// in `src`, weights returned.
vec3 fvvdp_expand_taps(int i, int m, out ivec3 src) {
    int h = i >> 1;
    src = clamp(ivec3(h - 1, h, h + 1), ivec3(0), ivec3(m - 1));
    return (i & 1) == 0 ? 2.0 * vec3(FVVDP_KERNEL[0], FVVDP_KERNEL[2], FVVDP_KERNEL[4])
                        : 2.0 * vec3(0.0, FVVDP_KERNEL[1], FVVDP_KERNEL[3]);
}

// detail::csfLookup: trilinear in log2 Y, log2 rho, sqrt(ecc), clamped to the table; without the
// sensitivity correction.
void fvvdp_axis(float q, float a, float b, out int i, out float f) {
    float t = (clamp(q, a, b) - a) / (b - a) * float(FVVDP_CSF_N - 1);
    i = min(int(t), FVVDP_CSF_N - 2);
    f = t - float(i);
}
// Both channels' sensitivities: x sustained, y transient.
vec2 fvvdp_csf(float rho, float luminance, float ecc) {
    const int n = FVVDP_CSF_N;
    int iy, ir, ie;
    float fy, fr, fe;
    fvvdp_axis(log2(max(luminance, exp2(params.csf_axes.x))), params.csf_axes.x, params.csf_axes.y, iy, fy);
    fvvdp_axis(log2(max(rho, exp2(params.csf_axes.z))), params.csf_axes.z, params.csf_axes.w, ir, fr);
    fvvdp_axis(sqrt(max(ecc, 0.0)), 0.0, params.csf_ecc.x, ie, fe);
    vec2 v[8];
    for (int c = 0; c < 8; ++c) {
        int y = c & 1, r = (c >> 1) & 1, e = c >> 2;
        v[c] = csf_table[((iy + y) * n + ir + r) * n + ie + e];
    }
    // v[y + 2r + 4e]; as the C++: rho innermost, then Y, then eccentricity.
    vec2 e0 = mix(mix(v[0], v[2], fr), mix(v[1], v[3], fr), fy);
    vec2 e1 = mix(mix(v[4], v[6], fr), mix(v[5], v[7], fr), fy);
    return exp2(mix(e0, e1, fe));
}

// detail::maskedDifference.
float fvvdp_masked_difference(float t, float r, float p, float q, float mask_gain) {
    if (t == r) return 0.0;
    float m = mask_gain * min(abs(t), abs(r));
    float d = pow(abs(t - r), p) / (1.0 + pow(m, q));
    return min(d, 1e4);
}

// detail::eccentricityDeg: the angle between the rays (tx, ty, -1) and (gtx, gty, -1), or (flat
// screen) the norm of the horizontal and vertical angle differences.
float fvvdp_eccentricity(bool flat_screen, float tx, float ty, float gtx, float gty) {
    if (!flat_screen) {
        vec3 c = vec3(ty - gty, gtx - tx, tx * gty - ty * gtx);
        return degrees(atan(length(c), tx * gtx + ty * gty + 1.0));
    }
    return length(degrees(vec2(atan(tx) - atan(gtx), atan(ty) - atan(gty))));
}

// detail::resolutionMagnification, (tan(a + δ) − tan a) / tan δ written as
// (1 + tan² a) / (1 − tan a · tan δ), which float evaluates without cancellation.
float fvvdp_resolution_magnification(float angle_deg, float ppd_centre) {
    float ta = tan(radians(min(angle_deg, 89.9)));
    float td = tan(radians(0.5 / ppd_centre));
    return (1.0 + ta * ta) / (1.0 - ta * td);
}

#endif
