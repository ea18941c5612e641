// Image formats an application may submit, per use (docs/conventions.md; docs/integrating.md, "The frame contract").
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

#include <vulkan/vulkan.h>

namespace wrsfov::layers {

/// What a swapchain's images hold.
enum class Usage : uint8_t { Color, Depth, Motion, ShadingRate };

/// Swapchain formats. Colour: RGBA8 (linear values), RGBA8_SRGB (sRGB-encoded, decoded on load),
/// RGBA16F (linear). Depth: D32F or R32F, values in [0, 1]. Motion: RG16F (dx, dy in pixels) or
/// RGBA16F (dx, dy, dz = z_prev - z_cur in view units, a ignored). Shading rate: R8UI, one texel per
/// block of pixels in VK_KHR_fragment_shading_rate's encoding (layers/frame.h, RateMapInfo).
enum class Format : uint8_t { RGBA8, RGBA8_SRGB, RGBA16F, D32F, R32F, RG16F, R8UI };

std::string_view toString(Usage usage);
std::string_view toString(Format format);
/// Parses the names printed by toString(Format) ("rgba8", "rgba8_srgb", ...).
std::optional<Format> parseFormat(std::string_view name);

/// Whether `format` may be used for `usage` (the table above).
bool isSupported(Usage usage, Format format);
VkFormat toVkFormat(Format format);
/// Bytes of one texel as stored and as uploaded through Swapchain::write.
std::size_t bytesPerTexel(Format format);
bool isDepthFormat(Format format);

}  // namespace wrsfov::layers
