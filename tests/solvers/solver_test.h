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

#endif
