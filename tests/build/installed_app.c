/*
 * A program built against the installed library alone (issue 17.5):
 * tests/build/test_install.sh installs xrad into a temporary prefix and
 * compiles this file with `pkg-config --cflags --libs xrad` and nothing of
 * the source tree. It checks what a user of the installed library relies
 * on:
 *  - the headers' version is the library's (xrad_version);
 *  - the furnace: a closed cube, every face emitting E = 1 and reflecting
 *    rho = 0.5, has B = E / (1 - rho) = 2 everywhere (energy balance), by
 *    the CPU reference and by a GPU method, on a context with the
 *    validation layer on and no message;
 *  - the public atlas layout (xrad_surface_info's tile): the surfaces'
 *    tiles cover exactly the texels that hold elements, without overlap.
 * Prints "N passed, N failed"; fails when a check fails or none ran.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <xrad.h>

static int passed, failed;

#define CHECK(cond, ...)                                                                          \
    do {                                                                                          \
        if (cond) {                                                                               \
            passed++;                                                                             \
        } else {                                                                                  \
            failed++;                                                                             \
            printf("FAIL %s:%d: ", __FILE__, __LINE__);                                           \
            printf(__VA_ARGS__);                                                                  \
            printf("\n");                                                                         \
        }                                                                                         \
    } while (0)

/* The unit cube's six faces, counter-clockwise seen from inside. */
static xrad_status build_furnace(xrad_scene **out, xrad_error *err)
{
    static const double faces[6][4][3] = {
        {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, /* floor y = 0, normal +y */
        {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}, /* ceiling y = 1, normal -y */
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, /* x = 0, normal +x */
        {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}, /* x = 1, normal -x */
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, /* z = 0, normal +z */
        {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, /* z = 1, normal -z */
    };
    xrad_scene_builder *b = NULL;
    uint32_t mat = 0;
    xrad_status st = xrad_scene_builder_create(&(xrad_scene_builder_desc){.name = "furnace",
                                                                          .density = 6},
                                               &b, err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){"glow", {0.5, 0.5, 0.5}, {1, 1, 1}}, &mat, err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "cube"}, err);
    for (int f = 0; f < 6 && !st; f++) {
        char name[8];
        snprintf(name, sizeof(name), "f%d", f);
        xrad_quad_desc q = {.name = name, .material = mat};
        memcpy(q.p, faces[f], sizeof(q.p));
        st = xrad_scene_builder_add_quad(b, &q, err);
    }
    if (!st)
        st = xrad_scene_builder_finish(b, out, err);
    xrad_scene_builder_destroy(&b);
    return st;
}

/* Largest |B / 2 - 1| over the atlas's element texels (alpha 1), and
 * their mean B / 2 - 1 in *mean. */
static double furnace_error(const xrad_atlas *a, uint32_t *texels, double *mean)
{
    double worst = 0, sum = 0;
    *texels = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++) {
        const float *t = a->rgba + i * 4;
        if (t[3] != 1)
            continue;
        (*texels)++;
        for (int c = 0; c < 3; c++) {
            worst = fmax(worst, fabs(t[c] / 2.0 - 1));
            sum += t[c] / 2.0 - 1;
        }
    }
    *mean = *texels ? sum / (3.0 * *texels) : 1;
    return worst;
}

static void check_tiles(const xrad_scene *scene, const xrad_atlas *a)
{
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    CHECK(info.atlas_width == a->width && info.atlas_height == a->height, "atlas %ux%u, info %ux%u",
          a->width, a->height, info.atlas_width, info.atlas_height);
    unsigned char *seen = calloc((size_t)a->width * a->height, 1);
    uint32_t tiled = 0, overlaps = 0, outside = 0;
    for (uint32_t s = 0; s < info.surfaces; s++) {
        xrad_surface_info sf;
        xrad_error err;
        if (xrad_scene_get_surface(scene, s, &sf, &err)) {
            CHECK(0, "%s", err.message);
            continue;
        }
        for (uint32_t y = sf.tile_y; y < sf.tile_y + sf.nv; y++)
            for (uint32_t x = sf.tile_x; x < sf.tile_x + sf.nu; x++) {
                if (x >= a->width || y >= a->height) {
                    outside++;
                    continue;
                }
                size_t i = (size_t)y * a->width + x;
                overlaps += seen[i];
                seen[i] = 1;
                tiled++;
            }
    }
    uint32_t mismatch = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++)
        mismatch += seen[i] != (a->rgba[i * 4 + 3] == 1);
    free(seen);
    CHECK(tiled == info.elements && !overlaps && !outside && !mismatch,
          "tiles: %u texels for %u elements, %u overlapping, %u outside, %u not element texels",
          tiled, info.elements, overlaps, outside, mismatch);
}

int main(void)
{
    CHECK(!strcmp(xrad_version(), XRAD_VERSION), "library %s, headers %s", xrad_version(),
          XRAD_VERSION);
    CHECK(XRAD_VERSION_NUMBER ==
              XRAD_MAKE_VERSION(XRAD_VERSION_MAJOR, XRAD_VERSION_MINOR, XRAD_VERSION_PATCH),
          "version number %d", XRAD_VERSION_NUMBER);

    xrad_error err = {0};
    xrad_scene *scene = NULL;
    xrad_atlas ref = {0}, gpu = {0};
    xrad_context *ctx = NULL;
    xrad_solver *solver = NULL;
    xrad_status st = build_furnace(&scene, &err);
    if (!st)
        st = xrad_atlas_create(scene, &ref, &err);
    if (!st)
        st = xrad_reference_solve(scene, NULL, &ref, NULL, &err);
    CHECK(!st, "reference: %s", err.message);
    if (!st) {
        uint32_t texels;
        double mean, e = furnace_error(&ref, &texels, &mean);
        CHECK(texels > 0 && e < 0.01, "reference: worst |B/2 - 1| %.4f over %u texels", e,
              texels);
        check_tiles(scene, &ref);
    }

    if (!st)
        st = xrad_context_create(&(xrad_context_desc){.validation = 1}, &ctx, &err);
    if (!st)
        st = xrad_solver_create(ctx, scene,
                                &(xrad_solver_desc){.method = XRAD_METHOD_PROGRESSIVE}, &solver,
                                &err);
    if (!st)
        st = xrad_solver_solve(solver, &err);
    if (!st)
        st = xrad_atlas_create(scene, &gpu, &err);
    if (!st)
        st = xrad_solver_read(solver, &gpu, &err);
    CHECK(!st, "progressive: %s", err.message);
    if (!st) {
        /* Issue 14's bounds: the mean within 1%, every element within 5%
         * (hemicube texels near the cube's edges). */
        uint32_t texels;
        double mean, e = furnace_error(&gpu, &texels, &mean);
        CHECK(texels > 0 && fabs(mean) < 0.01 && e < 0.05,
              "progressive on %s: mean B/2 - 1 %.4f, worst |B/2 - 1| %.4f over %u texels",
              xrad_context_device_name(ctx), mean, e, texels);
    }
    xrad_solver_destroy(&solver);
    if (ctx)
        CHECK(xrad_context_validation_messages(ctx) == 0, "%u validation messages",
              xrad_context_validation_messages(ctx));
    xrad_context_destroy(&ctx);
    xrad_atlas_destroy(&gpu);
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&scene);
    printf("%d passed, %d failed\n", passed, failed);
    return failed || !passed;
}
