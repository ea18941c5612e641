#include "layers/swapchain.h"

#include <algorithm>
#include <string>

namespace wrsfov::layers {

namespace {
Error err(SwapchainError code, std::string msg) { return Error{static_cast<int>(code), std::move(msg)}; }
}  // namespace

Status validateCreateInfo(const SwapchainCreateInfo& info) {
    constexpr uint32_t kMaxSize = 16384;
    if (info.width == 0 || info.height == 0 || info.width > kMaxSize || info.height > kMaxSize)
        return err(SwapchainError::InvalidCreateInfo, "swapchain size " + std::to_string(info.width) + "x" +
                                                          std::to_string(info.height) + " is outside 1..16384");
    if (info.arraySize == 0 || info.arraySize > 2)
        return err(SwapchainError::InvalidCreateInfo,
                   "swapchain array size " + std::to_string(info.arraySize) + " is not 1 or 2");
    if (info.imageCount == 0 || info.imageCount > 8)
        return err(SwapchainError::InvalidCreateInfo,
                   "swapchain image count " + std::to_string(info.imageCount) + " is outside 1..8");
    if (!isSupported(info.usage, info.format))
        return err(SwapchainError::UnsupportedFormat, "format " + std::string(toString(info.format)) +
                                                          " is not supported for " + std::string(toString(info.usage)) +
                                                          " swapchains");
    return {};
}

Result<uint32_t> Swapchain::acquire() {
    if (acquired_.size() + waited_.size() >= info_.imageCount)
        return err(SwapchainError::NoImageAvailable,
                   "all " + std::to_string(info_.imageCount) + " swapchain images are acquired; release one first");
    uint32_t index = next_;
    next_ = (next_ + 1) % info_.imageCount;
    acquired_.push_back(index);
    return index;
}

Status Swapchain::wait() {
    if (acquired_.empty()) return err(SwapchainError::CallOrder, "wait called with no acquired image");
    waited_.push_back(acquired_.front());
    acquired_.pop_front();
    return {};
}

Status Swapchain::release() {
    if (waited_.empty())
        return err(SwapchainError::CallOrder, acquired_.empty() ? "release called with no acquired image"
                                                                : "release called before wait");
    lastReleased_ = static_cast<int32_t>(waited_.front());
    waited_.pop_front();
    return {};
}

Status Swapchain::releasedElsewhere(uint32_t index) {
    if (index >= info_.imageCount)
        return err(SwapchainError::WriteOutOfRange, "image " + std::to_string(index) + " released elsewhere, but the "
                                                        "swapchain has " + std::to_string(info_.imageCount) + " images");
    if (busy()) return err(SwapchainError::CallOrder, "released elsewhere while an image is acquired here");
    lastReleased_ = static_cast<int32_t>(index);
    return {};
}

Result<std::vector<std::byte>> Swapchain::read(uint32_t, uint32_t) {
    return err(SwapchainError::DeviceFailure, "this swapchain cannot read its images back");
}

bool Swapchain::isWaited(uint32_t index) const {
    return std::find(waited_.begin(), waited_.end(), index) != waited_.end();
}

}  // namespace wrsfov::layers
