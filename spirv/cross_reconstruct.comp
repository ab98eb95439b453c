#version 450
// Cross redistribution, the shooting half (src/passes/cross_reconstruct.c;
// thesis Algorithm 4.4 lines 15-20 and Algorithm 4.5), one invocation per
// element looping over every patch of M:
//
//  element of M (R_p(M, M), reshooting): the total radiosity of each other
//  patch it sees at the new pose, RECONSTRUCTIONSHADER(s, e, total);
//
//  element e of C (R_p(M, C) + R_x(C, C), eq. 3.3.1 as DESIGN.md writes it):
//    where e sees s at the old pose:  rho_e F_old (P(C, s, e) - B^s_s)
//    where e sees s' at the new pose: rho_e F_new (B_s' - P(C, s', e))
//  B^s_s the patch's shot radiosity before the reset, B_s' its total after
//  R_g(C, M). The new-pose projected term is subtracted, as in eq. 3.3.1:
//  the patch now hides what lies behind it (line 39 of Algorithm 4.5
//  writes a plus; the sign test in tests/solvers/test_cross.c decides).
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
//
// Pairs (CROSS_PAIRS_*): where the solver keeps them, each (patch, static
// element) pair's new-pose F is stored, and the next redistribution, whose
// old pose this is, reads it instead of testing visibility and evaluating
// the form factor again: the same number (the last frame's ID hemicubes,
// frames and receiver points), so the patch's light is removed through
// exactly the form factor it was inserted with (thesis 6.2). P is not kept:
// the old pose's back hemicubes are drawn again with the shot radiosity of
// C in hand. Between two redistributions the progressive iterations change
// what lies behind a patch (the floor it shadows darkens as its negative
// unshot light is shot); a P kept from the last frame gave back more light
// than the new pose took away, and the power crept up by about 10% per 1000
// frames of a box sliding to and fro (tests/solvers/test_extremes.c).
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
layout(binding = CROSS_RECONSTRUCT_BINDING_IDS_OLD) uniform utexture2DArray ids_old;
layout(binding = CROSS_RECONSTRUCT_BINDING_IDS_NEW) uniform utexture2DArray ids_new;
layout(binding = CROSS_RECONSTRUCT_BINDING_BACK_OLD) uniform texture2DArray back_old;
layout(binding = CROSS_RECONSTRUCT_BINDING_BACK_NEW) uniform texture2DArray back_new;
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_PAIRS) buffer Pairs { float pairs[]; };

gpu_shooter frame(uint slot, uint table, uint p)
{
    return frames[(slot * CROSS_FRAME_TABLES + table) * pc.patch_count + p];
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
// read from the face they fall on. One copy per pose slot (macro): a
// texture chosen at run time would be fetched from both.
#define BACK_SAMPLERS(NAME, TEX)                                                                  \
    vec4 NAME##_nearest(uint p, vec3 d)                                                           \
    {                                                                                             \
        vec2 t;                                                                                   \
        int face = hemicube_face(d, pc.back_res, t);                                              \
        ivec2 px = clamp(ivec2(floor(t)), ivec2(0), ivec2(int(pc.back_res) - 1));                 \
        return texelFetch(TEX, ivec3(px, int(p) * HEMICUBE_FACES + face), 0);                     \
    }                                                                                             \
    vec4 NAME##_bilinear(uint p, vec3 d)                                                          \
    {                                                                                             \
        vec2 t;                                                                                   \
        int face = hemicube_face(d, pc.back_res, t);                                              \
        int base = int(p) * HEMICUBE_FACES;                                                       \
        int last = int(pc.back_res) - 1;                                                          \
        t -= 0.5;                                                                                 \
        ivec2 t0 = ivec2(floor(t));                                                               \
        vec2 f = t - vec2(t0);                                                                    \
        vec4 c[4];                                                                                \
        if (all(greaterThanEqual(t0, ivec2(0))) && all(lessThan(t0, ivec2(last)))) {              \
            int l = base + face;                                                                  \
            c[0] = texelFetch(TEX, ivec3(t0, l), 0);                                              \
            c[1] = texelFetch(TEX, ivec3(t0 + ivec2(1, 0), l), 0);                                \
            c[2] = texelFetch(TEX, ivec3(t0 + ivec2(0, 1), l), 0);                                \
            c[3] = texelFetch(TEX, ivec3(t0 + ivec2(1, 1), l), 0);                                \
        } else {                                                                                  \
            for (int k = 0; k < 4; k++) {                                                         \
                ivec2 tap = t0 + ivec2(k & 1, k >> 1);                                            \
                vec2 tab = (vec2(tap) + 0.5) / float(pc.back_res) * 2.0 - 1.0;                    \
                vec3 dir = HEMICUBE_FORWARD[face] + tab.x * HEMICUBE_RIGHT[face] +                \
                           tab.y * HEMICUBE_UP[face];                                             \
                dir.z = max(dir.z, 1e-6);                                                         \
                vec2 q;                                                                           \
                int qf = hemicube_face(dir, pc.back_res, q);                                      \
                ivec2 qi = clamp(ivec2(floor(q)), ivec2(0), ivec2(last));                         \
                c[k] = texelFetch(TEX, ivec3(qi, base + qf), 0);                                  \
            }                                                                                     \
        }                                                                                         \
        return mix(mix(c[0], c[1], f.x), mix(c[2], c[3], f.x), f.y);                              \
    }                                                                                             \
    vec3 NAME##_projected(uint slot, uint p, vec3 x, vec3 ne)                                     \
    {                                                                                             \
        gpu_shooter back = frame(slot, CROSS_FRAMES_BACK, p);                                     \
        mat3 to_local = basis(back);                                                              \
        cross_quad q = quads[slot * pc.patch_count + p];                                          \
        vec3 c = back.pos_area.xyz;                                                               \
        vec3 du = (q.corner[1].xyz - q.corner[0].xyz), dv = (q.corner[3].xyz - q.corner[0].xyz);  \
        vec3 dw = (q.corner[2].xyz - q.corner[3].xyz) - du;                                       \
        vec3 total = vec3(0.0);                                                                   \
        float weights = 0.0;                                                                      \
        float inv = 1.0 / float(pc.grid);                                                         \
        for (uint gy = 0u; gy < pc.grid; gy++) {                                                  \
            float tv = (float(gy) + 0.5) * inv;                                                   \
            for (uint gx = 0u; gx < pc.grid; gx++) {                                              \
                float tu = (float(gx) + 0.5) * inv;                                               \
                vec3 g = q.corner[0].xyz + tu * du + tv * dv + (tu * tv) * dw;                    \
                vec3 ray = g - x;                                                                 \
                vec3 r = normalize(ray);                                                          \
                vec3 dir = to_local * r;                                                          \
                if (dir.z <= 0.0)                                                                 \
                    continue;                                                                     \
                float w = max(dot(r, ne), 0.0) * dir.z / dot(ray, ray);                           \
                weights += w;                                                                     \
                float dist = NAME##_nearest(p, dir).a * pc.diameter;                              \
                if (dist > 0.0)                                                                   \
                    dir = to_local * (g + r * dist - c);                                          \
                if (dir.z <= 0.0)                                                                 \
                    continue;                                                                     \
                total += w * (pc.bilinear != 0u ? NAME##_bilinear(p, dir).rgb                     \
                                                : NAME##_nearest(p, dir).rgb);                    \
            }                                                                                     \
        }                                                                                         \
        return weights > 0.0 ? total * (pc.inv_scale / weights) : vec3(0.0);                      \
    }

BACK_SAMPLERS(back_old, back_old)
BACK_SAMPLERS(back_new, back_new)

// Where x (normal ne) and the front of patch p at the pose of `slot` face
// each other: x's offset d from the patch centre, the two cosines and x's
// direction in the patch's ID hemicube.
bool patch_facing(uint slot, uint p, vec3 x, vec3 ne, out vec3 d, out vec2 cosines,
                  out vec3 local)
{
    gpu_shooter f = frame(slot, CROSS_FRAMES_FRONT, p);
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
float patch_form_factor(uint slot, uint p, vec3 x, vec3 ne, vec3 d, vec2 cosines)
{
    float area = frame(slot, CROSS_FRAMES_FRONT, p).pos_area.w;
    if (shooting_near(d, area, pc.subdivide_ratio)) {
        cross_quad q = quads[slot * pc.patch_count + p];
        return shooting_point_to_quad(x, ne, vec3[4](q.corner[0].xyz, q.corner[1].xyz,
                                                     q.corner[2].xyz, q.corner[3].xyz));
    }
    return shooting_disk(d, cosines.x, cosines.y, area);
}

void main()
{
    if (gl_GlobalInvocationID.x >= pc.count)
        return;
    uint e = pc.first + gl_GlobalInvocationID.x;
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    uint ke = e - sr.first_element;
    vec3 x = shooting_cell_centroid(sr, ke % sr.nu, ke / sr.nu);
    vec3 ne = elements[e].normal.xyz;
    uint id = se + 1u;
    vec3 gathered = vec3(0.0);
    for (uint p = 0u; p < pc.patch_count; p++) {
        vec3 d, local;
        vec2 cosines;
        if (sr.dynamic != 0u) {
            if (frame(pc.new_slot, CROSS_FRAMES_FRONT, p).surface == se)
                continue;
            if (patch_facing(pc.new_slot, p, x, ne, d, cosines, local) &&
                shooting_visible(ids_new, pc.hemicube_res, pc.neighbours != 0u, local, p, id))
                gathered += patch_form_factor(pc.new_slot, p, x, ne, d, cosines) *
                            values[p].total.rgb;
            continue;
        }
        uint pair = p * pc.element_count + e;
        if ((pc.pairs & CROSS_PAIRS_READ) != 0u) {
            float f_old = pairs[pair];
            if (f_old > 0.0)
                gathered += f_old * (back_old_projected(pc.old_slot, p, x, ne) - values[p].shot.rgb);
        } else if (patch_facing(pc.old_slot, p, x, ne, d, cosines, local) &&
                   shooting_visible(ids_old, pc.hemicube_res, pc.neighbours != 0u, local, p, id)) {
            float f_old = patch_form_factor(pc.old_slot, p, x, ne, d, cosines);
            gathered += f_old * (back_old_projected(pc.old_slot, p, x, ne) - values[p].shot.rgb);
        }
        float kept = 0.0;
        if (patch_facing(pc.new_slot, p, x, ne, d, cosines, local) &&
            shooting_visible(ids_new, pc.hemicube_res, pc.neighbours != 0u, local, p, id)) {
            float f_new = patch_form_factor(pc.new_slot, p, x, ne, d, cosines);
            gathered += f_new * (values[p].total.rgb - back_new_projected(pc.new_slot, p, x, ne));
            kept = f_new;
        }
        if ((pc.pairs & CROSS_PAIRS_WRITE) != 0u)
            pairs[pair] = kept;
    }
    if (all(equal(gathered, vec3(0.0))))
        return;
    vec3 dB = materials[sr.material].albedo.rgb * gathered;
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
