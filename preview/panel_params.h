// Push constants of the preview's panel pass (preview/panel.comp), shared by C++ and GLSL.
// One dispatch per panel of the preview image; 16-byte rows, explicit padding.
#ifndef WRSFOV_PREVIEW_PANEL_PARAMS_H
#define WRSFOV_PREVIEW_PANEL_PARAMS_H

#ifdef __cplusplus
#include "shaders/glsl_cpp.h"
#else
#include "glsl_cpp.h"
#endif

// What a panel shows.
#define WRS_PANEL_OUTPUT 0u     // the compositor's output of one eye
#define WRS_PANEL_REFERENCE 1u  // the unfoveated reference of the same frame
#define WRS_PANEL_ERROR 2u      // |output - reference|, colour-mapped
#define WRS_PANEL_STRIP 3u      // the stats strip: dark background under the CPU-drawn text
#define WRS_PANEL_VISIBLE 4u    // FovVideoVDP's visible distortion (JOD units, from the CPU), colour-mapped

// Flags (PanelPush.size.w).
#define WRS_PANEL_CIRCLES 1u  // fovea and mid-periphery circles at their eccentricities
#define WRS_PANEL_MARKER 2u   // the gaze marker (only for a valid, non-fallback gaze)

// Overlay colours (sRGB-encoded, 0..255); tests look for them in screenshots.
#define WRS_MARKER_R 255u
#define WRS_MARKER_G 0u
#define WRS_MARKER_B 255u
#define WRS_FOVEA_R 0u
#define WRS_FOVEA_G 255u
#define WRS_FOVEA_B 255u
#define WRS_MID_R 255u
#define WRS_MID_G 200u
#define WRS_MID_B 0u

WRS_BEGIN

struct PanelPush {
    ivec4 panel;   // x, y: origin in the preview image; z: WRS_PANEL_*; w: eye (layer of the output image)
    uvec4 size;    // x, y: panel size (one eye's image); z: preview image width; w: WRS_PANEL_CIRCLES, WRS_PANEL_MARKER flags
    vec4 fov_tan;  // the eye's field of view: tan left, right, up, down
    vec4 gaze;     // xyz: unit gaze direction the compositor used; w: fovea radius r_f in degrees
    vec4 radii;    // x: mid-periphery radius r_m in degrees; y: error-map gain; z: marker radius (pixels);
                   // w: visible-difference gain (1 / the JOD shown at the top of the ramp)
};

WRS_END

#ifdef __cplusplus
static_assert(sizeof(wrsfov::gpu::PanelPush) == 80);
#endif

#endif
