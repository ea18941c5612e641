// Pass 3: temporal weighted reservoir sampling per pixel (paper §4, docs/conventions.md "Reservoirs"): reproject the
// previous reservoir by the motion vector, flush on a depth jump, bias (eq. 7), combine (Alg. 2),
// store the reservoir and output its sample.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const bool HAS_MOTION = false;
layout(constant_id = 1) const bool HAS_DEPTH = false;
layout(constant_id = 2) const uint CHANGE_METRIC = 1u;
layout(constant_id = 3) const bool BERNOULLI = true;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = frame.size.xy;
    if (any(greaterThanEqual(p, size))) return;
    EyeParams ep = frame.eye[eye];
    uint idx = pixel_index(eye, p);

    vec4 cand = candidate[idx];
    float z_cur = HAS_DEPTH ? load_depth(eye, p) : 0.0;

    uvec2 q = p;
    float dz = 0.0;
    bool on_screen = true;
    if (HAS_MOTION) {
        vec3 mv = texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xyz * ep.motion_scale.xyz;
        on_screen = wrs_reproject(p, size, mv, q, dz);
    }
    Reservoir hist = wrs_unpack(res_prev[pixel_index(eye, q)]);
    bool has_history = on_screen && wrs_reservoir_valid(hist);
    if (HAS_DEPTH && has_history && wrs_depth_flush(hist.z, z_cur, dz, frame.tuning.y)) has_history = false;

    float rnd = wrs_rand(p.x, p.y, eye, frame.size.z, frame.size.w);
    bool keep;
    Reservoir r = wrs_combine(has_history, hist, cand.rgb, cand.a, z_cur, rnd, CHANGE_METRIC, BERNOULLI, keep);
    res_cur[idx] = wrs_pack(r);
    store_output(eye, p, r.color);
    if (TRACK_BIRTH)
        birth_cur[idx] = keep ? birth_prev[pixel_index(eye, q)] : vec4(load_color(eye, p).rgb, 0.0);
}
