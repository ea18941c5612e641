// What tests and tools read back from a compositor, and the reservoirs they write (compositor.h).
#include "compositor/compositor.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "compositor/compose.h"
#include "compositor/compositor_internal.h"
#include "compositor/input.h"
#include "compositor/swapchain_vk.h"

namespace wrsfov {

using namespace detail;

Result<HostImage> Compositor::readImageLayer(uint32_t layer) {
    HostImage out = HostImage::make(layers::Format::RGBA8, width_, height_);
    auto bytes =
        ctx_.readImageLayer(output_.handle(), VK_IMAGE_ASPECT_COLOR_BIT, layer, width_, height_, out.data.size());
    if (!bytes) return bytes.error();
    out.data = std::move(*bytes);
    return out;
}

Result<HostImage> Compositor::readOutput(uint32_t eye) {
    if (eye >= WRS_EYES || !output_) return Error{1, "no output: eye out of range or no frame composited yet"};
    return readImageLayer(eye);
}

Result<std::vector<glm::uvec4>> Compositor::readReservoirs(uint32_t eye) {
    if (eye >= WRS_EYES || !output_) return Error{1, "no reservoirs: eye out of range or no frame composited yet"};
    auto res = readBuffer(reservoirs_[current_], eye);
    if (!res || !lastSparse_) return res;
    // Tiles that stored nothing hold whatever an earlier frame left there: no sample.
    auto held = readTileHeld(eye);
    if (!held) return held.error();
    const uint32_t tx = groups(width_, gpu::WRS_TILE);
    for (uint32_t y = 0; y < height_; ++y)
        for (uint32_t x = 0; x < width_; ++x)
            if ((*held)[(y / gpu::WRS_TILE) * tx + x / gpu::WRS_TILE] == 0.0f)
                (*res)[std::size_t(y) * width_ + x] = glm::uvec4(0u);
    return res;
}

Result<std::vector<float>> Compositor::readTileHeld(uint32_t eye) {
    if (eye >= WRS_EYES || !output_) return Error{1, "no held qualities: eye out of range or no frame composited yet"};
    if (!lastSparse_) return std::vector<float>{};
    const uint64_t perEye = uint64_t(groups(width_, gpu::WRS_TILE)) * groups(height_, gpu::WRS_TILE);
    // The last frame wrote the half the next one reads.
    auto words = readWords(tileHeld_, (heldPrev_ * WRS_EYES + eye) * perEye, perEye);
    if (!words) return words.error();
    std::vector<float> out(perEye);
    std::memcpy(out.data(), words->data(), perEye * 4);
    return out;
}

Result<std::vector<glm::vec4>> Compositor::readSteadyFloor(uint32_t eye) {
    if (eye >= WRS_EYES || !output_) return Error{1, "no steady floor: eye out of range or no frame composited yet"};
    if (!steadyValid_) return std::vector<glm::vec4>{};
    // The last frame's parameters describe the buffer as it wrote it.
    const glm::uvec4 l4 = params_.levels[gpu::WRS_STEADY_LEVEL];
    const uint64_t texels = uint64_t(l4.x) * l4.y;
    auto words = readWords(pyramid_, uint64_t(gpu::wrs_steady_offset(l4, steadySlot_, eye)) * 2, texels * 2);
    if (!words) return words.error();
    std::vector<glm::vec4> out(texels);
    for (uint64_t i = 0; i < texels; ++i) {
        const uint32_t a = (*words)[2 * i], b = (*words)[2 * i + 1];
        out[i] = glm::vec4(gpu::wrs_f16_to_f32(a & 0xffffu), gpu::wrs_f16_to_f32(a >> 16), gpu::wrs_f16_to_f32(b & 0xffffu),
                           gpu::wrs_f16_to_f32(b >> 16));
    }
    return out;
}

Result<std::vector<glm::vec4>> Compositor::readBirth(uint32_t eye) {
    if (eye >= WRS_EYES || !output_ || !birthAllocated_)
        return Error{1, "no birth colours: eye out of range, no frame composited yet or trackBirth off"};
    auto words = readBuffer(birth_[current_], eye);
    if (!words) return words.error();
    std::vector<glm::vec4> out(words->size());
    std::memcpy(out.data(), words->data(), out.size() * 16);
    return out;
}

Result<std::vector<glm::uvec4>> Compositor::readBuffer(const vk::Buffer& buffer, uint32_t eye) {
    const uint64_t n = uint64_t(width_) * height_;
    auto words = readWords(buffer, eye * n * 4, n * 4);
    if (!words) return words.error();
    std::vector<glm::uvec4> out(n);
    std::memcpy(out.data(), words->data(), n * 16);
    return out;
}

Result<std::vector<uint32_t>> Compositor::readWords(const vk::Buffer& buffer, uint64_t first, uint64_t count) {
    auto staging = ctx_.createBuffer(count * 4, VK_BUFFER_USAGE_TRANSFER_DST_BIT, true);
    if (!staging) return staging.error();
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferCopy region{first * 4, 0, count * 4};
        vkCmdCopyBuffer(cb, buffer.handle(), staging->handle(), 1, &region);
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                          VK_ACCESS_HOST_READ_BIT);
    });
    if (!s) return s.error();
    std::vector<uint32_t> out(count);
    std::memcpy(out.data(), staging->mapped(), count * 4);
    return out;
}

Status Compositor::writeReservoirs(uint32_t eye, const std::vector<glm::uvec4>& packed) {
    const uint64_t n = uint64_t(width_) * height_;
    if (eye >= WRS_EYES || !output_ || packed.size() != n)
        return Error{1, "writeReservoirs needs an eye of a composited frame and width*height reservoirs"};
    auto staging = ctx_.createBuffer(n * 16, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, true);
    if (!staging) return staging.error();
    std::memcpy(staging->mapped(), packed.data(), n * 16);
    Status s = ctx_.submitAndWait([&](VkCommandBuffer cb) {
        vk::memoryBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                          VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                          VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
        VkBufferCopy region{0, eye * n * 16, n * 16};
        vkCmdCopyBuffer(cb, staging->handle(), reservoirs_[current_].handle(), 1, &region);
        if (held_ == Held::Valid) {
            // Every pixel of the eye now holds what was written: its tiles count as holding anything.
            const uint64_t perEye = uint64_t(groups(width_, gpu::WRS_TILE)) * groups(height_, gpu::WRS_TILE);
            vkCmdFillBuffer(cb, tileHeld_.handle(), (heldPrev_ * WRS_EYES + eye) * perEye * 4, perEye * 4, 0x3f800000u);
        }
    });
    if (!s) return s;
    historyValid_ = true;
    return {};
}

}  // namespace wrsfov
