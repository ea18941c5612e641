// Where the preview's gaze comes from: the mouse (the cursor's pixel turned into each eye's pixel
// ray), the synthetic generator, a HID eye tracker, a gaze file, or a fixed direction.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "gaze/angles.h"
#include "layers/frame.h"
#include "layers/status.h"
#include "preview/scene_feed.h"
#include "scenes/text.h"

namespace wrsfov::preview {

enum class GazeKind : uint8_t { Mouse, Generator, Hid, File, Fixed };

/// A gaze source as given on the command line.
struct GazeSpec {
    GazeKind kind = GazeKind::Mouse;
    std::string argument;     ///< Hid: device (path, index or VID:PID; empty: the first eye tracker); File: path
    gaze::GazeAngle fixed{};  ///< Fixed: both eyes look along this angle
};

/// Parses `mouse`, `generator`, `hid`, `hid:DEVICE`, `file:PATH` or `fixed:AZ,EL` (degrees,
/// azimuth right +, elevation up +).
Result<GazeSpec> parseGazeSpec(std::string_view text);
/// The text parseGazeSpec reads back.
std::string toString(const GazeSpec& spec);

/// What a gaze source may need to know about the frame.
struct GazeQuery {
    double t = 0;                    ///< scene time in seconds
    layers::Fov fov[2];              ///< the eyes' fields of view
    uint32_t width = 0, height = 0;  ///< one eye's image
    /// Mouse: the cursor's position in an eye image (continuous pixels, y down), when it is over a panel.
    std::optional<std::array<float, 2>> cursor;
};

/// Gaze for both eyes, as the compositor takes it.
struct GazeReading {
    std::array<layers::EyeGaze, 2> eye;
    std::string note;  ///< e.g. "blink", "tracker lost: ...", "cursor outside"; empty when nothing to say
};

class GazeInput {
public:
    virtual ~GazeInput() = default;
    virtual GazeReading sample(const GazeQuery& query) = 0;
    const GazeSpec& spec() const { return spec_; }

protected:
    explicit GazeInput(GazeSpec spec) : spec_(std::move(spec)) {}

private:
    GazeSpec spec_;
};

/// What a source is made for: the generator reads the text scene's lines, or views the atrium freely.
struct GazeSetting {
    SceneKind scene = SceneKind::Text;
    scenes::TextLayout text;
    uint32_t seed = 1;
};

/// Opens a source. Fails with a message when a file cannot be read, no HID eye tracker is there or
/// the generator refuses its configuration.
Result<std::unique_ptr<GazeInput>> createGazeInput(const GazeSpec& spec, const GazeSetting& setting);

/// Mouse gaze: per eye, the ray through the cursor's pixel in that eye's view (docs/conventions.md, "Views");
/// both eyes use the same pixel position. Invalid without a cursor position.
std::array<layers::EyeGaze, 2> gazeFromCursor(const layers::Fov fov[2], uint32_t width, uint32_t height,
                                              std::optional<std::array<float, 2>> cursor);

}  // namespace wrsfov::preview
