#version 450
// Present pass, fragment stage: exposure x B of the display target's pixel
// (same size as the window), with pc.tonemap REINHARD divided by 1 + its
// luminance, clamped, sRGB-encoded here only where the window's format does
// not encode it itself. The tone mapping is the PNG writer's
// (src/core/image_png.c, README "Images"), so a window and a PNG of one
// frame show the same values (tests/passes/test_present.c).
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
    vec3 c = pc.exposure * b;
    // Reinhard et al. 2002, eq. 3, on the Rec. 709 luminance.
    if (pc.tonemap == PRESENT_TONEMAP_REINHARD)
        c /= 1.0 + max(dot(c, vec3(0.2126, 0.7152, 0.0722)), 0.0);
    c = clamp(c, 0.0, 1.0);
    color = vec4(pc.encode != 0u ? srgb_encode(c) : c, 1.0);
}
