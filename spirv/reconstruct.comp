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
//
// Conservation: point form factors (and a nearest-texel check that lets a
// receiver just inside a shadow see the shooter) make the receivers of a
// shot take more or less than the shooter sends: sum_e A_e F_es != A_s f_s,
// where f_s is the part of the shooter's hemisphere that front faces fill.
// At albedo 0.999 a gain above 1 makes the solution diverge and a loss of
// 1e-3 costs half the light; below that, total power misses the bound
// E / (1 - rho_max) by a few percent. So a shot stores every F (MODE_FF);
// per shooter (MODE_NORM, a workgroup each) f_s is the delta-form-factor
// sum of the ID hemicube's texels that show a surface's front (not the
// background, not a back face, which absorbs), and the form factors are
// scaled so that the receivers take exactly A_s f_s; then the transfer
// (MODE_APPLY). In a closed scene every shot then conserves the power it
// shoots. norm[] holds two factors per shooter: for the receivers that see
// it by its centre's visibility, and for those that see it block by block
// (near_cells). With conserve on they are one; with conserve far
// (CONSERVE_FAR) the blocks keep their exact form factors (factor 1)
// and the centre's receivers alone are scaled: a floor patch beside a box
// on the floor gives far receivers its whole area where the box hides
// part of it, and scaling that down took the same share from the box's
// sides, which see it block by block (room 5's box sides 0.94 of the CPU
// reference from the floor's light, 0.998 with far).
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "select_shared.h"
#include "reconstruct_shared.h"
#include "hemicube.glsl"

layout(local_size_x = RECONSTRUCT_GROUP) in;

layout(push_constant) uniform Push { reconstruct_push pc; };

layout(std430, binding = RECONSTRUCT_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = RECONSTRUCT_BINDING_BVH_NODES) readonly buffer BvhNodes { gpu_bvh_node bvh_nodes[]; };
layout(std430, binding = RECONSTRUCT_BINDING_BVH_ITEMS) readonly buffer BvhItems { uint bvh_items[]; };
// conserve far is compiled in only with RECONSTRUCT_FAR (a second SPIR-V,
// src/passes/reconstruct.c): llvmpipe runs both sides of a branch under a
// mask, and with a push constant choosing it every shot paid for far's
// block tests (the 0.999 furnace's 10,000 shots took 1149 s in a CI run
// with conserve on, against under 377 s before).
#ifdef RECONSTRUCT_FAR
const bool CONSERVE_FAR = true;
#define SHOOTING_BUNDLE
#else
const bool CONSERVE_FAR = false;
#endif
#define SHOOTING_BVH
// Where the hemicubes draw C alone, M hides nothing from C's receivers:
// its light and shadows are the cross projection's (cross.c).
#define SHOOTING_UNDRAWN(i) (pc.static_only != 0u && surfaces[i].dynamic != 0u)
#include "shooting.glsl"
layout(std430, binding = RECONSTRUCT_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = RECONSTRUCT_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = RECONSTRUCT_BINDING_B) buffer Total { vec4 B[]; };
layout(std430, binding = RECONSTRUCT_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = RECONSTRUCT_BINDING_SHOOTERS) readonly buffer Shooters { gpu_shooter shooters[]; };
layout(std430, binding = RECONSTRUCT_BINDING_STATUS) readonly buffer Status { select_status status; };
layout(binding = RECONSTRUCT_BINDING_HEMICUBES) uniform utexture2DArray hemicubes;
layout(std430, binding = RECONSTRUCT_BINDING_FF) buffer FormFactors { float ff[]; };
layout(std430, binding = RECONSTRUCT_BINDING_NORM) buffer Norm { float norm[]; };
layout(std430, binding = RECONSTRUCT_BINDING_SHOT) readonly buffer Shot { vec4 shot[]; };

// Rec. 709 luminance weights.
const vec3 LUMA = vec3(0.2126, 0.7152, 0.0722);

// The GPU_ELEMENT_* flags of receivers no light reaches in these shots.
// Where the hemicubes draw C alone, the solution is C's whatever the pose,
// so an element of C under M (BURIED_M) receives as any other: cross's
// covered() takes that light away per pose and gives it back when M
// leaves, which it cannot do for shots it never saw. Shots that a
// redistribution removes again leave contact to the hemicubes, as its pass
// does (incremental_reconstruct.comp says why). progressive.c gives select
// the same mask.
uint buried_mask()
{
    return pc.redistributed != 0u ? 0u
         : pc.static_only != 0u  ? GPU_ELEMENT_BURIED
                                 : GPU_ELEMENT_BURIED_ANY;
}

// Near a patch (near_within below) a receiver sees the radiosity vary
// across it: a ceiling element by a wall sees the dark top of the wall,
// not the wall's mean, and with the mean both the ceiling's and the wall's
// edge rows came out 1.2-1.3 times the CPU reference's in a plain room. So
// the patch counts as up to SHOOTING_NEAR_BLOCKS per side blocks of its
// elements, each with the exact form factor of its cells and the mean
// unshot radiosity of its open elements as select left them (`shot`, from
// the shooter's shot_first: a shot's group has one run per surface; w the
// element's area, -1 where buried_mask() excludes it); returned as the
// factor that gives that luminance with the patch's mean radiosity, so
// that conservation and the transfer treat it as any other form factor
// (the colour is the patch's). Visibility is each block's
// (the segment from its part in front of x, shooting_front_point, against
// the candidate occluders cand[0, ncand)).
float near_cells(vec3 x, vec3 ne, gpu_surface sf, gpu_shooter sh, uint cand[9], uint ncand)
{
    float mean = dot(sh.radiosity.rgb, LUMA);
    uint bi = (sh.i1 - sh.i0 + SHOOTING_NEAR_BLOCKS) / SHOOTING_NEAR_BLOCKS;
    uint bj = (sh.j1 - sh.j0 + SHOOTING_NEAR_BLOCKS) / SHOOTING_NEAR_BLOCKS;
    float sum = 0.0, magnitude = 0.0, seen = 0.0;
    for (uint j0 = sh.j0; j0 <= sh.j1; j0 += bj) {
        uint j1 = min(j0 + bj - 1u, sh.j1);
        for (uint i0 = sh.i0; i0 <= sh.i1; i0 += bi) {
            uint i1 = min(i0 + bi - 1u, sh.i1);
            float lum = 0.0, area = 0.0;
            bool partial = false;
            for (uint j = j0; j <= j1; j++) {
                for (uint i = i0; i <= i1; i++) {
                    vec4 v = shot[sh.shot_first + j * sf.nu + i];
                    if (v.w < 0.0) {
                        partial = true;
                        continue;
                    }
                    lum += v.w * dot(v.rgb, LUMA);
                    area += v.w;
                }
            }
            if (area == 0.0)
                continue;
            // A block partly buried (the floor under a box standing on it)
            // is its open cells alone with conserve far, run by run along
            // its rows (below; cell by cell, the same within 0.2% of any
            // surface's light and 10% dearer on room 5): the block's
            // form factor with its open cells' mean lit the buried part too,
            // the part nearest the box's side, and no scaling now takes that
            // back (cornell-small's plinth.front 1.071 of the CPU reference).
            // Visibility is the open cells' as one, from their middle (their
            // area-weighted centroid): a test per cell made cornell-small's
            // solve three times as long. Every block's visibility is one
            // segment test at one place in the code: with a second for the
            // partly buried blocks, llvmpipe ran conserve far's shots in
            // room 5 of tests/solvers/rooms.c at 2.2 times conserve on's
            // (15.4 s against 7.1 s), 1.5 times without them.
            bool cells = partial && CONSERVE_FAR;
            vec3 q[4], from = vec3(0.0);
            shooting_cell_quad(sf, i0, i1, j0, j1, q);
            if (cells) {
                for (uint j = j0; j <= j1; j++) {
                    for (uint i = i0; i <= i1; i++) {
                        float w = shot[sh.shot_first + j * sf.nu + i].w;
                        if (w >= 0.0)
                            from += w * cell_centroid(sf, i, j);
                    }
                }
                from /= area;
            } else {
                from = shooting_front_point(q, x, ne);
            }
            // A block hidden from x by a candidate occluder gives nothing.
            if (shooting_segment_hidden(from, x, cand, ncand))
                continue;
            // The block with its open cells' mean, or each run of open
            // cells along a row with its own (a box's side cuts a row in
            // at most two): one form factor call in the code, as above.
            uint nj = cells ? j1 - j0 + 1u : 1u;
            for (uint pj = 0u; pj < nj; pj++) {
                uint j = j0 + pj, i = i0;
                for (;;) {
                    float l = lum / area, l_abs = abs(l);
                    if (cells) {
                        while (i <= i1 && shot[sh.shot_first + j * sf.nu + i].w < 0.0)
                            i++;
                        if (i > i1)
                            break;
                        uint ia = i;
                        float run_lum = 0.0, run_abs = 0.0, run_area = 0.0;
                        for (; i <= i1; i++) {
                            vec4 v = shot[sh.shot_first + j * sf.nu + i];
                            if (v.w < 0.0)
                                break;
                            float c = dot(v.rgb, LUMA);
                            run_lum += v.w * c;
                            run_abs += v.w * abs(c);
                            run_area += v.w;
                        }
                        l = run_lum / max(run_area, 1e-30);
                        l_abs = run_abs / max(run_area, 1e-30);
                        shooting_cell_quad(sf, ia, i - 1u, j, j, q);
                    }
                    float f = shooting_point_to_quad(x, ne, q);
                    seen += f;
                    sum += f * l;
                    magnitude += f * l_abs;
                    if (!cells)
                        break;
                }
            }
        }
    }
    // A patch whose light cancels (negative beside positive, the dynamic
    // methods) has no mean to scale: the blocks x sees, by area alone.
    if (!(abs(mean) > 1e-3 * magnitude / max(seen, 1e-30)) || mean == 0.0)
        return seen;
    return sum / mean;
}

// This invocation's share of the part of shooter sh's hemisphere (delta
// form factors, thesis 2.2.2: dA / (pi (u^2 + v^2 + 1)^2) on the top face,
// times v on a side face's upper half) that its ID hemicube shows as a
// surface's front side: (front, total) over every RECONSTRUCT_GROUP-th
// weighing texel (hemicube_weighted_texel) from lane on. norm_reduce() sums
// the shares.
vec2 front_fraction_share(gpu_shooter sh, uint lane)
{
    uint res = pc.hemicube_res;
    vec3 t = sh.tangent.xyz, ns = sh.normal.xyz, b = cross(ns, t);
    float total = 0.0, front = 0.0;
    for (uint i = lane; i < 3u * res * res; i += RECONSTRUCT_GROUP) {
        uvec2 texel;
        uint face = hemicube_weighted_texel(i, res, texel);
        vec3 d = hemicube_texel_direction(face, texel, res);
        float r2 = dot(d, d), w = d.z / (r2 * r2);
        total += w;
        uint id = texelFetch(hemicubes, ivec3(ivec2(texel), int(sh.hemicube * 5u + face)), 0).r;
        if (id == 0u)
            continue;
        vec3 world = d.x * t + d.y * b + d.z * ns;
        if (dot(world, surfaces[id - 1u].normal_area.xyz) < 0.0)
            front += w;
    }
    return vec2(front, total);
}

// The NORM dispatch runs a workgroup per shooter (reconstruct.c). With one
// invocation looping over every element and texel in sequence (cornell-
// large: 10,342 elements and 3 x 64^2 texels), the first GPU run's
// reconstruct took 2.4-3.5 ms a shot whatever the shooter count, a third
// of cross's frame (tools/gpu-check.sh). Each invocation sums a strided
// share; the group adds the shares in shared memory.
shared vec4 s_norm[RECONSTRUCT_GROUP];

vec4 norm_reduce(vec4 v, uint lane)
{
    s_norm[lane] = v;
    barrier();
    for (uint stride = RECONSTRUCT_GROUP / 2u; stride > 0u; stride /= 2u) {
        if (lane < stride)
            s_norm[lane] += s_norm[lane + stride];
        barrier();
    }
    return s_norm[0];
}

// Whether a receiver at offset d from a patch of `area` sees it block by
// block (near_cells) where the pass may (pc.near_blocks): r^2 <
// SHOOTING_NEAR_REACH2 x A_s, two sizes. Within two sizes the receiver
// still sees the radiosity vary across the patch (a wall by a wall light
// takes the ceiling above the light mostly from its nearer, darker edge)
// and the occluders beside it hide one part and not another; at 1 (the
// patch's size) the rooms' box sides and the wall beside a wall light came
// out 3-5% dark (tests/solvers/rooms.c, progressive surface_error
// 0.024-0.051), at 2 within 1.8% but for one room at 2.9%, for 1.2-1.5
// times the frame time. Everywhere (every receiver block by block) cost
// 2-3 times and did no better.
bool near_within(vec3 d, float area)
{
    return pc.near_blocks != 0u && area * SHOOTING_NEAR_REACH2 > dot(d, d);
}

// Whether x's tangent plane cuts patch sh (ce = -d . ne).
bool near_cut(vec3 x, vec3 ne, float ce, gpu_shooter sh)
{
    return pc.near_blocks != 0u && shooting_straddles(x, ne, ce, surfaces[sh.surface], sh);
}

// Whether receiver x (normal ne) sees shooter sh block by block.
bool sees_blocks(gpu_shooter sh, vec3 x, vec3 ne)
{
    vec3 d = x - sh.pos_area.xyz;
    return near_within(d, sh.pos_area.w) || near_cut(x, ne, -dot(d, ne), sh);
}

// The receiver point of element e.
vec3 receiver_point(uint e)
{
    gpu_surface sr = surfaces[elements[e].surface];
    uint ke = e - sr.first_element;
    return cell_centroid(sr, ke % sr.nu, ke / sr.nu);
}

// What form_factor_direct returns where the factor is the patch's blocks'
// (form_factor_blocks): no form factor is negative there.
const float FF_BLOCKS = -1.0;

// Where receiver x (normal ne) lies from patch sh: d = x - centre, cs and
// ce its cosines at the patch and at x (unnormalised), and which of the
// near-field rules apply.
struct pair_geometry {
    vec3 d;
    float cs, ce, area;
    bool near, near_field, within, cut;
};

pair_geometry pair_at(gpu_shooter sh, vec3 x, vec3 ne)
{
    pair_geometry g;
    g.d = x - sh.pos_area.xyz;
    g.cs = dot(g.d, sh.normal.xyz);
    g.ce = -dot(g.d, ne);
    g.area = sh.pos_area.w;
    g.near = shooting_near(g.d, g.area, pc.subdivide_ratio);
    // Shots a redistribution removes again see as its pass does
    // (reconstruct_params.redistributed): the occluder test, but the
    // patch's mean and its centre's visibility in the near field.
    g.near_field = pc.redistributed == 0u && g.near && g.area > dot(g.d, g.d);
    // Near a patch, or where x's tangent plane cuts through it, its
    // visibility is its blocks' (near_cells) rather than its centre's: a
    // floor patch whose centre lies behind or under a box still lights the
    // box's side from its part in front (the sides' bottom rows were
    // 0.76-0.80 of the CPU reference's), and a ceiling light cut by the
    // plane of a floating box's side lights the side from the part in
    // front, which its centre, behind the plane, does not see (0.87-0.94).
    // Cross's iterations after its restart shoot signed changes and keep
    // the centre's visibility (pc.near_blocks 0): with the blocks', 10,000
    // frames of a sliding box settled 13% above the power bound after
    // frame 4000. Its restart, C's plain solve, sees block by block (room
    // 1's table sides at the floor 0.84 of the CPU reference's without).
    // (pc.near_blocks is 0 where pc.redistributed is 1, reconstruct.c.)
    g.within = near_within(g.d, g.area);
    g.cut = !g.within && near_cut(x, ne, g.ce, sh);
    return g;
}

// The local direction of x in patch sh's hemicube frame.
vec3 pair_local(gpu_shooter sh, pair_geometry g)
{
    vec3 t = sh.tangent.xyz;
    return vec3(dot(g.d, t), dot(g.d, cross(sh.normal.xyz, t)), g.cs);
}

// The form factor from receiver e (point x, normal ne, surface se) to
// shooter k, 0 where it does not see the shooter, or FF_BLOCKS where
// form_factor_blocks gives it. The two are apart so that main() can run
// the blocks after the loop over the shot's patches, for the pairs that
// need them alone: llvmpipe runs code under a mask, every lane whether it
// takes a branch or not, and with near_cells inside the loop every
// receiver paid for its loops once per patch (room 1 of
// tests/solvers/rooms.c, the reconstruct pass 6.0 -> 5.1 ms a hemicube
// with conserve off, 9.9 -> 7.8 with on, the solutions the same within
// 1e-7; measured 2026-12-07).
float form_factor_direct(uint k, vec3 x, vec3 ne, uint se)
{
    gpu_shooter sh = shooters[k];
    if (sh.surface == se)
        return 0.0;
    // Incremental's iterations after a redistribution: M took all of C's
    // light at the new pose, with what C reflects of M's, in the
    // redistribution (incremental_reconstruct.comp c_light), and is reset
    // to take it anew each frame. C's shots to M would give it C's changes
    // and M's light a second time: the box floating under
    // test_luminaires.c's lamp 1.153 of the CPU reference on its bottom,
    // 0.914 on a side.
    if (pc.redistributed != 0u && surfaces[se].dynamic != 0u && surfaces[sh.surface].dynamic == 0u)
        return 0.0;
    pair_geometry g = pair_at(sh, x, ne);
    bool blocks = g.within || g.cut;
    if (!shooting_faces(g.d, g.cs, g.ce, g.near || blocks))
        return 0.0;
    if (blocks)
        return FF_BLOCKS;
    if (!shooting_visible(hemicubes, pc.hemicube_res, pc.neighbours != 0u, pair_local(sh, g),
                          sh.hemicube, se + 1u, sh.pos_area.xyz, x, true))
        return 0.0;
    if (!g.near)
        return shooting_disk(g.d, g.cs, g.ce, g.area);
    if (!g.near_field)
        return shooting_quad(x, ne, surfaces[sh.surface], sh);
    // The centre's visibility and the blocks' radiosity.
    return FF_BLOCKS;
}

// The form factor where form_factor_direct returned FF_BLOCKS: the patch's
// blocks (near_cells), with their own visibility where x sees the patch
// block by block, or (the near field) the centre's.
float form_factor_blocks(uint k, vec3 x, vec3 ne, uint se)
{
    gpu_shooter sh = shooters[k];
    pair_geometry g = pair_at(sh, x, ne);
    uint cand[9];
    uint ncand = 0u;
    if (g.within || g.cut) {
        // The surfaces the texels towards x show are the candidate
        // occluders of every block. Cut by x's plane beyond the blocks'
        // reach, every surface is a candidate occluder
        // (SHOOTING_EVERY_SURFACE says why); mesh faces only where the
        // texels show them (SHOOTING_EVERY_QUAD). A mesh face as the
        // receiver, where curvature puts many shooters across its plane,
        // takes the texels' candidates alone: every segment a loop over the
        // scene's surfaces made a 1280-face ball's shots 10 times dearer
        // per element than an 80-face one's.
        ncand = shooting_candidates(hemicubes, pc.hemicube_res, pair_local(sh, g), sh.hemicube,
                                    se + 1u, cand);
        // With conserve far the blocks' form factors are not scaled, so
        // nothing makes up for an occluder the texels miss: every quad is
        // tested (room 5's table side 1.031 of the CPU reference with the
        // texels' candidates alone, 1.015 with every quad).
        // With far the quads are collected once for all the blocks
        // (shooting_collect_bundle).
        if (surfaces[se].mesh == 0u && (g.cut || CONSERVE_FAR))
            ncand |= SHOOTING_EVERY_QUAD;
#ifdef SHOOTING_BUNDLE
        if (surfaces[se].mesh == 0u) {
            vec3 q[4];
            shooting_cell_quad(surfaces[sh.surface], sh.i0, sh.i1, sh.j0, sh.j1, q);
            shooting_collect_bundle(q, x);
        }
#endif
    }
    float f = near_cells(x, ne, surfaces[sh.surface], sh, cand, ncand);
#ifdef SHOOTING_BUNDLE
    shooting_box_quad_count = SHOOTING_BOX_NONE;
#endif
    return f;
}

// Both: the form factor from receiver e to shooter k.
float form_factor(uint k, vec3 x, vec3 ne, uint se)
{
    float f = form_factor_direct(k, x, ne, se);
    return f == FF_BLOCKS ? form_factor_blocks(k, x, ne, se) : f;
}

void main()
{
    uint count = status.shooter_count;
    if (pc.mode == RECONSTRUCT_MODE_NORM) {
        // Uniform across the workgroup, so every return below is the
        // whole group's and no invocation misses a barrier.
        uint k = gl_WorkGroupID.x, lane = gl_LocalInvocationID.x;
        if (k >= count)
            return;
        // Fixed patches (the dynamic methods' M, and incremental's C) are
        // removed again by their redistribution with the form factors as
        // they are; scaled here, removal and insertion would differ and
        // the difference would pile up frame after frame. The first solve
        // scales them too (pc.conserve_fixed): at albedo 0.999 their gain
        // alone put cross's furnace 29% high, and what the first
        // redistribution removes then differs from what was shot once, not
        // every frame.
        if (surfaces[shooters[k].surface].patches_s != 0u && pc.conserve_fixed == 0u) {
            if (lane == 0u)
                norm[2u * k] = norm[2u * k + 1u] = 1.0;
            return;
        }
        gpu_shooter sh = shooters[k];
        vec2 taken = vec2(0.0); // (centre's visibility, block by block)
        for (uint i = lane; i < pc.element_count; i += RECONSTRUCT_GROUP) {
            // What the hemicube sends lands by the receivers' surface
            // cosines: a normal-mapped receiver (xrad.h normal_map, whose
            // factor ff[] holds with its mapped normal) counts here with
            // its surface's, and its mapped factor is scaled as the rest
            // (with the mapped factors the tilt itself was scaled away,
            // 8% off on a floor tilted by 25 degrees, test_normal_maps).
            float f = ff[k * pc.element_count + i];
            uint si = elements[i].surface;
            vec3 ng = surfaces[si].normal_area.xyz;
            if (dot(elements[i].normal.xyz, ng) < 0.999999)
                f = form_factor(k, receiver_point(i), ng, si);
            float a = elements[i].pos_area.w * f;
            if (a == 0.0)
                continue;
            if (CONSERVE_FAR &&
                sees_blocks(sh, receiver_point(i), elements[i].normal.xyz))
                taken.y += a;
            else
                taken.x += a;
        }
        vec4 sums = norm_reduce(vec4(taken, front_fraction_share(sh, lane)), lane);
        if (lane != 0u)
            return;
        float sent = sh.pos_area.w * (sums.w > 0.0 ? sums.z / sums.w : 0.0);
        // A receiver set far from what the hemicube shows (a shooter whose
        // visible front faces all lie on its own surface's plane, say) is
        // left as it is rather than scaled by a large factor.
        float all = sums.x + sums.y;
        float q = all > 0.0 ? sent / all : 1.0;
        q = q > 0.25 && q < 4.0 ? q : min(q, 1.0);
        // conserve far: the blocks' receivers keep their exact factors and
        // the rest make up the difference, unless that takes a factor
        // outside the bounds above. Where it would take more, nothing is
        // scaled up: a floor patch half under a table standing 2 mm above
        // it shoots from its centre under the table, whose hemicube shows
        // the underside alone; the few receivers that see the centre
        // cannot take the lit half's light, and the blocks scaled up by q
        // gave the underside all of it (lamp-room's table.-v 1.35 of the
        // CPU reference at 12 patches a side, 1.06 at 8). Not with on: the
        // same rule there (lamp-room's underside 1.04 -> 0.98 under cross)
        // put the power of test_extremes' 10,000 cross frames 1-3% above
        // E / (1 - rho) from frame 7000 on.
        float qf = sums.x > 0.0 ? (sent - sums.y) / sums.x : 0.0;
        bool far_only = CONSERVE_FAR && qf > 0.25 && qf < 4.0;
        float q_all = CONSERVE_FAR && qf >= 4.0 ? min(q, 1.0) : q;
        norm[2u * k] = far_only ? qf : q_all;
        norm[2u * k + 1u] = far_only ? 1.0 : q_all;
        return;
    }
    uint e = gl_GlobalInvocationID.x;
    if (e >= pc.element_count)
        return;
    vec3 ne = elements[e].normal.xyz;
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    vec3 x = receiver_point(e);
    // Buried (scene_find_buried), or of M where the hemicubes draw C alone:
    // the occluder test would find such an element visible (nothing drawn
    // hides it), and the light it took would be lost when cross resets M
    // (a 0.999 furnace with a floating box came out 36% low); which are
    // buried, buried_mask() says.
    if ((elements[e].flags & buried_mask()) != 0u ||
        (pc.static_only != 0u && sr.dynamic != 0u)) {
        if (pc.mode == RECONSTRUCT_MODE_FF)
            for (uint k = 0u; k < count; k++)
                ff[k * pc.element_count + e] = 0.0;
        return;
    }
    shooting_exact_mesh = pc.redistributed == 0u;
    vec3 gathered = vec3(0.0);
    if (pc.mode == RECONSTRUCT_MODE_APPLY) {
        for (uint k = 0u; k < count; k++) {
            float f = ff[k * pc.element_count + e] *
                      norm[2u * k + (CONSERVE_FAR && sees_blocks(shooters[k], x, ne) ? 1u : 0u)];
            gathered += shooters[k].radiosity.rgb * f;
        }
    } else {
        // The patches 32 at a time: first every factor that needs no
        // blocks, marking those that do, then the marked ones alone
        // (form_factor_direct says why).
        for (uint k0 = 0u; k0 < count; k0 += 32u) {
            uint k1 = min(k0 + 32u, count), marked = 0u;
            for (uint k = k0; k < k1; k++) {
                float f = form_factor_direct(k, x, ne, se);
                if (f == FF_BLOCKS) {
                    marked |= 1u << (k - k0);
                    f = 0.0;
                }
                if (pc.mode == RECONSTRUCT_MODE_FF)
                    ff[k * pc.element_count + e] = f;
                else
                    gathered += shooters[k].radiosity.rgb * f;
            }
            while (marked != 0u) {
                uint k = k0 + uint(findLSB(marked));
                marked &= marked - 1u;
                float f = form_factor_blocks(k, x, ne, se);
                if (pc.mode == RECONSTRUCT_MODE_FF)
                    ff[k * pc.element_count + e] = f;
                else
                    gathered += shooters[k].radiosity.rgb * f;
            }
        }
    }
    if (pc.mode == RECONSTRUCT_MODE_FF)
        return;
    if (count == 0u || all(equal(gathered, vec3(0.0))))
        return;
    vec3 rho = elements[e].albedo.rgb;
    vec3 dB = rho * gathered;
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}
