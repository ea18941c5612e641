// Submitted foveation (docs/integrating.md, "Quad views" and "Shading-rate maps"): the per-pixel math
// of the compose pass (shaders/compose.comp) that turns quad views or a shading-rate map into the
// output-sized candidate and each pixel's rendered quality. Shared by GLSL and C++ like wrs_common.h;
// the CPU reference (compositor/reference.cpp, composeEye) runs the same functions in the same order.
#ifndef WRSFOV_WRS_SUBMITTED_H
#define WRSFOV_WRS_SUBMITTED_H

#include "wrs_common.h"

WRS_BEGIN

// Exactly the same bits on the GPU and the CPU: the compose pass stores what it computes rounded to
// fp16, where a last-bit difference before the rounding would flip a whole fp16 step. So its math is
// additions, subtractions and multiplications only, each correctly rounded in Vulkan as in C++, kept
// from fusing into FMAs (WRS_PRECISE; the C++ side compiles with -ffp-contract=off); every quotient
// (tangent spans over pixel counts, the blend width) is worked out once per frame on the host
// (compositor/input.cpp) and passed in, because a shader's division may be 2.5 ULP off.

// Position (in a source image's pixels, a pixel's centre at +0.5) of output pixel p's centre: affine in
// the pixel, map.xy its scale and map.zw its offset (makeComposeParams).
WRS_FN vec2 wrs_source_pos(uvec2 p, vec4 map) {
    WRS_PRECISE vec2 c = vec2(p) + vec2(0.5f, 0.5f);
    WRS_PRECISE vec2 scaled = c * vec2(map.x, map.y);
    WRS_PRECISE vec2 pos = scaled + vec2(map.z, map.w);
    return pos;
}

// Bilinear taps of a source position: i0 and i1 (clamped to the image, as a clamp-to-edge sampler)
// and the fraction towards i1.
WRS_FN vec2 wrs_bilinear_taps(vec2 pos, uvec2 src, WRS_OUT(uvec2) i0, WRS_OUT(uvec2) i1) {
    vec2 s = pos - vec2(0.5f, 0.5f);
    vec2 fl = floor(s);
    vec2 f = s - fl;
    ivec2 lo = ivec2(fl);
    ivec2 hi_limit = ivec2(src) - ivec2(1, 1);
    i0 = uvec2(clamp(lo, ivec2(0, 0), hi_limit));
    i1 = uvec2(clamp(lo + ivec2(1, 1), ivec2(0, 0), hi_limit));
    return f;
}

// a + (b - a) t, unfused.
WRS_FN vec4 wrs_lerp_exact(vec4 a, vec4 b, float t) {
    WRS_PRECISE vec4 d = b - a;
    WRS_PRECISE vec4 s = d * t;
    WRS_PRECISE vec4 r = a + s;
    return r;
}

// Bilinear blend of four decoded taps whose alpha is their validity (1 or 0). An invalid tap (a
// non-finite texel) takes the colour of the first valid one in the order c00, c10, c01, c11, so that
// nothing non-finite is blended and no weight needs renormalising (a division); alpha of the result is
// 1 where any tap was valid, else the result is (0, 0, 0, 0).
WRS_FN vec4 wrs_bilinear_valid(vec4 c00, vec4 c10, vec4 c01, vec4 c11, vec2 f) {
    vec4 first = c00.w > 0.5f ? c00 : c10.w > 0.5f ? c10 : c01.w > 0.5f ? c01 : c11;
    if (!(first.w > 0.5f)) return vec4(0.0f, 0.0f, 0.0f, 0.0f);
    vec4 a = c00.w > 0.5f ? c00 : first, b = c10.w > 0.5f ? c10 : first;
    vec4 c = c01.w > 0.5f ? c01 : first, d = c11.w > 0.5f ? c11 : first;
    vec4 r = wrs_lerp_exact(wrs_lerp_exact(a, b, f.x), wrs_lerp_exact(c, d, f.x), f.y);
    return vec4(r.x, r.y, r.z, 1.0f);
}

// The inset's weight at a position in its pixels: 1 deeper inside than the blend width from its
// nearest edge, falling linearly to 0 at the edge, 0 outside. inv_blend: 1 / the blend width in inset
// pixels (0: a hard edge).
WRS_FN float wrs_inset_weight(vec2 ipos, uvec2 isize, float inv_blend) {
    WRS_PRECISE float dx = min(ipos.x, float(isize.x) - ipos.x);
    WRS_PRECISE float dy = min(ipos.y, float(isize.y) - ipos.y);
    float d = min(dx, dy);
    if (!(d > 0.0f)) return 0.0f;
    if (!(inv_blend > 0.0f)) return 1.0f;
    WRS_PRECISE float t = d * inv_blend;
    return min(t, 1.0f);
}

// The inset's weight once the sources' validity is known (t from wrs_inset_weight): a source with no
// valid tap leaves the pixel to the other one, at that one's quality.
WRS_FN float wrs_quad_weight(float t, bool inset_valid, bool wide_valid) {
    if (!(t > 0.0f) || !inset_valid) return 0.0f;
    if (!wide_valid) return 1.0f;
    return t;
}
// The composed colour of the wide and the inset sample at weight t (wrs_quad_weight): either source
// alone at 0 and 1, so that a pixel the inset covers needs no wide sample.
WRS_FN vec4 wrs_quad_color(vec4 wide, vec4 inset, float t) {
    if (t == 0.0f) return wide;
    if (t == 1.0f) return inset;
    return wrs_lerp_exact(wide, inset, t);
}

// The composed colour's alpha (the compose pass's output, read as WRS_INPUT_COMPOSED): the pixel's rendered
// quality q where a source tap was valid, 0 where none was (wrs_input_valid reads alpha > 0 as valid), so
// that the quality travels with the colour instead of in a buffer of its own.
WRS_FN float wrs_composed_alpha(bool valid, float q) { return valid ? q : 0.0f; }

// Quality of a quad-view pixel: 1 where the inset alone shows, q_wide (the wide view's density over
// the inset's, squared) where the wide view alone shows, linear across the blend.
WRS_FN float wrs_quad_quality(float q_wide, float t) {
    WRS_PRECISE float span = 1.0f - q_wide;
    WRS_PRECISE float s = span * t;
    WRS_PRECISE float q = q_wide + s;
    return q;
}

// Landed wide samples (docs/retention.md "Landed wide samples"): a wide view's pixel holds a sample
// of the scene at its position on the view's sample lattice (the centre of the pixel, moved by the
// view's jitter: InsetView/ProjectionView::sampleOffset), taken with texture detail at the display's
// density (an engine's LOD bias for temporal upsampling). For an output pixel, the wide sample
// nearest its centre is offered to retention as a candidate of its own where its footprint, one output
// pixel wide, covers at least a quarter of the pixel ((1 - |dx|)(1 - |dy|) >= 1/4): so a sample that
// landed in a neighbouring pixel, within 3/4 of a pixel of this one's centre on one axis, is offered too
// (at 0.25 density with 8 phases that left 7 % of the stable pixel pairs without a landed sample in two
// frames running, against 15 % with only the pixel it landed in). Every landed sample is of one class,
// WRS_LANDED_Q, above the bilinear wide view's quality q_wide and below the inset's (1): the rule merges
// them into a running mean (clipped to the box of the landed sample and the composed colour), a
// supersampled estimate of the pixel from the sample positions the jitter and the head's motion put
// near it, where classes by overlap (quarters) let the nearer sample replace the mean (docs/retention.md
// "One class of landed samples": on the headset cell with 8 phases, JOD +0.11 at 0.4 density, +0.39 at
// 0.25).
//
// Offset, in output pixels, of sample k of the wide view (its texel, as wrs_source_pos's `pos` counts
// them) from the centre of the output pixel that maps to `pos`: (k + 0.5 - pos) times the output's
// pixels per source pixel (`inv_scale`, worked out on the host; no division here).
WRS_FN vec2 wrs_landed_offset(vec2 pos, uvec2 k, vec2 inv_scale) {
    WRS_PRECISE vec2 centre = vec2(k) + vec2(0.5f, 0.5f);
    WRS_PRECISE vec2 ds = centre - pos;
    WRS_PRECISE vec2 d = ds * inv_scale;
    return d;
}
// Where a landed sample is stored (RetainInput::d): its offset in output pixels (wrs_landed_offset with
// ComposeEye::landed.xy, the output's pixels per wide pixel) moved onto the pixel's footprint, as the
// tracked lookup snaps a sample it takes from next door (wrs_track_snap). A sample stored at the
// centre instead was carried from there by the motion, up to the footprint's half-width (a pixel and
// more) from where it was seen; at an edge under a fast turn the pixels beside it then showed its
// colour a frame before the edge came (docs/retention.md "Where a landed sample is stored").
WRS_FN vec2 wrs_landed_position(vec2 pos, uvec2 k, vec4 landed) {
    return wrs_track_snap(wrs_landed_offset(pos, k, vec2(landed.x, landed.y)));
}
// The footprint grows with the wide pixel (docs/retention.md "`wrs`'s parameters, searched on the training cell"): its half-width is
// max(1, k s) output pixels per axis, s the output pixels per wide pixel (ComposeEye::landed.xy) and k
// the half-width in wide pixels (landed.w for `wrs`: CompositorConfig::landedFootprint; 0: one output
// pixel at every density). Over P jitter phases the landed samples of a wide pixel lie about s / sqrt(P)
// output pixels apart, so a footprint of one output pixel reaches fewer of its pixels the sparser the
// wide views: at 0.2 of the density (s = 5) and 8 phases, about 40 %, the rest showing the wide view's
// bilinear colour. This returns the offset's scale for wrs_landed_offset, s over the half-width.
WRS_FN vec2 wrs_landed_scale(vec4 landed) {
    vec2 s = vec2(landed.x, landed.y);
    return s / max(vec2(1.0f, 1.0f), s * landed.w);
}
// How much of an output pixel a sample that landed at offset d from its centre tells: the overlap of
// its footprint (one output pixel wide) with the pixel, 0 a pixel or more away on either axis.
WRS_FN float wrs_landed_overlap(vec2 d) {
    if (!(abs(d.x) < 1.0f && abs(d.y) < 1.0f)) return 0.0f;
    WRS_PRECISE float ox = 1.0f - abs(d.x);
    WRS_PRECISE float oy = 1.0f - abs(d.y);
    WRS_PRECISE float q = ox * oy;
    return q;
}
// The least overlap at which a landed sample is offered, and the one quality every landed sample has.
const float WRS_LANDED_MIN_OVERLAP = 0.25f;
const float WRS_LANDED_Q = 0.75f;
// The quality of a sample that landed at offset d from an output pixel's centre: WRS_LANDED_Q where its
// footprint covers at least WRS_LANDED_MIN_OVERLAP of the pixel, 0 below (not offered).
WRS_FN float wrs_landed_quality(vec2 d) {
    float o = wrs_landed_overlap(d);
    return o >= WRS_LANDED_MIN_OVERLAP ? WRS_LANDED_Q : 0.0f;
}
// Landed weights (CompositorConfig::landedWeights; EyeParams::motion_rect.z = WRS_LANDED_ON |
// WRS_LANDED_WEIGHTED): a landed sample's weight in the running mean of its class is its footprint's
// overlap with the pixel, (1 - |dx|)(1 - |dy|), from 1/4 to 1, instead of 1 for every sample offered:
// the mean is then a tent-filtered estimate of the pixel, as a temporal upsampler's reconstruction
// kernel weighs its samples, rather than the plain mean of everything within 3/4 of a pixel, which
// blurs where the head moves slowly and samples of many positions accumulate (docs/retention.md,
// "Landed weights").
const uint WRS_LANDED_ON = 1u;
const uint WRS_LANDED_WEIGHTED = 2u;
// The weight of a sample that landed at offset d (0: not offered, wrs_landed_quality): its overlap where
// `weighted`, else 1.
WRS_FN float wrs_landed_weight(vec2 d, bool weighted) {
    float o = wrs_landed_overlap(d);
    if (!(o >= WRS_LANDED_MIN_OVERLAP)) return 0.0f;
    return weighted ? o : 1.0f;
}
// A landed sample as the compose pass stores it for retention (two words a pixel after the qualities
// and the tiles' largest): fp16 R | G, fp16 B | quality; colour rounded by hand as every stored value.
// Quality 0: none landed in the pixel (or its texel was not finite), the words read back as no sample.
WRS_FN uvec2 wrs_pack_landed(vec3 c, float q) {
    if (!(q > 0.0f)) return uvec2(0u, 0u);
    return uvec2(wrs_f32_to_f16(c.x) | (wrs_f32_to_f16(c.y) << 16u), wrs_f32_to_f16(c.z) | (wrs_f32_to_f16(q) << 16u));
}
WRS_FN vec4 wrs_unpack_landed(uvec2 w) {
    return vec4(wrs_f16_to_f32(w.x & 0xffffu), wrs_f16_to_f32(w.x >> 16u), wrs_f16_to_f32(w.y & 0xffffu),
                wrs_f16_to_f32(w.y >> 16u));
}

// Retention's candidate at a pixel where a wide sample landed (wrs_unpack_landed: colour, quality):
// the landed sample where it tells more of the pixel than the composed candidate, as a sample of its
// own (flagged WRS_FLAG_LANDED). Its tap box spans it and the composed candidate's box (the composed
// colour, the bilinear wide view at the pixel; on a frame that merges every phase, the wide box around
// it), so that an equal-quality history within the local variation merges and one outside is clipped
// to it first; the composed candidate otherwise. The fingerprint stays the composed frame's. The
// oracles are not offered it (they bound what any retention of the composed candidates can reach).
// `landed`: colour and weight (wrs_landed_weight; 0: none landed); its quality is WRS_LANDED_Q; `d` where
// it lies from the pixel's centre (wrs_landed_position), where it is stored.
WRS_FN void wrs_offer_landed(WRS_INOUT(RetainInput) c, vec4 landed, vec2 d) {
    if (!(landed.w > 0.0f) || !(WRS_LANDED_Q > c.q)) return;
    c.color = vec3(landed);
    c.q = WRS_LANDED_Q;
    c.weight = landed.w;
    c.d = d;
    c.lo = min(c.lo, c.color);  // the composed candidate's box: its colour, or the wide box around it
    c.hi = max(c.hi, c.color);
    c.flags = WRS_FLAG_LANDED;
}

// ---------------------------------------------------------------------------------------------
// Every phase merged (docs/retention.md "Every phase merged"). On a frame whose wide views were
// jittered (their sample offsets moved since the frame before), `wrs` has no floor rule: a pixel's
// wide candidates of equal quality, the composed one or a landed sample's class, merge over the phases
// as every equal-quality sample merges (a running mean of up to WRS_MERGE_CAP candidates), instead of
// each frame's phase being taken fresh and flickering as `fov` on jittered views does. The history is
// first clipped to the box of the wide view around the pixel: the composed image's 3x3 taps one wide
// pixel apart (wrs_wide_box_tap), which spans the wide lattice's local range. A box of adjacent output
// pixels spans a fraction of one wide pixel's variation (the bilinear interpolation between two wide
// samples) and clipped a history of other phases back to this phase's colour: on the headset cell
// (0.25 density, 10° inset, 8 phases) temporal instability 0.0187 with it, 0.0148 one wide pixel apart,
// against 0.0250 without merging.
// ---------------------------------------------------------------------------------------------

// The wide box's tap spacing in output pixels along x and y, packed x | y << 16 (EyeParams
// depth_rect.w; 0: no wide box): the output pixels per wide pixel (ComposeEye landed.xy), rounded, at
// least 1.
WRS_FN uint wrs_wide_box_steps(vec2 per_wide) {
    uint sx = uint(max(floor(per_wide.x + 0.5f), 1.0f));
    uint sy = uint(max(floor(per_wide.y + 0.5f), 1.0f));
    return min(sx, 0xffffu) | (min(sy, 0xffffu) << 16u);
}
// Whether quality q is a wide view's: at most q_wide, the wide view's quality (ComposeEye
// wide_motion.w), up to WRS_Q_EQUAL; the inset's and its blend's are above it.
WRS_FN bool wrs_is_wide_quality(float q, float q_wide) { return q <= q_wide * (1.0f + WRS_Q_EQUAL); }
// Whether a candidate of quality q is a wide one (the composed wide view, or a landed sample's class
// up to it) whose box is the wide box. Candidates of the inset and of its blend keep their own box
// (the fovea stays exact).
WRS_FN bool wrs_wide_box_applies(float q, float q_wide) { return wrs_is_wide_quality(q, q_wide); }
// Tap k (0..8, row-major) of the wide box at pixel p: p offset by -1, 0 or +1 spacing per axis,
// clamped to the image.
WRS_FN uvec2 wrs_wide_box_tap(uvec2 p, uint k, uint steps, uvec2 size) {
    ivec2 step = ivec2(int(steps & 0xffffu), int(steps >> 16u));
    ivec2 d = ivec2(int(k % 3u) - 1, int(k / 3u) - 1);
    ivec2 q = clamp(ivec2(p) + d * step, ivec2(0, 0), ivec2(size) - ivec2(1, 1));
    return uvec2(q);
}
// Widens [lo, hi] by a tap's colour; a tap that was not finite (validity 0 in w) is left out.
WRS_FN void wrs_wide_box_add(WRS_INOUT(vec3) lo, WRS_INOUT(vec3) hi, vec4 tap) {
    if (!(tap.w > 0.5f)) return;
    lo = min(lo, vec3(tap));
    hi = max(hi, vec3(tap));
}

// ---------------------------------------------------------------------------------------------
// Method `taau-simple` (docs/retention.md "The first baseline: taau-simple"): the project's first temporal
// upsampling of jittered wide views. Each frame, each output pixel gathers the wide samples around it (the
// four of its bilinear cell) weighted by a kernel of their distance from its centre in output pixels; the
// reprojected history, clipped to the variance box of the composed neighbourhood, is accumulated with them
// by weight, its accumulated weight capped so that it keeps following the scene. Where the inset shows,
// the composed frame as it is (what `fov` shows there). Method `taau` (below) is the upsampler as engines
// ship it.
// ---------------------------------------------------------------------------------------------

// The gather's kernel: (1 - d^2 / r^2)^2 inside radius r (inv_r2 = 1 / r^2), 0 outside; smooth, compact,
// and multiplications only, so that the GPU and the reference agree on every weight.
WRS_FN float wrs_taau_simple_kernel(vec2 d, float inv_r2) {
    WRS_PRECISE float dx2 = d.x * d.x;
    WRS_PRECISE float dy2 = d.y * d.y;
    WRS_PRECISE float d2 = dx2 + dy2;
    WRS_PRECISE float s = d2 * inv_r2;
    WRS_PRECISE float t = 1.0f - s;
    if (!(t > 0.0f)) return 0.0f;
    WRS_PRECISE float w = t * t;
    return w;
}
// Tap j (0..3) of the bilinear cell [i0, i1] (wrs_bilinear_taps) that the gather reads: false for a
// tap a clamp made the same sample as another.
WRS_FN bool wrs_taau_cell_tap(uvec2 i0, uvec2 i1, uint j, WRS_OUT(uvec2) k) {
    k = uvec2((j & 1u) != 0u ? i1.x : i0.x, (j & 2u) != 0u ? i1.y : i0.y);
    return !(((j & 1u) != 0u && i1.x == i0.x) || ((j & 2u) != 0u && i1.y == i0.y));
}
// Adds a decoded wide texel (validity in alpha) at offset d from the pixel's centre to the gather
// (xyz: the weighted sum of colours, w: the sum of weights).
WRS_FN vec4 wrs_taau_simple_add(vec4 acc, vec4 texel, vec2 d, float inv_r2) {
    if (!(texel.w > 0.5f)) return acc;
    float w = wrs_taau_simple_kernel(d, inv_r2);
    WRS_PRECISE vec3 s = vec3(texel) * w;
    WRS_PRECISE vec4 r = vec4(acc.x + s.x, acc.y + s.y, acc.z + s.z, acc.w + w);
    return r;
}
// The gathered colour and its weight (packed by the compose pass as a landed sample, wrs_pack_landed:
// nothing where no sample was within the radius).
WRS_FN vec4 wrs_taau_gathered(vec4 acc) {
    if (!(acc.w > 0.0f)) return vec4(0.0f, 0.0f, 0.0f, 0.0f);
    vec3 c = wrs_div(vec3(acc), acc.w);
    return vec4(c.x, c.y, c.z, acc.w);
}

// The weight the composed (bilinear) candidate is always given: it decides a pixel no sample came near
// and that has no history, and steadies one the history alone would decide. Small against a sample's
// (up to 1 at the centre, 0.17 a frame on average at 0.4 density with radius 1).
const float WRS_TAAU_PRIOR = 0.02f;

// One taau-simple step at a pixel. nb: the composed neighbourhood (YCoCg, centre 4); gathered: this frame's
// gathered samples (colour, weight; weight 0: none); inset: the inset shows here (the composed colour is
// taken as it is, with the full history weight); hist, acc: the reprojected history and its accumulated
// weight (has_history); max_acc: the accumulated weight's cap; gamma: the clip box's width in sigmas.
// Returns the colour (linear RGB) and the accumulated weight to store.
WRS_FN vec4 wrs_taau_simple_step(vec3 nb[9], vec4 gathered, bool inset, vec3 hist, float acc, bool has_history,
                          float max_acc, float gamma) {
    vec3 cand = wrs_ycocg_to_rgb(nb[4]);
    if (inset) return vec4(cand.x, cand.y, cand.z, max_acc);
    float a = 0.0f;
    vec3 h = vec3(0.0f, 0.0f, 0.0f);
    if (has_history) {
        a = min(acc, max_acc);
        h = max(wrs_ycocg_to_rgb(wrs_taa_clip(nb, hist, gamma)), vec3(0.0f, 0.0f, 0.0f));
    }
    float w = gathered.w > 0.0f ? gathered.w : 0.0f;
    WRS_PRECISE float den = a + w + WRS_TAAU_PRIOR;
    WRS_PRECISE vec3 num = h * a + vec3(gathered) * w + cand * WRS_TAAU_PRIOR;
    vec3 c = max(wrs_div(num, den), vec3(0.0f, 0.0f, 0.0f));
    return vec4(c.x, c.y, c.z, min(den, max_acc));
}

// ---------------------------------------------------------------------------------------------
// Method `taau` (docs/retention.md "The field's baseline: taau"): temporal upsampling of jittered wide views
// after FSR 2's published design, the project's own code.
//   Reconstruction (the compose pass): each output pixel gathers the wide samples of the 4x4 wide texels
//     around it with a Lanczos-2 kernel of their distance in wide pixels (the output's distance scaled by
//     the upsampling ratio) over the kernel scale; the gathered colour deringed to the range of the taps
//     that weigh.
//   Accumulation (the taa pass): the history reprojected with the motion; dropped where the depth it was
//     seen at matches none of the current depth (disocclusion); clipped to a box of the wide samples around
//     the pixel (the composed colour at 3x3 taps one wide pixel apart) of boxSigma standard deviations when
//     still, shrinking to one as the pixel's motion reaches fullVelocity output pixels a frame; widened where
//     a thin feature is locked (a pixel whose luma stands out of all of its neighbours' locks for lockFrames
//     frames, unless its luma then changes by half); the new sample weighed down where its luma oscillates
//     from frame to frame (luma stability); accumulated with the history by weight, capped.
// The history is 16 bytes a pixel as the reservoirs are: colour and accumulated weight, linear depth and
// lock, the last sample's luma and its change, each in fp16 (rounded by hand: the same bits everywhere).
// ---------------------------------------------------------------------------------------------

// Lanczos-2 as a polynomial in x^2 (multiplications only, so the GPU and the reference agree on every
// weight): (25/16 (2/5 x^2 - 1)^2 - 9/16) (x^2/4 - 1)^2 for x^2 < 4, 0 beyond; 1 at 0, 0 at 1 and 2, a
// negative lobe between.
WRS_FN float wrs_lanczos2_sq(float x2) {
    if (!(x2 < 4.0f)) return 0.0f;
    WRS_PRECISE float a = 0.4f * x2 - 1.0f;
    WRS_PRECISE float b = 0.25f * x2 - 1.0f;
    WRS_PRECISE float la = 1.5625f * a;
    WRS_PRECISE float l = la * a - 0.5625f;
    WRS_PRECISE float bb = b * b;
    WRS_PRECISE float w = l * bb;
    return w;
}
// Tap j (0..15) of the 4x4 wide texels around the bilinear cell at i0 (wrs_bilinear_taps) in a wide view of
// `size`: false off the view.
WRS_FN bool wrs_taau_block_tap(uvec2 i0, uvec2 size, uint j, WRS_OUT(uvec2) k) {
    ivec2 t = ivec2(i0) + ivec2(int(j & 3u) - 1, int(j >> 2u) - 1);
    k = uvec2(max(t, ivec2(0, 0)));
    return t.x >= 0 && t.y >= 0 && t.x < int(size.x) && t.y < int(size.y);
}
// The gather of the wide samples around a pixel: the weighted sum (xyz: colour, w: weight) and the range of
// the taps that weigh (lo, hi), which deringing clamps the gathered colour to.
struct TaauGather {
    vec4 acc;
    vec3 lo;
    vec3 hi;
};
WRS_FN TaauGather wrs_taau_gather_start() {
    TaauGather g;
    g.acc = vec4(0.0f, 0.0f, 0.0f, 0.0f);
    g.lo = vec3(65504.0f, 65504.0f, 65504.0f);
    g.hi = vec3(0.0f, 0.0f, 0.0f);
    return g;
}
// Adds a decoded wide texel (validity in alpha) centred at wide texel k to the gather of the pixel at wide
// position `pos`; inv_k2 = 1 / kernel scale^2 (wide pixels).
WRS_FN void wrs_taau_gather_add(WRS_INOUT(TaauGather) g, vec4 texel, vec2 pos, uvec2 k, float inv_k2) {
    if (!(texel.w > 0.5f)) return;
    WRS_PRECISE vec2 ds = vec2(k) + vec2(0.5f, 0.5f) - pos;
    WRS_PRECISE float dx2 = ds.x * ds.x;
    WRS_PRECISE float dy2 = ds.y * ds.y;
    WRS_PRECISE float d2 = dx2 + dy2;
    WRS_PRECISE float x2 = d2 * inv_k2;
    float w = wrs_lanczos2_sq(x2);
    if (w == 0.0f) return;
    WRS_PRECISE vec3 sc = vec3(texel) * w;
    WRS_PRECISE vec4 r = vec4(g.acc.x + sc.x, g.acc.y + sc.y, g.acc.z + sc.z, g.acc.w + w);
    g.acc = r;
    if (w > 0.0f) {
        g.lo = min(g.lo, vec3(texel));
        g.hi = max(g.hi, vec3(texel));
    }
}
// The gathered colour (deringed) and its weight; nothing where the weights sum to none (packed as a landed
// sample: wrs_pack_landed).
WRS_FN vec4 wrs_taau_gather_result(TaauGather g) {
    vec4 c = wrs_taau_gathered(g.acc);
    if (!(c.w > 0.0f)) return c;
    vec3 d = clamp(vec3(c), g.lo, g.hi);
    return vec4(d.x, d.y, d.z, c.w);
}

// History resampling, as FSR 2 reads its history: a history reprojected to a fractional position is read
// with Lanczos-2 (wrs_lanczos2_sq) over the 4x4 pixels around its bilinear cell, the weighted sum deringed
// to the range of the cell's own four pixels (the accumulation of a TaauGather). A bilinear read blurs a
// history that is reprojected every frame a little on each frame, by an amount that follows the fraction,
// so that under fast motion the edges it keeps are soft and their softness changes from frame to frame:
// the steady display on the atrium's 120 degree-a-second turn (3 to 7 output pixels a frame) brought
// retention's flat checker squares a bright fringe every few frames (docs/retention.md, "History resampling").
// Tap j (0..15) of the 4x4 pixels around the bilinear cell at i0 (wrs_taa_reproject), clamped to the view.
WRS_FN uvec2 wrs_history_tap(uvec2 i0, uvec2 size, uint j) {
    ivec2 t = ivec2(i0) + ivec2(int(j & 3u) - 1, int(j >> 2u) - 1);
    return uvec2(clamp(t, ivec2(0, 0), ivec2(size) - ivec2(1, 1)));
}
// The Lanczos-2 weights of the four taps along one axis (offsets -1, 0, 1, 2 from the cell's first pixel)
// at the bilinear fraction f (wrs_taa_reproject): worked out once per axis, 8 weights for the 16 taps.
WRS_FN vec4 wrs_history_weights(float f) {
    WRS_PRECISE float d0 = -1.0f - f;
    WRS_PRECISE float d2 = 1.0f - f;
    WRS_PRECISE float d3 = 2.0f - f;
    WRS_PRECISE float s0 = d0 * d0;
    WRS_PRECISE float s1 = f * f;
    WRS_PRECISE float s2 = d2 * d2;
    WRS_PRECISE float s3 = d3 * d3;
    return vec4(wrs_lanczos2_sq(s0), wrs_lanczos2_sq(s1), wrs_lanczos2_sq(s2), wrs_lanczos2_sq(s3));
}
// Adds tap j's colour to the resampling `g` (from wrs_taau_gather_start): its weight wx[j & 3] * wy[j >> 2]
// (wrs_history_weights of the fraction's x and y), and the cell's range.
WRS_FN void wrs_history_add(WRS_INOUT(TaauGather) g, vec3 c, vec4 wx, vec4 wy, uint j) {
    uint i = j & 3u, k = j >> 2u;
    WRS_PRECISE float w = wx[int(i)] * wy[int(k)];
    WRS_PRECISE vec3 sc = c * w;
    g.acc = vec4(g.acc.x + sc.x, g.acc.y + sc.y, g.acc.z + sc.z, g.acc.w + w);
    if (i >= 1u && i <= 2u && k >= 1u && k <= 2u) {
        g.lo = min(g.lo, c);
        g.hi = max(g.hi, c);
    }
}
// The resampled history: the weighted mean clamped to the cell's range (the weights sum to about 1 and
// above 0: the cell's four are positive and outweigh the negative lobe's twelve).
WRS_FN vec3 wrs_history_result(TaauGather g) {
    vec4 c = wrs_taau_gathered(g.acc);
    return clamp(vec3(c), g.lo, g.hi);
}

// A pixel's history (unpacked).
struct TaauHistory {
    vec3 color;    // linear RGB
    float weight;  // accumulated weight (0: no history)
    float depth;   // linear depth it was seen at (<= 0: unknown)
    float lock;    // frames the thin-feature lock has left
    float luma;    // the last sample's luma
    float delta;   // its change from the frame before
};
WRS_FN uvec4 wrs_taau_pack(TaauHistory h) {
    return uvec4(wrs_f32_to_f16(h.color.x) | (wrs_f32_to_f16(h.color.y) << 16u),
                 wrs_f32_to_f16(h.color.z) | (wrs_f32_to_f16(h.weight) << 16u),
                 wrs_f32_to_f16(h.depth) | (wrs_f32_to_f16(h.lock) << 16u),
                 wrs_f32_to_f16(h.luma) | (wrs_f32_to_f16(h.delta) << 16u));
}
WRS_FN TaauHistory wrs_taau_unpack(uvec4 p) {
    TaauHistory h;
    h.color = vec3(wrs_f16_to_f32(p.x & 0xffffu), wrs_f16_to_f32(p.x >> 16u), wrs_f16_to_f32(p.y & 0xffffu));
    h.weight = wrs_f16_to_f32(p.y >> 16u);
    h.depth = wrs_f16_to_f32(p.z & 0xffffu);
    h.lock = wrs_f16_to_f32(p.z >> 16u);
    h.luma = wrs_f16_to_f32(p.w & 0xffffu);
    h.delta = wrs_f16_to_f32(p.w >> 16u);
    return h;
}
// Whether a packed history holds a pixel (its weight is never 0 once written: at least WRS_TAAU_PRIOR).
WRS_FN bool wrs_taau_packed_valid(uvec4 p) { return (p.y >> 16u) != 0u; }
// Whether depth `prev` (where the history was seen) is the surface at current depth `cur`, within the
// relative tolerance tau; unknown depths (<= 0 or not finite) match anything.
WRS_FN bool wrs_taau_depth_matches(float prev, float cur, float tau) {
    if (!(prev > 0.0f) || !(cur > 0.0f) || !wrs_finite(prev) || !wrs_finite(cur)) return true;
    WRS_PRECISE float d = abs(prev - cur);
    WRS_PRECISE float m = max(prev, cur) * tau;
    return d <= m;
}
// The four reprojected histories blended with the bilinear weights f (colour, weight, luma and its
// change), the lock of the nearest; the depths are tested apart (wrs_taau_depth_matches).
WRS_FN TaauHistory wrs_taau_blend(TaauHistory a, TaauHistory b, TaauHistory c, TaauHistory d, vec2 f) {
    TaauHistory h;
    h.color = vec3(wrs_bilinear(vec4(a.color, a.weight), vec4(b.color, b.weight), vec4(c.color, c.weight),
                                vec4(d.color, d.weight), f));
    h.weight = wrs_bilinear(vec4(a.weight), vec4(b.weight), vec4(c.weight), vec4(d.weight), f).x;
    h.luma = wrs_bilinear(vec4(a.luma), vec4(b.luma), vec4(c.luma), vec4(d.luma), f).x;
    h.delta = wrs_bilinear(vec4(a.delta), vec4(b.delta), vec4(c.delta), vec4(d.delta), f).x;
    bool right = f.x >= 0.5f, down = f.y >= 0.5f;
    h.lock = down ? (right ? d.lock : c.lock) : (right ? b.lock : a.lock);
    h.depth = 0.0f;
    return h;
}
// The history at a pixel from its four reprojected taps (bilinear weights f): blended into `h`; true where
// it is usable, finite and seen at the pixel's depth by at least one tap (false: disoccluded).
WRS_FN bool wrs_taau_reproject(TaauHistory a, TaauHistory b, TaauHistory c, TaauHistory d, vec2 f, float depth,
                               float tau, WRS_OUT(TaauHistory) h) {
    h = wrs_taau_blend(a, b, c, d, f);
    return wrs_finite3(h.color) &&
           (wrs_taau_depth_matches(a.depth, depth, tau) || wrs_taau_depth_matches(b.depth, depth, tau) ||
            wrs_taau_depth_matches(c.depth, depth, tau) || wrs_taau_depth_matches(d.depth, depth, tau));
}

// One taau step at a pixel. nb: the box taps (the composed colour at 3x3 taps one wide pixel apart, YCoCg,
// centre 4: the pixel's own); g: the gathered samples (colour, weight; 0: none); inset: the inset shows here
// (the composed colour as it is); h: the reprojected history where has_history (already false where the
// depth disoccluded it); depth: the pixel's linear depth; vel: its motion in output pixels a frame; max_acc,
// stability (depth_range.zw), box (EyeParams::taau: still box sigmas, full velocity, lock frames, lock
// threshold). Returns the colour shown; `next` the history to store.
WRS_FN vec3 wrs_taau_step(vec3 nb[9], vec4 g, bool inset, TaauHistory h, bool has_history, float depth, float vel,
                          float max_acc, float stability, vec4 box, WRS_OUT(TaauHistory) next) {
    vec3 cand = wrs_ycocg_to_rgb(nb[4]);
    float lc = nb[4].x;
    next.depth = depth;
    next.delta = 0.0f;
    if (inset) {
        next.color = cand;
        next.weight = max_acc;
        next.lock = 0.0f;
        next.luma = lc;
        return cand;
    }
    // A thin feature: the pixel's luma above all of its neighbours' by the threshold (relative), or below.
    float lmax = 0.0f;
    float lmin = 65504.0f;
    for (int i = 0; i < 9; ++i) {
        if (i == 4) continue;
        lmax = max(lmax, nb[i].x);
        lmin = min(lmin, nb[i].x);
    }
    WRS_PRECISE float above = lc - lmax;
    WRS_PRECISE float below = lmin - lc;
    WRS_PRECISE float ta = box.w * lc;
    WRS_PRECISE float tb = box.w * lmin;
    bool thin = above > ta || below > tb;
    float lock = 0.0f;
    float a = 0.0f;
    vec3 hc = vec3(0.0f, 0.0f, 0.0f);
    float w = g.w > 0.0f ? g.w : 0.0f;
    float ls = w > 0.0f ? wrs_rgb_to_ycocg(vec3(g)).x : lc;  // this frame's sample luma
    if (has_history) {
        // The box: boxSigma when still, one sigma at full velocity; locked: twice the still box.
        float vf = clamp(wrs_div(vel, box.y), 0.0f, 1.0f);
        WRS_PRECISE float gamma = box.x + (1.0f - box.x) * vf;
        WRS_PRECISE float hl = wrs_rgb_to_ycocg(h.color).x;
        WRS_PRECISE float change = abs(hl - lc);
        WRS_PRECISE float half_max = 0.5f * max(hl, lc);
        bool locked = h.lock > 0.0f && !(change > half_max);
        if (locked) gamma = 2.0f * box.x;
        if (locked) lock = h.lock - 1.0f;
        hc = max(wrs_ycocg_to_rgb(wrs_taa_clip(nb, h.color, gamma)), vec3(0.0f, 0.0f, 0.0f));
        a = min(h.weight, max_acc);
        // Luma stability: a sample whose luma turned back against last frame's change weighs less.
        WRS_PRECISE float d_now = ls - h.luma;
        WRS_PRECISE float turn = d_now * h.delta;
        if (turn < 0.0f) {
            WRS_PRECISE float osc = min(abs(d_now), abs(h.delta));
            WRS_PRECISE float ref = max(ls, h.luma) + 0.05f;
            WRS_PRECISE float rel = wrs_div(osc, ref);
            WRS_PRECISE float damp = 1.0f + stability * rel;
            w = wrs_div(w, damp);
        }
        next.delta = d_now;
    }
    if (thin) lock = box.z;
    WRS_PRECISE float den = a + w + WRS_TAAU_PRIOR;
    WRS_PRECISE vec3 num = hc * a + vec3(g) * w + cand * WRS_TAAU_PRIOR;
    vec3 c = max(wrs_div(num, den), vec3(0.0f, 0.0f, 0.0f));
    next.color = c;
    next.weight = min(den, max_acc);
    next.lock = lock;
    next.luma = ls;
    return c;
}

// The steady display (docs/retention.md "Steady display"; `wrs` on quad views with landed samples,
// CompositorConfig::steadyDisplay): what retention shows at a pixel of the wide views is filtered over
// time as TAA filters a frame, the display's previous colour reprojected with the pixel's motion
// (bilinear), clipped to a box of the wide view around the pixel (below), and blended with it by weight
// `alpha`. Retention keeps a sharp estimate per pixel, but where the head's motion carries landed samples
// across the pixels each pixel's estimate moves as samples arrive and leave; the filter keeps that
// movement from reading as flicker. Display only: the reservoirs and the rule are unchanged, and the
// inset's pixels (rendered sharper than the wide views) show retention's colour as it is.
//
// It runs in the retain pass (retain.comp DISPLAY), which shows the pixel, so nothing it shows goes
// through memory to a pass of its own. The box is one that pass has: the wide view's composed colour at
// the 3x3 taps one wide pixel apart (wrs_wide_box_tap, the merge's box; their YCoCg moments mu, sigma),
// mean ± WRS_DISPLAY_GAMMA sigma, grown to hold the shown colour. Grown, a still pixel converges to what
// retention shows (the variance box alone can leave out a pixel of fine detail that differs from its
// neighbours, and the filter would then pull it towards their mean on every frame, a blur that never
// settles). It replaced the 3x3 neighbourhood of what retention shows (a pass of its own, 40 B a pixel);
// docs/retention.md has the measurements of both.
// The default weight of the current frame, chosen on the moving-content study's training cell (dynamic,
// the head turning; 3 seeds, 0.3 and 0.2 density; docs/retention.md "Steady display"): the best JOD whose
// temporal instability stays within 3 % of taau's at both densities. 0.15 (the weight chosen first, on
// the headset cell with a translating head) lags where content moves: JOD 7.675 / 7.306 against 7.756 /
// 7.362 at 0.3; 0.4 is 13 % less steady than taau at 0.3 for +0.009 JOD.
const float WRS_DISPLAY_ALPHA = 0.3f;
// The weight where the pixel moves (CompositorConfig::steadyDisplaySpeed): `alpha` up to `full_speed`
// output pixels a frame, alpha * full_speed / |motion| beyond, down to alpha * WRS_DISPLAY_FAST_SHARE. Where
// the head turns fast each pixel's estimate changes as landed samples of other wide pixels arrive, and at
// one weight for every speed that change shows as flicker on content the turn leaves unchanged
// (docs/retention.md "`wrs`'s parameters, searched on the training cell"); the history is clipped to the
// wide box either way. `full_speed` 0 (or a motion that is not finite): `alpha` as it is.
// The full speed, chosen on the study's two training cells (dynamic turning at up to 26 degrees a second,
// under one output pixel a frame at 320 px, and the atrium yawing at 60 degrees a second, 1-2 pixels): the
// best JOD whose instability stays within 3 % of taau's at both densities. 1: +2.1 % and -4.7 % at the
// atrium's 0.3 and 0.2 (+10.9 % and +9.0 % at one weight), -0.11 and -0.08 JOD; 1.5: +6.7 % and +2.0 %;
// 2: +9.2 % and +5.9 %; 0.5 loses 0.33 JOD there (those without the floor below; with it, the default is
// +3.0 % and -3.1 %, at the rule's edge, for +0.026 JOD). Turning dynamic, no pixel reaches 1.
const float WRS_DISPLAY_FULL_SPEED = 1.0f;
// The least share of the weight a fast pixel keeps: half, the weight the display had before the study
// (0.15). Neither training cell moves a pixel more than about 2 output pixels a frame, where the share is
// half already; the floor keeps the falling weight from lagging without bound where the head turns faster,
// a bound set without a cell to choose it on (a head at 120 degrees a second moves 4 pixels a frame).
const float WRS_DISPLAY_FAST_SHARE = 0.5f;
WRS_FN float wrs_display_weight(float alpha, vec3 mv, float full_speed) {
    if (!(full_speed > 0.0f) || !wrs_finite(mv.x) || !wrs_finite(mv.y)) return alpha;
    float speed = sqrt(mv.x * mv.x + mv.y * mv.y);
    return speed > full_speed ? alpha * max(full_speed / speed, WRS_DISPLAY_FAST_SHARE) : alpha;
}
// The box's half-width in standard deviations of the wide neighbourhood. Headset cell (0.3 and 0.2
// density, 10-degree inset, 8 phases): temporal instability 0.00967 and 0.00927 at 1, 0.00878 and 0.00869
// at 2, 0.00816 and 0.00857 at 4 (JOD 8.46 / 8.05, 8.47 / 8.07, 8.49 / 8.08); the wide taps lie a wide
// pixel apart, where what retention shows varies within a pixel.
const float WRS_DISPLAY_GAMMA = 4.0f;
// A tap of the box's neighbourhood (decoded: validity in alpha); a tap whose input was not finite counts as
// the pixel's own composed colour `own`.
WRS_FN vec3 wrs_display_tap(vec4 tap, vec4 own) { return tap.w > 0.5f ? vec3(tap) : vec3(own); }
// One step of the steady display at a pixel of the wide views: `mu`, `sigma` the moments of its wide
// neighbourhood (wrs_moments_of_nine of wrs_display_tap, YCoCg), `shown` what retention shows there
// (linear RGB), `hist` the display's previous colour reprojected (linear RGB) where `has_history`.
// Returns the colour displayed, which is also the display's history.
WRS_FN vec3 wrs_display_fold_step(vec3 mu, vec3 sigma, vec3 shown, vec3 hist, bool has_history, float alpha) {
    if (!has_history || !wrs_finite3(hist)) return shown;
    vec3 s = wrs_rgb_to_ycocg(shown);
    vec3 lo = min(mu - 4.0f * sigma, s);
    vec3 hi = max(mu + 4.0f * sigma, s);
    WRS_PRECISE vec3 centre = (lo + hi) * 0.5f;
    WRS_PRECISE vec3 extent = (hi - lo) * 0.5f;
    vec3 h = wrs_clip_box(wrs_rgb_to_ycocg(hist), centre, extent);
    WRS_PRECISE vec3 out_ycocg = h + (s - h) * alpha;
    return max(wrs_ycocg_to_rgb(out_ycocg), vec3(0.0f, 0.0f, 0.0f));
}

// What the steady display stores of a colour, 8 bytes a pixel (fp16 RGB, then 1 where written): the
// retain pass's shown colour in the candidate buffer (store_output) and the display's own history. The
// display's output is made from the unrounded colour; only what the next pass or frame reads is fp16.
WRS_FN uvec2 wrs_pack_shown(vec3 c) { return uvec2(wrs_store_f16x2(c.x, c.y), wrs_store_f16x2(c.z, 1.0f)); }
WRS_FN vec3 wrs_unpack_shown(uvec2 w) { return vec3(wrs_unpack_f16x2(w.x), wrs_unpack_f16x2(w.y).x); }
WRS_FN bool wrs_shown_written(uvec2 w) { return (w.y >> 16u) != 0u; }

// Quality of a pixel shaded at rate texel v (VK_KHR_fragment_shading_rate: w = 2^((v >> 2) & 3),
// h = 2^(v & 3); bits 4..7 ignored): 1 / (w h). A size of 8 (field 3), absent from Vulkan's table of
// fragment sizes, is taken as 4.
WRS_FN float wrs_rate_quality(uint v) {
    uint lw = min((v >> 2u) & 3u, 2u), lh = min(v & 3u, 2u);
    return uintBitsToFloat((127u - lw - lh) << 23u);  // 2^-(lw + lh), exact (a quotient may be 2.5 ULP off)
}
// The lowest quality a rate map can give (4x4): the floor rule's quality for rate-map frames.
const float WRS_RATE_FLOOR = 0.0625f;

WRS_END

#endif
