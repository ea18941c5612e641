// The per-pixel math of wrsfov, in the common subset of GLSL and C++ (see glsl_cpp.h).
//
// Compiled into every compute shader and into the CPU reference (compositor/reference.cpp), so the
// GPU and the reference can only differ where the Vulkan spec leaves a result free: the built-ins
// spelled wrs_div, wrs_exp, wrs_pow, wrs_sqrt, wrs_length and wrs_normalize (whose other permitted
// results the reference can take: device_rounding.h), and the rounding direction of the rest. What is
// stored quantised (fp16, the fingerprint and output codes) is rounded by hand from unfused operations
// (docs/speed.md, "Rounding: what a conformant device may do differently"). Equation numbers refer to
// Cantory et al., MIG '25 ("the paper"); section names to docs/conventions.md.
#ifndef WRSFOV_WRS_COMMON_H
#define WRSFOV_WRS_COMMON_H

#include "glsl_cpp.h"
#include "config.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Numbers and guards
// ---------------------------------------------------------------------------------------------

const float WRS_PI = 3.14159265358979f;
const float WRS_RAD_TO_DEG = 57.2957795130823f;
// Largest value a packed fp16 channel holds; colours and depths are clamped to it before packing.
const float WRS_HALF_MAX = 65504.0f;
// A reservoir never has w_sum <= 0 (docs/conventions.md "Reservoirs"): this is the floor it is clamped to, and the weight
// given to a reservoir that had to be started from an invalid candidate.
const float WRS_WSUM_MIN = 1e-30f;
// and never overflows: w_sum grows by at most 1 per frame, so this is reached only by corruption.
const float WRS_WSUM_MAX = 1e30f;

// True for finite floats. Works on the bits: some drivers fold isnan()/isinf() away.
WRS_FN bool wrs_finite(float x) { return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u; }
WRS_FN bool wrs_finite3(vec3 v) { return wrs_finite(v.x) && wrs_finite(v.y) && wrs_finite(v.z); }

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

// ---------------------------------------------------------------------------------------------
// Foveation (paper §4.3, docs/conventions.md "Foveation"): which levels of the colour pyramid a pixel blends
// ---------------------------------------------------------------------------------------------

const uint WRS_FOV_NONE = 0u;   // the application rendered foveated already: level 0 only
const uint WRS_FOV_MIP = 1u;    // box mip chain, rates 1 / 8x8 / 16x16, 1° linear blends
const uint WRS_FOV_GAUSS = 2u;  // [1 3 3 1] Gaussian pyramid, sigma growing with eccentricity
// The application rendered foveated and said how (quad views, a shading-rate map): level 0 of what
// the compose pass made of it, each pixel with the quality it was rendered at (wrs_submitted_quality).
const uint WRS_FOV_SUBMITTED = 3u;
// Whether a mode foveates a full-resolution frame itself (and so has levels, tile classes and a floor).
WRS_FN bool wrs_mode_simulated(uint mode) { return mode == WRS_FOV_MIP || mode == WRS_FOV_GAUSS; }

// Effective Gaussian sigma, in level-0 pixels, of pyramid level k built by repeated [1 3 3 1]/8
// filtering and decimation: sigma_k^2 = 0.75 * (4^k - 1) / 3 * ... = 0.25 * (4^k - 1).
// Levels 3 and 4 land on sigma 3.97 and 7.98, i.e. half the 8x8 and 16x16 subsampling factors,
// which is what makes `gauss` comparable with `mip`.
WRS_FN float wrs_gauss_level_sigma(uint k) {
    float p = float(1u << (2u * k));
    return 0.5f * wrs_sqrt(p - 1.0f);
}

// sigma(e) for `gauss` (documented in README "Foveation modes"): 0 inside the fovea, rising linearly
// from 0.5 at r_f to 4 (= 8x8 rate / 2) at the end of the mid-periphery, then linearly to 8
// (= 16x16 rate / 2) over the next 5°, constant after. r_mid = max(r_m, r_f); the first ramp is at
// least 1° long so that a fovea larger than the mid-periphery still blends.
WRS_FN float wrs_gauss_sigma(float e, float r_f, float r_m) {
    if (e <= r_f) return 0.0f;
    float r_mid = max(r_m, r_f + 1.0f);
    if (e <= r_mid) return 0.5f + wrs_div(3.5f * (e - r_f), r_mid - r_f);
    return 4.0f + 4.0f * min(wrs_div(e - r_mid, 5.0f), 1.0f);
}

// Levels to blend for a pixel at eccentricity e: colour = mix(level a, level b, t).
// Returned as vec3(a, b, t).
WRS_FN vec3 wrs_foveation_levels(uint mode, float e, float r_f, float r_m) {
    if (!wrs_mode_simulated(mode) || e <= r_f) return vec3(0.0f, 0.0f, 0.0f);
    if (mode == WRS_FOV_MIP) {
        float r_mid = max(r_m, r_f);
        bool skip_mid = r_f + 1.0f > r_mid;  // fovea reaches into the far periphery
        if (e < r_f + 1.0f) return vec3(0.0f, skip_mid ? 4.0f : 3.0f, e - r_f);
        if (skip_mid) return vec3(4.0f, 4.0f, 0.0f);
        if (e <= r_mid) return vec3(3.0f, 3.0f, 0.0f);
        if (e < r_mid + 1.0f) return vec3(3.0f, 4.0f, e - r_mid);
        return vec3(4.0f, 4.0f, 0.0f);
    }
    float s = wrs_gauss_sigma(e, r_f, r_m);
    for (uint k = 0u; k + 1u < uint(WRS_LEVELS); ++k) {
        float s0 = wrs_gauss_level_sigma(k);
        float s1 = wrs_gauss_level_sigma(k + 1u);
        if (s <= s1) return vec3(float(k), float(k + 1u), wrs_div(s - s0, s1 - s0));
    }
    return vec3(float(WRS_LEVELS - 1), float(WRS_LEVELS - 1), 0.0f);
}

// Tiles (docs/speed.md "Tiles"): 8x8-pixel tiles whose every pixel gets the same levels, known
// from the tile's eccentricity range, run through a dispatch of their own whose shader has those
// levels as constants and computes no eccentricity. A class holds only where wrs_foveation_levels
// returns exactly its levels for every pixel of the tile, so the output is bit for bit the same.
const uint WRS_TILE = 8u;
const uint WRS_TILE_ANY = 0u;    // levels per pixel (mixed tiles, mode none)
const uint WRS_TILE_FOVEA = 1u;  // every pixel e <= r_f: level 0
const uint WRS_TILE_MID = 2u;    // mip, every pixel in [r_f + 1, r_mid]: level 3
const uint WRS_TILE_FAR = 3u;    // every pixel past the last blend: level 4
const uint WRS_TILE_CLASSES = 4u;
// Sparse retention (docs/retention.md "Sparse retention"): far tiles that can hold nothing sharper
// than their candidates go on a fifth list and run the foveating pass alone, at `fov`'s cost.
const uint WRS_TILE_SKIP = 4u;
const uint WRS_TILE_LISTS = 5u;
// Slack on the eccentricity range: far above the float rounding of a pixel's e (~1e-4 degrees).
const float WRS_TILE_MARGIN_DEG = 0.05f;

WRS_FN vec3 wrs_tile_levels(uint cls) {
    if (cls == WRS_TILE_MID) return vec3(3.0f, 3.0f, 0.0f);
    if (cls == WRS_TILE_FAR || cls == WRS_TILE_SKIP) return vec3(4.0f, 4.0f, 0.0f);
    return vec3(0.0f, 0.0f, 0.0f);
}

// The class of a tile whose pixels' eccentricities all lie in [lo, hi] (see wrs_foveation_levels).
WRS_FN uint wrs_tile_class_of_range(uint mode, float lo, float hi, float r_f, float r_m) {
    if (!wrs_mode_simulated(mode)) return WRS_TILE_ANY;
    if (hi <= r_f) return WRS_TILE_FOVEA;
    if (mode == WRS_FOV_MIP) {
        float r_mid = max(r_m, r_f);
        if (r_f + 1.0f > r_mid) return lo >= r_f + 1.0f ? WRS_TILE_FAR : WRS_TILE_ANY;
        if (lo >= r_f + 1.0f && hi <= r_mid) return WRS_TILE_MID;
        return lo >= r_mid + 1.0f ? WRS_TILE_FAR : WRS_TILE_ANY;
    }
    // gauss: sigma reaches 8 (past level 4's 7.98) 5 degrees beyond the mid-periphery.
    return lo >= max(r_m, r_f + 1.0f) + 5.0f ? WRS_TILE_FAR : WRS_TILE_ANY;
}

// Ray through a point of the image in pixel units (a pixel's centre is (x + 0.5, y + 0.5)).
WRS_FN vec3 wrs_image_point_ray(vec2 pt, uvec2 size, vec4 fov_tan) {
    float tx = fov_tan.x + wrs_div(pt.x, float(size.x)) * (fov_tan.y - fov_tan.x);
    float ty = fov_tan.z - wrs_div(pt.y, float(size.y)) * (fov_tan.z - fov_tan.w);
    return wrs_normalize(vec3(tx, ty, -1.0f));
}

// The classification's constants of a view (EyeParams::tile, set once per frame): a pixel's width
// and height on the image plane (z = -1, tangent units; x grows rightwards, y downwards) and rho, a
// bound in degrees on the angle from a tile's centre to any point of the tile. The central
// projection of the image plane onto the unit sphere shrinks every length, radially by 1 / (1 + r^2)
// and across by 1 / sqrt(1 + r^2) at distance r from the axis, so an angle in radians is at most the
// distance on the plane: rho is a tile's half-diagonal there (a partial tile at the edge is
// smaller). It is tight on the axis and about 1 / cos^2 too wide at an angle from it, which widens
// the mixed-tile rings around the fovea's edges a little when the gaze is far off-axis.
WRS_FN vec4 wrs_tile_geometry(uvec2 size, vec4 fov_tan) {
    vec2 pixel = vec2(fov_tan.y - fov_tan.x, fov_tan.z - fov_tan.w) / vec2(size);
    float rho = 0.5f * length(float(WRS_TILE) * pixel) * WRS_RAD_TO_DEG;
    return vec4(pixel.x, pixel.y, rho, 0.0f);
}

// The class of tile t of a view: the eccentricity range of its footprint is the centre's e plus and
// minus rho, widened by the margin (which also covers the centre's ray here being computed with the
// pixel size rather than as wrs_image_point_ray does: a few ulps). One ray and one arctangent per
// tile; the angle to each corner it replaced cost four more of each (docs/speed.md "Tiles").
WRS_FN uint wrs_tile_class(uint mode, uvec2 t, uvec2 size, vec4 fov_tan, vec4 tile, vec3 gaze, float r_f, float r_m) {
    vec2 c = 0.5f * vec2(t * WRS_TILE + min((t + uvec2(1u, 1u)) * WRS_TILE, size));
    vec3 ray = wrs_normalize(vec3(fov_tan.x + c.x * tile.x, fov_tan.z - c.y * tile.y, -1.0f));
    float e = wrs_eccentricity_deg(ray, gaze);
    return wrs_tile_class_of_range(mode, e - tile.z - WRS_TILE_MARGIN_DEG, e + tile.z + WRS_TILE_MARGIN_DEG, r_f, r_m);
}

// The lowest pyramid level above 0 that a mode's wrs_foveation_levels ever returns: `mip` blends
// level 0 with the 8x8 (3) and 16x16 (4) rates only, `gauss` any level, and `none` none (method
// `wrs` still reads level 4, its fingerprint). Levels below it are built (the chain needs them) but
// never stored.
WRS_FN uint wrs_first_stored_level(uint mode) {
    if (mode == WRS_FOV_MIP) return 3u;
    if (mode == WRS_FOV_GAUSS) return 1u;
    return uint(WRS_LEVELS) - 1u;
}

// Pyramid level sizes: each level halves, rounding up, never below 1.
WRS_FN uvec2 wrs_level_size(uvec2 size0, uint level) {
    uvec2 s = size0;
    for (uint k = 0u; k < level; ++k) s = max((s + uvec2(1u, 1u)) / 2u, uvec2(1u, 1u));
    return s;
}

// Offset (in texels) of a level inside one eye's pyramid, and the size of one eye's pyramid.
WRS_FN uint wrs_level_offset(uvec2 size0, uint level) {
    uint off = 0u;
    for (uint k = 0u; k < level; ++k) {
        uvec2 s = wrs_level_size(size0, k);
        off += s.x * s.y;
    }
    return off;
}
WRS_FN uint wrs_pyramid_texels(uvec2 size0) { return wrs_level_offset(size0, uint(WRS_LEVELS)); }

#ifdef __cplusplus
// A level's size over level 0's (FrameParams::level_scale), worked out once on the host: the bilinear
// weights of the fingerprint and of every foveated colour must be the same on every device, and a
// shader's division may be 2.5 ULP off.
WRS_FN vec2 wrs_level_scale(uvec2 size0, uint level) {
    const uvec2 s = wrs_level_size(size0, level);
    return vec2(float(double(s.x) / double(size0.x)), float(double(s.y) / double(size0.y)));
}
#endif

// Bilinear lookup of a coarser level at the centre of level-0 pixel p, clamp to edge; `scale` is
// wrs_level_scale of the level. Returns the integer corner in i0 (the other corner is i0 + 1
// clamped, in i1) and the weights. Unfused, so that every device computes the same weights.
WRS_FN vec2 wrs_bilinear_setup(uvec2 p, vec2 scale, uvec2 size_l, WRS_OUT(uvec2) i0, WRS_OUT(uvec2) i1) {
    WRS_PRECISE vec2 c = vec2(p) + vec2(0.5f, 0.5f);
    WRS_PRECISE vec2 at = c * scale - vec2(0.5f, 0.5f);
    vec2 pos = clamp(at, vec2(0.0f, 0.0f), vec2(size_l) - vec2(1.0f, 1.0f));
    vec2 f = floor(pos);
    i0 = uvec2(f);
    i1 = min(i0 + uvec2(1u, 1u), size_l - uvec2(1u, 1u));
    return pos - f;
}
// Unfused (a device may otherwise fuse each multiply and add, or not): the same bits everywhere.
WRS_FN vec4 wrs_bilinear(vec4 c00, vec4 c10, vec4 c01, vec4 c11, vec2 f) {
    WRS_PRECISE vec4 top = c00 + (c10 - c00) * f.x;
    WRS_PRECISE vec4 bottom = c01 + (c11 - c01) * f.x;
    WRS_PRECISE vec4 r = top + (bottom - top) * f.y;
    return r;
}

// Linear blend of two pyramid samples, written out and unfused so every device rounds alike.
WRS_FN vec4 wrs_blend(vec4 a, vec4 b, float t) {
    WRS_PRECISE vec4 r = a + (b - a) * t;
    return r;
}

// Source texel of a downsample tap: level-(k-1) index 2*d + o, clamped to the level.
WRS_FN uvec2 wrs_down_tap(uvec2 d, ivec2 o, uvec2 src_size) {
    ivec2 s = ivec2(2u * d) + o;
    return uvec2(clamp(s, ivec2(0, 0), ivec2(src_size) - ivec2(1, 1)));
}
// `mip`: 2x2 box over taps o in {0,1}^2, in the order (0,0) (1,0) (0,1) (1,1). The filters are kept in
// the order written (a device may otherwise reassociate the sums and fuse the multiplies).
WRS_FN vec4 wrs_down_box(vec4 t00, vec4 t10, vec4 t01, vec4 t11) {
    WRS_PRECISE vec4 r = ((t00 + t10) + (t01 + t11)) * 0.25f;
    return r;
}
// `gauss`: separable [1 3 3 1]/8 over taps o in {-1..2}^2, given as 4 rows of 4 taps each.
WRS_FN vec4 wrs_binomial_row(vec4 a, vec4 b, vec4 c, vec4 d) {
    WRS_PRECISE vec4 r = (a + d + 3.0f * (b + c)) * 0.125f;
    return r;
}

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

// ---------------------------------------------------------------------------------------------
// Random numbers: one hash of (x, y, eye, frame, seed), identical on CPU and GPU
// ---------------------------------------------------------------------------------------------

// PCG output permutation (O'Neill 2014; Jarzynski & Olano 2020 "hash functions for GPU rendering").
WRS_FN uint wrs_pcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
WRS_FN uint wrs_hash(uint x, uint y, uint eye, uint frame, uint seed) {
    uint h = wrs_pcg(x ^ wrs_pcg(seed));
    h = wrs_pcg(y ^ h);
    h = wrs_pcg(eye ^ h);
    return wrs_pcg(frame ^ h);
}
// 24 random bits as a float in [0, 1): exact on both sides.
WRS_FN float wrs_rand(uint x, uint y, uint eye, uint frame, uint seed) {
    return float(wrs_hash(x, y, eye, frame, seed) >> 8u) * (1.0f / 16777216.0f);
}

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

// Packed storage: 4 x 32 bits = 16 bytes per pixel (README "Reservoir layout").
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


// ---------------------------------------------------------------------------------------------
// Quality-aware retention (method `wrs`; `wrs-paper` above is the published rule, kept as the
// baseline). Departures from the paper's eq. 6–7, with the measurements behind them, are in
// docs/retention.md:
//   - a sample's quality is the shading rate it was foveated at, q = mix(4^-a, 4^-b, t) for the
//     levels (a, b, t) of wrs_foveation_levels (1 in the fovea, 1/64 at 8x8, 1/256 at 16x16);
//     with foveation `none` (the application foveated) it is the paper's p̂;
//   - a candidate of higher quality replaces the kept sample, a lower one never does, and equal
//     ones are merged (running mean, weight capped at 16 candidates) or, optionally, go through
//     the A-Chao combine of eq. 6;
//   - the change test compares a fingerprint of the scene around the sample (L* of pyramid level 4,
//     16x16 pixels, identical for a sharp and a foveated image of the same scene) with the one
//     stored when the sample was taken, so a shading-rate change is never a change;
//   - the kept sample carries its sub-pixel offset and follows the motion vectors; a sample that
//     leaves its pixel's footprint is looked up in the neighbouring pixel, else it is no history;
//   - under motion a kept sample is shown as the tent-weighted mean of the tracked samples of its
//     quality at the pixel centre (wrs_shown_add); the reservoir stores the sample itself.
// ---------------------------------------------------------------------------------------------

const uint WRS_RULE_MERGE = 0u;      // equal quality: running mean (default)
const uint WRS_RULE_RESERVOIR = 1u;  // equal quality: A-Chao combine with the eq. 6 bias
const uint WRS_RULE_ORACLE = 2u;     // evaluation only: keep whichever is closer to the reference
// Evaluation only: the oracle restricted to retention. The history is kept iff it is closer to the
// reference *and* of higher quality than the candidate; otherwise the candidate is taken. The ceiling
// of keeping what foveation throws away, without the plain oracle's selection among equally or less
// sharp samples (which needs the reference to tell which of two blurred values happens to be closer).
const uint WRS_RULE_ORACLE_Q = 3u;
WRS_FN bool wrs_rule_is_oracle(uint rule) { return rule == WRS_RULE_ORACLE || rule == WRS_RULE_ORACLE_Q; }

// Pyramid level whose L* is the change-test fingerprint (the pyramid pass stores L* in its alpha).
const uint WRS_FP_LEVEL = 4u;
// Alpha of a written pyramid texel: levels below WRS_FP_LEVEL keep the filtered validity (unused),
// level WRS_FP_LEVEL holds its L*, the change-test fingerprint of method `wrs`.
WRS_FN vec4 wrs_pyramid_texel(vec4 filtered, uint level) {
    if (level == WRS_FP_LEVEL) return vec4(filtered.x, filtered.y, filtered.z, wrs_linear_to_lab(vec3(filtered)).x);
    return filtered;
}
// Fingerprint storage: 8 bits, 2.55 codes per L* unit (L* 0..100 -> 0..255, above white saturates).
const float WRS_FP_SCALE = 2.55f;
// Change-test noise model, in L*: half a fingerprint code (0.196) + the largest L* step of one 8-bit
// sRGB input code (0.40, at mid grey: a 16x16 block moving by a whole code) + fp16 storage of the
// pyramid (the level-4 L* of then and of now each rounded by at most half a step, 1/32 below
// L* 128: 0.0625) = 0.66. Bilinear resampling adds nothing for a sample that never moved (same
// weights), and for one that moved the L* range of the four level-4 taps is added.
const float WRS_FP_TOL = 0.66f;
// Relative quality difference below which two samples count as equal (fp16 stores q to 2^-11).
const float WRS_Q_EQUAL = 0.0009765625f;  // 2^-10
// The merged weight is capped at this many candidates: the mean follows a slow change within ~16 frames.
const float WRS_MERGE_CAP = 16.0f;
// Offsets are stored as signed 8-bit, 254 codes per pixel: d in [-0.5, 0.5) maps to -127..126.
const float WRS_OFFSET_SCALE = 254.0f;

// Flags of a tracked reservoir.
const uint WRS_FLAG_MOVED = 1u;  // the sample has moved relative to the pixel grid since it was taken
const uint WRS_FLAG_LANDED = 2u;  // a landed wide sample (wrs_landed_quality): a wide view's, taken near the pixel

struct Tracked {
    vec3 color;   // the kept sample (or the mean of equal-quality samples), linear RGB
    float q;      // its quality, > 0 for a usable reservoir
    float w_sum;  // weight of the merged mean (merge) or the biased sum (reservoir), > 0
    float fp;     // fingerprint (L*) when the sample was taken, quantised to 1 / WRS_FP_SCALE
    uint flags;   // WRS_FLAG_*
    float z;      // linear depth of the pixel when the reservoir was written (0 unknown)
    vec2 d;       // sample position minus pixel centre, in pixels, each in [-0.5, 0.5]
};

// Quality of a sample foveated with levels lv = (a, b, t): the shading rate, 4^-level, blended.
WRS_FN float wrs_level_quality(vec3 lv) {
    // 4^-level from its exponent bits: exact (a quotient may be 2.5 ULP off).
    float qa = uintBitsToFloat((127u - 2u * uint(lv.x)) << 23u);
    float qb = uintBitsToFloat((127u - 2u * uint(lv.y)) << 23u);
    WRS_PRECISE float q = qa + (qb - qa) * lv.z;
    return q;
}

// The quality of a pixel's candidate, for every kind of input (the one place the retain pass and the
// CPU reference take it from): the shading rate of the levels it was foveated with (`mip`, `gauss`),
// the paper's p-hat (`none`: the application foveated and did not say how), or the quality it was
// rendered at (submitted foveation: q_sub, from the compose pass). 0 for an input pixel that was not
// finite (`valid` false): such a candidate never replaces a sharper history.
WRS_FN float wrs_candidate_quality(uint mode, vec3 lv, float e, float r_f, float q_sub, bool valid) {
    if (!valid) return 0.0f;
    if (mode == WRS_FOV_SUBMITTED) return q_sub;
    if (mode == WRS_FOV_NONE) return wrs_sample_weight(e, r_f);
    return wrs_level_quality(lv);
}

// 1 / WRS_FP_SCALE as a literal: a quotient may be 2.5 ULP off.
const float WRS_FP_STEP = 0.392156869f;
// Unfused: a fused multiply-add may round a value near a code boundary to the other code.
WRS_FN uint wrs_fp_code(float lstar) {
    WRS_PRECISE float x = lstar * WRS_FP_SCALE + 0.5f;
    return uint(clamp(floor(x), 0.0f, 255.0f));
}
WRS_FN float wrs_fp_value(uint code) { return float(code) * WRS_FP_STEP; }

WRS_FN uint wrs_offset_code(float d, float u) {
    // -127..126: the footprint is half-open, [-0.5, 0.5), so +127/254 = 0.5 would leave it.
    WRS_PRECISE float x = d * WRS_OFFSET_SCALE + u;
    int c = clamp(int(floor(x)), -127, 126);
    return uint(c) & 0xffu;
}
WRS_FN float wrs_offset_value(uint code) {
    int c = int(code & 0xffu);
    if (c > 127) c -= 256;
    return float(c) * 0.00393700786f;  // 1 / WRS_OFFSET_SCALE (exactly -0.5 for -127)
}

// Packed storage, 16 bytes per pixel like the paper's reservoir (README "Reservoir layout"):
//   word 0: colour R | G           (fp16, fp16)
//   word 1: colour B | q           (fp16, fp16)
//   word 2: w_sum | fp | flags     (fp16, uint8, uint8)
//   word 3: z | dx | dy            (fp16, snorm8 x 254, snorm8 x 254)
// The offset is quantised with a dither `u` in [0, 1) (floor(d * 254 + u)): wrs_offset_dither.
WRS_FN uvec4 wrs_pack_tracked(Tracked r, vec2 u) {
    uvec4 p;
    p.x = wrs_store_f16x2(r.color.x, r.color.y);
    p.y = wrs_store_f16x2(r.color.z, r.q);
    p.z = wrs_store_f16(r.w_sum) | (wrs_fp_code(r.fp) << 16u) | ((r.flags & 0xffu) << 24u);
    p.w = wrs_store_f16(r.z) | (wrs_offset_code(r.d.x, u.x) << 16u) | (wrs_offset_code(r.d.y, u.y) << 24u);
    return p;
}
// Single fields of a packed reservoir, for the lookups that unpack only what they test.
WRS_FN vec3 wrs_packed_color(uvec4 p) {
    return vec3(wrs_f16_to_f32(p.x & 0xffffu), wrs_f16_to_f32(p.x >> 16u), wrs_f16_to_f32(p.y & 0xffffu));
}
WRS_FN float wrs_packed_quality(uvec4 p) { return wrs_f16_to_f32(p.y >> 16u); }
WRS_FN float wrs_packed_depth(uvec4 p) { return wrs_f16_to_f32(p.w & 0xffffu); }
WRS_FN vec2 wrs_packed_offset(uvec4 p) { return vec2(wrs_offset_value(p.w >> 16u), wrs_offset_value(p.w >> 24u)); }
WRS_FN Tracked wrs_unpack_tracked(uvec4 p) {
    Tracked r;
    r.color = wrs_packed_color(p);
    r.q = wrs_packed_quality(p);
    r.w_sum = wrs_f16_to_f32(p.z & 0xffffu);
    r.fp = wrs_fp_value((p.z >> 16u) & 0xffu);
    r.flags = p.z >> 24u;
    r.z = wrs_packed_depth(p);
    r.d = wrs_packed_offset(p);
    return r;
}
// Usable as history: finite, positive quality and weight. All-zero storage (no history) fails.
WRS_FN bool wrs_tracked_valid(Tracked r) {
    return wrs_finite3(r.color) && wrs_finite(r.q) && r.q > 0.0f && wrs_finite(r.w_sum) && r.w_sum > 0.0f &&
           wrs_finite(r.z);
}

// The dither of the offset quantisation: the same for every pixel of a frame (from the hash of the
// frame alone), so that under uniform motion all samples round alike and their lattice stays
// intact (a per-pixel dither lets neighbours drift apart by 1/254 px per frame, and the half-open
// footprints then see doubles and holes), and different from frame to frame, so that a slow
// sub-pixel drift still accumulates in expectation instead of being rounded away.
WRS_FN vec2 wrs_offset_dither(uint frame, uint seed) {
    uint h = wrs_hash(0u, 0u, 0u, frame, seed);
    return vec2((float(h & 255u) + 0.5f) * 0.00390625f, (float((h >> 8u) & 255u) + 0.5f) * 0.00390625f);
}

// Motion reach (docs/retention.md "Motion reach"): a pixel whose motion moves it more than `reach`
// pixels on either axis in one frame (the compositor's limit, CompositorConfig::motionReachDeg at
// the view's centre) has no tracked history; it takes its candidate. Nothing is seen sharply that
// fast, and the limit lets the classification know without reading a tile's motion that no sample
// farther away than the reach can arrive there (wrs_reach_blocks). A departure from DESIGN.md's
// tracked reprojection, which tracks at any speed (a reach of +inf does so).
WRS_FN bool wrs_within_reach(vec2 m, float reach) { return abs(m.x) <= reach && abs(m.y) <= reach; }

// Tracked reprojection. Each reservoir's sample sits at its pixel's centre + d, |d| < 0.5. Pixel p
// looks for the sample now inside its footprint: its centre's previous position pos = centre + mv
// (a non-finite motion is zero motion), and a sample stored at pixel q, now at q + 0.5 + d_q in the
// previous frame, is inside iff q + 0.5 + d_q − pos is in [−0.5, 0.5)² (half-open, so a sample is
// inside exactly one footprint). Only the 2x2 pixels from base = floor(pos − 0.5) can hold one.
// Returns false when pos is off-screen, or when the motion is beyond the view's reach
// (wrs_within_reach): that pixel has no history.
WRS_FN bool wrs_track_start(uvec2 p, uvec2 size, vec3 mv, float reach, WRS_OUT(vec2) pos, WRS_OUT(ivec2) base) {
    bool finite_xy = wrs_finite(mv.x) && wrs_finite(mv.y);
    vec2 m = finite_xy ? vec2(mv.x, mv.y) : vec2(0.0f, 0.0f);
    pos = vec2(p) + vec2(0.5f, 0.5f) + m;
    base = ivec2(p);
    if (!wrs_within_reach(m, reach)) return false;
    if (!(pos.x >= 0.0f && pos.y >= 0.0f && pos.x < float(size.x) && pos.y < float(size.y))) return false;
    base = ivec2(floor(pos - vec2(0.5f, 0.5f)));
    return true;
}
// The k-th (0..3) pixel of the 2x2 block; false when it is off-screen.
WRS_FN bool wrs_track_tap(ivec2 base, uint k, uvec2 size, WRS_OUT(uvec2) q) {
    ivec2 t = base + ivec2(int(k & 1u), int(k >> 1u));
    q = uvec2(clamp(t, ivec2(0, 0), ivec2(size) - ivec2(1, 1)));
    return t.x >= 0 && t.y >= 0 && t.x < int(size.x) && t.y < int(size.y);
}
// Where the sample kept at pixel q (offset dq) sits now relative to p's centre.
WRS_FN vec2 wrs_track_offset(uvec2 q, vec2 dq, vec2 pos) { return vec2(q) + vec2(0.5f, 0.5f) + dq - pos; }
WRS_FN bool wrs_track_inside(vec2 d) { return d.x >= -0.5f && d.x < 0.5f && d.y >= -0.5f && d.y < 0.5f; }
// Fallback when no sample is inside p's footprint: a sample within a quarter pixel of it (|d| < 0.75
// per axis), moved onto the footprint's edge. Motion vectors are fp16 in most applications, and their
// per-pixel rounding (up to 1/256 px at 4..8 px of motion) makes neighbouring samples drift apart:
// without the fallback the gaps open holes that show the blurred candidate (and flicker), with it a
// sample is shown at most a quarter pixel from where it belongs (nearest-pixel reprojection: half).
WRS_FN bool wrs_track_near(vec2 d) { return abs(d.x) < 0.75f && abs(d.y) < 0.75f; }
WRS_FN vec2 wrs_track_snap(vec2 d) {
    const float hi = 126.0f / WRS_OFFSET_SCALE;  // the largest stored offset below 0.5
    return clamp(d, vec2(-0.5f, -0.5f), vec2(hi, hi));
}
// Of two samples inside the footprint (possible where neighbouring samples drifted unevenly), the
// higher quality one, then the one nearer the centre: is `a` preferred over `b`?
WRS_FN bool wrs_track_prefer(float qa, vec2 da, float qb, vec2 db) {
    return qa > qb || (qa == qb && dot(da, da) < dot(db, db));
}

// wrs_tracked_valid on a packed reservoir, without unpacking it: fp16 to fp32 is exact, so a half is
// finite iff its exponent is not all ones, and positive iff its sign is clear and it is not zero.
WRS_FN bool wrs_half_finite(uint h) { return (h & 0x7c00u) != 0x7c00u; }
WRS_FN bool wrs_half_positive(uint h) { return (h & 0x8000u) == 0u && (h & 0x7fffu) != 0u; }
WRS_FN bool wrs_packed_tracked_valid(uvec4 p) {
    return wrs_half_finite(p.x & 0xffffu) && wrs_half_finite(p.x >> 16u) && wrs_half_finite(p.y & 0xffffu) &&
           wrs_half_finite(p.y >> 16u) && wrs_half_positive(p.y >> 16u) && wrs_half_finite(p.z & 0xffffu) &&
           wrs_half_positive(p.z & 0xffffu) && wrs_half_finite(p.w & 0xffffu);
}

// The 2x2 lookup, fed one tap at a time (wrs_track_consider), then read (wrs_track_end): the best
// sample inside the footprint, else the best near it (snapped onto the footprint's edge). Candidates
// are kept packed, and only their quality and offset unpacked, until the one taken is unpacked once.
// Outside the footprint one tap is kept: the best near one, else the best within a pixel per axis
// (the gap's sample, wrs_track_gap), so a near tap always displaces a gap's.
struct TrackState {
    bool has_inside;
    uvec4 h;
    float hq;
    vec2 d;
    uvec2 q;
    bool has_outer;  // a tap within a pixel per axis outside the footprint
    bool has_near;   // ... and it is near (wrs_track_near)
    uvec4 hn;
    float hnq;
    vec2 dn;
    uvec2 qn;
};
WRS_FN TrackState wrs_track_begin(uvec2 p) {
    TrackState s;
    s.has_inside = false;
    s.h = uvec4(0u, 0u, 0u, 0u);
    s.hq = 0.0f;
    s.d = vec2(0.0f, 0.0f);
    s.q = p;
    s.has_outer = false;
    s.has_near = false;
    s.hn = s.h;
    s.hnq = 0.0f;
    s.dn = s.d;
    s.qn = p;
    return s;
}
// The packed reservoir pk stored at tap qk, for the pixel whose centre was at pos (wrs_track_start).
WRS_FN void wrs_track_consider(WRS_INOUT(TrackState) s, uvec4 pk, uvec2 qk, vec2 pos) {
    if (!wrs_packed_tracked_valid(pk)) return;
    float qual = wrs_packed_quality(pk);
    vec2 dk = wrs_track_offset(qk, wrs_packed_offset(pk), pos);
    if (wrs_track_inside(dk)) {
        if (s.has_inside && !wrs_track_prefer(qual, dk, s.hq, s.d)) return;
        s.has_inside = true;
        s.h = pk;
        s.hq = qual;
        s.d = dk;
        s.q = qk;
        return;
    }
    bool is_near = wrs_track_near(dk);
    if (!(abs(dk.x) < 1.0f && abs(dk.y) < 1.0f)) return;
    // The same tier as the tap held: the preferred one; a near tap over a gap's; never a gap's over a near.
    if (s.has_outer && (is_near == s.has_near ? !wrs_track_prefer(qual, dk, s.hnq, s.dn) : !is_near)) return;
    s.has_outer = true;
    s.has_near = is_near;
    s.hn = pk;
    s.hnq = qual;
    s.dn = dk;
    s.qn = qk;
}
// The history found (false: none; then h is all-zero, d = 0 and q the pixel itself), its offset
// and the pixel it was stored at.
WRS_FN bool wrs_track_end(TrackState s, WRS_OUT(Tracked) h, WRS_OUT(vec2) d, WRS_OUT(uvec2) q) {
    bool use_near = !s.has_inside && s.has_near;
    h = wrs_unpack_tracked(use_near ? s.hn : s.h);
    d = use_near ? wrs_track_snap(s.dn) : s.d;
    q = use_near ? s.qn : s.q;
    return s.has_inside || s.has_near;
}

// A gap between unevenly drifted samples (docs/retention.md "Natural texture in motion"): under a slow
// pan, samples kept in different frames sit at different sub-pixel phases and neighbours end up to
// two pixels apart, so a pixel's lookup can find nothing within the fallback's reach although kept
// samples lie within a pixel on either side. For such a pixel (wrs_track_end false), the nearest valid
// tap within a pixel per axis (the higher quality first, as wrs_track_prefer). For display only: the
// pixel stores its candidate as before (a sample moved a whole pixel onto the footprint would be
// misplaced by half a pixel from then on), and shows the kept neighbourhood (wrs_shown_color) where
// the retention rule would keep that sample. Returns the gap's sample (h, its offset snapped onto the
// footprint as wrs_track_end does, and the pixel it was stored at); false when no valid tap lies within
// a pixel. wrs_track_consider gathers it in the same pass over the taps as the lookup (the outer tap
// when none is near); it is meaningful only where wrs_track_end found nothing: then no valid tap
// within a pixel was inside or near, and the outer tap is the best of them.
WRS_FN bool wrs_track_gap(TrackState s, WRS_OUT(Tracked) h, WRS_OUT(vec2) d, WRS_OUT(uvec2) q) {
    h = wrs_unpack_tracked(s.hn);
    d = wrs_track_snap(s.dn);
    q = s.qn;
    return s.has_outer;
}

// Display of a kept sample under motion (docs/retention.md "Display"). The tracked samples of the
// 2x2 lookup sit at sub-pixel offsets from the pixel centre, so showing the one inside the footprint
// shows a colour up to half a pixel away; on sharp, aliased content that is the wrong side of an edge.
// Shown instead: the tent-weighted mean (bilinear on the samples' lattice) of the tracked samples of
// the kept sample's quality that pass the depth test, each weighted by max(0, 1 - |d|) per axis of
// its offset d from the centre. The reservoir keeps the sample itself, so the display never feeds
// back into what is stored. Fed one tap at a time, as wrs_track_consider; acc = (sum w c, sum w).
// In two steps: a tap's weight (wrs_shown_weight: 0 where it is not a valid sample or fails the depth
// test), which does not depend on the kept sample, so the retain pass works it out while it passes
// over the taps for the lookup and keeps a float per tap instead of the taps' depth and offset words;
// then the taps of the kept sample's quality are added with it (wrs_shown_add_weighted).
WRS_FN float wrs_shown_weight(uvec4 pk, uvec2 qk, vec2 pos, float z_cur, float dz, float tau) {
    if (!wrs_packed_tracked_valid(pk)) return 0.0f;
    if (wrs_depth_flush(wrs_packed_depth(pk), z_cur, dz, tau)) return 0.0f;
    vec2 dk = wrs_track_offset(qk, wrs_packed_offset(pk), pos);
    return max(0.0f, 1.0f - abs(dk.x)) * max(0.0f, 1.0f - abs(dk.y));
}
// Reads only pk's colour and quality (words 0 and 1). A weight of 0 adds nothing, as a valid tap of
// weight 0 would (its colour is finite), and an invalid tap is never read.
WRS_FN void wrs_shown_add_weighted(WRS_INOUT(vec4) acc, uvec4 pk, float w, float hq) {
    if (!(w > 0.0f)) return;
    if (abs(wrs_packed_quality(pk) - hq) > hq * WRS_Q_EQUAL) return;
    vec3 col = wrs_packed_color(pk);
    acc += vec4(col.x * w, col.y * w, col.z * w, w);
}
WRS_FN void wrs_shown_add(WRS_INOUT(vec4) acc, uvec4 pk, uvec2 qk, vec2 pos, float hq, float z_cur, float dz,
                          float tau) {
    wrs_shown_add_weighted(acc, pk, wrs_shown_weight(pk, qk, pos, z_cur, dz, tau), hq);
}
WRS_FN vec3 wrs_shown_end(vec4 acc, vec3 kept) {
    return acc.w > 0.0f ? vec3(wrs_div(acc.x, acc.w), wrs_div(acc.y, acc.w), wrs_div(acc.z, acc.w)) : kept;
}
// The shown colour of the kept sample (quality hq, colour `kept`) from the packed taps t0..t3 of the 2x2
// lookup and their weights w (wrs_shown_weight; 0 where a tap was not read).
WRS_FN vec3 wrs_shown_mean(uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3, vec4 w, float hq, vec3 kept) {
    vec4 acc = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    wrs_shown_add_weighted(acc, t0, w.x, hq);
    wrs_shown_add_weighted(acc, t1, w.y, hq);
    wrs_shown_add_weighted(acc, t2, w.z, hq);
    wrs_shown_add_weighted(acc, t3, w.w, hq);
    return wrs_shown_end(acc, kept);
}
// The same from the taps alone, at the 2x2 lookup at `base` (all-zero where a tap was not read), as the
// CPU reference computes it. A tap off the screen was not read, so it is invalid and weighs 0 before its
// pixel is used: the pixels are base + (k & 1, k >> 1) unclamped (wrs_track_tap's clamp is not needed).
// The four taps' weights (wrs_shown_weight) at the 2x2 lookup at `base`.
WRS_FN vec4 wrs_shown_weights(uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3, ivec2 base, vec2 pos, float z_cur, float dz,
                              float tau) {
    uvec2 b = uvec2(base);  // modular for a negative base: only read for on-screen taps
    return vec4(wrs_shown_weight(t0, b, pos, z_cur, dz, tau), wrs_shown_weight(t1, b + uvec2(1u, 0u), pos, z_cur, dz, tau),
                wrs_shown_weight(t2, b + uvec2(0u, 1u), pos, z_cur, dz, tau),
                wrs_shown_weight(t3, b + uvec2(1u, 1u), pos, z_cur, dz, tau));
}
WRS_FN vec3 wrs_shown_color(uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3, ivec2 base, vec2 pos, Tracked h,
                            float z_cur, float dz, float tau) {
    vec4 w = wrs_shown_weights(t0, t1, t2, t3, base, pos, z_cur, dz, tau);
    return wrs_shown_mean(t0, t1, t2, t3, w, h.q, h.color);
}

// A kept sample (of higher quality than the candidate) against a candidate that blends in level 0:
// the pixel's own full-rate colour is one of the candidate's taps, so their box [lo, hi] holds the
// true colour at the pixel centre, and a shown colour more than one 8-bit step outside it is clipped
// to it per channel, which can only bring each channel nearer the truth. `exact`: the candidate's
// level a is 0 and foveation is ours (with `none` the application's level 0 is itself foveated).
// Display only: the reservoir keeps the sample itself.
WRS_FN vec3 wrs_kept_shown(vec3 shown, vec3 lo, vec3 hi, bool exact) {
    vec3 slack = vec3(1.0f / 255.0f, 1.0f / 255.0f, 1.0f / 255.0f);
    if (exact && (any(lessThan(shown, lo - slack)) || any(greaterThan(shown, hi + slack)))) return clamp(shown, lo, hi);
    return shown;
}

// Per-channel min and max of four pyramid taps, widened into [lo, hi]; returns the range of their
// alpha (at the fingerprint level: the L* range).
WRS_FN float wrs_taps_range(vec4 a, vec4 b, vec4 c, vec4 d, WRS_INOUT(vec3) lo, WRS_INOUT(vec3) hi) {
    lo = min(lo, min(min(vec3(a), vec3(b)), min(vec3(c), vec3(d))));
    hi = max(hi, max(max(vec3(a), vec3(b)), max(vec3(c), vec3(d))));
    return max(max(a.w, b.w), max(c.w, d.w)) - min(min(a.w, b.w), min(c.w, d.w));
}

// Weight of the candidate in an equal-quality merge: a running mean over w_sum's worth of samples.
WRS_FN float wrs_merge_weight(float w_sum, float q) { return wrs_div(q, w_sum + q); }

// The candidate of one pixel as the retention rule sees it (`Candidate` names the buffer block).
struct RetainInput {
    vec3 color;   // foveated colour, linear RGB
    float q;      // its quality (0 when the input pixel was not finite: it never replaces history)
    vec3 lo;      // per-channel min and max of the pyramid taps it was blended from
    vec3 hi;
    float fp;     // fingerprint now (L*, unquantised) at the pixel
    float fp_range;  // L* range of the four fingerprint taps
    bool moved;   // this pixel has non-zero motion this frame
    float z;      // linear depth now (0 unknown)
    float q_floor;  // the floor rule's quality (wrs_rule_floor; 0: no floor rule)
    // The view the pixel's samples come from was jittered (a sample lattice that moves from frame to
    // frame by up to a source pixel): the change test allows the fingerprint taps' range, as for motion,
    // so that a new phase of the same content is not read as a change.
    bool jittered;
    uint flags;  // WRS_FLAG_* a fresh sample is stored with (WRS_FLAG_LANDED)
};

// Whether a gap's sample (wrs_track_gap) is shown: where the retention rule would keep it as sharper
// than the candidate (wrs_retain's WRS_OUT_KEPT for a sharper history: the change test passes and the
// candidate is of lower quality, or invalid with the history above the floor).
WRS_FN bool wrs_gap_shows(Tracked h, RetainInput c) {
    if (!(c.q > 0.0f)) return h.q > c.q_floor * (1.0f + WRS_Q_EQUAL);
    bool moved = (h.flags & WRS_FLAG_MOVED) != 0u || c.moved || c.jittered;
    float tol = WRS_FP_TOL + (moved ? c.fp_range : 0.0f);
    if (abs(h.fp - c.fp) > tol) return false;
    return c.q < h.q * (1.0f - WRS_Q_EQUAL);
}

// Landed display (docs/retention.md "Landed display"). Under motion a pixel of the wide views shows
// either the landed samples it keeps (each moved by the tracked lookup) or, where none is inside its
// footprint, the wide candidate: as the lattice of kept samples drifts over the pixels, a pixel turns
// from one to the other and its colour jumps between two reconstructions (on the headset cell at 0.25
// density, 13 % of the stable pixel pairs, half of `wrs`'s temporal instability). So where landed
// samples are kept, what is shown is one reconstruction of them, continuous in where they sit: the
// tent-weighted mean (max(0, 1 - |d|) per axis, wrs_shown_weight) of the landed samples of the 2x2
// lookup, each also weighted by its quality. Shown at a pixel that keeps a landed sample, and at one
// that shows a wide sample where a landed tap of a sharper class passes the change test against the
// candidate (as a gap's does, wrs_gap_shows). Display only: the reservoirs are unchanged.
//
// A landed tap's contribution to acc = (sum w q c, sum w q), for a display weight w (wrs_shown_weight).
WRS_FN void wrs_landed_add(WRS_INOUT(vec4) acc, uvec4 pk, float w) {
    if (!(w > 0.0f)) return;
    Tracked t = wrs_unpack_tracked(pk);
    if ((t.flags & WRS_FLAG_LANDED) == 0u) return;
    WRS_PRECISE float wq = w * t.q;
    acc += vec4(t.color.x * wq, t.color.y * wq, t.color.z * wq, wq);
}
// Of the taps t0..t3 with display weights w, the one of the highest quality above q, the first in tap
// order among equals; 4 where none is.
WRS_FN uint wrs_landed_fill_tap(uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3, vec4 w, float q) {
    uint best = 4u;
    float bq = q * (1.0f + WRS_Q_EQUAL);
    if (w.x > 0.0f && wrs_packed_quality(t0) > bq) { best = 0u; bq = wrs_packed_quality(t0); }
    if (w.y > 0.0f && wrs_packed_quality(t1) > bq) { best = 1u; bq = wrs_packed_quality(t1); }
    if (w.z > 0.0f && wrs_packed_quality(t2) > bq) { best = 2u; bq = wrs_packed_quality(t2); }
    if (w.w > 0.0f && wrs_packed_quality(t3) > bq) { best = 3u; bq = wrs_packed_quality(t3); }
    return best;
}
// The colour shown at a pixel of a frame with landed samples, under motion (the taps were read), from
// the colour the rule would show (`shown`): `kept` whether a sharper sample is shown (the rule kept h,
// or a gap shows h), r the sample stored, q_wide the wide views' quality, c the candidate.
WRS_FN vec3 wrs_landed_shown(uvec4 t0, uvec4 t1, uvec4 t2, uvec4 t3, vec4 w, bool kept, Tracked h, Tracked r,
                             float q_wide, RetainInput c, vec3 shown) {
    bool wide_px = !kept && r.q <= q_wide * (1.0f + WRS_Q_EQUAL);
    bool landed_px = kept && (h.flags & WRS_FLAG_LANDED) != 0u;
    if (!(wide_px || landed_px)) return shown;
    if (wide_px) {
        uint k = wrs_landed_fill_tap(t0, t1, t2, t3, w, r.q);
        if (k == 4u) return shown;
        uvec4 tk = k == 0u ? t0 : k == 1u ? t1 : k == 2u ? t2 : t3;
        if (!wrs_gap_shows(wrs_unpack_tracked(tk), c)) return shown;
    }
    vec4 acc = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    wrs_landed_add(acc, t0, w.x);
    wrs_landed_add(acc, t1, w.y);
    wrs_landed_add(acc, t2, w.z);
    wrs_landed_add(acc, t3, w.w);
    return wrs_shown_end(acc, shown);
}

// Outcomes of wrs_retain, for statistics and tests.
const uint WRS_OUT_FRESH = 0u;     // no usable history: the candidate
const uint WRS_OUT_CHANGED = 1u;   // the change test flushed the history: the candidate
const uint WRS_OUT_BETTER = 2u;    // the candidate is of higher quality: the candidate
const uint WRS_OUT_KEPT = 3u;      // the history is of higher quality (or won the combine): kept
const uint WRS_OUT_MERGED = 4u;    // equal quality: merged
const uint WRS_OUT_OUTSIDE = 5u;   // equal quality, history outside the taps: clipped, merged (point box: candidate)
const uint WRS_OUT_FLOOR = 6u;     // a floor-quality history against a floor-quality or invalid candidate: the candidate
const uint WRS_OUTCOMES = 7u;

WRS_FN Tracked wrs_tracked_from(RetainInput c, float w_sum) {
    Tracked r;
    r.color = c.color;
    r.q = c.q;
    r.w_sum = w_sum;
    r.fp = wrs_fp_value(wrs_fp_code(c.fp));
    r.flags = c.flags;
    r.z = c.z;
    r.d = vec2(0.0f, 0.0f);
    return r;
}

// Squared distance of two linear colours after sRGB encoding (the oracle's measure).
WRS_FN float wrs_srgb_dist2(vec3 a, vec3 b) {
    vec3 d = wrs_linear_to_srgb3(a) - wrs_linear_to_srgb3(b);
    return dot(d, d);
}

// One retention step for one pixel. `h` is the tracked history (used iff has_history), `d_new` its
// offset from this pixel's centre now, `ref` the unfoveated colour (oracle only), `rnd` in [0, 1)
// (reservoir only). `margin` returns how close the deciding comparison was to its threshold, in
// that comparison's own relative units, so tests can tell a rounding difference from a bug.
WRS_FN Tracked wrs_retain(uint rule, bool has_history, Tracked h, vec2 d_new, RetainInput c, vec3 ref, float rnd,
                          WRS_OUT(uint) outcome, WRS_OUT(float) margin) {
    Tracked fresh = wrs_tracked_from(c, max(c.q, WRS_WSUM_MIN));
    margin = 1.0f;
    outcome = WRS_OUT_FRESH;
    if (!has_history) return fresh;
    Tracked kept = h;
    kept.d = d_new;
    kept.z = c.z;
    if (c.moved) kept.flags = h.flags | WRS_FLAG_MOVED;
    // An invalid candidate (non-finite input: q = 0) never replaces history sharper than the floor,
    // not even through the change test (a large enough poisoned patch would move the fingerprint).
    // A floor-quality history is not kept for it (the floor rule below): the pixel shows what `fov`
    // shows there, and stores the invalid candidate, which no later frame reads as history.
    if (!(c.q > 0.0f)) {
        bool sharper = h.q > c.q_floor * (1.0f + WRS_Q_EQUAL);
        outcome = sharper ? WRS_OUT_KEPT : WRS_OUT_FLOOR;
        return sharper ? kept : fresh;
    }
    if (wrs_rule_is_oracle(rule)) {
        float dh = wrs_srgb_dist2(h.color, ref);
        float dc = wrs_srgb_dist2(c.color, ref);
        margin = abs(dh - dc) / max(max(dh, dc), 1e-12f);
        bool keep = dh < dc;
        if (rule == WRS_RULE_ORACLE_Q) {
            float hi_q = c.q * (1.0f + WRS_Q_EQUAL);
            margin = min(margin, abs(h.q - hi_q) / h.q);
            keep = keep && h.q > hi_q;
        }
        outcome = keep ? WRS_OUT_KEPT : WRS_OUT_BETTER;
        return keep ? kept : fresh;
    }
    // Change test against the fingerprint the sample was taken with.
    bool moved = (h.flags & WRS_FLAG_MOVED) != 0u || c.moved || c.jittered;
    float tol = WRS_FP_TOL + (moved ? c.fp_range : 0.0f);
    float diff = abs(h.fp - c.fp);
    margin = abs(diff - tol) / 100.0f;
    // The stored code may itself sit on a rounding boundary of the fingerprint.
    float frac_fp = fract(c.fp * WRS_FP_SCALE);
    if (diff > tol) {
        outcome = WRS_OUT_CHANGED;
        return fresh;
    }
    // Quality.
    float hi_q = h.q * (1.0f + WRS_Q_EQUAL), lo_q = h.q * (1.0f - WRS_Q_EQUAL);
    margin = min(margin, min(abs(c.q - hi_q), abs(c.q - lo_q)) / h.q);
    margin = min(margin, abs(frac_fp - 0.5f) / (WRS_FP_SCALE * 100.0f));
    if (c.q > hi_q) {
        outcome = WRS_OUT_BETTER;
        return fresh;
    }
    if (c.q < lo_q) {
        outcome = WRS_OUT_KEPT;
        return kept;
    }
    // The floor rule: at the lowest quality the mode has (the far periphery), an equal-quality history
    // is not combined with the candidate; the candidate is taken fresh. Nothing there can be sharper
    // than the candidate, so this is what lets a tile that held nothing sharper skip retention
    // altogether (wrs_tile_skips) with the same output as running it.
    if (c.q <= c.q_floor * (1.0f + WRS_Q_EQUAL)) {
        outcome = WRS_OUT_FLOOR;
        return fresh;
    }
    if (rule == WRS_RULE_RESERVOIR) {
        WRS_PRECISE float w1 = wrs_biased_history_weight(h.w_sum, c.q, 0.0f, true);
        WRS_PRECISE float total = w1 + c.q;
        WRS_PRECISE float lhs = rnd * total;
        margin = min(margin, abs(rnd - w1 / total));
        bool keep = lhs <= w1;
        Tracked r = keep ? kept : fresh;
        r.w_sum = clamp(total, WRS_WSUM_MIN, WRS_MERGE_CAP * c.q);
        outcome = keep ? WRS_OUT_KEPT : WRS_OUT_BETTER;
        return r;
    }
    // Merge. A history outside what the candidate's own taps allow (one 8-bit step of slack) means
    // the scene under an equal-quality sample changed in a way the coarse fingerprint missed (a
    // moving object of the same brightness, a sample carried across an edge): it is first clipped
    // to the taps' box (per channel, as TAA clamps its history to the neighbourhood) and then
    // merged, so the output moves towards the candidate as smoothly as a merge instead of jumping
    // to it. A sharp candidate's box is the candidate itself, which the clip would return: there the
    // candidate is taken as a fresh sample (at the pixel's centre), so the fovea stays exact.
    vec3 slack = vec3(1.0f / 255.0f, 1.0f / 255.0f, 1.0f / 255.0f);
    vec3 to_lo = abs(h.color - (c.lo - slack)), to_hi = abs(h.color - (c.hi + slack));
    margin = min(margin, min(min(min(to_lo.x, to_lo.y), to_lo.z), min(min(to_hi.x, to_hi.y), to_hi.z)) /
                             max(max(max(h.color.x, h.color.y), h.color.z), 1.0f));
    vec3 hist = h.color;
    outcome = WRS_OUT_MERGED;
    if (any(lessThan(h.color, c.lo - slack)) || any(greaterThan(h.color, c.hi + slack))) {
        outcome = WRS_OUT_OUTSIDE;
        if (all(equal(c.lo, c.hi))) return fresh;
        hist = clamp(h.color, c.lo, c.hi);
    }
    float t = wrs_merge_weight(h.w_sum, c.q);
    Tracked r = kept;
    r.color = hist + (c.color - hist) * t;
    r.d = d_new * (1.0f - t);
    r.w_sum = min(h.w_sum + c.q, WRS_MERGE_CAP * c.q);
    return r;
}

// ---------------------------------------------------------------------------------------------
// Sparse retention (docs/retention.md "Sparse retention")
// ---------------------------------------------------------------------------------------------
// Only a pixel whose tracked history is sharper than its candidate can keep anything. Each tile's
// retain workgroup records the best quality it stored, its held quality (float bits, 0: the tile
// stored nothing); the next frame's classification puts a far tile on the skip list when none of
// the tiles its tracked lookups can read held anything sharper than the floor. A skipped tile runs
// the foveating pass alone: no reservoir read or write, no depth fetch. With the floor rule of
// wrs_retain, the output and every stored sample outside skipped tiles are what running retention
// everywhere gives, bit for bit.

// The lowest quality a mode's candidates have: the far periphery's 16x16 rate (level 4) for `mip`
// and `gauss`. `none` has no floor (its weights fall with eccentricity without end): 0.
WRS_FN float wrs_floor_quality(uint mode) {
    if (!wrs_mode_simulated(mode)) return 0.0f;  // submitted foveation: the frame's (makeFrameParams)
    return wrs_level_quality(vec3(float(WRS_LEVELS - 1), float(WRS_LEVELS - 1), 0.0f));
}
// The floor of a rule: the plain oracle chooses among equally sharp samples too, so it has none.
WRS_FN float wrs_rule_floor(uint rule, uint mode) { return rule == WRS_RULE_ORACLE ? 0.0f : wrs_floor_quality(mode); }

// What a tracked lookup reads from a tile that stored nothing: a floor-quality sample at the pixel's
// centre, which is what retention would have stored there (every pixel of a skipped tile takes its
// floor-quality candidate fresh, at offset 0). Only a sample's quality and offset steer the lookup,
// and a floor-quality history is never kept, merged or shown, so its colour, fingerprint and depth
// never matter.
WRS_FN uvec4 wrs_floor_sample(float q_floor) {
    uint h = wrs_store_f16(q_floor);
    return uvec4(0u, h << 16u, h, 0u);
}

// The tiles a tile's tracked lookups can read. A pixel that did not move reads only itself; the 2x2
// block of one that moved sits at floor(p + mv) (wrs_track_start), so along each axis the tile's
// pixels read within [floor(first + mv_lo) - 1, floor(last + mv_hi) + 2], first and last being the
// tile's outer pixels and [mv_lo, mv_hi] the range of its pixels' finite motion within reach (the
// others read nothing), 0 included; the extra pixel each side absorbs the rounding of
// p + 0.5 + mv - 0.5. Returns false when that range is wholly off-screen; else s0 and s1 are the
// first and last source tile (inclusive).
WRS_FN bool wrs_tile_sources(uvec2 t, uvec2 size, vec2 mv_lo, vec2 mv_hi, WRS_OUT(uvec2) s0, WRS_OUT(uvec2) s1) {
    s0 = t;
    s1 = t;
    if (mv_lo.x == 0.0f && mv_lo.y == 0.0f && mv_hi.x == 0.0f && mv_hi.y == 0.0f) return true;  // nothing moved
    vec2 first = vec2(t * WRS_TILE);
    vec2 last = vec2(min((t + uvec2(1u, 1u)) * WRS_TILE, size) - uvec2(1u, 1u));
    vec2 lo = floor(first + mv_lo) - vec2(1.0f, 1.0f);
    vec2 hi = floor(last + mv_hi) + vec2(2.0f, 2.0f);
    vec2 top = vec2(size) - vec2(1.0f, 1.0f);
    s0 = uvec2(clamp(lo, vec2(0.0f, 0.0f), top)) / WRS_TILE;
    s1 = uvec2(clamp(hi, vec2(0.0f, 0.0f), top)) / WRS_TILE;
    return hi.x >= 0.0f && hi.y >= 0.0f && lo.x <= top.x && lo.y <= top.y;
}
// The most source tiles a classification reads: a tile whose motion spreads wider runs retention,
// which is always correct.
const uint WRS_SOURCE_TILES_MAX = 16u;
// Superblocks: WRS_SUPERBLOCK x WRS_SUPERBLOCK tiles (64 x 64 pixels), each holding the largest held
// quality of its tiles, so that the classification can look over a tile's whole reach in a few reads.
const uint WRS_SUPERBLOCK = 8u;
// The most superblocks a classification reads before it reads the tile's motion instead.
const uint WRS_REACH_BLOCKS_MAX = 64u;
// The superblocks [b0, b1] that hold every source tile tile t can have under any motion within
// `reach` (wrs_within_reach): the tile's sources (wrs_tile_sources) for motion anywhere in
// [-reach, reach]^2. False when all of them are off-screen.
WRS_FN bool wrs_reach_blocks(uvec2 t, uvec2 size, float reach, WRS_OUT(uvec2) b0, WRS_OUT(uvec2) b1) {
    uvec2 s0, s1;
    bool any = wrs_tile_sources(t, size, vec2(-reach, -reach), vec2(reach, reach), s0, s1);
    b0 = s0 / WRS_SUPERBLOCK;
    b1 = s1 / WRS_SUPERBLOCK;
    return any;
}
// Whether a tile of class `cls`, whose source tiles held at most `held`, skips retention: a far tile
// (every candidate at the floor) that nothing sharper than the floor can reach.
WRS_FN bool wrs_tile_skips(uint cls, float held, float q_floor) {
    return cls == WRS_TILE_FAR && q_floor > 0.0f && held <= q_floor;
}
// The class of a tile of a frame submitted foveated (quad views, a rate map; FOV_MODE
// WRS_FOV_SUBMITTED), from the largest quality any of its pixels was rendered at (the compose pass's
// per-tile maximum): far where every pixel was rendered at the floor quality, so that retention there
// takes the floor rule's fresh candidate as in a far tile of a simulated mode (a rendered quality is
// never below the frame's floor: the wide views' quality, or the 4x4 rate's), any otherwise (the
// pixels' own qualities, no levels: a submitted frame has no pyramid candidates).
WRS_FN uint wrs_submitted_tile_class(float q_max, float q_floor) {
    return q_floor > 0.0f && q_max <= q_floor * (1.0f + WRS_Q_EQUAL) ? WRS_TILE_FAR : WRS_TILE_ANY;
}

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

// ---------------------------------------------------------------------------------------------
// The steady floor (docs/retention.md "The steady floor"): the floor level's texels (level 4, one
// per 16x16 pixels), filtered over time as TAA filters pixels, for the retention methods whose floor
// rule takes the candidate there. Without it the far periphery shows each frame's 16x16 box averages,
// which crawl as content moves under them; the merge at the floor smoothed that at the price of
// retention in every far tile. Filtering 1/256 of the pixels steadies it as much; FovVideoVDP scores
// both smoothings lower than neither, so it is an option (CompositorConfig::steadyFloor).
// ---------------------------------------------------------------------------------------------

const uint WRS_STEADY_LEVEL = 4u;  // the floor level of `mip` and `gauss` (quality 1/256)
// Weight of the current texel. Atrium lateral at 512x384 (150 frames, fovea 5 deg, `mip`): temporal
// instability 0.00116 unfiltered, 0.00082 / 0.00074 / 0.00066 / 0.00060 at 0.4 / 0.25 / 0.15 / 0.1,
// near-gaze PSNR -0.013 / -0.018 / -0.022 / -0.026 dB (with bilinear resampling of the history, where
// level 4 is seen within 10 deg of the gaze); 0.25 keeps that within 0.02 dB.
const float WRS_STEADY_ALPHA = 0.25f;

// First texel of an eye's level 4 in slot `slot` (0 or 1) of the steady history, which follows both
// eyes' stored pyramids in the pyramid buffer; `l4` is level 4's row of FrameParams::levels.
WRS_FN uint wrs_steady_offset(uvec4 l4, uint slot, uint eye) { return 2u * l4.w + (slot * 2u + eye) * (l4.x * l4.y); }
// The pixel whose motion moves level-4 texel d: the centre of its 16x16 block, clamped to the image.
WRS_FN uvec2 wrs_steady_motion_pixel(uvec2 d, uvec2 size0) {
    uint s = 1u << WRS_STEADY_LEVEL;
    return min(d * s + uvec2(s / 2u, s / 2u), size0 - uvec2(1u, 1u));
}
// Catmull-Rom weights of the taps at -1, 0, 1, 2 for a sample at fraction f in [0, 1) past tap 0:
// the history's resampling. A bilinear one blurs by f(1 - f) texels^2 each frame (0.02 at a slow
// pan's 0.02 texels a frame), which the filter accumulates over its ~1/alpha frames into a blur of a
// quarter texel (4 pixels) on top of the 16x16 box; Catmull-Rom's blur at that f is ~30 times less.
WRS_FN vec4 wrs_catmull_rom(float f) {
    WRS_PRECISE float f2 = f * f, f3 = f2 * f;
    WRS_PRECISE vec4 w = vec4(-0.5f * f3 + f2 - 0.5f * f, 1.5f * f3 - 2.5f * f2 + 1.0f,
                              -1.5f * f3 + 2.0f * f2 + 0.5f * f, 0.5f * f3 - 0.5f * f2);
    return w;
}
// Tap k (each axis 0..3, for -1..2) of the 4x4 Catmull-Rom footprint at i0, clamped to the image.
WRS_FN uvec2 wrs_cubic_tap(uvec2 i0, ivec2 k, uvec2 size) {
    return uvec2(clamp(ivec2(i0) + k - ivec2(1, 1), ivec2(0, 0), ivec2(size) - ivec2(1, 1)));
}
// A pixel's motion in level-4 texels (the depth change is not used).
WRS_FN vec3 wrs_steady_motion(vec3 mv) {
    const float s = 0.0625f;  // 1 / 2^WRS_STEADY_LEVEL
    return vec3(mv.x * s, mv.y * s, 0.0f);
}

WRS_END

#endif
