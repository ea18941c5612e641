// FovVideoVDP pass 1, display model (detail::displayLuminance): the frame's sRGB-encoded test
// (z = 0) and reference (z = 1) images to absolute luminance in cd/m², four pixels per invocation,
// into the window slot push.at.y.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "fvvdp_common.glsl"

layout(local_size_x = FVVDP_QUAD_GROUP, local_size_y = 1, local_size_z = 1) in;

void main() {
    uint q = fvvdp_quad(), quads = params.image.w, img = gl_GlobalInvocationID.z;
    if (q >= quads) return;
    // Pixels 4q .. 4q + 3 are the 12 floats of three vec4.
    uint s = 3u * (img * quads + q);
    vec4 a = rgb[s], b = rgb[s + 1u], c = rgb[s + 2u];
    float peak = params.display.x, black = params.display.y;
    window_lum[(push.at.y * 2u + img) * quads + q] =
        vec4(fvvdp_display_luminance(a.xyz, peak, black), fvvdp_display_luminance(vec3(a.w, b.xy), peak, black),
             fvvdp_display_luminance(vec3(b.zw, c.x), peak, black), fvvdp_display_luminance(c.yzw, peak, black));
}
