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
#include "shooting.glsl"

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

void main()
{
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.element_count)
        return;
    uint count = status.shooter_count;
    vec3 ne = elements[e].normal.xyz;
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    uint ke = e - sr.first_element;
    vec3 x = shooting_cell_centroid(sr, ke % sr.nu, ke / sr.nu);
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
        if (!shooting_visible(hemicubes, pc.hemicube_res, pc.neighbours != 0u, local,
                              sh.hemicube, se + 1u))
            continue;
        float area = sh.pos_area.w;
        float ff = shooting_near(d, area, pc.subdivide_ratio)
                       ? shooting_quad(x, ne, surfaces[sh.surface], sh)
                       : shooting_disk(d, cs, ce, area);
        gathered += sh.radiosity.rgb * ff;
    }
    if (count == 0u || all(equal(gathered, vec3(0.0))))
        return;
    vec3 rho = materials[surfaces[se].material].albedo.rgb;
    vec3 dB = rho * gathered;
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
