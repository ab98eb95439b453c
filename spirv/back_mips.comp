#version 450
// Mip levels of the back hemicubes (src/passes/back_mips.c; issue 16.2,
// thesis 6.2: "a pre-integration scheme such as mipmapping for the
// back-hemicubes will avoid undersampling"). One invocation per texel of
// every level >= 1 of every layer: the mean of the level-0 texels it
// covers, read straight from the hemicube (no level waits for another).
// A side face's lower half lies below the hemicube's base and is never
// drawn: its texels are left out of a mean, and a block that lies wholly
// there (a coarse level's lower rows) takes the lowest drawn rows instead,
// so that a bilinear tap at the horizon reads what lies just above it.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "cross_shared.h"
#include "hemicube.glsl"
#include "back_mips.glsl"

layout(local_size_x = BACK_MIPS_GROUP) in;

layout(push_constant) uniform Push { back_mips_push pc; };

layout(binding = BACK_MIPS_BINDING_BACK) uniform texture2DArray back;
layout(std430, binding = BACK_MIPS_BINDING_MIPS) writeonly buffer Mips { vec4 mips[]; };

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count)
        return;
    uint per_layer = back_mip_layer_texels(pc.res, pc.levels);
    uint layer = i / per_layer, at = i % per_layer;
    uint k = 1u, r = pc.res >> 1u;
    while (k < pc.levels && at >= r * r) {
        at -= r * r;
        k++;
        r >>= 1u;
    }
    uint block = 1u << k;
    uint x0 = (at % r) * block, y0 = (at / r) * block, y1 = y0 + block;
    if (layer % uint(HEMICUBE_FACES) != 0u) {
        uint half_res = pc.res / 2u;
        y0 = max(y0, half_res);
        if (y0 >= y1) {
            y0 = half_res;
            y1 = half_res + min(block, half_res);
        }
    }
    vec4 sum = vec4(0.0);
    for (uint y = y0; y < y1; y++)
        for (uint x = x0; x < x0 + block; x++)
            sum += texelFetch(back, ivec3(ivec2(x, y), int(layer)), 0);
    mips[i] = sum / float((y1 - y0) * block);
}
