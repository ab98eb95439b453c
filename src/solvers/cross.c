/*
 * Cross redistribution radiosity (thesis 3.3 and 4.5, Algorithms 4.4 and
 * 4.5; DESIGN.md "CRR, one redistribution"). The first solve is
 * progressive refinement; every advance moves the dynamic set M from the
 * pose in hand to a new one in one redistribution that renders hemicubes
 * for the patches of M only, then continues with progressive iterations
 * for the unshot radiosity it created (thesis 4.5.3).
 *
 * One redistribution, in one command buffer (thesis order, DESIGN.md):
 *
 *   1. T.shot = area mean of B - Bu per patch of M (cross_update SHOT);
 *      the atlas gets B - Bu of C, 0 on M (SHOT_C + atlas scatter); M is
 *      reset to its emission (RESET).
 *   2. Per patch, at the new pose: an ID hemicube on its front; a shot
 *      radiosity hemicube at its coarse sample (the gather of R_g(C, M));
 *      a low-resolution shot radiosity + distance hemicube on its back,
 *      static geometry only (thesis 4.5.2). At the old pose the same ID and
 *      back hemicubes are needed. The ID hemicubes are by default those of
 *      the last redistribution, whose new pose this is (desc.cross_recompute
 *      = 0: what was inserted is removed through the same form factors,
 *      thesis 6.2, and each frame renders 4 hemicubes per patch instead of
 *      5); with cross_recompute, or when there is no last redistribution at
 *      this pose, they are rendered first, before the objects move. The
 *      back hemicubes of the old pose are drawn again every time: what lies
 *      behind a patch has been shot further since they were drawn, and the
 *      light given back where the patch leaves must be that of now
 *      (spirv/cross_reconstruct.comp). Where memory allows (the pairs
 *      buffer, elements x patches), the last redistribution's new-pose F
 *      of every pair is kept too and read instead of evaluated again.
 *   3. R_g(C, M): integrate the gather hemicubes; the elements of M take
 *      B = E + rho x (their surface's coarse samples, interpolated), Bu = 0
 *      (GATHERED), and T.total = area mean of B per patch (TOTAL).
 *   4-5. R_p(M, M) and R_p(M, C) + R_x(C, C) in one pass (cross_reconstruct).
 *   6. Progressive iterations (solvers/progressive.h), desc.frame_shots.
 *      They shoot the surfaces of M with the same fixed patches and
 *      hemicube rotations (dynamic_patches_fix), so that what step 5
 *      removes next frame is, block for block, what was shot.
 *
 * The old and new pose's hemicubes live in two slots that alternate: slot
 * `slot` holds the pose in hand. B^s of C does not change within a
 * redistribution (thesis 3.3.4): everything between step 1 and step 5 is
 * one submission with nothing else in it.
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

/* The per-pair cache of the last redistribution's terms grows with
 * elements x patches; above this the old pose is evaluated again from the
 * kept hemicubes instead (the same numbers, twice the work). */
#define MAX_PAIR_BYTES (64ull << 20)

typedef struct cross {
    progressive *prog;
    dynamic_patches dp;
    uint32_t P; /* patches of M */
    hemicube_pass *ids[2], *back[2], *gather;
    integrate_pass *integrate;
    atlas_scatter_pass *scatter;
    cross_update_pass *update;
    cross_reconstruct_pass *reconstruct;
    gpu_buffer patches;       /* struct cross_patch[P] */
    gpu_buffer values;        /* struct cross_value[P] */
    gpu_buffer gathered;      /* vec4[P] */
    gpu_buffer surface_patch; /* uint[surface_count] */
    gpu_buffer shot;          /* vec4[element_count]: B - Bu of C, 0 on M */
    gpu_buffer frames;        /* gpu_shooter[2 slots][3 tables][P], host-written */
    gpu_buffer quads;         /* struct cross_quad[2 slots][P], host-written */
    gpu_buffer pairs;         /* float[P x element_count]: last new-pose F per pair;
                                 empty where that would exceed MAX_PAIR_BYTES */
    double diameter;          /* m, the scale of the hemicubes' near plane and distances,
                                 fixed at create (the posed scene's diameter changes) */
    uint32_t slot;            /* the slot holding the pose in hand */
    bool cached;              /* ids[slot] and back[slot] were rendered at the pose in hand */
    double scale;
} cross;

static void destroy(xrad_solver *s)
{
    cross *c = s->impl;
    if (!c)
        return;
    struct xrad_context *ctx = s->ctx;
    progressive_destroy(s, &c->prog);
    for (int k = 0; k < 2; k++) {
        hemicube_destroy(ctx, &c->ids[k]);
        hemicube_destroy(ctx, &c->back[k]);
    }
    hemicube_destroy(ctx, &c->gather);
    integrate_destroy(ctx, &c->integrate);
    atlas_scatter_destroy(ctx, &c->scatter);
    cross_update_destroy(ctx, &c->update);
    cross_reconstruct_destroy(ctx, &c->reconstruct);
    gpu_buffer *buffers[] = {&c->patches, &c->values, &c->gathered, &c->surface_patch,
                             &c->shot,    &c->frames, &c->quads,          &c->pairs};
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

static xrad_status create_pairs(xrad_solver *s, cross *c, xrad_error *err)
{
    uint64_t bytes = (uint64_t)c->P * s->gs.element_count * sizeof(float);
    if (bytes > MAX_PAIR_BYTES || bytes > s->ctx->props.limits.maxStorageBufferRange)
        return XRAD_OK;
    return gpu_buffer_create(s->ctx, bytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                             GPU_MEM_REDISTRIBUTION, &c->pairs, err);
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
    xrad_status st;
    if ((st = gpu_buffer_create(ctx, P * sizeof(struct cross_patch), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->patches, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(struct cross_value), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->values, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(vec4), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->gathered, err)) ||
        (st = gpu_buffer_create(ctx, ns * sizeof(uint32_t), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->surface_patch, err)) ||
        (st = gpu_buffer_create(ctx, (size_t)gs->element_count * sizeof(vec4), storage,
                                GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &c->shot, err)) ||
        (st = gpu_buffer_create(ctx, 2 * CROSS_FRAME_TABLES * P * sizeof(struct gpu_shooter),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                                GPU_MEM_REDISTRIBUTION, &c->frames, err)) ||
        (st = gpu_buffer_create(ctx, 2 * P * sizeof(struct cross_quad),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                                GPU_MEM_REDISTRIBUTION, &c->quads, err)) ||
        (st = create_pairs(s, c, err)) ||
        (st = gpu_upload_buffer(ctx, &c->patches, 0, c->dp.patches,
                                P * sizeof(struct cross_patch), err)) ||
        (st = gpu_upload_buffer(ctx, &c->surface_patch, 0, c->dp.surface_patch,
                                gs->surface_count * sizeof(uint32_t), err)))
        return st;
    for (int k = 0; k < 2; k++)
        if ((st = hemicube_create_desc(ctx, &ids, &c->ids[k], err)) ||
            (st = hemicube_create_desc(ctx, &back, &c->back[k], err)))
            return st;
    if ((st = hemicube_create_desc(ctx, &gather, &c->gather, err)) ||
        (st = integrate_create(ctx, d->hemicube_res, &c->integrate, err)) ||
        (st = atlas_scatter_create(ctx, &c->scatter, err)) ||
        (st = cross_update_create(ctx, &c->update, err)) ||
        (st = cross_reconstruct_create(ctx, &c->reconstruct, err)))
        return st;
    cross_update_bind(ctx, c->update,
                      &(cross_update_bindings){&gs->surfaces, &gs->elements, &gs->materials,
                                               &gs->B, &gs->Bu, &c->patches, &c->values,
                                               &c->gathered, &c->shot, &c->surface_patch});
    cross_reconstruct_bind(
        ctx, c->reconstruct,
        &(cross_reconstruct_bindings){
            &gs->surfaces, &gs->elements, &gs->materials, &gs->B, &gs->Bu, &c->values, &c->frames,
            &c->quads,
            {hemicube_ids_view(c->ids[0]), hemicube_ids_view(c->ids[1])},
            {hemicube_image(c->back[0])->view, hemicube_image(c->back[1])->view},
            c->pairs.buffer ? &c->pairs : &c->gathered});
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
        (c->dp.count && (st = dynamic_patches_fix(s->ctx, &s->gs, &c->dp, err))) ||
        (st = progressive_create(s, &c->prog, err)))
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

/* The patches' frames and quads at scene time t into slot `slot`. The GPU
 * must not be reading that slot. */
static void write_slot(xrad_solver *s, cross *c, uint32_t slot, double t)
{
    struct gpu_shooter *f = c->frames.alloc.mapped;
    struct cross_quad *q = c->quads.alloc.mapped;
    size_t table = (size_t)slot * CROSS_FRAME_TABLES;
    dynamic_patches_pose(s->scene, &c->dp, t, s->desc.seed,
                         f + (table + CROSS_FRAMES_FRONT) * c->P,
                         f + (table + CROSS_FRAMES_BACK) * c->P,
                         f + (table + CROSS_FRAMES_GATHER) * c->P, q + (size_t)slot * c->P);
}

static xrad_status solve(xrad_solver *s, xrad_error *err)
{
    cross *c = s->impl;
    c->cached = false;
    xrad_status st = progressive_run(s, c->prog, true, 0, err);
    /* The pose in hand, for the first redistribution from it. */
    if (!st && c->P)
        write_slot(s, c, c->slot, s->desc.time);
    solver_collect_times(s);
    return st;
}

static uint32_t frames_first(const cross *c, uint32_t slot, uint32_t table)
{
    return (slot * CROSS_FRAME_TABLES + table) * c->P;
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

/* The atlas gets B - Bu of C (0 on M), ready for the radiosity hemicubes. */
static void record_shot_atlas(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    cross_update_record(c->update, cmd, CROSS_UPDATE_SHOT_C, c->P, s->gs.element_count);
    compute_barrier(cmd);
    atlas_scatter_record(c->scatter, cmd,
                         &(atlas_scatter_draw){&s->gs.elements, &c->shot, s->gs.element_count,
                                               &s->gs.atlas});
    gpu_image_barrier(cmd, &s->gs.atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
}

/* The back hemicubes (static geometry, shot radiosity) of slot `slot`,
 * whose frames are written. */
static void record_back(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t slot)
{
    const gpu_scene *gs = &s->gs;
    gpu_timer_begin(s->timer, cmd, "cross.back");
    hemicube_record(c->back[slot], cmd,
                    &(hemicube_draw){.vertices = &gs->vertices,
                                     .vertex_count = gs->static_vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, slot, CROSS_FRAMES_BACK),
                                     .count = c->P, .atlas = &gs->atlas,
                                     .scale = (float)c->scale});
    gpu_timer_end(s->timer, cmd);
    s->stats.hemicubes += c->P;
}

/* The ID hemicubes on the patches' fronts and the back hemicubes of slot
 * `slot`, whose frames are written. */
static void record_pose_hemicubes(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t slot)
{
    const gpu_scene *gs = &s->gs;
    gpu_timer_begin(s->timer, cmd, "cross.hemicube");
    hemicube_record(c->ids[slot], cmd,
                    &(hemicube_draw){.vertices = &gs->vertices, .vertex_count = gs->vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, slot, CROSS_FRAMES_FRONT),
                                     .count = c->P});
    gpu_timer_end(s->timer, cmd);
    s->stats.hemicubes += c->P;
    record_back(s, c, cmd, slot);
}

static xrad_status run(xrad_solver *s, gpu_cmd *cmd, xrad_error *err)
{
    full_barrier(cmd->cmd);
    return solver_submit_wait(s, cmd, err);
}

/* The old pose's hemicubes, rendered at the pose in hand (before it moves)
 * from the frames slot c->slot holds since that pose was taken: the scene
 * may have changed since (xrad_scene_set_offset). */
static xrad_status render_old_pose(xrad_solver *s, cross *c, xrad_error *err)
{
    gpu_cmd cmd;
    xrad_status st = gpu_cmd_begin(s->ctx, &cmd, err);
    if (st)
        return st;
    gpu_timer_start(s->timer, cmd.cmd);
    full_barrier(cmd.cmd);
    record_shot_atlas(s, c, cmd.cmd);
    record_pose_hemicubes(s, c, cmd.cmd, c->slot);
    return run(s, &cmd, err);
}

/* The redistribution's first part: M's values leave the solution, the
 * new pose's front and back hemicubes, and with `back_old` the old pose's
 * back hemicubes again, with the shot radiosity of C in hand (the ones kept
 * from the last redistribution show C as it was then). */
static void record_update(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t slot,
                          bool back_old)
{
    uint32_t n = s->gs.element_count, P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.update");
    cross_update_record(c->update, cmd, CROSS_UPDATE_SHOT, P, n);
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_RESET, P, n);
    compute_barrier(cmd);
    record_shot_atlas(s, c, cmd);
    gpu_timer_end(s->timer, cmd);
    if (back_old)
        record_back(s, c, cmd, 1 - slot);
    record_pose_hemicubes(s, c, cmd, slot);
}

/* R_g(C, M) at the patches' coarse samples. */
static void record_gather(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t slot)
{
    const gpu_scene *gs = &s->gs;
    uint32_t n = gs->element_count, P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.gather");
    hemicube_record(c->gather, cmd,
                    &(hemicube_draw){.vertices = &gs->vertices, .vertex_count = gs->vertex_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, slot, CROSS_FRAMES_GATHER),
                                     .count = P, .atlas = &gs->atlas,
                                     .scale = (float)c->scale});
    s->stats.hemicubes += P;
    integrate_record(c->integrate, cmd,
                     &(integrate_draw){.hemicubes = hemicube_image(c->gather)->view, .count = P,
                                       .out = &c->gathered, .scale = (float)c->scale});
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_GATHERED, P, n);
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_TOTAL, P, n);
    compute_barrier(cmd);
    gpu_timer_end(s->timer, cmd);
}

/* The cross projection of elements [first, first + count). */
static void record_reconstruct(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t slot,
                               uint32_t pairs, uint32_t first, uint32_t count)
{
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.reconstruct");
    cross_reconstruct_record(c->reconstruct, cmd,
                             &(cross_reconstruct_params){
                                 .element_count = s->gs.element_count,
                                 .patch_count = c->P,
                                 .hemicube_res = s->desc.hemicube_res,
                                 .back_res = s->desc.back_res,
                                 .grid = s->desc.cross_grid,
                                 .bilinear = !s->desc.back_nearest,
                                 .new_slot = slot,
                                 .subdivide_ratio = s->desc.subdivide_ratio,
                                 .back_scale = c->scale,
                                 .diameter = c->diameter,
                                 .pairs = pairs,
                                 .first = first,
                                 .count = count,
                                 .exact_texel_only = s->desc.id_check == XRAD_ID_CHECK_EXACT,
                             });
    gpu_timer_end(s->timer, cmd);
}

/* The redistribution to the pose in slot `slot`: one submission, or with
 * desc.slice_elements, one for the hemicubes, one for the gather and one
 * per slice of the cross projection, each waited for, so that another
 * thread's work on the queue (a display) gets in between. */
static xrad_status redistribute(xrad_solver *s, cross *c, uint32_t slot, uint32_t pairs,
                                bool back_old, xrad_error *err)
{
    uint32_t n = s->gs.element_count, slice = s->desc.slice_elements;
    gpu_cmd cmd;
    xrad_status st = gpu_cmd_begin(s->ctx, &cmd, err);
    if (st)
        return st;
    gpu_timer_start(s->timer, cmd.cmd);
    record_update(s, c, cmd.cmd, slot, back_old);
    if (slice) {
        if ((st = run(s, &cmd, err)) || (st = gpu_cmd_begin(s->ctx, &cmd, err)))
            return st;
        gpu_timer_start(s->timer, cmd.cmd);
    }
    record_gather(s, c, cmd.cmd, slot);
    for (uint32_t first = 0; first < n;) {
        uint32_t count = slice && slice < n - first ? slice : n - first;
        if (slice) {
            if ((st = run(s, &cmd, err)) || (st = gpu_cmd_begin(s->ctx, &cmd, err)))
                return st;
            gpu_timer_start(s->timer, cmd.cmd);
        }
        record_reconstruct(s, c, cmd.cmd, slot, pairs, first, count);
        first += count;
    }
    return run(s, &cmd, err);
}

static xrad_status advance(xrad_solver *s, double time, xrad_error *err)
{
    cross *c = s->impl;
    xrad_status st;
    double t0 = solver_now_ms();
    if (c->P) {
        /* The old pose's form factors: kept per pair, or from the kept ID
         * hemicubes, or (thesis, or nothing kept yet) rendered now; its back
         * hemicubes are drawn again in any case. */
        bool reuse = c->cached && !s->desc.cross_recompute;
        uint32_t pairs = c->pairs.buffer ? CROSS_PAIRS_WRITE | (reuse ? CROSS_PAIRS_READ : 0) : 0;
        if (!reuse && (st = render_old_pose(s, c, err)))
            return st;
        if ((st = gpu_scene_pose(s->ctx, &s->gs, time, err)))
            return st;
        uint32_t slot = 1 - c->slot;
        write_slot(s, c, slot, time);
        c->cached = false;
        if ((st = redistribute(s, c, slot, pairs, reuse, err)))
            return st;
        c->slot = slot;
        c->cached = true;
    } else if ((st = gpu_scene_pose(s->ctx, &s->gs, time, err))) {
        return st;
    }
    s->stats.redistribute_ms = solver_now_ms() - t0;
    st = progressive_run(s, c->prog, false, s->desc.frame_shots, err);
    solver_collect_times(s);
    return st;
}

const solver_ops cross_ops = {create, solve, destroy, advance};
