// docs/bad-input.md, "Compositor configuration": every out-of-range value of CompositorConfig is
// refused by Compositor::create and by setConfig with ConfigError::InvalidValue and a message naming
// the field; a refused setConfig leaves the compositor bit-identical to a twin that never got it.
// Extreme values that are in range are taken and give finite reservoirs.
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "robust_rig.h"

namespace wrsfov::test {
namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();

struct ConfigRow {
    std::string name;
    std::function<void(CompositorConfig&)> set;
    std::string message;
};
void PrintTo(const ConfigRow& r, std::ostream* os) { *os << r.name; }

std::vector<ConfigRow> refusedRows() {
    std::vector<ConfigRow> r;
    struct Field {
        const char* name;
        float CompositorConfig::*member;
        const char* message;
        float tooLarge;
    };
    const Field fields[] = {
        {"fovea", &CompositorConfig::foveaDeg, "fovea size must be in (0°, 180°]", 180.5f},
        {"mid_periphery", &CompositorConfig::midPeripheryDeg, "mid-periphery size must be in (0°, 180°]", 181.0f},
        {"fallback_fovea", &CompositorConfig::fallbackFoveaDeg, "fallback fovea size must be in (0°, 180°]", 360.0f},
        {"depth_tau", &CompositorConfig::depthTau, "depth tolerance must be positive and finite", 1.5e6f},
    };
    const std::pair<const char*, float> kinds[] = {{"nan", kNaN},  {"pos_inf", kInf},   {"neg_inf", -kInf},
                                                   {"zero", 0.0f}, {"negative", -1.0f}, {"neg_zero", -0.0f},
                                                   {"huge", 3e38f}};
    for (const Field& f : fields) {
        for (auto [kind, v] : kinds)
            r.push_back({std::string(f.name) + "_" + kind, [m = f.member, v = v](CompositorConfig& c) { c.*m = v; },
                         f.message});
        r.push_back({std::string(f.name) + "_just_too_large",
                     [m = f.member, v = f.tooLarge](CompositorConfig& c) { c.*m = v; }, f.message});
    }
    // The first value past each enum's last, and 255.
    // Method taau-simple's parameters (CompositorConfig::TaauSimple): non-finite, zero, negative and too large.
    struct SimpleField {
        const char* name;
        float CompositorConfig::TaauSimple::*member;
        const char* message;
        float tooLarge;
    };
    const SimpleField simpleFields[] = {
        {"taau_simple_radius", &CompositorConfig::TaauSimple::radius, "taau-simple radius must be in (0, 8] output pixels", 8.5f},
        {"taau_simple_weight", &CompositorConfig::TaauSimple::maxWeight, "taau-simple weight cap must be in (0, 1024]", 2048.0f},
        {"taau_simple_clip", &CompositorConfig::TaauSimple::clipGamma, "taau-simple clip box must be in (0, 64] sigmas", 65.0f},
    };
    for (const SimpleField& f : simpleFields)
        for (float v : {kNaN, kInf, 0.0f, -1.0f, f.tooLarge})
            r.push_back({std::string(f.name) + "_" + std::to_string(int(r.size())),
                         [m = f.member, v](CompositorConfig& c) { c.taauSimple.*m = v; }, f.message});
    // Method taau's (CompositorConfig::Taau): non-finite, negative and too large; zero where it means nothing
    // (the lock's lifetime and the luma stability may be 0: off).
    struct TaauField {
        const char* name;
        float CompositorConfig::Taau::*member;
        const char* message;
        float tooLarge;
        bool zeroAllowed;
    };
    const TaauField taauFields[] = {
        {"taau_kernel", &CompositorConfig::Taau::kernel, "taau kernel scale must be in (0, 4] wide pixels", 4.5f, false},
        {"taau_weight", &CompositorConfig::Taau::maxWeight, "taau weight cap must be in (0, 1024]", 2048.0f, false},
        {"taau_box", &CompositorConfig::Taau::boxSigma, "taau clamp box must be in (0, 64] sigmas", 65.0f, false},
        {"taau_velocity", &CompositorConfig::Taau::fullVelocity, "taau box velocity must be in (0, 1e4]", 2e4f, false},
        {"taau_lock_frames", &CompositorConfig::Taau::lockFrames, "taau lock lifetime must be in [0, 64] frames", 65.0f, true},
        {"taau_lock_threshold", &CompositorConfig::Taau::lockThreshold, "taau lock threshold must be in (0, 16]", 17.0f, false},
        {"taau_stability", &CompositorConfig::Taau::stability, "taau luma stability must be in [0, 1024]", 1025.0f, true},
    };
    for (const TaauField& f : taauFields)
        for (float v : {kNaN, kInf, 0.0f, -1.0f, f.tooLarge}) {
            if (v == 0.0f && f.zeroAllowed) continue;
            r.push_back({std::string(f.name) + "_" + std::to_string(int(r.size())),
                         [m = f.member, v](CompositorConfig& c) { c.taau.*m = v; }, f.message});
        }
    // The steady display's weight: [0, 1] (0 turns it off).
    for (float v : {kNaN, kInf, -0.5f, 1.5f})
        r.push_back({"steady_display_" + std::to_string(int(r.size())), [v](CompositorConfig& c) { c.steadyDisplay = v; },
                     "steady display weight must be in [0, 1]"});
    // The steady display's full speed: [0, 1024] output pixels a frame (0: one weight at every speed).
    for (float v : {kNaN, kInf, -1.0f, 2048.0f})
        r.push_back({"steady_display_speed_" + std::to_string(int(r.size())),
                     [v](CompositorConfig& c) { c.steadyDisplaySpeed = v; }, "steady display full speed must be in [0, 1024]"});
    // The landed footprint: [0, 1] wide pixels (0: one output pixel).
    for (float v : {kNaN, kInf, -0.1f, 1.5f})
        r.push_back({"landed_footprint_" + std::to_string(int(r.size())),
                     [v](CompositorConfig& c) { c.landedFootprint = v; }, "landed footprint must be in [0, 1]"});
    for (uint8_t v : {uint8_t(uint8_t(Method::TaauSimple) + 1), uint8_t(255)})
        r.push_back({"method_" + std::to_string(v), [v](CompositorConfig& c) { c.method = Method(v); }, "method must be"});
    for (uint8_t v : {uint8_t(5), uint8_t(255)}) {
        const std::string n = std::to_string(v);
        r.push_back(
            {"foveation_" + n, [v](CompositorConfig& c) { c.foveation = FoveationMode(v); }, "foveation mode must be"});
        r.push_back(
            {"change_metric_" + n, [v](CompositorConfig& c) { c.change = ChangeMetric(v); }, "change metric must be"});
        r.push_back({"equal_quality_" + n, [v](CompositorConfig& c) { c.equalQuality = EqualQuality(v); },
                     "equal-quality rule must be"});
    }
    return r;
}

bool sameConfig(const CompositorConfig& a, const CompositorConfig& b) {
    auto bits = [](float f) {
        uint32_t u;
        std::memcpy(&u, &f, 4);
        return u;
    };
    return a.method == b.method && a.foveation == b.foveation && bits(a.foveaDeg) == bits(b.foveaDeg) &&
           bits(a.midPeripheryDeg) == bits(b.midPeripheryDeg) && bits(a.fallbackFoveaDeg) == bits(b.fallbackFoveaDeg) &&
           a.change == b.change && a.bernoulli == b.bernoulli && bits(a.depthTau) == bits(b.depthTau) &&
           a.seed == b.seed && a.measureCopy == b.measureCopy && a.equalQuality == b.equalQuality &&
           a.trackBirth == b.trackBirth;
}

TwinChain& chain() {
    static TwinChain c(CompositorConfig{.method = Method::WrsPaper, .foveaDeg = 10.0f, .seed = 23}, LaneFormats{});
    return c;
}

class Refused : public GpuTest, public ::testing::WithParamInterface<ConfigRow> {};

TEST_P(Refused, Row) {
    const ConfigRow& row = GetParam();
    CompositorConfig bad = chain().main.comp->config();
    bad.method = Method::Fov;  // would reset history if it were taken
    row.set(bad);
    auto created = Compositor::create(context(), bad);
    ASSERT_FALSE(created.ok()) << row.name << " was taken by Compositor::create";
    EXPECT_EQ(created.error().code, int(ConfigError::InvalidValue));
    EXPECT_TRUE(contains(created.error().message, row.message)) << created.error().message;

    TwinChain& c = chain();
    const int warmUp = c.next() == 1 ? 2 : 1;  // some history first
    for (int i = 0; i < warmUp; ++i) ASSERT_NO_FATAL_FAILURE(c.stepBoth("before"));
    const CompositorConfig before = c.main.comp->config();
    const Status s = c.main.comp->setConfig(bad);
    ASSERT_FALSE(s.ok()) << row.name << " was taken by setConfig";
    EXPECT_EQ(s.error().code, int(ConfigError::InvalidValue));
    EXPECT_TRUE(contains(s.message(), row.message)) << s.message();
    EXPECT_TRUE(sameConfig(before, c.main.comp->config()));
    // Nothing pending: the next frame is the twin's exactly (a taken config would switch to fov).
    ASSERT_NO_FATAL_FAILURE(c.stepBoth("after the refused configuration"));
    expectSane(*c.main.comp, row.name);
}

INSTANTIATE_TEST_SUITE_P(BadConfig, Refused, ::testing::ValuesIn(refusedRows()),
                         [](const ::testing::TestParamInfo<ConfigRow>& i) { return i.param.name; });

std::vector<ConfigRow> acceptedRows() {
    auto set = [](auto fn) { return std::function<void(CompositorConfig&)>(fn); };
    return {
        {"fovea_180", set([](CompositorConfig& c) { c.foveaDeg = 180.0f; }), ""},
        {"fovea_tiny", set([](CompositorConfig& c) { c.foveaDeg = 1e-6f; }), ""},
        {"fovea_larger_than_mid_periphery", set([](CompositorConfig& c) { c.foveaDeg = 40.0f; }), ""},
        {"fovea_larger_than_mid_periphery_gauss", set([](CompositorConfig& c) {
             c.foveaDeg = 40.0f;
             c.foveation = FoveationMode::Gauss;
         }),
         ""},
        {"mid_periphery_tiny", set([](CompositorConfig& c) { c.midPeripheryDeg = 1e-6f; }), ""},
        {"fallback_fovea_180", set([](CompositorConfig& c) { c.fallbackFoveaDeg = 180.0f; }), ""},
        {"depth_tau_1e6", set([](CompositorConfig& c) { c.depthTau = 1e6f; }), ""},
        {"depth_tau_tiny", set([](CompositorConfig& c) { c.depthTau = 1e-30f; }), ""},
        {"seed_max", set([](CompositorConfig& c) { c.seed = 0xffffffffu; }), ""},
        {"taa_with_de94", set([](CompositorConfig& c) {
             c.method = Method::FovTaa;
             c.change = ChangeMetric::DeltaE94;
         }),
         ""},
    };
}

class Accepted : public GpuTest, public ::testing::WithParamInterface<ConfigRow> {};

TEST_P(Accepted, Row) {
    CompositorConfig cfg;
    GetParam().set(cfg);
    auto comp = Compositor::create(context(), cfg);
    ASSERT_TRUE(comp.ok()) << comp.error().message;
    StereoApp app(**comp, kW, kH, layers::Format::RGBA16F, layers::Format::R32F, layers::Format::RGBA16F);
    for (uint64_t f = 1; f <= 3; ++f) {
        // Depth jumps between frames, so that a tiny tolerance flushes and a huge one keeps.
        std::array<EyeFrame, 2> eyes = goodFrame(f, LaneFormats{});
        if (f == 2)
            for (auto& e : eyes) e.depth = RandomScene(uint32_t(f)).depth(layers::Format::R32F, kW, kH);
        const Status s = app.submit(f, eyes);
        ASSERT_TRUE(s.ok()) << s.message();
    }
    expectSane(**comp, GetParam().name);
    // The same values through setConfig are taken at the next frame.
    auto other = Compositor::create(context(), CompositorConfig{});
    ASSERT_TRUE(other.ok());
    EXPECT_TRUE((*other)->setConfig(cfg).ok());
}

INSTANTIATE_TEST_SUITE_P(BadConfig, Accepted, ::testing::ValuesIn(acceptedRows()),
                         [](const ::testing::TestParamInfo<ConfigRow>& i) { return i.param.name; });

}  // namespace
}  // namespace wrsfov::test
