// Pass 1: the colour pyramid, levels 1..4, read straight from the submitted colour (level 0 is never
// stored) and written as fp16 RGBA. Level 4 carries its L* in alpha (wrs_pyramid_texel).
//
// FILTER 1 (`mip`, and the fingerprint pyramid of `wrs` under `none`): 2x2 box, all levels in one
// dispatch; only the levels the mode samples are stored (3 and 4 for `mip`, 4 for `none`). A 16x16
// tile of level 0 is exactly the support of one level-4 texel (clamped taps stay inside their
// tile), so a group of 8x8 invocations builds a 32x32-pixel tile's four level-4 texels: each
// invocation reduces a 4x4 block of level 0 to its 2x2 level-1 texels and its level-2 texel in
// registers, then levels 3 and 4 go through shared memory, one barrier per level, as single-pass
// downsamplers do. The sRGB table is staged in shared memory once per group, so that the 48 decodes
// of an invocation read it there rather than from a buffer.
// FILTER 2 (`gauss`): separable [1 3 3 1]/8, whose support crosses tiles; one dispatch per level.
// Level 1 (push.level == 1) stages the 18x18 level-0 texels of its 8x8 output tile in shared memory,
// each decoded once; levels 2..4 read the level below from the buffer.
// FILTER 3: the steady floor (wrs_common.h), one invocation per level-4 texel, z = eye, after the
// pyramid. Phase 0 filters level 4 over time into this frame's slot of the steady history (after
// both eyes' stored pyramids in the same buffer: two slots of both eyes' level 4, push.pad0 the slot
// written, push.pad1 the slot read, push.pad2 1 where that slot holds a history); phase 1 puts the
// filtered colour into level 4, keeping its alpha (the fingerprint's L*, unfiltered). Two dispatches,
// because phase 0 reads the 3x3 neighbourhood of the unfiltered texels.
// Shared and stored values are the fp16-rounded ones, so each level is built from exactly what the
// CPU reference (compositor/reference.cpp) builds it from.
#version 450
#extension GL_GOOGLE_include_directive : require
// The sRGB table (bindings.glsl, load_color) is read from the group's copy in shared memory.
shared float s_srgb[256];
#define WRS_SRGB_TABLE s_srgb
#include "bindings.glsl"

layout(constant_id = 0) const uint FILTER = 1u;
layout(constant_id = 1) const uint FIRST_STORED = 1u;  // wrs_first_stored_level of the foveation mode
layout(constant_id = 2) const bool HAS_MOTION = false;  // FILTER 3: the views have motion vectors
layout(constant_id = 3) const uint STEADY_PHASE = 0u;   // FILTER 3: 0 filter, 1 copy into level 4
layout(push_constant) uniform Push { LevelPush push; };
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

const uint GAUSS_SPAN = 2u * WRS_GROUP_X + 2u;  // level-0 texels behind 8 level-1 texels: taps -1..2
shared vec4 s_texels[GAUSS_SPAN * GAUSS_SPAN];

// Copies the sRGB table into shared memory (every group, before its first load_color), where the
// input's encoding reads it.
void stage_srgb_table() {
    if (!input_reads_srgb_table()) return;
    for (uint i = gl_LocalInvocationIndex; i < 256u; i += WRS_GROUP_X * WRS_GROUP_Y) s_srgb[i] = srgb_table[i];
    barrier();
}

// Rounds a filtered texel to its stored fp16 value and writes it where the level has that texel and
// the foveation mode samples the level.
vec4 store_texel(uint eye, uint level, uvec2 d, vec4 filtered) {
    uvec2 h = pyr_pack(wrs_pyramid_texel(filtered, level));
    if (level >= FIRST_STORED && all(lessThan(d, level_size(level)))) pyr_write(eye, level, d, h);
    return pyr_unpack(h);
}

// The level-1 texel d from its four clamped level-0 taps.
vec4 level1_texel(uint eye, uvec2 d, uvec2 size0) {
    vec4 r = wrs_down_box(
        load_color(eye, wrs_down_tap(d, ivec2(0, 0), size0)), load_color(eye, wrs_down_tap(d, ivec2(1, 0), size0)),
        load_color(eye, wrs_down_tap(d, ivec2(0, 1), size0)), load_color(eye, wrs_down_tap(d, ivec2(1, 1), size0)));
    return store_texel(eye, 1u, d, r);
}

void mip_chain(uint eye) {
    uvec2 t = gl_LocalInvocationID.xy;
    uvec2 g = gl_WorkGroupID.xy;
    uvec2 size0 = frame.size.xy;
    stage_srgb_table();
    // This invocation's level-2 texel and the four level-1 texels it is built from.
    uvec2 d2 = g * 8u + t;
    uvec2 d1 = 2u * d2;
    vec4 l1[4];
    l1[0] = level1_texel(eye, d1, size0);
    l1[1] = level1_texel(eye, d1 + uvec2(1u, 0u), size0);
    l1[2] = level1_texel(eye, d1 + uvec2(0u, 1u), size0);
    l1[3] = level1_texel(eye, d1 + uvec2(1u, 1u), size0);
    // The level-2 texel's taps d1 + o, clamped to level 1: d1 + 1 where it lies inside level 1, else
    // d1 (a level-2 texel inside the image has d1 inside level 1). A texel outside the image is never
    // read by the levels above, whatever it holds.
    uvec2 size1 = level_size(1u);
    bool cx = d1.x + 1u < size1.x, cy = d1.y + 1u < size1.y;
    vec4 t10 = cx ? l1[1] : l1[0];
    vec4 t01 = cy ? l1[2] : l1[0];
    vec4 t11 = cy ? (cx ? l1[3] : l1[2]) : t10;
    s_texels[t.y * 8u + t.x] = store_texel(eye, 2u, d2, wrs_down_box(l1[0], t10, t01, t11));
    barrier();
    uint n = 4u;  // texels per tile side at `level`
    for (uint level = 3u; level < uint(WRS_LEVELS); ++level, n /= 2u) {
        bool inside = all(lessThan(t, uvec2(n)));
        vec4 v = vec4(0.0);
        if (inside) {
            uvec2 src = level_size(level - 1u);
            uvec2 dd = g * n + t;
            uvec2 origin = g * (2u * n);  // this tile's first texel at level - 1
            // Clamped taps stay in the tile: 2*dd <= tap <= 2*dd + 1 and origin <= src - 1.
            uvec2 a = wrs_down_tap(dd, ivec2(0, 0), src) - origin, b = wrs_down_tap(dd, ivec2(1, 0), src) - origin;
            uvec2 c = wrs_down_tap(dd, ivec2(0, 1), src) - origin, e = wrs_down_tap(dd, ivec2(1, 1), src) - origin;
            uint w = 2u * n;
            v = store_texel(eye, level, dd,
                            wrs_down_box(s_texels[a.y * w + a.x], s_texels[b.y * w + b.x], s_texels[c.y * w + c.x],
                                         s_texels[e.y * w + e.x]));
        }
        barrier();
        if (inside) s_texels[t.y * n + t.x] = v;
        barrier();
    }
}

void gauss_level1(uint eye) {
    uvec2 t = gl_LocalInvocationID.xy;
    uvec2 size0 = frame.size.xy;
    uvec2 first = gl_WorkGroupID.xy * 8u;  // the tile's first level-1 texel
    ivec2 origin = ivec2(2u * first) - ivec2(1, 1);
    stage_srgb_table();
    for (uint i = gl_LocalInvocationIndex; i < GAUSS_SPAN * GAUSS_SPAN; i += WRS_GROUP_X * WRS_GROUP_Y) {
        ivec2 s = clamp(origin + ivec2(i % GAUSS_SPAN, i / GAUSS_SPAN), ivec2(0), ivec2(size0) - ivec2(1));
        s_texels[i] = load_color(eye, uvec2(s));
    }
    barrier();
    uvec2 d = first + t;
    if (any(greaterThanEqual(d, level_size(1u)))) return;
    // Tap (2d + o) sits at local 2t + o + 1; its clamped value was staged there.
    vec4 rows[4];
    for (uint j = 0u; j < 4u; ++j) {
        uint row = (2u * t.y + j) * GAUSS_SPAN + 2u * t.x;
        rows[j] = wrs_binomial_row(s_texels[row], s_texels[row + 1u], s_texels[row + 2u], s_texels[row + 3u]);
    }
    store_texel(eye, 1u, d, wrs_binomial_row(rows[0], rows[1], rows[2], rows[3]));
}

vec4 tap(uint eye, uint level, uvec2 d, ivec2 o, uvec2 src_size) {
    return pyr_read(eye, level, wrs_down_tap(d, o, src_size));
}

void gauss_level(uint eye, uint level) {
    uvec2 d = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(d, level_size(level)))) return;
    uvec2 src_size = level_size(level - 1u);
    uint src = level - 1u;
    vec4 rows[4];
    for (int j = 0; j < 4; ++j) {
        rows[j] =
            wrs_binomial_row(tap(eye, src, d, ivec2(-1, j - 1), src_size), tap(eye, src, d, ivec2(0, j - 1), src_size),
                             tap(eye, src, d, ivec2(1, j - 1), src_size), tap(eye, src, d, ivec2(2, j - 1), src_size));
    }
    store_texel(eye, level, d, wrs_binomial_row(rows[0], rows[1], rows[2], rows[3]));
}

// Texel d of an eye's level 4 in slot `slot` of the steady history.
uint steady_index(uint slot, uint eye, uvec2 d) {
    uvec4 l = frame.levels[WRS_STEADY_LEVEL];
    return wrs_steady_offset(l, slot, eye) + d.y * l.x + d.x;
}
vec4 steady_read(uint slot, uint eye, uvec2 d) { return pyr_unpack(pyramid[steady_index(slot, eye, d)]); }

void steady_floor(uint eye) {
    uvec2 d = gl_GlobalInvocationID.xy;
    uvec2 size4 = level_size(WRS_STEADY_LEVEL);
    if (any(greaterThanEqual(d, size4))) return;
    if (STEADY_PHASE == 1u) {
        vec4 s = steady_read(push.pad0, eye, d);
        vec4 raw = pyr_read(eye, WRS_STEADY_LEVEL, d);
        pyr_write(eye, WRS_STEADY_LEVEL, d, pyr_pack(vec4(s.rgb, raw.a)));
        return;
    }
    vec3 nb[9];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i)
            nb[j * 3 + i] = wrs_rgb_to_ycocg(pyr_read(eye, WRS_STEADY_LEVEL, wrs_taa_tap(d, ivec2(i - 1, j - 1), size4)).rgb);
    EyeParams ep = frame.eye[eye];
    vec3 mv = vec3(0.0);
    if (HAS_MOTION) {
        uvec2 p = wrs_steady_motion_pixel(d, frame.size.xy);
        mv = wrs_steady_motion(texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz);
    }
    uvec2 i0, i1;
    vec2 f;
    uint prev = push.pad1;
    bool has = push.pad2 != 0u && wrs_taa_reproject(d, size4, mv, i0, i1, f) && steady_read(prev, eye, d).a != 0.0;
    // Unfused, as the reference sums it.
    precise vec3 hist = vec3(0.0);
    if (has) {
        vec4 wx = wrs_catmull_rom(f.x), wy = wrs_catmull_rom(f.y);
        for (int j = 0; j < 4; ++j) {
            precise vec3 row = vec3(0.0);
            for (int i = 0; i < 4; ++i) row += wx[i] * steady_read(prev, eye, wrs_cubic_tap(i0, ivec2(i, j), size4)).rgb;
            hist += wy[j] * row;
        }
        has = wrs_finite3(hist);
    }
    vec3 c = wrs_taa_step(nb, hist, has, WRS_STEADY_ALPHA);
    pyramid[steady_index(push.pad0, eye, d)] = pyr_pack(vec4(c, 1.0));
}

void main() {
    uint eye = gl_WorkGroupID.z;
    if (FILTER == 3u) {
        steady_floor(eye);
    } else if (FILTER == 1u) {
        mip_chain(eye);
    } else if (push.level == 1u) {
        gauss_level1(eye);
    } else {
        gauss_level(eye, push.level);
    }
}
