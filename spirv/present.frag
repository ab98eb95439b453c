#version 450
// Present pass, fragment stage: exposure x B of the display target's pixel
// (same size as the window), clamped, sRGB-encoded here only where the
// window's format does not encode it itself. The tone mapping is the PNG
// writer's (README "Images": exposure only), so a window and a PNG of one
// frame show the same values.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push { present_push pc; };
layout(binding = PRESENT_BINDING_SOURCE) uniform sampler2D source;

layout(location = 0) out vec4 color;

vec3 srgb_encode(vec3 c)
{
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

void main()
{
    vec3 b = texelFetch(source, ivec2(gl_FragCoord.xy), 0).rgb;
    vec3 c = clamp(pc.exposure * b, 0.0, 1.0);
    color = vec4(pc.encode != 0u ? srgb_encode(c) : c, 1.0);
}
