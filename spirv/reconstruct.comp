#version 450
// Reconstruct pass (src/passes/reconstruct.c): thesis Algorithm 4.2
// RECONSTRUCTIONSHADER, one invocation per receiving element, looping over
// every shooter of the shot.
//
// Receiver point: the centroid of the element's cell (the part of the
// surface within half a sample spacing of its sample, src/scene/scene.h),
// not the sample itself. Edge samples lie on the surface's edges, i.e. in the
// plane of a perpendicular neighbour, where the point form factor to that
// neighbour is 0 although it tends to 1/2 just inside; the cell centroid
// makes the element sum a midpoint rule over the surface (on a unit cube the
// transfer to the other faces then sums to 1; from the samples, to 0.77-0.97
// depending on the element count) and needs no corner offset.
//
// Visibility: the element's surface ID (surface + 1) in the shooter's ID
// hemicube in the direction of the receiver point, or in one of the 8 texels
// around it (nearest-texel check, thesis 4.3.3).
//
// Form factor (eq. 2.2.8 with m = 1): dB = rho B_s A_s cos cos / (pi r^2 +
// A_s), Wallace's disk approximation (eq. 2.2.7). Where A_s / r^2 exceeds the
// subdivide ratio, thesis 4.3.3 subdivides the disk; near a shooter the sum
// over sub-disks still falls short (a/(pi r^2 + a) per sub-disk is exact only
// on the disk's axis; on a unit cube the transfer sums to 0.92-0.99 with up
// to 16 x 16 sub-disks), so the subdivision is taken to its limit: the exact
// form factor from the receiver point to the shooter patch's quad (Lambert's
// formula, clipped to the receiver's front half-space). The sum over the
// shooters of the shot is added to B and Bu. The shooter's own surface
// receives nothing.
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

// Form factor from the point x (unit normal n) to the convex polygon q[0..3]
// clipped to the half-space in front of x (Lambert: (1/2pi) sum_k gamma_k
// n . (R_k x R_k+1) / |R_k x R_k+1|, ground-truth.md).
float point_to_quad(vec3 x, vec3 n, vec3 q[4])
{
    vec3 r[5];
    int count = 0;
    for (int k = 0; k < 4; k++) {
        vec3 a = q[k] - x, b = q[(k + 1) % 4] - x;
        float da = dot(a, n), db = dot(b, n);
        if (da > 0.0 && count < 5)
            r[count++] = a;
        if ((da > 0.0) != (db > 0.0) && count < 5)
            r[count++] = mix(a, b, da / (da - db));
    }
    float sum = 0.0;
    for (int k = 0; k < count; k++) {
        vec3 c = cross(r[k], r[(k + 1) % count]);
        float cl = length(c);
        if (cl > 0.0)
            sum += atan(cl, dot(r[k], r[(k + 1) % count])) * dot(n, c) / cl;
    }
    return abs(sum) / (2.0 * PI);
}

// The receiver point of element e: the centroid of its cell.
vec3 cell_centroid(uint e, uint se)
{
    gpu_surface sf = surfaces[se];
    uint k = e - sf.first_element;
    uint i = k % sf.nu, j = k / sf.nu;
    vec2 rs = param_range(i, i, sf.nu), rt = param_range(j, j, sf.nv);
    return bilinear(sf, 0.5 * (rs.x + rs.y), 0.5 * (rt.x + rt.y));
}

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.element_count)
        return;
    uint count = status.shooter_count;
    vec3 ne = elements[e].normal.xyz;
    uint se = elements[e].surface;
    vec3 x = cell_centroid(e, se);
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
        float ff; // form factor from the receiver point to the shooter patch
        if (area > pc.subdivide_ratio * r2) {
            gpu_surface sf = surfaces[sh.surface];
            vec2 rs = param_range(sh.i0, sh.i1, sf.nu), rt = param_range(sh.j0, sh.j1, sf.nv);
            vec3 q[4] = vec3[4](bilinear(sf, rs.x, rt.x), bilinear(sf, rs.y, rt.x),
                                bilinear(sf, rs.y, rt.y), bilinear(sf, rs.x, rt.y));
            ff = point_to_quad(x, ne, q);
        } else {
            ff = area * cs * ce / (r2 * (PI * r2 + area));
        }
        gathered += sh.radiosity.rgb * ff;
    }
    if (count == 0u || all(equal(gathered, vec3(0.0))))
        return;
    vec3 rho = materials[surfaces[se].material].albedo.rgb;
    vec3 dB = rho * gathered;
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
