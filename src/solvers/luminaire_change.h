/*
 * The luminaires' direct light as the redistributing methods follow it
 * (issue 18.3). A luminaire's light enters a solve as the lit elements'
 * starting radiosity (gpu_scene_reset, scene_luminaire.h), at the solve's
 * pose; a moving object then changes what it lights. Per pose this keeps,
 * for the GPU, rho x the luminaires' direct light at the pose on the
 * elements of M (what they take as their own emission there) and its
 * change against a base on the elements of C (the shadow M casts, new
 * light that the progressive iterations shoot on): incremental's base is
 * the light of the last pose, cross's the light of C alone (the static
 * scene it solves; what M hides is its redistribution's source).
 */
#ifndef XRAD_SOLVERS_LUMINAIRE_CHANGE_H
#define XRAD_SOLVERS_LUMINAIRE_CHANGE_H

#include <stdbool.h>

#include "core/vec.h"
#include "gpu/buffer.h"
#include "scene/scene.h"

struct xrad_context;

typedef struct luminaire_change {
    bool active;       /* the scene has luminaires: the buffer is written per pose */
    gpu_buffer buffer; /* vec4[element_count], host-visible (vec4[1] where not active) */
    vec3 *base;        /* [element_count]: on C, the light the solution holds */
    vec3 *now;         /* [element_count]: scratch, the light at the pose */
} luminaire_change;

xrad_status luminaire_change_create(struct xrad_context *ctx, const xrad_scene *scene,
                                    luminaire_change *lc, xrad_error *err);
void luminaire_change_destroy(struct xrad_context *ctx, luminaire_change *lc);

/* base = rho x the luminaires' light at scene time `time`, shadowed by
 * every object (dynamic_too) or by the static ones alone. */
xrad_status luminaire_change_set_base(luminaire_change *lc, const xrad_scene *scene, double time,
                                      bool dynamic_too, xrad_error *err);

/* The buffer for the pose at `time`: the light there on M, the light there
 * less base on C; with `advance`, base takes the light there. The GPU must
 * be done with the buffer (the methods wait for each submission). */
xrad_status luminaire_change_pose(luminaire_change *lc, const xrad_scene *scene, double time,
                                  bool advance, xrad_error *err);

#endif
