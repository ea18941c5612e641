// Quad layers (XrCompositionLayerQuad) over the composited view: where a pixel's ray meets the quad
// and how its colour is blended, shared by quad.comp and the runtime's C++ tests.
#ifndef WRSFOV_QUAD_LAYER_H
#define WRSFOV_QUAD_LAYER_H

#include "glsl_cpp.h"

WRS_BEGIN

// The quad lies in the z = 0 plane of its own space, centred at the origin, x right, y up, with
// extent size (metres). Given the ray origin and direction in quad space, the quad's texture
// coordinate hit (u right, v down, both in [0, 1]), or (-1, -1) when the ray misses it or runs
// parallel to it or away from it.
WRS_FN vec2 wrs_quad_uv(vec3 origin, vec3 dir, vec2 size) {
    if (abs(dir.z) < 1e-12f) return vec2(-1.0f);
    float s = -origin.z / dir.z;
    if (!(s > 0.0f)) return vec2(-1.0f);
    vec2 hit = vec2(origin.x + s * dir.x, origin.y + s * dir.y);
    vec2 uv = vec2(hit.x / size.x + 0.5f, 0.5f - hit.y / size.y);
    if (uv.x < 0.0f || uv.x > 1.0f || uv.y < 0.0f || uv.y > 1.0f) return vec2(-1.0f);
    return uv;
}

// Source-over in linear colour. blend_alpha: XR_COMPOSITION_LAYER_BLEND_TEXTURE_SOURCE_ALPHA_BIT
// (otherwise the quad is opaque); unpremultiplied: XR_COMPOSITION_LAYER_UNPREMULTIPLIED_ALPHA_BIT
// (otherwise the texture's colour is already multiplied by its alpha).
WRS_FN vec3 wrs_quad_blend(vec3 dst, vec4 src, bool blend_alpha, bool unpremultiplied) {
    if (!blend_alpha) return vec3(src.x, src.y, src.z);
    float a = clamp(src.w, 0.0f, 1.0f);
    vec3 c = unpremultiplied ? vec3(src.x, src.y, src.z) * a : vec3(src.x, src.y, src.z);
    return c + dst * (1.0f - a);
}

WRS_END

#endif
