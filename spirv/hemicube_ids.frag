#version 450
// ID hemicube, fragment stage: the quad ID (surface + 1; 0, the clear
// value, is "nothing") of the triangle drawn (its provoking vertex's,
// hemicube_shared.h) and the distance of the point drawn from the
// hemicube's origin (m, float bits; spirv/shooting.glsl's depth rule for
// mesh faces). The radiosity variant's inputs are declared so that both
// fragment stages consume what the shared vertex stage writes.
layout(location = 0) flat in uvec2 ids; // surface, triangle
layout(location = 1) flat in vec3 origin;
layout(location = 2) in vec3 rel;
layout(location = 3) centroid in vec3 rel_c;
layout(location = 4) flat in uint own;

layout(location = 0) out uvec2 out_id;

void main() { out_id = uvec2(ids.x + 1u, floatBitsToUint(length(rel))); }
