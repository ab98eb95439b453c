/*
 * Luminaires (issue 18.3, scene_luminaire.h) against closed forms:
 *
 *  - an isotropic point light of I W/sr h m above a plane of albedo rho,
 *    alone (the plane sees nothing, so nothing bounces): every element's
 *    radiosity is rho I cos(theta) / d^2 at its sample point (cos(theta)
 *    = h / d), within 1%, in the CPU reference and in every method;
 *  - the shipped asymmetric EULUMDAT and IES files (tools/gen_photometry.py:
 *    I = I0 cos(g) (1 + 0.5 cos C + 0.3 sin C) cd below the horizon, I0 =
 *    1000 / pi), aimed down with `up` +x: C0 towards +x, C90 towards -z
 *    (counterclockwise seen from above), radiometric at 683 lm/W: the
 *    reference's plane within 2% of rho I(C, g) / 683 cos(theta) / d^2
 *    (the file's table is bilinear in 15-degree C-planes);
 *  - a spot of cone 30 degrees without falloff: the plane lit within the
 *    cone's circle as the point light, dark outside it;
 *  - a 1 x 1 m square between the light and the plane: the elements whose
 *    segment to the light crosses it well inside are dark (0), the rest
 *    as the point light (the square's back faces the plane and emits
 *    nothing);
 *  - a room lit by a point light alone: every method against the CPU
 *    reference, surface_error <= 5% and element p95 <= 8% (the light the
 *    walls reflect bounces on as any other);
 *  - the room with a box sliding between the light and the floor:
 *    incremental and cross, frame by frame, against the reference at the
 *    last frame's pose, as above (moving_box);
 *  - a scene file's "luminaires", and its errors naming the field.
 *
 * `test_luminaires reference` leaves out the GPU methods.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "solvers/solver_test.h"
#include "xrad.h"

#define PI 3.14159265358979323846
#define H 1.2 /* m, the light above the plane */

typedef enum light_kind { POINT, SPOT, LDT, IES, SHADOW } light_kind;

/* A 4 x 4 m plane at y = 0 facing up, albedo 0.5, density 4; the light at
 * (0, H, 0). */
static xrad_scene *plane(light_kind kind)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *sc = NULL;
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "lit-plane", .density = 4}, &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "grey", .albedo = {0.5, 0.5, 0.5}}, &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "floor"}, &err);
    if (!st)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){.name = "plane",
                              .material = m,
                              .p = {{-2, 0, -2}, {-2, 0, 2}, {2, 0, 2}, {2, 0, -2}}},
            &err);
    if (!st && kind == SHADOW) {
        /* Facing up, 0.6 m above the plane: its back faces the plane. */
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "shade"}, &err);
        if (!st)
            st = xrad_scene_builder_add_quad(
                b,
                &(xrad_quad_desc){
                    .name = "square",
                    .material = m,
                    .p = {{0, 0.6, -0.5}, {0, 0.6, 0.5}, {1, 0.6, 0.5}, {1, 0.6, -0.5}}},
                &err);
    }
    char path[1024];
    xrad_luminaire_desc l = {.name = "lamp", .position = {0, H, 0}, .up = {1, 0, 0}};
    if (kind == LDT || kind == IES) {
        test_source_path(kind == LDT ? "tests/data/photometry/asymmetric.ldt"
                                     : "tests/data/photometry/asymmetric.ies",
                         path, sizeof(path));
        l.file = path;
    } else {
        l.intensity[0] = l.intensity[1] = l.intensity[2] = 3;
        if (kind == SPOT)
            l.cone_degrees = 30;
    }
    if (!st)
        st = xrad_scene_builder_add_luminaire(b, &l, &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    CHECK(st == XRAD_OK, "lit plane: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return sc;
}

/* What the closed form says an element at (x, 0, z) of the plane reflects. */
static double expected(light_kind kind, double x, double z)
{
    double d2 = x * x + H * H + z * z, d = sqrt(d2), ct = H / d;
    double I = 3;
    if (kind == SPOT && ct < cos(30 * PI / 180))
        I = 0;
    if (kind == LDT || kind == IES) {
        /* Straight down each C-plane has its own value (1.5, 1.3, 0.5,
         * 0.7 I0): the element there is left out. */
        if (hypot(x, z) < 1e-9)
            return -1;
        double c = atan2(-z, x); /* C90 towards -z */
        I = 1000 / PI * ct * (1 + 0.5 * cos(c) + 0.3 * sin(c)) / 683;
    }
    if (kind == SHADOW) {
        /* The segment meets y = 0.6 halfway: at (x / 2, z / 2). Inside the
         * square by a margin of an element: dark; near its edge: either. */
        double sx = x / 2, sz = z / 2, m = 0.15;
        if (sx > m && sx < 1 - m && fabs(sz) < 0.5 - m)
            I = 0;
        else if (sx > -m && sx < 1 + m && fabs(sz) < 0.5 + m)
            return -1;
    }
    return 0.5 * I * ct / d2;
}

static const char *const kind_name[] = {"point", "spot", "ldt", "ies", "shadow"};

/* Worst relative error of the plane's elements against the closed form,
 * relative to the largest expected value (1 where it is 0). */
static double worst_plane(const xrad_scene *sc, const xrad_atlas *a, light_kind kind)
{
    const surface *sf = &sc->surfaces[0];
    double top = 0, worst = 0;
    for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
        vec3 p = sc->elements[sf->first_element + k].pos;
        top = fmax(top, expected(kind, p.x, p.z));
    }
    for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
        const element *e = &sc->elements[sf->first_element + k];
        double want = expected(kind, e->pos.x, e->pos.z);
        if (want < 0)
            continue;
        const float *t = &a->rgba[4 * ((size_t)e->texel_y * a->width + e->texel_x)];
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, want > 0 ? fabs(t[c] / want - 1) : t[c] / top);
    }
    return worst;
}

/* Solves with solver_test_methods[m]'s method at its defaults. */
static xrad_status solve(xrad_context *ctx, const xrad_scene *scene, size_t m, xrad_atlas *atlas,
                         xrad_error *err)
{
    xrad_solver_desc d = {.method = solver_test_methods[m].method};
    return solver_test_solve(ctx, scene, &d, atlas, err);
}

static void closed_forms(xrad_context *ctx)
{
    for (int kind = POINT; kind <= SHADOW; kind++) {
        xrad_scene *sc = plane((light_kind)kind);
        /* Every method on the plane alone; the reference for the rest. */
        size_t count = ctx && kind == POINT ? SOLVER_TEST_METHODS : 1;
        for (size_t m = 0; sc && m < count; m++) {
            xrad_atlas a = {0};
            xrad_error err = {0};
            xrad_status st = solve(ctx, sc, m, &a, &err);
            CHECK(st == XRAD_OK, "%s light, %s: %s", kind_name[kind], solver_test_methods[m].name,
                  err.message);
            if (!st) {
                double w = worst_plane(sc, &a, (light_kind)kind);
                double tol = kind == LDT || kind == IES ? 0.02 : 0.01;
                fprintf(stderr, "%-6s light %-11s worst element %.2e off the closed form\n",
                        kind_name[kind], solver_test_methods[m].name, w);
                CHECK(w <= tol, "%s light, %s: an element %.4f off rho I cos / d^2",
                      kind_name[kind], solver_test_methods[m].name, w);
            }
            xrad_atlas_destroy(&a);
        }
        xrad_scene_destroy(&sc);
    }
}

/* A 2 x 1.5 x 2 m room of albedo 0.6 (floor, ceiling, four walls facing
 * in; density 3) lit only by a point light of 2 W/sr 0.3 m under the
 * ceiling's centre: the light it reflects bounces on. With `mover`, a
 * 0.4 m box of albedo 0.6 floats 0.4-0.8 m above the floor between the
 * light and the floor's -x half, and slides 1 m along +x over 1 s (once):
 * its shadow crosses the floor. */
static xrad_scene *room(bool mover)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *sc = NULL;
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = mover ? "luminaire-mover" : "luminaire-room",
                                   .density = 3},
        &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "wall", .albedo = {0.6, 0.6, 0.6}}, &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "room"}, &err);
    const double X = 2, Y = 1.5, Z = 2;
    const xrad_quad_desc q[6] = {
        {.name = "floor", .material = m, .p = {{0, 0, 0}, {0, 0, Z}, {X, 0, Z}, {X, 0, 0}}},
        {.name = "ceiling", .material = m, .p = {{0, Y, 0}, {X, Y, 0}, {X, Y, Z}, {0, Y, Z}}},
        {.name = "back", .material = m, .p = {{0, 0, 0}, {X, 0, 0}, {X, Y, 0}, {0, Y, 0}}},
        {.name = "front", .material = m, .p = {{0, 0, Z}, {0, Y, Z}, {X, Y, Z}, {X, 0, Z}}},
        {.name = "left", .material = m, .p = {{0, 0, 0}, {0, Y, 0}, {0, Y, Z}, {0, 0, Z}}},
        {.name = "right", .material = m, .p = {{X, 0, 0}, {X, 0, Z}, {X, Y, Z}, {X, Y, 0}}},
    };
    for (int k = 0; k < 6 && !st; k++)
        st = xrad_scene_builder_add_quad(b, &q[k], &err);
    /* The box: each face of the room scaled onto it, wound the other way
     * (facing out). */
    const xrad_keyframe slide[2] = {{.time = 0}, {.time = 1, .translate = {1, 0, 0}}};
    if (!st && mover)
        st = xrad_scene_builder_begin_object(
            b,
            &(xrad_object_desc){.name = "mover", .dynamic = 1,
                                .animation = &(xrad_animation_desc){.keyframes = slide,
                                                                    .keyframe_count = 2,
                                                                    .once = 1}},
            &err);
    const double lo[3] = {0.3, 0.4, 0.8}, size = 0.4, span[3] = {X, Y, Z};
    for (int k = 0; mover && k < 6 && !st; k++) {
        xrad_quad_desc f = {.name = q[k].name, .material = m};
        for (int i = 0; i < 4; i++)
            for (int c = 0; c < 3; c++)
                f.p[i][c] = lo[c] + q[k].p[(4 - i) % 4][c] / span[c] * size;
        st = xrad_scene_builder_add_quad(b, &f, &err);
    }
    if (!st)
        st = xrad_scene_builder_add_luminaire(b,
                                              &(xrad_luminaire_desc){.name = "bulb",
                                                                     .intensity = {2, 2, 2},
                                                                     .position = {1, Y - 0.3, 1}},
                                              &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    CHECK(st == XRAD_OK, "%s: %s", mover ? "luminaire room with a box" : "luminaire room",
          err.message);
    xrad_scene_builder_destroy(&b);
    return sc;
}

static void lit_room(xrad_context *ctx)
{
    xrad_error err = {0};
    xrad_scene *sc = room(false);
    xrad_status st = sc ? XRAD_OK : XRAD_ERROR_INPUT;
    xrad_atlas ref = {0};
    if (!st)
        st = solve(ctx, sc, 0, &ref, &err);
    CHECK(st == XRAD_OK, "luminaire room, reference: %s", err.message);
    for (size_t k = 1; !st && k < SOLVER_TEST_METHODS; k++) {
        xrad_atlas a = {0};
        st = solve(ctx, sc, k, &a, &err);
        CHECK(st == XRAD_OK, "luminaire room, %s: %s", solver_test_methods[k].name, err.message);
        xrad_element_metrics em;
        if (!st && !(st = xrad_atlas_compare(sc, &a, &ref, &em, NULL, &err))) {
            fprintf(stderr, "luminaire room %-11s surface_error %.4f p95 %.4f\n",
                    solver_test_methods[k].name, em.surface_error, em.p95);
            CHECK(em.surface_error <= 0.05 && em.p95 <= 0.08,
                  "luminaire room, %s: surface_error %.4f, element p95 %.4f",
                  solver_test_methods[k].name, em.surface_error, em.p95);
        }
        xrad_atlas_destroy(&a);
    }
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&sc);
}

/* The room with the box sliding under the light: incremental and cross
 * follow the luminaire's light frame by frame (the box's shadow crosses
 * the floor, its top and sides are lit as it goes). Solved at t = 0, 10
 * frames of 0.1 s to t = 1, then each method within surface_error 3.5% and
 * element p95 8% of the CPU reference at t = 1 (the static room: 5%):
 *  - incremental, at once (0.026; its box takes back its own light on C
 *    reflected once and twice, incremental_reconstruct.comp c_light: with
 *    once alone 0.045, its bottom at 0.955);
 *  - cross at its defaults (cross_regather after: M gathers after each
 *    frame's progressive iterations), at once;
 *  - cross with cross_regather off after one more frame at t = 1 (the box
 *    has stopped): a frame gathers M's light before its progressive
 *    iterations, so on the last moving frame the box's bottom showed the
 *    floor as the frame before left it (0.847 of the reference; with an
 *    area light of the same intensity in the luminaire's place, 0.77);
 *  - cross with cross_regather on, at once (M gathers again after them). */
static void moving_box(xrad_context *ctx)
{
    xrad_error err = {0};
    xrad_scene *sc = room(true);
    xrad_atlas ref[2] = {{0}, {0}};
    xrad_status st = sc ? XRAD_OK : XRAD_ERROR_INPUT;
    for (int k = 0; k < 2 && !st; k++) {
        if (!(st = xrad_atlas_create(sc, &ref[k], &err)))
            st = xrad_reference_solve(sc, &(xrad_reference_desc){.threads = 2, .time = k},
                                      &ref[k], NULL, &err);
        CHECK(st == XRAD_OK, "moving box, reference at t = %d: %s", k, err.message);
    }
    /* The pose matters: the two references differ where the shadow was
     * and went (else following it would prove nothing). */
    xrad_element_metrics em;
    if (!st && !(st = xrad_atlas_compare(sc, &ref[0], &ref[1], &em, NULL, &err))) {
        fprintf(stderr, "moving box: the reference at t = 0 against t = 1: surface_error %.4f\n",
                em.surface_error);
        CHECK(em.surface_error > 0.2, "moving box: t = 0 and t = 1 differ by surface_error %.4f",
              em.surface_error);
    }
    static const struct {
        const char *name;
        xrad_method method;
        uint32_t regather;
        int still; /* frames at t = 1 after the 10 */
    } runs[] = {
        {"incremental", XRAD_METHOD_INCREMENTAL, 0, 0},
        {"cross", XRAD_METHOD_CROSS, 0, 0},
        {"cross off", XRAD_METHOD_CROSS, XRAD_CROSS_REGATHER_OFF, 1},
        {"cross regather", XRAD_METHOD_CROSS, XRAD_CROSS_REGATHER_ON, 0},
    };
    for (size_t r = 0; !st && r < sizeof(runs) / sizeof(runs[0]); r++) {
        xrad_solver *s = NULL;
        xrad_atlas a = {0};
        st = xrad_solver_create(
            ctx, sc,
            &(xrad_solver_desc){.method = runs[r].method, .cross_regather = runs[r].regather}, &s,
            &err);
        if (!st)
            st = xrad_solver_solve(s, &err);
        for (int f = 1; f <= 10 + runs[r].still && !st; f++)
            st = xrad_solver_advance(s, fmin(1.0, 0.1 * f), &err);
        if (!st && !(st = xrad_atlas_create(sc, &a, &err)))
            st = xrad_solver_read(s, &a, &err);
        CHECK(st == XRAD_OK, "moving box, %s: %s", runs[r].name, err.message);
        if (!st && !(st = xrad_atlas_compare(sc, &a, &ref[1], &em, NULL, &err))) {
            fprintf(stderr,
                    "moving box %-14s at t = 1: surface_error %.4f (surface %u) p95 %.4f\n",
                    runs[r].name, em.surface_error, em.worst_surface, em.p95);
            CHECK(em.surface_error <= 0.035 && em.p95 <= 0.08,
                  "moving box, %s at t = 1: surface_error %.4f (surface %u), element p95 %.4f",
                  runs[r].name, em.surface_error, em.worst_surface, em.p95);
        }
        xrad_atlas_destroy(&a);
        xrad_solver_destroy(&s);
    }
    for (int k = 0; k < 2; k++)
        xrad_atlas_destroy(&ref[k]);
    xrad_scene_destroy(&sc);
}

static void scene_files(void)
{
    static const char good[] =
        "{\"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],\n"
        " \"objects\": [{\"name\": \"floor\", \"surfaces\": [{\"name\": \"plane\", \"material\":"
        " \"grey\", \"quad\": {\"origin\": [-2, 0, 2], \"u\": [4, 0, 0], \"v\": [0, 0, -4]}}]},"
        " {\"name\": \"box\", \"dynamic\": true, \"surfaces\": [{\"name\": \"top\", \"material\":"
        " \"grey\", \"quad\": {\"origin\": [0, 0.3, 0.2], \"u\": [0.2, 0, 0], \"v\": [0, 0, "
        "-0.2]}}]}],\n"
        " \"luminaires\": [{\"name\": \"lamp\", \"position\": [0, 1.2, 0], \"intensity\": [3, 3, "
        "3],"
        " \"cone\": 60, \"falloff\": 10}]}";
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(good, sizeof(good) - 1, "lamp.json", &sc, &err);
    CHECK(st == XRAD_OK && sc->luminaire_count == 1, "lamp.json: %s",
          st ? err.message : "no luminaire");
    for (int w = 0; !st && w < (int)xrad_scene_warning_count(sc); w++)
        CHECK(!strstr(xrad_scene_warning(sc, (uint32_t)w), "emits"), "lit by a luminaire, yet: %s",
              xrad_scene_warning(sc, (uint32_t)w));
    xrad_scene_destroy(&sc);
    static const struct {
        const char *lum, *want;
    } bad[] = {
        {"{\"name\": \"l\", \"position\": [0, 1, 0]}", "luminaire 'l': field 'file': missing"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"intensity\": [-1, 0, 0]}",
         "luminaire 'l': field 'intensity'"},
        {"{\"name\": \"l\", \"intensity\": [1, 1, 1]}", "luminaire 'l': field 'position': missing"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"intensity\": [1, 1, 1], \"cone\": 200}",
         "luminaire 'l': field 'cone'"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"intensity\": [1, 1, 1], \"cone\": 20, "
         "\"falloff\": 30}",
         "luminaire 'l': field 'falloff'"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"intensity\": [1, 1, 1], \"aim\": [0, 1, "
         "0], \"up\": [0, 2, 0]}",
         "luminaire 'l': field 'up'"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"file\": \"missing.ldt\"}",
         "luminaire 'l': field 'file'"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"file\": \"x.ldt\", \"intensity\": [1, "
         "1, 1]}",
         "luminaire 'l': field 'intensity'"},
        {"{\"name\": \"l\", \"position\": [0, 1, 0], \"intensity\": [1, 1, 1], \"colour\": 1}",
         "colour"},
    };
    for (size_t k = 0; k < sizeof(bad) / sizeof(bad[0]); k++) {
        char json[1024];
        snprintf(json, sizeof(json),
                 "{\"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],\n"
                 " \"objects\": [{\"name\": \"floor\", \"surfaces\": [{\"name\": \"plane\", "
                 "\"material\": \"grey\", \"quad\": {\"origin\": [0, 0, 0], \"u\": [1, 0, 0], "
                 "\"v\": [0, 0, -1]}}]}],\n \"luminaires\": [%s]}",
                 bad[k].lum);
        st = xrad_scene_parse(json, strlen(json), "bad.json", &sc, &err);
        CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "bad.json") &&
                  strstr(err.message, bad[k].want),
              "luminaire %zu: status %d, '%s' not in '%s'", k, st, bad[k].want, err.message);
        xrad_scene_destroy(&sc);
    }
}

int main(int argc, char **argv)
{
    bool reference_only = argc > 1 && !strcmp(argv[1], "reference");
    if (argc > 1 && !reference_only) {
        fprintf(stderr, "usage: test_luminaires [reference]\n");
        return 2;
    }
    xrad_context *ctx = reference_only ? NULL : gpu_test_context();
    if (!reference_only && !ctx)
        return test_finish();
    closed_forms(ctx);
    if (ctx) {
        lit_room(ctx);
        moving_box(ctx);
    }
    scene_files();
    if (ctx)
        gpu_test_end(&ctx);
    return test_finish();
}
