/*
 * Cross redistribution radiosity (thesis 3.3 and 4.5, Algorithms 4.4 and
 * 4.5; DESIGN.md "CRR, one redistribution"). Every redistribution puts
 * the dynamic set M at the pose in hand, rendering hemicubes for the
 * patches of M only, and the progressive iterations after it shoot the
 * unshot radiosity it created (thesis 4.5.3).
 *
 * One redistribution, in two submissions:
 *
 *   1. M is reset to its emission with nothing unshot (RESET); the atlas
 *      gets B - Bu - E of C, 0 on M (INDIRECT_C + atlas scatter), and its
 *      largest value sets the fp16 scale of the radiosity hemicubes.
 *   2. Per patch: an ID hemicube on its front; a radiosity hemicube at its
 *      coarse sample (the gather of R_g(C, M)); a low-resolution radiosity
 *      + distance hemicube on its back, static geometry only (thesis
 *      4.5.2); its mips where back_mips is on (thesis 6.2). Per light
 *      patch of C (its emitters, fixed blocks) whose plane has some of M
 *      in front (light_reach): an ID hemicube with M at the pose; the one
 *      of C alone was drawn at create.
 *   3. R_g(C, M): integrate the gather hemicubes; the elements of M take
 *      B = E + rho x (their surface's coarse samples, interpolated)
 *      (GATHERED), a mesh group's faces rho x its gather hemicube read
 *      from each face's own point (GROUPS), then rho x the direct light of C's lights through the
 *      lights' hemicubes and of the luminaires (M_DIRECT), and T.total =
 *      area mean of B per patch (TOTAL).
 *   4. R_p(M, M) into B of M, and TOTAL again: what M shoots to C holds
 *      one bounce inside M.
 *   5. R_p(M, C) + R_x(C, C): every element of C gets the new pose's terms
 *      of eq. 3.3.1, with the direct light M hides taken from the lights'
 *      hemicubes and the luminaires' change from C's own (luminaire_
 *      change.h), in place of the ones the last redistribution gave it,
 *      which each element keeps (cross_reconstruct.comp): the old pose's
 *      terms are removed exactly as they were inserted.
 *   6. Progressive iterations (solvers/progressive.h), desc.frame_shots,
 *      on C alone: their hemicubes do not draw M, and M shoots nothing in
 *      them (its light is in its patches' totals, step 5).
 *   7. With cross_regather after (the default) or on: steps 1, 3 and 4
 *      again (regather_m), so that M's own light follows C as step 6 left
 *      it. With after, a frame's redistribution leaves steps 3 and 4 out:
 *      step 5 shoots the totals the last frame's step 7 left (M's light
 *      of the last pose, moved with M), and a frame costs one gather as
 *      in the thesis's order (off), where M showed its surroundings a
 *      frame late (room 1's sliding box of tests/solvers/rooms.c 0.955 of
 *      the CPU reference on the side it leaves behind after three 33 ms
 *      frames, 0.987 with after; on, both gathers, costs 1.27 times a
 *      frame on cornell-large and came out within 0.003 of after's
 *      surface_error on the generic rooms).
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
 * power rose to 1.11 times the bound E / (1 - rho) (tests/solvers/
 * test_extremes.c). Here the progressive iterations solve C alone, and M
 * enters only as the source X of step 5, replaced whole at every
 * redistribution: the solution is always that of C with the source of the
 * pose in hand, and nothing of M adds up (the same slide stays within the
 * bound to frame 10,000; what the iterations shot of earlier poses' signed
 * changes does wander, 0.944-0.976 of the bound at one pose, README
 * "Shooter subdivision").
 *
 * What that asks of step 5: every shadow M casts is in X, none in the
 * shots' hemicubes. The cross projection cannot resolve a light smaller
 * than a back hemicube's texel (a 1 mm^2 lamp lit M and shadowed C 18%
 * off the CPU reference per element), so direct light goes through the
 * lights' own hemicubes (M_DIRECT; blocked_direct in step 5) and the
 * radiosity hemicubes show C without emission. A receiver of C in contact
 * with M's front (a box standing on it) sees no patch of M, so X sets it
 * to its emission.
 *
 * The first solve is progressive refinement of C alone, then rounds of
 * (redistribution, progressive iterations to the threshold): each round
 * puts in what M does to the light the last one left.
 *
 * The gpu_scene's atlas holds B - Bu - E of C, not B, in this method.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "cross_shared.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "passes/atlas_scatter.h"
#include "passes/back_mips.h"
#include "passes/cross_reconstruct.h"
#include "passes/cross_update.h"
#include "passes/hemicube.h"
#include "passes/hemicube_geometry.h"
#include "passes/integrate.h"
#include "radiosity.h"
#include "solvers/cross.h"
#include "solvers/dynamic_patches.h"
#include "solvers/luminaire_change.h"
#include "solvers/progressive.h"
#include "solvers/solver.h"

/* The largest value the radiosity hemicubes show, after scaling: far below
 * fp16's 65504 (bilinear taps and MSAA resolves stay within it), far above
 * its smallest normal 6.1e-5. */
#define HEMICUBE_PEAK 256.0

/* Rounds of (redistribution, progressive iterations) in the first solve. */
#define SOLVE_ROUNDS 4

/* A redistribution draws its radiosity hemicubes at the scale the last one
 * measured, without waiting for its own measure, and is made again only if
 * the two differ by more than this factor either way: then the largest
 * value shown would pass 256 x 16 or fall below 256 / 16, still far inside
 * fp16's range, so no light is lost by it either. */
#define SCALE_SLACK 16.0

/* The most (element, patch) pairs the cross projection lists per submission
 * (32 bytes each): elements past it loop over the patches themselves. */
#define PAIR_CAPACITY_MAX (1u << 20)

typedef struct cross {
    progressive *prog;
    dynamic_patches dp;
    uint32_t P;             /* patches of M */
    bool groups;            /* some are mesh groups (dynamic_patches.h): the GROUPS update runs */
    dynamic_patches lights; /* the lights of C in fixed patches (direct light) */
    uint32_t L;
    hemicube_pass *ids, *back, *gather;
    hemicube_pass *light_ids_c, *light_ids; /* per light patch: C alone; C and M at the pose */
    integrate_pass *integrate;
    atlas_scatter_pass *scatter;
    cross_update_pass *update;
    cross_reconstruct_pass *reconstruct;
    back_mips_pass *mips;     /* NULL where back_mips is off */
    uint32_t back_levels;     /* mip levels above 0 the projection reads */
    gpu_buffer patches;       /* struct cross_patch[P] */
    gpu_buffer values;        /* struct cross_value[P] */
    gpu_buffer gathered;      /* vec4[2 P]: per patch the gathered sum, then its horizon
                                 ring's mean (integrate_shared.h; mesh groups) */
    gpu_buffer surface_patch; /* uint[dp.surface_patch_size] */
    gpu_buffer shot;          /* vec4[element_count]: B - Bu of C, 0 on M */
    gpu_buffer inserted;      /* vec4[element_count]: what step 5 last added to C */
    gpu_buffer frames;        /* gpu_shooter[3 tables][P], host-written */
    gpu_buffer quads;         /* struct cross_quad[P], host-written */
    gpu_buffer peak;          /* uint, host-visible: largest |B - Bu - E| on C (float bits) */
    gpu_buffer light_frames;  /* gpu_shooter[L] */
    gpu_buffer light_quads;   /* struct cross_quad[L] */
    gpu_buffer reach_frames;  /* gpu_shooter[L], host-written per pose: the lights M can reach */
    gpu_buffer light_layers;  /* uint[L], host-written per pose (cross_shared.h) */
    struct gpu_shooter *light_host; /* [L]: the lights' frames */
    luminaire_change lum;     /* the luminaires' light, base: C's alone (luminaire_change.h) */
    uint32_t reach_count;     /* lights drawn with M at the pose (light_reach) */
    bool reach_all;           /* every light drawn, M where it may be (tests) */
    uint32_t m_objects;       /* dynamic objects */
    uint32_t *m_object;       /* [m_objects]: their indices */
    vec3 *m_box;              /* [2 m_objects]: their object-space bounds, lo and hi */
    vec3 *m_corners;          /* [8 m_objects]: those bounds' corners at the pose */
    gpu_buffer pairs;         /* struct cross_pair[pair_capacity] */
    gpu_buffer ranges;        /* uvec2[element_count]: each element's pairs */
    gpu_buffer pair_state;    /* struct cross_pair_state, host-visible: the count read back */
    gpu_buffer order;         /* uint[pair_capacity]: the pairs in patch order */
    gpu_buffer patch_lists;   /* uint[3 P] */
    gpu_buffer back_mips;     /* the back hemicubes' mips (passes/back_mips.h) */
    uint32_t pair_capacity;
    double diameter;          /* m, the scale of the hemicubes' near plane and distances,
                                 fixed at create (the posed scene's diameter changes) */
    double scale;             /* the radiosity hemicubes hold values x this (HEMICUBE_PEAK) */
    bool scale_known;         /* scale was measured by an earlier redistribution of this solve */
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
    hemicube_destroy(ctx, &c->light_ids_c);
    hemicube_destroy(ctx, &c->light_ids);
    integrate_destroy(ctx, &c->integrate);
    atlas_scatter_destroy(ctx, &c->scatter);
    cross_update_destroy(ctx, &c->update);
    cross_reconstruct_destroy(ctx, &c->reconstruct);
    back_mips_destroy(ctx, &c->mips);
    gpu_buffer *buffers[] = {&c->patches, &c->values,       &c->gathered,   &c->surface_patch,
                             &c->shot,    &c->inserted,     &c->frames,     &c->quads,
                             &c->light_frames, &c->light_quads, &c->peak,
                             &c->reach_frames, &c->light_layers,
                             &c->pairs,   &c->ranges,       &c->pair_state,
                             &c->order,   &c->patch_lists, &c->back_mips};
    for (size_t k = 0; k < sizeof(buffers) / sizeof(buffers[0]); k++)
        gpu_buffer_destroy(ctx, buffers[k]);
    luminaire_change_destroy(ctx, &c->lum);
    dynamic_patches_free(&c->dp);
    dynamic_patches_free(&c->lights);
    free(c->light_host);
    free(c->m_object);
    free(c->m_box);
    free(c->m_corners);
    free(c);
    s->impl = NULL;
}

/* The dynamic objects' object-space bounds, for light_reach. */
static xrad_status m_bounds(const xrad_scene *scene, cross *c, xrad_error *err)
{
    for (uint32_t o = 0; o < scene->object_count; o++)
        c->m_objects += scene->objects[o].dynamic;
    c->m_object = calloc(c->m_objects ? c->m_objects : 1, sizeof(*c->m_object));
    c->m_box = calloc(2 * (c->m_objects ? c->m_objects : 1), sizeof(*c->m_box));
    c->m_corners = calloc(8 * (c->m_objects ? c->m_objects : 1), sizeof(*c->m_corners));
    if (!c->m_object || !c->m_box || !c->m_corners)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory for the moving objects");
    uint32_t m = 0;
    for (uint32_t o = 0; o < scene->object_count; o++) {
        if (!scene->objects[o].dynamic)
            continue;
        c->m_object[m] = o;
        scene_object_box(scene, o, &c->m_box[2 * m], &c->m_box[2 * m + 1]);
        m++;
    }
    return XRAD_OK;
}

/* Issue 16.3: which lights' hemicubes with M are drawn at scene time t.
 * A light whose plane has every corner of every moving object's posed
 * bounds behind it (or on it, within 1e-6 of the scene's diameter) sees
 * no part of M: its hemicube with M is its hemicube of C alone, no point
 * of M faces it (M takes none of its light) and M hides none of it, so the
 * projection leaves it out (CROSS_LIGHT_UNREACHED) and it is not drawn.
 * The others' frames go to reach_frames one after another. */
static void light_reach(xrad_solver *s, cross *c, double t)
{
    uint32_t *layer = c->light_layers.alloc.mapped;
    struct gpu_shooter *drawn = c->reach_frames.alloc.mapped;
    double tol = 1e-6 * c->diameter;
    /* The posed corners, once for every light. */
    for (uint32_t m = 0; m < c->m_objects; m++) {
        xform pose = scene_object_pose(s->scene, c->m_object[m], t);
        const vec3 *box = &c->m_box[2 * m];
        for (int k = 0; k < 8; k++)
            c->m_corners[8 * m + k] =
                xf_point(&pose, v3(box[k & 1].x, box[(k >> 1) & 1].y, box[k >> 2].z));
    }
    uint32_t n = 0;
    for (uint32_t l = 0; l < c->L; l++) {
        const struct gpu_shooter *f = &c->light_host[l];
        vec3 centre = v3(f->pos_area.x, f->pos_area.y, f->pos_area.z);
        vec3 normal = v3(f->normal.x, f->normal.y, f->normal.z);
        bool reach = c->reach_all;
        for (uint32_t k = 0; k < 8 * c->m_objects && !reach; k++)
            reach = v3_dot(v3_sub(c->m_corners[k], centre), normal) > -tol;
        layer[l] = reach ? n : CROSS_LIGHT_UNREACHED;
        if (reach)
            drawn[n++] = *f;
    }
    c->reach_count = n;
}

/* The lights' frames, quads and ID hemicubes; those of C alone are drawn
 * here, once: C does not move. */
static xrad_status create_lights(xrad_solver *s, cross *c, xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    const gpu_scene *gs = &s->gs;
    uint32_t L = c->L;
    struct gpu_shooter *f = calloc(L, sizeof(*f));
    struct cross_quad *q = calloc(L, sizeof(*q));
    xrad_status st = XRAD_OK;
    if (!f || !q) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory for the lights");
        goto done;
    }
    if ((st = m_bounds(s->scene, c, err)))
        goto done;
    for (uint32_t l = 0; l < L; l++) {
        const struct cross_patch *p = &c->lights.patches[l];
        fixed_patch_frame(s->scene, p->surface, p->i0, p->i1, p->j0, p->j1, l, s->desc.seed,
                          s->desc.time, &f[l], &q[l]);
    }
    hemicube_desc ids = {.kind = HEMICUBE_IDS, .res = s->desc.hemicube_res, .max_hemicubes = L,
                         .msaa = 1, .path = HEMICUBE_PATH_AUTO, .diameter = c->diameter,
                         .redistribution = true};
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    gpu_cmd cmd;
    if ((st = gpu_buffer_create(ctx, L * sizeof(*f), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->light_frames, err)) ||
        (st = gpu_buffer_create(ctx, L * sizeof(*q), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->light_quads, err)) ||
        (st = gpu_upload_buffer(ctx, &c->light_frames, 0, f, L * sizeof(*f), err)) ||
        (st = gpu_upload_buffer(ctx, &c->light_quads, 0, q, L * sizeof(*q), err)) ||
        (st = gpu_buffer_create(ctx, L * sizeof(*f), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                GPU_MEM_UPLOAD, GPU_MEM_REDISTRIBUTION, &c->reach_frames,
                                err)) ||
        (st = gpu_buffer_create(ctx, L * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                GPU_MEM_UPLOAD, GPU_MEM_REDISTRIBUTION, &c->light_layers,
                                err)) ||
        (st = hemicube_create_desc(ctx, &ids, &c->light_ids_c, err)) ||
        (st = hemicube_create_desc(ctx, &ids, &c->light_ids, err)) ||
        (st = gpu_cmd_begin(ctx, &cmd, err)))
        goto done;
    hemicube_record(c->light_ids_c, cmd.cmd,
                    &(hemicube_draw){.mesh = gpu_scene_hemicube_mesh(gs),
                                     .index_count = gs->static_index_count,
                                     .frames = &c->light_frames, .count = L});
    /* The hemicubes with M too, once, so that their image is in the layout
     * the projection binds it in before any pose draws one (light_reach
     * may leave them all out). */
    hemicube_record(c->light_ids, cmd.cmd,
                    &(hemicube_draw){.mesh = gpu_scene_hemicube_mesh(gs),
                                     .index_count = gs->static_index_count,
                                     .frames = &c->light_frames, .count = L});
    st = solver_submit_wait(s, &cmd, err);
done:
    c->light_host = f;
    free(q);
    if (st)
        xrad_error_prefix(err, "lights");
    return st;
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
    /* One sample, as the thesis's combined ID + radiosity hemicube (5.3.1).
     * open_only: the floor strip at a box's foot was dragged towards the
     * buried samples under the box, and the box's lower rows lit too
     * little (hemicube_radiosity.frag). */
    hemicube_desc gather = {.kind = HEMICUBE_RADIOSITY, .res = d->hemicube_res,
                            .max_hemicubes = P, .msaa = 1, .path = HEMICUBE_PATH_AUTO,
                            .diameter = diameter,
                            .fp32 = d->radiosity_format == XRAD_RADIOSITY_FP32,
                            .open_only = true,
                            .redistribution = true};
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    size_t element_bytes = (size_t)gs->element_count * sizeof(vec4);
    uint64_t most_pairs = (uint64_t)gs->element_count * P;
    c->pair_capacity = most_pairs < PAIR_CAPACITY_MAX ? (uint32_t)most_pairs : PAIR_CAPACITY_MAX;
    bool listed = d->cross_pairs == XRAD_CROSS_PAIRS_ON && c->pair_capacity;
    /* The projection's second SPIR-V only where it is needed. */
    bool full = (d->back_mips == XRAD_BACK_MIPS_ON && back_mips_levels(d->back_res)) ||
                d->cross_cut > 0;
    if (!listed)
        c->pair_capacity = 0;
    xrad_status st;
    if ((st = gpu_buffer_create(ctx, P * sizeof(struct cross_patch), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->patches, err)) ||
        (st = gpu_buffer_create(ctx, P * sizeof(struct cross_value),
                                storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->values, err)) ||
        (st = gpu_buffer_create(ctx, 2 * P * sizeof(vec4), storage, GPU_MEM_DEVICE,
                                GPU_MEM_REDISTRIBUTION, &c->gathered, err)) ||
        (st = gpu_buffer_create(ctx, c->dp.surface_patch_size * sizeof(uint32_t), storage,
                                GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &c->surface_patch, err)) ||
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
        (st = gpu_buffer_create(ctx, sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                GPU_MEM_READBACK, GPU_MEM_REDISTRIBUTION, &c->peak, err)) ||
        (st = gpu_upload_buffer(ctx, &c->patches, 0, c->dp.patches,
                                P * sizeof(struct cross_patch), err)) ||
        (st = gpu_upload_buffer(ctx, &c->surface_patch, 0, c->dp.surface_patch,
                                c->dp.surface_patch_size * sizeof(uint32_t), err)) ||
        (st = hemicube_create_desc(ctx, &ids, &c->ids, err)) ||
        (st = hemicube_create_desc(ctx, &back, &c->back, err)) ||
        (st = hemicube_create_desc(ctx, &gather, &c->gather, err)) ||
        (st = integrate_create(ctx, d->hemicube_res, &c->integrate, err)) ||
        (st = atlas_scatter_create(ctx, &c->scatter, err)) ||
        (st = cross_update_create(ctx, &c->update, err)) ||
        (st = cross_reconstruct_create(ctx, full, &c->reconstruct, err)) ||
        (st = luminaire_change_create(ctx, s->scene, &c->lum, err)) ||
        (st = luminaire_change_set_base(&c->lum, s->scene, d->time, false, err)))
        return st;
    if (c->L && (st = create_lights(s, c, err)))
        return st;
    if (listed &&
        ((st = gpu_buffer_create(ctx, (VkDeviceSize)c->pair_capacity * sizeof(struct cross_pair),
                                 storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_DEVICE,
                                 GPU_MEM_REDISTRIBUTION, &c->pairs, err)) ||
         (st = gpu_buffer_create(ctx, (VkDeviceSize)gs->element_count * 2 * sizeof(uint32_t),
                                 storage | VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_DEVICE,
                                 GPU_MEM_REDISTRIBUTION, &c->ranges, err)) ||
         (st = gpu_buffer_create(ctx, (VkDeviceSize)c->pair_capacity * sizeof(uint32_t),
                                 storage, GPU_MEM_DEVICE, GPU_MEM_REDISTRIBUTION, &c->order,
                                 err)) ||
         (st = gpu_buffer_create(ctx, 3 * P * sizeof(uint32_t), storage, GPU_MEM_DEVICE,
                                 GPU_MEM_REDISTRIBUTION, &c->patch_lists, err)) ||
         (st = gpu_buffer_create(ctx, sizeof(struct cross_pair_state),
                                 storage | VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                 GPU_MEM_READBACK, GPU_MEM_REDISTRIBUTION, &c->pair_state,
                                 err))))
        return st;
    if (d->back_mips == XRAD_BACK_MIPS_ON && back_mips_levels(d->back_res)) {
        c->back_levels = back_mips_levels(d->back_res);
        if ((st = back_mips_create(ctx, &c->mips, err)) ||
            (st = gpu_buffer_create(ctx, back_mips_bytes(d->back_res, P * HEMICUBE_FACES),
                                    VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                                    GPU_MEM_REDISTRIBUTION, &c->back_mips, err)))
            return st;
        back_mips_bind(ctx, c->mips, hemicube_image(c->back)->view, &c->back_mips);
    }
    /* The update pass binds the gather hemicubes in every mode, before the
     * first gather draws them. */
    gpu_cmd init;
    if ((st = gpu_cmd_begin(ctx, &init, err)))
        return st;
    gpu_image_transition(init.cmd, hemicube_image(c->gather), VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    st = gpu_cmd_run(ctx, &init, err);
    gpu_cmd_destroy(ctx, &init);
    if (st)
        return st;
    /* Without the list its bindings are placeholders: pair_capacity 0 reads none;
     * so for the mips where back_levels is 0. */
    const gpu_buffer *none = &c->values;
    cross_update_bind(ctx, c->update,
                      &(cross_update_bindings){&gs->surfaces, &gs->elements, &gs->materials,
                                               &gs->B, &gs->Bu, &c->patches, &c->values,
                                               &c->gathered, &c->shot, &c->surface_patch,
                                               &c->peak, &c->frames,
                                               hemicube_image(c->gather)->view});
    cross_reconstruct_bind(ctx, c->reconstruct,
                           &(cross_reconstruct_bindings){
                               &gs->surfaces, &gs->elements, &gs->materials, &gs->B, &gs->Bu,
                               &c->values, &c->frames, &c->quads, hemicube_ids_view(c->ids),
                               hemicube_image(c->back)->view, &c->inserted,
                               c->L ? &c->light_frames : &c->values,
                               c->L ? &c->light_quads : &c->values,
                               hemicube_ids_view(c->L ? c->light_ids_c : c->ids),
                               hemicube_ids_view(c->L ? c->light_ids : c->ids),
                               &gs->bvh_nodes, &gs->bvh_items, listed ? &c->pairs : none,
                               listed ? &c->ranges : none, listed ? &c->pair_state : none,
                               listed ? &c->order : none, listed ? &c->patch_lists : none,
                               &c->peak, c->mips ? &c->back_mips : none,
                               c->L ? &c->light_layers : none, &c->lum.buffer});
    return XRAD_OK;
}

static xrad_status create(xrad_solver *s, xrad_error *err)
{
    cross *c = calloc(1, sizeof(*c));
    if (!c)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "cross solver: out of host memory");
    s->impl = c;
    xrad_status st;
    /* Without dynamic objects there is nothing to redistribute: plain
     * progressive refinement, with all it sees. */
    if ((st = dynamic_patches_build(s->scene, s->desc.max_patches, true, &c->dp, err)) ||
        (st = progressive_create(s, c->dp.count ? PROGRESSIVE_STATIC_ONLY : 0u, &c->prog, err)))
        goto fail;
    c->P = c->dp.count;
    for (uint32_t p = 0; p < c->P; p++)
        c->groups = c->groups || c->dp.patches[p].member_count > 0;
    /* The lights matter where something moves in front of them. */
    if (c->P && (st = dynamic_patches_build_lights(s->scene, s->desc.max_patches,
                                                   s->gs.diameter, &c->lights, err)))
        goto fail;
    c->L = c->lights.count;
    s->stats.cross_patches = c->P;
    s->stats.cross_light_patches = c->L;
    const VkPhysicalDeviceLimits *lim = &s->ctx->props.limits;
    uint32_t layers = lim->maxImageArrayLayers < lim->maxFramebufferLayers
                          ? lim->maxImageArrayLayers
                          : lim->maxFramebufferLayers;
    if ((uint64_t)(c->P > c->L ? c->P : c->L) * HEMICUBE_FACES > layers) {
        st = xrad_fail(err, XRAD_ERROR_INPUT,
                       "%s: the dynamic objects have %u cross patches (cross_density, or "
                       "blocks of a quarter of the object's size, at most max_patches %u a "
                       "side, where none is given) and the lights %u; the device draws at most "
                       "%u hemicubes at once",
                       s->scene->path, c->P, s->desc.max_patches, c->L,
                       layers / HEMICUBE_FACES);
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

/* Step 1: M reset; the atlas holding B - Bu - E of C, 0 on M, for the
 * radiosity hemicubes drawn next; its largest value into c->peak, zeroed
 * before. */
static void record_reset(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    const gpu_scene *gs = &s->gs;
    uint32_t n = gs->element_count;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.update");
    cross_update_record(c->update, cmd, CROSS_UPDATE_RESET, c->P, n, NULL);
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_INDIRECT_C, c->P, n, NULL);
    compute_barrier(cmd);
    atlas_scatter_record(c->scatter, cmd,
                         &(atlas_scatter_draw){&gs->elements, &c->shot, n, &gs->atlas});
    gpu_image_barrier(cmd, &gs->atlas, VK_IMAGE_LAYOUT_GENERAL, VK_IMAGE_LAYOUT_GENERAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu_timer_end(s->timer, cmd);
}

/* The patches' radiosity hemicubes of frame table `table` over the atlas
 * (scaled by c->scale), drawing the first `index_count` indices. */
static hemicube_draw radiosity_draw(const xrad_solver *s, const cross *c, uint32_t table,
                                    uint32_t index_count)
{
    return (hemicube_draw){.mesh = gpu_scene_hemicube_mesh(&s->gs),
                           .index_count = index_count,
                           .frames = &c->frames,
                           .first = frames_first(c, table),
                           .count = c->P,
                           .atlas = &s->gs.atlas,
                           .scale = (float)c->scale};
}

/* R_g(C, M) (step 3's gather): the patches' gather hemicubes over the
 * atlas (scaled by c->scale), integrated, and the elements of M set to
 * E + rho x the gathered light. */
static void record_gather(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    const gpu_scene *gs = &s->gs;
    uint32_t n = gs->element_count, P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.gather");
    hemicube_draw d = radiosity_draw(s, c, CROSS_FRAMES_GATHER, gs->index_count);
    hemicube_record(c->gather, cmd, &d);
    integrate_record(c->integrate, cmd,
                     &(integrate_draw){.hemicubes = hemicube_image(c->gather)->view, .count = P,
                                       .out = &c->gathered, .scale = (float)c->scale,
                                       .ring = true, .ring_first = P});
    compute_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_GATHERED, P, n, NULL);
    if (c->groups)
        cross_update_record(c->update, cmd, CROSS_UPDATE_GROUPS, P, n,
                            &(cross_update_gather){.res = s->desc.hemicube_res,
                                                   .scale = (float)c->scale,
                                                   .diameter = (float)c->diameter});
    gpu_timer_end(s->timer, cmd);
    s->stats.hemicubes += P;
}

/* Step 2 at the pose in hand, but for the gather (record_m): the patches'
 * ID and back hemicubes (the back ones over the atlas, scaled by
 * c->scale), the lights' ID hemicubes with M. The frames are written. */
static void record_hemicubes(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    const gpu_scene *gs = &s->gs;
    uint32_t P = c->P;
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, "cross.hemicube");
    hemicube_record(c->ids, cmd,
                    &(hemicube_draw){.mesh = gpu_scene_hemicube_mesh(gs),
                                     .index_count = gs->index_count,
                                     .frames = &c->frames,
                                     .first = frames_first(c, CROSS_FRAMES_FRONT), .count = P});
    if (c->reach_count)
        hemicube_record(c->light_ids, cmd,
                        &(hemicube_draw){.mesh = gpu_scene_hemicube_mesh(gs),
                                         .index_count = gs->index_count,
                                         .frames = &c->reach_frames, .count = c->reach_count});
    gpu_timer_end(s->timer, cmd);
    gpu_timer_begin(s->timer, cmd, "cross.back");
    hemicube_draw back = radiosity_draw(s, c, CROSS_FRAMES_BACK, gs->static_index_count);
    hemicube_record(c->back, cmd, &back);
    if (c->mips) {
        full_barrier(cmd);
        back_mips_record(c->mips, cmd, s->desc.back_res, P * HEMICUBE_FACES);
    }
    gpu_timer_end(s->timer, cmd);
    s->stats.hemicubes += 2 * P + c->reach_count;
}

/* Phase `phase` of the cross reconstruct pass for elements [first, first +
 * count), timed as `timer`. */
static void record_phase(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t phase,
                         uint32_t first, uint32_t count, const char *timer)
{
    full_barrier(cmd);
    gpu_timer_begin(s->timer, cmd, timer);
    cross_reconstruct_record(c->reconstruct, cmd,
                             &(cross_reconstruct_params){
                                 .phase = phase,
                                 .element_count = s->gs.element_count,
                                 .patch_count = c->P,
                                 .light_count = c->L,
                                 .hemicube_res = s->desc.hemicube_res,
                                 .back_res = s->desc.back_res,
                                 .grid = s->desc.cross_grid,
                                 .grid_ff = s->desc.cross_grid_ff,
                                 .bilinear = !s->desc.back_nearest,
                                 .subdivide_ratio = s->desc.subdivide_ratio,
                                 .back_scale = c->scale,
                                 .diameter = c->diameter,
                                 .first = first,
                                 .count = count,
                                 .exact_texel_only = s->desc.id_check == XRAD_ID_CHECK_EXACT,
                                 .pair_capacity = c->pair_capacity,
                                 .cut = s->desc.cross_cut,
                                 .back_levels = c->back_levels,
                                 .luminaires = c->lum.active,
                             });
    gpu_timer_end(s->timer, cmd);
}

static void record_reconstruct(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t phase,
                               uint32_t first, uint32_t count)
{
    record_phase(s, c, cmd, phase, first, count, "cross.reconstruct");
}

/* Step 3 and 4 for M: R_g(C, M) from the gather hemicubes over the atlas
 * that record_reset wrote, the lights' direct light through their ID
 * hemicubes as record_hemicubes drew them, R_p(M, M), and the patches'
 * totals. */
static void record_m(xrad_solver *s, cross *c, VkCommandBuffer cmd)
{
    uint32_t n = s->gs.element_count;
    record_gather(s, c, cmd);
    if (c->reach_count || c->lum.active)
        record_reconstruct(s, c, cmd, CROSS_RECONSTRUCT_M_DIRECT, 0, n);
    full_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_TOTAL, c->P, n, NULL);
    record_reconstruct(s, c, cmd, CROSS_RECONSTRUCT_M, 0, n);
    full_barrier(cmd);
    cross_update_record(c->update, cmd, CROSS_UPDATE_TOTAL, c->P, n, NULL);
}

/* Step 5 for elements [first, first + count): the pairs that see each
 * other listed (cross.pairs), then traced one invocation each and summed
 * per element (cross.reconstruct). */
static void record_step5(xrad_solver *s, cross *c, VkCommandBuffer cmd, uint32_t first,
                         uint32_t count)
{
    full_barrier(cmd);
    vkCmdFillBuffer(cmd, c->pair_state.buffer, 0, sizeof(uint32_t), 0);
    vkCmdFillBuffer(cmd, c->patch_lists.buffer, 0, VK_WHOLE_SIZE, 0);
    record_phase(s, c, cmd, CROSS_RECONSTRUCT_C_PAIRS, first, count, "cross.pairs");
    record_phase(s, c, cmd, CROSS_RECONSTRUCT_C_ARGS, 0, 1, "cross.pairs");
    record_phase(s, c, cmd, CROSS_RECONSTRUCT_C_SCATTER, 0, 0, "cross.pairs");
    record_reconstruct(s, c, cmd, CROSS_RECONSTRUCT_C_EVAL, 0, 0);
    record_reconstruct(s, c, cmd, CROSS_RECONSTRUCT_C, first, count);
}

/* The pairs the last step 5 submission listed, into the stats. */
static void count_pairs(xrad_solver *s, const cross *c)
{
    if (!c->pair_capacity)
        return;
    const struct cross_pair_state *st = c->pair_state.alloc.mapped;
    s->stats.cross_pairs += st->count;
    if (st->count > c->pair_capacity)
        s->stats.cross_pairs_unlisted += st->count - c->pair_capacity;
}

static xrad_status run(xrad_solver *s, gpu_cmd *cmd, xrad_error *err)
{
    full_barrier(cmd->cmd);
    return solver_submit_wait(s, cmd, err);
}

/* The scale that maps the largest |B - Bu - E| of C, measured by the
 * reset pass into c->peak, to HEMICUBE_PEAK. */
static double peak_scale(const cross *c)
{
    float top;
    memcpy(&top, c->peak.alloc.mapped, sizeof(top));
    return top > 0 && isfinite(top) ? HEMICUBE_PEAK / top : 1.0;
}

/* Whether the scale the last reset measured (peak_scale) is more than
 * SCALE_SLACK off c->scale, which then takes it: the work that used the
 * old one is to be made again (stats.cross_rescaled). */
static bool rescaled(xrad_solver *s, cross *c)
{
    double want = peak_scale(c);
    if (want <= c->scale * SCALE_SLACK && want >= c->scale / SCALE_SLACK)
        return false;
    c->scale = want;
    s->stats.cross_rescaled++;
    return true;
}

/* A command buffer begun with step 1 recorded, c->peak zeroed for the
 * reset's measure. */
static xrad_status begin_reset(xrad_solver *s, cross *c, gpu_cmd *cmd, xrad_error *err)
{
    *(uint32_t *)c->peak.alloc.mapped = 0;
    xrad_status st = gpu_cmd_begin(s->ctx, cmd, err);
    if (st)
        return st;
    gpu_timer_start(s->timer, cmd->cmd);
    record_reset(s, c, cmd->cmd);
    return XRAD_OK;
}

/* Steps 1-5 (3 and 4 with `gather`), recorded and run at the pose the
 * frames hold. With `measure` the reset is a submission of its own and the
 * hemicubes take the scale it measured (one host wait more); without,
 * c->scale as it is. */
static xrad_status record_run(xrad_solver *s, cross *c, bool measure, bool gather, xrad_error *err)
{
    uint32_t n = s->gs.element_count, slice = s->desc.slice_elements;
    gpu_cmd cmd;
    xrad_status st = begin_reset(s, c, &cmd, err);
    if (st)
        return st;
    if (measure) {
        if ((st = run(s, &cmd, err)) || (st = gpu_cmd_begin(s->ctx, &cmd, err)))
            return st;
        c->scale = peak_scale(c);
        gpu_timer_start(s->timer, cmd.cmd);
    }
    record_hemicubes(s, c, cmd.cmd);
    if (gather)
        record_m(s, c, cmd.cmd);
    for (uint32_t first = 0; first < n;) {
        uint32_t count = slice && slice < n - first ? slice : n - first;
        if (slice) {
            if ((st = run(s, &cmd, err)))
                return st;
            if (first)
                count_pairs(s, c);
            if ((st = gpu_cmd_begin(s->ctx, &cmd, err)))
                return st;
            gpu_timer_start(s->timer, cmd.cmd);
        }
        if (c->pair_capacity)
            record_step5(s, c, cmd.cmd, first, count);
        else
            record_reconstruct(s, c, cmd.cmd, CROSS_RECONSTRUCT_C, first, count);
        first += count;
    }
    if (!(st = run(s, &cmd, err)))
        count_pairs(s, c);
    return st;
}

/* Steps 1-5 at scene time t (without `gather`, steps 3 and 4 left out:
 * step 5 shoots the patches' totals as they are): one submission, or with
 * desc.slice_elements, one for the hemicubes and the gather and one per
 * slice of step 5, each
 * waited for, so that another thread's work on the queue (a display) gets
 * in between. B^s of C does not change within it (thesis 3.3.4): nothing
 * else is in those submissions, and the progressive iterations come after.
 *
 * The radiosity hemicubes are fp16: their scale follows what they will
 * show (a 1 mm^2 lamp at 1e6 W/m^2 lights walls to 0.2 W/m^2, which any
 * scale made from the lamp's own radiosity sends below fp16's range). The
 * first redistribution of a solve measures it first, in a submission of
 * its own; later ones use the last measure and check it after the fact
 * (issue 16.4: no host wait in the frame for it). Where it was off by more
 * than SCALE_SLACK (C's light changed that much in a frame: a lamp of M
 * came close, tests/solvers/test_cross_scale.c) steps 1-5 are made again
 * at the right scale. That is exact: step 5 adds the same change to B and Bu of
 * C, so the B - Bu - E the reset measures is the same the second time, and
 * the second step 5 replaces what the first inserted. */
static xrad_status redistribute(xrad_solver *s, cross *c, double t, bool gather, xrad_error *err)
{
    struct gpu_shooter *f = c->frames.alloc.mapped;
    dynamic_patches_pose(s->scene, &c->dp, t, s->desc.seed, f + CROSS_FRAMES_FRONT * c->P,
                         f + CROSS_FRAMES_BACK * c->P, f + CROSS_FRAMES_GATHER * c->P,
                         c->quads.alloc.mapped);
    if (c->L)
        light_reach(s, c, t);
    /* The luminaires' light at the pose: M's own, and on C what M takes
     * from (or gives back to) the light of C alone that the progressive
     * solve started from, as part of the source X (step 5). */
    xrad_status st = luminaire_change_pose(&c->lum, s->scene, t, false, err);
    if (st)
        return st;
    bool measure = !c->scale_known;
    st = record_run(s, c, measure, gather, err);
    if (st || measure) {
        c->scale_known = !st;
        return st;
    }
    return rescaled(s, c) ? record_run(s, c, false, gather, err) : XRAD_OK;
}

/* M gathers again, at the same pose, from C as the frame's progressive
 * iterations left it (steps 1, 3 and 4; the ID hemicubes and the lights'
 * are the redistribution's). What M shot to C in this frame's step 5
 * stays as it is; the totals this leaves are what the next frame's step 5
 * shoots with cross_regather after. Gathered only before the frame
 * changed C, a moving box's sides showed the floor as it was a frame
 * earlier (room 1's sliding box's -x side at 0.955 of the CPU reference
 * with 33 ms frames, 0.844 with 100 ms ones). */
static xrad_status regather_once(xrad_solver *s, cross *c, xrad_error *err)
{
    gpu_cmd cmd;
    xrad_status st = begin_reset(s, c, &cmd, err);
    if (st)
        return st;
    record_m(s, c, cmd.cmd);
    return run(s, &cmd, err);
}

/* The regather's reset measures C's light as the iterations left it; where
 * the gather hemicubes' scale was off by more than SCALE_SLACK (a lamp of
 * M came close to the floor in this frame, test_cross_scale.c), it is made
 * again at the right scale, as redistribute() does: it sets M anew from C,
 * so the second time replaces the first. */
static xrad_status regather_m(xrad_solver *s, cross *c, xrad_error *err)
{
    xrad_status st = regather_once(s, c, err);
    if (st)
        return st;
    return rescaled(s, c) ? regather_once(s, c, err) : XRAD_OK;
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
    c->scale_known = false;
    xrad_status st = c->P ? clear_inserted(s, c, err) : XRAD_OK;
    if (!st)
        st = progressive_run(s, c->prog, true, 0, err);
    /* The rounds shoot what M changes at this pose with the restart's
     * finer patches: with the frames' linear rule, few large patches shot
     * the shadow M casts around the plinth from their centres, and
     * cornell-small's plinth sides came out 0.84-1.31 of the CPU
     * reference's (surface_error 0.31, element p95 0.23; 0.084 and 0.148
     * with these). Frames keep the linear rule (select.comp says why). */
    progressive_set_square_root_rule(c->prog, true);
    for (int round = 0; c->P && !st && round < SOLVE_ROUNDS; round++)
        if (!(st = redistribute(s, c, s->desc.time, true, err)))
            st = progressive_run(s, c->prog, false, 0, err);
    progressive_set_square_root_rule(c->prog, false);
    /* As a frame ends (step 7): M shows C as the last round left it, and
     * with after, the first frame's step 5 shoots these totals. */
    if (!st && c->P && s->desc.cross_regather != XRAD_CROSS_REGATHER_OFF)
        st = regather_m(s, c, err);
    solver_collect_times(s);
    return st;
}

static xrad_status advance(xrad_solver *s, double time, xrad_error *err)
{
    cross *c = s->impl;
    double t0 = solver_now_ms();
    xrad_status st = gpu_scene_pose(s->ctx, &s->gs, time, err);
    bool after = s->desc.cross_regather == XRAD_CROSS_REGATHER_AFTER;
    if (!st && c->P)
        st = redistribute(s, c, time, !after, err);
    if (st)
        return st;
    s->stats.redistribute_ms = solver_now_ms() - t0;
    st = progressive_run(s, c->prog, false, s->desc.frame_shots, err);
    if (!st && c->P && s->desc.cross_regather != XRAD_CROSS_REGATHER_OFF)
        st = regather_m(s, c, err);
    solver_collect_times(s);
    return st;
}

xrad_status cross_read_pairs(xrad_solver *s, cross_pair_readback *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    cross *c = s->desc.method == XRAD_METHOD_CROSS ? s->impl : NULL;
    if (!c || !c->pair_capacity)
        return xrad_fail(err, XRAD_ERROR_INPUT, "cross_read_pairs: not a cross solver with "
                                                "cross_pairs on and dynamic objects");
    const struct cross_pair_state *ps = c->pair_state.alloc.mapped;
    uint32_t n = ps->count < c->pair_capacity ? ps->count : c->pair_capacity;
    out->patch_count = c->P;
    out->element_count = s->gs.element_count;
    out->pair_count = n;
    out->pairs = malloc((n ? n : 1) * sizeof(*out->pairs));
    out->ranges = malloc((size_t)(out->element_count ? out->element_count : 1) * 2 *
                         sizeof(*out->ranges));
    out->quads = malloc(c->P * sizeof(*out->quads));
    out->fronts = malloc(c->P * sizeof(*out->fronts));
    out->values = malloc(c->P * sizeof(*out->values));
    memcpy(&out->peak, c->peak.alloc.mapped, sizeof(out->peak));
    xrad_status st = XRAD_OK;
    if (!out->pairs || !out->ranges || !out->quads || !out->fronts || !out->values)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "cross_read_pairs: out of host memory");
    if (!st && n)
        st = gpu_readback_buffer(s->ctx, &c->pairs, 0, out->pairs, n * sizeof(*out->pairs), err);
    if (!st)
        st = gpu_readback_buffer(s->ctx, &c->ranges, 0, out->ranges,
                                 (size_t)out->element_count * 2 * sizeof(*out->ranges), err);
    if (!st)
        st = gpu_readback_buffer(s->ctx, &c->values, 0, out->values,
                                 c->P * sizeof(*out->values), err);
    if (!st) {
        memcpy(out->quads, c->quads.alloc.mapped, c->P * sizeof(*out->quads));
        memcpy(out->fronts, (const struct gpu_shooter *)c->frames.alloc.mapped +
                                frames_first(c, CROSS_FRAMES_FRONT),
               c->P * sizeof(*out->fronts));
    } else {
        cross_pair_readback_free(out);
    }
    return st;
}

void cross_draw_every_light(xrad_solver *s)
{
    if (s->desc.method == XRAD_METHOD_CROSS && s->impl)
        ((cross *)s->impl)->reach_all = true;
}

void cross_shot_draw_counts(xrad_solver *s, uint32_t *host, uint32_t *command)
{
    progressive_draw_counts(((cross *)s->impl)->prog, host, command);
}

void cross_pair_readback_free(cross_pair_readback *r)
{
    free(r->pairs);
    free(r->ranges);
    free(r->quads);
    free(r->fronts);
    free(r->values);
    memset(r, 0, sizeof(*r));
}

const solver_ops cross_ops = {create, solve, destroy, advance};
