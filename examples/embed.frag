#version 450
// examples/embed.c: the GLSL snippet of include/xrad.h, as an engine would
// write it: the fragment's surface parameters (s, t) from the interpolated
// attribute, then the atlas texel between the element samples.
layout(push_constant) uniform Push {
    mat4 clip_from_object;
    vec4 atlas; // atlas width, height; scale (exposure); unused
} pc;
layout(binding = 0) uniform sampler2D atlas;

layout(location = 0) in vec3 a;
layout(location = 1) flat in vec4 tile_n;

layout(location = 0) out vec4 color;

void main()
{
    vec2 st = vec2(a.z > 0.0 ? a.x / a.z : 0.5, a.y);
    vec2 uv = (tile_n.xy + 0.5 + clamp(st, 0.0, 1.0) * (tile_n.zw - 1.0)) / pc.atlas.xy;
    color = vec4(texture(atlas, uv).rgb * pc.atlas.z, 1.0);
}
