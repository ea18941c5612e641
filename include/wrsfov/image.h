// CPU-side images: what an application uploads and reads back (StereoCompositor::readOutput), and what
// tests, tools and the CPU reference compare.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "layers/formats.h"
#include "layers/status.h"

namespace wrsfov {

/// Tightly packed texels of one 2D image in a swapchain format.
struct HostImage {
    layers::Format format = layers::Format::RGBA8;
    uint32_t width = 0;
    uint32_t height = 0;
    std::vector<std::byte> data;

    static HostImage make(layers::Format format, uint32_t width, uint32_t height);
    std::size_t texelBytes() const { return layers::bytesPerTexel(format); }
    std::span<const std::byte> bytes() const { return data; }

    /// Texel as a shader's texelFetch returns it: UNORM8 -> c/255 (sRGB not decoded: the load
    /// pass decodes), fp16 -> float, R8UI -> the integer as a float, missing channels (0, 0, 0, 1).
    glm::vec4 fetch(uint32_t x, uint32_t y) const;
    /// Writes a texel, converting to the format (UNORM8 rounds and clamps; fp16 rounds to nearest
    /// even; R8UI truncates and clamps to 0..255). Values are stored as given: no sRGB encoding.
    void store(uint32_t x, uint32_t y, glm::vec4 v);
    /// The sub-rectangle (x, y, w, h), same format.
    HostImage crop(uint32_t x, uint32_t y, uint32_t w, uint32_t h) const;
};

}  // namespace wrsfov
