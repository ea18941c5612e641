// The application side for CPU-made images: stereo swapchains (two array layers, layer = eye) that
// it fills through acquire/wait/write/release, and the frame end it submits. Tools and tests use it
// to drive the compositor exactly as an application would.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>

#include "compositor/compositor.h"
#include "wrsfov/image.h"
#include "layers/frame.h"

namespace wrsfov {

/// What one eye submits in a frame.
struct EyeSubmission {
    HostImage color;
    std::optional<HostImage> depth;   ///< R32F or D32F, [0, 1]
    std::optional<HostImage> motion;  ///< RG16F or RGBA16F, pixels
    layers::Fov fov;
    layers::EyeGaze gaze;
};

class HostStereoApp {
public:
    struct Options {
        uint32_t width = 0, height = 0;
        layers::Format color = layers::Format::RGBA8_SRGB;
        std::optional<layers::Format> depth;
        std::optional<layers::Format> motion;
        float nearZ = 0.1f, farZ = 100.0f;
        bool reversedZ = false;
        /// One view shown to both eyes (a monitor, a mono preview): only eye 0's images are written
        /// and both views reference them, which lets the compositor do the work once.
        bool monoView = false;
        /// Images per swapchain: 1 is enough when every frame end waits for its work (Compositor::endFrame).
        uint32_t imageCount = 2;
    };
    /// Creates the swapchains on `compositor`; fails with the swapchain error.
    static Result<std::unique_ptr<HostStereoApp>> create(Compositor& compositor, const Options& options);

    /// An app that submits `source`'s images to another compositor on the same device, with no copy
    /// and no upload: its swapchains import source's images, and submitShared() ends a frame with
    /// what `source` last released. Several compositors fed this way read the very same inputs
    /// (the benchmark's sweep keeps a scene's frames on the device so). `source` must outlive it.
    static Result<std::unique_ptr<HostStereoApp>> share(Compositor& compositor, HostStereoApp& source);

    /// Writes both eyes' images (acquire, wait, write, release).
    Status write(const std::array<EyeSubmission, 2>& eyes);
    /// The frame end for the images last written.
    layers::FrameEndInfo frameEnd(uint64_t frameIndex, double time_s, const std::array<EyeSubmission, 2>& eyes) const;
    /// write() then Compositor::endFrame().
    Status submit(uint64_t frameIndex, double time_s, const std::array<EyeSubmission, 2>& eyes);
    /// For an app made by share(): Compositor::endFrame() with the images its source last released
    /// (`eyes` gives the field of view and gaze only). Refused for an app not made by share().
    Status submitShared(uint64_t frameIndex, double time_s, const std::array<EyeSubmission, 2>& eyes);

    /// One image of each swapchain, as drawInPlace hands them over (depth and motion 0 where the app
    /// has no such swapchain).
    struct Images {
        uint32_t color = 0, depth = 0, motion = 0;
    };
    /// For a renderer that draws into the swapchains itself, as a Vulkan application does: acquires
    /// and waits for one image of each swapchain, runs `draw` on them (render, read back), and releases
    /// every image it acquired whatever happened. The first failure (acquire, wait, `draw`) is returned.
    Status drawInPlace(const std::function<Status(const Images&)>& draw);
    /// Inside drawInPlace's `draw`: eye `eye`'s layer of the images `im` read back, in the swapchains'
    /// formats and size; `depth` and `motion` where the app has those swapchains.
    Status readBack(const Images& im, uint32_t eye, HostImage& color, HostImage* depth, HostImage* motion);

    layers::Swapchain& color() { return *color_; }
    layers::Swapchain* depth() { return depth_.get(); }
    layers::Swapchain* motion() { return motion_.get(); }
    const Options& options() const { return options_; }

private:
    HostStereoApp(Compositor& c, const Options& o) : comp_(c), options_(o) {}
    Compositor& comp_;
    Options options_;
    std::unique_ptr<layers::Swapchain> color_, depth_, motion_;
    HostStereoApp* source_ = nullptr;  // share(): whose images these swapchains import
};

/// A typical HMD per-eye field of view (0 left, 1 right): asymmetric, the nasal side narrower than
/// the temporal side, mirrored between the eyes; 92° x 93° per eye.
layers::Fov hmdFov(int eye);

/// Unit direction through the centre of pixel (x, y) of a view (docs/conventions.md, "Views"), for turning
/// a point on the image into a gaze direction.
glm::vec3 pixelDirection(const layers::Fov& fov, uint32_t width, uint32_t height, float x, float y);

}  // namespace wrsfov
