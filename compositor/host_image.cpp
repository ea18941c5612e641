#include "wrsfov/image.h"

#include <algorithm>
#include <cmath>
#include <cstring>


#include "shaders/wrs_common.h"

namespace wrsfov {

using layers::Format;

HostImage HostImage::make(Format format, uint32_t width, uint32_t height) {
    HostImage h;
    h.format = format;
    h.width = width;
    h.height = height;
    h.data.assign(std::size_t(width) * height * layers::bytesPerTexel(format), std::byte{0});
    return h;
}

namespace {
uint16_t loadU16(const std::byte* p) {
    uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
}
void storeU16(std::byte* p, uint16_t v) { std::memcpy(p, &v, 2); }
}  // namespace

glm::vec4 HostImage::fetch(uint32_t x, uint32_t y) const {
    const std::byte* p = data.data() + (std::size_t(y) * width + x) * texelBytes();
    switch (format) {
    case Format::RGBA8:
    case Format::RGBA8_SRGB:
        return glm::vec4(float(uint8_t(p[0])), float(uint8_t(p[1])), float(uint8_t(p[2])), float(uint8_t(p[3]))) /
               255.0f;
    case Format::RGBA16F:
        return glm::vec4(gpu::wrs_f16_to_f32(loadU16(p)), gpu::wrs_f16_to_f32(loadU16(p + 2)),
                         gpu::wrs_f16_to_f32(loadU16(p + 4)), gpu::wrs_f16_to_f32(loadU16(p + 6)));
    case Format::RG16F:
        return glm::vec4(gpu::wrs_f16_to_f32(loadU16(p)), gpu::wrs_f16_to_f32(loadU16(p + 2)), 0.0f, 1.0f);
    case Format::D32F:
    case Format::R32F: {
        float f;
        std::memcpy(&f, p, 4);
        return glm::vec4(f, 0.0f, 0.0f, 1.0f);
    }
    case Format::R8UI: return glm::vec4(float(uint8_t(p[0])), 0.0f, 0.0f, 1.0f);  // the integer, as usampler2D
    }
    return glm::vec4(0.0f);
}

void HostImage::store(uint32_t x, uint32_t y, glm::vec4 v) {
    std::byte* p = data.data() + (std::size_t(y) * width + x) * texelBytes();
    switch (format) {
    case Format::RGBA8:
    case Format::RGBA8_SRGB:
        for (int i = 0; i < 4; ++i) {
            float c = std::isnan(v[i]) ? 0.0f : std::clamp(v[i], 0.0f, 1.0f);
            p[i] = std::byte(uint8_t(std::lround(c * 255.0f)));
        }
        break;
    case Format::RGBA16F:
        for (int i = 0; i < 4; ++i) storeU16(p + 2 * i, uint16_t(gpu::wrs_f32_to_f16(v[i])));
        break;
    case Format::RG16F:
        for (int i = 0; i < 2; ++i) storeU16(p + 2 * i, uint16_t(gpu::wrs_f32_to_f16(v[i])));
        break;
    case Format::D32F:
    case Format::R32F: std::memcpy(p, &v.x, 4); break;
    case Format::R8UI: p[0] = std::byte(uint8_t(std::isnan(v.x) ? 0.0f : std::clamp(v.x, 0.0f, 255.0f))); break;
    }
}

HostImage HostImage::crop(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h) const {
    HostImage out = make(format, w, h);
    std::size_t tb = texelBytes();
    for (uint32_t y = 0; y < h; ++y)
        std::memcpy(out.data.data() + std::size_t(y) * w * tb, data.data() + (std::size_t(y0 + y) * width + x0) * tb,
                    w * tb);
    return out;
}

}  // namespace wrsfov
