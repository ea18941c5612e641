// NaN, ±Inf, negative and huge values in colour, depth, motion and gaze never reach a reservoir or an
// output: after each poisoned frame every reservoir unpacks finite with w_sum > 0, the GPU agrees
// with the CPU reference started from the GPU's own history, and pixels keep their history through
// the poisoned frame and the valid frame after it.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

#include "gpu_checks.h"

namespace wrsfov::test {
namespace {

using layers::Format;

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

class NonFinite : public GpuTest {
protected:
    static constexpr uint32_t W = 64, H = 48;
    // The poisoned patch; kind = (x + y) % 8 picks what a pixel gets.
    static bool inPatch(uint32_t x, uint32_t y) { return x >= 8 && x < 40 && y >= 8 && y < 20; }
    static uint32_t kind(uint32_t x, uint32_t y) { return (x + y) % 8u; }

    // Colour kinds 0-3 are not finite (the candidate is invalid), 4-7 are finite but out of range.
    static void poisonColor(HostImage& img) {
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x) {
                if (!inPatch(x, y)) continue;
                uint16_t bits[4];
                std::memcpy(bits, img.data.data() + (std::size_t(y) * W + x) * 8, 8);
                switch (kind(x, y)) {
                case 0: bits[0] = bits[1] = bits[2] = 0x7e00; break;  // NaN
                case 1: bits[0] = 0x7c00; break;                      // +Inf in R
                case 2: bits[1] = 0xfc00; break;                      // -Inf in G
                case 3: bits[2] = 0x7d01; break;                      // signalling NaN in B
                case 4: bits[0] = bits[1] = bits[2] = 0xc200; break;  // -3
                case 5: bits[0] = bits[1] = bits[2] = 0x7bff; break;  // 65504, the fp16 maximum
                case 6: bits[0] = 0x7b53; break;                      // 60000 in R
                case 7: bits[3] = 0x7e00; break;                      // NaN alpha only (unused)
                }
                std::memcpy(img.data.data() + (std::size_t(y) * W + x) * 8, bits, 8);
            }
    }
    static bool colorInvalid(uint32_t x, uint32_t y) { return inPatch(x, y) && kind(x, y) < 4; }

    static void poisonDepth(HostImage& img) {
        const float values[8] = {kNaN, kInf, -kInf, -0.5f, 1.5f, 1e30f, -1e-30f, std::nextafter(1.0f, 2.0f)};
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x)
                if (inPatch(x, y)) img.store(x, y, glm::vec4(values[kind(x, y)]));
    }

    // Motion kinds 3 and 4 are huge (off-screen: no history); the others are not finite and read as
    // no motion (xy) or no depth change (dz).
    static void poisonMotion(HostImage& img) {
        const glm::vec4 values[8] = {{kNaN, 0, 0, 0},       {0, kInf, 0, 0},        {-kInf, kNaN, 0, 0},
                                     {65504.0f, 0, 0, 0},   {0, -65504.0f, 0, 0},   {0, 0, kNaN, 0},
                                     {0, 0, kInf, 0},       {kNaN, kNaN, -kInf, kNaN}};
        for (uint32_t y = 0; y < H; ++y)
            for (uint32_t x = 0; x < W; ++x)
                if (inPatch(x, y)) img.store(x, y, values[kind(x, y)]);
    }
    static bool motionOffScreen(uint32_t x, uint32_t y) { return inPatch(x, y) && (kind(x, y) == 3 || kind(x, y) == 4); }
};

TEST_F(NonFinite, PoisonedInputsNeverReachReservoirsOrOutputs) {
    CompositorConfig cfg;
    cfg.method = Method::WrsPaper;  // the published rule's reservoir layout (wrs: test_gpu_retain.cpp)
    cfg.foveaDeg = 10.0f;
    cfg.seed = 11;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    Compositor& c = **comp;
    StereoApp app(c, W, H, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    Reference ref(cfg);
    RandomScene rs(77);
    std::array<HostImage, 2> baseColor, baseDepth;
    std::array<glm::vec3, 2> gaze;
    for (int e = 0; e < 2; ++e) {
        baseDepth[e] = rs.depth(Format::R32F, W, H);
        gaze[e] = rs.gaze(hmdFov(e));
    }
    std::mt19937 noise(5);
    std::uniform_real_distribution<float> jitter(-0.03f, 0.03f);

    enum Poison : unsigned { kNone = 0, kColor = 1, kDepth = 2, kMotion = 4, kGaze = 8 };
    struct Step {
        unsigned poison;
        layers::EyeGaze gaze[2];  // used when kGaze is set
        const char* name;
    };
    const layers::EyeGaze nanGaze{{kNaN, 0, -1}, true, 1}, zeroGaze{{0, 0, 0}, true, 1},
        notValid{{0.1f, 0, -1}, false, 0}, overflow{{1e30f, 1e30f, -1e30f}, true, 1},
        tiny{{1e-20f, 0, -1e-20f}, true, 1}, infGaze{{kInf, 0, -1}, true, 1};
    const std::vector<Step> steps = {
        {kNone, {}, "valid 1"},
        {kNone, {}, "valid 2"},
        {kColor, {}, "colour NaN/Inf/negative/huge"},
        {kNone, {}, "valid after colour"},
        {kDepth, {}, "depth NaN/Inf/out of range"},
        {kNone, {}, "valid after depth"},
        {kMotion, {}, "motion NaN/Inf/huge"},
        {kNone, {}, "valid after motion"},
        {kGaze, {nanGaze, zeroGaze}, "gaze NaN / zero length"},
        {kGaze, {notValid, overflow}, "gaze not valid / overflowing length"},
        {kGaze, {tiny, infGaze}, "gaze tiny / infinite"},
        {kNone, {}, "valid after gaze"},
        {kColor | kDepth | kMotion | kGaze, {nanGaze, notValid}, "everything at once"},
        {kNone, {}, "valid after everything"},
    };
    StepTally tally;
    Reservoirs before;  // reservoirs after the previous frame
    for (std::size_t f = 0; f < steps.size(); ++f) {
        const Step& st = steps[f];
        if (f % 4 == 0)
            for (int e = 0; e < 2; ++e) baseColor[e] = rs.color(Format::RGBA16F, W, H);
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            eyes[e].color = baseColor[e];
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x)
                    eyes[e].color.store(x, y, eyes[e].color.fetch(x, y) +
                                                  glm::vec4(jitter(noise), jitter(noise), jitter(noise), 0.0f));
            eyes[e].depth = baseDepth[e];
            eyes[e].motion = HostImage::make(Format::RGBA16F, W, H);
            eyes[e].gaze = (st.poison & kGaze) ? st.gaze[e] : layers::EyeGaze{gaze[e], true, 1.0f};
            if (st.poison & kColor) poisonColor(eyes[e].color);
            if (st.poison & kDepth) poisonDepth(*eyes[e].depth);
            if (st.poison & kMotion) poisonMotion(*eyes[e].motion);
        }
        Reservoirs prev = stepBoth(c, app, ref, f + 1, eyes, tally, st.name);
        ASSERT_FALSE(HasFailure()) << "stopped at: " << st.name;
        for (uint32_t e = 0; e < 2; ++e) {
            EXPECT_EQ(c.stats().gazeFallback[e], (st.poison & kGaze) != 0) << st.name << " eye " << e;
        }
        Reservoirs now = readReservoirs(c);
        for (uint32_t e = 0; e < 2; ++e) {
            expectReservoirsSane(now[e], std::string(st.name) + (e ? " right" : " left"));
            if (f == 0) continue;
            auto out = c.readOutput(e);
            ASSERT_TRUE(out.ok());
            // M continues everywhere (motion zero, depth constant) except where huge motion points
            // off-screen; invalid colour keeps the history sample exactly and outputs it.
            uint64_t wrongM = 0, lost = 0;
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const std::size_t i = std::size_t(y) * W + x;
                    const gpu::Reservoir r = gpu::wrs_unpack(now[e][i]), h = gpu::wrs_unpack(prev[e][i]);
                    const bool off = (st.poison & kMotion) && motionOffScreen(x, y);
                    wrongM += r.M != (off ? 1u : std::min(h.M + 1u, WRS_M_MAX));
                    if ((st.poison & kColor) && colorInvalid(x, y)) {
                        if (off) continue;
                        lost += now[e][i].x != prev[e][i].x || now[e][i].y != prev[e][i].y;
                        const glm::u8vec4 o = encodeOutput(h.color);
                        for (int ch = 0; ch < 3; ++ch)
                            lost += std::abs(int(uint8_t(out->data[i * 4 + ch])) - int(o[ch])) > 1;
                    }
                }
            EXPECT_EQ(wrongM, 0u) << st.name << " eye " << e << ": M did not continue";
            EXPECT_EQ(lost, 0u) << st.name << " eye " << e << ": an invalid colour replaced the history sample";
        }
        before = std::move(now);
    }
    std::printf("  %zu frames: %llu decisions with history, %llu selection mismatches (%llu within 1e-6 of the "
                "threshold), max output difference %d/255\n",
                steps.size(), (unsigned long long)tally.decisions, (unsigned long long)tally.mismatches,
                (unsigned long long)tally.nearThreshold, tally.maxOutputDiff);
    EXPECT_EQ(tally.mismatches, tally.nearThreshold);
    EXPECT_LE(tally.maxOutputDiff, 1);
    // By the end every pixel has a long history again: nothing was lost for good.
    for (uint32_t e = 0; e < 2; ++e) {
        uint64_t young = 0;
        for (const auto& p : before[e]) young += gpu::wrs_unpack(p).M < 2u;
        EXPECT_EQ(young, 0u);
    }
}

TEST_F(NonFinite, PoisonedFirstFrameStillInitialisesSanely) {
    // No history to fall back on: invalid candidates start reservoirs with the floor weight, and the
    // next valid frame replaces them.
    CompositorConfig cfg;
    cfg.method = Method::WrsPaper;  // the published rule's reservoir layout (wrs: test_gpu_retain.cpp)
    cfg.foveaDeg = 10.0f;
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok());
    Compositor& c = **comp;
    StereoApp app(c, W, H, Format::RGBA16F, Format::R32F, Format::RGBA16F);
    Reference ref(cfg);
    RandomScene rs(3);
    StepTally tally;
    for (int f = 0; f < 2; ++f) {
        std::array<EyeFrame, 2> eyes;
        for (int e = 0; e < 2; ++e) {
            eyes[e].fov = hmdFov(e);
            eyes[e].color = rs.color(Format::RGBA16F, W, H);
            eyes[e].depth = rs.depth(Format::R32F, W, H);
            eyes[e].motion = HostImage::make(Format::RGBA16F, W, H);
            eyes[e].gaze = f == 0 ? layers::EyeGaze{{kNaN, kNaN, kNaN}, true, 1} : layers::EyeGaze{rs.gaze(eyes[e].fov), true, 1};
            if (f == 0) {
                poisonColor(eyes[e].color);
                poisonDepth(*eyes[e].depth);
                poisonMotion(*eyes[e].motion);
            }
        }
        stepBoth(c, app, ref, f + 1, eyes, tally, f == 0 ? "poisoned first frame" : "valid second frame");
        Reservoirs now = readReservoirs(c);
        for (uint32_t e = 0; e < 2; ++e) {
            expectReservoirsSane(now[e], "first frames");
            for (uint32_t y = 0; y < H; ++y)
                for (uint32_t x = 0; x < W; ++x) {
                    const gpu::Reservoir r = gpu::wrs_unpack(now[e][std::size_t(y) * W + x]);
                    if (f == 0) {
                        EXPECT_EQ(r.M, 1u);
                        if (colorInvalid(x, y)) {
                            EXPECT_EQ(r.w, 0.0f);
                        }
                    } else if (colorInvalid(x, y) && !motionOffScreen(x, y)) {
                        // The valid candidate replaced the invalid start (it weighs more than 1e-30).
                        EXPECT_GT(r.w, 0.0f) << x << "," << y;
                    }
                }
        }
    }
    EXPECT_EQ(tally.mismatches, tally.nearThreshold);
}

}  // namespace
}  // namespace wrsfov::test
