#include "compositor/compositor.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "compositor/compose.h"
#include "compositor/compositor_internal.h"
#include "compositor/frame_work.h"
#include "compositor/input.h"
#include "compositor/swapchain_vk.h"
#include "shaders/wrs_submitted.h"
#include "classify_spv.h"
#include "copy_spv.h"
#include "foveate_spv.h"
#include "half_probe_spv.h"
#include "pyramid_spv.h"
#include "retain_spv.h"
#include "taa_spv.h"
#include "wrs_spv.h"

namespace wrsfov {

using layers::SubmitError;
using namespace detail;

namespace {

// The compositor's pipelines among the context's shared ones (vk::Context::sharedPipeline).
constexpr uint32_t kSharedPipelineTag = 1;

static_assert(gpu::WRS_TILE == WRS_GROUP_X && gpu::WRS_TILE == WRS_GROUP_Y, "a tiled dispatch runs one group per tile");

bool finite3(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

Status checkConfig(const CompositorConfig& c) {
    auto bad = [](float v, float lo, float hi) { return !std::isfinite(v) || v <= lo || v > hi; };
    auto refuse = [](const char* what) { return Error{static_cast<int>(ConfigError::InvalidValue), what}; };
    if (bad(c.foveaDeg, 0.0f, 180.0f)) return refuse("fovea size must be in (0°, 180°]");
    if (bad(c.midPeripheryDeg, 0.0f, 180.0f)) return refuse("mid-periphery size must be in (0°, 180°]");
    if (bad(c.fallbackFoveaDeg, 0.0f, 180.0f)) return refuse("fallback fovea size must be in (0°, 180°]");
    if (bad(c.depthTau, 0.0f, 1e6f)) return refuse("depth tolerance must be positive and finite");
    if (!std::isfinite(c.motionReachDeg) || c.motionReachDeg < 0.0f || c.motionReachDeg > 180.0f)
        return refuse("motion reach must be in [0°, 180°] (0: no limit)");
    // Enums may come from casts of file or command-line values: out-of-range ones are refused, not guessed.
    if (uint8_t(c.method) > uint8_t(Method::TaauSimple))
        return refuse("method must be fov, fov+taa, wrs-paper, wrs, oracle, oracle-q, taau or taau-simple");
    if (bad(c.taauSimple.radius, 0.0f, 8.0f)) return refuse("taau-simple radius must be in (0, 8] output pixels");
    if (bad(c.taauSimple.maxWeight, 0.0f, 1024.0f)) return refuse("taau-simple weight cap must be in (0, 1024]");
    if (bad(c.taauSimple.clipGamma, 0.0f, 64.0f)) return refuse("taau-simple clip box must be in (0, 64] sigmas");
    if (bad(c.taau.kernel, 0.0f, 4.0f)) return refuse("taau kernel scale must be in (0, 4] wide pixels");
    if (bad(c.taau.maxWeight, 0.0f, 1024.0f)) return refuse("taau weight cap must be in (0, 1024]");
    if (bad(c.taau.boxSigma, 0.0f, 64.0f)) return refuse("taau clamp box must be in (0, 64] sigmas");
    if (bad(c.taau.fullVelocity, 0.0f, 1e4f)) return refuse("taau box velocity must be in (0, 1e4] output pixels a frame");
    auto outside = [](float v, float lo, float hi) { return !std::isfinite(v) || v < lo || v > hi; };
    if (outside(c.taau.lockFrames, 0.0f, 64.0f)) return refuse("taau lock lifetime must be in [0, 64] frames");
    if (bad(c.taau.lockThreshold, 0.0f, 16.0f)) return refuse("taau lock threshold must be in (0, 16]");
    if (outside(c.taau.stability, 0.0f, 1024.0f)) return refuse("taau luma stability must be in [0, 1024]");
    if (uint8_t(c.equalQuality) > uint8_t(EqualQuality::Reservoir)) return refuse("equal-quality rule must be merge or reservoir");
    if (uint8_t(c.foveation) > uint8_t(FoveationMode::Gauss))
        return refuse("foveation mode must be none, mip or gauss (submitted foveation comes with the frame: quad "
                      "views or a rate map)");
    if (!std::isfinite(c.insetBlendPx) || c.insetBlendPx < 0.0f || c.insetBlendPx > 1024.0f)
        return refuse("inset blend width must be in [0, 1024] inset pixels");
    if (!std::isfinite(c.landedFootprint) || c.landedFootprint < 0.0f || c.landedFootprint > 1.0f)
        return refuse("landed footprint must be in [0, 1] wide pixels (0: one output pixel)");
    if (!std::isfinite(c.steadyDisplay) || c.steadyDisplay < 0.0f || c.steadyDisplay > 1.0f)
        return refuse("steady display weight must be in [0, 1] (0: off)");
    if (!std::isfinite(c.steadyDisplaySpeed) || c.steadyDisplaySpeed < 0.0f || c.steadyDisplaySpeed > 1024.0f)
        return refuse("steady display full speed must be in [0, 1024] output pixels a frame (0: one weight at every speed)");
    if (uint8_t(c.change) > uint8_t(ChangeMetric::DeltaE94)) return refuse("change metric must be off, lstar or de94");
    return {};
}

}  // namespace

gpu::FrameParams makeFrameParams(const CompositorConfig& config, const layers::FrameEndInfo& frame, uint32_t width,
                                 uint32_t height, bool fallback[2]) {
    gpu::FrameParams p{};
    const layers::ProjectionLayer& layer = frame.layers.at(0);
    // Quad views: the passes read the compose pass's images (layer = eye, at the origin, motion already
    // in output pixels) in place of the submitted ones.
    const bool composed = layers::submittedFoveation(layer) == layers::SubmittedFoveation::Quad;
    for (int i = 0; i < 2; ++i) {
        const layers::ProjectionView& v = layer.views.at(i);
        gpu::EyeParams& e = p.eye[i];
        e.fov_tan = glm::vec4(std::tan(v.fov.angleLeft), std::tan(v.fov.angleRight), std::tan(v.fov.angleUp),
                              std::tan(v.fov.angleDown));
        e.tile = gpu::wrs_tile_geometry(glm::uvec2(width, height), e.fov_tan);
        const layers::EyeGaze& g = frame.gaze[i];
        float len = finite3(g.dir) ? glm::length(g.dir) : 0.0f;
        fallback[i] = !(g.valid && std::isfinite(len) && len > 1e-6f);
        if (!fallback[i]) {
            e.gaze = glm::vec4(g.dir / len, config.foveaDeg * 0.5f);
        } else {
            // View centre (asymmetric fields of view look off-axis) with the larger fallback fovea.
            glm::vec3 c((e.fov_tan.x + e.fov_tan.y) * 0.5f, (e.fov_tan.z + e.fov_tan.w) * 0.5f, -1.0f);
            e.gaze = glm::vec4(glm::normalize(c), config.fallbackFoveaDeg * 0.5f);
        }
        // (The layer fields are informative: each eye's image layer is bound as a view of its own; a
        // composed frame's say 0, so that two identical submitted views give identical parameters.)
        e.color_rect = composed ? glm::uvec4(0u, 0u, gpu::WRS_INPUT_COMPOSED, 0u)
                                : glm::uvec4(v.color.rect.x, v.color.rect.y,
                                             colorEncoding(v.color), v.color.arrayIndex);
        if (v.depth) {
            e.depth_rect = composed ? glm::uvec4(0u, 0u, v.depth->reversedZ ? 1u : 0u, 0u)
                                    : glm::uvec4(v.depth->subImage.rect.x, v.depth->subImage.rect.y,
                                                 v.depth->reversedZ ? 1u : 0u, v.depth->subImage.arrayIndex);
            e.depth_range = glm::vec4(v.depth->nearZ, v.depth->farZ, 0.0f, 0.0f);
        }
        // Motion reach in pixels: the degrees at the view's centre, where a pixel spans the most angle
        // (tangent space: d tan / d angle = 1 there, more off-axis), on the axis with more pixels per radian.
        const float pxPerRad = std::max(float(width) / (e.fov_tan.y - e.fov_tan.x), float(height) / (e.fov_tan.z - e.fov_tan.w));
        const float reach = config.motionReachDeg > 0.0f && std::isfinite(pxPerRad)
                                ? glm::radians(config.motionReachDeg) * std::abs(pxPerRad)
                                : std::numeric_limits<float>::infinity();
        e.motion_scale = glm::vec4(1.0f, 1.0f, 1.0f, reach);
        if (v.reference) {
            e.ref_rect = glm::uvec4(v.reference->rect.x, v.reference->rect.y, colorEncoding(*v.reference),
                                    v.reference->arrayIndex);
        }
        if (v.motion && composed) {
            e.motion_rect = glm::uvec4(0u, 0u, 0u, 0u);
        } else if (v.motion) {
            e.motion_rect =
                glm::uvec4(v.motion->subImage.rect.x, v.motion->subImage.rect.y, 0u, v.motion->subImage.arrayIndex);
            e.motion_scale = glm::vec4(v.motion->scale, reach);
        }
    }
    p.size = glm::uvec4(width, height, uint32_t(frame.frameIndex), config.seed);
    const glm::uvec2 size0(width, height);
    const uint32_t level0 = width * height, stored = gpu::wrs_pyramid_texels(size0) - level0;
    for (uint32_t k = 0; k < WRS_LEVELS; ++k) {
        const glm::uvec2 s = gpu::wrs_level_size(size0, k);
        p.levels[k] = glm::uvec4(s, k == 0 ? 0u : gpu::wrs_level_offset(size0, k) - level0, stored);
        p.level_scale[k] = glm::vec4(gpu::wrs_level_scale(size0, k), 0.0f, 0.0f);
    }
    // z is unused: whether birth colours are tracked is the passes' constant TRACK_BIRTH.
    // The floor rule's quality: the mode's far periphery, or for a frame submitted foveated the lowest
    // quality it was rendered at (submittedFloor), under the same conditions (floorQuality).
    float floor = floorQuality(config);
    if (layers::submittedFoveation(layer) != layers::SubmittedFoveation::Full) {
        CompositorConfig simulated = config;
        simulated.foveation = FoveationMode::Mip;
        floor = floorQuality(simulated) > 0.0f ? submittedFloor(layer) : 0.0f;
    }
    p.tuning = glm::vec4(config.midPeripheryDeg * 0.5f, config.depthTau, 0.0f, floor);
    p.held = glm::uvec4(0u, 0u, runsSparse(config) ? 1u : 0u, 0u);  // the offsets are the compositor's
    return p;
}

namespace detail {

std::array<std::pair<const layers::SubImage*, const char*>, 8> subImagesOf(const layers::ProjectionView& v) {
    const layers::InsetView* in = v.inset ? &*v.inset : nullptr;
    return {{{&v.color, "colour"},
             {v.depth ? &v.depth->subImage : nullptr, "depth"},
             {v.motion ? &v.motion->subImage : nullptr, "motion"},
             {in ? &in->color : nullptr, "inset colour"},
             {in && in->depth ? &in->depth->subImage : nullptr, "inset depth"},
             {in && in->motion ? &in->motion->subImage : nullptr, "inset motion"},
             {v.rateMap ? &v.rateMap->subImage : nullptr, "rate map"},
             {v.reference ? &*v.reference : nullptr, "reference"}}};
}

}  // namespace detail

Result<std::unique_ptr<Compositor>> Compositor::create(vk::Context& context, const CompositorConfig& config) {
    if (Status s = checkConfig(config); !s) return s.error();
    std::unique_ptr<Compositor> c(new Compositor(context));
    c->config_ = config;
    c->frame_ = config;
    if (Status s = c->init(); !s) return s.error();
    return c;
}

Compositor::~Compositor() {
    if (ctx_.device()) vkDeviceWaitIdle(ctx_.device());
    if (cmd_) ctx_.freeCommandBuffer(cmd_);
}

Status Compositor::setConfig(const CompositorConfig& config) {
    if (Status s = checkConfig(config); !s) return s;
    pending_ = config;
    configPending_ = true;
    return {};
}

std::vector<VkDescriptorSetLayoutBinding> Compositor::passSetBindings() {
    auto binding = [](uint32_t i, VkDescriptorType t, uint32_t count = 1) {
        return VkDescriptorSetLayoutBinding{i, t, count, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    };
    const VkDescriptorType ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, image = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
    return {binding(kFrame, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER), binding(kColor, image, 2), binding(kDepth, image, 2),
            binding(kMotion, image, 2), binding(kPyramidBuf, ssbo), binding(kCandidate, ssbo),
            binding(kResPrev, ssbo), binding(kResCur, ssbo), binding(kOutput, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE),
            binding(kBirthPrev, ssbo), binding(kBirthCur, ssbo), binding(kSrgbTable, ssbo),
            binding(kTiles, ssbo), binding(kTileHeld, ssbo), binding(kQuality, ssbo), binding(kReference, image, 2),
            binding(kDisplay, ssbo), binding(kCompose, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER), binding(kWide, image, 2)};
}

Status Compositor::init() {
    VkDevice dev = ctx_.device();
    auto binding = [](uint32_t i, VkDescriptorType t, uint32_t count = 1) {
        return VkDescriptorSetLayoutBinding{i, t, count, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
    };
    const VkDescriptorType ssbo = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    const std::vector<VkDescriptorSetLayoutBinding> passBindings = passSetBindings();
    auto layout = ctx_.createSetLayout(passBindings);
    if (!layout) return named("the passes' descriptor set layout", layout.error());
    setLayout_ = std::move(*layout);
    auto pipelineLayout =
        ctx_.createPipelineLayout(setLayout_.get(), sizeof(gpu::LevelPush), VK_SHADER_STAGE_COMPUTE_BIT);
    if (!pipelineLayout) return named("the passes' pipeline layout", pipelineLayout.error());
    pipelineLayout_ = std::move(*pipelineLayout);
    auto copyLayout = ctx_.createSetLayout({binding(0, ssbo), binding(1, ssbo)});
    if (!copyLayout) return named("the copy kernel's descriptor set layout", copyLayout.error());
    copySetLayout_ = std::move(*copyLayout);
    auto copyPipelineLayout =
        ctx_.createPipelineLayout(copySetLayout_.get(), sizeof(uint32_t), VK_SHADER_STAGE_COMPUTE_BIT);
    if (!copyPipelineLayout) return named("the copy kernel's pipeline layout", copyPipelineLayout.error());
    copyPipelineLayout_ = std::move(*copyPipelineLayout);
    const VkDescriptorSetLayout sl = setLayout_.get(), csl = copySetLayout_.get();

    // Four pass sets (two ping-pong, two in place, see sets_) and the copy kernel's.
    VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, 8},
                                    {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 40},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 46},
                                    {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 4}};
    VkDescriptorPoolCreateInfo dpci{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    dpci.maxSets = 5;
    dpci.poolSizeCount = 4;
    dpci.pPoolSizes = sizes;
    VkDescriptorPool pool = VK_NULL_HANDLE;
    if (Status s = ctx_.createObject("vkCreateDescriptorPool",
                                     [&] { return vkCreateDescriptorPool(dev, &dpci, nullptr, &pool); });
        !s)
        return named("the compositor's descriptor pool", s.error());
    descriptorPool_ = vk::DescriptorPool(dev, pool);
    VkDescriptorSetLayout layouts[5] = {sl, sl, sl, sl, csl};
    VkDescriptorSet sets[5];
    VkDescriptorSetAllocateInfo dsai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
    dsai.descriptorPool = pool;
    dsai.descriptorSetCount = 5;
    dsai.pSetLayouts = layouts;
    if (Status s = ctx_.createObject("vkAllocateDescriptorSets", [&] { return vkAllocateDescriptorSets(dev, &dsai, sets); });
        !s)
        return named("the compositor's descriptor sets", s.error());
    for (int i = 0; i < 4; ++i) sets_[i] = sets[i];
    copySet_ = sets[4];

    VkSamplerCreateInfo sci{VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO};
    sci.magFilter = sci.minFilter = VK_FILTER_NEAREST;
    sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
    sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
    VkSampler sampler = VK_NULL_HANDLE;
    if (Status s = ctx_.createObject("vkCreateSampler", [&] { return vkCreateSampler(dev, &sci, nullptr, &sampler); });
        !s)
        return named("the compositor's sampler", s.error());
    sampler_ = vk::Sampler(dev, sampler);

    VkQueryPoolCreateInfo qci{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qci.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qci.queryCount = kTimestamps;
    VkQueryPool qp = VK_NULL_HANDLE;
    if (Status s = ctx_.createObject("vkCreateQueryPool", [&] { return vkCreateQueryPool(dev, &qci, nullptr, &qp); }); !s)
        return named("the compositor's timestamp queries", s.error());
    queries_ = vk::QueryPool(dev, qp);

    struct Code {
        const uint32_t* words;
        size_t bytes;
    };
    const Code code[kShaderCount] = {{pyramid_spv, sizeof(pyramid_spv)}, {foveate_spv, sizeof(foveate_spv)},
                                     {wrs_spv, sizeof(wrs_spv)},         {taa_spv, sizeof(taa_spv)},
                                     {copy_spv, sizeof(copy_spv)},       {retain_spv, sizeof(retain_spv)},
                                     {classify_spv, sizeof(classify_spv)}, {half_probe_spv, sizeof(half_probe_spv)}};
    for (const Code& c : code) {
        auto module = ctx_.createShaderModule(c.words, c.bytes);
        if (!module) return named("the passes' shader modules", module.error());
        modules_.push_back(std::move(*module));
    }

    auto ubo = ctx_.createBuffer(sizeof(gpu::FrameParams), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT, true);
    if (!ubo) return named("compositor frame parameters", ubo.error());
    ubo_ = std::move(*ubo);
    const auto& table = gpu::wrs_srgb8_table();
    auto srgb = ctx_.createBuffer(sizeof(table), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, true);
    if (!srgb) return named("sRGB decode table", srgb.error());
    srgbTable_ = std::move(*srgb);
    std::memcpy(srgbTable_.mapped(), table.data(), sizeof(table));
    for (VkDescriptorSet set : sets_) {
        VkDescriptorBufferInfo bi{srgbTable_.handle(), 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w = vk::bufferWrite(set, kSrgbTable, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi);
        vkUpdateDescriptorSets(dev, 1, &w, 0, nullptr);
    }

    vk::ImageCreateInfo dci;
    dci.format = VK_FORMAT_R16G16B16A16_SFLOAT;
    dci.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
    auto dummy = ctx_.createImage(dci);
    if (!dummy) return named("compositor placeholder image", dummy.error());
    dummy_ = std::move(*dummy);
    Status st = ctx_.submitAndWait([&](VkCommandBuffer cmd) {
        VkImageMemoryBarrier ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        ib.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        ib.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        ib.newLayout = VK_IMAGE_LAYOUT_GENERAL;
        ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = dummy_.handle();
        ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &ib);
        VkClearColorValue zero{};
        vkCmdClearColorImage(cmd, dummy_.handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &ib.subresourceRange);
    });
    if (!st) return st;
    auto cmd = ctx_.allocateCommandBuffer();
    if (!cmd) return named("the compositor's command buffer", cmd.error());
    cmd_ = *cmd;
    VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    if (Status s = ctx_.createObject("vkCreateFence", [&] { return vkCreateFence(dev, &fci, nullptr, &fence); }); !s)
        return named("the compositor's frame fence", s.error());
    frameFence_ = vk::Fence(dev, fence);
    if (!ctx_.halfProbe()) ctx_.setHalfProbe(probeHardwareHalf());
    hardwareHalf_ = config_.hardwareHalf && *ctx_.halfProbe() && !handHalfForced();
    return {};
}

static std::vector<float> halfProbeValues() {
    // What the passes hand the device's conversion (wrs_store_f16): values already on fp16's grid, every
    // normal fp16 value of either sign. A conformant conversion returns each exactly; how a device rounds
    // a value fp16 cannot hold no longer reaches a stored bit (those values are rounded by hand first).
    std::vector<float> v;
    for (uint32_t h = 0x0400u; h <= 0x7bffu; ++h) {
        v.push_back(gpu::wrs_f16_to_f32(h));
        v.push_back(-gpu::wrs_f16_to_f32(h));
    }
    return v;
}

bool Compositor::probeHardwareHalf() {
    // Where the probe cannot run (no memory, no pipeline, a lost device) the passes convert by hand: the
    // same bits. One submission: the packing of every value the passes hand the device's conversion,
    // then the unpacking of every finite fp16 value (wrs_f16_to_f32), each value's bits as a float.
    const std::vector<float> packed = halfProbeValues();
    std::vector<float> values = packed;
    for (uint32_t h = 0; h <= 0xffffu; ++h)
        if ((h & 0x7c00u) != 0x7c00u || (h & 0x3ffu) == 0u) values.push_back(std::bit_cast<float>(h));
    const uint32_t packs = uint32_t(packed.size()), count = uint32_t(values.size());
    static_assert(sizeof(float) == 4);
    if (packs > 0xffffu || count - packs > 0xffffu) return false;
    const VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    auto src = ctx_.createBuffer(uint64_t(count) * 4, use, true);
    auto dst = ctx_.createBuffer(uint64_t(count) * 4, use, true);
    if (!src || !dst) return false;
    std::memcpy(src->mapped(), values.data(), values.size() * 4);
    VkDescriptorBufferInfo bi[2] = {{src->handle(), 0, VK_WHOLE_SIZE}, {dst->handle(), 0, VK_WHOLE_SIZE}};
    VkWriteDescriptorSet w[2] = {vk::bufferWrite(copySet_, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[0]),
                                 vk::bufferWrite(copySet_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[1])};
    vkUpdateDescriptorSets(ctx_.device(), 2, w, 0, nullptr);
    const uint32_t groupsTotal = (count + 63) / 64, gx = std::min<uint32_t>(groupsTotal, 65535),
                   gy = (groupsTotal + gx - 1) / gx;
    const uint32_t push = packs | ((count - packs) << 16);
    Result<VkPipeline> probe = pipeline(kHalfProbe, {});
    if (!probe) return false;
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, *probe);
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, copyPipelineLayout_.get(), 0, 1, &copySet_, 0,
                                nullptr);
        vkCmdPushConstants(cb, copyPipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cb, gx, gy, 1);
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                          VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    });
    // The copy kernel's set is written again when its buffers are made (measureCopy).
    copySrc_ = vk::Buffer();
    if (!s) return false;
    const uint32_t* got = static_cast<const uint32_t*>(dst->mapped());
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t want = i < packs ? gpu::wrs_f32_to_f16(values[i])
                                        : std::bit_cast<uint32_t>(gpu::wrs_f16_to_f32(std::bit_cast<uint32_t>(values[i])));
        if (got[i] != want) return false;
    }
    return true;
}

double Compositor::timeCopy(uint64_t bytes) {
    const uint32_t count = uint32_t(std::min<uint64_t>(bytes / 2, copySrc_.size()) / 16);
    const uint32_t groupsTotal = std::max<uint32_t>((count + 63) / 64, 1);
    const uint32_t cgx = std::min<uint32_t>(groupsTotal, 65535), cgy = (groupsTotal + cgx - 1) / cgx;
    Result<VkPipeline> copy = pipeline(kCopy, {0, 0, 0, 0});
    if (!copy) return 0.0;  // no figure, as for a failed submission
    const auto submitted = std::chrono::steady_clock::now();
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vkCmdResetQueryPool(cb, queries_.get(), kFrameStamps, 2);
        vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, *copy);
        vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, copyPipelineLayout_.get(), 0, 1, &copySet_, 0,
                                nullptr);
        vkCmdPushConstants(cb, copyPipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(count), &count);
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, queries_.get(), kFrameStamps);
        vkCmdDispatch(cb, cgx, cgy, 1);
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), kFrameStamps + 1);
    });
    if (ctx_.isCpuDevice())  // see PassTimes::hostTimed
        return s ? std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - submitted).count() : 0.0;
    uint64_t ts[2];
    if (!s || vkGetQueryPoolResults(ctx_.device(), queries_.get(), kFrameStamps, 2, sizeof(ts), ts, sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) != VK_SUCCESS)
        return 0.0;
    return double(ts[1] - ts[0]) * ctx_.timestampPeriodNs() * 1e-6;
}

Result<VkPipeline> Compositor::pipeline(int shader, const SpecConstants& passConstants) {
    // Constants 0..6 and 9 are the pass's; 7 (HARDWARE_HALF) and 8 (TRACK_BIRTH, bindings.glsl) every pass's.
    SpecConstants constants = passConstants;
    constants[7] = hardwareHalf_;
    constants[8] = birthAllocated_;
    std::array<uint32_t, 13> key{uint32_t(shader)};
    std::copy(constants.begin(), constants.end(), key.begin() + 1);
    auto it = pipelines_.find(key);
    if (it != pipelines_.end()) return it->second;
    // Shared on the context: every compositor defines its two pipeline layouts the same way (init).
    std::vector<uint32_t> shared{kSharedPipelineTag};
    shared.insert(shared.end(), key.begin(), key.end());
    Result<VkPipeline> made = ctx_.sharedPipeline(
        shared,
        [&] {
            return ctx_.createComputePipeline(
                modules_[shader].get(),
                shader == kCopy || shader == kHalfProbe ? copyPipelineLayout_.get() : pipelineLayout_.get(),
                constants);
        },
        &recordTally_);
    if (!made) {
        static const char* const names[kShaderCount] = {"pyramid", "foveate", "wrs",      "taa",
                                                        "copy",    "retain",  "classify", "half_probe"};
        return pipelineError(std::string("the ") + names[shader] + ".comp pipeline", constants, made.error());
    }
    return pipelines_.emplace(key, *made).first->second;
}

bool Compositor::bindPipeline(VkCommandBuffer cb, int shader, const SpecConstants& passConstants) {
    if (recordError_) return false;
    Result<VkPipeline> p = pipeline(shader, passConstants);
    if (!p) {
        recordError_ = p.error();
        return false;
    }
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, *p);
    return true;
}

Status Compositor::resize(uint32_t width, uint32_t height, bool birth, bool display) {
    vkDeviceWaitIdle(ctx_.device());
    // Everything of the new size is made before anything old is released: when an allocation fails
    // (out of device memory), the compositor keeps its old size, history and output untouched. The
    // price is that old and new resources exist together for the moment of a resize.
    const VkBufferUsageFlags usage =
        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    const uint64_t pixels = uint64_t(width) * height * WRS_EYES;
    // Levels 1..4 only (level 0 is the submitted image), fp16 RGBA.
    // Then the steady floor's two slots of both eyes' level 4 (pyramid.comp, FILTER 3).
    const glm::uvec2 level4 = gpu::wrs_level_size(glm::uvec2(width, height), gpu::WRS_STEADY_LEVEL);
    const uint64_t pyramidTexels =
        (uint64_t(gpu::wrs_pyramid_texels(glm::uvec2(width, height))) - uint64_t(width) * height) * WRS_EYES +
        2ull * WRS_EYES * level4.x * level4.y;
    vk::Buffer pyramid, candidate, reservoirs[2], births[2], tiles, held, counts, displayed;
    struct Alloc {
        vk::Buffer* buffer;
        uint64_t bytes;
        const char* what;
    };
    for (const Alloc& a :
         {Alloc{&pyramid, pyramidTexels * 8, "colour pyramid"}, Alloc{&candidate, pixels * 16, "candidates"},
          Alloc{&reservoirs[0], pixels * 16, "reservoirs"}, Alloc{&reservoirs[1], pixels * 16, "reservoirs"}, Alloc{&births[0], birth ? pixels * 16 : 16, "births"},
          Alloc{&births[1], birth ? pixels * 16 : 16, "births"},
          Alloc{&displayed, display ? 2 * pixels * 8 : 16, "steady display"}}) {
        auto r = ctx_.createBuffer(a.bytes, usage, false);
        if (!r) return named(a.what, r.error());
        *a.buffer = std::move(*r);
    }
    {
        // Tile lists: the classes' indirect dispatches, then a list of every tile of both eyes per class.
        const uint64_t tileCount = uint64_t(groups(width, gpu::WRS_TILE)) * groups(height, gpu::WRS_TILE) * WRS_EYES;
        auto r = ctx_.createBuffer(16 * gpu::WRS_TILE_LISTS + tileCount * 4 * gpu::WRS_TILE_LISTS,
                                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                   false);
        if (!r) return named("tile lists", r.error());
        tiles = std::move(*r);
        // Two frames' held qualities per tile, then one per superblock (wrs_reach_blocks).
        const uint64_t tilesX = groups(width, gpu::WRS_TILE), tilesY = groups(height, gpu::WRS_TILE);
        const uint64_t blockCount =
            uint64_t(groups(uint32_t(tilesX), gpu::WRS_SUPERBLOCK)) * groups(uint32_t(tilesY), gpu::WRS_SUPERBLOCK) * WRS_EYES;
        auto h = ctx_.createBuffer((2 * tileCount + blockCount) * 4, usage, false);
        if (!h) return named("held qualities", h.error());
        held = std::move(*h);
        auto c = ctx_.createBuffer(16 * gpu::WRS_TILE_LISTS, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
        if (!c) return named("tile counts", c.error());
        counts = std::move(*c);
    }

    vk::ImageCreateInfo oci;
    oci.format = VK_FORMAT_R8G8B8A8_UNORM;
    oci.width = width;
    oci.height = height;
    oci.layers = WRS_EYES;
    oci.usage = VK_IMAGE_USAGE_STORAGE_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                VK_IMAGE_USAGE_SAMPLED_BIT;
    auto out = ctx_.createImage(oci);
    if (!out) return named("output image", out.error());
    // The output black and the reservoirs empty (all zero: no sample) from the start, so that what a
    // reader sees of the new size is defined even where its first frame fails after this resize (a
    // pipeline the driver cannot make, docs/bad-input.md "Device faults").
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        VkImageMemoryBarrier ib{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER};
        ib.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        ib.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
        ib.newLayout = VK_IMAGE_LAYOUT_GENERAL;
        ib.srcQueueFamilyIndex = ib.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
        ib.image = out->handle();
        ib.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, WRS_EYES};
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                             nullptr, 1, &ib);
        const VkClearColorValue black{};
        vkCmdClearColorImage(cb, out->handle(), VK_IMAGE_LAYOUT_GENERAL, &black, 1, &ib.subresourceRange);
        for (const vk::Buffer& r : reservoirs) vkCmdFillBuffer(cb, r.handle(), 0, VK_WHOLE_SIZE, 0);
    });
    if (!s) return s;

    output_ = std::move(*out);
    pyramid_ = std::move(pyramid);
    candidate_ = std::move(candidate);
    reservoirs_[0] = std::move(reservoirs[0]);
    reservoirs_[1] = std::move(reservoirs[1]);
    birth_[0] = std::move(births[0]);
    birth_[1] = std::move(births[1]);
    tiles_ = std::move(tiles);
    tileHeld_ = std::move(held);
    tileCounts_ = std::move(counts);
    held_ = Held::Unknown;
    lastTiled_ = false;
    birthAllocated_ = birth;
    display_ = std::move(displayed);
    displayAllocated_ = display;
    displayValid_ = false;
    for (uint32_t set = 0; set < 4; ++set) {
        // Sets 0, 1 read reservoirs[i] and write reservoirs[1 - i]; sets 2, 3 read and write reservoirs[i].
        const uint32_t i = set % 2, o = set < 2 ? 1 - i : i;
        VkDescriptorBufferInfo bi[7] = {
            {ubo_.handle(), 0, VK_WHOLE_SIZE},           {pyramid_.handle(), 0, VK_WHOLE_SIZE},
            {candidate_.handle(), 0, VK_WHOLE_SIZE},     {reservoirs_[i].handle(), 0, VK_WHOLE_SIZE},
            {reservoirs_[o].handle(), 0, VK_WHOLE_SIZE}, {birth_[i].handle(), 0, VK_WHOLE_SIZE},
            {birth_[o].handle(), 0, VK_WHOLE_SIZE}};
        const uint32_t bindings[7] = {kFrame, kPyramidBuf, kCandidate, kResPrev, kResCur, kBirthPrev, kBirthCur};
        VkWriteDescriptorSet w[12];
        for (int k = 0; k < 7; ++k)
            w[k] =
                vk::bufferWrite(sets_[set], bindings[k],
                                k == 0 ? VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[k]);
        VkDescriptorImageInfo oi{VK_NULL_HANDLE, output_.arrayView(), VK_IMAGE_LAYOUT_GENERAL};
        w[7] = vk::imageWrite(sets_[set], kOutput, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, &oi);
        VkDescriptorBufferInfo ti{tiles_.handle(), 0, VK_WHOLE_SIZE};
        w[8] = vk::bufferWrite(sets_[set], kTiles, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &ti);
        VkDescriptorBufferInfo hi{tileHeld_.handle(), 0, VK_WHOLE_SIZE};
        w[9] = vk::bufferWrite(sets_[set], kTileHeld, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &hi);
        // The rendered qualities are read only by frames submitted foveated, which bind their own buffer
        // (prepareSubmitted); until then any buffer keeps the set valid.
        VkDescriptorBufferInfo qi{srgbTable_.handle(), 0, VK_WHOLE_SIZE};
        w[10] = vk::bufferWrite(sets_[set], kQuality, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &qi);
        VkDescriptorBufferInfo di{display_.handle(), 0, VK_WHOLE_SIZE};
        w[11] = vk::bufferWrite(sets_[set], kDisplay, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &di);
        vkUpdateDescriptorSets(ctx_.device(), 12, w, 0, nullptr);
    }
    width_ = width;
    height_ = height;
    current_ = 0;
    historyValid_ = false;
    return {};
}

Result<std::unique_ptr<layers::Swapchain>> Compositor::createSwapchain(const layers::SwapchainCreateInfo& info,
                                                                       const SwapchainImageOptions& options) {
    auto sc = VulkanSwapchain::create(ctx_, this, info, options);
    if (!sc) return sc.error();
    return std::unique_ptr<layers::Swapchain>(std::move(*sc));
}

Result<std::unique_ptr<layers::Swapchain>> Compositor::importSwapchain(const layers::SwapchainCreateInfo& info,
                                                                       std::span<const VkImage> images,
                                                                       const SwapchainImageOptions& options) {
    auto sc = VulkanSwapchain::import(ctx_, this, info, images, options);
    if (!sc) return sc.error();
    return std::unique_ptr<layers::Swapchain>(std::move(*sc));
}

}  // namespace wrsfov
