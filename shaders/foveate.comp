// Pass 2: per pixel eccentricity, foveated colour (blend of pyramid levels) and sample weight p̂.
// Method `fov` (WRITE_OUTPUT) stores the result as the output; `wrs` hands it to the wrs pass.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const uint FOV_MODE = 1u;
layout(constant_id = 1) const bool WRITE_OUTPUT = false;
// 0: every pixel; 1 + class: the tiles of one class (WRITE_OUTPUT only: no weight, no eccentricity).
// The skip list (1 + WRS_TILE_SKIP) is the far tiles where sparse retention runs this pass alone.
layout(constant_id = 5) const uint TILE = 0u;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

void main() {
    uint eye;
    uvec2 p;
    invocation_pixel(TILE, eye, p);
    if (any(greaterThanEqual(p, frame.size.xy))) return;
    EyeParams ep = frame.eye[eye];

    float e;
    vec3 lv = pixel_levels(TILE, FOV_MODE, eye, p, e);
    vec4 level0 = load_color(eye, p);
    WrsCandidate c = wrs_candidate_at(eye_pyramid(eye), FOV_MODE, p, level0, lv, e, ep.gaze.w, 0.0, false);

    if (WRITE_OUTPUT) {
        store_output(eye, p, c.rule.color);
        // A skipped tile shows its candidate, taken now (the stale-pixel evaluation's birth colour).
        if (TILE == 1u + WRS_TILE_SKIP && TRACK_BIRTH) birth_cur[pixel_index(eye, p)] = vec4(level0.rgb, 0.0);
    } else {
        candidate[pixel_index(eye, p)] = vec4(c.rule.color, c.w);
    }
}
