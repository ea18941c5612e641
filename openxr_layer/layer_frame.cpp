// XR_APILAYER_WRSFOV_foveation: the frame end (the projection layer composited, the output copied into the
// layer's swapchain, a patched frame end down the chain).
#include "openxr_layer/layer_state.h"

namespace wrsfov::xrlayer {

// ---- Frame end --------------------------------------------------------------------------------

namespace {

/// The layer's output swapchain of w x h, two layers; made (again) when the size changes.
bool ensureOutput(SessionState& s, const Next& n, XrSession session, uint32_t w, uint32_t h) {
    if (s.out && s.outWidth == w && s.outHeight == h) return true;
    waitCopied(s);
    if (s.out) n.destroySwapchain(s.out);
    s.out = XR_NULL_HANDLE;
    s.outImages.clear();
    uint32_t count = 0;
    n.enumerateSwapchainFormats(session, 0, &count, nullptr);
    std::vector<int64_t> formats(count);
    n.enumerateSwapchainFormats(session, count, &count, formats.data());
    // The output holds sRGB-encoded bytes: an sRGB swapchain shows them as meant.
    s.outFormat = 0;
    for (int64_t f : {int64_t(VK_FORMAT_R8G8B8A8_SRGB), int64_t(VK_FORMAT_R8G8B8A8_UNORM)})
        if (!s.outFormat && std::find(formats.begin(), formats.end(), f) != formats.end()) s.outFormat = f;
    if (!s.outFormat) return false;
    XrSwapchainCreateInfo ci{XR_TYPE_SWAPCHAIN_CREATE_INFO};
    ci.usageFlags = XR_SWAPCHAIN_USAGE_COLOR_ATTACHMENT_BIT | XR_SWAPCHAIN_USAGE_TRANSFER_DST_BIT;
    ci.format = s.outFormat;
    ci.sampleCount = 1;
    ci.width = w;
    ci.height = h;
    ci.faceCount = 1;
    ci.arraySize = 2;
    ci.mipCount = 1;
    if (n.createSwapchain(session, &ci, &s.out) != XR_SUCCESS) return false;
    n.enumerateSwapchainImages(s.out, 0, &count, nullptr);
    std::vector<XrSwapchainImageVulkanKHR> imgs(count, {XR_TYPE_SWAPCHAIN_IMAGE_VULKAN_KHR});
    if (n.enumerateSwapchainImages(s.out, count, &count, reinterpret_cast<XrSwapchainImageBaseHeader*>(imgs.data())) !=
        XR_SUCCESS)
        return false;
    for (auto& i : imgs) s.outImages.push_back(i.image);
    s.outWidth = w;
    s.outHeight = h;
    return true;
}

}  // namespace

/// Composites the projection layer and copies the output into the layer's swapchain; false when the
/// frame must pass through (logged once per reason).
bool process(SessionState& s, const Next& n, XrSession session, const XrFrameEndInfo& info,
             const XrCompositionLayerProjection& proj, XrCompositionLayerProjection& patched,
             std::array<XrCompositionLayerProjectionView, 2>& views) {
    auto once = [&](int code, const std::string& why) {
        if (!s.logged[code]) logLine("frame passed through: " + why);
        s.logged[code] = true;
        return false;
    };
    const bool quad = s.quad && proj.viewCount == 4 && proj.views;
    if (!quad && (proj.viewCount != 2 || !proj.views)) return once(1, "not a stereo projection layer");
    layers::FrameEndInfo fe;
    fe.frameIndex = s.frames;
    fe.time_s = double(info.displayTime) * 1e-9;
    // The application's views, their colour, depth and motion where the compositor reads them
    // (xr::projectionViews, the runtime's conversion): an imported sub-image of the application's, or none.
    auto imported = [](const XrSwapchainSubImage& x) -> std::optional<layers::SubImage> {
        auto it = g_swapchains.find(x.swapchain);
        if (it == g_swapchains.end() || !it->second.imported) return std::nullopt;
        return xr::subImage(it->second.imported.get(), x);
    };
    xr::LayerReading reading;
    reading.depthExt = reading.warpExt = true;
    reading.quadViews = quad;
    reading.displayWidth = s.displayWidth;
    reading.displayHeight = s.displayHeight;
    xr::LayerExtras ex;
    std::optional<std::array<layers::ProjectionView, 4>> views4 = xr::projectionViews(proj, imported, reading, &ex);
    if (ex.locomotion) s.comp->resetHistory();
    if (!views4) return once(2, "a view's swapchain is not one the compositor reads");
    if (quad) {
        // Quad views: each wide view with its inset, composed at the runtime's stereo size. Wide views
        // rendered jittered (the runtime's located stereo field of view shifted by under half a pixel)
        // are composed on the located grid with their samples where they were taken.
        XrViewLocateInfo li{XR_TYPE_VIEW_LOCATE_INFO};
        li.viewConfigurationType = kStereo;
        li.displayTime = info.displayTime;
        li.space = proj.space;
        XrViewState vs{XR_TYPE_VIEW_STATE};
        XrView located[2] = {{XR_TYPE_VIEW}, {XR_TYPE_VIEW}};
        uint32_t count = 0;
        if (n.locateViews(session, &li, &vs, 2, &count, located) == XR_SUCCESS && count == 2) {
            std::array<layers::Fov, 2> fov;
            for (uint32_t e = 0; e < 2; ++e) {
                const XrFovf& f = located[e].fov;
                fov[e] = layers::Fov{f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
            }
            reading.located = fov;
        }
    }
    const layers::ProjectionLayer layer = xr::composedLayer(*views4, reading, &ex);
    fe.layers.push_back(layer);
    const auto g = eyeGaze(s, n, proj, info.displayTime);
    fe.gaze[0] = g[0];
    fe.gaze[1] = g[1];
    // The last frame's GPU times (its work has normally finished by now; endFrame waits for it anyway).
    waitComposited(s);
    if (s.disabled) return false;
    if (!s.composited) {
        VkSemaphoreCreateInfo sci{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkSemaphore sem = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        const VkDevice dev = s.ctx->device();
        if (vkCreateSemaphore(dev, &sci, nullptr, &sem) != VK_SUCCESS ||
            vkCreateFence(dev, &fci, nullptr, &fence) != VK_SUCCESS) {
            if (sem) vkDestroySemaphore(dev, sem, nullptr);
            disable(s, "no semaphore or fence for the frame's work");
            return false;
        }
        s.composited = vk::Semaphore(dev, sem);
        s.copied = vk::Fence(dev, fence);
        auto cb = s.ctx->allocateCommandBuffer();
        if (!cb) {
            disable(s, "no command buffer for the frame's copies: " + cb.error().message);
            return false;
        }
        s.copyCb = *cb;
    }
    FrameSubmission submission;
    submission.mode = FrameSubmission::Mode::Submit;
    const VkSemaphore composited = s.composited.get();
    submission.signalSemaphores = {&composited, 1};
    if (Status st = s.comp->endFrame(fe, submission); !st) {
        if (st.error().code == int(layers::SubmitError::DeviceFailure)) disable(s, st.message());
        return once(100 + st.error().code, st.message());
    }
    s.statsPending = true;
    const FrameStats& stats = s.comp->stats();
    if (stats.gazeFallback[0] || stats.gazeFallback[1]) ++s.fallbackFrames;
    if (s.frames % 300 == 0) {
        char line[160];
        std::snprintf(line, sizeof line, "frame %llu: passes %.2f ms a frame so far, gaze %s",
                      (unsigned long long)s.frames, s.gpuFrames ? s.gpuMs / double(s.gpuFrames) : 0.0,
                      stats.gazeFallback[0] || stats.gazeFallback[1] ? "fallback (view centre)" : "tracked");
        logLine(line);
    }
    const uint32_t w = s.comp->width(), h = s.comp->height();
    // The copy waits for the semaphore the compositor signalled: from here on this frame's
    // semaphore signal must be consumed, so every failure below still submits or waits it out.
    auto abandon = [&](const std::string& why) {
        waitComposited(s);  // the semaphore stays signalled: no later frame uses it
        s.composited.reset();
        disable(s, why);
        return false;
    };
    waitCopied(s);  // the last frame's copy, before its command buffer is recorded again
    if (s.disabled) return abandon(s.why);
    if (!ensureOutput(s, n, session, w, h)) return abandon("the runtime made no RGBA8 swapchain for the output");
    uint32_t index = 0;
    XrSwapchainImageWaitInfo wi{XR_TYPE_SWAPCHAIN_IMAGE_WAIT_INFO};
    wi.timeout = XR_INFINITE_DURATION;
    if (n.acquireSwapchainImage(s.out, nullptr, &index) != XR_SUCCESS || n.waitSwapchainImage(s.out, &wi) != XR_SUCCESS)
        return abandon("the output swapchain could not be acquired");
    const VkImage dst = s.outImages.at(index);
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    VkResult rec = vkBeginCommandBuffer(s.copyCb, &bi);
    if (rec == VK_SUCCESS) {
        VkCommandBuffer cb = s.copyCb;
        vk::layoutTransition(cb, dst, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        VkImageCopy c{};
        c.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2};
        c.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 2};
        c.extent = {w, h, 1};
        // The compositor's output rests in GENERAL; it is copied from TRANSFER_SRC_OPTIMAL and put back.
        const VkImage src = s.comp->outputImage().handle();
        vk::layoutTransition(cb, src, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_GENERAL,
                             VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
        vkCmdCopyImage(cb, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &c);
        vk::layoutTransition(cb, src, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                             VK_IMAGE_LAYOUT_GENERAL);
        // Back to the layout the runtime expects at release, visible to whatever it runs next on the queue.
        vk::layoutTransition(cb, dst, VK_IMAGE_ASPECT_COLOR_BIT, 2, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL);
        rec = vkEndCommandBuffer(cb);
    }
    if (rec == VK_SUCCESS) {
        const VkPipelineStageFlags stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
        si.waitSemaphoreCount = 1;
        si.pWaitSemaphores = &composited;
        si.pWaitDstStageMask = &stage;
        si.commandBufferCount = 1;
        si.pCommandBuffers = &s.copyCb;
        rec = s.ctx->submitNoWait(si, s.copied.get());
        s.copyInFlight = rec == VK_SUCCESS;
    }
    // Released without waiting: the copy is on the session's queue, ahead of anything the runtime
    // submits there to read the image (XR_KHR_vulkan_enable: images are released to that queue).
    n.releaseSwapchainImage(s.out, nullptr);
    if (rec != VK_SUCCESS) return abandon(std::string("copying the output: ") + vk::resultString(rec));
    patched = proj;
    for (uint32_t e = 0; e < 2; ++e) {
        views[e] = proj.views[e];  // pose, fov and the chained depth info stay the application's
        // ... except a jittered wide view's field of view: the output was composed on the located grid
        // (xr::placeJitter), and the runtime places the image by the field of view it is given.
        if (quad) {
            const layers::Fov& f = layer.views[e].fov;
            views[e].fov = {f.angleLeft, f.angleRight, f.angleUp, f.angleDown};
        }
        views[e].subImage.swapchain = s.out;
        views[e].subImage.imageRect = {{0, 0}, {int32_t(w), int32_t(h)}};
        views[e].subImage.imageArrayIndex = e;
        if (quad) views[e].next = nullptr;  // the wide views' depth is not the output's size
    }
    patched.viewCount = 2;
    patched.views = views.data();
    return true;
}

namespace {

/// A frame end the layer does not composite, down the chain. In a session with the quad views the
/// layer offers, each four-view projection layer goes down as its two wide views (the runtime's
/// session is stereo): the application's frame is still shown, at the wide views' density.
XrResult endDown(const SessionState& s, const Next& n, XrSession session, const XrFrameEndInfo* info) {
    if (!s.quad || !info || info->type != XR_TYPE_FRAME_END_INFO || !info->layers) return n.endFrame(session, info);
    std::vector<const XrCompositionLayerBaseHeader*> layers(info->layers, info->layers + info->layerCount);
    std::vector<XrCompositionLayerProjection> wide;
    wide.reserve(layers.size());
    for (auto& l : layers)
        if (l && l->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            wide.push_back(*reinterpret_cast<const XrCompositionLayerProjection*>(l));
            if (wide.back().viewCount == 4) wide.back().viewCount = 2;
            l = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&wide.back());
        }
    XrFrameEndInfo fe = *info;
    fe.layers = layers.data();
    return n.endFrame(session, &fe);
}

}  // namespace

XRAPI_ATTR XrResult XRAPI_CALL layerEndFrame(XrSession session, const XrFrameEndInfo* info) {
    std::lock_guard lock(g_mutex);
    auto it = g_sessions.find(session);
    if (it == g_sessions.end()) return XR_ERROR_HANDLE_INVALID;
    SessionState& s = it->second;
    const Next& n = g_instances.at(s.instance).next;
    // Quad views the layer offers: a projection layer has the configuration's four views (the runtime
    // below would count them against its stereo configuration). A refused frame end is no frame.
    if (s.quad && info && info->type == XR_TYPE_FRAME_END_INFO && info->layers)
        for (uint32_t i = 0; i < info->layerCount; ++i)
            if (info->layers[i] && info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
                const auto* p = reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[i]);
                if (p->viewCount != 4) {
                    logLine("xrEndFrame: XR_ERROR_VALIDATION_FAILURE: (frameEndInfo->layers[" + std::to_string(i) +
                            "]->viewCount == " + std::to_string(p->viewCount) +
                            ") is not the 4 views of XR_VIEW_CONFIGURATION_TYPE_PRIMARY_QUAD_VARJO");
                    return XR_ERROR_VALIDATION_FAILURE;
                }
            }
    if (info && info->type == XR_TYPE_FRAME_END_INFO) ++s.frames;
    if (!info || info->type != XR_TYPE_FRAME_END_INFO || !info->layers) return endDown(s, n, session, info);
    uint32_t projIndex = info->layerCount;
    for (uint32_t i = 0; i < info->layerCount; ++i)
        if (info->layers[i] && info->layers[i]->type == XR_TYPE_COMPOSITION_LAYER_PROJECTION) {
            projIndex = i;
            break;
        }
    if (projIndex == info->layerCount) return n.endFrame(session, info);  // nothing to foveate
    ++s.projected;
    if (s.disabled) return endDown(s, n, session, info);
    XrCompositionLayerProjection patched{};
    std::array<XrCompositionLayerProjectionView, 2> views{};
    const auto& proj = *reinterpret_cast<const XrCompositionLayerProjection*>(info->layers[projIndex]);
    const auto t0 = std::chrono::steady_clock::now();
    if (!process(s, n, session, *info, proj, patched, views)) return endDown(s, n, session, info);
    s.endFrameMs += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    ++s.processed;
    std::vector<const XrCompositionLayerBaseHeader*> layers(info->layers, info->layers + info->layerCount);
    layers[projIndex] = reinterpret_cast<const XrCompositionLayerBaseHeader*>(&patched);
    XrFrameEndInfo fe = *info;
    fe.layers = layers.data();
    return endDown(s, n, session, &fe);
}

}  // namespace wrsfov::xrlayer
