// Atrium scene: procedural high-frequency materials (bricks, checkers, stripes, a text poster
// texture; filtered over the pixel footprint unless AtriumOptions::materialSamples is 1), simple
// lighting, sRGB colour, motion vectors in pixels and the linear depth change.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "atrium.glsl"

layout(set = 0, binding = 1) uniform sampler2D poster;

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec2 v_uv;
layout(location = 3) flat in uint v_material;
layout(location = 4) in vec4 v_prev_clip;
layout(location = 5) in float v_zcur;
layout(location = 6) in float v_zprev;
layout(location = 7) in vec4 v_cur_clip;

layout(location = 0) out vec4 out_color;   // written to an sRGB view: hardware encodes
layout(location = 1) out vec4 out_motion;  // RGBA16F: dx, dy (pixels), dz = z_prev - z_cur, 0

float checker(vec2 uv, float n) {
    vec2 c = floor(uv * n);
    return mod(c.x + c.y, 2.0);
}

vec3 bricks(vec2 uv) {
    vec2 b = uv * vec2(8.0, 16.0);
    if (mod(floor(b.y), 2.0) > 0.5) b.x += 0.5;
    vec2 f = fract(b);
    bool mortar = f.x < 0.06 || f.y < 0.1;
    float n = fract(sin(dot(floor(b), vec2(12.9898, 78.233))) * 43758.5453);
    return mortar ? vec3(0.75, 0.72, 0.68) : vec3(0.55 + 0.2 * n, 0.22 + 0.08 * n, 0.15);
}

float hash(vec2 c) { return fract(sin(dot(c, vec2(12.9898, 78.233))) * 43758.5453); }

// Foliage cut-out (material 7, the `thin` scene): in each cell of a 9 x 14 grid a leaf, an ellipse of
// random tilt and place; outside every leaf the fragment is discarded (an alpha test at the pixel
// centre, as engines test cut-outs: not anti-aliased).
bool leaf(vec2 uv) {
    vec2 g = uv * vec2(9.0, 14.0);
    for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
            vec2 c = floor(g) + vec2(i, j);
            vec2 centre = c + vec2(hash(c), hash(c + 5.3));
            float a = 6.2831853 * hash(c + 11.7);
            vec2 d = g - centre;
            d = vec2(cos(a) * d.x + sin(a) * d.y, -sin(a) * d.x + cos(a) * d.y);
            if (dot(d / vec2(0.55, 0.16), d / vec2(0.55, 0.16)) < 1.0) return true;
        }
    return false;
}

vec3 material(vec2 uv) {
    vec3 base;
    if (v_material == 0u) {
        base = mix(vec3(0.08), vec3(0.85), checker(uv, 16.0));           // floor
    } else if (v_material == 1u) {
        base = bricks(uv);                                                 // walls
    } else if (v_material == 2u) {
        float s = step(0.5, fract(uv.y * 40.0));
        base = mix(vec3(0.2, 0.35, 0.7), vec3(0.9, 0.9, 0.8), s);           // columns: fine stripes
    } else if (v_material == 3u) {
        base = texture(poster, uv, log2(cam.light.z)).rgb;                 // posters with text
    } else if (v_material == 4u) {
        base = mix(vec3(0.9, 0.3, 0.1), vec3(0.1, 0.1, 0.1), checker(uv, 6.0));  // moving objects
    } else if (v_material == 6u) {
        base = vec3(0.10, 0.11, 0.13);                                       // metal tubes (thin)
    } else if (v_material == 7u) {
        vec2 c = floor(uv * vec2(9.0, 14.0));                                // leaves (thin)
        float n = hash(c + 17.0);
        base = mix(vec3(0.08, 0.30, 0.05), vec3(0.35, 0.62, 0.12), n);
    } else {
        base = vec3(0.6, 0.6, 0.65);                                         // ceiling
    }
    return base;
}

void main() {
    // Procedural materials filtered over the pixel's footprint, as a mipmapped texture would be: four
    // rotated-grid shading samples in the material's uv (the 4x pattern of MSAA), averaged in linear
    // colour. With one sample the material is point-sampled at the pixel centre (aliased).
    // The cut-out's test first, its discard after the filtered material: the derivatives it takes need the
    // whole quad of fragments.
    bool cut = v_material == 7u && !leaf(v_uv);
    vec3 base;
    if (cam.light.y > 1.5) {
        vec2 dx = dFdx(v_uv) * cam.light.z, dy = dFdy(v_uv) * cam.light.z;
        const vec2 o[4] = vec2[4](vec2(-0.375, -0.125), vec2(0.125, -0.375), vec2(0.375, 0.125), vec2(-0.125, 0.375));
        base = vec3(0.0);
        for (int i = 0; i < 4; ++i) base += material(v_uv + dx * o[i].x + dy * o[i].y);
        base *= 0.25;
    } else {
        base = material(v_uv);
    }
    if (cut) discard;
    vec3 n = normalize(v_normal);
    vec3 l = normalize(vec3(0.3, 1.0, 0.5));
    float light = cam.light.x * (0.45 + 0.55 * max(dot(n, l), 0.0));
    vec3 colour = base * light;
    // View-dependent highlights of the `thin` scene: Blinn-Phong from two lights under the ceiling on the
    // metal tubes, the leaves and (AtriumCamera::light.w) the floor; they move with the eye, not the surface.
    float ks = v_material == 6u ? 1.2 : v_material == 7u ? 0.3 : (v_material == 0u && cam.light.w > 0.5) ? 0.45 : 0.0;
    if (ks > 0.0) {
        float shininess = v_material == 6u ? 90.0 : v_material == 7u ? 24.0 : 60.0;
        vec3 v = normalize(cam.eye_pos.xyz - v_world);
        if (dot(n, v) < 0.0) n = -n;  // tubes and leaves are seen from both sides
        float spec = 0.0;
        for (int i = 0; i < 2; ++i) {
            vec3 lp = vec3(0.0, 3.7, i == 0 ? -4.0 : -10.0);
            vec3 pl = normalize(lp - v_world);
            spec += pow(max(dot(n, normalize(pl + v)), 0.0), shininess) * max(dot(n, pl), 0.0);
        }
        colour += vec3(cam.light.x * ks * spec);
    }
    out_color = vec4(colour, 1.0);

    // Both ends from interpolated clip positions computed the same way (not gl_FragCoord), so a
    // point that did not move gets exactly zero motion rather than interpolation rounding.
    vec2 cur = (v_cur_clip.xy / v_cur_clip.w * 0.5 + 0.5) * cam.viewport.xy;
    vec2 prev = (v_prev_clip.xy / v_prev_clip.w * 0.5 + 0.5) * cam.viewport.xy;
    out_motion = vec4(prev - cur, v_zprev - v_zcur, 0.0);
}
