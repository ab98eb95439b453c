/*
 * The reference solver's analytic form factor kernels against closed forms
 * from Howell's catalog of configuration factors (www.thermalradiation.net)
 * and against direct quadrature of the form factor integrand (thesis eq.
 * 2.2.3), plus the properties the kernels must have: front side only,
 * clipping at the receiver's tangent plane, additivity, closure of a cube.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "xrad.h"

/* Howell B-3: plane element dA1 parallel to a plane rectangle a x b at
 * distance c, the element's normal passing through a corner of the
 * rectangle. A = a/c, B = b/c:
 *   F = 1/(2 pi) [ A/sqrt(1+A^2) atan(B/sqrt(1+A^2))
 *                + B/sqrt(1+B^2) atan(A/sqrt(1+B^2)) ] */
static double howell_b3(double a, double b, double c)
{
    double A = a / c, B = b / c;
    double sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
    return (A / sa * atan(B / sa) + B / sb * atan(A / sb)) / (2 * REF_PI);
}

/* Howell C-11 as written in ground-truth.md. */
static double howell_c11(double a, double b, double c)
{
    double X = a / c, Y = b / c;
    double x1 = 1 + X * X, y1 = 1 + Y * Y;
    return 2 / (REF_PI * X * Y) *
           (log(sqrt(x1 * y1 / (1 + X * X + Y * Y))) + X * sqrt(y1) * atan(X / sqrt(y1)) +
            Y * sqrt(x1) * atan(Y / sqrt(x1)) - X * atan(X) - Y * atan(Y));
}

/* Howell C-14 as written in ground-truth.md: A1 = l x w, A2 = l x h. */
static double howell_c14(double l, double w, double h)
{
    double W = w / l, H = h / l;
    double W2 = W * W, H2 = H * H, s = sqrt(H2 + W2);
    double lg = log((1 + W2) * (1 + H2) / (1 + W2 + H2) *
                    pow(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2)), W2) *
                    pow(H2 * (1 + W2 + H2) / ((1 + H2) * (W2 + H2)), H2));
    return (W * atan(1 / W) + H * atan(1 / H) - s * atan(1 / s) + 0.25 * lg) / (REF_PI * W);
}

/* Axis-aligned rectangle [x0,x1] x [y0,y1] in the plane z = h, wound so its
 * front faces -z (towards a point below it). */
static void rect_facing_down(double x0, double x1, double y0, double y1, double h, vec3 q[4])
{
    q[0] = v3(x0, y0, h);
    q[1] = v3(x0, y1, h);
    q[2] = v3(x1, y1, h);
    q[3] = v3(x1, y0, h);
}

static void test_gauss_legendre(void)
{
    /* An n-point rule integrates x^k exactly on [-1, 1] for k <= 2n - 1. */
    double x[REF_GL_MAX], w[REF_GL_MAX];
    int orders[] = {1, 2, 5, 16, 64};
    for (size_t o = 0; o < sizeof orders / sizeof orders[0]; o++) {
        int n = orders[o];
        CHECK(ref_gauss_legendre(n, x, w), "order %d", n);
        for (int k = 0; k <= 2 * n - 1 && k <= 40; k++) {
            double sum = 0;
            for (int i = 0; i < n; i++)
                sum += w[i] * pow(x[i], k);
            CHECK_ABS(sum, k % 2 ? 0.0 : 2.0 / (k + 1), 1e-13);
        }
    }
    CHECK(!ref_gauss_legendre(0, x, w), "order 0 refused");
    CHECK(!ref_gauss_legendre(REF_GL_MAX + 1, x, w), "order too large refused");
}

/* Direct quadrature of thesis eq. 2.2.3 (no occlusion) over the
 * parallelogram o + s e1 + t e2, s, t in [0, 1], front side along e1 x e2,
 * from the point p with unit normal n: cos_i = n.r/|r|, cos_j = -N.r/|r|.
 * Valid when the parallelogram lies wholly above p's tangent plane and in
 * front of p, where the integrand is smooth and a high-order product rule
 * converges to rounding. */
static double quad_direct(vec3 p, vec3 n, vec3 o, vec3 e1, vec3 e2)
{
    double x[REF_GL_MAX], w[REF_GL_MAX];
    ref_gauss_legendre(REF_GL_MAX, x, w);
    vec3 cr = v3_cross(e1, e2);
    double area = v3_len(cr);
    vec3 big = v3_scale(cr, 1 / area);
    double sum = 0;
    for (int i = 0; i < REF_GL_MAX; i++)
        for (int k = 0; k < REF_GL_MAX; k++) {
            vec3 q = v3_add(o, v3_add(v3_scale(e1, 0.5 * (x[i] + 1)), v3_scale(e2, 0.5 * (x[k] + 1))));
            vec3 r = v3_sub(q, p);
            double r2 = v3_dot(r, r);
            sum += w[i] * w[k] * v3_dot(n, r) * -v3_dot(big, r) / (REF_PI * r2 * r2);
        }
    return sum * 0.25 * area;
}

static void test_point_parallel(void)
{
    vec3 p = v3(0, 0, 0), n = v3(0, 0, 1), q[4];
    /* Under a corner (B-3 directly). */
    double cases[][3] = {{1, 1, 1}, {2, 0.5, 0.3}, {0.01, 0.02, 5}, {100, 100, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double a = cases[c][0], b = cases[c][1], h = cases[c][2];
        rect_facing_down(0, a, 0, b, h, q);
        CHECK_REL(ref_ff_point_polygon(p, n, q, 4), howell_b3(a, b, h), 1e-12);
    }
    /* B-3 limits, so the formula in this test is trusted on its own: a
     * quarter plane gives 1/4, a small rectangle gives dA cos cos/(pi r^2). */
    CHECK_REL(howell_b3(1e7, 1e7, 1), 0.25, 1e-6);
    CHECK_REL(howell_b3(1e-4, 2e-4, 1), 2e-8 / REF_PI, 1e-6);

    /* Under the centre of a square of side 2a at height h: four corners. */
    rect_facing_down(-1, 1, -1, 1, 0.7, q);
    CHECK_REL(ref_ff_point_polygon(p, n, q, 4), 4 * howell_b3(1, 1, 0.7), 1e-12);
    /* Under a point outside the rectangle's shadow: [1,3] x [-1,2] is
     * [0,3] x [0,2] + [0,3] x [0,1] - [0,1] x [0,2] - [0,1] x [0,1]. */
    rect_facing_down(1, 3, -1, 2, 1.3, q);
    double want = howell_b3(3, 2, 1.3) + howell_b3(3, 1, 1.3) - howell_b3(1, 2, 1.3) -
                  howell_b3(1, 1, 1.3);
    CHECK_REL(ref_ff_point_polygon(p, n, q, 4), want, 1e-12);

    /* The same rectangle wound the other way faces up, away from p. */
    vec3 r[4] = {q[3], q[2], q[1], q[0]};
    CHECK(ref_ff_point_polygon(p, n, r, 4) == 0, "back side of the emitter gives 0");
    /* A point above the rectangle is behind it. */
    CHECK(ref_ff_point_polygon(v3(2, 0, 2), v3(0, 0, -1), q, 4) == 0, "point behind gives 0");
    /* Receiver facing away: the rectangle lies entirely below its tangent plane. */
    CHECK(ref_ff_point_polygon(p, v3(0, 0, -1), q, 4) == 0, "polygon below tangent plane gives 0");
    /* A tilted receiver and a tilted emitter, wholly above the tangent
     * plane: direct quadrature of the integrand. */
    vec3 tn = v3_norm(v3(0.3, -0.2, 1));
    vec3 o = v3(-0.4, 0.2, 1.1), e1 = v3(0.0, 0.8, 0.3), e2 = v3(0.9, 0.1, -0.2);
    vec3 tilted[4] = {o, v3_add(o, e1), v3_add(o, v3_add(e1, e2)), v3_add(o, e2)};
    if (v3_dot(v3_cross(e1, e2), v3_sub(p, o)) < 0) {
        vec3 t = e1;
        e1 = e2;
        e2 = t;
        tilted[1] = v3_add(o, e1);
        tilted[3] = v3_add(o, e2);
    }
    CHECK_REL(ref_ff_point_polygon(p, tn, tilted, 4), quad_direct(p, tn, o, e1, e2), 1e-10);
}

static void test_point_clipped(void)
{
    vec3 p = v3(0, 0, 0), n = v3(0, 0, 1);
    double a = 1.3, b = 0.9, d = 0.8;
    /* Plane y = d, facing -y: winding with (q1 - q0) x (q3 - q0) = -y. */
    vec3 upper[4] = {v3(0, d, 0), v3(a, d, 0), v3(a, d, b), v3(0, d, b)};
    double want = quad_direct(p, n, v3(0, d, 0), v3(a, 0, 0), v3(0, 0, b));
    CHECK_REL(ref_ff_point_polygon(p, n, upper, 4), want, 1e-10);
    /* Extending the rectangle below the tangent plane adds nothing: the
     * lower part is clipped away (Sutherland-Hodgman). */
    vec3 straddle[4] = {v3(0, d, -2), v3(a, d, -2), v3(a, d, b), v3(0, d, b)};
    CHECK_REL(ref_ff_point_polygon(p, n, straddle, 4), want, 1e-12);
    /* A triangle straddling diagonally: its clipped part is the triangle
     * above z = 0, which the kernel must equal. */
    vec3 tri[3] = {v3(0, d, -1), v3(2, d, 1), v3(0, d, 1)};
    vec3 tri_above[4] = {v3(0, d, 0), v3(1, d, 0), v3(2, d, 1), v3(0, d, 1)};
    CHECK_REL(ref_ff_point_polygon(p, n, tri, 3), ref_ff_point_polygon(p, n, tri_above, 4), 1e-12);

    /* An emitter entirely below the tangent plane gives 0. */
    vec3 below[4] = {v3(0, d, -2), v3(a, d, -2), v3(a, d, -0.5), v3(0, d, -0.5)};
    CHECK(ref_ff_point_polygon(p, n, below, 4) == 0, "below tangent plane gives 0");
}

static void test_point_degenerate(void)
{
    vec3 n = v3(0, 0, 1);
    /* A perpendicular rectangle through p's position (p in its plane; one
     * edge through p): cos phi_j = 0 everywhere, F = 0, and no NaN. */
    vec3 wall[4] = {v3(0, -1, 0), v3(0, -1, 1), v3(0, 1, 1), v3(0, 1, 0)};
    double f = ref_ff_point_polygon(v3(0, 0, 0), n, wall, 4);
    CHECK(f == 0, "p in the emitter's plane: F = %g", f);
    /* A vertex at p. */
    vec3 corner[4] = {v3(0, 0, 0), v3(0, 0, 1), v3(0, 1, 1), v3(0, 1, 0)};
    f = ref_ff_point_polygon(v3(0, 0, 0), n, corner, 4);
    CHECK(f == 0, "vertex at p: F = %g", f);
    /* A wall (facing +x) seen from a hair in front of its bottom edge: an
     * infinite wall x = 0, z > 0 seen from (d, 0, 0) with normal +z gives
     * integral of z d / (pi r^4) dy dz = 1/2 for every d > 0; a finite wall
     * of half-size L falls short by O(d / L). The receiver lies in the
     * wall's plane up to 1e-10 of the wall's size. */
    vec3 big[4] = {v3(0, -1e4, 0), v3(0, 1e4, 0), v3(0, 1e4, 1e4), v3(0, -1e4, 1e4)};
    f = ref_ff_point_polygon(v3(1e-6, 0, 0), n, big, 4);
    CHECK(isfinite(f), "finite");
    CHECK_ABS(f, 0.5, 1e-6);
    /* Degenerate polygons. */
    vec3 line[4] = {v3(0, 0, 1), v3(1, 0, 1), v3(2, 0, 1), v3(3, 0, 1)};
    CHECK(ref_ff_point_polygon(v3(0, 0, 0), n, line, 4) == 0, "collinear polygon gives 0");
    vec3 dot[3] = {v3(0, 0, 1), v3(0, 0, 1), v3(0, 0, 1)};
    CHECK(ref_ff_point_polygon(v3(0, 0, 0), n, dot, 3) == 0, "point polygon gives 0");
}

/* Area average over A1 (receiver, front +z at z = 0) of the kernel towards
 * A2 (facing down at z = c): Howell C-11. */
static double kernel_c11(double a, double b, double c, int order, int levels)
{
    vec3 recv[4] = {v3(0, 0, 0), v3(a, 0, 0), v3(a, b, 0), v3(0, b, 0)};
    vec3 emit[4];
    rect_facing_down(0, a, 0, b, c, emit);
    return ref_ff_area_polygon(recv, 4, emit, 4, order, levels);
}

/* Howell C-14: A1 = l x w in z = 0 (x in [0, w], y in [0, l], front +z),
 * A2 = l x h in x = 0 (z in [0, h], front +x), sharing the edge x = z = 0. */
static double kernel_c14(double l, double w, double h, int order, int levels)
{
    vec3 recv[4] = {v3(0, 0, 0), v3(w, 0, 0), v3(w, l, 0), v3(0, l, 0)};
    vec3 emit[4] = {v3(0, 0, 0), v3(0, l, 0), v3(0, l, h), v3(0, 0, h)};
    return ref_ff_area_polygon(recv, 4, emit, 4, order, levels);
}

static void test_area_closed_forms(void)
{
    /* The closed forms as written in the test reproduce ground-truth.md. */
    CHECK_REL(howell_c11(1, 1, 1), 0.19982, 1e-4);
    CHECK_REL(howell_c11(1, 1.5, 0.5), 0.47558, 1e-4);
    CHECK_REL(howell_c11(2, 2, 1), 0.41525, 1e-4);
    CHECK_REL(howell_c14(1, 1, 1), 0.20004, 1e-4);
    CHECK_REL(howell_c14(1, 1, 2), 0.23285, 1e-4);

    double c11[][3] = {{1, 1, 1}, {1, 1.5, 0.5}, {2, 2, 1}};
    for (int k = 0; k < 3; k++) {
        double a = c11[k][0], b = c11[k][1], c = c11[k][2];
        double got = kernel_c11(a, b, c, 12, 0), want = howell_c11(a, b, c);
        fprintf(stderr, "C-11 a=%g b=%g c=%g: kernel %.12f closed form %.12f rel %.2g\n", a, b, c, got, want, fabs(got - want) / want);
        CHECK_REL(got, want, 1e-4);
    }
    double c14[][3] = {{1, 1, 1}, {1, 1, 2}};
    for (int k = 0; k < 2; k++) {
        double l = c14[k][0], w = c14[k][1], h = c14[k][2];
        double got = kernel_c14(l, w, h, 8, 8), want = howell_c14(l, w, h);
        fprintf(stderr, "C-14 l=%g w=%g h=%g: kernel %.12f closed form %.12f rel %.2g\n", l, w, h, got, want, fabs(got - want) / want);
        CHECK_REL(got, want, 1e-4);
    }
    /* Reciprocity of C-14 through the kernel: A1 F12 = A2 F21. */
    CHECK_REL(1 * 1 * kernel_c14(1, 1, 2, 8, 8), 1 * 2 * kernel_c14(1, 2, 1, 8, 8), 1e-6);
}

static void test_cube_closure(void)
{
    /* Unit cube seen from inside: the bottom face (front +z) to the other
     * five faces, each wound with its front towards the interior. */
    vec3 bottom[4] = {v3(0, 0, 0), v3(1, 0, 0), v3(1, 1, 0), v3(0, 1, 0)};
    vec3 faces[5][4] = {
        {v3(0, 0, 1), v3(0, 1, 1), v3(1, 1, 1), v3(1, 0, 1)}, /* top, front -z */
        {v3(0, 0, 0), v3(0, 1, 0), v3(0, 1, 1), v3(0, 0, 1)}, /* x = 0, front +x */
        {v3(1, 0, 0), v3(1, 0, 1), v3(1, 1, 1), v3(1, 1, 0)}, /* x = 1, front -x */
        {v3(0, 0, 0), v3(0, 0, 1), v3(1, 0, 1), v3(1, 0, 0)}, /* y = 0, front +y */
        {v3(0, 1, 0), v3(1, 1, 0), v3(1, 1, 1), v3(0, 1, 1)}, /* y = 1, front -y */
    };
    double sum = 0;
    for (int f = 0; f < 5; f++) {
        vec3 nrm = v3_norm(ref_polygon_newell(faces[f], 4));
        vec3 centre = v3_scale(v3_add(faces[f][0], faces[f][2]), 0.5);
        CHECK(v3_dot(nrm, v3_sub(v3(0.5, 0.5, 0.5), centre)) > 0, "face %d faces inward", f);
        double got = ref_ff_area_polygon(bottom, 4, faces[f], 4, 8, 8);
        CHECK_REL(got, f == 0 ? howell_c11(1, 1, 1) : howell_c14(1, 1, 1), 1e-4);
        sum += got;
    }
    fprintf(stderr, "unit cube: bottom to the other five faces sums to %.12f\n", sum);
    CHECK_ABS(sum, 1.0, 1e-4);
}

/* xrad_reference_desc.cell_points: two opposed unit squares 1 apart, the
 * upper emitting E = 1 (albedo 0), the lower of albedo 0.5 split into
 * 3 x 3 elements (edge elements half, corner ones a quarter of a cell).
 * Its area-weighted mean radiosity is 0.5 F(A -> A) exactly when every
 * element holds its cell's mean (Howell C-11: 0.19982); from the cells'
 * centres (cell_points 1) it is the midpoint rule's estimate. */
static double lower_mean(uint32_t cell_points, double *want)
{
    static const char *json =
        "{\"density\": 2, \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]},"
        " {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [1, 1, 1]}],"
        " \"objects\": [{\"name\": \"o\", \"surfaces\": ["
        "{\"name\": \"lower\", \"material\": \"grey\", \"quad\": {\"origin\": [0, 0, 0],"
        " \"u\": [1, 0, 0], \"v\": [0, 1, 0]}},"
        "{\"name\": \"upper\", \"material\": \"lamp\", \"quad\": {\"origin\": [0, 0, 1],"
        " \"u\": [0, 1, 0], \"v\": [1, 0, 0]}}]}]}";
    xrad_error err = {0};
    xrad_scene *sc = NULL;
    xrad_atlas a = {0};
    xrad_surface_info si;
    double mean = NAN;
    *want = 0.5 * howell_c11(1, 1, 1);
    if (xrad_scene_parse(json, strlen(json), "squares.json", &sc, &err) ||
        xrad_scene_get_surface(sc, 0, &si, &err) || xrad_atlas_create(sc, &a, &err) ||
        xrad_reference_solve(sc, &(xrad_reference_desc){.cell_points = cell_points, .threads = 2},
                             &a, NULL, &err)) {
        CHECK(0, "cell_points %u: %s", cell_points, err.message);
        goto done;
    }
    CHECK(si.nu == 3 && si.nv == 3, "the lower square has %u x %u elements, want 3 x 3", si.nu,
          si.nv);
    double sum = 0, w_sum = 0;
    for (uint32_t j = 0; j < si.nv; j++)
        for (uint32_t i = 0; i < si.nu; i++) {
            double w = (i == 0 || i == si.nu - 1 ? 0.5 : 1) * (j == 0 || j == si.nv - 1 ? 0.5 : 1);
            sum += w * a.rgba[4 * ((size_t)(si.tile_y + j) * a.width + si.tile_x + i)];
            w_sum += w;
        }
    mean = sum / w_sum;
done:
    xrad_atlas_destroy(&a);
    xrad_scene_destroy(&sc);
    return mean;
}

static void test_cell_points(void)
{
    double want;
    double centre = lower_mean(1, &want), cells = lower_mean(8, &want);
    double e1 = fabs(centre / want - 1), e8 = fabs(cells / want - 1);
    fprintf(stderr,
            "cell means: 0.5 F(A->A) = %.6f; cell_points 1: %.6f (%.2g off), 8: %.6f (%.2g off)\n",
            want, centre, e1, cells, e8);
    CHECK(e8 < 2e-3, "cell_points 8: the mean %.6f is %.2g off 0.5 F(A->A) = %.6f", cells, e8,
          want);
    CHECK(e1 > 3 * e8, "cell_points 1 (%.2g off) is no worse than 8 (%.2g): the test shows nothing",
          e1, e8);
    xrad_error err = {0};
    xrad_scene *sc = NULL;
    const char *json = "{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
                       " \"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"s\","
                       " \"material\": \"m\", \"quad\": {\"origin\": [0, 0, 0],"
                       " \"u\": [1, 0, 0], \"v\": [0, 1, 0]}}]}]}";
    xrad_atlas a = {0};
    if (!xrad_scene_parse(json, strlen(json), "one.json", &sc, &err) &&
        !xrad_atlas_create(sc, &a, &err)) {
        CHECK(xrad_reference_solve(sc, &(xrad_reference_desc){.cell_points = 9}, &a, NULL, &err) ==
                      XRAD_ERROR_INPUT &&
                  strstr(err.message, "cell_points"),
              "cell_points 9: %s", err.message);
        CHECK(xrad_reference_solve(
                  sc,
                  &(xrad_reference_desc){.cell_points = 2, .solver = XRAD_REFERENCE_SOLVER_GATHER},
                  &a, NULL, &err) == XRAD_ERROR_INPUT &&
                  strstr(err.message, "dense"),
              "cell_points with the gather solver: %s", err.message);
    }
    xrad_atlas_destroy(&a);
    xrad_scene_destroy(&sc);
}

int main(void)
{
    test_gauss_legendre();
    test_point_parallel();
    test_point_clipped();
    test_point_degenerate();
    test_area_closed_forms();
    test_cube_closure();
    test_cell_points();
    return test_finish();
}
