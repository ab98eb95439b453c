#version 450
// Atlas scatter pass (src/passes/atlas_scatter.c): per-element values (B)
// into the element texels of the radiosity atlas, which the radiosity
// hemicubes and the display sample bilinearly (thesis 4.1). Alpha is 1, 0
// where the element is buried (radiosity.h): a filter that must not drag
// free surface towards the dark samples under a box reads it
// (hemicube_radiosity.frag, OPEN_ONLY).
#extension GL_GOOGLE_include_directive : require
#include "radiosity.h"
#include "atlas_scatter_shared.h"

layout(local_size_x = ATLAS_SCATTER_GROUP) in;

layout(push_constant) uniform Push { atlas_scatter_push pc; };
layout(std430, binding = ATLAS_SCATTER_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = ATLAS_SCATTER_BINDING_VALUES) readonly buffer Values { vec4 values[]; };
layout(binding = ATLAS_SCATTER_BINDING_ATLAS, rgba32f) uniform writeonly image2D atlas;

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.element_count)
        return;
    float open = (elements[e].flags & GPU_ELEMENT_BURIED_ANY) != 0u ? 0.0 : 1.0;
    imageStore(atlas, ivec2(elements[e].texel_x, elements[e].texel_y), vec4(values[e].rgb, open));
}
