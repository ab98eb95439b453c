#include "passes/incremental_reconstruct.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/kernel.h"
#include "incremental_reconstruct.comp.h"
#include "incremental_shared.h"

struct incremental_reconstruct_pass {
    gpu_kernel kernel;
    incremental_reconstruct_params params;
};

xrad_status incremental_reconstruct_create(struct xrad_context *ctx,
                                           const incremental_reconstruct_params *params,
                                           incremental_reconstruct_pass **out,
                                           xrad_error *err)
{
    *out = NULL;
    incremental_reconstruct_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "incremental reconstruct pass: out of host memory");
    p->params = *params;
    VkDescriptorType types[INCR_BINDING_COUNT];
    for (uint32_t b = 0; b < INCR_BINDING_COUNT; b++)
        types[b] = b >= INCR_BINDING_IDS_OLD ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                                             : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc d = {
        .spv = incremental_reconstruct_comp_spv,
        .spv_bytes = sizeof(incremental_reconstruct_comp_spv),
        .types = types,
        .binding_count = INCR_BINDING_COUNT,
        .push_bytes = sizeof(struct incr_push),
        .name = "incremental reconstruct pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void incremental_reconstruct_destroy(struct xrad_context *ctx,
                                     incremental_reconstruct_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void incremental_reconstruct_bind(struct xrad_context *ctx, incremental_reconstruct_pass *p,
                                  const incremental_reconstruct_bindings *b)
{
    gpu_kernel_resource r[INCR_BINDING_COUNT] = {
        [INCR_BINDING_SURFACES] = {b->surfaces, 0},
        [INCR_BINDING_ELEMENTS] = {b->elements, 0},
        [INCR_BINDING_MATERIALS] = {b->materials, 0},
        [INCR_BINDING_B] = {b->B, 0},
        [INCR_BINDING_BU] = {b->Bu, 0},
        [INCR_BINDING_SHOOTERS] = {b->shooters, 0},
        [INCR_BINDING_VALUES] = {b->values, 0},
        [INCR_BINDING_POWER] = {b->power, 0},
        [INCR_BINDING_OLD_SURFACES] = {b->old_surfaces, 0},
        [INCR_BINDING_M_LIGHT] = {b->m_light, 0},
        [INCR_BINDING_LUMINAIRES] = {b->luminaires, 0},
        [INCR_BINDING_IDS_OLD] = {NULL, b->ids_old},
        [INCR_BINDING_IDS_NEW] = {NULL, b->ids_new},
    };
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void incremental_reconstruct_record(incremental_reconstruct_pass *p, VkCommandBuffer cmd,
                                    uint32_t mode, uint32_t first, uint32_t count)
{
    const incremental_reconstruct_params *q = &p->params;
    struct incr_push push = {
        .mode = mode,
        .first = first,
        .count = mode == INCR_MODE_POWER                              ? q->surface_count
                 : mode == INCR_MODE_RESET || mode == INCR_MODE_CLEAR ? q->element_count
                                                                      : count,
        .element_count = q->element_count,
        .hemicube_res = q->hemicube_res,
        .neighbours = q->exact_texel_only ? 0u : 1u,
        .subdivide_ratio = (float)q->subdivide_ratio,
        .luminaires = q->luminaires ? 1u : 0u,
    };
    /* Shooting steps run one invocation per receiving element. */
    uint32_t invocations = mode == INCR_MODE_NEGATIVE || mode == INCR_MODE_INCREMENT ||
                                   mode == INCR_MODE_M_LIGHT || mode == INCR_MODE_RECEIVE_M
                               ? (count ? q->element_count : 0)
                               : push.count;
    gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, invocations, INCR_GROUP);
}
