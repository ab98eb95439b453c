/*
 * The real-time loop as the public API gives it (include/xrad_vulkan.h):
 * the scheduler (scheduler.h) with requests checked on the caller's thread
 * and frames in Vulkan handles.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "schedule/scheduler.h"
#include "xrad_vulkan.h"

struct xrad_scheduler {
    scheduler *s;
    uint64_t requests; /* made so far: the next one's serial - 1 */
};

xrad_status xrad_scheduler_create(xrad_context *ctx, xrad_scene *scene,
                                  const xrad_scheduler_desc *desc, xrad_scheduler **out,
                                  xrad_error *err)
{
    *out = NULL;
    if (!ctx || !scene)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scheduler: a context and a scene are required");
    scheduler_desc d = {.solver = desc ? desc->solver : (xrad_solver_desc){0}};
    if (!d.solver.method)
        d.solver.method = XRAD_METHOD_CROSS;
    xrad_scheduler *x = calloc(1, sizeof(*x));
    if (!x)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (scheduler)");
    xrad_status st = scheduler_create(ctx, scene, &d, &x->s, err);
    if (st) {
        free(x);
        return st;
    }
    *out = x;
    return XRAD_OK;
}

void xrad_scheduler_destroy(xrad_scheduler **px)
{
    if (!px || !*px)
        return;
    scheduler_destroy(&(*px)->s);
    free(*px);
    *px = NULL;
}

xrad_status xrad_scheduler_request(xrad_scheduler *x, const xrad_request *r, uint64_t *serial,
                                   xrad_error *err)
{
    const xrad_scene *scene = scheduler_scene(x->s);
    if (!isfinite(r->time))
        return xrad_fail(err, XRAD_ERROR_INPUT, "scheduler request: time is not finite");
    if (r->method && !xrad_method_name(r->method))
        return xrad_fail(err, XRAD_ERROR_INPUT, "scheduler request: unknown method %d",
                         (int)r->method);
    if (r->pose_count > SCHEDULER_MAX_OBJECTS || r->emission_count > SCHEDULER_MAX_MATERIALS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "scheduler request: %u poses and %u emissions, at most %d and %d",
                         r->pose_count, r->emission_count, SCHEDULER_MAX_OBJECTS,
                         SCHEDULER_MAX_MATERIALS);
    scheduler_request q;
    memset(&q, 0, sizeof(q));
    q.time = r->time;
    q.method = r->method;
    xrad_status st;
    for (uint32_t i = 0; i < r->pose_count; i++) {
        const xrad_object_pose *p = &r->poses[i];
        if ((st = scene_check_pose(scene, p->object, p->clear ? NULL : p->matrix, NULL, err))) {
            xrad_error_prefix(err, "scheduler request");
            return st;
        }
        q.poses[i] = (scheduler_pose){.object = p->object, .clear = p->clear != 0};
        memcpy(q.poses[i].matrix, p->matrix, sizeof(p->matrix));
    }
    q.pose_count = r->pose_count;
    for (uint32_t i = 0; i < r->emission_count; i++) {
        const xrad_emission_change *e = &r->emissions[i];
        if ((st = scene_check_emission(scene, e->material, e->emission, err))) {
            xrad_error_prefix(err, "scheduler request");
            return st;
        }
        q.emissions[i].material = e->material;
        memcpy(q.emissions[i].emission, e->emission, sizeof(e->emission));
    }
    q.emission_count = r->emission_count;
    if ((st = scheduler_status(x->s, err)))
        return st;
    scheduler_request_frame(x->s, &q);
    x->requests++;
    if (serial)
        *serial = x->requests;
    return XRAD_OK;
}

xrad_status xrad_scheduler_begin_frame(xrad_scheduler *x, xrad_frame *f, xrad_error *err)
{
    memset(f, 0, sizeof(*f));
    scheduler_frame sf;
    xrad_status st = scheduler_frame_begin(x->s, &sf, err);
    if (st)
        return st;
    if (sf.atlas) {
        f->image = sf.atlas->image;
        f->view = sf.atlas->view;
        f->format = sf.atlas->format;
        f->width = sf.atlas->width;
        f->height = sf.atlas->height;
    }
    f->layout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    f->serial = sf.serial;
    f->time = sf.time;
    f->swapped = sf.swapped;
    f->wait = sf.wait;
    f->wait_value = sf.wait_value;
    f->wait_stage = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    f->signal = sf.signal;
    f->signal_value = sf.signal_value;
    return XRAD_OK;
}

xrad_status xrad_scheduler_end_frame(xrad_scheduler *x, const xrad_frame *f, int submitted,
                                     xrad_error *err)
{
    scheduler_frame sf = {
        .atlas = scheduler_atlas_of(x->s, f->image),
        .serial = f->serial,
        .wait = f->wait,
        .wait_value = f->wait_value,
        .signal = f->signal,
        .signal_value = f->signal_value,
    };
    return scheduler_frame_end(x->s, &sf, submitted != 0, err);
}

xrad_status xrad_scheduler_wait(xrad_scheduler *x, uint64_t serial, xrad_error *err)
{
    return scheduler_wait_published(x->s, serial, err);
}

void xrad_scheduler_get_stats(xrad_scheduler *x, xrad_scheduler_stats *out)
{
    scheduler_stats st;
    scheduler_get_stats(x->s, &st);
    memset(out, 0, sizeof(*out));
    out->requested = st.requested;
    out->published = st.published;
    out->time = st.time;
    out->method = st.method;
    out->busy = st.busy;
    out->frame_ms = st.frame_ms;
    out->redistribute_ms = st.redistribute_ms;
    out->pass_count = sliding_table_means(&st.passes, out->passes, XRAD_MAX_PASSES);
    out->last = st.last;
}

scheduler *scheduler_api_inner(xrad_scheduler *x) { return x->s; }
