// Evaluates the shared header's building blocks for a table of inputs, so tests can measure how far
// this device's built-ins (pow, exp, atan, sqrt) are from the CPU's.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "wrs_common.h"

layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer In { vec4 inputs[]; };
layout(std430, binding = 1) writeonly buffer Out { float outputs[]; };
layout(push_constant) uniform Push { uint count; };

const uint FUNCS = 8u;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= count) return;
    vec4 v = inputs[i];
    outputs[i * FUNCS + 0u] = wrs_srgb_to_linear(v.x);
    outputs[i * FUNCS + 1u] = wrs_lab_f(v.x);
    outputs[i * FUNCS + 2u] = exp(-v.y);
    outputs[i * FUNCS + 3u] = wrs_eccentricity_deg(normalize(vec3(v.z, v.w, -1.0)), vec3(0.0, 0.0, -1.0));
    outputs[i * FUNCS + 4u] = wrs_sample_weight(v.y, 2.5);
    outputs[i * FUNCS + 5u] = wrs_change(WRS_CHANGE_LSTAR, vec3(v.x), vec3(v.x * 0.9 + 0.05));
    outputs[i * FUNCS + 6u] = wrs_change(WRS_CHANGE_DE94, vec3(v.x, v.z * 0.5 + 0.5, 0.3), vec3(v.x * 0.9, 0.5, v.w * 0.5 + 0.5));
    outputs[i * FUNCS + 7u] = wrs_linear_to_srgb(v.x);
}
