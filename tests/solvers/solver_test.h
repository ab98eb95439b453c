/* Helpers shared by the solver tests: a solver's solution as the camera
 * sees it, the way a user looks at it. */
#ifndef XRAD_TESTS_SOLVER_TEST_H
#define XRAD_TESTS_SOLVER_TEST_H

#include "gpu/gpu_test.h"

/* The scene's camera image (192 x 192) of the solver's solution, posed at
 * scene time t; NULL (after a failed CHECK) on error. free() it. */
static inline float *solver_test_render(xrad_context *ctx, const xrad_scene *scene,
                                        xrad_solver *s, double t, uint32_t *w, uint32_t *h)
{
    xrad_error err = {0};
    xrad_atlas a = {0};
    float *img = NULL;
    xrad_view_desc v = {.time = t, .width = 192, .height = 192};
    CHECK(xrad_atlas_create(scene, &a, &err) == XRAD_OK &&
              xrad_solver_read(s, &a, &err) == XRAD_OK &&
              xrad_render_view(ctx, scene, &a, &v, &img, w, h, &err) == XRAD_OK,
          "render: %s", err.message);
    xrad_atlas_destroy(&a);
    return img;
}

/* The CPU reference (method 0) and the four GPU methods. */
static const struct solver_test_method {
    const char *name;
    xrad_method method;
} solver_test_methods[] = {
    {"reference", (xrad_method)0},
    {"gather", XRAD_METHOD_GATHER},
    {"progressive", XRAD_METHOD_PROGRESSIVE},
    {"incremental", XRAD_METHOD_INCREMENTAL},
    {"cross", XRAD_METHOD_CROSS},
};
#define SOLVER_TEST_METHODS (sizeof(solver_test_methods) / sizeof(solver_test_methods[0]))

/* Solves `scene` into a new *atlas (destroy it): with the CPU reference
 * (2 threads) where d->method is 0, else with a solver of `d`. */
static inline xrad_status solver_test_solve(xrad_context *ctx, const xrad_scene *scene,
                                            const xrad_solver_desc *d, xrad_atlas *atlas,
                                            xrad_error *err)
{
    xrad_status st = xrad_atlas_create(scene, atlas, err);
    if (st)
        return st;
    if (!d->method)
        return xrad_reference_solve(scene, &(xrad_reference_desc){.threads = 2}, atlas, NULL,
                                    err);
    xrad_solver *s = NULL;
    if (!(st = xrad_solver_create(ctx, scene, d, &s, err)) && !(st = xrad_solver_solve(s, err)))
        st = xrad_solver_read(s, atlas, err);
    xrad_solver_destroy(&s);
    return st;
}

/* The largest difference between two atlases' texels, relative to the
 * largest texel of b; INFINITY where b is all zero. */
static inline double solver_test_atlas_diff(const xrad_atlas *a, const xrad_atlas *b)
{
    double d = 0, top = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++) {
        d = fmax(d, fabs((double)a->rgba[i] - b->rgba[i]));
        top = fmax(top, fabs((double)b->rgba[i]));
    }
    return top > 0 ? d / top : INFINITY;
}

#endif
