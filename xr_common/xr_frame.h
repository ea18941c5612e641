// Reading an OpenXR frame end into the layers API: the simulated-HMD runtime's and the API layer's one
// conversion (projectionLayer, projectionView) and the OpenXR conventions it follows (depth ranges,
// space-warp motion, jittered views).
#pragma once

#include <openxr/openxr.h>

#include <algorithm>
#include <array>
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

/// An XrSwapchainSubImage as the compositor reads it, in `swapchain` (the image of the application's
/// swapchain the compositor has: the runtime's own, or the layer's import).
inline layers::SubImage subImage(layers::Swapchain* swapchain, const XrSwapchainSubImage& x) {
    return layers::SubImage{swapchain,
                            {x.imageRect.offset.x, x.imageRect.offset.y, uint32_t(x.imageRect.extent.width),
                             uint32_t(x.imageRect.extent.height)},
                            x.imageArrayIndex};
}

/// The space-warp appSpaceDeltaPose moved the layer space (artificial locomotion the motion vectors
/// do not carry): the history no longer lines up.
inline bool movesLayerSpace(XrPosef d) {
    d = spaceWarpDeltaPose(d);
    return std::abs(d.position.x) + std::abs(d.position.y) + std::abs(d.position.z) > 1e-4f ||
           std::abs(std::abs(d.orientation.w) - 1.0f) > 1e-6f;
}

/// A view rendered at the located field of view `located` shifted by at most half a pixel, as an
/// engine jitters for temporal upsampling (TAAU, FSR 2) and submits the shifted field of view: the
/// shift in the view's pixels (+x right, +y down), which is its ProjectionView::sampleOffset. nullopt
/// for the located field of view itself and for any other one (another size, a larger shift, a
/// non-finite angle): such a view is composed in its own field of view, as submitted. A shift moves
/// both sides of an axis together, to a thousandth of a pixel. `w` x `h`: the view's image size.
inline std::optional<glm::vec2> jitterOf(const layers::Fov& submitted, const layers::Fov& located, uint32_t w,
                                         uint32_t h) {
    const double s[4] = {std::tan(double(submitted.angleLeft)), std::tan(double(submitted.angleRight)),
                         std::tan(double(submitted.angleUp)), std::tan(double(submitted.angleDown))};
    const double l[4] = {std::tan(double(located.angleLeft)), std::tan(double(located.angleRight)),
                         std::tan(double(located.angleUp)), std::tan(double(located.angleDown))};
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(s[i]) || !std::isfinite(l[i])) return std::nullopt;
    const double spanX = l[1] - l[0], spanY = l[2] - l[3];
    if (!(spanX > 0.0) || !(spanY > 0.0) || w == 0 || h == 0) return std::nullopt;
    const double px = spanX / w, py = spanY / h;  // one pixel in tangent units
    const double dl = s[0] - l[0], dr = s[1] - l[1], du = s[2] - l[2], dd = s[3] - l[3];
    if (std::abs(dl - dr) > 1e-3 * px || std::abs(du - dd) > 1e-3 * py) return std::nullopt;
    const double ox = 0.5 * (dl + dr) / px, oy = -0.5 * (du + dd) / py;
    if (ox == 0.0 && oy == 0.0) return std::nullopt;
    constexpr double kEdge = 0.5 + 1e-4;
    if (std::abs(ox) > kEdge || std::abs(oy) > kEdge) return std::nullopt;
    return glm::vec2(float(std::clamp(ox, -0.5, 0.5)), float(std::clamp(oy, -0.5, 0.5)));
}

/// A wide (or stereo) view submitted at its located field of view shifted by a sub-pixel jitter
/// (jitterOf): composed on the located field of view's grid with its samples placed where they were
/// taken (ProjectionView::sampleOffset), so that the output does not move with the jitter. Returns
/// whether it was jittered. (An inset needs no such step: it is placed by the field of view it was
/// rendered with, wherever that lies.)
inline bool placeJitter(layers::ProjectionView& v, const layers::Fov& located) {
    const std::optional<glm::vec2> o = jitterOf(v.fov, located, v.color.rect.width, v.color.rect.height);
    if (!o) return false;
    v.fov = located;
    v.sampleOffset = *o;
    return true;
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

/// How projectionLayer reads a frame's projection layer.
struct LayerReading {
    bool depthExt = false;  ///< XR_KHR_composition_layer_depth is enabled
    bool warpExt = false;   ///< XR_FB_space_warp is enabled
    /// The session's views are quad views (XR_VARJO_quad_views): four views, 0 and 1 the wide views,
    /// 2 and 3 their insets, composed into stereo at displayWidth x displayHeight. Else two views.
    bool quadViews = false;
    uint32_t displayWidth = 0, displayHeight = 0;
    /// Quad views: each eye's located field of view, where the wide views may come jittered about it
    /// (placeJitter); nullopt where it is not known (the wide views are then composed as submitted).
    std::optional<std::array<layers::Fov, 2>> located;
};

/// What projectionLayer found beside the layer's images.
struct LayerExtras {
    bool depthRangeUnused = false;   ///< a view's depth came with a range other than [0, 1]: not used
    bool locomotion = false;         ///< a space warp's appSpaceDeltaPose moved the layer space
    bool quadDepthDropped = false;   ///< quad views: depth or motion not on all four views, not used
};

/// The views of a projection layer as the compositor reads them (projectionView each; the first two,
/// or four with quad views): nullopt where the layer does not have the views `r` names or a view's
/// colour is in a swapchain the compositor does not read (`subImageOf` as projectionView's). `extras`
/// is filled either way, with what the views converted before one failed carried.
template <class SubImageOf>
std::optional<std::array<layers::ProjectionView, 4>> projectionViews(const XrCompositionLayerProjection& proj,
                                                                     SubImageOf&& subImageOf, const LayerReading& r,
                                                                     LayerExtras* extras = nullptr) {
    const uint32_t count = r.quadViews ? 4 : 2;
    LayerExtras ex;
    std::array<layers::ProjectionView, 4> v;
    bool ok = proj.viewCount == count && proj.views;
    for (uint32_t i = 0; ok && i < count; ++i) {
        ViewExtras vx;
        std::optional<layers::ProjectionView> pv = projectionView(proj.views[i], subImageOf, r.depthExt, r.warpExt, &vx);
        ex.depthRangeUnused = ex.depthRangeUnused || vx.depthRangeUnused;
        ex.locomotion = ex.locomotion || vx.locomotion;
        if (pv) v[i] = *pv;
        ok = pv.has_value();
    }
    if (extras) *extras = ex;
    if (!ok) return std::nullopt;
    return v;
}

/// The projection layer the compositor composites from the views projectionViews read: with quad
/// views the four composed by layers::quadLayer at the display's size, the wide views placed on the
/// located grid where they came jittered (r.located); else the first two as submitted.
inline layers::ProjectionLayer composedLayer(std::array<layers::ProjectionView, 4> v, const LayerReading& r,
                                             LayerExtras* extras = nullptr) {
    layers::ProjectionLayer layer;
    if (r.quadViews) {
        if (r.located)
            for (uint32_t e = 0; e < 2; ++e) placeJitter(v[e], (*r.located)[e]);
        // Depth (and motion) is used where all four views have it with one range per eye.
        bool dropped = false;
        layer = layers::quadLayer(v, r.displayWidth, r.displayHeight, &dropped);
        if (extras) extras->quadDepthDropped = dropped;
    } else {
        // (A jittered full-resolution view is composed in its own field of view: the passes read it at
        // its pixels; ProjectionView::sampleOffset.)
        layer.views = {v[0], v[1]};
    }
    return layer;
}

/// A projection layer as the compositor reads it: the runtime's and the API layer's one conversion of
/// an XrCompositionLayerProjection (projectionViews, then composedLayer). nullopt as projectionViews.
template <class SubImageOf>
std::optional<layers::ProjectionLayer> projectionLayer(const XrCompositionLayerProjection& proj, SubImageOf&& subImageOf,
                                                       const LayerReading& r, LayerExtras* extras = nullptr) {
    std::optional<std::array<layers::ProjectionView, 4>> v = projectionViews(proj, subImageOf, r, extras);
    if (!v) return std::nullopt;
    return composedLayer(*v, r, extras);
}

}  // namespace wrsfov::xr
