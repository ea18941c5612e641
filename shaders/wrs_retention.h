// Quality-aware retention: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_RETENTION_H
#define WRSFOV_WRS_RETENTION_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_numbers.h"
#include "wrs_views.h"
#include "wrs_foveation.h"
#include "wrs_colour.h"
#include "wrs_depth.h"
#include "wrs_random.h"
#include "wrs_reservoir.h"

WRS_BEGIN

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

// Packed storage, 16 bytes per pixel like the paper's reservoir (docs/retention.md "Reservoir layout"):
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
    // Its weight in a merge of its class, as a share of its quality (1; a landed sample's footprint
    // overlap under landed weights, wrs_landed_weight).
    float weight;
    // Where the sample lies from the pixel's centre, in output pixels, inside the footprint: 0 for a
    // composed candidate (taken at the centre), a landed sample's own position (wrs_landed_position).
    vec2 d;
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
    r.d = c.d;
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
    Tracked fresh = wrs_tracked_from(c, max(c.q * c.weight, WRS_WSUM_MIN));
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
    float t = wrs_merge_weight(h.w_sum, c.q * c.weight);
    Tracked r = kept;
    r.color = hist + (c.color - hist) * t;
    // The mean sits where its samples do, weighted as they are (a composed candidate's at the centre).
    WRS_PRECISE vec2 d_kept = d_new * (1.0f - t);
    WRS_PRECISE vec2 d_cand = c.d * t;
    r.d = d_kept + d_cand;
    r.w_sum = min(h.w_sum + c.q * c.weight, WRS_MERGE_CAP * c.q);
    return r;
}

WRS_END

#endif
