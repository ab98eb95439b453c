/*
 * Internals of the CPU reference solver (xrad_reference_solve), exposed for
 * its tests. The solver shares no radiosity code with the GPU path: form
 * factors come from the analytic point-to-polygon kernel (ff_kernel.h),
 * visibility from polygon clipping (shadow.h), and B from Gauss-Seidel on
 * the dense system B = E + rho F B (thesis eq. 2.2.2 with elements, 2.2.4).
 *
 * Discretisation: element i receives at its sample point x_i (scene.h) with
 * its surface's normal; element j emits from its cell, the part of its
 * surface within half a sample spacing of its sample, clipped to the
 * surface. F_ij is the kernel summed over the part of cell_j that x_i sees
 * past the other quads, cut out exactly by clipping, so that the rows of F
 * close in a closed scene. Where clipping gives up (more pieces than
 * shadow.h allows, or an occluder's edge nearly in line with x_i), F_ij =
 * F(x_i -> cell_j) * V_ij instead, where V_ij is the visible fraction of
 * `rays` segments from x_i to stratified points of cell_j (raycast.h), each
 * segment weighted by the form factor integrand at its end point.
 *
 * Clipping culls occluder candidates by a loop over every quad for every
 * (receiver, surface) pair: O(N S^2) for N elements and S surfaces, fine for
 * quad scenes (S < 100), an hour for a mesh of a thousand triangles. Beyond
 * XRAD_REFERENCE_CLIP_SURFACES surfaces (or when asked) every pair takes the ray
 * estimate instead, through Embree's BVH (embree_rays.h): O(N^2 rays log S).
 */
#ifndef XRAD_REFERENCE_REFERENCE_H
#define XRAD_REFERENCE_REFERENCE_H

#include <stdbool.h>
#include <stdint.h>

#include "reference/embree_rays.h"
#include "reference/raycast.h"
#include "reference/shadow.h"
#include "scene/scene.h"
#include "xrad.h"

/* The scene at one time, in world space, ready for form factors. */
typedef struct ref_geometry {
    uint32_t element_count, surface_count;
    uint32_t rays;         /* visibility rays per pair where clipping gives up */
    double scale;          /* m, diagonal of the scene's bounding box */
    double tol;            /* m, separation tolerance of occluder culling and clipping */
    ref_quad *quads;       /* per surface, world corners */
    uint32_t *surface_first, *surface_elements; /* per surface, its element range */
    uint32_t *surface_of;  /* per element */
    vec3 *recv;            /* per element, the receiving point (world) */
    vec3 *origin;          /* per element, the rays' origin: recv a hair along normal */
    vec3 *normal;          /* per element, unit (world): the receiver normal, its normal
                              map's where it has one (scene_element_normal) */
    vec3 (*cell)[4];       /* per element, its cell's world corners, wound like its surface */
    ref_rays *bvh;         /* rays visibility (XRAD_VISIBILITY_RAYS): every pair by `rays`
                              Embree rays; NULL: exact clipping */
} ref_geometry;

/* Ray origins sit this fraction of the scene's diagonal above the surface. */
#define REF_RAY_HAIR 1e-7


/* Builds the world-space geometry at scene time `time`; with `bvh`, also
 * the ray BVH (rays visibility). */
xrad_status ref_geometry_create(const xrad_scene *scene, double time, uint32_t rays, bool bvh,
                                ref_geometry **out, xrad_error *err);
void ref_geometry_destroy(ref_geometry **geometry);

/* A receiving point of element `element` (surface `surface`): its
 * position p, receiver normal n and rays' origin o. An element's own is
 * its cell's centre (ref_receiver_of); xrad_reference_desc.cell_points
 * adds others over its cell. */
typedef struct ref_receiver {
    vec3 p, n, o;
    uint32_t element, surface;
} ref_receiver;

static inline ref_receiver ref_receiver_of(const ref_geometry *g, uint32_t i)
{
    return (ref_receiver){g->recv[i], g->normal[i], g->origin[i], i, g->surface_of[i]};
}

/* A receiving point pressed against another face: within REF_CONTACT_TOL
 * of the scene's diagonal of a quad (not its own) that faces it, normals
 * within a degree of opposite (a box standing on a plinth: its bottom and
 * the plinth's top under it). It sees nothing: its form factors are 0.
 * Without this test its rays, which leave a hair above its surface, would
 * start behind the face it lies on and see whatever that face closes in.
 * The GPU methods find the same elements by their own rays
 * (scene_find_enclosed). */
#define REF_CONTACT_TOL 1e-6
bool ref_receiver_pressed(const ref_geometry *g, const ref_receiver *r);

/* The visible fraction of F(x_i -> polygon) (thesis eq. 2.2.3's HID
 * term): g->rays rays from the origin of receiver r to stratified points
 * of `poly` (4 world corners, wound like its surface; `poly_normal` its unit
 * normal) drawn from `seed`, each weighted by the form factor integrand at
 * its end (cos phi_i cos phi_j / r^2; the 1/pi and the uniform area
 * element cancel in the ratio), so that the estimate converges to the
 * exact visible form factor as rays grow; an unweighted fraction of the
 * area converges to a biased value where the polygon is large next to its
 * distance to x_i. Blockers: the `count` candidate quads, or with g->bvh
 * every quad but r's own, `target` (the polygon's surface) and those in
 * their planes. */
double ref_visible_fraction(const ref_geometry *g, const ref_receiver *r, uint32_t target,
                            const vec3 *poly, vec3 poly_normal, uint64_t seed, const uint32_t *cand,
                            uint32_t count);

/* Working memory of ref_form_factor_row, one per thread: per surface an
 * occluder candidate, its shadow cone and a candidate of one cell, the
 * visible pieces of one cell, and a row. */
typedef struct ref_row_scratch {
    uint32_t *cand, *cell_cand;
    ref_cone *cone;
    ref_pieces *pieces;
    float *row; /* a row of element_count, for a cell's points (cell_points) */
} ref_row_scratch;

/* Allocates scratch for g; false when out of memory (s is then finished). */
bool ref_row_scratch_init(ref_row_scratch *s, const ref_geometry *g);
void ref_row_scratch_finish(ref_row_scratch *s);

/* Fills row[0..element_count-1] with F_ij for receiver r (0 for elements of
 * r's own surface and for cells that face away) and returns the row's sum.
 * Thread-safe for distinct rows and scratch. */
double ref_form_factor_row(const ref_geometry *g, const ref_receiver *r, float *row,
                           ref_row_scratch *scratch);

/* The dense form factor matrix, row-major element_count^2 floats (malloc'd,
 * *F owns it), built with desc->threads threads (desc may be NULL). Fills
 * form_factor_seconds and max_row_sum of `stats` (may be NULL). Refuses a
 * matrix over REF_MATRIX_MAX_BYTES. */
#define REF_MATRIX_MAX_BYTES ((uint64_t)2 << 30)
xrad_status ref_form_factor_matrix(const xrad_scene *scene, const xrad_reference_desc *desc,
                                   float **F, xrad_reference_stats *stats, xrad_error *err);

/* The Monte Carlo gather solver (XRAD_REFERENCE_SOLVER_GATHER, xrad.h):
 * B (3 doubles per element) for the resolved desc `d`; fills the stats'
 * timings, sweeps, residual, gather_rays and max_row_sum (the largest
 * fraction of an element's gather rays that meet a surface's front).
 * `lum` (NULL: none): the luminaires' irradiance per element, added to
 * the emitters' direct light (scene_luminaire.h). */
xrad_status ref_gather_solve(const xrad_scene *scene, const xrad_reference_desc *d,
                             const vec3 *lum, double *b, xrad_reference_stats *stats,
                             xrad_error *err);

/* The end of a Gauss-Seidel sweep: the residual, max |delta B| / max |B|
 * per channel and the largest of the three (a channel whose values are
 * small next to another's still converges relative to its own scale),
 * reported to d->progress as log(residual) / log(d->residual) by whole
 * percents (*reported: the last fraction reported, -1 at first). */
double ref_sweep_residual(const xrad_reference_desc *d, const double max_delta[3],
                          const double max_b[3], double *reported);

/* Monotonic wall clock, s. */
double ref_seconds(void);

#endif
