// The device's own fp16 conversions: packHalf2x16 of each of the first `count & 0xffff` input floats (low
// 16 bits), then unpackHalf2x16 of the low 16 bits of each of the next `count >> 16` (as float bits). The compositor compares them
// with wrs_f32_to_f16 on every value the passes give it (every normal fp16 value: they round to fp16's
// grid by hand first, wrs_store_f16) and with wrs_f16_to_f32 on every finite fp16 value (subnormals
// included) before it lets the passes use them (Compositor::hardwareHalf).
#version 450
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer Src { float src[]; };
layout(std430, set = 0, binding = 1) writeonly buffer Dst { uint dst[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
    uint i = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * 64u;
    uint packs = count & 0xffffu, n = packs + (count >> 16u);
    if (i >= n) return;
    if (i >= packs)
        dst[i] = floatBitsToUint(unpackHalf2x16(floatBitsToUint(src[i]) & 0xffffu).x);
    else
        dst[i] = packHalf2x16(vec2(src[i], 0.0)) & 0xffffu;
}
