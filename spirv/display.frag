#version 450
// Display pass, fragment stage: the linear radiosity B of the surface, no
// tone mapping. Texture coordinates run between the element samples of one
// tile, whose outer texel centres lie on the surface edges (thesis 4.1), so
// bilinear interpolation never needs a texel of another tile; clamping to
// the tile's texel centres keeps rounding from reaching one.
#extension GL_GOOGLE_include_directive : require
#include "shared.h"

layout(push_constant) uniform Push { display_push pc; };
layout(binding = DISPLAY_BINDING_ATLAS) uniform sampler2D atlas;

layout(location = 0) in vec2 uv;
layout(location = 1) flat in uvec4 tile;

layout(location = 0) out vec4 color;

void main()
{
    vec2 lo = (vec2(tile.xy) + 0.5) * pc.atlas_size.zw;
    vec2 hi = (vec2(tile.zw) + 0.5) * pc.atlas_size.zw;
    vec2 p = clamp(uv, lo, hi);
    vec3 b;
    if (pc.mode == DISPLAY_MODE_LINEAR_SHADER) {
        // Texel space with texel centres on integers.
        vec2 t = p * pc.atlas_size.xy - 0.5;
        ivec2 first = ivec2(tile.xy), last = ivec2(tile.zw);
        ivec2 i0 = clamp(ivec2(floor(t)), first, last);
        ivec2 i1 = min(i0 + 1, last);
        vec2 f = clamp(t - vec2(i0), 0.0, 1.0);
        vec3 b00 = texelFetch(atlas, i0, 0).rgb;
        vec3 b10 = texelFetch(atlas, ivec2(i1.x, i0.y), 0).rgb;
        vec3 b01 = texelFetch(atlas, ivec2(i0.x, i1.y), 0).rgb;
        vec3 b11 = texelFetch(atlas, i1, 0).rgb;
        b = mix(mix(b00, b10, f.x), mix(b01, b11, f.x), f.y);
    } else {
        b = texture(atlas, p).rgb;
    }
    // Alpha marks covered pixels: 1 here, 0 where the clear shows.
    color = vec4(b, 1.0);
}
