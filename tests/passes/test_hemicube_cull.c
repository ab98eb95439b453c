/*
 * The hemicube cull pass (src/passes/hemicube_cull.h) on scenes/heavy-sphere
 * (a closed 100,820-triangle displaced sphere in a room): for frames on the
 * floor, on a wall, at the light, on the sphere itself and on the floor
 * under the sphere's rim (inside its box, where the cone test must stand
 * aside), each ID hemicube drawn with the culled commands must show what
 * the plain draw of every vertex shows: the same surface in every pixel
 * above the base plane (the side faces' lower halves look below it, carry
 * no weight, and show what culling leaves out: counted, not checked), but
 * where the plain draw shows the back of a face of the closed mesh (a
 * silhouette pixel a back face won by rounding), at most 0.2% of them.
 * And culling must cull: from the sphere's own faces nearly the
 * whole sphere lies behind the base, from the floor and the light the
 * far side faces away.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "passes/hemicube.h"
#include "passes/hemicube_cull.h"
#include "passes/hemicube_geometry.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "solvers/gpu_scene.h"

#define RES 64
#define FRAMES 9

typedef struct frame {
    const char *what;
    vec3 origin, z;
    double max_drawn; /* the fraction of triangles the culled draw may keep */
} frame;

static uint32_t find_surface(const xrad_scene *sc, const char *name)
{
    for (uint32_t i = 0; i < sc->surface_count; i++)
        if (!strcmp(sc->surfaces[i].name, name))
            return i;
    CHECK(0, "no surface '%s'", name);
    return 0;
}

static frame frame_at(const xrad_scene *sc, uint32_t s, double u, double v, const char *what,
                      double max_drawn)
{
    vec3 c[4], n;
    scene_surface_world(sc, s, 0, c, &n);
    return (frame){what, v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v), n,
                   max_drawn};
}

static struct gpu_shooter shooter(const frame *f, uint32_t seed)
{
    vec3 a = fabs(f->z.x) < 0.6 ? v3(1, 0, 0) : v3(0, 1, 0);
    vec3 x = v3_norm(v3_cross(a, f->z));
    mat3 r = m3_rotation(f->z, hemicube_rotation(seed));
    x = m3_apply(&r, x);
    return (struct gpu_shooter){
        .pos_area = {(float)f->origin.x, (float)f->origin.y, (float)f->origin.z, 0},
        .normal = {(float)f->z.x, (float)f->z.y, (float)f->z.z, 0},
        .tangent = {(float)x.x, (float)x.y, (float)x.z, 0},
    };
}

/* Renders hemicube `k` of the frames plainly (commands NULL) or with the
 * cull pass; reads the IDs into ids and, culled, the indices drawn. */
static xrad_status render(xrad_context *ctx, const gpu_scene *gs, hemicube_pass *pass,
                          hemicube_cull_pass *cull, const gpu_buffer *frames,
                          const gpu_buffer *commands, uint32_t k, uint32_t *ids,
                          uint32_t *drawn, xrad_error *err)
{
    gpu_cmd c = {0};
    xrad_status s = gpu_cmd_begin(ctx, &c, err);
    if (s)
        return s;
    hemicube_draw d = {.mesh = gpu_scene_hemicube_mesh(gs), .index_count = gs->index_count,
                       .frames = frames, .first = k, .count = 1};
    if (cull) {
        hemicube_cull_record(
            cull, c.cmd,
            &(hemicube_cull_params){.cluster_count = gs->cluster_count, .first = k,
                                    .count_word = 0,
                                    .instances = hemicube_instances_per_hemicube(pass),
                                    .margin = 4 * HEMICUBE_HAIR_FRACTION * gs->diameter});
        gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                           VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_HOST_READ_BIT);
        d.commands = commands;
        d.command_count = gs->cluster_count;
    }
    hemicube_record(pass, c.cmd, &d);
    s = gpu_cmd_run(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
    size_t px = (size_t)HEMICUBE_FACES * RES * RES;
    uint32_t *both = malloc(2 * px * sizeof(uint32_t));
    if (!s && !both)
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "out of memory");
    if (!s)
        s = gpu_readback_image(ctx, hemicube_image(pass), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                               both, 2 * px * sizeof(uint32_t), err);
    for (size_t i = 0; !s && i < px; i++)
        ids[i] = both[2 * i];
    free(both);
    if (!s && cull) {
        const uint32_t *cmds = commands->alloc.mapped;
        *drawn = 0;
        for (uint32_t q = 0; q < gs->cluster_count; q++)
            *drawn += cmds[CULL_COMMAND_WORDS * q];
    }
    return s;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    char path[1024];
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_load(test_source_path("scenes/heavy-sphere.json", path, sizeof path), &sc,
                          &err) == XRAD_OK,
          "heavy-sphere: %s", err.message);
    gpu_scene gs = {0};
    hemicube_pass *pass = NULL;
    hemicube_cull_pass *cull = NULL;
    gpu_buffer frames = {0}, status = {0}, commands = {0};
    uint32_t *plain = malloc((size_t)HEMICUBE_FACES * RES * RES * sizeof(uint32_t));
    uint32_t *culled = malloc((size_t)HEMICUBE_FACES * RES * RES * sizeof(uint32_t));
    if (!sc || !plain || !culled)
        goto done;
    xrad_status s = gpu_scene_create(ctx, sc, 0, 0, &gs, &err);
    CHECK(s == XRAD_OK, "gpu scene: %s", err.message);
    if (s)
        goto done;

    /* The sphere is one closed object: its clusters carry normal cones. */
    uint32_t sphere_obj = UINT32_MAX;
    for (uint32_t o = 0; o < sc->object_count; o++)
        if (!strcmp(sc->objects[o].name, "sphere"))
            sphere_obj = o;
    CHECK(sphere_obj != UINT32_MAX && gs.layout.closed[sphere_obj] &&
              gs.cluster_count > 300,
          "the sphere: object %u, closed %d, %u clusters", sphere_obj,
          sphere_obj != UINT32_MAX ? gs.layout.closed[sphere_obj] : -1, gs.cluster_count);

    /* Frames: the floor's middle and a corner, a wall, the light (facing
     * down), four of the sphere's faces, and the floor under the sphere's
     * rim. */
    frame f[FRAMES];
    uint32_t nf = 0;
    f[nf++] = frame_at(sc, find_surface(sc, "floor"), 0.5, 0.15, "floor, front", 0.85);
    f[nf++] = frame_at(sc, find_surface(sc, "floor"), 0.1, 0.9, "floor, corner", 0.85);
    f[nf++] = frame_at(sc, find_surface(sc, "back"), 0.5, 0.5, "back wall", 0.85);
    f[nf++] = frame_at(sc, find_surface(sc, "light"), 0.5, 0.5, "light", 0.85);
    uint32_t first = sc->objects[sphere_obj].first_surface;
    uint32_t count = sc->objects[sphere_obj].surface_count;
    for (uint32_t k = 0; k < 4; k++) {
        uint32_t s_k = first + (uint32_t)((k * 2654435761u) % count);
        f[nf++] = frame_at(sc, s_k, 0.4, 0.3, "on the sphere", 0.35);
    }
    /* Under the rim: the sphere's box reaches down to the floor. */
    {
        vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
        for (uint32_t s_k = first; s_k < first + count; s_k++) {
            vec3 c[4], n;
            scene_surface_world(sc, s_k, 0, c, &n);
            for (int q = 0; q < 4; q++) {
                lo = v3(fmin(lo.x, c[q].x), fmin(lo.y, c[q].y), fmin(lo.z, c[q].z));
                hi = v3(fmax(hi.x, c[q].x), fmax(hi.y, c[q].y), fmax(hi.z, c[q].z));
            }
        }
        /* Near the bottom corner of the sphere's box, facing up: outside
         * the sphere, inside its box. */
        f[nf] = frame_at(sc, find_surface(sc, "floor"), 0.5, 0.5, "under the rim", 1.0);
        f[nf].origin = v3(lo.x + 0.02 * (hi.x - lo.x), lo.y + 0.01 * (hi.y - lo.y),
                          0.5 * (lo.z + hi.z));
        nf++;
    }

    struct gpu_shooter sh[FRAMES];
    for (uint32_t k = 0; k < nf; k++)
        sh[k] = shooter(&f[k], k);
    if ((s = gpu_buffer_create(ctx, sizeof sh, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                               GPU_MEM_GEOMETRY, &frames, &err)) ||
        (s = gpu_buffer_create(ctx, 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                               GPU_MEM_OTHER, &status, &err)) ||
        (s = gpu_buffer_create(ctx, (VkDeviceSize)gs.cluster_count *
                                   sizeof(VkDrawIndexedIndirectCommand),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                               GPU_MEM_READBACK, GPU_MEM_OTHER, &commands, &err)) ||
        (s = hemicube_create(ctx, gs.diameter, RES, 1, &pass, &err)) ||
        (s = hemicube_cull_create(ctx, &cull, &err))) {
        CHECK(0, "setup: %s", err.message);
        goto done;
    }
    memcpy(frames.alloc.mapped, sh, sizeof sh);
    ((uint32_t *)status.alloc.mapped)[0] = 1; /* one hemicube a shot */
    hemicube_cull_bind(ctx, cull,
                       &(hemicube_cull_buffers){&gs.clusters, &frames, &status, &commands});

    size_t px = (size_t)HEMICUBE_FACES * RES * RES;
    for (uint32_t k = 0; k < nf; k++) {
        uint32_t drawn = 0;
        if ((s = render(ctx, &gs, pass, NULL, &frames, &commands, k, plain, NULL, &err)) ||
            (s = render(ctx, &gs, pass, cull, &frames, &commands, k, culled, &drawn, &err))) {
            CHECK(0, "%s: %s", f[k].what, err.message);
            break;
        }
        uint32_t differ = 0, not_back = 0, below = 0, above = 0;
        for (size_t i = 0; i < px; i++) {
            /* Side faces' rows below the middle look below the base
             * plane: no weight (hemicube_geometry.h), and what lies there
             * is what culling leaves out. */
            size_t face = i / ((size_t)RES * RES), row = i / RES % RES;
            bool horizon_below = face > 0 && row < RES / 2;
            above += !horizon_below;
            if (plain[i] == culled[i])
                continue;
            if (horizon_below) {
                below++;
                continue;
            }
            differ++;
            /* The plain draw showed a face of the closed mesh from behind. */
            uint32_t id = plain[i];
            bool back = false;
            if (id != HEMICUBE_ID_NONE && id - 1 < sc->surface_count) {
                const surface *q = &sc->surfaces[id - 1];
                vec3 c[4], n;
                scene_surface_world(sc, id - 1, 0, c, &n);
                back = q->closed && v3_dot(n, v3_sub(f[k].origin, c[0])) < 0;
            }
            not_back += !back;
        }
        double kept = (double)drawn / gs.index_count;
        fprintf(stderr, "%-20s culled draw keeps %5.1f%% of the triangles; %u of %u pixels "
                "above the base differ (%u not a closed face's back), %u below\n",
                f[k].what, 100 * kept, differ, above, not_back, below);
        CHECK(not_back == 0 && differ <= above / 500,
              "%s: %u pixels differ from the plain draw, %u of them not a closed mesh's back",
              f[k].what, differ, not_back);
        CHECK(kept <= f[k].max_drawn, "%s: the culled draw keeps %.1f%% of the triangles (at "
              "most %.0f%%)", f[k].what, 100 * kept, 100 * f[k].max_drawn);
    }
done:
    hemicube_cull_destroy(ctx, &cull);
    hemicube_destroy(ctx, &pass);
    gpu_buffer_destroy(ctx, &commands);
    gpu_buffer_destroy(ctx, &status);
    gpu_buffer_destroy(ctx, &frames);
    gpu_scene_destroy(ctx, &gs);
    xrad_scene_destroy(&sc);
    free(plain);
    free(culled);
    gpu_test_end(&ctx);
    return test_finish();
}
