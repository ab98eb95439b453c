#version 450
// ID hemicube, fragment stage: the quad ID (surface + 1; 0, the clear
// value, is "nothing") of the triangle drawn (hemicube_shared.h) and the
// distance of the point drawn from the hemicube's origin (m, float bits;
// spirv/shooting.glsl's depth rule for mesh faces).
#extension GL_GOOGLE_include_directive : require
#include "hemicube_shared.h"

layout(std430, binding = HEMICUBE_BINDING_TRIANGLES) readonly buffer Triangles {
    gpu_hemicube_triangle triangles[];
};

layout(location = 0) flat in uint first_triangle;
layout(location = 1) flat in vec3 origin;
layout(location = 2) centroid in vec3 rel;

layout(location = 0) out uvec2 out_id;

void main()
{
    uint t = first_triangle + uint(gl_PrimitiveID);
    out_id = uvec2(triangles[t].surface + 1u, floatBitsToUint(length(rel)));
}
