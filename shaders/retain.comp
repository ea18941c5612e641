// Pass 2 of method `wrs` (and the evaluation-only `oracle` and `oracle-q`): foveation and quality-aware
// retention in one pass (shaders/wrs_common.h, "Quality-aware retention"). Per pixel: the foveated
// candidate with its quality and tap range, the level-4 fingerprint, the tracked reprojection of
// the kept sample, the depth and change tests, the retention rule, the reservoir store and the output.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const bool HAS_MOTION = false;
layout(constant_id = 1) const bool HAS_DEPTH = false;
layout(constant_id = 2) const uint FOV_MODE = 1u;
layout(constant_id = 3) const uint RULE = 0u;
// Reservoirs updated in place (no motion: only the pixel's own is read; bindings 7 and 8 are the same
// buffer): a pixel whose packed reservoir did not change is not stored.
layout(constant_id = 4) const bool IN_PLACE = false;
// 0: every pixel (levels per pixel); 1 + class: the tiles of one class (wrs_tile_levels, no eccentricity).
layout(constant_id = 5) const uint TILE = 0u;
// Sparse retention (tiled only; docs/retention.md "Sparse retention"): a tap in a tile that stored
// nothing reads as a floor-quality sample at its centre (wrs_floor_sample), and each group (one tile)
// records the best quality it stored in TileHeld.
layout(constant_id = 6) const bool SPARSE = false;
// The steady display folded in (docs/retention.md "Steady display"; `wrs` on quad views with landed samples,
// frame.tuning.z its weight): the pass filters what it shows where it shows the wide views
// (wrs_display_fold_step) and writes the output and the display's history, slot push.pad0 (the last
// frame's, push.pad1, valid where push.pad2 says so).
layout(constant_id = 10) const bool DISPLAY = false;
// Quad views with landed samples: how the wide views' colour is encoded (WRS_INPUT_*, ComposeEye
// wide_color.z, the same for both eyes), or WRS_INPUT_ANY (each eye's, read at run time).
layout(constant_id = 11) const uint WIDE_ENCODING = 4u;
layout(push_constant) uniform Push { LevelPush push; };
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

shared uint group_held;

// The stored sample at pixel q of the previous frame, as a tracked lookup reads it.
uvec4 history_tap(uint eye, uvec2 q) {
    if (SPARSE && tile_held[frame.held.x + tile_index(eye, q / WRS_TILE)] == 0u) return wrs_floor_sample(frame.tuning.w);
    return res_prev[pixel_index(eye, q)];
}

// Quad views: pixel p's landed wide sample (colour, quality; quality 0: none), as the compose pass's LANDED 1
// finds it (wrs_landed_quality of the wide texel nearest the pixel's centre) and as it would store it
// (wrs_pack_landed), read from the wide view here rather than through memory. Where the inset alone shows
// the compose pass offers none; here the sample may be found, but a candidate of the inset's quality (1)
// is above any landed sample's, so wrs_offer_landed never takes it there: the same outcome. `d`: where it
// lies from the pixel's centre (wrs_landed_position).
vec4 landed_sample(uint eye, uvec2 p, out vec2 d) {
    ComposeEye ce = compose.eye[eye];
    vec2 wpos = wrs_source_pos(p, ce.wide_map);
    uvec2 k = uvec2(clamp(ivec2(floor(wpos)), ivec2(0), ivec2(ce.sizes.xy) - ivec2(1)));
    d = wrs_landed_position(wpos, k, ce.landed);
    bool weighted = (frame.eye[eye].motion_rect.z & WRS_LANDED_WEIGHTED) != 0u;
    float ql = wrs_landed_weight(wrs_landed_offset(wpos, k, wrs_landed_scale(ce.landed)), weighted);
    if (!(ql > 0.0)) return vec4(0.0);
    uint encoding = WIDE_ENCODING == WRS_INPUT_ANY ? ce.wide_color.z : WIDE_ENCODING;
    vec4 s = wrs_decode_input(vec4(texelFetch(wideIn[eye], ivec2(k + ce.wide_color.xy), 0).rgb, 1.0), encoding);
    if (s.w == 0.0) return vec4(0.0);
    // wrs_unpack_landed(wrs_pack_landed(s.rgb, ql)): the colour and the weight rounded to fp16
    // (wrs_f16_value: the same bits; a weight of 1 fp16 holds exactly).
    return vec4(wrs_f16_value(s.x), wrs_f16_value(s.y), wrs_f16_value(s.z), wrs_f16_value(ql));
}

// The steady display's previous colour at pixel q (wrs_pack_shown), of slot push.pad1.
vec4 display_rgb(uint eye, uvec2 q) { return vec4(wrs_unpack_shown(display_history[display_index(push.pad1, eye, q)]), 0.0); }
// The steady display folded in: what pixel p shows, filtered over time where it shows the wide views
// (`filters`; m1, m2 the moments of its wide neighbourhood), its display history stored either way (the
// inset's pixels: what they show).
vec3 display(uint eye, uvec2 p, vec3 shown, vec3 mv, bool filters, vec3 m1, vec3 m2) {
    vec3 c = shown;
    if (filters) {
        uvec2 i0, i1;
        vec2 f;
        bool has = push.pad2 != 0u && wrs_taa_reproject(p, frame.size.xy, mv, i0, i1, f) &&
                   wrs_shown_written(display_history[display_index(push.pad1, eye, p)]);
        vec3 hist = vec3(0.0);
        if (has) {  // resampled with Lanczos-2 (wrs_history_add)
            TaauGather hg = wrs_taau_gather_start();
            vec4 wx = wrs_history_weights(f.x), wy = wrs_history_weights(f.y);
            for (uint j = 0u; j < 16u; ++j) wrs_history_add(hg, display_rgb(eye, wrs_history_tap(i0, frame.size.xy, j)).rgb, wx, wy, j);
            hist = wrs_history_result(hg);
        }
        vec3 mu, sigma;
        wrs_moments_of_nine(m1, m2, mu, sigma);
        // The weight falls where the pixel moves fast (wrs_display_weight; display.y: the full speed's bits).
        float alpha = wrs_display_weight(frame.tuning.z, mv, uintBitsToFloat(frame.eye[eye].display.y));
        c = wrs_display_fold_step(mu, sigma, shown, hist, has, alpha);
    }
    display_history[display_index(push.pad0, eye, p)] = wrs_pack_shown(c);
    return c;
}

// Retention at pixel p: stores its reservoir and output; returns the quality stored.
float retain_pixel(uint eye, uvec2 p) {
    uvec2 size = frame.size.xy;
    EyeParams ep = frame.eye[eye];
    uint idx = pixel_index(eye, p);

    // Candidate: foveated colour, quality, the range of the taps it came from and the fingerprint.
    float e;
    vec3 lv = pixel_levels(TILE, FOV_MODE, eye, p, e);
    vec4 ref = load_color(eye, p);
    float q_sub = FOV_MODE == WRS_FOV_SUBMITTED ? submitted_quality(eye, p, idx) : 0.0;
    RetainInput c = wrs_candidate_at(eye_pyramid(eye), FOV_MODE, p, ref, lv, e, ep.gaze.w, q_sub, true).rule;
    c.z = HAS_DEPTH ? load_depth(eye, p) : 0.0;
    c.q_floor = frame.tuning.w;
    // The wide view's composed colour at the 3x3 taps one wide pixel apart, in one pass over them: every
    // phase merged, a wide candidate's box spans them; the steady display clips its history to their
    // moments where it filters the pixel (display.x and depth_rect.w are the same spacing where both are set).
    bool filters = DISPLAY && display_filters(eye, p, idx);
    vec3 m1 = vec3(0.0), m2 = vec3(0.0);
    if (FOV_MODE == WRS_FOV_SUBMITTED) {
        c.jittered = ep.motion_rect.w != 0u;
        bool box = ep.depth_rect.w != 0u && wrs_wide_box_applies(c.q, ep.tile.w);
        if (box || filters) {
            uint steps = filters ? ep.display.x : ep.depth_rect.w;
            for (uint k = 0u; k < 9u; ++k) {
                vec4 t = load_color(eye, wrs_wide_box_tap(p, k, steps, size));
                if (box) wrs_wide_box_add(c.lo, c.hi, t);
                if (filters) wrs_moments_add(m1, m2, wrs_rgb_to_ycocg(wrs_display_tap(t, ref)));
            }
        }
        if (ep.motion_rect.z != 0u && !wrs_rule_is_oracle(RULE)) {
            vec2 dl;
            vec4 l = landed_sample(eye, p, dl);
            wrs_offer_landed(c, l, dl);
        }
    }

    // Tracked reprojection of the kept sample.
    vec3 mv = vec3(0.0);
    if (HAS_MOTION) mv = texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz;
    c.moved = wrs_finite(mv.x) && wrs_finite(mv.y) && (mv.x != 0.0 || mv.y != 0.0);
    vec2 pos;
    ivec2 base;
    bool on_screen = wrs_track_start(p, size, mv, ep.motion_scale.w, pos, base);
    // Without motion only the pixel's own sample can be inside its footprint (footprints are disjoint
    // and every stored offset lies inside its own): one read instead of four, the same result.
    uint taps = c.moved ? 4u : 1u;
    float dz = wrs_finite(mv.z) ? mv.z : 0.0;
    TrackState ts = wrs_track_begin(p);
    // Kept for the display of a kept sample: each tap's colour and quality words and its weight
    // (wrs_shown_weight, worked out here so that its depth and offset words need not stay live).
    uvec4 tap[4];
    vec4 tap_w = vec4(0.0);
    for (uint k = 0u; k < 4u; ++k) {
        tap[k] = uvec4(0u);  // all-zero storage is no sample
        uvec2 qk;
        if (k >= taps || !on_screen || !wrs_track_tap(base, k, size, qk)) continue;
        tap[k] = history_tap(eye, qk);
        wrs_track_consider(ts, tap[k], qk, pos);
        tap_w[k] = wrs_shown_weight(tap[k], qk, pos, c.z, dz, frame.tuning.y);
    }
    Tracked h;
    vec2 d;
    uvec2 q;
    bool found = wrs_track_end(ts, h, d, q);
    bool has_history = found;
    if (HAS_DEPTH && has_history && !wrs_rule_is_oracle(RULE) && wrs_depth_flush(h.z, c.z, dz, frame.tuning.y))
        has_history = false;

    // What a kept sample shows under motion: the tent-weighted mean of the tracked samples of its
    // quality around the centre (wrs_shown_add). Worked out only for a kept sample (the oracle, which
    // judges the history as it would be shown, needs it before its decision).
    bool show_mean = has_history && c.moved;
    vec3 h_shown = h.color;
    if (wrs_rule_is_oracle(RULE) && show_mean)
        h_shown = wrs_shown_mean(tap[0], tap[1], tap[2], tap[3], tap_w, h.q, h.color);
    float rnd = wrs_rand(p.x, p.y, eye, frame.size.z, frame.size.w);
    uint outcome;
    float margin;
    Tracked hd = h;
    if (wrs_rule_is_oracle(RULE)) hd.color = h_shown;
    // The oracles compare with the unfoveated colour: the submitted one, or for a frame submitted
    // foveated the full-resolution reference that came with it.
    vec3 truth = wrs_rule_is_oracle(RULE) && FOV_MODE == WRS_FOV_SUBMITTED ? load_reference(eye, p) : ref.rgb;
    Tracked r = wrs_retain(RULE, has_history, hd, d, c, truth, rnd, outcome, margin);
    if (outcome == WRS_OUT_KEPT) r.color = h.color;  // the sample itself is stored; only the display differs
    // A gap between unevenly drifted kept samples (wrs_track_gap): the nearest kept sample within a
    // pixel is shown where the rule keeps a sharper sample (wrs_gap_shows); the candidate is stored.
    Tracked hg;
    vec2 dg;
    uvec2 qg = q;
    bool gap = !found && c.moved && on_screen && !wrs_rule_is_oracle(RULE) &&
               wrs_track_gap(ts, hg, dg, qg) &&
               !(HAS_DEPTH && wrs_depth_flush(hg.z, c.z, dz, frame.tuning.y)) && wrs_gap_shows(hg, c);
    bool kept = outcome == WRS_OUT_KEPT || gap;
    if (!wrs_rule_is_oracle(RULE) && kept) {
        Tracked hs = gap ? hg : h;
        if (show_mean || gap) h_shown = wrs_shown_mean(tap[0], tap[1], tap[2], tap[3], tap_w, hs.q, hs.color);
        h_shown = wrs_kept_shown(h_shown, c.lo, c.hi, wrs_mode_simulated(FOV_MODE) && uint(lv.x) == 0u);
    }
    uvec4 packed_r = wrs_pack_tracked(r, wrs_offset_dither(frame.size.z, frame.size.w));
    if (!IN_PLACE || any(notEqual(packed_r, res_prev[idx]))) res_cur[idx] = packed_r;
    vec3 shown = kept ? h_shown : r.color;
    // Landed display (wrs_landed_shown): under motion, one reconstruction of the landed samples kept.
    if (FOV_MODE == WRS_FOV_SUBMITTED && ep.motion_rect.z != 0u && !wrs_rule_is_oracle(RULE) && c.moved && on_screen)
        shown = wrs_landed_shown(tap[0], tap[1], tap[2], tap[3], tap_w, kept, gap ? hg : h, r, ep.tile.w, c, shown);
    if (DISPLAY)
        imageStore(outImage, ivec3(ivec2(p), int(eye)), vec4(wrs_output_value(display(eye, p, shown, mv, filters, m1, m2)), 1.0));
    else
        store_output(eye, p, shown);
    if (TRACK_BIRTH) {
        vec4 b = vec4(ref.rgb, 0.0);
        vec4 hb = birth_prev[pixel_index(eye, q)];
        if (outcome == WRS_OUT_KEPT) b = hb;
        if (gap) b = birth_prev[pixel_index(eye, qg)];  // what is shown
        // A clipped merge (WRS_OUT_OUTSIDE) counts as taken now: its colour lies within the box of the
        // candidate's own taps, the bound a fresh candidate has.
        if (outcome == WRS_OUT_MERGED) b = hb + (b - hb) * wrs_merge_weight(h.w_sum, c.q * c.weight);
        birth_cur[idx] = b;
    }
    return r.q;
}

void main() {
    uint eye;
    uvec2 p;
    invocation_pixel(TILE, eye, p);
    bool inside = all(lessThan(p, frame.size.xy));
    if (!SPARSE) {
        if (inside) retain_pixel(eye, p);
        return;
    }
    if (gl_LocalInvocationIndex == 0u) group_held = 0u;
    barrier();
    float q = inside ? retain_pixel(eye, p) : 0.0;
    // Stored qualities are finite and >= 0 (an invalid candidate stores 0), so their bits order as they do.
    if (q > 0.0) atomicMax(group_held, floatBitsToUint(q));
    barrier();
    if (gl_LocalInvocationIndex == 0u) tile_held[frame.held.y + tile_index(eye, p / WRS_TILE)] = group_held;
}
