// Swapchains the application renders into, OpenXR style: acquire -> wait -> (render or write) ->
// release. The compositor reads the most recently released image of each swapchain at frame end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include <vulkan/vulkan.h>

#include "layers/formats.h"
#include "layers/status.h"

namespace wrsfov::layers {

struct SwapchainCreateInfo {
    Usage usage = Usage::Color;
    Format format = Format::RGBA8_SRGB;
    uint32_t width = 0;
    uint32_t height = 0;
    uint32_t arraySize = 1;   ///< layers per image (2 lets both eyes share one swapchain)
    uint32_t imageCount = 3;  ///< 1..8
    /// The use is known only at frame end (OpenXR: an RGBA16F swapchain may hold colour or motion):
    /// the swapchain may be given for any use its format allows, not only `usage`.
    bool anyUse = false;
};

/// Refusals of swapchain calls.
enum class SwapchainError : int {
    InvalidCreateInfo = 1,  ///< zero or too large size, array size or image count
    UnsupportedFormat,      ///< the format is not allowed for the usage (see formats.h)
    NoImageAvailable,       ///< every image is acquired and not yet released
    CallOrder,              ///< wait without acquire, release without wait
    WriteOutOfRange,        ///< write with a wrong index, layer or byte count
    DeviceFailure,          ///< the device could not create or fill the images
};

/// Checks a create info; used by every implementation before it allocates.
Status validateCreateInfo(const SwapchainCreateInfo& info);

/// A ring of images. The state machine is here; the images come from the compositor's device.
/// Images stay in VK_IMAGE_LAYOUT_GENERAL for their whole life, so an application rendering with
/// Vulkan needs no layout hand-over, only its own submission ordered before the frame end.
class Swapchain {
public:
    virtual ~Swapchain() = default;
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    const SwapchainCreateInfo& info() const { return info_; }

    /// Next image index to render into (round robin). Fails when all images are acquired.
    Result<uint32_t> acquire();
    /// Waits until the oldest acquired image may be written (it is, as soon as the previous frame
    /// that read it has finished: frame end is synchronous).
    Status wait();
    /// Hands the oldest waited image back; it becomes what the next frame end reads.
    Status release();
    /// For images whose acquire/wait/release runs elsewhere (an OpenXR runtime's, imported by an API
    /// layer): image `index` was released there and is what the next frame end reads. Refused while
    /// an image is acquired here, or for an index out of range.
    Status releasedElsewhere(uint32_t index);

    /// Writes CPU pixels (tightly packed rows of bytesPerTexel(format)) into one layer of an image
    /// the caller has acquired and waited for. Depth D32F takes 4-byte floats.
    virtual Status write(uint32_t index, uint32_t arrayLayer, std::span<const std::byte> texels) = 0;
    /// Reads one layer of an image back (tightly packed texels), e.g. for screenshots and tests.
    /// Implementations without a readback path refuse with DeviceFailure.
    virtual Result<std::vector<std::byte>> read(uint32_t index, uint32_t arrayLayer);
    virtual VkImage image(uint32_t index) const = 0;

    /// Index of the image the compositor will read, -1 if none was released yet.
    int32_t lastReleased() const { return lastReleased_; }
    /// True while an image is acquired or waited and not released.
    bool busy() const { return !acquired_.empty() || !waited_.empty(); }
    bool isWaited(uint32_t index) const;

protected:
    explicit Swapchain(const SwapchainCreateInfo& info) : info_(info) {}

private:
    SwapchainCreateInfo info_;
    uint32_t next_ = 0;
    std::deque<uint32_t> acquired_;
    std::deque<uint32_t> waited_;
    int32_t lastReleased_ = -1;
};

}  // namespace wrsfov::layers
