// Pass 3 of the FOV+TAA baseline: reproject the previous output with the motion vectors (bilinear),
// clip it to the variance box of the current foveated 3x3 neighbourhood in YCoCg, blend with
// alpha 0.1. History is linear RGB in the reservoir buffers (same 16 bytes per pixel).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const bool HAS_MOTION = false;
// Method taau (wrs_taau_step): this frame's gathered wide samples accumulated with the history by weight
// (EyeParams::motion_rect.z: the compose pass gathered them; depth_range.zw: the weight cap, the clip
// box's sigmas); the history's alpha holds its accumulated weight.
layout(constant_id = 1) const bool UPSAMPLE = false;
// Method wrs, the steady display (wrs_display_step): the neighbourhood is what the retain pass showed
// (it wrote the candidate buffer in fp16, wrs_pack_shown, frame.tuning.z being the filter's weight);
// the display's history is slot push.pad1 of the Display buffer, valid where push.pad2 says so, and
// this frame's is written to slot push.pad0.
layout(constant_id = 2) const bool DISPLAY = false;
// Method taau on quad views: the neighbourhood and the candidate are the composed colour itself
// (load_color), which no foveating pass copies into the candidate buffer first.
layout(constant_id = 3) const bool COMPOSED = false;
layout(push_constant) uniform Push { LevelPush push; };
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

vec3 history_at(uint eye, uvec2 q) { return uintBitsToFloat(res_prev[pixel_index(eye, q)].xyz); }
// The steady display's history at pixel q (wrs_pack_shown).
uvec2 display_at(uint eye, uvec2 q) { return display_history[display_index(push.pad1, eye, q)]; }
vec4 display_rgb(uint eye, uvec2 q) { return vec4(wrs_unpack_shown(display_at(eye, q)), 0.0); }
// What the retain pass showed at pixel q, in the candidate buffer (store_output).
vec3 shown_at(uint eye, uvec2 q) { return wrs_unpack_shown(candidate_shown[pixel_index(eye, q)]); }
// The candidate at pixel q: the foveating pass's, or the composed colour (COMPOSED).
vec3 candidate_at(uint eye, uvec2 q) { return COMPOSED ? load_color(eye, q).rgb : candidate[pixel_index(eye, q)].rgb; }

void display_pixel(uint eye, uvec2 p, vec3 nb[9], vec3 mv) {
    uvec2 size = frame.size.xy;
    uint idx = pixel_index(eye, p);
    uvec2 i0, i1;
    vec2 f;
    bool has = push.pad2 != 0u && wrs_taa_reproject(p, size, mv, i0, i1, f) && wrs_shown_written(display_at(eye, p));
    vec3 hist = vec3(0.0);
    if (has)
        hist = wrs_bilinear(display_rgb(eye, i0), display_rgb(eye, uvec2(i1.x, i0.y)),
                            display_rgb(eye, uvec2(i0.x, i1.y)), display_rgb(eye, i1), f).rgb;
    bool wide = display_filters(eye, idx);
    vec3 c = wrs_display_step(nb, shown_at(eye, p), hist, has, wide, frame.tuning.z);
    display_history[display_index(push.pad0, eye, p)] = wrs_pack_shown(c);
    // A pixel the display does not filter was shown by the pass before it, from the unrounded colour.
    if (wide) imageStore(outImage, ivec3(ivec2(p), int(eye)), vec4(wrs_output_value(c), 1.0));
}

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy;
    if (any(greaterThanEqual(p, size))) return;
    EyeParams ep = frame.eye[eye];

    vec3 nb[9];
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            uvec2 q = wrs_taa_tap(p, ivec2(i - 1, j - 1), size);
            nb[j * 3 + i] = wrs_rgb_to_ycocg(DISPLAY ? shown_at(eye, q) : candidate_at(eye, q));
        }
    vec3 mv = HAS_MOTION ? texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz
                         : vec3(0.0);
    uvec2 i0, i1;
    vec2 f;
    if (DISPLAY) {
        display_pixel(eye, p, nb, mv);
        return;
    }
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
        bool inset = gathered && !wrs_is_wide_quality(submitted_quality(idx), ep.tile.w);
        float acc = has ? uintBitsToFloat(res_prev[idx].w) : 0.0;
        vec4 r = wrs_taau_step(nb, g, inset, hist, acc, has, ep.depth_range.z, ep.depth_range.w);
        res_cur[idx] = uvec4(floatBitsToUint(r.xyz), floatBitsToUint(max(r.w, WRS_TAAU_PRIOR)));
        store_output(eye, p, r.xyz);
        return;
    }
    vec3 c = wrs_taa(nb, hist, has);  // fov+taa: the foveating pass's candidates
    res_cur[pixel_index(eye, p)] = uvec4(floatBitsToUint(c), 1u);
    store_output(eye, p, c);
}
