// Pass 3 of the FOV+TAA baseline: reproject the previous output with the motion vectors (bilinear),
// clip it to the variance box of the current foveated 3x3 neighbourhood in YCoCg, blend with
// alpha 0.1. History is linear RGB in the reservoir buffers (same 16 bytes per pixel).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const bool HAS_MOTION = false;
// Methods taau and taau-simple: this frame's gathered wide samples accumulated with the history by weight
// (EyeParams::motion_rect.z: the compose pass gathered them; depth_range.zw: the weight cap and
// taau-simple's clip box in sigmas, or taau's luma stability).
layout(constant_id = 1) const bool UPSAMPLE = false;
// Method taau (wrs_taau_step, with UPSAMPLE): FSR 2's design. The box of the wide samples around the
// pixel (EyeParams::display.x: one wide pixel's spacing), depth disocclusion (HAS_DEPTH), the velocity,
// locks and luma stability; its history packed in fp16 (wrs_taau_pack). Without it, taau-simple
// (wrs_taau_simple_step): the composed neighbourhood's box, the history's alpha its accumulated weight.
layout(constant_id = 2) const bool FSR = false;
// Method taau on quad views: the neighbourhood and the candidate are the composed colour itself
// (load_color), which no foveating pass copies into the candidate buffer first.
layout(constant_id = 3) const bool COMPOSED = false;
// Method taau: the frame has depth (the composed depth on quad views).
layout(constant_id = 4) const bool HAS_DEPTH = false;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

vec3 history_at(uint eye, uvec2 q) { return uintBitsToFloat(res_prev[pixel_index(eye, q)].xyz); }
// The candidate at pixel q: the foveating pass's, or the composed colour (COMPOSED).
vec3 candidate_at(uint eye, uvec2 q) { return COMPOSED ? load_color(eye, q).rgb : candidate[pixel_index(eye, q)].rgb; }

// Method taau at pixel p.
void taau_pixel(uint eye, uvec2 p, uvec2 size, EyeParams ep) {
    uint idx = pixel_index(eye, p);
    vec3 nb[9];
    uint steps = ep.display.x;
    for (uint k = 0u; k < 9u; ++k)
        nb[k] = wrs_rgb_to_ycocg(candidate_at(eye, wrs_wide_box_tap(p, k, steps, size)));
    vec3 mv = HAS_MOTION ? texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz
                         : vec3(0.0);
    float depth = HAS_DEPTH ? load_depth(eye, p) : 0.0;
    uvec2 i0, i1;
    vec2 f;
    bool has = wrs_taa_reproject(p, size, mv, i0, i1, f) && wrs_taau_packed_valid(res_prev[idx]);
    TaauHistory h;
    if (has) {
        TaauHistory a = wrs_taau_unpack(res_prev[pixel_index(eye, i0)]);
        TaauHistory b = wrs_taau_unpack(res_prev[pixel_index(eye, uvec2(i1.x, i0.y))]);
        TaauHistory c = wrs_taau_unpack(res_prev[pixel_index(eye, uvec2(i0.x, i1.y))]);
        TaauHistory d = wrs_taau_unpack(res_prev[pixel_index(eye, i1)]);
        has = wrs_taau_reproject(a, b, c, d, f, depth, frame.tuning.y, h);
        // The colour resampled with Lanczos-2 (wrs_history_add); the other fields stay bilinear.
        TaauGather hg = wrs_taau_gather_start();
        vec4 wx = wrs_history_weights(f.x), wy = wrs_history_weights(f.y);
        for (uint j = 0u; j < 16u; ++j)
            wrs_history_add(hg, wrs_taau_unpack(res_prev[pixel_index(eye, wrs_history_tap(i0, size, j))]).color, wx, wy, j);
        h.color = wrs_history_result(hg);
        has = has && wrs_finite3(h.color);
    }
    bool gathered = ep.motion_rect.z != 0u;
    vec4 g = gathered ? submitted_landed(idx) : vec4(candidate_at(eye, p), 1.0);
    bool inset = gathered && !wrs_is_wide_quality(submitted_quality(eye, p, idx), ep.tile.w);
    bool finite_xy = wrs_finite(mv.x) && wrs_finite(mv.y);
    float vel = finite_xy ? wrs_length(mv.xy) : 0.0;
    TaauHistory next;
    vec3 r = wrs_taau_step(nb, g, inset, h, has, depth, vel, ep.depth_range.z, ep.depth_range.w, ep.taau, next);
    res_cur[idx] = wrs_taau_pack(next);
    store_output(eye, p, r);
}

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy;
    if (any(greaterThanEqual(p, size))) return;
    EyeParams ep = frame.eye[eye];
    if (UPSAMPLE && FSR) {
        taau_pixel(eye, p, size, ep);
        return;
    }

    vec3 nb[9];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            uvec2 q = wrs_taa_tap(p, ivec2(i - 1, j - 1), size);
            nb[j * 3 + i] = wrs_rgb_to_ycocg(candidate_at(eye, q));
        }
    vec3 mv = HAS_MOTION ? texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz
                         : vec3(0.0);
    uvec2 i0, i1;
    vec2 f;
    bool has = wrs_taa_reproject(p, size, mv, i0, i1, f) && res_prev[pixel_index(eye, p)].w != 0u;
    vec3 hist = vec3(0.0);
    if (has) {
        hist = wrs_bilinear(vec4(history_at(eye, i0), 0.0), vec4(history_at(eye, uvec2(i1.x, i0.y)), 0.0),
                            vec4(history_at(eye, uvec2(i0.x, i1.y)), 0.0), vec4(history_at(eye, i1), 0.0), f).rgb;
        has = wrs_finite3(hist);
    }
    if (UPSAMPLE) {
        uint idx = pixel_index(eye, p);
        bool gathered = ep.motion_rect.z != 0u;
        vec4 g = gathered ? submitted_landed(idx) : vec4(0.0);
        // Without gathered samples (a frame not of quad views): the composed colour is the sample, weight 1.
        if (!gathered) g = vec4(candidate_at(eye, p), 1.0);
        bool inset = gathered && !wrs_is_wide_quality(submitted_quality(eye, p, idx), ep.tile.w);
        float acc = has ? uintBitsToFloat(res_prev[idx].w) : 0.0;
        vec4 r = wrs_taau_simple_step(nb, g, inset, hist, acc, has, ep.depth_range.z, ep.depth_range.w);
        res_cur[idx] = uvec4(floatBitsToUint(r.xyz), floatBitsToUint(max(r.w, WRS_TAAU_PRIOR)));
        store_output(eye, p, r.xyz);
        return;
    }
    vec3 c = wrs_taa(nb, hist, has);  // fov+taa: the foveating pass's candidates
    res_cur[pixel_index(eye, p)] = uvec4(floatBitsToUint(c), 1u);
    store_output(eye, p, c);
}
