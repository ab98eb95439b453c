/* Drift (DESIGN.md "Numerical notes"; thesis 3.1, 4.5.2 error analysis,
 * 6.2): 1000 frames of cornell-lowq's animation with the cross method,
 * each a redistribution plus progressive iterations, end within image
 * NRMSE 0.01 of a fresh progressive solve of the final pose. Incremental
 * radiosity is run the same way. Cross replaces what the last
 * redistribution gave C instead of updating it (src/solvers/cross.c), so
 * where it ends cannot depend on the way there: 30 frames of the
 * animation, then advances to the last frame's time until it settles,
 * against a cross solve at that time. */
#include <stdio.h>

#include "solvers/solver_test.h"

#define FRAMES 1000
#define FPS 30.0
/* Advances at the last pose for the path check: those of the solve's
 * rounds (cross.c) and as many again. */
#define SETTLE 8
#define PATH_NRMSE 1e-3

/* The image after `frames` frames of `m` from t = 0 and `settle` more
 * advances to the last frame's time (NULL on failure); *ms the mean wall
 * time per frame. */
static float *run_frames(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                         uint32_t frames, uint32_t settle, uint32_t *w, uint32_t *h, double *ms)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    xrad_solver_desc d = {.method = m};
    CHECK(xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK &&
              xrad_solver_solve(s, &err) == XRAD_OK,
          "%s: %s", xrad_method_name(m), err.message);
    xrad_status st = XRAD_OK;
    *ms = 0;
    for (uint32_t f = 1; s && f <= frames && !st; f++) {
        st = xrad_solver_advance(s, f / FPS, &err);
        xrad_solver_stats stats;
        xrad_solver_get_stats(s, &stats);
        *ms += stats.wall_ms / frames;
    }
    for (uint32_t k = 0; s && k < settle && !st; k++)
        st = xrad_solver_advance(s, frames / FPS, &err);
    CHECK(st == XRAD_OK, "%s: advance: %s", xrad_method_name(m), err.message);
    float *img = s && !st ? solver_test_render(ctx, scene, s, frames / FPS, w, h) : NULL;
    xrad_solver_destroy(&s);
    return img;
}

/* NRMSE of `frames` frames of `m` from t = 0 against a fresh solve at the end. */
static double drift(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                    const float *fresh, uint32_t frames)
{
    uint32_t w, h;
    double ms, e = -1;
    float *img = run_frames(ctx, scene, m, frames, 0, &w, &h, &ms);
    if (img) {
        e = xrad_image_nrmse(img, fresh, w, h);
        fprintf(stderr, "drift %s: %u frames, NRMSE %.5f vs a fresh solve, %.1f ms per frame\n",
                xrad_method_name(m), frames, e, ms);
    }
    free(img);
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
        double cached = drift(ctx, scene, XRAD_METHOD_CROSS, fresh, FRAMES);
        CHECK(cached >= 0 && cached < 0.01, "cross with the hemicube cache drifted to NRMSE %.5f",
              cached);
        double incremental = drift(ctx, scene, XRAD_METHOD_INCREMENTAL, fresh, FRAMES);
        CHECK(incremental >= 0 && incremental < 0.01, "incremental drifted to NRMSE %.5f",
              incremental);
    }
    free(fresh);
    uint32_t w0, h0, w1, h1;
    double ms;
    float *moved = run_frames(ctx, scene, XRAD_METHOD_CROSS, 30, SETTLE, &w0, &h0, &ms);
    float *solved = NULL;
    d = (xrad_solver_desc){.method = XRAD_METHOD_CROSS, .time = 30 / FPS};
    CHECK(xrad_solver_create(ctx, scene, &d, &f, &err) == XRAD_OK &&
              xrad_solver_solve(f, &err) == XRAD_OK,
          "cross solve: %s", err.message);
    if (f)
        solved = solver_test_render(ctx, scene, f, 30 / FPS, &w1, &h1);
    xrad_solver_destroy(&f);
    if (moved && solved && w0 == w1 && h0 == h1) {
        double e = xrad_image_nrmse(moved, solved, w0, h0);
        fprintf(stderr, "cross, 30 frames and %d advances more against a solve at the last "
                        "pose: NRMSE %.2e\n", SETTLE, e);
        CHECK(e >= 0 && e < PATH_NRMSE, "cross depends on the way to a pose: NRMSE %g", e);
    } else {
        CHECK(false, "cross, 30 frames against a solve did not finish");
    }
    free(moved);
    free(solved);
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
