/*
 * ID hemicubes (src/passes/hemicube.h) against a CPU ray cast of the same
 * scene. From frames on the floor under the light, on the back wall, on the
 * short block's top and on a side of the tall block of the Cornell Box
 * (scenes/cornell-box.json: no coincident surfaces), every pixel of every face
 * must show the quad that a ray through the pixel centre hits first (this
 * file's own Moller-Trumbore cast against the two triangles the pass draws
 * per surface); at least 99.5% agree, and a pixel that differs must lie on
 * an edge (its GPU ID is what the CPU sees in a neighbouring pixel). Known
 * facts hold: from under the light, the top face's centre shows the light
 * and the floor shows nowhere above the horizon. With the count from an
 * indirect draw command, hemicubes beyond the count stay clear. Every path
 * the device draws correctly is exercised; the path check must pass for at
 * least one path, and the automatic choice must take multiview exactly when
 * its check passes. A path that fails the check still runs (validation-clean:
 * every layer ends in the layout the pass promises).
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "passes/hemicube.h"
#include "passes/hemicube_geometry.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "solvers/gpu_scene.h"

#define RES 64
#define CUBES 4
#define MAX_CUBES 5

typedef struct frame {
    vec3 origin, x, y, z;
} frame;

static uint32_t find_surface(const xrad_scene *sc, const char *name)
{
    for (uint32_t i = 0; i < sc->surface_count; i++)
        if (!strcmp(sc->surfaces[i].name, name))
            return i;
    CHECK(0, "no surface '%s'", name);
    return 0;
}

/* A frame at parameter (u, v) of a surface, its normal, rotated. */
static frame frame_on(const xrad_scene *sc, uint32_t sf, double u, double v, uint32_t seed)
{
    vec3 c[4], n;
    scene_surface_world(sc, sf, 0, c, &n);
    frame f;
    f.origin = v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v);
    f.z = n;
    vec3 e = v3_sub(c[1], c[0]);
    vec3 x0 = v3_norm(v3_sub(e, v3_scale(n, v3_dot(e, n))));
    mat3 r = m3_rotation(n, hemicube_rotation(seed));
    f.x = m3_apply(&r, x0);
    f.y = v3_cross(f.z, f.x);
    return f;
}

/* Moller-Trumbore; t of the hit or INFINITY. */
static double ray_triangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c)
{
    vec3 e1 = v3_sub(b, a), e2 = v3_sub(c, a);
    vec3 p = v3_cross(d, e2);
    double det = v3_dot(e1, p);
    if (fabs(det) < 1e-300)
        return INFINITY;
    vec3 s = v3_sub(o, a);
    double u = v3_dot(s, p) / det;
    if (u < 0 || u > 1)
        return INFINITY;
    vec3 q = v3_cross(s, e1);
    double v = v3_dot(d, q) / det;
    if (v < 0 || u + v > 1)
        return INFINITY;
    return v3_dot(e2, q) / det;
}

/* The ID a ray through the pixel centre sees first, hits nearer than
 * `near` along the face axis ignored (d has unit length along it). */
static uint32_t cpu_id(const xrad_scene *sc, vec3 o, vec3 d, double near)
{
    uint32_t best = HEMICUBE_ID_NONE;
    double best_t = INFINITY;
    for (uint32_t s = 0; s < sc->surface_count; s++) {
        vec3 c[4], n;
        scene_surface_world(sc, s, 0, c, &n);
        double t1 = ray_triangle(o, d, c[0], c[1], c[2]);
        double t2 = ray_triangle(o, d, c[0], c[2], c[3]);
        double t = fmin(t1, t2);
        if (t > near && t < best_t) {
            best_t = t;
            best = s + 1;
        }
    }
    return best;
}

static void cpu_hemicube(const xrad_scene *sc, const frame *f, double diameter, uint32_t *out)
{
    vec3 o = v3_mad(f->origin, f->z, HEMICUBE_HAIR_FRACTION * diameter);
    for (int face = 0; face < HEMICUBE_FACES; face++) {
        vec3 rt, up, fw;
        hemicube_face_axes(face, &rt, &up, &fw);
        for (uint32_t row = 0; row < RES; row++)
            for (uint32_t col = 0; col < RES; col++) {
                double a = -1 + (col + 0.5) * 2.0 / RES, b = -1 + (row + 0.5) * 2.0 / RES;
                vec3 l = v3_add(fw, v3_add(v3_scale(rt, a), v3_scale(up, b)));
                vec3 d = v3_add(v3_scale(f->x, l.x), v3_add(v3_scale(f->y, l.y), v3_scale(f->z, l.z)));
                out[((size_t)face * RES + row) * RES + col] =
                    cpu_id(sc, o, d, HEMICUBE_NEAR_FRACTION * diameter);
            }
    }
}

/* Compares one hemicube; returns the pixels that agree. */
static uint32_t compare(const uint32_t *gpu, const uint32_t *cpu, const char *what, uint32_t *edge,
                        uint32_t *wrong)
{
    uint32_t agree = 0;
    *edge = *wrong = 0;
    for (int face = 0; face < HEMICUBE_FACES; face++)
        for (int row = 0; row < RES; row++)
            for (int col = 0; col < RES; col++) {
                size_t i = ((size_t)face * RES + row) * RES + col;
                if (gpu[i] == cpu[i]) {
                    agree++;
                    continue;
                }
                bool near_edge = false;
                for (int dy = -1; dy <= 1; dy++)
                    for (int dx = -1; dx <= 1; dx++) {
                        int y = row + dy, x = col + dx;
                        if (x >= 0 && y >= 0 && x < RES && y < RES &&
                            cpu[((size_t)face * RES + y) * RES + x] == gpu[i])
                            near_edge = true;
                    }
                if (near_edge)
                    (*edge)++;
                else if ((*wrong)++ < 3)
                    fprintf(stderr, "%s: face %d pixel (%d, %d): GPU %u, CPU %u\n", what, face,
                            col, row, gpu[i], cpu[i]);
            }
    return agree;
}

static void upload_frames(xrad_context *ctx, const frame *f, gpu_buffer *buf)
{
    struct gpu_shooter sh[MAX_CUBES];
    memset(sh, 0, sizeof(sh));
    for (int h = 0; h < CUBES; h++) {
        sh[h].pos_area = (vec4){(float)f[h].origin.x, (float)f[h].origin.y, (float)f[h].origin.z, 0};
        sh[h].normal = (vec4){(float)f[h].z.x, (float)f[h].z.y, (float)f[h].z.z, 0};
        sh[h].tangent = (vec4){(float)f[h].x.x, (float)f[h].x.y, (float)f[h].x.z, 0};
        sh[h].hemicube = (uint32_t)h;
    }
    /* A fifth frame for the indirect draw to leave out. */
    sh[CUBES] = sh[0];
    xrad_error err = {0};
    xrad_status s = gpu_buffer_create(ctx, sizeof(sh), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                      GPU_MEM_UPLOAD, GPU_MEM_GEOMETRY, buf, &err);
    CHECK(s == XRAD_OK, "frames: %s", err.message);
    if (!s)
        memcpy(buf->alloc.mapped, sh, sizeof(sh));
}

/* Renders with `path`; direct count CUBES, then an indirect count of 2. */
static void run_path(xrad_context *ctx, gpu_scene *gs, hemicube_path path, const gpu_buffer *fbuf,
                     uint32_t **cpu, uint32_t light, uint32_t floor_id, bool correct)
{
    const char *name = hemicube_path_label(path);
    xrad_error err = {0};
    hemicube_pass *pass = NULL;
    hemicube_desc desc = {
        .kind = HEMICUBE_IDS,
        .res = RES,
        .max_hemicubes = MAX_CUBES,
        .path = path,
        .diameter = gs->diameter,
    };
    xrad_status s = hemicube_create_desc(ctx, &desc, &pass, &err);
    CHECK(s == XRAD_OK, "%s: create: %s", name, err.message);
    if (s)
        return;
    CHECK(!strcmp(hemicube_path_name(pass), name), "path %s", hemicube_path_name(pass));
    size_t cube_px = (size_t)HEMICUBE_FACES * RES * RES;
    /* Two words a texel (HEMICUBE_ID_FORMAT): the ID, then the distance. */
    size_t bytes = 2 * MAX_CUBES * cube_px * sizeof(uint32_t);
    uint32_t *gpu = malloc(bytes);
    gpu_buffer indirect = {0};
    gpu_cmd c = {0};
    CHECK(gpu != NULL, "out of memory");
    if (!gpu)
        goto done;

    for (int mode = 0; mode < 2; mode++) {
        uint32_t count = mode == 0 ? CUBES : 2;
        hemicube_draw d = {
            .mesh = gpu_scene_hemicube_mesh(gs),
            .index_count = gs->index_count,
            .frames = fbuf,
            .count = count,
        };
        if (mode == 1) {
            /* The count a GPU pass would write: a VkDrawIndexedIndirectCommand
             * at offset 16. */
            s = gpu_buffer_create(ctx, 64,
                                  VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                  GPU_MEM_UPLOAD, GPU_MEM_OTHER, &indirect, &err);
            CHECK(s == XRAD_OK, "indirect: %s", err.message);
            if (s)
                break;
            uint32_t *w = indirect.alloc.mapped;
            memset(w, 0, 64);
            w[4] = gs->index_count;
            w[5] = count * hemicube_instances_per_hemicube(pass);
            d.indirect = &indirect;
            d.indirect_offset = 16;
        }
        if ((s = gpu_cmd_begin(ctx, &c, &err)))
            break;
        hemicube_record(pass, c.cmd, &d);
        s = gpu_cmd_run(ctx, &c, &err);
        gpu_cmd_destroy(ctx, &c);
        if (!s)
            s = gpu_readback_image(ctx, hemicube_image(pass), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                   gpu, bytes, &err);
        CHECK(s == XRAD_OK, "%s: render: %s", name, err.message);
        if (s)
            break;
        for (size_t i = 0; i < MAX_CUBES * cube_px; i++)
            gpu[i] = gpu[2 * i];
        for (uint32_t h = 0; h < count; h++) {
            char what[64];
            snprintf(what, sizeof what, "%s %s hemicube %u", name, mode ? "indirect" : "direct", h);
            uint32_t edge, wrong;
            uint32_t agree = compare(gpu + h * cube_px, cpu[h], what, &edge, &wrong);
            fprintf(stderr, "%s: %u of %zu pixels agree, %u differ on edges, %u elsewhere\n",
                    what, agree, cube_px, edge, wrong);
            if (!correct)
                continue;
            CHECK(agree >= 0.995 * cube_px, "%s: only %u of %zu pixels agree", what, agree,
                  cube_px);
            CHECK(wrong == 0, "%s: %u pixels differ away from edges", what, wrong);
        }
        for (uint32_t h = count; h < MAX_CUBES && mode == 1 && correct; h++) {
            uint32_t set = 0;
            for (size_t i = 0; i < cube_px; i++)
                set += gpu[h * cube_px + i] != HEMICUBE_ID_NONE;
            CHECK(set == 0, "%s: hemicube %u beyond the indirect count has %u pixels drawn", name,
                  h, set);
        }
        if (mode == 0 && correct) {
            /* From the floor under the light: the top face's 2 x 2 centre
             * pixels see the light; above the horizon the floor is
             * nowhere. */
            const uint32_t *top = gpu;
            for (int dy = 0; dy < 2; dy++)
                for (int dx = 0; dx < 2; dx++) {
                    uint32_t id = top[(RES / 2 - 1 + dy) * RES + RES / 2 - 1 + dx];
                    CHECK(id == light + 1, "%s: top face centre shows %u, the light is %u", name,
                          id, light + 1);
                }
            uint32_t floor_seen = 0;
            for (int face = 0; face < HEMICUBE_FACES; face++)
                for (uint32_t row = face ? RES / 2 : 0; row < RES; row++)
                    for (uint32_t col = 0; col < RES; col++)
                        floor_seen += gpu[((size_t)face * RES + row) * RES + col] == floor_id + 1;
            CHECK(floor_seen == 0, "%s: the floor shows in %u pixels above the horizon", name,
                  floor_seen);
        }
    }
done:
    gpu_buffer_destroy(ctx, &indirect);
    free(gpu);
    hemicube_destroy(ctx, &pass);
}

/* xrad_context_desc.hemicube_path (and XRAD_HEMICUBE_PATH): a context
 * restricted to one path draws with it where its check passed (ok[] as
 * the checks above found), and fails with a message saying why where it
 * did not; anything but auto, multiview and layered is an input error. */
static void test_path_choice(const bool ok[2])
{
    const char *names[2] = {"multiview", "layered"};
    for (int i = 0; i < 2; i++) {
        xrad_context *ctx = NULL;
        xrad_error err = {0};
        xrad_context_desc d = {.validation = 1, .device = getenv("XRAD_DEVICE"),
                               .hemicube_path = names[i]};
        xrad_status s = xrad_context_create(&d, &ctx, &err);
        CHECK(s == XRAD_OK, "context with hemicube_path %s: %s", names[i], err.message);
        if (s)
            continue;
        hemicube_pass *pass = NULL;
        s = hemicube_create(ctx, 1.0, RES, MAX_CUBES, &pass, &err);
        if (ok[i]) {
            CHECK(s == XRAD_OK && !strcmp(hemicube_path_name(pass), names[i]),
                  "hemicube_path %s: %s", names[i], s ? err.message : hemicube_path_name(pass));
        } else {
            CHECK(s == XRAD_ERROR_SYSTEM && strstr(err.message, "of those allowed"),
                  "hemicube_path %s, which the device draws wrongly: status %d, '%s'", names[i],
                  (int)s, s ? err.message : "created");
        }
        fprintf(stderr, "hemicube_path %s: %s\n", names[i],
                s ? err.message : hemicube_path_name(pass));
        hemicube_destroy(ctx, &pass);
        gpu_test_end(&ctx);
    }
    xrad_context *ctx = NULL;
    xrad_error err = {0};
    xrad_context_desc d = {.hemicube_path = "layerd"};
    xrad_status s = xrad_context_create(&d, &ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "'layerd'") && !ctx,
          "hemicube_path 'layerd': status %d, '%s'", (int)s, err.message);
    xrad_context_destroy(&ctx);
    setenv("XRAD_HEMICUBE_PATH", "both", 1);
    xrad_context_desc e = {0};
    s = xrad_context_desc_from_env(&e, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "XRAD_HEMICUBE_PATH") &&
              strstr(err.message, "'both'"),
          "XRAD_HEMICUBE_PATH=both: status %d, '%s'", (int)s, err.message);
    setenv("XRAD_HEMICUBE_PATH", "layered", 1);
    e = (xrad_context_desc){0};
    s = xrad_context_desc_from_env(&e, &err);
    CHECK(s == XRAD_OK && e.hemicube_path && !strcmp(e.hemicube_path, "layered"),
          "XRAD_HEMICUBE_PATH=layered: %s", s ? err.message : "not taken");
    unsetenv("XRAD_HEMICUBE_PATH");
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    xrad_error err = {0};

    /* The path check: at least one path draws the known scene right. */
    hemicube_path paths[2] = {HEMICUBE_PATH_MULTIVIEW, HEMICUBE_PATH_LAYERED};
    bool ok[2] = {false, false};
    for (int i = 0; i < 2; i++) {
        if (!hemicube_path_supported(ctx, paths[i])) {
            fprintf(stderr, "%s: not supported by %s\n", hemicube_path_label(paths[i]),
                    xrad_context_device_name(ctx));
            continue;
        }
        hemicube_check_result r;
        xrad_status s = hemicube_check_path(ctx, paths[i], &r, &err);
        CHECK(s == XRAD_OK, "check %s: %s", hemicube_path_label(paths[i]), err.message);
        CHECK(r.pixels == 3 * HEMICUBE_FACES * 32 * 32, "%u pixels checked", r.pixels);
        ok[i] = s == XRAD_OK && r.ok;
        fprintf(stderr, "path check %s on %s: %u pixels, %u differ on edges, %u elsewhere: %s\n",
                hemicube_path_label(paths[i]), xrad_context_device_name(ctx), r.pixels, r.edge,
                r.wrong, r.ok ? "correct" : "WRONG");
    }
    CHECK(ok[0] || ok[1], "no hemicube path draws correctly");

    char path[512];
    xrad_scene *sc = NULL;
    xrad_status s =
        xrad_scene_load(test_source_path("scenes/cornell-box.json", path, sizeof path), &sc, &err);
    CHECK(s == XRAD_OK, "load: %s", err.message);
    gpu_scene gs = {0};
    if (!s) {
        s = gpu_scene_create(ctx, sc, 0, 0, &gs, &err);
        CHECK(s == XRAD_OK, "gpu scene: %s", err.message);
    }
    if (!s) {
        /* The automatic choice. */
        hemicube_pass *pass = NULL;
        s = hemicube_create(ctx, gs.diameter, RES, MAX_CUBES, &pass, &err);
        CHECK(s == XRAD_OK, "auto: %s", err.message);
        if (!s) {
            /* XRAD_HEMICUBE_PATH (gpu_test_context applies it) may allow one path. */
            const char *only = getenv("XRAD_HEMICUBE_PATH");
            bool mv = ok[0] && !(only && !strcmp(only, "layered"));
            const char *want = mv ? "multiview" : "layered";
            CHECK(!strcmp(hemicube_path_name(pass), want), "auto took %s, want %s",
                  hemicube_path_name(pass), want);
            CHECK(hemicube_pass_check(pass).ok, "auto's check result is not ok");
            CHECK(hemicube_instances_per_hemicube(pass) == (mv ? 1u : 5u),
                  "instances per hemicube %u", hemicube_instances_per_hemicube(pass));
            fprintf(stderr, "automatic path: %s\n", hemicube_path_name(pass));
        }
        hemicube_destroy(ctx, &pass);

        uint32_t light = find_surface(sc, "light"), floor_s = find_surface(sc, "floor");
        uint32_t back = find_surface(sc, "back"), block = find_surface(sc, "short.top");
        uint32_t side = find_surface(sc, "tall.side-b");
        /* The floor point under the light's centre, in floor parameters. */
        vec3 lc[4], fc[4], n;
        scene_surface_world(sc, light, 0, lc, &n);
        scene_surface_world(sc, floor_s, 0, fc, &n);
        vec3 centre = v3_scale(v3_add(v3_add(lc[0], lc[1]), v3_add(lc[2], lc[3])), 0.25);
        vec3 fu = v3_sub(fc[1], fc[0]), fv = v3_sub(fc[3], fc[0]), rel = v3_sub(centre, fc[0]);
        double u = v3_dot(rel, fu) / v3_dot(fu, fu), v = v3_dot(rel, fv) / v3_dot(fv, fv);
        frame frames[CUBES] = {
            frame_on(sc, floor_s, u, v, 1),
            frame_on(sc, back, 0.3, 0.6, 2),
            frame_on(sc, block, 0.5, 0.5, 3),
            frame_on(sc, side, 0.4, 0.45, 4),
        };
        uint32_t *cpu[CUBES] = {0};
        for (int h = 0; h < CUBES; h++) {
            cpu[h] = malloc((size_t)HEMICUBE_FACES * RES * RES * sizeof(uint32_t));
            CHECK(cpu[h] != NULL, "out of memory");
            if (cpu[h])
                cpu_hemicube(sc, &frames[h], gs.diameter, cpu[h]);
        }
        /* The CPU agrees with the geometry, independently of the GPU. */
        if (cpu[0])
            CHECK(cpu[0][(RES / 2) * RES + RES / 2] == light + 1, "CPU: top centre shows %u",
                  cpu[0][(RES / 2) * RES + RES / 2]);
        gpu_buffer fbuf = {0};
        upload_frames(ctx, frames, &fbuf);
        /* A path the device draws wrongly still runs, validation-clean,
         * with nothing asserted about its pictures. */
        for (int i = 0; i < 2 && fbuf.buffer && cpu[CUBES - 1]; i++)
            if (hemicube_path_supported(ctx, paths[i]))
                run_path(ctx, &gs, paths[i], &fbuf, cpu, light, floor_s, ok[i]);
        gpu_buffer_destroy(ctx, &fbuf);
        for (int h = 0; h < CUBES; h++)
            free(cpu[h]);
    }
    gpu_scene_destroy(ctx, &gs);
    xrad_scene_destroy(&sc);
    gpu_test_end(&ctx);
    if (ok[0] || ok[1])
        test_path_choice(ok);
    return test_finish();
}
