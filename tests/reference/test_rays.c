/*
 * The reference's rays visibility (XRAD_VISIBILITY_RAYS: every pair's
 * visible fraction from stratified rays traced through Embree), against
 * closed forms and against exact clipping:
 *
 *  - a point under the centre of a square ceiling (test_visibility.c's
 *    plates), with quad and triangle occluders: Howell B-3 sums over the
 *    visible rectangles, exact where the shadow follows cell edges (every
 *    ray of a cell agrees) and within the estimate's noise where it splits
 *    cells; a triangle's shadow by the point-to-polygon kernel over its
 *    central projection (the kernel is checked against closed forms in
 *    test_ff_closed_forms.c);
 *  - whole solutions of the Cornell box and of a triangle-mesh room against
 *    the clipping reference of the same scene, per surface and per element;
 *  - the same matrix whatever the thread count; bad settings refused.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "reference/reference.h"

static double howell_b3(double a, double b, double c)
{
    double A = a / c, B = b / c;
    double sa = sqrt(1 + A * A), sb = sqrt(1 + B * B);
    return (A / sa * atan(B / sa) + B / sb * atan(A / sb)) / (2 * REF_PI);
}

/* Occluders of the plates: a quad (4 corners) or a triangle (3). */
typedef struct occluder {
    int corners;
    double p[4][3];
} occluder;

/* Floor [-1,1]^2 at z = 0 facing up with 3 x 3 samples (the middle one at
 * the origin), ceiling [-1,1]^2 at z = 1 facing down with 9 x 9 samples
 * (cell edges at +-0.125, +-0.375, ...), and the occluders, one object
 * each (a triangle through the builder's mesh path). */
static xrad_scene *plates(const occluder *occ, int count)
{
    xrad_scene_builder *b = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_builder_create(&(xrad_scene_builder_desc){.name = "plates"}, &b,
                                               &err);
    uint32_t m = 0;
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "m", .albedo = {0.5, 0.5, 0.5}, .emission = {1, 1, 1}},
            &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "plates"}, &err);
    if (!st)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){"floor", m, {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}},
                              .samples = {3, 3}},
            &err);
    if (!st)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){"ceiling", m, {{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}},
                              .samples = {9, 9}},
            &err);
    for (int k = 0; k < count && !st; k++) {
        char name[16];
        snprintf(name, sizeof name, "occ%d", k);
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = name}, &err);
        if (st)
            break;
        if (occ[k].corners == 4) {
            xrad_quad_desc q = {"o", m, .samples = {2, 2}};
            memcpy(q.p, occ[k].p, sizeof q.p);
            st = xrad_scene_builder_add_quad(b, &q, &err);
        } else {
            float pos[9];
            for (int c = 0; c < 9; c++)
                pos[c] = (float)occ[k].p[c / 3][c % 3];
            st = xrad_scene_builder_add_mesh(
                b,
                &(xrad_mesh_desc){.name = "t", .positions = pos, .vertex_count = 3,
                                  .indices = (const uint32_t[]){0, 1, 2}, .triangle_count = 1,
                                  .material = m, .density = 2},
                &err);
        }
    }
    xrad_scene *scene = NULL;
    if (!st)
        st = xrad_scene_builder_finish(b, &scene, &err);
    xrad_scene_builder_destroy(&b);
    CHECK(st == XRAD_OK, "plates: %s", err.message);
    return scene;
}

/* Sum over the ceiling's cells of F from the floor's middle element with
 * rays visibility; negative on failure. */
static double ceiling_sum(const occluder *occ, int count, uint32_t rays)
{
    xrad_scene *scene = plates(occ, count);
    if (!scene)
        return -1;
    xrad_error err = {0};
    xrad_reference_stats stats = {0};
    xrad_reference_desc desc = {.threads = 2, .rays = rays, .visibility = XRAD_VISIBILITY_RAYS};
    float *F = NULL;
    xrad_status st = ref_form_factor_matrix(scene, &desc, &F, &stats, &err);
    CHECK(st == XRAD_OK, "matrix: %s", err.message);
    CHECK(!st && stats.visibility == XRAD_VISIBILITY_RAYS && stats.rays == rays,
          "stats: visibility %d, %u rays", (int)stats.visibility, stats.rays);
    double sum = -1;
    if (!st) {
        const surface *floor = &scene->surfaces[0], *ceil = &scene->surfaces[1];
        uint32_t i = floor->first_element + 1 * floor->nu + 1, n = scene->element_count;
        sum = 0;
        for (uint32_t j = ceil->first_element; j < ceil->first_element + ceil->nu * ceil->nv; j++)
            sum += F[(size_t)i * n + j];
    }
    free(F);
    xrad_scene_destroy(&scene);
    return sum;
}

static occluder square(double x0, double x1, double y0, double y1, double z)
{
    return (occluder){4, {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}};
}

static void closed_forms(void)
{
    double open = 4 * howell_b3(1, 1, 1);
    double f = ceiling_sum(NULL, 0, 16);
    fprintf(stderr, "no occluder: %.9f, closed form %.9f\n", f, open);
    CHECK_REL(f, open, 1e-6);

    /* Shadow [-0.375, 0.375]^2: exactly 3 x 3 cells, so every ray of a cell
     * agrees and 16 rays give the closed form. */
    occluder o = square(-0.1875, 0.1875, -0.1875, 0.1875, 0.5);
    f = ceiling_sum(&o, 1, 16);
    double want = open - 4 * howell_b3(0.375, 0.375, 1);
    fprintf(stderr, "centred square: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 1e-5);

    /* The half-space x < 0 blocked splits the middle column of cells: an
     * estimate there, within its noise (stratified: about 1/rays of a
     * column's share). */
    o = square(-3, 0, -3, 3, 0.5);
    double f64 = ceiling_sum(&o, 1, 64), f1024 = ceiling_sum(&o, 1, 1024);
    fprintf(stderr, "split cells: 64 rays %.9f, 1024 rays %.9f, closed form %.9f\n", f64, f1024,
            open / 2);
    CHECK_REL(f64, open / 2, 5e-3);
    CHECK_REL(f1024, open / 2, 1e-3);

    /* A half-plane through the axis at 30 degrees to the cells: its edge
     * along (c, s) through the origin, reaching 6 to one side. */
    double c = cos(REF_PI / 6), s = sin(REF_PI / 6);
    o = (occluder){4,
                   {{-3 * c, -3 * s, 0.5},
                    {3 * c, 3 * s, 0.5},
                    {3 * c - 6 * s, 3 * s + 6 * c, 0.5},
                    {-3 * c - 6 * s, -3 * s + 6 * c, 0.5}}};
    f = ceiling_sum(&o, 1, 256);
    fprintf(stderr, "oblique half-plane: %.9f, closed form %.9f\n", f, open / 2);
    CHECK_REL(f, open / 2, 3e-3);

    /* A triangle (the mesh path) with corners (0, 0), (0.4, 0), (0, 0.4) at
     * half height: its shadow is the triangle (0, 0), (0.8, 0), (0, 0.8) of
     * the ceiling, which the point sees as that polygon's form factor. */
    o = (occluder){3, {{0, 0, 0.5}, {0.4, 0, 0.5}, {0, 0.4, 0.5}}};
    f = ceiling_sum(&o, 1, 256);
    vec3 shadow[3] = {{0, 0, 1}, {0, 0.8, 1}, {0.8, 0, 1}}; /* facing the point */
    want = open - ref_ff_point_polygon(v3(0, 0, 0), v3(0, 0, 1), shadow, 3);
    fprintf(stderr, "triangle occluder: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 2e-3);

    /* Two overlapping shadows (test_visibility.c): the overlap once. */
    occluder two[2] = {square(-0.15, 0.15, -0.15, 0.15, 0.5), square(-3, 0.05, -3, 3, 0.25)};
    f = ceiling_sum(two, 2, 256);
    want = 2 * (howell_b3(1, 1, 1) - howell_b3(0.3, 1, 1)) +
           2 * (howell_b3(0.3, 1, 1) - howell_b3(0.2, 1, 1) - howell_b3(0.3, 0.3, 1) +
                howell_b3(0.2, 0.3, 1));
    fprintf(stderr, "overlapping occluders: %.9f, closed form %.9f\n", f, want);
    CHECK_REL(f, want, 3e-3);
}

/* Rays against clipping on a whole solution of the scene file `rel`. */
static void against_clipping(const char *rel, double surface_tol, double p95_tol)
{
    char path[1024];
    test_source_path(rel, path, sizeof path);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_load(path, &scene, &err);
    CHECK(st == XRAD_OK, "%s: %s", rel, err.message);
    if (st)
        return;
    xrad_atlas clip = {0}, rays = {0};
    xrad_reference_stats sc = {0}, sr = {0};
    if (!(st = xrad_atlas_create(scene, &clip, &err)) &&
        !(st = xrad_atlas_create(scene, &rays, &err)) &&
        !(st = xrad_reference_solve(
              scene, &(xrad_reference_desc){.threads = 2, .visibility = XRAD_VISIBILITY_CLIP},
              &clip, &sc, &err)))
        st = xrad_reference_solve(
            scene, &(xrad_reference_desc){.threads = 2, .visibility = XRAD_VISIBILITY_RAYS}, &rays,
            &sr, &err);
    CHECK(st == XRAD_OK, "%s: %s", rel, err.message);
    xrad_element_metrics m = {0};
    if (!st)
        st = xrad_atlas_compare(scene, &rays, &clip, &m, NULL, &err);
    CHECK(st == XRAD_OK, "%s: compare: %s", rel, err.message);
    if (!st) {
        xrad_surface_info si = {0};
        xrad_scene_get_surface(scene, m.worst_surface, &si, &err);
        fprintf(stderr,
                "%s: rays (%u a pair, %.2f s) against clipping (%.2f s): surface_error %.5f (%s), "
                "p95 %.5f, max %.5f, mean ratio %.6f\n",
                rel, sr.rays, sr.form_factor_seconds, sc.form_factor_seconds, m.surface_error,
                si.name, m.p95, m.max, m.mean_ratio);
        CHECK(sr.visibility == XRAD_VISIBILITY_RAYS && sc.visibility == XRAD_VISIBILITY_CLIP,
              "%s: visibility used %d / %d", rel, (int)sr.visibility, (int)sc.visibility);
        CHECK(m.elements > 0 && m.surface_error <= surface_tol && m.p95 <= p95_tol,
              "%s: surface_error %.5f (<= %g), p95 %.5f (<= %g)", rel, m.surface_error,
              surface_tol, m.p95, p95_tol);
    }
    xrad_atlas_destroy(&clip);
    xrad_atlas_destroy(&rays);
    xrad_scene_destroy(&scene);
}

/* A row depends on its index alone: one thread or two, the same matrix. */
static void threads(void)
{
    occluder two[2] = {square(-0.15, 0.15, -0.15, 0.15, 0.5),
                       {3, {{0, 0, 0.3}, {0.4, 0, 0.3}, {0, 0.4, 0.3}}}};
    xrad_scene *scene = plates(two, 2);
    if (!scene)
        return;
    float *F1 = NULL, *F2 = NULL;
    xrad_error err = {0};
    xrad_status st = ref_form_factor_matrix(
        scene, &(xrad_reference_desc){.threads = 1, .visibility = XRAD_VISIBILITY_RAYS}, &F1, NULL,
        &err);
    if (!st)
        st = ref_form_factor_matrix(
            scene, &(xrad_reference_desc){.threads = 2, .visibility = XRAD_VISIBILITY_RAYS}, &F2,
            NULL, &err);
    CHECK(st == XRAD_OK, "matrix: %s", err.message);
    size_t n = scene->element_count;
    CHECK(!st && !memcmp(F1, F2, n * n * sizeof *F1), "rays: 1 and 2 threads differ");
    free(F1);
    free(F2);

    /* Auto clips a scene this small; a visibility that is none of the
     * three is refused. */
    xrad_atlas a = {0};
    xrad_reference_stats s = {0};
    if (!(st = xrad_atlas_create(scene, &a, &err)))
        st = xrad_reference_solve(scene, &(xrad_reference_desc){.threads = 2}, &a, &s, &err);
    CHECK(st == XRAD_OK && s.visibility == XRAD_VISIBILITY_CLIP, "auto: %d, %s",
          (int)s.visibility, err.message);
    st = xrad_reference_solve(scene, &(xrad_reference_desc){.visibility = (xrad_visibility)7}, &a,
                              NULL, &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "visibility"), "bad visibility: %d %s",
          st, err.message);
    xrad_atlas_destroy(&a);
    xrad_scene_destroy(&scene);
}

int main(void)
{
    closed_forms();
    threads();
    /* 64 rays a pair: on a room with a 320-triangle ball the two agreed to
     * 2e-4 per surface and 1.4e-4 at p95 (embree_rays.h). */
    against_clipping("scenes/cornell-box.json", 0.003, 0.003);
    against_clipping("tests/data/lamp-room.json", 0.003, 0.003);
    return test_finish();
}
