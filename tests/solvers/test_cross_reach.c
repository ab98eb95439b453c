/* Cross draws a light's hemicube with M only where M can reach it (issue
 * 16.3; src/solvers/cross.c light_reach): a one-sided panel light facing
 * down in the middle of a room, a ceiling light, and a box that rises from
 * below the panel to above it. Once the box's bounds lie wholly behind the
 * panel's plane, the panel's light patches are not drawn (fewer hemicubes
 * a frame than with every light drawn, by the panel's patches, and as many
 * while the box is below it), and the solution is that of a solver that
 * draws and reads every light at every pose (cross_draw_every_light), to
 * 1e-5 of the largest radiosity, at each frame: the box behind the plane
 * neither takes the panel's light nor hides any of it. */
#include "gpu/gpu_test.h"
#include "solver_test.h"
#include "scene/scene.h"
#include "solvers/cross.h"
#include "solvers/solver.h"

static const char *scene_json =
    "{\"unit\": \"m\", \"density\": 8,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"red\", \"albedo\": [0.7, 0.2, 0.2]},"
    "   {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [10, 10, 10]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"walls\", \"material\": \"white\", \"box\": {\"origin\": [0, 0, 0],"
    "     \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1]}, \"inward\": true},"
    "   {\"name\": \"ceiling_light\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.1, 0.99, 0.1],"
    "     \"u\": [0.15, 0, 0], \"v\": [0, 0, 0.15]}},"
    "   {\"name\": \"panel\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.55, 0.5, 0.3],"
    "     \"u\": [0.3, 0, 0], \"v\": [0, 0, 0.4]}}]},"
    "  {\"name\": \"box\", \"dynamic\": true, \"cross_density\": 4, \"surfaces\": ["
    "   {\"name\": \"b\", \"material\": \"red\", \"box\": {\"origin\": [0.15, 0.15, 0.4],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0.2, 0], \"w\": [0, 0, 0.2]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
    "     {\"time\": 1, \"translate\": [0, 0.55, 0]}], \"loop\": false}}],"
    " \"camera\": {\"position\": [0.5, 0.5, 0.02], \"look_at\": [0.5, 0.5, 1],"
    "   \"fov_degrees\": 70, \"width\": 32, \"height\": 32}}";

static xrad_solver *make(xrad_context *ctx, const xrad_scene *scene, bool every,
                         xrad_error *err)
{
    xrad_solver_desc d = {.method = XRAD_METHOD_CROSS, .hemicube_res = 32, .msaa = 1};
    xrad_solver *s = NULL;
    if (xrad_solver_create(ctx, scene, &d, &s, err))
        return NULL;
    if (every)
        cross_draw_every_light(s);
    if (xrad_solver_solve(s, err))
        xrad_solver_destroy(&s);
    return s;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_parse(scene_json, strlen(scene_json), "cross_reach.json", &scene, &err) ==
              XRAD_OK,
          "%s", err.message);
    if (!ctx || !scene)
        return test_finish();
    xrad_solver *cut = make(ctx, scene, false, &err);
    CHECK(cut, "cross: %s", err.message);
    xrad_solver *every = make(ctx, scene, true, &err);
    CHECK(every, "cross, every light drawn: %s", err.message);
    xrad_atlas a = {0}, b = {0};
    CHECK(xrad_atlas_create(scene, &a, &err) == XRAD_OK &&
              xrad_atlas_create(scene, &b, &err) == XRAD_OK,
          "%s", err.message);
    /* The box's top is at 0.35 + 0.55 t: below the panel (0.5) to t = 0.27,
     * its bottom (0.15 + 0.55 t) above it from t = 0.64. */
    const double times[] = {0.1, 0.5, 0.8, 1.0};
    uint32_t fewer = 0;
    for (int f = 0; cut && every && f < 4; f++) {
        double t = times[f];
        CHECK(xrad_solver_advance(cut, t, &err) == XRAD_OK, "%s", err.message);
        CHECK(xrad_solver_advance(every, t, &err) == XRAD_OK, "%s", err.message);
        xrad_solver_stats sc, se;
        xrad_solver_get_stats(cut, &sc);
        xrad_solver_get_stats(every, &se);
        CHECK(xrad_solver_read(cut, &a, &err) == XRAD_OK &&
                  xrad_solver_read(every, &b, &err) == XRAD_OK,
              "%s", err.message);
        double d = solver_test_atlas_diff(&a, &b);
        printf("t = %.2f: %llu hemicubes a frame, %llu with every light drawn (%u light "
               "patches); largest difference %.2e of the largest value\n",
               t, (unsigned long long)sc.hemicubes, (unsigned long long)se.hemicubes,
               se.cross_light_patches, d);
        CHECK(d < 1e-5, "t = %.2f: the solutions differ by %.2e of the largest value", t, d);
        if (t < 0.27)
            CHECK(sc.hemicubes == se.hemicubes,
                  "t = %.2f: box below the panel, yet %llu hemicubes against %llu", t,
                  (unsigned long long)sc.hemicubes, (unsigned long long)se.hemicubes);
        if (t > 0.64) {
            CHECK(sc.hemicubes < se.hemicubes,
                  "t = %.2f: box above the panel, yet %llu hemicubes against %llu", t,
                  (unsigned long long)sc.hemicubes, (unsigned long long)se.hemicubes);
            fewer++;
        }
    }
    CHECK(fewer == 2, "%u frames with the box above the panel checked", fewer);
    /* The progressive shots cross runs solve C alone: their ID hemicubes
     * draw the static quads (6 indices each) and not the box, on the host's
     * count (the multiview path's) as on the select pass's (the layered
     * path's). Drawn with M on the multiview path, M shadowed C twice and
     * the box's faces came out at 0.27-0.78 of the CPU reference. */
    uint32_t static_quads = 0, host = 0, command = 0;
    for (uint32_t k = 0; k < scene->surface_count; k++)
        static_quads += !scene->objects[scene->surfaces[k].object].dynamic;
    if (cut) {
        cross_shot_draw_counts(cut, &host, &command);
        printf("shots' ID hemicubes: %u indices on the host's count, %u in the indirect "
               "command, %u static quads\n", host, command, static_quads);
        CHECK(host == 6 * static_quads && command == 6 * static_quads,
              "the shots draw %u (host) and %u (command) indices, want %u: C alone", host,
              command, 6 * static_quads);
    }
    xrad_atlas_destroy(&a);
    xrad_atlas_destroy(&b);
    xrad_solver_destroy(&cut);
    xrad_solver_destroy(&every);
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
