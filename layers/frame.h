// What an application submits at the end of a frame: one projection layer with two views (left,
// right), each with colour and optionally depth and motion, plus per-eye gaze. Modelled on
// XrCompositionLayerProjection, XrCompositionLayerDepthInfoKHR and XrFrameEndInfo.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "layers/status.h"
#include "layers/swapchain.h"

namespace wrsfov::layers {

/// Field of view as four angles in radians, like XrFovf: angleLeft < 0 < angleRight,
/// angleDown < 0 < angleUp; asymmetric allowed; each inside (-90°, 90°).
struct Fov {
    float angleLeft = -0.785398f;
    float angleRight = 0.785398f;
    float angleUp = 0.785398f;
    float angleDown = -0.785398f;
};

struct Rect {
    int32_t x = 0;
    int32_t y = 0;
    uint32_t width = 0;
    uint32_t height = 0;
};

/// A rectangle of one layer of a swapchain's last released image.
struct SubImage {
    Swapchain* swapchain = nullptr;
    Rect rect;
    uint32_t arrayIndex = 0;
};

/// Depth of a view (like XrCompositionLayerDepthInfoKHR). Depth values are in [0, 1]; farZ may be
/// +infinity (infinite projection); reversedZ maps near to 1.
struct DepthInfo {
    SubImage subImage;
    float nearZ = 0.1f;
    float farZ = 100.0f;
    bool reversedZ = false;
};

/// Motion vectors of a view, in pixels: previous position = current position + mv. With an RGBA16F
/// swapchain the third channel is z_prev - z_cur (linear depth), else taken as 0.
struct MotionInfo {
    SubImage subImage;
    /// Multiplies each texel before use, so motion in other units needs no conversion pass: x, y in
    /// pixels per unit, z for the third channel (0 ignores it). Pixels: (1, 1, 1). OpenXR
    /// XR_FB_space_warp (current - previous NDC, Vulkan NDC y down): (-w/2, -h/2, 0). Must be finite.
    glm::vec3 scale{1.0f, 1.0f, 1.0f};
};

/// A foveated inset (quad views, XR_VARJO_quad_views): the same eye and pose as its view, a field of
/// view inside the view's, rendered at a higher pixel density (typically following the gaze). The
/// view itself is then the wide view, rendered at a low density. The compositor resamples both into
/// the output (ProjectionLayer::outputWidth x outputHeight over the wide view's field of view) and
/// blends them over the inset's outer CompositorConfig::insetBlendPx pixels; each output pixel's
/// quality is what it was rendered at: 1 in the inset, (wide px/deg / inset px/deg)^2 outside it,
/// interpolated across the blend (docs/integrating.md, "Quad views").
struct InsetView {
    Fov fov;                          ///< inside the wide view's, each angle
    SubImage color;                   ///< any size; its density must be at least the wide view's
    std::optional<DepthInfo> depth;   ///< exactly when the wide view has depth, same near/far/reversed
    std::optional<MotionInfo> motion; ///< exactly when the wide view has motion; in the inset's pixels
    /// Where the inset's samples were taken, in its own pixels (ProjectionView::sampleOffset).
    glm::vec2 sampleOffset{0.0f, 0.0f};
};

/// A shading-rate map (VK_KHR_fragment_shading_rate's attachment): one R8UI texel per
/// texelWidth x texelHeight block of the view, holding the rate the block was shaded at, w x h pixels
/// per sample with w = 2^((v >> 2) & 3), h = 2^(v & 3). The view's colour is what that rendering gave:
/// one sample per w x h block, replicated. Each pixel's quality is 1 / (w h). Sizes of 8 (a field of
/// 3), which Vulkan's table of fragment sizes never lists, are taken as 4; bits 4..7 are ignored, as
/// the extension's formula does (docs/integrating.md, "Shading-rate maps").
struct RateMapInfo {
    SubImage subImage;  ///< R8UI (Usage::ShadingRate), ceil(W / texelWidth) x ceil(H / texelHeight) texels
    uint32_t texelWidth = 16, texelHeight = 16;  ///< pixels per texel: powers of two, 1..64
};

struct ProjectionView {
    Fov fov;
    SubImage color;
    std::optional<DepthInfo> depth;
    std::optional<MotionInfo> motion;
    /// Submitted foveation, at most one of the two, on both views or neither.
    std::optional<InsetView> inset;
    std::optional<RateMapInfo> rateMap;
    /// Evaluation only: the frame as a full-resolution render would have shown it (colour, at the output
    /// size), for the oracles, which compare with it; they refuse frames submitted foveated without it.
    /// Not read by any other method.
    std::optional<SubImage> reference;
    /// Where the colour's samples were taken, in its own pixels (+x right, +y down): pixel (x, y) holds
    /// the scene at (x + 0.5 + sampleOffset.x, y + 0.5 + sampleOffset.y) of `fov`'s pixel grid, as an
    /// engine renders for temporal upsampling (a per-frame sub-pixel jitter of its projection; in
    /// OpenXR, the located field of view shifted by less than a pixel). Each component finite and in
    /// [-0.5, 0.5] (SubmitError::InvalidSampleOffset). The compose pass places a quad view's samples
    /// where they were taken, so the output stays on `fov`'s grid; a full-resolution frame is read at
    /// its pixels (the offset is not used: docs/integrating.md, "Jittered views").
    glm::vec2 sampleOffset{0.0f, 0.0f};
};

/// Exactly two views: index 0 is the left eye, 1 the right eye.
struct ProjectionLayer {
    std::vector<ProjectionView> views;
    /// Quad views (views with an inset): the size of each eye's output, both or neither given (0: the
    /// left inset's pixel density over the left view's field of view, rounded). Other frames: 0, or the
    /// views' colour size.
    uint32_t outputWidth = 0, outputHeight = 0;
};

/// A quad-view projection layer from four views as OpenXR's PRIMARY_QUAD_VARJO configuration orders
/// them (0, 1 the wide views, 2, 3 their insets), composed at `outWidth` x `outHeight` or the wide views'
/// size where that is larger. Depth (and motion) is kept where all four views have it (and each inset's
/// depth range is its wide view's), else dropped from all; `dropped` (optional) says whether any was.
ProjectionLayer quadLayer(const std::array<ProjectionView, 4>& views, uint32_t outWidth, uint32_t outHeight,
                          bool* dropped = nullptr);

/// How a frame was foveated before it was submitted.
enum class SubmittedFoveation : uint8_t { Full, Quad, Rate };
/// Full, Quad (views have an inset) or Rate (views have a rate map), from the left view.
SubmittedFoveation submittedFoveation(const ProjectionLayer& layer);
/// The size of each eye's output for a validated layer: the colour's size, or for quad views
/// outputWidth x outputHeight or the inset's density over the wide view (ProjectionLayer).
glm::uvec2 outputSize(const ProjectionLayer& layer);

/// Gaze of one eye: unit direction in that eye's space (-Z forward). An invalid or non-finite gaze
/// is not a refusal: the compositor falls back to the view centre with the fallback fovea size.
struct EyeGaze {
    glm::vec3 dir{0.0f, 0.0f, -1.0f};
    bool valid = false;
    float confidence = 0.0f;
};

struct FrameEndInfo {
    uint64_t frameIndex = 0;  ///< strictly increasing
    double time_s = 0.0;      ///< display time, non-decreasing
    std::vector<ProjectionLayer> layers;  ///< exactly one projection layer
    EyeGaze gaze[2];
};

/// Every way a frame end can be refused. Each has its own message from validateFrameEnd().
enum class SubmitError : int {
    LayerCount = 1,         ///< not exactly one projection layer
    MissingEye,             ///< the layer does not have exactly two views
    NullSwapchain,          ///< a sub-image without a swapchain
    WrongUsage,             ///< e.g. a depth swapchain given as colour
    UnsupportedFormat,      ///< a format this compositor cannot read for that use
    SizeMismatch,           ///< colour/depth/motion rectangles or the two views differ in size
    RectOutOfBounds,        ///< a rectangle outside its swapchain image, or empty
    ArrayIndexOutOfRange,   ///< arrayIndex >= the swapchain's array size
    ImageNotReleased,       ///< a swapchain with no released image, or one still acquired
    FrameOutOfOrder,        ///< frame index not increasing or time going back / not finite
    InvalidFov,             ///< angles non-finite, outside (-90°, 90°) or not left<right, down<up
    InvalidDepthRange,      ///< near/far non-finite (far may be +inf), near <= 0, or far <= near
    InconsistentViews,      ///< one view has depth or motion and the other does not, or formats differ
    ForeignSwapchain,       ///< a swapchain made by another compositor (or another implementation)
    DeviceFailure,          ///< out of device memory (the compositor stays usable at its old size) or device
                            ///< lost (every later frame is refused: make a new Context and Compositor)
    InvalidMotionScale,     ///< MotionInfo::scale not finite
    InvalidSubmission,      ///< a FrameSubmission (compositor.h) that cannot be carried out
    InvalidInset,           ///< an inset outside its view, less dense than it, or an output size out of range
    InvalidRateMap,         ///< a rate map of the wrong size for its view, or a texel size that is not 1..64, 2^k
    InvalidSampleOffset,    ///< a view's or an inset's sample offset not finite or outside its pixel ([-0.5, 0.5])
};

std::string_view toString(SubmitError e);

/// Checks one frame end against the previous accepted one (frame order). Returns the first refusal.
/// On success the caller commits `frameIndex`/`time_s` as the new "previous".
class FrameValidator {
public:
    Status validate(const FrameEndInfo& frame) const;
    void accept(const FrameEndInfo& frame);
    void reset() { have_ = false; }

private:
    bool have_ = false;
    uint64_t lastIndex_ = 0;
    double lastTime_ = 0.0;
};

}  // namespace wrsfov::layers
