// Colour: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_COLOUR_H
#define WRSFOV_WRS_COLOUR_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Colour
// ---------------------------------------------------------------------------------------------

WRS_FN float wrs_srgb_to_linear(float c) {
    return c <= 0.04045f ? wrs_div(c, 12.92f) : wrs_pow(wrs_div(c + 0.055f, 1.055f), 2.4f);
}
WRS_FN float wrs_linear_to_srgb(float c) {
    c = clamp(c, 0.0f, 1.0f);
    return c <= 0.0031308f ? c * 12.92f : 1.055f * wrs_pow(c, 1.0f / 2.4f) - 0.055f;
}
WRS_FN vec3 wrs_srgb_to_linear3(vec3 c) {
    return vec3(wrs_srgb_to_linear(c.x), wrs_srgb_to_linear(c.y), wrs_srgb_to_linear(c.z));
}
// An 8-bit sRGB code (0..255) decodes through a table of 256 linear values, the same on both sides:
// the GPU reads it from a buffer the compositor fills from wrs_srgb8_table() (bindings.glsl,
// load_color), the CPU reference indexes it directly. Exact and alike where a pow per channel differs
// in the last bit between the two, which the fp16 pyramid would turn into a whole fp16 step.
WRS_FN uint wrs_srgb8_code(float unorm) { return uint(clamp(floor(unorm * 255.0f + 0.5f), 0.0f, 255.0f)); }
#ifdef __cplusplus
// Computed in double precision, rounded once to float.
inline const std::array<float, 256>& wrs_srgb8_table() {
    static const std::array<float, 256> table = [] {
        std::array<float, 256> t{};
        for (int k = 0; k < 256; ++k) {
            const double c = k / 255.0;
            t[k] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
        }
        return t;
    }();
    return table;
}
#endif
WRS_FN vec3 wrs_linear_to_srgb3(vec3 c) {
    return vec3(wrs_linear_to_srgb(c.x), wrs_linear_to_srgb(c.y), wrs_linear_to_srgb(c.z));
}
// The 8-bit code of an sRGB value in [0, 1] (half up), unfused.
WRS_FN uint wrs_unorm8_code(float s) {
    WRS_PRECISE float x = clamp(s, 0.0f, 1.0f) * 255.0f + 0.5f;
    return uint(floor(x));
}
// code / 255 as the nearest float, whose product with 255 is the code exactly: a store to an 8-bit UNORM
// image must return that whole number as it is (fundamentals-fpfixedconv), where any other value may be
// stored as either of the two nearest codes. code times the nearest float to 1/255 is that float for
// 130 of the 256 codes and one ULP above it for the others (RoundingModels checks every code); there the
// float below is taken.
WRS_FN float wrs_unorm8_value(uint code) {
    WRS_PRECISE float f = float(code) * 0.00392156886f;
    WRS_PRECISE float back = f * 255.0f;
    return back > float(code) ? uintBitsToFloat(floatBitsToUint(f) - 1u) : f;
}
// What the RGBA8 output stores of a linear colour: sRGB-encoded and quantised to 8 bits by hand, so the
// image's conversion, which the spec leaves to the device, is given whole codes.
WRS_FN vec3 wrs_output_value(vec3 linear) {
    vec3 s = wrs_linear_to_srgb3(linear);
    return vec3(wrs_unorm8_value(wrs_unorm8_code(s.x)), wrs_unorm8_value(wrs_unorm8_code(s.y)),
                wrs_unorm8_value(wrs_unorm8_code(s.z)));
}

// What a colour becomes before it enters the pipeline: non-finite channels -> 0, negative -> 0,
// larger than fp16 can hold -> 65504. `valid` reports whether the input was usable as-is finite.
WRS_FN vec3 wrs_sanitize_color(vec3 c, WRS_OUT(bool) valid) {
    valid = wrs_finite3(c);
    vec3 r = vec3(wrs_finite(c.x) ? c.x : 0.0f, wrs_finite(c.y) ? c.y : 0.0f, wrs_finite(c.z) ? c.z : 0.0f);
    return clamp(r, vec3(0.0f, 0.0f, 0.0f), vec3(WRS_HALF_MAX, WRS_HALF_MAX, WRS_HALF_MAX));
}

// How a pass's colour input is encoded and read (EyeParams::color_rect.z, ComposeEye::wide_color.z):
// linear; sRGB-encoded 8-bit read through a UNORM view (the image was made MUTABLE_FORMAT by whoever
// the compositor knows made it: the pass reads the code); the compose pass's output for quad views
// (linear, alpha 0 where no source tap was valid); or sRGB-encoded 8-bit read through a view of its
// own sRGB format (an image whose creation flags the compositor cannot vouch for, such as a runtime's
// seen by the API layer: the device decoded it, and the pass recovers the code, wrs_srgb8_code_of).
const uint WRS_INPUT_LINEAR = 0u;
const uint WRS_INPUT_SRGB = 1u;
const uint WRS_INPUT_COMPOSED = 2u;
const uint WRS_INPUT_SRGB_VIEW = 3u;
// A pass's encoding constant (bindings.glsl INPUT_ENCODING, compose.comp's) where the frame's views differ:
// each view's own encoding, read from its parameters at run time.
const uint WRS_INPUT_ANY = 4u;
WRS_FN bool wrs_input_srgb8(uint encoding) { return encoding == WRS_INPUT_SRGB || encoding == WRS_INPUT_SRGB_VIEW; }
// The 8-bit code of an sRGB channel that a device decoded to `decoded` (an sRGB view): the code whose
// sRGB value it encodes back to, rounded. Adjacent codes are at least 1/3295 apart in linear value (codes
// 0 and 1), and re-encoding maps that step to a whole code, so a device decode off by less than a third
// of that step (a thousand times what a table-driven or float decode is off by) gives the code itself,
// whatever the device's pow (tests/core: Input.SrgbViewRecoversEveryCode).
// (A view returns no NaN; one is read as 0 all the same, so no code is undefined.)
WRS_FN uint wrs_srgb8_code_of(float decoded) {
    return wrs_unorm8_code(wrs_linear_to_srgb(wrs_finite(decoded) ? decoded : 0.0f));
}
// The 8-bit code of channel value v of an sRGB input read as `encoding` says.
WRS_FN uint wrs_input_code(float v, uint encoding) {
    return encoding == WRS_INPUT_SRGB_VIEW ? wrs_srgb8_code_of(v) : wrs_srgb8_code(v);
}
// Whether a decoded input texel is usable: finite, and for composed input marked valid in alpha (its
// rendered quality there, above 0; 0 where no source tap was valid: wrs_composed_alpha).
WRS_FN bool wrs_input_valid(bool finite, uint encoding, float alpha) {
    return finite && (encoding != WRS_INPUT_COMPOSED || alpha > 0.0f);
}

// t^(1/3) for t > 0 from additions and multiplications only: three Newton steps for t^(-1/3) from a
// first guess made of t's bits, then t y^2 (relative error under 5e-7 from 1e-4 to 2e5). pow, inherited
// from exp2(y log2 t), may be ~10 ULP off and differ between devices, which the fp16 rounding of the
// fingerprint turns into whole steps; these operations are correctly rounded and kept unfused
// (WRS_PRECISE), so every device that rounds to nearest gets the CPU's bits.
WRS_FN float wrs_cbrt(float t) {
    WRS_PRECISE float y = uintBitsToFloat(0x54a21d2au - floatBitsToUint(t) / 3u);
    WRS_PRECISE float t3 = t * 0.333333343f;
    for (int i = 0; i < 3; ++i) {
        WRS_PRECISE float y3 = y * y * y;
        WRS_PRECISE float e = 1.33333337f - t3 * y3;
        y = y * e;
    }
    WRS_PRECISE float r = t * (y * y);
    return r;
}

// CIE 1976 L* of linear sRGB (D65), Y from the Rec. 709 primaries. No pow and no division (the
// constants' reciprocals are literals), every operation unfused: the same bits on every device.
WRS_FN float wrs_lab_f(float t) {
    WRS_PRECISE float lin = t * 7.78703690f + 0.137931034f;  // t / (3 (6/29)^2) + 4/29
    return t > 0.00885645207f ? wrs_cbrt(t) : lin;           // (6/29)^3
}
WRS_FN vec3 wrs_linear_to_lab(vec3 c) {
    WRS_PRECISE float X = 0.4124564f * c.x + 0.3575761f * c.y + 0.1804375f * c.z;
    WRS_PRECISE float Y = 0.2126729f * c.x + 0.7151522f * c.y + 0.0721750f * c.z;
    WRS_PRECISE float Z = 0.0193339f * c.x + 0.1191920f * c.y + 0.9503041f * c.z;
    WRS_PRECISE float xn = X * 1.05211103f;   // X / 0.95047
    WRS_PRECISE float zn = Z * 0.918417037f;  // Z / 1.08883
    float fx = wrs_lab_f(xn);
    float fy = wrs_lab_f(Y);
    float fz = wrs_lab_f(zn);
    WRS_PRECISE vec3 lab = vec3(116.0f * fy - 16.0f, 500.0f * (fx - fy), 200.0f * (fy - fz));
    return lab;
}

const uint WRS_CHANGE_OFF = 0u;    // eq. 6 only
const uint WRS_CHANGE_LSTAR = 1u;  // eq. 7 with ΔL = |L*1 − L*2| / 100 (the default)
const uint WRS_CHANGE_DE94 = 2u;   // eq. 7 with ΔE94 / 100 (graphic arts, kL = kC = kH = 1)

// |ΔL| of eq. 7, clamped to [0, 1].
WRS_FN float wrs_change(uint metric, vec3 a, vec3 b) {
    if (metric == WRS_CHANGE_OFF) return 0.0f;
    vec3 la = wrs_linear_to_lab(a);
    vec3 lb = wrs_linear_to_lab(b);
    float d;
    if (metric == WRS_CHANGE_LSTAR) {
        d = abs(la.x - lb.x);
    } else {
        float c1 = wrs_sqrt(la.y * la.y + la.z * la.z);
        float c2 = wrs_sqrt(lb.y * lb.y + lb.z * lb.z);
        float dl = la.x - lb.x;
        float dc = c1 - c2;
        float da = la.y - lb.y;
        float db = la.z - lb.z;
        float dh2 = max(da * da + db * db - dc * dc, 0.0f);
        float sc = 1.0f + 0.045f * c1;
        float sh = 1.0f + 0.015f * c1;
        float dcs = wrs_div(dc, sc);
        d = wrs_sqrt(dl * dl + dcs * dcs + wrs_div(dh2, sh * sh));
    }
    float r = wrs_div(d, 100.0f);
    return wrs_finite(r) ? clamp(r, 0.0f, 1.0f) : 1.0f;
}

WRS_END

#endif
