// Pass 1: read each eye's submitted colour (and depth), decode to linear, sanitize, and write
// pyramid level 0 (validity in alpha) and linear view depth.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const bool HAS_DEPTH = false;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 p = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(p, frame.size.xy))) return;
    EyeParams ep = frame.eye[eye];

    vec3 c = texelFetch(colorIn[eye], ivec2(p + ep.color_rect.xy), 0).rgb;
    if (ep.color_rect.z != 0u) c = wrs_srgb_to_linear3(c);
    bool valid;
    c = wrs_sanitize_color(c, valid);
    pyramid[pyramid_index(eye, 0u, p)] = vec4(c, valid ? 1.0 : 0.0);

    if (HAS_DEPTH) {
        float d = texelFetch(depthIn[eye], ivec2(p + ep.depth_rect.xy), 0).r;
        zlin[pixel_index(eye, p)] = wrs_linear_depth(d, ep.depth_range.x, ep.depth_range.y, ep.depth_rect.z != 0u);
    }
}
