/* The public solver object: settings, defaults, dispatch to the method. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "scene/quality.h"
#include "solvers/solver.h"

static const struct {
    xrad_method method;
    const char *name;
    const solver_ops *ops;
} methods[] = {
    /* Each method file adds its line here when it lands. */
    {XRAD_METHOD_GATHER, "gather", &gather_ops},
    {XRAD_METHOD_PROGRESSIVE, "progressive", &progressive_ops},
    {XRAD_METHOD_INCREMENTAL, "incremental", &incremental_ops},
    {XRAD_METHOD_CROSS, "cross", &cross_ops},
    {0, NULL, NULL},
};

const char *xrad_method_name(xrad_method method)
{
    for (size_t i = 0; i < sizeof(methods) / sizeof(methods[0]); i++)
        if (methods[i].ops && methods[i].method == method)
            return methods[i].name;
    return NULL;
}

xrad_method xrad_method_from_name(const char *name)
{
    for (size_t i = 0; name && i < sizeof(methods) / sizeof(methods[0]); i++)
        if (methods[i].ops && !strcmp(methods[i].name, name))
            return methods[i].method;
    return 0;
}

/* Fills defaults and checks ranges; the messages name the setting. */
static xrad_status settle(xrad_solver_desc *d, xrad_error *err)
{
    if (!xrad_method_name(d->method))
        return xrad_fail(err, XRAD_ERROR_INPUT, "solver: method %d is unknown", (int)d->method);
    /* The quality settings: one table of defaults and ranges (quality.c). */
    xrad_quality q = {.solver = *d, .density_scale = 1};
    xrad_status st = quality_resolve(&q, err);
    if (st) {
        xrad_error_prefix(err, "solver");
        return st;
    }
    *d = q.solver;
    if (!d->max_iterations)
        d->max_iterations = 100000;
    /* max_patches 0: 12 for progressive, whose rooms (tests/solvers/rooms.c)
     * all came within 2% with it (room 2 0.0203 at 8); 8 for incremental
     * and cross, whose frames shoot too (incremental's 1.4 times as long
     * at 12 on cornell-large), and whose shipped scenes at 12 moved away
     * from the CPU reference with conserve far too (cross's cornell-large
     * 0.031 -> 0.052, README "far for every method"). */
    if (!d->max_patches)
        d->max_patches = d->method == XRAD_METHOD_PROGRESSIVE ? 12 : 8;
    /* conserve auto: far for every method. The dynamic methods had on
     * (far made incremental's frames in room 1 1.1 times as long), but far
     * brought incremental closer to the CPU reference on eight of the ten
     * shipped scenes and cross on seven (lamp-room 0.035 -> 0.010,
     * indirect-light 0.069 -> 0.041); it costs cornell-small's cross
     * (0.084 -> 0.198, README "far for every method"). */
    if (d->conserve == XRAD_CONSERVE_AUTO)
        d->conserve = XRAD_CONSERVE_FAR;
    if (!(d->time == d->time) || d->time > 1e9 || d->time < -1e9)
        return xrad_fail(err, XRAD_ERROR_INPUT, "solver: time must be finite, got %g", d->time);
    return XRAD_OK;
}

xrad_status xrad_solver_create(xrad_context *ctx, const xrad_scene *scene,
                               const xrad_solver_desc *desc, xrad_solver **out,
                               xrad_error *err)
{
    *out = NULL;
    xrad_solver_desc d = desc ? *desc : (xrad_solver_desc){0};
    xrad_status st = settle(&d, err);
    if (st)
        return st;
    xrad_solver *s = calloc(1, sizeof(*s));
    if (!s)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "solver: out of memory");
    s->ctx = ctx;
    s->scene = scene;
    s->desc = d;
    for (size_t i = 0; i < sizeof(methods) / sizeof(methods[0]); i++)
        if (methods[i].ops && methods[i].method == d.method)
            s->ops = methods[i].ops;
    /* What a moving object closes in is buried at every pose (gpu_scene.h;
     * 1-5 ms a pose on one core for the shipped scenes): progressive and
     * gather solve each pose afresh, incremental's first solve too
     * (progressive_run's restart), and cross's reconstruction takes the
     * light of C's elements so closed in (cross_reconstruct.comp). */
    uint32_t scene_flags = GPU_SCENE_ENCLOSE_MOVING;
    s->reporting = true;
    if ((st = gpu_scene_create(ctx, scene, d.time, scene_flags, &s->gs, err)) ||
        (st = gpu_timer_create(ctx, 256, &s->timer, err)) || (st = s->ops->create(s, err))) {
        xrad_solver_destroy(&s);
        return st;
    }
    s->reporting = false;
    *out = s;
    return XRAD_OK;
}

void xrad_solver_destroy(xrad_solver **solver)
{
    if (!solver || !*solver)
        return;
    xrad_solver *s = *solver;
    if (s->impl)
        s->ops->destroy(s);
    gpu_timer_destroy(s->ctx, &s->timer);
    gpu_scene_destroy(s->ctx, &s->gs);
    free(s);
    *solver = NULL;
}

double solver_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

void solver_progress(const xrad_solver *s, const char *stage, double fraction)
{
    if (s->reporting && s->desc.progress)
        s->desc.progress(s->desc.progress_user, stage,
                         fraction < 0 ? 0 : fraction > 1 ? 1 : fraction);
}

void solver_stats_begin(xrad_solver *s)
{
    xrad_solver_stats kept = s->stats;
    memset(&s->stats, 0, sizeof(s->stats));
    /* What creation fixed stays. */
    s->stats.hemicube_path = kept.hemicube_path;
    s->stats.cross_patches = kept.cross_patches;
    s->stats.cross_light_patches = kept.cross_light_patches;
    /* Pass times are per call. */
    memset(s->timer->totals, 0, sizeof(s->timer->totals));
    s->timer->name_count = 0;
}

xrad_status xrad_solver_solve(xrad_solver *s, xrad_error *err)
{
    solver_stats_begin(s);
    double t0 = solver_now_ms();
    s->solved = false;
    s->reporting = true;
    xrad_status st = s->ops->solve(s, err);
    s->reporting = false;
    s->stats.wall_ms = solver_now_ms() - t0;
    s->solved = st == XRAD_OK;
    return st;
}

xrad_status xrad_solver_advance(xrad_solver *s, double time, xrad_error *err)
{
    if (!(time >= -1e9 && time <= 1e9))
        return xrad_fail(err, XRAD_ERROR_INPUT, "solver: time must be finite, got %g", time);
    if (!s->ops->advance || !s->solved) {
        xrad_status st = xrad_solver_set_time(s, time, err);
        return st ? st : xrad_solver_solve(s, err);
    }
    solver_stats_begin(s);
    double t0 = solver_now_ms();
    s->solved = false;
    xrad_status st = s->ops->advance(s, time, err);
    s->stats.wall_ms = solver_now_ms() - t0;
    if (!st)
        s->desc.time = time;
    s->solved = st == XRAD_OK;
    return st;
}

xrad_status xrad_solver_set_time(xrad_solver *s, double time, xrad_error *err)
{
    if (!(time >= -1e9 && time <= 1e9))
        return xrad_fail(err, XRAD_ERROR_INPUT, "solver: time must be finite, got %g", time);
    xrad_status st = gpu_scene_pose(s->ctx, &s->gs, time, err);
    if (!st)
        s->desc.time = time;
    /* The solution in hand belongs to the old pose: a redistribution from
     * it would start from the wrong geometry. */
    s->solved = false;
    return st;
}

xrad_status xrad_solver_read(xrad_solver *s, xrad_atlas *atlas, xrad_error *err)
{
    /* Gather keeps no unshot radiosity to estimate from. */
    bool ambient = s->desc.ambient == XRAD_AMBIENT_ON && s->desc.method != XRAD_METHOD_GATHER;
    return gpu_scene_read(s->ctx, &s->gs, atlas, ambient, err);
}

void xrad_solver_get_stats(const xrad_solver *s, xrad_solver_stats *stats) { *stats = s->stats; }

xrad_status solver_submit_wait(xrad_solver *s, gpu_cmd *c, xrad_error *err)
{
    xrad_status st = gpu_cmd_submit(s->ctx, c, err);
    if (!st) {
        s->stats.submissions++;
        st = gpu_cmd_wait(s->ctx, c, err);
        s->stats.host_waits++;
    }
    gpu_cmd_destroy(s->ctx, c);
    if (!st)
        st = gpu_scene_collect_pose(s->ctx, &s->gs, err);
    return st ? st : gpu_timer_collect(s->ctx, s->timer, err);
}

void solver_collect_times(xrad_solver *s)
{
    const gpu_timer *t = s->timer;
    for (uint32_t i = 0; i < t->name_count; i++) {
        xrad_pass_time *p = NULL;
        for (uint32_t k = 0; k < s->stats.pass_count; k++)
            if (!strcmp(s->stats.passes[k].name, t->totals[i].name))
                p = &s->stats.passes[k];
        if (!p && s->stats.pass_count < XRAD_MAX_PASSES) {
            p = &s->stats.passes[s->stats.pass_count++];
            snprintf(p->name, sizeof(p->name), "%s", t->totals[i].name);
        }
        if (p) {
            p->ms = t->totals[i].ms;
            p->count = t->totals[i].count;
        }
    }
    s->stats.gpu_ms = 0;
    for (uint32_t k = 0; k < s->stats.pass_count; k++)
        s->stats.gpu_ms += s->stats.passes[k].ms;
}
