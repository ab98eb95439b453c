/*
 * Visibility rays for the CPU reference solver through Embree (Debian's
 * libembree-dev, Embree 3): the scene's quads in one BVH, segments tested
 * for occlusion in streams. The exact clipping of shadow.h culls occluder
 * candidates by a loop over every quad for every (receiver, surface) pair,
 * O(N S^2) for N elements and S surfaces, which a mesh of a thousand
 * triangles already makes an hour; a BVH answers a segment in O(log S).
 *
 * A segment counts as blocked by any quad but the two it joins and the
 * quads coplanar with either (a floor's neighbouring triangles, a wall's
 * other quads): a ray that leaves one plane from its front and arrives at
 * the other's front cannot cross them, and in float a grazing ray could
 * seem to.
 */
#ifndef XRAD_REFERENCE_EMBREE_RAYS_H
#define XRAD_REFERENCE_EMBREE_RAYS_H

#include <stdbool.h>
#include <stdint.h>

#include "core/vec.h"
#include "reference/raycast.h"
#include "xrad.h"

typedef struct ref_rays ref_rays;

/* A BVH over quads[0, count) (kept by reference: they must outlive it);
 * scale is the scene's diagonal (m), for the planes' tolerance and the
 * rays' start. */
xrad_status ref_rays_create(const ref_quad *quads, uint32_t count, double scale, ref_rays **out,
                            xrad_error *err);
void ref_rays_destroy(ref_rays **rays);

/* At most this many segments per ref_rays_occluded call. */
#define REF_RAYS_BATCH 16

/* blocked[k] for the segment from `from` to to[k], k < count <=
 * REF_RAYS_BATCH, from a point of quad `own` to a point of quad `target`.
 * Thread-safe. */
void ref_rays_occluded(const ref_rays *rays, uint32_t own, uint32_t target, vec3 from,
                       const vec3 *to, uint32_t count, bool *blocked);

/* The first quad each ray from `from` along dirs[k] (k < count <=
 * REF_RAYS_BATCH) meets: hit[k], at from + t[k] dirs[k]; UINT32_MAX and
 * infinity where it meets none. Quad `own` (the ray's source) and the
 * quads in its plane are passed through, as for segments. Thread-safe. */
void ref_rays_closest(const ref_rays *rays, uint32_t own, vec3 from, const vec3 *dirs,
                      uint32_t count, uint32_t *hit, double *t);

/* True where the segment from `from` along `dir` (its length the
 * segment's) meets a quad other than `own` whose normal is within a degree
 * of -n: a face pressed against point `from`'s surface (normal n), the
 * test of ref_receiver_pressed. Thread-safe. */
bool ref_rays_touching(const ref_rays *rays, uint32_t own, vec3 n, vec3 from, vec3 dir);

#endif
