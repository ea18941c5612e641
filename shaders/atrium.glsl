// Shared by atrium.vert / atrium.frag: per-draw push constants and per-eye camera block.
#ifndef WRSFOV_ATRIUM_GLSL
#define WRSFOV_ATRIUM_GLSL
#include "wrs_common.h"
#include "atrium_params.h"

layout(std140, set = 0, binding = 0) uniform CameraBlock { AtriumCamera cam; };
layout(push_constant) uniform DrawBlock { AtriumDraw draw; };
#endif
