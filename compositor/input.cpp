#include "compositor/input.h"

#include <algorithm>
#include <cmath>

#include "compositor/swapchain_vk.h"
#include "shaders/config.h"
#include "shaders/wrs_submitted.h"

namespace wrsfov {

namespace {

glm::vec4 tangents(const layers::Fov& f) {
    return {std::tan(f.angleLeft), std::tan(f.angleRight), std::tan(f.angleUp), std::tan(f.angleDown)};
}

// Pixels per tangent unit of an image over a field of view, per axis.
glm::dvec2 density(const glm::vec4& tan, uint32_t w, uint32_t h) {
    return {w / (double(tan.y) - tan.x), h / (double(tan.z) - tan.w)};
}

}  // namespace

uint32_t colorEncoding(const layers::SubImage& s) {
    if (const auto* vs = dynamic_cast<const VulkanSwapchain*>(s.swapchain)) return vs->colorEncoding();
    return s.swapchain->info().format == layers::Format::RGBA8_SRGB ? gpu::WRS_INPUT_SRGB : gpu::WRS_INPUT_LINEAR;
}

glm::uvec4 insetGroups(const gpu::ComposeEye& e, glm::uvec2 out) {
    const uint32_t gx = (out.x + WRS_GROUP_X - 1) / WRS_GROUP_X, gy = (out.y + WRS_GROUP_Y - 1) / WRS_GROUP_Y;
    // Pixel p's inset position is (p + 0.5) s + o (wrs_source_pos), inside for 0 < it < size.
    auto span = [](double s, double o, double size, uint32_t n, uint32_t group, uint32_t groups) {
        if (!(s > 0.0) || !std::isfinite(o) || n == 0) return glm::uvec2(0, groups);  // all of it, to be safe
        const double lo = std::floor(-o / s - 0.5) - 1.0, hi = std::ceil((size - o) / s - 0.5) + 1.0;
        if (hi < 0.0 || lo > double(n - 1) || lo > hi) return glm::uvec2(0, 0);
        const uint32_t p0 = uint32_t(std::max(lo, 0.0)), p1 = uint32_t(std::min(hi, double(n - 1)));
        return glm::uvec2(p0 / group, p1 / group + 1);
    };
    const glm::uvec2 x = span(e.inset_map.x, e.inset_map.z, e.sizes.z, out.x, WRS_GROUP_X, gx);
    const glm::uvec2 y = span(e.inset_map.y, e.inset_map.w, e.sizes.w, out.y, WRS_GROUP_Y, gy);
    if (x.x >= x.y || y.x >= y.y) return glm::uvec4(0);
    return glm::uvec4(x.x, y.x, x.y, y.y);
}

float wideQuality(const layers::ProjectionView& v) {
    if (!v.inset) return 1.0f;
    const glm::dvec2 wide = density(tangents(v.fov), v.color.rect.width, v.color.rect.height);
    const glm::dvec2 inset = density(tangents(v.inset->fov), v.inset->color.rect.width, v.inset->color.rect.height);
    const double q = (wide.x / inset.x) * (wide.y / inset.y);
    // On fp16's grid: the composed colour carries each pixel's quality in fp16 (wrs_composed_alpha), and a
    // wide view's pixel's is then this value exactly.
    return gpu::wrs_f16_value(float(std::clamp(q, 1e-6, 1.0)));
}

float submittedFloor(const layers::ProjectionLayer& layer) {
    switch (layers::submittedFoveation(layer)) {
    case layers::SubmittedFoveation::Quad: return std::min(wideQuality(layer.views[0]), wideQuality(layer.views[1]));
    case layers::SubmittedFoveation::Rate: return gpu::WRS_RATE_FLOOR;
    case layers::SubmittedFoveation::Full: break;
    }
    return 0.0f;
}

gpu::ComposeParams makeComposeParams(const layers::ProjectionLayer& layer, glm::uvec2 out, float blendPx) {
    gpu::ComposeParams p{};
    p.size = glm::uvec4(out, 0u, 0u);
    for (uint32_t i = 0; i < 2 && i < layer.views.size(); ++i) {
        const layers::ProjectionView& v = layer.views[i];
        gpu::ComposeEye& e = p.eye[i];
        const glm::vec4 outTan = tangents(v.fov);
        // Output pixel centre c maps to a source's pixel (c * scale + offset) per axis (wrs_source_pos):
        // x = (tan_x(c) - src.left) * srcW / srcSpanX, y = (src.up - tan_y(c)) * srcH / srcSpanY, with
        // tan_x(c) = out.left + c * outSpanX / W and tan_y(c) = out.up - c * outSpanY / H. In double, rounded once.
        // A jittered source (sampleOffset o: its pixel i holds the scene at i + 0.5 + o of that grid) is
        // read on the lattice of its samples: the position less o, so each sample is placed where it
        // was taken and the output stays on the view's grid.
        auto map = [&](const glm::vec4& src, uint32_t sw, uint32_t sh, glm::vec2 o) {
            const double kx = sw / (double(src.y) - src.x), ky = sh / (double(src.z) - src.w);
            const double ox = (double(outTan.y) - outTan.x) / out.x, oy = (double(outTan.z) - outTan.w) / out.y;
            return glm::vec4(float(ox * kx), float(oy * ky), float((double(outTan.x) - src.x) * kx - double(o.x)),
                             float((double(src.z) - outTan.z) * ky - double(o.y)));
        };
        // (Rate maps: the colour is read at its own pixels, which are the output's; no offset.)
        const glm::vec2 wideOffset = v.inset ? v.sampleOffset : glm::vec2(0.0f);
        e.wide_map = map(outTan, v.color.rect.width, v.color.rect.height, wideOffset);
        // Output pixels per wide pixel (wrs_landed_offset); whether landed samples are written is the
        // compositor's (CompositorConfig::landedSamples).
        e.landed = glm::vec4(float(1.0 / double(e.wide_map.x)), float(1.0 / double(e.wide_map.y)), 0.0f, 0.0f);
        e.sizes = glm::uvec4(v.color.rect.width, v.color.rect.height, 0u, 0u);
        e.wide_color = glm::uvec4(v.color.rect.x, v.color.rect.y, colorEncoding(v.color), 0u);
        if (v.rateMap) {
            const layers::RateMapInfo& m = *v.rateMap;
            e.rate = glm::uvec4(m.subImage.rect.x, m.subImage.rect.y, m.texelWidth, m.texelHeight);
        }
        if (!v.inset) continue;
        const layers::InsetView& in = *v.inset;
        const glm::vec4 insetTan = tangents(in.fov);
        e.inset_map = map(insetTan, in.color.rect.width, in.color.rect.height, in.sampleOffset);
        e.sizes.z = in.color.rect.width;
        e.sizes.w = in.color.rect.height;
        e.inset_color = glm::uvec4(in.color.rect.x, in.color.rect.y, colorEncoding(in.color), 0u);
        if (v.depth) {
            e.offsets.x = v.depth->subImage.rect.x, e.offsets.y = v.depth->subImage.rect.y;
            e.inset_offsets.x = in.depth->subImage.rect.x, e.inset_offsets.y = in.depth->subImage.rect.y;
        }
        // Motion in output pixels: each source's pixels scaled by the output's density over its own.
        const glm::dvec2 outDensity = density(outTan, out.x, out.y);
        glm::vec3 wideScale(1.0f), insetScale(1.0f);
        if (v.motion) {
            e.offsets.z = v.motion->subImage.rect.x, e.offsets.w = v.motion->subImage.rect.y;
            e.inset_offsets.z = in.motion->subImage.rect.x, e.inset_offsets.w = in.motion->subImage.rect.y;
            const glm::dvec2 w = outDensity / density(outTan, v.color.rect.width, v.color.rect.height);
            const glm::dvec2 n = outDensity / density(insetTan, in.color.rect.width, in.color.rect.height);
            wideScale = v.motion->scale * glm::vec3(float(w.x), float(w.y), 1.0f);
            insetScale = in.motion->scale * glm::vec3(float(n.x), float(n.y), 1.0f);
        }
        e.wide_motion = glm::vec4(wideScale, wideQuality(v));
        e.inset_motion = glm::vec4(insetScale, blendPx > 0.0f ? float(1.0 / blendPx) : 0.0f);
    }
    return p;
}

}  // namespace wrsfov
