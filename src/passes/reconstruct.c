#include "passes/reconstruct.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "reconstruct.comp.h"
#include "reconstruct_shared.h"

struct reconstruct_pass {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
};

uint32_t reconstruct_group_size(void) { return RECONSTRUCT_GROUP; }

xrad_status reconstruct_create(struct xrad_context *ctx, reconstruct_pass **out,
                               xrad_error *err)
{
    *out = NULL;
    reconstruct_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reconstruct pass: out of host memory");
    VkDescriptorSetLayoutBinding bindings[RECONSTRUCT_BINDING_COUNT];
    for (uint32_t b = 0; b < RECONSTRUCT_BINDING_COUNT; b++)
        bindings[b] = (VkDescriptorSetLayoutBinding){
            .binding = b,
            .descriptorType = b == RECONSTRUCT_BINDING_HEMICUBES
                                  ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE
                                  : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
    VkDescriptorPoolSize sizes[2] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, RECONSTRUCT_BINDING_COUNT - 1},
        {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1},
    };
    xrad_status s;
    if ((s = gpu_descriptor_layout_create(ctx, bindings, RECONSTRUCT_BINDING_COUNT,
                                          &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct reconstruct_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, reconstruct_comp_spv, sizeof(reconstruct_comp_spv),
                                         p->layout, NULL, &p->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, sizes, 2, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
        reconstruct_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void reconstruct_destroy(struct xrad_context *ctx, reconstruct_pass **pass)
{
    if (!pass || !*pass)
        return;
    reconstruct_pass *p = *pass;
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    free(p);
    *pass = NULL;
}

void reconstruct_bind(struct xrad_context *ctx, reconstruct_pass *p,
                      const reconstruct_bindings *b)
{
    const gpu_buffer *buffers[RECONSTRUCT_BINDING_COUNT] = {
        [RECONSTRUCT_BINDING_SURFACES] = b->surfaces, [RECONSTRUCT_BINDING_ELEMENTS] = b->elements,
        [RECONSTRUCT_BINDING_MATERIALS] = b->materials, [RECONSTRUCT_BINDING_B] = b->B,
        [RECONSTRUCT_BINDING_BU] = b->Bu,             [RECONSTRUCT_BINDING_SHOOTERS] = b->shooters,
        [RECONSTRUCT_BINDING_FF] = b->ff,             [RECONSTRUCT_BINDING_NORM] = b->norm,
        [RECONSTRUCT_BINDING_STATUS] = b->status,      [RECONSTRUCT_BINDING_SHOT] = b->shot,
        [RECONSTRUCT_BINDING_BVH_NODES] = b->bvh_nodes, [RECONSTRUCT_BINDING_BVH_ITEMS] = b->bvh_items,
    };
    VkDescriptorBufferInfo info[RECONSTRUCT_BINDING_COUNT];
    VkDescriptorImageInfo image = {
        .imageView = b->hemicubes,
        .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
    };
    VkWriteDescriptorSet writes[RECONSTRUCT_BINDING_COUNT];
    for (uint32_t i = 0; i < RECONSTRUCT_BINDING_COUNT; i++) {
        writes[i] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = p->set,
            .dstBinding = i,
            .descriptorCount = 1,
        };
        if (i == RECONSTRUCT_BINDING_HEMICUBES) {
            writes[i].descriptorType = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
            writes[i].pImageInfo = &image;
        } else {
            info[i] = (VkDescriptorBufferInfo){buffers[i]->buffer, 0, VK_WHOLE_SIZE};
            writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            writes[i].pBufferInfo = &info[i];
        }
    }
    vkUpdateDescriptorSets(ctx->device, RECONSTRUCT_BINDING_COUNT, writes, 0, NULL);
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
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatchIndirect(cmd, status->buffer, dispatch_offset);
    if (!params->conserve)
        return;
    const VkPipelineStageFlags cs = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    gpu_memory_barrier(cmd, cs, VK_ACCESS_SHADER_WRITE_BIT, cs, VK_ACCESS_SHADER_READ_BIT);
    push.mode = RECONSTRUCT_MODE_NORM;
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (params->max_shooters + RECONSTRUCT_GROUP - 1) / RECONSTRUCT_GROUP, 1, 1);
    gpu_memory_barrier(cmd, cs, VK_ACCESS_SHADER_WRITE_BIT, cs, VK_ACCESS_SHADER_READ_BIT);
    push.mode = RECONSTRUCT_MODE_APPLY;
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatchIndirect(cmd, status->buffer, dispatch_offset);
}
