/* Drift (DESIGN.md "Numerical notes"; thesis 3.1, 4.5.2 error analysis,
 * 6.2): 1000 frames of cornell-lowq's animation with the cross method,
 * each a redistribution plus progressive iterations, end within image
 * NRMSE 0.01 of a fresh progressive solve of the final pose with the
 * hemicube cache (desc.cross_recompute = 0, the default), and the value
 * without it (the thesis's four hemicubes per patch and frame) is
 * reported. Incremental radiosity is run the same way for comparison. */
#include <stdio.h>

#include "solvers/solver_test.h"

#define FRAMES 1000
#define FPS 30.0

/* NRMSE of `frames` frames of `m` from t = 0 against a fresh solve at the end. */
static double drift(xrad_context *ctx, const xrad_scene *scene, xrad_method m, int recompute,
                    const float *fresh, uint32_t frames)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    xrad_solver_desc d = {.method = m, .cross_recompute = recompute};
    CHECK(xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK &&
              xrad_solver_solve(s, &err) == XRAD_OK,
          "%s: %s", xrad_method_name(m), err.message);
    double e = -1, ms = 0;
    xrad_status st = XRAD_OK;
    for (uint32_t f = 1; s && f <= frames && !st; f++) {
        st = xrad_solver_advance(s, f / FPS, &err);
        xrad_solver_stats stats;
        xrad_solver_get_stats(s, &stats);
        ms += stats.wall_ms;
    }
    CHECK(st == XRAD_OK, "%s: advance: %s", xrad_method_name(m), err.message);
    uint32_t w, h;
    float *img = s && !st ? solver_test_render(ctx, scene, s, frames / FPS, &w, &h) : NULL;
    if (img) {
        e = xrad_image_nrmse(img, fresh, w, h);
        fprintf(stderr, "drift %s%s: %u frames, NRMSE %.5f vs a fresh solve, %.1f ms per frame\n",
                xrad_method_name(m), m == XRAD_METHOD_CROSS && recompute ? " (recompute)" : "",
                frames, e, ms / frames);
    }
    free(img);
    xrad_solver_destroy(&s);
    return e;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    char path[1024];
    xrad_error err = {0};
    xrad_scene *scene = NULL;
    CHECK(xrad_scene_load(test_source_path("scenes/cornell-lowq.json", path, sizeof(path)),
                          &scene, &err) == XRAD_OK,
          "%s", err.message);
    if (!ctx || !scene) {
        xrad_scene_destroy(&scene);
        gpu_test_end(&ctx);
        return test_finish();
    }
    xrad_solver *f = NULL;
    xrad_solver_desc d = {.method = XRAD_METHOD_PROGRESSIVE, .time = FRAMES / FPS};
    CHECK(xrad_solver_create(ctx, scene, &d, &f, &err) == XRAD_OK &&
              xrad_solver_solve(f, &err) == XRAD_OK,
          "fresh: %s", err.message);
    uint32_t w, h;
    float *fresh = f ? solver_test_render(ctx, scene, f, FRAMES / FPS, &w, &h) : NULL;
    xrad_solver_destroy(&f);
    if (fresh) {
        double cached = drift(ctx, scene, XRAD_METHOD_CROSS, 0, fresh, FRAMES);
        CHECK(cached >= 0 && cached < 0.01, "cross with the hemicube cache drifted to NRMSE %.5f",
              cached);
        double recomputed = drift(ctx, scene, XRAD_METHOD_CROSS, 1, fresh, FRAMES);
        CHECK(recomputed >= 0, "cross without the cache did not finish");
        double incremental = drift(ctx, scene, XRAD_METHOD_INCREMENTAL, 0, fresh, FRAMES);
        CHECK(incremental >= 0 && incremental < 0.01, "incremental drifted to NRMSE %.5f",
              incremental);
    }
    free(fresh);
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
