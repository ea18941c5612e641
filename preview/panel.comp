// The preview's panel pass: one panel of the preview image per dispatch. Copies one eye of the
// compositor's output (or of the reference, their difference as an error map, or FovVideoVDP's
// visible distortion) into the preview image and draws the gaze marker and the fovea /
// mid-periphery circles at their eccentricities, computed with the compositor's own ray and angle
// functions (shaders/wrs_common.h).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "wrs_common.h"
#include "panel_params.h"

layout(local_size_x = WRS_GROUP_X, local_size_y = WRS_GROUP_Y, local_size_z = 1) in;

layout(set = 0, binding = 0) uniform sampler2DArray outputImage;     // RGBA8, sRGB-encoded values
layout(set = 0, binding = 1) uniform sampler2DArray referenceImage;  // same layout, unfoveated
layout(std430, set = 0, binding = 2) readonly buffer Strip { uint strip[]; };  // RGBA8, premultiplied
layout(set = 0, binding = 3, rgba8) uniform writeonly image2D target;  // the preview image (UNORM view)
// Visible distortion in JOD units per eye (eye-major rows of size.x; zeros when none was computed).
layout(std430, set = 0, binding = 4) readonly buffer Visible { float visible[]; };
layout(push_constant) uniform Push { PanelPush pc; };

// Error ramp: black -> purple -> orange -> light yellow.
vec3 heat(float t) {
    t = clamp(t, 0.0, 1.0);
    vec3 c0 = vec3(0.0), c1 = vec3(0.35, 0.05, 0.55), c2 = vec3(0.95, 0.45, 0.1), c3 = vec3(1.0, 1.0, 0.75);
    if (t < 1.0 / 3.0) return mix(c0, c1, t * 3.0);
    if (t < 2.0 / 3.0) return mix(c1, c2, t * 3.0 - 1.0);
    return mix(c2, c3, t * 3.0 - 2.0);
}

float eccentricity(ivec2 p) {
    return wrs_eccentricity_deg(wrs_pixel_ray(uint(p.x), uint(p.y), pc.size.x, pc.size.y, pc.fov_tan), pc.gaze.xyz);
}

// True where the pixel lies on the circle of eccentricity `r` degrees, drawn about 1.5 pixels wide:
// the distance in degrees is turned into pixels with the local angular size of a pixel.
bool on_circle(float e, float deg_per_px, float r) { return abs(e - r) <= 0.75 * deg_per_px; }

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (p.x >= int(pc.size.x) || p.y >= int(pc.size.y)) return;
    uint kind = uint(pc.panel.z);
    int eye = pc.panel.w;
    vec3 c;
    if (kind == WRS_PANEL_STRIP) {
        uint v = strip[uint(p.y) * pc.size.x + uint(p.x)];
        vec4 o = unpackUnorm4x8(v);  // premultiplied text over a dark background
        c = o.rgb + (1.0 - o.a) * vec3(0.08);
        imageStore(target, pc.panel.xy + p, vec4(c, 1.0));
        return;
    }
    vec3 out_c = texelFetch(outputImage, ivec3(p, eye), 0).rgb;
    if (kind == WRS_PANEL_OUTPUT) {
        c = out_c;
    } else {
        vec3 ref_c = texelFetch(referenceImage, ivec3(p, eye), 0).rgb;
        if (kind == WRS_PANEL_REFERENCE) {
            c = ref_c;
        } else if (kind == WRS_PANEL_VISIBLE) {
            c = heat(visible[(uint(eye) * pc.size.y + uint(p.y)) * pc.size.x + uint(p.x)] * pc.radii.w);
        } else {
            vec3 d = abs(out_c - ref_c);
            c = heat(max(d.r, max(d.g, d.b)) * pc.radii.y);
        }
    }

    uint flags = pc.size.w;
    if ((flags & WRS_PANEL_CIRCLES) != 0u) {
        float e = eccentricity(p);
        // Angular size of this pixel from its right / lower neighbour (left / upper at the edge).
        ivec2 qx = ivec2(p.x + 1 < int(pc.size.x) ? p.x + 1 : p.x - 1, p.y);
        ivec2 qy = ivec2(p.x, p.y + 1 < int(pc.size.y) ? p.y + 1 : p.y - 1);
        float ex = eccentricity(qx) - e, ey = eccentricity(qy) - e;
        float deg_per_px = max(sqrt(ex * ex + ey * ey), 1e-4);
        if (on_circle(e, deg_per_px, pc.radii.x)) c = vec3(WRS_MID_R, WRS_MID_G, WRS_MID_B) / 255.0;
        if (on_circle(e, deg_per_px, pc.gaze.w)) c = vec3(WRS_FOVEA_R, WRS_FOVEA_G, WRS_FOVEA_B) / 255.0;
    }
    if ((flags & WRS_PANEL_MARKER) != 0u && pc.gaze.z < 0.0) {
        // The gaze ray through the image plane, in continuous pixel coordinates (centres at +0.5).
        vec2 t = pc.gaze.xy / -pc.gaze.z;
        vec2 g = vec2((t.x - pc.fov_tan.x) / (pc.fov_tan.y - pc.fov_tan.x) * float(pc.size.x),
                      (pc.fov_tan.z - t.y) / (pc.fov_tan.z - pc.fov_tan.w) * float(pc.size.y));
        float d = length(vec2(p) + 0.5 - g);
        if (d <= pc.radii.z) c = vec3(WRS_MARKER_R, WRS_MARKER_G, WRS_MARKER_B) / 255.0;
        else if (d <= pc.radii.z + 1.25) c = vec3(0.0);
    }
    imageStore(target, pc.panel.xy + p, vec4(c, 1.0));
}
