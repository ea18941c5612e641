// The `text` scene (the paper's experiment 1): a page of text for reading spanning ±20° horizontally,
// peripheral nonsense text around it, characters 0.5° wide so that a 5° fovea shows about 10 of
// them. The page is a plane in front of a static stereo camera; each eye's image is rendered by
// intersecting its pixel rays with the plane and supersampling a page texture drawn with OpenCV
// (FreeType with DejaVu Sans where installed, Hershey otherwise).
#pragma once

#include <array>
#include <string>

#include <opencv2/core.hpp>

#include "wrsfov/image.h"
#include "layers/frame.h"

namespace wrsfov::scenes {

/// Where the text is, in degrees of visual angle seen from the cyclopean eye (azimuth right +,
/// elevation up +); what the reading gaze generator needs to follow the lines.
struct TextLayout {
    double charDeg = 0.5;          ///< advance of one character at the page centre
    double lineSpacingDeg = 1.5;   ///< distance between baselines
    int lineChars = 80;            ///< characters per line: 80 x 0.5° = ±20°
    int lines = 12;
    /// Elevation of the centre of line i (x-height middle), the convention of the reading gaze
    /// generator: the block is centred on the view axis.
    double lineCentreDeg(int i) const { return 0.5 * (lines - 1) * lineSpacingDeg - i * lineSpacingDeg; }
    double leftEdgeAzimuthDeg() const { return -0.5 * lineChars * charDeg; }
};

struct TextOptions {
    uint32_t width = 512, height = 512;  ///< per eye
    float ipd = 0.063f;                  ///< metres; 0 gives identical eyes
    float distance = 0.6f;               ///< metres from the eyes to the page plane
    bool monitor = false;                ///< one symmetric 76° x 60° view for both eyes (no disparity)
    uint32_t seed = 1;
    TextLayout layout;
    float nearZ = 0.05f, farZ = 100.0f;
};

/// Per-eye field of view of the text scene (HMD-like asymmetric, or the monitor's symmetric one).
layers::Fov textFov(const TextOptions& o, int eye);

/// Renders both eyes once (the scene is static). Colour is RGBA8_SRGB, depth R32F (the plane).
class TextScene {
public:
    explicit TextScene(const TextOptions& options);
    const HostImage& color(int eye) const { return color_[eye]; }
    const HostImage& depth(int eye) const { return depth_[eye]; }
    const TextOptions& options() const { return options_; }
    /// True when the FreeType font was found; otherwise Hershey glyphs were used.
    bool usedFreeType() const { return freetype_; }
    /// The same page through other views (same eye positions), each eye `fovs[eye]` at width x height:
    /// e.g. a quad view's wide view at a low density or its inset around the gaze. The renderer is the
    /// same at any size (2x2 samples per pixel of a page texture made for TextOptions' density), so a
    /// sparser view aliases as a renderer at that density would.
    /// `footprint` < 1 gathers each pixel's 2x2 subsamples from that fraction of it around its centre: a
    /// view rendered for temporal upsampling samples the page at the display's density (the view's
    /// density over the display's), so each pixel is a sharp sample at its centre.
    void renderViews(const std::array<layers::Fov, 2>& fovs, uint32_t width, uint32_t height,
                     std::array<HostImage, 2>& color, std::array<HostImage, 2>& depth, float footprint = 1.0f) const;

private:
    TextOptions options_;
    std::array<HostImage, 2> color_, depth_;
    cv::Mat page_;      // linear RGB (BGR order), CV_32FC3
    double ppt_ = 0.0;  // page texels per tangent unit
    bool freetype_ = false;
};

}  // namespace wrsfov::scenes
