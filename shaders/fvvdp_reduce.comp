// FovVideoVDP pass 3, Gaussian pyramid (detail::pyramidReduce): level push.at.x + 1 of the four
// channels from level push.at.x, the 5-tap kernel at every second sample, borders mirrored. One
// dispatch per level.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(local_size_x = FVVDP_GROUP, local_size_y = FVVDP_GROUP, local_size_z = 1) in;

void main() {
    uint src = push.at.x;
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = params.level[src + 1u].xy, ssize = params.level[src].xy;
    if (any(greaterThanEqual(p, size))) return;
    int xs[5];
    for (int k = 0; k < 5; ++k) xs[k] = fvvdp_reduce_tap(int(p.x), k, int(ssize.x));
    vec4 acc = vec4(0.0);
    for (int ky = 0; ky < 5; ++ky) {
        uint row = params.level[src].z + uint(fvvdp_reduce_tap(int(p.y), ky, int(ssize.y))) * ssize.x;
        vec4 r = vec4(0.0);
        for (int kx = 0; kx < 5; ++kx) r += FVVDP_KERNEL[kx] * pyr[row + uint(xs[kx])];
        acc += FVVDP_KERNEL[ky] * r;
    }
    pyr[fvvdp_texel(src + 1u, p)] = acc;
}
