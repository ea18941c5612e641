// FovVideoVDP pass 4, one band (push.at.x) of all four channels: the Laplacian band (the level less
// the expanded next level), band contrast against the expanded reference sustained channel, the
// CSF of frequency, luminance and eccentricity, mutual masking, and D^beta summed over each group
// into `partial` (the host pools the sums: fvvdp::detail::poolFrame). One dispatch per band; the
// bands are independent.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(constant_id = 0) const bool FOVEATED = true;      // false: the foveal CSF at the band's central frequency
layout(constant_id = 1) const bool FLAT_SCREEN = false;  // ViewGeometry::Model::FlatScreen
layout(local_size_x = FVVDP_GROUP, local_size_y = FVVDP_GROUP, local_size_z = 1) in;

const uint LANES = uint(FVVDP_GROUP * FVVDP_GROUP);
shared vec2 s_sum[LANES];

void main() {
    uint b = push.at.x;
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = params.level[b].xy, nsize = params.level[b + 1u].xy;
    vec2 sum = vec2(0.0);
    if (all(lessThan(p, size))) {
        // Expanded next level (detail::pyramidExpand at this pixel: 3 x 3 taps).
        ivec3 xs, ys;
        vec3 wx = fvvdp_expand_taps(int(p.x), int(nsize.x), xs), wy = fvvdp_expand_taps(int(p.y), int(nsize.y), ys);
        vec4 e = vec4(0.0);
        for (int ky = 0; ky < 3; ++ky) {
            uint row = params.level[b + 1u].z + uint(ys[ky]) * nsize.x;
            e += wy[ky] * (wx.x * pyr[row + uint(xs.x)] + wx.y * pyr[row + uint(xs.y)] + wx.z * pyr[row + uint(xs.z)]);
        }
        vec4 band = pyr[fvvdp_texel(b, p)] - e;
        // Contrast against the reference's sustained background, capped; bands below the finest doubled.
        float l_bkg = max(e.y, 0.1);
        vec4 c = min(band / l_bkg, vec4(1000.0)) * params.band[b].y;

        float rho = params.band[b].x, ecc = 0.0;
        if (FOVEATED) {
            vec4 t = params.fov_tan;
            float tx = t.x + (float(p.x) + 0.5) / float(size.x) * (t.y - t.x);
            float ty = t.z - (float(p.y) + 0.5) / float(size.y) * (t.z - t.w);
            ecc = fvvdp_eccentricity(FLAT_SCREEN, tx, ty, params.gaze.x, params.gaze.y);
            float angle = fvvdp_eccentricity(FLAT_SCREEN, tx, ty, 0.0, 0.0);
            rho *= fvvdp_resolution_magnification(angle, params.gaze.z);
        }
        vec2 sens = params.display.z * fvvdp_csf(rho, l_bkg, ecc);
        for (uint cc = 0u; cc < 2u; ++cc) {
            float s = sens[cc];
            float q = cc == 0u ? params.mask.z : params.mask.w;
            float d = fvvdp_masked_difference(c[2u * cc] * s, c[2u * cc + 1u] * s, params.mask.x, q, params.mask.y);
            if (d > 0.0) sum[cc] = pow(d, params.pool.x);
        }
    }
    // One barrier, then the first lane adds the group's 64 sums (a tree would take 6 barriers, each
    // of which a CPU device pays for by splitting the group's loop).
    uint lane = gl_LocalInvocationIndex;
    s_sum[lane] = sum;
    barrier();
    if (lane == 0u) {
        vec2 total = vec2(0.0);
        for (uint i = 0u; i < LANES; ++i) total += s_sum[i];
        uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
        uint at = params.level[b].w + 2u * group;
        partial[at] = total.x;
        partial[at + 1u] = total.y;
    }
}
