#include "passes/select.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "scene/scene.h"
#include "select.comp.h"
#include "select_shared.h"
#include "select_power.comp.h"

struct select_pass {
    uint32_t surface_count;
    gpu_buffer power; /* float[surface_count] */
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline power_pipeline, select_pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
};

xrad_status select_create(struct xrad_context *ctx, uint32_t surface_count, select_pass **out,
                          xrad_error *err)
{
    *out = NULL;
    if (surface_count == 0)
        return xrad_fail(err, XRAD_ERROR_INPUT, "select pass: the scene has no surfaces");
    select_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "select pass: out of host memory");
    p->surface_count = surface_count;
    VkDescriptorSetLayoutBinding bindings[SELECT_BINDING_COUNT];
    for (uint32_t b = 0; b < SELECT_BINDING_COUNT; b++)
        bindings[b] = (VkDescriptorSetLayoutBinding){
            .binding = b,
            .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, SELECT_BINDING_COUNT};
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, (VkDeviceSize)surface_count * sizeof(float),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                               GPU_MEM_RADIOSITY, &p->power, err)) ||
        (s = gpu_descriptor_layout_create(ctx, bindings, SELECT_BINDING_COUNT, &p->set_layout,
                                          err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct select_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, select_power_comp_spv,
                                         sizeof(select_power_comp_spv), p->layout, NULL,
                                         &p->power_pipeline, err)) ||
        (s = gpu_compute_pipeline_create(ctx, select_comp_spv, sizeof(select_comp_spv),
                                         p->layout, NULL, &p->select_pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, &size, 1, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
        select_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void select_destroy(struct xrad_context *ctx, select_pass **pass)
{
    if (!pass || !*pass)
        return;
    select_pass *p = *pass;
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->select_pipeline, NULL);
    vkDestroyPipeline(ctx->device, p->power_pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    gpu_buffer_destroy(ctx, &p->power);
    free(p);
    *pass = NULL;
}

void select_bind(struct xrad_context *ctx, select_pass *p, const select_buffers *b)
{
    const gpu_buffer *buffers[SELECT_BINDING_COUNT] = {
        [SELECT_BINDING_SURFACES] = b->surfaces, [SELECT_BINDING_ELEMENTS] = b->elements,
        [SELECT_BINDING_BU] = b->Bu,             [SELECT_BINDING_POWER] = &p->power,
        [SELECT_BINDING_SHOOTERS] = b->shooters, [SELECT_BINDING_STATUS] = b->status,
        [SELECT_BINDING_SHOT] = b->shot,
    };
    VkDescriptorBufferInfo info[SELECT_BINDING_COUNT];
    VkWriteDescriptorSet writes[SELECT_BINDING_COUNT];
    for (uint32_t i = 0; i < SELECT_BINDING_COUNT; i++) {
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
    vkUpdateDescriptorSets(ctx->device, SELECT_BINDING_COUNT, writes, 0, NULL);
}

void select_record(select_pass *p, VkCommandBuffer cmd, const select_params *params)
{
    struct select_push push = {
        .surface_count = p->surface_count,
        .element_count = params->element_count,
        .max_patches = params->max_patches ? params->max_patches : 1,
        .max_shooters = params->max_shooters ? params->max_shooters : 1,
        .draw_index_count = params->draw_index_count,
        .instances_per_hemicube = params->instances_per_hemicube,
        .seed = params->seed,
        .reconstruct_group = params->reconstruct_group ? params->reconstruct_group : 1,
        .threshold = (float)params->threshold,
        .linear_rule = params->linear_rule ? 1u : 0u,
        .buried_mask = params->buried_mask,
        .unshot_share = (float)params->unshot_share,
        .group_shooters = params->group_shooters,
        .group_elements = params->group_elements,
        .shot_first = params->shot_first,
    };
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->power_pipeline);
    vkCmdDispatch(cmd, (p->surface_count + SELECT_POWER_GROUP - 1) / SELECT_POWER_GROUP, 1, 1);
    /* The powers are complete before the argmax reads them. */
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_READ_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0, 1, &barrier, 0, NULL, 0, NULL);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->select_pipeline);
    vkCmdDispatch(cmd, 1, 1, 1);
}

uint32_t select_shot_capacity(const xrad_scene *scene)
{
    uint32_t most = 1;
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        uint32_t n = scene->surfaces[k].nu * scene->surfaces[k].nv;
        most = n > most ? n : most;
    }
    return most;
}
