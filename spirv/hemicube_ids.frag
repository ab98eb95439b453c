#version 450
// ID hemicube, fragment stage: the quad ID (surface + 1; 0, the clear
// value, is "nothing"). The radiosity variant's inputs are declared so that
// both fragment stages consume what the shared vertex stage writes.
layout(location = 0) flat in uint id;
layout(location = 1) centroid in vec3 uvw;
layout(location = 2) flat in vec4 tile;
layout(location = 3) flat in float front;
layout(location = 4) in vec3 rel;

layout(location = 0) out uint out_id;

void main() { out_id = id; }
