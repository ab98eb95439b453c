#version 450
// Integrate pass (src/passes/integrate.c; thesis 2.2.2, Algorithm 4.1 line
// 8): the sum over a hemicube's pixels of radiosity x delta form factor,
// i.e. the irradiance-like gathered radiosity sum_j F_ij B_j of the
// hemicube's point. One workgroup per hemicube: every invocation sums a
// strided share of the weighted pixels (the top face and the upper halves
// of the side faces; the lower halves weigh 0), then a shared-memory tree
// adds the shares. With pc.ring, also the mean radiosity of the horizon
// ring (integrate_shared.h): what a mesh face tilted from its group's
// hemicube sees below that hemicube's horizon (spirv/cross_update.comp).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "integrate_shared.h"
#include "hemicube.glsl"

layout(local_size_x = INTEGRATE_GROUP) in;

layout(push_constant) uniform Push { integrate_push pc; };
layout(binding = INTEGRATE_BINDING_HEMICUBES) uniform texture2DArray hemicubes;
layout(std430, binding = INTEGRATE_BINDING_TABLE) readonly buffer Table { float table[]; };
layout(std430, binding = INTEGRATE_BINDING_OUT) writeonly buffer Out { vec4 sums[]; };

shared vec3 partial[INTEGRATE_GROUP];
shared vec4 partial_ring[INTEGRATE_GROUP];

// The horizon ring (integrate_push.ring): side-face texels with v below
// this, directions within about 15 degrees above the horizon
// (cross_update.comp says what it is for).
const float RING_V = 0.27;

void main()
{
    uint h = gl_WorkGroupID.x;
    uint res = pc.res, face_px = res * res;
    uint weighted = 3u * face_px; // the top face and four upper halves
    vec3 sum = vec3(0.0);
    vec4 ring = vec4(0.0);
    for (uint i = gl_LocalInvocationID.x; i < weighted; i += INTEGRATE_GROUP) {
        uvec2 t;
        uint face = hemicube_weighted_texel(i, res, t);
        ivec3 at = ivec3(ivec2(t), int(h * 5u + face));
        vec3 b = texelFetch(hemicubes, at, 0).rgb;
        vec3 w = b * table[face * face_px + t.y * res + t.x];
        sum += w;
        if (pc.ring != 0u) {
            vec3 d = hemicube_texel_direction(face, t, res);
            float r2 = dot(d, d);
            if (face != 0u && d.z < RING_V)
                ring += vec4(b, 1.0) / (r2 * sqrt(r2)); // by solid angle
        }
    }
    uint l = gl_LocalInvocationID.x;
    partial[l] = sum;
    partial_ring[l] = ring;
    barrier();
    for (uint stride = INTEGRATE_GROUP / 2u; stride > 0u; stride /= 2u) {
        if (l < stride) {
            partial[l] += partial[l + stride];
            partial_ring[l] += partial_ring[l + stride];
        }
        barrier();
    }
    if (l == 0u) {
        sums[pc.out_first + h] = vec4(partial[0] * pc.inv_scale, 0.0);
        if (pc.ring != 0u) {
            vec4 r = partial_ring[0];
            sums[pc.ring_first + h] = vec4(r.w > 0.0 ? r.rgb / r.w * pc.inv_scale : vec3(0.0), 0.0);
        }
    }
}
