/*
 * Incremental radiosity (thesis 4.4, Algorithm 4.3 with the reshooting of
 * 4.4.1; DESIGN.md "Methods"). The first solve is progressive refinement
 * (solvers/progressive.h). Each frame then redistributes the solution in
 * hand from the old pose to the new one, in the order of thesis 4.4.1
 * "Overview", and continues with progressive iterations.
 *
 * Consistent patches. What a redistribution removes (-shot) must be what
 * was shot, patch for patch and hemicube texel for texel; else every frame
 * leaves a little behind and repeated frames drift. So both sets shoot
 * with fixed patches everywhere: M's layout (solvers/dynamic_patches.h) is
 * fixed on the gpu_scene at create, before progressive_create (as the
 * cross method does), and C's after each solve, cut by the select pass's
 * power rule (thesis 4.3.3) from each surface's converged total power
 * (fix_static_layout). From then on the select pass shoots every surface
 * with those patches, and patch k of a surface turns its hemicube by
 * patch_rotation(seed, patch_first + k) in every pass that shoots it,
 * progressive iterations and the redistribution alike (thesis 4.2's
 * random rotation, fixed per patch rather than per shot). The solve
 * itself, before the fix, shoots C by power as progressive refinement
 * does, and sees as it does (progressive_run's restart): what its shots
 * left in the solution differs from what the fixed
 * patches remove by the discretisation of one subdivision against
 * another, a bounded error that a hidden receiver carries until it is
 * seen again, not one that adds up per frame.
 *
 *  1. Old pose (Algorithm 4.3 lines 3-5, first part of R_p(M, C)): copy
 *     the hemicube vertices (the old geometry of M, for step 3), capture
 *     each fixed patch of M's shot radiosity and shoot it negated to the
 *     elements of C through an ID hemicube at the patch's old front frame
 *     (dynamic_patches_pose), with the old form factor.
 *  2. gpu_scene_pose(new time). M's patches at the new pose shoot their
 *     radiosity of the old pose once more, not into C's solution but into
 *     m_light: M's light on C at the new pose, which the progressive
 *     iterations of step 4 give C anew, and what M will see of its own
 *     light (M -> C -> M) in step 3.
 *  3. M back to its emission (line 6), with the luminaires' direct light
 *     at the new pose, and C's elements take the change in theirs as
 *     unshot radiosity (solvers/luminaire_change.h). For every surface q
 *     of C (lines 7-20), its fixed patches (line 8); the GPU captures each
 *     patch's shot, unshot and total area means, then clears C's unshot
 *     radiosity (line 9). Per patch s two ID hemicubes with the same
 *     frame, one drawn with the old vertices and one with the new (lines
 *     11-12; only M moved), and the reconstruction: elements of C take
 *     -shot, +total or +unshot as the two hemicubes say (line 17, R_p(C,
 *     C)), and m_light once more reflected where the new hemicube sees
 *     them. The patches of all surfaces of C are captured before any of
 *     them shoots, so their order does not matter; what C receives here is
 *     unshot radiosity the progressive iterations shoot on. Then, after
 *     every patch of C (line 14 moved after line 17), the elements of M
 *     receive rho F (B + m_light) of C's patches through new ID
 *     hemicubes: R_p(C, M) reshot from C as it is at the new pose, with
 *     M's light in it (incremental_reconstruct.comp c_light says what the
 *     thesis's order lost: 0.63 of the CPU reference at a sliding box's
 *     foot).
 *  4. Progressive iterations (desc.frame_shots): R_p(M, M) and the second
 *     part of R_p(M, C), as thesis 4.4.1 defers them. C does not shoot M
 *     there: M took all of C's light in step 3 and is reset every frame
 *     (spirv/reconstruct.comp form_factor).
 *
 * The shooters of C go through the GPU in chunks of at most CHUNK_MAX, each
 * chunk's hemicubes in two hemicube passes (old, new) of that many layers
 * blocks, so hemicube memory stays bounded whatever the scene; several
 * chunks share a command buffer. No frame reads anything back. A scene
 * without dynamic objects allocates none of this: a frame is then a pose
 * and more progressive iterations.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/error.h"
#include "core/vec.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "incremental_shared.h"
#include "passes/hemicube.h"
#include "passes/hemicube_geometry.h"
#include "passes/incremental_reconstruct.h"
#include "hemicube_shared.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "solvers/dynamic_patches.h"
#include "solvers/luminaire_change.h"
#include "solvers/progressive.h"
#include "solvers/solver.h"

/* Shooters per chunk: hemicubes per pass. */
#define CHUNK_MAX 64u
/* Image memory of one of the two hemicube passes. */
#define MAX_CHUNK_BYTES (64ull << 20)
/* Hemicubes per command buffer: a few seconds on lavapipe, well inside the
 * context's wait limit (as gather.c). */
#define HEMICUBES_PER_SUBMISSION 2048u

typedef struct incremental {
    progressive *engine;
    /* Redistribution state: all zero without dynamic objects. */
    dynamic_patches dp;
    uint32_t m_count;    /* shooters of M: the fixed patches, table entries [0, m_count) */
    uint32_t c_capacity; /* most shooters C's layout can have */
    uint32_t c_count;    /* C's fixed patches, entries [m_count, m_count + c_count) */
    bool c_fixed;        /* C's layout is fixed on the gpu_scene (after a solve) */
    uint32_t chunk;      /* shooters per chunk */
    uint32_t chunks_per_submission;
    hemicube_pass *old_ids, *new_ids;
    incremental_reconstruct_pass *pass;
    gpu_buffer prev_vertices; /* struct gpu_hemicube_vertex[vertex_count]: the old pose */
    gpu_buffer prev_surfaces; /* struct gpu_surface[surface_count]: the old pose */
    gpu_buffer m_light;       /* vec4[element_count]: M's light on C at the new pose */
    gpu_buffer shooters;      /* struct gpu_shooter[m_count + c_capacity], device */
    gpu_buffer staging;       /* the same, host-written, copied in per step */
    gpu_buffer values;        /* struct incr_value[m_count + c_capacity] */
    gpu_buffer power;         /* float[surface_count], host-visible: read once per solve */
    uint32_t *fixed;          /* [3 * surface_count]: gpu_scene_fix_patches' table */
    luminaire_change lum;     /* the luminaires' light, base: the pose's in the solution */
} incremental;

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint32_t min_u32(uint32_t a, uint32_t b) { return a < b ? a : b; }

static void destroy_state(xrad_solver *s, incremental *inc)
{
    incremental_reconstruct_destroy(s->ctx, &inc->pass);
    hemicube_destroy(s->ctx, &inc->new_ids);
    hemicube_destroy(s->ctx, &inc->old_ids);
    gpu_buffer_destroy(s->ctx, &inc->power);
    gpu_buffer_destroy(s->ctx, &inc->values);
    gpu_buffer_destroy(s->ctx, &inc->staging);
    gpu_buffer_destroy(s->ctx, &inc->shooters);
    gpu_buffer_destroy(s->ctx, &inc->prev_vertices);
    gpu_buffer_destroy(s->ctx, &inc->prev_surfaces);
    gpu_buffer_destroy(s->ctx, &inc->m_light);
    luminaire_change_destroy(s->ctx, &inc->lum);
    free(inc->fixed);
    inc->fixed = NULL;
    dynamic_patches_free(&inc->dp);
}

static void destroy(xrad_solver *s)
{
    incremental *inc = s->impl;
    if (!inc)
        return;
    destroy_state(s, inc);
    progressive_destroy(s, &inc->engine);
    free(inc);
    s->impl = NULL;
}

/* The redistribution's passes and buffers, for a scene with dynamic surfaces. */
static xrad_status create_state(xrad_solver *s, incremental *inc, xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    const gpu_scene *gs = &s->gs;
    const xrad_scene *scene = s->scene;
    xrad_status st;
    inc->m_count = inc->dp.count;
    inc->fixed = calloc(3 * (size_t)(gs->surface_count ? gs->surface_count : 1), sizeof(uint32_t));
    if (!inc->fixed)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "incremental solver: out of host memory");
    /* The patch rule gives a surface at most max_patches and its element
     * count per side. */
    uint32_t mp = s->desc.max_patches;
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        const surface *sf = &scene->surfaces[k];
        if (!scene->objects[sf->object].dynamic)
            inc->c_capacity += min_u32(sf->nu, mp) * min_u32(sf->nv, mp);
    }
    uint32_t most = inc->m_count > inc->c_capacity ? inc->m_count : inc->c_capacity;
    uint64_t per = 8ull * s->desc.hemicube_res * s->desc.hemicube_res * HEMICUBE_FACES;
    uint64_t by_memory = MAX_CHUNK_BYTES / per;
    uint32_t layers = ctx->props.limits.maxImageArrayLayers / HEMICUBE_FACES;
    inc->chunk = min_u32(min_u32(CHUNK_MAX, most ? most : 1), layers);
    if (inc->chunk > by_memory)
        inc->chunk = (uint32_t)by_memory;
    if (!inc->chunk)
        inc->chunk = 1;
    inc->chunks_per_submission = HEMICUBES_PER_SUBMISSION / (2 * inc->chunk);
    if (!inc->chunks_per_submission)
        inc->chunks_per_submission = 1;

    uint32_t table = inc->m_count + inc->c_capacity;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    hemicube_desc ids = {
        .kind = HEMICUBE_IDS,
        .res = s->desc.hemicube_res,
        .max_hemicubes = inc->chunk,
        .msaa = 1,
        .path = HEMICUBE_PATH_AUTO,
        .diameter = gs->diameter > 0 ? gs->diameter : 1.0,
        .redistribution = true,
    };
    if ((st = gpu_buffer_create(ctx, (VkDeviceSize)(gs->vertex_count ? gs->vertex_count : 1) *
                                         sizeof(struct gpu_hemicube_vertex),
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT |
                                    VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &inc->prev_vertices, err)) ||
        (st = gpu_buffer_create(ctx,
                                (VkDeviceSize)(gs->surface_count ? gs->surface_count : 1) *
                                    sizeof(struct gpu_surface),
                                storage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &inc->prev_surfaces, err)) ||
        (st = gpu_buffer_create(ctx,
                                (VkDeviceSize)(gs->element_count ? gs->element_count : 1) *
                                    sizeof(vec4),
                                storage, GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &inc->m_light,
                                err)) ||
        (st = gpu_buffer_create(ctx, (VkDeviceSize)table * sizeof(struct gpu_shooter),
                                storage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &inc->shooters, err)) ||
        (st = gpu_buffer_create(ctx, (VkDeviceSize)table * sizeof(struct gpu_shooter),
                                VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_UPLOAD,
                                GPU_MEM_REDISTRIBUTION, &inc->staging, err)) ||
        (st = gpu_buffer_create(ctx, (VkDeviceSize)table * sizeof(struct incr_value), storage,
                                GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &inc->values, err)) ||
        (st = gpu_buffer_create(ctx, (VkDeviceSize)gs->surface_count * sizeof(float), storage,
                                GPU_MEM_READBACK, GPU_MEM_REDISTRIBUTION, &inc->power, err)) ||
        (st = hemicube_create_desc(ctx, &ids, &inc->old_ids, err)) ||
        (st = hemicube_create_desc(ctx, &ids, &inc->new_ids, err)) ||
        (st = luminaire_change_create(ctx, scene, &inc->lum, err)))
        return st;
    /* Every dispatch of the reconstruct pass binds both hemicube images,
     * also where only the old pose's was drawn (NEGATIVE): an empty
     * recording puts all their layers in SHADER_READ_ONLY_OPTIMAL, where
     * every later recording leaves them. */
    gpu_cmd c;
    if ((st = gpu_cmd_begin(ctx, &c, err)))
        return st;
    hemicube_draw none = {.mesh = gpu_scene_hemicube_mesh(gs), .frames = &inc->shooters};
    hemicube_record(inc->old_ids, c.cmd, &none);
    hemicube_record(inc->new_ids, c.cmd, &none);
    st = gpu_cmd_run(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
    if (st)
        return st;
    if (!inc->staging.alloc.mapped || !inc->power.alloc.mapped)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "incremental solver: host-visible buffers are not mapped");
    incremental_reconstruct_params params = {
        .element_count = gs->element_count,
        .surface_count = gs->surface_count,
        .hemicube_res = s->desc.hemicube_res,
        .subdivide_ratio = s->desc.subdivide_ratio,
        .exact_texel_only = s->desc.id_check == XRAD_ID_CHECK_EXACT,
        .luminaires = inc->lum.active,
    };
    if ((st = incremental_reconstruct_create(ctx, &params, &inc->pass, err)))
        return st;
    incremental_reconstruct_bind(ctx, inc->pass,
                                 &(incremental_reconstruct_bindings){
                                     &gs->surfaces, &gs->elements, &gs->materials, &gs->B,
                                     &gs->Bu, &inc->shooters, &inc->values, &inc->power,
                                     &inc->prev_surfaces, &inc->m_light, &inc->lum.buffer,
                                     hemicube_ids_view(inc->old_ids),
                                     hemicube_ids_view(inc->new_ids)});
    /* Per command buffer: two updates, and a hemicube and a reconstruct
     * interval per chunk. */
    uint32_t intervals = 2 * inc->chunks_per_submission + 4;
    if (s->timer->capacity < intervals) {
        gpu_timer_destroy(ctx, &s->timer);
        if ((st = gpu_timer_create(ctx, intervals, &s->timer, err)))
            return st;
    }
    return XRAD_OK;
}

static xrad_status create(xrad_solver *s, xrad_error *err)
{
    incremental *inc = calloc(1, sizeof(*inc));
    if (!inc)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "incremental solver: out of host memory");
    /* M's layout is fixed before progressive_create, so that the shooter
     * capacity accounts for it (as cross.c). */
    xrad_status st = dynamic_patches_build(s->scene, s->desc.max_patches, false, &inc->dp, err);
    if (!st && inc->dp.count)
        st = dynamic_patches_fix(s->ctx, &s->gs, &inc->dp, err);
    if (!st)
        st = progressive_create(s, inc->dp.count ? PROGRESSIVE_REDISTRIBUTED : 0u, &inc->engine,
                                err); /* nothing to redistribute: plain progressive */
    if (!st && inc->dp.count)
        st = create_state(s, inc, err);
    if (st) {
        destroy_state(s, inc);
        progressive_destroy(s, &inc->engine);
        free(inc);
        return st;
    }
    s->impl = inc;
    return XRAD_OK;
}

/* ------------------------------------------------------ redistribution */

/* Patches along s and t for a surface of C with total power `power`: the
 * rule of the select pass (spirv/select.comp patch_counts), about
 * max_patches^2 x power / max_power, shaped to the surface, at most
 * max_patches and the element count per side. */
static void patch_counts(const xrad_solver *s, const vec3 c[4], const surface *sf, double power,
                         double max_power, uint32_t *kx, uint32_t *ky)
{
    double lu = 0.5 * (v3_len(v3_sub(c[1], c[0])) + v3_len(v3_sub(c[2], c[3])));
    double lv = 0.5 * (v3_len(v3_sub(c[3], c[0])) + v3_len(v3_sub(c[2], c[1])));
    uint32_t mp = s->desc.max_patches;
    double ratio = power / max_power;
    double n = (double)(mp * mp) * (ratio < 0 ? 0 : ratio > 1 ? 1 : ratio);
    double aspect = lu / lv;
    double ax = ceil(sqrt(n * aspect) - 1e-3), ay = ceil(sqrt(n / aspect) - 1e-3);
    double mx = min_u32(sf->nu, mp), my = min_u32(sf->nv, mp);
    *kx = (uint32_t)(ax < 1 ? 1 : ax > mx ? mx : ax);
    *ky = (uint32_t)(ay < 1 ? 1 : ay > my ? my : ay);
}

/* GENERATESHOOTINGPATCHES for every surface of C (Algorithm 4.3 line 8),
 * fixed once per solve: each surface of C is cut by the rule of the select
 * pass from its total power `power` (thesis 4.3.3), and the cut is
 * registered with the gpu_scene (gpu_scene_fix_patches) with the layout of
 * M, so that the select pass shoots C with these same patches from now on.
 * Patch k of a surface is numbered patch_first + k, after M's patches, and
 * its hemicube frame is the select pass's (spirv/select.comp): centre
 * bilinear at the centre of the block's parameter range, area the block's
 * element areas summed, tangent the u edge projected onto the surface plane
 * and turned by patch_rotation(seed, patch_first + k). What step 3 removes
 * and reshoots with these frames is then what the progressive iterations
 * shot with them, patch for patch and hemicube texel for texel. The frames
 * go into the staging table's C entries, which keep them (C does not
 * move); they are copied to the device with each step's upload. */
static xrad_status fix_static_layout(xrad_solver *s, incremental *inc, const float *power,
                                     xrad_error *err)
{
    const xrad_scene *scene = s->scene;
    struct gpu_shooter *out = (struct gpu_shooter *)inc->staging.alloc.mapped + inc->m_count;
    double max_power = 0;
    for (uint32_t k = 0; k < scene->surface_count; k++)
        max_power = power[k] > max_power ? power[k] : max_power;
    uint32_t n = 0;
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        const surface *sf = &scene->surfaces[k];
        uint32_t *fx = &inc->fixed[3 * k];
        uint32_t p = inc->dp.surface_patch[k];
        if (p != DYNAMIC_PATCH_NONE) {
            /* M: as dynamic_patches_fix. */
            fx[0] = inc->dp.patches[p].cx;
            fx[1] = inc->dp.patches[p].cy;
            fx[2] = p;
            continue;
        }
        vec3 c[4];
        scene_surface_world(scene, k, s->gs.time, c, NULL);
        uint32_t kx = 1, ky = 1;
        if (max_power > 0)
            patch_counts(s, c, sf, power[k], max_power, &kx, &ky);
        if (n + kx * ky > inc->c_capacity)
            return xrad_fail(err, XRAD_ERROR_SYSTEM,
                             "incremental solver: C's patches exceed the table");
        uint32_t first = inc->m_count + n;
        fx[0] = kx;
        fx[1] = ky;
        fx[2] = first;
        for (uint32_t q = 0; q < kx * ky; q++) {
            uint32_t px = q % kx, py = q / kx;
            fixed_patch_frame(scene, k, px * sf->nu / kx, (px + 1) * sf->nu / kx - 1,
                              py * sf->nv / ky, (py + 1) * sf->nv / ky - 1, first + q,
                              s->desc.seed, s->gs.time, &out[n], NULL);
            out[n].hemicube = n % inc->chunk;
            n++;
        }
    }
    inc->c_count = n;
    xrad_status st = gpu_scene_fix_patches(s->ctx, &s->gs, inc->fixed, err);
    inc->c_fixed = !st;
    return st;
}

/* The static surfaces' total powers after a solve, read back once. */
static xrad_status read_power(xrad_solver *s, incremental *inc, xrad_error *err)
{
    gpu_cmd c;
    xrad_status st = gpu_cmd_begin(s->ctx, &c, err);
    if (st)
        return st;
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    incremental_reconstruct_record(inc->pass, c.cmd, INCR_MODE_POWER, 0, 0);
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    st = gpu_cmd_run(s->ctx, &c, err);
    gpu_cmd_destroy(s->ctx, &c);
    if (!st) {
        s->stats.submissions++;
        s->stats.host_waits++;
    }
    return st;
}

/* Progressive refinement from emission (thesis 4.4: the first solve). With
 * M, C's shooting patches are then fixed from the converged powers; a
 * restart drops the previous fix first, so that the solve cuts C by power
 * as progressive refinement does. (Solving once more with the fixed
 * patches, so that all of C's shots were made with them, doubles the
 * solve and ends further from a fresh progressive solve: 0.0019 against
 * 0.0006 image NRMSE after 30 frames of cornell-lowq, 0.0022 against
 * 0.0010 after 300.) */
/* M's front frames at the pose in hand into the staging table's M entries,
 * what the next redistribution's ID hemicubes of line 4 are placed on.
 * Taken when the pose is, because the scene may change before that
 * redistribution (xrad_scene_set_offset). The C entries follow them. */
static void pose_m_frames(xrad_solver *s, incremental *inc)
{
    struct gpu_shooter *host = inc->staging.alloc.mapped;
    dynamic_patches_pose(s->scene, &inc->dp, s->gs.time, s->desc.seed, host, NULL, NULL, NULL);
    for (uint32_t p = 0; p < inc->m_count; p++)
        host[p].hemicube = p % inc->chunk;
}

static xrad_status solve(xrad_solver *s, xrad_error *err)
{
    incremental *inc = s->impl;
    xrad_status st = XRAD_OK;
    if (inc->m_count && inc->c_fixed) {
        inc->c_fixed = false;
        inc->c_count = 0;
        st = dynamic_patches_fix(s->ctx, &s->gs, &inc->dp, err);
    }
    if (!st)
        st = progressive_run(s, inc->engine, true, 0, err);
    /* The luminaires' light the restart started from (gpu_scene_reset). */
    if (!st && inc->m_count)
        st = luminaire_change_set_base(&inc->lum, s->scene, s->gs.time, true, err);
    if (!st && inc->m_count && !(st = read_power(s, inc, err)) &&
        !(st = fix_static_layout(s, inc, inc->power.alloc.mapped, err)))
        pose_m_frames(s, inc);
    solver_collect_times(s);
    return st;
}

/* What the previous steps wrote (B, Bu, values, hemicube images) is
 * visible to the compute step that follows. */
static void compute_barrier(VkCommandBuffer cmd)
{
    gpu_memory_barrier(cmd,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                           VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                       VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
}

/* Copies the host's shooters [first, first + count) into the table (and,
 * for the old pose, the hemicube vertices and the surfaces), before the
 * hemicubes' vertex stages and the compute steps read them. */
static void record_upload(xrad_solver *s, incremental *inc, VkCommandBuffer cmd, uint32_t first,
                          uint32_t count, bool vertices)
{
    if (vertices) {
        VkBufferCopy v = {0, 0,
                          (VkDeviceSize)s->gs.vertex_count * sizeof(struct gpu_hemicube_vertex)};
        if (s->gs.vertex_count)
            vkCmdCopyBuffer(cmd, s->gs.vertices.buffer, inc->prev_vertices.buffer, 1, &v);
        VkBufferCopy f = {0, 0, (VkDeviceSize)s->gs.surface_count * sizeof(struct gpu_surface)};
        if (s->gs.surface_count)
            vkCmdCopyBuffer(cmd, s->gs.surfaces.buffer, inc->prev_surfaces.buffer, 1, &f);
    }
    if (count) {
        VkDeviceSize at = (VkDeviceSize)first * sizeof(struct gpu_shooter);
        VkBufferCopy r = {at, at, (VkDeviceSize)count * sizeof(struct gpu_shooter)};
        vkCmdCopyBuffer(cmd, inc->staging.buffer, inc->shooters.buffer, 1, &r);
    }
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                           VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_SHADER_READ_BIT);
}

/* One chunk, shooters [first, first + n): its ID hemicubes and the
 * reconstruction. NEGATIVE: M's patches at the old pose (the vertices
 * still holds it); M_LIGHT: M's patches at the new pose; INCREMENT: C's
 * patches, old vertices and new; RECEIVE_M: C's patches, new vertices. The
 * render pass orders each hemicube image after the previous chunk's
 * reconstruction read it. */
static void record_chunk(xrad_solver *s, incremental *inc, VkCommandBuffer cmd, uint32_t mode,
                         uint32_t first, uint32_t n)
{
    hemicube_draw d = {
        .mesh = gpu_scene_hemicube_mesh(&s->gs),
        .index_count = s->gs.index_count,
        .frames = &inc->shooters,
        .first = first,
        .count = n,
    };
    gpu_timer_begin(s->timer, cmd, "incr.hemicube");
    if (mode == INCR_MODE_INCREMENT) {
        /* Lines 11-12: the same frame with the old geometry of M and the new. */
        hemicube_draw old = d;
        old.mesh.vertices = &inc->prev_vertices;
        hemicube_record(inc->old_ids, cmd, &old);
        hemicube_record(inc->new_ids, cmd, &d);
        s->stats.hemicubes += 2 * n;
    } else if (mode == INCR_MODE_RECEIVE_M) {
        hemicube_record(inc->new_ids, cmd, &d);
        s->stats.hemicubes += n;
    } else {
        hemicube_record(inc->old_ids, cmd, &d);
        s->stats.hemicubes += n;
    }
    gpu_timer_end(s->timer, cmd);
    compute_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "incr.reconstruct");
    incremental_reconstruct_record(inc->pass, cmd, mode, first, n);
    gpu_timer_end(s->timer, cmd);
}

/* Ends, submits and waits for a command buffer, then reads its timers. */
static xrad_status finish(xrad_solver *s, gpu_cmd *c, xrad_error *err)
{
    /* B, Bu, the powers and the copied vertices are complete for the host
     * and for later submissions (the pose upload, the progressive
     * iterations, gpu_scene_read). */
    gpu_memory_barrier(c->cmd,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_ACCESS_HOST_READ_BIT | VK_ACCESS_MEMORY_READ_BIT |
                           VK_ACCESS_MEMORY_WRITE_BIT);
    return solver_submit_wait(s, c, err);
}

/* Shoots table entries [first, first + count) in chunks, as many chunks per
 * command buffer as HEMICUBES_PER_SUBMISSION allows. The first command
 * buffer starts with the step's preparation (upload; the capture of what
 * the shooters shoot, and for INCREMENT the reset; for M_LIGHT the clear of
 * m_light; for RECEIVE_M the capture of C's light with M's); NEGATIVE ends with the
 * static surfaces' total powers, once C has lost M's shot radiosity. */
static xrad_status shoot(xrad_solver *s, incremental *inc, uint32_t mode, uint32_t first,
                         uint32_t count, xrad_error *err)
{
    uint32_t done = 0;
    bool prepare = true;
    do {
        gpu_cmd c;
        xrad_status st = gpu_cmd_begin(s->ctx, &c, err);
        if (st)
            return st;
        gpu_timer_start(s->timer, c.cmd);
        if (prepare) {
            /* RECEIVE_M's shooters are INCREMENT's, uploaded by it. */
            record_upload(s, inc, c.cmd, first, mode == INCR_MODE_RECEIVE_M ? 0 : count,
                          mode == INCR_MODE_NEGATIVE);
            gpu_timer_begin(s->timer, c.cmd, "incr.update");
            if (mode == INCR_MODE_RECEIVE_M) {
                /* What M takes from each patch of C: C's light now, with
                 * M's (incremental_reconstruct.comp c_light). */
                incremental_reconstruct_record(inc->pass, c.cmd, INCR_MODE_CAPTURE_LIT, first,
                                               count);
            } else if (mode == INCR_MODE_M_LIGHT) {
                /* M's radiosity as NEGATIVE captured it, shot into m_light
                 * from the new pose. */
                incremental_reconstruct_record(inc->pass, c.cmd, INCR_MODE_CLEAR, 0, 0);
            } else {
                /* Line 8 (and line 4's shot radiosity): every shooter's
                 * values before any of this step's shots changes B or Bu. */
                incremental_reconstruct_record(inc->pass, c.cmd, INCR_MODE_CAPTURE, first, count);
            }
            if (mode == INCR_MODE_INCREMENT) {
                /* Lines 6 and 9, after the capture read C's Bu. */
                compute_barrier(c.cmd);
                incremental_reconstruct_record(inc->pass, c.cmd, INCR_MODE_RESET, 0, 0);
            }
            gpu_timer_end(s->timer, c.cmd);
            prepare = false;
        }
        for (uint32_t k = 0; k < inc->chunks_per_submission && done < count; k++) {
            uint32_t n = min_u32(inc->chunk, count - done);
            record_chunk(s, inc, c.cmd, mode, first + done, n);
            done += n;
        }
        if ((st = finish(s, &c, err)))
            return st;
    } while (done < count);
    return XRAD_OK;
}

/* Steps 1-3 of the header: from the solution at the current pose to one
 * at `time` with unshot radiosity left for the progressive iterations. */
static xrad_status redistribute(xrad_solver *s, incremental *inc, double time, xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    /* Step 1: from M's front frames at the old pose (pose_m_frames). */
    xrad_status st = shoot(s, inc, INCR_MODE_NEGATIVE, 0, inc->m_count, err);
    if (st)
        return st;
    /* The GPU is done: the geometry may be replaced. The pose upload's
     * copies (where the device memory is not mapped) are a submission the
     * host does not wait for: count it from the context's counter. */
    uint64_t before = ctx->timeline_value;
    st = gpu_scene_pose(ctx, &s->gs, time, err);
    s->stats.submissions += (uint32_t)(ctx->timeline_value - before);
    if (st)
        return st;
    pose_m_frames(s, inc);
    /* The luminaires' light at the new pose, which the reset of step 2
     * gives M and adds to C as its change (incremental_reconstruct.comp). */
    if ((st = luminaire_change_pose(&inc->lum, s->scene, time, true, err)))
        return st;
    /* Steps 2-3: M's light on C at the new pose, C's changes, then what M
     * takes from C (line 14) with both. */
    st = shoot(s, inc, INCR_MODE_M_LIGHT, 0, inc->m_count, err);
    if (!st)
        st = shoot(s, inc, INCR_MODE_INCREMENT, inc->m_count, inc->c_count, err);
    if (!st)
        st = shoot(s, inc, INCR_MODE_RECEIVE_M, inc->m_count, inc->c_count, err);
    return st;
}

static xrad_status advance(xrad_solver *s, double time, xrad_error *err)
{
    incremental *inc = s->impl;
    double t0 = now_ms();
    xrad_status st;
    if (inc->m_count) {
        st = redistribute(s, inc, time, err);
    } else {
        /* Nothing moves: the solution stays valid at the new time. */
        uint64_t before = s->ctx->timeline_value;
        st = gpu_scene_pose(s->ctx, &s->gs, time, err);
        s->stats.submissions += (uint32_t)(s->ctx->timeline_value - before);
    }
    s->stats.redistribute_ms = now_ms() - t0;
    /* Step 4 (thesis 4.4.1 "Overview"): R_p(M, M) and the second part of
     * R_p(M, C) are regular progressive shots of the unshot radiosity. */
    if (!st)
        st = progressive_run(s, inc->engine, false, s->desc.frame_shots, err);
    solver_collect_times(s);
    return st;
}

const solver_ops incremental_ops = {create, solve, destroy, advance};
