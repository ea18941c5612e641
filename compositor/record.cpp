// The frame's commands (recordFrame, recordPasses), the passes as commands (Compositor::record*, in the
// order recordPasses calls them) and their times (collectTimes).
#include "compositor/compositor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "compositor/compose.h"
#include "compositor/compositor_internal.h"
#include "compositor/frame_work.h"
#include "compositor/input.h"
#include "compositor/pass_table.h"
#include "compositor/swapchain_vk.h"

namespace wrsfov {

using layers::SubmitError;
using namespace detail;

Result<VkCommandBuffer> Compositor::recordFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission,
                                                const FrameWork& work) {
    recordTally_ = {};  // endFrame keeps it in the frame's stats
    if (work.record) {
        // Rehearsed first in the compositor's own command buffer (idle: acceptFrame waited for its last
        // use), so that every pipeline the frame binds exists before a command goes into the caller's
        // buffer: a pipeline failing half-way there could not be taken back. The cost is one more
        // recording of the frame's few dozen commands on the host.
        const Status rehearsal = recordPasses(cmd_, true, frame, work);
        vkResetCommandBuffer(cmd_, 0);  // never submitted; the next own recording resets it again anyway
        if (!rehearsal) return rehearsal.error();
        if (Status s = recordPasses(submission.commandBuffer, false, frame, work); !s) return s.error();
        return submission.commandBuffer;
    }
    if (Status s = recordPasses(cmd_, true, frame, work); !s) return s.error();
    return cmd_;
}

Status Compositor::recordPasses(VkCommandBuffer cb, bool own, const layers::FrameEndInfo& frame,
                                const FrameWork& work) {
    const layers::ProjectionLayer& layer = frame.layers[0];
    auto failed = [&](const char* call, VkResult r) {
        return submitError(SubmitError::DeviceFailure,
                           std::string("recording the frame: ") + call + " failed: " + vk::resultString(r));
    };
    recordError_.reset();
    if (own) {
        if (VkResult r = vkResetCommandBuffer(cb, 0); r != VK_SUCCESS) return failed("vkResetCommandBuffer", r);
        VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
        bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
        if (VkResult r = vkBeginCommandBuffer(cb, &bi); r != VK_SUCCESS) return failed("vkBeginCommandBuffer", r);
    }
    const bool timing = ctx_.timestampPeriodNs() > 0 && !work.record;
    if (timing) vkCmdResetQueryPool(cb, queries_.get(), 0, kFrameStamps);
    {
        // Whatever the application wrote (uploads, its own rendering) and the last frame's
        // readbacks are done before the passes read or overwrite them.
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                          VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_MEMORY_READ_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
    }
    // Images an application leaves in another layout (an OpenXR runtime's: colour attachment) are
    // read in GENERAL and handed back afterwards; each image once, however many views use it.
    std::vector<std::pair<const VulkanSwapchain*, uint32_t>> handOver;
    for (const layers::ProjectionView& v : layer.views)
        for (auto [s, field] : subImagesOf(v)) {
            if (!s) continue;
            const VulkanSwapchain* vs = vkSwapchain(*s);
            std::pair<const VulkanSwapchain*, uint32_t> img{vs, uint32_t(vs->lastReleased())};
            if (vs->restingLayout() != VK_IMAGE_LAYOUT_GENERAL &&
                std::find(handOver.begin(), handOver.end(), img) == handOver.end())
                handOver.push_back(img);
        }
    auto transitionInputs = [&](bool toGeneral) {
        for (auto [vs, index] : handOver) {
            const VkImageLayout rest = vs->restingLayout();
            vk::layoutTransition(cb, vs->image(index), vs->aspect(), vs->info().arraySize,
                                 toGeneral ? rest : VK_IMAGE_LAYOUT_GENERAL, toGeneral ? VK_IMAGE_LAYOUT_GENERAL : rest);
        }
    };
    transitionInputs(true);
    const PassPlan& p = work.passes;
    const Recording plan{cb,         work.w,     work.h,      work.eyes,    work.hasDepth, work.hasMotion,
                         p.retain,   p.wrsPaper, p.taa,       p.temporal,   p.pyramid,     work.tiled,
                         work.sparse, work.inPlace, work.mono, timing,       work.steady,   p.display,
                         work.written, work.tilesPerEye};
    // The passes, in the order they run (the frame's pass table, pass_table.h); timestamps between the
    // stages (kFrameStamps, passStage).
    recordHistoryStart(plan);
    stamp(plan, 0);
    uint32_t stamped = 0;
    bool setBound = false, listsReset = false;
    for (const PassDispatch& d : framePasses(frame_, p, work.trafficIn, composeLandedMode(composeParams_))) {
        while (stamped + 1 < passStage(d.pass)) stamp(plan, ++stamped);
        if (d.pass == PassId::Compose) {  // a set of its own layout: the passes' set is bound after it
            recordCompose(plan, d);
            continue;
        }
        if (!setBound) {
            vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_.get(), 0, 1, &work.set, 0,
                                    nullptr);
            setBound = true;
        }
        if ((d.pass == PassId::Reach || d.pass == PassId::Classify) && !listsReset) {
            recordListsReset(plan);
            listsReset = true;
        }
        recordDispatch(plan, d);
    }
    recordMonoCopies(plan);
    while (stamped < kFrameStamps - 1) stamp(plan, ++stamped);
    transitionInputs(false);
    recordTileCounts(plan, work.record);
    // The output (and the history) is visible to whatever the caller runs next on the queue or
    // after its semaphores: presentation, a copy, its own composition.
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                      VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
    if (recordError_) {
        // Every command recorded before the failure is valid; the buffer is never submitted.
        if (own) vkResetCommandBuffer(cb, 0);
        return submitError(SubmitError::DeviceFailure, recordError_->message);
    }
    if (own)
        if (VkResult r = vkEndCommandBuffer(cb); r != VK_SUCCESS) return failed("vkEndCommandBuffer", r);
    lastTiled_ = work.tiled && !work.record;  // waitFrame reads the counts
    return {};
}

void Compositor::stamp(const Recording& plan, uint32_t i) {
    if (plan.timing) vkCmdWriteTimestamp(plan.cb, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), i);
}

void Compositor::recordCompose(const Recording& plan, const PassDispatch& d) {
    if (recordError_) return;
    std::array<uint32_t, 9> k;
    std::copy_n(d.constants.begin(), k.size(), k.begin());
    // Its dispatches: the whole output (a rate map), or per eye the groups of its inset rectangle
    // (insetGroups) or the up to four rectangles around it.
    const glm::uvec2 out(plan.w, plan.h);
    const glm::uvec3 all = dispatchSize(DispatchShape::Pixels, 0, plan.w, plan.h, 1);
    std::vector<ComposeDispatch> list;
    auto rect = [&](uint32_t x0, uint32_t y0, uint32_t x1, uint32_t y1, uint32_t eye) {
        if (x0 < x1 && y0 < y1) list.push_back({{x0, y0, eye}, {x1 - x0, y1 - y0, 1}});
    };
    for (uint32_t eye = 0; eye < plan.eyes; ++eye) {
        const glm::uvec4 r = insetGroups(composeParams_.eye[eye], out);
        const bool none = r.x >= r.z || r.y >= r.w;
        if (d.shape == DispatchShape::InsetGroups) {
            rect(r.x, r.y, r.z, r.w, eye);
        } else if (d.shape == DispatchShape::OutsideInset) {
            if (none) {
                rect(0, 0, all.x, all.y, eye);
                continue;
            }
            rect(0, 0, all.x, r.y, eye);      // above
            rect(0, r.w, all.x, all.y, eye);  // below
            rect(0, r.y, r.x, r.w, eye);      // left
            rect(r.z, r.y, all.x, r.w, eye);  // right
        } else {
            rect(0, 0, all.x, all.y, eye);
        }
    }
    if (Status s = compose_->record(plan.cb, k, list, &recordTally_); !s) {
        recordError_ = s.error();
        return;
    }
    recordBarrier(plan.cb, d.after);
}

void Compositor::recordHistoryStart(const Recording& plan) {
    VkCommandBuffer cb = plan.cb;
    if (plan.temporal && !historyValid_) {
        // No usable history: all-zero reservoirs are invalid on load (M = 0), so every pixel starts anew.
        vkCmdFillBuffer(cb, reservoirs_[current_].handle(), 0, VK_WHOLE_SIZE, 0);
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    }
    if (plan.sparse && (!historyValid_ || held_ == Held::Unknown)) {
        // The held qualities this frame reads: nothing after a reset (the reservoirs are empty), and
        // anything where the last frame did not record them (every pixel's reservoir is real there).
        const uint32_t word = historyValid_ ? 0x3f800000u : 0u;  // 1.0f: the best quality there is
        vkCmdFillBuffer(cb, tileHeld_.handle(), VkDeviceSize(params_.held.x) * 4,
                        VkDeviceSize(plan.tilesPerEye) * WRS_EYES * 4, word);
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                          VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    }
}

void Compositor::recordListsReset(const Recording& plan) {
    uint32_t args[gpu::WRS_TILE_LISTS][4];
    for (auto& a : args) a[0] = 0, a[1] = 1, a[2] = 1, a[3] = 0;  // no tiles yet; y = z = 1
    vkCmdUpdateBuffer(plan.cb, tiles_.handle(), 0, sizeof(args), args);
    vk::memoryBarrier(plan.cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

void Compositor::recordBarrier(VkCommandBuffer cb, Barrier b) {
    if (b == Barrier::Compute) computeBarrier(cb);
    if (b == Barrier::Lists) listsBarrier(cb);
}

void Compositor::recordDispatch(const Recording& plan, const PassDispatch& d) {
    VkCommandBuffer cb = plan.cb;
    auto push = [&](const gpu::LevelPush& lp) {
        vkCmdPushConstants(cb, pipelineLayout_.get(), VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(lp), &lp);
    };
    // The push constants a pass reads (LevelPush): the pyramid's level; the steady floor's and the
    // display's slots, written: the slot the last frame did not write; read: the last frame's, where it
    // wrote one (a history reset starts either anew, as it does the reservoirs).
    switch (d.pass) {
        case PassId::Steady:
            push({0, 1 - steadySlot_, steadySlot_, steadyValid_ && historyValid_ ? 1u : 0u});
            break;
        case PassId::Retain:  // the steady display (constant 10) reads and writes its slots
            if (d.constants[10]) push({0, 1 - displaySlot_, displaySlot_, displayValid_ && historyValid_ ? 1u : 0u});
            break;
        default:
            break;
    }
    if (!bindPipeline(cb, shaderIndex(d.shader), d.constants)) return;
    auto dispatch = [&](DispatchShape shape, uint32_t level) {
        const glm::uvec3 g = dispatchSize(shape, level, plan.w, plan.h, plan.eyes);
        vkCmdDispatch(cb, g.x, g.y, g.z);
    };
    switch (d.shape) {
        case DispatchShape::TileList:
            vkCmdDispatchIndirect(cb, tiles_.handle(), VkDeviceSize(16) * uint32_t(d.tileClass));
            break;
        case DispatchShape::MipTiles:  // every level in one dispatch of WRS_MIP_TILE-pixel tiles
            push({d.level, 0, 0, 0});
            dispatch(d.shape, d.level);
            break;
        case DispatchShape::GaussLevels:  // one dispatch per level, each reading the one before
            for (uint32_t level = 1; level < WRS_LEVELS; ++level) {
                push({level, 0, 0, 0});
                dispatch(DispatchShape::Level, level);
                if (level + 1 < WRS_LEVELS) computeBarrier(cb);
            }
            break;
        default:
            dispatch(d.shape, d.level);
            break;
    }
    recordBarrier(cb, d.after);
}

void Compositor::recordMonoCopies(const Recording& plan) {
    if (!plan.mono) return;
    VkCommandBuffer cb = plan.cb;
    // Right eye = left eye: output layer, and the history this frame wrote; the copies read and
    // write what the passes wrote.
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT);
    VkImageCopy ic{};
    ic.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    ic.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 1};
    ic.extent = {plan.w, plan.h, 1};
    vkCmdCopyImage(cb, output_.handle(), VK_IMAGE_LAYOUT_GENERAL, output_.handle(), VK_IMAGE_LAYOUT_GENERAL, 1, &ic);
    const VkDeviceSize eyeBytes = VkDeviceSize(plan.w) * plan.h * 16;
    const VkBufferCopy bc{0, eyeBytes, eyeBytes};
    if (plan.temporal) vkCmdCopyBuffer(cb, reservoirs_[plan.written].handle(), reservoirs_[plan.written].handle(), 1, &bc);
    if (plan.temporal && birthAllocated_)
        vkCmdCopyBuffer(cb, birth_[plan.written].handle(), birth_[plan.written].handle(), 1, &bc);
    const VkBufferCopy hc{VkDeviceSize(params_.held.y) * 4, VkDeviceSize(params_.held.y + plan.tilesPerEye) * 4,
                          VkDeviceSize(plan.tilesPerEye) * 4};
    if (plan.sparse) vkCmdCopyBuffer(cb, tileHeld_.handle(), tileHeld_.handle(), 1, &hc);
    if (plan.display) {  // the right eye's displayed colour in the slot this frame wrote (8 B a pixel)
        const VkDeviceSize displayBytes = VkDeviceSize(plan.w) * plan.h * 8;
        const VkDeviceSize slot = VkDeviceSize(1 - displaySlot_) * 2 * displayBytes;
        const VkBufferCopy dc{slot, slot + displayBytes, displayBytes};
        vkCmdCopyBuffer(cb, display_.handle(), display_.handle(), 1, &dc);
    }
    if (plan.steady) {  // the right eye's steady floor, which its next stereo frame reads
        const glm::uvec4 l4 = params_.levels[gpu::WRS_STEADY_LEVEL];
        const VkDeviceSize left = gpu::wrs_steady_offset(l4, 1 - steadySlot_, 0);
        const VkDeviceSize right = gpu::wrs_steady_offset(l4, 1 - steadySlot_, 1);
        const VkBufferCopy sc{left * 8, right * 8, VkDeviceSize(l4.x) * l4.y * 8};
        vkCmdCopyBuffer(cb, pyramid_.handle(), pyramid_.handle(), 1, &sc);
    }
    vk::memoryBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

void Compositor::recordTileCounts(const Recording& plan, bool record) {
    if (!plan.tiled || record) return;  // Record mode: the caller's submission, no statistics
    // The lists' counts, for FrameStats::tiles.
    vk::memoryBarrier(plan.cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    const VkBufferCopy tc{0, 0, 16 * gpu::WRS_TILE_LISTS};
    vkCmdCopyBuffer(plan.cb, tiles_.handle(), tileCounts_.handle(), 1, &tc);
    vk::memoryBarrier(plan.cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                      VK_ACCESS_HOST_READ_BIT);
}

void Compositor::collectTimes(double hostMs, const TrafficInputs& trafficIn, uint32_t eyes) {
    if (lastTiled_) {
        for (uint32_t k = 0; k < gpu::WRS_TILE_LISTS; ++k)
            std::memcpy(&stats_.tiles[k], static_cast<const uint8_t*>(tileCounts_.mapped()) + 16 * k, 4);
        // The skip list's fourth word counts the tiles whose motion the classification read.
        std::memcpy(&stats_.motionTiles, static_cast<const uint8_t*>(tileCounts_.mapped()) + 16 * gpu::WRS_TILE_SKIP + 12, 4);
    }
    TrafficInputs in = trafficIn;
    if (stats_.sparse && lastTiled_) {
        in.retainShare = stats_.retainShare();
        in.motionShare = stats_.motionShare();
    }
    if (ctx_.timestampPeriodNs() <= 0) return;
    uint64_t ts[kFrameStamps];
    if (vkGetQueryPoolResults(ctx_.device(), queries_.get(), 0, kFrameStamps, sizeof(ts), ts, sizeof(uint64_t),
                              VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT) == VK_SUCCESS) {
        double ms = ctx_.timestampPeriodNs() * 1e-6;
        stats_.gpu.compose = double(ts[1] - ts[0]) * ms;
        stats_.gpu.pyramid = double(ts[2] - ts[1]) * ms;
        stats_.gpu.foveate = double(ts[3] - ts[2]) * ms;
        stats_.gpu.temporal = double(ts[4] - ts[3]) * ms;
        stats_.gpu.total = double(ts[4] - ts[0]) * ms;
        stats_.gpu.valid = true;
    }
    if (ctx_.isCpuDevice()) {  // see PassTimes::hostTimed
        stats_.gpu.total = hostMs;
        stats_.gpu.hostTimed = true;
    }
    if (frame_.measureCopy) {
        // The yardsticks, each in a submission of its own after the frame: lavapipe moves time
        // between adjacent dispatches of one submission, which made a copy recorded before the
        // passes read as a fraction of what it costs alone.
        stats_.gpu.copy = timeCopy(trafficBytes(frame_, in) / WRS_EYES * eyes);
        stats_.gpu.copyFloor = timeCopy(floorBytes(frame_, in) / WRS_EYES * eyes);
    }
}

}  // namespace wrsfov
