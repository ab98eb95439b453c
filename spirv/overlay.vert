#version 450
// Overlay, vertex stage (src/passes/overlay.c): stb_easy_font's vertices,
// in pixels from the text's origin with y down, to clip space (Vulkan's
// clip y points down too).
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push { overlay_push pc; };

layout(location = 0) in vec2 pixel;
layout(location = 1) in vec4 color; // UNORM bytes

layout(location = 0) out vec4 v_color;

void main()
{
    v_color = color;
    gl_Position = vec4(pixel * vec2(pc.scale_x, pc.scale_y) + vec2(pc.offset_x, pc.offset_y),
                       0.0, 1.0);
}
