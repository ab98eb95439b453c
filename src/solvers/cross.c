/*
 * Cross redistribution radiosity (thesis 3.3 and 4.5, Algorithms 4.4 and
 * 4.5; DESIGN.md "CRR, one redistribution"). Every redistribution puts
 * the dynamic set M at the pose in hand, rendering hemicubes for the
 * patches of M only, and the progressive iterations after it shoot the
 * unshot radiosity it created (thesis 4.5.3).
 *
 * One redistribution, in one command buffer:
 *
 *   1. M is reset to its emission with nothing unshot (RESET); the atlas
 *      gets B - Bu of C, 0 on M (SHOT_C + atlas scatter).
 *   2. Per patch: an ID hemicube on its front; a shot radiosity hemicube at
 *      its coarse sample (the gather of R_g(C, M)); a low-resolution shot
 *      radiosity + distance hemicube on its back, static geometry only
 *      (thesis 4.5.2).
 *   3. R_g(C, M): integrate the gather hemicubes; the elements of M take
 *      B = E + rho x (their surface's coarse samples, interpolated)
 *      (GATHERED), and T.total = area mean of B per patch (TOTAL).
 *   4. R_p(M, M) into B of M, and TOTAL again: what M shoots to C holds
 *      one bounce inside M.
 *   5. R_p(M, C) + R_x(C, C): every element of C gets the new pose's terms
 *      of eq. 3.3.1 in place of the ones the last redistribution gave it,
 *      which each element keeps (cross_reconstruct.comp): the old pose's
 *      terms are removed exactly as they were inserted.
 *   6. Progressive iterations (solvers/progressive.h), desc.frame_shots,
 *      on C alone: their hemicubes do not draw M, and M shoots nothing in
 *      them (its light is in its patches' totals, step 5).
 *
 * Why step 6 leaves M out (thesis 3.3.4: "if the shot radiosity B^s
 * changes (for a patch in C) in between the redistribution iterations,
 * this change is not negated thus introducing error which accumulates";
 * the thesis avoids it by removing M before each progressive iteration and
 * inserting it after, and finds that too costly): with M in the shots'
 * hemicubes, light shot between two redistributions is blocked by the ID
 * hemicube at the shooter, while the next redistribution gives back what
 * the cross projection says M blocked of it. The two differ by their
 * discretisation, and on a box sliding to and fro for 10,000 frames the
 * power rose to 1.11 times the bound E / (1 - rho). Here the progressive
 * iterations solve C alone, and M enters only as the source X of step 5,
 * replaced whole at every redistribution: the solution is always that of
 * C with the source of the pose in hand, and nothing adds up. The cost is
 * nothing: one redistribution per frame, three hemicubes per patch.
 *
 * The first solve is progressive refinement of C alone, then rounds of
 * (redistribution, progressive iterations to the threshold): each round
 * puts in what M does to the light the last one left.
 *
 * The hemicubes hold shot radiosity x scale in fp16, scale = 1/2 of the
 * bound E_max / (1 - rho_max) on any radiosity (room for B - Bu > B where Bu
 * is negative), so no emission leaves fp16's range; gathered sums and
 * projected radiosity divide it out. The gpu_scene's atlas holds the shot
 * radiosity of C, not B, in this method.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "cross_shared.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "passes/atlas_scatter.h"
#include "passes/cross_reconstruct.h"
#include "passes/cross_update.h"
#include "passes/hemicube.h"
#include "passes/hemicube_geometry.h"
#include "passes/integrate.h"
#include "radiosity.h"
#include "solvers/dynamic_patches.h"
#include "solvers/progressive.h"
#include "solvers/solver.h"

/* Rounds of (redistribution, progressive iterations) in the first solve. */
#define SOLVE_ROUNDS 4

typedef struct cross {
    progressive *prog;
    dynamic_patches dp;
    uint32_t P; /* patches of M */
    hemicube_pass *ids, *back, *gather;
    integrate_pass *integrate;
    atlas_scatter_pass *scatter;
    cross_update_pass *update;
    cross_reconstruct_pass *reconstruct;
    gpu_buffer patches;       /* struct cross_patch[P] */
    gpu_buffer values;        /* struct cross_value[P] */
    gpu_buffer gathered;      /* vec4[P] */
    gpu_buffer surface_patch; /* uint[surface_count] */
    gpu_buffer shot;          /* vec4[element_count]: B - Bu of C, 0 on M */
    gpu_buffer inserted;      /* vec4[element_count]: what step 5 last added to C */
    gpu_buffer frames;        /* gpu_shooter[3 tables][P], host-written */
    gpu_buffer quads;         /* struct cross_quad[P], host-written */
    double diameter;          /* m, the scale of the hemicubes' near plane and distances,
                                 fixed at create (the posed scene's diameter changes) */
    double scale;
} cross;

static void destroy(xrad_solver *s)
{
    cross *c = s->impl;
    if (!c)
        return;
    struct xrad_context *ctx = s->ctx;
    progressive_destroy(s, &c->prog);
    hemicube_destroy(ctx, &c->ids);
    hemicube_destroy(ctx, &c->back);
    hemicube_destroy(ctx, &c->gather);
    integrate_destroy(ctx, &c->integrate);
    atlas_scatter_destroy(ctx, &c->scatter);
    cross_update_destroy(ctx, &c->update);
    cross_reconstruct_destroy(ctx, &c->reconstruct);
    gpu_buffer *buffers[] = {&c->patches, &c->values,   &c->gathered, &c->surface_patch,
                             &c->shot,    &c->inserted, &c->frames,   &c->quads};
    for (size_t k = 0; k < sizeof(buffers) / sizeof(buffers[0]); k++)
        gpu_buffer_destroy(ctx, buffers[k]);
    dynamic_patches_free(&c->dp);
    free(c);
    s->impl = NULL;
}

/* The bound E_max / (1 - rho_max) on any radiosity of the scene. */
static double radiosity_bound(const xrad_scene *scene)
{
    double e = 0, rho = 0;
    for (uint32_t m = 0; m < scene->material_count; m++) {
        const material *mt = &scene->materials[m];
        e = fmax(e, fmax(mt->emission.x, fmax(mt->emission.y, mt->emission.z)));
        rho = fmax(rho, fmax(mt->albedo.x, fmax(mt->albedo.y, mt->albedo.z)));
    }
    return e > 0 ? e / (1 - rho) : 1;
}

static xrad_status create_redistribution(xrad_solver *s, cross *c, xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    const gpu_scene *gs = &s->gs;
    const xrad_solver_desc *d = &s->desc;
    uint32_t P = c->P;
    double diameter = c->diameter = gs->diameter > 0 ? gs->diameter : 1.0;
    hemicube_desc ids = {.kind = HEMICUBE_IDS, .res = d->hemicube_res, .max_hemicubes = P,
                         .msaa = 1, .path = HEMICUBE_PATH_AUTO, .diameter = diameter,
                         .redistribution = true};
    hemicube_desc back = {.kind = HEMICUBE_RADIOSITY, .res = d->back_res, .max_hemicubes = P,
                          .msaa = d->back_msaa, .path = HEMICUBE_PATH_AUTO,
                          .diameter = diameter,
                          .fp32 = d->radiosity_format == XRAD_RADIOSITY_FP32,
                          .redistribution = true};
    /* One sample, as the thesis's combined ID + radiosity hemicube (5.3.1). */
    hemicube_desc gather = {.kind = HEMICUBE_RADIOSITY, .res = d->hemicube_res,
                            .max_hemicubes = P, .msaa = 1, .path = HEMICUBE_PATH_AUTO,
                            .diameter = diameter,
                            .fp32 = d->radiosity_format == XRAD_RADIOSITY_FP32,
                            .redistribution = true};
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    size_t ns = gs->surface_count ? gs->surface_count : 1;
    size_t element_bytes = (size_t)gs->element_count * sizeof(vec4);
    xrad_status st;
    if ((st = gpu_buffer_create(ctx, P * sizeof(struct cross_patch), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->patches, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(struct cross_value), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->values, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(vec4), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->gathered, err)) ||
        (st = gpu_buffer_create(ctx, ns * sizeof(uint32_t), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->surface_patch, err)) ||
        (st = gpu_buffer_create(ctx, element_bytes, storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->shot, err)) ||
        (st = gpu_buffer_create(ctx, element_bytes, storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->inserted, err)) ||
        (st = gpu_buffer_create(ctx, CROSS_FRAME_TABLES * P * sizeof(struct gpu_shooter),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                                GPU_MEM_REDISTRIBUTION, &c->frames, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(struct cross_quad),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                                GPU_MEM_REDISTRIBUTION, &c->quads, err)) ||
        (st = gpu_upload_buffer(ctx, &c->patches, 0, c->dp.patches,
                                P * sizeof(struct cross_patch), err)) ||
        (st = gpu_upload_buffer(ctx, &c->surface_patch, 0, c->dp.surface_patch,
                                gs->surface_count * sizeof(uint32_t), err)) ||
        (st = hemicube_create_desc(ctx, &ids, &c->ids, err)) ||
        (st = hemicube_create_desc(ctx, &back, &c->back, err)) ||
        (st = hemicube_create_desc(ctx, &gather, &c->gather, err)) ||
        (st = integrate_create(ctx, d->hemicube_res, &c->integrate, err)) ||
        (st = atlas_scatter_create(ctx, &c->scatter, err)) ||
        (st = cross_update_create(ctx, &c->update, err)) ||
        (st = cross_reconstruct_create(ctx, &c->reconstruct, err)))
        return st;
    cross_update_bind(ctx, c->update,
                      &(cross_update_bindings){&gs->surfaces, &gs->elements, &gs->materials,
                                               &gs->B, &gs->Bu, &c->patches, &c->values,
                                               &c->gathered, &c->shot, &c->surface_patch});
    cross_reconstruct_bind(ctx, c->reconstruct,
                           &(cross_reconstruct_bindings){
                               &gs->surfaces, &gs->elements, &gs->materials, &gs->B, &gs->Bu,
                               &c->values, &c->frames, &c->quads, hemicube_ids_view(c->ids),
                               hemicube_image(c->back)->view, &c->inserted});
    c->scale = 0.5 / radiosity_bound(s->scene);
    return XRAD_OK;
}

static xrad_status create(xrad_solver *s, xrad_error *err)
{
    cross *c = calloc(1, sizeof(*c));
    if (!c)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "cross solver: out of host memory");
    s->impl = c;
    xrad_status st;
    if ((st = dynamic_patches_build(s->scene, s->desc.max_patches, &c->dp, err)) ||
        (st = progressive_create(s, true, &c->prog, err)))
        goto fail;
    c->P = c->dp.count;
    const VkPhysicalDeviceLimits *lim = &s->ctx->props.limits;
    uint32_t layers = lim->maxImageArrayLayers < lim->maxFramebufferLayers
                          ? lim->maxImageArrayLayers
                          : lim->maxFramebufferLayers;
    if ((uint64_t)c->P * HEMICUBE_FACES > layers) {
        st = xrad_fail(err, XRAD_ERROR_INPUT,
                       "%s: the dynamic objects have %u cross patches (cross_density, or "
                       "max_patches %u per side where none is given); the device draws at most "
                       "%u hemicubes at once",
                       s->scene->path, c->P, s->desc.max_patches, layers / HEMICUBE_FACES);
        goto fail;
    }
    /* A scene without dynamic objects needs no redistribution state. */
    if (c->P && (st = create_redistribution(s, c, err)))
        goto fail;
    return XRAD_OK;

fail:
    destroy(s);
    xrad_error_prefix(err, "cross solver");
    return st;
}

/* Everything earlier in the queue (other submissions, host writes) is done
 * with and visible to everything later. */
static void full_barrier(VkCommandBuffer cmd)
{
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_MEMORY_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT,
                       VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                       VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT |
                           VK_ACCESS_HOST_READ_BIT);
}

/* Compute writes (B, Bu, values, the shot values) -> compute reads and writes. */
static void compute_barrier(VkCommandBuffer cmd)
{
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

static uint32_t frames_first(const cross *c, uint32_t table)
{
    return table * c->P;
}

/* Steps 1 and 2: M reset, the atlas holding B - Bu of C (0 on M), and the
 * ID and back hemicubes of the patches at the pose in hand, whose frames
 * are written. */
static void record_hemicubes(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    const gpu_scene *gs = &s->gs;
    uint32_t n = gs->element_count, P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.update");
    cross_update_record(c->update, cmd, CROSS_UPDATE_RESET, P, n);
    cross_update_record(c->update, cmd, CROSS_UPDATE_SHOT_C, P, n);
    compute_barrier(cmd);
    atlas_scatter_record(c->scatter, cmd,
                         &(atlas_scatter_draw){&gs->elements, &c->shot, n, &gs->atlas});
    gpu_image_barrier(cmd, &gs->atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu_timer_end(s->timer, cmd);
    gpu_timer_begin(s->timer, cmd, "cross.hemicube");
    hemicube_record(c->ids, cmd,
                    &(hemicube_draw){.vertices = &gs->vertices, .vertex_count = gs->vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, CROSS_FRAMES_FRONT), .count = P});
    gpu_timer_end(s->timer, cmd);
    gpu_timer_begin(s->timer, cmd, "cross.back");
    hemicube_record(c->back, cmd,
                    &(hemicube_draw){.vertices = &gs->vertices,
                                     .vertex_count = gs->static_vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, CROSS_FRAMES_BACK), .count = P,
                                     .atlas = &gs->atlas, .scale = (float)c->scale});
    gpu_timer_end(s->timer, cmd);
    s->stats.hemicubes += 2 * P;
}

/* Steps 3 and 4: R_g(C, M) at the patches' coarse samples, then R_p(M, M). */
static void record_gather(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    const gpu_scene *gs = &s->gs;
    uint32_t n = gs->element_count, P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.gather");
    hemicube_record(c->gather, cmd,
                    &(hemicube_draw){.vertices = &gs->vertices, .vertex_count = gs->vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, CROSS_FRAMES_GATHER), .count = P,
                                     .atlas = &gs->atlas, .scale = (float)c->scale});
    s->stats.hemicubes += P;
    integrate_record(c->integrate, cmd,
                     &(integrate_draw){.hemicubes = hemicube_image(c->gather)->view, .count = P,
                                       .out = &c->gathered, .scale = (float)c->scale});
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_GATHERED, P, n);
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_TOTAL, P, n);
    gpu_timer_end(s->timer, cmd);
}

/* Phase `phase` of the cross reconstruct pass for elements [first, first + count). */
static void record_reconstruct(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t phase,
                               uint32_t first, uint32_t count)
{
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.reconstruct");
    cross_reconstruct_record(c->reconstruct, cmd,
                             &(cross_reconstruct_params){
                                 .phase = phase,
                                 .element_count = s->gs.element_count,
                                 .patch_count = c->P,
                                 .hemicube_res = s->desc.hemicube_res,
                                 .back_res = s->desc.back_res,
                                 .grid = s->desc.cross_grid,
                                 .bilinear = !s->desc.back_nearest,
                                 .subdivide_ratio = s->desc.subdivide_ratio,
                                 .back_scale = c->scale,
                                 .diameter = c->diameter,
                                 .first = first,
                                 .count = count,
                                 .exact_texel_only = s->desc.id_check == XRAD_ID_CHECK_EXACT,
                             });
    gpu_timer_end(s->timer, cmd);
}

static xrad_status run(xrad_solver *s, gpu_cmd *cmd, xrad_error *err)
{
    full_barrier(cmd->cmd);
    return solver_submit_wait(s, cmd, err);
}

/* Steps 1-5 at scene time t: one submission, or with desc.slice_elements,
 * one for the hemicubes and the gather and one per slice of step 5, each
 * waited for, so that another thread's work on the queue (a display) gets
 * in between. B^s of C does not change within it (thesis 3.3.4): nothing
 * else is in those submissions, and the progressive iterations come after. */
static xrad_status redistribute(xrad_solver *s, cross *c, double t, xrad_error *err)
{
    uint32_t n = s->gs.element_count, slice = s->desc.slice_elements;
    struct gpu_shooter *f = c->frames.alloc.mapped;
    dynamic_patches_pose(s->scene, &c->dp, t, s->desc.seed, f + CROSS_FRAMES_FRONT * c->P,
                         f + CROSS_FRAMES_BACK * c->P, f + CROSS_FRAMES_GATHER * c->P,
                         c->quads.alloc.mapped);
    gpu_cmd cmd;
    xrad_status st = gpu_cmd_begin(s->ctx, &cmd, err);
    if (st)
        return st;
    gpu_timer_start(s->timer, cmd.cmd);
    record_hemicubes(s, c, cmd.cmd);
    record_gather(s, c, cmd.cmd);
    record_reconstruct(s, c, cmd.cmd, CROSS_RECONSTRUCT_M, 0, n);
    full_barrier(cmd.cmd);
    cross_update_record(c->update, cmd.cmd, CROSS_UPDATE_TOTAL, c->P, n);
    for (uint32_t first = 0; first < n;) {
        uint32_t count = slice && slice < n - first ? slice : n - first;
        if (slice) {
            if ((st = run(s, &cmd, err)) || (st = gpu_cmd_begin(s->ctx, &cmd, err)))
                return st;
            gpu_timer_start(s->timer, cmd.cmd);
        }
        record_reconstruct(s, c, cmd.cmd, CROSS_RECONSTRUCT_C, first, count);
        first += count;
    }
    return run(s, &cmd, err);
}

/* Nothing inserted yet: the start of a solve. */
static xrad_status clear_inserted(xrad_solver *s, cross *c, xrad_error *err)
{
    size_t bytes = (size_t)s->gs.element_count * sizeof(vec4);
    void *zero = calloc(1, bytes ? bytes : 1);
    if (!zero)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "cross solver: out of host memory");
    xrad_status st = gpu_upload_buffer(s->ctx, &c->inserted, 0, zero, bytes, err);
    free(zero);
    return st;
}

static xrad_status solve(xrad_solver *s, xrad_error *err)
{
    cross *c = s->impl;
    xrad_status st = c->P ? clear_inserted(s, c, err) : XRAD_OK;
    if (!st)
        st = progressive_run(s, c->prog, true, 0, err);
    for (int round = 0; c->P && !st && round < SOLVE_ROUNDS; round++)
        if (!(st = redistribute(s, c, s->desc.time, err)))
            st = progressive_run(s, c->prog, false, 0, err);
    solver_collect_times(s);
    return st;
}

static xrad_status advance(xrad_solver *s, double time, xrad_error *err)
{
    cross *c = s->impl;
    double t0 = solver_now_ms();
    xrad_status st = gpu_scene_pose(s->ctx, &s->gs, time, err);
    if (!st && c->P)
        st = redistribute(s, c, time, err);
    if (st)
        return st;
    s->stats.redistribute_ms = solver_now_ms() - t0;
    st = progressive_run(s, c->prog, false, s->desc.frame_shots, err);
    solver_collect_times(s);
    return st;
}

const solver_ops cross_ops = {create, solve, destroy, advance};
