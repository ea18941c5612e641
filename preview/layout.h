// Where things are in the preview: the panels of the preview image (one eye's output, reference or
// error map each), the stats strip under them, where the preview image lands in the window, and
// which eye pixel the cursor is over.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace wrsfov::preview {

/// What the window shows.
enum class View : uint8_t {
    Stereo,   ///< both eyes' output side by side (left | right)
    Left,     ///< the left eye's output alone
    Right,    ///< the right eye's output alone
    Compare,  ///< output above the unfoveated reference, both eyes
    Error,    ///< |output - reference| per eye, colour-mapped
    Visible,  ///< FovVideoVDP's visible distortion of the output against the reference per eye, colour-mapped
};
/// Every view, in the V key's order.
inline constexpr View kViews[] = {View::Stereo, View::Left, View::Right, View::Compare, View::Error, View::Visible};
std::string_view toString(View v);
std::optional<View> parseView(std::string_view name);
/// The next view in the order above (the V key).
View nextView(View v);
/// True when the view needs the reference compositor.
bool needsReference(View v);

/// Values equal WRS_PANEL_* in panel_params.h.
enum class PanelKind : uint32_t { Output = 0, Reference = 1, Error = 2, Visible = 4 };

struct Panel {
    uint32_t x = 0, y = 0;  ///< origin in the preview image
    PanelKind kind = PanelKind::Output;
    uint32_t eye = 0;
};

/// The preview image: panels of one eye's size, then the stats strip across the full width.
struct Layout {
    View view = View::Stereo;
    uint32_t eyeWidth = 0, eyeHeight = 0;
    uint32_t width = 0, height = 0;  ///< the whole preview image
    uint32_t stripY = 0, stripHeight = 0;
    uint32_t stripLines = 0;
    std::vector<Panel> panels;
};

/// Line height of the stats strip in pixels.
inline constexpr uint32_t kStripLineHeight = 14;

/// `stripLines` = 0: as many strip lines as the width likely needs for the stats.
Layout makeLayout(View view, uint32_t eyeWidth, uint32_t eyeHeight, uint32_t stripLines = 0);

/// Where the preview image is drawn in a framebuffer: scaled to fit with its aspect ratio kept,
/// centred (the rest is black).
struct Placement {
    int32_t x = 0, y = 0;
    uint32_t width = 0, height = 0;
};
Placement placeInWindow(uint32_t contentWidth, uint32_t contentHeight, uint32_t fbWidth, uint32_t fbHeight);

/// The panel under a framebuffer position and the position inside that eye's image, in continuous
/// pixel coordinates (0..W, 0..H, y down; pixel (i, j) covers [i, i+1) x [j, j+1)).
struct PanelHit {
    uint32_t eye = 0;
    PanelKind kind = PanelKind::Output;
    float x = 0, y = 0;
};
std::optional<PanelHit> hitTest(const Layout& layout, const Placement& placement, double fbX, double fbY);

}  // namespace wrsfov::preview
