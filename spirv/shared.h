/*
 * Struct layouts and binding numbers shared by C and GLSL. glslang defines
 * VULKAN when compiling for Vulkan; C sees plain typedefs with the same
 * std430 layout (only 4-byte scalars and 16-byte vec4s are used, so the two
 * agree without padding rules).
 */
#ifndef XRAD_SPIRV_SHARED_H
#define XRAD_SPIRV_SHARED_H

#ifndef VULKAN
#include <stdint.h>
typedef uint32_t uint;
typedef struct { float x, y, z, w; } vec4;
typedef struct { float m[16]; } mat4; /* column-major, as GLSL */
#endif

/* Display pass (src/passes/display.c, spirv/display.vert|frag). */
#define DISPLAY_BINDING_ATLAS 0
#define DISPLAY_MODE_NEAREST 0u       /* the sampler picks the nearest element */
#define DISPLAY_MODE_LINEAR 1u        /* the sampler interpolates bilinearly */
#define DISPLAY_MODE_LINEAR_SHADER 2u /* bilinear from texelFetch, where RGBA32F cannot be filtered */

struct display_push {
    mat4 clip_from_view; /* camera-relative world position (m) -> clip, reversed Z */
    vec4 atlas_size;     /* width, height, 1 / width, 1 / height in texels */
    uint mode;           /* DISPLAY_MODE_* */
    uint pad0, pad1, pad2;
};

/* Present pass (src/passes/present.c, spirv/present.vert|frag): the display
 * target's linear B to a window's 8-bit sRGB image. */
#define PRESENT_BINDING_SOURCE 0

struct present_push {
    float exposure;  /* display value = exposure x B, then clamped to [0, 1] */
    uint encode;     /* 1: the shader applies the sRGB transfer (UNORM swapchain) */
    uint tonemap;    /* an xrad_tonemap: PRESENT_TONEMAP_REINHARD divides by 1 + luminance */
    uint pad0;
};
#define PRESENT_TONEMAP_REINHARD 1 /* XRAD_TONEMAP_REINHARD */

/* Overlay (src/passes/overlay.c, spirv/overlay.vert|frag): text quads in
 * pixels over a window's image. clip = pixel x scale + offset. */
struct overlay_push {
    float scale_x, scale_y;   /* zoom x 2 / framebuffer size */
    float offset_x, offset_y; /* -1 + 2 x origin / framebuffer size */
};

#endif
