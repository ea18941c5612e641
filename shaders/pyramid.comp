// Pass 2 (foveation modes mip and gauss): build pyramid level `level` from level - 1.
// FILTER 1: 2x2 box (mip chain); FILTER 2: separable [1 3 3 1]/8 (Gaussian pyramid). Level 4
// carries its L* in alpha (wrs_pyramid_texel).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const uint FILTER = 1u;
layout(push_constant) uniform Push { LevelPush push; };
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

vec4 tap(uint eye, uint level, uvec2 d, ivec2 o, uvec2 src_size) {
    return pyramid[pyramid_index(eye, level, wrs_down_tap(d, o, src_size))];
}

void main() {
    uint eye = gl_WorkGroupID.z;
    uint level = push.level;
    uvec2 d = gl_GlobalInvocationID.xy;
    uvec2 dst_size = wrs_level_size(frame.size.xy, level);
    if (any(greaterThanEqual(d, dst_size))) return;
    uvec2 src_size = wrs_level_size(frame.size.xy, level - 1u);
    uint src = level - 1u;
    vec4 r;
    if (FILTER == 1u) {
        r = wrs_down_box(tap(eye, src, d, ivec2(0, 0), src_size), tap(eye, src, d, ivec2(1, 0), src_size),
                         tap(eye, src, d, ivec2(0, 1), src_size), tap(eye, src, d, ivec2(1, 1), src_size));
    } else {
        vec4 rows[4];
        for (int j = 0; j < 4; ++j) {
            rows[j] = wrs_binomial_row(tap(eye, src, d, ivec2(-1, j - 1), src_size),
                                       tap(eye, src, d, ivec2(0, j - 1), src_size),
                                       tap(eye, src, d, ivec2(1, j - 1), src_size),
                                       tap(eye, src, d, ivec2(2, j - 1), src_size));
        }
        r = wrs_binomial_row(rows[0], rows[1], rows[2], rows[3]);
    }
    pyramid[pyramid_index(eye, level, d)] = wrs_pyramid_texel(r, level);
}
