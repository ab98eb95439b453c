#version 450
// Select pass, step 1 (src/passes/select.c): the area-weighted unshot power
// of every surface, sum_e |luminance(Bu_e)| A_e in W, the quantity thesis
// 4.3.2 FINDSHOOTINGQUAD ranks quads by. The absolute value lets negative
// light (the dynamic methods) be shot as well, element by element: a
// surface holding a shadow's negative light next to positive light (a
// floor a moving box darkens here and lights there) has both to shoot,
// which the absolute value of their sum would hide. One invocation per surface; the
// elements of a surface are contiguous (src/scene/scene.h).
#extension GL_GOOGLE_include_directive : require
#include "radiosity.h"
#include "select_shared.h"

layout(local_size_x = SELECT_POWER_GROUP) in;

layout(push_constant) uniform Push { select_push pc; };

layout(std430, binding = SELECT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = SELECT_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = SELECT_BINDING_BU) readonly buffer Unshot { vec4 Bu[]; };
layout(std430, binding = SELECT_BINDING_POWER) writeonly buffer Power { float power[]; };

// Rec. 709 luminance weights.
const vec3 LUMA = vec3(0.2126, 0.7152, 0.0722);

void main()
{
    uint s = gl_GlobalInvocationID.x;
    if (s >= pc.surface_count)
        return;
    uint first = surfaces[s].first_element;
    uint n = surfaces[s].nu * surfaces[s].nv;
    float sum = 0.0;
    for (uint k = 0u; k < n; k++)
        sum += abs(dot(Bu[first + k].rgb, LUMA)) * elements[first + k].pos_area.w;
    power[s] = sum;
}
