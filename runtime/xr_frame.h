// Reading an OpenXR frame end into the layers API: what the simulated-HMD runtime and the API layer
// both need (one copy of the OpenXR conventions for depth ranges and space-warp motion).
#pragma once

#include <openxr/openxr.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include <glm/glm.hpp>

#include "layers/frame.h"

namespace wrsfov::xr {

/// The first structure of `type` in a `next` chain, or nullptr.
inline const XrBaseInStructure* findNext(const void* next, XrStructureType type) {
    for (auto* n = static_cast<const XrBaseInStructure*>(next); n; n = n->next)
        if (n->type == type) return n;
    return nullptr;
}

/// Depth of XrCompositionLayerDepthInfoKHR or XrCompositionLayerSpaceWarpInfoFB as the compositor
/// reads it (sub-image left to the caller). OpenXR: nearZ is the distance at minDepth, so
/// nearZ > farZ is reversed Z. Only the full [0, 1] range is used: nullopt otherwise.
inline std::optional<layers::DepthInfo> depthInfo(float minDepth, float maxDepth, float nearZ, float farZ) {
    if (minDepth != 0.0f || maxDepth != 1.0f) return std::nullopt;
    layers::DepthInfo di;
    di.reversedZ = nearZ > farZ;
    di.nearZ = std::min(nearZ, farZ);
    di.farZ = std::max(nearZ, farZ);
    return di;
}

/// XR_FB_space_warp motion is current − previous in NDC (Vulkan NDC: x right, y down, [−1, 1] across
/// the image); the compositor wants pixels to the previous position: −ndc · size / 2. Its third
/// channel is an NDC depth difference, not the linear one the compositor reads: scaled to 0.
inline glm::vec3 spaceWarpMotionScale(const layers::Rect& rect) {
    return {-0.5f * float(rect.width), -0.5f * float(rect.height), 0.0f};
}

/// appSpaceDeltaPose as the compositor uses it: a zero-initialised pose (`XrPosef{}`, the
/// quaternion {0, 0, 0, 0}) is what an application without locomotion leaves there, and
/// XR_FB_space_warp's conformance tests submit it; it is read as the identity. Any other
/// orientation must be a unit quaternion (XR_ERROR_POSE_INVALID otherwise).
inline XrPosef spaceWarpDeltaPose(XrPosef d) {
    const XrQuaternionf& q = d.orientation;
    if (q.x == 0.0f && q.y == 0.0f && q.z == 0.0f && q.w == 0.0f) d.orientation.w = 1.0f;
    return d;
}

/// The space-warp appSpaceDeltaPose moved the layer space (artificial locomotion the motion vectors
/// do not carry): the history no longer lines up.
inline bool movesLayerSpace(XrPosef d) {
    d = spaceWarpDeltaPose(d);
    return std::abs(d.position.x) + std::abs(d.position.y) + std::abs(d.position.z) > 1e-4f ||
           std::abs(std::abs(d.orientation.w) - 1.0f) > 1e-6f;
}

/// What projectionView found beside a view's images.
struct ViewExtras {
    bool depthRangeUnused = false;  ///< depth came with a range other than [0, 1]: not used
    bool locomotion = false;        ///< the space warp's appSpaceDeltaPose moved the layer space
};

/// One view of a projection layer as the compositor reads it (the runtime's and the API layer's one
/// conversion): its field of view and colour; depth from XrCompositionLayerDepthInfoKHR where
/// `depthExt`, and motion from XrCompositionLayerSpaceWarpInfoFB where `warpExt`, whose depth stands in
/// where the first gives none. `subImageOf(const XrSwapchainSubImage&)` returns the compositor's
/// std::optional<layers::SubImage> for a sub-image (nullopt: a swapchain it does not read; depth or
/// motion there is then not used). nullopt where the colour's swapchain is one it does not read.
template <class SubImageOf>
std::optional<layers::ProjectionView> projectionView(const XrCompositionLayerProjectionView& v, SubImageOf&& subImageOf,
                                                     bool depthExt, bool warpExt, ViewExtras* extras = nullptr) {
    ViewExtras ex;
    std::optional<layers::SubImage> color = subImageOf(v.subImage);
    if (!color) return std::nullopt;
    layers::ProjectionView pv;
    pv.fov = {v.fov.angleLeft, v.fov.angleRight, v.fov.angleUp, v.fov.angleDown};
    pv.color = *color;
    auto depthOf = [&](const XrSwapchainSubImage& x, float minDepth, float maxDepth, float nearZ, float farZ) {
        std::optional<layers::DepthInfo> di = depthInfo(minDepth, maxDepth, nearZ, farZ);
        if (!di) {
            ex.depthRangeUnused = true;
            return;
        }
        std::optional<layers::SubImage> si = subImageOf(x);
        if (!si) return;
        di->subImage = *si;
        pv.depth = di;
    };
    if (const auto* n = findNext(v.next, XR_TYPE_COMPOSITION_LAYER_DEPTH_INFO_KHR); n && depthExt) {
        const auto* d = reinterpret_cast<const XrCompositionLayerDepthInfoKHR*>(n);
        depthOf(d->subImage, d->minDepth, d->maxDepth, d->nearZ, d->farZ);
    }
    if (const auto* n = findNext(v.next, XR_TYPE_COMPOSITION_LAYER_SPACE_WARP_INFO_FB); n && warpExt) {
        const auto* w = reinterpret_cast<const XrCompositionLayerSpaceWarpInfoFB*>(n);
        if (std::optional<layers::SubImage> si = subImageOf(w->motionVectorSubImage)) {
            layers::MotionInfo mi;
            mi.subImage = *si;
            mi.scale = spaceWarpMotionScale(si->rect);
            pv.motion = mi;
        }
        if (!pv.depth) depthOf(w->depthSubImage, w->minDepth, w->maxDepth, w->nearZ, w->farZ);
        ex.locomotion = movesLayerSpace(w->appSpaceDeltaPose);
    }
    if (extras) *extras = ex;
    return pv;
}

}  // namespace wrsfov::xr
