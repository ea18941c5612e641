// FovVideoVDP pass 1, display model (detail::displayLuminance): the frame's sRGB-encoded test
// (z = 0) and reference (z = 1) images to absolute luminance in cd/m², into the window slot
// push.at.y.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(local_size_x = FVVDP_GROUP, local_size_y = FVVDP_GROUP, local_size_z = 1) in;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    uvec2 size = params.image.xy;
    if (any(greaterThanEqual(p, size))) return;
    uint npix = size.x * size.y, img = gl_GlobalInvocationID.z, i = p.y * size.x + p.x;
    uint s = 3u * (img * npix + i);
    window_lum[(push.at.y * 2u + img) * npix + i] =
        fvvdp_display_luminance(vec3(rgb[s], rgb[s + 1u], rgb[s + 2u]), params.display.x, params.display.y);
}
