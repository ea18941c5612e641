#include "runtime/xr_quad.h"

#include "quad_spv.h"

namespace wrsfov::xr {

namespace {
constexpr uint32_t kMaxQuadDraws = 2 * 16;  // both eyes of every layer a frame may have

struct QuadPush {
    glm::mat4 quadFromEye;
    glm::vec4 fovTan;
    glm::vec4 uvRect;
    glm::vec4 sizeFlags;
    glm::uvec4 target;
};
static_assert(sizeof(QuadPush) == 128, "the push-constant block every device supports");
}  // namespace

Result<std::unique_ptr<QuadPass>> QuadPass::create(vk::Context& ctx) {
    std::unique_ptr<QuadPass> q(new QuadPass(ctx));
    VkDescriptorSetLayoutBinding out{0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    VkDescriptorSetLayoutBinding img{1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, VK_SHADER_STAGE_COMPUTE_BIT,
                                     nullptr};
    auto quadError = [](const Error& e) { return Error{e.code, "quad layers: " + e.message}; };
    auto layout = ctx.createSetLayout({out, img});
    if (!layout) return quadError(layout.error());
    q->setLayout_ = std::move(*layout);
    auto pipelineLayout = ctx.createPipelineLayout(q->setLayout_.get(), sizeof(QuadPush), VK_SHADER_STAGE_COMPUTE_BIT);
    if (!pipelineLayout) return quadError(pipelineLayout.error());
    q->pipelineLayout_ = std::move(*pipelineLayout);
    VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, kMaxQuadDraws},
                                     {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kMaxQuadDraws}};
    VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpi.maxSets = kMaxQuadDraws;
    dpi.poolSizeCount = 2;
    dpi.pPoolSizes = sizes;
    VkDescriptorPool pool;
    if (VkResult r = vkCreateDescriptorPool(ctx.device(), &dpi, nullptr, &pool); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkCreateDescriptorPool: ") + vk::resultString(r)};
    q->pool_ = vk::DescriptorPool(ctx.device(), pool);
    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_LINEAR;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler s;
    if (VkResult r = vkCreateSampler(ctx.device(), &sci, nullptr, &s); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkCreateSampler: ") + vk::resultString(r)};
    q->sampler_ = vk::Sampler(ctx.device(), s);
    auto module = ctx.createShaderModule(quad_spv, sizeof(quad_spv));
    if (!module) return quadError(module.error());
    q->module_ = std::move(*module);
    VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    cpi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    cpi.stage.module = q->module_.get();
    cpi.stage.pName = "main";
    cpi.layout = q->pipelineLayout_.get();
    VkPipeline p;
    if (VkResult r = vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &cpi, nullptr, &p); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkCreateComputePipelines: ") + vk::resultString(r)};
    q->pipeline_ = vk::Pipeline(ctx.device(), p);
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence f;
    if (VkResult r = vkCreateFence(ctx.device(), &fci, nullptr, &f); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkCreateFence: ") + vk::resultString(r)};
    q->fence_ = vk::Fence(ctx.device(), f);
    auto cb = ctx.allocateCommandBuffer();
    if (!cb) return quadError(cb.error());
    q->cb_ = *cb;
    return q;
}

QuadPass::~QuadPass() {
    waitIdle();
    if (cb_) ctx_.freeCommandBuffer(cb_);
}

void QuadPass::waitIdle() {
    if (!pending_) return;
    pending_ = false;
    VkFence f = fence_.get();
    (void)ctx_.waitSubmission(f);  // a lost device returns at once; nothing more to do with it
    vkResetFences(ctx_.device(), 1, &f);
}

Status QuadPass::draw(Compositor& compositor, const std::vector<QuadDraw>& quads) {
    if (quads.empty()) return {};
    if (quads.size() > kMaxQuadDraws) return Error{1, "more quad draws than layers allow"};
    waitIdle();  // the last frame's draw: its descriptor sets and command buffer are reused
    vkResetDescriptorPool(ctx_.device(), pool_.get(), 0);
    std::vector<VkDescriptorSet> sets(quads.size());
    std::vector<VkDescriptorSetLayout> layouts(quads.size(), setLayout_.get());
    VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    ai.descriptorPool = pool_.get();
    ai.descriptorSetCount = uint32_t(sets.size());
    ai.pSetLayouts = layouts.data();
    if (VkResult r = vkAllocateDescriptorSets(ctx_.device(), &ai, sets.data()); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkAllocateDescriptorSets: ") + vk::resultString(r)};
    const vk::Image& output = compositor.outputImage();
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const QuadDraw& d = quads[i];
        VkDescriptorImageInfo oi{VK_NULL_HANDLE, output.arrayView(), VK_IMAGE_LAYOUT_GENERAL};
        VkDescriptorImageInfo si{sampler_.get(),
                                 d.swapchain->sampledView(uint32_t(d.swapchain->lastReleased()), d.arrayIndex),
                                 VK_IMAGE_LAYOUT_GENERAL};
        VkWriteDescriptorSet w[2] = {vk::imageWrite(sets[i], 0, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &oi),
                                     vk::imageWrite(sets[i], 1, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &si)};
        vkUpdateDescriptorSets(ctx_.device(), 2, w, 0, nullptr);
    }
    VkCommandBuffer cb = cb_;
    auto failed = [](const char* call, VkResult r) {
        return Error{int(r), std::string("quad layers: ") + call + " failed: " + vk::resultString(r)};
    };
    if (VkResult r = vkResetCommandBuffer(cb, 0); r != VK_SUCCESS) return failed("vkResetCommandBuffer", r);
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    if (VkResult r = vkBeginCommandBuffer(cb, &bi); r != VK_SUCCESS) return failed("vkBeginCommandBuffer", r);
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline_.get());
    for (std::size_t i = 0; i < quads.size(); ++i) {
        const QuadDraw& d = quads[i];
        VkImage src = d.swapchain->image(uint32_t(d.swapchain->lastReleased()));
        const uint32_t layers = d.swapchain->info().arraySize;
        // The application's image is in its attachment layout between frames; read in GENERAL.
        vk::layoutTransition(cb, src, d.swapchain->aspect(), layers, d.swapchain->restingLayout(),
                             VK_IMAGE_LAYOUT_GENERAL);
        QuadPush push{d.quadFromEye, d.fovTan, d.uvRect,
                      glm::vec4(d.size, d.swapchain->colorEncoding() == gpu::WRS_INPUT_SRGB ? 1.0f : 0.0f,
                                float((d.blendAlpha ? 1 : 0) | (d.unpremultiplied ? 2 : 0))),
                      glm::uvec4(d.eye, compositor.width(), compositor.height(), 0)};
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_.get(), 0, 1, &sets[i], 0,
                                nullptr);
        vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cb, (compositor.width() + 7) / 8, (compositor.height() + 7) / 8, 1);
        // Quads overlap: each sees the one before it.
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        vk::layoutTransition(cb, src, d.swapchain->aspect(), layers, VK_IMAGE_LAYOUT_GENERAL,
                             d.swapchain->restingLayout());
    }
    // The output is read after this by the window's copy or a read-back, later on the queue.
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
    if (VkResult r = vkEndCommandBuffer(cb); r != VK_SUCCESS) return failed("vkEndCommandBuffer", r);
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    if (VkResult r = ctx_.submitNoWait(si, fence_.get()); r != VK_SUCCESS)
        return Error{int(r), std::string("quad layers: vkQueueSubmit: ") + vk::resultString(r)};
    pending_ = true;
    return {};
}

}  // namespace wrsfov::xr
