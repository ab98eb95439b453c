#version 450
// Hemicube cull pass (src/passes/hemicube_cull.c): one invocation per
// cluster of hemicube vertices writes that cluster's indirect draw for the
// shot's hemicubes, with no vertices where no hemicube can see any of its
// triangles:
//  - behind: every corner of its box lies below the plane of every
//    hemicube's base (the hemicube sees only z > near > 0: those triangles
//    are clipped whole, so leaving them out changes no texel);
//  - facing away: its triangles are on the outside of a closed mesh and
//    every one of them faces away from every origin outside that mesh's
//    box (a ray from outside a closed mesh meets one of its front faces
//    before any back face, so the nearest texel is the same but along a
//    silhouette, where a back face can win the depth test by rounding).
//    The cone test: from an origin o at distance d > r from the cluster's
//    centre, at angle alpha from the cone's axis, the faces (normals within
//    theta of the axis, points within r of the centre) all face away when
//    alpha - theta > acos(-r / d): then n.(o - p) <= d cos(alpha - theta)
//    + r < 0 for every face normal n and point p.
#extension GL_GOOGLE_include_directive : require
#include "radiosity.h"
#include "hemicube_cull_shared.h"

layout(local_size_x = CULL_GROUP) in;

layout(push_constant) uniform Push { cull_push pc; };

layout(std430, binding = CULL_BINDING_CLUSTERS) readonly buffer Clusters { gpu_cluster clusters[]; };
layout(std430, binding = CULL_BINDING_FRAMES) readonly buffer Frames { gpu_shooter frames[]; };
layout(std430, binding = CULL_BINDING_STATUS) readonly buffer Status { uint status[]; };
layout(std430, binding = CULL_BINDING_COMMANDS) writeonly buffer Commands { uint commands[]; };

bool seen_from(gpu_cluster c, vec3 o, vec3 z)
{
    // Behind the base plane: the box's highest corner along z.
    float top = dot(c.center.xyz - o, z) + dot(c.half_size.xyz, abs(z));
    if (top < -pc.margin)
        return false;
    float theta = c.half_size.w;
    if (theta < 0.0)
        return true;
    // Inside the closed mesh's box: the mesh may enclose o.
    if (all(greaterThan(o, c.object_lo.xyz - pc.margin)) &&
        all(lessThan(o, c.object_hi.xyz + pc.margin)))
        return true;
    vec3 v = o - c.center.xyz;
    float d = length(v), r = c.center.w + pc.margin;
    if (d <= r)
        return true;
    float alpha = acos(clamp(dot(v / d, c.cone_axis.xyz), -1.0, 1.0));
    // 1e-4 rad of slack for acos's rounding.
    return !(alpha - theta > acos(-r / d) + 1e-4);
}

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= pc.cluster_count)
        return;
    gpu_cluster c = clusters[k];
    uint hemicubes = pc.count_word == CULL_NO_COUNT ? pc.count : status[pc.count_word];
    bool seen = false;
    for (uint h = 0; h < hemicubes && !seen; h++) {
        gpu_shooter f = frames[pc.first + h];
        seen = seen_from(c, f.pos_area.xyz, normalize(f.normal.xyz));
    }
    // VkDrawIndexedIndirectCommand: indexCount, instanceCount, firstIndex,
    // vertexOffset, firstInstance.
    uint w = CULL_COMMAND_WORDS * k;
    commands[w + 0] = seen ? c.index_count : 0u;
    commands[w + 1] = pc.instances != 0u ? pc.instances : status[pc.instance_word];
    commands[w + 2] = c.first_index;
    commands[w + 3] = 0u;
    commands[w + 4] = 0u;
}
