// Parameters of the atrium scene renderer (scenes/atrium.cpp), shared by C++ and GLSL.
#ifndef WRSFOV_ATRIUM_PARAMS_H
#define WRSFOV_ATRIUM_PARAMS_H

#include "glsl_cpp.h"

WRS_BEGIN

// One eye's camera for the current and the previous frame (motion vectors come from the difference).
struct AtriumCamera {
    mat4 view_proj;       // world -> clip, this frame
    mat4 prev_view_proj;  // world -> clip, previous frame
    vec4 viewport;        // width, height, near, far
    vec4 eye_pos;         // world position of the eye, w: reversed-Z (1) or not (0)
    mat4 view;            // world -> view, this frame (linear depth)
    mat4 prev_view;       // world -> view, previous frame
    vec4 light;           // x: scale of the room light (the `dynamic` scene dims it), y: shading samples
                          // per pixel of the procedural materials (1 or 4, AtriumOptions::materialSamples),
                          // z: the footprint the materials and the poster are filtered over, as a fraction of
                          // the view's pixel (1; a wide view rendered for temporal upsampling: the display's
                          // density over its own, a texture LOD bias of log2 z), w: the `thin` scene's
                          // specular floor (1) or none (0)
};

// Per draw: object transform now and one frame ago, material.
struct AtriumDraw {
    mat4 model;
    mat4 prev_model;
};

WRS_END

#ifdef __cplusplus
static_assert(sizeof(wrsfov::gpu::AtriumCamera) == 4 * 64 + 48);
static_assert(sizeof(wrsfov::gpu::AtriumDraw) == 128);
#endif

#endif
