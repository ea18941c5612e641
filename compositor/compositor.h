// The stereo compositor: takes a frame end (layers/frame.h), runs the per-eye passes on the GPU,
// both eyes in one dispatch per pass, and keeps the output and the reservoirs.
//
// Passes, in the order they run (shaders/); level 0 and linear depth are never stored, each pass
// decodes the submitted images where it reads them:
//   -. compose  – frames submitted foveated only (quad views, rate maps; compose.h): quad views into
//                 output-sized colour, depth and motion that the passes below read instead, and each
//                 pixel's rendered quality; the passes then run with foveation FoveationMode::Submitted
//   0. classify – (CompositorConfig::skipTiles) 8x8 tiles onto the lists of their class (fovea, mid,
//                 far, any); passes 2 and 2+3 then run one indirect dispatch per class
//   1. pyramid  – levels 1..4 from the submitted colour, fp16 (box for `mip`, all levels in one
//                 dispatch; [1 3 3 1] Gaussian for `gauss`, one dispatch per level; skipped for `none`)
//   2. foveate  – eccentricity, foveated colour, weight p̂ (method `fov` writes the output here)
//   3. wrs      – reprojection, depth flush, biased combine, reservoir store, output (`wrs-paper`)
//      or taa   – reprojected history clipped to the neighbourhood's variance box (method `fov+taa`)
//   2+3. retain – foveation fused with quality-aware retention (`wrs`, `oracle`, `oracle-q`): no
//                 candidate buffer; the pyramid is built for every foveation mode (fingerprint)
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "compositor/compose.h"
#include "wrsfov/image.h"
#include "compositor/vk_context.h"
#include "layers/frame.h"
#include "layers/status.h"
#include "layers/swapchain.h"
#include "shaders/wrs_common.h"
#include "shaders/compose_params.h"
#include "shaders/wrs_params.h"
#include "wrsfov/settings.h"
#include "wrsfov/submission.h"

namespace wrsfov {

/// A pipeline's specialisation constants: 0..6 the pass's own (compose.comp: 0..5), 7 HARDWARE_HALF and
/// 8 TRACK_BIRTH (every pass but compose; the compositor sets them), 9 INPUT_ENCODING (the passes that read
/// the submitted colour; shaders/bindings.glsl), 10 and 11 the pass's own again (retain.comp: DISPLAY, WIDE_ENCODING).
using SpecConstants = std::array<uint32_t, 12>;
struct PassDispatch;           // compositor/pass_table.h
enum class Barrier : uint8_t;  // compositor/pass_table.h

/// Methods whose foveation and retention run fused in the retain pass (wrs and the oracles).
constexpr bool usesRetainPass(Method m) { return m == Method::Wrs || isOracle(m); }
/// What `wrs` does with a candidate of the same quality as the kept sample (shader WRS_RULE_*).
enum class EqualQuality : uint8_t { Merge = 0, Reservoir = 1 };
/// Whether a mode foveates a full-resolution frame itself (mip, gauss): levels, tile classes, a floor.
constexpr bool simulatesFoveation(FoveationMode m) { return m == FoveationMode::Mip || m == FoveationMode::Gauss; }
/// Values equal the shader constants WRS_CHANGE_*.
enum class ChangeMetric : uint8_t { Off = 0, LStar = 1, DeltaE94 = 2 };

std::string_view toString(EqualQuality e);
std::string_view toString(ChangeMetric m);

/// Refusal of a configuration (Compositor::create, Compositor::setConfig).
enum class ConfigError : int { InvalidValue = 100 };

/// The compositor's whole configuration: what an integrator sets (Settings, wrsfov/settings.h) and the
/// switches the evaluation and its studies vary (the published rule's terms, tile skipping, sparse
/// retention, the steady floor and display, birth tracking, copy-kernel timing, the parameters of
/// `taau`). This header is the evaluation build's and the project's own programs'; it is not installed.
/// An integrator's program uses StereoCompositor (wrsfov/stereo_compositor.h).
struct CompositorConfig {
    Method method = Method::Wrs;
    FoveationMode foveation = FoveationMode::Mip;
    float foveaDeg = 5.0f;           ///< fovea diameter in degrees (r_f = foveaDeg / 2)
    float midPeripheryDeg = 15.0f;   ///< mid-periphery diameter (r_m = 7.5°)
    float fallbackFoveaDeg = 20.0f;  ///< fovea diameter used while gaze is invalid (view centre)
    ChangeMetric change = ChangeMetric::LStar;  ///< wrs-paper: the eq. 7 change term
    bool bernoulli = true;           ///< wrs-paper: eq. 6 survival bias of the history
    EqualQuality equalQuality = EqualQuality::Merge;  ///< wrs: equal-quality candidates
    float depthTau = 0.05f;          ///< relative depth difference that flushes history
    /// Motion reach (docs/retention.md "Motion reach"): `wrs` and the oracles track a kept sample only
    /// where the motion moved the pixel at most this many degrees (at the view's centre) per frame
    /// on either axis; faster pixels take their candidate. It bounds where a kept sample can arrive,
    /// so the classification reads the motion only of tiles that have one within reach. 0: no limit.
    float motionReachDeg = 8.0f;
    uint32_t seed = 1;
    /// After every frame, time two copy kernels, each alone in a submission: one moving the frame's
    /// traffic (trafficBytes), one the method's floor (floorBytes): the yardsticks benchmarks report against.
    bool measureCopy = false;
    /// Evaluation (wrs-paper, wrs, oracle): keep per pixel the submitted colour at the time the
    /// shown sample was taken (merged as the samples are), readable with readBirth(), so a
    /// benchmark can find pixels showing a sample whose scene has changed since. 32 B/px more.
    bool trackBirth = false;
    /// Methods `fov`, `wrs` and `oracle` with foveation `mip` or `gauss`: 8x8 tiles whose pixels all
    /// get the same pyramid levels (fovea, mid-periphery, far periphery) run in a dispatch of their
    /// own that computes no eccentricity (docs/speed.md "Tiles"). The output is the same bit for
    /// bit either way; off runs every pixel through the per-pixel path (bench and preview --no-skip).
    bool skipTiles = true;
    /// Sparse retention (docs/retention.md "Sparse retention"; `wrs` and `oracle-q` with skipTiles and
    /// foveation `mip` or `gauss`): far tiles where no sample sharper than the floor quality can be
    /// held run the foveating pass alone, with no reservoir traffic, so retention's cost follows
    /// the area the gaze has visited. The output is the same bit for bit either way; the reservoirs
    /// differ only in skipped tiles, which store nothing (readReservoirs shows them empty).
    bool sparseRetention = true;
    /// `wrs`: merge equal-quality samples at the floor quality too (the far periphery), as before sparse
    /// retention: a running mean of the level-4 candidates that smooths their flicker under motion,
    /// at the price of retention in every far tile (no sparse retention). Off (the default): the floor
    /// rule takes the candidate there (docs/retention.md "Sparse retention").
    bool floorMerge = false;
    /// Where the floor rule applies (steadyFloorActive): level 4, the far periphery's candidate, is
    /// filtered over time at its own resolution (16x16 pixels a texel) before any pass samples it, as
    /// TAA filters pixels: reprojected with the motion at each texel's centre, clipped to its 3x3
    /// neighbourhood's variance box (docs/retention.md "The steady floor"). It steadies what the floor
    /// rule shows under motion (temporal instability 3-37 % lower on pans), as the merge at the floor
    /// did, for 1/256 of the pixels' work, but softens the far periphery, and FovVideoVDP scores it
    /// 0.02-0.08 JOD lower than without; off by default.
    bool steadyFloor = false;
    /// Convert to fp16 for storage (pyramid, reservoirs) with the device's own instruction where the
    /// first compositor on the context found it exact on every value the passes give it (values already
    /// rounded to fp16's grid by hand, wrs_store_f16): the same bits, a fraction of the arithmetic. Off:
    /// always by hand.
    bool hardwareHalf = true;
    /// Quad views (layers::InsetView): width in inset pixels of the band inside the inset's edge over
    /// which the output blends from the wide view to the inset (and the quality from the wide view's to
    /// 1). 0: a hard edge.
    float insetBlendPx = 8.0f;
    /// Quad views, `wrs`: the wide sample nearest each output pixel's centre is offered to retention
    /// as a candidate of its own where its footprint covers a quarter of the pixel, all such samples of
    /// one quality (wrs_landed_quality; docs/retention.md "Landed wide samples"), so that reservoirs
    /// gather the wide views' samples a jittered (or moving) sample lattice places near each pixel. It assumes, as temporal upsampling does, that the wide
    /// views sample texture detail at the display's density (a LOD bias of log2 of their density); an
    /// application that filters its wide views over their own pixels should turn it off.
    bool landedSamples = true;
    /// Quad views, `wrs`, on a frame whose wide views were jittered: no floor rule, so that a pixel's
    /// wide candidates of equal quality merge over the phases, the history clipped to the wide view
    /// around the pixel (docs/retention.md "Every phase merged"), instead of each phase being taken
    /// fresh. Such a frame skips no tile (sparse retention has nothing to skip there). It runs on the
    /// frames that offer landed samples (landedSamples on), whose classes it merges too.
    bool phaseMerge = true;
    /// Quad views, `wrs`, with landed samples: each landed sample weighs into the running mean of its
    /// class by its footprint's overlap with the pixel, (1 - |dx|)(1 - |dy|), rather than equally
    /// (wrs_landed_weight; docs/retention.md "Landed weights"): a tent-filtered estimate of the pixel in
    /// place of the plain mean of everything within 3/4 of a pixel. Off by default until the
    /// moving-content study has run with it (`wrsfov-bench --landed-weights`).
    bool landedWeights = false;
    /// Quad views, `wrs`: the half-width of a landed wide sample's footprint in wide pixels, at least one
    /// output pixel (wrs_landed_scale; docs/retention.md "`wrs`'s parameters, searched on the training cell"): a sample is offered to the
    /// pixels whose tent of that half-width it overlaps by a quarter or more. In [0, 1]; 0: one output
    /// pixel at every density. 0.3 was chosen on the moving-content study's training cell: one output
    /// pixel at 0.3 of the density, 1.5 at 0.2.
    float landedFootprint = 0.3f;
    /// Quad views, `wrs`, on frames that offer landed samples (landedSamples on): the steady display
    /// (wrs_display_fold_step, in the retain pass; docs/retention.md "Steady display"). What retention shows
    /// at a pixel of the wide views is filtered over time as TAA filters a frame, the display's previous
    /// colour reprojected with the motion and clipped to the wide view around the pixel; this is the weight
    /// of the current frame, in [0, 1] (0: off; the default is shaders/wrs_submitted.h's WRS_DISPLAY_ALPHA,
    /// which a test checks). Display only: the reservoirs do not change. Its history is 32 B/px of memory
    /// (two slots), 16 B/px of traffic; with it no tile skips retention on quad views.
    float steadyDisplay = 0.3f;
    /// The steady display's full speed, in output pixels a frame (wrs_display_weight): up to it the current
    /// frame weighs steadyDisplay; a pixel that moves faster weighs steadyDisplay * speed / |motion|, down to
    /// half of steadyDisplay (WRS_DISPLAY_FAST_SHARE), so the display averages a fast turn over more frames
    /// than a slow one. 0: the weight is
    /// steadyDisplay at every speed. In [0, 1024]; the default is shaders/wrs_submitted.h's
    /// WRS_DISPLAY_FULL_SPEED, which a test checks.
    float steadyDisplaySpeed = 1.0f;
    /// Method taau-simple's parameters (docs/retention.md "The first baseline: taau-simple", chosen for its
    /// best JOD on the headset cell): the gather kernel's radius in output pixels, the cap of the history's
    /// accumulated weight (a sample at a pixel's centre weighs 1), and the history's clip box in sigmas
    /// of the composed neighbourhood.
    struct TaauSimple {
        float radius = 1.25f;
        float maxWeight = 2.0f;
        float clipGamma = 20.0f;
    } taauSimple;
    /// Method taau's parameters (wrs_taau_step; docs/retention.md "The field's baseline: taau"): the
    /// Lanczos-2 kernel's scale in wide pixels (1: the wide views' own resolution), the cap of the history's
    /// accumulated weight (a sample at a wide texel's centre weighs 1), the clamp box in sigmas of the wide
    /// samples around the pixel when still, the motion (output pixels a frame) at which the box has shrunk to
    /// one sigma, a thin-feature lock's lifetime in frames and the luma contrast (relative) that sets one,
    /// and how strongly an oscillating luma weighs a new sample down (0: not at all). The defaults are the
    /// best JOD of a 21-point search on a training cell (docs/retention.md, "The field's baseline: taau").
    struct Taau {
        float kernel = 0.35f;
        float maxWeight = 1.5f;
        float boxSigma = 6.0f;
        float fullVelocity = 8.0f;
        float lockFrames = 8.0f;
        float lockThreshold = 0.2f;
        float stability = 0.0f;
    } taau;
};
/// An integrator's Settings as the compositor's configuration (every other field its default), as
/// StereoCompositor runs them; refused (ConfigError::InvalidValue) for the evaluation-only methods.
Result<CompositorConfig> compositorConfig(const Settings& settings);
/// The retention rule (shader WRS_RULE_*) the retain pass runs for a method with usesRetainPass:
/// the oracle's, the retention oracle's, or `wrs`'s equal-quality rule.
uint32_t retainRule(const CompositorConfig& c);
/// True where the environment sets WRSFOV_HARDWARE_HALF=0: every compositor then stores fp16 with the
/// hand conversion, whatever CompositorConfig::hardwareHalf and the probe say.
bool handHalfForced();
/// The floor rule's quality of a config (wrs_rule_floor; 0 for methods without the retain pass).
float floorQuality(const CompositorConfig& c);
/// Whether frames with config `c` run sparse retention (CompositorConfig::sparseRetention and what it needs).
bool runsSparse(const CompositorConfig& c);
/// Whether frames with config `c` filter the floor level over time (CompositorConfig::steadyFloor
/// where the floor rule applies: floorQuality > 0).
bool steadyFloorActive(const CompositorConfig& c);
/// Whether frames with config `c` may run the steady display (CompositorConfig::steadyDisplay; `wrs` on
/// frames submitted foveated with landed samples: it runs where they are quad views).
bool displayActive(const CompositorConfig& c);
/// On quad views, what the compose pass writes beside the composed images (its LANDED constant,
/// shaders/compose.comp): 2 the gathered wide samples (`taau`), 1 the landed wide samples (`wrs` with
/// landedSamples, for each eye whose wide view is sparser than the output), 0 nothing.
uint32_t composeLanded(const CompositorConfig& c);

/// Which passes a frame runs, and how. One pure function of the frame's configuration (foveation
/// Submitted for a frame submitted foveated) and inputs serves Compositor::endFrame, which records
/// these passes, traffic(), which counts their bytes, and eval::pipelineVariants, which lists their
/// pipelines for the cost model.
struct PassPlan {
    bool retain = false;    ///< the retain pass (wrs, the oracles), foveation fused into it
    bool wrsPaper = false;  ///< the published WRS pass after the foveating pass
    bool taa = false;       ///< fov+taa's pass after the foveating pass
    bool temporal = false;  ///< a pass with history in the reservoir buffers
    bool pyramid = false;   ///< levels 1..4: simulated foveation, or retain's fingerprint level
    bool tiled = false;     ///< the classification first, then per-pixel passes per tile class
    bool sparse = false;    ///< sparse retention: far tiles with nothing sharper in reach skip it
    bool inPlace = false;   ///< reservoirs updated in place (retain without motion or birth buffers)
    bool steady = false;    ///< the steady floor after the pyramid
    /// The steady display after the retain pass (CompositorConfig::steadyDisplay), where the frame's quad
    /// views offer landed samples: a frame of another kind does not run it (Compositor::planFrame).
    bool display = false;
};
/// `hasMotion`: the frame's views carry motion; `birth`: birth buffers exist (stale tracking); `quad`: the
/// frame comes as quad views that offer landed samples (where the steady display runs, folded into the
/// retain pass).
PassPlan planPasses(const CompositorConfig& c, bool hasMotion, bool birth, bool quad = false);

/// GPU time of each pass for both eyes together, in milliseconds (valid = false when not measured).
/// On a CPU device (Mesa lavapipe) timestamps do not bracket the dispatches between them: a pass's
/// time lands in a later interval, and a lone dispatch reads as almost free (a 14 MB copy stamped
/// 0.08 ms that takes 2 ms). There `total` and the copies are the host's wall-clock time from submission
/// to completion (`hostTimed`), which for a CPU driver is the work itself; per-pass values stay
/// timestamps and only say where work was recorded. On GPUs every value is a timestamp difference.
struct PassTimes {
    double pyramid = 0, foveate = 0, temporal = 0, total = 0;  ///< temporal: the wrs, taa or retain pass
    double copy = 0;       ///< copy kernel moving the frame's traffic (CompositorConfig::measureCopy)
    double copyFloor = 0;  ///< copy kernel moving the method's floor bytes (measureCopy)
    bool valid = false;
    bool hostTimed = false;  ///< total and copies are host wall-clock times (CPU device)
    /// Quad views and rate maps: the compose pass, with the classification recorded after it (tiled frames).
    double compose = 0;
};

/// What one view of a frame gives the passes: size and bytes per texel of each submitted image
/// (0 where the view has none).
struct TrafficInputs {
    uint32_t width = 0, height = 0;
    uint32_t colorBytes = 4, depthBytes = 0, motionBytes = 0;
    /// Sparse retention (runsSparse): the share of tiles that ran retention, and the share of tiles
    /// whose motion the classification read (FrameStats::retainShare, motionShare; mean over frames
    /// in a bench).
    double retainShare = 1.0, motionShare = 0.0;
    /// Frames submitted foveated: bytes per output pixel the compose pass reads and writes (0 for a full
    /// frame); its per-pixel quality (4 B) is then read by the foveating or retain pass.
    double composeRead = 0, composeWrite = 0;
    /// How the passes read the colour (gpu::WRS_INPUT_*: the composed images for a frame submitted
    /// foveated), and how the compose pass reads the wide views' and the insets' colour; WRS_INPUT_ANY
    /// where the two eyes differ (or it is not known).
    uint32_t colorEncoding = gpu::WRS_INPUT_ANY, wideEncoding = gpu::WRS_INPUT_ANY, insetEncoding = gpu::WRS_INPUT_ANY;
    /// Quad views: bytes per output pixel of the wide views' colour (their texels once).
    double wideColorRead = 0;
    /// Quad views: the share of both eyes' 8x8 groups of output pixels in which the compose pass reads
    /// the inset (insetGroups, compositor/input.h).
    double insetShare = 0;
};
/// What a frame gives the passes (the left view's sizes and formats; for quad views the output size and
/// the composed images' formats, with the compose pass's own traffic).
TrafficInputs trafficInputs(const layers::ProjectionLayer& layer);
/// Bytes one pass reads and writes per pixel of one view, from its bindings and formats
/// (shaders/bindings.glsl), each texel of each binding counted once: the memory traffic of the pass
/// with caches that hold a neighbourhood (bilinear, 2x2 and 3x3 taps), not the number of loads.
struct PassTraffic {
    std::string pass;
    double read = 0, write = 0;
};
struct Traffic {
    std::vector<PassTraffic> passes;
    /// What the method cannot avoid: the colour in and the output out, and for methods with history
    /// the reservoir read and written (2 x 16 B) and the depth and motion they use.
    double floor = 0;
    double perPixel() const;  ///< all passes, read + write, per pixel of one view
};
Traffic traffic(const CompositorConfig& config, const TrafficInputs& in);
/// Traffic of a whole frame (both views), in bytes: what the copy kernel moves, half read, half written.
uint64_t trafficBytes(const CompositorConfig& config, const TrafficInputs& in);
uint64_t floorBytes(const CompositorConfig& config, const TrafficInputs& in);

struct FrameStats {
    uint64_t frameIndex = 0;
    PassTimes gpu;
    bool gazeFallback[2] = {false, false};  ///< gaze was invalid: view centre + fallback fovea
    bool usedDepth = false;
    bool usedMotion = false;
    bool historyReset = false;  ///< this frame started without history (first frame, size/method change)
    /// Both views were the same (same images, field of view and gaze): the passes ran for the left
    /// eye only and its output and history were copied to the right eye.
    bool monoViews = false;
    /// `wrs` or the oracle without motion (and without stale tracking): the reservoirs were updated in
    /// place and only pixels whose reservoir changed were stored.
    bool inPlace = false;
    /// The foveating pass ran per tile class (CompositorConfig::skipTiles and a method and mode
    /// that have classes).
    bool tiled = false;
    /// The retain pass ran (usesRetainPass).
    bool retained = false;
    /// Sparse retention ran (runsSparse).
    bool sparse = false;
    /// The floor level was filtered over time (steadyFloorActive).
    bool steadyFloor = false;
    /// The steady display ran (CompositorConfig::steadyDisplay; quad views offering landed samples).
    bool steadyDisplay = false;
    /// The frame merged its wide candidates over the phases (CompositorConfig::phaseMerge: `wrs`, quad
    /// views jittered since the frame before).
    bool phaseMerge = false;
    /// Tiled frames (Wait and Submit modes): tiles of both eyes on each list (WRS_TILE_FOVEA, MID,
    /// FAR, ANY and SKIP), read back after the frame; all zero otherwise.
    std::array<uint32_t, gpu::WRS_TILE_LISTS> tiles{};
    /// Share of the tiles that ran retention (every list but SKIP) in a tiled frame of a method
    /// with the retain pass; 1 where every pixel ran it (or the counts were not read back: Record
    /// mode), 0 for methods without it.
    double retainShare() const;
    /// Share of the tiles on the far and skip lists (0 without counts).
    double farShare() const;
    /// Sparse retention with motion: far tiles of both eyes whose motion the classification read
    /// (the others had no sample sharper than the floor within the motion reach; read back with tiles).
    uint32_t motionTiles = 0;
    /// motionTiles as a share of all tiles (0 without counts).
    double motionShare() const;
    /// Pipelines this frame made (the first use of a variant on its vk::Context) and the host time that
    /// took, inside endFrame: the frame's compile hitch. 0 once every variant the frames use exists.
    uint32_t pipelinesMade = 0;
    double pipelineMs = 0.0;
};

/// Builds the shader parameter block of a frame (gaze fallback included). Used by the compositor
/// and by the CPU reference, so both see the same numbers.
gpu::FrameParams makeFrameParams(const CompositorConfig& config, const layers::FrameEndInfo& frame, uint32_t width,
                                 uint32_t height, bool fallback[2]);

class Compositor {
public:
    static Result<std::unique_ptr<Compositor>> create(vk::Context& context, const CompositorConfig& config = {});
    ~Compositor();

    /// A swapchain whose images live on this compositor's device.
    Result<std::unique_ptr<layers::Swapchain>> createSwapchain(const layers::SwapchainCreateInfo& info,
                                                               const SwapchainImageOptions& options = {});
    /// A swapchain over images someone else made on this compositor's device and keeps owning (an
    /// OpenXR runtime's, seen by an API layer): info.imageCount images of info's format, size and
    /// array size (options.flags: the create flags the owner vouches for), with SAMPLED usage (and
    /// TRANSFER_SRC for read()), initialised and in options.restingLayout whenever the compositor may read them. The
    /// compositor creates views only and destroys nothing else.
    Result<std::unique_ptr<layers::Swapchain>> importSwapchain(const layers::SwapchainCreateInfo& info,
                                                               std::span<const VkImage> images,
                                                               const SwapchainImageOptions& options = {});

    /// Validates and composites one frame (synchronously). A refused frame changes nothing (the error
    /// code is a layers::SubmitError), with one exception: a frame of a new size refused after the
    /// resize (a pipeline the driver could not make) leaves that size, its output black and its
    /// reservoirs empty.
    Status endFrame(const layers::FrameEndInfo& frame);
    /// The same, handing the GPU work over as `submission` says. A submission that cannot be
    /// carried out (Record without a command buffer, semaphores with Record or Wait, a stage count
    /// that is not the semaphore count) is refused with SubmitError::InvalidSubmission.
    Status endFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission);
    /// Waits for the GPU work of the last frame submitted with Mode::Submit (nothing to do
    /// otherwise) and fills stats().gpu. DeviceFailure if the device was lost meanwhile.
    Status waitFrame();

    const FrameStats& stats() const { return stats_; }
    const gpu::FrameParams& lastParams() const { return params_; }
    /// The compose pass's parameters of the last frame (zero unless it came as quad views or rate maps).
    const gpu::ComposeParams& lastComposeParams() const { return composeParams_; }
    /// How the last frame was foveated before it was submitted.
    layers::SubmittedFoveation lastSubmitted() const { return submitted_; }
    const CompositorConfig& config() const { return config_; }
    /// Whether the passes store fp16 with the device's conversion (CompositorConfig::hardwareHalf and
    /// the probe). Fixed at creation.
    bool usesHardwareHalf() const { return hardwareHalf_; }
    /// Takes effect at the next frame; a change of method or foveation resets history. A config
    /// with an out-of-range value is refused here (ConfigError::InvalidValue) and changes nothing.
    Status setConfig(const CompositorConfig& config);
    void resetHistory() { historyValid_ = false; }

    /// The last frame's output of one eye: RGBA8, sRGB-encoded.
    Result<HostImage> readOutput(uint32_t eye);
    /// The reservoirs the last frame wrote (packed, see wrs_common.h), W*H per eye. Tiles that stored
    /// nothing (sparse retention) read as all-zero: no sample.
    Result<std::vector<glm::uvec4>> readReservoirs(uint32_t eye);
    /// The held quality of each 8x8 tile of one eye after the last frame (row-major, float; 0: the tile
    /// stored nothing), as sparse retention's next classification reads it. Empty when the last frame
    /// did not run sparse retention (every tile then counts as holding anything).
    Result<std::vector<float>> readTileHeld(uint32_t eye);
    /// The steady floor the last frame wrote (level-4 texels row-major, linear RGB, alpha 1), which the
    /// next frame reads as its history; empty when the last frame did not filter the floor.
    Result<std::vector<glm::vec4>> readSteadyFloor(uint32_t eye);
    /// CompositorConfig::trackBirth: per pixel of one eye, the linear colour submitted when the
    /// shown sample was taken (W*H, rgb; alpha unused).
    Result<std::vector<glm::vec4>> readBirth(uint32_t eye);
    /// Replaces the history the next frame reads (tests use it to line up with the reference). The
    /// eye's tiles then count as holding anything: the next frame runs retention in all of them.
    Status writeReservoirs(uint32_t eye, const std::vector<glm::uvec4>& packed);
    /// The output image (2 layers, layer = eye), in VK_IMAGE_LAYOUT_GENERAL.
    const vk::Image& outputImage() const { return output_; }
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }

    vk::Context& context() { return ctx_; }

    /// The passes' descriptor set layout (shaders/bindings.glsl); their push constants are a
    /// gpu::LevelPush. The cost model compiles with the same.
    static std::vector<VkDescriptorSetLayoutBinding> passSetBindings();

private:
    explicit Compositor(vk::Context& context) : ctx_(context) {}
    Status init();
    Status resize(uint32_t width, uint32_t height, bool birth, bool display);
    Result<std::vector<glm::uvec4>> readBuffer(const vk::Buffer& buffer, uint32_t eye);
    /// `count` 32-bit words of a buffer from word `first`.
    Result<std::vector<uint32_t>> readWords(const vk::Buffer& buffer, uint64_t first, uint64_t count);
    /// The pipeline of `shader` with the pass's constants (found, or made and shared on the context);
    /// an error naming the shader and constants where the driver cannot make it.
    Result<VkPipeline> pipeline(int shader, const SpecConstants& passConstants);
    /// Records the bind of pipeline(shader, constants); where it cannot be made, or an earlier one of
    /// this recording could not, records nothing, keeps the first error in recordError_ and returns
    /// false (the pass then records nothing more).
    bool bindPipeline(VkCommandBuffer cb, int shader, const SpecConstants& passConstants);
    std::optional<Error> recordError_;
    vk::PipelineTally recordTally_;  ///< the pipelines the frame being recorded made
    /// Runs the device's fp16 conversion over halfProbeValues() and compares it with wrs_f32_to_f16.
    bool probeHardwareHalf();
    bool hardwareHalf_ = false;  // CompositorConfig::hardwareHalf and the probe: pipelines' constant 7
    /// GPU milliseconds of the copy kernel moving `bytes` (half read, half written), alone in a submission.
    double timeCopy(uint64_t bytes);
    Result<HostImage> readImageLayer(uint32_t layer);

    vk::Context& ctx_;
    CompositorConfig config_;
    /// config_ as the current frame runs it: foveation Submitted for a frame that came foveated.
    CompositorConfig frame_;
    layers::SubmittedFoveation submitted_ = layers::SubmittedFoveation::Full;
    FoveationMode lastFoveation_ = FoveationMode::Mip;  // frame_.foveation of the last frame (history)
    gpu::ComposeParams composeParams_{};
    /// Each eye's sample offsets of the last frame planned (wide xy, inset zw): a view whose offset
    /// changed was jittered (EyeParams::motion_rect.w).
    std::array<glm::vec4, 2> lastOffsets_{};
    std::unique_ptr<ComposePass> compose_;
    vk::Buffer quality_;  // submitted foveation: each pixel's rendered quality (binding 15)
    vk::Image dummyUint_;  // bound where a view has no rate map (usampler2D)
    CompositorConfig pending_;
    bool configPending_ = false;
    layers::FrameValidator validator_;
    FrameStats stats_;
    gpu::FrameParams params_{};

    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::DescriptorPool descriptorPool_;
    // Sets 0, 1 ping-pong (set i reads reservoirs[i], writes reservoirs[1-i]); sets 2, 3 update
    // reservoirs[i] in place (FrameStats::inPlace).
    VkDescriptorSet sets_[4] = {};
    vk::DescriptorSetLayout copySetLayout_;
    vk::PipelineLayout copyPipelineLayout_;
    VkDescriptorSet copySet_ = VK_NULL_HANDLE;
    vk::Sampler sampler_;
    vk::QueryPool queries_;
    std::vector<vk::ShaderModule> modules_;
    std::map<std::array<uint32_t, 13>, VkPipeline> pipelines_;  // the context's (Context::sharedPipeline)

    uint32_t width_ = 0, height_ = 0;
    vk::Buffer ubo_;
    vk::Buffer srgbTable_;  // wrs_srgb8_table(), read by load_color
    vk::Buffer pyramid_, candidate_;
    vk::Buffer reservoirs_[2];
    vk::Buffer birth_[2];  // trackBirth: ping-pong like the reservoirs (16 B each when off)
    bool birthAllocated_ = false;
    vk::Buffer copySrc_, copyDst_;  // the copy kernel's buffers (measureCopy)
    vk::Buffer tiles_;              // tile classes: indirect dispatches and tile lists (skipTiles)
    vk::Buffer tileCounts_;         // host-visible copy of the lists' counts (FrameStats::tiles)
    // Sparse retention: per tile and eye the held quality (float bits), two frames' worth: the frame
    // reads the half at heldPrev_ and writes the other one.
    vk::Buffer tileHeld_;
    uint32_t heldPrev_ = 0;
    // The steady floor's two slots after the stored pyramids: the last frame wrote steadySlot_, and
    // steadyValid_ says it did (for both eyes).
    uint32_t steadySlot_ = 0;
    bool steadyValid_ = false;
    // The steady display's history (CompositorConfig::steadyDisplay): two slots of every pixel's displayed
    // colour, allocated with the other buffers where a quad-view frame of `wrs` runs it (16 B otherwise);
    // the last frame wrote displaySlot_, and displayValid_ says it did.
    vk::Buffer display_;
    bool displayAllocated_ = false;
    uint32_t displaySlot_ = 0;
    bool displayValid_ = false;
    // What the half at heldPrev_ says: written by the last frame (Valid), all zero after a history
    // reset (nothing held), or unknown (the last frame did not run sparse retention, or reservoirs were
    // written from outside: the next sparse frame first marks every tile as holding anything).
    enum class Held : uint8_t { Valid, Unknown } held_ = Held::Unknown;
    bool lastSparse_ = false;   // the last frame ran sparse retention
    bool lastTiled_ = false;    // the last frame's tile counts are in tileCounts_
    uint32_t current_ = 0;  // reservoirs_[current_] holds the latest frame's reservoirs
    bool historyValid_ = false;
    vk::Image output_;
    vk::Image dummy_;  // bound where a view has no depth / motion
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    vk::Fence frameFence_;  // signalled by each frame's submission, reset after the wait
    bool inFlight_ = false;  // a Mode::Submit frame not waited for yet
    std::chrono::steady_clock::time_point submittedAt_;
    /// endFrame's stages, in order (compositor.cpp): accept (the frame's refusals; nothing changes),
    /// allocate (buffers of its size: a failed allocation refuses it before any state changed), plan
    /// (configuration, which passes run, the frame's parameters), inputs (its images bound), record,
    /// submit, keep (the history moves on). FrameWork carries the frame from one to the next.
    struct FrameWork;
    Status acceptFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission, FrameWork& work);
    Status allocateFrame(const layers::FrameEndInfo& frame, FrameWork& work);
    void planFrame(const layers::FrameEndInfo& frame, FrameWork& work);
    void bindInputs(const layers::FrameEndInfo& frame, FrameWork& work);
    Result<VkCommandBuffer> recordFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission,
                                        const FrameWork& work);
    /// The frame's commands into `cb` (begun and ended by the caller unless `own`, the compositor's).
    Status recordPasses(VkCommandBuffer cb, bool own, const layers::FrameEndInfo& frame, const FrameWork& work);
    /// Puts back what planFrame and bindInputs changed, for a frame that fails before its submission.
    void restorePlan(const FrameWork& work);
    Status submitFrame(const FrameSubmission& submission, VkCommandBuffer cb, FrameWork& work);
    void keepFrame(const layers::FrameEndInfo& frame, const FrameWork& work);
    /// What a frame runs, decided once in endFrame; each pass records itself from it (recordX, in the
    /// order endFrame calls them).
    struct Recording {
        VkCommandBuffer cb;
        uint32_t w, h, eyes;  ///< size per eye; eyes the passes run for (1 with mono views)
        bool hasDepth, hasMotion;
        bool retain, wrsPaper, taa, temporal, pyramid;  ///< which passes (temporal: a pass with history)
        bool tiled, sparse, inPlace, mono, timing;
        bool steady;           ///< the steady floor (steadyFloorActive)
        bool display;          ///< the steady display (PassPlan::display)
        uint32_t written;      ///< the reservoir buffer the frame writes
        uint32_t tilesPerEye;  ///< 8x8 tiles of one eye
    };
    void stamp(const Recording& plan, uint32_t i);
    /// The compose pass (frames submitted foveated: ComposePass), with the barrier after it.
    void recordCompose(const Recording& plan, const PassDispatch& d);
    /// The compose pass, the rate-map placeholder and the rendered qualities for an output of
    /// width x height, made on the first frame submitted foveated (and the qualities again on a resize).
    Status prepareSubmitted(uint32_t width, uint32_t height, bool gathered);
    /// Reservoirs zeroed after a history reset; the held qualities the frame reads where unrecorded.
    void recordHistoryStart(const Recording& plan);
    /// The tile lists emptied before the classification fills them.
    void recordListsReset(const Recording& plan);
    /// One dispatch of the pass table (its push constants, pipeline, dispatch and the barrier after it).
    void recordDispatch(const Recording& plan, const PassDispatch& d);
    static void recordBarrier(VkCommandBuffer cb, Barrier b);
    /// Mono views: the right eye's output, reservoirs, births and held qualities from the left's.
    void recordMonoCopies(const Recording& plan);
    /// The tile lists' counts into host memory (FrameStats::tiles).
    void recordTileCounts(const Recording& plan, bool record);
    /// Reads the frame's timestamps into stats_.gpu (and the copy kernels when measured).
    void collectTimes(double hostMs, const TrafficInputs& trafficIn, uint32_t eyes);
    TrafficInputs inFlightTraffic_;
    uint32_t inFlightEyes_ = 0;
};

}  // namespace wrsfov
