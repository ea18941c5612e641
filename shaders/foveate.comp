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

// `level0`: the pixel's own decoded colour (load_color), read once per pixel.
vec4 sample_level(uint eye, uint level, uvec2 p, vec4 level0) {
    if (level == 0u) return level0;
    uvec2 sl = level_size(level);
    uvec2 i0, i1;
    vec2 f = wrs_bilinear_setup(p, frame.level_scale[level].xy, sl, i0, i1);
    return wrs_bilinear(pyr_read(eye, level, i0), pyr_read(eye, level, uvec2(i1.x, i0.y)),
                        pyr_read(eye, level, uvec2(i0.x, i1.y)), pyr_read(eye, level, i1), f);
}

void main() {
    uint eye;
    uvec2 p;
    invocation_pixel(TILE, eye, p);
    if (any(greaterThanEqual(p, frame.size.xy))) return;
    EyeParams ep = frame.eye[eye];

    float e;
    float r_f = ep.gaze.w;
    vec3 lv = pixel_levels(TILE, FOV_MODE, eye, p, e);
    vec4 level0 = load_color(eye, p);
    vec4 c = sample_level(eye, uint(lv.x), p, level0);
    if (lv.z > 0.0) c = wrs_blend(c, sample_level(eye, uint(lv.y), p, level0), lv.z);
    bool valid = level0.a > 0.5;
    float w = valid ? wrs_sample_weight(e, r_f) : 0.0;

    if (WRITE_OUTPUT) {
        store_output(eye, p, c.rgb);
        // A skipped tile shows its candidate, taken now (the stale-pixel evaluation's birth colour).
        if (TILE == 1u + WRS_TILE_SKIP && TRACK_BIRTH) birth_cur[pixel_index(eye, p)] = vec4(level0.rgb, 0.0);
    } else {
        candidate[pixel_index(eye, p)] = vec4(c.rgb, w);
    }
}
