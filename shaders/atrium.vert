// Atrium scene: transforms to both the current and the previous clip space so that the fragment
// shader can write motion vectors (previous pixel - current pixel) and the depth change.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "atrium.glsl"

layout(location = 0) in vec3 in_pos;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in uint in_material;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec2 v_uv;
layout(location = 3) flat out uint v_material;
layout(location = 4) out vec4 v_prev_clip;
layout(location = 5) out float v_zcur;
layout(location = 6) out float v_zprev;
layout(location = 7) out vec4 v_cur_clip;

void main() {
    vec4 world = draw.model * vec4(in_pos, 1.0);
    vec4 prev_world = draw.prev_model * vec4(in_pos, 1.0);
    v_world = world.xyz;
    v_normal = normalize(mat3(draw.model) * in_normal);
    v_uv = in_uv;
    v_material = in_material;
    v_prev_clip = cam.prev_view_proj * prev_world;
    v_zcur = -(cam.view * world).z;
    v_zprev = -(cam.prev_view * prev_world).z;
    gl_Position = cam.view_proj * world;
    v_cur_clip = gl_Position;
}
