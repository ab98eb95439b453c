/*
 * Ray casting for the CPU reference solver's visibility term (the HID
 * function of thesis eq. 2.2.3): segments against world-space planar convex
 * quads, a conservative test that rules out quads which cannot meet any
 * segment from a point to a polygon, and a deterministic sample pattern.
 * Scenes have fewer than about a hundred quads, so a loop over candidates
 * replaces a hierarchy.
 */
#ifndef XRAD_REFERENCE_RAYCAST_H
#define XRAD_REFERENCE_RAYCAST_H

#include <stdbool.h>
#include <stdint.h>

#include "core/vec.h"

/* A planar convex quad in world space. Occlusion ignores sidedness: a quad
 * blocks a segment from either side. */
typedef struct ref_quad {
    vec3 p[4];
    vec3 normal; /* unit, right-handed about p[0..3] */
} ref_quad;

/* Fills q->normal from the corners (Newell). Returns false for a quad of
 * zero area. */
bool ref_quad_init(ref_quad *q, const vec3 corners[4]);

/* True if the segment a -> b crosses q at a parameter in (eps, 1 - eps)
 * (eps relative to the segment's length, see REF_RAY_EPS). Boundary points
 * of q count as inside. */
#define REF_RAY_EPS 1e-9
bool ref_segment_hits_quad(const ref_quad *q, vec3 a, vec3 b);

/* Two faces whose normals are within a degree of opposite (cos 179 deg)
 * can be pressed together (ref_receiver_pressed). */
#define REF_CONTACT_COS 0.99985

/* Conservative separation test: false only if q certainly does not meet the
 * interior of the convex hull of `apex` and the convex polygon base[0..3]
 * (so no segment from apex to a point of the base can cross q), where
 * touching within `tol` (a length) counts as separate. Uses the hull's face
 * planes and q's plane as separating axes; true means "may block". */
bool ref_quad_may_block(const ref_quad *q, vec3 apex, const vec3 *base, double tol);

/* 64-bit mix of two indices (splitmix64 finaliser), so that sample patterns
 * depend on the element pair only, never on thread scheduling. */
uint64_t ref_pair_seed(uint32_t a, uint32_t b);

/* Sample k of `count` stratified points in [0, 1)^2 for `seed`: a
 * Hammersley set (k / count, radical inverse of k in base 2) with a random
 * toroidal shift (Cranley-Patterson rotation) drawn from the seed. Any
 * count gives one point per column of width 1/count and, for count a power
 * of two, one per elementary interval. */
void ref_sample(uint64_t seed, uint32_t k, uint32_t count, double *s, double *t);

#endif
