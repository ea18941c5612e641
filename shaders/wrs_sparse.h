// Sparse retention: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_SPARSE_H
#define WRSFOV_WRS_SPARSE_H

#include "glsl_cpp.h"
#include "config.h"
#include "wrs_foveation.h"
#include "wrs_reservoir.h"
#include "wrs_retention.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Sparse retention (docs/retention.md "Sparse retention")
// ---------------------------------------------------------------------------------------------
// Only a pixel whose tracked history is sharper than its candidate can keep anything. Each tile's
// retain workgroup records the best quality it stored, its held quality (float bits, 0: the tile
// stored nothing); the next frame's classification puts a far tile on the skip list when none of
// the tiles its tracked lookups can read held anything sharper than the floor. A skipped tile runs
// the foveating pass alone: no reservoir read or write, no depth fetch. With the floor rule of
// wrs_retain, the output and every stored sample outside skipped tiles are what running retention
// everywhere gives, bit for bit.

// The lowest quality a mode's candidates have: the far periphery's 16x16 rate (level 4) for `mip`
// and `gauss`. `none` has no floor (its weights fall with eccentricity without end): 0.
WRS_FN float wrs_floor_quality(uint mode) {
    if (!wrs_mode_simulated(mode)) return 0.0f;  // submitted foveation: the frame's (makeFrameParams)
    return wrs_level_quality(vec3(float(WRS_LEVELS - 1), float(WRS_LEVELS - 1), 0.0f));
}
// The floor of a rule: the plain oracle chooses among equally sharp samples too, so it has none.
WRS_FN float wrs_rule_floor(uint rule, uint mode) { return rule == WRS_RULE_ORACLE ? 0.0f : wrs_floor_quality(mode); }

// What a tracked lookup reads from a tile that stored nothing: a floor-quality sample at the pixel's
// centre, which is what retention would have stored there (every pixel of a skipped tile takes its
// floor-quality candidate fresh, at offset 0). Only a sample's quality and offset steer the lookup,
// and a floor-quality history is never kept, merged or shown, so its colour, fingerprint and depth
// never matter.
WRS_FN uvec4 wrs_floor_sample(float q_floor) {
    uint h = wrs_store_f16(q_floor);
    return uvec4(0u, h << 16u, h, 0u);
}

// The tiles a tile's tracked lookups can read. A pixel that did not move reads only itself; the 2x2
// block of one that moved sits at floor(p + mv) (wrs_track_start), so along each axis the tile's
// pixels read within [floor(first + mv_lo) - 1, floor(last + mv_hi) + 2], first and last being the
// tile's outer pixels and [mv_lo, mv_hi] the range of its pixels' finite motion within reach (the
// others read nothing), 0 included; the extra pixel each side absorbs the rounding of
// p + 0.5 + mv - 0.5. Returns false when that range is wholly off-screen; else s0 and s1 are the
// first and last source tile (inclusive).
WRS_FN bool wrs_tile_sources(uvec2 t, uvec2 size, vec2 mv_lo, vec2 mv_hi, WRS_OUT(uvec2) s0, WRS_OUT(uvec2) s1) {
    s0 = t;
    s1 = t;
    if (mv_lo.x == 0.0f && mv_lo.y == 0.0f && mv_hi.x == 0.0f && mv_hi.y == 0.0f) return true;  // nothing moved
    vec2 first = vec2(t * WRS_TILE);
    vec2 last = vec2(min((t + uvec2(1u, 1u)) * WRS_TILE, size) - uvec2(1u, 1u));
    vec2 lo = floor(first + mv_lo) - vec2(1.0f, 1.0f);
    vec2 hi = floor(last + mv_hi) + vec2(2.0f, 2.0f);
    vec2 top = vec2(size) - vec2(1.0f, 1.0f);
    s0 = uvec2(clamp(lo, vec2(0.0f, 0.0f), top)) / WRS_TILE;
    s1 = uvec2(clamp(hi, vec2(0.0f, 0.0f), top)) / WRS_TILE;
    return hi.x >= 0.0f && hi.y >= 0.0f && lo.x <= top.x && lo.y <= top.y;
}
// The most source tiles a classification reads: a tile whose motion spreads wider runs retention,
// which is always correct.
const uint WRS_SOURCE_TILES_MAX = 16u;
// Superblocks: WRS_SUPERBLOCK x WRS_SUPERBLOCK tiles (64 x 64 pixels), each holding the largest held
// quality of its tiles, so that the classification can look over a tile's whole reach in a few reads.
const uint WRS_SUPERBLOCK = 8u;
// The most superblocks a classification reads before it reads the tile's motion instead.
const uint WRS_REACH_BLOCKS_MAX = 64u;
// The superblocks [b0, b1] that hold every source tile tile t can have under any motion within
// `reach` (wrs_within_reach): the tile's sources (wrs_tile_sources) for motion anywhere in
// [-reach, reach]^2. False when all of them are off-screen.
WRS_FN bool wrs_reach_blocks(uvec2 t, uvec2 size, float reach, WRS_OUT(uvec2) b0, WRS_OUT(uvec2) b1) {
    uvec2 s0, s1;
    bool any = wrs_tile_sources(t, size, vec2(-reach, -reach), vec2(reach, reach), s0, s1);
    b0 = s0 / WRS_SUPERBLOCK;
    b1 = s1 / WRS_SUPERBLOCK;
    return any;
}
// Whether a tile of class `cls`, whose source tiles held at most `held`, skips retention: a far tile
// (every candidate at the floor) that nothing sharper than the floor can reach.
WRS_FN bool wrs_tile_skips(uint cls, float held, float q_floor) {
    return cls == WRS_TILE_FAR && q_floor > 0.0f && held <= q_floor;
}
// The class of a tile of a frame submitted foveated (quad views, a rate map; FOV_MODE
// WRS_FOV_SUBMITTED), from the largest quality any of its pixels was rendered at (the compose pass's
// per-tile maximum): far where every pixel was rendered at the floor quality, so that retention there
// takes the floor rule's fresh candidate as in a far tile of a simulated mode (a rendered quality is
// never below the frame's floor: the wide views' quality, or the 4x4 rate's), any otherwise (the
// pixels' own qualities, no levels: a submitted frame has no pyramid candidates).
WRS_FN uint wrs_submitted_tile_class(float q_max, float q_floor) {
    return q_floor > 0.0f && q_max <= q_floor * (1.0f + WRS_Q_EQUAL) ? WRS_TILE_FAR : WRS_TILE_ANY;
}

WRS_END

#endif
