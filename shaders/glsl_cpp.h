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
#define WRS_FN inline
#define WRS_OUT(T) T&
#define WRS_INOUT(T) T&
// C++ side is compiled with -ffp-contract=off, which gives the same guarantee as GLSL `precise`.
#define WRS_PRECISE
#else
#define WRS_BEGIN
#define WRS_END
#define WRS_FN
#define WRS_OUT(T) out T
#define WRS_INOUT(T) inout T
#define WRS_PRECISE precise
#endif

#endif
