/*
 * Direct light pass layouts shared by C (src/passes/direct.c) and GLSL
 * (spirv/direct.comp). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_DIRECT_SHARED_H
#define XRAD_SPIRV_DIRECT_SHARED_H

#include "shared.h"

#define DIRECT_BINDING_SURFACES 0  /* struct gpu_surface[]: the scene at the frames' pose */
#define DIRECT_BINDING_MATERIALS 1 /* struct gpu_material[] */
#define DIRECT_BINDING_FRAMES 2    /* struct gpu_shooter[]: receiver point and normal */
#define DIRECT_BINDING_LIGHTS 3    /* uint[]: indices of the emitting surfaces */
#define DIRECT_BINDING_OUT 4       /* vec4[]: sum over lights of F x E, one per frame */
#define DIRECT_BINDING_BVH_NODES 5 /* struct gpu_bvh_node[]: over the surfaces */
#define DIRECT_BINDING_BVH_ITEMS 6 /* uint[] */
#define DIRECT_BINDINGS 7

#define DIRECT_GROUP 64u
/* Most blocks along a light's side: a light is split into up to 8 x 8
 * blocks, each with its exact form factor and its own visibility. */
#define DIRECT_MAX_BLOCKS 8u
/* Walk steps of one invocation past which it may have met lavapipe's
 * loop limit (65,535 iterations of all its loops; the walks are most of
 * them): out[].w counts the light chunks that came this far. */
#define DIRECT_STEP_ALARM 49152u
/* Parts per side of a block in a penumbra (direct.comp). */
#define DIRECT_SPLIT 4u

struct direct_push {
    uint first;       /* this dispatch's frames: [first, first + count) */
    uint count;
    uint light_first; /* this dispatch's lights: lights[light_first, + light_count) */
    uint light_count;
    uint accumulate;  /* 1: add to out[] (a later chunk of the lights), 0: write it */
    uint pad0, pad1, pad2;
};

#endif
