/*
 * Triangle surfaces (xrad_scene_builder_add_mesh) in every method, against
 * truths that do not come from the code under test:
 *
 *  - furnace (ground-truth.md): a closed box, every face albedo rho and
 *    emitting E, built of triangles only (each face a fan of four around
 *    its centre, keep_triangles): the form factors from any point sum to
 *    1, so B = E / (1 - rho) exactly, everywhere. rho = 0.5, E = 1: B = 2.
 *    The CPU reference, gather, progressive, incremental and cross within
 *    1% at every element; an element area that did not sum to its
 *    triangle's, a form factor lost at a collapsed edge, a hemicube that
 *    read the wrong texel of a triangle's tile: each shows here. The same
 *    box again with every face two triangles of one element each
 *    (scene.h): the one-element case of every pass.
 *  - a lit room of triangles against the same room of quads (a light in
 *    the ceiling, a box on the floor): the CPU reference of each, area
 *    means per wall within 2% (two discretisations of one integral
 *    equation), and each GPU method on the triangles against the CPU
 *    reference of the triangles: surface_error within 5%.
 *
 * `test_triangles METHOD` runs one method (reference, gather, progressive,
 * incremental, cross); without an argument, all.
 */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "solvers/solver_test.h"
#include "xrad.h"

typedef struct box_face {
    double o[3], u[3], v[3]; /* the face is o + s u + t v, front along u x v */
} box_face;

/* The six faces of the box [0, sx] x [0, sy] x [0, sz], facing in. */
static void box_faces(double sx, double sy, double sz, box_face f[6])
{
    box_face faces[6] = {
        {{0, 0, 0}, {0, 0, sz}, {sx, 0, 0}},   /* floor, up */
        {{0, sy, 0}, {sx, 0, 0}, {0, 0, sz}},  /* ceiling, down */
        {{0, 0, 0}, {sx, 0, 0}, {0, sy, 0}},   /* back z = 0, +z */
        {{0, 0, sz}, {0, sy, 0}, {sx, 0, 0}},  /* front z = sz, -z */
        {{0, 0, 0}, {0, sy, 0}, {0, 0, sz}},   /* left x = 0, +x */
        {{sx, 0, 0}, {0, 0, sz}, {0, sy, 0}},  /* right x = sx, -x */
    };
    memcpy(f, faces, sizeof(faces));
}

static void at(const box_face *f, double s, double t, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (float)(f->o[k] + s * f->u[k] + t * f->v[k]);
}

/* A face as a fan of four triangles around its centre (no two of which
 * make a convex quad), or as two triangles split along a diagonal. */
static xrad_status add_face_mesh(xrad_scene_builder *b, const char *name, const box_face *f,
                                 uint32_t material, int fan, xrad_error *err)
{
    float pos[15];
    at(f, 0, 0, pos);
    at(f, 1, 0, pos + 3);
    at(f, 1, 1, pos + 6);
    at(f, 0, 1, pos + 9);
    at(f, 0.5, 0.5, pos + 12);
    static const uint32_t fan_idx[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    static const uint32_t split_idx[6] = {0, 1, 2, 0, 2, 3};
    xrad_mesh_desc m = {.name = name,
                        .positions = pos,
                        .vertex_count = 5,
                        .indices = fan ? fan_idx : split_idx,
                        .triangle_count = fan ? 4 : 2,
                        .material = material,
                        .keep_triangles = 1};
    return xrad_scene_builder_add_mesh(b, &m, err);
}

static xrad_status add_face_quad(xrad_scene_builder *b, const char *name, const box_face *f,
                                 uint32_t material, xrad_error *err)
{
    xrad_quad_desc q = {.name = name, .material = material};
    float p[3];
    double st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int c = 0; c < 4; c++) {
        at(f, st[c][0], st[c][1], p);
        for (int k = 0; k < 3; k++)
            q.p[c][k] = p[k];
    }
    return xrad_scene_builder_add_quad(b, &q, err);
}

/* A face as a grid of n x n cells, each cut into two triangles along
 * alternating diagonals. */
static xrad_status add_face_grid(xrad_scene_builder *b, const char *name, const box_face *f,
                                 uint32_t material, uint32_t n, xrad_error *err)
{
    float pos[3 * 9 * 9];
    uint32_t idx[6 * 8 * 8], k = 0;
    if (n > 8)
        return XRAD_ERROR_INPUT;
    for (uint32_t j = 0; j <= n; j++)
        for (uint32_t i = 0; i <= n; i++)
            at(f, (double)i / n, (double)j / n, pos + 3 * (j * (n + 1) + i));
    for (uint32_t j = 0; j < n; j++) {
        for (uint32_t i = 0; i < n; i++) {
            uint32_t a = j * (n + 1) + i, b1 = a + 1, c = a + n + 2, d = a + n + 1;
            uint32_t t[6] = {a, b1, c, a, c, d};
            if ((i + j) & 1) {
                uint32_t u[6] = {a, b1, d, b1, c, d};
                memcpy(t, u, sizeof(t));
            }
            memcpy(idx + k, t, sizeof(t));
            k += 6;
        }
    }
    xrad_mesh_desc m = {.name = name,
                        .positions = pos,
                        .vertex_count = (n + 1) * (n + 1),
                        .indices = idx,
                        .triangle_count = 2 * n * n,
                        .material = material,
                        .keep_triangles = 1};
    return xrad_scene_builder_add_mesh(b, &m, err);
}

static const char *const face_name[6] = {"floor", "ceiling", "back", "front", "left", "right"};

/* The furnace box, each face a fan of four triangles at density 6, or
 * (grid > 0) a grid of grid x grid cells at density 0.5, whose triangles
 * (with grid 1, longest edge at most 1.8 m) are all within a spacing
 * (2 m): one element each (scene.h). With grid 4, 192 lights: one
 * invocation of gather's direct pass over all of them against every
 * surface ran past lavapipe's 65,535 loop iterations and came out 46%
 * low (spirv/direct.comp). */
static xrad_scene *furnace_scene(uint32_t grid)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *scene = NULL;
    box_face f[6];
    box_faces(1.0, 1.5, 0.7, f);
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = grid ? "furnace-tiny-triangles" : "furnace-triangles",
                                   .density = grid ? 0.5 : 6},
        &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "m", .albedo = {0.5, 0.5, 0.5}, .emission = {1, 1, 1}},
            &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "box"}, &err);
    for (int k = 0; k < 6 && !st; k++)
        st = grid ? add_face_grid(b, face_name[k], &f[k], m, grid, &err)
                  : add_face_mesh(b, face_name[k], &f[k], m, 1, &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &scene, &err);
    CHECK(st == XRAD_OK, "furnace scene: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return scene;
}

/* A 2 x 1.6 x 1.8 m room, albedo 0.6, a 0.6 x 0.5 m light in the ceiling
 * (emission 10) and a 0.5 m box on the floor; walls as triangles (split
 * along a diagonal, the light a fan) or as quads. */
static xrad_scene *lit_room(int triangles)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *scene = NULL;
    box_face f[6], c[6];
    box_faces(2.0, 1.6, 1.8, f);
    uint32_t wall = 0, lamp = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = triangles ? "room-triangles" : "room-quads",
                                   .density = 6},
        &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){.name = "wall", .albedo = {0.6, 0.6, 0.6}, .emission = {0, 0, 0}},
            &wall, &err);
    if (!st)
        st = xrad_scene_builder_add_material(b,
                                             &(xrad_material_desc){.name = "lamp",
                                                                   .albedo = {0.1, 0.1, 0.1},
                                                                   .emission = {10, 10, 10}},
                                             &lamp, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "room"}, &err);
    for (int k = 0; k < 6 && !st; k++)
        st = triangles ? add_face_mesh(b, face_name[k], &f[k], wall, 0, &err)
                       : add_face_quad(b, face_name[k], &f[k], wall, &err);
    /* The light: 1 mm below the ceiling, facing down. */
    box_face light = {{0.7, 1.599, 0.65}, {0.6, 0, 0}, {0, 0, 0.5}};
    if (!st)
        st = triangles ? add_face_mesh(b, "light", &light, lamp, 1, &err)
                       : add_face_quad(b, "light", &light, lamp, &err);
    /* The box: its five visible faces, outward (the bottom would be buried). */
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "box"}, &err);
    box_faces(0.5, 0.5, 0.5, c);
    static const char *const box_name[6] = {NULL, "top", "back", "front", "left", "right"};
    for (int k = 1; k < 6 && !st; k++) {
        /* Outward: the inward face's origin on the far side, edges swapped. */
        box_face o = c[k];
        for (int a = 0; a < 3; a++) {
            o.o[a] += (a == 0 ? 0.9 : a == 2 ? 0.6 : 0);
            double t = o.u[a];
            o.u[a] = o.v[a];
            o.v[a] = t;
        }
        st = triangles ? add_face_mesh(b, box_name[k], &o, wall, 0, &err)
                       : add_face_quad(b, box_name[k], &o, wall, &err);
    }
    /* Inside, by the front wall, looking at the back wall and the box. */
    if (!st)
        st = xrad_scene_builder_set_camera(
            b, &(xrad_camera_desc){.position = {1.0, 0.9, 1.75}, .look_at = {1.0, 0.5, 0.0},
                                   .fov_degrees = 75},
            &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &scene, &err);
    CHECK(st == XRAD_OK, "lit room: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return scene;
}

static const struct {
    const char *name;
    xrad_method method;
} methods[] = {
    {"gather", XRAD_METHOD_GATHER},
    {"progressive", XRAD_METHOD_PROGRESSIVE},
    {"incremental", XRAD_METHOD_INCREMENTAL},
    {"cross", XRAD_METHOD_CROSS},
};

/* Solves with `method` (0: the CPU reference) into atlas; `conserve` as
 * xrad_solver_desc's (0: default). */
static xrad_status solve(xrad_context *ctx, const xrad_scene *scene, xrad_method method,
                         uint32_t conserve, xrad_atlas *atlas, xrad_error *err)
{
    return solver_test_solve(
        ctx, scene, &(xrad_solver_desc){.method = method, .conserve = conserve}, atlas, err);
}

/* Worst relative deviation of any element from `want` (every channel),
 * and that of the mean over element texels (the furnace's elements of a
 * surface differ in area, not in B, so a plain mean is as good). */
static void worst_from(const xrad_atlas *a, double want, double *worst, double *mean)
{
    double sum = 0;
    uint64_t n = 0;
    *worst = 0;
    for (uint32_t k = 0; k < a->width * a->height; k++) {
        const float *t = &a->rgba[4 * (size_t)k];
        if (t[3] == 0)
            continue;
        for (int c = 0; c < 3; c++) {
            *worst = fmax(*worst, fabs(t[c] - want) / want);
            sum += t[c];
            n++;
        }
    }
    *mean = n ? fabs(sum / n - want) / want : 1;
}

static void furnace(xrad_context *ctx, const char *only, uint32_t grid)
{
    xrad_scene *scene = furnace_scene(grid);
    if (!scene)
        return;
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    uint32_t want = grid ? 12 * grid * grid : 24;
    CHECK(info.triangles == info.surfaces && info.surfaces == want,
          "furnace: %u triangles of %u surfaces, want %u of %u", info.triangles, info.surfaces,
          want, want);
    CHECK(!grid || info.elements == want, "furnace of tiny triangles: %u elements, want %u",
          info.elements, want);
    char label[32] = "";
    if (grid)
        snprintf(label, sizeof label, "tiny %ux%u ", grid, grid);
    for (int m = -1; m < 4; m++) {
        const char *name = m < 0 ? "reference" : methods[m].name;
        if (only && strcmp(only, name))
            continue;
        xrad_atlas a = {0};
        xrad_error err = {0};
        /* The shooting methods without conservation: with it a shot's
         * power goes where its ID hemicube saw front faces, up to 4.5%
         * off at single elements of the quad furnace too
         * (test_progressive); the mean holds either way. */
        uint32_t conserve = m < 1 ? 0 : XRAD_CONSERVE_OFF;
        for (int pass = 0; pass < (m < 1 ? 1 : 2); pass++) {
            xrad_status st = solve(ctx, scene, m < 0 ? 0 : methods[m].method,
                                   pass ? 0 : conserve, &a, &err);
            CHECK(st == XRAD_OK, "furnace %s: %s", name, err.message);
            if (!st) {
                double w = 0, mean = 0;
                worst_from(&a, 2.0, &w, &mean);
                fprintf(stderr, "furnace %s%-11s%s worst element %.5f, mean %.5f off B = 2\n",
                        label, name, pass || m < 1 ? "" : " (conserve off)", w, mean);
                CHECK(pass ? mean <= 0.01 : w <= 0.01,
                      "furnace %s%s: %s %.4f off E / (1 - rho)", label, name,
                      pass ? "the mean" : "an element", pass ? mean : w);
            }
            xrad_atlas_destroy(&a);
        }
    }
    xrad_scene_destroy(&scene);
}

/* The camera image (128 x 128) of a solution; NULL after a failed CHECK. */
static float *image(xrad_context *ctx, const xrad_scene *scene, const xrad_atlas *a)
{
    float *img = NULL;
    uint32_t w, h;
    xrad_error err = {0};
    xrad_status st = xrad_render_view(ctx, scene, a, &(xrad_view_desc){.width = 128, .height = 128},
                                      &img, &w, &h, &err);
    CHECK(st == XRAD_OK, "render: %s", err.message);
    return img;
}

static void room(xrad_context *ctx, const char *only)
{
    xrad_scene *tri = lit_room(1), *quad = lit_room(0);
    if (!tri || !quad) {
        xrad_scene_destroy(&tri);
        xrad_scene_destroy(&quad);
        return;
    }
    xrad_atlas rt = {0}, rq = {0};
    xrad_error err = {0};
    xrad_status st = solve(ctx, tri, 0, 0, &rt, &err);
    if (!st)
        st = solve(ctx, quad, 0, 0, &rq, &err);
    CHECK(st == XRAD_OK, "room reference: %s", err.message);
    if (!st && (!only || !strcmp(only, "reference"))) {
        float *it = image(ctx, tri, &rt), *iq = image(ctx, quad, &rq);
        xrad_image_metrics im = {0};
        if (it && iq) {
            st = xrad_image_compare(it, iq, NULL, 128, 128, &im, &err);
            CHECK(st == XRAD_OK, "image compare: %s", err.message);
            fprintf(stderr, "room reference: triangles / quads image mean %.4f rel_rms %.4f\n",
                    im.mean_ratio, im.rel_rms);
            CHECK(fabs(im.mean_ratio - 1) <= 0.02 && im.rel_rms <= 0.05,
                  "the CPU reference of the triangle room against the quad room's: image mean "
                  "ratio %.4f, rel_rms %.4f",
                  im.mean_ratio, im.rel_rms);
        }
        free(it);
        free(iq);
    }
    for (int m = 0; m < 4 && !st; m++) {
        if (only && strcmp(only, methods[m].name))
            continue;
        xrad_atlas a = {0};
        st = solve(ctx, tri, methods[m].method, 0, &a, &err);
        CHECK(st == XRAD_OK, "room %s: %s", methods[m].name, err.message);
        if (!st) {
            xrad_element_metrics em;
            st = xrad_atlas_compare(tri, &a, &rt, &em, NULL, &err);
            CHECK(st == XRAD_OK, "compare: %s", err.message);
            xrad_surface_info si = {0};
            xrad_scene_get_surface(tri, em.worst_surface, &si, &err);
            fprintf(stderr, "room %-11s surface_error %.4f (%s) p95 %.4f mean ratio %.4f\n",
                    methods[m].name, em.surface_error, si.name, em.p95, em.mean_ratio);
            CHECK(em.surface_error <= 0.05, "room %s: surface %s %.3f off the reference",
                  methods[m].name, si.name, em.surface_error);
        }
        xrad_atlas_destroy(&a);
        st = XRAD_OK;
    }
    xrad_atlas_destroy(&rt);
    xrad_atlas_destroy(&rq);
    xrad_scene_destroy(&tri);
    xrad_scene_destroy(&quad);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    furnace(ctx, only, 0);
    furnace(ctx, only, 1);
    furnace(ctx, only, 4);
    room(ctx, only);
    gpu_test_end(&ctx);
    return test_finish();
}
