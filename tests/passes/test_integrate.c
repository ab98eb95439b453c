/*
 * Radiosity hemicubes + integrate (src/passes/hemicube.h, integrate.h,
 * atlas_scatter.h) against closed forms:
 *  - the delta form factor table on the GPU sums to 1 within 1e-4 at 64 x 64;
 *  - inside a closed box whose every wall emits E, any hemicube (any point,
 *    any orientation, 1 or 4 samples) integrates to E within 1e-3, also for
 *    E = 1e6, where the scale keeps fp16 from overflowing; for E = 6.123292
 *    with scale 1 / E (B x scale lands just below 1) within half an fp16
 *    step, 2.5e-4: the attachment must not truncate (lavapipe's float ->
 *    half conversion did, 4.9e-4 low);
 *  - under a unit-square emitting ceiling at height 1, the floor centre
 *    gathers E F with F = 4 F_corner(1/2, 1/2), the differential area to a
 *    parallel rectangle whose corner lies on its normal at unit distance
 *    (Howell's catalog B-3): F_corner(a, b) = 1/(2 pi) [a / sqrt(1 + a^2)
 *    atan(b / sqrt(1 + a^2)) + b / sqrt(1 + b^2) atan(a / sqrt(1 + b^2))].
 *    An unrotated hemicube puts the square's edges on pixel boundaries, so
 *    the exact delta form factors give F to rounding (1e-3); rotated, the
 *    edges cut pixels (1e-2 with 4 samples).
 *  - the horizon ring's mean radiosity (integrate_shared.h, ring): E
 *    inside the uniform box (1e-3), 0 under the square, which lies above
 *    every direction within 15 degrees of the horizon from points inside
 *    its footprint.
 *  - open_only (hemicube_desc): a slab lies on the floor over exactly one
 *    floor element's cell, which is buried; every other floor element has
 *    B = V, the rest 0. From the ceiling's centre the visible floor is
 *    open cells only, so the gather is V (F_floor - F_top), F_top the
 *    slab's top as a parallel square (B-3 again). Plain bilinear drags the
 *    strip round the slab towards the buried sample's 0 and gathers less;
 *    without buried elements open_only gives plain bilinear's sums to the
 *    bit.
 */
#include <stdio.h>
#include <string.h>

#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "passes/atlas_scatter.h"
#include "passes/hemicube.h"
#include "passes/hemicube_geometry.h"
#include "passes/integrate.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "solvers/gpu_scene.h"

#define RES 64
#define MAX_CUBES 4

/* The unit box, walls facing inward, each its own material. */
static const char *box_json =
    "{\"unit\":\"m\",\"density\":4,\"materials\":["
    "{\"name\":\"wall\",\"albedo\":[0.5,0.5,0.5],\"emission\":[%g,%g,%g]},"
    "{\"name\":\"top\",\"albedo\":[0.5,0.5,0.5],\"emission\":[%g,%g,%g]}],"
    "\"objects\":[{\"name\":\"box\",\"surfaces\":["
    "{\"name\":\"floor\",\"material\":\"wall\",\"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}},"
    "{\"name\":\"ceiling\",\"material\":\"top\",\"quad\":{\"origin\":[0,0,1],\"u\":[0,1,0],\"v\":[1,0,0]}},"
    "{\"name\":\"x0\",\"material\":\"wall\",\"quad\":{\"origin\":[0,0,0],\"u\":[0,1,0],\"v\":[0,0,1]}},"
    "{\"name\":\"x1\",\"material\":\"wall\",\"quad\":{\"origin\":[1,0,0],\"u\":[0,0,1],\"v\":[0,1,0]}},"
    "{\"name\":\"y0\",\"material\":\"wall\",\"quad\":{\"origin\":[0,0,0],\"u\":[0,0,1],\"v\":[1,0,0]}},"
    "{\"name\":\"y1\",\"material\":\"wall\",\"quad\":{\"origin\":[0,1,0],\"u\":[1,0,0],\"v\":[0,0,1]}}"
    "]}]}";

typedef struct frame {
    vec3 origin, normal;
    double angle; /* of the tangent about the normal, from the x axis projected */
} frame;

static xrad_scene *load_box(const double wall[3], const double top[3])
{
    char json[2048];
    snprintf(json, sizeof json, box_json, wall[0], wall[1], wall[2], top[0], top[1], top[2]);
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status s = xrad_scene_parse(json, strlen(json), "box.json", &sc, &err);
    CHECK(s == XRAD_OK, "parse: %s", err.message);
    return sc;
}

static struct gpu_shooter to_shooter(const frame *f)
{
    vec3 z = v3_norm(f->normal);
    vec3 a = fabs(z.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
    vec3 x0 = v3_norm(v3_sub(a, v3_scale(z, v3_dot(a, z))));
    mat3 r = m3_rotation(z, f->angle);
    vec3 x = m3_apply(&r, x0);
    struct gpu_shooter sh;
    memset(&sh, 0, sizeof(sh));
    sh.pos_area = (vec4){(float)f->origin.x, (float)f->origin.y, (float)f->origin.z, 0};
    sh.normal = (vec4){(float)z.x, (float)z.y, (float)z.z, 0};
    sh.tangent = (vec4){(float)x.x, (float)x.y, (float)x.z, 0};
    return sh;
}

/* B -> atlas (b, or the scene's emission where NULL), n radiosity
 * hemicubes (with open_only: hemicube_desc), integrate; sums[h] rgb, with
 * `ring` ring[h] the horizon ring's mean radiosity, with `buried` each
 * element's gpu_scene buried mark. */
static xrad_status gather_with(xrad_context *ctx, const xrad_scene *sc, const frame *frames,
                               uint32_t n, uint32_t msaa, float scale, bool open_only,
                               const vec4 *b, double sums[][3], double (*ring)[3], uint8_t *buried)
{
    xrad_error err = {0};
    gpu_scene gs = {0};
    hemicube_pass *hc = NULL;
    integrate_pass *ip = NULL;
    atlas_scatter_pass *sp = NULL;
    gpu_buffer fbuf = {0}, out = {0};
    gpu_cmd c = {0};
    struct gpu_shooter sh[MAX_CUBES];
    for (uint32_t h = 0; h < n; h++)
        sh[h] = to_shooter(&frames[h]);
    xrad_status s;
    if ((s = gpu_scene_create(ctx, sc, 0, 0, &gs, &err)))
        goto done;
    hemicube_desc hd = {
        .kind = HEMICUBE_RADIOSITY,
        .res = RES,
        .max_hemicubes = MAX_CUBES,
        .msaa = msaa,
        .path = HEMICUBE_PATH_AUTO,
        .diameter = gs.diameter,
        .open_only = open_only,
    };
    if (buried)
        memcpy(buried, gs.buried, gs.element_count);
    if (b && (s = gpu_upload_buffer(ctx, &gs.B, 0, b, gs.element_count * sizeof(vec4), &err)))
        goto done;
    if ((s = hemicube_create_desc(ctx, &hd, &hc, &err)) ||
        (s = integrate_create(ctx, RES, &ip, &err)) || (s = atlas_scatter_create(ctx, &sp, &err)) ||
        (s = gpu_buffer_create(ctx, sizeof(sh), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                               GPU_MEM_GEOMETRY, &fbuf, &err)) ||
        (s = gpu_buffer_create(ctx, 2 * MAX_CUBES * sizeof(vec4),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_READBACK, GPU_MEM_OTHER,
                               &out, &err)) ||
        (s = gpu_upload_buffer(ctx, &fbuf, 0, sh, n * sizeof(sh[0]), &err)) ||
        (s = gpu_cmd_begin(ctx, &c, &err)))
        goto done;
    atlas_scatter_record(sp, c.cmd,
                         &(atlas_scatter_draw){&gs.elements, &gs.B, gs.element_count, &gs.atlas});
    gpu_image_barrier(c.cmd, &gs.atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    hemicube_record(hc, c.cmd,
                    &(hemicube_draw){.mesh = gpu_scene_hemicube_mesh(&gs),
                                     .index_count = gs.index_count,
                                     .frames = &fbuf,
                                     .count = n,
                                     .atlas = &gs.atlas,
                                     .scale = scale});
    integrate_record(ip, c.cmd,
                     &(integrate_draw){.hemicubes = hemicube_image(hc)->view,
                                       .count = n,
                                       .out = &out,
                                       .scale = scale,
                                       .ring = ring != NULL,
                                       .ring_first = n});
    VkMemoryBarrier host = {VK_STRUCTURE_TYPE_MEMORY_BARRIER, NULL, VK_ACCESS_SHADER_WRITE_BIT,
                            VK_ACCESS_HOST_READ_BIT};
    vkCmdPipelineBarrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &host, 0, NULL, 0, NULL);
    if ((s = gpu_cmd_run(ctx, &c, &err)))
        goto done;
    const vec4 *v = out.alloc.mapped;
    for (uint32_t h = 0; h < n; h++) {
        sums[h][0] = v[h].x;
        sums[h][1] = v[h].y;
        sums[h][2] = v[h].z;
        if (ring) {
            ring[h][0] = v[n + h].x;
            ring[h][1] = v[n + h].y;
            ring[h][2] = v[n + h].z;
        }
    }
done:
    CHECK(s == XRAD_OK, "%s", err.message);
    gpu_cmd_destroy(ctx, &c);
    gpu_buffer_destroy(ctx, &out);
    gpu_buffer_destroy(ctx, &fbuf);
    atlas_scatter_destroy(ctx, &sp);
    integrate_destroy(ctx, &ip);
    hemicube_destroy(ctx, &hc);
    gpu_scene_destroy(ctx, &gs);
    return s;
}

static xrad_status gather_ring(xrad_context *ctx, const xrad_scene *sc, const frame *frames,
                               uint32_t n, uint32_t msaa, float scale, double sums[][3],
                               double (*ring)[3])
{
    return gather_with(ctx, sc, frames, n, msaa, scale, false, NULL, sums, ring, NULL);
}

static xrad_status gather_sums(xrad_context *ctx, const xrad_scene *sc, const frame *frames,
                               uint32_t n, uint32_t msaa, float scale, double sums[][3])
{
    return gather_ring(ctx, sc, frames, n, msaa, scale, sums, NULL);
}

static void test_table(xrad_context *ctx)
{
    xrad_error err = {0};
    integrate_pass *ip = NULL;
    xrad_status s = integrate_create(ctx, RES, &ip, &err);
    CHECK(s == XRAD_OK, "integrate: %s", err.message);
    if (s)
        return;
    size_t n = (size_t)HEMICUBE_FACES * RES * RES;
    float *t = malloc(n * sizeof(float));
    CHECK(t != NULL, "out of memory");
    if (t && !(s = gpu_readback_buffer(ctx, (gpu_buffer *)integrate_table(ip), 0, t,
                                       n * sizeof(float), &err))) {
        double sum = 0;
        for (size_t i = 0; i < n; i++)
            sum += t[i];
        fprintf(stderr, "delta form factors at %u: sum %.9f\n", RES, sum);
        CHECK_ABS(sum, 1.0, 1e-4);
    }
    CHECK(s == XRAD_OK, "readback: %s", err.message);
    free(t);
    integrate_destroy(ctx, &ip);
}

static const frame uniform_frames[MAX_CUBES] = {
    {{0.5, 0.5, 0}, {0, 0, 1}, 0},        /* floor centre */
    {{0.3, 0.6, 0.45}, {0.3, -0.5, 0.8}, 1.1}, /* inside, tilted */
    {{0.03, 0.02, 0.04}, {1, 1, 1}, 2.3},  /* near a corner, facing the box's diagonal */
    {{1, 0.7, 0.2}, {-1, 0, 0}, 4.0},      /* on a wall */
};

static void test_uniform_box(xrad_context *ctx, double e, uint32_t msaa, double tol)
{
    const double em[3] = {e, 0.5 * e, 0.25 * e};
    xrad_scene *sc = load_box(em, em);
    if (!sc)
        return;
    double sums[MAX_CUBES][3], rings[MAX_CUBES][3];
    if (!gather_ring(ctx, sc, uniform_frames, MAX_CUBES, msaa, (float)(1.0 / e), sums, rings)) {
        for (int h = 0; h < MAX_CUBES; h++) {
            double worst = 0, ring = 0;
            for (int c = 0; c < 3; c++) {
                worst = fmax(worst, fabs(sums[h][c] - em[c]) / em[c]);
                ring = fmax(ring, fabs(rings[h][c] - em[c]) / em[c]);
            }
            fprintf(stderr,
                    "uniform box E = %g, %u sample(s), hemicube %d: worst relative error %.2e, "
                    "horizon ring %.2e\n",
                    e, msaa, h, worst, ring);
            CHECK(worst < tol, "E = %g, msaa %u, hemicube %d: (%g %g %g) vs (%g %g %g)", e, msaa,
                  h, sums[h][0], sums[h][1], sums[h][2], em[0], em[1], em[2]);
            CHECK(ring < tol, "E = %g, msaa %u, hemicube %d: horizon ring (%g %g %g) vs E", e, msaa,
                  h, rings[h][0], rings[h][1], rings[h][2]);
        }
    }
    xrad_scene_destroy(&sc);
}

static double f_corner(double a, double b)
{
    double sa = sqrt(1 + a * a), sb = sqrt(1 + b * b);
    return (a / sa * atan(b / sa) + b / sb * atan(a / sb)) / (2 * M_PI);
}

static void test_ceiling(xrad_context *ctx)
{
    const double zero[3] = {0, 0, 0}, e[3] = {3, 2, 1};
    xrad_scene *sc = load_box(zero, e);
    if (!sc)
        return;
    double f = 4 * f_corner(0.5, 0.5);
    const frame frames[2] = {
        {{0.5, 0.5, 0}, {0, 0, 1}, 0},   /* unrotated: the square's edges on pixel boundaries */
        {{0.5, 0.5, 0}, {0, 0, 1}, 0.7}, /* rotated: they cut pixels */
    };
    for (uint32_t msaa = 1; msaa <= 4; msaa += 3) {
        double sums[2][3];
        if (gather_sums(ctx, sc, frames, 2, msaa, 1.0f / 3, sums))
            break;
        for (int h = 0; h < 2; h++) {
            double worst = 0;
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(sums[h][c] - e[c] * f) / (e[c] * f));
            fprintf(stderr, "ceiling, F = %.6f, %s, %u sample(s): worst relative error %.2e\n", f,
                    h ? "rotated" : "aligned", msaa, worst);
            double tol = h == 0 ? 1e-3 : msaa == 4 ? 1e-2 : 3e-2;
            CHECK(worst < tol, "ceiling, hemicube %d, msaa %u: (%g %g %g), want %g x E", h, msaa,
                  sums[h][0], sums[h][1], sums[h][2], f);
        }
    }
    xrad_scene_destroy(&sc);
}

/* The horizon ring under the unit square at z = 1 (x, y in [0, 1]) from
 * points inside its footprint: the square lies above every direction
 * within 15 degrees of the horizon there, so nothing is in the ring. */
static void test_ring_empty(xrad_context *ctx)
{
    const double zero[3] = {0, 0, 0}, e[3] = {3, 2, 1};
    xrad_scene *sc = load_box(zero, e);
    if (!sc)
        return;
    const frame frames[2] = {{{0.2, 0.3, 0}, {0, 0, 1}, 0}, {{0.85, 0.6, 0}, {0, 0, 1}, 0}};
    double sums[2][3], rings[2][3];
    if (!gather_ring(ctx, sc, frames, 2, 4, 1.0f / 3, sums, rings)) {
        for (int h = 0; h < 2; h++) {
            fprintf(stderr, "horizon ring under the square at (%.2f, %.2f): (%g %g %g)\n",
                    frames[h].origin.x, frames[h].origin.y, rings[h][0], rings[h][1], rings[h][2]);
            for (int c = 0; c < 3; c++)
                CHECK(rings[h][c] == 0, "horizon ring, hemicube %d: %g where it shows nothing", h,
                      rings[h][c]);
            CHECK(sums[h][0] > 0, "hemicube %d: the square gathered nothing", h);
        }
    }
    xrad_scene_destroy(&sc);
}

/* The unit box with a slab of side 0.25 and height SLAB_H lying on the
 * floor over [0.375, 0.625]^2: the cell of the floor's middle element
 * (density 4: samples 0.25 apart, cells half a spacing round them). */
#define SLAB_H 0.05 /* as slab_json has it */
static const char *slab_json =
    ",{\"name\":\"slab\",\"surfaces\":["
    "{\"name\":\"top\",\"material\":\"wall\",\"quad\":{\"origin\":[0.375,0.375,0.05],\"u\":[0.25,0,0],\"v\":[0,0.25,0]}},"
    "{\"name\":\"bottom\",\"material\":\"wall\",\"quad\":{\"origin\":[0.375,0.375,0],\"u\":[0,0.25,0],\"v\":[0.25,0,0]}},"
    "{\"name\":\"x0\",\"material\":\"wall\",\"quad\":{\"origin\":[0.375,0.375,0],\"u\":[0,0,0.05],\"v\":[0,0.25,0]}},"
    "{\"name\":\"x1\",\"material\":\"wall\",\"quad\":{\"origin\":[0.625,0.375,0],\"u\":[0,0.25,0],\"v\":[0,0,0.05]}},"
    "{\"name\":\"y0\",\"material\":\"wall\",\"quad\":{\"origin\":[0.375,0.375,0],\"u\":[0.25,0,0],\"v\":[0,0,0.05]}},"
    "{\"name\":\"y1\",\"material\":\"wall\",\"quad\":{\"origin\":[0.375,0.625,0],\"u\":[0,0,0.05],\"v\":[0.25,0,0]}}"
    "]}]}";

static xrad_scene *load_box_slab(void)
{
    const double zero[3] = {0, 0, 0};
    char box[2048], json[4096];
    snprintf(box, sizeof box, box_json, zero[0], zero[1], zero[2], zero[0], zero[1], zero[2]);
    size_t len = strlen(box);
    CHECK(len > 2 && !strcmp(box + len - 2, "]}"), "the box's JSON ends its objects");
    snprintf(json, sizeof json, "%.*s%s", (int)(len - 2), box, slab_json);
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status s = xrad_scene_parse(json, strlen(json), "box-slab.json", &sc, &err);
    CHECK(s == XRAD_OK, "parse: %s", err.message);
    return sc;
}

static void test_open_only(xrad_context *ctx)
{
    xrad_scene *sc = load_box_slab();
    if (!sc)
        return;
    const surface *floor = &sc->surfaces[0];
    uint32_t n = sc->element_count, middle = floor->first_element + 2 * floor->nu + 2;
    vec4 *b = calloc(n, sizeof(vec4));
    uint8_t *buried = calloc(n, 1);
    CHECK(b && buried, "out of memory");
    CHECK(floor->nu == 5 && floor->nv == 5, "floor: %u x %u samples, want 5 x 5", floor->nu,
          floor->nv);
    if (!b || !buried || floor->nu != 5 || floor->nv != 5)
        goto done;
    const vec4 v = {2, 1, 0.5f, 0};
    for (uint32_t e = floor->first_element; e < floor->first_element + 25; e++)
        b[e] = e == middle ? (vec4){0, 0, 0, 0} : v;
    const frame above[1] = {{{0.5, 0.5, 1}, {0, 0, -1}, 0}};
    double open[1][3], plain[1][3];
    if (gather_with(ctx, sc, above, 1, 4, 0.5f, true, b, open, NULL, buried) ||
        gather_with(ctx, sc, above, 1, 4, 0.5f, false, b, plain, NULL, NULL))
        goto done;
    uint32_t floor_buried = 0;
    for (uint32_t e = floor->first_element; e < floor->first_element + 25; e++)
        floor_buried += buried[e] != 0;
    CHECK(buried[middle] && floor_buried == 1,
          "the slab buries the floor's middle element alone (%u buried)", floor_buried);
    double f = 4 * f_corner(0.5, 0.5) - 4 * f_corner(0.125 / (1 - SLAB_H), 0.125 / (1 - SLAB_H));
    const double vv[3] = {v.x, v.y, v.z};
    double worst = 0, plain_low = 1;
    for (int c = 0; c < 3; c++) {
        worst = fmax(worst, fabs(open[0][c] - vv[c] * f) / (vv[c] * f));
        plain_low = fmin(plain_low, (vv[c] * f - plain[0][c]) / (vv[c] * f));
    }
    fprintf(stderr, "slab on the floor, F = %.6f: open_only off by %.2e, plain bilinear %.2e low\n",
            f, worst, plain_low);
    CHECK(worst < 2e-3, "open_only: (%g %g %g), want %g x V", open[0][0], open[0][1], open[0][2],
          f);
    /* The case must show the filter: plain bilinear is darker by the strip. */
    CHECK(plain_low > 5e-3, "plain bilinear only %.2e below V F", plain_low);
done:
    free(buried);
    free(b);
    xrad_scene_destroy(&sc);
}

/* Without buried elements open_only is plain bilinear, to the bit: B
 * varying from element to element, hemicubes anywhere. */
static void test_open_only_plain(xrad_context *ctx)
{
    const double one[3] = {1, 1, 1};
    xrad_scene *sc = load_box(one, one);
    if (!sc)
        return;
    vec4 *b = calloc(sc->element_count, sizeof(vec4));
    CHECK(b != NULL, "out of memory");
    double open[MAX_CUBES][3], plain[MAX_CUBES][3];
    if (b) {
        for (uint32_t e = 0; e < sc->element_count; e++)
            b[e] = (vec4){(float)(1 + (e * 7919u) % 13), (float)(1 + (e * 104729u) % 7), 1, 0};
        if (!gather_with(ctx, sc, uniform_frames, MAX_CUBES, 1, 1.0f / 16, true, b, open, NULL,
                         NULL) &&
            !gather_with(ctx, sc, uniform_frames, MAX_CUBES, 1, 1.0f / 16, false, b, plain, NULL,
                         NULL))
            for (int h = 0; h < MAX_CUBES; h++)
                CHECK(!memcmp(open[h], plain[h], sizeof(open[h])),
                      "hemicube %d: open_only (%.9g) against plain (%.9g) with nothing buried", h,
                      open[h][0], plain[h][0]);
    }
    free(b);
    xrad_scene_destroy(&sc);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_table(ctx);
    test_uniform_box(ctx, 1, 1, 1e-3);
    test_uniform_box(ctx, 1, 4, 1e-3);
    test_uniform_box(ctx, 1e6, 4, 1e-3);
    test_uniform_box(ctx, 6.123292, 1, 2.5e-4);
    test_uniform_box(ctx, 6.123292, 4, 2.5e-4);
    test_ceiling(ctx);
    test_ring_empty(ctx);
    test_open_only(ctx);
    test_open_only_plain(ctx);
    gpu_test_end(&ctx);
    return test_finish();
}
