/*
 * The contract of xrad_reference_solve beyond its numbers: bad input is
 * refused with a message (a matrix too large, a foreign atlas, bad
 * settings), progress is reported in bounded, ordered steps, the result
 * does not depend on the thread count, and a scene without emission stays
 * dark.
 */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "reference/reference.h"

/* A room with a panel inside that shadows parts of it. `%s` is the room's
 * emission. */
static const char *room_fmt =
    "{\"unit\":\"m\",\"density\":%g,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.7,0.6,0.5],\"emission\":[%s]},"
    "{\"name\":\"lamp\",\"albedo\":[0.5,0.5,0.5],\"emission\":[%s]}],"
    "\"objects\":[{\"name\":\"room\",\"surfaces\":[{\"name\":\"walls\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1.2,0,0],\"v\":[0,1,0],\"w\":[0,0,0.8]},\"inward\":true}]},"
    "{\"name\":\"panel\",\"surfaces\":[{\"name\":\"p\",\"material\":\"lamp\","
    "\"quad\":{\"origin\":[0.3,0.6,0.2],\"u\":[0,-0.1,0.4],\"v\":[0.5,0.05,0]}}]}],"
    "\"camera\":{\"position\":[0.6,0.5,0.1],\"look_at\":[0.6,0.5,0.8],\"up\":[0,1,0],"
    "\"fov_degrees\":60}}";

static xrad_scene *room(double density, const char *room_e, const char *lamp_e)
{
    char json[2048];
    snprintf(json, sizeof json, room_fmt, density, room_e, lamp_e);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "room.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    return st ? NULL : scene;
}

static void test_refusals(void)
{
    /* 200 x 200 = 40000 elements: the dense solver's 6.0 GiB matrix is
     * refused before any allocation; auto takes the gather solver. */
    const char *big =
        "{\"unit\":\"m\",\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5]}],"
        "\"objects\":[{\"name\":\"o\",\"surfaces\":[{\"name\":\"s\",\"material\":\"m\","
        "\"elements\":[200,200],\"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}}]}]}";
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(big, strlen(big), "big.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (!st) {
        xrad_atlas atlas = {0};
        st = xrad_atlas_create(scene, &atlas, &err);
        CHECK(st == XRAD_OK, "atlas: %s", err.message);
        st = xrad_reference_solve(
            scene, &(xrad_reference_desc){.solver = XRAD_REFERENCE_SOLVER_DENSE}, &atlas, NULL,
            &err);
        CHECK(st == XRAD_ERROR_INPUT, "40000 elements, dense: status %d", st);
        CHECK(strstr(err.message, "40000") && strstr(err.message, "GiB"), "message: %s", err.message);
        fprintf(stderr, "refused: %s\n", err.message);
        /* A lone unlit plane: every ray leaves, B = 0. */
        xrad_reference_stats stats = {0};
        st = xrad_reference_solve(scene, &(xrad_reference_desc){.gather_rays = 16}, &atlas,
                                  &stats, &err);
        CHECK(st == XRAD_OK && stats.solver == XRAD_REFERENCE_SOLVER_GATHER,
              "40000 elements, auto: status %d, solver %d: %s", st, (int)stats.solver,
              err.message);
        size_t nonzero = 0;
        for (size_t k = 0; !st && k < (size_t)atlas.width * atlas.height * 4; k++)
            nonzero += k % 4 != 3 && atlas.rgba[k] != 0;
        CHECK(nonzero == 0 && stats.max_row_sum == 0,
              "40000 elements, auto: %zu non-zero channels, %.3f of a row's rays met a surface",
              nonzero, stats.max_row_sum);
        xrad_atlas_destroy(&atlas);
        xrad_scene_destroy(&scene);
    }

    scene = room(3, "0,0,0", "1,1,1");
    if (!scene)
        return;
    xrad_atlas atlas = {0};
    st = xrad_atlas_create(scene, &atlas, &err);
    CHECK(st == XRAD_OK, "atlas: %s", err.message);
    xrad_atlas wrong = atlas;
    wrong.width++;
    CHECK(xrad_reference_solve(scene, NULL, &wrong, NULL, &err) == XRAD_ERROR_INPUT,
          "foreign atlas accepted");
    xrad_reference_desc bad = {.residual = -1};
    CHECK(xrad_reference_solve(scene, &bad, &atlas, NULL, &err) == XRAD_ERROR_INPUT,
          "negative residual accepted");
    bad = (xrad_reference_desc){.time = NAN};
    CHECK(xrad_reference_solve(scene, &bad, &atlas, NULL, &err) == XRAD_ERROR_INPUT,
          "NaN time accepted");
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

typedef struct progress_log {
    int calls[2];
    double last[2];
    int bad;
} progress_log;

static void on_progress(void *user, const char *stage, double fraction)
{
    progress_log *log = user;
    int k = !strcmp(stage, "form factors") ? 0 : !strcmp(stage, "solve") ? 1 : -1;
    if (k < 0 || !(fraction >= 0 && fraction <= 1) || fraction < log->last[k] ||
        (k == 0 && log->calls[1] > 0)) {
        log->bad++;
        fprintf(stderr, "bad progress call: %s %g\n", stage, fraction);
        return;
    }
    log->calls[k]++;
    log->last[k] = fraction;
}

static void test_progress_and_dark(void)
{
    xrad_scene *scene = room(8, "0,0,0", "0,0,0");
    if (!scene)
        return;
    xrad_error err = {0};
    xrad_atlas atlas = {0};
    xrad_status st = xrad_atlas_create(scene, &atlas, &err);
    progress_log log = {{0, 0}, {0, 0}, 0};
    xrad_reference_desc desc = {.threads = 2, .progress = on_progress, .progress_user = &log};
    xrad_reference_stats stats = {0};
    if (!st)
        st = xrad_reference_solve(scene, &desc, &atlas, &stats, &err);
    CHECK(st == XRAD_OK, "solve: %s", err.message);
    fprintf(stderr, "%u elements: %d form factor and %d solve progress calls\n",
            scene->element_count, log.calls[0], log.calls[1]);
    CHECK(scene->element_count > 200, "%u elements: too few to exercise progress", scene->element_count);
    CHECK(log.bad == 0, "%d bad progress calls", log.bad);
    CHECK(log.calls[0] >= 2 && log.calls[0] <= 102, "%d form factor calls", log.calls[0]);
    CHECK(log.calls[1] >= 1 && log.calls[1] <= 102, "%d solve calls", log.calls[1]);
    CHECK(log.last[0] == 1 && log.last[1] == 1, "last fractions %g %g", log.last[0], log.last[1]);
    /* No emission anywhere: B = 0 after one sweep. */
    double worst = 0;
    for (uint32_t k = 0; k < 4 * atlas.width * atlas.height; k++)
        if (k % 4 != 3)
            worst = fmax(worst, fabs(atlas.rgba[k]));
    CHECK(worst == 0, "dark scene has B up to %g", worst);
    CHECK(stats.sweeps == 1, "%u sweeps", stats.sweeps);
    CHECK(stats.form_factor_seconds > 0, "form factor time %g", stats.form_factor_seconds);
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

static void test_threads(void)
{
    /* Sample patterns depend on the element pair only: the matrix is the
     * same bit for bit with 1 and 3 threads. */
    xrad_scene *scene = room(6, "0,0,0", "1,1,1");
    if (!scene)
        return;
    xrad_error err = {0};
    float *a = NULL, *b = NULL;
    xrad_reference_desc one = {.threads = 1}, three = {.threads = 3};
    CHECK(ref_form_factor_matrix(scene, &one, &a, NULL, &err) == XRAD_OK, "%s", err.message);
    CHECK(ref_form_factor_matrix(scene, &three, &b, NULL, &err) == XRAD_OK, "%s", err.message);
    size_t n = scene->element_count;
    if (a && b) {
        CHECK(!memcmp(a, b, n * n * sizeof *a), "matrices differ between 1 and 3 threads");
        /* The panel does shadow: some pair is partly visible. */
        int partial = 0;
        ref_geometry *g = NULL;
        if (ref_geometry_create(scene, 0, 16, false, &g, &err) == XRAD_OK) {
            for (size_t i = 0; i < n && !partial; i++)
                for (size_t j = 0; j < n && !partial; j++) {
                    double f = ref_ff_point_polygon(g->recv[i], g->normal[i], g->cell[j], 4);
                    double got = a[i * n + j];
                    partial = g->surface_of[i] != g->surface_of[j] && f > 1e-4 &&
                              got > 0.05 * f && got < 0.95 * f;
                }
            ref_geometry_destroy(&g);
        }
        CHECK(partial, "no partly visible pair: the test scene does not exercise occlusion");
    }
    free(a);
    free(b);
    xrad_scene_destroy(&scene);
}

int main(void)
{
    test_refusals();
    test_progress_and_dark();
    test_threads();
    return test_finish();
}
