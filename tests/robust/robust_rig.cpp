#include "robust_rig.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace wrsfov::test {

using layers::Format;
using layers::Usage;

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

layers::SwapchainCreateInfo stereoInfo(Usage usage, Format format, uint32_t w, uint32_t h) {
    layers::SwapchainCreateInfo ci;
    ci.usage = usage;
    ci.format = format;
    ci.width = w;
    ci.height = h;
    ci.arraySize = 2;
    ci.imageCount = 2;
    return ci;
}

std::array<EyeFrame, 2> goodFrame(uint64_t index, const LaneFormats& formats) {
    RandomScene colour(uint32_t(1000 + index)), fixed(7);
    std::array<EyeFrame, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        eyes[e].fov = hmdFov(e);
        eyes[e].color = colour.color(formats.color, kW, kH);
        if (formats.depth) eyes[e].depth = fixed.depth(*formats.depth, kW, kH);
        if (formats.motion) eyes[e].motion = HostImage::make(*formats.motion, kW, kH);
        eyes[e].gaze = {e == 0 ? gazeDir(6.0f, 4.0f) : gazeDir(-3.0f, -5.0f), true, 1.0f};
    }
    return eyes;
}

Snapshot snapshot(Compositor& comp) {
    Snapshot s;
    s.reservoirs = readReservoirs(comp);
    for (uint32_t e = 0; e < 2; ++e) {
        auto out = comp.readOutput(e);
        EXPECT_TRUE(out.ok()) << (out.ok() ? "" : out.error().message);
        if (out.ok()) s.output[e] = std::move(out->data);
    }
    s.stats = comp.stats();
    s.params = comp.lastParams();
    return s;
}

std::string difference(const Snapshot& a, const Snapshot& b) {
    for (int e = 0; e < 2; ++e) {
        const char* eye = e == 0 ? "left " : "right ";
        if (a.reservoirs[e].size() != b.reservoirs[e].size()) return std::string(eye) + "reservoir counts differ";
        for (std::size_t i = 0; i < a.reservoirs[e].size(); ++i)
            if (a.reservoirs[e][i] != b.reservoirs[e][i])
                return std::string(eye) + "reservoir " + std::to_string(i) + " (" + std::to_string(i % kW) + "," +
                       std::to_string(i / kW) + ") differs";
        if (a.output[e] != b.output[e]) return std::string(eye) + "output differs";
    }
    const FrameStats &x = a.stats, &y = b.stats;
    if (x.frameIndex != y.frameIndex) return "stats frame index differs";
    if (x.gazeFallback[0] != y.gazeFallback[0] || x.gazeFallback[1] != y.gazeFallback[1])
        return "gaze fallback differs";
    if (x.usedDepth != y.usedDepth || x.usedMotion != y.usedMotion || x.historyReset != y.historyReset)
        return "stats flags differ";
    if (std::memcmp(&a.params, &b.params, sizeof(a.params)) != 0) return "frame parameters differ";
    return {};
}

void expectSane(Compositor& comp, const std::string& what) {
    Reservoirs r = readReservoirs(comp);
    for (uint32_t e = 0; e < 2; ++e) {
        ASSERT_EQ(r[e].size(), std::size_t(comp.width()) * comp.height()) << what;
        const std::string eye = what + (e == 0 ? " (left)" : " (right)");
        if (comp.config().method == Method::WrsPaper) {
            expectReservoirsSane(r[e], eye);
        } else if (comp.config().method == Method::FovTaa) {
            // The TAA history in the same buffers: linear RGB as three fp32 and a 1.
            uint64_t bad = 0;
            for (const glm::uvec4& p : r[e]) {
                float c[3];
                std::memcpy(c, &p, sizeof(c));
                bad += !(std::isfinite(c[0]) && std::isfinite(c[1]) && std::isfinite(c[2]) && c[0] >= 0.0f &&
                         c[1] >= 0.0f && c[2] >= 0.0f && p.w == 1u);
            }
            EXPECT_EQ(bad, 0u) << eye << ": TAA history not finite";
        }
        auto out = comp.readOutput(e);
        ASSERT_TRUE(out.ok()) << what;
        EXPECT_EQ(out->data.size(), std::size_t(comp.width()) * comp.height() * 4) << what;
    }
}

Lane::Lane(vk::Context& ctx, const CompositorConfig& config, const LaneFormats& f) : formats(f) {
    auto c = Compositor::create(ctx, config);
    if (!c) {
        std::fprintf(stderr, "robust rig: cannot create a compositor: %s\n", c.error().message.c_str());
        std::abort();
    }
    comp = std::move(*c);
    app = std::make_unique<StereoApp>(*comp, kW, kH, f.color, f.depth, f.motion);
}

TwinChain::TwinChain(const CompositorConfig& config, const LaneFormats& formats)
    : main(context(), config, formats), twin(context(), config, formats) {}

void TwinChain::stepBoth(const std::string& what, const std::array<EyeFrame, 2>* eyes) {
    const std::array<EyeFrame, 2> e = eyes ? *eyes : goodFrame(next_, main.formats);
    stepPair(what, e, e);
}

void TwinChain::stepPair(const std::string& what, const std::array<EyeFrame, 2>& mainEyes,
                         const std::array<EyeFrame, 2>& twinEyes) {
    Status a = main.app->submit(next_, mainEyes);
    Status b = twin.app->submit(next_, twinEyes);
    ASSERT_TRUE(a.ok()) << what << ": main refused frame " << next_ << ": " << a.message();
    ASSERT_TRUE(b.ok()) << what << ": twin refused frame " << next_ << ": " << b.message();
    ++next_;
    const std::string d = difference(snapshot(*main.comp), snapshot(*twin.comp));
    EXPECT_TRUE(d.empty()) << what << ": main and twin differ after frame " << next_ - 1 << ": " << d;
}

void TwinChain::stepEdited(const std::string& what, const std::function<void(Lane&, layers::FrameEndInfo&)>& edit) {
    const std::array<EyeFrame, 2> eyes = goodFrame(next_, main.formats);
    for (Lane* lane : {&main, &twin}) {
        lane->app->write(eyes);
        layers::FrameEndInfo f = lane->app->frameEnd(next_, eyes);
        edit(*lane, f);
        Status s = lane->comp->endFrame(f);
        ASSERT_TRUE(s.ok()) << what << ": " << (lane == &main ? "main" : "twin") << " refused frame " << next_ << ": "
                            << s.message();
    }
    ++next_;
    const std::string d = difference(snapshot(*main.comp), snapshot(*twin.comp));
    EXPECT_TRUE(d.empty()) << what << ": main and twin differ after frame " << next_ - 1 << ": " << d;
}

layers::Swapchain& TwinChain::foreignColor() {
    if (!foreign_) {
        auto c = Compositor::create(context(), main.comp->config());
        EXPECT_TRUE(c.ok());
        other_ = std::move(*c);
        auto sc = other_->createSwapchain(stereoInfo(Usage::Color, main.formats.color));
        EXPECT_TRUE(sc.ok());
        foreign_ = std::move(*sc);
        EXPECT_TRUE(foreign_->acquire().ok() && foreign_->wait().ok() && foreign_->release().ok());
    }
    return *foreign_;
}

layers::Swapchain& TwinChain::neverReleased(Usage u, Format f) {
    std::unique_ptr<layers::Swapchain>& sc = never_[int(u) * 16 + int(f)];
    if (!sc) {
        auto r = main.comp->createSwapchain(stereoInfo(u, f));
        EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
        sc = std::move(*r);
    }
    return *sc;
}

FakeSwapchain::FakeSwapchain(Usage usage, Format format, uint32_t width, uint32_t height, uint32_t arraySize)
    : Swapchain([&] {
          layers::SwapchainCreateInfo ci = stereoInfo(usage, format, width, height);
          ci.arraySize = arraySize;
          return ci;
      }()) {
    EXPECT_TRUE(acquire().ok() && wait().ok() && release().ok());
}

}  // namespace wrsfov::test
