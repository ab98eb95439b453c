#include "method.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"

const char *method_list(void) { return "reference, gather, progressive, incremental, cross"; }

int method_known(const char *name)
{
    return !strcmp(name, "reference") || xrad_method_from_name(name) != 0;
}

xrad_status method_open(xrad_context *ctx, const xrad_scene *scene, const char *name,
                        const method_settings *settings, method_run_state *run,
                        xrad_error *err)
{
    memset(run, 0, sizeof(*run));
    run->ctx = ctx;
    run->scene = scene;
    run->name = name;
    run->settings = *settings;
    if (!strcmp(name, "reference"))
        return XRAD_OK;
    xrad_solver_desc desc = settings->solver;
    desc.method = xrad_method_from_name(name);
    return xrad_solver_create(ctx, scene, &desc, &run->solver, err);
}

xrad_status method_frame(method_run_state *run, double t, xrad_atlas *atlas,
                         method_result *result, xrad_error *err)
{
    memset(result, 0, sizeof(*result));
    double t0 = cli_now();
    xrad_status st;
    if (!run->solver) {
        xrad_reference_desc d = run->settings.reference;
        d.time = t;
        st = xrad_reference_solve(run->scene, &d, atlas, &result->ref, err);
        result->wall_ms = (cli_now() - t0) * 1e3;
    } else {
        /* The first frame solves (there is no solution to advance yet). */
        st = xrad_solver_advance(run->solver, t, err);
        result->wall_ms = (cli_now() - t0) * 1e3;
        if (!st)
            st = xrad_solver_read(run->solver, atlas, err);
        result->gpu = 1;
        xrad_solver_get_stats(run->solver, &result->stats);
    }
    if (!st)
        run->frames++;
    return st;
}

void method_close(method_run_state *run)
{
    xrad_solver_destroy(&run->solver);
    memset(run, 0, sizeof(*run));
}

xrad_status method_run(xrad_context *ctx, const xrad_scene *scene, const char *name,
                       const method_settings *settings, xrad_atlas *atlas,
                       method_result *result, xrad_error *err)
{
    method_run_state run;
    memset(result, 0, sizeof(*result));
    xrad_status st = method_open(ctx, scene, name, settings, &run, err);
    if (!st)
        st = method_frame(&run, run.solver ? settings->solver.time : settings->reference.time,
                          atlas, result, err);
    method_close(&run);
    return st;
}

int method_solver_option(cli_args *a, const char *opt, xrad_solver_desc *d)
{
    if (!strcmp(opt, "hemicube-res"))
        cli_uint(a, 8, 1024, &d->hemicube_res);
    else if (!strcmp(opt, "msaa"))
        cli_uint(a, 1, 4, &d->msaa);
    else if (!strcmp(opt, "bounces"))
        cli_uint(a, 0, 100000, &d->bounces);
    else if (!strcmp(opt, "threshold"))
        cli_double(a, 1e-12, 0.5, &d->threshold);
    else if (!strcmp(opt, "batch"))
        cli_uint(a, 1, 4096, &d->batch);
    else if (!strcmp(opt, "max-patches"))
        cli_uint(a, 1, 64, &d->max_patches);
    else if (!strcmp(opt, "seed"))
        cli_uint(a, 0, UINT32_MAX, &d->seed);
    else if (!strcmp(opt, "frame-shots"))
        cli_uint(a, 0, 10000000, &d->frame_shots);
    else if (!strcmp(opt, "cross-grid"))
        cli_uint(a, 1, 16, &d->cross_grid);
    else if (!strcmp(opt, "back-res"))
        cli_uint(a, 8, 256, &d->back_res);
    else if (!strcmp(opt, "back-msaa"))
        cli_uint(a, 1, 4, &d->back_msaa);
    else if (!strcmp(opt, "back-nearest"))
        d->back_nearest = 1;
    else if (!strcmp(opt, "cross-recompute"))
        d->cross_recompute = 1;
    else if (!strcmp(opt, "slice"))
        cli_uint(a, 0, UINT32_MAX, &d->slice_elements);
    else
        return 0;
    return 1;
}

void method_print_passes(const method_result *r)
{
    if (!r->gpu)
        return;
    const xrad_solver_stats *s = &r->stats;
    printf("gpu passes (timestamp queries, hemicube path %s):\n",
           s->hemicube_path ? s->hemicube_path : "-");
    for (uint32_t i = 0; i < s->pass_count; i++)
        printf("  %-14s %10.2f ms  (%u)\n", s->passes[i].name, s->passes[i].ms,
               s->passes[i].count);
    printf("  %-14s %10.2f ms\n", "total", s->gpu_ms);
    printf("hemicubes %u, shots %u, iterations %u, submissions %u, host waits %u, "
           "residual %.3g\n",
           s->hemicubes, s->shots, s->iterations, s->submissions, s->host_waits, s->residual);
    if (s->redistribute_ms > 0)
        printf("redistribution %.1f ms of %.1f ms (host wall time)\n", s->redistribute_ms,
               s->wall_ms);
}
