#include "compositor/compose.h"

#include <algorithm>
#include <cstring>
#include <string>

#include "compose_spv.h"
#include "compositor/compositor_internal.h"

namespace wrsfov {

namespace {
// The compose pass's pipelines among the context's shared ones (vk::Context::sharedPipeline).
constexpr uint32_t kSharedPipelineTag = 2;

enum Binding : uint32_t {
    kParams = 0,
    kSrcColor = 1,
    kSrcDepth = 2,
    kSrcMotion = 3,
    kRateMap = 4,
    kQuality = 5,
    kSrgb = 6,
    kOutColor = 7,
    kOutDepth = 8,
    kOutMotion = 9,
    kOutput = 10
};
}  // namespace

std::vector<VkDescriptorSetLayoutBinding> ComposePass::setBindings() {
    auto binding = [](uint32_t i, VkDescriptorType t, uint32_t count = 1) {
        return VkDescriptorSetLayoutBinding{i, t, count, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    };
    const VkDescriptorType sampled = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                           storage = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    return {binding(kParams, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER), binding(kSrcColor, sampled, 4),
            binding(kSrcDepth, sampled, 4), binding(kSrcMotion, sampled, 4), binding(kRateMap, sampled, 2),
            binding(kQuality, ssbo), binding(kSrgb, ssbo), binding(kOutColor, storage), binding(kOutDepth, storage),
            binding(kOutMotion, storage), binding(kOutput, storage)};
}

Result<std::unique_ptr<ComposePass>> ComposePass::create(vk::Context& ctx, VkBuffer srgbTable) {
    std::unique_ptr<ComposePass> c(new ComposePass(ctx));
    const std::vector<VkDescriptorSetLayoutBinding> bindings = setBindings();
    auto layout = ctx.createSetLayout(bindings);
    if (!layout) return detail::named("the compose pass's descriptor set layout", layout.error());
    c->setLayout_ = std::move(*layout);
    auto pipelineLayout = ctx.createPipelineLayout(c->setLayout_.get(), kPushBytes, VK_SHADER_STAGE_COMPUTE_BIT);
    if (!pipelineLayout) return detail::named("the compose pass's pipeline layout", pipelineLayout.error());
    c->pipelineLayout_ = std::move(*pipelineLayout);
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 1},
                                    {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 14},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 4}};
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 1;
    dpci.poolSizeCount = 4;
    dpci.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    if (Status s = ctx.createObject("vkCreateDescriptorPool",
                                    [&] { return vkCreateDescriptorPool(ctx.device(), &dpci, nullptr, &pool); });
        !s)
        return detail::named("the compose pass's descriptor pool", s.error());
    c->pool_ = vk::DescriptorPool(ctx.device(), pool);
    VkDescriptorSetLayout sl = c->setLayout_.get();
    VkDescriptorSetAllocateInfo dsai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    dsai.descriptorPool = pool;
    dsai.descriptorSetCount = 1;
    dsai.pSetLayouts = &sl;
    if (Status s = ctx.createObject("vkAllocateDescriptorSets",
                                    [&] { return vkAllocateDescriptorSets(ctx.device(), &dsai, &c->set_); });
        !s)
        return detail::named("the compose pass's descriptor set", s.error());
    auto module = ctx.createShaderModule(compose_spv, sizeof(compose_spv));
    if (!module) return detail::named("the compose pass's shader module", module.error());
    c->module_ = std::move(*module);
    auto ubo = ctx.createBuffer(sizeof(gpu::ComposeParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
    if (!ubo) return Error{ubo.error().code, "compose parameters: " + ubo.error().message};
    c->params_ = std::move(*ubo);
    c->srgbTable_ = srgbTable;
    return c;
}

Result<VkPipeline> ComposePass::pipeline(const std::array<uint32_t, 9>& constants, vk::PipelineTally* tally) {
    if (auto it = pipelines_.find(constants); it != pipelines_.end()) return it->second;
    // Shared on the context: every compose pass defines its pipeline layout the same way (create).
    std::vector<uint32_t> shared{kSharedPipelineTag};
    shared.insert(shared.end(), constants.begin(), constants.end());
    Result<VkPipeline> made =
        ctx_.sharedPipeline(shared,
                            [&] { return ctx_.createComputePipeline(module_.get(), pipelineLayout_.get(), constants); },
                            tally);
    if (!made)
        return detail::pipelineError("the compose pass's pipeline", constants, made.error());
    return pipelines_.emplace(constants, *made).first->second;
}

uint32_t composeLandedMode(const gpu::ComposeParams& params) {
    float mode = 0.0f;
    for (const gpu::ComposeEye& e : params.eye) mode = std::max(mode, e.landed.z);
    return mode >= 3.0f ? 3u : mode >= 2.0f ? 2u : mode > 0.0f ? 1u : 0u;
}

Status ComposePass::prepare(layers::SubmittedFoveation kind, const gpu::ComposeParams& params, const Sources& sources,
                            VkBuffer quality, VkSampler sampler, VkImageView placeholder, VkImageView placeholderUint) {
    // Quad views: images of the output's size. Rate maps write none, but the set still needs storage
    // images: 1x1 ones until a quad frame comes.
    const bool quadFrame = kind == layers::SubmittedFoveation::Quad;
    const glm::uvec2 size = quadFrame ? glm::uvec2(params.size.x, params.size.y) : glm::uvec2(1, 1);
    if (quadFrame ? size != size_ : !color_) {
        // All three first, then swapped in: a failed allocation keeps the old images.
        vk::Image made[3];
        const VkFormat formats[3] = {VK_FORMAT_R16G16B16A16_SFLOAT, VK_FORMAT_R32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT};
        const char* what[3] = {"composed colour", "composed depth", "composed motion"};
        for (int k = 0; k < 3; ++k) {
            vk::ImageCreateInfo ici;
            ici.format = formats[k];
            ici.width = size.x;
            ici.height = size.y;
            ici.layers = 2;
            ici.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_SAMPLED_BIT;
            auto img = ctx_.createImage(ici);
            if (!img) return Error{img.error().code, std::string(what[k]) + ": " + img.error().message};
            made[k] = std::move(*img);
        }
        Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
            for (const vk::Image& img : made)
                vk::layoutTransition(cb, img.handle(), VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_UNDEFINED,
                                     VK_IMAGE_LAYOUT_GENERAL);
        });
        if (!s) return s;
        color_ = std::move(made[0]);
        depth_ = std::move(made[1]);
        motion_ = std::move(made[2]);
        size_ = quadFrame ? size : glm::uvec2(0, 0);
    }
    std::memcpy(params_.mapped(), &params, sizeof(params));
    auto image = [&](VkImageView v, VkImageView fallback) {
        return VkDescriptorImageInfo{sampler, v ? v : fallback, VK_IMAGE_LAYOUT_GENERAL};
    };
    VkDescriptorImageInfo src[3][4], rate[2];
    const std::array<VkImageView, 4>* lists[3] = {&sources.color, &sources.depth, &sources.motion};
    for (int k = 0; k < 3; ++k)
        for (int i = 0; i < 4; ++i) src[k][i] = image((*lists[k])[i], placeholder);
    for (int i = 0; i < 2; ++i) rate[i] = image(sources.rate[i], placeholderUint);
    VkDescriptorBufferInfo ubo{params_.handle(), 0, VK_WHOLE_SIZE}, q{quality, 0, VK_WHOLE_SIZE},
        srgb{srgbTable_, 0, VK_WHOLE_SIZE};
    VkDescriptorImageInfo out[3] = {{VK_NULL_HANDLE, color_.arrayView(), VK_IMAGE_LAYOUT_GENERAL},
                                    {VK_NULL_HANDLE, depth_.arrayView(), VK_IMAGE_LAYOUT_GENERAL},
                                    {VK_NULL_HANDLE, motion_.arrayView(), VK_IMAGE_LAYOUT_GENERAL}};
    VkWriteDescriptorSet w[10];
    uint32_t n = 0;
    w[n++] = vk::bufferWrite(set_, kParams, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ubo);
    w[n++] = vk::imageWrite(set_, kSrcColor, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src[0], 4);
    w[n++] = vk::imageWrite(set_, kSrcDepth, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src[1], 4);
    w[n++] = vk::imageWrite(set_, kSrcMotion, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, src[2], 4);
    w[n++] = vk::imageWrite(set_, kRateMap, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, rate, 2);
    w[n++] = vk::bufferWrite(set_, kQuality, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &q);
    w[n++] = vk::bufferWrite(set_, kSrgb, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &srgb);
    for (int k = 0; k < 3; ++k) w[n++] = vk::imageWrite(set_, kOutColor + k, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &out[k]);
    vkUpdateDescriptorSets(ctx_.device(), n, w, 0, nullptr);
    return {};
}

Status ComposePass::record(VkCommandBuffer cb, const std::array<uint32_t, 9>& constants,
                           std::span<const ComposeDispatch> dispatches, vk::PipelineTally* tally) {
    Result<VkPipeline> pipe = pipeline(constants, tally);
    if (!pipe) return pipe.error();
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, *pipe);
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_.get(), 0, 1, &set_, 0, nullptr);
    for (const ComposeDispatch& d : dispatches) {
        if (d.groups.x == 0 || d.groups.y == 0 || d.groups.z == 0) continue;
        const glm::uvec4 origin(d.origin, 0u);
        vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, kPushBytes, &origin);
        vkCmdDispatch(cb, d.groups.x, d.groups.y, d.groups.z);
    }
    return {};
}

void ComposePass::bindOutput(VkImageView view) {
    const VkDescriptorImageInfo out{VK_NULL_HANDLE, view, VK_IMAGE_LAYOUT_GENERAL};
    const VkWriteDescriptorSet w = vk::imageWrite(set_, kOutput, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &out);
    vkUpdateDescriptorSets(ctx_.device(), 1, &w, 0, nullptr);
}

}  // namespace wrsfov
