/*
 * A bounding volume hierarchy over world quads (4 corners each), for the
 * scene layer's own rays (scene_contact.c's enclosure test): it only
 * narrows the candidates, whose exact tests stay with the caller, so the
 * answers are those of a loop over every quad. Median splits along the
 * longest axis of the centres, at most QUAD_BVH_LEAF quads a leaf.
 */
#ifndef XRAD_SCENE_QUAD_BVH_H
#define XRAD_SCENE_QUAD_BVH_H

#include <stdbool.h>
#include <stdint.h>

#include "core/vec.h"
#include "xrad.h"

#define QUAD_BVH_LEAF 4

typedef struct quad_bvh_node {
    double lo[3], hi[3];
    uint32_t first, count; /* leaf: items[first, first + count); inner: count 0, children
                              `first` and `first + 1` */
} quad_bvh_node;

typedef struct quad_bvh {
    quad_bvh_node *nodes;
    uint32_t *items; /* quad indices */
    uint32_t node_count;
} quad_bvh;

/* Over quads[0, n) (corners[4 q + k]), each box grown by `pad` (m). */
xrad_status quad_bvh_build(const vec3 *corners, uint32_t n, double pad, quad_bvh *out,
                           xrad_error *err);
/* Accepts a zeroed struct; zeroes it. */
void quad_bvh_free(quad_bvh *bvh);

/* Calls visit(user, q, &tmax) for every quad q whose box the ray
 * o + t d meets at some t in [tmin, tmax]; visit may lower tmax (a nearer
 * hit) and returns true to stop. Returns whether a visit stopped it. */
bool quad_bvh_ray(const quad_bvh *bvh, vec3 o, vec3 d, double tmin, double tmax,
                  bool (*visit)(void *user, uint32_t q, double *tmax), void *user);

#endif
