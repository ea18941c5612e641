// Descriptor set 0, shared by the per-eye passes (load, pyramid, foveate, wrs). Each eye's images
// are bound as element [eye] of an array and indexed with gl_WorkGroupID.z (dynamically uniform).
#ifndef WRSFOV_BINDINGS_GLSL
#define WRSFOV_BINDINGS_GLSL

#include "wrs_common.h"
#include "wrs_params.h"

layout(std140, set = 0, binding = 0) uniform FrameBlock { FrameParams frame; };
layout(set = 0, binding = 1) uniform sampler2D colorIn[2];   // RGBA8 (sRGB viewed as UNORM), RGBA16F
layout(set = 0, binding = 2) uniform sampler2D depthIn[2];   // D32F / R32F, [0, 1]
layout(set = 0, binding = 3) uniform sampler2D motionIn[2];  // RG16F / RGBA16F, pixels (+ dz)
// Colour pyramid, linear RGB + validity in alpha, eye-major then level-major (wrs_level_offset).
layout(std430, set = 0, binding = 4) buffer Pyramid { vec4 pyramid[]; };
layout(std430, set = 0, binding = 5) buffer LinearDepth { float zlin[]; };
// Foveated candidate: linear RGB and its weight p̂ (0 when the input pixel was not finite).
layout(std430, set = 0, binding = 6) buffer Candidate { vec4 candidate[]; };
layout(std430, set = 0, binding = 7) readonly buffer ReservoirPrev { uvec4 res_prev[]; };
layout(std430, set = 0, binding = 8) writeonly buffer ReservoirCur { uvec4 res_cur[]; };
// Evaluation only (frame.tuning.z != 0): the submitted linear colour when the shown sample was taken.
layout(std430, set = 0, binding = 10) readonly buffer BirthPrev { vec4 birth_prev[]; };
layout(std430, set = 0, binding = 11) writeonly buffer BirthCur { vec4 birth_cur[]; };
// Output per eye (layer = eye), sRGB-encoded 8-bit.
layout(set = 0, binding = 9, rgba8) uniform writeonly image2DArray outImage;

uint eye_index(uint eye) { return eye; }
uint pixel_index(uint eye, uvec2 p) { return (eye * frame.size.y + p.y) * frame.size.x + p.x; }
uint pyramid_index(uint eye, uint level, uvec2 q) {
    uvec2 size0 = frame.size.xy;
    uvec2 sl = wrs_level_size(size0, level);
    return eye * wrs_pyramid_texels(size0) + wrs_level_offset(size0, level) + q.y * sl.x + q.x;
}
void store_output(uint eye, uvec2 p, vec3 linear_rgb) {
    imageStore(outImage, ivec3(ivec2(p), int(eye)), vec4(wrs_linear_to_srgb3(linear_rgb), 1.0));
}

#endif
