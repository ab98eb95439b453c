/*
 * The reference's gather solver (XRAD_REFERENCE_SOLVER_GATHER: lights by
 * form factor and rays, the rest by Monte Carlo gathering through Embree,
 * no matrix), against truths it does not compute:
 *
 *  - a closed box whose every wall emits E with albedo rho: B = E / (1 -
 *    rho) everywhere (every gather ray meets a wall's front and the
 *    emitters' form factors close, so the estimate has no noise here);
 *  - the Cornell box and a triangle-mesh room against the dense solver
 *    (exact clipping), per surface and per element, and the element error
 *    falling as the rays grow, as Monte Carlo noise does (1 / sqrt(rays));
 *  - the same B whatever the thread count; bad settings refused.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "reference/reference.h"

static xrad_scene *load(const char *rel)
{
    char path[1024];
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_load(test_source_path(rel, path, sizeof path), &scene, &err) == XRAD_OK,
          "%s: %s", rel, err.message);
    return scene;
}

/* B of element e, R + G + B. */
static double element_sum(const xrad_scene *scene, const xrad_atlas *a, uint32_t e)
{
    const element *el = &scene->elements[e];
    const float *p = &a->rgba[4 * ((size_t)el->texel_y * a->width + el->texel_x)];
    return (double)p[0] + p[1] + p[2];
}

/* A 2 x 1.5 x 1 m box, every wall facing in, emitting 1 with albedo 0.9
 * (B = 10), its back wall a mesh of two triangles (kept apart): mesh faces
 * too. */
static xrad_scene *furnace_scene(void)
{
    static const double walls[5][4][3] = {
        {{0, 0, 0}, {0, 0, 1}, {2, 0, 1}, {2, 0, 0}},         /* floor */
        {{0, 1.5, 0}, {2, 1.5, 0}, {2, 1.5, 1}, {0, 1.5, 1}}, /* ceiling */
        {{0, 0, 0}, {0, 1.5, 0}, {0, 1.5, 1}, {0, 0, 1}},     /* left */
        {{2, 0, 0}, {2, 0, 1}, {2, 1.5, 1}, {2, 1.5, 0}},     /* right */
        {{0, 0, 0}, {2, 0, 0}, {2, 1.5, 0}, {0, 1.5, 0}},     /* front */
    };
    static const float back[12] = {0, 0, 1, 0, 1.5f, 1, 2, 1.5f, 1, 2, 0, 1};
    xrad_scene_builder *b = NULL;
    xrad_error err = {0};
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "furnace", .density = 6}, &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "m", .albedo = {0.9, 0.9, 0.9}, .emission = {1, 1, 1}},
            &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "box"}, &err);
    for (int w = 0; w < 5 && !st; w++) {
        char name[8];
        snprintf(name, sizeof name, "wall%d", w);
        xrad_quad_desc q = {.name = name, .material = m};
        memcpy(q.p, walls[w], sizeof q.p);
        st = xrad_scene_builder_add_quad(b, &q, &err);
    }
    if (!st)
        st = xrad_scene_builder_add_mesh(
            b,
            &(xrad_mesh_desc){.name = "back", .positions = back, .vertex_count = 4,
                              .indices = (const uint32_t[]){0, 1, 2, 0, 2, 3},
                              .triangle_count = 2, .material = m, .keep_triangles = 1},
            &err);
    xrad_scene *scene = NULL;
    if (!st)
        st = xrad_scene_builder_finish(b, &scene, &err);
    xrad_scene_builder_destroy(&b);
    CHECK(st == XRAD_OK, "furnace: %s", err.message);
    return scene;
}

static void furnace(void)
{
    xrad_scene *scene = furnace_scene();
    if (!scene)
        return;
    xrad_atlas a = {0};
    xrad_reference_stats st = {0};
    xrad_error err = {0};
    xrad_status s = xrad_atlas_create(scene, &a, &err);
    if (!s)
        s = xrad_reference_solve(
            scene, &(xrad_reference_desc){.solver = XRAD_REFERENCE_SOLVER_GATHER, .threads = 2,
                                          .gather_rays = 64, .residual = 1e-9},
            &a, &st, &err);
    CHECK(s == XRAD_OK, "furnace: %s", err.message);
    if (!s) {
        double worst = 0;
        uint32_t triangles = 0;
        for (uint32_t e = 0; e < scene->element_count; e++) {
            worst = fmax(worst, fabs(element_sum(scene, &a, e) / 30.0 - 1));
            triangles += scene->surfaces[scene->elements[e].surface].triangle;
        }
        fprintf(stderr, "furnace (gather, 64 rays): worst element %.2e off B = 10, %u of %u "
                "elements on triangles, %u sweeps, every ray met a front: %.6f\n",
                worst, triangles, scene->element_count, st.sweeps, st.max_row_sum);
        CHECK(triangles > 0, "furnace: no element on a triangle");
        CHECK(st.solver == XRAD_REFERENCE_SOLVER_GATHER && st.gather_rays == 64,
              "furnace: solver %d, %u gather rays", (int)st.solver, st.gather_rays);
        CHECK(st.max_row_sum == 1.0, "furnace: the largest share of rays meeting a front is %.6f",
              st.max_row_sum);
        CHECK(worst < 1e-4, "furnace: worst element %.2e off E / (1 - rho)", worst);
    }
    xrad_atlas_destroy(&a);
    xrad_scene_destroy(&scene);
}

/* Gather (gather_rays) against dense clipping on the scene file `rel`;
 * returns the element p50 (-1 on failure). */
static double against_dense(const char *rel, uint32_t gather_rays, double surface_tol,
                            double p50_tol, double mean_tol)
{
    xrad_scene *scene = load(rel);
    if (!scene)
        return -1;
    xrad_atlas dense = {0}, gather = {0};
    xrad_reference_stats sd = {0}, sg = {0};
    xrad_error err = {0};
    xrad_status st;
    if (!(st = xrad_atlas_create(scene, &dense, &err)) &&
        !(st = xrad_atlas_create(scene, &gather, &err)) &&
        !(st = xrad_reference_solve(scene,
                                    &(xrad_reference_desc){.threads = 2,
                                                           .solver = XRAD_REFERENCE_SOLVER_DENSE,
                                                           .visibility = XRAD_VISIBILITY_CLIP},
                                    &dense, &sd, &err)))
        st = xrad_reference_solve(scene,
                                  &(xrad_reference_desc){.threads = 2,
                                                         .solver = XRAD_REFERENCE_SOLVER_GATHER,
                                                         .gather_rays = gather_rays},
                                  &gather, &sg, &err);
    CHECK(st == XRAD_OK, "%s: %s", rel, err.message);
    xrad_element_metrics m = {0};
    if (!st)
        st = xrad_atlas_compare(scene, &gather, &dense, &m, NULL, &err);
    CHECK(st == XRAD_OK, "%s: compare: %s", rel, err.message);
    double p50 = -1;
    if (!st) {
        xrad_surface_info si = {0};
        xrad_scene_get_surface(scene, m.worst_surface, &si, &err);
        fprintf(stderr,
                "%s: gather (%u rays, %.2f s) against dense clipping (%.2f s): surface_error "
                "%.5f (%s), p50 %.5f, p95 %.5f, mean ratio %.6f\n",
                rel, gather_rays, sg.form_factor_seconds + sg.solve_seconds,
                sd.form_factor_seconds + sd.solve_seconds, m.surface_error, si.name, m.p50, m.p95,
                m.mean_ratio);
        CHECK(sg.solver == XRAD_REFERENCE_SOLVER_GATHER && sd.solver == XRAD_REFERENCE_SOLVER_DENSE,
              "%s: solvers used %d / %d", rel, (int)sg.solver, (int)sd.solver);
        CHECK(m.elements > 0 && m.surface_error <= surface_tol && m.p50 <= p50_tol &&
                  fabs(m.mean_ratio - 1) <= mean_tol,
              "%s, %u rays: surface_error %.5f (<= %g), p50 %.5f (<= %g), mean ratio %.6f "
              "(within %g)",
              rel, gather_rays, m.surface_error, surface_tol, m.p50, p50_tol, m.mean_ratio,
              mean_tol);
        p50 = m.p50;
    }
    xrad_atlas_destroy(&dense);
    xrad_atlas_destroy(&gather);
    xrad_scene_destroy(&scene);
    return p50;
}

/* An element's sample pattern depends on its index alone. */
static void threads_and_refusals(void)
{
    xrad_scene *scene = load("scenes/cornell-box.json");
    if (!scene)
        return;
    xrad_atlas a1 = {0}, a2 = {0};
    xrad_error err = {0};
    xrad_status st;
    if (!(st = xrad_atlas_create(scene, &a1, &err)) && !(st = xrad_atlas_create(scene, &a2, &err)) &&
        !(st = xrad_reference_solve(
              scene, &(xrad_reference_desc){.solver = XRAD_REFERENCE_SOLVER_GATHER, .threads = 1,
                                            .gather_rays = 32},
              &a1, NULL, &err)))
        st = xrad_reference_solve(
            scene, &(xrad_reference_desc){.solver = XRAD_REFERENCE_SOLVER_GATHER, .threads = 2,
                                          .gather_rays = 32},
            &a2, NULL, &err);
    CHECK(st == XRAD_OK, "threads: %s", err.message);
    CHECK(!st && !memcmp(a1.rgba, a2.rgba, (size_t)a1.width * a1.height * 4 * sizeof *a1.rgba),
          "gather: 1 and 2 threads differ");

    /* Auto takes the dense solver where its matrix fits. */
    xrad_reference_stats s = {0};
    st = xrad_reference_solve(scene, &(xrad_reference_desc){.threads = 2}, &a1, &s, &err);
    CHECK(st == XRAD_OK && s.solver == XRAD_REFERENCE_SOLVER_DENSE, "auto: solver %d, %s",
          (int)s.solver, err.message);
    static const struct {
        xrad_reference_desc desc;
        const char *want;
    } bad[] = {
        {{.solver = (xrad_reference_solver)9}, "solver"},
        {{.solver = XRAD_REFERENCE_SOLVER_GATHER, .visibility = XRAD_VISIBILITY_CLIP}, "clip"},
        {{.solver = XRAD_REFERENCE_SOLVER_GATHER, .gather_rays = 70000}, "gather rays"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        err = (xrad_error){0};
        st = xrad_reference_solve(scene, &bad[k].desc, &a1, NULL, &err);
        CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, bad[k].want),
              "bad setting %zu: status %d, '%s' not in: %s", k, st, bad[k].want, err.message);
    }
    xrad_atlas_destroy(&a1);
    xrad_atlas_destroy(&a2);
    xrad_scene_destroy(&scene);
}

int main(void)
{
    furnace();
    threads_and_refusals();
    /* Measured: 256 rays, p50 0.0050 and p95 0.034; 1024 rays, p50 0.0018,
     * p95 0.011, surface_error 0.003, mean ratio 1.00003. */
    double p256 = against_dense("scenes/cornell-box.json", 256, 0.01, 0.008, 0.002);
    double p1024 = against_dense("scenes/cornell-box.json", 1024, 0.006, 0.003, 0.001);
    CHECK(p256 > 0 && p1024 > 0 && p1024 < 0.7 * p256,
          "4 x the rays took the element p50 from %.5f to %.5f, not near half", p256, p1024);
    against_dense("tests/data/lamp-room.json", 1024, 0.01, 0.005, 0.002);
    return test_finish();
}
