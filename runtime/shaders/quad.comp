// One quad layer over one eye of the composited output (runtime/xr_quad.cpp): each pixel's ray
// meets the quad (quad_layer.h), samples its sub-image bilinearly and blends in linear colour; the
// output stays sRGB-encoded RGBA8 as the compositor wrote it.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "wrs_common.h"
#include "quad_layer.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba8) uniform image2DArray outputImage;
layout(set = 0, binding = 1) uniform sampler2D quadImage;

layout(push_constant) uniform QuadPush {
    mat4 quad_from_eye;  // eye space -> quad space
    vec4 fov_tan;        // the eye's view (XrFovf tangents)
    vec4 uv_rect;        // sub-image: uv offset xy, uv scale zw in the quad's image
    vec4 size_flags;     // quad width, height (m); z: 1 if sRGB codes read through a UNORM view (an sRGB view decodes itself); w: bit 0 blend alpha, bit 1 unpremultiplied
    uvec4 target;        // x: output layer (eye), y: width, z: height
} pc;

void main() {
    uvec2 p = gl_GlobalInvocationID.xy;
    if (p.x >= pc.target.y || p.y >= pc.target.z) return;
    vec3 ray = wrs_pixel_ray(p.x, p.y, pc.target.y, pc.target.z, pc.fov_tan);
    vec3 origin = (pc.quad_from_eye * vec4(0.0, 0.0, 0.0, 1.0)).xyz;
    vec3 dir = (pc.quad_from_eye * vec4(ray, 0.0)).xyz;
    vec2 uv = wrs_quad_uv(origin, dir, pc.size_flags.xy);
    if (uv.x < 0.0) return;
    vec4 src = texture(quadImage, pc.uv_rect.xy + uv * pc.uv_rect.zw);
    if (pc.size_flags.z > 0.5) src.rgb = wrs_srgb_to_linear3(src.rgb);
    ivec3 q = ivec3(p, int(pc.target.x));
    vec4 dst = imageLoad(outputImage, q);
    uint flags = uint(pc.size_flags.w);
    vec3 lin = wrs_quad_blend(wrs_srgb_to_linear3(dst.rgb), src, (flags & 1u) != 0u, (flags & 2u) != 0u);
    vec3 enc = vec3(wrs_linear_to_srgb(lin.x), wrs_linear_to_srgb(lin.y), wrs_linear_to_srgb(lin.z));
    imageStore(outputImage, q, vec4(enc, 1.0));
}
