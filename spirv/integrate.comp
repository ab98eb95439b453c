#version 450
// Integrate pass (src/passes/integrate.c; thesis 2.2.2, Algorithm 4.1 line
// 8): the sum over a hemicube's pixels of radiosity x delta form factor,
// i.e. the irradiance-like gathered radiosity sum_j F_ij B_j of the
// hemicube's point. One workgroup per hemicube: every invocation sums a
// strided share of the weighted pixels (the top face and the upper halves
// of the side faces; the lower halves weigh 0), then a shared-memory tree
// adds the shares.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "integrate_shared.h"

layout(local_size_x = INTEGRATE_GROUP) in;

layout(push_constant) uniform Push { integrate_push pc; };
layout(binding = INTEGRATE_BINDING_HEMICUBES) uniform texture2DArray hemicubes;
layout(std430, binding = INTEGRATE_BINDING_TABLE) readonly buffer Table { float table[]; };
layout(std430, binding = INTEGRATE_BINDING_OUT) writeonly buffer Out { vec4 sums[]; };

shared vec3 partial[INTEGRATE_GROUP];

void main()
{
    uint h = gl_WorkGroupID.x;
    uint res = pc.res, face_px = res * res, half_px = face_px / 2u;
    uint weighted = face_px + 4u * half_px;
    vec3 sum = vec3(0.0);
    for (uint i = gl_LocalInvocationID.x; i < weighted; i += INTEGRATE_GROUP) {
        uint face, px; // px: row * res + col within the face
        if (i < face_px) {
            face = 0u;
            px = i;
        } else {
            uint j = i - face_px;
            face = 1u + j / half_px;
            px = half_px + j % half_px; // rows res/2 .. res-1: above the horizon
        }
        ivec3 at = ivec3(int(px % res), int(px / res), int(h * 5u + face));
        sum += texelFetch(hemicubes, at, 0).rgb * table[face * face_px + px];
    }
    partial[gl_LocalInvocationID.x] = sum;
    barrier();
    for (uint stride = INTEGRATE_GROUP / 2u; stride > 0u; stride /= 2u) {
        if (gl_LocalInvocationID.x < stride)
            partial[gl_LocalInvocationID.x] += partial[gl_LocalInvocationID.x + stride];
        barrier();
    }
    if (gl_LocalInvocationID.x == 0u)
        sums[pc.out_first + h] = vec4(partial[0] * pc.inv_scale, 0.0);
}
