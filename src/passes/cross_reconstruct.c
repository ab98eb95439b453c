#include "passes/cross_reconstruct.h"

#include <stddef.h>
#include <stdlib.h>

#include "core/error.h"
#include "cross_reconstruct.comp.h"
#include "cross_reconstruct_full.comp.h"
#include "cross_shared.h"
#include "gpu/kernel.h"

struct cross_reconstruct_pass {
    gpu_kernel kernel;
    const gpu_buffer *pair_state; /* C_EVAL's indirect dispatch */
};

xrad_status cross_reconstruct_create(struct xrad_context *ctx, bool full,
                                     cross_reconstruct_pass **out, xrad_error *err)
{
    *out = NULL;
    cross_reconstruct_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "cross reconstruct pass: out of host memory");
    VkDescriptorType types[CROSS_RECONSTRUCT_BINDING_COUNT];
    for (uint32_t b = 0; b < CROSS_RECONSTRUCT_BINDING_COUNT; b++)
        types[b] = b == CROSS_RECONSTRUCT_BINDING_IDS || b == CROSS_RECONSTRUCT_BINDING_BACK ||
                           b == CROSS_RECONSTRUCT_BINDING_LIGHT_IDS_C ||
                           b == CROSS_RECONSTRUCT_BINDING_LIGHT_IDS
                       ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                       : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc d = {
        .spv = full ? cross_reconstruct_full_comp_spv : cross_reconstruct_comp_spv,
        .spv_bytes = full ? sizeof(cross_reconstruct_full_comp_spv)
                          : sizeof(cross_reconstruct_comp_spv),
        .types = types,
        .binding_count = CROSS_RECONSTRUCT_BINDING_COUNT,
        .set_count = 1,
        .push_bytes = sizeof(struct cross_reconstruct_push),
        .name = "cross reconstruct pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void cross_reconstruct_destroy(struct xrad_context *ctx, cross_reconstruct_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void cross_reconstruct_bind(struct xrad_context *ctx, cross_reconstruct_pass *p,
                            const cross_reconstruct_bindings *b)
{
    gpu_kernel_resource r[CROSS_RECONSTRUCT_BINDING_COUNT] = {
        [CROSS_RECONSTRUCT_BINDING_SURFACES] = {b->surfaces, 0},
        [CROSS_RECONSTRUCT_BINDING_ELEMENTS] = {b->elements, 0},
        [CROSS_RECONSTRUCT_BINDING_MATERIALS] = {b->materials, 0},
        [CROSS_RECONSTRUCT_BINDING_B] = {b->B, 0},
        [CROSS_RECONSTRUCT_BINDING_BU] = {b->Bu, 0},
        [CROSS_RECONSTRUCT_BINDING_VALUES] = {b->values, 0},
        [CROSS_RECONSTRUCT_BINDING_FRAMES] = {b->frames, 0},
        [CROSS_RECONSTRUCT_BINDING_QUADS] = {b->quads, 0},
        [CROSS_RECONSTRUCT_BINDING_IDS] = {NULL, b->ids},
        [CROSS_RECONSTRUCT_BINDING_BACK] = {NULL, b->back},
        [CROSS_RECONSTRUCT_BINDING_INSERTED] = {b->inserted, 0},
        [CROSS_RECONSTRUCT_BINDING_LIGHTS] = {b->lights, 0},
        [CROSS_RECONSTRUCT_BINDING_LIGHT_QUADS] = {b->light_quads, 0},
        [CROSS_RECONSTRUCT_BINDING_LIGHT_IDS_C] = {NULL, b->light_ids_c},
        [CROSS_RECONSTRUCT_BINDING_LIGHT_IDS] = {NULL, b->light_ids},
        [CROSS_RECONSTRUCT_BINDING_BVH_NODES] = {b->bvh_nodes, 0},
        [CROSS_RECONSTRUCT_BINDING_BVH_ITEMS] = {b->bvh_items, 0},
        [CROSS_RECONSTRUCT_BINDING_PAIRS] = {b->pairs, 0},
        [CROSS_RECONSTRUCT_BINDING_RANGES] = {b->ranges, 0},
        [CROSS_RECONSTRUCT_BINDING_PAIR_STATE] = {b->pair_state, 0},
        [CROSS_RECONSTRUCT_BINDING_ORDER] = {b->order, 0},
        [CROSS_RECONSTRUCT_BINDING_PATCH_LISTS] = {b->patch_lists, 0},
        [CROSS_RECONSTRUCT_BINDING_PEAK] = {b->peak, 0},
        [CROSS_RECONSTRUCT_BINDING_BACK_MIPS] = {b->back_mips, 0},
        [CROSS_RECONSTRUCT_BINDING_LIGHT_LAYERS] = {b->light_layers, 0},
        [CROSS_RECONSTRUCT_BINDING_LUMINAIRES] = {b->luminaires, 0},
    };
    p->pair_state = b->pair_state;
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void cross_reconstruct_record(cross_reconstruct_pass *p, VkCommandBuffer cmd,
                              const cross_reconstruct_params *q)
{
    struct cross_reconstruct_push push = {
        .element_count = q->element_count,
        .patch_count = q->patch_count,
        .hemicube_res = q->hemicube_res,
        .back_res = q->back_res,
        .grid = q->grid,
        .bilinear = q->bilinear ? 1u : 0u,
        .phase = q->phase,
        .neighbours = q->exact_texel_only ? 0u : 1u,
        .subdivide_ratio = (float)q->subdivide_ratio,
        .inv_scale = (float)(1.0 / q->back_scale),
        .diameter = (float)q->diameter,
        .first = q->first,
        .count = q->count ? q->count : q->element_count - q->first,
        .light_count = q->light_count,
        .grid_ff = (float)q->grid_ff,
        .pair_capacity = q->pair_capacity,
        .cut = (float)q->cut,
        .back_levels = q->back_levels,
        .luminaires = q->luminaires ? 1u : 0u,
    };
    if (q->phase == CROSS_RECONSTRUCT_C_ARGS)
        gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, 1, CROSS_RECONSTRUCT_GROUP);
    else if (q->phase == CROSS_RECONSTRUCT_C_SCATTER)
        gpu_kernel_dispatch_indirect(&p->kernel, cmd, 0, &push, p->pair_state,
                                     offsetof(struct cross_pair_state, scatter));
    else if (q->phase == CROSS_RECONSTRUCT_C_EVAL)
        gpu_kernel_dispatch_indirect(&p->kernel, cmd, 0, &push, p->pair_state,
                                     offsetof(struct cross_pair_state, eval));
    else
        gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, push.count, CROSS_RECONSTRUCT_GROUP);
}
