// The `atrium` and `dynamic` scenes: a room of textured columns, floor, walls and text posters,
// rendered per eye with a Vulkan graphics pipeline straight into an application's swapchain images
// (colour, depth, motion), like an XR application would. Motion vectors come from the previous
// frame's camera and object transforms.
#pragma once

#include <array>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "compositor/vk_context.h"
#include "layers/frame.h"
#include "layers/status.h"
#include "layers/swapchain.h"

namespace wrsfov::scenes {

enum class CameraPath : uint8_t {
    Static,   ///< head still, looking down the room
    Lateral,  ///< back-and-forth sideways motion, 0.5 m amplitude, 4 s period
    Turn,     ///< head yaw ±25°, 6 s period (26 °/s at its peak)
    Yaw30,    ///< head yaw at a constant 30 °/s (turning left), from looking down the room at t = 0
    Yaw60,    ///< the same at 60 °/s
    Yaw120,   ///< the same at 120 °/s
    /// Looking around: the gaze shifts between targets 15-50° apart every 0.6 s and the head follows
    /// each shift (eye-head coordination): a saccade on the main sequence, the head starting 20 ms later
    /// with a minimum-jerk turn over 85 % of the shift (up to about 190 °/s), the eye counter-rotating
    /// while the head catches up and never more than 35° from the head's straight ahead
    /// (lookAroundGaze: the study's gaze follows it).
    LookAround,
};
/// Every path, in the order the tools list them.
constexpr CameraPath kCameraPaths[] = {CameraPath::Static, CameraPath::Lateral, CameraPath::Turn,
                                       CameraPath::Yaw30,  CameraPath::Yaw60,   CameraPath::Yaw120,
                                       CameraPath::LookAround};

/// "static", "lateral", "turn", "yaw30", "yaw60", "yaw120", "look-around"; nullopt for anything else.
std::optional<CameraPath> parseCameraPath(std::string_view name);
std::string_view toString(CameraPath path);
/// The head's largest angular speed on the path, degrees per second (0 for the still and sideways paths).
double headDegPerS(CameraPath path);

/// Where the head of a camera path is at time t: world position (y up, eyes 1.6 m above the
/// floor) and yaw about +Y in radians. The atrium's cameras and the OpenXR runtime's simulated
/// head follow the same paths.
struct HeadPose {
    glm::vec3 position{0.0f, 1.6f, 0.0f};
    float yaw = 0.0f;
};
HeadPose headPose(CameraPath path, double t);

/// Where the eye looks in the head on CameraPath::LookAround at time t, degrees (azimuth positive to the
/// left, as the head's yaw; elevation positive up): the scripted gaze shift's target in the world less
/// the head's yaw, within the eye's ±35° range. The local exploration around each target (fixations,
/// small saccades, drift, blinks) comes from the gaze generator, added on top.
struct GazeInHead {
    float azimuthDeg = 0.0f, elevationDeg = 0.0f;
};
GazeInHead lookAroundGaze(double t);

struct AtriumOptions {
    uint32_t width = 256, height = 256;  ///< per eye
    bool dynamic = false;                ///< moving boxes that occlude and disocclude the room, a light change
    /// The `thin` scene: the room with thin high-contrast geometry where temporal methods ghost and
    /// shimmer: railings of 1.6-5 cm tubes, cables of 8 mm across the room and down from the ceiling,
    /// alpha-tested foliage cut-outs, and view-dependent (Blinn-Phong) highlights from two ceiling lights on
    /// the tubes, the leaves and a glossy floor.
    bool thin = false;
    CameraPath path = CameraPath::Lateral;
    float ipd = 0.063f;                  ///< metres
    float nearZ = 0.05f, farZ = 100.0f;
    bool reversedZ = false;
    bool monitor = false;                ///< one symmetric 76° x 60° view for both eyes (no disparity)
    /// HMD stereo only: > 0 replaces the HMD's asymmetric field of view by a symmetric square one of
    /// this many degrees per eye (the central part of the HMD view), e.g. to reach a pixel density
    /// at a size a CPU renderer can afford.
    float fovDeg = 0.0f;
    /// Shading samples per pixel of the procedural materials (floor checker, bricks, column stripes,
    /// the boxes): 4 filters them over the pixel's footprint (rotated grid, averaged in linear colour),
    /// as mipmapping filters an application's textures; 1 point-samples them at the pixel centre, which
    /// aliases the stripes and checker edges (the scene before filtering, docs/retention.md). Geometry
    /// edges are not anti-aliased either way.
    uint32_t materialSamples = 4;
};

/// Scale of the room light at time t: 1, except in the `dynamic` scene, whose light dims to 0.6 at
/// t = 1 s and recovers at t = 2.2 s, every 3 s (0.1 s ramps).
float atriumLight(const AtriumOptions& o, double t);

/// Per-eye asymmetric field of view of the stereo camera (HMD-like; mirrored between eyes).
layers::Fov atriumFov(int eye);
/// The field of view of one eye of the scene: atriumFov(eye), monitorFov() in monitor mode, or the
/// symmetric square AtriumOptions::fovDeg.
layers::Fov atriumFov(const AtriumOptions& o, int eye);
/// Monitor mode of the built-in scenes: one symmetric view of 76° x 60° (the paper's desktop
/// setting of about 70-80° horizontally), submitted as both views.
layers::Fov monitorFov();

/// World -> view matrix of one eye at time t (OpenXR axes: -Z forward, +Y up).
glm::mat4 atriumView(const AtriumOptions& o, int eye, double t);
/// Projection for a field of view into Vulkan clip space (y down, depth [0,1], reversed or not).
glm::mat4 projection(const layers::Fov& fov, float nearZ, float farZ, bool reversedZ);

class AtriumRenderer {
public:
    static Result<std::unique_ptr<AtriumRenderer>> create(vk::Context& ctx, const AtriumOptions& options);
    ~AtriumRenderer();

    /// Renders both eyes at time t into layer 0 (left) and 1 (right) of the given swapchain images
    /// (which the caller has acquired and waited for). `prevT` is the time of the previous frame for
    /// motion vectors (equal to t on the first frame: zero motion).
    Status render(double t, double prevT, layers::Swapchain& color, uint32_t colorIndex, layers::Swapchain& depth,
                  uint32_t depthIndex, layers::Swapchain& motion, uint32_t motionIndex);

    /// The same scene at time t through other views: eye e seen through `fovs[e]` (same eye pose) at the
    /// swapchains' size, e.g. a quad view's wide view at a low density or its inset around the gaze.
    /// Materials are filtered over each pixel's footprint at that size (AtriumOptions::materialSamples),
    /// as a renderer with mip-mapped textures does at that density; motion in that image's pixels.
    /// `footprint` < 1 filters them over that fraction of the pixel (the poster with a LOD bias of its
    /// log2): a view rendered for temporal upsampling samples its textures at the display's density,
    /// the wide view's density over the display's, so that each pixel is a sharp point sample.
    Status renderViews(double t, double prevT, const std::array<layers::Fov, 2>& fovs, layers::Swapchain& color,
                       uint32_t colorIndex, layers::Swapchain& depth, uint32_t depthIndex, layers::Swapchain& motion,
                       uint32_t motionIndex, float footprint = 1.0f);

    const AtriumOptions& options() const { return options_; }

    /// The device's time for the last render()/renderViews() (both eyes: from a timestamp before the
    /// first render pass to one after the last), in ms; NaN where the queue has no timestamps.
    double lastGpuMs() const { return lastGpuMs_; }

private:
    explicit AtriumRenderer(vk::Context& ctx, const AtriumOptions& o) : ctx_(ctx), options_(o) {}
    Status init();
    VkImageView view(VkImage image, VkFormat format, VkImageAspectFlags aspect, uint32_t layer);
    VkFramebuffer framebuffer(VkImageView color, VkImageView motion, VkImageView depth, uint32_t width, uint32_t height);

    struct Vertex {
        glm::vec3 pos;
        glm::vec3 normal;
        glm::vec2 uv;
        uint32_t material;
    };
    struct Object {
        uint32_t first, count;
    };

    vk::Context& ctx_;
    AtriumOptions options_;
    VkRenderPass renderPass_ = VK_NULL_HANDLE;
    VkFormat colorFormat_ = VK_FORMAT_UNDEFINED;
    vk::DescriptorSetLayout setLayout_;
    vk::PipelineLayout pipelineLayout_;
    vk::Pipeline pipeline_;
    vk::DescriptorPool pool_;
    VkDescriptorSet sets_[2] = {};
    vk::Buffer vertices_;
    vk::Buffer cameras_[2];
    vk::Image poster_;
    vk::Sampler sampler_;
    Object room_{}, cube_{};
    std::map<std::tuple<VkImage, VkFormat, uint32_t>, VkImageView> views_;
    std::map<std::tuple<VkImageView, VkImageView, VkImageView>, VkFramebuffer> framebuffers_;
    vk::QueryPool queries_;  // two timestamps around a render; none without timestamps
    double lastGpuMs_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace wrsfov::scenes
