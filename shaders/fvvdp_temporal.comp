// FovVideoVDP pass 2, temporal channels: the sustained and transient FIR filters over the last N
// frames of the window (frames before the first replicate it, the reference's padding), four
// pixels per invocation, into level 0 of the pyramid as (test sustained, reference sustained, test
// transient, reference transient).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(local_size_x = FVVDP_QUAD_GROUP, local_size_y = 1, local_size_z = 1) in;

void main() {
    uint q = fvvdp_quad(), quads = params.image.w, n = params.image.z;
    if (q >= quads) return;
    uint newest = push.at.z - 1u;  // frame index of this frame; it sits in slot push.at.y
    uint slot = push.at.y;
    vec4 ts = vec4(0.0), rs = vec4(0.0), tt = vec4(0.0), rt = vec4(0.0);
    for (uint k = 0u; k < n; ++k) {
        vec4 t = window_lum[(slot * 2u) * quads + q], r = window_lum[(slot * 2u + 1u) * quads + q];
        float fs = filters[k], ft = filters[n + k];
        ts += fs * t;
        rs += fs * r;
        tt += ft * t;
        rt += ft * r;
        if (k < newest) slot = slot == 0u ? n - 1u : slot - 1u;  // else: the first frame, replicated
    }
    uint npix = params.image.x * params.image.y;
    for (uint j = 0u; j < 4u; ++j)
        if (4u * q + j < npix) pyr[params.level[0].z + 4u * q + j] = vec4(ts[j], rs[j], tt[j], rt[j]);
}
