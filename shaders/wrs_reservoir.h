// Reservoirs: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_RESERVOIR_H
#define WRSFOV_WRS_RESERVOIR_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"
#include "wrs_colour.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Reservoirs (paper §3.1, §4.1–4.3; docs/conventions.md "Reservoirs")
// ---------------------------------------------------------------------------------------------

struct Reservoir {
    vec3 color;   // the kept sample, linear RGB
    float w;      // its weight p̂ when it was taken
    float w_sum;  // sum of (biased) candidate weights, > 0
    uint M;       // candidates seen, capped at WRS_M_MAX
    float z;      // linear depth of this pixel in the frame the reservoir was written (0 unknown)
};

WRS_FN Reservoir wrs_reservoir(vec3 color, float w, float w_sum, uint M, float z) {
    Reservoir r;
    r.color = color;
    r.w = w;
    r.w_sum = w_sum;
    r.M = M;
    r.z = z;
    return r;
}

// Packed storage: 4 x 32 bits = 16 bytes per pixel (docs/stability.md "The layout of `wrs-paper`").
//   word 0: colour R | G    (fp16, fp16)
//   word 1: colour B | w    (fp16, fp16)
//   word 2: w_sum           (fp32)
//   word 3: z | M           (fp16, uint16)
// fp16 is converted here, by hand and with round-to-nearest-even, because packHalf2x16 leaves
// the rounding to the implementation.
WRS_FN uint wrs_f32_to_f16(float f) {
    uint x = floatBitsToUint(f);
    uint sign = (x >> 16u) & 0x8000u;
    uint ax = x & 0x7fffffffu;
    if (ax >= 0x7f800000u) return sign | 0x7c00u | (ax > 0x7f800000u ? 0x200u : 0u);  // inf / nan
    if (ax >= 0x477ff000u) return sign | 0x7c00u;                                      // overflow
    if (ax >= 0x38800000u) {                                                           // normal
        uint base = ax - 0x38000000u;
        uint h = base >> 13u;
        uint rem = base & 0x1fffu;
        if (rem > 0x1000u || (rem == 0x1000u && (h & 1u) != 0u)) h += 1u;
        return sign | h;
    }
    uint e = ax >> 23u;
    if (e < 102u) return sign;  // below half the smallest subnormal: rounds to zero
    uint m = (ax & 0x7fffffu) | 0x800000u;
    uint shift = 126u - e;  // 14..24
    uint h = m >> shift;
    uint rem = m & ((1u << shift) - 1u);
    uint halfway = 1u << (shift - 1u);
    if (rem > halfway || (rem == halfway && (h & 1u) != 0u)) h += 1u;
    return sign | h;
}
// fp16 to fp32 is exact: where the compositor found the device's conversions exact (WRS_HARDWARE_HALF,
// Compositor::hardwareHalf, whose probe also unpacks every finite fp16 value, subnormals included) a shader
// takes the device's (one instruction against a dozen); the bits are the same.
WRS_FN float wrs_f16_to_f32(uint h) {
#if !defined(__cplusplus) && defined(WRS_HARDWARE_HALF)
    if (WRS_HARDWARE_HALF) return unpackHalf2x16(h).x;
#endif
    uint sign = (h & 0x8000u) << 16u;
    uint e = (h >> 10u) & 0x1fu;
    uint m = h & 0x3ffu;
    if (e == 0u) {
        float v = float(m) * 5.9604644775390625e-8f;  // m * 2^-24, exact
        return sign != 0u ? -v : v;
    }
    if (e == 31u) return uintBitsToFloat(sign | 0x7f800000u | (m << 13u));
    return uintBitsToFloat(sign | ((e + 112u) << 23u) | (m << 13u));
}
WRS_FN float wrs_round_f16(float f) { return wrs_f16_to_f32(wrs_f32_to_f16(f)); }
// Two fp16 values (low half first) as floats. fp16 to fp32 is exact, so the device's unpackHalf2x16 (a
// few operations, as the pyramid is read) agrees with the hand conversion on the CPU; a device that
// flushed fp16 subnormal inputs would differ below 6.1e-5 (docs/speed.md, "Not yet built").
#ifdef __cplusplus
WRS_FN vec2 wrs_unpack_f16x2(uint w) { return vec2(wrs_f16_to_f32(w & 0xffffu), wrs_f16_to_f32(w >> 16u)); }
#else
vec2 wrs_unpack_f16x2(uint w) { return unpackHalf2x16(w); }
#endif
#ifdef __cplusplus
// fp16 bits of f as a device's packHalf2x16 may give them (device_rounding.h): ties to even by default;
// otherwise, for a value fp16 cannot hold, the neighbour DeviceRounding::half picks (a finite value
// beyond the largest fp16: infinity or 65504), and a denormal result may be flushed to zero. A value
// fp16 holds converts exactly in every mode.
WRS_FN std::uint32_t wrs_device_f32_to_f16(float f) {
    const std::uint32_t h = wrs_f32_to_f16(f);
    const Permitted p = deviceRounding().half;
    const std::uint32_t ax = floatBitsToUint(f) & 0x7fffffffu;
    if (p == Permitted::Nearest || ax >= 0x7f800000u || wrs_f16_to_f32(h) == f) return h;
    const std::uint32_t sign = h & 0x8000u, mag = h & 0x7fffu;
    // The fp16 magnitudes either side of |f|: mag is one of them (overflow: infinity or 65504).
    const float af = std::fabs(f), am = std::fabs(wrs_f16_to_f32(mag));
    const std::uint32_t below = am > af ? mag - 1u : mag, above = am > af ? mag : mag + 1u;
    const double d = rounding_detail::direction(p, floatBitsToUint(f) ^ 0x68616cu);
    // Low and High are towards -inf and +inf; a value between is rounded as the hash says.
    const bool up = sign ? d < 0.0 : d > 0.0;
    std::uint32_t m = (p == Permitted::Mixed ? d > 0.0 : up) ? above : below;
    if (m > 0x7c00u) m = 0x7c00u;
    if (m < 0x400u) m = 0u;  // an fp16 denormal result may be flushed to zero
    return sign | m;
}
WRS_FN uint wrs_device_pack_half2x16(vec2 v) {
    return wrs_device_f32_to_f16(v.x) | (wrs_device_f32_to_f16(v.y) << 16u);
}
#endif
// fp16 for storage, rounded to nearest even on every device. Where the compositor lets the passes use
// the device's own conversion (Compositor::hardwareHalf: a shader that includes this header defines
// WRS_HARDWARE_HALF as its specialisation constant; in C++ the modelled device's choice), the value is
// first put on fp16's grid by hand (wrs_f16_grid: four integer operations against ~20 for
// wrs_f32_to_f16, which made the pyramid pass arithmetic-bound on a GPU) and the device converts a
// value fp16 holds exactly, which every conformant conversion returns as it is (spirvenv-correctly-
// rounded): the direction a conversion of an inexact value may round to, or a compiler's folding of
// pack and unpack into the computation of the value, never reaches a stored bit. Zeros, fp16
// denormals (which a device may flush), overflow and non-finite values get the hand conversion's bits
// by a shorter route (wrs_f16_outside_normal). Either way the bits are wrs_f32_to_f16's.
WRS_FN float wrs_f16_grid(float f) {
    uint b = floatBitsToUint(f);
    return uintBitsToFloat((b + 0xfffu + ((b >> 13u) & 1u)) & 0xffffe000u);
}
// |f| rounds to a normal fp16 value: [2^-14, 65520).
WRS_FN bool wrs_f16_normal(float f) {
    uint ax = floatBitsToUint(f) & 0x7fffffffu;
    return ax >= 0x38800000u && ax < 0x477ff000u;
}
// wrs_round_f16(f), bit for bit, in fewer operations where f rounds to a normal fp16 (wrs_f16_grid);
// for a 16-bit image store, which converts a value fp16 holds exactly on every device.
WRS_FN float wrs_f16_value(float f) { return wrs_f16_normal(f) ? wrs_f16_grid(f) : wrs_round_f16(f); }
#if defined(__cplusplus) && !defined(WRS_HARDWARE_HALF)
#define WRS_HARDWARE_HALF WRS_HARDWARE_HALF_MODEL
#endif
#ifdef WRS_HARDWARE_HALF
// The hand conversion's bits of a value outside fp16's normal range, in a few operations: below it
// (zeros, fp16 denormals) |f| 2^24 rounded to even, an exact product; above it infinity, or a NaN.
WRS_FN uint wrs_f16_outside_normal(float f) {
    uint b = floatBitsToUint(f), ax = b & 0x7fffffffu, sign = (b >> 16u) & 0x8000u;
    if (ax < 0x38800000u) return sign | uint(roundEven(abs(f) * 16777216.0f));
    return sign | 0x7c00u | (ax > 0x7f800000u ? 0x200u : 0u);
}
WRS_FN uint wrs_store_f16(float f) {
    if (!WRS_HARDWARE_HALF) return wrs_f32_to_f16(f);
    if (!wrs_f16_normal(f)) return wrs_f16_outside_normal(f);
    return wrs_device_pack_half2x16(vec2(wrs_f16_grid(f), 0.0f)) & 0xffffu;
}
WRS_FN uint wrs_store_f16x2(float a, float b) {
    if (!WRS_HARDWARE_HALF) return wrs_f32_to_f16(a) | (wrs_f32_to_f16(b) << 16u);
    if (wrs_f16_normal(a) && wrs_f16_normal(b)) return wrs_device_pack_half2x16(vec2(wrs_f16_grid(a), wrs_f16_grid(b)));
    return wrs_store_f16(a) | (wrs_store_f16(b) << 16u);
}
#else
WRS_FN uint wrs_store_f16(float f) { return wrs_f32_to_f16(f); }
WRS_FN uint wrs_store_f16x2(float a, float b) { return wrs_f32_to_f16(a) | (wrs_f32_to_f16(b) << 16u); }
#endif

WRS_FN uvec4 wrs_pack(Reservoir r) {
    uvec4 p;
    p.x = wrs_store_f16x2(r.color.x, r.color.y);
    p.y = wrs_store_f16x2(r.color.z, r.w);
    p.z = floatBitsToUint(r.w_sum);
    p.w = wrs_store_f16(r.z) | (min(r.M, WRS_M_MAX) << 16u);
    return p;
}
WRS_FN Reservoir wrs_unpack(uvec4 p) {
    Reservoir r;
    r.color = vec3(wrs_f16_to_f32(p.x & 0xffffu), wrs_f16_to_f32(p.x >> 16u), wrs_f16_to_f32(p.y & 0xffffu));
    r.w = wrs_f16_to_f32(p.y >> 16u);
    r.w_sum = uintBitsToFloat(p.z);
    r.z = wrs_f16_to_f32(p.w & 0xffffu);
    r.M = p.w >> 16u;
    return r;
}
// A loaded reservoir is usable as history only if everything in it is finite and w_sum > 0:
// corrupted or never-written storage (all zero) is discarded on load, never propagated.
WRS_FN bool wrs_reservoir_valid(Reservoir r) {
    return wrs_finite3(r.color) && wrs_finite(r.w) && wrs_finite(r.w_sum) && r.w_sum > 0.0f && wrs_finite(r.z) &&
           r.M > 0u;
}

// Options of the temporal combine.
const uint WRS_BIAS_BERNOULLI = 1u;  // eq. 6: scale history by its survival probability

// History weight after the temporal bias (eq. 7 = eq. 6 x change term), all from w_sum as loaded:
// w_sum1 = w_sum · (1 − |ΔL|) · (1 − w_cur / (w_sum + w_cur)).
WRS_FN float wrs_biased_history_weight(float w_sum, float w_cur, float change, bool bernoulli) {
    WRS_PRECISE float w1 = w_sum * (1.0f - change);
    if (bernoulli) w1 = w1 * (1.0f - wrs_div(w_cur, w_sum + w_cur));  // w_sum > 0, so the division is safe
    return max(w1, 0.0f);
}

// Probability threshold of the combine: history is kept iff rand <= wrs_keep_threshold.
// Used by tests to know how close a decision was.
WRS_FN float wrs_keep_threshold(float w_sum1, float w_cur) {
    float t = w_sum1 + w_cur;
    return t > 0.0f ? wrs_div(w_sum1, t) : 1.0f;
}

// One temporal step for one pixel (Alg. 2 with the biased history). Without usable history the
// reservoir starts from the candidate. `keep` reports whether the history sample was kept.
// An invalid candidate (w_cur == 0) never replaces history; a reservoir started from one gets
// w_sum = WRS_WSUM_MIN so that the next valid candidate replaces it.
WRS_FN Reservoir wrs_combine(bool has_history, Reservoir hist, vec3 cur_color, float w_cur, float z_cur, float rnd,
                             uint change_metric, bool bernoulli, WRS_OUT(bool) keep) {
    keep = false;
    if (!has_history) return wrs_reservoir(cur_color, w_cur, max(w_cur, WRS_WSUM_MIN), 1u, z_cur);
    float change = wrs_change(change_metric, cur_color, hist.color);
    WRS_PRECISE float w_sum1 = wrs_biased_history_weight(hist.w_sum, w_cur, change, bernoulli);
    WRS_PRECISE float total = w_sum1 + w_cur;
    WRS_PRECISE float lhs = rnd * total;
    keep = lhs <= w_sum1;
    Reservoir r = keep ? hist : wrs_reservoir(cur_color, w_cur, 0.0f, 0u, 0.0f);
    r.w_sum = clamp(total, WRS_WSUM_MIN, WRS_WSUM_MAX);
    r.M = min(hist.M + 1u, WRS_M_MAX);
    r.z = z_cur;
    return r;
}

WRS_END

#endif
