#version 450
// Display pass, vertex stage: one vertex per element sample (src/passes/display.c).
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push { display_push pc; };

layout(location = 0) in vec3 in_pos;   // m, world relative to the camera
layout(location = 1) in vec2 in_uv;    // atlas texel centre of the element
layout(location = 2) in uvec4 in_tile; // the surface's tile: first and last texel

layout(location = 0) out vec2 uv;
layout(location = 1) flat out uvec4 tile;

void main()
{
    gl_Position = pc.clip_from_view * vec4(in_pos, 1.0);
    uv = in_uv;
    tile = in_tile;
}
