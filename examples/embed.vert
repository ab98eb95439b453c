#version 450
// examples/embed.c: a surface drawn with xrad's radiosity. `a` is the
// per-vertex attribute include/xrad.h ("A surface and where its radiosity
// lies in the atlas") defines; tile_n the surface's tile and element grid.
layout(push_constant) uniform Push {
    mat4 clip_from_object; // projection * view * the object's pose
    vec4 atlas;            // atlas width, height; scale; unused
} pc;

layout(location = 0) in vec3 in_pos;    // m, object space
layout(location = 1) in vec3 in_a;      // (s w, t, w)
layout(location = 2) in vec4 in_tile_n; // tile_x, tile_y, nu, nv

layout(location = 0) out vec3 a;
layout(location = 1) flat out vec4 tile_n;

void main()
{
    gl_Position = pc.clip_from_object * vec4(in_pos, 1.0);
    a = in_a;
    tile_n = in_tile_n;
}
