#version 450
// Reconstruct pass (src/passes/reconstruct.c): thesis Algorithm 4.2
// RECONSTRUCTIONSHADER, one invocation per receiving element, looping over
// every shooter of the shot. Visibility: the element's surface ID in the
// shooter's ID hemicube, or in one of the 8 texels around it (nearest-texel
// check, thesis 4.3.3: element samples lie on surface edges, where the
// texel hit may belong to the neighbour). Form factor: the disk
// approximation of eq. 2.2.7, split into g x g sub-disks over the shooter
// patch when area / distance^2 is large (4.3.3 "Adaptive form factor
// subdivision"). Eq. 2.2.8: dB = rho B_s A_s (1/m) sum_k cos cos / (pi r_k^2
// + A_s / m), added to B and Bu. The shooter's own surface receives nothing.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "select_shared.h"
#include "reconstruct_shared.h"
#include "hemicube.glsl"

layout(local_size_x = RECONSTRUCT_GROUP) in;

layout(push_constant) uniform Push { reconstruct_push pc; };

layout(std430, binding = RECONSTRUCT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = RECONSTRUCT_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = RECONSTRUCT_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = RECONSTRUCT_BINDING_B) buffer Total { vec4 B[]; };
layout(std430, binding = RECONSTRUCT_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = RECONSTRUCT_BINDING_SHOOTERS) readonly buffer Shooters { gpu_shooter shooters[]; };
layout(std430, binding = RECONSTRUCT_BINDING_STATUS) readonly buffer Status { select_status status; };
layout(binding = RECONSTRUCT_BINDING_HEMICUBES) uniform utexture2DArray hemicubes;

const float PI = 3.14159265358979323846;

bool visible(vec3 local, uint hemicube, uint id)
{
    uvec2 px;
    int face = hemicube_lookup(local, pc.hemicube_res, px);
    int layer = int(hemicube) * HEMICUBE_FACES + face;
    if (texelFetch(hemicubes, ivec3(px, layer), 0).r == id)
        return true;
    if (pc.neighbours == 0u)
        return false;
    int last = int(pc.hemicube_res) - 1;
    for (int dy = -1; dy <= 1; dy++) {
        for (int dx = -1; dx <= 1; dx++) {
            ivec2 q = clamp(ivec2(px) + ivec2(dx, dy), ivec2(0), ivec2(last));
            if (texelFetch(hemicubes, ivec3(q, layer), 0).r == id)
                return true;
        }
    }
    return false;
}

vec3 bilinear(gpu_surface sf, float s, float t)
{
    return mix(mix(sf.corner[0].xyz, sf.corner[1].xyz, s), mix(sf.corner[3].xyz, sf.corner[2].xyz, s), t);
}

// As in select.comp: the parameter interval of samples [i0, i1] of n.
vec2 param_range(uint i0, uint i1, uint n)
{
    float h = 1.0 / float(n - 1u);
    return vec2(max(0.0, (float(i0) - 0.5) * h), min(1.0, (float(i1) + 0.5) * h));
}

// (1/m) sum_k cos_e cos_s / (pi r_k^2 + A/m) over g x g sub-disks at the
// centres of equal parameter cells of the shooter patch.
float subdivided_kernel(gpu_shooter sh, vec3 x, vec3 ne, uint g)
{
    gpu_surface sf = surfaces[sh.surface];
    vec2 rs = param_range(sh.i0, sh.i1, sf.nu), rt = param_range(sh.j0, sh.j1, sf.nv);
    vec3 ns = sh.normal.xyz;
    float m = float(g * g);
    float a = sh.pos_area.w / m;
    float sum = 0.0;
    for (uint b = 0u; b < g; b++) {
        float t = mix(rt.x, rt.y, (float(b) + 0.5) / float(g));
        for (uint c = 0u; c < g; c++) {
            float s = mix(rs.x, rs.y, (float(c) + 0.5) / float(g));
            vec3 d = x - bilinear(sf, s, t);
            float cs = dot(d, ns), ce = -dot(d, ne);
            if (cs <= 0.0 || ce <= 0.0)
                continue;
            float r2 = dot(d, d);
            sum += cs * ce / (r2 * (PI * r2 + a));
        }
    }
    return sum / m;
}

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.element_count)
        return;
    uint count = status.shooter_count;
    vec3 x = elements[e].pos_area.xyz;
    vec3 ne = elements[e].normal.xyz;
    uint se = elements[e].surface;
    vec3 gathered = vec3(0.0);
    for (uint k = 0u; k < count; k++) {
        gpu_shooter sh = shooters[k];
        if (sh.surface == se)
            continue;
        vec3 ns = sh.normal.xyz;
        vec3 d = x - sh.pos_area.xyz;
        float cs = dot(d, ns), ce = -dot(d, ne);
        if (cs <= 0.0 || ce <= 0.0)
            continue;
        vec3 t = sh.tangent.xyz;
        vec3 local = vec3(dot(d, t), dot(d, cross(ns, t)), cs);
        if (!visible(local, sh.hemicube, se + 1u))
            continue;
        float r2 = dot(d, d);
        float area = sh.pos_area.w;
        float f;
        if (area > pc.subdivide_ratio * r2) {
            // g sub-disks per side bring each one's area / r^2 near the ratio.
            uint g = uint(clamp(ceil(sqrt(area / (pc.subdivide_ratio * r2))), 1.0, float(pc.max_subdivision)));
            f = subdivided_kernel(sh, x, ne, g);
        } else {
            f = cs * ce / (r2 * (PI * r2 + area));
        }
        gathered += sh.radiosity.rgb * (area * f);
    }
    if (count == 0u || all(equal(gathered, vec3(0.0))))
        return;
    vec3 rho = materials[surfaces[se].material].albedo.rgb;
    vec3 dB = rho * gathered;
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
