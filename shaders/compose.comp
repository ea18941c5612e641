// Pass 0 for frames submitted foveated (docs/integrating.md, "Quad views", "Shading-rate maps"):
// per output pixel, the candidate and the quality it was rendered at.
//   KIND 1 (quad views): the wide view and the inset, each resampled bilinearly into the output view
//     and blended over the inset's outer edge (wrs_inset_weight), into the composed colour (linear,
//     validity in alpha), depth and motion (nearest texel of the source that weighs more, motion in
//     output pixels), which every later pass reads in place of the submitted images; the quality
//     wrs_quad_quality.
//   With ComposeEye::landed.z, each pixel's landed wide sample too (wrs_landed_offset): the wide texel
//   nearest its centre and its quality, packed (wrs_pack_landed) after the tiles' largest qualities,
//   for retention's own candidate; the composed colour is the same either way. With landed.z == 2
//   (method taau-simple) in their place the pixel's gathered wide samples (wrs_taau_simple_add), colour and
//   weight; with 3 (method taau) the Lanczos-2 gather of the 4x4 wide texels around it (wrs_taau_gather_add).
//   KIND 2 (a rate map): the submitted colour is the candidate as it is; the quality
//     wrs_rate_quality of the pixel's texel.
// Each group is one 8x8 tile (WRS_TILE): after the pixels' qualities (eye-major, 2 W H of them) it
// writes its tile's largest (tile_index order), from which the classification finds the tiles rendered
// at the floor quality only (wrs_submitted_tile_class; sparse retention skips them).
// Stored values are rounded to fp16 by hand (wrs_f16_value) before a 16-bit image stores them, so the
// device's own conversion, which may round either way, has nothing left to round.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "wrs_submitted.h"
#include "compose_params.h"

layout(constant_id = 0) const uint KIND = 1u;
layout(constant_id = 1) const bool HAS_DEPTH = false;
layout(constant_id = 2) const bool HAS_MOTION = false;
// What the pass writes beside the composed images, the largest of the two eyes' ComposeEye::landed.z:
// 0 nothing, 1 the landed wide samples (`wrs`; an eye's landed.z is 1 or 0), 2 the gathered wide
// samples (`taau-simple`; both eyes' are 2), 3 the Lanczos-2 gather (`taau`; both eyes' are 3). A
// pipeline carries its method's code only.
layout(constant_id = 3) const uint LANDED = 0u;
// How the wide views' and the insets' colour is encoded (WRS_INPUT_*, ComposeEye wide_color.z and
// inset_color.z, the same for both eyes), so that the pass carries that decoding only; WRS_INPUT_ANY
// where the eyes differ (each eye's own, read at run time).
layout(constant_id = 4) const uint WIDE_ENCODING = 4u;
layout(constant_id = 5) const uint INSET_ENCODING = 4u;
// Quad views: whether the dispatch's groups may meet the inset (wrs_inset_weight > 0). The compositor
// dispatches the groups of each eye's inset rectangle (insetGroups, compositor/input.h) with it and the
// others without, which never read the inset (docs/speed.md "The compose pass at its bytes").
layout(constant_id = 6) const bool INSET = true;
// Quad views, method fov: the composed colour is the frame's output, written here (sRGB-encoded, as the
// foveating pass would write it) instead of the composed images, qualities and landed samples that only
// the later passes of the other methods read.
layout(constant_id = 7) const bool OUTPUT = false;
// A classification follows (the frame is tiled: sparse retention): each group writes its tile's largest
// quality, counting the landed wide samples; otherwise nothing reads them and the pass writes none.
layout(constant_id = 8) const bool TILES = true;
// The dispatch's first group (xy) and eye (z, added to gl_WorkGroupID.z): a dispatch may cover a
// rectangle of one eye's groups.
layout(push_constant) uniform Push { uvec4 origin; } push;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

layout(std140, set = 0, binding = 0) uniform ComposeBlock { ComposeParams params; };
// Element eye: the wide view; element 2 + eye: the inset.
layout(set = 0, binding = 1) uniform sampler2D srcColor[4];
layout(set = 0, binding = 2) uniform sampler2D srcDepth[4];
layout(set = 0, binding = 3) uniform sampler2D srcMotion[4];
layout(set = 0, binding = 4) uniform usampler2D rateMap[2];
// Float bits: each pixel's quality (eye-major, 2 W H), each tile's largest (2 tiles), then with
// landed samples two words a pixel (eye-major).
layout(std430, set = 0, binding = 5) writeonly buffer Quality { uint quality[]; };
layout(std430, set = 0, binding = 6) readonly buffer SrgbTable { float srgb_table[256]; };
// The group's copy of the sRGB table: each decoded tap reads it from shared memory, not from a buffer
// load that depends on the texel fetch before it (as the pyramid pass does).
shared float s_srgb[256];
layout(set = 0, binding = 7, rgba16f) uniform writeonly image2DArray composedColor;
layout(set = 0, binding = 8, r32f) uniform writeonly image2DArray composedDepth;
layout(set = 0, binding = 9, rgba16f) uniform writeonly image2DArray composedMotion;
// The compositor's output (OUTPUT: method fov), sRGB-encoded 8-bit, layer = eye.
layout(set = 0, binding = 10, rgba8) uniform writeonly image2DArray outImage;

#define WRS_SRGB_TABLE s_srgb
#include "wrs_input.h"
// Texel q of source k (eye, or 2 + eye), decoded and sanitised as load_color does; validity in alpha.
vec4 source_texel(uint k, uvec2 q, uvec4 rect) {
    uint constant_encoding = k < 2u ? WIDE_ENCODING : INSET_ENCODING;
    uint encoding = constant_encoding == WRS_INPUT_ANY ? rect.z : constant_encoding;
    return wrs_decode_input(vec4(texelFetch(srcColor[k], ivec2(q + rect.xy), 0).rgb, 1.0), encoding);
}
bool reads_srgb_table(uint encoding) { return encoding == WRS_INPUT_ANY || wrs_input_srgb8(encoding); }

vec4 source_bilinear(uint k, vec2 pos, uvec2 size, uvec4 rect) {
    uvec2 i0, i1;
    vec2 f = wrs_bilinear_taps(pos, size, i0, i1);
    return wrs_bilinear_valid(source_texel(k, i0, rect), source_texel(k, uvec2(i1.x, i0.y), rect),
                              source_texel(k, uvec2(i0.x, i1.y), rect), source_texel(k, i1, rect), f);
}

uvec2 tile_count(uvec2 size) { return (size + uvec2(WRS_GROUP_X - 1u, WRS_GROUP_Y - 1u)) / uvec2(WRS_GROUP_X, WRS_GROUP_Y); }
uint landed_base(uvec2 size) {
    uvec2 tiles = tile_count(size);
    return 2u * (size.x * size.y + tiles.x * tiles.y);
}

uvec2 nearest(vec2 pos, uvec2 size) { return uvec2(clamp(ivec2(floor(pos)), ivec2(0), ivec2(size) - ivec2(1))); }

vec4 round_f16(vec4 v) { return vec4(wrs_f16_value(v.x), wrs_f16_value(v.y), wrs_f16_value(v.z), wrs_f16_value(v.w)); }

shared uint tile_q;  // the group's tile's largest quality, as bits (qualities are finite and >= 0)

// Composes pixel p of an eye; returns the quality it stored.
float compose_pixel(uint eye, uvec2 p, uvec2 size) {
    ComposeEye ce = params.eye[eye];
    uint idx = (eye * size.y + p.y) * size.x + p.x;
    if (KIND == 2u) {
        uvec2 t = p / ce.rate.zw;
        float q = wrs_rate_quality(texelFetch(rateMap[eye], ivec2(t + ce.rate.xy), 0).r);
        quality[idx] = floatBitsToUint(q);
        return q;
    }
    uvec2 wsize = ce.sizes.xy, isize = ce.sizes.zw;
    vec2 wpos = wrs_source_pos(p, ce.wide_map);
    vec2 ipos = wrs_source_pos(p, ce.inset_map);
    float t = INSET ? wrs_inset_weight(ipos, isize, ce.inset_motion.w) : 0.0;
    vec4 inset = t > 0.0 ? source_bilinear(2u + eye, ipos, isize, ce.inset_color) : vec4(0.0);
    // Where the inset alone shows (and has a valid tap), the wide view is not read.
    bool inset_only = t == 1.0 && inset.w != 0.0;
    vec4 wide = inset_only ? vec4(0.0) : source_bilinear(eye, wpos, wsize, ce.wide_color);
    t = wrs_quad_weight(t, inset.w != 0.0, wide.w != 0.0);
    vec4 c = wrs_quad_color(wide, inset, t);
    if (OUTPUT) {
        imageStore(outImage, ivec3(p, eye), vec4(wrs_output_value(vec3(round_f16(c))), 1.0));
        return 0.0;
    }
    // The pixel's rendered quality in the composed colour's alpha (wrs_composed_quality: 0 where no source tap
    // was valid), rounded to fp16 as it is stored; the tile's largest counts the same value.
    vec4 stored = round_f16(vec4(c.x, c.y, c.z, wrs_composed_alpha(c.w > 0.5, wrs_quad_quality(ce.wide_motion.w, t))));
    float q = stored.w;
    imageStore(composedColor, ivec3(p, eye), stored);
    if (LANDED == 3u && ce.landed.z == 3.0) {
        // Method taau: the wide samples of the 4x4 texels around the pixel's bilinear cell, Lanczos-2 in wide
        // pixels over the kernel scale (landed.w: 1 / scale^2), deringed (wrs_taau_gather_result).
        TaauGather gather = wrs_taau_gather_start();
        if (!inset_only) {
            uvec2 i0, i1;
            wrs_bilinear_taps(wpos, wsize, i0, i1);
            for (uint j = 0u; j < 16u; ++j) {
                uvec2 k;
                if (!wrs_taau_block_tap(i0, wsize, j, k)) continue;
                wrs_taau_gather_add(gather, source_texel(eye, k, ce.wide_color), wpos, k, ce.landed.w);
            }
        }
        vec4 g = wrs_taau_gather_result(gather);
        uvec2 words = wrs_pack_landed(g.rgb, g.w);
        uint at = landed_base(size) + 2u * idx;
        quality[at] = words.x;
        quality[at + 1u] = words.y;
    } else if (LANDED == 2u && ce.landed.z == 2.0) {
        // Method taau-simple: the four wide samples of the pixel's bilinear cell gathered by the kernel of
        // their distance (wrs_taau_simple_add), radius 1 / sqrt(landed.w) output pixels.
        vec4 acc = vec4(0.0);
        if (!inset_only) {
            uvec2 i0, i1;
            wrs_bilinear_taps(wpos, wsize, i0, i1);
            for (uint j = 0u; j < 4u; ++j) {
                uvec2 k;
                if (!wrs_taau_cell_tap(i0, i1, j, k)) continue;
                acc = wrs_taau_simple_add(acc, source_texel(eye, k, ce.wide_color), wrs_landed_offset(wpos, k, ce.landed.xy),
                                   ce.landed.w);
            }
        }
        vec4 g = wrs_taau_gathered(acc);
        uvec2 words = wrs_pack_landed(g.rgb, g.w);
        uint at = landed_base(size) + 2u * idx;
        quality[at] = words.x;
        quality[at + 1u] = words.y;
    } else if (TILES && LANDED == 1u && ce.landed.z != 0.0) {
        // The wide sample nearest the pixel's centre (not read where the inset alone shows): the tile's
        // largest quality counts what retention may take. The retain pass reads the sample itself from the
        // wide view (retain.comp landed_sample).
        uvec2 k = nearest(wpos, wsize);
        float ql = inset_only ? 0.0 : wrs_landed_quality(wrs_landed_offset(wpos, k, wrs_landed_scale(ce.landed)));
        if (ql > 0.0 && source_texel(eye, k, ce.wide_color).w == 0.0) ql = 0.0;
        q = max(q, ql);
    }
    bool from_inset = t >= 0.5;
    if (HAS_DEPTH) {
        uvec2 q = from_inset ? nearest(ipos, isize) : nearest(wpos, wsize);
        uvec2 o = from_inset ? ce.inset_offsets.xy : ce.offsets.xy;
        float d = texelFetch(srcDepth[from_inset ? 2u + eye : eye], ivec2(q + o), 0).r;
        imageStore(composedDepth, ivec3(p, eye), vec4(d, 0.0, 0.0, 0.0));
    }
    if (HAS_MOTION) {
        uvec2 q = from_inset ? nearest(ipos, isize) : nearest(wpos, wsize);
        uvec2 o = from_inset ? ce.inset_offsets.zw : ce.offsets.zw;
        vec3 scale = from_inset ? ce.inset_motion.xyz : ce.wide_motion.xyz;
        precise vec3 mv = texelFetch(srcMotion[from_inset ? 2u + eye : eye], ivec2(q + o), 0).xyz * scale;
        imageStore(composedMotion, ivec3(p, eye), round_f16(vec4(mv, 0.0)));
    }
    return q;
}

void main() {
    uint eye = gl_WorkGroupID.z + push.origin.z;
    uvec2 group = gl_WorkGroupID.xy + push.origin.xy;
    uvec2 p = group * uvec2(WRS_GROUP_X, WRS_GROUP_Y) + gl_LocalInvocationID.xy;
    uvec2 size = params.size.xy;
    if (TILES && gl_LocalInvocationIndex == 0u) tile_q = 0u;
    if (KIND == 1u && (reads_srgb_table(WIDE_ENCODING) || reads_srgb_table(INSET_ENCODING)))
        for (uint i = gl_LocalInvocationIndex; i < 256u; i += WRS_GROUP_X * WRS_GROUP_Y) s_srgb[i] = srgb_table[i];
    barrier();
    if (all(lessThan(p, size))) {
        float q = compose_pixel(eye, p, size);
        if (TILES && !OUTPUT) atomicMax(tile_q, floatBitsToUint(q));
    }
    if (!TILES || OUTPUT) return;
    barrier();
    if (gl_LocalInvocationIndex == 0u) {
        uvec2 tiles = tile_count(size);
        uvec2 t = group;
        quality[2u * size.x * size.y + (eye * tiles.y + t.y) * tiles.x + t.x] = tile_q;
    }
}
