/*
 * xrad's own display of the real-time loop as the public API gives it
 * (include/xrad_vulkan.h): the viewer (viewer.h) with a public camera and
 * statistics.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "render/viewer.h"
#include "schedule/scheduler.h"
#include "xrad_vulkan.h"

struct xrad_viewer {
    viewer *v;
};

xrad_status xrad_viewer_create(xrad_context *ctx, const xrad_scene *scene,
                               const xrad_viewer_desc *desc, xrad_viewer **out, xrad_error *err)
{
    *out = NULL;
    if (!ctx || !scene || !desc || !desc->surface)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "viewer: a context, a scene and a window surface are required");
    xrad_viewer *x = calloc(1, sizeof(*x));
    if (!x)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (viewer)");
    viewer_desc d = {.surface = desc->surface,
                     .width = desc->width,
                     .height = desc->height,
                     .vsync = desc->vsync != 0};
    xrad_status st = viewer_create(ctx, scene, &d, &x->v, err);
    if (st) {
        free(x);
        return st;
    }
    *out = x;
    return XRAD_OK;
}

void xrad_viewer_destroy(xrad_viewer **px)
{
    if (!px || !*px)
        return;
    viewer_destroy(&(*px)->v);
    free(*px);
    *px = NULL;
}

xrad_status xrad_viewer_frame(xrad_viewer *x, xrad_scheduler *s, const xrad_viewer_frame_desc *d,
                              xrad_error *err)
{
    const xrad_camera_desc *c = &d->camera;
    viewer_frame_desc f = {
        .cam = {.position = v3(c->position[0], c->position[1], c->position[2]),
                .look_at = v3(c->look_at[0], c->look_at[1], c->look_at[2]),
                .up = v3(c->up[0], c->up[1], c->up[2]),
                .fov_y = c->fov_degrees * M_PI / 180.0},
        .time = d->time,
        .exposure = d->exposure,
        .tonemap = d->tonemap,
        .nearest = d->nearest != 0,
        .width = d->width,
        .height = d->height,
        .screenshot = d->screenshot,
        .overlay = d->overlay,
    };
    return viewer_frame(x->v, scheduler_api_inner(s), &f, err);
}

void xrad_viewer_get_stats(const xrad_viewer *x, xrad_viewer_stats *out)
{
    viewer_stats vs;
    viewer_get_stats(x->v, &vs);
    memset(out, 0, sizeof(*out));
    out->frames = vs.frames;
    out->recreations = vs.recreations;
    out->exposure = vs.exposure;
    out->tonemap = vs.tonemap;
    out->serial = vs.serial;
    out->solution_time = vs.solution_time;
    out->frame_ms = sliding_mean(&vs.frame_ms);
    out->pass_count = sliding_table_means(&vs.passes, out->passes, XRAD_MAX_PASSES);
}
