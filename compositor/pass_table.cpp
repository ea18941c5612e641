// The frame's passes, described once (pass_table.h): their order, constants, shapes, barriers and bytes.
#include "compositor/pass_table.h"

#include <algorithm>

#include "shaders/config.h"
#include "shaders/wrs_common.h"

namespace wrsfov {

std::string_view toString(ShaderId s) {
    switch (s) {
        case ShaderId::Classify:
            return "classify";
        case ShaderId::Pyramid:
            return "pyramid";
        case ShaderId::Foveate:
            return "foveate";
        case ShaderId::Wrs:
            return "wrs";
        case ShaderId::Taa:
            return "taa";
        case ShaderId::Retain:
            return "retain";
        case ShaderId::Compose:
            return "compose";
    }
    return "?";
}

std::string_view toString(PassId p) {
    switch (p) {
        case PassId::Compose:
            return "compose";
        case PassId::Reach:
            return "reach";
        case PassId::Classify:
            return "classify";
        case PassId::Pyramid:
            return "pyramid";
        case PassId::Steady:
            return "steady";
        case PassId::SteadyCopy:
            return "steady-copy";
        case PassId::Foveate:
            return "foveate";
        case PassId::Retain:
            return "retain";
        case PassId::Skip:
            return "skip";
        case PassId::WrsPaper:
            return "wrs-paper";
        case PassId::Taa:
            return "taa";
    }
    return "?";
}

uint32_t passStage(PassId p) {
    switch (p) {
        case PassId::Compose:
        case PassId::Reach:
        case PassId::Classify:
            return 1;
        case PassId::Pyramid:
        case PassId::Steady:
        case PassId::SteadyCopy:
            return 2;
        case PassId::Foveate:
            return 3;
        default:
            return 4;
    }
}

glm::uvec3 dispatchSize(DispatchShape shape, uint32_t level, uint32_t w, uint32_t h, uint32_t eyes) {
    auto groups = [](uint32_t n, uint32_t size) { return (n + size - 1) / size; };
    const uint32_t tilesX = groups(w, gpu::WRS_TILE), tilesY = groups(h, gpu::WRS_TILE);
    switch (shape) {
        case DispatchShape::Pixels:
            return {groups(w, WRS_GROUP_X), groups(h, WRS_GROUP_Y), eyes};
        case DispatchShape::Tiles:
            return {groups(tilesX, WRS_GROUP_X), groups(tilesY, WRS_GROUP_Y), eyes};
        case DispatchShape::Superblocks:
            static_assert(gpu::WRS_SUPERBLOCK == WRS_GROUP_X && gpu::WRS_SUPERBLOCK == WRS_GROUP_Y);
            return {groups(tilesX, gpu::WRS_SUPERBLOCK), groups(tilesY, gpu::WRS_SUPERBLOCK), eyes};
        case DispatchShape::MipTiles:
            return {groups(w, WRS_MIP_TILE), groups(h, WRS_MIP_TILE), eyes};
        case DispatchShape::Level: {
            const glm::uvec2 ls = gpu::wrs_level_size(glm::uvec2(w, h), level);
            return {groups(ls.x, WRS_GROUP_X), groups(ls.y, WRS_GROUP_Y), eyes};
        }
        case DispatchShape::TileList:
        case DispatchShape::GaussLevels:
        case DispatchShape::InsetGroups:
        case DispatchShape::OutsideInset:
            break;
    }
    return {0, 0, 0};
}

uint64_t dispatchGroups(const PassDispatch& d, uint32_t w, uint32_t h, uint32_t eyes) {
    auto count = [](glm::uvec3 g) { return uint64_t(g.x) * g.y * g.z; };
    if (d.shape == DispatchShape::InsetGroups || d.shape == DispatchShape::OutsideInset)
        return uint64_t(std::llround(d.cover * double(count(dispatchSize(DispatchShape::Pixels, 0, w, h, eyes)))));
    if (d.shape != DispatchShape::GaussLevels) return count(dispatchSize(d.shape, d.level, w, h, eyes));
    uint64_t n = 0;
    for (uint32_t level = 1; level < WRS_LEVELS; ++level)
        n += count(dispatchSize(DispatchShape::Level, level, w, h, eyes));
    return n;
}

std::vector<PassDispatch> framePasses(const CompositorConfig& c, const TrafficInputs& in) {
    return framePasses(c, planPasses(c, in.motionBytes > 0, c.trackBirth, in.composeWrite > 4), in, composeLanded(c));
}

std::vector<PassDispatch> framePasses(const CompositorConfig& c, const PassPlan& plan, const TrafficInputs& in,
                                      uint32_t landedMode) {
    const bool hasDepth = in.depthBytes > 0, hasMotion = in.motionBytes > 0;
    const uint32_t fov = uint32_t(c.foveation);
    const glm::uvec2 size0(std::max(in.width, 1u), std::max(in.height, 1u));
    const double px = double(size0.x) * size0.y;
    constexpr double kTexel = 8;                          // a pyramid texel: fp16 RGBA
    constexpr double kTileWord = 4.0 / (gpu::WRS_TILE * gpu::WRS_TILE);  // a word per 8x8 tile, per pixel
    double level[WRS_LEVELS] = {};  // pyramid texels of each level per level-0 pixel
    for (uint32_t k = 1; k < WRS_LEVELS; ++k) {
        const glm::uvec2 s = gpu::wrs_level_size(size0, k);
        level[k] = double(s.x) * s.y / px;
    }
    // Stored and sampled: the levels from wrs_first_stored_level up (mip: 3 and 4; none: 4).
    const uint32_t first = gpu::wrs_first_stored_level(fov);
    double levels = 0;
    for (uint32_t k = first; k < WRS_LEVELS; ++k) levels += level[k];
    const bool usesDepth = plan.wrsPaper || plan.retain || (plan.taa && c.method == Method::Taau);
    const double depth = usesDepth ? in.depthBytes : 0, motion = plan.temporal ? in.motionBytes : 0;
    const double birth = c.trackBirth && (plan.wrsPaper || plan.retain) ? 16 : 0;
    const double levelsRead = plan.pyramid ? levels * kTexel : 0;  // every stored level is sampled somewhere
    const double share = plan.sparse ? std::clamp(in.retainShare, 0.0, 1.0) : 1.0;
    const bool composed = in.composeWrite > 0;
    const bool quad = in.composeWrite > 4;  // a rate map's compose pass writes its qualities alone
    const uint32_t landed = quad ? landedMode : 0u;
    // taau: the compose pass's gathered wide samples, two words a pixel, written by it and read by the taa
    // pass. wrs: its retain pass reads each pixel's landed wide sample from the wide view itself (a texel
    // of it per landed sample, cached: the wide colour's bytes).
    const double landedWords = landed >= 2 ? 8.0 : 0.0;
    const double wideColor = landed == 1 ? in.wideColorRead : 0.0;
    // A rate map's rendered quality, a word a pixel (quad views carry it in the composed colour's alpha).
    const double quality = composed && !quad && plan.retain ? 4 : 0;
    const double history = 16, output = 4;
    // The steady display, in the retain pass (constant 10): its history in (bilinear, once) and out.
    const bool display = plan.display && quad;
    const double shown = 8;  // what the display reads of a shown colour, and its own history (wrs_pack_shown)

    std::vector<PassDispatch> d;
    // Constant 9 of the passes that decode the submitted colour (load_color): its encoding.
    auto readsColor = [](ShaderId s) {
        return s == ShaderId::Pyramid || s == ShaderId::Foveate || s == ShaderId::Retain || s == ShaderId::Wrs ||
               s == ShaderId::Taa;
    };
    auto add = [&](PassId pass, ShaderId shader, SpecConstants k, DispatchShape shape, Barrier after,
                   double read, double write) -> PassDispatch& {
        PassDispatch x;
        x.pass = pass;
        x.shader = shader;
        if (readsColor(shader)) k[9] = in.colorEncoding;
        x.constants = k;
        x.shape = shape;
        x.after = after;
        x.read = read;
        x.write = write;
        d.push_back(x);
        return d.back();
    };
    // A per-pixel pass over every pixel, or one indirect dispatch per tile class (constant 5 = 1 + class).
    // `aliased`: the pass reads a buffer it also writes (the in-place reservoirs), so a barrier separates its
    // dispatches (each touches its own pixels only, but synchronization validation tracks whole ranges).
    // `last` is the barrier after its last dispatch.
    auto addPixels = [&](PassId pass, ShaderId shader, SpecConstants k, bool aliased, Barrier last,
                         double read, double write, double cover) {
        if (!plan.tiled) {
            add(pass, shader, k, DispatchShape::Pixels, last, read, write).cover = cover;
            return;
        }
        for (uint32_t cls = 0; cls < gpu::WRS_TILE_CLASSES; ++cls) {
            k[5] = 1 + cls;
            const bool final = cls + 1 == gpu::WRS_TILE_CLASSES;
            PassDispatch& x = add(pass, shader, k, DispatchShape::TileList,
                                  final ? last : aliased ? Barrier::Compute : Barrier::None, read, write);
            x.tileClass = int(cls);
            x.cover = cover;
        }
    };

    // Frames submitted foveated: the compose pass first (ComposePass::record), quad views (kind 1, with the
    // views' depth and motion and the method's landed or gathered wide samples) or a rate map (kind 2). It
    // writes each tile's largest quality after the pixels'. Quad views: the groups where the inset may
    // show with constant 6 (INSET), the others without, side by side (their pixels are disjoint). Method
    // `fov` on quad views: the composed colour is the output (constant 7, OUTPUT), and nothing else is
    // written or read after it.
    const bool composeOutput = quad && c.method == Method::Fov;
    if (quad) {
        const double insetShare = std::clamp(in.insetShare, 0.0, 1.0);
        const double written = composeOutput ? output : in.composeWrite + (plan.tiled ? kTileWord : 0.0) + landedWords;
        for (const bool inset : {false, true}) {
            PassDispatch& x = add(PassId::Compose, ShaderId::Compose,
                                  {1u, hasDepth && !composeOutput, hasMotion && !composeOutput, landed,
                                   in.wideEncoding, in.insetEncoding, inset, composeOutput, plan.tiled},
                                  inset ? DispatchShape::InsetGroups : DispatchShape::OutsideInset,
                                  inset ? Barrier::Compute : Barrier::None, in.composeRead, written);
            x.cover = inset ? insetShare : 1.0 - insetShare;
        }
    } else if (composed) {
        add(PassId::Compose, ShaderId::Compose, {2u, 0u, 0u, 0u, in.wideEncoding, in.insetEncoding, 0u, 0u, plan.tiled},
            DispatchShape::Pixels, Barrier::Compute, in.composeRead, in.composeWrite + (plan.tiled ? kTileWord : 0.0));
    }
    // The classification: one invocation per tile, each writing its list entry; with sparse retention it
    // reads the held qualities and, where a sharper sample is within reach, the tile's motion.
    if (plan.tiled) {
        const double heldWords = plan.sparse ? kTileWord : 0.0;
        if (plan.sparse && hasMotion)  // phase 1: a superblock's largest held quality from its tiles' words
            add(PassId::Reach, ShaderId::Classify, {fov, 1u, 1u, 1u}, DispatchShape::Superblocks, Barrier::Compute,
                kTileWord, 0.0);
        // The pyramid follows with no barrier (recordClassify): a GPU overlaps the two; its last barrier
        // publishes the lists.
        add(PassId::Classify, ShaderId::Classify, {fov, plan.sparse, hasMotion, 0u}, DispatchShape::Tiles,
            plan.pyramid ? Barrier::None : Barrier::Lists,
            (plan.sparse ? in.motionBytes * std::clamp(in.motionShare, 0.0, 1.0) : 0.0) + heldWords +
                (composed ? kTileWord : 0.0),
            kTileWord);
    }
    if (plan.pyramid) {
        // mip: one dispatch, colour in, the stored levels out. gauss: level 1 from the colour, level k from k - 1.
        const bool gauss = c.foveation == FoveationMode::Gauss;
        const double below = gauss ? (level[1] + level[2] + level[3]) * kTexel : 0;
        PassDispatch& p = add(PassId::Pyramid, ShaderId::Pyramid, {gauss ? 2u : 1u, first},
                              gauss ? DispatchShape::GaussLevels : DispatchShape::MipTiles,
                              plan.tiled ? Barrier::Lists : Barrier::Compute, in.colorBytes + below, levels * kTexel);
        p.level = 1;
    }
    if (plan.steady) {
        // Per level-4 texel: its 3x3 neighbourhood (each texel read by nine, once from memory), the
        // history's 4x4 Catmull-Rom taps (once), one motion texel; the filtered texel out. Then level 4 and
        // the filtered texel in, level 4 out.
        const double motionTexel = in.motionBytes > 0 ? in.motionBytes : 0;
        for (uint32_t phase = 0; phase < 2; ++phase) {
            PassDispatch& s = add(phase == 0 ? PassId::Steady : PassId::SteadyCopy, ShaderId::Pyramid,
                                  {3u, first, hasMotion, phase}, DispatchShape::Level, Barrier::Compute,
                                  level[4] * (phase == 0 ? 2 * kTexel + motionTexel : 2 * kTexel), level[4] * kTexel);
            s.level = gpu::WRS_STEADY_LEVEL;
        }
    }
    // The output, or the candidate the temporal pass reads. Not on quad views for `fov` (the compose pass
    // wrote the output) nor for `taau` and `taau-simple` (their pass reads the composed colour).
    const bool taaReadsComposed = quad && isTaau(c.method);
    if (!plan.retain && !composeOutput && !taaReadsComposed)
        addPixels(PassId::Foveate, ShaderId::Foveate, {fov, plan.temporal ? 0u : 1u}, false, Barrier::Compute,
                  in.colorBytes + levelsRead, plan.temporal ? 16.0 : 4.0, 1.0);
    if (plan.retain) {
        // Sparse retention: the tiles that retained, then the far tiles that skip it through the foveating
        // pass alone (colour in, output out; with stale tracking the birth colour too).
        const Barrier last = plan.sparse ? (plan.inPlace ? Barrier::Compute : Barrier::None) : Barrier::Compute;
        const double displayed = display ? shown : 0.0;  // the display's history, read and written
        addPixels(PassId::Retain, ShaderId::Retain,
                  {hasMotion, hasDepth, fov, retainRule(c), plan.inPlace, 0, plan.sparse, 0, 0, 0, display,
                   landed == 1 ? in.wideEncoding : 0u},
                  plan.inPlace, last,
                  in.colorBytes + levelsRead + history + depth + motion + birth + quality + wideColor + displayed,
                  history + output + birth + displayed, share);
        if (plan.sparse) {
            PassDispatch& s = add(PassId::Skip, ShaderId::Foveate, {fov, 1u, 0, 0, 0, 1 + gpu::WRS_TILE_SKIP, 0},
                                  DispatchShape::TileList, Barrier::Compute, in.colorBytes + levelsRead,
                                  output + birth);
            s.tileClass = int(gpu::WRS_TILE_SKIP);
            s.cover = 1.0 - share;
        }
    } else if (plan.wrsPaper) {
        add(PassId::WrsPaper, ShaderId::Wrs, {hasMotion, hasDepth, uint32_t(c.change), c.bernoulli},
            DispatchShape::Pixels, Barrier::Compute, 16 + history + depth + motion + (birth ? birth + in.colorBytes : 0),
            history + output + birth);
    } else if (plan.taa) {
        // Its neighbourhood: the foveating pass's candidates (16 B), or on quad views for `taau` and
        // `taau-simple` the composed colour itself (constant 3); `taau` (constant 2) reads the depth too
        // (constant 4).
        const bool upsample = isTaau(c.method);
        const bool fsr = c.method == Method::Taau;
        add(PassId::Taa, ShaderId::Taa, {hasMotion, upsample, fsr, taaReadsComposed, fsr && hasDepth},
            DispatchShape::Pixels, Barrier::Compute,
            (taaReadsComposed ? in.colorBytes : 16.0) + history + motion + depth +
                (upsample && landed >= 2 ? landedWords : 0.0),
            history + output);
    }
    return d;
}

}  // namespace wrsfov
