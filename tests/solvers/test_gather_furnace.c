/*
 * Gather solver in the furnace (ground-truth.md): inside a closed box of
 * albedo rho emitting E everywhere, Jacobi bounce k gives exactly
 * B_k = E (1 + rho + ... + rho^k) = E (1 - rho^(k+1)) / (1 - rho), since
 * the direct light of every element is E (the box's form factors sum to
 * 1) and every hemicube sees the box's uniform B_(k-1) - E over a delta
 * form factor table that sums to 1; converged, B = E / (1 - rho). With
 * rho = 0.9, E = 1:
 *  - bounces = 5: every element 4.68559 within 1e-3, 5 bounces, 4 x
 *    elements hemicubes (the first bounce is the direct pass's);
 *  - to convergence (threshold 1e-4): bounce K adds power rho^K x the
 *    emitted and the bounces after it rho^K rho / (1 - rho), below 1e-4
 *    from K = 109 on (sooner where fp16 rounding stops the change first);
 *    the geometric rest then added makes every element 10 within 1e-3,
 *    the residual below the threshold.
 * A zero-emission scene stops after one bounce with B = 0.
 */
#include <stdio.h>
#include <string.h>

#include "gpu/gpu_test.h"
#include "harness.h"
#include "xrad.h"

static const char *box_json =
    "{\"unit\":\"m\",\"density\":6,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.9,0.9,0.9],\"emission\":[%g,%g,%g]}],"
    "\"objects\":[{\"name\":\"box\",\"surfaces\":[{\"name\":\"b\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1.5,0],\"w\":[0,0,0.7]},"
    "\"inward\":true}]}]}";

/* Solves and returns the worst relative deviation from `want` (every
 * element texel, every channel); -1 on failure. */
static double solve_box(xrad_context *ctx, double e, uint32_t bounces, double want,
                        xrad_solver_stats *stats)
{
    char json[1024];
    snprintf(json, sizeof json, box_json, e, e, e);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "furnace.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return -1;
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    xrad_atlas atlas = {0};
    xrad_solver *solver = NULL;
    xrad_solver_desc desc = {
        .method = XRAD_METHOD_GATHER, .hemicube_res = 16, .msaa = 1, .bounces = bounces};
    double worst = -1;
    if ((st = xrad_atlas_create(scene, &atlas, &err)) ||
        (st = xrad_solver_create(ctx, scene, &desc, &solver, &err)) ||
        (st = xrad_solver_solve(solver, &err)) || (st = xrad_solver_read(solver, &atlas, &err))) {
        CHECK(0, "furnace: %s", err.message);
    } else {
        xrad_solver_get_stats(solver, stats);
        worst = 0;
        uint32_t texels = 0;
        for (uint32_t k = 0; k < atlas.width * atlas.height; k++) {
            const float *px = atlas.rgba + 4 * (size_t)k;
            if (px[3] == 0)
                continue;
            texels++;
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, want > 0 ? fabs(px[c] - want) / want : fabs(px[c]));
        }
        CHECK(texels == info.elements, "%u texels for %u elements", texels, info.elements);
        CHECK(stats->hemicubes == (stats->iterations - 1) * info.elements,
              "%u hemicubes for %u bounces of %u elements", stats->hemicubes, stats->iterations,
              info.elements);
        fprintf(stderr,
                "furnace E %g, bounces %u (asked %u), %u elements: worst relative error %.3g "
                "(want %g), residual %.3g, GPU %.0f ms, wall %.0f ms\n",
                e, stats->iterations, bounces, info.elements, worst, want, stats->residual,
                stats->gpu_ms, stats->wall_ms);
    }
    xrad_solver_destroy(&solver);
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
    return worst;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    xrad_solver_stats st;
    double w = solve_box(ctx, 1, 5, (1 - pow(0.9, 6)) / (1 - 0.9), &st);
    CHECK(w >= 0 && w < 1e-3, "5 bounces: worst relative error %g", w);
    CHECK(st.iterations == 5, "%u bounces, asked 5", st.iterations);

    w = solve_box(ctx, 1, 0, 10, &st);
    CHECK(w >= 0 && w < 1e-3, "converged: worst relative error %g", w);
    CHECK(st.residual < 1e-4, "residual %g", st.residual);
    /* 109 in exact arithmetic; the hemicubes hold B - E in fp16, whose
     * rounding ends the changes' decay sooner once rho^K drops under its
     * step (measured: 105). */
    CHECK(st.iterations >= 60 && st.iterations <= 109, "%u bounces, at most 109 expected",
          st.iterations);

    w = solve_box(ctx, 0, 0, 0, &st);
    CHECK(w == 0, "dark box: largest B %g", w);
    CHECK(st.iterations == 1, "dark box: %u bounces", st.iterations);
    gpu_test_end(&ctx);
    return test_finish();
}
