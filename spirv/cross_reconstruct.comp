#version 450
// Cross redistribution, the shooting half (src/passes/cross_reconstruct.c;
// thesis Algorithm 4.4 lines 15-20 and Algorithm 4.5), in dispatches
// (phase) of one invocation per element, except C_ARGS, C_SCATTER and
// C_EVAL:
//
//  CROSS_RECONSTRUCT_M_DIRECT, element of M: rho x the direct light of the
//  lights of C, through their ID hemicubes with M (lit_direct), and the
//  luminaires' at the pose (`luminaires`), into B;
//
//  CROSS_RECONSTRUCT_M, element of M (R_p(M, M), reshooting): the total
//  radiosity of each other patch it sees, RECONSTRUCTIONSHADER(s, e,
//  total), into B alone: the patches' totals are taken again after this,
//  and that is how M's light reaches C (Bu of M stays 0);
//
//  with cross_pairs on, before phase C (issue 16.1):
//  CROSS_RECONSTRUCT_C_PAIRS, element e of C: the patches that see it
//  (facing, the nearest-texel check in their ID hemicubes), as pairs in a
//  list, with their form factors, and a count per patch;
//  CROSS_RECONSTRUCT_C_ARGS, one invocation: the patches' first places
//  (the prefix sum of their counts) and the indirect dispatches;
//  CROSS_RECONSTRUCT_C_SCATTER, per pair: its place in patch order;
//  CROSS_RECONSTRUCT_C_EVAL, per pair in that order: F (B_s' - P(C, s',
//  e)), the projection below. Only the pairs that see each other cost
//  rays, with no lane idle beside one that traces; without the list
//  (cross_pairs off) phase C loops over every patch itself;
//
//  CROSS_RECONSTRUCT_C, element e of C (R_p(M, C) + R_x(C, C), the
//  new-pose half of eq. 3.3.1 as DESIGN.md writes it), summing its pairs:
//    X_e = rho_e (sum over the patches s' e sees of F (B_s' - P(C, s', e))
//                 - the direct light M hides from e, blocked_direct)
//          + the change M makes in the luminaires' light reflected (lum),
//  B_s' the patch's total, P(C, s', e) the shot radiosity of C less its
//  emission that s' hides from e. The new-pose projected term is subtracted, as in eq.
//  3.3.1: the patch hides what lies behind it (line 39 of Algorithm 4.5
//  writes a plus; the sign test in tests/solvers/test_dynamic.c decides).
//  The old-pose half is the X the last redistribution added, kept per
//  element (inserted[e]): e gets X_e - inserted[e] in B and in Bu (the
//  change is shot on by the progressive iterations), and inserted[e] = X_e.
//  What was inserted is removed exactly, whatever happened in between
//  (thesis 3.3.4, 6.2). The progressive iterations do not see M (their
//  hemicubes draw C alone, src/solvers/cross.c), so X is all M does to C:
//  the solution is that of C plus the source X of the pose in hand, and no
//  error can add up over frames. An element in contact with M (covered())
//  gets X = E - (B without X): its emission alone.
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
// be taken with the edges of the hemicube"). With pc.back_levels the
// radiosity comes from the mip level that matches the width of the cone
// the ray stands for (thesis 6.2, back_radiosity() below).
//
// With pc.cut a pair whose term is bounded below a share of the frame's
// largest radiosity is left out (cut_level(), kept()).
//
// The mips and the cut are compiled in only with CROSS_RECONSTRUCT_FULL
// (a second SPIR-V, src/passes/cross_reconstruct.c), which the pass uses
// where either is on: llvmpipe runs both sides of a branch under a mask,
// and their dead code doubled cornell-large's projection (243 ms a frame
// before them, 500 with them off).
//
// Visibility, receiver point and form factor are those of the reconstruct
// pass (spirv/shooting.glsl).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "cross_shared.h"
#include "hemicube.glsl"
#include "back_mips.glsl"

layout(local_size_x = CROSS_RECONSTRUCT_GROUP) in;

// Contact distance, a fraction of the scene's diameter (covered()).
const float CONTACT = 1e-4;

layout(push_constant) uniform Push { cross_reconstruct_push pc; };

layout(std430, binding = CROSS_RECONSTRUCT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_BVH_NODES) readonly buffer BvhNodes { gpu_bvh_node bvh_nodes[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_BVH_ITEMS) readonly buffer BvhItems { uint bvh_items[]; };
#define SHOOTING_BVH
#include "shooting.glsl"
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
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_LUMINAIRES) readonly buffer Luminaires { vec4 luminaires[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_LIGHTS) readonly buffer Lights { gpu_shooter lights[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_LIGHT_QUADS) readonly buffer LightQuads { cross_quad light_quads[]; };
layout(binding = CROSS_RECONSTRUCT_BINDING_LIGHT_IDS_C) uniform utexture2DArray light_ids_c;
layout(binding = CROSS_RECONSTRUCT_BINDING_LIGHT_IDS) uniform utexture2DArray light_ids;
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_PAIRS) buffer Pairs { cross_pair pairs[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_RANGES) buffer Ranges { uvec2 ranges[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_PAIR_STATE) buffer PairState {
    cross_pair_state state;
};
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_ORDER) buffer Order { uint order[]; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_PATCH_LISTS) buffer PatchLists {
    uint patch_lists[];
};
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_PEAK) readonly buffer Peak { uint peak_bits; };
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_BACK_MIPS) readonly buffer BackMips {
    vec4 back_mips[];
};
layout(std430, binding = CROSS_RECONSTRUCT_BINDING_LIGHT_LAYERS) readonly buffer LightLayers {
    uint light_layers[];
};

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

// Texel px of layer `layer` of the back hemicubes at mip level k (0: the
// hemicube itself; above, spirv/back_mips.glsl).
vec4 back_texel(int layer, ivec2 px, uint k)
{
#ifdef CROSS_RECONSTRUCT_FULL
    if (k != 0u) {
        uint r = pc.back_res >> k;
        return back_mips[uint(layer) * back_mip_layer_texels(pc.back_res, pc.back_levels) +
                         back_mip_first(pc.back_res, k) + uint(px.y) * r + uint(px.x)];
    }
#endif
    return texelFetch(back, ivec3(px, layer), 0);
}

// Samples of the back hemicube of patch p in local direction d (d.z > 0)
// at level k: rgb the shot radiosity x scale, a the distance / diameter.
// Nearest, or bilinear with taps beyond a face's edge turned back into
// directions and read from the face they fall on.
vec4 back_nearest(uint p, vec3 d, uint k)
{
    vec2 t;
    uint res = pc.back_res >> k;
    int face = hemicube_face(d, res, t);
    ivec2 px = clamp(ivec2(floor(t)), ivec2(0), ivec2(int(res) - 1));
    return back_texel(int(p) * HEMICUBE_FACES + face, px, k);
}

vec4 back_bilinear(uint p, vec3 d, uint k)
{
    vec2 t;
    uint res = pc.back_res >> k;
    int face = hemicube_face(d, res, t);
    int base = int(p) * HEMICUBE_FACES;
    int last = int(res) - 1;
    t -= 0.5;
    ivec2 t0 = ivec2(floor(t));
    vec2 f = t - vec2(t0);
    vec4 c[4];
    if (all(greaterThanEqual(t0, ivec2(0))) && all(lessThan(t0, ivec2(last)))) {
        int l = base + face;
        c[0] = back_texel(l, t0, k);
        c[1] = back_texel(l, t0 + ivec2(1, 0), k);
        c[2] = back_texel(l, t0 + ivec2(0, 1), k);
        c[3] = back_texel(l, t0 + ivec2(1, 1), k);
    } else {
        for (int n = 0; n < 4; n++) {
            ivec2 tap = t0 + ivec2(n & 1, n >> 1);
            vec2 tab = (vec2(tap) + 0.5) / float(res) * 2.0 - 1.0;
            vec3 dir = HEMICUBE_FORWARD[face] + tab.x * HEMICUBE_RIGHT[face] +
                       tab.y * HEMICUBE_UP[face];
            dir.z = max(dir.z, 1e-6);
            vec2 q;
            int qf = hemicube_face(dir, res, q);
            ivec2 qi = clamp(ivec2(floor(q)), ivec2(0), ivec2(last));
            c[n] = back_texel(base + qf, qi, k);
        }
    }
    return mix(mix(c[0], c[1], f.x), mix(c[2], c[3], f.x), f.y);
}

// The shot radiosity the back hemicube of patch p shows toward d, at level
// of detail lod (0: the hemicube's texels): between the two nearest mip
// levels, each read as pc.bilinear says.
vec3 back_radiosity(uint p, vec3 d, float lod)
{
#ifdef CROSS_RECONSTRUCT_FULL
    uint k = uint(lod);
    vec3 v = pc.bilinear != 0u ? back_bilinear(p, d, k).rgb : back_nearest(p, d, k).rgb;
    float f = lod - float(k);
    if (f > 0.0 && k < pc.back_levels)
        v = mix(v, pc.bilinear != 0u ? back_bilinear(p, d, k + 1u).rgb
                                     : back_nearest(p, d, k + 1u).rgb, f);
    return v;
#else
    return pc.bilinear != 0u ? back_bilinear(p, d, 0u).rgb : back_nearest(p, d, 0u).rgb;
#endif
}

// PROJECTEDRADIOSITY(s, e), above, for a pair of form factor ff. The rays
// a side follow the patch's solid angle from x (issue 16; thesis 6.2 asks
// for fewer rays far away): the full grid from pc.grid_ff on, below it
// ceil(grid sqrt(ff / grid_ff)), so that the ray count goes with ff and a
// pair's sampling error, a share of ff x P, stays about the same share of
// the largest pair's. On cornell-large one ray for every pair left
// surface_error and element p95 within 0.001 of sixteen.
vec3 projected(uint p, vec3 x, vec3 ne, float ff)
{
    uint n = pc.grid;
    if (ff < pc.grid_ff)
        n = clamp(uint(ceil(float(pc.grid) * sqrt(ff / pc.grid_ff))), 1u, pc.grid);
    gpu_shooter bf = frame(CROSS_FRAMES_BACK, p);
    mat3 to_local = basis(bf);
    cross_quad q = quads[p];
    vec3 c = bf.pos_area.xyz;
    vec3 du = (q.corner[1].xyz - q.corner[0].xyz), dv = (q.corner[3].xyz - q.corner[0].xyz);
    vec3 dw = (q.corner[2].xyz - q.corner[3].xyz) - du;
    vec3 total = vec3(0.0);
    float weights = 0.0;
    float inv = 1.0 / float(n);
    float cell = sqrt(bf.pos_area.w) * inv;
    for (uint gy = 0u; gy < n; gy++) {
        float tv = (float(gy) + 0.5) * inv;
        for (uint gx = 0u; gx < n; gx++) {
            float tu = (float(gx) + 0.5) * inv;
            vec3 g = q.corner[0].xyz + tu * du + tv * dv + (tu * tv) * dw;
            vec3 ray = g - x;
            vec3 r = normalize(ray);
            vec3 dir = to_local * r;
            if (dir.z <= 0.0)
                continue;
            float w = max(dot(r, ne), 0.0) * dir.z / dot(ray, ray);
            weights += w;
            float dist = back_nearest(p, dir, 0u).a * pc.diameter;
            float lod = 0.0;
            if (dist > 0.0) {
                dir = to_local * (g + r * dist - c);
                // Mips (thesis 6.2): the ray stands for a cell of side
                // `cell` on the patch; the cone from x through it is
                // cell (|ray| + dist) / |ray| wide where it meets what
                // lies behind, seen from the hemicube's origin at |dir|
                // over an angle of that / |dir|, which a face's texel
                // (2 / res of the face at distance 1) divides into. The
                // level is that of half the cone's width: a bilinear read
                // spans two texels of its level, and a level's blocks lie
                // on the face's grid, not centred on the ray. Against
                // cross_grid 16 on cornell-large, the full width made
                // element p95 17x worse at one ray a pair, half of it 1.5x
                // better, a quarter as good as no mips (README).
#ifdef CROSS_RECONSTRUCT_FULL
                if (pc.back_levels > 0u) {
                    float along = length(ray);
                    float texels = cell * (along + dist) / (along * max(length(dir), 1e-6)) *
                                   0.25 * float(pc.back_res);
                    lod = clamp(log2(max(texels, 1.0)), 0.0, float(pc.back_levels));
                }
#endif
            }
            if (dir.z <= 0.0)
                continue;
            total += w * back_radiosity(p, dir, lod);
        }
    }
    return weights > 0.0 ? total * (pc.inv_scale / weights) : vec3(0.0);
}

// Where x (normal ne) and the front of the patch with frame f face each
// other: x's offset d from the patch centre, the two cosines and x's
// direction in the patch's ID hemicube.
bool facing(gpu_shooter f, vec3 x, vec3 ne, out vec3 d, out vec2 cosines, out vec3 local)
{
    d = x - f.pos_area.xyz;
    cosines = vec2(dot(d, f.normal.xyz), -dot(d, ne));
    local = vec3(0.0);
    if (!shooting_faces(d, cosines.x, cosines.y, shooting_near(d, f.pos_area.w, pc.subdivide_ratio)))
        return false;
    local = basis(f) * d;
    return true;
}

// The form factor from x to the patch (frame f, corners q;
// spirv/shooting.glsl), once facing() said yes and the ID hemicube showed
// x: asked after the visibility test because the near-field form factor
// costs more.
float form_factor(gpu_shooter f, cross_quad q, vec3 x, vec3 ne, vec3 d, vec2 cosines)
{
    float area = f.pos_area.w;
    if (shooting_near(d, area, pc.subdivide_ratio))
        return shooting_point_to_quad(x, ne, vec3[4](q.corner[0].xyz, q.corner[1].xyz,
                                                     q.corner[2].xyz, q.corner[3].xyz));
    return shooting_disk(d, cosines.x, cosines.y, area);
}

// Whether x (normal ne) lies on patch p's front face to face (an object
// of M resting on it): in the patch's plane within tol, inside its quad,
// the normals opposed. Such a receiver sees no patch of M (the cosine at
// the patch is 0), so the cross projection cannot take from it the light
// that the progressive iterations, which do not see M, bring it.
bool covered(uint p, vec3 x, vec3 ne, float tol)
{
    // A group's quad stands for faces that need not lie in its plane (a
    // ball's underside touches the floor at a point, not over the quad).
    if (frame(CROSS_FRAMES_FRONT, p).group != 0u)
        return false;
    vec3 n = frame(CROSS_FRAMES_FRONT, p).normal.xyz;
    cross_quad q = quads[p];
    if (dot(ne, n) >= 0.0 || abs(dot(x - q.corner[0].xyz, n)) > tol)
        return false;
    for (int k = 0; k < 4; k++) {
        vec3 a = q.corner[k].xyz, b = q.corner[(k + 1) & 3].xyz;
        if (dot(cross(b - a, x - a), n) < 0.0)
            return false;
    }
    return true;
}

// Patch p's form factor to x where x sees it (the ID hemicube shows x), else 0.
float seen(uint p, vec3 x, vec3 ne, uint id)
{
    vec3 d, local;
    vec2 cosines;
    gpu_shooter f = frame(CROSS_FRAMES_FRONT, p);
    if (!facing(f, x, ne, d, cosines, local) ||
        !shooting_visible(ids, pc.hemicube_res, pc.neighbours != 0u, local, p, id, f.pos_area.xyz,
                          x, false))
        return 0.0;
    return form_factor(f, quads[p], x, ne, d, cosines);
}

// The direct light of the lights of C at x (an element of M): the
// emission of every light patch whose ID hemicube with M shows x, through
// the form factor a progressive shot uses. The gather hemicubes see C
// without emission (INDIRECT_C): a light is often far smaller than a
// texel of theirs (a 1 mm^2 lamp), while its own hemicube resolves what it
// lights as the progressive shots do.
vec3 lit_direct(vec3 x, vec3 ne, uint id)
{
    vec3 sum = vec3(0.0);
    for (uint l = 0u; l < pc.light_count; l++) {
        // M behind the light's plane: x, a point of M, is too.
        uint layer = light_layers[l];
        if (layer == CROSS_LIGHT_UNREACHED)
            continue;
        vec3 d, local;
        vec2 cosines;
        gpu_shooter f = lights[l];
        vec3 emission = materials[surfaces[f.surface].material].emission.rgb;
        cross_quad lq = light_quads[l];
        vec3 q[4] = vec3[4](lq.corner[0].xyz, lq.corner[1].xyz, lq.corner[2].xyz,
                            lq.corner[3].xyz);
        // A light patch cut by x's tangent plane lights x from its part in
        // front, which its centre, behind the plane, may not see (the
        // segment runs through x's own object): visible unless a surface
        // lies between that part and x (SHOOTING_EVERY_SURFACE), and the
        // exact form factor of that part (spirv/shooting.glsl). A floating
        // box's side in the plane of a ceiling light's edge took 0.89 of
        // its light without.
        d = x - f.pos_area.xyz;
        if (shooting_quad_straddles(q, x, ne, -dot(d, ne), f.pos_area.w)) {
            if (!shooting_faces(d, dot(d, f.normal.xyz), -dot(d, ne), true))
                continue;
            uint cand[9];
            if (!shooting_front_hidden(q, x, ne, cand, SHOOTING_EVERY_SURFACE))
                sum += shooting_point_to_quad(x, ne, q) * emission;
            continue;
        }
        // The nearest-texel check, as the rest of the redistribution sees
        // (spirv/shooting.glsl): with the occluder test here, 10,000 frames
        // of a sliding box settled 28% above the power bound after frame
        // 7000 (test_extremes). Mesh faces seen edge-on from the light
        // still count through the depth rule.
        if (facing(f, x, ne, d, cosines, local) &&
            shooting_visible(light_ids, pc.hemicube_res, pc.neighbours != 0u, local, layer, id,
                             f.pos_area.xyz, x, false))
            sum += form_factor(f, lq, x, ne, d, cosines) * emission;
    }
    return sum;
}

// Whether the texel toward local direction `local` of ID hemicube l in
// `ids` shows a surface of M.
bool shows_m(utexture2DArray ids, vec3 local, uint l)
{
    uvec2 px;
    int face = hemicube_lookup(local, pc.hemicube_res, px);
    uint shown = texelFetch(ids, ivec3(px, int(l) * HEMICUBE_FACES + face), 0).r;
    return shown != 0u && surfaces[shown - 1u].dynamic != 0u;
}

// The direct light M takes from x: the emission of every light patch whose
// ID hemicube of C alone shows x and whose hemicube with M shows M in x's
// direction, through the form factor a progressive shot uses. The back
// hemicubes hold C without emission (INDIRECT_C), so the cross projection
// handles indirect light only: a light is often far smaller than a back
// hemicube's texel (a 1 mm^2 lamp), which no projection through one can
// resolve, while the light's own hemicube resolves what M hides of it as
// the progressive shots do. "Shows M in x's direction" rather than "does
// not show x": the nearest-texel check, which finds x in a neighbouring
// texel M leaves free, would shrink every shadow by a texel, and unlike a
// progressive shot this term has no conservation to give that light back.
// "Shows x" by the occluder test, as the shots of C that lit x decided it
// (spirv/reconstruct.comp): what is taken away is what was given. With the
// plain nearest-texel check here, the floor round a plinth under a moving
// box came out 0.92-0.95 of the CPU reference (cornell-large with its floor
// cut in five, surface_error 0.26), 0.98-1.00 with the occluder test (0.074).
vec3 blocked_direct(vec3 x, vec3 ne, uint id)
{
    vec3 sum = vec3(0.0);
    for (uint l = 0u; l < pc.light_count; l++) {
        // M behind the light's plane hides none of its light.
        uint layer = light_layers[l];
        if (layer == CROSS_LIGHT_UNREACHED)
            continue;
        vec3 d, local;
        vec2 cosines;
        gpu_shooter f = lights[l];
        if (facing(f, x, ne, d, cosines, local) && shows_m(light_ids, local, layer) &&
            shooting_visible(light_ids_c, pc.hemicube_res, pc.neighbours != 0u, local, l, id,
                             f.pos_area.xyz, x, true))
            sum += form_factor(f, light_quads[l], x, ne, d, cosines) *
                   materials[surfaces[f.surface].material].emission.rgb;
    }
    return sum;
}

// The contribution bound (issue 16.1, xrad.h cross_cut). A pair's term
// F (B_s - P) is at most F max(B_s, Pmax) (radiosities are not negative;
// P is a weighted mean of what the back hemicubes show, at most Pmax, the
// largest |B - Bu - E| of C measured this redistribution), and no pair's
// can pass Rmax = max(Pmax, every B_s), since F <= 1. A pair is left out
// where its bound is below pc.cut x Rmax: an element loses at most
// rho x pc.cut x Rmax per patch, and nothing where pc.cut is 0.
float largest(vec3 v)
{
    return max(max(abs(v.r), abs(v.g)), abs(v.b));
}

float shown_peak()
{
    float p = uintBitsToFloat(peak_bits);
    return p > 0.0 && !isinf(p) ? p : 0.0;
}

// pc.cut x Rmax; 0 where nothing is left out.
float cut_level()
{
#ifndef CROSS_RECONSTRUCT_FULL
    return 0.0;
#endif
    if (pc.cut <= 0.0)
        return 0.0;
    float r = shown_peak();
    for (uint p = 0u; p < pc.patch_count; p++)
        r = max(r, largest(values[p].total.rgb));
    return pc.cut * r;
}

bool kept(uint p, float ff, float level)
{
#ifndef CROSS_RECONSTRUCT_FULL
    return true;
#endif
    return level <= 0.0 || ff * max(largest(values[p].total.rgb), shown_peak()) >= level;
}

// Element e's receiver point and normal.
void receiver(uint e, out vec3 x, out vec3 ne)
{
    gpu_surface sr = surfaces[elements[e].surface];
    uint ke = e - sr.first_element;
    x = cell_centroid(sr, ke % sr.nu, ke / sr.nu);
    ne = elements[e].normal.xyz;
}

// C_PAIRS: the patches element e sees, as pairs in the list, its range in
// ranges[e]. Kept here first (one pass over the patches), so that one
// atomic reserves the element's pairs together and phase C sums them in
// patch order; an element that sees more than CROSS_PAIRS_LOCAL patches,
// or finds the list full, loops over the patches in phase C itself.
void list_pairs(uint e, vec3 x, vec3 ne, uint id)
{
    uint local_patch[CROSS_PAIRS_LOCAL];
    float local_ff[CROSS_PAIRS_LOCAL];
    uint n = 0u;
    // Closed in by M at this pose (gpu_scene.h, ENCLOSE_MOVING): as covered.
    if ((elements[e].flags & GPU_ELEMENT_BURIED_M) != 0u) {
        ranges[e] = uvec2(0u, CROSS_RANGE_HIDDEN);
        return;
    }
    float level = cut_level();
    for (uint p = 0u; p < pc.patch_count; p++) {
        if (covered(p, x, ne, CONTACT * pc.diameter)) {
            ranges[e] = uvec2(0u, CROSS_RANGE_HIDDEN);
            return;
        }
        float f = seen(p, x, ne, id);
        if (f > 0.0 && kept(p, f, level)) {
            if (n == CROSS_PAIRS_LOCAL) {
                ranges[e] = uvec2(0u, CROSS_RANGE_INLINE);
                return;
            }
            local_patch[n] = p;
            local_ff[n] = f;
            n++;
        }
    }
    uint first = n > 0u ? atomicAdd(state.count, n) : 0u;
    if (first + n > pc.pair_capacity || first + n < first) {
        // The slots it was given below the capacity hold no pair.
        for (uint k = first; k < pc.pair_capacity && k < first + n; k++)
            pairs[k].patch_index = 0xffffffffu;
        ranges[e] = uvec2(0u, CROSS_RANGE_INLINE);
        return;
    }
    for (uint k = 0u; k < n; k++) {
        pairs[first + k].element = e;
        pairs[first + k].patch_index = local_patch[k];
        pairs[first + k].ff = local_ff[k];
        atomicAdd(patch_lists[local_patch[k]], 1u);
    }
    ranges[e] = uvec2(first, n);
}

// C_EVAL, pair i: F (B_s - P(C, s, e)) (eq. 3.3.1's new-pose terms).
void eval_pair(uint i)
{
    cross_pair q = pairs[i];
    if (q.element >= pc.element_count || q.patch_index >= pc.patch_count)
        return;
    vec3 x, ne;
    receiver(q.element, x, ne);
    uint p = q.patch_index;
    pairs[i].value = vec4(q.ff * (values[p].total.rgb - projected(p, x, ne, q.ff)), 0.0);
}

void main()
{
    if (pc.phase == CROSS_RECONSTRUCT_C_ARGS) {
        if (gl_GlobalInvocationID.x == 0u) {
            uint n = min(state.count, pc.pair_capacity);
            uint at = 0u;
            for (uint p = 0u; p < pc.patch_count; p++) {
                patch_lists[pc.patch_count + p] = at;
                at += patch_lists[p];
            }
            state.listed = at;
            state.scatter[0] = (n + CROSS_RECONSTRUCT_GROUP - 1u) / CROSS_RECONSTRUCT_GROUP;
            state.scatter[1] = 1u;
            state.scatter[2] = 1u;
            state.eval[0] = (at + CROSS_RECONSTRUCT_GROUP - 1u) / CROSS_RECONSTRUCT_GROUP;
            state.eval[1] = 1u;
            state.eval[2] = 1u;
        }
        return;
    }
    // The pairs in patch order: neighbouring invocations trace through one
    // patch's back hemicube from neighbouring elements, as the loop per
    // element did (in the list's element order they read as many patches).
    if (pc.phase == CROSS_RECONSTRUCT_C_SCATTER) {
        uint i = gl_GlobalInvocationID.x;
        if (i < min(state.count, pc.pair_capacity) && pairs[i].patch_index < pc.patch_count) {
            uint p = pairs[i].patch_index;
            uint k = atomicAdd(patch_lists[2u * pc.patch_count + p], 1u);
            if (k < patch_lists[p])
                order[patch_lists[pc.patch_count + p] + k] = i;
        }
        return;
    }
    if (pc.phase == CROSS_RECONSTRUCT_C_EVAL) {
        if (gl_GlobalInvocationID.x < state.listed) {
            uint i = order[gl_GlobalInvocationID.x];
            if (i < pc.pair_capacity)
                eval_pair(i);
        }
        return;
    }
    if (gl_GlobalInvocationID.x >= pc.count)
        return;
    uint e = pc.first + gl_GlobalInvocationID.x;
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    bool dynamic = sr.dynamic != 0u;
    bool phase_c = pc.phase == CROSS_RECONSTRUCT_C || pc.phase == CROSS_RECONSTRUCT_C_PAIRS;
    if (dynamic != !phase_c)
        return;
    // In contact (scene_find_buried): no light reaches it. An element of C
    // under M or closed in by it (BURIED_M) goes on to `hidden` below,
    // which takes away the light it had before M came.
    uint buried = elements[e].flags & (dynamic ? GPU_ELEMENT_BURIED_ANY : GPU_ELEMENT_BURIED);
    if (buried != 0u) {
        if (pc.phase == CROSS_RECONSTRUCT_C_PAIRS)
            ranges[e] = uvec2(0u, CROSS_RANGE_SKIP);
        return;
    }
    uint ke = e - sr.first_element;
    vec3 x = cell_centroid(sr, ke % sr.nu, ke / sr.nu);
    vec3 ne = elements[e].normal.xyz;
    uint id = se + 1u;
    vec3 rho = elements[e].albedo.rgb;
    // The luminaires' light (src/solvers/luminaire_change.h): M's at the
    // pose; on C the change from C's own that M makes.
    vec3 lum = pc.luminaires != 0u ? luminaires[e].rgb : vec3(0.0);
    if (pc.phase == CROSS_RECONSTRUCT_M_DIRECT) {
        B[e].rgb += rho * lit_direct(x, ne, id) + lum;
        return;
    }
    if (pc.phase == CROSS_RECONSTRUCT_C_PAIRS) {
        list_pairs(e, x, ne, id);
        return;
    }
    // Phase C sums the values C_EVAL wrote for the element's pairs; phase M,
    // and an element the full list left out, loop over the patches here.
    vec3 gathered = vec3(0.0);
    uvec2 range = dynamic || pc.pair_capacity == 0u ? uvec2(0u, CROSS_RANGE_INLINE) : ranges[e];
    // Closed in by M (a bottomless box over the floor: tests/solvers/rooms.c
    // room 5, whose floor under it kept C's light, 3.3 against the
    // reference's 0): as covered, below.
    bool hidden = range.y == CROSS_RANGE_HIDDEN ||
                  (!dynamic && (elements[e].flags & GPU_ELEMENT_BURIED_M) != 0u);
    if (range.y == CROSS_RANGE_INLINE) {
        float level = dynamic ? 0.0 : cut_level();
        for (uint p = 0u; p < pc.patch_count; p++) {
            if (dynamic && frame(CROSS_FRAMES_FRONT, p).surface == se)
                continue;
            if (!dynamic && covered(p, x, ne, CONTACT * pc.diameter)) {
                hidden = true;
                break;
            }
            float f = seen(p, x, ne, id);
            if (f > 0.0 && kept(p, f, level))
                gathered += f * (dynamic ? values[p].total.rgb
                                         : values[p].total.rgb - projected(p, x, ne, f));
        }
    } else if (!hidden) {
        for (uint k = 0u; k < range.y; k++)
            gathered += pairs[range.x + k].value.rgb;
    }
    if (dynamic) {
        B[e].rgb += rho * gathered;
        return;
    }
    // A covered element keeps its emission alone: X takes away all it got
    // from C (B - E without the last X). Like any X it is replaced next time,
    // so the light returns when the object leaves.
    vec3 X = hidden ? materials[sr.material].emission.rgb - (B[e].rgb - inserted[e].rgb)
                    : rho * (gathered - blocked_direct(x, ne, id)) + lum;
    vec3 dB = X - inserted[e].rgb;
    inserted[e] = vec4(X, 0.0);
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
