// What an integrator chooses: the method, how a full-resolution frame is foveated, the fovea's size
// and the random seed (Settings, for StereoCompositor). The enums are the compositor's own; the
// evaluation build's CompositorConfig (compositor/compositor.h, not installed) holds them with the
// research switches beside.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

namespace wrsfov {

/// fov: foveation only; fovTaa: foveation + TAA baseline (Karis/Salvi); wrsPaper: foveation + WRS
/// as published (eq. 6 + eq. 7); wrs: foveation + quality-aware retention (shaders/wrs_retention.h, the
/// default); oracle: keeps whichever of history and candidate is closer to the submitted
/// (unfoveated) colour, the ceiling of any keep-or-replace rule with wrs's reprojection; oracleQ:
/// the oracle restricted to retention, keeping the history only when it is closer and of higher
/// quality than the candidate (the ceiling of keeping what foveation throws away, without choosing
/// among equally sharp samples). The oracles exist for evaluation only: they need the full-rate
/// image, which a foveated renderer never has (StereoCompositor refuses them). taau: temporal upsampling
/// of jittered wide views as engines ship it, after FSR 2's published design (quad views; wrs_taau_step,
/// docs/retention.md "The field's baseline: taau"): a Lanczos-2 reconstruction of the wide samples, depth
/// disocclusion, a clamp box of the wide samples that shrinks with velocity, luma-stability-weighted
/// history and thin-feature locks, composed with the inset as fov is; on other frames TAA by accumulated
/// weight. taauSimple: the project's first temporal upsampler (wrs_taau_simple_step): the four samples of
/// the pixel's bilinear cell, a wide variance clip, no disocclusion, kept for comparison.
enum class Method : uint8_t { Fov, FovTaa, WrsPaper, Wrs, Oracle, OracleQ, Taau, TaauSimple };
/// The temporal upsamplers (taau, taau-simple).
constexpr bool isTaau(Method m) { return m == Method::Taau || m == Method::TaauSimple; }
/// The evaluation-only methods (Oracle, OracleQ).
constexpr bool isOracle(Method m) { return m == Method::Oracle || m == Method::OracleQ; }

/// Values equal the shader constants WRS_FOV_*. None, Mip and Gauss are configuration values: how a
/// full-resolution frame is foveated. Submitted is what the compositor runs a frame with that came
/// foveated already (quad views or a rate map, layers/frame.h), whatever the configured mode; it is
/// not a configuration value (refused where one is set).
enum class FoveationMode : uint8_t { None = 0, Mip = 1, Gauss = 2, Submitted = 3 };

/// "fov", "fov+taa", "wrs-paper", "wrs", "oracle", "oracle-q", "taau", "taau-simple".
std::string_view toString(Method m);
/// The inverse of toString(Method); nullopt for anything else.
std::optional<Method> parseMethod(std::string_view name);
/// "none", "mip", "gauss" ("submitted" for Submitted).
std::string_view toString(FoveationMode m);
/// "none", "mip", "gauss"; nullopt for anything else.
std::optional<FoveationMode> parseFoveationMode(std::string_view name);

/// A StereoCompositor's settings. Every other value is the compositor's default (the figures of
/// docs/measurements.md were measured with them).
struct Settings {
    Method method = Method::Wrs;
    /// How a full-resolution frame is foveated (mip, gauss, or none). Frames submitted foveated (quad
    /// views, rate maps) are composed as they come, whatever this says.
    FoveationMode foveation = FoveationMode::Mip;
    /// Fovea diameter in degrees, in (0, 180].
    float foveaDeg = 5.0f;
    /// The sequence of random choices (reservoir sampling); the same seed, frames and gaze give the same output.
    uint32_t seed = 1;
    /// Quad views, `wrs`: offer the wide sample nearest each output pixel to retention (docs/retention.md
    /// "Landed wide samples"). It assumes the wide views sample texture detail at the display's density
    /// (a LOD bias of log2 of their density), as temporal upsampling does; an application that filters
    /// its wide views over their own pixels turns it off.
    bool landedSamples = true;
};

}  // namespace wrsfov
