// GPU results that hold on every conformant device. Where the Vulkan spec leaves a result free (the
// rounding direction of a conversion, the ULP error of a division or of exp and pow, a UNORM store's
// code), the CPU reference takes each other permitted result in turn (shaders/device_rounding.h) and
// must still agree with this device, on the frames of the GPU-vs-CPU comparison and with its checks
// (vs_cpu.cpp): a decision differs only near its threshold, outputs by one 8-bit step, stored values
// by the rounding of their own quantisation. docs/speed.md, "Rounding: what a conformant device may
// do differently", says what each clause allows and how the passes are kept from depending on it.
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>

#include "vs_cpu.h"

namespace wrsfov::test {
namespace {

using gpu::DeviceRounding;
using gpu::Permitted;

// The devices modelled: fp16 stored with the device's conversion rounding down, up or either way per
// value (flushing fp16 denormals), built-ins at the low or high end of their error bounds or anywhere
// between, UNORM stores to either neighbouring code, and all of it at once.
std::vector<Variant> permittedDevices() {
    auto make = [](const char* name, Permitted half, Permitted builtins, Permitted unorm) {
        Variant v{name};
        v.model.half = half;
        v.model.builtins = builtins;
        v.model.unorm = unorm;
        v.model.hardwareHalf = half != Permitted::Nearest;
        v.model.seed = 17;
        return v;
    };
    const Permitted N = Permitted::Nearest, L = Permitted::Low, H = Permitted::High, M = Permitted::Mixed;
    return {make("fp16 conversion down", L, N, N),
            make("fp16 conversion up", H, N, N),
            make("fp16 conversion either way", M, N, N),
            make("built-ins low", N, L, N),
            make("built-ins high", N, H, N),
            make("built-ins mixed", N, M, N),
            make("UNORM store down", N, N, L),
            make("UNORM store up", N, N, H),
            make("everything mixed", M, M, M)};
}

// The pipelines whose GPU-vs-CPU tests an NVIDIA H200 failed (docs/speed.md), and the steady floor.
std::vector<Case> roundingPipelines() {
    std::vector<Case> out;
    for (const Case& c : comparedPipelines()) {
        const std::string n = c.name;
        if (n == "wrs_mip_depth_motion" || n == "retain_mip_depth_motion" || n == "retain_none_nodepth_nomotion" ||
            n == "oracle_mip_motion" || n == "fov_mip")
            out.push_back(c);
    }
    out.push_back(Case{"retain_mip_motion_steady", Method::Wrs, FoveationMode::Mip, layers::Format::RGBA16F,
                       std::nullopt, layers::Format::RG16F, ChangeMetric::LStar, false, EqualQuality::Merge, true});
    return out;
}

class Rounding : public GpuTest, public ::testing::WithParamInterface<Case> {};

TEST_P(Rounding, EveryPermittedRoundingAgreesWithThisDevice) {
    std::vector<Variant> devices = permittedDevices();
    runAgainstReferences(GetParam(), 88, 72, 60, devices);
    if (HasFatalFailure()) return;
    for (const Variant& v : devices) expectAgreement(GetParam(), v);
}

TEST_P(Rounding, OddSizesToo) {
    std::vector<Variant> devices = permittedDevices();
    // Under the sanitizers (host code checked) the last model alone: it takes each permitted result
    // of every clause per value, so every path of the models' code runs.
    if (kSanitized) devices.erase(devices.begin(), devices.end() - 1);
    for (auto [w, h] : {std::pair{87u, 69u}, std::pair{33u, 17u}}) {
        for (Variant& v : devices) v.t = {}, v.rt = {}, v.st = {};
        runAgainstReferences(GetParam(), w, h, 6, devices);
        if (HasFatalFailure()) return;
        for (const Variant& v : devices) expectAgreement(GetParam(), v);
    }
}

INSTANTIATE_TEST_SUITE_P(Pipelines, Rounding, ::testing::ValuesIn(roundingPipelines()),
                         [](const ::testing::TestParamInfo<Case>& i) { return std::string(i.param.name); });

// The models themselves: each stays inside what the spec permits, and moves where it may.
TEST(RoundingModels, StayWithinTheirBounds) {
    for (Permitted p : {Permitted::Low, Permitted::High, Permitted::Mixed}) {
        DeviceRounding m;
        m.half = m.builtins = m.unorm = p;
        m.seed = 3;
        gpu::ScopedDeviceRounding scope(m);
        int movedDiv = 0, movedPow = 0, movedHalf = 0;
        for (int i = 1; i < 2000; ++i) {
            const float a = 0.37f * float(i), b = 1.0f + 0.013f * float(i);
            // OpFDiv: within 2.5 ULP of the exact quotient.
            const double exact = double(a) / b;
            const float q = gpu::wrs_div(a, b);
            EXPECT_LE(std::fabs(q - exact), 2.5 * gpu::rounding_detail::ulp(float(exact))) << a << "/" << b;
            movedDiv += q != a / b;
            // pow: within its inherited bound of the exact power.
            const float x = 0.001f * float(i);
            const double px = std::pow(double(x), 1.0 / 2.4);
            const float pr = gpu::wrs_pow(x, 1.0f / 2.4f);
            EXPECT_LE(std::fabs(pr - px),
                      gpu::wrs_pow_error_ulps(x, 1.0f / 2.4f, float(px)) * gpu::rounding_detail::ulp(float(px)))
                << x;
            movedPow += pr != std::pow(x, 1.0f / 2.4f);
            // fp16: one of the two neighbours of an inexact value, the value itself when exact.
            const uint32_t h = gpu::wrs_device_f32_to_f16(x), n = gpu::wrs_f32_to_f16(x);
            EXPECT_LE(std::abs(int(h) - int(n)), 1) << x;
            if (gpu::wrs_f16_to_f32(n) == x) {
                EXPECT_EQ(h, n);
            }
            movedHalf += h != n;
            // UNORM: a whole code is that code.
            EXPECT_EQ(gpu::wrs_device_unorm8(float(i % 256) / 255.0f), i % 256);
        }
        EXPECT_GT(movedDiv, 100);
        EXPECT_GT(movedPow, 100);
        EXPECT_GT(movedHalf, 100);
    }
}

// What the passes now compute by hand instead of leaving to the device.
TEST(RoundingModels, HandQuantisationIsExact) {
    // fp16's grid by hand: the hand conversion's value for every float that rounds to a normal fp16.
    std::mt19937 rng(9);
    std::uniform_int_distribution<uint32_t> bits(0x38800000u, 0x477fefffu);
    for (int i = 0; i < 200000; ++i) {
        const float f = glm::uintBitsToFloat(bits(rng) | (i % 2 ? 0x80000000u : 0u));
        ASSERT_TRUE(gpu::wrs_f16_normal(f));
        ASSERT_EQ(gpu::wrs_f16_grid(f), gpu::wrs_round_f16(f)) << f;
    }
    // The compose pass's rounding before a 16-bit store: wrs_round_f16's bits for every float (the
    // normal range by the grid, the rest by the hand conversion), specials and fp16 denormals included.
    {
        std::uniform_int_distribution<uint32_t> any;
        const float specials[] = {0.0f, -0.0f, 6.0e-8f, 3.0e-8f, 6.1e-5f, 65504.0f, 65519.0f, 65520.0f, 1e30f,
                                  std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                                  std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::denorm_min()};
        for (float f : specials)
            ASSERT_EQ(glm::floatBitsToUint(gpu::wrs_f16_value(f)), glm::floatBitsToUint(gpu::wrs_round_f16(f))) << f;
        for (int i = 0; i < 400000; ++i) {
            const float f = glm::uintBitsToFloat(any(rng));
            ASSERT_EQ(glm::floatBitsToUint(gpu::wrs_f16_value(f)), glm::floatBitsToUint(gpu::wrs_round_f16(f)))
                << std::hex << glm::floatBitsToUint(f);
        }
    }
    EXPECT_FALSE(gpu::wrs_f16_normal(0.0f));
    EXPECT_FALSE(gpu::wrs_f16_normal(65520.0f));
    EXPECT_FALSE(gpu::wrs_f16_normal(6.0e-5f));
    // The stores with the device's conversion (here a conformant one that rounds down): the hand
    // conversion's bits for every float, zeros, denormals, overflow, infinities and NaNs included.
    {
        DeviceRounding m;
        m.hardwareHalf = true;
        m.half = Permitted::Low;
        gpu::ScopedDeviceRounding scope(m);
        std::uniform_int_distribution<uint32_t> any;
        for (int i = 0; i < 400000; ++i) {
            const uint32_t u = i < 64 ? (i % 2 ? 0x80000000u : 0u) | (0x38800000u + uint32_t(i / 2) - 16u) : any(rng);
            const float f = glm::uintBitsToFloat(u), g = glm::uintBitsToFloat(any(rng));
            ASSERT_EQ(gpu::wrs_store_f16(f), gpu::wrs_f32_to_f16(f)) << std::hex << u;
            ASSERT_EQ(gpu::wrs_store_f16x2(f, g), gpu::wrs_f32_to_f16(f) | (gpu::wrs_f32_to_f16(g) << 16u))
                << std::hex << u;
        }
        for (float f : {0.0f, -0.0f, 65504.0f, 65519.0f, 65520.0f, 1e30f, 5.9604645e-8f, 2.9802322e-8f, 6.1e-5f})
            EXPECT_EQ(gpu::wrs_store_f16(f), gpu::wrs_f32_to_f16(f)) << f;
    }
    // Whole 8-bit codes: code / 255 to the nearest float, and 255 times it is the code.
    for (uint32_t k = 0; k < 256; ++k) {
        const float f = gpu::wrs_unorm8_value(k);
        EXPECT_EQ(f, float(k) / 255.0f) << k;
        EXPECT_EQ(f * 255.0f, float(k)) << k;
        EXPECT_EQ(gpu::wrs_unorm8_code(f), k);
    }
    // The cube root of L* without pow: within 5e-7 of the true one.
    double worst = 0.0;
    for (double t = 1e-4; t < 2e5; t *= 1.001) {
        const float f = float(t);
        worst = std::max(worst, std::fabs(gpu::wrs_cbrt(f) - std::cbrt(double(f))) / std::cbrt(double(f)));
    }
    EXPECT_LT(worst, 5e-7);
}

}  // namespace
}  // namespace wrsfov::test
