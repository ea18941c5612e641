// The frame's passes, described once (docs/speed.md "The passes"): every dispatch a frame records, in
// order, with its shader, specialisation constants, shape, the barrier after it and the bytes it moves.
// Compositor::recordPasses records this list, traffic() sums its bytes and the cost model
// (eval::pipelineVariants) compiles and weighs its pipelines, so a pass added or changed here shows in
// all three with no second edit.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "compositor/compositor.h"

namespace wrsfov {

/// The compositor's per-frame compute shaders (shaders/*.comp).
enum class ShaderId : uint8_t { Classify, Pyramid, Foveate, Wrs, Taa, Retain, Compose };
std::string_view toString(ShaderId s);

/// The passes (a pass may take several dispatches: one per tile class, or per pyramid level).
enum class PassId : uint8_t {
    Compose,     ///< quad views or a rate map into the output's view (compose.comp; its own layout)
    Reach,       ///< the classification's first phase: each superblock's held quality (sparse, motion)
    Classify,    ///< 8x8 tiles onto the lists of their class
    Pyramid,     ///< levels 1..4 (or the fingerprint level)
    Steady,      ///< the steady floor: level 4 filtered over time
    SteadyCopy,  ///< ... and copied back into level 4
    Foveate,     ///< foveation (the output of `fov`, the candidate of fov+taa and wrs-paper)
    Retain,      ///< foveation fused with quality-aware retention (`wrs`, the oracles)
    Skip,        ///< sparse retention's skipped tiles through the foveating pass
    WrsPaper,    ///< the published WRS step
    Taa,         ///< fov+taa and taau
};
/// traffic()'s and the cost model's name of a pass: "compose", "reach", "classify", "pyramid", "steady",
/// "steady-copy", "foveate", "retain", "skip", "wrs-paper", "taa".
std::string_view toString(PassId p);

/// How a dispatch's workgroups cover the frame (both eyes: z = eye, or the eye in each tile's entry).
enum class DispatchShape : uint8_t {
    Pixels,       ///< WRS_GROUP_X x WRS_GROUP_Y pixels a group over the output
    TileList,     ///< indirect: one group per tile of list `tileClass` (gpu::WRS_TILE_*)
    Tiles,        ///< one invocation per 8x8 tile, WRS_GROUP_X x WRS_GROUP_Y tiles a group
    Superblocks,  ///< one group per superblock (WRS_SUPERBLOCK^2 tiles), one invocation per tile
    MipTiles,     ///< WRS_MIP_TILE^2 pixels a group (every level of the mip pyramid at once)
    Level,        ///< WRS_GROUP_X x WRS_GROUP_Y texels a group over pyramid level `level`
    GaussLevels,  ///< one Level dispatch per level 1..WRS_LEVELS-1, barriers between (`gauss`)
    /// The compose pass on quad views: the groups of each eye's inset rectangle (insetGroups), and the
    /// groups outside it (up to four rectangles an eye); one dispatch per rectangle, `cover` of the frame.
    InsetGroups,
    OutsideInset,
};

/// What a dispatch is followed by.
enum class Barrier : uint8_t {
    None,     ///< nothing: the next dispatch may run beside it (a GPU overlaps them)
    Compute,  ///< compute writes visible to later compute reads and writes
    Lists,    ///< the same, and the tile lists' dispatch arguments to indirect dispatches
};

/// One dispatch of a frame.
struct PassDispatch {
    PassId pass = PassId::Foveate;
    ShaderId shader = ShaderId::Foveate;
    /// Specialisation constants (SpecConstants): the pass's own and INPUT_ENCODING; the compositor (and
    /// the cost model) set 7 and 8 (HARDWARE_HALF, TRACK_BIRTH: bindings.glsl) of every pass but compose.
    SpecConstants constants{};
    DispatchShape shape = DispatchShape::Pixels;
    int tileClass = -1;  ///< TileList: the list
    uint32_t level = 0;  ///< Level: the pyramid level; Pyramid (mip): its push constant
    Barrier after = Barrier::None;
    /// Bytes read and written per output pixel of one view that the dispatch covers (a tile list's: its
    /// own pixels'), each texel of each binding counted once (caches that hold a neighbourhood).
    double read = 0, write = 0;
    /// The share of the view's pixels the pass covers with all its dispatches: 1, or for sparse
    /// retention the share of tiles that retained (retain) and that did not (skip). traffic() weighs
    /// the pass's bytes by it.
    double cover = 1.0;
};

/// The dispatches of a frame with configuration `c` (foveation Submitted for a frame submitted
/// foveated), pass plan `plan` (planPasses, with what Compositor::planFrame decided at run time) and
/// views like `in`; `composeLanded` is the compose pass's LANDED constant (composeLandedMode of the
/// frame's parameters; composeLanded(c) for a model).
std::vector<PassDispatch> framePasses(const CompositorConfig& c, const PassPlan& plan, const TrafficInputs& in,
                                      uint32_t composeLanded);
/// The same for a configuration alone (the plan planPasses gives, composeLanded(c)): what traffic()
/// and the cost model see.
std::vector<PassDispatch> framePasses(const CompositorConfig& c, const TrafficInputs& in);

/// The workgroups of one dispatch of `shape` (Level: of pyramid level `level`) over output images of
/// w x h per eye, `eyes` eyes (z). TileList, GaussLevels, InsetGroups and OutsideInset have none of their
/// own: (0, 0, 0).
glm::uvec3 dispatchSize(DispatchShape shape, uint32_t level, uint32_t w, uint32_t h, uint32_t eyes);
/// All the workgroups of a dispatch that is not a tile list (GaussLevels: its levels together; InsetGroups
/// and OutsideInset: `cover` of the frame's 8x8 groups).
uint64_t dispatchGroups(const PassDispatch& d, uint32_t w, uint32_t h, uint32_t eyes);

/// Timestamp interval a pass is recorded in (compositor_internal.h kFrameStamps: 1 compose and
/// classification, 2 pyramid, 3 foveation, 4 the temporal passes).
uint32_t passStage(PassId p);

}  // namespace wrsfov
