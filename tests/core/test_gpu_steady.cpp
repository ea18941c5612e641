// The steady floor (docs/retention.md "The steady floor"): level 4, the far periphery's candidate, is
// filtered over time at its own resolution. Under a slow pan the far periphery then changes less
// from frame to frame than with each frame's 16x16 box averages, without losing accuracy there; a
// light change is not smeared over frames (the history is clipped to the new neighbourhood); the
// GPU matches the CPU reference while it filters, and non-finite motion or colour leaves every
// filtered texel finite.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

class SteadyFloor : public GpuTest {};

constexpr uint32_t W = 160, H = 120;
constexpr double kGazeX = 24, kGazeY = 24;

layers::Fov wideFov() { return layers::Fov{std::atan(-0.8f), std::atan(0.8f), std::atan(0.6f), std::atan(-0.6f)}; }

// Pixels far from the gaze (about 30 degrees and more at this field of view): the floor level only.
bool far(uint32_t x, uint32_t y) { return std::hypot(double(x) + 0.5 - kGazeX, double(y) + 0.5 - kGazeY) > 70.0; }

// Texture with energy at 12-20 px wavelengths, above level 4's Nyquist frequency (32 px) but not
// removed by its 16x16 boxes: it aliases into level 4 and crawls there as it moves, sampled at the shifted pixel
// centres, scaled in brightness.
HostImage crawlTexture(float sx, float brightness) {
    HostImage img = HostImage::make(layers::Format::RGBA16F, W, H);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const float u = float(x) + 0.5f - sx, v = float(y) + 0.5f;
            const float c = 0.5f + 0.2f * std::sin(u * 0.31f + 1.0f) + 0.15f * std::sin(u * 0.26f + v * 0.2f) +
                            0.1f * std::sin(u * 0.48f - v * 0.33f);
            img.store(x, y, glm::vec4(c * brightness, (1.0f - c) * 0.8f * brightness, 0.3f * brightness, 1.0f));
        }
    return img;
}

std::array<EyeFrame, 2> panFrame(float shift, float speed, float brightness) {
    std::array<EyeFrame, 2> eyes;
    for (int e = 0; e < 2; ++e) {
        eyes[e].fov = wideFov();
        eyes[e].color = crawlTexture(shift, brightness);
        eyes[e].motion = uniformMotion(W, H, -speed, 0.0f);
        eyes[e].gaze = {gazeAtPixel(kGazeX, kGazeY, W, H, wideFov()) + glm::vec3(0.0f, 0.001f * float(e), 0.0f), true,
                        1.0f};
    }
    return eyes;
}

struct Lane {
    std::unique_ptr<Compositor> comp;
    std::unique_ptr<StereoApp> app;
};

CompositorConfig wrsConfig(bool steady) {
    CompositorConfig cfg;
    cfg.method = Method::Wrs;
    cfg.foveation = FoveationMode::Mip;
    cfg.foveaDeg = 5.0f;
    cfg.steadyFloor = steady;
    return cfg;
}

Lane makeLane(bool steady) {
    auto c = Compositor::create(context(), wrsConfig(steady));
    EXPECT_TRUE(c.ok());
    Lane l;
    l.comp = std::move(*c);
    l.app = std::make_unique<StereoApp>(*l.comp, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
    return l;
}

// Mean absolute difference over the far pixels of eye 0, in 8-bit codes: between two outputs, or
// (truth given) between an output and the truth encoded as the output is.
double farDiff(const HostImage& a, const HostImage& b) {
    double sum = 0;
    uint64_t n = 0;
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            if (!far(x, y)) continue;
            for (int k = 0; k < 3; ++k)
                sum += std::abs(int(uint8_t(a.data[(y * W + x) * 4 + k])) - int(uint8_t(b.data[(y * W + x) * 4 + k])));
            n += 3;
        }
    return sum / double(n);
}

HostImage encoded(const HostImage& linear) {
    HostImage out = HostImage::make(layers::Format::RGBA8, W, H);
    for (uint32_t y = 0; y < H; ++y)
        for (uint32_t x = 0; x < W; ++x) {
            const glm::u8vec4 o = encodeOutput(glm::vec3(linear.fetch(x, y)));
            std::memcpy(out.data.data() + (std::size_t(y) * W + x) * 4, &o, 4);
        }
    return out;
}

TEST_F(SteadyFloor, SteadiesTheFarPeripheryUnderASlowPan) {
    Lane on = makeLane(true), off = makeLane(false);
    const float speed = 0.37f;
    double changeOn = 0, changeOff = 0, errorOn = 0, errorOff = 0;
    int counted = 0;
    HostImage lastOn, lastOff;
    for (uint64_t f = 1; f <= 40; ++f) {
        const auto eyes = panFrame(speed * float(f), speed, 1.0f);
        ASSERT_TRUE(on.app->submit(f, eyes).ok());
        ASSERT_TRUE(off.app->submit(f, eyes).ok());
        EXPECT_TRUE(on.comp->stats().steadyFloor);
        EXPECT_FALSE(off.comp->stats().steadyFloor);
        auto oOn = on.comp->readOutput(0), oOff = off.comp->readOutput(0);
        ASSERT_TRUE(oOn.ok() && oOff.ok());
        if (f > 10) {
            const HostImage truth = encoded(eyes[0].color);
            changeOn += farDiff(*oOn, lastOn);
            changeOff += farDiff(*oOff, lastOff);
            errorOn += farDiff(*oOn, truth);
            errorOff += farDiff(*oOff, truth);
            ++counted;
        }
        lastOn = std::move(*oOn);
        lastOff = std::move(*oOff);
    }
    changeOn /= counted, changeOff /= counted, errorOn /= counted, errorOff /= counted;
    std::printf(
        "far periphery, slow pan: change per frame %.4f codes steady, %.4f unfiltered; error %.3f / %.3f codes\n",
        changeOn, changeOff, errorOn, errorOff);
    EXPECT_GT(changeOff, 0.05) << "the pan must make the unfiltered floor crawl for this test to mean anything";
    // Measured 0.84x: a filter over time takes out the frame-to-frame flicker of the aliased detail,
    // not the smooth part of its crawl.
    EXPECT_LT(changeOn, 0.9 * changeOff) << "the steady floor must change less from frame to frame";
    EXPECT_LT(errorOn, errorOff * 1.02) << "and must not lose accuracy against the full-rate image there";
}

TEST_F(SteadyFloor, ALightChangeIsNotSmearedOverFrames) {
    Lane on = makeLane(true), off = makeLane(false);
    for (uint64_t f = 1; f <= 14; ++f) {
        const auto eyes = panFrame(0.0f, 0.0f, f <= 10 ? 1.0f : 0.6f);
        ASSERT_TRUE(on.app->submit(f, eyes).ok());
        ASSERT_TRUE(off.app->submit(f, eyes).ok());
        if (f < 11) continue;
        auto oOn = on.comp->readOutput(0), oOff = off.comp->readOutput(0);
        ASSERT_TRUE(oOn.ok() && oOff.ok());
        // The first frame after the change: the clip to the new neighbourhood's variance box leaves at
        // most the box's spread of the old light, a fraction of the 40 % step (about 50 codes here).
        const double d = farDiff(*oOn, *oOff);
        std::printf("frame %llu after the light change: steady and unfiltered differ by %.3f codes\n",
                    (unsigned long long)(f - 10), d);
        EXPECT_LT(d, f == 11 ? 2.0 : 1.0) << "frame " << f;
    }
}

TEST_F(SteadyFloor, GpuMatchesTheReferenceWhileFiltering) {
    const CompositorConfig cfg = wrsConfig(true);
    auto c = Compositor::create(context(), cfg);
    ASSERT_TRUE(c.ok());
    StereoApp app(**c, W, H, layers::Format::RGBA16F, std::nullopt, layers::Format::RG16F);
    Reference ref(cfg);
    int maxOutputDiff = 0;
    for (uint64_t f = 1; f <= 12; ++f) {
        // A pan, a light change, then a pan the other way; on frame 10, non-finite motion at the
        // pixels two level-4 texels take their motion from, and a non-finite colour.
        const float speed = f <= 8 ? 0.37f : -0.6f;
        const float shift = 0.37f * float(std::min<uint64_t>(f, 8)) - 0.6f * float(f > 8 ? f - 8 : 0);
        auto eyes = panFrame(shift, speed, f == 6 ? 0.7f : 1.0f);
        if (f == 10) {
            const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
            for (EyeFrame& e : eyes) {
                e.motion->store(24, 8, glm::vec4(nan, nan, 0.0f, 0.0f));
                e.motion->store(40, 24, glm::vec4(inf, -inf, 0.0f, 0.0f));
                e.color.store(100, 60, glm::vec4(nan, inf, -inf, 1.0f));
            }
        }
        // The reference steps from the GPU's history: reservoirs, held qualities and steady floor.
        if (f > 1)
            for (uint32_t e = 0; e < 2; ++e) {
                ref.setHistory(e, *(*c)->readReservoirs(e), *(*c)->readTileHeld(e));
                ref.setSteadyFloor(e, *(*c)->readSteadyFloor(e));
            }
        ASSERT_TRUE(app.submit(f, eyes).ok());
        ref.step((*c)->lastParams(), referenceInputs(eyes));
        ASSERT_TRUE((*c)->stats().steadyFloor);
        for (uint32_t e = 0; e < 2; ++e) {
            auto gpu = (*c)->readSteadyFloor(e);
            ASSERT_TRUE(gpu.ok());
            const std::vector<glm::vec4>& cpu = ref.steadyFloor(e);
            ASSERT_EQ(gpu->size(), cpu.size());
            ASSERT_FALSE(cpu.empty());
            for (const glm::vec4& t : *gpu)
                ASSERT_TRUE(std::isfinite(t.x) && std::isfinite(t.y) && std::isfinite(t.z) && std::isfinite(t.w))
                    << "frame " << f;
            int differ = 0;
            for (std::size_t i = 0; i < cpu.size(); ++i) {
                const glm::vec4 d = glm::abs((*gpu)[i] - cpu[i]);
                // fp16 storage: at most one step apart (2^-11 relative) where the float math rounds differently.
                if (glm::any(glm::greaterThan(d, glm::abs(cpu[i]) * (1.0f / 1024.0f) + 1e-6f))) ++differ;
            }
            EXPECT_EQ(differ, 0) << "frame " << f << " eye " << e
                                 << ": steady floor texels differing from the reference";
            auto out = (*c)->readOutput(e);
            ASSERT_TRUE(out.ok());
            for (std::size_t i = 0; i < out->data.size(); ++i)
                maxOutputDiff =
                    std::max(maxOutputDiff, std::abs(int(uint8_t(out->data[i])) - int(uint8_t(ref.output(e).data[i]))));
        }
    }
    EXPECT_LE(maxOutputDiff, 1);
}

TEST_F(SteadyFloor, SparseRetentionAndMonoViewsKeepTheirGuarantees) {
    // Sparse and dense retention read the same filtered level 4: the same output bit for bit. With one
    // view as both eyes the passes run for the left eye, and the right eye's steady floor, which its
    // next stereo frame reads, is copied from the left's.
    const CompositorConfig cfg = wrsConfig(true);
    CompositorConfig dense = cfg;
    dense.sparseRetention = false;
    auto a = Compositor::create(context(), cfg);
    auto b = Compositor::create(context(), dense);
    ASSERT_TRUE(a.ok() && b.ok());
    HostStereoApp::Options o;
    o.width = W;
    o.height = H;
    o.color = layers::Format::RGBA16F;
    o.motion = layers::Format::RG16F;
    o.monoView = true;
    auto appA = HostStereoApp::create(**a, o);
    auto appB = HostStereoApp::create(**b, o);
    ASSERT_TRUE(appA.ok() && appB.ok());
    for (uint64_t f = 1; f <= 14; ++f) {
        std::array<EyeSubmission, 2> eyes = panFrame(0.37f * float(f), 0.37f, 1.0f);
        eyes[1] = eyes[0];
        ASSERT_TRUE((*appA)->submit(f, f / 90.0, eyes).ok());
        ASSERT_TRUE((*appB)->submit(f, f / 90.0, eyes).ok());
        ASSERT_TRUE((*a)->stats().monoViews && (*a)->stats().sparse && (*a)->stats().steadyFloor);
        const std::string what = "frame " + std::to_string(f);
        expectSameOutputs(**a, **b, what);
        auto left = (*a)->readSteadyFloor(0), right = (*a)->readSteadyFloor(1);
        ASSERT_TRUE(left.ok() && right.ok());
        ASSERT_FALSE(left->empty());
        EXPECT_TRUE(*left == *right) << what << ": the right eye's steady floor is the left eye's";
        if (HasFailure()) return;
    }
}

}  // namespace
}  // namespace wrsfov::test
