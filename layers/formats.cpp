#include "layers/formats.h"

namespace wrsfov::layers {

std::string_view toString(Usage usage) {
    switch (usage) {
    case Usage::Color: return "color";
    case Usage::Depth: return "depth";
    case Usage::Motion: return "motion";
    case Usage::ShadingRate: return "shading-rate";
    }
    return "?";
}

std::string_view toString(Format format) {
    switch (format) {
    case Format::RGBA8: return "rgba8";
    case Format::RGBA8_SRGB: return "rgba8_srgb";
    case Format::RGBA16F: return "rgba16f";
    case Format::D32F: return "d32f";
    case Format::R32F: return "r32f";
    case Format::RG16F: return "rg16f";
    case Format::R8UI: return "r8ui";
    }
    return "?";
}

std::optional<Format> parseFormat(std::string_view name) {
    for (Format f : {Format::RGBA8, Format::RGBA8_SRGB, Format::RGBA16F, Format::D32F, Format::R32F, Format::RG16F, Format::R8UI})
        if (toString(f) == name) return f;
    return std::nullopt;
}

bool isSupported(Usage usage, Format format) {
    switch (usage) {
    case Usage::Color: return format == Format::RGBA8 || format == Format::RGBA8_SRGB || format == Format::RGBA16F;
    case Usage::Depth: return format == Format::D32F || format == Format::R32F;
    case Usage::Motion: return format == Format::RG16F || format == Format::RGBA16F;
    case Usage::ShadingRate: return format == Format::R8UI;
    }
    return false;
}

VkFormat toVkFormat(Format format) {
    switch (format) {
    case Format::RGBA8: return VK_FORMAT_R8G8B8A8_UNORM;
    case Format::RGBA8_SRGB: return VK_FORMAT_R8G8B8A8_SRGB;
    case Format::RGBA16F: return VK_FORMAT_R16G16B16A16_SFLOAT;
    case Format::D32F: return VK_FORMAT_D32_SFLOAT;
    case Format::R32F: return VK_FORMAT_R32_SFLOAT;
    case Format::RG16F: return VK_FORMAT_R16G16_SFLOAT;
    case Format::R8UI: return VK_FORMAT_R8_UINT;
    }
    return VK_FORMAT_UNDEFINED;
}

std::size_t bytesPerTexel(Format format) {
    switch (format) {
    case Format::RGBA8:
    case Format::RGBA8_SRGB:
    case Format::D32F:
    case Format::R32F:
    case Format::RG16F: return 4;
    case Format::RGBA16F: return 8;
    case Format::R8UI: return 1;
    }
    return 0;
}

bool isDepthFormat(Format format) { return format == Format::D32F; }

}  // namespace wrsfov::layers
