// Random numbers: one stage of the per-pixel math shared by GLSL and C++ (wrs_common.h, the umbrella header
// every shader and the CPU reference include, says how; glsl_cpp.h the common subset).
#ifndef WRSFOV_WRS_RANDOM_H
#define WRSFOV_WRS_RANDOM_H

#include "glsl_cpp.h"
#include "config.h"

WRS_BEGIN

// ---------------------------------------------------------------------------------------------
// Random numbers: one hash of (x, y, eye, frame, seed), identical on CPU and GPU
// ---------------------------------------------------------------------------------------------

// PCG output permutation (O'Neill 2014; Jarzynski & Olano 2020 "hash functions for GPU rendering").
WRS_FN uint wrs_pcg(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
WRS_FN uint wrs_hash(uint x, uint y, uint eye, uint frame, uint seed) {
    uint h = wrs_pcg(x ^ wrs_pcg(seed));
    h = wrs_pcg(y ^ h);
    h = wrs_pcg(eye ^ h);
    return wrs_pcg(frame ^ h);
}
// 24 random bits as a float in [0, 1): exact on both sides.
WRS_FN float wrs_rand(uint x, uint y, uint eye, uint frame, uint seed) {
    return float(wrs_hash(x, y, eye, frame, seed) >> 8u) * (1.0f / 16777216.0f);
}

WRS_END

#endif
