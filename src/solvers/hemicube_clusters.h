/*
 * The hemicubes' indexed triangle list (gpu_scene.h) and its layout in
 * clusters the cull pass can leave out (passes/hemicube_cull.h): static
 * surfaces first (a draw of the first static_index_count indices shows the
 * static set C alone), object by object, and within an object along a
 * Morton curve of the surfaces' centres, so that a run of surfaces is a
 * compact patch with a narrow cone of normals; a cluster is such a run of
 * at most HEMICUBE_CLUSTER_TRIANGLES triangles (a quad counts two) of one
 * object.
 *
 * Vertices are shared within a cluster: its corners at the same model
 * position are one vertex (a mesh vertex, a box's corner), numbered in
 * the order the triangles first use them, so that each cluster's
 * triangles use a run of vertices of their own, and the hemicubes draw
 * cluster by cluster. Each triangle names first a vertex no other
 * triangle names first, its provoking vertex, which carries its surface
 * and number as flat attributes (spirv/hemicube_shared.h): about one
 * vertex a triangle in all (heavy-sphere: 103,877 for 100,838), against
 * three unindexed. Per ID hemicube on lavapipe (64 x 64, 32 hemicubes a
 * draw), unindexed -> indexed: heavy-sphere 28 -> 15 ms, wuson-room 3.9 ->
 * 3.2-3.6 ms, a 5,120-face ball in a room 2.3 -> 2.2 ms.
 * An object whose surfaces close up (every edge shared by exactly two of
 * them, wound opposite ways) with their fronts outside (positive volume)
 * gets normal cones: seen from outside, its back faces lie behind its
 * front faces.
 *
 * Built once per scene (the order does not change with the pose); the
 * bounds follow every pose.
 */
#ifndef XRAD_SOLVERS_HEMICUBE_CLUSTERS_H
#define XRAD_SOLVERS_HEMICUBE_CLUSTERS_H

#include <stdbool.h>
#include <stdint.h>

#include "hemicube_cull_shared.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "xrad.h"

#define HEMICUBE_CLUSTER_TRIANGLES 256u

typedef struct hemicube_clusters {
    uint32_t *order;        /* surface_count: the surfaces in drawing order */
    uint32_t *first_index;  /* surface_count, by surface: its first index (3 per triangle) */
    uint32_t *indices;      /* index_count: 3 per triangle, in drawing order, its provoking
                               vertex first */
    uint8_t *corners;       /* index_count: the surface corner (scene.h p0..p3) of each index */
    uint32_t *triangle_surface; /* index_count / 3 */
    uint32_t index_count, static_index_count;
    uint32_t vertex_count;
    uint32_t *vertex_source;   /* vertex_count: 4 x surface + corner of the corner it is at */
    uint32_t *vertex_triangle; /* vertex_count: the triangle it provokes, or UINT32_MAX */
    uint32_t *start;        /* count + 1: cluster k is order[start[k] .. start[k + 1]) */
    uint32_t *first;        /* count + 1: cluster k's indices are [first[k], first[k + 1]) */
    uint32_t count;         /* clusters */
    uint32_t static_count;  /* the first static_count clusters hold the static surfaces */
    uint8_t *closed;        /* object_count: 1 where the object is closed, fronts outside */
} hemicube_clusters;

/* Hemicube triangles of a surface: a quad's two, a triangle's one (its
 * second would be the collapsed one: work for nothing). */
static inline uint32_t hemicube_surface_triangles(const surface *sf)
{
    return sf->triangle ? 1 : 2;
}

/* Corners of triangle k of a surface (scene.h p0..p3): 0 1 2, then 0 2 3. */
static inline int hemicube_triangle_corner(uint32_t k, int i)
{
    static const int corner[2][3] = {{0, 1, 2}, {0, 2, 3}};
    return corner[k][i];
}

xrad_status hemicube_clusters_build(const xrad_scene *scene, hemicube_clusters *out,
                                    xrad_error *err);
/* Accepts a zeroed struct; zeroes it. */
void hemicube_clusters_free(hemicube_clusters *c);

/* out[count]: each cluster's bounds from the posed surfaces (world
 * corners and normals). */
void hemicube_clusters_bounds(const hemicube_clusters *c, const xrad_scene *scene,
                              const struct gpu_surface *surfaces, struct gpu_cluster *out);

#endif
