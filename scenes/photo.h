// The `photo` scene: natural texture on a plane. An image (a PNG or JPEG file, or a texture the
// scene generates: `grass`, 1/f noise with strands, or `wood`, stretched 1/f noise with rings) lies
// on a plane at a given distance in front of the viewer, repeated mirrored beyond its edges, one
// texel per pixel at the view's centre. The head is still, pans sideways or turns at a constant speed
// given in pixels per frame at the view's centre. Each frame is resampled from the texture with an
// 8x8 Lanczos kernel through the exact screen-to-plane mapping (band-limited, not integer shifts),
// with the plane's exact depth and motion vectors (previous position - current, in pixels, and the
// change of view depth).
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <opencv2/core.hpp>

#include "wrsfov/image.h"
#include "layers/frame.h"
#include "layers/status.h"

namespace wrsfov::scenes {

enum class PhotoMotion : uint8_t {
    Static,  ///< head still
    Pan,     ///< sideways translation parallel to the plane: every pixel moves alike
    Turn,    ///< yaw about the eyes: motion grows off-axis
};
/// "static", "pan", "turn"; nullopt for anything else.
std::optional<PhotoMotion> parsePhotoMotion(std::string_view name);
std::string_view toString(PhotoMotion m);

struct PhotoOptions {
    uint32_t width = 1024, height = 768;  ///< per eye
    bool monitor = true;                  ///< one symmetric 76° x 60° view for both eyes; else HMD stereo
    /// HMD stereo only: > 0 replaces the HMD's field of view by a symmetric square one of this many
    /// degrees per eye (as the atrium's AtriumOptions::fovDeg).
    float fovDeg = 0.0f;
    float ipd = 0.063f;                   ///< metres (HMD stereo)
    float distance = 1.0f;                ///< metres from the eyes to the plane
    PhotoMotion motion = PhotoMotion::Static;
    float speed = 0.37f;  ///< pixels per frame at the view's centre (pan and turn)
    /// An image file (PNG, JPEG: anything OpenCV reads), or `grass` / `wood` for a generated texture.
    std::string image = "grass";
    /// Texels of the image per pixel at the view's centre (1: the image's own detail at full resolution).
    float imageScale = 1.0f;
    uint32_t frames = 300;  ///< frames the generated texture must cover without repeating (pans)
    uint32_t seed = 1;
    float nearZ = 0.05f, farZ = 100.0f;
};

/// A generated texture of w x h texels: linear RGB, CV_32FC3 (R, G, B order), values in [0, 1].
/// `kind` is "grass" (1/f noise under thousands of thin curved strands) or "wood" (1/f noise stretched
/// along the grain, with rings); the same seed gives the same texture.
Result<cv::Mat> generatePhotoTexture(std::string_view kind, int w, int h, uint32_t seed);

/// Per-eye field of view (monitorFov() in monitor mode, the HMD's otherwise).
layers::Fov photoFov(const PhotoOptions& o, int eye);

class PhotoScene {
public:
    /// Loads or generates the texture; fails with a message on an unreadable file or a bad option.
    static Result<std::unique_ptr<PhotoScene>> create(const PhotoOptions& options);

    /// Frame `index` (0 first: no motion) of eye `eye`: colour RGBA8_SRGB, depth D32F (standard
    /// depth, near/far of the options), motion RGBA16F (x, y in pixels to the previous position, z
    /// the view depth there minus here).
    Status render(uint32_t index, int eye, HostImage& color, HostImage& depth, HostImage& motion) const;
    /// The same at a fractional frame (frames at the speed's rate), motion from `prevFrame`: for a
    /// viewer whose frames do not come at a fixed rate.
    Status renderAt(double frame, double prevFrame, int eye, HostImage& color, HostImage& depth, HostImage& motion) const;
    /// The same eye through another view at another size (a quad view's wide view at a low density, or
    /// its inset on the gaze): one Lanczos sample of the texture at each pixel's centre, as a renderer
    /// sampling the texture once per pixel does at that density (a sparse view aliases the texture's
    /// fine detail; it is not a blur of the full-resolution frame); depth and motion in that view's
    /// pixels. With photoFov(eye) at the options' size it is renderAt, bit for bit.
    Status renderViewAt(double frame, double prevFrame, int eye, const layers::Fov& fov, uint32_t width,
                        uint32_t height, HostImage& color, HostImage& depth, HostImage& motion) const;
    const PhotoOptions& options() const { return options_; }
    /// Pixels per tangent unit at the view's centre (the texture's density on the plane).
    double pixelsPerTangent() const { return ppt_; }

private:
    PhotoScene() = default;
    struct Pose {
        double x = 0, yaw = 0;  ///< head position along the plane (metres) and yaw (radians, left +)
    };
    Pose pose(double frame) const;

    PhotoOptions options_;
    cv::Mat texture_;  ///< linear RGB, CV_32FC3
    double ppt_ = 1, originX_ = 0, originY_ = 0;  ///< texel (0,0)'s corner on the plane, tangent units
};

}  // namespace wrsfov::scenes
