/*
 * Exact visibility for the CPU reference solver (the HID function of thesis
 * eq. 2.2.3 for a point and a polygon): the part of a planar convex polygon
 * that a point sees past planar convex quads, cut by plane clipping into
 * disjoint convex pieces. The visible form factor is the analytic kernel
 * (ff_kernel.h) summed over the pieces, so it is exact up to rounding and
 * the clipping tolerance; the ray estimate (raycast.h) is kept for the pairs
 * whose pieces exceed the caps here.
 *
 * The shadow of an occluder Q on a polygon C seen from p is the set of
 * points x of C whose segment p -> x meets Q. Only the part of Q between
 * C's plane and the plane through p parallel to it can meet such a segment;
 * with Q clipped to that slab, the shadow is C intersected with the cone
 * from p through the clipped Q: the half-spaces bounded by the planes
 * through p and each of its edges. C is clipped by those planes directly;
 * nothing is projected, so no coordinate grows without bound as Q nears
 * p's parallel plane.
 */
#ifndef XRAD_REFERENCE_SHADOW_H
#define XRAD_REFERENCE_SHADOW_H

#include <stdbool.h>
#include <stdint.h>

#include "core/vec.h"
#include "reference/ff_kernel.h"
#include "reference/raycast.h"

/* A quad clipped by the two planes of a slab has at most 6 edges. */
#define REF_CONE_MAX 6

/* The shadow cone of one occluder from apex p onto one plane: the points x
 * with m[k] . (x - p) >= 0 for every k < count (m unit). count 0: the
 * occluder blocks nothing there. */
typedef struct ref_cone {
    int count;
    vec3 m[REF_CONE_MAX];
} ref_cone;

/* The cone of quad q from apex p onto the plane through `at` with unit
 * normal `normal`, p on its front side. Parts of q within `tol` (a length)
 * of that plane do not block: they meet segments from p at their end, which
 * is what a coplanar or touching occluder does. q blocks nothing when p
 * lies within `tol` of q's plane (segments from p meet it edge-on) or when
 * its clipped part is narrower than `tol`. Returns false when an edge of
 * the clipped quad is so nearly in line with p that its plane through p is
 * not resolved to the tolerance; the cone is then unusable. */
bool ref_cone_init(ref_cone *cone, const ref_quad *q, vec3 p, vec3 at, vec3 normal, double tol);

/* Caps on the visible part's pieces: past them a pair falls back to rays. */
#define REF_PIECES_MAX 64

/* Working memory of ref_ff_point_visible: the visible part so far, as
 * disjoint convex polygons of at most REF_POLY_MAX vertices each. */
typedef struct ref_pieces {
    int count;
    int verts[REF_PIECES_MAX];
    vec3 v[REF_PIECES_MAX][REF_POLY_MAX];
} ref_pieces;

/* Form factor from point p (unit normal n) to the part of the convex planar
 * polygon poly[0..count-1] (count 3..REF_POLY_MAX) outside every cone of
 * cones[0..cone_count-1], all with apex p and built for poly's plane.
 * `whole` is ref_ff_point_polygon(p, n, poly, count), returned unchanged
 * when no cone reaches the polygon. Clipping treats a vertex within `tol`
 * of a cone's plane as on it, so a polygon that only grazes a cone is not
 * cut into slivers. Writes *f and returns true, or returns false without
 * writing when the visible part needs more than REF_PIECES_MAX pieces or a
 * piece more than REF_POLY_MAX vertices. Thread-safe for distinct `work`. */
bool ref_ff_point_visible(vec3 p, vec3 n, const vec3 *poly, int count, double whole,
                          const ref_cone *cones, uint32_t cone_count, double tol,
                          ref_pieces *work, double *f);

#endif
