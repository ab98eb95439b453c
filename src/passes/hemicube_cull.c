/* Hemicube cull pass (hemicube_cull.h). */
#include "passes/hemicube_cull.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "hemicube_cull.comp.h"
#include "hemicube_cull_shared.h"

#define BINDINGS 4

struct hemicube_cull_pass {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
};

xrad_status hemicube_cull_create(struct xrad_context *ctx, hemicube_cull_pass **out,
                                 xrad_error *err)
{
    *out = NULL;
    hemicube_cull_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube cull pass: out of host memory");
    VkDescriptorSetLayoutBinding bindings[BINDINGS];
    for (uint32_t b = 0; b < BINDINGS; b++)
        bindings[b] = (VkDescriptorSetLayoutBinding){
            .binding = b,
            .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, BINDINGS};
    xrad_status s;
    if ((s = gpu_descriptor_layout_create(ctx, bindings, BINDINGS, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct cull_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, hemicube_cull_comp_spv,
                                         sizeof(hemicube_cull_comp_spv), p->layout, NULL,
                                         &p->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, &size, 1, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
        hemicube_cull_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void hemicube_cull_destroy(struct xrad_context *ctx, hemicube_cull_pass **pass)
{
    if (!pass || !*pass)
        return;
    hemicube_cull_pass *p = *pass;
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    free(p);
    *pass = NULL;
}

void hemicube_cull_bind(struct xrad_context *ctx, hemicube_cull_pass *p,
                        const hemicube_cull_buffers *b)
{
    const gpu_buffer *buffers[BINDINGS] = {
        [CULL_BINDING_CLUSTERS] = b->clusters, [CULL_BINDING_FRAMES] = b->frames,
        [CULL_BINDING_STATUS] = b->status,     [CULL_BINDING_COMMANDS] = b->commands,
    };
    VkDescriptorBufferInfo info[BINDINGS];
    VkWriteDescriptorSet writes[BINDINGS];
    for (uint32_t i = 0; i < BINDINGS; i++) {
        info[i] = (VkDescriptorBufferInfo){buffers[i]->buffer, 0, VK_WHOLE_SIZE};
        writes[i] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = p->set,
            .dstBinding = i,
            .descriptorCount = 1,
            .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .pBufferInfo = &info[i],
        };
    }
    vkUpdateDescriptorSets(ctx->device, BINDINGS, writes, 0, NULL);
}

void hemicube_cull_record(hemicube_cull_pass *p, VkCommandBuffer cmd,
                          const hemicube_cull_params *params)
{
    if (params->cluster_count == 0)
        return;
    struct cull_push push = {
        .cluster_count = params->cluster_count,
        .first = params->first,
        .count_word = params->count_word,
        .count = params->count,
        .instances = params->instances,
        .instance_word = params->instance_word,
        .margin = (float)params->margin,
    };
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (params->cluster_count + CULL_GROUP - 1) / CULL_GROUP, 1, 1);
}
