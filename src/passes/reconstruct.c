#include "passes/reconstruct.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "reconstruct.comp.h"
#include "reconstruct_far.comp.h"
#include "reconstruct_shared.h"

struct reconstruct_pass {
    gpu_kernel kernel;
};

uint32_t reconstruct_group_size(void) { return RECONSTRUCT_GROUP; }

xrad_status reconstruct_create(struct xrad_context *ctx, bool conserve_far,
                               reconstruct_pass **out, xrad_error *err)
{
    *out = NULL;
    reconstruct_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reconstruct pass: out of host memory");
    VkDescriptorType types[RECONSTRUCT_BINDING_COUNT];
    for (uint32_t b = 0; b < RECONSTRUCT_BINDING_COUNT; b++)
        types[b] = b == RECONSTRUCT_BINDING_HEMICUBES ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                                                      : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc d = {
        .spv = conserve_far ? reconstruct_far_comp_spv : reconstruct_comp_spv,
        .spv_bytes = conserve_far ? sizeof(reconstruct_far_comp_spv) : sizeof(reconstruct_comp_spv),
        .types = types,
        .binding_count = RECONSTRUCT_BINDING_COUNT,
        .push_bytes = sizeof(struct reconstruct_push),
        .name = "reconstruct pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void reconstruct_destroy(struct xrad_context *ctx, reconstruct_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void reconstruct_bind(struct xrad_context *ctx, reconstruct_pass *p,
                      const reconstruct_bindings *b)
{
    gpu_kernel_resource r[RECONSTRUCT_BINDING_COUNT] = {
        [RECONSTRUCT_BINDING_SURFACES] = {b->surfaces},
        [RECONSTRUCT_BINDING_ELEMENTS] = {b->elements},
        [RECONSTRUCT_BINDING_MATERIALS] = {b->materials},
        [RECONSTRUCT_BINDING_B] = {b->B},
        [RECONSTRUCT_BINDING_BU] = {b->Bu},
        [RECONSTRUCT_BINDING_SHOOTERS] = {b->shooters},
        [RECONSTRUCT_BINDING_FF] = {b->ff},
        [RECONSTRUCT_BINDING_NORM] = {b->norm},
        [RECONSTRUCT_BINDING_STATUS] = {b->status},
        [RECONSTRUCT_BINDING_SHOT] = {b->shot},
        [RECONSTRUCT_BINDING_BVH_NODES] = {b->bvh_nodes},
        [RECONSTRUCT_BINDING_BVH_ITEMS] = {b->bvh_items},
        [RECONSTRUCT_BINDING_HEMICUBES] = {.view = b->hemicubes},
    };
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void reconstruct_record(reconstruct_pass *p, VkCommandBuffer cmd,
                        const reconstruct_params *params, const gpu_buffer *status,
                        VkDeviceSize dispatch_offset)
{
    struct reconstruct_push push = {
        .element_count = params->element_count,
        .hemicube_res = params->hemicube_res,
        .neighbours = params->exact_texel_only ? 0u : 1u,
        .mode = params->conserve ? RECONSTRUCT_MODE_FF : RECONSTRUCT_MODE_DIRECT,
        .subdivide_ratio = (float)params->subdivide_ratio,
        .max_shooters = params->max_shooters,
        .conserve_fixed = params->conserve_fixed ? 1u : 0u,
        .static_only = params->static_only ? 1u : 0u,
        .redistributed = params->redistributed ? 1u : 0u,
        .near_blocks = params->near_blocks && !params->redistributed ? 1u : 0u,
    };
    gpu_kernel_dispatch_indirect(&p->kernel, cmd, 0, &push, status, dispatch_offset);
    if (!params->conserve)
        return;
    const VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    gpu_memory_barrier(cmd, cs, VK_ACCESS_SHADER_WRITE_BIT, cs, VK_ACCESS_SHADER_READ_BIT);
    push.mode = RECONSTRUCT_MODE_NORM;
    gpu_kernel_dispatch_groups(&p->kernel, cmd, 0, &push, params->max_shooters); /* a group per shooter */
    gpu_memory_barrier(cmd, cs, VK_ACCESS_SHADER_WRITE_BIT, cs, VK_ACCESS_SHADER_READ_BIT);
    push.mode = RECONSTRUCT_MODE_APPLY;
    gpu_kernel_dispatch_indirect(&p->kernel, cmd, 0, &push, status, dispatch_offset);
}
