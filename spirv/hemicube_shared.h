/*
 * Hemicube render pass layouts shared by C (src/passes/hemicube.c) and GLSL
 * (spirv/hemicube_*.vert|frag). Same rules as shared.h.
 *
 * The hemicubes draw an indexed triangle list (gpu_scene.h,
 * solvers/hemicube_clusters.h): vertices are shared between triangles, and
 * each triangle has a vertex of its own that it names first, its
 * provoking vertex, whose flat attributes (surface, triangle) are the
 * triangle's. The fragment stages look up the rest (atlas coordinates) by
 * the triangle's number. Vertex work is the hemicube cost on lavapipe,
 * and gl_PrimitiveID is no way round it there: a fragment shader that
 * reads it makes lavapipe copy out three vertices per triangle.
 */
#ifndef XRAD_SPIRV_HEMICUBE_SHARED_H
#define XRAD_SPIRV_HEMICUBE_SHARED_H

#include "shared.h"

#define HEMICUBE_BINDING_FRAMES 0 /* struct gpu_shooter[]: origin, normal, tangent per hemicube */
#define HEMICUBE_BINDING_COUNTS 1 /* uint[]: the indirect draw command (multiview reads its count) */
#define HEMICUBE_BINDING_ATLAS 2  /* radiosity variant: the atlas, sampled */
/* Radiosity variant only: */
#define HEMICUBE_BINDING_TRIANGLES 3 /* struct gpu_hemicube_triangle[] */
#define HEMICUBE_BINDING_VERTICES 4  /* struct gpu_hemicube_vertex[] */
#define HEMICUBE_BINDING_INDICES 5   /* uint[3] per triangle */

#define HEMICUBE_NO_COUNT 0xffffffffu

/* Vertex attribute locations (struct gpu_hemicube_vertex). */
#define HEMICUBE_ATTR_POS 0
#define HEMICUBE_ATTR_IDS 1

/* A hemicube vertex. surface and triangle are those of the triangle whose
 * provoking vertex it is (any, where it is none's). */
struct gpu_hemicube_vertex {
    float x, y, z; /* m, world */
    uint surface, triangle;
};

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
    float sign;   /* +1 or -1: the front normal is sign x (p1 - p0) x (p2 - p0) */
    uint pad0, pad1, pad2;
};

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
