/*
 * Furnace test of the reference solver (ground-truth.md): inside a closed
 * box whose every surface emits E and reflects rho, B = E (1 + rho + rho^2
 * + ...) = E / (1 - rho) everywhere, whatever the geometry of the box. A
 * solver that drops bounces, or form factors whose rows do not sum to 1,
 * comes out low or high. With a box floating in the room the same holds,
 * but only if occlusion is exact: rho = 0.999 turns a closure error of the
 * form factor rows into a thousand times that error in B.
 */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "reference/reference.h"
#include "xrad.h"

static const char *box_json =
    "{\"unit\":\"m\",\"density\":%g,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[%g,%g,%g],\"emission\":[%g,%g,%g]}],"
    "\"objects\":[{\"name\":\"box\"%s,\"surfaces\":[{\"name\":\"b\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1.5,0],\"w\":[0,0,0.7]},"
    "\"inward\":true}]}],"
    "\"camera\":{\"position\":[0.5,0.5,0.1],\"look_at\":[0.5,0.5,1],\"up\":[0,1,0],"
    "\"fov_degrees\":60}}";

/* Solves the box and checks every element's B against E / (1 - rho) per
 * channel, and that texels outside elements stay zero. */
static void furnace(const double rho[3], const double e[3], const char *object_extra,
                    double time, double rel)
{
    char json[2048];
    snprintf(json, sizeof json, box_json, 3.0, rho[0], rho[1], rho[2], e[0], e[1], e[2],
             object_extra);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "furnace.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return;
    xrad_atlas atlas = {0};
    st = xrad_atlas_create(scene, &atlas, &err);
    CHECK(st == XRAD_OK, "atlas: %s", err.message);
    xrad_reference_desc desc = {.time = time, .threads = 2};
    xrad_reference_stats stats = {0};
    if (!st) {
        st = xrad_reference_solve(scene, &desc, &atlas, &stats, &err);
        CHECK(st == XRAD_OK, "solve: %s", err.message);
    }
    if (!st) {
        xrad_scene_info info;
        xrad_scene_get_info(scene, &info);
        double worst = 0;
        uint32_t texels = 0;
        for (uint32_t k = 0; k < atlas.width * atlas.height; k++) {
            const float *px = atlas.rgba + 4 * (size_t)k;
            if (px[3] == 0) {
                CHECK(px[0] == 0 && px[1] == 0 && px[2] == 0, "texel %u outside elements is not zero", k);
                continue;
            }
            texels++;
            CHECK(px[3] == 1, "alpha %g", px[3]);
            for (int c = 0; c < 3; c++) {
                double want = e[c] / (1 - rho[c]);
                double d = fabs(px[c] - want) / want;
                worst = d > worst ? d : worst;
            }
        }
        CHECK(texels == info.elements, "%u element texels, want %u", texels, info.elements);
        fprintf(stderr,
                "rho (%g %g %g), %u elements, t = %g: worst relative error %.3g, %u sweeps, "
                "residual %.3g, max row sum %.9f\n",
                rho[0], rho[1], rho[2], info.elements, time, worst, stats.sweeps, stats.residual,
                stats.max_row_sum);
        CHECK(worst <= rel, "worst relative error %g > %g", worst, rel);
        CHECK(stats.residual < 1e-6, "residual %g", stats.residual);
        CHECK(fabs(stats.max_row_sum - 1) < 1e-5, "max row sum %.9f", stats.max_row_sum);
    }
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

/* A closed unit room (density 5) with a static box floating inside it,
 * everything emitting 1 and reflecting 0.999: B = 1000 everywhere. */
static const char *room_box_json =
    "{\"unit\":\"m\",\"density\":5,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.999,0.999,0.999],\"emission\":[1,1,1]}],"
    "\"objects\":[{\"name\":\"room\",\"surfaces\":[{\"name\":\"walls\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0],\"w\":[0,0,1]},\"inward\":true}]},"
    "{\"name\":\"box\",\"surfaces\":[{\"name\":\"b\",\"material\":\"m\","
    "\"box\":{\"origin\":[0.3,0.2,0.3],\"u\":[0.3,0,0],\"v\":[0,0.3,0],\"w\":[0,0,0.3]}}]}],"
    "\"camera\":{\"position\":[0.5,0.5,0.02],\"look_at\":[0.5,0.45,1],\"up\":[0,1,0],"
    "\"fov_degrees\":70}}";

/* Every row of F closes to 1 within 1e-5 with `rays` rays (the box hides
 * part of the room from most elements, so this holds only if what it hides
 * is subtracted exactly), and with 4 rays every element is within 1% of
 * 1000. */
static void furnace_with_box(uint32_t rays)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st =
        xrad_scene_parse(room_box_json, strlen(room_box_json), "room-box.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return;
    xrad_reference_desc desc = {.threads = 2, .rays = rays, .residual = 1e-8};
    float *F = NULL;
    st = ref_form_factor_matrix(scene, &desc, &F, NULL, &err);
    CHECK(st == XRAD_OK, "matrix: %s", err.message);
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    uint32_t n = info.elements;
    double worst_row = 0;
    for (uint32_t i = 0; F && i < n; i++) {
        double sum = 0;
        for (uint32_t j = 0; j < n; j++)
            sum += F[(size_t)i * n + j];
        worst_row = fmax(worst_row, fabs(sum - 1));
    }
    free(F);

    xrad_atlas atlas = {0};
    st = xrad_atlas_create(scene, &atlas, &err);
    CHECK(st == XRAD_OK, "atlas: %s", err.message);
    xrad_reference_stats stats = {0};
    if (!st) {
        st = xrad_reference_solve(scene, &desc, &atlas, &stats, &err);
        CHECK(st == XRAD_OK, "solve: %s", err.message);
    }
    double worst = 0;
    for (uint32_t k = 0; !st && k < atlas.width * atlas.height; k++) {
        const float *px = atlas.rgba + 4 * (size_t)k;
        if (px[3] != 0)
            worst = fmax(worst, fabs(px[0] - 1000.0) / 1000.0);
    }
    fprintf(stderr,
            "room with a box, rho 0.999, %u rays, %u elements: max |row sum - 1| %.3g, worst "
            "relative error %.3g, %u sweeps\n",
            rays, n, worst_row, worst, stats.sweeps);
    CHECK(worst_row < 1e-5, "%u rays: max |row sum - 1| = %.3g", rays, worst_row);
    if (rays == 4)
        CHECK(worst < 0.01, "%u rays: worst relative error %.3g", rays, worst);
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

int main(void)
{
    const double rhos[] = {0.5, 0.9, 0.99};
    for (int k = 0; k < 3; k++) {
        double rho[3] = {rhos[k], rhos[k], rhos[k]}, e[3] = {1, 1, 1};
        furnace(rho, e, "", 0, 1e-3);
    }
    /* All three at once in RGB, with a different emission per channel, on a
     * box that turns and slides (posed at t = 1.7 s): a closed box stays a
     * closed box in any pose. */
    double rho[3] = {0.5, 0.9, 0.99}, e[3] = {2, 0.5, 1e-3};
    furnace(rho, e,
            ",\"dynamic\":true,\"animation\":{\"rotate\":{\"axis\":[1,2,3],"
            "\"pivot\":[0.5,0.5,0.5],\"degrees_per_second\":40},"
            "\"keyframes\":[{\"time\":0,\"translate\":[0,0,0]},{\"time\":3,\"translate\":[2,-1,0.5]}]}",
            1.7, 1e-3);
    furnace_with_box(4);
    furnace_with_box(16);
    return test_finish();
}
