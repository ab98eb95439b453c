#version 450
// Cross redistribution, the shooting half (src/passes/cross_reconstruct.c;
// thesis Algorithm 4.4 lines 15-20 and Algorithm 4.5), one invocation per
// element looping over every patch of M, in two dispatches (phase):
//
//  CROSS_RECONSTRUCT_M, element of M (R_p(M, M), reshooting): the total
//  radiosity of each other patch it sees, RECONSTRUCTIONSHADER(s, e,
//  total), into B alone: the patches' totals are taken again after this,
//  and that is how M's light reaches C (Bu of M stays 0);
//
//  CROSS_RECONSTRUCT_C, element e of C (R_p(M, C) + R_x(C, C), the
//  new-pose half of eq. 3.3.1 as DESIGN.md writes it):
//    X_e = rho_e sum over the patches s' e sees of F (B_s' - P(C, s', e)),
//  B_s' the patch's total, P(C, s', e) the shot radiosity of C that s'
//  hides from e. The new-pose projected term is subtracted, as in eq.
//  3.3.1: the patch hides what lies behind it (line 39 of Algorithm 4.5
//  writes a plus; the sign test in tests/solvers/test_dynamic.c decides).
//  The old-pose half is the X the last redistribution added, kept per
//  element (inserted[e]): e gets X_e - inserted[e] in B and in Bu (the
//  change is shot on by the progressive iterations), and inserted[e] = X_e.
//  What was inserted is removed exactly, whatever happened in between
//  (thesis 3.3.4, 6.2). The progressive iterations do not see M (their
//  hemicubes draw C alone, src/solvers/cross.c), so X is all M does to C:
//  the solution is that of C plus the source X of the pose in hand, and no
//  error can add up over frames.
//
// PROJECTEDRADIOSITY(s, e): grid x grid rays from e's receiver point
// through the centres of a grid over the patch; each is REPROJECTed through
// the patch's back hemicube (static geometry C drawn with its shot
// radiosity, alpha = distance from the hemicube's origin): the distance
// read in the ray's own direction (r' parallel to r, thesis 4.5.2) places
// p' on the ray behind the patch, and the radiosity is read in the
// direction of p' from the hemicube's origin. Eq. 3.3.2 takes the plain
// area mean over the patch; here each ray is weighted by the point-to-area
// kernel cos_e cos_s / r^2 of its grid cell, so that F x P is the kernel
// integral of the radiosity seen through the patch rather than F times an
// unweighted mean (on the sign test's occluder the plain mean removed 5%
// too little light).
//
// The distance is read at the nearest texel; radiosity bilinearly (unless
// pc.bilinear is 0), and a tap beyond a face's edge is turned back into a
// direction and read from the face it falls on (thesis 4.5.2: "care must
// be taken with the edges of the hemicube").
//
// Visibility, receiver point and form factor are those of the reconstruct
// pass (spirv/shooting.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "cross_shared.h"
#include "hemicube.glsl"
#include "shooting.glsl"

layout(local_size_x = CROSS_RECONSTRUCT_GROUP) in;

layout(push_constant) uniform Push { cross_reconstruct_push pc; };

layout(std430, binding = CROSS_RECONSTRUCT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_B) buffer Total { vec4 B[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_VALUES) readonly buffer Values { cross_value values[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_FRAMES) readonly buffer Frames { gpu_shooter frames[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_QUADS) readonly buffer Quads { cross_quad quads[]; };
layout(binding = CROSS_RECONSTRUCT_BINDING_IDS) uniform utexture2DArray ids;
layout(binding = CROSS_RECONSTRUCT_BINDING_BACK) uniform texture2DArray back;
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_INSERTED) buffer Inserted { vec4 inserted[]; };

gpu_shooter frame(uint table, uint p)
{
    return frames[table * pc.patch_count + p];
}

// The local frame of a hemicube (as spirv/hemicube_vert.glsl builds it;
// the host wrote unit, orthogonal normal and tangent,
// solvers/dynamic_patches.c).
mat3 basis(gpu_shooter f)
{
    vec3 z = f.normal.xyz, x = f.tangent.xyz;
    return transpose(mat3(x, cross(z, x), z));
}

// Samples of the back hemicube of patch p in local direction d (d.z > 0):
// rgb the shot radiosity x scale, a the distance / diameter. Nearest, or
// bilinear with taps beyond a face's edge turned back into directions and
// read from the face they fall on.
vec4 back_nearest(uint p, vec3 d)
{
    vec2 t;
    int face = hemicube_face(d, pc.back_res, t);
    ivec2 px = clamp(ivec2(floor(t)), ivec2(0), ivec2(int(pc.back_res) - 1));
    return texelFetch(back, ivec3(px, int(p) * HEMICUBE_FACES + face), 0);
}

vec4 back_bilinear(uint p, vec3 d)
{
    vec2 t;
    int face = hemicube_face(d, pc.back_res, t);
    int base = int(p) * HEMICUBE_FACES;
    int last = int(pc.back_res) - 1;
    t -= 0.5;
    ivec2 t0 = ivec2(floor(t));
    vec2 f = t - vec2(t0);
    vec4 c[4];
    if (all(greaterThanEqual(t0, ivec2(0))) && all(lessThan(t0, ivec2(last)))) {
        int l = base + face;
        c[0] = texelFetch(back, ivec3(t0, l), 0);
        c[1] = texelFetch(back, ivec3(t0 + ivec2(1, 0), l), 0);
        c[2] = texelFetch(back, ivec3(t0 + ivec2(0, 1), l), 0);
        c[3] = texelFetch(back, ivec3(t0 + ivec2(1, 1), l), 0);
    } else {
        for (int k = 0; k < 4; k++) {
            ivec2 tap = t0 + ivec2(k & 1, k >> 1);
            vec2 tab = (vec2(tap) + 0.5) / float(pc.back_res) * 2.0 - 1.0;
            vec3 dir = HEMICUBE_FORWARD[face] + tab.x * HEMICUBE_RIGHT[face] +
                       tab.y * HEMICUBE_UP[face];
            dir.z = max(dir.z, 1e-6);
            vec2 q;
            int qf = hemicube_face(dir, pc.back_res, q);
            ivec2 qi = clamp(ivec2(floor(q)), ivec2(0), ivec2(last));
            c[k] = texelFetch(back, ivec3(qi, base + qf), 0);
        }
    }
    return mix(mix(c[0], c[1], f.x), mix(c[2], c[3], f.x), f.y);
}

// PROJECTEDRADIOSITY(s, e), above.
vec3 projected(uint p, vec3 x, vec3 ne)
{
    gpu_shooter bf = frame(CROSS_FRAMES_BACK, p);
    mat3 to_local = basis(bf);
    cross_quad q = quads[p];
    vec3 c = bf.pos_area.xyz;
    vec3 du = (q.corner[1].xyz - q.corner[0].xyz), dv = (q.corner[3].xyz - q.corner[0].xyz);
    vec3 dw = (q.corner[2].xyz - q.corner[3].xyz) - du;
    vec3 total = vec3(0.0);
    float weights = 0.0;
    float inv = 1.0 / float(pc.grid);
    for (uint gy = 0u; gy < pc.grid; gy++) {
        float tv = (float(gy) + 0.5) * inv;
        for (uint gx = 0u; gx < pc.grid; gx++) {
            float tu = (float(gx) + 0.5) * inv;
            vec3 g = q.corner[0].xyz + tu * du + tv * dv + (tu * tv) * dw;
            vec3 ray = g - x;
            vec3 r = normalize(ray);
            vec3 dir = to_local * r;
            if (dir.z <= 0.0)
                continue;
            float w = max(dot(r, ne), 0.0) * dir.z / dot(ray, ray);
            weights += w;
            float dist = back_nearest(p, dir).a * pc.diameter;
            if (dist > 0.0)
                dir = to_local * (g + r * dist - c);
            if (dir.z <= 0.0)
                continue;
            total += w * (pc.bilinear != 0u ? back_bilinear(p, dir).rgb
                                            : back_nearest(p, dir).rgb);
        }
    }
    return weights > 0.0 ? total * (pc.inv_scale / weights) : vec3(0.0);
}

// Where x (normal ne) and the front of patch p face each other: x's offset
// d from the patch centre, the two cosines and x's direction in the
// patch's ID hemicube.
bool patch_facing(uint p, vec3 x, vec3 ne, out vec3 d, out vec2 cosines, out vec3 local)
{
    gpu_shooter f = frame(CROSS_FRAMES_FRONT, p);
    d = x - f.pos_area.xyz;
    cosines = vec2(dot(d, f.normal.xyz), -dot(d, ne));
    local = vec3(0.0);
    if (cosines.x <= 0.0 || cosines.y <= 0.0)
        return false;
    local = basis(f) * d;
    return true;
}

// The form factor from x to patch p (spirv/shooting.glsl), once
// patch_facing said yes and the ID hemicube showed x: asked after the
// visibility test because the near-field form factor costs more.
float patch_form_factor(uint p, vec3 x, vec3 ne, vec3 d, vec2 cosines)
{
    float area = frame(CROSS_FRAMES_FRONT, p).pos_area.w;
    if (shooting_near(d, area, pc.subdivide_ratio)) {
        cross_quad q = quads[p];
        return shooting_point_to_quad(x, ne, vec3[4](q.corner[0].xyz, q.corner[1].xyz,
                                                     q.corner[2].xyz, q.corner[3].xyz));
    }
    return shooting_disk(d, cosines.x, cosines.y, area);
}

// Patch p's form factor to x where x sees it (the ID hemicube shows x), else 0.
float seen(uint p, vec3 x, vec3 ne, uint id)
{
    vec3 d, local;
    vec2 cosines;
    if (!patch_facing(p, x, ne, d, cosines, local) ||
        !shooting_visible(ids, pc.hemicube_res, pc.neighbours != 0u, local, p, id))
        return 0.0;
    return patch_form_factor(p, x, ne, d, cosines);
}

void main()
{
    if (gl_GlobalInvocationID.x >= pc.count)
        return;
    uint e = pc.first + gl_GlobalInvocationID.x;
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    bool dynamic = sr.dynamic != 0u;
    if (dynamic != (pc.phase == CROSS_RECONSTRUCT_M))
        return;
    uint ke = e - sr.first_element;
    vec3 x = shooting_cell_centroid(sr, ke % sr.nu, ke / sr.nu);
    vec3 ne = elements[e].normal.xyz;
    uint id = se + 1u;
    vec3 rho = materials[sr.material].albedo.rgb;
    vec3 gathered = vec3(0.0);
    for (uint p = 0u; p < pc.patch_count; p++) {
        if (dynamic && frame(CROSS_FRAMES_FRONT, p).surface == se)
            continue;
        float f = seen(p, x, ne, id);
        if (f > 0.0)
            gathered += f * (dynamic ? values[p].total.rgb
                                     : values[p].total.rgb - projected(p, x, ne));
    }
    if (dynamic) {
        B[e].rgb += rho * gathered;
        return;
    }
    vec3 X = rho * gathered;
    vec3 dB = X - inserted[e].rgb;
    inserted[e] = vec4(X, 0.0);
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
