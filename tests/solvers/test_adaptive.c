/*
 * Adaptive subdivision (issue 18.5, xrad.h xrad_adaptive_desc; Wallner 4),
 * against truths the code under test does not give:
 *
 *  - layout (host, scenes/shadow-room.json: a room, a small ceiling lamp,
 *    a table whose shadow falls on the floor, nothing else shadowed): off,
 *    the layout is the plain one; with 1 level only the floor is split,
 *    each element in four (nu -> 2 nu - 1); with 2 levels the floor twice
 *    and its neighbours, the walls, once (levels within one across an
 *    edge) and the ceiling, which meets the floor nowhere, not at all;
 *    the same room without the table has no shadow and is not split; an
 *    upper bound below the floor's visible fraction leaves it whole; a
 *    floor cut in two coplanar halves with the shadow on one takes one
 *    level on both (shared edge samples: no T-vertex) and is as fine as
 *    the whole floor split; bad settings are errors naming the field.
 *  - accuracy (suite 'accuracy'): at about equal element counts, the
 *    adaptive layout (1 level) against a uniform one (the density scaled
 *    up to at least as many elements), both solved by the CPU reference
 *    and by progressive refinement, each compared with a fine CPU
 *    reference (4 x the density) per surface (surface_error, xrad.h
 *    xrad_element_metrics: the area-weighted means, which a coarse grid
 *    gets wrong where a shadow's edge crosses it) and on the floor as the
 *    display shows it (each solution interpolated bilinearly at the fine
 *    layout's receiver points, xrad.h xrad_surface_info): adaptive must
 *    be closer on both counts.
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "solvers/solver_test.h"
#include "xrad.h"

static xrad_scene *load(const char *rel, const xrad_scene_load_desc *d)
{
    char path[1024];
    xrad_error err = {0};
    xrad_scene *sc = NULL;
    test_source_path(rel, path, sizeof(path));
    CHECK(xrad_scene_load_with(path, d, &sc, &err) == XRAD_OK, "%s: %s", rel, err.message);
    return sc;
}

static uint32_t find_surface(const xrad_scene *sc, const char *name)
{
    for (uint32_t s = 0; s < sc->surface_count; s++)
        if (!strcmp(sc->surfaces[s].name, name))
            return s;
    CHECK(0, "no surface '%s'", name);
    return 0;
}

static void check_grid(const xrad_scene *plain, const xrad_scene *sc, const char *name, int splits,
                       const char *what)
{
    const surface *a = &plain->surfaces[find_surface(plain, name)];
    const surface *b = &sc->surfaces[find_surface(sc, name)];
    uint32_t nu = a->nu, nv = a->nv;
    for (int k = 0; k < splits; k++) {
        nu = 2 * nu - 1;
        nv = 2 * nv - 1;
    }
    CHECK(b->nu == nu && b->nv == nv, "%s: %s is %u x %u, want %u x %u (%d splits of %u x %u)",
          what, name, b->nu, b->nv, nu, nv, splits, a->nu, a->nv);
}

static const char *const room_surfaces[] = {"back", "front", "left", "right"};

/* The shadow room's JSON changed as `which` says: "no-table" leaves the
 * table out, "halves" cuts the floor in two coplanar parts at z = 3. */
static xrad_scene *room_variant(const char *which, uint32_t levels, xrad_error *err)
{
    char path[1024];
    test_source_path("scenes/shadow-room.json", path, sizeof(path));
    FILE *f = fopen(path, "rb");
    static char json[16384];
    size_t n = f ? fread(json, 1, sizeof(json) - 1, f) : 0;
    if (f)
        fclose(f);
    json[n] = 0;
    char out[20000];
    const char *cut = NULL, *with = NULL;
    if (!strcmp(which, "no-table")) {
        cut = strstr(json, ",\n    {\n      \"name\": \"table\"");
        const char *end = cut ? strstr(cut, "\n    }\n  ]") : NULL;
        if (!cut || !end)
            return NULL;
        snprintf(out, sizeof(out), "%.*s%s", (int)(cut - json), json, end + 6);
    } else {
        cut = strstr(json, "{\"name\": \"floor\"");
        const char *end = cut ? strstr(cut, "\n") : NULL;
        with = "{\"name\": \"floor\", \"material\": \"white\", \"quad\": {\"origin\": [0, 0, 0], "
               "\"u\": [0, 0, 3], \"v\": [4, 0, 0]}},\n        {\"name\": \"floor.b\", "
               "\"material\": \"white\", \"quad\": {\"origin\": [0, 0, 3], \"u\": [0, 0, 1], "
               "\"v\": [4, 0, 0]}},";
        if (!cut || !end)
            return NULL;
        snprintf(out, sizeof(out), "%.*s%s%s", (int)(cut - json), json, with, end);
    }
    xrad_scene *sc = NULL;
    xrad_scene_load_desc d = {.adaptive = {.levels = levels}};
    if (xrad_scene_parse_with(out, strlen(out), which, &d, &sc, err))
        return NULL;
    return sc;
}

static void layout_part(void)
{
    xrad_error err = {0};
    xrad_scene *plain = load("scenes/shadow-room.json", NULL);
    xrad_scene *one = load("scenes/shadow-room.json", &(xrad_scene_load_desc){.adaptive = {1}});
    xrad_scene *two = load("scenes/shadow-room.json", &(xrad_scene_load_desc){.adaptive = {2}});
    xrad_scene *high = load("scenes/shadow-room.json",
                            &(xrad_scene_load_desc){.adaptive = {.levels = 1, .upper = 0.5}});
    if (!plain || !one || !two || !high)
        goto done;
    xrad_scene_info in;
    xrad_scene_get_info(plain, &in);
    CHECK(in.adaptive_refined_surfaces == 0, "off: %u surfaces split",
          in.adaptive_refined_surfaces);
    xrad_scene_get_info(one, &in);
    CHECK(in.adaptive_refined_surfaces == 1 && in.adaptive_partial_surfaces == 1,
          "1 level: %u split, %u partial; want the floor alone", in.adaptive_refined_surfaces,
          in.adaptive_partial_surfaces);
    check_grid(plain, one, "floor", 1, "1 level");
    check_grid(plain, one, "ceiling", 0, "1 level");
    check_grid(plain, one, "top", 0, "1 level");
    for (int k = 0; k < 4; k++)
        check_grid(plain, one, room_surfaces[k], 0, "1 level");
    check_grid(plain, two, "floor", 2, "2 levels");
    check_grid(plain, two, "ceiling", 0, "2 levels");
    for (int k = 0; k < 4; k++)
        check_grid(plain, two, room_surfaces[k], 1, "2 levels");
    /* The floor sees the lamp from about 90% of its points: a bound of
     * 0.5 leaves it whole (Wallner's b_u: a short shadow boundary). */
    check_grid(plain, high, "floor", 0, "upper 0.5");

    xrad_scene *bare = room_variant("no-table", 2, &err);
    CHECK(bare, "no-table: %s", err.message);
    if (bare) {
        xrad_scene_get_info(bare, &in);
        CHECK(in.adaptive_refined_surfaces == 0, "no shadow, yet %u surfaces split",
              in.adaptive_refined_surfaces);
        xrad_scene_destroy(&bare);
    }
    /* The floor cut at z = 3: the table's shadow (z < 2.4) falls on the
     * first part only, the second sees the whole lamp from everywhere,
     * and takes the first's level for their shared edge along x. */
    xrad_scene *halves0 = room_variant("halves", 0, &err);
    xrad_scene *halves = halves0 ? room_variant("halves", 1, &err) : NULL;
    CHECK(halves0 && halves, "halves: %s", err.message);
    if (halves0 && halves) {
        xrad_scene_get_info(halves, &in);
        CHECK(in.adaptive_partial_surfaces == 1 && in.adaptive_refined_surfaces == 2,
              "halves: %u partial, %u split; want 1 and 2", in.adaptive_partial_surfaces,
              in.adaptive_refined_surfaces);
        check_grid(halves0, halves, "floor", 1, "halves");
        check_grid(halves0, halves, "floor.b", 1, "halves");
        const surface *a = &halves->surfaces[find_surface(halves, "floor")];
        const surface *b = &halves->surfaces[find_surface(halves, "floor.b")];
        CHECK(a->nv == b->nv, "halves: %u and %u samples along their shared edge", a->nv, b->nv);
    }
    xrad_scene_destroy(&halves0);
    xrad_scene_destroy(&halves);

    /* Bad settings name the field. */
    xrad_scene *bad = NULL;
    char path[1024];
    test_source_path("scenes/shadow-room.json", path, sizeof(path));
    CHECK(xrad_scene_load_with(path, &(xrad_scene_load_desc){.adaptive = {.levels = 5}}, &bad,
                               &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "adaptive levels") && strstr(err.message, "shadow-room.json"),
          "levels 5: %s", err.message);
    CHECK(xrad_scene_load_with(path, &(xrad_scene_load_desc){.adaptive = {.upper = 1.5}}, &bad,
                               &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "adaptive upper"),
          "upper 1.5: %s", err.message);
    const char *json =
        "{\"quality\": {\"adaptive_levels\": 7}, \"materials\": [], \"objects\": []}";
    CHECK(xrad_scene_parse(json, strlen(json), "q.json", &bad, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "adaptive_levels") && strstr(err.message, "q.json"),
          "quality.adaptive_levels 7: %s", err.message);
done:
    xrad_scene_destroy(&plain);
    xrad_scene_destroy(&one);
    xrad_scene_destroy(&two);
    xrad_scene_destroy(&high);
}

/* Area-weighted mean of R + G + B over surface s of an atlas. */
static double surface_mean(const xrad_scene *sc, const xrad_atlas *a, uint32_t s)
{
    const surface *sf = &sc->surfaces[s];
    double sum = 0, area = 0;
    for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
        const element *e = &sc->elements[sf->first_element + k];
        const float *t = &a->rgba[4 * ((size_t)e->texel_y * a->width + e->texel_x)];
        sum += e->area * ((double)t[0] + t[1] + t[2]);
        area += e->area;
    }
    return sum / area;
}

/* What the display shows of surface s at parameters (u, v): the tile's
 * bilinear interpolation (xrad.h xrad_surface_info), R + G + B. */
static double display_value(const xrad_scene *sc, const xrad_atlas *a, uint32_t s, double u,
                            double v)
{
    const surface *sf = &sc->surfaces[s];
    double x = u * (sf->nu - 1), y = v * (sf->nv - 1);
    uint32_t i = (uint32_t)fmin(floor(x), sf->nu > 1 ? sf->nu - 2 : 0);
    uint32_t j = (uint32_t)fmin(floor(y), sf->nv > 1 ? sf->nv - 2 : 0);
    double fx = sf->nu > 1 ? x - i : 0, fy = sf->nv > 1 ? y - j : 0;
    double out = 0;
    for (int c = 0; c < 4; c++) {
        uint32_t ii = i + (c & 1 && sf->nu > 1), jj = j + (c >> 1 && sf->nv > 1);
        const float *t = &a->rgba[4 * ((size_t)(sf->tile_y + jj) * a->width + sf->tile_x + ii)];
        double w = (c & 1 ? fx : 1 - fx) * (c >> 1 ? fy : 1 - fy);
        out += w * ((double)t[0] + t[1] + t[2]);
    }
    return out;
}

typedef struct errors {
    double surface_error; /* max over non-emitting surfaces, xrad_element_metrics' ratio */
    const char *worst;
    double floor_rms; /* the floor as displayed at the fine receiver points, relative RMS */
} errors;

static bool emitting(const xrad_scene *sc, uint32_t s)
{
    vec3 e = sc->materials[sc->surfaces[s].material].emission;
    return e.x > 0 || e.y > 0 || e.z > 0;
}

/* sol (on sc) against the fine reference (on fine): the same surfaces. */
static errors compare(const xrad_scene *sc, const xrad_atlas *sol, const xrad_scene *fine,
                      const xrad_atlas *ref)
{
    errors r = {0, "", 0};
    double sum = 0, area = 0;
    for (uint32_t s = 0; s < fine->surface_count; s++)
        if (!emitting(fine, s)) {
            sum += fine->surfaces[s].area * surface_mean(fine, ref, s);
            area += fine->surfaces[s].area;
        }
    double floor_b = 1e-3 * sum / area;
    for (uint32_t s = 0; s < fine->surface_count; s++) {
        if (emitting(fine, s))
            continue;
        double b = surface_mean(fine, ref, s), a = surface_mean(sc, sol, s);
        double e = fabs(a - b) / fmax(b, floor_b);
        if (e > r.surface_error) {
            r.surface_error = e;
            r.worst = fine->surfaces[s].name;
        }
    }
    uint32_t fl = find_surface(fine, "floor");
    const surface *ff = &fine->surfaces[fl];
    double d2 = 0, b2 = 0;
    for (uint32_t k = 0; k < ff->nu * ff->nv; k++) {
        const element *e = &fine->elements[ff->first_element + k];
        const float *t = &ref->rgba[4 * ((size_t)e->texel_y * ref->width + e->texel_x)];
        double u, v, b = (double)t[0] + t[1] + t[2];
        scene_cell_centre(ff, e->i, e->j, &u, &v);
        double a = display_value(sc, sol, find_surface(sc, "floor"), u, v);
        d2 += e->area * (a - b) * (a - b);
        b2 += e->area * b;
    }
    r.floor_rms = sqrt(d2 / ff->area) / (b2 / ff->area);
    return r;
}

static void solves_part(xrad_context *ctx)
{
    xrad_error err = {0};
    xrad_scene *fine = load("scenes/shadow-room.json", &(xrad_scene_load_desc){.density_scale = 4});
    xrad_scene *adapt = load("scenes/shadow-room.json", &(xrad_scene_load_desc){.adaptive = {1}});
    xrad_scene *uni = NULL;
    xrad_atlas ref = {0};
    if (!fine || !adapt)
        goto done;
    /* The uniform layout: the least density scale (steps of 1%) with at
     * least the adaptive layout's elements. */
    double scale = 1;
    for (; scale < 4; scale += 0.01) {
        uni = load("scenes/shadow-room.json", &(xrad_scene_load_desc){.density_scale = scale});
        if (!uni || uni->element_count >= adapt->element_count)
            break;
        xrad_scene_destroy(&uni);
    }
    if (!uni)
        goto done;
    fprintf(stderr, "elements: adaptive %u, uniform %u (density x %.2f), fine %u\n",
            adapt->element_count, uni->element_count, scale, fine->element_count);
    CHECK(uni->element_count <= adapt->element_count * 1.1,
          "uniform %u elements against adaptive %u: not a like-for-like count", uni->element_count,
          adapt->element_count);
    CHECK(solver_test_solve(ctx, fine, &(xrad_solver_desc){0}, &ref, &err) == XRAD_OK,
          "fine reference: %s", err.message);
    if (err.message[0])
        goto done;
    const struct {
        const char *name;
        xrad_method method;
    } methods[] = {{"reference", (xrad_method)0}, {"progressive", XRAD_METHOD_PROGRESSIVE}};
    for (size_t m = 0; m < sizeof(methods) / sizeof(methods[0]); m++) {
        xrad_atlas aa = {0}, ua = {0};
        xrad_solver_desc d = {.method = methods[m].method};
        CHECK(solver_test_solve(ctx, adapt, &d, &aa, &err) == XRAD_OK &&
                  solver_test_solve(ctx, uni, &d, &ua, &err) == XRAD_OK,
              "%s: %s", methods[m].name, err.message);
        if (aa.rgba && ua.rgba) {
            errors ea = compare(adapt, &aa, fine, &ref), eu = compare(uni, &ua, fine, &ref);
            fprintf(stderr,
                    "%-12s surface_error adaptive %.4f (%s), uniform %.4f (%s); floor as "
                    "displayed, relative RMS: adaptive %.4f, uniform %.4f\n",
                    methods[m].name, ea.surface_error, ea.worst, eu.surface_error, eu.worst,
                    ea.floor_rms, eu.floor_rms);
            CHECK(ea.surface_error < eu.surface_error,
                  "%s: adaptive surface_error %.4f is not below uniform's %.4f", methods[m].name,
                  ea.surface_error, eu.surface_error);
            CHECK(ea.floor_rms < eu.floor_rms,
                  "%s: adaptive floor error %.4f is not below uniform's %.4f", methods[m].name,
                  ea.floor_rms, eu.floor_rms);
        }
        xrad_atlas_destroy(&aa);
        xrad_atlas_destroy(&ua);
    }
done:
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&fine);
    xrad_scene_destroy(&adapt);
    xrad_scene_destroy(&uni);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    if (only && strcmp(only, "layout") && strcmp(only, "solves")) {
        fprintf(stderr, "usage: test_adaptive [layout|solves]\n");
        return 2;
    }
    if (!only || !strcmp(only, "layout"))
        layout_part();
    if (!only || !strcmp(only, "solves")) {
        xrad_context *ctx = gpu_test_context();
        if (!ctx)
            return test_finish();
        solves_part(ctx);
        gpu_test_end(&ctx);
    }
    return test_finish();
}
