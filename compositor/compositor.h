// The stereo compositor: takes a frame end (layers/frame.h), runs the per-eye passes on the GPU,
// both eyes in one dispatch per pass, and keeps the output and the reservoirs.
//
// Passes, in the order they run (shaders/):
//   1. load     – decode the submitted colour to linear, sanitize, linearize depth
//   2. pyramid  – levels 1..4 (box for `mip`, [1 3 3 1] Gaussian for `gauss`; skipped for `none`)
//   3. foveate  – eccentricity, foveated colour, weight p̂ (method `fov` writes the output here)
//   4. wrs      – reprojection, depth flush, biased combine, reservoir store, output (`wrs-paper`)
//      or taa   – reprojected history clipped to the neighbourhood's variance box (method `fov+taa`)
//   3+4. retain – foveation fused with quality-aware retention (methods `wrs` and `oracle`): no
//                 candidate buffer; the pyramid is built for every foveation mode (fingerprint)
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "compositor/host_image.h"
#include "compositor/vk_context.h"
#include "layers/frame.h"
#include "layers/status.h"
#include "layers/swapchain.h"
#include "shaders/wrs_common.h"
#include "shaders/wrs_params.h"

namespace wrsfov {

/// fov: foveation only; fovTaa: foveation + TAA baseline (Karis/Salvi); wrsPaper: foveation + WRS
/// as published (eq. 6 + eq. 7); wrs: foveation + quality-aware retention (wrs_common.h, the
/// default); oracle: keeps whichever of history and candidate is closer to the submitted
/// (unfoveated) colour, the ceiling of any keep-or-replace rule with wrs's reprojection. The oracle
/// exists for evaluation only: it needs the full-rate image, which a foveated renderer never has.
enum class Method : uint8_t { Fov, FovTaa, WrsPaper, Wrs, Oracle };
/// What `wrs` does with a candidate of the same quality as the kept sample (shader WRS_RULE_*).
enum class EqualQuality : uint8_t { Merge = 0, Reservoir = 1 };
/// Values equal the shader constants WRS_FOV_*.
enum class FoveationMode : uint8_t { None = 0, Mip = 1, Gauss = 2 };
/// Values equal the shader constants WRS_CHANGE_*.
enum class ChangeMetric : uint8_t { Off = 0, LStar = 1, DeltaE94 = 2 };

std::string_view toString(Method m);
std::string_view toString(EqualQuality e);
/// "fov", "fov+taa", "wrs-paper", "wrs", "oracle"; nullopt for anything else.
std::optional<Method> parseMethod(std::string_view name);
std::string_view toString(FoveationMode m);
std::string_view toString(ChangeMetric m);

/// Refusal of a configuration (Compositor::create, Compositor::setConfig).
enum class ConfigError : int { InvalidValue = 100 };

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
    uint32_t seed = 1;
    /// Append a copy kernel moving the frame's estimated traffic (trafficBytes) to every frame's
    /// submission and time it: the yardstick benchmarks report the passes against.
    bool measureCopy = false;
    /// Evaluation (wrs-paper, wrs, oracle): keep per pixel the submitted colour at the time the
    /// shown sample was taken (merged as the samples are), readable with readBirth(), so a
    /// benchmark can find pixels showing a sample whose scene has changed since. 32 B/px more.
    bool trackBirth = false;
};

/// GPU time of each pass for both eyes together, in milliseconds (valid = false when not measured).
struct PassTimes {
    double load = 0, pyramid = 0, foveate = 0, temporal = 0, total = 0;  ///< temporal: the wrs or taa pass
    double copy = 0;  ///< the same-bytes copy kernel right after the passes (CompositorConfig::measureCopy)
    bool valid = false;
};

/// Estimated bytes the passes of a frame read and write for both eyes, each texel counted once
/// (layouts in shaders/bindings.glsl): what the copy kernel moves, half read and half written.
uint64_t trafficBytes(const CompositorConfig& config, uint32_t width, uint32_t height, bool depth, bool motion);

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
    Result<std::unique_ptr<layers::Swapchain>> createSwapchain(const layers::SwapchainCreateInfo& info);

    /// Validates and composites one frame (synchronously). A refused frame changes nothing:
    /// the error code is a layers::SubmitError.
    Status endFrame(const layers::FrameEndInfo& frame);

    const FrameStats& stats() const { return stats_; }
    const gpu::FrameParams& lastParams() const { return params_; }
    const CompositorConfig& config() const { return config_; }
    /// Takes effect at the next frame; a change of method or foveation resets history. A config
    /// with an out-of-range value is refused here (ConfigError::InvalidValue) and changes nothing.
    Status setConfig(const CompositorConfig& config);
    void resetHistory() { historyValid_ = false; }

    /// The last frame's output of one eye: RGBA8, sRGB-encoded.
    Result<HostImage> readOutput(uint32_t eye);
    /// The reservoirs the last frame wrote (packed, see wrs_common.h), W*H per eye.
    Result<std::vector<glm::uvec4>> readReservoirs(uint32_t eye);
    /// CompositorConfig::trackBirth: per pixel of one eye, the linear colour submitted when the
    /// shown sample was taken (W*H, rgb; alpha unused).
    Result<std::vector<glm::vec4>> readBirth(uint32_t eye);
    /// Replaces the history the next frame reads (tests use it to line up with the reference).
    Status writeReservoirs(uint32_t eye, const std::vector<glm::uvec4>& packed);
    /// The output image (2 layers, layer = eye), in VK_IMAGE_LAYOUT_GENERAL.
    const vk::Image& outputImage() const { return output_; }
    uint32_t width() const { return width_; }
    uint32_t height() const { return height_; }

    vk::Context& context() { return ctx_; }

private:
    explicit Compositor(vk::Context& context) : ctx_(context) {}
    Status init();
    Status resize(uint32_t width, uint32_t height, bool birth);
    Result<std::vector<glm::uvec4>> readBuffer(const vk::Buffer& buffer, uint32_t eye);
    VkPipeline pipeline(int shader, std::array<uint32_t, 4> constants);
    Result<HostImage> readImageLayer(uint32_t layer);

    vk::Context& ctx_;
    CompositorConfig config_;
    CompositorConfig pending_;
    bool configPending_ = false;
    layers::FrameValidator validator_;
    FrameStats stats_;
    gpu::FrameParams params_{};

    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::DescriptorPool descriptorPool_;
    VkDescriptorSet sets_[2] = {};  // ping-pong: set i reads reservoirs[i], writes reservoirs[1-i]
    vk::DescriptorSetLayout copySetLayout_;
    vk::PipelineLayout copyPipelineLayout_;
    VkDescriptorSet copySet_ = VK_NULL_HANDLE;
    vk::Sampler sampler_;
    vk::QueryPool queries_;
    std::vector<vk::ShaderModule> modules_;
    std::map<std::array<uint32_t, 5>, vk::Pipeline> pipelines_;

    uint32_t width_ = 0, height_ = 0;
    vk::Buffer ubo_;
    vk::Buffer pyramid_, zlin_, candidate_;
    vk::Buffer reservoirs_[2];
    vk::Buffer birth_[2];  // trackBirth: ping-pong like the reservoirs (16 B each when off)
    bool birthAllocated_ = false;
    vk::Buffer copySrc_, copyDst_;  // the copy kernel's buffers (measureCopy)
    uint32_t current_ = 0;  // reservoirs_[current_] holds the latest frame's reservoirs
    bool historyValid_ = false;
    vk::Image output_;
    vk::Image dummy_;  // bound where a view has no depth / motion
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    vk::Fence frameFence_;  // signalled by each frame's submission, reset after the wait
};

}  // namespace wrsfov
