// Tile classification (docs/speed.md "Tiles"): one invocation per 8x8-pixel tile and eye puts the
// tile on the list of its class (wrs_tile_class) and counts it into the class's indirect dispatch.
// With sparse retention (docs/retention.md "Sparse retention") a far tile that none of its source
// tiles can bring a sample sharper than the floor goes on the skip list instead, and its held
// quality for this frame is 0 (it stores nothing); the retain pass writes every other tile's.
// Phase 1 (sparse retention with motion, dispatched first): one group per superblock and eye
// writes the largest held quality of its tiles, so that phase 0 reads a tile's motion only where a
// sample sharper than the floor is within the motion reach (docs/retention.md "Motion reach").
//
// Phase 1's max over a superblock's 8x8 tiles is a group of 64 invocations reading one word each
// (WRS_SUPERBLOCK = WRS_GROUP_X = WRS_GROUP_Y). A tile's motion range over its 8x8 pixels reads in
// unrolled rows with indices clamped to the last valid one (max and min are unchanged by a repeated
// element), so that the loads of a row are independent and issue together. Read one at a time these
// reductions made chains of 64 dependent memory latencies; on an NVIDIA H200 reach + classify took a
// fixed ~85 us per frame at 2x512^2 and 2x1024^2 alike (docs/speed.md "On a GPU"). One invocation
// per superblock reading its 64 words unrolled still cost a wave's whole latency in a dispatch of a
// few dozen groups (docs/speed.md "Cost model"). The reach and source loops read a few words (a few
// superblocks, at most 16 tiles) and stay plain loops.
#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
#include "bindings.glsl"

layout(constant_id = 0) const uint FOV_MODE = 1u;
layout(constant_id = 1) const bool SPARSE = false;
layout(constant_id = 2) const bool HAS_MOTION = false;
layout(constant_id = 3) const uint PHASE = 0u;
layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;
shared uint superblock_held;  // phase 1: the group's superblock's largest held quality, as bits

// The largest held quality among the tiles tile t's tracked lookups can read (wrs_tile_sources),
// or 1 (anything) where the motion spreads over more than WRS_SOURCE_TILES_MAX tiles. Where every
// superblock within the reach holds at most the floor, their largest: the motion is not read.
float source_held(uint eye, uvec2 t) {
    if (!HAS_MOTION) return held_prev(eye, t);  // every pixel reads only itself
    EyeParams ep = frame.eye[eye];
    uvec2 size = frame.size.xy;
    float reach = ep.motion_scale.w;
    uvec2 b0, b1;
    if (!wrs_reach_blocks(t, size, reach, b0, b1)) return 0.0;
    if ((b1.x - b0.x + 1u) * (b1.y - b0.y + 1u) <= WRS_REACH_BLOCKS_MAX) {
        float near = 0.0;
        for (uint y = b0.y; y <= b1.y; ++y)
            for (uint x = b0.x; x <= b1.x; ++x) near = max(near, uintBitsToFloat(tile_held[superblock_word(eye, uvec2(x, y))]));
        if (near <= frame.tuning.w) return near;
    }
    atomicAdd(tile_args[WRS_TILE_SKIP].w, 1u);  // tiles whose motion was read (FrameStats::motionTiles)
    vec2 lo = vec2(0.0), hi = vec2(0.0);
    uvec2 first = t * WRS_TILE, last = min(first + uvec2(WRS_TILE), size) - uvec2(1u);
    [[dont_unroll]] for (uint j = 0u; j < WRS_TILE; ++j)
        [[unroll]] for (uint i = 0u; i < WRS_TILE; ++i) {
            uvec2 p = min(first + uvec2(i, j), last);
            vec2 mv = texelFetch(motionIn[eye], ivec2(p + ep.motion_rect.xy), 0).xy * ep.motion_scale.xy;
            // Non-finite motion is zero motion (in the range already); beyond the reach, no history.
            if (!wrs_finite(mv.x) || !wrs_finite(mv.y) || !wrs_within_reach(mv, reach)) continue;
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
    if (PHASE == 1u) {
        // One group per superblock, one invocation per tile: each reads one word, and the group's
        // maximum gathers in shared memory (held qualities are finite and >= 0, so their bits order
        // as the values do; a tile past the edge adds 0, which changes no maximum).
        if (gl_LocalInvocationIndex == 0u) superblock_held = 0u;
        barrier();
        uvec2 b = gl_WorkGroupID.xy, t = b * WRS_SUPERBLOCK + gl_LocalInvocationID.xy;
        if (all(lessThan(t, tile_count()))) atomicMax(superblock_held, floatBitsToUint(held_prev(eye, t)));
        barrier();
        if (gl_LocalInvocationIndex == 0u) tile_held[superblock_word(eye, b)] = superblock_held;
        return;
    }
    uvec2 t = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(t, tile_count()))) return;
    EyeParams ep = frame.eye[eye];
    uint cls = FOV_MODE == WRS_FOV_SUBMITTED
                   ? wrs_submitted_tile_class(submitted_tile_quality(eye, t), frame.tuning.w)
                   : wrs_tile_class(FOV_MODE, t, frame.size.xy, ep.fov_tan, ep.tile, ep.gaze.xyz, ep.gaze.w, frame.tuning.x);
    if (SPARSE && cls == WRS_TILE_FAR && wrs_tile_skips(cls, source_held(eye, t), frame.tuning.w)) {
        cls = WRS_TILE_SKIP;
        tile_held[frame.held.y + tile_index(eye, t)] = 0u;
    }
    uint slot = atomicAdd(tile_args[cls].x, 1u);
    tile_list[cls * tile_capacity() + slot] = (eye << 30u) | (t.y << 15u) | t.x;
}
