// What a conformant Vulkan device may compute differently from the CPU reference, where the spec
// leaves the result free (docs/speed.md, "Rounding: what a conformant device may do differently"):
// the C++ side of the shared headers' wrs_div, wrs_exp, wrs_pow, wrs_sqrt, wrs_length,
// wrs_normalize, wrs_device_pack_half2x16 and wrs_device_unorm8. C++ only: in a shader each of these
// is the built-in itself (glsl_cpp.h), so nothing here reaches the SPIR-V.
//
// By default every hook returns what the reference always computed (correctly rounded, ties to
// even; fp16 and UNORM conversions by hand). A test sets another permitted result for the process
// (DeviceRounding, ScopedDeviceRounding) and checks that the GPU still agrees with it. A plain global
// rather than a thread_local: the compositor library links nothing beyond libc, libm, libstdc++,
// libgcc_s and Vulkan (a thread_local adds the dynamic loader's TLS), and only tests set it.
#ifndef WRSFOV_DEVICE_ROUNDING_H
#define WRSFOV_DEVICE_ROUNDING_H

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <glm/glm.hpp>
#include <limits>

namespace wrsfov::gpu {

/// Which of the results the Vulkan spec permits a hook returns.
enum class Permitted : std::uint8_t {
    Nearest,  ///< the reference's own: correctly rounded, ties to even
    Low,      ///< the lowest permitted (a conversion: the neighbour below; a built-in: its whole error below)
    High,     ///< the highest permitted
    Mixed,    ///< per value, from a hash of its inputs and DeviceRounding::seed: anything from Low to High
};

/// The device the reference models.
struct DeviceRounding {
    /// The device's fp16 conversion (packHalf2x16) of a value fp16 cannot hold: "conversions between types:
    /// correctly rounded" with the rounding mode unspecified (spirvenv-correctly-rounded: either neighbour;
    /// fundamentals-fp-conversion), and an fp16 denormal result may be flushed to zero (spirvenv-precision-operation).
    Permitted half = Permitted::Nearest;
    /// A float store to an 8-bit UNORM image of a value f with f * 255 not a whole number: either of the two
    /// nearest codes (fundamentals-fpfixedconv, convertFloatToUint).
    Permitted unorm = Permitted::Nearest;
    /// OpFDiv (2.5 ULP), exp (3 + 2|x| ULP), pow (inherited from exp2(y log2 x)), sqrt (inherited from
    /// 1 / inversesqrt), length and normalize (inherited from dot and inversesqrt): moved by their whole
    /// error bound (spirvenv-op-prec), less the reference's own error.
    Permitted builtins = Permitted::Nearest;
    std::uint32_t seed = 0;  ///< Mixed: which value goes which way
    /// The passes store fp16 with the device's conversion (the pipelines' constant HARDWARE_HALF).
    bool hardwareHalf = false;
};

/// The model every reference of the process steps with.
inline DeviceRounding& deviceRounding() {
    static DeviceRounding model;
    return model;
}

/// Sets the model until the end of the scope.
class ScopedDeviceRounding {
public:
    explicit ScopedDeviceRounding(const DeviceRounding& model) : saved_(deviceRounding()) { deviceRounding() = model; }
    ~ScopedDeviceRounding() { deviceRounding() = saved_; }
    ScopedDeviceRounding(const ScopedDeviceRounding&) = delete;
    ScopedDeviceRounding& operator=(const ScopedDeviceRounding&) = delete;

private:
    DeviceRounding saved_;
};

namespace rounding_detail {

inline std::uint32_t bits(float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
}
inline std::uint32_t mix(std::uint32_t h, std::uint32_t v) {
    h ^= v + 0x9e3779b9u + (h << 6) + (h >> 2);
    h *= 0x85ebca6bu;
    return h ^ (h >> 15);
}
// Where in [-1, 1] a value goes: -1 Low, +1 High, 0 Nearest; Mixed from the hash of `key`.
inline double direction(Permitted p, std::uint32_t key) {
    switch (p) {
        case Permitted::Low:
            return -1.0;
        case Permitted::High:
            return 1.0;
        case Permitted::Mixed: {
            const std::uint32_t h = mix(mix(0x2545f491u, deviceRounding().seed), key);
            return double(h % 2001u) / 1000.0 - 1.0;
        }
        default:
            return 0.0;
    }
}
// The smaller of the gaps to the floats either side of r (the spec's ulp(x) for x near r).
inline double ulp(float r) {
    const float a = std::fabs(r);
    if (!std::isfinite(a)) return 0.0;
    const float up = std::nextafter(a, std::numeric_limits<float>::infinity());
    const float down = std::nextafter(a, 0.0f);
    const double gapUp = std::isfinite(up) ? double(up) - a : std::numeric_limits<double>::infinity();
    return a == 0.0f ? double(up) : std::min(gapUp, double(a) - down);
}
// r, the reference's result within `own` ULP of the exact value, moved towards the edge of the range
// [x - allowed ulp, x + allowed ulp] the spec permits, by whole ULPs and never past it.
inline float perturb(float r, double allowed, double own, Permitted p, std::uint32_t key) {
    if (p == Permitted::Nearest || !std::isfinite(r)) return r;
    const double steps = std::floor(allowed - own);
    if (!(steps >= 1.0)) return r;
    const double shift = std::round(direction(p, key) * steps) * ulp(r);
    const double target = double(r) + shift;
    float f = float(target);
    if (std::fabs(double(f) - r) > std::fabs(shift)) f = std::nextafter(f, r);
    return f;
}

}  // namespace rounding_detail

// ---------------------------------------------------------------------------------------------
// Built-ins within their error bounds (spirvenv-op-prec). Each checks the model first, so the
// reference's results are its own unless a test set another model.
// ---------------------------------------------------------------------------------------------

inline float wrs_div(float a, float b) {
    const float r = a / b;
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    // OpFDiv: 2.5 ULP for |b| in [2^-126, 2^126]; outside that range nothing is promised and nothing is moved.
    const float ab = std::fabs(b);
    if (!(ab >= 0x1p-126f && ab <= 0x1p126f)) return r;
    return rounding_detail::perturb(r, 2.5, 0.5, p,
                                    rounding_detail::mix(rounding_detail::bits(a), rounding_detail::bits(b)));
}
template <glm::length_t N>
inline glm::vec<N, float> wrs_div(glm::vec<N, float> a, glm::vec<N, float> b) {
    glm::vec<N, float> r;
    for (glm::length_t i = 0; i < N; ++i) r[i] = wrs_div(a[i], b[i]);
    return r;
}
template <glm::length_t N>
inline glm::vec<N, float> wrs_div(glm::vec<N, float> a, float b) {
    return wrs_div(a, glm::vec<N, float>(b));
}

inline float wrs_exp(float x) {
    const float r = std::exp(x);
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    // exp: 3 + 2|x| ULP; the reference's expf is within one.
    return rounding_detail::perturb(r, 3.0 + 2.0 * std::fabs(double(x)), 1.0, p,
                                    rounding_detail::mix(0x657870u, rounding_detail::bits(x)));
}

/// The error, in ULP of the result r, that pow(x, y) may have: inherited from exp2(y * log2(x)) with
/// log2 within 3 ULP (absolute 2^-21 in [0.5, 2]), the product correctly rounded to either neighbour
/// and exp2 within 3 + 2|y log2 x| ULP.
inline double wrs_pow_error_ulps(float x, float y, float r) {
    if (!(x > 0.0f) || !std::isfinite(x) || !std::isfinite(r) || r == 0.0f) return 0.0;
    const double l = std::log2(double(x));
    const double errLog = (x >= 0.5f && x <= 2.0f) ? 0x1p-21 : 3.0 * rounding_detail::ulp(float(l));
    const double prod = double(y) * l;
    const double errProd = std::fabs(double(y)) * errLog + rounding_detail::ulp(float(prod));
    // exp2(prod + e) = exp2(prod) * 2^e: a relative error of e ln 2 (to first order; e is tiny).
    return 3.0 + 2.0 * std::fabs(prod) + std::fabs(double(r)) * std::log(2.0) * errProd / rounding_detail::ulp(r);
}
inline float wrs_pow(float x, float y) {
    const float r = std::pow(x, y);
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    return rounding_detail::perturb(
        r, wrs_pow_error_ulps(x, y, r), 1.0, p,
        rounding_detail::mix(rounding_detail::bits(x), rounding_detail::bits(y) ^ 0x706f77u));
}

/// The error, in ULP of the result r = sqrt(x), inherited from 1 / inversesqrt(x): inversesqrt within
/// 2 ULP (a relative error that carries over to the quotient), the division within 2.5.
inline double wrs_sqrt_error_ulps(float r) {
    if (!(r > 0.0f) || !std::isfinite(r)) return 0.0;
    const float inv = float(1.0 / double(r));
    return 2.0 * rounding_detail::ulp(inv) / inv * r / rounding_detail::ulp(r) + 2.5;
}
inline float wrs_sqrt(float x) {
    const float r = std::sqrt(x);
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    return rounding_detail::perturb(r, wrs_sqrt_error_ulps(r), 0.5, p,
                                    rounding_detail::mix(0x737172u, rounding_detail::bits(x)));
}
template <glm::length_t N>
inline glm::vec<N, float> wrs_sqrt(glm::vec<N, float> x) {
    glm::vec<N, float> r;
    for (glm::length_t i = 0; i < N; ++i) r[i] = wrs_sqrt(x[i]);
    return r;
}
// length: inherited from sqrt(dot(v, v)); only the square root's share of the error is used (the dot
// product's roundings add to it), which keeps the result inside the permitted range.
template <glm::length_t N>
inline float wrs_length(glm::vec<N, float> v) {
    const float r = glm::length(v);
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    std::uint32_t key = 0x6c656eu;
    for (glm::length_t i = 0; i < N; ++i) key = rounding_detail::mix(key, rounding_detail::bits(v[i]));
    // glm's length rounds twice (the dot product and the root): one ULP of its own.
    return rounding_detail::perturb(r, wrs_sqrt_error_ulps(r), 1.0, p, key);
}
// normalize: inherited from v * inversesqrt(dot(v, v)): inversesqrt's 2 ULP of relative error (at least
// one ULP of each component) and the product's rounding to either neighbour; glm's own error is about
// one and a half, so each component moves by one ULP.
template <glm::length_t N>
inline glm::vec<N, float> wrs_normalize(glm::vec<N, float> v) {
    glm::vec<N, float> r = glm::normalize(v);
    const Permitted p = deviceRounding().builtins;
    if (p == Permitted::Nearest) return r;
    std::uint32_t key = 0x6e6f72u;
    for (glm::length_t i = 0; i < N; ++i) key = rounding_detail::mix(key, rounding_detail::bits(v[i]));
    for (glm::length_t i = 0; i < N; ++i)
        r[i] = rounding_detail::perturb(r[i], 3.0, 1.5, p, rounding_detail::mix(key, i));
    return r;
}

// ---------------------------------------------------------------------------------------------
// Conversions a device may round either way
// ---------------------------------------------------------------------------------------------

/// The 8-bit code a device's store of f to a UNORM8 image may give: the nearest code (half away from
/// zero) by default; where f * 255 (in float) is not a whole number, the neighbour DeviceRounding::unorm
/// picks. A whole number is returned exactly in every mode.
inline std::uint8_t wrs_device_unorm8(float f) {
    const float c = std::clamp(f, 0.0f, 1.0f);
    const float r = c * 255.0f;
    const float lo = std::floor(r);
    if (r == lo) return std::uint8_t(lo);
    const double d = rounding_detail::direction(deviceRounding().unorm, rounding_detail::bits(f) ^ 0x756e6fu);
    if (deviceRounding().unorm == Permitted::Nearest || d == 0.0) return std::uint8_t(std::lround(r));
    return std::uint8_t(d < 0.0 ? lo : lo + 1.0f);
}

}  // namespace wrsfov::gpu

#endif
