/*
 * Visibility in the reference solver's form factors: a point under the
 * centre of a square ceiling, with and without occluders between them.
 * Without occlusion the ceiling's cells add up to Howell B-3 four times
 * (cells tile the ceiling and the point-to-polygon kernel is additive).
 * With an occluder, the cells it shadows drop out exactly as central
 * projection from the point says. Visibility is exact by clipping, so
 * shadows that split cells (along a cell's middle, at an oblique angle, from
 * a tilted occluder, two overlapping) give the closed form too, whatever
 * the number of rays. A face pressed against the point's sees nothing.
 */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "reference/reference.h"

/* Same formula as in test_ff_closed_forms.c (Howell B-3): plane element
 * under a corner of a parallel a x b rectangle at distance c. */
static double howell_b3(double a, double b, double c)
{
    double A = a / c, B = b / c;
    double sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
    return (A / sa * atan(B / sa) + B / sb * atan(A / sb)) / (2 * REF_PI);
}

/* Floor [-1,1]^2 at z = 0 facing up with 3 x 3 samples (the middle one at
 * the origin), ceiling [-1,1]^2 at z = 1 facing down with 9 x 9 samples
 * (cell boundaries at +-0.125, +-0.375, ...; the middle cell centred on
 * the axis), and an optional occluder object. */
static const char *json_fmt =
    "{\"unit\":\"m\","
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5],\"emission\":[1,1,1]}],"
    "\"objects\":["
    "{\"name\":\"plates\",\"surfaces\":["
    "{\"name\":\"floor\",\"material\":\"m\",\"elements\":[3,3],"
    "\"quad\":{\"origin\":[-1,-1,0],\"u\":[2,0,0],\"v\":[0,2,0]}},"
    "{\"name\":\"ceiling\",\"material\":\"m\",\"elements\":[9,9],"
    "\"quad\":{\"origin\":[-1,-1,1],\"u\":[0,2,0],\"v\":[2,0,0]}}]}"
    "%s],"
    "\"camera\":{\"position\":[0,0,-3],\"look_at\":[0,0,0],\"up\":[0,1,0],\"fov_degrees\":60}}";

/* How ceiling_sum's solves see: auto (clipping here) unless a check sets it. */
static xrad_visibility visibility = XRAD_VISIBILITY_AUTO;

/* Sum over the ceiling's cells of F from the floor's middle element, at
 * scene time t; negative on failure. */
static double ceiling_sum(const char *occluder, double t, uint32_t rays)
{
    char json[16384];
    snprintf(json, sizeof json, json_fmt, occluder);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "plates.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return -1;
    xrad_reference_desc desc = {.time = t, .threads = 2, .rays = rays, .visibility = visibility};
    float *F = NULL;
    st = ref_form_factor_matrix(scene, &desc, &F, NULL, &err);
    CHECK(st == XRAD_OK, "matrix: %s", err.message);
    double sum = -1;
    if (!st) {
        const surface *floor = &scene->surfaces[0], *ceil = &scene->surfaces[1];
        uint32_t i = floor->first_element + 1 * floor->nu + 1, n = scene->element_count;
        const element *e = &scene->elements[i];
        CHECK(fabs(e->pos.x) < 1e-15 && fabs(e->pos.y) < 1e-15 && e->pos.z == 0,
              "middle floor element at (%g, %g, %g)", e->pos.x, e->pos.y, e->pos.z);
        sum = 0;
        for (uint32_t j = ceil->first_element; j < ceil->first_element + ceil->nu * ceil->nv; j++)
            sum += F[(size_t)i * n + j];
    }
    free(F);
    xrad_scene_destroy(&scene);
    return sum;
}

/* F from the origin to the rectangle [x0,x1] x [y0,y1] of the ceiling,
 * from Howell B-3 by inclusion-exclusion over the rectangles [0,x] x [0,y]
 * (signed by the quadrant they lie in). */
static double ceiling_rect(double x0, double x1, double y0, double y1)
{
    double xs[2] = {x0, x1}, ys[2] = {y0, y1}, f = 0;
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++) {
            double x = xs[a], y = ys[b];
            double g = (x < 0) == (y < 0) ? howell_b3(fabs(x), fabs(y), 1)
                                           : -howell_b3(fabs(x), fabs(y), 1);
            f += (a == b ? 1 : -1) * g;
        }
    return f;
}

/* An occluder object named `name`: the quad origin, origin + u, origin + u
 * + v, origin + v, with 2 x 2 elements. */
static void occluder_quad(char *buf, size_t n, const char *name, const double o[3],
                          const double u[3], const double v[3])
{
    snprintf(buf, n,
             ",{\"name\":\"%s\",\"surfaces\":[{\"name\":\"o\",\"material\":\"m\","
             "\"elements\":[2,2],\"quad\":{\"origin\":[%.17g,%.17g,%.17g],\"u\":[%.17g,%.17g,%.17g],"
             "\"v\":[%.17g,%.17g,%.17g]}}]}",
             name, o[0], o[1], o[2], u[0], u[1], u[2], v[0], v[1], v[2]);
}

/* An occluder object: one square [x0,x1] x [y0,y1] at height z, facing up
 * or down as `up` says (occlusion does not care). */
static void occluder(char *buf, size_t n, double x0, double x1, double y0, double y1, double z,
                     int up, const char *extra)
{
    if (up)
        snprintf(buf, n,
                 ",{\"name\":\"occ\"%s,\"surfaces\":[{\"name\":\"o\",\"material\":\"m\","
                 "\"elements\":[2,2],\"quad\":{\"origin\":[%g,%g,%g],\"u\":[%g,0,0],\"v\":[0,%g,0]}}]}",
                 extra, x0, y0, z, x1 - x0, y1 - y0);
    else
        snprintf(buf, n,
                 ",{\"name\":\"occ\"%s,\"surfaces\":[{\"name\":\"o\",\"material\":\"m\","
                 "\"elements\":[2,2],\"quad\":{\"origin\":[%g,%g,%g],\"u\":[0,%g,0],\"v\":[%g,0,0]}}]}",
                 extra, x0, y0, z, y1 - y0, x1 - x0);
}

int main(void)
{
    char occ[1024];
    double open = 4 * howell_b3(1, 1, 1);

    double f = ceiling_sum("", 0, 0);
    fprintf(stderr, "no occluder: %.9f, closed form %.9f\n", f, open);
    CHECK_REL(f, open, 1e-6);

    /* A square at half height with half-size 0.1875 shadows the ceiling's
     * middle [-0.375, 0.375]^2 (central projection doubles it), exactly 3 x 3
     * cells. */
    occluder(occ, sizeof occ, -0.1875, 0.1875, -0.1875, 0.1875, 0.5, 1, "");
    f = ceiling_sum(occ, 0, 0);
    double want = open - 4 * howell_b3(0.375, 0.375, 1);
    fprintf(stderr, "centred square occluder: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 1e-6);

    /* The half-space x < -0.0625 blocked at half height (the occluder faces
     * down, towards the point: occlusion ignores sides): its shadow is the
     * ceiling's x < -0.125, the 4 columns of cells left of the middle one. */
    occluder(occ, sizeof occ, -3, -0.0625, -3, 3, 0.5, 0, "");
    f = ceiling_sum(occ, 0, 0);
    want = open - 2 * (howell_b3(1, 1, 1) - howell_b3(0.125, 1, 1));
    fprintf(stderr, "half occluder: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 1e-6);

    /* The half-space x < 0 blocked: the middle column of cells is split
     * down its centre line, and F is half the open value. The ray count
     * is that of the fallback only; clipping splits the cells exactly. */
    occluder(occ, sizeof occ, -3, 0, -3, 3, 0.5, 1, "");
    double f16 = ceiling_sum(occ, 0, 16), f1024 = ceiling_sum(occ, 0, 1024);
    fprintf(stderr, "split cells: 16 rays %.9f, 1024 rays %.9f, closed form %.9f\n", f16, f1024,
            open / 2);
    CHECK_REL(f16, open / 2, 1e-6);
    CHECK_REL(f1024, open / 2, 1e-6);

    /* Any half-plane through the ceiling's centre leaves half of F (the
     * ceiling is symmetric about its centre): one at 30 degrees to the
     * cells, at half height, cuts the cells along it at that angle. */
    double c30 = cos(REF_PI / 6), s30 = sin(REF_PI / 6);
    occluder_quad(occ, sizeof occ, "occ", (double[3]){-3 * c30, -3 * s30, 0.5},
                  (double[3]){6 * c30, 6 * s30, 0}, (double[3]){-6 * s30, 6 * c30, 0});
    f = ceiling_sum(occ, 0, 1);
    fprintf(stderr, "oblique half-plane: %.9f, closed form %.9f\n", f, open / 2);
    CHECK_REL(f, open / 2, 1e-6);

    /* A tilted plate whose upper edge runs along y at x = 0.1, z = 0.4,
     * sloping down to x = -0.5, z = 0.1: the ray to the ceiling point
     * (x, y, 1) meets it at height 0.4 - (0.1 - 0.4 x) / (2 - x), on the
     * plate for every x < 0.25 and for no x > 0.25. The shadow edge x =
     * 0.25 (similar triangles: 0.1 / 0.4) runs through the middle of a
     * column of cells; the ceiling's x > 0.25 stays in view. */
    occluder_quad(occ, sizeof occ, "occ", (double[3]){0.1, -3, 0.4}, (double[3]){0, 6, 0},
                  (double[3]){-0.6, 0, -0.3});
    f = ceiling_sum(occ, 0, 1);
    want = 2 * (howell_b3(1, 1, 1) - howell_b3(0.25, 1, 1));
    fprintf(stderr, "tilted occluder: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 1e-6);

    /* Two occluders whose shadows overlap: the square [-0.15, 0.15]^2 at
     * height 0.5 shadows [-0.3, 0.3]^2, the half-space x < 0.05 at height
     * 0.25 shadows x < 0.2. In view: x > 0.3, and x in [0.2, 0.3] with
     * |y| > 0.3. Subtracting both shadows whole would take their overlap
     * away twice. */
    char both[2048];
    occluder_quad(occ, sizeof occ, "square", (double[3]){-0.15, -0.15, 0.5},
                  (double[3]){0.3, 0, 0}, (double[3]){0, 0.3, 0});
    size_t len = strlen(occ);
    memcpy(both, occ, len);
    occluder_quad(occ, sizeof occ, "half", (double[3]){-3, -3, 0.25}, (double[3]){3.05, 0, 0},
                  (double[3]){0, 6, 0});
    snprintf(both + len, sizeof both - len, "%s", occ);
    f = ceiling_sum(both, 0, 1);
    want = 2 * (howell_b3(1, 1, 1) - howell_b3(0.3, 1, 1)) +
           2 * (howell_b3(0.3, 1, 1) - howell_b3(0.2, 1, 1) - howell_b3(0.3, 0.3, 1) +
                howell_b3(0.2, 0.3, 1));
    fprintf(stderr, "overlapping occluders: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 1e-6);

    /* 5 x 5 small squares at half height, of side 0.008 on a staggered
     * grid (so that no two share an edge line), punch 25 holes of side
     * 0.016 into the middle cell: more convex pieces than clipping keeps
     * (shadow.h), so that cell falls back to rays, which now decide its
     * value (16 and 4096 rays differ) and converge to the closed form; the
     * other cells stay exact. */
    char grid[12288];
    size_t at = (size_t)snprintf(grid, sizeof grid, ",{\"name\":\"grid\",\"surfaces\":[");
    want = open;
    for (int k = 0; k < 25; k++) {
        int col = k % 5, row = k / 5;
        double cx = 0.02 * (col - 2) + 0.003 * row, cy = 0.02 * (row - 2) + 0.003 * col;
        at += (size_t)snprintf(grid + at, sizeof grid - at,
                               "%s{\"name\":\"g%d\",\"material\":\"m\",\"elements\":[2,2],"
                               "\"quad\":{\"origin\":[%.17g,%.17g,0.5],\"u\":[0.008,0,0],"
                               "\"v\":[0,0.008,0]}}",
                               k ? "," : "", k, cx - 0.004, cy - 0.004);
        want -= ceiling_rect(2 * cx - 0.008, 2 * cx + 0.008, 2 * cy - 0.008, 2 * cy + 0.008);
    }
    snprintf(grid + at, sizeof grid - at, "]}");
    f16 = ceiling_sum(grid, 0, 16);
    double f4096 = ceiling_sum(grid, 0, 4096);
    fprintf(stderr, "25 holes: 16 rays %.9f, 4096 rays %.9f, closed form %.9f\n", f16, f4096,
            want);
    CHECK(f16 != f4096, "25 holes: the ray count changes nothing, so no pair fell back");
    CHECK_REL(f16, want, 1e-2);
    CHECK_REL(f4096, want, 2e-4);

    /* A plate covering everything removes the ceiling entirely. */
    occluder(occ, sizeof occ, -3, 3, -3, 3, 0.5, 1, "");
    f = ceiling_sum(occ, 0, 0);
    CHECK(f == 0, "full occluder: %g", f);

    /* A plate lying on the floor, facing down onto it, over the middle
     * element: pressed against it, that element sees nothing, by clipping
     * and by rays alike (its rays leave a hair above the floor, above the
     * plate: without the contact test it saw the whole ceiling). The same
     * plate facing up, the floor's twin, or facing down but beside the
     * point, hides nothing. */
    for (int rays = 0; rays < 2; rays++) {
        visibility = rays ? XRAD_VISIBILITY_RAYS : XRAD_VISIBILITY_CLIP;
        const char *how = rays ? "rays" : "clip";
        occluder(occ, sizeof occ, -0.5, 0.5, -0.5, 0.5, 0, 0, "");
        f = ceiling_sum(occ, 0, 0);
        CHECK(f == 0, "%s: plate pressed on the floor: %g", how, f);
        occluder(occ, sizeof occ, -0.5, 0.5, -0.5, 0.5, 0, 1, "");
        f = ceiling_sum(occ, 0, 0);
        fprintf(stderr, "%s: plate in the floor's plane facing up: %.9f, closed form %.9f\n", how,
                f, open);
        CHECK_REL(f, open, rays ? 2e-2 : 1e-6);
        occluder(occ, sizeof occ, 0.2, 0.5, -0.5, 0.5, 0, 0, "");
        f = ceiling_sum(occ, 0, 0);
        fprintf(stderr, "%s: plate on the floor beside the point: %.9f, closed form %.9f\n", how, f,
                open);
        CHECK_REL(f, open, rays ? 2e-2 : 1e-6);
    }
    visibility = XRAD_VISIBILITY_AUTO;

    /* A dynamic occluder is posed at the solve's time: the full plate slid
     * 10 m sideways by t = 1 s blocks nothing then, everything at t = 0. */
    occluder(occ, sizeof occ, -3, 3, -3, 3, 0.5, 1,
             ",\"dynamic\":true,\"animation\":{\"loop\":false,\"keyframes\":["
             "{\"time\":0,\"translate\":[0,0,0]},{\"time\":1,\"translate\":[10,0,0]}]}");
    f = ceiling_sum(occ, 0, 0);
    CHECK(f == 0, "dynamic occluder at t = 0: %g", f);
    f = ceiling_sum(occ, 1, 0);
    CHECK_REL(f, open, 1e-6);
    return test_finish();
}
