// Reading a submitted colour texel: the one decoding every pass and the CPU reference share.
//
// A texel as a pass fetched it (through the view the compositor made of the image: linear, an sRGB
// image's UNORM view, its sRGB view, or the compose pass's output) becomes linear RGB, sanitised, with
// its validity in alpha. sRGB-encoded 8-bit input decodes through the table of 256 linear values, the
// same on both sides, whichever view it was read through (wrs_input_code recovers the code from a
// device's decode), so the GPU and the reference agree bit for bit.
//
// Include after declaring the table: WRS_SRGB8(k) is the linear value of code k. In GLSL, define
// WRS_SRGB_TABLE (a float[256] the pass reads: its buffer or its shared copy) before including; in C++
// it is wrs_srgb8_table().
#ifndef WRSFOV_WRS_INPUT_H
#define WRSFOV_WRS_INPUT_H

#include "wrs_common.h"

#ifdef __cplusplus
#define WRS_SRGB8(k) (::wrsfov::gpu::wrs_srgb8_table()[k])
#else
#define WRS_SRGB8(k) WRS_SRGB_TABLE[k]
#endif

WRS_BEGIN

WRS_FN vec3 wrs_decode_rgb(vec3 c, uint encoding) {
    if (!wrs_input_srgb8(encoding)) return c;
    return vec3(WRS_SRGB8(wrs_input_code(c.x, encoding)), WRS_SRGB8(wrs_input_code(c.y, encoding)),
                WRS_SRGB8(wrs_input_code(c.z, encoding)));
}

// Texel t read as `encoding` says: linear RGB, sanitised (wrs_sanitize_color), alpha 1 if usable.
WRS_FN vec4 wrs_decode_input(vec4 t, uint encoding) {
    bool valid;
    vec3 c = wrs_sanitize_color(wrs_decode_rgb(vec3(t), encoding), valid);
    valid = wrs_input_valid(valid, encoding, t.w);
    return vec4(c, valid ? 1.0f : 0.0f);
}

WRS_END

#endif
