/*
 * Hemicube render pass layouts shared by C (src/passes/hemicube.c) and GLSL
 * (spirv/hemicube_*.vert|frag). Same rules as shared.h.
 *
 * The hemicubes draw an indexed triangle list (gpu_scene.h): a vertex is a
 * position alone, shared by every triangle that meets it, and what belongs
 * to a triangle (its surface, its atlas coordinates) is looked up by the
 * fragment stages from the triangle's number, the draw's first triangle
 * plus gl_PrimitiveID. Vertex work is the hemicube cost on lavapipe; a
 * mesh vertex is shared by about six triangles.
 */
#ifndef XRAD_SPIRV_HEMICUBE_SHARED_H
#define XRAD_SPIRV_HEMICUBE_SHARED_H

#include "shared.h"

#define HEMICUBE_BINDING_FRAMES 0    /* struct gpu_shooter[]: origin, normal, tangent per hemicube */
#define HEMICUBE_BINDING_COUNTS 1    /* uint[]: the indirect draw command (multiview reads its count) */
#define HEMICUBE_BINDING_ATLAS 2     /* radiosity variant: the atlas, sampled */
#define HEMICUBE_BINDING_TRIANGLES 3 /* struct gpu_hemicube_triangle[] */
#define HEMICUBE_BINDING_COMMANDS 4  /* VkDrawIndexedIndirectCommand[]: the cull pass's (their
                                        firstIndex / 3 is the draw's first triangle) */
#define HEMICUBE_BINDING_POSITIONS 5 /* radiosity variant: float[3] per vertex, world */
#define HEMICUBE_BINDING_INDICES 6   /* radiosity variant: uint[3] per triangle */

#define HEMICUBE_NO_COUNT 0xffffffffu

/* Vertex attribute location: the position, float[3], world (m). */
#define HEMICUBE_ATTR_POS 0

/* Words of one VkDrawIndexedIndirectCommand: indexCount, instanceCount,
 * firstIndex, vertexOffset, firstInstance. */
#define HEMICUBE_COMMAND_WORDS 5u

/* What a fragment needs of the triangle it belongs to. */
struct gpu_hemicube_triangle {
    /* The atlas coordinate (u, v) of the triangle's corners (index order)
     * as (u w, v, w, 0): w is 1 at a quad's corners and 0 at a triangle
     * surface's apex, and the fragment takes u = (u w) / w, so that u
     * across a triangle is the collapsed quad's s = b1 / (b0 + b1)
     * (scene.h), not the linear b1 + b2 a plain uv would give. Each is the
     * element texel centre of that corner. */
    vec4 uvw[3];
    vec4 tile;    /* atlas coordinates of the surface tile's first and last texel centres
                     (u0, v0, u1, v1): lookups clamp to them */
    uint surface; /* ID hemicubes write surface + 1 */
    float sign;   /* +1 or -1: the front normal is sign x (p1 - p0) x (p2 - p0) */
    uint pad0, pad1;
};

struct hemicube_push {
    uint first;      /* frame of the draw's hemicube 0 */
    uint hemicube;   /* multiview: the hemicube of this render pass instance */
    uint count_word; /* multiview with an indirect count: index of the uint in COUNTS holding the
                        hemicube count; HEMICUBE_NO_COUNT otherwise */
    uint commands;   /* 1: the draws are COMMANDS' (the first triangle is command
                        command_base + gl_DrawID's firstIndex / 3); 0: first_triangle */
    float near;      /* m: geometry nearer than this along a face's axis is clipped */
    float hair;      /* m: the origin sits this far in front of its surface */
    float scale;     /* radiosity variant: the image holds B x scale (keeps fp16 in range) */
    float depth_scale; /* radiosity variant: alpha = distance from the origin x this */
    uint first_triangle; /* without commands: the draw's first triangle */
    uint command_base;   /* with commands: the first command of this draw call */
    uint pad0, pad1;
};

#endif
