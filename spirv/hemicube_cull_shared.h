/*
 * Hemicube cull pass layouts shared by C (src/passes/hemicube_cull.c,
 * src/solvers/gpu_scene.c) and GLSL (spirv/hemicube_cull.comp). Same rules
 * as shared.h.
 */
#ifndef XRAD_SPIRV_HEMICUBE_CULL_SHARED_H
#define XRAD_SPIRV_HEMICUBE_CULL_SHARED_H

#include "shared.h"

#define CULL_BINDING_CLUSTERS 0 /* struct gpu_cluster[] */
#define CULL_BINDING_FRAMES 1   /* struct gpu_shooter[]: the hemicubes' frames */
#define CULL_BINDING_STATUS 2   /* uint[]: the shot's hemicube count at count_word */
#define CULL_BINDING_COMMANDS 3 /* VkDrawIndexedIndirectCommand[]: one per cluster, written */

#define CULL_GROUP 64u
#define CULL_NO_COUNT 0xffffffffu /* cull_push.count_word: the count is cull_push.count */
#define CULL_COMMAND_WORDS 5u      /* uints of one VkDrawIndexedIndirectCommand */

/* A run of hemicube triangles (whole surfaces of one object, gpu_scene.h)
 * and its bounds at the pose the positions hold, world space. */
struct gpu_cluster {
    vec4 center;     /* xyz: centre of the bounding box; w: its half diagonal (m) */
    vec4 half_size;  /* xyz: half the box's size; w: the normal cone's half-angle (rad), or
                        < 0 where the triangles are not all on a closed mesh's outside */
    vec4 cone_axis;  /* xyz: unit mean direction of the triangles' front normals */
    vec4 object_lo;  /* the closed mesh's box: an origin in it skips the cone test */
    vec4 object_hi;
    uint first_index, index_count, pad0, pad1; /* its indices: 3 per triangle */
};

struct cull_push {
    uint cluster_count;
    uint first;       /* frame of hemicube 0 */
    uint count_word;  /* uint of STATUS holding the shot's hemicube count, or CULL_NO_COUNT */
    uint instances;   /* each command's instanceCount; 0: STATUS's uint at instance_word */
    uint instance_word;
    float margin;     /* m: tests pass only by more than this (the origin's hair, rounding) */
    uint count;       /* the number of hemicubes where count_word is CULL_NO_COUNT */
    float pad0;
};

#endif
