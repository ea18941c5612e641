// Tile classification (docs/speed.md "Tiles"): one invocation per 8x8-pixel tile and eye puts the
// tile on the list of its class (wrs_tile_class) and counts it into the class's indirect dispatch.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const uint FOV_MODE = 1u;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 t = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(t, tile_count()))) return;
    EyeParams ep = frame.eye[eye];
    uint cls = wrs_tile_class(FOV_MODE, t, frame.size.xy, ep.fov_tan, ep.gaze.xyz, ep.gaze.w, frame.tuning.x);
    uint slot = atomicAdd(tile_args[cls].x, 1u);
    tile_list[cls * tile_capacity() + slot] = (eye << 30u) | (t.y << 15u) | t.x;
}
