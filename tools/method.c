#include "method.h"

#include <stdio.h>
#include <string.h>

#include "cli.h"

const char *method_list(void) { return "reference, gather, progressive"; }

int method_known(const char *name)
{
    return !strcmp(name, "reference") || xrad_method_from_name(name) != 0;
}

xrad_status method_run(xrad_context *ctx, const xrad_scene *scene, const char *name,
                       const method_settings *settings, xrad_atlas *atlas,
                       method_result *result, xrad_error *err)
{
    memset(result, 0, sizeof(*result));
    double t0 = cli_now();
    if (!strcmp(name, "reference")) {
        xrad_status st = xrad_reference_solve(scene, &settings->reference, atlas, &result->ref, err);
        result->wall_ms = (cli_now() - t0) * 1e3;
        return st;
    }
    xrad_solver_desc desc = settings->solver;
    desc.method = xrad_method_from_name(name);
    xrad_solver *solver = NULL;
    xrad_status st = xrad_solver_create(ctx, scene, &desc, &solver, err);
    if (st)
        return st;
    t0 = cli_now();
    st = xrad_solver_solve(solver, err);
    result->wall_ms = (cli_now() - t0) * 1e3;
    if (!st)
        st = xrad_solver_read(solver, atlas, err);
    result->gpu = 1;
    xrad_solver_get_stats(solver, &result->stats);
    xrad_solver_destroy(&solver);
    return st;
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
}
