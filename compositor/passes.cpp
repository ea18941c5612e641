// Configuration values, the pass plan of a frame and the traffic model (compositor.h).
#include "compositor/compositor.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "compositor/compose.h"
#include "compositor/compositor_internal.h"
#include "compositor/input.h"
#include "compositor/pass_table.h"
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
        case Method::TaauSimple:
            return "taau-simple";
    }
    return "?";
}
std::string_view toString(EqualQuality e) { return e == EqualQuality::Merge ? "merge" : "reservoir"; }
std::optional<Method> parseMethod(std::string_view name) {
    for (Method m : {Method::Fov, Method::FovTaa, Method::WrsPaper, Method::Wrs, Method::Oracle, Method::OracleQ,
                     Method::Taau, Method::TaauSimple})
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
    // The encodings the passes are specialised for: the views' own where both eyes agree.
    auto common = [&](auto encodingOf) {
        const uint32_t a = encodingOf(layer.views.at(0)), b = encodingOf(layer.views.at(1));
        return a == b ? a : gpu::WRS_INPUT_ANY;
    };
    in.colorEncoding = common([](const layers::ProjectionView& w) { return colorEncoding(w.color); });
    if (v.inset) {
        in.wideEncoding = in.colorEncoding;
        in.insetEncoding = common([](const layers::ProjectionView& w) {
            return w.inset ? colorEncoding(w.inset->color) : gpu::WRS_INPUT_ANY;
        });
        in.colorEncoding = gpu::WRS_INPUT_COMPOSED;
        const gpu::ComposeParams maps = makeComposeParams(layer, out, 0.0f);
        double insetGroupCount = 0;
        for (const gpu::ComposeEye& e : maps.eye) {
            const glm::uvec4 r = insetGroups(e, out);
            insetGroupCount += double(r.z - r.x) * (r.w - r.y);
        }
        in.insetShare = insetGroupCount / (2.0 * groups(out.x, WRS_GROUP_X) * groups(out.y, WRS_GROUP_Y));
        // Every texel of both sources once (bilinear neighbourhoods cached), per output pixel; the
        // composed colour (RGBA16F, the rendered quality in its alpha), depth (R32F) and motion (RGBA16F)
        // out, which the later passes read in place of the submitted images.
        const layers::InsetView& n = *v.inset;
        const double wide = double(v.color.rect.width) * v.color.rect.height / px;
        const double inset = double(n.color.rect.width) * n.color.rect.height / px;
        in.wideColorRead = wide * in.colorBytes;
        in.composeRead = wide * (in.colorBytes + in.depthBytes + in.motionBytes) +
                         inset * (bytes(n.color) + in.depthBytes + in.motionBytes);
        in.colorBytes = 8;
        if (v.depth) in.depthBytes = 4;
        if (v.motion) in.motionBytes = 8;
        in.composeWrite = in.colorBytes + in.depthBytes + in.motionBytes;  // the quality in the colour's alpha
    } else if (v.rateMap) {
        // A rate map's colour is read as submitted, by the passes; its compose pass reads the map alone.
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

PassPlan planPasses(const CompositorConfig& c, bool hasMotion, bool birth, bool quad) {
    PassPlan p;
    p.retain = usesRetainPass(c.method);
    p.wrsPaper = c.method == Method::WrsPaper;
    p.taa = c.method == Method::FovTaa || isTaau(c.method);
    p.temporal = p.retain || p.wrsPaper || p.taa;
    p.pyramid = simulatesFoveation(c.foveation) || p.retain;
    // Tile classes (docs/speed.md "Tiles"): where a pass's levels can be constants for whole tiles. A
    // frame submitted foveated has two classes, far (rendered at the floor quality only) and any
    // (wrs_submitted_tile_class), which only sparse retention uses.
    // The steady display, folded into the retain pass on quad views (docs/retention.md "Steady display"),
    // filters every pixel the pass shows: no tile skips retention there.
    p.display = displayActive(c) && quad;
    const bool sparse = runsSparse(c) && !p.display;
    p.tiled = c.skipTiles && ((simulatesFoveation(c.foveation) && (c.method == Method::Fov || p.retain)) ||
                              (c.foveation == FoveationMode::Submitted && sparse));
    p.sparse = p.tiled && sparse;
    // Without motion, `wrs` and the oracle read only each pixel's own reservoir, so they update the
    // reservoirs in place; with motion a pixel reads its 2x2 neighbourhood and the buffers ping-pong,
    // as they do with stale tracking's birth buffers.
    p.inPlace = p.retain && !hasMotion && !birth;
    p.steady = p.pyramid && steadyFloorActive(c);
    return p;
}

bool displayActive(const CompositorConfig& c) {
    return c.method == Method::Wrs && c.foveation == FoveationMode::Submitted && c.landedSamples && c.steadyDisplay > 0.0f;
}

uint32_t composeLanded(const CompositorConfig& c) {
    if (c.method == Method::TaauSimple) return 2;
    if (c.method == Method::Taau) return 3;
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
    // The frame's pass table (pass_table.h): each pass's dispatches weighed by the share of the view each
    // covers; a pass's tile lists once (their cover is the pass's: each moves the same bytes per pixel).
    Traffic t;
    std::vector<std::string_view> listed;  // passes whose tile lists are counted
    for (const PassDispatch& d : framePasses(c, in)) {
        const std::string_view name = toString(d.pass);
        if (d.shape == DispatchShape::TileList) {
            if (std::find(listed.begin(), listed.end(), name) != listed.end()) continue;
            listed.push_back(name);
        }
        auto it = std::find_if(t.passes.begin(), t.passes.end(), [&](const PassTraffic& p) { return p.pass == name; });
        if (it == t.passes.end()) it = t.passes.insert(t.passes.end(), PassTraffic{std::string(name), 0.0, 0.0});
        it->read += d.read * d.cover;
        it->write += d.write * d.cover;
    }
    // The floor: the colour in and the output out, and for methods with history the reservoir read and
    // written and the depth and motion they use, where retention ran.
    const PassPlan plan = planPasses(c, in.motionBytes > 0, c.trackBirth, in.composeWrite > 4);
    const double share = plan.sparse ? std::clamp(in.retainShare, 0.0, 1.0) : 1.0;
    const double depth = plan.wrsPaper || plan.retain ? in.depthBytes : 0, motion = plan.temporal ? in.motionBytes : 0;
    constexpr double history = 16, output = 4;
    t.floor = in.colorBytes + output + (plan.temporal ? share * (2 * history + depth + motion) : 0);
    return t;
}

uint64_t trafficBytes(const CompositorConfig& c, const TrafficInputs& in) {
    return uint64_t(traffic(c, in).perPixel() * double(in.width) * in.height * WRS_EYES);
}
uint64_t floorBytes(const CompositorConfig& c, const TrafficInputs& in) {
    return uint64_t(traffic(c, in).floor * double(in.width) * in.height * WRS_EYES);
}

}  // namespace wrsfov
