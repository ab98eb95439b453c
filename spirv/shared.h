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

#endif
