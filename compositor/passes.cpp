// Configuration values, the pass plan of a frame and the traffic model (compositor.h).
#include "compositor/compositor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "compositor/compose.h"
#include "compositor/compositor_internal.h"
#include "compositor/input.h"
#include "compositor/swapchain_vk.h"

namespace wrsfov {

using namespace detail;

std::string_view toString(Method m) {
    switch (m) {
        case Method::Fov:
            return "fov";
        case Method::FovTaa:
            return "fov+taa";
        case Method::WrsPaper:
            return "wrs-paper";
        case Method::Wrs:
            return "wrs";
        case Method::Oracle:
            return "oracle";
        case Method::OracleQ:
            return "oracle-q";
        case Method::Taau:
            return "taau";
    }
    return "?";
}
std::string_view toString(EqualQuality e) { return e == EqualQuality::Merge ? "merge" : "reservoir"; }
std::optional<Method> parseMethod(std::string_view name) {
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::Oracle, Method::OracleQ,
                     Method::Taau})
        if (name == toString(m)) return m;
    return std::nullopt;
}
std::optional<FoveationMode> parseFoveationMode(std::string_view name) {
    for (FoveationMode m : {FoveationMode::None, FoveationMode::Mip, FoveationMode::Gauss})
        if (name == toString(m)) return m;
    return std::nullopt;
}
std::string_view toString(FoveationMode m) {
    switch (m) {
        case FoveationMode::None:
            return "none";
        case FoveationMode::Mip:
            return "mip";
        case FoveationMode::Gauss:
            return "gauss";
        case FoveationMode::Submitted:
            return "submitted";
    }
    return "?";
}
std::string_view toString(ChangeMetric m) {
    switch (m) {
        case ChangeMetric::Off:
            return "off";
        case ChangeMetric::LStar:
            return "lstar";
        case ChangeMetric::DeltaE94:
            return "de94";
    }
    return "?";
}


TrafficInputs trafficInputs(const layers::ProjectionLayer& layer) {
    const layers::ProjectionView& v = layer.views.at(0);
    TrafficInputs in;
    const glm::uvec2 out = layers::outputSize(layer);
    in.width = out.x;
    in.height = out.y;
    auto bytes = [](const layers::SubImage& s) { return uint32_t(layers::bytesPerTexel(s.swapchain->info().format)); };
    in.colorBytes = bytes(v.color);
    if (v.depth) in.depthBytes = bytes(v.depth->subImage);
    if (v.motion) in.motionBytes = bytes(v.motion->subImage);
    const double px = double(out.x) * out.y;
    if (v.inset) {
        // Every texel of both sources once (bilinear neighbourhoods cached), per output pixel; the
        // composed colour (RGBA16F), depth (R32F), motion (RGBA16F) and quality out, which the later
        // passes read in place of the submitted images.
        const layers::InsetView& n = *v.inset;
        const double wide = double(v.color.rect.width) * v.color.rect.height / px;
        const double inset = double(n.color.rect.width) * n.color.rect.height / px;
        in.composeRead = wide * (in.colorBytes + in.depthBytes + in.motionBytes) +
                         inset * (bytes(n.color) + in.depthBytes + in.motionBytes);
        in.colorBytes = 8;
        if (v.depth) in.depthBytes = 4;
        if (v.motion) in.motionBytes = 8;
        in.composeWrite = in.colorBytes + in.depthBytes + in.motionBytes + 4;
    } else if (v.rateMap) {
        in.composeRead = 1.0 / (double(v.rateMap->texelWidth) * v.rateMap->texelHeight);
        in.composeWrite = 4;
    }
    return in;
}

// The check for a driver whose passes differ with its own conversion though the probe passed
// (docs/speed.md, "GPU against the CPU reference on an NVIDIA H200").
bool handHalfForced() {
    const char* v = std::getenv("WRSFOV_HARDWARE_HALF");
    return v && std::string_view(v) == "0";
}

uint32_t retainRule(const CompositorConfig& c) {
    if (c.method == Method::Oracle) return gpu::WRS_RULE_ORACLE;
    if (c.method == Method::OracleQ) return gpu::WRS_RULE_ORACLE_Q;
    return uint32_t(c.equalQuality);
}

float floorQuality(const CompositorConfig& c) {
    if (!usesRetainPass(c.method) || c.floorMerge) return 0.0f;
    return gpu::wrs_rule_floor(retainRule(c), uint32_t(c.foveation));
}

double FrameStats::retainShare() const {
    uint64_t all = 0;
    for (uint32_t n : tiles) all += n;
    if (!retained) return 0.0;
    if (all == 0) return 1.0;
    return double(all - tiles[gpu::WRS_TILE_SKIP]) / double(all);
}

double FrameStats::farShare() const {
    uint64_t all = 0;
    for (uint32_t n : tiles) all += n;
    return all ? double(tiles[gpu::WRS_TILE_FAR] + tiles[gpu::WRS_TILE_SKIP]) / double(all) : 0.0;
}

double FrameStats::motionShare() const {
    uint64_t all = 0;
    for (uint32_t n : tiles) all += n;
    return all ? double(motionTiles) / double(all) : 0.0;
}

bool runsSparse(const CompositorConfig& c) {
    if (!c.sparseRetention || !c.skipTiles) return false;
    // A frame submitted foveated brings its floor (submittedFloor) where the rule has one at all.
    if (c.foveation == FoveationMode::Submitted) {
        CompositorConfig simulated = c;
        simulated.foveation = FoveationMode::Mip;
        return floorQuality(simulated) > 0.0f;
    }
    return floorQuality(c) > 0.0f;
}

PassPlan planPasses(const CompositorConfig& c, bool hasMotion, bool birth) {
    PassPlan p;
    p.retain = usesRetainPass(c.method);
    p.wrsPaper = c.method == Method::WrsPaper;
    p.taa = c.method == Method::FovTaa || c.method == Method::Taau;
    p.temporal = p.retain || p.wrsPaper || p.taa;
    p.pyramid = simulatesFoveation(c.foveation) || p.retain;
    // Tile classes (docs/speed.md "Tiles"): where a pass's levels can be constants for whole tiles. A
    // frame submitted foveated has two classes, far (rendered at the floor quality only) and any
    // (wrs_submitted_tile_class), which only sparse retention uses.
    const bool sparse = runsSparse(c);
    p.tiled = c.skipTiles && ((simulatesFoveation(c.foveation) && (c.method == Method::Fov || p.retain)) ||
                              (c.foveation == FoveationMode::Submitted && sparse));
    p.sparse = p.tiled && sparse;
    // Without motion, `wrs` and the oracle read only each pixel's own reservoir, so they update the
    // reservoirs in place; with motion a pixel reads its 2x2 neighbourhood and the buffers ping-pong,
    // as they do with stale tracking's birth buffers.
    p.inPlace = p.retain && !hasMotion && !birth;
    p.steady = p.pyramid && steadyFloorActive(c);
    p.display = displayActive(c);
    return p;
}

bool displayActive(const CompositorConfig& c) {
    return c.method == Method::Wrs && c.foveation == FoveationMode::Submitted && c.landedSamples && c.steadyDisplay > 0.0f;
}

uint32_t composeLanded(const CompositorConfig& c) {
    if (c.method == Method::Taau) return 2;
    return c.method == Method::Wrs && c.landedSamples ? 1 : 0;
}

bool steadyFloorActive(const CompositorConfig& c) {
    return c.steadyFloor && floorQuality(c) > 0.0f && simulatesFoveation(c.foveation);
}

double Traffic::perPixel() const {
    double b = 0;
    for (const PassTraffic& p : passes) b += p.read + p.write;
    return b;
}

Traffic traffic(const CompositorConfig& c, const TrafficInputs& in) {
    const glm::uvec2 size0(std::max(in.width, 1u), std::max(in.height, 1u));
    const double px = double(size0.x) * size0.y;
    constexpr double kTexel = 8;  // a pyramid texel: fp16 RGBA
    double level[WRS_LEVELS] = {};  // pyramid texels of each level per level-0 pixel
    for (uint32_t k = 1; k < WRS_LEVELS; ++k) {
        const glm::uvec2 s = gpu::wrs_level_size(size0, k);
        level[k] = double(s.x) * s.y / px;
    }
    // Stored and sampled: the levels from wrs_first_stored_level up (mip: 3 and 4; none: 4).
    const uint32_t first = gpu::wrs_first_stored_level(uint32_t(c.foveation));
    double levels = 0;
    for (uint32_t k = first; k < WRS_LEVELS; ++k) levels += level[k];
    const PassPlan plan = planPasses(c, in.motionBytes > 0, c.trackBirth);
    const bool retain = plan.retain, temporal = plan.temporal, pyramid = plan.pyramid;
    const bool usesDepth = c.method == Method::WrsPaper || retain;
    const bool usesMotion = temporal;
    const double depth = usesDepth ? in.depthBytes : 0, motion = usesMotion ? in.motionBytes : 0;
    const double birth = c.trackBirth && (c.method == Method::WrsPaper || retain) ? 16 : 0;
    const double levelsRead = pyramid ? levels * kTexel : 0;  // every stored level is sampled somewhere

    // Sparse retention: the retain pass in the tiles that ran it; the others run the foveating pass
    // (with the birth colour when tracked), and the classification reads the far tiles' motion.
    const bool sparse = plan.sparse;
    const double share = sparse ? std::clamp(in.retainShare, 0.0, 1.0) : 1.0;
    Traffic t;
    const bool composed = in.composeWrite > 0;
    if (composed) t.passes.push_back({"compose", in.composeRead, in.composeWrite});
    const double quality = composed && retain ? 4 : 0;  // the retain pass reads each pixel's rendered quality
    if (sparse) t.passes.push_back({"classify", in.motionBytes * std::clamp(in.motionShare, 0.0, 1.0), 0.0});
    if (pyramid) {
        // mip: one dispatch, colour in, the stored levels out. gauss: level 1 from the colour, level k from k - 1.
        const bool gauss = c.foveation == FoveationMode::Gauss;
        const double below = gauss ? (level[1] + level[2] + level[3]) * kTexel : 0;
        t.passes.push_back({"pyramid", in.colorBytes + below, levels * kTexel});
    }
    if (plan.steady) {
        // Per level-4 texel: its 3x3 neighbourhood (each texel read by nine, once from memory), the
        // history's 4x4 Catmull-Rom taps (once), one motion texel; the filtered texel out. Then level 4 and
        // the filtered texel in, level 4 out.
        const double motionTexel = in.motionBytes > 0 ? in.motionBytes : 0;
        t.passes.push_back({"steady", level[4] * (2 * kTexel + motionTexel), level[4] * kTexel});
        t.passes.push_back({"steady-copy", level[4] * 2 * kTexel, level[4] * kTexel});
    }
    if (!retain)
        t.passes.push_back({"foveate", in.colorBytes + levelsRead, temporal ? 16.0 : 4.0});  // candidate or output
    const double history = 16, output = 4;
    if (plan.wrsPaper)
        t.passes.push_back({"wrs-paper", 16 + history + depth + motion + (birth ? birth + in.colorBytes : 0),
                            history + output + birth});
    if (plan.taa) t.passes.push_back({"taa", 16 + history + motion, history + output});
    // The steady display: the retain pass's colour in the candidate buffer (fp16) instead of the output, then per
    // pixel its 3x3 neighbourhood (each read by nine, once from memory), the display's history (bilinear,
    // once), the motion; the history (fp16) and the output out. Quad views only (a rate map's compose pass
    // writes its qualities alone, 4 bytes).
    const bool display = plan.display && in.composeWrite > 4;
    const double shown = 8;  // what the display reads of a shown colour, and its own history (wrs_pack_shown)
    if (retain)  // the fingerprint level is among the stored ones in every mode
        t.passes.push_back({"retain", share * (in.colorBytes + levelsRead + history + depth + motion + birth + quality),
                            share * (history + (display ? shown : output) + birth)});
    if (display) t.passes.push_back({"display", shown + shown + motion, shown + output});
    if (sparse)
        t.passes.push_back({"skip", (1 - share) * (in.colorBytes + levelsRead),
                            (1 - share) * ((display ? shown : output) + birth)});
    t.floor = in.colorBytes + output + (temporal ? share * (2 * history + depth + motion) : 0);
    return t;
}

uint64_t trafficBytes(const CompositorConfig& c, const TrafficInputs& in) {
    return uint64_t(traffic(c, in).perPixel() * double(in.width) * in.height * WRS_EYES);
}
uint64_t floorBytes(const CompositorConfig& c, const TrafficInputs& in) {
    return uint64_t(traffic(c, in).floor * double(in.width) * in.height * WRS_EYES);
}

}  // namespace wrsfov
