#version 450
// ID hemicube, fragment stage: the quad ID (surface + 1; 0, the clear
// value, is "nothing") and the distance of the point drawn from the
// hemicube's origin (m, float bits; spirv/shooting.glsl's depth rule for
// mesh faces). The radiosity variant's inputs are declared so that both
// fragment stages consume what the shared vertex stage writes.
layout(location = 0) flat in uint id;
layout(location = 1) centroid in vec3 uvw;
layout(location = 2) flat in vec4 tile;
layout(location = 3) flat in float front;
layout(location = 4) in vec3 rel;

layout(location = 0) out uvec2 out_id;

void main() { out_id = uvec2(id, floatBitsToUint(length(rel))); }
