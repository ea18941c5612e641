// The device's own fp16 conversion (packHalf2x16) of each input float, low 16 bits: the compositor
// compares it with wrs_f32_to_f16 on every value the passes give it (every normal fp16 value: they round
// to fp16's grid by hand first, wrs_store_f16) before it lets the passes use it (Compositor::hardwareHalf).
#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Src { float src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    if (i < count) dst[i] = packHalf2x16(vec2(src[i], 0.0)) & 0xffffu;
}
