/* Drift (DESIGN.md "Numerical notes"; thesis 3.1, 4.5.2 error analysis,
 * 6.2): FRAMES frames of cornell-lowq's animation with the cross method,
 * each a redistribution plus progressive iterations, checked against fresh
 * progressive solves of the pose at frame EARLY and at the last frame: at
 * the end within image NRMSE 0.01, and the error grows from EARLY to the
 * end by at most DRIFT_PER_FRAME per frame. Incremental radiosity is run
 * the same way. Cross replaces what the last redistribution gave C
 * instead of updating it (src/solvers/cross.c), so where it ends cannot
 * depend on the way there: 30 frames of the animation, then advances to
 * the last frame's time until it settles, against a cross solve at that
 * time.
 *
 * 100 frames, not 1000 (issue 14: the 1000-frame run took about 13
 * minutes of an idle 2-core machine, nine tenths of it incremental's
 * frames, and timed out on a busy one; 300 frames took 1000 s of CI's
 * 2-core 45 minutes, and 200 frames 557 s idle on 2026-12-05, 480 s of
 * it incremental's frames at 2.4 s each, 999 s beside one other test).
 * Measured over 1000 frames against fresh solves:
 * cross's NRMSE moves with the pose between 0.0015 and 0.0022 and does
 * not grow; incremental's grows about linearly, 0.00055 after 1 frame,
 * 0.00065 after 30, 0.00102 after 300, 0.00187 after 1000 (about 1.3e-6
 * per frame; 2026-12-05, 200 frames: cross 0.00036 -> 0.00040,
 * incremental 0.00042 -> 0.00044). The 1000-frame test, NRMSE below 0.01
 * at the end, failed a steady drift of about 1e-5 per frame or more; the
 * growth check fails that same drift within 100 frames (7e-4 over frames
 * 30-100, against at most 1e-4 measured), and a drift that grows like the
 * square root of the frame count at a smaller size than the 1000-frame
 * test did. A drift that only sets in after frame 100 goes unseen here;
 * the 10,000-frame runs of suite long (test_extremes --long) hold both
 * methods finite and within the power bound. */
#include <stdio.h>

#include "solvers/solver_test.h"

#define FRAMES 100
#define EARLY 30
#define FPS 30.0
#define END_NRMSE 0.01
#define DRIFT_PER_FRAME 1e-5
/* Advances at the last pose for the path check: those of the solve's
 * rounds (cross.c) and as many again. */
#define SETTLE 8
#define PATH_NRMSE 1e-3
/* Every solve with conserve on, the dynamic methods' default rule (auto,
 * xrad.h): what drifts is the frames' work, and far solves (a test build
 * gave all six of cornell-lowq far) made the test 763 s in a loaded suite
 * run, against 250-280 s. */
#define CONSERVE XRAD_CONSERVE_ON

/* The image after `frames` frames of `m` from t = 0 and `settle` more
 * advances to the last frame's time (NULL on failure). */
static float *run_frames(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                         uint32_t frames, uint32_t settle, uint32_t *w, uint32_t *h)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    xrad_solver_desc d = {.method = m, .conserve = CONSERVE};
    CHECK(xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK &&
              xrad_solver_solve(s, &err) == XRAD_OK,
          "%s: %s", xrad_method_name(m), err.message);
    xrad_status st = XRAD_OK;
    for (uint32_t f = 1; s && f <= frames && !st; f++)
        st = xrad_solver_advance(s, f / FPS, &err);
    for (uint32_t k = 0; s && k < settle && !st; k++)
        st = xrad_solver_advance(s, frames / FPS, &err);
    CHECK(st == XRAD_OK, "%s: advance: %s", xrad_method_name(m), err.message);
    float *img = s && !st ? solver_test_render(ctx, scene, s, frames / FPS, w, h) : NULL;
    xrad_solver_destroy(&s);
    return img;
}

/* A fresh progressive solve's image at frame `frame` (NULL on failure). */
static float *fresh_solve(xrad_context *ctx, const xrad_scene *scene, uint32_t frame)
{
    xrad_error err = {0};
    xrad_solver *f = NULL;
    xrad_solver_desc d = {.method = XRAD_METHOD_PROGRESSIVE, .time = frame / FPS,
                          .conserve = CONSERVE};
    CHECK(xrad_solver_create(ctx, scene, &d, &f, &err) == XRAD_OK &&
              xrad_solver_solve(f, &err) == XRAD_OK,
          "fresh solve at frame %u: %s", frame, err.message);
    uint32_t w, h;
    float *img = f ? solver_test_render(ctx, scene, f, frame / FPS, &w, &h) : NULL;
    xrad_solver_destroy(&f);
    return img;
}

/* FRAMES frames of `m` from t = 0; e[k] the NRMSE against fresh[k] at
 * frame EARLY (k = 0) and FRAMES (k = 1), -1 where it failed. */
static void drift(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                  float *const fresh[2], double e[2])
{
    static const uint32_t at[2] = {EARLY, FRAMES};
    xrad_error err = {0};
    xrad_solver *s = NULL;
    /* Incremental at most 4 patches a side: its redistribution shoots C
     * again with the fixed patches of every shot since the solve, and a
     * frame of cornell-lowq took 2.5 s against 5.1 s at the default 8
     * (2026-12-07, beside another test); what drifts is the frames' work,
     * whatever the patches. */
    xrad_solver_desc d = {
        .method = m, .conserve = CONSERVE, .max_patches = m == XRAD_METHOD_INCREMENTAL ? 4 : 0};
    e[0] = e[1] = -1;
    CHECK(xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK &&
              xrad_solver_solve(s, &err) == XRAD_OK,
          "%s: %s", xrad_method_name(m), err.message);
    xrad_status st = XRAD_OK;
    double ms = 0;
    for (uint32_t f = 1, k = 0; s && f <= FRAMES && !st; f++) {
        st = xrad_solver_advance(s, f / FPS, &err);
        xrad_solver_stats stats;
        xrad_solver_get_stats(s, &stats);
        ms += stats.wall_ms / FRAMES;
        if (!st && k < 2 && f == at[k]) {
            uint32_t w, h;
            float *img = solver_test_render(ctx, scene, s, f / FPS, &w, &h);
            if (img && fresh[k])
                e[k] = xrad_image_nrmse(img, fresh[k], w, h);
            free(img);
            k++;
        }
    }
    CHECK(st == XRAD_OK, "%s: advance: %s", xrad_method_name(m), err.message);
    fprintf(stderr,
            "drift %s: NRMSE %.5f after %u frames, %.5f after %u, against fresh solves; "
            "%.1f ms per frame\n",
            xrad_method_name(m), e[0], EARLY, e[1], FRAMES, ms);
    xrad_solver_destroy(&s);
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
    float *fresh[2] = {fresh_solve(ctx, scene, EARLY), fresh_solve(ctx, scene, FRAMES)};
    xrad_method methods[2] = {XRAD_METHOD_CROSS, XRAD_METHOD_INCREMENTAL};
    for (int m = 0; m < 2 && fresh[0] && fresh[1]; m++) {
        double e[2];
        drift(ctx, scene, methods[m], fresh, e);
        const char *name = xrad_method_name(methods[m]);
        CHECK(e[1] >= 0 && e[1] < END_NRMSE, "%s drifted to NRMSE %.5f after %u frames", name,
              e[1], FRAMES);
        CHECK(e[0] >= 0 && e[1] - e[0] <= DRIFT_PER_FRAME * (FRAMES - EARLY),
              "%s drifts: NRMSE %.5f after %u frames, %.5f after %u (more than %g per frame)",
              name, e[0], EARLY, e[1], FRAMES, DRIFT_PER_FRAME);
    }
    free(fresh[0]);
    free(fresh[1]);
    uint32_t w0, h0, w1, h1;
    float *moved = run_frames(ctx, scene, XRAD_METHOD_CROSS, 30, SETTLE, &w0, &h0);
    float *solved = NULL;
    xrad_solver *f = NULL;
    xrad_solver_desc d = {.method = XRAD_METHOD_CROSS, .time = 30 / FPS, .conserve = CONSERVE};
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
