// Pass 0 of a frame submitted foveated (shaders/compose.comp): quad views resampled and blended into
// output-sized colour, depth and motion images, which the later passes read in place of the submitted
// images; and every output pixel's rendered quality (quad views and rate maps), which they read as
// the candidate's quality. Internal to the compositor.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <vector>

#include "compositor/vk_context.h"
#include "layers/frame.h"
#include "shaders/compose_params.h"

namespace wrsfov {

/// One dispatch of the compose pass: its first group (x, y) and eye (z), and its groups.
struct ComposeDispatch {
    glm::uvec3 origin{0, 0, 0};
    glm::uvec3 groups{0, 0, 0};
};

/// The compose pass's LANDED constant for `params` (shaders/compose.comp): 0 none, 1 landed wide samples
/// (`wrs`), 2 gathered wide samples (`taau-simple`), 3 their Lanczos-2 gather (`taau`); the largest of the two eyes' ComposeEye::landed.z.
uint32_t composeLandedMode(const gpu::ComposeParams& params);

class ComposePass {
public:
    /// `srgbTable`: the compositor's sRGB decode table (wrs_srgb8_table), read by the pass.
    static Result<std::unique_ptr<ComposePass>> create(vk::Context& ctx, VkBuffer srgbTable);

    /// The sources of one frame, as sampled views: wide views of eyes 0, 1 then insets of eyes 0, 1
    /// (quad views), and the rate maps of eyes 0, 1. VK_NULL_HANDLE where absent (the placeholder is bound).
    struct Sources {
        std::array<VkImageView, 4> color{}, depth{}, motion{};
        std::array<VkImageView, 2> rate{};
    };
    /// Makes the composed images for quad views of `params.size` (kept while the size holds; a failed
    /// allocation changes nothing) and points the pass at this frame's sources, `quality` and `params`.
    Status prepare(layers::SubmittedFoveation kind, const gpu::ComposeParams& params, const Sources& sources,
                   VkBuffer quality, VkSampler sampler, VkImageView placeholder, VkImageView placeholderUint);
    /// Records the pass's `dispatches` with specialisation constants `constants` (kind, depth, motion, landed,
    /// the wide views' and the insets' encodings, inset, output, tiles: the frame's pass table,
    /// compositor/pass_table.h; the caller records the barrier after it). Fails, having recorded nothing,
    /// where its pipeline cannot be made. `tally` counts the pipelines this call made.
    Status record(VkCommandBuffer cb, const std::array<uint32_t, 9>& constants,
                  std::span<const ComposeDispatch> dispatches, vk::PipelineTally* tally = nullptr);
    /// Points the pass's output binding (method fov on quad views writes the output) at `view`, the
    /// compositor's output image (2 layers, storage, GENERAL).
    void bindOutput(VkImageView view);
    /// The parameters of the last frame prepared (gpu::ComposeParams, a uniform buffer), which the retain
    /// pass reads too (its landed wide samples).
    VkBuffer paramsBuffer() const { return params_.handle(); }
    /// The pass's descriptor set layout and push constants (the cost model compiles with the same).
    static std::vector<VkDescriptorSetLayoutBinding> setBindings();
    static constexpr uint32_t kPushBytes = 16;  ///< compose.comp's origin (uvec4)

    /// The composed images (2 layers, layer = eye, VK_IMAGE_LAYOUT_GENERAL): RGBA16F linear colour with
    /// validity in alpha, R32F depth as submitted, RGBA16F motion in output pixels.
    const vk::Image& color() const { return color_; }
    const vk::Image& depth() const { return depth_; }
    const vk::Image& motion() const { return motion_; }

private:
    explicit ComposePass(vk::Context& ctx) : ctx_(ctx) {}
    Result<VkPipeline> pipeline(const std::array<uint32_t, 9>& constants, vk::PipelineTally* tally);
    vk::Context& ctx_;
    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::DescriptorPool pool_;
    VkDescriptorSet set_ = VK_NULL_HANDLE;
    vk::ShaderModule module_;
    // By constants; the context's (vk::Context::sharedPipeline)
    std::map<std::array<uint32_t, 9>, VkPipeline> pipelines_;
    vk::Buffer params_;
    VkBuffer srgbTable_ = VK_NULL_HANDLE;
    vk::Image color_, depth_, motion_;
    glm::uvec2 size_{0, 0};
};

}  // namespace wrsfov
