// Refusals through the real compositor and its swapchains: every SubmitError from its own malformed
// frame, the swapchain write checks, and that a refused frame changes nothing: a run with refused
// frames in between is bit-identical to the same run without them.
#include <cmath>
#include <cstring>
#include <functional>
#include <initializer_list>
#include <limits>
#include <string>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

using layers::Format;
using layers::SubmitError;
using layers::SwapchainError;
using layers::Usage;

const float kNaN = std::numeric_limits<float>::quiet_NaN();

class FakeSwapchain final : public layers::Swapchain {
public:
    explicit FakeSwapchain(const layers::SwapchainCreateInfo& info) : Swapchain(info) {}
    Status write(uint32_t, uint32_t, std::span<const std::byte>) override { return {}; }
    VkImage image(uint32_t) const override { return VK_NULL_HANDLE; }
};

layers::SwapchainCreateInfo createInfo(Usage usage, Format format, uint32_t w, uint32_t h) {
    layers::SwapchainCreateInfo ci;
    ci.usage = usage;
    ci.format = format;
    ci.width = w;
    ci.height = h;
    ci.arraySize = 2;
    ci.imageCount = 2;
    return ci;
}

void releaseOne(layers::Swapchain& sc) {
    ASSERT_TRUE(sc.acquire().ok());
    ASSERT_TRUE(sc.wait().ok());
    ASSERT_TRUE(sc.release().ok());
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

class Refusals : public GpuTest {
protected:
    static constexpr uint32_t W = 48, H = 40;
};

TEST_F(Refusals, SwapchainCreationAndWrites) {
    auto comp = Compositor::create(context());
    ASSERT_TRUE(comp.ok());
    // Unsupported formats are refused at creation, before anything is allocated.
    auto bad = (*comp)->createSwapchain(createInfo(Usage::Color, Format::D32F, W, H));
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, int(SwapchainError::UnsupportedFormat));
    EXPECT_TRUE(contains(bad.error().message, "d32f")) << bad.error().message;
    bad = (*comp)->createSwapchain(createInfo(Usage::Motion, Format::RGBA8, W, H));
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, int(SwapchainError::UnsupportedFormat));
    auto zero = createInfo(Usage::Color, Format::RGBA8, 0, H);
    bad = (*comp)->createSwapchain(zero);
    ASSERT_FALSE(bad.ok());
    EXPECT_EQ(bad.error().code, int(SwapchainError::InvalidCreateInfo));

    auto sc = (*comp)->createSwapchain(createInfo(Usage::Color, Format::RGBA16F, W, H));
    ASSERT_TRUE(sc.ok()) << sc.error().message;
    layers::Swapchain& s = **sc;
    HostImage img = HostImage::make(Format::RGBA16F, W, H);
    // Never acquired.
    Status st = s.write(0, 0, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::CallOrder));
    EXPECT_TRUE(contains(st.message(), "not acquired and waited")) << st.message();
    // Acquired but not waited.
    auto idx = s.acquire();
    ASSERT_TRUE(idx.ok());
    st = s.write(*idx, 0, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::CallOrder));
    ASSERT_TRUE(s.wait().ok());
    // Wrong byte count, layer and image index.
    st = s.write(*idx, 0, std::span<const std::byte>(img.data).first(img.data.size() - 8));
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::WriteOutOfRange));
    EXPECT_TRUE(contains(st.message(), std::to_string(img.data.size() - 8) + " bytes")) << st.message();
    EXPECT_TRUE(contains(st.message(), "takes " + std::to_string(img.data.size()))) << st.message();
    HostImage rgba8 = HostImage::make(Format::RGBA8, W, H);  // half the bytes
    st = s.write(*idx, 0, rgba8.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::WriteOutOfRange));
    st = s.write(*idx, 2, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::WriteOutOfRange));
    EXPECT_TRUE(contains(st.message(), "layer 2")) << st.message();
    st = s.write(5, 0, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::WriteOutOfRange));
    // The waited image takes the right write; the other image (not acquired) still does not.
    EXPECT_TRUE(s.write(*idx, 1, img.bytes()).ok());
    st = s.write(1 - *idx, 0, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::CallOrder));
    ASSERT_TRUE(s.release().ok());
    // Released: no more writes to it.
    st = s.write(*idx, 0, img.bytes());
    ASSERT_FALSE(st.ok());
    EXPECT_EQ(st.error().code, int(SwapchainError::CallOrder));
    // Acquire until none is left.
    ASSERT_TRUE(s.acquire().ok());
    ASSERT_TRUE(s.acquire().ok());
    auto none = s.acquire();
    ASSERT_FALSE(none.ok());
    EXPECT_EQ(none.error().code, int(SwapchainError::NoImageAvailable));
}

// A stereo sequence with depth and motion; `refuse` is called before every frame after the first and
// may submit refused frames (it must not change what the compositor does next).
std::array<Reservoirs, 8> runSequence(Compositor& comp, StereoApp& app,
                                      const std::function<void(uint64_t next, const std::array<EyeFrame, 2>&)>& refuse,
                                      std::array<std::array<HostImage, 2>, 8>* outputs) {
    std::array<Reservoirs, 8> res;
    RandomScene rs(31);
    for (int f = 0; f < 8; ++f) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            eyes[e].color = rs.color(Format::RGBA8_SRGB, 48, 40);
            eyes[e].depth = rs.depth(Format::R32F, 48, 40);
            eyes[e].motion = rs.motion(Format::RGBA16F, 48, 40);
            eyes[e].gaze = {rs.gaze(eyes[e].fov), true, 1.0f};
        }
        if (f > 0 && refuse) refuse(uint64_t(f + 1), eyes);
        Status s = app.submit(uint64_t(f + 1), eyes);
        EXPECT_TRUE(s.ok()) << "frame " << f + 1 << ": " << s.message();
        res[f] = readReservoirs(comp);
        for (uint32_t e = 0; e < 2; ++e) {
            auto o = comp.readOutput(e);
            EXPECT_TRUE(o.ok());
            if (o.ok()) (*outputs)[f][e] = std::move(*o);
        }
    }
    return res;
}

TEST_F(Refusals, EveryCodeThroughEndFrameAndNoneChangesState) {
    CompositorConfig cfg;
    cfg.foveaDeg = 10.0f;
    cfg.seed = 5;
    // Run without refusals.
    auto plain = Compositor::create(context(), cfg);
    ASSERT_TRUE(plain.ok());
    StereoApp plainApp(**plain, W, H, Format::RGBA8_SRGB, Format::R32F, Format::RGBA16F);
    std::array<std::array<HostImage, 2>, 8> plainOut, refusedOut;
    auto expected = runSequence(**plain, plainApp, nullptr, &plainOut);

    // The same run with every kind of refused frame before every frame.
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok());
    Compositor& c = **comp;
    StereoApp app(c, W, H, Format::RGBA8_SRGB, Format::R32F, Format::RGBA16F);
    auto other = Compositor::create(context(), cfg);
    ASSERT_TRUE(other.ok());
    auto foreign = (*other)->createSwapchain(createInfo(Usage::Color, Format::RGBA8_SRGB, W, H));
    ASSERT_TRUE(foreign.ok());
    releaseOne(**foreign);
    auto neverReleased = c.createSwapchain(createInfo(Usage::Motion, Format::RGBA16F, W, H));
    ASSERT_TRUE(neverReleased.ok());
    FakeSwapchain fakeD32Color(createInfo(Usage::Color, Format::D32F, W, H));
    releaseOne(fakeD32Color);
    FakeSwapchain fakeColor(createInfo(Usage::Color, Format::RGBA8_SRGB, W, H));
    releaseOne(fakeColor);

    struct Case {
        const char* name;
        SubmitError code;
        std::vector<std::string> message;
        std::function<void(layers::FrameEndInfo&)> edit;
    };
    using F = layers::FrameEndInfo;
    auto views = [](F& f) -> std::vector<layers::ProjectionView>& { return f.layers[0].views; };
    const std::vector<Case> cases = {
        {"no layer", SubmitError::LayerCount, {"got 0"}, [](F& f) { f.layers.clear(); }},
        {"two layers", SubmitError::LayerCount, {"got 2"}, [](F& f) { f.layers.push_back(f.layers[0]); }},
        {"one view", SubmitError::MissingEye, {"got 1"}, [&](F& f) { views(f).pop_back(); }},
        {"null colour", SubmitError::NullSwapchain, {"right colour"}, [&](F& f) { views(f)[1].color.swapchain = nullptr; }},
        {"depth as colour", SubmitError::WrongUsage, {"left colour", "depth"},
         [&](F& f) { views(f)[0].color.swapchain = app.depth(); }},
        {"d32f colour", SubmitError::UnsupportedFormat, {"left colour", "d32f"},
         [&](F& f) { views(f)[0].color.swapchain = &fakeD32Color; }},
        {"depth size", SubmitError::SizeMismatch, {"left depth"},
         [&](F& f) { views(f)[0].depth->subImage.rect.width -= 1; }},
        {"motion size", SubmitError::SizeMismatch, {"right motion"},
         [&](F& f) { views(f)[1].motion->subImage.rect.height -= 2; }},
        {"left vs right", SubmitError::SizeMismatch, {"left and right"},
         [&](F& f) {
             views(f)[1].color.rect.width = W / 2;
             views(f)[1].depth->subImage.rect.width = W / 2;
             views(f)[1].motion->subImage.rect.width = W / 2;
         }},
        {"rect outside", SubmitError::RectOutOfBounds, {"right colour"}, [&](F& f) { views(f)[1].color.rect.x = 1; }},
        {"array index", SubmitError::ArrayIndexOutOfRange, {"left motion", "array layer 2"},
         [&](F& f) { views(f)[0].motion->subImage.arrayIndex = 2; }},
        {"never released", SubmitError::ImageNotReleased, {"left motion", "no released image"},
         [&](F& f) {
             views(f)[0].motion->subImage.swapchain = neverReleased->get();
             views(f)[1].motion->subImage.swapchain = neverReleased->get();
         }},
        {"same index", SubmitError::FrameOutOfOrder, {"frame index"}, [](F& f) { f.frameIndex -= 1; }},
        {"time back", SubmitError::FrameOutOfOrder, {"frame time"}, [](F& f) { f.time_s = -1.0; }},
        {"NaN time", SubmitError::FrameOutOfOrder, {"not finite"},
         [](F& f) { f.time_s = std::numeric_limits<double>::quiet_NaN(); }},
        {"NaN fov", SubmitError::InvalidFov, {"right view field of view"},
         [&](F& f) { views(f)[1].fov.angleLeft = kNaN; }},
        {"90° fov", SubmitError::InvalidFov, {"left view field of view"},
         [&](F& f) { views(f)[0].fov.angleUp = 1.5707964f; }},
        {"left >= right", SubmitError::InvalidFov, {"left view field of view", "angleLeft < angleRight"},
         [&](F& f) { views(f)[0].fov.angleLeft = views(f)[0].fov.angleRight; }},
        {"near 0", SubmitError::InvalidDepthRange, {"left depth range"}, [&](F& f) { views(f)[0].depth->nearZ = 0.0f; }},
        {"far < near", SubmitError::InvalidDepthRange, {"right depth range"},
         [&](F& f) { views(f)[1].depth->farZ = 0.01f; }},
        {"one motion", SubmitError::InconsistentViews, {"motion"}, [&](F& f) { views(f)[1].motion.reset(); }},
        {"one depth", SubmitError::InconsistentViews, {"depth"}, [&](F& f) { views(f)[0].depth.reset(); }},
        {"other compositor", SubmitError::ForeignSwapchain, {"left colour"},
         [&](F& f) { views(f)[0].color.swapchain = foreign->get(); }},
        {"not a Vulkan swapchain", SubmitError::ForeignSwapchain, {"right colour"},
         [&](F& f) { views(f)[1].color.swapchain = &fakeColor; }},
    };
    uint64_t refused = 0;
    auto refuse = [&](uint64_t next, const std::array<EyeFrame, 2>& eyes) {
        const FrameStats before = c.stats();
        const gpu::FrameParams paramsBefore = c.lastParams();
        for (const Case& k : cases) {
            for (uint64_t index : {next, next + 100}) {  // a refused frame with a later index must not advance it
                if (k.code == SubmitError::FrameOutOfOrder && index != next) continue;
                F f = app.frameEnd(index, eyes);
                k.edit(f);
                Status s = c.endFrame(f);
                ASSERT_FALSE(s.ok()) << k.name;
                EXPECT_EQ(s.error().code, int(k.code))
                    << k.name << ": got " << layers::toString(SubmitError(s.error().code)) << ": " << s.message();
                for (const std::string& part : k.message)
                    EXPECT_TRUE(contains(s.message(), part)) << k.name << ": '" << s.message() << "' lacks '" << part << "'";
                refused++;
            }
        }
        // Still acquired: the application has not released what it is writing.
        ASSERT_TRUE(app.color().acquire().ok());
        Status s = c.endFrame(app.frameEnd(next, eyes));
        EXPECT_EQ(s.error().code, int(SubmitError::ImageNotReleased)) << s.message();
        EXPECT_TRUE(contains(s.message(), "left colour")) << s.message();
        ASSERT_TRUE(app.color().wait().ok());
        s = c.endFrame(app.frameEnd(next, eyes));
        EXPECT_EQ(s.error().code, int(SubmitError::ImageNotReleased)) << s.message();
        ASSERT_TRUE(app.color().release().ok());
        refused += 2;
        EXPECT_EQ(c.stats().frameIndex, before.frameIndex);
        EXPECT_EQ(std::memcmp(&c.lastParams(), &paramsBefore, sizeof(paramsBefore)), 0);
    };
    auto got = runSequence(c, app, refuse, &refusedOut);
    EXPECT_GT(refused, 7u * cases.size());
    for (int f = 0; f < 8; ++f)
        for (uint32_t e = 0; e < 2; ++e) {
            ASSERT_EQ(got[f][e].size(), expected[f][e].size());
            std::size_t differ = 0;
            for (std::size_t i = 0; i < got[f][e].size(); ++i) differ += got[f][e][i] != expected[f][e][i];
            EXPECT_EQ(differ, 0u) << "frame " << f + 1 << " eye " << e << ": reservoirs differ from the run without refusals";
            EXPECT_TRUE(refusedOut[f][e].data == plainOut[f][e].data) << "frame " << f + 1 << " eye " << e;
        }
}

TEST_F(Refusals, InvalidConfigIsRefusedAndChangesNothing) {
    CompositorConfig bad;
    bad.foveaDeg = kNaN;
    auto refused = Compositor::create(context(), bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_EQ(refused.error().code, int(ConfigError::InvalidValue));
    EXPECT_NE(refused.error().message.find("fovea size"), std::string::npos) << refused.error().message;

    auto comp = Compositor::create(context(), CompositorConfig{});
    ASSERT_TRUE(comp.ok());
    for (auto mutate : std::initializer_list<std::function<void(CompositorConfig&)>>{
             [](CompositorConfig& c) { c.foveaDeg = -1.0f; },
             [](CompositorConfig& c) { c.midPeripheryDeg = std::numeric_limits<float>::infinity(); },
             [](CompositorConfig& c) { c.fallbackFoveaDeg = 0.0f; },
             [](CompositorConfig& c) { c.depthTau = kNaN; }}) {
        CompositorConfig c;
        c.method = Method::Fov;  // would reset history if it were taken
        mutate(c);
        Status s = (*comp)->setConfig(c);
        EXPECT_FALSE(s.ok());
        EXPECT_EQ(s.error().code, int(ConfigError::InvalidValue)) << s.message();
    }
    // Nothing pending: the compositor keeps its original configuration.
    EXPECT_EQ((*comp)->config().method, Method::Wrs);
    EXPECT_EQ((*comp)->config().foveaDeg, CompositorConfig{}.foveaDeg);
}

}  // namespace
}  // namespace wrsfov::test
