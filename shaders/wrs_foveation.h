// Foveation: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_FOVEATION_H
#define WRSFOV_WRS_FOVEATION_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"
#include "wrs_views.h"

WRS_BEGIN

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

// sigma(e) for `gauss` (documented in docs/conventions.md "Foveation"): 0 inside the fovea, rising linearly
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

WRS_END

#endif
