/*
 * Select pass layouts shared by C (src/passes/select.c) and GLSL
 * (spirv/select_power.comp, spirv/select.comp): the status block the pass
 * writes for every shot, and the push constants. Same rules as shared.h:
 * vec4s and 4-byte scalars only, every struct a multiple of 16 bytes.
 */
#ifndef XRAD_SPIRV_SELECT_SHARED_H
#define XRAD_SPIRV_SELECT_SHARED_H

#include "shared.h"

#define SELECT_BINDING_SURFACES 0
#define SELECT_BINDING_ELEMENTS 1
#define SELECT_BINDING_BU 2
#define SELECT_BINDING_POWER 3
#define SELECT_BINDING_SHOOTERS 4
#define SELECT_BINDING_STATUS 5
#define SELECT_BINDING_SHOT 6 /* vec4[select_shot_capacity()]: the shot surfaces' Bu in rgb,
                                 the element's area in w, -1 where buried (select.comp) */
#define SELECT_BINDING_COUNT 7

#define SELECT_POWER_GROUP 64u /* select_power.comp: one invocation per surface */
#define SELECT_GROUP 256u      /* select.comp: one workgroup does the whole choice */
#define SELECT_NONE 0xffffffffu
/* A shot's group (select.comp): the surfaces that join the chosen one hold
 * at least this share of its power; at most SELECT_GROUP_MAX join. */
#define SELECT_GROUP_SHARE 0.125
#define SELECT_GROUP_MAX 64u

/* Written by every shot; read by the hemicube pass (draw), the reconstruct
 * pass (dispatch, shooter_count) and, once per batch, by the host.
 * The host zeroes it before the first shot of a solve. */
struct select_status {
    /* VkDrawIndexedIndirectCommand of the ID hemicube draw: index_count from
     * the push constants, instance_count = shooter_count x
     * instances_per_hemicube. */
    uint draw_index_count, draw_instance_count, draw_first_index, draw_vertex_offset,
        draw_first_instance;
    /* VkDispatchIndirectCommand of the reconstruct pass (x = 0 when there is
     * nothing to shoot), then the shooters of this shot. */
    uint dispatch_x, dispatch_y, dispatch_z, shooter_count;
    uint surface;   /* chosen this shot; SELECT_NONE when nothing was shot */
    uint kx, ky;    /* patches along the surface's s and t */
    uint converged; /* sticky: 1 once the largest power fell to threshold x max_power */
    float power;     /* luminance of sum_e Bu_e A_e of the surface examined this shot, W */
    float max_power; /* largest such power seen in this solve (the first shot's) */
    float unshot;     /* the sum of that power over every surface, before this shot, W */
    float max_unshot; /* largest such sum seen in this solve (the first shot's: all emitted) */
    uint selections; /* shots that shot something, this solve */
    uint patches;    /* shooting patches (= ID hemicubes) shot, this solve */
    uint surfaces;   /* surfaces shot, this solve: a shot's group counts each */
};

struct select_push {
    uint surface_count;
    uint element_count;
    uint max_patches;   /* most patches along a side (thesis 4.3.3) */
    uint max_shooters;  /* room in the shooter table and the hemicube image */
    uint draw_index_count;
    uint instances_per_hemicube;
    uint seed;          /* hemicube rotations (thesis 4.2) */
    uint reconstruct_group; /* workgroup size of the reconstruct dispatch */
    float threshold;    /* converged when power <= threshold x max_power ... */
    uint linear_rule;   /* 1: patches follow the power share, not its square root */
    uint buried_mask;   /* GPU_ELEMENT_* flags of elements a patch does not shoot from */
    float unshot_share; /* ... and unshot <= unshot_share x max_unshot (0: no such test) */
    uint group_shooters; /* most shooters of a shot with its group (0: no group) */
    uint group_elements; /* most elements of a surface that joins a group; its `shot`
                            entries start at the chosen surface's count + j x this */
    uint shot_first;    /* entries of `shot` the chosen surface may take */
    uint pad0;
};

#endif
