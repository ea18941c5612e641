// Type and keyword bridge so that one header compiles as GLSL 4.50 and as C++20 with GLM.
//
// Shared headers include this first and then use only the common subset: GLSL vector types,
// `uint`, scalar `const` globals, structs assigned field by field, and the WRS_* macros below for
// what the two languages spell differently (out/inout parameters, `precise`, `inline`).
#ifndef WRSFOV_GLSL_CPP_H
#define WRSFOV_GLSL_CPP_H

#ifdef __cplusplus
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>

namespace wrsfov::gpu {
using namespace glm;
using uint = std::uint32_t;
}  // namespace wrsfov::gpu

#define WRS_BEGIN namespace wrsfov::gpu {
#define WRS_END }
// Internal linkage: each translation unit calls its own copy, compiled with its own flags. With
// external linkage the linker keeps one copy of each, the first it meets, and a test executable's
// objects come before the libraries: the CPU reference (-O1 or -O2) then ran the test files' copies,
// which the sanitizer build compiles at -O0 (tests/CMakeLists.txt), five times slower. A C++ function
// in a header that calls these is static inline too (one definition rule).
#define WRS_FN static inline
#define WRS_OUT(T) T&
#define WRS_INOUT(T) T&
// C++ side is compiled with -ffp-contract=off, which gives the same guarantee as GLSL `precise`.
#define WRS_PRECISE
// The built-ins whose result a device may round differently (wrs_div, wrs_exp, wrs_pow, ...): C++
// functions that model what the spec permits (device_rounding.h); the reference's own by default.
#include "device_rounding.h"
// Whether the passes store fp16 with the device's conversion: in a shader the pipelines' constant
// (bindings.glsl), in C++ the modelled device's.
#define WRS_HARDWARE_HALF_MODEL (::wrsfov::gpu::deviceRounding().hardwareHalf)
#else
#define WRS_BEGIN
#define WRS_END
#define WRS_FN
#define WRS_OUT(T) out T
#define WRS_INOUT(T) inout T
#define WRS_PRECISE precise
// The built-ins themselves; C++ models what else a conformant device may return (device_rounding.h).
#define wrs_div(a, b) ((a) / (b))
#define wrs_exp exp
#define wrs_pow pow
#define wrs_sqrt sqrt
#define wrs_length length
#define wrs_normalize normalize
#define wrs_device_pack_half2x16 packHalf2x16
#endif

#endif
