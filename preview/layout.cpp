#include "preview/layout.h"

#include <algorithm>
#include <cmath>

namespace wrsfov::preview {

std::string_view toString(View v) {
    switch (v) {
        case View::Stereo:
            return "stereo";
        case View::Left:
            return "left";
        case View::Right:
            return "right";
        case View::Compare:
            return "compare";
        case View::Error:
            return "error";
        case View::Visible:
            return "visible";
    }
    return "?";
}

std::optional<View> parseView(std::string_view name) {
    for (View v : kViews)
        if (toString(v) == name) return v;
    return std::nullopt;
}

View nextView(View v) {
    for (size_t i = 0; i < std::size(kViews); ++i)
        if (kViews[i] == v) return kViews[(i + 1) % std::size(kViews)];
    return View::Stereo;
}

bool needsReference(View v) { return v == View::Compare || v == View::Error || v == View::Visible; }

Layout makeLayout(View view, uint32_t w, uint32_t h, uint32_t stripLines) {
    Layout l;
    l.view = view;
    l.eyeWidth = w;
    l.eyeHeight = h;
    auto add = [&](uint32_t col, uint32_t row, PanelKind kind, uint32_t eye) {
        l.panels.push_back({col * w, row * h, kind, eye});
    };
    uint32_t cols = 2, rows = 1;
    switch (view) {
        case View::Stereo:
            add(0, 0, PanelKind::Output, 0);
            add(1, 0, PanelKind::Output, 1);
            break;
        case View::Left:
        case View::Right:
            cols = 1;
            add(0, 0, PanelKind::Output, view == View::Left ? 0 : 1);
            break;
        case View::Compare:
            rows = 2;
            add(0, 0, PanelKind::Output, 0);
            add(1, 0, PanelKind::Output, 1);
            add(0, 1, PanelKind::Reference, 0);
            add(1, 1, PanelKind::Reference, 1);
            break;
        case View::Error:
        case View::Visible: {
            const PanelKind k = view == View::Error ? PanelKind::Error : PanelKind::Visible;
            add(0, 0, k, 0);
            add(1, 0, k, 1);
            break;
        }
    }
    l.width = cols * w;
    // About 6.5 pixels per character of the strip font and up to ~300 characters of stats: as many lines
    // as the width needs, at least two.
    l.stripLines = stripLines ? stripLines : std::clamp<uint32_t>((2000 + l.width - 1) / l.width, 2, 12);
    l.stripY = rows * h;
    l.stripHeight = l.stripLines * kStripLineHeight + 4;
    l.height = l.stripY + l.stripHeight;
    return l;
}

Placement placeInWindow(uint32_t cw, uint32_t ch, uint32_t fw, uint32_t fh) {
    Placement p;
    if (cw == 0 || ch == 0 || fw == 0 || fh == 0) return p;
    const double s = std::min(double(fw) / cw, double(fh) / ch);
    p.width = std::clamp<uint32_t>(uint32_t(std::lround(cw * s)), 1, fw);
    p.height = std::clamp<uint32_t>(uint32_t(std::lround(ch * s)), 1, fh);
    p.x = int32_t((fw - p.width) / 2);
    p.y = int32_t((fh - p.height) / 2);
    return p;
}

std::optional<PanelHit> hitTest(const Layout& l, const Placement& p, double fx, double fy) {
    if (p.width == 0 || p.height == 0) return std::nullopt;
    // Framebuffer -> preview image coordinates (continuous).
    const double cx = (fx - p.x) * double(l.width) / p.width;
    const double cy = (fy - p.y) * double(l.height) / p.height;
    for (const Panel& panel : l.panels) {
        const double px = cx - panel.x, py = cy - panel.y;
        if (px >= 0 && py >= 0 && px < l.eyeWidth && py < l.eyeHeight)
            return PanelHit{panel.eye, panel.kind, float(px), float(py)};
    }
    return std::nullopt;
}

}  // namespace wrsfov::preview
