#version 450
// Incremental radiosity (src/passes/incremental_reconstruct.c; thesis
// Algorithm 4.3 with the reshooting of 4.4.1), one mode per dispatch
// (spirv/incremental_shared.h):
//  CAPTURE    per shooter: the area means of shot (B - Bu), unshot (Bu) and
//             total (B) radiosity over its elements (GENERATESHOOTINGPATCHES
//             with "shot and unshot", line 8), taken before anything of the
//             redistribution changes them;
//  CLEAR      per element: m_light = 0;
//  M_LIGHT    per element of C, for the chunk's shooters of M at the new
//             pose: m_light += their radiosity as the NEGATIVE step's
//             capture found it, through their ID hemicubes at the new
//             pose: M's light on C there, which the progressive iterations
//             give C anew;
//  CAPTURE_LIT per shooter of C, after INCREMENT: the area mean of
//             B + m_light (`lit`, what M takes in RECEIVE_M);
//  POWER      per surface: |luminance(sum_e B_e A_e)| on C, 0 on M: what
//             the host sizes the shooting patches of C by (thesis 4.3.3);
//  RESET      per element: M back to its emission, B = Bu = E (line 6, to
//             be reshot), and C's unshot radiosity cleared (line 9: the
//             C shooters shoot it in this redistribution); the luminaires'
//             light at the new pose with them (reset());
//  NEGATIVE   per element of C: the first part of R_p(M, C) (lines 3-5):
//             minus the shot radiosity of each patch of M, through its ID
//             hemicube at the old pose, with the old form factor;
//  INCREMENT  per element of C, for the chunk's shooters of C (lines
//             22-37, INCREMENTALRECONSTRUCTIONSHADER, R_p(C, C)): seen
//             before and not now -> -shot, now and not before -> +total,
//             both -> +unshot, neither -> nothing; and m_light reflected
//             once more where the new hemicube sees the element;
//  RECEIVE_M  per element of M, for the chunk's shooters of C, after every
//             chunk's INCREMENT (lines 13-18 moved after them): the total
//             radiosity of C at the new pose with M's light on it
//             (c_light, `lit`) where the new hemicube sees the element
//             (RECONSTRUCTIONSHADER(s, e, total), the reshooting of
//             R_p(C, M)), block by block near a patch or where its centre
//             does not see it (visible_blocks).
// Receiver point, visibility and form factor as the reconstruct pass
// (spirv/shooting.glsl; reasons in reconstruct.comp). Each shooter's frame
// is the same in both of its hemicubes (C does not move), so the two
// lookups differ only where M changed what the shooter sees.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_samplerless_texture_functions : require
#include "radiosity.h"
#include "incremental_shared.h"
#include "hemicube.glsl"

layout(local_size_x = INCR_GROUP) in;

layout(push_constant) uniform Push { incr_push pc; };

layout(std430, binding = INCR_BINDING_SURFACES) readonly buffer Surfaces { gpu_surface surfaces[]; };
layout(std430, binding = INCR_BINDING_OLD_SURFACES) readonly buffer OldSurfaces { gpu_surface old_surfaces[]; };
// The old hemicubes show M where old_surfaces has it. Copied member by
// member: the two blocks' gpu_surface are distinct SPIR-V types, and a
// select between them is invalid SPIR-V.
gpu_surface occluder_at(uint i, bool old)
{
    gpu_surface s = surfaces[i];
    if (old) {
        s.normal_area = old_surfaces[i].normal_area;
        for (int k = 0; k < 4; k++)
            s.corner[k] = old_surfaces[i].corner[k];
    }
    return s;
}
#define SHOOTING_OCCLUDER(i, old) occluder_at(i, old)
#include "shooting.glsl"
layout(std430, binding = INCR_BINDING_ELEMENTS) readonly buffer Elements { gpu_element elements[]; };
layout(std430, binding = INCR_BINDING_MATERIALS) readonly buffer Materials { gpu_material materials[]; };
layout(std430, binding = INCR_BINDING_B) buffer Total { vec4 B[]; };
layout(std430, binding = INCR_BINDING_BU) buffer Unshot { vec4 Bu[]; };
layout(std430, binding = INCR_BINDING_SHOOTERS) readonly buffer Shooters { gpu_shooter shooters[]; };
layout(std430, binding = INCR_BINDING_VALUES) buffer Values { incr_value values[]; };
layout(std430, binding = INCR_BINDING_M_LIGHT) buffer MLight { vec4 m_light[]; };
layout(std430, binding = INCR_BINDING_POWER) writeonly buffer Power { float power[]; };
layout(std430, binding = INCR_BINDING_LUMINAIRES) readonly buffer Luminaires { vec4 luminaires[]; };
layout(binding = INCR_BINDING_IDS_OLD) uniform utexture2DArray ids_old;
layout(binding = INCR_BINDING_IDS_NEW) uniform utexture2DArray ids_new;

// Rec. 709 luminance weights, as select_power.comp.
const vec3 LUMA = vec3(0.2126, 0.7152, 0.0722);

void capture(uint k)
{
    gpu_shooter sh = shooters[k];
    gpu_surface sf = surfaces[sh.surface];
    vec3 b = vec3(0.0), u = vec3(0.0), m = vec3(0.0);
    float area = 0.0;
    for (uint j = sh.j0; j <= sh.j1; j++) {
        for (uint i = sh.i0; i <= sh.i1; i++) {
            uint e = sf.first_element + j * sf.nu + i;
            float a = elements[e].pos_area.w;
            b += B[e].rgb * a;
            u += Bu[e].rgb * a;
            m += m_light[e].rgb * a;
            area += a;
        }
    }
    float inv = area > 0.0 ? 1.0 / area : 0.0;
    values[k].shot = vec4((b - u) * inv, 0.0);
    values[k].unshot = vec4(u * inv, 0.0);
    values[k].total = vec4(b * inv, 0.0);
    // INCREMENT: M's light on the patch (M_LIGHT), which it passes on
    // (CAPTURE_LIT replaces it after INCREMENT).
    values[k].lit = vec4(m * inv, 0.0);
}

// What M takes from an element of C (RECEIVE_M): its light at the new pose,
// after INCREMENT, with M's light on it (m_light, M_LIGHT). Taken in the
// thesis's place (INCREMENT, Algorithm 4.3 line 14), M read C before C's
// changes at the new pose: the floor M uncovers, dark as the old pose had
// it, and the elements it half covers, whose values change with every
// pose, lit the side of room 1's sliding box (tests/solvers/rooms.c) that
// trails at 0.63 of the CPU reference by the floor after one frame (0.951
// the whole side). Without M's light, M lost what it sends to C and C
// sends back (M -> C -> M), which only the progressive iterations of later
// frames shot again: the leading side of the same box, moved 13 cm a
// frame, at 0.928. m_light is M's radiosity of the old pose through its
// patches at the new, and that once more reflected by C (INCREMENT): with
// the first bounce alone, the box floating under test_luminaires.c's lamp
// stayed at 0.955 on its bottom (0.974 with the second; progressive
// refinement solved at the same pose 0.977). M is reset every frame, so
// the old pose's radiosity in it does not add up.
vec3 c_light(uint e)
{
    return B[e].rgb + m_light[e].rgb;
}

// Patch k's mean of c_light over its elements not under M at the new pose
// (M does not see them; they are dark).
void capture_lit(uint k)
{
    gpu_shooter sh = shooters[k];
    gpu_surface sf = surfaces[sh.surface];
    vec3 b = vec3(0.0);
    float area = 0.0;
    for (uint j = sh.j0; j <= sh.j1; j++) {
        for (uint i = sh.i0; i <= sh.i1; i++) {
            uint e = sf.first_element + j * sf.nu + i;
            if ((elements[e].flags & GPU_ELEMENT_BURIED_M) != 0u)
                continue;
            float a = elements[e].pos_area.w;
            b += c_light(e) * a;
            area += a;
        }
    }
    values[k].lit = vec4(area > 0.0 ? b / area : vec3(0.0), 0.0);
}

void surface_power(uint s)
{
    gpu_surface sf = surfaces[s];
    vec3 sum = vec3(0.0);
    if (sf.dynamic == 0u) {
        uint n = sf.nu * sf.nv;
        for (uint k = 0u; k < n; k++)
            sum += B[sf.first_element + k].rgb * elements[sf.first_element + k].pos_area.w;
    }
    power[s] = abs(dot(sum, LUMA));
}

void reset(uint e)
{
    gpu_surface sf = surfaces[elements[e].surface];
    vec3 emission = materials[sf.material].emission.rgb;
    // The luminaires' direct light (solvers/incremental.c): on M what it
    // reflects of it at the new pose, emitted as its own light is; on C the
    // change from the old pose (a shadow M casts, or takes away), new
    // light of C that the progressive iterations shoot on.
    vec3 lum = pc.luminaires != 0u ? luminaires[e].rgb : vec3(0.0);
    if (sf.dynamic != 0u) {
        B[e] = vec4(emission + lum, 0.0);
        Bu[e] = vec4(emission + lum, 0.0);
    } else if ((elements[e].flags & GPU_ELEMENT_BURIED_M) != 0u) {
        // Under M or closed in by it at the new pose: no light reaches it,
        // so B is its emission, and all it held beyond that (shot by the
        // end of this step) is retracted as negative unshot radiosity.
        // Taking it off shot by shot (-shot x form factor in receive())
        // does not match what the conservation-scaled shots gave: room
        // 5's floor under its moving box came out at -0.41 W/m^2 (+0.16
        // with --conserve off) against the reference's 0.
        Bu[e] = vec4(emission - B[e].rgb, 0.0);
        B[e] = vec4(emission, 0.0);
    } else {
        B[e].rgb += lum;
        Bu[e] = vec4(lum, 0.0);
    }
}

// What an element of M takes from a patch of C by blocks, each block's
// visibility its own (reconstruct.comp near_cells): the sum over the
// blocks of patch sh that the candidate occluders cand[0, ncand) leave
// visible from x of their form factor times their mean radiosity, over
// the elements nothing covers or closes in at this pose (gpu_element.flags),
// each's c_light. With
// the centre's visibility and the patch's mean, a floor patch whose centre
// M covers gave M's sides nothing (room 1's sliding box's sides at 0.66 of
// the CPU reference by the floor).
vec3 visible_blocks(vec3 x, vec3 ne, gpu_surface sf, gpu_shooter sh, uint cand[9], uint ncand)
{
    uint bi = (sh.i1 - sh.i0 + SHOOTING_NEAR_BLOCKS) / SHOOTING_NEAR_BLOCKS;
    uint bj = (sh.j1 - sh.j0 + SHOOTING_NEAR_BLOCKS) / SHOOTING_NEAR_BLOCKS;
    vec3 sum = vec3(0.0);
    for (uint j0 = sh.j0; j0 <= sh.j1; j0 += bj) {
        uint j1 = min(j0 + bj - 1u, sh.j1);
        for (uint i0 = sh.i0; i0 <= sh.i1; i0 += bi) {
            uint i1 = min(i0 + bi - 1u, sh.i1);
            vec3 b = vec3(0.0);
            float area = 0.0;
            bool partial = false;
            for (uint j = j0; j <= j1; j++) {
                for (uint i = i0; i <= i1; i++) {
                    uint e = sf.first_element + j * sf.nu + i;
                    if ((elements[e].flags & GPU_ELEMENT_BURIED_ANY) != 0u) {
                        partial = true;
                        continue;
                    }
                    b += c_light(e) * elements[e].pos_area.w;
                    area += elements[e].pos_area.w;
                }
            }
            if (area == 0.0)
                continue;
            // A block partly under M (the plinth top around the box's
            // foot) is its open cells one by one, as reconstruct.comp's
            // near_cells with conserve far: the block's form factor with
            // the open cells' mean lit the covered part too, the part
            // nearest M's side, and no conservation scales it back here
            // (cornell-large's rotating box 1.065 of the CPU reference on
            // its -w side, its bottom row 1.07-1.5). Visibility is the
            // open cells' as one, from their middle. One segment test and
            // one form factor in the code for both kinds of block, as
            // there (near_cells says what two cost).
            // The middle is summed for a partly covered block alone, as
            // near_cells does.
            vec3 q[4], from = vec3(0.0);
            shooting_cell_quad(sf, i0, i1, j0, j1, q);
            if (partial) {
                for (uint j = j0; j <= j1; j++) {
                    for (uint i = i0; i <= i1; i++) {
                        uint e = sf.first_element + j * sf.nu + i;
                        if ((elements[e].flags & GPU_ELEMENT_BURIED_ANY) == 0u)
                            from += elements[e].pos_area.w * cell_centroid(sf, i, j);
                    }
                }
                from /= area;
            } else {
                from = shooting_front_point(q, x, ne);
            }
            if (shooting_segment_hidden(from, x, cand, ncand))
                continue;
            uint ni = partial ? i1 - i0 + 1u : 1u, nj = partial ? j1 - j0 + 1u : 1u;
            for (uint pj = 0u; pj < nj; pj++) {
                for (uint pi = 0u; pi < ni; pi++) {
                    vec3 light = b / area;
                    if (partial) {
                        uint e = sf.first_element + (j0 + pj) * sf.nu + i0 + pi;
                        if ((elements[e].flags & GPU_ELEMENT_BURIED_ANY) != 0u)
                            continue;
                        light = c_light(e);
                        shooting_cell_quad(sf, i0 + pi, i0 + pi, j0 + pj, j0 + pj, q);
                    }
                    sum += light * shooting_point_to_quad(x, ne, q);
                }
            }
        }
    }
    return sum;
}

// NEGATIVE, INCREMENT and RECEIVE_M: element e gathers from shooters
// [first, first + count), shooter first + h having its hemicubes in layers
// h * 5...
void receive(uint e)
{
    uint se = elements[e].surface;
    gpu_surface sr = surfaces[se];
    bool moving = sr.dynamic != 0u;
    // M is reset, and takes C's light in RECEIVE_M; only C keeps what M
    // shot and takes C's changes.
    if (moving != (pc.mode == INCR_MODE_RECEIVE_M))
        return;
    // An element of M in contact (a box's bottom on the floor) takes
    // nothing: M is reset every frame, so this need not match any shot, and
    // the blocks below would light it (the floor fills its hemisphere
    // edge-on; cornell-large's box bottom at 8 times the CPU reference).
    if (moving && (elements[e].flags & GPU_ELEMENT_BURIED_ANY) != 0u)
        return;
    // An element of C under M at the new pose was set to its emission by
    // reset() and takes nothing in this step.
    if ((pc.mode == INCR_MODE_INCREMENT || pc.mode == INCR_MODE_M_LIGHT) &&
        (elements[e].flags & GPU_ELEMENT_BURIED_M) != 0u)
        return;
    // Otherwise contact (gpu_element.flags) is not tested: the hemicubes
    // alone decide here and in the progressive shots this pass removes
    // again (reconstruct_params.redistributed). Skipping buried receivers
    // in both without the reset's retraction, 10,000 frames of a sliding
    // box lost 0.4% of the power per 100 frames, steadily (an enclosed
    // ceiling element above the lamp): an element of C that M covers must
    // give back what it took while uncovered, not keep it.
    vec3 ne = elements[e].normal.xyz;
    uint ke = e - sr.first_element;
    vec3 x = cell_centroid(sr, ke % sr.nu, ke / sr.nu);
    bool near_texels = pc.neighbours != 0u;
    vec3 gathered = vec3(0.0), second = vec3(0.0);
    // The patches 32 at a time; those M's receivers see block by block
    // are marked and taken after the others (reconstruct.comp
    // form_factor_direct says why: llvmpipe ran visible_blocks' loops
    // once per patch for every receiver, M's or not).
    for (uint h0 = 0u; h0 < pc.count; h0 += 32u) {
        uint h1 = min(h0 + 32u, pc.count), marked = 0u;
        for (uint h = h0; h < h1; h++) {
            uint k = pc.first + h;
            gpu_shooter sh = shooters[k];
            if (sh.surface == se)
                continue;
            vec3 ns = sh.normal.xyz;
            vec3 d = x - sh.pos_area.xyz;
            float cs = dot(d, ns), ce = -dot(d, ne);
            bool near = shooting_near(d, sh.pos_area.w, pc.subdivide_ratio);
            if (!shooting_faces(d, cs, ce, near))
                continue;
            vec3 t = sh.tangent.xyz;
            vec3 local = vec3(dot(d, t), dot(d, cross(ns, t)), cs);
            vec3 r, m_seen = vec3(0.0);
            if (pc.mode == INCR_MODE_NEGATIVE) {
                if (!shooting_visible_at(ids_old, pc.hemicube_res, near_texels, local, h, se + 1u,
                                         sh.pos_area.xyz, x, true, true))
                    continue;
                r = -values[k].shot.rgb;
            } else if (pc.mode == INCR_MODE_M_LIGHT) {
                // M's patches at the new pose, drawn into ids_old.
                if (!shooting_visible_at(ids_old, pc.hemicube_res, near_texels, local, h, se + 1u,
                                         sh.pos_area.xyz, x, true, false))
                    continue;
                r = values[k].total.rgb;
            } else if (moving) {
                // M is reset every frame and takes C's total anew: how it sees
                // C need not match any shot that a frame removes again. Where
                // the progressive shots see a patch block by block
                // (reconstruct.comp near_within, near_cut: within two patch
                // sizes, or x's plane cutting the patch), or where its centre
                // does not see x (M covers it, or an occluder's edge passes
                // between), x sees it block by block. Within one size alone,
                // room 3's floating box (tests/solvers/rooms.c) came out at
                // 0.976 on its -z side one frame after a solve that had it at
                // 0.998, the box not moved.
                if ((near && SHOOTING_NEAR_REACH2 * sh.pos_area.w > dot(d, d)) ||
                    shooting_straddles(x, ne, ce, surfaces[sh.surface], sh) ||
                    !shooting_visible_at(ids_new, pc.hemicube_res, near_texels, local, h, se + 1u,
                                         sh.pos_area.xyz, x, true, false)) {
                    marked |= 1u << (h - h0);
                    continue;
                }
                r = values[k].lit.rgb;
            } else {
                bool was = shooting_visible_at(ids_old, pc.hemicube_res, near_texels, local, h,
                                               se + 1u, sh.pos_area.xyz, x, true, true);
                bool is = shooting_visible_at(ids_new, pc.hemicube_res, near_texels, local, h,
                                              se + 1u, sh.pos_area.xyz, x, true, false);
                if (!was && !is)
                    continue;
                r = was && !is   ? -values[k].shot.rgb  // occluded by M
                    : !was && is ? values[k].total.rgb  // unoccluded
                                 : values[k].unshot.rgb; // unchanged: a progressive shot
                // M's light reflected once more by C, for M to take back
                // (c_light): the unshot radiosity shot here holds the NEGATIVE
                // step's, which takes that bounce off C until the progressive
                // iterations shoot M's light again.
                if (is)
                    m_seen = values[k].lit.rgb;
            }
            if (all(equal(r, vec3(0.0))) && all(equal(m_seen, vec3(0.0))))
                continue;
            float ff = near ? shooting_quad(x, ne, surfaces[sh.surface], sh)
                            : shooting_disk(d, cs, ce, sh.pos_area.w);
            gathered += r * ff;
            second += m_seen * ff;
        }
        while (marked != 0u) {
            uint h = h0 + uint(findLSB(marked));
            marked &= marked - 1u;
            gpu_shooter sh = shooters[pc.first + h];
            vec3 ns = sh.normal.xyz, t = sh.tangent.xyz;
            vec3 d = x - sh.pos_area.xyz;
            vec3 local = vec3(dot(d, t), dot(d, cross(ns, t)), dot(d, ns));
            uint cand[9];
            uint nc = shooting_candidates(ids_new, pc.hemicube_res, local, h, se + 1u, cand);
            gathered += visible_blocks(x, ne, surfaces[sh.surface], sh, cand, nc);
        }
    }
    if (pc.mode == INCR_MODE_INCREMENT)
        m_light[e].rgb += elements[e].albedo.rgb * second;
    if (all(equal(gathered, vec3(0.0))))
        return;
    vec3 dB = elements[e].albedo.rgb * gathered;
    if (pc.mode == INCR_MODE_M_LIGHT) {
        m_light[e].rgb += dB;
        return;
    }
    B[e].rgb += dB;
    Bu[e].rgb += dB;
}

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (pc.mode == INCR_MODE_CAPTURE) {
        if (k < pc.count)
            capture(pc.first + k);
    } else if (pc.mode == INCR_MODE_CAPTURE_LIT) {
        if (k < pc.count)
            capture_lit(pc.first + k);
    } else if (pc.mode == INCR_MODE_CLEAR) {
        if (k < pc.count)
            m_light[k] = vec4(0.0);
    } else if (pc.mode == INCR_MODE_POWER) {
        if (k < pc.count)
            surface_power(k);
    } else if (pc.mode == INCR_MODE_RESET) {
        if (k < pc.count)
            reset(k);
    } else if (k < pc.element_count) {
        receive(k);
    }
}
