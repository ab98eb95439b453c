/*
 * Visibility in the reference solver's form factors: a point under the
 * centre of a square ceiling, with and without occluders between them.
 * Without occlusion the ceiling's cells add up to Howell B-3 four times
 * (cells tile the ceiling and the point-to-polygon kernel is additive).
 * With an occluder, the cells it shadows drop out exactly as central
 * projection from the point says: the occluders are placed so that their
 * shadows fall on cell boundaries. Where a shadow splits cells, the
 * integrand-weighted visible fraction converges to the exact value as the
 * rays grow.
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

/* Sum over the ceiling's cells of F from the floor's middle element, at
 * scene time t; negative on failure. */
static double ceiling_sum(const char *occluder, double t, uint32_t rays)
{
    char json[4096];
    snprintf(json, sizeof json, json_fmt, occluder);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "plates.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return -1;
    xrad_reference_desc desc = {.time = t, .threads = 2, .rays = rays};
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
     * down its centre line, and F is half the open value. 16 rays per pair
     * estimate the split cells' visible fraction; 1024 rays pin it down. */
    occluder(occ, sizeof occ, -3, 0, -3, 3, 0.5, 1, "");
    double f16 = ceiling_sum(occ, 0, 16), f1024 = ceiling_sum(occ, 0, 1024);
    fprintf(stderr, "split cells: 16 rays %.9f, 1024 rays %.9f, closed form %.9f\n", f16, f1024,
            open / 2);
    CHECK_REL(f16, open / 2, 2e-3);
    CHECK_REL(f1024, open / 2, 1e-4);

    /* A plate covering everything removes the ceiling entirely. */
    occluder(occ, sizeof occ, -3, 3, -3, 3, 0.5, 1, "");
    f = ceiling_sum(occ, 0, 0);
    CHECK(f == 0, "full occluder: %g", f);

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
