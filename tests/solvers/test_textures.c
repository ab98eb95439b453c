/*
 * Albedo maps in the solve (issue 18.1, scene_texture.h), against truths
 * the code under test does not give:
 *
 *  - element albedos (host): on a quad mapped with a two-colour texture,
 *    elements wholly on one colour take it (x the material's albedo),
 *    the element across the seam the mean of the two, and the area-
 *    weighted mean of a surface's elements is the texture's mean over it:
 *    (c1 + c2) / 2 for a quad, 1/2 c00 + 1/4 c10 + 1/4 c01 for a triangle
 *    mapped onto the lower-left half of a 2 x 2 texture (the texels'
 *    shares of its area); the same through a mesh whose triangle pair
 *    joins into one quad. A pair whose coordinates are not one affine map
 *    stays two triangles. Bad maps and coordinates are errors that name
 *    the field.
 *  - a room whose walls carry a constant texture c x albedo a solves as
 *    the same room with albedo a c, in the CPU reference and every GPU
 *    method (within fp32 rounding): the element albedo reaches every
 *    pass that reflects.
 *  - a room with a two-colour floor: with black walls, the CPU
 *    reference's floor elements, mirror images across the seam under the
 *    light, differ by the ratio of their albedos (their irradiance, the
 *    light's alone, is the same by symmetry); with grey walls, every GPU
 *    method against the CPU reference of the same scene, surface_error
 *    <= 5% (as the triangle room of test_triangles) and element p95 <= 8%.
 *
 * Suite 'scene' runs the host part (`albedo`, also under the sanitizers),
 * suite 'accuracy' the solves (`constant two-colour`, about 20 s idle).
 *
 * `test_textures albedo|constant|two-colour` runs one part, `solves` the
 * last two.
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "solvers/solver_test.h"
#include "xrad.h"

static const float c1[3] = {0.2f, 0.4f, 0.6f}, c2[3] = {0.8f, 0.6f, 0.25f};

/* A w x h texture of colour a, with the texels where right(x, y) colour b. */
static void two_colour(float *rgb, uint32_t w, uint32_t h, int split_x, const float a[3],
                       const float b[3])
{
    for (uint32_t y = 0; y < h; y++)
        for (uint32_t x = 0; x < w; x++)
            memcpy(&rgb[3 * (y * w + x)], (split_x ? x >= w / 2 : (x + y) & 1) ? b : a,
                   3 * sizeof(float));
}

/* Area-weighted mean albedo of surface si's elements. */
static vec3 surface_mean(const xrad_scene *sc, uint32_t si)
{
    const surface *sf = &sc->surfaces[si];
    vec3 sum = v3(0, 0, 0);
    double area = 0;
    for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
        uint32_t e = sf->first_element + k;
        sum = v3_mad(sum, scene_element_albedo(sc, e), sc->elements[e].area);
        area += sc->elements[e].area;
    }
    return v3_scale(sum, 1.0 / area);
}

static double off(vec3 got, const double want[3])
{
    return fmax(fabs(got.x - want[0]), fmax(fabs(got.y - want[1]), fabs(got.z - want[2])));
}

typedef struct mapped_scene {
    const xrad_image_desc *map; /* NULL: the material plain */
    double albedo;
    const float *uvs; /* mesh, 4 vertices */
    const float *pos;
    const uint32_t *idx;
    uint32_t triangles;
    int keep_triangles;
} mapped_scene;

/* One object: a 1 x 1 m quad (no mesh) or the mesh, material `albedo`
 * (grey) with the map; density 4 per m. */
static xrad_status build_mapped(const mapped_scene *d, xrad_scene **out, xrad_error *err)
{
    xrad_scene_builder *b = NULL;
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "mapped", .density = 4}, &b, err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){
                .name = "paint", .albedo = {d->albedo, d->albedo, d->albedo}, .albedo_map = d->map},
            &m, err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "lamp", .emission = {1, 1, 1}}, NULL, err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "o"}, err);
    if (!st && !d->pos)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){
                .name = "q", .material = m, .p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
            err);
    if (!st && d->pos)
        st = xrad_scene_builder_add_mesh(b,
                                         &(xrad_mesh_desc){.name = "mesh",
                                                           .positions = d->pos,
                                                           .vertex_count = 4,
                                                           .indices = d->idx,
                                                           .triangle_count = d->triangles,
                                                           .material = m,
                                                           .keep_triangles = d->keep_triangles,
                                                           .uvs = d->uvs},
                                         err);
    if (!st)
        st = xrad_scene_builder_finish(b, out, err);
    xrad_scene_builder_destroy(&b);
    return st;
}

static void albedo_part(void)
{
    xrad_error err = {0};
    float tex[3 * 2 * 2];
    two_colour(tex, 2, 1, 1, c1, c2);
    xrad_image_desc halves = {2, 1, tex};
    xrad_scene *sc = NULL;
    xrad_status st = build_mapped(&(mapped_scene){.map = &halves, .albedo = 0.9}, &sc, &err);
    CHECK(st == XRAD_OK, "mapped quad: %s", err.message);
    if (!st) {
        const surface *sf = &sc->surfaces[0];
        CHECK(sc->element_albedo && sf->nu == 5, "quad: %u samples along u, want 5", sf->nu);
        double worst = 0;
        for (uint32_t j = 0; sc->element_albedo && j < sf->nv; j++)
            for (uint32_t i = 0; i < sf->nu; i += 2) {
                /* Cells [0, 1/8] [1/8, 3/8] | [3/8, 5/8] | ...: the middle one
                 * straddles the seam at u = 1/2 evenly. */
                double want[3];
                for (int c = 0; c < 3; c++)
                    want[c] = 0.9 * (i < 2 ? c1[c] : i > 2 ? c2[c] : 0.5 * (c1[c] + c2[c]));
                worst = fmax(
                    worst, off(scene_element_albedo(sc, sf->first_element + j * sf->nu + i), want));
            }
        fprintf(stderr, "quad, two halves: worst element %.2e off its colour\n", worst);
        CHECK(worst <= 1e-6, "quad: an element %.2e off the colour under it", worst);
        double mean[3];
        for (int c = 0; c < 3; c++)
            mean[c] = 0.9 * 0.5 * (c1[c] + c2[c]);
        double o = off(surface_mean(sc, 0), mean);
        CHECK(o <= 1e-6, "quad: area mean %.2e off the texture's", o);
    }
    xrad_scene_destroy(&sc);

    /* A triangle on the lower-left half of a 2 x 2 texture: row 0 (top,
     * v = 1) holds c01 (x 0) and c11, row 1 c00 and c10. */
    static const float cols[4][3] = {{0.1f, 0.2f, 0.3f},  /* c01 */
                                     {0.9f, 0.9f, 0.9f},  /* c11: outside the triangle */
                                     {0.7f, 0.5f, 0.3f},  /* c00 */
                                     {0.3f, 0.8f, 0.6f}}; /* c10 */
    memcpy(tex, cols, sizeof(cols));
    xrad_image_desc quarters = {2, 2, tex};
    static const float pos[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const float uv_tri[8] = {0, 0, 1, 0, 1, 1, 0, 1};
    static const uint32_t one[3] = {0, 1, 3};
    st = build_mapped(&(mapped_scene){.map = &quarters,
                                      .albedo = 0.5,
                                      .uvs = uv_tri,
                                      .pos = pos,
                                      .idx = one,
                                      .triangles = 1,
                                      .keep_triangles = 1},
                      &sc, &err);
    CHECK(st == XRAD_OK, "mapped triangle: %s", err.message);
    if (!st) {
        double want[3];
        for (int c = 0; c < 3; c++)
            want[c] = 0.5 * (0.5 * cols[2][c] + 0.25 * cols[3][c] + 0.25 * cols[0][c]);
        double o = off(surface_mean(sc, 0), want);
        fprintf(stderr, "triangle on three texels: area mean %.2e off their shares (%u elements)\n",
                o, sc->element_count);
        CHECK(sc->surfaces[0].triangle && o <= 0.01 * fmax(want[0], fmax(want[1], want[2])),
              "triangle: area mean %.4f off the texels' shares of it", o);
    }
    xrad_scene_destroy(&sc);

    /* Two triangles of the square, one affine map (the identity): one
     * quad, and its mean is the checkerboard's. */
    float checker[3 * 8 * 8];
    two_colour(checker, 8, 8, 0, c1, c2);
    xrad_image_desc board = {8, 8, checker};
    static const uint32_t pair[6] = {0, 1, 2, 0, 2, 3};
    st = build_mapped(
        &(mapped_scene){
            .map = &board, .albedo = 0.5, .uvs = uv_tri, .pos = pos, .idx = pair, .triangles = 2},
        &sc, &err);
    CHECK(st == XRAD_OK, "mapped pair: %s", err.message);
    if (!st) {
        double want[3];
        for (int c = 0; c < 3; c++)
            want[c] = 0.5 * 0.5 * (c1[c] + c2[c]);
        double o = off(surface_mean(sc, 0), want);
        fprintf(stderr, "pair on a checkerboard: %u surface(s), area mean %.2e off\n",
                sc->surface_count, o);
        CHECK(sc->surface_count == 1 && !sc->surfaces[0].triangle,
              "an affine-mapped pair: %u surfaces, want one quad", sc->surface_count);
        CHECK(o <= 0.01 * fmax(want[0], fmax(want[1], want[2])),
              "pair: area mean %.4f off the checkerboard's", o);
    }
    xrad_scene_destroy(&sc);
    /* The same pair, its fourth corner's coordinates moved: two maps. */
    static const float uv_bent[8] = {0, 0, 1, 0, 1, 1, 0, 0.5f};
    st = build_mapped(
        &(mapped_scene){
            .map = &board, .albedo = 0.5, .uvs = uv_bent, .pos = pos, .idx = pair, .triangles = 2},
        &sc, &err);
    CHECK(st == XRAD_OK && sc->surface_count == 2,
          "a pair of two maps: %s, %u surfaces, want 2 triangles", st ? err.message : "built",
          st ? 0 : sc->surface_count);
    xrad_scene_destroy(&sc);

    /* Errors name the field. */
    st = build_mapped(
        &(mapped_scene){.map = &board, .albedo = 0.5, .pos = pos, .idx = pair, .triangles = 2}, &sc,
        &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "uvs"),
          "a mapped mesh without uvs: %d '%s'", st, err.message);
    float nan_uv[8] = {0, 0, 1, 0, 1, 1, 0, NAN};
    st = build_mapped(
        &(mapped_scene){
            .map = &board, .albedo = 0.5, .uvs = nan_uv, .pos = pos, .idx = pair, .triangles = 2},
        &sc, &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "uvs[3]"), "a NaN coordinate: %d '%s'", st,
          err.message);
    checker[5] = 1.5f;
    st = build_mapped(&(mapped_scene){.map = &board, .albedo = 0.5}, &sc, &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "albedo_map") &&
              strstr(err.message, "'paint'"),
          "a texel above 1: %d '%s'", st, err.message);
    st = build_mapped(&(mapped_scene){.map = &(xrad_image_desc){0, 4, checker}, .albedo = 0.5}, &sc,
                      &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "albedo_map"),
          "a map 0 texels wide: %d '%s'", st, err.message);
    /* 16384 x 8192: within the side, past the count; refused before any
     * texel is read. */
    st = build_mapped(
        &(mapped_scene){.map = &(xrad_image_desc){16384, 8192, checker}, .albedo = 0.5}, &sc,
        &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "albedo_map") &&
              strstr(err.message, "16384 x 8192"),
          "a map of 128M texels: %d '%s'", st, err.message);
    xrad_scene_destroy(&sc);
}

/* A 2 x 1.5 x 2 m room: floor, ceiling and four walls facing in, a 0.5 x
 * 0.5 m light centred under the ceiling; density 3 (gather renders a
 * hemicube per element per bounce). The floor takes
 * `floor_map` x floor_albedo, the rest `wall_map` x wall_albedo. */
static xrad_scene *room(const xrad_image_desc *floor_map, double floor_albedo,
                        const xrad_image_desc *wall_map, double wall_albedo)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *sc = NULL;
    uint32_t fl = 0, wl = 0, lamp = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "textured-room", .density = 3}, &b, &err);
    double fa = floor_albedo, wa = wall_albedo;
    if (!st)
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){.name = "floor", .albedo = {fa, fa, fa}, .albedo_map = floor_map},
            &fl, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){.name = "wall", .albedo = {wa, wa, wa}, .albedo_map = wall_map},
            &wl, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "lamp", .emission = {10, 10, 10}}, &lamp, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "room"}, &err);
    const double X = 2, Y = 1.5, Z = 2;
    const xrad_quad_desc q[7] = {
        {.name = "floor", .material = fl, .p = {{0, 0, 0}, {0, 0, Z}, {X, 0, Z}, {X, 0, 0}}},
        {.name = "ceiling", .material = wl, .p = {{0, Y, 0}, {X, Y, 0}, {X, Y, Z}, {0, Y, Z}}},
        {.name = "back", .material = wl, .p = {{0, 0, 0}, {X, 0, 0}, {X, Y, 0}, {0, Y, 0}}},
        {.name = "front", .material = wl, .p = {{0, 0, Z}, {0, Y, Z}, {X, Y, Z}, {X, 0, Z}}},
        {.name = "left", .material = wl, .p = {{0, 0, 0}, {0, Y, 0}, {0, Y, Z}, {0, 0, Z}}},
        {.name = "right", .material = wl, .p = {{X, 0, 0}, {X, 0, Z}, {X, Y, Z}, {X, Y, 0}}},
        {.name = "light",
         .material = lamp,
         .p = {{0.75, Y - 0.001, 0.75},
               {1.25, Y - 0.001, 0.75},
               {1.25, Y - 0.001, 1.25},
               {0.75, Y - 0.001, 1.25}}},
    };
    for (int k = 0; k < 7 && !st; k++)
        st = xrad_scene_builder_add_quad(b, &q[k], &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    CHECK(st == XRAD_OK, "textured room: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return sc;
}

/* Solves with solver_test_methods[m]'s method (gather: `bounces`, 0 until
 * converged). */
static xrad_status solve(xrad_context *ctx, const xrad_scene *scene, size_t m, uint32_t bounces,
                         xrad_atlas *atlas, xrad_error *err)
{
    xrad_method method = solver_test_methods[m].method;
    xrad_solver_desc d = {.method = method, .bounces = method == XRAD_METHOD_GATHER ? bounces : 0};
    return solver_test_solve(ctx, scene, &d, atlas, err);
}

/* Largest |a - b| / max(b, 1e-3 max b) over element texels. */
static double worst_rel(const xrad_atlas *a, const xrad_atlas *b)
{
    double top = 0, worst = 0;
    for (size_t k = 0; k < 4 * (size_t)b->width * b->height; k++)
        top = fmax(top, b->rgba[k]);
    for (size_t k = 0; k < (size_t)a->width * a->height; k++) {
        if (b->rgba[4 * k + 3] == 0)
            continue;
        for (int c = 0; c < 3; c++)
            worst = fmax(worst, fabs(a->rgba[4 * k + c] - b->rgba[4 * k + c]) /
                                    fmax(b->rgba[4 * k + c], 1e-3 * top));
    }
    return worst;
}

static void constant_part(xrad_context *ctx)
{
    /* 0.75 and 0.8 x 0.75 = 0.6 in binary within an ulp. */
    float grey[3] = {0.75f, 0.75f, 0.75f};
    xrad_image_desc flat = {1, 1, grey};
    xrad_scene *mapped = room(&flat, 0.8, &flat, 0.8), *plain = room(NULL, 0.6, NULL, 0.6);
    for (size_t m = 0; mapped && plain && m < SOLVER_TEST_METHODS; m++) {
        xrad_atlas a = {0}, p = {0};
        xrad_error err = {0};
        /* Two bounces of gather: equal albedos give equal solutions at
         * any count, and each bounce is a hemicube per element. */
        xrad_status st = solve(ctx, mapped, m, 2, &a, &err);
        if (!st)
            st = solve(ctx, plain, m, 2, &p, &err);
        CHECK(st == XRAD_OK, "constant map, %s: %s", solver_test_methods[m].name, err.message);
        if (!st) {
            double w = worst_rel(&a, &p);
            fprintf(stderr, "constant map %-11s worst element %.2e off albedo a c\n",
                    solver_test_methods[m].name, w);
            CHECK(w <= 1e-4, "%s: a constant map 0.75 x 0.8 is %.2e off albedo 0.6",
                  solver_test_methods[m].name, w);
        }
        xrad_atlas_destroy(&a);
        xrad_atlas_destroy(&p);
    }
    xrad_scene_destroy(&mapped);
    xrad_scene_destroy(&plain);
}

static void two_colour_part(xrad_context *ctx)
{
    float tex[3 * 2];
    two_colour(tex, 2, 1, 1, c1, c2);
    xrad_image_desc halves = {2, 1, tex};
    /* Black walls first: the floor's irradiance is the light's alone,
     * the same at mirror images across the seam. */
    xrad_scene *sc = room(&halves, 0.9, NULL, 0);
    if (!sc)
        return;
    xrad_atlas ref = {0};
    xrad_error err = {0};
    xrad_status st = solve(ctx, sc, 0, 0, &ref, &err);
    CHECK(st == XRAD_OK, "two-colour floor, black walls, reference: %s", err.message);
    if (!st) {
        /* The floor is p0 (0,0,0) p1 (0,0,Z) p2 (X,0,Z): u along z, so the
         * seam (u = 1/2) is z = 1, under the light's centre; element (i, j)
         * and (nu-1-i, j) are mirror images across it. */
        const surface *sf = &sc->surfaces[0];
        double worst = 0;
        for (uint32_t j = 1; j + 1 < sf->nv; j++)
            for (uint32_t i = 1; i < sf->nu / 2; i++) {
                const element *e1 = &sc->elements[sf->first_element + j * sf->nu + i];
                const element *e2 = &sc->elements[sf->first_element + j * sf->nu + sf->nu - 1 - i];
                const float *b1 = &ref.rgba[4 * ((size_t)e1->texel_y * ref.width + e1->texel_x)];
                const float *b2 = &ref.rgba[4 * ((size_t)e2->texel_y * ref.width + e2->texel_x)];
                for (int c = 0; c < 3; c++)
                    worst = fmax(worst, fabs((b1[c] / c1[c]) / (b2[c] / c2[c]) - 1));
            }
        fprintf(stderr, "two-colour floor, reference: mirror elements' B / albedo %.2e apart\n",
                worst);
        CHECK(worst <= 0.02, "reference: mirror elements' B / albedo %.4f apart", worst);
    }
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&sc);
    /* Grey walls: light that bounces off the two colours. */
    if (st || !(sc = room(&halves, 0.9, NULL, 0.6)))
        return;
    st = solve(ctx, sc, 0, 0, &ref, &err);
    CHECK(st == XRAD_OK, "two-colour floor, reference: %s", err.message);
    for (size_t m = 1; !st && m < SOLVER_TEST_METHODS; m++) {
        xrad_atlas a = {0};
        st = solve(ctx, sc, m, 0, &a, &err);
        CHECK(st == XRAD_OK, "two-colour floor, %s: %s", solver_test_methods[m].name, err.message);
        if (!st) {
            xrad_element_metrics em;
            double ratio[7] = {0};
            st = xrad_atlas_compare(sc, &a, &ref, &em, ratio, &err);
            CHECK(st == XRAD_OK, "compare: %s", err.message);
            fprintf(stderr,
                    "two-colour floor %-11s floor %.4f of the reference's, surface_error %.4f "
                    "p95 %.4f\n",
                    solver_test_methods[m].name, ratio[0], em.surface_error, em.p95);
            /* p95 too: an albedo by surface rather than by element keeps
             * the floor's mean and puts its elements 40% off. */
            CHECK(em.surface_error <= 0.05 && em.p95 <= 0.08,
                  "two-colour floor, %s: surface_error %.4f, element p95 %.4f",
                  solver_test_methods[m].name, em.surface_error, em.p95);
        }
        xrad_atlas_destroy(&a);
    }
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&sc);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    if (only && strcmp(only, "albedo") && strcmp(only, "constant") && strcmp(only, "two-colour") &&
        strcmp(only, "solves")) {
        fprintf(stderr, "usage: test_textures [albedo|constant|two-colour|solves]\n");
        return 2;
    }
    bool solves = only && !strcmp(only, "solves");
    if (!only || !strcmp(only, "albedo"))
        albedo_part();
    if (!only || strcmp(only, "albedo")) {
        xrad_context *ctx = gpu_test_context();
        if (!ctx)
            return test_finish();
        if (!only || solves || !strcmp(only, "constant"))
            constant_part(ctx);
        if (!only || solves || !strcmp(only, "two-colour"))
            two_colour_part(ctx);
        gpu_test_end(&ctx);
    }
    return test_finish();
}
