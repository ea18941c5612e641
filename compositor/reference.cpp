#include "compositor/reference.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "shaders/wrs_submitted.h"

// The candidate stage's bridge (shaders/wrs_candidate.h): an eye's pyramid as the reference stores it,
// levels 0..WRS_LEVELS-1 at wrs_level_offset, each texel already rounded as the pyramid buffer stores it.
namespace wrsfov::gpu {
struct WrsPyramid {
    const vec4* texels;
    uvec2 size0;
};
inline vec4 wrs_pyr_texel(WrsPyramid s, uint level, uvec2 q) {
    return s.texels[wrs_level_offset(s.size0, level) + q.y * wrs_level_size(s.size0, level).x + q.x];
}
inline uvec2 wrs_pyr_level_size(WrsPyramid s, uint level) { return wrs_level_size(s.size0, level); }
inline vec2 wrs_pyr_level_scale(WrsPyramid s, uint level) { return wrs_level_scale(s.size0, level); }
}  // namespace wrsfov::gpu
#include "shaders/wrs_candidate.h"
#include "shaders/wrs_input.h"

namespace wrsfov {

using namespace gpu;

glm::u8vec4 encodeOutput(glm::vec3 linear) {
    // What store_output hands the RGBA8 image (whole codes), converted as the modelled device converts it.
    glm::vec3 s = wrs_output_value(linear);
    return glm::u8vec4(wrs_device_unorm8(s.x), wrs_device_unorm8(s.y), wrs_device_unorm8(s.z), 255);
}

namespace {

// The 3x3 neighbourhood of pixel p in YCoCg, as taa.comp gathers it (taps clamped to the image of size
// `size`); `colourAt(q)` gives the linear RGB at pixel q.
template <typename ColourAt>
void taaNeighbourhood(uvec2 p, uvec2 size, ColourAt colourAt, vec3 nb[9]) {
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) nb[j * 3 + i] = wrs_rgb_to_ycocg(colourAt(wrs_taa_tap(p, ivec2(i - 1, j - 1), size)));
}

// What a pass fetches of an input texel read as `encoding` says: HostImage::fetch gives an 8-bit image's
// code / 255, what a UNORM view returns; through an sRGB view the device returns the code's linear
// value (the table: the nearest float to it, as a table-driven decode gives).
vec4 asFetched(vec4 t, uint encoding) {
    if (encoding != WRS_INPUT_SRGB_VIEW) return t;
    const auto& table = wrs_srgb8_table();
    return vec4(table[wrs_srgb8_code(t.x)], table[wrs_srgb8_code(t.y)], table[wrs_srgb8_code(t.z)], t.w);
}

// A source texel decoded as compose.comp's source_texel does (wrs_decode_input).
vec4 sourceTexel(const HostImage& img, uvec2 q, uint encoding) {
    return wrs_decode_input(vec4(vec3(asFetched(img.fetch(q.x, q.y), encoding)), 1.0f), encoding);
}

vec4 sourceBilinear(const HostImage& img, vec2 pos, uint encoding) {
    const uvec2 size(img.width, img.height);
    uvec2 i0, i1;
    const vec2 f = wrs_bilinear_taps(pos, size, i0, i1);
    return wrs_bilinear_valid(sourceTexel(img, i0, encoding), sourceTexel(img, uvec2(i1.x, i0.y), encoding),
                              sourceTexel(img, uvec2(i0.x, i1.y), encoding), sourceTexel(img, i1, encoding), f);
}

uvec2 nearestTexel(vec2 pos, uvec2 size) {
    return uvec2(glm::clamp(ivec2(glm::floor(pos)), ivec2(0), ivec2(size) - ivec2(1)));
}

vec4 roundF16(vec4 v) { return vec4(wrs_round_f16(v.x), wrs_round_f16(v.y), wrs_round_f16(v.z), wrs_round_f16(v.w)); }

}  // namespace

Reference::EyeInput composeQuadViews(const ComposeParams& params, uint32_t eye, const QuadSources& src) {
    const uvec2 size(params.size.x, params.size.y);
    const ComposeEye& ce = params.eye[eye];
    const uvec2 wsize(ce.sizes.x, ce.sizes.y), isize(ce.sizes.z, ce.sizes.w);
    Reference::EyeInput out;
    out.color = HostImage::make(layers::Format::RGBA16F, size.x, size.y);
    if (src.wideDepth) out.depth = HostImage::make(layers::Format::R32F, size.x, size.y);
    if (src.wideMotion) out.motion = HostImage::make(layers::Format::RGBA16F, size.x, size.y);
    out.quality.resize(std::size_t(size.x) * size.y);
    for (uint y = 0; y < size.y; ++y)
        for (uint x = 0; x < size.x; ++x) {
            const uvec2 p(x, y);
            const vec2 wpos = wrs_source_pos(p, ce.wide_map);
            const vec2 ipos = wrs_source_pos(p, ce.inset_map);
            float t = wrs_inset_weight(ipos, isize, ce.inset_motion.w);
            const vec4 wide = sourceBilinear(src.wideColor, wpos, ce.wide_color.z);
            const vec4 inset = t > 0.0f ? sourceBilinear(src.insetColor, ipos, ce.inset_color.z) : vec4(0.0f);
            t = wrs_quad_weight(t, inset.w != 0.0f, wide.w != 0.0f);
            const vec4 c = wrs_quad_color(wide, inset, t);
            // As compose.comp: the quality in the composed colour's alpha, rounded as stored.
            const vec4 stored = roundF16(vec4(vec3(c), wrs_composed_alpha(c.w > 0.5f, wrs_quad_quality(ce.wide_motion.w, t))));
            out.quality[std::size_t(y) * size.x + x] = stored.w;
            out.color.store(x, y, stored);
            const bool insetOnly = t == 1.0f && inset.w != 0.0f;
            if (ce.landed.z == 3.0f) {
                // As compose.comp: taau's Lanczos-2 gather of the 4x4 wide texels around the pixel.
                TaauGather gather = wrs_taau_gather_start();
                if (!insetOnly) {
                    uvec2 i0, i1;
                    wrs_bilinear_taps(wpos, wsize, i0, i1);
                    for (uint j = 0; j < 16u; ++j) {
                        uvec2 k;
                        if (!wrs_taau_block_tap(i0, wsize, j, k)) continue;
                        wrs_taau_gather_add(gather, sourceTexel(src.wideColor, k, ce.wide_color.z), wpos, k, ce.landed.w);
                    }
                }
                const vec4 g = wrs_taau_gather_result(gather);
                if (out.landed.empty()) out.landed.resize(std::size_t(size.x) * size.y);
                out.landed[std::size_t(y) * size.x + x] = wrs_unpack_landed(wrs_pack_landed(vec3(g), g.w));
            } else if (ce.landed.z == 2.0f) {
                // As compose.comp: taau-simple's gather of the four wide samples of the pixel's bilinear cell.
                vec4 acc(0.0f);
                if (!insetOnly) {
                    uvec2 i0, i1;
                    wrs_bilinear_taps(wpos, wsize, i0, i1);
                    for (uint j = 0; j < 4u; ++j) {
                        uvec2 k;
                        if (!wrs_taau_cell_tap(i0, i1, j, k)) continue;
                        acc = wrs_taau_simple_add(acc, sourceTexel(src.wideColor, k, ce.wide_color.z),
                                           wrs_landed_offset(wpos, k, vec2(ce.landed)), ce.landed.w);
                    }
                }
                const vec4 g = wrs_taau_gathered(acc);
                if (out.landed.empty()) out.landed.resize(std::size_t(size.x) * size.y);
                out.landed[std::size_t(y) * size.x + x] = wrs_unpack_landed(wrs_pack_landed(vec3(g), g.w));
            } else if (ce.landed.z != 0.0f) {
                // As compose.comp: the wide sample nearest the centre, not read where the inset alone shows.
                const uvec2 k = nearestTexel(wpos, wsize);
                const vec2 d = wrs_landed_offset(wpos, k, wrs_landed_scale(ce.landed));
                float ql = insetOnly ? 0.0f : wrs_landed_quality(d);
                const vec4 s = ql > 0.0f ? sourceTexel(src.wideColor, k, ce.wide_color.z) : vec4(0.0f);
                if (s.w == 0.0f) ql = 0.0f;
                if (out.landed.empty()) out.landed.resize(std::size_t(size.x) * size.y);
                if (out.landedOverlap.empty()) out.landedOverlap.resize(std::size_t(size.x) * size.y);
                if (out.landedPosition.empty()) out.landedPosition.resize(std::size_t(size.x) * size.y);
                out.landed[std::size_t(y) * size.x + x] = wrs_unpack_landed(wrs_pack_landed(vec3(s), ql));
                out.landedOverlap[std::size_t(y) * size.x + x] = ql > 0.0f ? wrs_landed_weight(d, true) : 0.0f;
                out.landedPosition[std::size_t(y) * size.x + x] = wrs_landed_position(wpos, k, ce.landed);
            }
            const bool fromInset = t >= 0.5f;
            const uvec2 q = fromInset ? nearestTexel(ipos, isize) : nearestTexel(wpos, wsize);
            if (out.depth) {
                const HostImage& d = fromInset ? *src.insetDepth : *src.wideDepth;
                out.depth->store(x, y, vec4(d.fetch(q.x, q.y).x, 0.0f, 0.0f, 0.0f));
            }
            if (out.motion) {
                const HostImage& m = fromInset ? *src.insetMotion : *src.wideMotion;
                const vec3 scale = fromInset ? vec3(ce.inset_motion) : vec3(ce.wide_motion);
                out.motion->store(x, y, roundF16(vec4(vec3(m.fetch(q.x, q.y)) * scale, 0.0f)));
            }
        }
    return out;
}

std::vector<float> rateMapQualities(const ComposeParams& params, uint32_t eye, const HostImage& map) {
    const uvec2 size(params.size.x, params.size.y);
    const uvec4 rate = params.eye[eye].rate;
    std::vector<float> q(std::size_t(size.x) * size.y);
    for (uint y = 0; y < size.y; ++y)
        for (uint x = 0; x < size.x; ++x)
            q[std::size_t(y) * size.x + x] = wrs_rate_quality(uint(map.fetch(x / rate.z, y / rate.w).x));
    return q;
}

void Reference::setHistory(uint32_t eye, std::vector<glm::uvec4> packed, std::vector<float> held) {
    res_[eye] = std::move(packed);
    held_[eye] = std::move(held);
    history_ = true;
}

void Reference::step(const FrameParams& params, const std::array<EyeInput, 2>& eyes) {
    const uvec2 size0(params.size.x, params.size.y);
    const uint W = size0.x, H = size0.y;
    const uint frame = params.size.z, seed = params.size.w;
    // Frames submitted foveated (an input with qualities) run as the compositor runs them: mode submitted.
    CompositorConfig cfg = config_;
    if (!eyes[0].quality.empty()) cfg.foveation = FoveationMode::Submitted;
    const uint mode = uint(cfg.foveation);
    const bool wrs = config_.method == Method::WrsPaper;
    const bool retain = usesRetainPass(config_.method);
    const bool taau = isTaau(config_.method);
    const bool fsr = config_.method == Method::Taau;
    const bool taa = config_.method == Method::FovTaa || taau;
    motionTiles_ = 0;

    for (uint eye = 0; eye < 2; ++eye) {
        const EyeParams& ep = params.eye[eye];
        const EyeInput& in = eyes[eye];
        const bool hasDepth = in.depth.has_value();
        const bool hasMotion = in.motion.has_value();

        // Level 0 and linear depth: what every pass decodes from the submitted images (load_color,
        // load_depth in shaders/bindings.glsl).
        std::vector<vec4> pyr(wrs_pyramid_texels(size0));
        std::vector<float> zlin(std::size_t(W) * H, 0.0f);
        for (uint y = 0; y < H; ++y)
            for (uint x = 0; x < W; ++x) {
                pyr[y * W + x] = wrs_decode_input(asFetched(in.color.fetch(x, y), ep.color_rect.z), ep.color_rect.z);
                if (hasDepth)
                    zlin[y * W + x] =
                        wrs_linear_depth(in.depth->fetch(x, y).x, ep.depth_range.x, ep.depth_range.y, ep.depth_rect.z != 0u);
            }
        auto at = [&](uint level, uvec2 q) -> vec4& {
            uvec2 sl = wrs_level_size(size0, level);
            return pyr[wrs_level_offset(size0, level) + q.y * sl.x + q.x];
        };

        // What a texel of the pyramid buffer stores: fp16 RGBA, converted as pyr_pack does (wrs_store_f16).
        auto round4 = [](vec4 v) {
            const uvec2 h(wrs_store_f16x2(v.x, v.y), wrs_store_f16x2(v.z, v.w));
            return vec4(wrs_f16_to_f32(h.x & 0xffffu), wrs_f16_to_f32(h.x >> 16u), wrs_f16_to_f32(h.y & 0xffffu),
                        wrs_f16_to_f32(h.y >> 16u));
        };

        // Pass 1: pyramid levels 1..4 (methods wrs and oracle need level 4 for every mode: a box pyramid for `none`).
        if (wrs_mode_simulated(mode) || retain) {
            for (uint level = 1; level < uint(WRS_LEVELS); ++level) {
                uvec2 src = wrs_level_size(size0, level - 1u), dst = wrs_level_size(size0, level);
                auto tap = [&](uvec2 d, ivec2 o) { return at(level - 1u, wrs_down_tap(d, o, src)); };
                for (uint y = 0; y < dst.y; ++y)
                    for (uint x = 0; x < dst.x; ++x) {
                        uvec2 d(x, y);
                        vec4 r;
                        if (mode != WRS_FOV_GAUSS) {
                            r = wrs_down_box(tap(d, ivec2(0, 0)), tap(d, ivec2(1, 0)), tap(d, ivec2(0, 1)),
                                             tap(d, ivec2(1, 1)));
                        } else {
                            vec4 rows[4];
                            for (int j = 0; j < 4; ++j)
                                rows[j] = wrs_binomial_row(tap(d, ivec2(-1, j - 1)), tap(d, ivec2(0, j - 1)),
                                                           tap(d, ivec2(1, j - 1)), tap(d, ivec2(2, j - 1)));
                            r = wrs_binomial_row(rows[0], rows[1], rows[2], rows[3]);
                        }
                        // Stored as fp16 (pyramid.comp), and the next level is built from that.
                        at(level, d) = round4(wrs_pyramid_texel(r, level));
                    }
            }
        }
        // Pass 1b: the steady floor (pyramid.comp, FILTER 3): level 4 filtered over time, its alpha
        // (the fingerprint's L*) kept.
        if (steadyFloorActive(cfg)) {
            const uvec2 s4 = wrs_level_size(size0, WRS_STEADY_LEVEL);
            const std::size_t n4 = std::size_t(s4.x) * s4.y;
            const std::vector<vec4> prev = history_ && steady_[eye].size() == n4 ? steady_[eye] : std::vector<vec4>{};
            std::vector<vec4> cur(n4);
            for (uint y = 0; y < s4.y; ++y)
                for (uint x = 0; x < s4.x; ++x) {
                    uvec2 d(x, y);
                    vec3 nb[9];
                    taaNeighbourhood(d, s4, [&](uvec2 q) { return vec3(at(WRS_STEADY_LEVEL, q)); }, nb);
                    vec3 mv(0.0f);
                    if (hasMotion) {
                        uvec2 p = wrs_steady_motion_pixel(d, size0);
                        mv = wrs_steady_motion(vec3(in.motion->fetch(p.x, p.y)) * vec3(ep.motion_scale));
                    }
                    uvec2 i0, i1;
                    vec2 f;
                    auto hAt = [&](uvec2 q) { return prev[std::size_t(q.y) * s4.x + q.x]; };
                    bool has = !prev.empty() && wrs_taa_reproject(d, s4, mv, i0, i1, f) && hAt(d).w != 0.0f;
                    vec3 hist(0.0f);
                    if (has) {
                        const vec4 wx = wrs_catmull_rom(f.x), wy = wrs_catmull_rom(f.y);
                        for (int j = 0; j < 4; ++j) {
                            vec3 row(0.0f);
                            for (int i = 0; i < 4; ++i) row += wx[i] * vec3(hAt(wrs_cubic_tap(i0, ivec2(i, j), s4)));
                            hist += wy[j] * row;
                        }
                        has = wrs_finite3(hist);
                    }
                    cur[std::size_t(y) * s4.x + x] = round4(vec4(wrs_taa_step(nb, hist, has, WRS_STEADY_ALPHA), 1.0f));
                }
            for (uint y = 0; y < s4.y; ++y)
                for (uint x = 0; x < s4.x; ++x) {
                    vec4& t = at(WRS_STEADY_LEVEL, uvec2(x, y));
                    t = vec4(vec3(cur[std::size_t(y) * s4.x + x]), t.w);
                }
            steady_[eye] = std::move(cur);
        } else {
            steady_[eye].clear();
        }

        // Pass 2: foveate.
        const WrsPyramid pyramid{pyr.data(), size0};
        cand_[eye].assign(std::size_t(W) * H, vec4(0.0f));
        out_[eye] = HostImage::make(layers::Format::RGBA8, W, H);
        for (uint y = 0; y < H; ++y)
            for (uint x = 0; x < W; ++x) {
                uvec2 p(x, y);
                vec3 ray = wrs_pixel_ray(x, y, W, H, ep.fov_tan);
                float e = wrs_eccentricity_deg(ray, vec3(ep.gaze));
                float r_f = ep.gaze.w;
                vec3 lv = wrs_foveation_levels(mode, e, r_f, params.tuning.x);
                const WrsCandidate c = wrs_candidate_at(pyramid, mode, p, at(0u, p), lv, e, r_f, 0.0f, false);
                cand_[eye][y * W + x] = vec4(c.rule.color, c.w);
                glm::u8vec4 o = encodeOutput(c.rule.color);
                std::memcpy(out_[eye].data.data() + (std::size_t(y) * W + x) * 4, &o, 4);
            }
        if (!wrs && !taa && !retain) continue;

        prev_[eye] = history_ && res_[eye].size() == std::size_t(W) * H ? res_[eye]
                                                                         : std::vector<uvec4>(std::size_t(W) * H, uvec4(0u));
        res_[eye].assign(std::size_t(W) * H, uvec4(0u));
        if (taa) {
            // Pass 3 of FOV+TAA.
            auto histAt = [&](uvec2 q) {
                uvec4 h = prev_[eye][std::size_t(q.y) * W + q.x];
                return vec4(uintBitsToFloat(h.x), uintBitsToFloat(h.y), uintBitsToFloat(h.z), 0.0f);
            };
            for (uint y = 0; y < H; ++y)
                for (uint x = 0; x < W; ++x) {
                    uvec2 p(x, y);
                    std::size_t idx = std::size_t(y) * W + x;
                    if (fsr) {  // as taa.comp's taau_pixel
                        vec3 nb[9];
                        for (uint k = 0; k < 9u; ++k) {
                            const uvec2 q = wrs_wide_box_tap(p, k, ep.display.x, size0);
                            nb[k] = wrs_rgb_to_ycocg(vec3(cand_[eye][std::size_t(q.y) * W + q.x]));
                        }
                        const vec3 mv = hasMotion ? vec3(in.motion->fetch(x, y)) * vec3(ep.motion_scale) : vec3(0.0f);
                        const float depth = hasDepth ? zlin[idx] : 0.0f;
                        uvec2 i0, i1;
                        vec2 f;
                        bool has = wrs_taa_reproject(p, size0, mv, i0, i1, f) && wrs_taau_packed_valid(prev_[eye][idx]);
                        TaauHistory h{};
                        if (has) {
                            auto at = [&](uvec2 q) { return wrs_taau_unpack(prev_[eye][std::size_t(q.y) * W + q.x]); };
                            const TaauHistory a = at(i0), b = at(uvec2(i1.x, i0.y)), c = at(uvec2(i0.x, i1.y)), d = at(i1);
                            has = wrs_taau_reproject(a, b, c, d, f, depth, params.tuning.y, h);
                            TaauGather hg = wrs_taau_gather_start();  // as taa.comp: the colour resampled
                            const vec4 wx = wrs_history_weights(f.x), wy = wrs_history_weights(f.y);
                            for (uint j = 0; j < 16u; ++j) wrs_history_add(hg, at(wrs_history_tap(i0, size0, j)).color, wx, wy, j);
                            h.color = wrs_history_result(hg);
                            has = has && wrs_finite3(h.color);
                        }
                        const bool gathered = ep.motion_rect.z != 0u && !in.landed.empty();
                        const vec4 g = gathered ? in.landed[idx] : vec4(vec3(cand_[eye][idx]), 1.0f);
                        const bool inset = gathered && !wrs_is_wide_quality(in.quality[idx], ep.tile.w);
                        const bool finiteXy = wrs_finite(mv.x) && wrs_finite(mv.y);
                        const float vel = finiteXy ? wrs_length(vec2(mv)) : 0.0f;
                        TaauHistory next{};
                        const vec3 c = wrs_taau_step(nb, g, inset, h, has, depth, vel, ep.depth_range.z, ep.depth_range.w,
                                                     ep.taau, next);
                        res_[eye][idx] = wrs_taau_pack(next);
                        glm::u8vec4 o = encodeOutput(c);
                        std::memcpy(out_[eye].data.data() + idx * 4, &o, 4);
                        continue;
                    }
                    vec3 nb[9];
                    taaNeighbourhood(p, size0, [&](uvec2 q) { return vec3(cand_[eye][std::size_t(q.y) * W + q.x]); }, nb);
                    vec3 mv = hasMotion ? vec3(in.motion->fetch(x, y)) * vec3(ep.motion_scale) : vec3(0.0f);
                    uvec2 i0, i1;
                    vec2 f;
                    bool has = wrs_taa_reproject(p, size0, mv, i0, i1, f) && prev_[eye][std::size_t(y) * W + x].w != 0u;
                    vec3 hist(0.0f);
                    if (has) {
                        hist = vec3(wrs_bilinear(histAt(i0), histAt(uvec2(i1.x, i0.y)), histAt(uvec2(i0.x, i1.y)),
                                                 histAt(i1), f));
                        has = wrs_finite3(hist);
                    }
                    vec3 c;
                    if (taau) {  // as taa.comp's UPSAMPLE
                        const bool gathered = ep.motion_rect.z != 0u && !in.landed.empty();
                        const vec4 g = gathered ? in.landed[idx] : vec4(vec3(cand_[eye][idx]), 1.0f);
                        const bool inset = gathered && !wrs_is_wide_quality(in.quality[idx], ep.tile.w);
                        const float acc = has ? uintBitsToFloat(prev_[eye][idx].w) : 0.0f;
                        const vec4 r = wrs_taau_simple_step(nb, g, inset, hist, acc, has, ep.depth_range.z, ep.depth_range.w);
                        c = vec3(r);
                        res_[eye][idx] = uvec4(floatBitsToUint(c.x), floatBitsToUint(c.y), floatBitsToUint(c.z),
                                               floatBitsToUint(std::max(r.w, WRS_TAAU_PRIOR)));
                    } else {
                        c = wrs_taa(nb, hist, has);
                        res_[eye][idx] = uvec4(floatBitsToUint(c.x), floatBitsToUint(c.y), floatBitsToUint(c.z), 1u);
                    }
                    glm::u8vec4 o = encodeOutput(c);
                    std::memcpy(out_[eye].data.data() + idx * 4, &o, 4);
                }
            continue;
        }

        if (retain) {
            // Pass 2 of wrs / oracle (shaders/retain.comp): candidate, tracked history, retention.
            const uint rule = retainRule(config_);
            // Sparse retention (classify.comp): the held qualities the step reads (nothing after a
            // reset; anything where none were recorded), and which far tiles skip retention.
            // The steady display folded into the retain pass (retain.comp DISPLAY: where the frame runs it,
            // its weight in tuning.z) filters each pixel as it is shown; no tile skips retention then.
            const bool display = params.tuning.z > 0.0f;
            const bool sparse = runsSparse(cfg) && !display;
            const bool displayHistory = display && history_ && displayed_ && display_[eye].size() == std::size_t(W) * H;
            std::vector<vec4> prevDisplay = displayHistory ? std::move(display_[eye]) : std::vector<vec4>{};
            display_[eye].clear();
            if (display) display_[eye].assign(std::size_t(W) * H, vec4(0.0f));
            auto displayAt = [&](uvec2 q) { return vec4(vec3(prevDisplay[std::size_t(q.y) * W + q.x]), 0.0f); };
            const uvec2 tiles((W + WRS_TILE - 1u) / WRS_TILE, (H + WRS_TILE - 1u) / WRS_TILE);
            std::vector<float> heldPrev(std::size_t(tiles.x) * tiles.y, history_ ? 1.0f : 0.0f);
            if (history_ && held_[eye].size() == heldPrev.size()) heldPrev = held_[eye];
            std::vector<bool> skip(heldPrev.size(), false);
            std::vector<float> heldCur(heldPrev.size(), 0.0f);
            const float reach = ep.motion_scale.w;
            // Superblocks (classify.comp phase 1): the largest held quality of their tiles.
            const uvec2 blocks = (tiles + uvec2(WRS_SUPERBLOCK - 1u)) / WRS_SUPERBLOCK;
            std::vector<float> blockHeld(std::size_t(blocks.x) * blocks.y, 0.0f);
            for (uint ty = 0; ty < tiles.y; ++ty)
                for (uint tx = 0; tx < tiles.x; ++tx) {
                    float& b = blockHeld[(ty / WRS_SUPERBLOCK) * blocks.x + tx / WRS_SUPERBLOCK];
                    b = std::max(b, heldPrev[ty * tiles.x + tx]);
                }
            // classify.comp's source_held: within the reach from the superblocks, else from the motion.
            auto sourceHeld = [&](uvec2 t) {
                if (!hasMotion) return heldPrev[t.y * tiles.x + t.x];
                uvec2 b0, b1;
                if (!wrs_reach_blocks(t, size0, reach, b0, b1)) return 0.0f;
                if ((b1.x - b0.x + 1u) * (b1.y - b0.y + 1u) <= WRS_REACH_BLOCKS_MAX) {
                    float near = 0.0f;
                    for (uint by = b0.y; by <= b1.y; ++by)
                        for (uint bx = b0.x; bx <= b1.x; ++bx) near = std::max(near, blockHeld[by * blocks.x + bx]);
                    if (near <= params.tuning.w) return near;
                }
                ++motionTiles_;
                vec2 lo(0.0f), hi(0.0f);
                for (uint y = t.y * WRS_TILE; y < std::min((t.y + 1u) * WRS_TILE, H); ++y)
                    for (uint x = t.x * WRS_TILE; x < std::min((t.x + 1u) * WRS_TILE, W); ++x) {
                        vec2 mv = vec2(in.motion->fetch(x, y)) * vec2(ep.motion_scale);
                        if (!wrs_finite(mv.x) || !wrs_finite(mv.y) || !wrs_within_reach(mv, reach)) continue;
                        lo = min(lo, mv);
                        hi = max(hi, mv);
                    }
                uvec2 s0, s1;
                if (!wrs_tile_sources(t, size0, lo, hi, s0, s1)) return 0.0f;
                if ((s1.x - s0.x + 1u) * (s1.y - s0.y + 1u) > WRS_SOURCE_TILES_MAX) return 1.0f;
                float held = 0.0f;
                for (uint sy = s0.y; sy <= s1.y; ++sy)
                    for (uint sx = s0.x; sx <= s1.x; ++sx) held = std::max(held, heldPrev[sy * tiles.x + sx]);
                return held;
            };
            for (uint ty = 0; sparse && ty < tiles.y; ++ty)
                for (uint tx = 0; tx < tiles.x; ++tx) {
                    const uvec2 t(tx, ty);
                    uint cls;
                    if (mode == WRS_FOV_SUBMITTED) {
                        // The compose pass's per-tile maximum of the rendered qualities.
                        float q_max = 0.0f;
                        for (uint y = ty * WRS_TILE; y < std::min((ty + 1u) * WRS_TILE, H); ++y)
                            for (uint x = tx * WRS_TILE; x < std::min((tx + 1u) * WRS_TILE, W); ++x)
                                q_max = std::max({q_max, in.quality[std::size_t(y) * W + x],
                                                  in.landed.empty() ? 0.0f : in.landed[std::size_t(y) * W + x].w});
                        cls = wrs_submitted_tile_class(q_max, params.tuning.w);
                    } else {
                        cls = wrs_tile_class(mode, t, size0, ep.fov_tan, ep.tile, vec3(ep.gaze), ep.gaze.w,
                                             params.tuning.x);
                    }
                    if (cls != WRS_TILE_FAR) continue;
                    skip[ty * tiles.x + tx] = wrs_tile_skips(cls, sourceHeld(t), params.tuning.w);
                }
            auto tileOf = [&](uvec2 q) { return std::size_t(q.y / WRS_TILE) * tiles.x + q.x / WRS_TILE; };
            trace_[eye].assign(std::size_t(W) * H, Trace{});
            for (uint y = 0; y < H; ++y)
                for (uint x = 0; x < W; ++x) {
                    uvec2 p(x, y);
                    std::size_t idx = std::size_t(y) * W + x;
                    // A skipped tile: the candidate (the foveate pass's output above), nothing stored.
                    if (skip[tileOf(p)]) {
                        trace_[eye][idx].skipped = true;
                        continue;
                    }
                    vec3 ray = wrs_pixel_ray(x, y, W, H, ep.fov_tan);
                    float e = wrs_eccentricity_deg(ray, vec3(ep.gaze));
                    float r_f = ep.gaze.w;
                    vec3 lv = wrs_foveation_levels(mode, e, r_f, params.tuning.x);
                    const vec4 ref = at(0u, p);
                    const float q_sub = mode == WRS_FOV_SUBMITTED ? in.quality[idx] : 0.0f;
                    RetainInput c = wrs_candidate_at(pyramid, mode, p, ref, lv, e, r_f, q_sub, true).rule;
                    c.z = hasDepth ? zlin[idx] : 0.0f;
                    c.q_floor = params.tuning.w;
                    const bool filters = display && ep.motion_rect.z != 0u && !in.quality.empty() &&
                                         wrs_is_wide_quality(in.quality[idx], ep.tile.w);
                    vec3 m1(0.0f), m2(0.0f);
                    if (mode == WRS_FOV_SUBMITTED) {  // as retain.comp
                        c.jittered = ep.motion_rect.w != 0u;
                        const bool box = ep.depth_rect.w != 0u && wrs_wide_box_applies(c.q, ep.tile.w);
                        if (box || filters) {
                            const uint steps = filters ? ep.display.x : ep.depth_rect.w;
                            for (uint k = 0; k < 9u; ++k) {
                                const vec4 tk = at(0u, wrs_wide_box_tap(p, k, steps, size0));
                                if (box) wrs_wide_box_add(c.lo, c.hi, tk);
                                if (filters) wrs_moments_add(m1, m2, wrs_rgb_to_ycocg(wrs_display_tap(tk, ref)));
                            }
                        }
                        if (ep.motion_rect.z != 0u && !wrs_rule_is_oracle(rule) && !in.landed.empty()) {
                            // As retain.comp's landed_sample: colour and weight (fp16), 0 where none landed.
                            vec4 l = in.landed[idx];
                            if (l.w > 0.0f)
                                l.w = (ep.motion_rect.z & WRS_LANDED_WEIGHTED) != 0u && !in.landedOverlap.empty()
                                          ? wrs_round_f16(in.landedOverlap[idx])
                                          : 1.0f;
                            wrs_offer_landed(c, l, in.landedPosition.empty() ? vec2(0.0f) : in.landedPosition[idx]);
                        }
                    }
                    vec3 mv = hasMotion ? vec3(in.motion->fetch(x, y)) * vec3(ep.motion_scale) : vec3(0.0f);
                    c.moved = wrs_finite(mv.x) && wrs_finite(mv.y) && (mv.x != 0.0f || mv.y != 0.0f);
                    vec2 pos;
                    ivec2 base;
                    const bool on_screen = wrs_track_start(p, size0, mv, reach, pos, base);
                    const uint taps = c.moved ? 4u : 1u;  // as retain.comp: without motion, the pixel's own
                    TrackState ts = wrs_track_begin(p);
                    uvec4 tap[4] = {uvec4(0u), uvec4(0u), uvec4(0u), uvec4(0u)};  // all-zero: not read
                    for (uint k = 0; k < taps && on_screen; ++k) {
                        uvec2 qk;
                        if (!wrs_track_tap(base, k, size0, qk)) continue;
                        tap[k] = sparse && heldPrev[tileOf(qk)] == 0.0f ? wrs_floor_sample(params.tuning.w)
                                                                        : prev_[eye][std::size_t(qk.y) * W + qk.x];
                        wrs_track_consider(ts, tap[k], qk, pos);
                    }
                    Tracked h;
                    vec2 d;
                    uvec2 q;
                    const bool found = wrs_track_end(ts, h, d, q);
                    bool has_history = found;
                    float dz = wrs_finite(mv.z) ? mv.z : 0.0f;
                    if (hasDepth && has_history && !wrs_rule_is_oracle(rule) &&
                        wrs_depth_flush(h.z, c.z, dz, params.tuning.y))
                        has_history = false;
                    // As retain.comp: a kept sample shows the tent-weighted mean of the tracked
                    // samples of its quality (wrs_shown_add); the oracle judges that.
                    vec3 h_shown = has_history && c.moved
                                       ? wrs_shown_color(tap[0], tap[1], tap[2], tap[3], base, pos, h, c.z, dz,
                                                         params.tuning.y)
                                       : h.color;
                    float rnd = wrs_rand(x, y, eye, frame, seed);
                    Trace& t = trace_[eye][idx];
                    Tracked hd = h;
                    if (wrs_rule_is_oracle(rule)) hd.color = h_shown;
                    // The oracles of a frame submitted foveated compare with its full-resolution reference.
                    vec3 truth = vec3(ref);
                    if (wrs_rule_is_oracle(rule) && mode == WRS_FOV_SUBMITTED && in.reference) {
                        truth = vec3(wrs_decode_input(asFetched(in.reference->fetch(x, y), ep.ref_rect.z), ep.ref_rect.z));
                    }
                    Tracked r = wrs_retain(rule, has_history, hd, d, c, truth, rnd, t.outcome, t.margin);
                    if (t.outcome == WRS_OUT_KEPT) r.color = h.color;
                    if (!wrs_rule_is_oracle(rule) && t.outcome == WRS_OUT_KEPT)
                        h_shown = wrs_kept_shown(h_shown, c.lo, c.hi, wrs_mode_simulated(mode) && uint(lv.x) == 0u);
                    res_[eye][idx] = wrs_pack_tracked(r, wrs_offset_dither(frame, seed));
                    if (r.q > 0.0f) heldCur[tileOf(p)] = std::max(heldCur[tileOf(p)], r.q);
                    t.hadHistory = has_history;
                    t.keep = t.outcome == WRS_OUT_KEPT || t.outcome == WRS_OUT_MERGED;
                    t.rnd = rnd;
                    t.source = q.y * W + q.x;
                    vec3 shown = t.outcome == WRS_OUT_KEPT ? h_shown : r.color;
                    // As retain.comp: a gap between unevenly drifted kept samples shows the kept
                    // neighbourhood where the rule keeps a sharper sample (wrs_track_gap, wrs_gap_shows).
                    Tracked hg;
                    vec2 dg;
                    uvec2 qg;
                    const bool gap = !found && c.moved && on_screen && !wrs_rule_is_oracle(rule) &&
                                     wrs_track_gap(ts, hg, dg, qg) &&
                                     !(hasDepth && wrs_depth_flush(hg.z, c.z, dz, params.tuning.y)) &&
                                     wrs_gap_shows(hg, c);
                    if (gap)
                        shown = wrs_kept_shown(wrs_shown_color(tap[0], tap[1], tap[2], tap[3], base, pos, hg, c.z,
                                                               dz, params.tuning.y),
                                               c.lo, c.hi, wrs_mode_simulated(mode) && uint(lv.x) == 0u);
                    t.gapShown = gap;
                    // As retain.comp: under motion, the landed samples kept shown as one reconstruction
                    // (wrs_landed_shown), with the taps' display weights.
                    if (mode == WRS_FOV_SUBMITTED && ep.motion_rect.z != 0u && !wrs_rule_is_oracle(rule) && c.moved &&
                        on_screen) {
                        const vec4 w = wrs_shown_weights(tap[0], tap[1], tap[2], tap[3], base, pos, c.z, dz,
                                                         params.tuning.y);
                        shown = wrs_landed_shown(tap[0], tap[1], tap[2], tap[3], w, t.outcome == WRS_OUT_KEPT || gap,
                                                 gap ? hg : h, r, ep.tile.w, c, shown);
                    }
                    if (display) {  // as retain.comp's display()
                        if (filters) {
                            uvec2 i0, i1;
                            vec2 f;
                            const bool has = displayHistory && wrs_taa_reproject(p, size0, mv, i0, i1, f) &&
                                             prevDisplay[idx].w != 0.0f;
                            vec3 hist(0.0f);
                            if (has) {  // resampled with Lanczos-2, as retain.comp
                                TaauGather hg = wrs_taau_gather_start();
                                const vec4 wx = wrs_history_weights(f.x), wy = wrs_history_weights(f.y);
                                for (uint j = 0; j < 16u; ++j) wrs_history_add(hg, vec3(displayAt(wrs_history_tap(i0, size0, j))), wx, wy, j);
                                hist = wrs_history_result(hg);
                            }
                            vec3 mu, sigma;
                            wrs_moments_of_nine(m1, m2, mu, sigma);
                            const float alpha = wrs_display_weight(params.tuning.z, mv, uintBitsToFloat(ep.display.y));
                            shown = wrs_display_fold_step(mu, sigma, shown, hist, has, alpha);
                        }
                        display_[eye][idx] = vec4(wrs_unpack_shown(wrs_pack_shown(shown)), 1.0f);
                    }
                    glm::u8vec4 o = encodeOutput(shown);
                    std::memcpy(out_[eye].data.data() + idx * 4, &o, 4);
                }
            held_[eye] = sparse ? std::move(heldCur) : std::vector<float>{};
            continue;
        }

        // Pass 3: temporal WRS as published (wrs-paper).
        trace_[eye].assign(std::size_t(W) * H, Trace{});
        for (uint y = 0; y < H; ++y)
            for (uint x = 0; x < W; ++x) {
                uvec2 p(x, y);
                std::size_t idx = std::size_t(y) * W + x;
                vec4 cand = cand_[eye][idx];
                float z_cur = hasDepth ? zlin[idx] : 0.0f;
                uvec2 q = p;
                float dz = 0.0f;
                bool on_screen = true;
                if (hasMotion)
                    on_screen = wrs_reproject(p, size0, vec3(in.motion->fetch(x, y)) * vec3(ep.motion_scale), q, dz);
                Reservoir hist = wrs_unpack(prev_[eye][std::size_t(q.y) * W + q.x]);
                bool has_history = on_screen && wrs_reservoir_valid(hist);
                if (hasDepth && has_history && wrs_depth_flush(hist.z, z_cur, dz, params.tuning.y)) has_history = false;
                float rnd = wrs_rand(x, y, eye, frame, seed);
                bool keep;
                Reservoir r = wrs_combine(has_history, hist, vec3(cand), cand.w, z_cur, rnd, uint(config_.change),
                                          config_.bernoulli, keep);
                res_[eye][idx] = wrs_pack(r);
                Trace& t = trace_[eye][idx];
                t.hadHistory = has_history;
                t.keep = keep;
                t.rnd = rnd;
                t.source = q.y * W + q.x;
                if (has_history) {
                    float change = wrs_change(uint(config_.change), vec3(cand), hist.color);
                    t.threshold = wrs_keep_threshold(
                        wrs_biased_history_weight(hist.w_sum, cand.w, change, config_.bernoulli), cand.w);
                }
                glm::u8vec4 o = encodeOutput(r.color);
                std::memcpy(out_[eye].data.data() + idx * 4, &o, 4);
            }
    }
    history_ = wrs || taa || retain;
    displayed_ = retain && params.tuning.z > 0.0f;
}

}  // namespace wrsfov
