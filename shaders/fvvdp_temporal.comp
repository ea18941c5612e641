// FovVideoVDP pass 2, temporal channels: the sustained and transient FIR filters over the last N
// frames of the window (frames before the first replicate it, the reference's padding), into
// level 0 of the pyramid as (test sustained, reference sustained, test transient, reference transient).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(local_size_x = FVVDP_GROUP, local_size_y = FVVDP_GROUP, local_size_z = 1) in;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = params.image.xy;
    if (any(greaterThanEqual(p, size))) return;
    uint npix = size.x * size.y, i = p.y * size.x + p.x, n = params.image.z;
    uint newest = push.at.z - 1u;  // frame index of this frame
    uint filters = 2u * FVVDP_CSF_TABLE;
    vec4 acc = vec4(0.0);
    for (uint k = 0u; k < n; ++k) {
        uint slot = (newest - min(k, newest)) % n;
        float t = window_lum[(slot * 2u) * npix + i], r = window_lum[(slot * 2u + 1u) * npix + i];
        float fs = tables[filters + k], ft = tables[filters + n + k];
        acc += vec4(fs * t, fs * r, ft * t, ft * r);
    }
    pyr[fvvdp_texel(0u, p)] = acc;
}
