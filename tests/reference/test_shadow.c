/*
 * Exact visibility by clipping (reference/shadow.h) on one cell: the unit
 * square [0,1]^2 in the plane z = 0, facing up, seen from p = (0.5, 0.5, 1)
 * facing down. Expected form factors are Howell B-3 sums over the visible
 * rectangle (the shadows are placed by similar triangles), so they are
 * independent of the clipping. Also: the slab clip (occluder parts behind
 * the cell or above p block nothing), coplanar, degenerate and edge-on
 * occluders, the union of overlapping shadows, and the piece cap.
 */
#include <stdio.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "reference/shadow.h"

/* The clipping tolerance (m). Occluder parts within it of the cell's plane
 * block nothing, which moves the shadow edge of an occluder standing on
 * the cell by about TOL: expected values hold to 1e-8. */
#define TOL 1e-9

/* Same formula as in test_ff_closed_forms.c (Howell B-3): plane element
 * under a corner of a parallel a x b rectangle at distance c. */
static double howell_b3(double a, double b, double c)
{
    double A = a / c, B = b / c;
    double sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
    return (A / sa * atan(B / sa) + B / sb * atan(A / sb)) / (2 * REF_PI);
}

static const vec3 cell[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
static const vec3 p = {0.5, 0.5, 1}, n = {0, 0, -1};

static ref_pieces work;

/* The quad o, o + u, o + u + v, o + v. */
static ref_quad quad(vec3 o, vec3 u, vec3 v)
{
    vec3 c[4] = {o, v3_add(o, u), v3_add(v3_add(o, u), v), v3_add(o, v)};
    ref_quad q;
    CHECK(ref_quad_init(&q, c), "zero-area test quad");
    return q;
}

/* Visible F of the cell past quads q[0..count-1]; negative when clipping
 * gives up. */
static double visible(const ref_quad *q, int count)
{
    ref_cone cones[8];
    for (int k = 0; k < count; k++)
        CHECK(ref_cone_init(&cones[k], &q[k], p, cell[0], v3(0, 0, 1), TOL), "cone %d unresolved", k);
    double whole = ref_ff_point_polygon(p, n, cell, 4), f = -1;
    if (!ref_ff_point_visible(p, n, cell, 4, whole, cones, (uint32_t)count, TOL, &work, &f))
        return -1;
    CHECK(isfinite(f) && f >= 0 && f <= whole, "visible F %g of %g", f, whole);
    return f;
}

int main(void)
{
    double whole = 4 * howell_b3(0.5, 0.5, 1);
    CHECK_REL(visible(NULL, 0), whole, 1e-12);

    /* A wall x = 0.75 standing on the cell, 0.6 high: the ray from p to a
     * point x of the cell passes x = 0.75 at height 1 - 0.25 / (x - 0.5),
     * under 0.6 for every x in [0.75, 1], so the strip x > 0.75 is hidden
     * and [0, 0.75] x [0, 1] seen. The wall's foot lies on the cell. */
    double strip = 2 * howell_b3(0.5, 0.5, 1) + 2 * howell_b3(0.25, 0.5, 1);
    ref_quad wall = quad(v3(0.75, -1, 0), v3(0, 3, 0), v3(0, 0, 0.6));
    double f = visible(&wall, 1);
    fprintf(stderr, "standing wall: %.12f, closed form %.12f\n", f, strip);
    CHECK_REL(f, strip, 1e-8);

    /* The same wall reaching 2 m, above p: what lies above p blocks
     * nothing and the shadow is the same. */
    wall = quad(v3(0.75, -1, 0), v3(0, 3, 0), v3(0, 0, 2));
    CHECK_REL(visible(&wall, 1), strip, 1e-8);

    /* A wall x = 0.75 + z / 2 piercing the cell's plane: a ray to x meets
     * it at parameter 0.75 / x, before the cell exactly for x >= 0.75. Its
     * part under the cell (down to z = -1) must not shadow [0.375, 0.75],
     * where rays towards it cross the cell first. */
    wall = quad(v3(0.25, -1, -1), v3(0, 3, 0), v3(0.8, 0, 1.6));
    f = visible(&wall, 1);
    fprintf(stderr, "piercing wall: %.12f, closed form %.12f\n", f, strip);
    CHECK_REL(f, strip, 1e-8);

    /* Two overlapping occluders: the square [0.35, 0.65]^2 at height 0.5,
     * whose shadow is [0.2, 0.8]^2 (central projection from height 1
     * doubles distances from the foot (0.5, 0.5)), and the half-plane
     * x > 0.55 at height 0.8, whose edge casts x = 0.5 + 0.05 / 0.2 = 0.75.
     * Seen: the strip x < 0.2, and x in [0.2, 0.75] with y outside
     * [0.2, 0.8]; the shadows' overlap [0.75, 0.8] x [0.2, 0.8] must not be
     * taken away twice. Both orders give the same. */
    ref_quad two[2] = {quad(v3(0.35, 0.35, 0.5), v3(0.3, 0, 0), v3(0, 0.3, 0)),
                       quad(v3(0.55, -1, 0.8), v3(3, 0, 0), v3(0, 3, 0))};
    double left = 2 * howell_b3(0.5, 0.5, 1) - 2 * howell_b3(0.3, 0.5, 1);
    double bands = 2 * (howell_b3(0.3, 0.5, 1) - howell_b3(0.3, 0.3, 1)) +
                   2 * (howell_b3(0.25, 0.5, 1) - howell_b3(0.25, 0.3, 1));
    double want = left + bands;
    f = visible(two, 2);
    fprintf(stderr, "overlapping occluders: %.12f, closed form %.12f\n", f, want);
    CHECK_REL(f, want, 1e-9);
    ref_quad swapped[2] = {two[1], two[0]};
    CHECK_REL(visible(swapped, 2), want, 1e-9);

    /* A plate covering the whole cone hides everything; one beside it
     * nothing, and the result is then `whole` as given. */
    ref_quad cover = quad(v3(-1, -1, 0.5), v3(3, 0, 0), v3(0, 3, 0));
    CHECK(visible(&cover, 1) == 0, "covered cell: %g", visible(&cover, 1));
    ref_quad beside = quad(v3(0.8, 0.8, 0.5), v3(1, 0, 0), v3(0, 1, 0));
    CHECK(visible(&beside, 1) == ref_ff_point_polygon(p, n, cell, 4), "occluder beside the cone");

    /* Degenerate occluders block nothing: one in the cell's plane (it meets
     * segments only at their end), one in a plane through p (edge-on), and
     * one of zero area (given a normal by hand). */
    ref_cone cone;
    ref_quad coplanar = quad(v3(0.2, 0.2, 0), v3(0.5, 0, 0), v3(0, 0.5, 0));
    CHECK(ref_cone_init(&cone, &coplanar, p, cell[0], v3(0, 0, 1), TOL) && cone.count == 0,
          "coplanar occluder: %d planes", cone.count);
    CHECK_REL(visible(&coplanar, 1), whole, 1e-12);
    ref_quad edge_on = quad(v3(0.5, -1, 0.2), v3(0, 3, 0), v3(0, 0, 0.5));
    CHECK(ref_cone_init(&cone, &edge_on, p, cell[0], v3(0, 0, 1), TOL) && cone.count == 0,
          "occluder in a plane through p: %d planes", cone.count);
    ref_quad line = {{{0.2, 0.5, 0.5}, {0.4, 0.5, 0.5}, {0.6, 0.5, 0.5}, {0.8, 0.5, 0.5}},
                     {0, 0, 1}};
    CHECK(ref_cone_init(&cone, &line, p, cell[0], v3(0, 0, 1), TOL) && cone.count == 0,
          "zero-area occluder: %d planes", cone.count);

    /* A grid of 10 x 10 small squares at half height punches 100 holes in
     * the visible part, far more convex pieces than the cap: clipping gives
     * up (the caller then casts rays) and leaves f alone. */
    ref_cone grid[100];
    for (int k = 0; k < 100; k++) {
        ref_quad q = quad(v3(0.27 + 0.05 * (k % 10), 0.27 + 0.05 * (k / 10), 0.5), v3(0.02, 0, 0),
                          v3(0, 0.02, 0));
        CHECK(ref_cone_init(&grid[k], &q, p, cell[0], v3(0, 0, 1), TOL), "grid cone %d", k);
    }
    f = -1;
    CHECK(!ref_ff_point_visible(p, n, cell, 4, whole, grid, 100, TOL, &work, &f) && f == -1,
          "100 holes: clipping did not give up (f = %g)", f);
    return test_finish();
}
