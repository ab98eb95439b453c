/*
 * Analytic form factor kernels of the CPU reference solver. Independent of
 * the GPU path: nothing here rasterises or approximates a shooter by disks.
 *
 * Conventions: a polygon is convex and planar, its front side is along the
 * right-handed (Newell) normal of its vertex order; light leaves a polygon
 * from its front side only. A receiving point has a unit normal n and
 * receives from the half-space n . (x - p) > 0 only.
 */
#ifndef XRAD_REFERENCE_FF_KERNEL_H
#define XRAD_REFERENCE_FF_KERNEL_H

#include "core/vec.h"

/* math.h defines M_PI only outside strict C11. */
#define REF_PI 3.14159265358979323846

/* Most vertices a polygon handed to the kernels may have: room for the
 * pieces that exact visibility (shadow.h) cuts a cell into. */
#define REF_POLY_MAX 32

/* Most Gauss-Legendre points per interval ref_gauss_legendre computes. */
#define REF_GL_MAX 64

/* Differential area (point p, unit normal n) to polygon form factor, by
 * Lambert's contour formula (ground-truth.md; thesis eq. 2.2.3 without
 * occlusion): the polygon is first clipped to the half-space above p's
 * tangent plane. Returns 0 for a polygon seen from its back side or with p
 * in its plane, a polygon entirely below the tangent plane, and a degenerate
 * polygon; otherwise a value in [0, 1]. `count` is 3..REF_POLY_MAX. */
double ref_ff_point_polygon(vec3 p, vec3 n, const vec3 *poly, int count);

/* Sutherland-Hodgman clip of polygon in[0..count-1] to the half-space
 * n . (x - p) >= 0 into `out`; returns the new count. A convex polygon cut
 * by one plane gains at most one vertex; any polygon at most doubles, which
 * is what `out` must hold. */
int ref_polygon_clip(vec3 p, vec3 n, const vec3 *in, int count, vec3 *out);

/* Newell normal of a polygon (not normalised; its length is twice the area
 * of a planar polygon). */
vec3 ref_polygon_newell(const vec3 *poly, int count);

/* The n-point Gauss-Legendre rule on [-1, 1]: nodes x[0..n-1] ascending and
 * weights w[0..n-1]. n is 1..REF_GL_MAX; returns 0 on a bad n, else 1. */
int ref_gauss_legendre(int n, double *x, double *w);

/* Area-averaged form factor from a receiving convex planar polygon (front
 * side along its Newell normal) to a polygon: (1 / A_r) times the integral
 * over the receiver of ref_ff_point_polygon, i.e. thesis eq. 2.2.1 without
 * occlusion; A_r F_re = A_e F_er (reciprocity) holds to quadrature error.
 * Every point of a planar receiver shares one tangent plane, so the kernel
 * is smooth where it is not zero; the zero part (receiver points behind the
 * emitter's plane) is clipped off first, so that no kink of the integrand
 * lies inside the domain. The rest is split into a fan of triangles, each
 * mapped from the unit square (Duffy), and integrated with an `order`-point
 * Gauss-Legendre rule per interval of a composite mesh graded geometrically
 * towards the square's edges with `levels` levels (ratio REF_GRADE_RATIO;
 * 0 = one interval). Grading matters where the emitter touches the
 * receiver (a shared edge): there the kernel jumps from about 1/2 to 0.
 * Counts are 3..REF_POLY_MAX. Returns a negative value on bad arguments. */
#define REF_GRADE_RATIO 0.15
#define REF_GRADE_MAX 24
double ref_ff_area_polygon(const vec3 *recv, int recv_count, const vec3 *poly, int count,
                           int order, int levels);

#endif
