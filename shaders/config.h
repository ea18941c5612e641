// Workgroup sizes and limits shared by C++ and GLSL. One "why" per value.
#ifndef WRSFOV_CONFIG_H
#define WRSFOV_CONFIG_H

// 8x8 threads: 64 lanes fill a wave on most desktop GPUs and two SIMD groups on lavapipe's 256-bit
// LLVM backend; square tiles keep the neighbourhood reads of the downsample pass cache-friendly.
#define WRS_GROUP_X 8
#define WRS_GROUP_Y 8

// The mip pyramid pass: each group builds the levels of a 32x32-pixel tile of level 0 (each of its 8x8
// invocations a 4x4 block), the support of 2x2 level-4 texels (shaders/pyramid.comp).
#define WRS_MIP_TILE 32

// Levels 0..4: the fovea samples level 0, the mid-periphery the 8x8 shading rate (level 3) and the
// far periphery 16x16 (level 4), as in docs/conventions.md "Foveation".
#define WRS_LEVELS 5

// The candidate count M is stored in 16 bits of the packed reservoir.
#define WRS_M_MAX 65535u

// Stereo: one dispatch carries both eyes in z.
#define WRS_EYES 2

#endif
