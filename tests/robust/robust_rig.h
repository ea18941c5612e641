// Scaffolding of the GPU robustness tests (docs/bad-input.md): small deterministic stereo frames,
// snapshots of everything a frame leaves behind (both eyes' reservoirs and outputs, stats and
// parameters), and a "twin chain": two compositors fed the same good frames, of which only one
// sees the bad input. After a refused bad frame the two must stay bit-identical.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "../core/gpu_checks.h"
#include "../core/gpu_rig.h"

namespace wrsfov::test {

/// Image size of every robustness frame: small, so that the whole suite stays fast on lavapipe.
inline constexpr uint32_t kW = 32, kH = 24;

/// Swapchain formats of a lane; depth and motion are optional.
struct LaneFormats {
    layers::Format color = layers::Format::RGBA16F;
    std::optional<layers::Format> depth = layers::Format::R32F;
    std::optional<layers::Format> motion = layers::Format::RGBA16F;
};

/// One good frame: colour changes with the frame index, depth is fixed patches, motion is zero,
/// gaze is valid and fixed per eye. The same index always gives the same frame.
std::array<EyeFrame, 2> goodFrame(uint64_t index, const LaneFormats& formats);

/// Everything a frame leaves behind in a compositor.
struct Snapshot {
    Reservoirs reservoirs;
    std::array<std::vector<std::byte>, 2> output;
    FrameStats stats;
    gpu::FrameParams params{};
};
Snapshot snapshot(Compositor& comp);
/// Empty when equal bit for bit; else what differs first.
std::string difference(const Snapshot& a, const Snapshot& b);

/// Every reservoir of both eyes unpacks finite with w_sum > 0 and M >= 1; both outputs can be read.
void expectSane(Compositor& comp, const std::string& what);

/// A compositor and the application that feeds it.
struct Lane {
    Lane(vk::Context& ctx, const CompositorConfig& config, const LaneFormats& formats);
    std::unique_ptr<Compositor> comp;
    std::unique_ptr<StereoApp> app;
    LaneFormats formats;
};

/// Two lanes with the same configuration; `main` gets the bad input, `twin` never does.
class TwinChain {
public:
    TwinChain(const CompositorConfig& config, const LaneFormats& formats);
    /// Index of the next frame to submit (the last accepted one + 1).
    uint64_t next() const { return next_; }
    /// Both lanes take good frame next() (or `eyes`, if given) and must end bit-identical.
    void stepBoth(const std::string& what, const std::array<EyeFrame, 2>* eyes = nullptr);
    /// Frames that main and twin took with different (but documented-equivalent) inputs.
    void stepPair(const std::string& what, const std::array<EyeFrame, 2>& mainEyes,
                  const std::array<EyeFrame, 2>& twinEyes);
    /// Both lanes write good frame next() and end it with their frame end changed by `edit`.
    void stepEdited(const std::string& what, const std::function<void(Lane&, layers::FrameEndInfo&)>& edit);
    /// The next frame gets this index (frame indices may jump; only their order is checked).
    void jumpTo(uint64_t index) { next_ = index; }

    Lane main, twin;

    /// Extra swapchains the bad frames point at, made on first use.
    layers::Swapchain& foreignColor();                                    ///< made by another compositor, released
    layers::Swapchain& neverReleased(layers::Usage u, layers::Format f);  ///< on main, never released

private:
    uint64_t next_ = 1;
    std::unique_ptr<Compositor> other_;
    std::unique_ptr<layers::Swapchain> foreign_;
    std::map<int, std::unique_ptr<layers::Swapchain>> never_;
};

/// A swapchain of no compositor: the base class's state machine only, with any format (also
/// those validateCreateInfo refuses), one image released.
class FakeSwapchain final : public layers::Swapchain {
public:
    FakeSwapchain(layers::Usage usage, layers::Format format, uint32_t width, uint32_t height, uint32_t arraySize = 2);
    Status write(uint32_t, uint32_t, std::span<const std::byte>) override { return {}; }
    VkImage image(uint32_t) const override { return VK_NULL_HANDLE; }
};

bool contains(const std::string& s, const std::string& part);

/// A create info of a stereo swapchain (two layers, two images).
layers::SwapchainCreateInfo stereoInfo(layers::Usage usage, layers::Format format, uint32_t w = kW, uint32_t h = kH);

}  // namespace wrsfov::test
