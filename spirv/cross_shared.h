/*
 * Cross redistribution radiosity layouts shared by C (src/passes/
 * cross_update.c, src/passes/cross_reconstruct.c, src/solvers/cross.c) and
 * GLSL (spirv/cross_update.comp, spirv/cross_reconstruct.comp). Same rules
 * as shared.h.
 *
 * The patches of the dynamic set M (thesis 4.5.1: no substructuring of M,
 * one patch per coarse sample) are fixed: every dynamic surface is cut into
 * cx x cy rectangles of its elements, cx x cy the sample counts of the
 * object's cross_density (scene.h). Patch p owns the coarse sample (ci, cj)
 * of its surface, where its gather hemicube sits (R_g(C, M), thesis 4.5.1);
 * the elements of M take B from C by bilinear interpolation of those
 * samples, as the display interpolates elements (thesis 4.1).
 *
 * Buffers:
 *   patches[p]       cross_patch   the fixed layout, what no pose changes
 *   values[p]        cross_value   total radiosity after R_g(C, M) and R_p(M, M)
 *   frames[...]      gpu_shooter   hemicube frames, written by the host per pose
 *   quads[p]         cross_quad    world corners of each patch at the pose
 *   inserted[e]      vec4          what the last redistribution added to B of
 *                                  static element e: R_p(M, C) + R_x(C, C)
 *   gathered[p]      vec4          R_g(C, M) sums (integrate pass output); then
 *                                  [P + p] the horizon ring's mean radiosity
 *                                  (integrate_shared.h)
 *   surface_patch[s] uint          the patch (ci, cj) = (0, 0) of dynamic surface s (a
 *                                  mesh face: its group); after surface_count of them,
 *                                  the groups' member surfaces
 */
#ifndef XRAD_SPIRV_CROSS_SHARED_H
#define XRAD_SPIRV_CROSS_SHARED_H

#include "shared.h"

/* A block patch covers elements of one surface; a group patch (a dynamic
 * mesh's faces, member_count > 0) covers every element of the surfaces
 * surface_patch[member_first .. member_first + member_count - 1] (the tail
 * of that buffer), and its one gather hemicube gives them all their B. */
struct cross_patch {
    uint surface;    /* a dynamic surface (a group: its first member) */
    uint i0, i1, j0; /* its elements [i0, i1] x [j0, j1] (blocks) */
    uint j1;
    uint ci, cj;     /* its coarse sample (gather hemicube) */
    uint cx, cy;     /* coarse samples of that surface along s and t, each >= 2 (blocks) */
    uint member_first, member_count; /* groups; 0 0 for blocks */
    uint pad0;
};

struct cross_value {
    vec4 total; /* area mean of B after R_g(C, M), then after R_p(M, M) */
};

struct cross_quad {
    vec4 corner[4]; /* world, at one pose, counter-clockwise seen from the front */
};

/* Frames buffer: three tables of patch_count gpu_shooter each: front (patch centre, normal), back (same
 * centre, normal reversed: sees what lies behind the patch) and gather
 * (coarse sample, normal). */
#define CROSS_FRAMES_FRONT 0u
#define CROSS_FRAMES_BACK 1u
#define CROSS_FRAMES_GATHER 2u
#define CROSS_FRAME_TABLES 3u

/* cross_update.comp modes */
#define CROSS_UPDATE_RESET 0u      /* per element of M: B = E, Bu = 0 */
#define CROSS_UPDATE_INDIRECT_C 1u /* per element: out = B - Bu - E on C, 0 on M (the atlas), peak */
#define CROSS_UPDATE_GATHERED 2u   /* per element of M: B = E + rho x gathered (interpolated), Bu = 0 */
#define CROSS_UPDATE_TOTAL 3u      /* per patch: values.total = mean(B) */
/* a workgroup per mesh group: B = E + rho x its gather hemicube reprojected
 * to each face's point, Bu = 0 (GATHERED leaves those elements) */
#define CROSS_UPDATE_GROUPS 4u

#define CROSS_UPDATE_BINDING_SURFACES 0
#define CROSS_UPDATE_BINDING_ELEMENTS 1
#define CROSS_UPDATE_BINDING_MATERIALS 2
#define CROSS_UPDATE_BINDING_B 3
#define CROSS_UPDATE_BINDING_BU 4
#define CROSS_UPDATE_BINDING_PATCHES 5
#define CROSS_UPDATE_BINDING_VALUES 6
#define CROSS_UPDATE_BINDING_GATHERED 7
#define CROSS_UPDATE_BINDING_OUT 8
#define CROSS_UPDATE_BINDING_SURFACE_PATCH 9 /* uint[surface]: its patch (0, 0); static: none;
                                                then the groups' members */
/* uint: INDIRECT_C's largest |component| written, as float bits (atomicMax:
 * the bits of non-negative floats order as the floats). */
#define CROSS_UPDATE_BINDING_PEAK 10
/* gpu_shooter[3][patch_count]: the frames (GATHERED: a group's gather frame) */
#define CROSS_UPDATE_BINDING_FRAMES 11
/* The gather hemicubes (texture2DArray, patch p in layers 5p..5p+4; RGB: B
 * x scale, A: distance / diameter, hemicube_radiosity.frag): GATHERED
 * reprojects a group's hemicube to each of its faces. */
#define CROSS_UPDATE_BINDING_GATHER_HEMICUBES 12
#define CROSS_UPDATE_BINDING_COUNT 13

#define CROSS_UPDATE_GROUP 64u

struct cross_update_push {
    uint mode;
    uint count;        /* invocations: patches or elements */
    uint element_count;
    uint patch_count;
    /* GATHERED: the gather hemicubes' resolution, the scale they hold B
     * by, and the distance their alpha is a fraction of (m) */
    uint res;
    float inv_scale;
    float diameter;
    uint pad;
};

#define CROSS_RECONSTRUCT_BINDING_SURFACES 0
#define CROSS_RECONSTRUCT_BINDING_ELEMENTS 1
#define CROSS_RECONSTRUCT_BINDING_MATERIALS 2
#define CROSS_RECONSTRUCT_BINDING_B 3
#define CROSS_RECONSTRUCT_BINDING_BU 4
#define CROSS_RECONSTRUCT_BINDING_VALUES 5
#define CROSS_RECONSTRUCT_BINDING_FRAMES 6
#define CROSS_RECONSTRUCT_BINDING_QUADS 7
#define CROSS_RECONSTRUCT_BINDING_IDS 8  /* R32_UINT array, patch p in layers p*5.. */
#define CROSS_RECONSTRUCT_BINDING_BACK 9 /* RGBA16F array: shot radiosity x scale, distance */
#define CROSS_RECONSTRUCT_BINDING_INSERTED 10 /* vec4[element_count] */
/* The lights of C (static emitters) in fixed patches: gpu_shooter and
 * cross_quad [light_count], and their ID hemicubes of C alone and of C
 * and M at the pose (R32_UINT arrays, light l in layers l*5..). */
#define CROSS_RECONSTRUCT_BINDING_LIGHTS 11
#define CROSS_RECONSTRUCT_BINDING_LIGHT_QUADS 12
#define CROSS_RECONSTRUCT_BINDING_LIGHT_IDS_C 13
#define CROSS_RECONSTRUCT_BINDING_LIGHT_IDS 14
/* The hierarchy over the surfaces at the pose (gpu_bvh_node, uint). */
#define CROSS_RECONSTRUCT_BINDING_BVH_NODES 15
#define CROSS_RECONSTRUCT_BINDING_BVH_ITEMS 16
/* The pair list of phase C (issue 16.1): cross_pair[pair_capacity], uvec2
 * per element (its first pair and count, or CROSS_RANGE_*), and
 * cross_pair_state (the count and the indirect dispatch). */
#define CROSS_RECONSTRUCT_BINDING_PAIRS 17
#define CROSS_RECONSTRUCT_BINDING_RANGES 18
#define CROSS_RECONSTRUCT_BINDING_PAIR_STATE 19
/* uint[pair_capacity]: the pairs in patch order (C_SCATTER), which C_EVAL
 * follows; uint[3 patch_count]: per patch its pairs, its first place in
 * that order, the places taken. */
#define CROSS_RECONSTRUCT_BINDING_ORDER 20
#define CROSS_RECONSTRUCT_BINDING_PATCH_LISTS 21
/* uint: the largest |B - Bu - E| of C as float bits (cross_update.comp's
 * INDIRECT_C): the most the back hemicubes show (pc.cut). */
#define CROSS_RECONSTRUCT_BINDING_PEAK 22
/* vec4[]: the back hemicubes' levels 1..back_levels (spirv/back_mips.glsl). */
#define CROSS_RECONSTRUCT_BINDING_BACK_MIPS 23
/* uint[light_count]: light l's hemicube in LIGHT_IDS (the lights whose
 * view M can reach at the pose are drawn, one after another), or
 * CROSS_LIGHT_UNREACHED: M lies behind the light's plane, so M neither
 * takes its light nor hides any of it. */
#define CROSS_RECONSTRUCT_BINDING_LIGHT_LAYERS 24
/* vec4[element_count] (push `luminaires`): rho x the luminaires' direct
 * light at the pose on M, its change from that of C alone on C
 * (src/solvers/luminaire_change.h). */
#define CROSS_RECONSTRUCT_BINDING_LUMINAIRES 25
#define CROSS_RECONSTRUCT_BINDING_COUNT 26
#define CROSS_LIGHT_UNREACHED 0xffffffffu

/* cross_reconstruct.comp phases */
#define CROSS_RECONSTRUCT_M_DIRECT 0u /* elements of M: the direct light of C's lights */
#define CROSS_RECONSTRUCT_M 1u        /* elements of M: R_p(M, M) */
#define CROSS_RECONSTRUCT_C 2u        /* elements of C: R_p(M, C) + R_x(C, C) replace the last
                                         ones, from the pairs' values */
#define CROSS_RECONSTRUCT_C_PAIRS 3u  /* elements of C: the (element, patch) pairs it sees */
#define CROSS_RECONSTRUCT_C_ARGS 4u   /* one invocation: the patches' places, the indirect
                                         dispatch of C_SCATTER and C_EVAL */
#define CROSS_RECONSTRUCT_C_SCATTER 6u /* per pair (indirect): its place in patch order */
#define CROSS_RECONSTRUCT_C_EVAL 5u   /* per pair in patch order (indirect): F (B_s - P(C, s, e)) */

/* One (element, patch) pair of phase C: the patch's form factor to the
 * element where it sees it; C_EVAL writes value. */
struct cross_pair {
    uint element, patch_index;
    float ff;
    uint pad0;
    vec4 value;
};

/* The most pairs one element keeps while it looks (C_PAIRS). */
#define CROSS_PAIRS_LOCAL 64u

/* ranges[e].y where element e has no pairs of its own to sum */
#define CROSS_RANGE_SKIP 0xffffffffu   /* M, or buried: phase C leaves it */
#define CROSS_RANGE_HIDDEN 0xfffffffeu /* covered by a patch (covered()) */
#define CROSS_RANGE_INLINE 0xfffffffdu /* the list was full, or the element sees more than
                                          CROSS_PAIRS_LOCAL patches: phase C loops */

struct cross_pair_state {
    uint count;       /* pairs asked for (may pass the capacity) */
    uint listed;      /* pairs in the list (C_ARGS) */
    uint pad0, pad1;
    uint scatter[4];  /* VkDispatchIndirectCommand of C_SCATTER (every slot asked for), a pad */
    uint eval[4];     /* that of C_EVAL (the pairs listed), a pad */
};

#define CROSS_RECONSTRUCT_GROUP 64u

struct cross_reconstruct_push {
    uint element_count;
    uint patch_count;
    uint hemicube_res;     /* ID hemicubes */
    uint back_res;         /* back hemicubes */
    uint grid;             /* PROJECTEDRADIOSITY rays per side (thesis 4.5.3 gridSize) */
    uint bilinear;         /* 1: back hemicubes filtered bilinearly across face edges */
    uint phase;            /* CROSS_RECONSTRUCT_M or _C */
    uint neighbours;       /* 1: nearest-texel visibility check (thesis 4.3.3) */
    float subdivide_ratio; /* exact form factor where A_s / r^2 exceeds this (4.3.3) */
    float inv_scale;       /* 1 / the back hemicubes' radiosity scale */
    float diameter;        /* m: back hemicube alpha x this = distance */
    uint first;            /* elements [first, first + count) of this dispatch */
    uint count;
    uint light_count;      /* light patches (0: the light bindings are placeholders) */
    float grid_ff;         /* a pair of form factor F below this gets
                              ceil(grid sqrt(F / grid_ff)) rays a side, at least 1 */
    uint pair_capacity;    /* cross_pair entries of the list; 0: no list (cross_pairs off) */
    float cut;             /* a pair of C whose term can be at most this share of the
                              largest radiosity is left out (xrad.h cross_cut); 0: none */
    uint back_levels;      /* mip levels of the back hemicubes above level 0 (0: none) */
    uint luminaires;       /* 1: M_DIRECT and phase C add the luminaires buffer */
};

/* Back hemicube mips (src/passes/back_mips.c, spirv/back_mips.comp; layout
 * in spirv/back_mips.glsl). */
#define BACK_MIPS_BINDING_BACK 0 /* RGBA16F/32F array, SHADER_READ_ONLY_OPTIMAL */
#define BACK_MIPS_BINDING_MIPS 1 /* vec4[layers x levels' texels] */
#define BACK_MIPS_BINDING_COUNT 2
#define BACK_MIPS_GROUP 64u
#define BACK_MIPS_MAX_LEVELS 8u

struct back_mips_push {
    uint res;    /* level 0's face side */
    uint levels; /* levels made above level 0: res is divisible by 2^levels */
    uint count;  /* invocations: layers x back_mip_layer_texels */
    uint pad0;
};

#endif
