// What an application submits at the end of a frame: one projection layer with two views (left,
// right), each with colour and optionally depth and motion, plus per-eye gaze. Modelled on
// XrCompositionLayerProjection, XrCompositionLayerDepthInfoKHR and XrFrameEndInfo.
#pragma once

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

struct ProjectionView {
    Fov fov;
    SubImage color;
    std::optional<DepthInfo> depth;
    std::optional<MotionInfo> motion;
};

/// Exactly two views: index 0 is the left eye, 1 the right eye.
struct ProjectionLayer {
    std::vector<ProjectionView> views;
};

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
