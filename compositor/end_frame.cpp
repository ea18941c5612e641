// Compositor::endFrame, stage by stage (accept, allocate, plan, bind, record, submit, keep), and the
// frame's wait. The resources it runs on are made in compositor.cpp.
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

namespace wrsfov {

using layers::SubmitError;
using namespace detail;

namespace {

Status checkSubmission(const FrameSubmission& sub) {
    using Mode = FrameSubmission::Mode;
    if (sub.mode != Mode::Wait && sub.mode != Mode::Submit && sub.mode != Mode::Record)
        return submitError(SubmitError::InvalidSubmission, "frame submission mode " + std::to_string(int(sub.mode)) +
                                                               " is not Wait, Submit or Record");
    if (sub.mode == Mode::Record) {
        if (!sub.commandBuffer)
            return submitError(SubmitError::InvalidSubmission, "Record needs the caller's command buffer");
        if (!sub.waitSemaphores.empty() || !sub.signalSemaphores.empty())
            return submitError(SubmitError::InvalidSubmission,
                               "semaphores go with Submit or Wait; with Record the caller's own submission waits "
                               "and signals");
    } else if (sub.commandBuffer) {
        return submitError(SubmitError::InvalidSubmission, "a command buffer goes with Record only");
    }
    if (sub.waitStages.size() != sub.waitSemaphores.size())
        return submitError(SubmitError::InvalidSubmission,
                           std::to_string(sub.waitSemaphores.size()) + " wait semaphores need as many stage masks, got " +
                               std::to_string(sub.waitStages.size()));
    for (std::size_t i = 0; i < sub.waitStages.size(); ++i)
        if (sub.waitStages[i] == 0)
            return submitError(SubmitError::InvalidSubmission, "wait stage mask " + std::to_string(i) + " is empty");
    for (auto list : {sub.waitSemaphores, sub.signalSemaphores})
        for (VkSemaphore sem : list)
            if (sem == VK_NULL_HANDLE) return submitError(SubmitError::InvalidSubmission, "a semaphore is VK_NULL_HANDLE");
    return {};
}

}  // namespace

Status Compositor::endFrame(const layers::FrameEndInfo& frame) { return endFrame(frame, FrameSubmission{}); }

Status Compositor::waitFrame() {
    if (!inFlight_) return {};
    inFlight_ = false;
    VkFence f = frameFence_.get();
    const VkResult r = ctx_.waitSubmission(f);
    const double hostMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - submittedAt_).count();
    vkResetFences(ctx_.device(), 1, &f);
    if (r == VK_ERROR_DEVICE_LOST) return submitError(SubmitError::DeviceFailure, kDeviceLost);
    if (r != VK_SUCCESS)
        return submitError(SubmitError::DeviceFailure, std::string("the device failed while compositing: ") + vk::resultString(r));
    collectTimes(hostMs, inFlightTraffic_, inFlightEyes_);
    return {};
}

// ---- Compositor::endFrame, stage by stage --------------------------------------------------------
// accept (refusals: nothing changes), allocate (buffers of the frame's size: a failed allocation
// refuses the frame before any state changed), plan (configuration, which passes run, the frame's
// parameters), inputs (the frame's images bound), record, submit, keep (the history moves on).

Status Compositor::endFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission) {
    FrameWork work;
    if (Status s = acceptFrame(frame, submission, work); !s) return s;
    if (Status s = allocateFrame(frame, work); !s) {
        composeParams_ = work.before.composeParams;  // lastComposeParams() stays the last frame's
        return s;
    }
    planFrame(frame, work);
    bindInputs(frame, work);
    Result<VkCommandBuffer> cb = recordFrame(frame, submission, work);
    if (!cb) {
        restorePlan(work);
        return cb.error();
    }
    stats_.pipelinesMade = recordTally_.made;
    stats_.pipelineMs = recordTally_.ms;
    if (Status s = submitFrame(submission, *cb, work); !s) {
        if (!work.queued) restorePlan(work);
        return s;
    }
    keepFrame(frame, work);
    return {};
}

Status Compositor::acceptFrame(const layers::FrameEndInfo& frame, const FrameSubmission& submission, FrameWork& work) {
    // The last Submit frame first: its command buffer, parameters and descriptor sets are reused.
    if (Status s = waitFrame(); !s) return s;
    if (ctx_.deviceLost()) return submitError(SubmitError::DeviceFailure, kDeviceLost);
    if (Status s = validator_.validate(frame); !s) return s;
    if (Status s = checkSubmission(submission); !s) return s;
    work.record = submission.mode == FrameSubmission::Mode::Record;
    const layers::ProjectionLayer& layer = frame.layers[0];
    for (std::size_t eye = 0; eye < layer.views.size(); ++eye)
        for (auto [s, field] : subImagesOf(layer.views[eye])) {
            if (!s) continue;
            const VulkanSwapchain* vs = vkSwapchain(*s);
            if (!vs || vs->owner() != this)
                return submitError(SubmitError::ForeignSwapchain, std::string(eye == 0 ? "left " : "right ") + field +
                                                                      " swapchain was not created by this compositor");
        }
    work.kind = layers::submittedFoveation(layer);
    if (work.kind != layers::SubmittedFoveation::Full && isOracle((configPending_ ? pending_ : config_).method) &&
        !(layer.views[0].reference && layer.views[1].reference))
        return submitError(SubmitError::InvalidSubmission,
                           "the oracles compare with the full-resolution image, which quad views and rate maps do not "
                           "carry: give each view its reference (ProjectionView::reference) to evaluate them");
    const glm::uvec2 outSize = layers::outputSize(layer);
    work.w = outSize.x;
    work.h = outSize.y;
    work.hasDepth = layer.views[0].depth.has_value();
    work.hasMotion = layer.views[0].motion.has_value();
    work.next = configPending_ ? pending_ : config_;
    if (work.kind != layers::SubmittedFoveation::Full) work.next.foveation = FoveationMode::Submitted;
    work.trafficIn = trafficInputs(layer);
    return {};
}

Status Compositor::allocateFrame(const layers::FrameEndInfo& frame, FrameWork& work) {
    const layers::ProjectionLayer& layer = frame.layers[0];
    // Buffers of a new size first (copy kernel, then the passes'): a failed allocation refuses the
    // frame before any state (size, history, configuration) has changed.
    if (work.next.measureCopy) {
        // Half the frame's traffic is read and half written: the copy moves the same bytes. The floor
        // copy moves a prefix of the same buffers (the floor is part of the traffic).
        const uint64_t half = (trafficBytes(work.next, work.trafficIn) / 2 + 15) / 16 * 16;
        if (copySrc_.size() != half) {
            vkDeviceWaitIdle(ctx_.device());
            const VkBufferUsageFlags use = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
            auto src = ctx_.createBuffer(half, use, false);
            auto dst = ctx_.createBuffer(half, use, false);
            if (!src || !dst)
                return submitError(SubmitError::DeviceFailure,
                                   "copy-kernel buffers: " + (src ? dst.error() : src.error()).message);
            copySrc_ = std::move(*src);
            copyDst_ = std::move(*dst);
            // Real data in both buffers, so the copy never reads or writes untouched pages.
            Status filled = ctx_.submitAndWait([&](VkCommandBuffer c) {
                vkCmdFillBuffer(c, copySrc_.handle(), 0, VK_WHOLE_SIZE, 0x3f800000u);
                vkCmdFillBuffer(c, copyDst_.handle(), 0, VK_WHOLE_SIZE, 0u);
            });
            if (!filled) return submitError(SubmitError::DeviceFailure, filled.message());
            VkDescriptorBufferInfo bi[2] = {{copySrc_.handle(), 0, VK_WHOLE_SIZE},
                                            {copyDst_.handle(), 0, VK_WHOLE_SIZE}};
            VkWriteDescriptorSet w2[2] = {vk::bufferWrite(copySet_, 0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[0]),
                                          vk::bufferWrite(copySet_, 1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &bi[1])};
            vkUpdateDescriptorSets(ctx_.device(), 2, w2, 0, nullptr);
        }
    }
    // Quad views and rate maps come with their own foveation: the frame runs with mode Submitted, and
    // the composed images and qualities are made first, before anything else changes (a failed allocation
    // refuses the frame).
    work.before.composeParams = composeParams_;
    composeParams_ = gpu::ComposeParams{};
    if (work.kind != layers::SubmittedFoveation::Full) {
        composeParams_ = makeComposeParams(layer, glm::uvec2(work.w, work.h), work.next.insetBlendPx);
        // Landed wide samples: only `wrs`'s retention reads them (the oracles do not: wrs_offer_landed).
        // Methods taau-simple and taau: the compose pass gathers the wide samples in their place (landed.z 2
        // and 3; landed.w the kernel's 1 / r^2 in output pixels, or 1 / scale^2 in wide pixels).
        const bool quad = work.kind == layers::SubmittedFoveation::Quad;
        const uint32_t mode = quad ? composeLanded(work.next) : 0u;
        for (gpu::ComposeEye& e : composeParams_.eye) {
            e.landed.z = mode >= 2 ? float(mode) : mode == 1 && e.wide_motion.w < 1.0f ? 1.0f : 0.0f;
            const double r = mode == 3 ? double(work.next.taau.kernel) : double(work.next.taauSimple.radius);
            // `wrs` (landed.z 1): the landed footprint's half-width in wide pixels (wrs_landed_scale).
            e.landed.w = mode == 1 ? work.next.landedFootprint : float(1.0 / (r * r));
        }
        for (int eye = 0; eye < 2; ++eye) {
            const layers::ProjectionView& v = layer.views[eye];
            work.srcColor[eye] = sampledView(v.color);
            if (v.depth) work.srcDepth[eye] = sampledView(v.depth->subImage);
            if (v.motion) work.srcMotion[eye] = sampledView(v.motion->subImage);
            if (v.inset) {
                work.srcColor[2 + eye] = sampledView(v.inset->color);
                if (v.inset->depth) work.srcDepth[2 + eye] = sampledView(v.inset->depth->subImage);
                if (v.inset->motion) work.srcMotion[2 + eye] = sampledView(v.inset->motion->subImage);
            }
            if (v.rateMap) work.srcRate[eye] = sampledView(v.rateMap->subImage);
        }
        if (Status s = prepareSubmitted(work.w, work.h, composeParams_.eye[0].landed.z >= 2.0f ||
                                                            composeParams_.eye[1].landed.z >= 2.0f);
            !s)
            return submitError(SubmitError::DeviceFailure, ctx_.deviceLost() ? std::string(kDeviceLost) : s.message());
        const ComposePass::Sources sources{work.srcColor, work.srcDepth, work.srcMotion, work.srcRate};
        if (Status s = compose_->prepare(work.kind, composeParams_, sources, quality_.handle(), sampler_.get(),
                                         dummy_.layerView(0), dummyUint_.layerView(0));
            !s)
            return submitError(SubmitError::DeviceFailure, ctx_.deviceLost() ? std::string(kDeviceLost) : s.message());
    }
    // The steady display's history, where a quad-view frame runs it (kept while the configuration does).
    const bool display = work.kind == layers::SubmittedFoveation::Quad && displayActive(work.next);
    const bool keepDisplay = display || (displayAllocated_ && work.next.steadyDisplay > 0.0f);
    if (work.w != width_ || work.h != height_ || work.next.trackBirth != birthAllocated_ ||
        (display && !displayAllocated_)) {
        if (Status s = resize(work.w, work.h, work.next.trackBirth, keepDisplay); !s)
            return submitError(SubmitError::DeviceFailure,
                               ctx_.deviceLost() ? std::string(kDeviceLost)
                                                 : "resizing to " + std::to_string(work.w) + "x" +
                                                       std::to_string(work.h) + ": " + s.message());
    }
    return {};
}

void Compositor::planFrame(const layers::FrameEndInfo& frame, FrameWork& work) {
    work.before = {config_,        pending_,     frame_,  configPending_, historyValid_,
                   steadyValid_,   submitted_,   lastFoveation_, lastOffsets_, stats_,
                   params_,        work.before.composeParams};
    if (configPending_) {
        if (pending_.method != config_.method || pending_.foveation != config_.foveation) historyValid_ = false;
        if (!steadyFloorActive(pending_)) steadyValid_ = false;
        config_ = pending_;
        configPending_ = false;
    }
    frame_ = work.next;
    submitted_ = work.kind;
    if (work.kind != layers::SubmittedFoveation::Full)  // after any resize, which binds the placeholder
        for (VkDescriptorSet set : sets_) {
            VkDescriptorBufferInfo qi{quality_.handle(), 0, VK_WHOLE_SIZE};
            VkWriteDescriptorSet wq = vk::bufferWrite(set, kQuality, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, &qi);
            vkUpdateDescriptorSets(ctx_.device(), 1, &wq, 0, nullptr);
        }
    // A change between full and submitted frames is a change of foveation: history starts anew.
    if (frame_.foveation != lastFoveation_) historyValid_ = false;
    lastFoveation_ = frame_.foveation;
    // Which passes run (planPasses, as traffic() and the cost model see them).
    // Quad views that offer landed samples run the steady display (folded into the retain pass).
    const bool landedOffered = composeParams_.eye[0].landed.z == 1.0f || composeParams_.eye[1].landed.z == 1.0f;
    work.passes = planPasses(frame_, work.hasMotion, birthAllocated_,
                             work.kind == layers::SubmittedFoveation::Quad && landedOffered);

    stats_ = FrameStats{};
    stats_.frameIndex = frame.frameIndex;
    stats_.usedDepth = work.hasDepth;
    stats_.usedMotion = work.hasMotion && work.passes.temporal;
    stats_.historyReset = work.passes.temporal && !historyValid_;
    params_ = makeFrameParams(frame_, frame, work.w, work.h, stats_.gazeFallback);
    // Landed wide samples and jitter (EyeParams::motion_rect zw): whether retention reads the eye's
    // landed samples, and whether its views' sample offsets moved since the frame before.
    for (int eye = 0; eye < 2; ++eye) {
        const layers::ProjectionView& v = frame.layers[0].views[eye];
        const glm::vec4 offsets(v.sampleOffset, v.inset ? v.inset->sampleOffset : glm::vec2(0.0f));
        params_.eye[eye].motion_rect.z = composeParams_.eye[eye].landed.z != 0.0f ? gpu::WRS_LANDED_ON : 0u;
        if (params_.eye[eye].motion_rect.z != 0u && frame_.method == Method::Wrs && frame_.landedWeights)
            params_.eye[eye].motion_rect.z |= gpu::WRS_LANDED_WEIGHTED;
        // The wide views' quality (0 without quad views): taau's inset shows above it, and the wide
        // box of a frame that merges every phase applies up to it.
        params_.eye[eye].tile.w = composeParams_.eye[eye].wide_motion.w;
        if (frame_.method == Method::TaauSimple)
            params_.eye[eye].depth_range = glm::vec4(glm::vec2(params_.eye[eye].depth_range),
                                                     frame_.taauSimple.maxWeight, frame_.taauSimple.clipGamma);
        if (frame_.method == Method::Taau) {
            const CompositorConfig::Taau& t = frame_.taau;
            params_.eye[eye].depth_range = glm::vec4(glm::vec2(params_.eye[eye].depth_range), t.maxWeight, t.stability);
            params_.eye[eye].taau = glm::vec4(t.boxSigma, t.fullVelocity, t.lockFrames, t.lockThreshold);
            // Its box's taps one wide pixel apart (on full-resolution frames, adjacent pixels).
            const glm::vec2 perWide = composeParams_.eye[eye].landed.z == 3.0f
                                          ? glm::vec2(composeParams_.eye[eye].landed)
                                          : glm::vec2(1.0f);
            params_.eye[eye].display.x = gpu::wrs_wide_box_steps(perWide);
        }
        params_.eye[eye].motion_rect.w = offsets != lastOffsets_[eye] ? 1u : 0u;
        lastOffsets_[eye] = offsets;
    }
    // The steady display: on frames whose quad views offer landed samples (which only `wrs`'s do).
    work.passes.display = work.passes.display && displayAllocated_ &&
                          (params_.eye[0].motion_rect.z != 0u || params_.eye[1].motion_rect.z != 0u);
    if (work.passes.display) {
        params_.tuning.z = frame_.steadyDisplay;
        // Its neighbourhood's taps one wide pixel apart (the merge's wide box has the same spacing).
        for (int eye = 0; eye < 2; ++eye) {
            params_.eye[eye].display.x = gpu::wrs_wide_box_steps(glm::vec2(composeParams_.eye[eye].landed));
            params_.eye[eye].display.y = glm::floatBitsToUint(frame_.steadyDisplaySpeed);
        }
    }
    stats_.steadyDisplay = work.passes.display;
    // Every phase merged (wrs_submitted.h): on a frame of `wrs` whose wide views were jittered, no floor
    // rule (so no tile skips it) and each eye's wide box, one wide pixel apart.
    const bool jittered = params_.eye[0].motion_rect.w != 0u || params_.eye[1].motion_rect.w != 0u;
    if (frame_.method == Method::Wrs && frame_.phaseMerge && jittered &&
        (params_.eye[0].motion_rect.z != 0u || params_.eye[1].motion_rect.z != 0u)) {
        params_.tuning.w = 0.0f;
        for (int eye = 0; eye < 2; ++eye)
            params_.eye[eye].depth_rect.w = gpu::wrs_wide_box_steps(glm::vec2(composeParams_.eye[eye].landed));
    }
    stats_.phaseMerge = params_.eye[0].depth_rect.w != 0u;
    // Sparse retention: this frame reads the held qualities at heldPrev_ and writes the other half.
    work.sparse = work.passes.sparse;
    work.tilesPerEye = groups(work.w, gpu::WRS_TILE) * groups(work.h, gpu::WRS_TILE);
    const uint32_t tileCount = work.tilesPerEye * uint32_t(WRS_EYES);
    params_.held.x = heldPrev_ * tileCount;
    params_.held.y = (1 - heldPrev_) * tileCount;
    params_.held.w = 2 * tileCount;  // the superblocks
    stats_.sparse = work.sparse;
    stats_.retained = usesRetainPass(frame_.method);
    std::memcpy(ubo_.mapped(), &params_, sizeof(params_));

    // In place: the retain pass skips the store of a pixel whose reservoir did not change (a kept
    // sample of a still scene: most of the periphery).
    work.inPlace = work.passes.inPlace;
    work.written = work.inPlace ? current_ : 1 - current_;
    stats_.inPlace = work.inPlace;
    work.tiled = work.passes.tiled;
    stats_.tiled = work.tiled;
    work.steady = work.passes.steady;
    stats_.steadyFloor = work.steady;
}

void Compositor::bindInputs(const layers::FrameEndInfo& frame, FrameWork& work) {
    const layers::ProjectionLayer& layer = frame.layers[0];
    // Per-frame inputs: the last released image of each swapchain.
    work.set = sets_[current_ + (work.inPlace ? 2 : 0)];
    // The compose pass's output binding (method fov on quad views writes the output there), after any resize.
    if (compose_ && work.kind != layers::SubmittedFoveation::Full) compose_->bindOutput(output_.arrayView());
    VkDescriptorImageInfo ii[6];
    const bool composed = work.kind == layers::SubmittedFoveation::Quad;
    for (int eye = 0; eye < 2; ++eye) {
        const layers::ProjectionView& v = layer.views[eye];
        // Quad views: the compose pass's images, layer = eye.
        ii[0 + eye] = {sampler_.get(), composed ? compose_->color().layerView(eye) : sampledView(v.color),
                       VK_IMAGE_LAYOUT_GENERAL};
        ii[2 + eye] = {sampler_.get(),
                       !v.depth ? dummy_.layerView(0)
                                : composed ? compose_->depth().layerView(eye) : sampledView(v.depth->subImage),
                       VK_IMAGE_LAYOUT_GENERAL};
        ii[4 + eye] = {sampler_.get(),
                       !v.motion ? dummy_.layerView(0)
                                 : composed ? compose_->motion().layerView(eye) : sampledView(v.motion->subImage),
                       VK_IMAGE_LAYOUT_GENERAL};
    }
    // The same images, field of view and gaze in both views (a monitor, a mono preview): the passes
    // run once and the right eye gets copies, output and history alike, so a later stereo frame
    // finds the history it would have had.
    // Not for the rules that draw random numbers (wrs-paper, wrs with the reservoir rule): their
    // hash includes the eye, so two identical views legitimately select differently.
    // A frame submitted foveated is mono where both views read the same images (wide views, insets, rate
    // maps, references) with the same parameters: the compose pass then runs for the left eye only too.
    const bool eyeRandom = frame_.method == Method::WrsPaper ||
                           (frame_.method == Method::Wrs && frame_.equalQuality == EqualQuality::Reservoir);
    const auto& src = work;
    const bool sameInputs =
        work.kind == layers::SubmittedFoveation::Full
            ? ii[0].imageView == ii[1].imageView && ii[2].imageView == ii[3].imageView &&
                  ii[4].imageView == ii[5].imageView
            : src.srcColor[0] == src.srcColor[1] && src.srcColor[2] == src.srcColor[3] &&
                  src.srcDepth[0] == src.srcDepth[1] && src.srcDepth[2] == src.srcDepth[3] &&
                  src.srcMotion[0] == src.srcMotion[1] && src.srcMotion[2] == src.srcMotion[3] &&
                  src.srcRate[0] == src.srcRate[1] &&
                  std::memcmp(&composeParams_.eye[0], &composeParams_.eye[1], sizeof(gpu::ComposeEye)) == 0;
    const auto refView = [&](int eye) {
        return layer.views[eye].reference ? sampledView(*layer.views[eye].reference) : VK_NULL_HANDLE;
    };
    work.mono = !eyeRandom && sameInputs && refView(0) == refView(1) &&
                std::memcmp(&params_.eye[0], &params_.eye[1], sizeof(gpu::EyeParams)) == 0;
    work.eyes = work.mono ? 1u : uint32_t(WRS_EYES);
    stats_.monoViews = work.mono;
    // The oracles' full-resolution reference of a frame submitted foveated (a placeholder otherwise).
    VkDescriptorImageInfo ri[2];
    for (int eye = 0; eye < 2; ++eye) {
        const layers::ProjectionView& v = layer.views[eye];
        ri[eye] = {sampler_.get(), v.reference ? sampledView(*v.reference) : dummy_.layerView(0),
                   VK_IMAGE_LAYOUT_GENERAL};
    }
    // Quad views: the compose pass's parameters and the wide views, from which the retain pass takes each
    // pixel's landed wide sample (placeholders otherwise).
    VkDescriptorImageInfo wi[2];
    for (int eye = 0; eye < 2; ++eye)
        wi[eye] = {sampler_.get(), composed ? work.srcColor[eye] : dummy_.layerView(0), VK_IMAGE_LAYOUT_GENERAL};
    const VkDescriptorBufferInfo ci{composed ? compose_->paramsBuffer() : ubo_.handle(), 0, sizeof(gpu::ComposeParams)};
    VkWriteDescriptorSet wr[6];
    for (uint32_t k = 0; k < 3; ++k)
        wr[k] = vk::imageWrite(work.set, kColor + k, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, &ii[2 * k], 2);
    wr[3] = vk::imageWrite(work.set, kReference, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, ri, 2);
    wr[4] = vk::imageWrite(work.set, kWide, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, wi, 2);
    wr[5] = vk::bufferWrite(work.set, kCompose, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, &ci);
    vkUpdateDescriptorSets(ctx_.device(), 6, wr, 0, nullptr);
}

void Compositor::restorePlan(const FrameWork& work) {
    const FrameWork::Before& b = work.before;
    config_ = b.config;
    pending_ = b.pending;
    frame_ = b.frame;
    configPending_ = b.configPending;
    historyValid_ = b.historyValid;
    steadyValid_ = b.steadyValid;
    submitted_ = b.submitted;
    lastFoveation_ = b.lastFoveation;
    lastOffsets_ = b.lastOffsets;
    stats_ = b.stats;
    params_ = b.params;
    composeParams_ = b.composeParams;
    std::memcpy(ubo_.mapped(), &params_, sizeof(params_));
}

Status Compositor::submitFrame(const FrameSubmission& submission, VkCommandBuffer cb, FrameWork& work) {
    if (work.record) {  // the caller's buffer holds the frame; the caller submits
        work.queued = true;
        return {};
    }
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    si.waitSemaphoreCount = uint32_t(submission.waitSemaphores.size());
    si.pWaitSemaphores = submission.waitSemaphores.data();
    si.pWaitDstStageMask = submission.waitStages.data();
    si.signalSemaphoreCount = uint32_t(submission.signalSemaphores.size());
    si.pSignalSemaphores = submission.signalSemaphores.data();
    // Both modes submit the same way; Wait then waits here, before the history moves on, so
    // that a failed frame changes nothing (waitFrame also collects the GPU times).
    submittedAt_ = std::chrono::steady_clock::now();
    const VkResult r = ctx_.submitNoWait(si, frameFence_.get());
    if (r == VK_ERROR_DEVICE_LOST) return submitError(SubmitError::DeviceFailure, kDeviceLost);
    if (r != VK_SUCCESS)
        return submitError(SubmitError::DeviceFailure,
                           std::string("the device failed while compositing: ") + vk::resultString(r));
    work.queued = true;
    inFlight_ = true;
    inFlightTraffic_ = work.trafficIn;
    inFlightEyes_ = work.eyes;
    if (submission.mode == FrameSubmission::Mode::Wait)
        if (Status s = waitFrame(); !s) return s;
    return {};
}

void Compositor::keepFrame(const layers::FrameEndInfo& frame, const FrameWork& work) {
    if (work.passes.temporal) {
        current_ = work.written;
        historyValid_ = true;
    } else {
        historyValid_ = false;  // the history buffers did not follow this frame
    }
    if (work.sparse) heldPrev_ = 1 - heldPrev_;
    held_ = work.sparse ? Held::Valid : Held::Unknown;
    if (work.steady) steadySlot_ = 1 - steadySlot_;
    steadyValid_ = work.steady;
    if (work.passes.display) displaySlot_ = 1 - displaySlot_;
    displayValid_ = work.passes.display;
    lastSparse_ = work.sparse;
    validator_.accept(frame);
}

Status Compositor::prepareSubmitted(uint32_t width, uint32_t height, bool gathered) {
    // Made on the first frame submitted foveated, so that a compositor of full-resolution frames
    // allocates and submits nothing more than before.
    if (!compose_) {
        auto compose = ComposePass::create(ctx_, srgbTable_.handle());
        if (!compose) return compose.error();
        compose_ = std::move(*compose);
    }
    if (!dummyUint_) {
        // The placeholder of a rate map (an integer image, as usampler2D needs).
        vk::ImageCreateInfo uci;
        uci.format = VK_FORMAT_R8_UINT;
        uci.usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT;
        auto img = ctx_.createImage(uci);
        if (!img) return named("rate map placeholder", img.error());
        Status st = ctx_.submitAndWait([&](VkCommandBuffer cmd) {
            vk::layoutTransition(cmd, img->handle(), VK_IMAGE_ASPECT_COLOR_BIT, 1, VK_IMAGE_LAYOUT_UNDEFINED,
                                 VK_IMAGE_LAYOUT_GENERAL);
            VkClearColorValue zero{};
            VkImageSubresourceRange range{VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
            vkCmdClearColorImage(cmd, img->handle(), VK_IMAGE_LAYOUT_GENERAL, &zero, 1, &range);
        });
        if (!st) return st;
        dummyUint_ = std::move(*img);
    }
    // Each pixel's quality, then each tile's largest, then (taau) each pixel's gathered wide samples
    // (compose.comp; `wrs`'s retain pass reads its landed samples from the wide views).
    const uint64_t tiles = uint64_t(groups(width, gpu::WRS_TILE)) * groups(height, gpu::WRS_TILE);
    const uint64_t bytes = (uint64_t(width) * height * (gathered ? 3 : 1) + tiles) * WRS_EYES * 4;
    if (quality_.size() != bytes) {
        auto q = ctx_.createBuffer(bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);
        if (!q) return named("rendered qualities", q.error());
        quality_ = std::move(*q);
    }
    return {};
}

}  // namespace wrsfov
