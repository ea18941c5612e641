// CPU reference of the whole per-eye pipeline, built on the same shared header as the shaders
// (shaders/wrs_common.h). Tests compare the GPU against it pixel by pixel.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "compositor/compositor.h"
#include "wrsfov/image.h"
#include "shaders/compose_params.h"
#include "shaders/wrs_params.h"

namespace wrsfov {

class Reference {
public:
    /// One eye's submitted images, already cut to the view rectangle (W x H of the frame).
    struct EyeInput {
        HostImage color;
        std::optional<HostImage> depth;
        std::optional<HostImage> motion;
        /// Submitted foveation: each pixel's rendered quality (W*H), and `color`, `depth`, `motion`
        /// what the compose pass makes of the submission (composeQuadViews, rateMapQualities). Empty
        /// for a full-resolution frame.
        std::vector<float> quality;
        /// Quad views with landed samples (ComposeEye::landed.z): each pixel's landed wide sample as the
        /// compose pass stores it (wrs_unpack_landed: colour, quality; W*H). Empty otherwise.
        std::vector<glm::vec4> landed;
        /// With `landed`, of method wrs: the footprint overlap of each pixel's landed sample (its weight
        /// under landed weights, wrs_landed_weight; 0 where none landed).
        std::vector<float> landedOverlap;
        /// With `landed`, of method wrs: where each pixel's landed sample lies from its centre, where
        /// retention stores it (wrs_landed_position, output pixels).
        std::vector<glm::vec2> landedPosition;
        /// Submitted foveation, the oracles: the full-resolution reference (ProjectionView::reference).
        std::optional<HostImage> reference;
    };
    /// What the combine decided at one pixel, and how close it was.
    struct Trace {
        bool hadHistory = false;
        bool keep = false;
        float rnd = 0;
        float threshold = 0;  ///< history kept iff rnd <= threshold (wrs_keep_threshold)
        uint32_t source = 0;  ///< pixel index the history was read from (after reprojection)
        /// Methods wrs and oracle: the outcome (WRS_OUT_*) and how close its deciding comparison
        /// was to the threshold, relative (wrs_retain).
        uint32_t outcome = 0;
        float margin = 1.0f;
        /// wrs: the lookup found no sample, but a kept sample within a pixel (a gap between unevenly
        /// drifted samples, wrs_track_gap) is shown; the candidate is stored.
        bool gapShown = false;
        /// Sparse retention skipped the pixel's tile: it shows its candidate and stores nothing.
        bool skipped = false;
    };

    explicit Reference(const CompositorConfig& config) : config_(config) {}

    /// Runs load, pyramid, foveate and the temporal pass of the configured method for both eyes.
    void step(const gpu::FrameParams& params, const std::array<EyeInput, 2>& eyes);

    void setConfig(const CompositorConfig& config) { config_ = config; }
    void resetHistory() { history_ = false; }
    /// The steady display's colour after the last step (linear RGB, alpha 1; W*H; empty where it did not run).
    const std::vector<glm::vec4>& displayed(uint32_t eye) const { return display_[eye]; }
    /// Replaces the steady floor the next step reads as its history (Compositor::readSteadyFloor).
    void setSteadyFloor(uint32_t eye, std::vector<glm::vec4> steady) { steady_[eye] = std::move(steady); }
    /// The steady floor after the last step (empty where it did not filter the floor).
    const std::vector<glm::vec4>& steadyFloor(uint32_t eye) const { return steady_[eye]; }
    /// Replaces the history the next step reads (packed reservoirs, W*H) and, for sparse retention,
    /// the held quality of each tile (Compositor::readTileHeld; empty: every tile may hold anything).
    void setHistory(uint32_t eye, std::vector<glm::uvec4> packed, std::vector<float> held = {});

    const std::vector<glm::uvec4>& reservoirs(uint32_t eye) const { return res_[eye]; }
    const HostImage& output(uint32_t eye) const { return out_[eye]; }
    const std::vector<Trace>& trace(uint32_t eye) const { return trace_[eye]; }
    /// Sparse retention: the held quality of each tile after the last step (row-major; 0: stored
    /// nothing); empty when the step did not run sparse retention.
    const std::vector<float>& tileHeld(uint32_t eye) const { return held_[eye]; }
    /// Sparse retention with motion: the far tiles of both eyes whose motion the last step's
    /// classification read (FrameStats::motionTiles).
    uint32_t motionTiles() const { return motionTiles_; }
    /// Foveated colour (linear RGB) and weight p̂ per pixel.
    const std::vector<glm::vec4>& candidates(uint32_t eye) const { return cand_[eye]; }

private:
    CompositorConfig config_;
    bool history_ = false;
    std::array<std::vector<glm::uvec4>, 2> prev_, res_;
    std::array<std::vector<float>, 2> held_;
    std::array<std::vector<glm::vec4>, 2> steady_;
    // The steady display's colour after the last step (where it ran: displayed_), as the Display buffer.
    std::array<std::vector<glm::vec4>, 2> display_;
    bool displayed_ = false;
    uint32_t motionTiles_ = 0;
    std::array<std::vector<glm::vec4>, 2> cand_;
    std::array<std::vector<Trace>, 2> trace_;
    std::array<HostImage, 2> out_;
};

/// One eye's quad views as submitted, each image cut to its rectangle (the wide view's W x H of the
/// view, the inset's its own size).
struct QuadSources {
    HostImage wideColor;
    std::optional<HostImage> wideDepth, wideMotion;
    HostImage insetColor;
    std::optional<HostImage> insetDepth, insetMotion;
};
/// What the compose pass (shaders/compose.comp) makes of one eye's quad views: the composed colour
/// (RGBA16F, validity in alpha), depth (R32F) and motion (RGBA16F, output pixels) at the output size,
/// and each pixel's quality: the Reference's input for that eye.
Reference::EyeInput composeQuadViews(const gpu::ComposeParams& params, uint32_t eye, const QuadSources& sources);
/// The qualities the compose pass gives one eye's pixels from its rate map (R8UI, cut to its rectangle).
std::vector<float> rateMapQualities(const gpu::ComposeParams& params, uint32_t eye, const HostImage& map);

/// Encodes linear RGB for the RGBA8 output exactly as the GPU store does (sRGB, round to nearest).
glm::u8vec4 encodeOutput(glm::vec3 linear);

}  // namespace wrsfov
