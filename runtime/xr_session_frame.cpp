// The runtime's frame loop: xrWaitFrame's timing, xrBeginFrame, and xrEndFrame (its checks, the
// projection layer through the compositor, the quad layers, the recording).
#include <chrono>
#include <cmath>
#include <cstring>
#include <thread>

#define GLM_ENABLE_EXPERIMENTAL
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtx/quaternion.hpp>

#include "compositor/host_app.h"
#include "compositor/input.h"
#include "compositor/reference.h"
#include "compositor/swapchain_vk.h"
#include "gaze/frame_gaze.h"
#include "preview/gaze_input.h"
#include "scenes/png.h"

#include <opencv2/imgcodecs.hpp>
#include "xr_common/xr_frame.h"
#include "xr_common/xr_inset.h"
#include "runtime/xr_objects.h"
#include "runtime/xr_verify.h"
#include "runtime/xr_session.h"

namespace wrsfov::xr {

// ---------------------------------------------------------------------------------------------
// Frames

XRAPI_ATTR XrResult XRAPI_CALL xrWaitFrame(XrSession h, const XrFrameWaitInfo* info, XrFrameState* state) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if ((info && info->type != XR_TYPE_FRAME_WAIT_INFO) || !state || state->type != XR_TYPE_FRAME_STATE)
        return XR_ERROR_VALIDATION_FAILURE;
    std::unique_lock lock(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    // A second xrWaitFrame waits until the frame before has been begun (the specification's order;
    // a pipelined application waits at most one frame ahead).
    s->frameCv.wait(lock, [s] { return s->waited == 0 || !s->running; });
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    const Instance& inst = *s->instance;
    const XrDuration p = period(inst);
    XrTime now = nowXrTime();
    if (s->nextDisplayTime == 0)
        s->nextDisplayTime = inst.config.pace ? now + p : std::max(inst.freeDisplayTime.load(), inst.epoch) + p;
    XrTime display;
    if (inst.config.pace) {
        // Paced by the display and by the compositor: consecutive frames are at least the
        // compositor's time apart (hand-over to completion, measured and smoothed; rounded up to
        // whole periods), so a compositor slower than the display slows the loop instead of queueing
        // frames, and xrEndFrame rarely finds the frame before still in flight (which it then waits
        // for: one frame in flight at most). The frame is shown at the first such slot at least half a
        // period away; a late application skips slots. Display times stay on the slot grid and
        // increase; the application is woken one period before its slot.
        const XrDuration composite = std::min<XrDuration>(s->compositeNs, 1000000000);  // a second at most
        const XrDuration interval = std::max<XrDuration>(1, (composite + p - 1) / p) * p;
        if (s->lastDisplayTime != 0) s->nextDisplayTime = std::max(s->nextDisplayTime, s->lastDisplayTime + interval);
        const XrTime earliest = now + p / 2;
        if (s->nextDisplayTime < earliest) s->nextDisplayTime += ((earliest - s->nextDisplayTime) / p + 1) * p;
        display = s->nextDisplayTime;
        s->nextDisplayTime += p;
        s->lastDisplayTime = display;
        const XrTime wake = display - p;
        if (wake > now) {
            // Sleeps with the frame lock released: xrBeginFrame / xrEndFrame of the frame before go on.
            s->frameCv.wait_for(lock, std::chrono::nanoseconds(wake - now),
                                [s] { return !s->running || s->shutdown; });
            if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
        }
    } else {
        display = s->nextDisplayTime;
        s->nextDisplayTime += p;
        inst.freeDisplayTime = display;
    }
    ++s->waited;
    s->waitedDisplayTimes.push_back(display);
    if (s->state == XR_SESSION_STATE_READY && !s->stopRequested) {
        setState(s, XR_SESSION_STATE_SYNCHRONIZED);
        setState(s, XR_SESSION_STATE_VISIBLE);
        setState(s, XR_SESSION_STATE_FOCUSED);
    }
    state->predictedDisplayTime = display;
    state->predictedDisplayPeriod = p;
    state->shouldRender =
        s->state == XR_SESSION_STATE_VISIBLE || s->state == XR_SESSION_STATE_FOCUSED ? XR_TRUE : XR_FALSE;
    return XR_SUCCESS;
}

XRAPI_ATTR XrResult XRAPI_CALL xrBeginFrame(XrSession h, const XrFrameBeginInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (info && info->type != XR_TYPE_FRAME_BEGIN_INFO) return XR_ERROR_VALIDATION_FAILURE;
    std::lock_guard lock(s->frameMutex);
    if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
    if (s->waited == 0) return XR_ERROR_CALL_ORDER_INVALID;
    --s->waited;
    s->frameDisplayTime = s->waitedDisplayTimes.front();  // pipelined: the oldest waited frame is begun
    s->waitedDisplayTimes.pop_front();
    s->frameCv.notify_all();  // a pipelined xrWaitFrame may go on
    if (s->begun) {
        ++s->framesDiscarded;  // the previous frame was begun and never ended
        return XR_FRAME_DISCARDED;
    }
    s->begun = true;
    return XR_SUCCESS;
}

namespace {

/// Reads one submitted sub-image back (for recording).
Result<HostImage> readSubImage(const layers::SubImage& sub) {
    auto* sc = sub.swapchain;
    auto bytes = sc->read(uint32_t(sc->lastReleased()), sub.arrayIndex);
    if (!bytes) return bytes.error();
    HostImage full = HostImage::make(sc->info().format, sc->info().width, sc->info().height);
    full.data = std::move(*bytes);
    if (sub.rect.x == 0 && sub.rect.y == 0 && sub.rect.width == full.width && sub.rect.height == full.height)
        return full;
    return full.crop(uint32_t(sub.rect.x), uint32_t(sub.rect.y), sub.rect.width, sub.rect.height);
}

/// Appends a composited frame to the recording: what the application submitted, our gaze, and the
/// compositor's output (NNNNNN_{L,R}_output.png beside the sequence's files).
void recordFrame(Session* s, const layers::FrameEndInfo& f, bool withOutput) {
    const RuntimeConfig& c = s->instance->config;
    if (c.record.empty() || s->recordingStopped) return;
    auto stop = [&](const std::string& why) {
        logLine("recording stopped: " + why);
        s->recordingStopped = true;
    };
    const layers::ProjectionLayer& layer = f.layers[0];
    std::array<EyeSubmission, 2> eyes;
    const bool quad = layers::submittedFoveation(layer) == layers::SubmittedFoveation::Quad;
    std::array<std::optional<std::pair<HostImage, HostImage>>, 2> views;  // quad views: wide, inset (sRGB)
    for (int e = 0; e < 2 && quad; ++e) {
        // Quad views: the sequence's colour, depth and motion are what the four views compose to at the
        // output's size (the compose pass's CPU reference); the views themselves go beside them.
        const layers::ProjectionView& v = layer.views[e];
        QuadSources q;
        auto read = [&](const layers::SubImage& sub, HostImage& out) {
            auto img = readSubImage(sub);
            if (!img) {
                stop(img.error().message);
                return false;
            }
            out = std::move(*img);
            return true;
        };
        if (!read(v.color, q.wideColor) || !read(v.inset->color, q.insetColor)) return;
        if (v.depth) {
            q.wideDepth.emplace();
            q.insetDepth.emplace();
            if (!read(v.depth->subImage, *q.wideDepth) || !read(v.inset->depth->subImage, *q.insetDepth)) return;
        }
        if (v.motion) {
            q.wideMotion.emplace();
            q.insetMotion.emplace();
            if (!read(v.motion->subImage, *q.wideMotion) || !read(v.inset->motion->subImage, *q.insetMotion)) return;
        }
        if (q.wideColor.format == layers::Format::RGBA8_SRGB && q.insetColor.format == layers::Format::RGBA8_SRGB)
            views[e] = {q.wideColor, q.insetColor};
        const gpu::ComposeParams params =
            makeComposeParams(layer, layers::outputSize(layer), c.compositor.insetBlendPx);
        Reference::EyeInput in = composeQuadViews(params, uint32_t(e), q);
        eyes[e].color = std::move(in.color);
        eyes[e].depth = std::move(in.depth);
        eyes[e].motion = std::move(in.motion);
        eyes[e].fov = v.fov;
        eyes[e].gaze = f.gaze[e];
    }
    for (int e = 0; e < 2 && !quad; ++e) {
        const layers::ProjectionView& v = layer.views[e];
        auto color = readSubImage(v.color);
        if (!color) return stop(color.error().message);
        eyes[e].color = std::move(*color);
        if (v.depth) {
            auto depth = readSubImage(v.depth->subImage);
            if (!depth) return stop(depth.error().message);
            eyes[e].depth = std::move(*depth);
        }
        if (v.motion) {
            // Recorded in pixels: the submitted texels times the layer's scale (space warp: NDC).
            auto motion = readSubImage(v.motion->subImage);
            if (!motion) return stop(motion.error().message);
            HostImage m = std::move(*motion);
            for (uint32_t y = 0; y < m.height; ++y)
                for (uint32_t x = 0; x < m.width; ++x)
                    m.store(x, y, glm::vec4(glm::vec3(m.fetch(x, y)) * v.motion->scale, 0.0f));
            eyes[e].motion = std::move(m);
        }
        eyes[e].fov = v.fov;
        eyes[e].gaze = f.gaze[e];
    }
    if (!s->recorder) {
        eval::SequenceInfo info;
        info.width = eyes[0].color.width;
        info.height = eyes[0].color.height;
        info.frameCount = 999999;  // an upper bound: close() writes the real count
        info.fps = c.displayHz;
        info.color = eyes[0].color.format == layers::Format::RGBA8_SRGB ? eval::ColorFile::Png : eval::ColorFile::Exr;
        info.fov = {layer.views[0].fov, layer.views[1].fov};
        if (layer.views[0].depth) {
            const auto& d = *layer.views[0].depth;
            info.depth = eval::SequenceDepth{d.nearZ, d.farZ, d.reversedZ};
        }
        if (layer.views[0].motion) info.motion = eval::MotionUnits::Pixels;
        info.description = "recorded by the wrsfov OpenXR runtime from '" + s->instance->applicationName + "'";
        auto w = eval::SequenceWriter::create(c.record, info);
        if (!w) return stop(w.error().message);
        s->recorder = std::move(*w);
    }
    const uint32_t index = s->recorder->written();
    if (Status st = s->recorder->writeFrame(index, eyes); !st) return stop(st.message());
    for (int e = 0; e < 2; ++e)
        if (views[e])
            for (const auto& [img, name] :
                 {std::pair{&views[e]->first, "wide.png"}, std::pair{&views[e]->second, "inset.png"}})
                if (Status st = writePng(*img, c.record + "/" + eval::frameFileName(index, e, name)); !st)
                    return stop(st.message());
    for (int e = 0; e < 2 && withOutput; ++e) {
        auto out = s->compositor->readOutput(uint32_t(e));
        if (!out) return stop(out.error().message);
        if (Status st = writePng(*out, c.record + "/" + eval::frameFileName(index, e, "output.png")); !st)
            return stop(st.message());
    }
}

/// What xrEndFrame hands to the compositor besides the application's structures: the frame's
/// display time and the poses of the quad layers' spaces (read under the instance's lock first).
struct LayerPoses {
    XrTime displayTime = 0;
    std::vector<std::optional<Pose>> layerSpaces;  // per layer: its space's pose at displayTime (quads only)
};

/// The poses of the quad layers' spaces (an action space's pose depends on the action state).
LayerPoses layerPoses(Session* s, const XrFrameEndInfo* info, XrTime displayTime) {
    LayerPoses poses;
    poses.displayTime = displayTime;
    poses.layerSpaces.resize(info->layerCount);
    std::lock_guard lock(s->instance->mutex);
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        if (info->layers[i]->type != XR_TYPE_COMPOSITION_LAYER_QUAD) continue;
        Pose space;
        if (spacePose(*getSpace(info->layers[i]->space), displayTime, space)) poses.layerSpaces[i] = space;
    }
    return poses;
}

/// Quad layers after the projection layer, in order, over the composited output (those before it
/// are hidden by the opaque projection).
void drawQuads(Session* s, const XrFrameEndInfo* info, uint32_t projIndex, const layers::FrameEndInfo& f,
               const LayerPoses& poses) {
    std::vector<QuadDraw> draws;
    const XrTime t = poses.displayTime;
    for (uint32_t i = projIndex + 1; i < info->layerCount; ++i) {
        if (info->layers[i]->type != XR_TYPE_COMPOSITION_LAYER_QUAD) continue;
        auto* q = reinterpret_cast<const XrCompositionLayerQuad*>(info->layers[i]);
        if (q->size.width == 0.0f || q->size.height == 0.0f) continue;  // covers nothing
        if (!poses.layerSpaces[i]) continue;  // an untracked space: not shown
        const Pose quadInStage = *poses.layerSpaces[i] * fromXr(q->pose);
        Swapchain* sc = getSwapchain(q->subImage.swapchain);
        const XrRect2Di& r = q->subImage.imageRect;
        for (uint32_t e = 0; e < 2; ++e) {
            if ((q->eyeVisibility == XR_EYE_VISIBILITY_LEFT && e == 1) ||
                (q->eyeVisibility == XR_EYE_VISIBILITY_RIGHT && e == 0))
                continue;
            const Pose m = inverse(quadInStage) * eyeAt(*s, t, int(e));
            QuadDraw d;
            d.eye = e;
            d.quadFromEye = glm::translate(glm::mat4(1.0f), m.p) * glm::mat4_cast(m.q);
            const layers::Fov& fov = f.layers[0].views[e].fov;
            d.fovTan = glm::vec4(std::tan(fov.angleLeft), std::tan(fov.angleRight), std::tan(fov.angleUp),
                                 std::tan(fov.angleDown));
            d.uvRect = glm::vec4(float(r.offset.x) / float(sc->info.width), float(r.offset.y) / float(sc->info.height),
                                 float(r.extent.width) / float(sc->info.width),
                                 float(r.extent.height) / float(sc->info.height));
            d.size = glm::vec2(q->size.width, q->size.height);
            d.blendAlpha = q->layerFlags & XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT;
            d.unpremultiplied = q->layerFlags & XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT;
            d.swapchain = static_cast<const VulkanSwapchain*>(sc->images.get());
            d.arrayIndex = q->subImage.imageArrayIndex;
            draws.push_back(d);
        }
    }
    if (Status st = s->quads->draw(*s->compositor, draws); !st && s->refusalsLogged.insert(-3).second)
        logLine("quad layers not drawn: " + st.message());
}

/// Runs the first stereo projection layer through the compositor: submits its passes, the quads and
/// the window's copy to the session's queue without waiting for them (with `record`, the read-backs
/// wait). Returns whether the window asked the application to stop. With gpuMutex held.
bool compose(Session* s, const XrFrameEndInfo* info, const LayerPoses& poses, uint64_t frameIndex) {
    const XrCompositionLayerProjection* proj = nullptr;
    uint32_t projIndex = 0;
    for (uint32_t i = 0; i < info->layerCount; ++i)
        if (info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION && !proj) {
            proj = reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[i]);
            projIndex = i;
        }
    if (!proj) {
        bool quads = false;
        for (uint32_t i = 0; i < info->layerCount; ++i) quads |= info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_QUAD;
        if (quads && s->refusalsLogged.insert(-1).second)
            logLine("quad layers without a projection layer are not shown (the display is the projection's output)");
        return false;
    }
    const RuntimeConfig& c = s->instance->config;
    LayerReading reading;
    reading.depthExt = s->instance->enabled(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    reading.warpExt = s->instance->enabled(XR_FB_SPACE_WARP_EXTENSION_NAME);
    // Quad views: composed at the display's size (or the wide views' where an application renders
    // them larger); wide views rendered jittered about the located field of view are composed on its
    // grid, their samples where they were taken.
    reading.quadViews = proj->viewCount == 4;
    reading.displayWidth = c.width;
    reading.displayHeight = c.height;
    reading.located = std::array<layers::Fov, 2>{c.fov[0], c.fov[1]};
    // Every swapchain of a verified frame end is one of this session's.
    auto sub = [](const XrSwapchainSubImage& x) -> std::optional<layers::SubImage> {
        return subImage(getSwapchain(x.swapchain)->images.get(), x);
    };
    LayerExtras ex;
    std::optional<layers::ProjectionLayer> layer = projectionLayer(*proj, sub, reading, &ex);
    if (!layer) return false;  // not reached: a verified frame end has the configuration's views
    if (ex.depthRangeUnused && s->refusalsLogged.insert(-2).second)
        logLine("depth with a range other than [0, 1] is not used (the compositor reads depth in [0, 1])");
    if (ex.quadDepthDropped && s->refusalsLogged.insert(-4).second)
        logLine(
            "quad views: depth or motion not given for all four views (or depth ranges that differ "
            "between a wide view and its inset) are not used");
    const bool locomotion = ex.locomotion;
    layers::FrameEndInfo f;
    f.frameIndex = frameIndex;
    f.time_s = s->instance->seconds(poses.displayTime);
    f.layers.push_back(std::move(*layer));
    const auto gaze = frameGaze(*s, poses.displayTime, f.layers[0].views[0]);
    f.gaze[0] = gaze[0];
    f.gaze[1] = gaze[1];
    {
        std::lock_guard lock(s->gazeMutex);
        s->lastGaze = gaze;
    }
    if (!s->instance->config.compose) {  // method = off: shown and recorded as submitted
        ++s->framesPassed;
        recordFrame(s, f, false);
        return false;
    }
    if (locomotion) s->compositor->resetHistory();
    FrameSubmission submission;
    submission.mode = FrameSubmission::Mode::Submit;  // the compositor thread waits (frameFence)
    Status st = s->compositor->endFrame(f, submission);
    if (!st) {
        ++s->framesRefused;
        if (s->refusalsLogged.insert(st.error().code).second)
            logLine("frame " + std::to_string(f.frameIndex) + " not composited: " + st.message() +
                    " (logged once per reason)");
        return false;
    }
    ++s->framesComposited;
    s->pipelinesMade += s->compositor->stats().pipelinesMade;
    s->pipelineMs += s->compositor->stats().pipelineMs;
    drawQuads(s, info, projIndex, f, poses);
    recordFrame(s, f, true);
    if (s->window) {
        const FrameStats& st = s->compositor->stats();
        char gpu[64];
        std::snprintf(gpu, sizeof gpu, "GPU %.2f ms", st.gpu.total);
        std::vector<std::string> items = {
            s->instance->applicationName, std::string(toString(c.compositor.method)),
            std::string(toString(c.compositor.foveation)),
            "fovea " + std::to_string(int(c.compositor.foveaDeg + 0.5f)) + " deg",
            "frame " + std::to_string(s->framesComposited), st.gpu.valid ? std::string(gpu) : std::string("GPU -"),
            st.gazeFallback[0] || st.gazeFallback[1] ? "gaze: fallback (view centre)" : "gaze: tracked"};
        if (Status p = s->window->present(*s->compositor, items); !p) {
            logLine("window: " + p.message() + "; headless from now on");
            s->window.reset();
        } else if (s->window->closeRequested()) {
            logLine("window closed: asking the application to stop");
            return true;
        }
    }
    return false;
}

/// Every swapchain image the frame reads, so that it stays the compositor's until the frame is
/// complete (xrWaitSwapchainImage, xrDestroySwapchain wait for that).
void markReadBy(Session* s, const XrFrameEndInfo* info, uint64_t frame) {
    auto mark = [&](const XrSwapchainSubImage& sub) {
        Swapchain* sc = getSwapchain(sub.swapchain);
        std::lock_guard lock(sc->mutex);
        sc->readByFrame[uint32_t(sc->images->lastReleased())] = frame;
    };
    const bool depthExt = s->instance->enabled(XR_KHR_COMPOSITION_LAYER_DEPTH_EXTENSION_NAME);
    const bool warpExt = s->instance->enabled(XR_FB_SPACE_WARP_EXTENSION_NAME);
    for (uint32_t i = 0; i < info->layerCount; ++i) {
        const XrCompositionLayerBaseHeader* l = info->layers[i];
        if (l->type == XR_TYPE_COMPOSITION_LAYER_QUAD) {
            mark(reinterpret_cast<const XrCompositionLayerQuad*>(l)->subImage);
            continue;
        }
        auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(l);
        for (uint32_t v = 0; v < p->viewCount; ++v) {
            mark(p->views[v].subImage);
            if (auto* n = findNext(p->views[v].next, XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR); n && depthExt)
                mark(reinterpret_cast<const XrCompositionLayerDepthInfoKHR*>(n)->subImage);
            if (auto* n = findNext(p->views[v].next, XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB); n && warpExt) {
                mark(reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(n)->motionVectorSubImage);
                mark(reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(n)->depthSubImage);
            }
        }
    }
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL xrEndFrame(XrSession h, const XrFrameEndInfo* info) {
    Session* s = getSession(h);
    if (!s) return XR_ERROR_HANDLE_INVALID;
    if (!info || info->type != XR_TYPE_FRAME_END_INFO) return XR_ERROR_VALIDATION_FAILURE;
    XrTime displayTime;
    {
        std::lock_guard frame(s->frameMutex);
        if (!s->running) return XR_ERROR_SESSION_NOT_RUNNING;
        if (!s->begun) return XR_ERROR_CALL_ORDER_INVALID;
        displayTime = s->frameDisplayTime;
    }
    if (Refusal r = checkFrameEnd(s, info)) {
        logLine("xrEndFrame: " + describe(r));
        return r.result;
    }
    const LayerPoses poses = layerPoses(s, info, displayTime);

    std::lock_guard gpu(s->gpuMutex);
    uint64_t serial;
    {
        // The frame before must be complete: the compositor's buffers and frameFence are reused (one
        // frame in flight). xrWaitFrame's throttling has usually seen to that already.
        std::unique_lock frame(s->frameMutex);
        waitForFrame(s, frame, s->framesHandedOver, XR_INFINITE_DURATION);
        serial = s->framesHandedOver + 1;
    }
    if (VkResult r = vkResetFences(s->context->device(), 1, &s->frameFence); r != VK_SUCCESS) {
        logLine(std::string("xrEndFrame: vkResetFences failed: ") + vk::resultString(r));
        return XR_ERROR_RUNTIME_FAILURE;
    }
    const bool closed = compose(s, info, poses, s->framesEnded + 1);
    markReadBy(s, info, serial);
    // After everything the frame submitted (queue order): the compositor thread waits for this fence.
    const VkResult submitted = s->context->deviceLost()
                                   ? VK_ERROR_DEVICE_LOST
                                   : vkQueueSubmit(s->context->queue(), 0, nullptr, s->frameFence);

    std::lock_guard frame(s->frameMutex);
    s->framesHandedOver = serial;
    s->handedOverAt = nowXrTime();
    if (submitted != VK_SUCCESS) s->framesCompleted = serial;  // nothing to wait for on a lost device
    s->frameCv.notify_all();
    s->begun = false;
    ++s->framesEnded;
    const uint64_t limit = s->instance->config.frames;
    if (limit > 0 && s->framesEnded >= limit && !s->stopRequested) {
        logLine("frame limit reached (" + std::to_string(limit) + "): asking the application to stop");
        beginStopping(s);
    }
    if (closed) beginStopping(s);
    return XR_SUCCESS;
}

}  // namespace wrsfov::xr
