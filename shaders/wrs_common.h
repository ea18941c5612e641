// The per-pixel math of wrsfov, in the common subset of GLSL and C++ (see glsl_cpp.h).
//
// Compiled into every compute shader and into the CPU reference (compositor/reference.cpp), so the
// GPU and the reference can only differ where the Vulkan spec leaves a result free: the built-ins
// spelled wrs_div, wrs_exp, wrs_pow, wrs_sqrt, wrs_length and wrs_normalize (whose other permitted
// results the reference can take: device_rounding.h), and the rounding direction of the rest. What is
// stored quantised (fp16, the fingerprint and output codes) is rounded by hand from unfused operations
// (docs/speed.md, "Rounding: what a conformant device may do differently"). Equation numbers refer to
// Cantory et al., MIG '25 ("the paper"); section names to docs/conventions.md.
//
// This header is the umbrella: each stage of the math is one header, in the order a frame uses them.
#ifndef WRSFOV_WRS_COMMON_H
#define WRSFOV_WRS_COMMON_H

#include "glsl_cpp.h"
#include "config.h"

#include "wrs_numbers.h"  // Numbers and guards
#include "wrs_views.h"  // Views, eccentricity and the sample weight
#include "wrs_foveation.h"  // Foveation
#include "wrs_colour.h"  // Colour
#include "wrs_depth.h"  // Depth
#include "wrs_random.h"  // Random numbers
#include "wrs_reservoir.h"  // Reservoirs
#include "wrs_retention.h"  // Quality-aware retention
#include "wrs_sparse.h"  // Sparse retention
#include "wrs_taa.h"  // The FOV+TAA baseline
#include "wrs_floor.h"  // The steady floor

#endif
