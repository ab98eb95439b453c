/*
 * Progressive refinement radiosity (thesis 4.3, Algorithm 4.2 with the
 * improvements of 4.3.3; DESIGN.md "Methods"). From B = Bu = E, each shot
 * selects the surface with the largest unshot power, splits it into
 * shooting patches sized from that power, renders an ID hemicube per patch
 * and lets every element gather from all patches of the shot:
 *
 *     select (passes/select.h) -> ID hemicubes (passes/hemicube.h, instance
 *     count from the select pass's indirect draw) -> reconstruct
 *     (passes/reconstruct.h, indirect dispatch)
 *
 * desc.batch shots go into one command buffer with the barriers between
 * them; the host submits it, waits once, and reads the select pass's status
 * word once, to stop when the largest unshot power fell to desc.threshold x
 * the largest emitted power and all of it, over every surface, to
 * desc.unshot x the emitted (the select pass then records nothing more), or
 * after desc.max_iterations shots. Nothing is read back per shot. Solves
 * from B = E shoot in groups (select.h): a mesh's faces many a shot.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "passes/hemicube.h"
#include "passes/hemicube_cull.h"
#include "passes/hemicube_geometry.h"
#include "passes/reconstruct.h"
#include "passes/select.h"
#include "radiosity.h"
#include "select_shared.h"
#include "solvers/progressive.h"
#include "solvers/solver.h"

/* Hemicube image memory a solver may hold, all shooters of a shot together. */
#define MAX_HEMICUBE_BYTES (256ull << 20)
#define MAX_FF_BYTES (64ull << 20)
/* A shot's group (spirv/select.comp): at most this many shooters in all,
 * each joining surface of at most GROUP_ELEMENTS elements. */
#define GROUP_SHOOTERS 32u
#define GROUP_ELEMENTS 64u

struct progressive {
    select_pass *select;
    hemicube_pass *hemicube;
    reconstruct_pass *reconstruct;
    gpu_buffer shooters; /* struct gpu_shooter[max_shooters] */
    gpu_buffer ff, norm; /* the reconstruct pass's conservation (reconstruct.h) */
    gpu_buffer shot;     /* the shot surface's Bu by element (select.h) */
    gpu_buffer status;   /* struct select_status, host-visible: read once per batch */
    hemicube_cull_pass *cull; /* NULL: desc.cull off, or no clusters */
    gpu_buffer commands; /* the cull pass's VkDrawIndexedIndirectCommand per cluster */
    hemicube_cull_params cull_params;
    uint32_t max_shooters;
    bool static_only;
    bool redistributed; /* PROGRESSIVE_REDISTRIBUTED */
    bool square_root;   /* progressive_set_square_root_rule */
    select_params select_params;
    reconstruct_params reconstruct_params;
    uint32_t recorded_index_count; /* the host count the last shot's hemicubes drew */
};

/* Shooters one shot may need: the largest kx x ky of the patch rule over
 * the scene's surfaces, within the image-array and memory limits. */
static uint32_t shooter_capacity(const xrad_solver *s)
{
    uint32_t mp = s->desc.max_patches, need = 1;
    for (uint32_t k = 0; k < s->scene->surface_count; k++) {
        const surface *sf = &s->scene->surfaces[k];
        uint32_t n = (sf->nu < mp ? sf->nu : mp) * (sf->nv < mp ? sf->nv : mp);
        if (s->gs.fixed_patches && s->gs.fixed_patches[3 * k])
            n = s->gs.fixed_patches[3 * k] * s->gs.fixed_patches[3 * k + 1];
        need = n > need ? n : need;
    }
    /* Room for a group where there are surfaces to join one. */
    uint32_t group = s->scene->surface_count < GROUP_SHOOTERS ? s->scene->surface_count
                                                                : GROUP_SHOOTERS;
    need = group > need ? group : need;
    uint32_t layers = s->ctx->props.limits.maxImageArrayLayers / HEMICUBE_FACES;
    uint64_t per = 8ull * s->desc.hemicube_res * s->desc.hemicube_res * HEMICUBE_FACES;
    uint64_t by_memory = MAX_HEMICUBE_BYTES / per;
    if (need > layers)
        need = layers;
    if (need > by_memory)
        need = (uint32_t)by_memory;
    return need ? need : 1;
}

void progressive_destroy(xrad_solver *s, progressive **engine)
{
    progressive *p = engine ? *engine : NULL;
    if (!p)
        return;
    reconstruct_destroy(s->ctx, &p->reconstruct);
    hemicube_cull_destroy(s->ctx, &p->cull);
    gpu_buffer_destroy(s->ctx, &p->commands);
    hemicube_destroy(s->ctx, &p->hemicube);
    select_destroy(s->ctx, &p->select);
    gpu_buffer_destroy(s->ctx, &p->status);
    gpu_buffer_destroy(s->ctx, &p->shooters);
    gpu_buffer_destroy(s->ctx, &p->ff);
    gpu_buffer_destroy(s->ctx, &p->norm);
    gpu_buffer_destroy(s->ctx, &p->shot);
    free(p);
    *engine = NULL;
}

xrad_status progressive_create(xrad_solver *s, uint32_t flags, progressive **out,
                               xrad_error *err)
{
    bool static_only = (flags & PROGRESSIVE_STATIC_ONLY) != 0;
    *out = NULL;
    progressive *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "progressive solver: out of host memory");
    struct xrad_context *ctx = s->ctx;
    const gpu_scene *gs = &s->gs;
    p->max_shooters = shooter_capacity(s);
    p->static_only = static_only;
    p->redistributed = (flags & PROGRESSIVE_REDISTRIBUTED) != 0;
    xrad_status st;
    if ((st = gpu_buffer_create(ctx, (VkDeviceSize)p->max_shooters * sizeof(struct gpu_shooter),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_RADIOSITY, &p->shooters, err)) ||
        (st = gpu_buffer_create(ctx, sizeof(struct select_status),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                    VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                GPU_MEM_READBACK, GPU_MEM_RADIOSITY, &p->status, err)) ||
        (st = select_create(ctx, gs->surface_count, &p->select, err)) ||
        (st = hemicube_create(ctx, gs->diameter, s->desc.hemicube_res, p->max_shooters, &p->hemicube,
                              err)))
        goto fail;
    /* Conservation keeps every form factor of a shot: up to 64 MiB, else
     * the single-pass transfer. */
    uint64_t ff_bytes = (uint64_t)p->max_shooters * (gs->element_count ? gs->element_count : 1) *
                        sizeof(float);
    bool conserve = s->desc.conserve != XRAD_CONSERVE_OFF && ff_bytes <= MAX_FF_BYTES &&
                    ff_bytes <= ctx->props.limits.maxStorageBufferRange;
    if ((st = reconstruct_create(ctx, conserve && s->desc.conserve == XRAD_CONSERVE_FAR,
                                 &p->reconstruct, err)))
        goto fail;
    if ((st = gpu_buffer_create(ctx, conserve ? ff_bytes : 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                GPU_MEM_DEVICE, GPU_MEM_RADIOSITY, &p->ff, err)) ||
        (st = gpu_buffer_create(ctx, (VkDeviceSize)p->max_shooters * 2 * sizeof(float),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_RADIOSITY, &p->norm, err)) ||
        (st = gpu_buffer_create(ctx,
                                (VkDeviceSize)(select_shot_capacity(s->scene) +
                                               GROUP_SHOOTERS * GROUP_ELEMENTS) *
                                    sizeof(vec4),
                                VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_RADIOSITY, &p->shot, err)))
        goto fail;
    /* Culling: one command per cluster (the static ones alone where the
     * shots see C alone). */
    uint32_t clusters = static_only ? gs->static_cluster_count : gs->cluster_count;
    if (solver_culls(s, clusters)) {
        if ((st = gpu_buffer_create(ctx,
                                    (VkDeviceSize)clusters * sizeof(VkDrawIndexedIndirectCommand),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                        VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                    GPU_MEM_DEVICE, GPU_MEM_RADIOSITY, &p->commands, err)) ||
            (st = hemicube_cull_create(ctx, &p->cull, err)))
            goto fail;
        hemicube_cull_bind(ctx, p->cull,
                           &(hemicube_cull_buffers){&gs->clusters, &p->shooters, &p->status,
                                                    &p->commands});
        bool multiview = hemicube_pass_path(p->hemicube) == HEMICUBE_PATH_MULTIVIEW;
        p->cull_params = (hemicube_cull_params){
            .cluster_count = clusters,
            .count_word = offsetof(struct select_status, shooter_count) / 4,
            .instances = multiview ? 1 : 0,
            .instance_word = offsetof(struct select_status, draw_instance_count) / 4,
        };
    }
    /* Three timed passes per shot in one command buffer. */
    if (s->timer->capacity < 3 * s->desc.batch + 1) {
        gpu_timer_destroy(ctx, &s->timer);
        if ((st = gpu_timer_create(ctx, 3 * s->desc.batch + 1, &s->timer, err)))
            goto fail;
    }
    select_bind(ctx, p->select,
                &(select_buffers){&gs->surfaces, &gs->elements, &gs->Bu, &p->shooters,
                                  &p->status, &p->shot});
    reconstruct_bind(ctx, p->reconstruct,
                     &(reconstruct_bindings){&gs->surfaces, &gs->elements, &gs->materials,
                                             &gs->B, &gs->Bu, &p->shooters, &p->status,
                                             hemicube_ids_view(p->hemicube), &p->ff, &p->norm,
                                             &p->shot, &gs->bvh_nodes, &gs->bvh_items});
    p->select_params = (select_params){
        .element_count = gs->element_count,
        .max_patches = s->desc.max_patches,
        .max_shooters = p->max_shooters,
        .draw_index_count = static_only ? gs->static_index_count : gs->index_count,
        .instances_per_hemicube = hemicube_instances_per_hemicube(p->hemicube),
        .reconstruct_group = reconstruct_group_size(),
        .seed = s->desc.seed,
        .threshold = s->desc.threshold,
        .group_elements = GROUP_ELEMENTS,
        .shot_first = select_shot_capacity(s->scene),
        /* as buried_mask() in spirv/reconstruct.comp */
        .buried_mask = (flags & PROGRESSIVE_REDISTRIBUTED) ? 0u
                       : static_only                      ? GPU_ELEMENT_BURIED
                                                          : GPU_ELEMENT_BURIED_ANY,
    };
    p->reconstruct_params = (reconstruct_params){
        .element_count = gs->element_count,
        .hemicube_res = s->desc.hemicube_res,
        .subdivide_ratio = s->desc.subdivide_ratio,
        .exact_texel_only = s->desc.id_check == XRAD_ID_CHECK_EXACT,
        .conserve = conserve,
        .max_shooters = p->max_shooters,
        .static_only = static_only,
        .redistributed = (flags & PROGRESSIVE_REDISTRIBUTED) != 0,
    };
    s->stats.hemicube_path = hemicube_path_name(p->hemicube);
    *out = p;
    return XRAD_OK;

fail:
    progressive_destroy(s, &p);
    return st;
}

/* How far a solve has come, for desc.progress: the unshot power's way
 * down to the stop, on a log scale (it falls about geometrically), by the
 * criterion furthest from met. */
static double progress(const progressive *p, const struct select_status *status)
{
    double f = 1;
    if (status->max_power > 0 && p->select_params.threshold > 0 &&
        p->select_params.threshold < 1 && status->power > 0)
        f = fmin(f, log(status->power / status->max_power) / log(p->select_params.threshold));
    if (status->max_unshot > 0 && p->select_params.unshot_share > 0 &&
        p->select_params.unshot_share < 1 && status->unshot > 0)
        f = fmin(f, log(status->unshot / status->max_unshot) /
                        log(p->select_params.unshot_share));
    return f < 0 ? 0 : f > 0.999 ? 0.999 : f;
}

/* One shot of Algorithm 4.2. */
static void record_shot(xrad_solver *s, progressive *p, VkCommandBuffer cmd)
{
    const VkPipelineStageFlags draw_reads = VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                                            VK_PIPELINE_STAGE_VERTEX_SHADER_BIT;
    /* The previous shot's reconstruct wrote B and Bu, which select reads and
     * clears; its hemicube draw and reconstruct read the shooters and the
     * status that select rewrites. */
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | draw_reads,
                   VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
    gpu_timer_begin(s->timer, cmd, "select");
    select_record(p->select, cmd, &p->select_params);
    gpu_timer_end(s->timer, cmd);
    /* Shooters and status feed the indirect draw, the vertex shader, the
     * indirect dispatch and the reconstruct shader; the ID image the last
     * reconstruct sampled is about to be drawn over. */
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                   draw_reads | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                       VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                       VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT,
                   VK_ACCESS_INDIRECT_COMMAND_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
    gpu_timer_begin(s->timer, cmd, "hemicube");
    if (p->cull) {
        /* Past the origin's hair (hemicube.h) and float rounding of the
         * bounds, at the diameter of the pose (gpu_scene_pose). */
        p->cull_params.margin = 4 * HEMICUBE_HAIR_FRACTION * s->gs.diameter;
        hemicube_cull_record(p->cull, cmd, &p->cull_params);
        gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                           VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                           VK_ACCESS_INDIRECT_COMMAND_READ_BIT);
    }
    hemicube_mesh mesh = gpu_scene_hemicube_mesh(&s->gs);
    /* The count the select pass writes into the indirect command: C alone
     * under cross. The multiview path draws this host count, not the
     * command's. It was the whole scene's: on an NVIDIA H200 (multiview,
     * 2026-12-04) M shadowed C twice, in the shots and in cross's X, and
     * a moving ball's faces came out at 0.27-0.38 of the CPU reference; a
     * lavapipe build whose command drew M too gave the same figures. */
    p->recorded_index_count = p->select_params.draw_index_count;
    hemicube_record_ids(p->hemicube, cmd, &mesh, p->recorded_index_count, &p->shooters,
                        &p->status,
                        offsetof(struct select_status, draw_index_count),
                        p->cull ? &p->commands : NULL, p->cull_params.cluster_count);
    gpu_timer_end(s->timer, cmd);
    /* The ID hemicubes are complete before any element looks them up. */
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                   VK_ACCESS_SHADER_READ_BIT);
    gpu_timer_begin(s->timer, cmd, "reconstruct");
    reconstruct_record(p->reconstruct, cmd, &p->reconstruct_params, &p->status,
                       offsetof(struct select_status, dispatch_x));
    gpu_timer_end(s->timer, cmd);
}

xrad_status progressive_run(xrad_solver *s, progressive *p, bool restart, uint32_t max_shots,
                            xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    struct select_status *status = p->status.alloc.mapped;
    xrad_status st;
    if (restart) {
        /* gpu_scene_reset uploads with one-shot copies, each submitted and
         * waited for (or none where B and Bu are host-visible): count them
         * from the context's submission counter. */
        uint64_t before = ctx->timeline_value;
        if ((st = gpu_scene_reset(ctx, &s->gs, p->static_only, err)))
            return st;
        s->stats.submissions += (uint32_t)(ctx->timeline_value - before);
        s->stats.host_waits += (uint32_t)(ctx->timeline_value - before);
        memset(status, 0, sizeof(*status));
    } else {
        /* Continue: keep max_power (the emitted power, the threshold's
         * scale) and let the select pass shoot again. */
        status->converged = 0;
    }
    p->reconstruct_params.conserve_fixed = restart;
    p->reconstruct_params.near_blocks = !p->static_only || restart;
    /* A redistribution removes again what the shots after a restart give,
     * frame after frame, and those must see as it does; the restart's own
     * shots it meets once, when their receivers' view changes, a bounded
     * difference (the solve's power-rule patches against the fixed ones
     * already differ so). So the restart shoots as plain progressive
     * refinement does (contact, buried receivers, near patches block by
     * block): incremental's first solve in room 1 of tests/solvers/rooms.c
     * was 2.8% below the CPU reference over all, element p95 0.10, with
     * the redistribution's terms (0.036 now). */
    if (p->redistributed) {
        p->reconstruct_params.redistributed = !restart;
        p->select_params.buried_mask = restart ? GPU_ELEMENT_BURIED_ANY : 0u;
    }
    /* Cross's iterations after a restart shoot the signed changes a pose
     * brings, with the linear patch rule (select_params.linear_rule); the
     * restart itself is C's plain solve, with the square root's finer
     * patches (cornell-box's ceiling 1.045 of the CPU reference with the
     * linear rule). */
    p->select_params.linear_rule = p->static_only && !restart && !p->square_root;
    /* A solve from B = E (and plain progressive refinement) stops also on
     * all that is unshot, and shoots in groups (select.comp says why);
     * the iterations after a redistribution shoot the signed changes of a
     * pose, a few surfaces, to the threshold alone. */
    bool from_emission = restart || (!p->static_only && !p->redistributed);
    p->select_params.unshot_share = from_emission ? s->desc.unshot : 0;
    p->select_params.group_shooters = from_emission ? GROUP_SHOOTERS : 0;
    uint32_t limit = max_shots ? max_shots : s->desc.max_iterations;
    uint32_t first = status->selections, first_patches = status->patches,
             first_surfaces = status->surfaces;
    uint32_t selected = 0;
    bool done = false;
    /* A continuation after a redistribution often needs only a few shots,
     * and every shot recorded after convergence still costs its (empty)
     * passes: start small and double up to desc.batch. */
    uint32_t batch = restart ? s->desc.batch : (s->desc.batch < 4 ? s->desc.batch : 4);
    while (!done) {
        uint32_t n = limit - selected;
        n = n < batch ? n : batch;
        double t0 = solver_now_ms();
        gpu_cmd c;
        if ((st = gpu_cmd_begin(ctx, &c, err)))
            return st;
        gpu_timer_start(s->timer, c.cmd);
        for (uint32_t k = 0; k < n; k++)
            record_shot(s, p, c.cmd);
        /* B, Bu and the status are complete for the host (the status read
         * below) and for later submissions (gpu_scene_read, the next batch). */
        gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_ACCESS_HOST_READ_BIT | VK_ACCESS_MEMORY_READ_BIT |
                           VK_ACCESS_MEMORY_WRITE_BIT);
        if (!(st = gpu_cmd_submit(ctx, &c, err))) {
            s->stats.submissions++;
            st = gpu_cmd_wait(ctx, &c, err);
            s->stats.host_waits++;
        }
        gpu_cmd_destroy(ctx, &c);
        if (st || (st = gpu_timer_collect(ctx, s->timer, err)))
            return st;
        /* Double the batch up to desc.batch while a submission takes under
         * a second, halve it past a quarter of the context's wait limit: a
         * batch of many patches over many elements on a slow device
         * (lavapipe under load: 32 shots of 576 patches over 5230 elements
         * ran past the 60 s) must stay well below it. */
        double took = (solver_now_ms() - t0) * 1e-3;
        if (took > 0.25e-9 * (double)ctx->wait_timeout_ns && batch > 1)
            batch /= 2;
        else if (took < 1.0)
            batch = 2 * batch < s->desc.batch ? 2 * batch : s->desc.batch;
        selected = status->selections - first;
        done = status->converged || selected >= limit;
        solver_progress(s, "progressive", done ? 1 : progress(p, status));
    }
    s->stats.iterations += status->selections - first;
    s->stats.shots += status->patches - first_patches;
    s->stats.hemicubes += status->patches - first_patches;
    s->stats.residual = status->max_power > 0 ? status->power / status->max_power : 0;
    s->stats.unshot = status->max_unshot > 0 ? status->unshot / status->max_unshot : 0;
    s->stats.surfaces_shot += status->surfaces - first_surfaces;
    return XRAD_OK;
}

static void destroy(xrad_solver *s)
{
    progressive *p = s->impl;
    progressive_destroy(s, &p);
    s->impl = NULL;
}

static xrad_status create(xrad_solver *s, xrad_error *err)
{
    progressive *p = NULL;
    xrad_status st = progressive_create(s, 0, &p, err);
    s->impl = p;
    return st;
}

static xrad_status solve(xrad_solver *s, xrad_error *err)
{
    xrad_status st = progressive_run(s, s->impl, true, 0, err);
    solver_collect_times(s);
    return st;
}

const solver_ops progressive_ops = {create, solve, destroy, NULL};

void progressive_set_square_root_rule(progressive *p, bool square_root)
{
    p->square_root = square_root;
}

void progressive_draw_counts(const progressive *p, uint32_t *host, uint32_t *command)
{
    const struct select_status *st = p->status.alloc.mapped;
    *host = p->recorded_index_count;
    *command = st->draw_index_count;
}
