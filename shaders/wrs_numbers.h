// Numbers and guards: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_NUMBERS_H
#define WRSFOV_WRS_NUMBERS_H

#include "glsl_cpp.h"
#include "config.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Numbers and guards
// ---------------------------------------------------------------------------------------------

const float WRS_PI = 3.14159265358979f;
const float WRS_RAD_TO_DEG = 57.2957795130823f;
// Largest value a packed fp16 channel holds; colours and depths are clamped to it before packing.
const float WRS_HALF_MAX = 65504.0f;
// A reservoir never has w_sum <= 0 (docs/conventions.md "Reservoirs"): this is the floor it is clamped to, and the weight
// given to a reservoir that had to be started from an invalid candidate.
const float WRS_WSUM_MIN = 1e-30f;
// and never overflows: w_sum grows by at most 1 per frame, so this is reached only by corruption.
const float WRS_WSUM_MAX = 1e30f;

// True for finite floats. Works on the bits: some drivers fold isnan()/isinf() away.
WRS_FN bool wrs_finite(float x) { return (floatBitsToUint(x) & 0x7f800000u) != 0x7f800000u; }
WRS_FN bool wrs_finite3(vec3 v) { return wrs_finite(v.x) && wrs_finite(v.y) && wrs_finite(v.z); }

WRS_END

#endif
