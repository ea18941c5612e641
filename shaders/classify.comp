// Tile classification (docs/speed.md "Tiles"): one invocation per 8x8-pixel tile and eye puts the
// tile on the list of its class (wrs_tile_class) and counts it into the class's indirect dispatch.
// With sparse retention (docs/retention.md "Sparse retention") a far tile that none of its source
// tiles can bring a sample sharper than the floor goes on the skip list instead, and its held
// quality for this frame is 0 (it stores nothing); the retain pass writes every other tile's.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "bindings.glsl"

layout(constant_id = 0) const uint FOV_MODE = 1u;
layout(constant_id = 1) const bool SPARSE = false;
layout(constant_id = 2) const bool HAS_MOTION = false;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

// The largest held quality among the tiles tile t's tracked lookups can read (wrs_tile_sources),
// or 1 (anything) where the motion spreads over more than WRS_SOURCE_TILES_MAX tiles.
float source_held(uint eye, uvec2 t) {
    if (!HAS_MOTION) return held_prev(eye, t);  // every pixel reads only itself
    EyeParams ep = frame.eye[eye];
    uvec2 size = frame.size.xy;
    vec2 lo = vec2(0.0), hi = vec2(0.0);
    uvec2 first = t * WRS_TILE, end = min(first + uvec2(WRS_TILE), size);
    for (uint y = first.y; y < end.y; ++y)
        for (uint x = first.x; x < end.x; ++x) {
            vec2 mv = texelFetch(motionIn[eye], ivec2(uvec2(x, y) + ep.motion_rect.xy), 0).xy * ep.motion_scale.xy;
            if (!wrs_finite(mv.x) || !wrs_finite(mv.y)) continue;  // no history for that pixel
            lo = min(lo, mv);
            hi = max(hi, mv);
        }
    uvec2 s0, s1;
    if (!wrs_tile_sources(t, size, lo, hi, s0, s1)) return 0.0;
    if ((s1.x - s0.x + 1u) * (s1.y - s0.y + 1u) > WRS_SOURCE_TILES_MAX) return 1.0;
    float held = 0.0;
    for (uint y = s0.y; y <= s1.y; ++y)
        for (uint x = s0.x; x <= s1.x; ++x) held = max(held, held_prev(eye, uvec2(x, y)));
    return held;
}

void main() {
    uint eye = gl_WorkGroupID.z;
    uvec2 t = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(t, tile_count()))) return;
    EyeParams ep = frame.eye[eye];
    uint cls = wrs_tile_class(FOV_MODE, t, frame.size.xy, ep.fov_tan, ep.gaze.xyz, ep.gaze.w, frame.tuning.x);
    if (SPARSE && cls == WRS_TILE_FAR && wrs_tile_skips(cls, source_held(eye, t), frame.tuning.w)) {
        cls = WRS_TILE_SKIP;
        tile_held[frame.held.y + tile_index(eye, t)] = 0u;
    }
    uint slot = atomicAdd(tile_args[cls].x, 1u);
    tile_list[cls * tile_capacity() + slot] = (eye << 30u) | (t.y << 15u) | t.x;
}
