/*
 * Hemicube render pass layouts shared by C (src/passes/hemicube.c) and GLSL
 * (spirv/hemicube_*.vert|frag). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_HEMICUBE_SHARED_H
#define XRAD_SPIRV_HEMICUBE_SHARED_H

#include "shared.h"

#define HEMICUBE_BINDING_FRAMES 0 /* struct gpu_shooter[]: origin, normal, tangent per hemicube */
#define HEMICUBE_BINDING_COUNTS 1 /* uint[]: the indirect draw command (multiview reads its count) */
#define HEMICUBE_BINDING_ATLAS 2  /* radiosity variant: the atlas, sampled */

#define HEMICUBE_NO_COUNT 0xffffffffu

/* Vertex attribute locations (gpu_scene_vertex, src/solvers/gpu_scene.h). */
#define HEMICUBE_ATTR_POS 0
#define HEMICUBE_ATTR_SURFACE 1
#define HEMICUBE_ATTR_UV 2
#define HEMICUBE_ATTR_TILE 3
#define HEMICUBE_ATTR_NORMAL 4

struct hemicube_push {
    uint first;      /* frame of the draw's hemicube 0 */
    uint hemicube;   /* multiview: the hemicube of this render pass instance */
    uint count_word; /* multiview with an indirect count: index of the uint in COUNTS holding the
                        hemicube count; HEMICUBE_NO_COUNT otherwise */
    uint pad0;
    float near;      /* m: geometry nearer than this along a face's axis is clipped */
    float hair;      /* m: the origin sits this far in front of its surface */
    float scale;     /* radiosity variant: the image holds B x scale (keeps fp16 in range) */
    float depth_scale; /* radiosity variant: alpha = distance from the origin x this */
};

#endif
