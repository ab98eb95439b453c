/*
 * Reconstruct pass layouts shared by C (src/passes/reconstruct.c) and GLSL
 * (spirv/reconstruct.comp). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_RECONSTRUCT_SHARED_H
#define XRAD_SPIRV_RECONSTRUCT_SHARED_H

#include "shared.h"

#define RECONSTRUCT_BINDING_SURFACES 0
#define RECONSTRUCT_BINDING_ELEMENTS 1
#define RECONSTRUCT_BINDING_MATERIALS 2
#define RECONSTRUCT_BINDING_B 3
#define RECONSTRUCT_BINDING_BU 4
#define RECONSTRUCT_BINDING_SHOOTERS 5
#define RECONSTRUCT_BINDING_STATUS 6     /* struct select_status: shooter_count */
#define RECONSTRUCT_BINDING_HEMICUBES 7  /* R32_UINT 2D array, layer = hemicube * 5 + face */
#define RECONSTRUCT_BINDING_FF 8         /* float[max_shooters * element_count]: F, shooter-major */
#define RECONSTRUCT_BINDING_NORM 9       /* float[max_shooters]: min(1, A_s / sum_e A_e F_es) */
#define RECONSTRUCT_BINDING_SHOT 10      /* vec4[]: the shot surface's Bu by element (select) */
#define RECONSTRUCT_BINDING_BVH_NODES 11 /* gpu_bvh_node[]: over the surfaces at the pose */
#define RECONSTRUCT_BINDING_BVH_ITEMS 12 /* uint[] */
#define RECONSTRUCT_BINDING_COUNT 13

/* With conservation, a shot takes three dispatches (see reconstruct.comp). */
#define RECONSTRUCT_MODE_DIRECT 0u   /* F and the transfer in one pass (no conservation) */
#define RECONSTRUCT_MODE_FF 1u       /* per receiver: F to every shooter into ff[] */
#define RECONSTRUCT_MODE_NORM 2u     /* a workgroup per shooter: the normalisation from ff[] */
#define RECONSTRUCT_MODE_APPLY 3u    /* per receiver: rho sum_s B_s F norm_s */

/* One invocation per receiving element; a power of two (NORM sums by halving). */
#define RECONSTRUCT_GROUP 64u

struct reconstruct_push {
    uint element_count;
    uint hemicube_res;    /* pixels per face side */
    uint neighbours;      /* 1: nearest-texel visibility check (thesis 4.3.3) */
    uint mode;            /* RECONSTRUCT_MODE_* */
    float subdivide_ratio; /* exact form factor where A_s / r^2 exceeds this (4.3.3) */
    uint max_shooters;     /* rows of ff[] */
    uint conserve_fixed;   /* 1: fixed patches are scaled too (a first solve) */
    uint static_only;      /* 1: the hemicubes draw C alone; M's elements receive nothing */
    uint redistributed;    /* 1: as incremental_reconstruct.comp sees (removed again) */
    uint near_blocks;      /* 1: near patches seen block by block (near_cells) */
};

#endif
