/*
 * Gather radiosity (thesis 4.2, Algorithm 4.1; DESIGN.md "Methods"): every
 * bounce renders one radiosity hemicube per element, integrates it against
 * the delta form factors and sets B_e = E_e + rho_e * gathered_e, a Jacobi
 * iteration: the whole bounce reads the atlas of the previous bounce.
 *
 * The emitters' share, sum_l F_el E_l = D_e, comes from the direct pass
 * (passes/direct.h: exact form factors over blocks of each light, each
 * block's visibility by a segment), once per pose; the hemicubes show
 * B - E, the reflected light alone, so that
 *
 *     B_e = E_e + rho_e (D_e + sum_j F_ej (B_j - E_j)).
 *
 * A small bright lamp covers a few hemicube texels, and which ones it
 * covered set an element's direct light 10-14% off either way (a dark hall
 * with one small lamp: element p95 0.136 at 64 x 64, 0.046 at 256 x 256;
 * 0.004 with the direct pass). The first bounce, from B = E, is D alone;
 * each later one, in command buffers of many hemicubes each:
 *
 *     B - E -> atlas (passes/atlas_scatter.h), then per batch of K
 *     elements: radiosity hemicubes (passes/hemicube.h, K per render,
 *     without the clusters none of them can see where the solver culls,
 *     passes/hemicube_cull.h) -> integrate (passes/integrate.h) into the
 *     gathered sums
 *
 * and after the last one the sums are copied to host memory. The host then
 * forms the next B (O(elements), in double precision), measures the power
 * the bounce added and the light still to come (solve()), and hands B to the
 * next bounce's first command buffer, which copies it into place. One host
 * wait per command buffer; nothing per hemicube.
 *
 * Hemicube placement: at the centroid of the element's cell (the part of
 * the surface it stands for, scene.h), not at its sample: samples on a
 * surface's edge lie in the plane of a perpendicular neighbour, which a
 * hemicube there sees edge-on (the same reason as the reconstruct pass's
 * receiver point); the centroid makes each element's gathered value a
 * midpoint estimate of the area average the reference solver computes.
 * The frame's tangent is the surface's u edge turned about the normal by
 * hemicube_rotation (thesis 4.2: random rotation breaks up aliasing).
 *
 * The hemicubes hold (B - E) x scale in fp16, scale = 1 / its largest
 * value in the bounce, so that any light stays inside fp16's range, and
 * the lamps' emission no longer sets the scale of the dim rest; integrate
 * divides it out. After the solve B is in gs.B and the atlas, and Bu is 0:
 * a gathered solution has nothing left to shoot.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "passes/atlas_scatter.h"
#include "passes/direct.h"
#include "passes/hemicube.h"
#include "passes/hemicube_cull.h"
#include "passes/hemicube_geometry.h"
#include "passes/integrate.h"
#include "radiosity.h"
#include "scene/scene_luminaire.h"
#include "solvers/solver.h"

/* Render-target memory for one batch of radiosity hemicubes. */
#define MAX_BATCH_BYTES (64ull << 20)
#define MAX_BATCH 256u
/* Hemicubes per command buffer: a few seconds on lavapipe, well inside the
 * context's wait limit; a fraction of a millisecond each on a GPU. */
#define HEMICUBES_PER_SUBMISSION 2048u
/* Receivers of the direct pass per command buffer: wuson-room's 12,076 in
 * one ran past the 60 s wait on lavapipe (the lamp's blocks against a
 * hierarchy of 3,738 surfaces, each receiver a few milliseconds there). */
#define DIRECT_PER_SUBMISSION 1024u
/* The largest bounce-to-bounce ratio the stop believes: above it the
 * series' tail estimate r / (1 - r) would blow up on noise. */
#define MAX_BOUNCE_RATIO 0.99

typedef struct gather {
    hemicube_pass *hemicube;
    hemicube_cull_pass *cull; /* NULL where the hemicubes draw every cluster */
    gpu_buffer commands;      /* the cull pass's VkDrawIndexedIndirectCommand per cluster */
    integrate_pass *integrate;
    atlas_scatter_pass *scatter;
    direct_pass *direct;
    gpu_buffer frames;   /* struct gpu_shooter[element_count]: one hemicube frame per element */
    gpu_buffer sums;     /* vec4[element_count]: gathered sum_j F_ej B_j */
    gpu_buffer readback; /* the sums, host-visible */
    gpu_buffer upload;   /* B for the next bounce, host-visible */
    uint32_t batch;      /* hemicubes per render */
    double *emission, *albedo; /* 3 per element */
    double *B;                 /* 3 per element, the current bounce */
    double *dB;                /* 3 per element, the last bounce's change */
    double *D;                 /* 3 per element, sum_l F_el E_l: the direct light at the
                                  frames' pose (passes/direct.h) */
    double emitted;            /* sum of area x emission over elements and channels, and the
                                  luminaires' light they reflect (direct_light) */
    double emitted_surfaces;   /* that of the emission alone */
    double frames_time; /* pose the frames were built for */
} gather;

static uint32_t batch_size(const xrad_solver *s)
{
    uint64_t res = s->desc.hemicube_res, msaa = s->desc.msaa;
    uint64_t color = s->desc.radiosity_format == XRAD_RADIOSITY_FP32 ? 16 : 8;
    /* Colour and depth (D32) at msaa samples, plus the resolve target. */
    uint64_t per = res * res * HEMICUBE_FACES * ((color + 4) * msaa + (msaa > 1 ? color : 0));
    uint64_t k = MAX_BATCH_BYTES / per;
    const VkPhysicalDeviceLimits *lim = &s->ctx->props.limits;
    uint32_t layers = (lim->maxImageArrayLayers < lim->maxFramebufferLayers
                           ? lim->maxImageArrayLayers
                           : lim->maxFramebufferLayers) /
                      HEMICUBE_FACES;
    if (k > MAX_BATCH)
        k = MAX_BATCH;
    if (k > layers)
        k = layers;
    if (k > s->gs.element_count)
        k = s->gs.element_count;
    return k ? (uint32_t)k : 1;
}

static void destroy(xrad_solver *s)
{
    gather *g = s->impl;
    if (!g)
        return;
    atlas_scatter_destroy(s->ctx, &g->scatter);
    direct_destroy(s->ctx, &g->direct);
    integrate_destroy(s->ctx, &g->integrate);
    hemicube_destroy(s->ctx, &g->hemicube);
    hemicube_cull_destroy(s->ctx, &g->cull);
    gpu_buffer_destroy(s->ctx, &g->commands);
    gpu_buffer_destroy(s->ctx, &g->upload);
    gpu_buffer_destroy(s->ctx, &g->readback);
    gpu_buffer_destroy(s->ctx, &g->sums);
    gpu_buffer_destroy(s->ctx, &g->frames);
    free(g->emission);
    free(g->albedo);
    free(g->B);
    free(g->dB);
    free(g->D);
    free(g);
    s->impl = NULL;
}

static vec3 bilinear(const vec3 c[4], double u, double v)
{
    return v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v);
}

/* g->D: the direct light at each frame, from the direct pass through the
 * sums buffer (free between bounces), DIRECT_PER_SUBMISSION receivers a
 * submission. */
static xrad_status direct_light(xrad_solver *s, gather *g, xrad_error *err)
{
    uint32_t n = s->gs.element_count;
    xrad_status st = XRAD_OK;
    for (uint32_t first = 0; first < n && !st; first += DIRECT_PER_SUBMISSION) {
        uint32_t count = n - first < DIRECT_PER_SUBMISSION ? n - first : DIRECT_PER_SUBMISSION;
        solver_progress(s, "gather: direct", (double)first / n);
        bool last = first + count == n;
        gpu_cmd c;
        if ((st = gpu_cmd_begin(s->ctx, &c, err)))
            return st;
        gpu_timer_start(s->timer, c.cmd);
        /* The frames' upload and any earlier use of the sums come first. */
        gpu_memory_barrier(c.cmd,
                           VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        gpu_timer_begin(s->timer, c.cmd, "direct");
        direct_record(g->direct, c.cmd,
                      &(direct_draw){.surfaces = &s->gs.surfaces,
                                     .materials = &s->gs.materials,
                                     .frames = &g->frames,
                                     .first = first,
                                     .count = count,
                                     .out = &g->sums,
                                     .bvh_nodes = &s->gs.bvh_nodes,
                                     .bvh_items = &s->gs.bvh_items,
                                     .bvh_depth = s->gs.bvh_depth});
        gpu_timer_end(s->timer, c.cmd);
        if (last) {
            VkBufferCopy region = {0, 0, (VkDeviceSize)n * sizeof(vec4)};
            gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                               VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                               VK_ACCESS_TRANSFER_READ_BIT);
            vkCmdCopyBuffer(c.cmd, g->sums.buffer, g->readback.buffer, 1, &region);
            gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                               VK_ACCESS_TRANSFER_WRITE_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                               VK_ACCESS_HOST_READ_BIT);
        }
        st = solver_submit_wait(s, &c, err);
    }
    if (st || !n)
        return st;
    solver_progress(s, "gather: direct", 1);
    /* The luminaires' direct irradiance joins the emitters' (scene_
     * luminaire.h): the first bounce reflects both, and what it reflects
     * is power the stop compares with, as the emission's. */
    const xrad_scene *scene = s->scene;
    vec3 *lum = scene->luminaire_count ? calloc(n, sizeof(vec3)) : NULL;
    if (scene->luminaire_count && !lum)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gather solver: out of host memory");
    if (lum && (st = scene_luminaire_irradiance(scene, s->desc.time, true, lum, err))) {
        free(lum);
        return st;
    }
    const vec4 *d = g->readback.alloc.mapped;
    uint32_t alarms = 0;
    g->emitted = g->emitted_surfaces;
    for (uint32_t e = 0; e < n; e++) {
        vec3 h = lum ? lum[e] : v3(0, 0, 0);
        g->D[3 * e + 0] = d[e].x + h.x;
        g->D[3 * e + 1] = d[e].y + h.y;
        g->D[3 * e + 2] = d[e].z + h.z;
        alarms += d[e].w > 0;
        if (lum && !s->gs.buried[e])
            g->emitted += scene->elements[e].area *
                          v3_dot(v3_mul(scene_element_albedo(scene, e), h), v3(1, 1, 1));
    }
    free(lum);
    /* A CPU driver (lavapipe) ends every loop of an invocation past 65,535
     * iterations without a word; say where that may have happened rather
     * than hand back a solution darker than it should be. */
    if (alarms && s->ctx->props.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU)
        gpu_log(s->ctx, XRAD_LOG_WARNING,
                "gather: the direct light of %u of %u receivers came near the CPU driver's "
                "shader loop limit (65,535 iterations) and may be too dark there (README "
                "\"Accuracy\")",
                alarms, n);
    return XRAD_OK;
}

/* One frame per element: cell centroid, surface normal, rotated u edge;
 * then the direct light at them. */
static xrad_status build_frames(xrad_solver *s, gather *g, xrad_error *err)
{
    const xrad_scene *scene = s->scene;
    uint32_t n = scene->element_count;
    struct gpu_shooter *f = calloc(n ? n : 1, sizeof(*f));
    if (!f)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gather: out of host memory for frames");
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        const surface *sf = &scene->surfaces[k];
        vec3 c[4], normal;
        scene_surface_world(scene, k, s->desc.time, c, &normal);
        vec3 u = v3_sub(c[1], c[0]);
        vec3 x0 = v3_norm(v3_sub(u, v3_scale(normal, v3_dot(u, normal))));
        xform pose = scene_object_pose(scene, sf->object, s->desc.time);
        for (uint32_t j = 0; j < sf->nv; j++) {
            for (uint32_t i = 0; i < sf->nu; i++) {
                uint32_t e = sf->first_element + j * sf->nu + i;
                struct gpu_shooter *fe = &f[e];
                double cs, ct;
                scene_cell_centre(sf, i, j, &cs, &ct);
                fe->pos_area = gpu_vec4(bilinear(c, cs, ct), scene->elements[e].area);
                /* A normal-mapped element gathers about its mapped normal
                 * (Wallner 3.3): its hemicube tilts with it, and draws its
                 * own surface black (hemicube_desc.own_black). */
                vec3 nm = normal, xm = x0;
                if (scene->element_normal) {
                    nm = v3_norm(xf_dir(&pose, scene->element_normal[e]));
                    xm = v3_sub(x0, v3_scale(nm, v3_dot(x0, nm)));
                    xm = v3_len(xm) > 1e-6 ? v3_norm(xm) : v3_norm(v3_cross(nm, u));
                }
                mat3 r = m3_rotation(nm, hemicube_rotation(s->desc.seed * 0x9e3779b9u + e));
                fe->normal = gpu_vec4(nm, 0);
                fe->tangent = gpu_vec4(m3_apply(&r, xm), 0);
                fe->surface = k;
                fe->i0 = fe->i1 = i;
                fe->j0 = fe->j1 = j;
                fe->hemicube = e;
            }
        }
    }
    xrad_status st = gpu_upload_buffer(s->ctx, &g->frames, 0, f, (n ? n : 1) * sizeof(*f), err);
    free(f);
    if (!st && !(st = direct_light(s, g, err)))
        g->frames_time = s->desc.time;
    return st;
}

static xrad_status create(xrad_solver *s, xrad_error *err)
{
    gather *g = calloc(1, sizeof(*g));
    if (!g)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gather solver: out of host memory");
    s->impl = g;
    struct xrad_context *ctx = s->ctx;
    const xrad_scene *scene = s->scene;
    uint32_t n = scene->element_count;
    size_t nn = n ? n : 1;
    g->emission = malloc(3 * nn * sizeof(double));
    g->albedo = malloc(3 * nn * sizeof(double));
    g->B = malloc(3 * nn * sizeof(double));
    g->dB = calloc(3 * nn, sizeof(double));
    g->D = calloc(3 * nn, sizeof(double));
    uint32_t *lights = malloc((scene->surface_count ? scene->surface_count : 1) * sizeof(*lights));
    uint32_t light_count = 0;
    if (!g->emission || !g->albedo || !g->B || !g->dB || !g->D || !lights) {
        free(lights);
        destroy(s);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gather solver: out of host memory");
    }
    for (uint32_t e = 0; e < n; e++) {
        const material *m = &scene->materials[scene->surfaces[scene->elements[e].surface].material];
        const double em[3] = {m->emission.x, m->emission.y, m->emission.z};
        const vec3 rho = scene_element_albedo(scene, e);
        const double al[3] = {rho.x, rho.y, rho.z};
        for (int c = 0; c < 3; c++) {
            g->emission[3 * e + c] = em[c];
            g->albedo[3 * e + c] = al[c];
            g->emitted_surfaces += scene->elements[e].area * em[c];
        }
    }
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        vec3 em = scene->materials[scene->surfaces[k].material].emission;
        if (em.x > 0 || em.y > 0 || em.z > 0)
            lights[light_count++] = k;
    }
    g->batch = batch_size(s);
    hemicube_desc hd = {
        .kind = HEMICUBE_RADIOSITY,
        .res = s->desc.hemicube_res,
        .max_hemicubes = g->batch,
        .msaa = s->desc.msaa,
        .path = HEMICUBE_PATH_AUTO,
        .diameter = s->gs.diameter > 0 ? s->gs.diameter : 1.0,
        .fp32 = s->desc.radiosity_format == XRAD_RADIOSITY_FP32,
        .cells = true,
        .own_black = true,
    };
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
    xrad_status st;
    if ((st = gpu_buffer_create(ctx, nn * sizeof(struct gpu_shooter), storage, GPU_MEM_DEVICE,
                                GPU_MEM_GEOMETRY, &g->frames, err)) ||
        (st = gpu_buffer_create(ctx, nn * sizeof(vec4), storage, GPU_MEM_DEVICE,
                                GPU_MEM_RADIOSITY, &g->sums, err)) ||
        (st = gpu_buffer_create(ctx, nn * sizeof(vec4), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                GPU_MEM_READBACK, GPU_MEM_STAGING, &g->readback, err)) ||
        (st = gpu_buffer_create(ctx, nn * sizeof(vec4), VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                GPU_MEM_UPLOAD, GPU_MEM_STAGING, &g->upload, err)) ||
        (st = hemicube_create_desc(ctx, &hd, &g->hemicube, err)) ||
        (st = integrate_create(ctx, s->desc.hemicube_res, &g->integrate, err)) ||
        (st = atlas_scatter_create(ctx, &g->scatter, err)) ||
        (st = direct_create(ctx, lights, light_count, &g->direct, err)) ||
        (st = build_frames(s, g, err)))
        goto fail;
    /* Culled only on request: a batch is up to 256 elements of a surface
     * or a few, whose bases cut away little of a room; the dispatch and
     * the draw by commands cost more than they saved (a 320-face ball in
     * a room: 139 s of hemicubes culled against 123 s, the same result). */
    if (s->desc.cull == XRAD_CULL_ON && s->gs.cluster_count > 0) {
        if ((st = gpu_buffer_create(ctx,
                                    (VkDeviceSize)s->gs.cluster_count *
                                        sizeof(VkDrawIndexedIndirectCommand),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                        VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                    GPU_MEM_DEVICE, GPU_MEM_RADIOSITY, &g->commands, err)) ||
            (st = hemicube_cull_create(ctx, &g->cull, err)))
            goto fail;
        /* The host gives the counts: frames stand in for the status. */
        hemicube_cull_bind(ctx, g->cull,
                           &(hemicube_cull_buffers){&s->gs.clusters, &g->frames, &g->frames,
                                                    &g->commands});
    }
    free(lights);
    lights = NULL;
    /* Two timed passes per batch and the scatter, per command buffer. */
    uint32_t intervals = 2 * (HEMICUBES_PER_SUBMISSION / g->batch + 1) + 2;
    if (s->timer->capacity < intervals) {
        gpu_timer_destroy(ctx, &s->timer);
        if ((st = gpu_timer_create(ctx, intervals, &s->timer, err)))
            goto fail;
    }
    s->stats.hemicube_path = hemicube_path_name(g->hemicube);
    return XRAD_OK;

fail:
    free(lights);
    destroy(s);
    xrad_error_prefix(err, "gather solver");
    return st;
}

/* Copies the host's B into gs.B and scatters it into the atlas. */
static void record_b(xrad_solver *s, gather *g, VkCommandBuffer cmd)
{
    VkBufferCopy region = {0, 0, (VkDeviceSize)s->gs.element_count * sizeof(vec4)};
    /* Earlier readers of B and the atlas (the last bounce's hemicubes, the
     * display, readbacks) come first. */
    gpu_memory_barrier(cmd,
                   VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                       VK_PIPELINE_STAGE_TRANSFER_BIT,
                   VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                   VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdCopyBuffer(cmd, g->upload.buffer, s->gs.B.buffer, 1, &region);
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                   VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu_timer_begin(s->timer, cmd, "scatter");
    atlas_scatter_record(g->scatter, cmd,
                         &(atlas_scatter_draw){&s->gs.elements, &s->gs.B, s->gs.element_count,
                                               &s->gs.atlas});
    gpu_timer_end(s->timer, cmd);
    /* The atlas is sampled by the hemicubes' fragment shaders. */
    gpu_image_barrier(cmd, &s->gs.atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                          VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

/* Writes the host's B, as float, to the upload buffer, less the emission
 * where `reflected` (what the bounces' hemicubes show: the direct pass
 * has the emission's share); returns the largest channel value. */
static double stage_b(const xrad_solver *s, gather *g, bool reflected)
{
    vec4 *up = g->upload.alloc.mapped;
    double max_b = 0;
    for (uint32_t e = 0; e < s->gs.element_count; e++) {
        double b[3];
        for (int c = 0; c < 3; c++)
            b[c] = g->B[3 * e + c] - (reflected ? g->emission[3 * e + c] : 0);
        up[e] = (vec4){(float)b[0], (float)b[1], (float)b[2], 0};
        max_b = fmax(max_b, fmax(b[0], fmax(b[1], b[2])));
    }
    return max_b;
}

/* One bounce: every element gathers from the atlas of the host's B; the
 * sums land in g->readback. */
static xrad_status bounce(xrad_solver *s, gather *g, float scale, xrad_error *err)
{
    uint32_t n = s->gs.element_count;
    xrad_status st = XRAD_OK;
    uint32_t first = 0;
    char stage[32];
    snprintf(stage, sizeof(stage), "gather: bounce %u", s->stats.iterations + 1);
    do {
        solver_progress(s, stage, (double)first / n);
        gpu_cmd c;
        if ((st = gpu_cmd_begin(s->ctx, &c, err)))
            return st;
        gpu_timer_start(s->timer, c.cmd);
        if (first == 0)
            record_b(s, g, c.cmd);
        uint32_t end = n - first > HEMICUBES_PER_SUBMISSION ? first + HEMICUBES_PER_SUBMISSION : n;
        while (first < end) {
            uint32_t count = end - first < g->batch ? end - first : g->batch;
            hemicube_draw hd = {
                .mesh = gpu_scene_hemicube_mesh(&s->gs),
                .index_count = s->gs.index_count,
                .frames = &g->frames,
                .first = first,
                .count = count,
                .atlas = &s->gs.atlas,
                .scale = scale,
            };
            gpu_timer_begin(s->timer, c.cmd, "hemicube");
            if (g->cull) {
                /* After the last batch's draw read the commands. */
                gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT, 0,
                                   VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0);
                bool multiview = hemicube_pass_path(g->hemicube) == HEMICUBE_PATH_MULTIVIEW;
                hemicube_cull_record(
                    g->cull, c.cmd,
                    &(hemicube_cull_params){
                        .cluster_count = s->gs.cluster_count,
                        .first = first,
                        .count_word = CULL_NO_COUNT,
                        .count = count,
                        .instances = multiview ? 1 : count * HEMICUBE_FACES,
                        /* as progressive's (record_shot) */
                        .margin = 4 * HEMICUBE_HAIR_FRACTION * s->gs.diameter,
                    });
                gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                                   VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                                   VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
                hd.commands = &g->commands;
                hd.command_count = s->gs.cluster_count;
            }
            hemicube_record(g->hemicube, c.cmd, &hd);
            gpu_timer_end(s->timer, c.cmd);
            integrate_draw id = {
                .hemicubes = hemicube_image(g->hemicube)->view,
                .count = count,
                .out = &g->sums,
                .out_first = first,
                .scale = scale,
            };
            gpu_timer_begin(s->timer, c.cmd, "integrate");
            integrate_record(g->integrate, c.cmd, &id);
            gpu_timer_end(s->timer, c.cmd);
            s->stats.hemicubes += count;
            first += count;
        }
        if (first >= n) {
            VkBufferCopy region = {0, 0, (VkDeviceSize)n * sizeof(vec4)};
            gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                           VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_ACCESS_TRANSFER_READ_BIT);
            vkCmdCopyBuffer(c.cmd, g->sums.buffer, g->readback.buffer, 1, &region);
            gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
        }
        if ((st = solver_submit_wait(s, &c, err)))
            return st;
    } while (first < n);
    solver_progress(s, stage, 1);
    return XRAD_OK;
}

/* B = E + rho * (D + gathered), gathered the sums of the bounce's
 * hemicubes in g->readback (or 0 where `hemicubes` is false: the first
 * bounce, from B = E, reflects D alone); returns the bounce's change in power,
 * sum of area x |dB| over elements and channels: in a Jacobi iteration
 * from B = E that is the power the next bounce spreads, the unshot power
 * of progressive refinement. */
static double update(const xrad_solver *s, gather *g, bool hemicubes)
{
    const vec4 *sum = g->readback.alloc.mapped;
    const vec4 zero = {0, 0, 0, 0};
    double power = 0;
    for (uint32_t e = 0; e < s->gs.element_count; e++) {
        /* A buried element's hemicube sits in the contact and shows what
         * lies past it through the rounding of the depth test: it keeps
         * its emission (scene_find_buried). */
        bool open = !s->gs.buried[e];
        const vec4 h = hemicubes ? sum[e] : zero;
        const double gathered[3] = {h.x + g->D[3 * e], h.y + g->D[3 * e + 1],
                                    h.z + g->D[3 * e + 2]};
        for (int c = 0; c < 3; c++) {
            double b = g->emission[3 * e + c] + (open ? g->albedo[3 * e + c] * gathered[c] : 0);
            g->dB[3 * e + c] = b - g->B[3 * e + c];
            power += s->scene->elements[e].area * fabs(g->dB[3 * e + c]);
            g->B[3 * e + c] = b;
        }
    }
    return power;
}

static xrad_status solve(xrad_solver *s, xrad_error *err)
{
    gather *g = s->impl;
    uint32_t n = s->gs.element_count;
    xrad_status st = XRAD_OK;
    /* The objects moved since the frames were built (xrad_solver_set_time). */
    if (g->frames_time != s->desc.time && (st = build_frames(s, g, err)))
        return st;
    memcpy(g->B, g->emission, 3 * (size_t)n * sizeof(double));
    uint32_t limit = s->desc.bounces ? s->desc.bounces : s->desc.max_iterations;
    if (limit > s->desc.max_iterations)
        limit = s->desc.max_iterations;
    /* The stop: the light still to come, relative to the emitted power,
     * below the threshold, as progressive refinement stops on its unshot
     * power. Bounce k's change P_k shrinks by about the room's mean
     * reflectance r = P_k / P_k-1 per bounce, so the bounces after it add
     * P_k r / (1 - r) (a geometric series). The largest change of one
     * element relative to the largest emission, the rule before, stopped
     * a dark hall lit by a small bright lamp after 3 bounces with its
     * ceiling, lit only by the second bounce on, 3% dark. */
    double residual = 0, last = 0, tail = 0;
    for (uint32_t k = 0; k < limit && n; k++) {
        /* The first bounce is the direct light: B - E is still 0. */
        if (k > 0) {
            double max_b = stage_b(s, g, true);
            float scale = max_b > 0 ? (float)(1.0 / max_b) : 1.0f;
            if ((st = bounce(s, g, scale, err)))
                return st;
        }
        double power = update(s, g, k > 0);
        s->stats.iterations++;
        double r = k > 0 && last > 0 ? fmin(power / last, MAX_BOUNCE_RATIO) : 0;
        tail = r / (1 - r);
        last = power;
        residual = g->emitted > 0 ? power * (k > 0 ? tail : 1) / g->emitted : 0;
        if (!s->desc.bounces && residual < s->desc.threshold)
            break;
    }
    /* What the bounces not made would add, as the same series spread like
     * the last bounce's change (its shape settles on the iteration's
     * dominant mode): second order in the stop's residual. Not with a
     * fixed count of bounces, which asks for exactly those. */
    if (!s->desc.bounces)
        for (size_t i = 0; i < 3 * (size_t)n; i++)
            g->B[i] += g->dB[i] * tail;
    s->stats.residual = residual;
    /* The final B into gs.B and the atlas; nothing is left unshot. */
    stage_b(s, g, false);
    gpu_cmd c;
    if ((st = gpu_cmd_begin(s->ctx, &c, err)))
        return st;
    gpu_timer_start(s->timer, c.cmd);
    if (n) {
        record_b(s, g, c.cmd);
        vkCmdFillBuffer(c.cmd, s->gs.Bu.buffer, 0, VK_WHOLE_SIZE, 0);
    }
    /* B, Bu and the atlas are complete for later submissions and the host. */
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                   VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_SHADER_WRITE_BIT,
                   VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                   VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT |
                       VK_ACCESS_HOST_READ_BIT);
    if ((st = solver_submit_wait(s, &c, err)))
        return st;
    solver_collect_times(s);
    return XRAD_OK;
}

const solver_ops gather_ops = {create, solve, destroy, NULL};
