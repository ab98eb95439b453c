#include "passes/atlas_scatter.h"

#include <stdlib.h>

#include "atlas_scatter.comp.h"
#include "atlas_scatter_shared.h"
#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"

struct atlas_scatter_pass {
    struct xrad_context *ctx;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkBuffer bound_elements, bound_values;
    VkImageView bound_atlas;
};

xrad_status atlas_scatter_create(struct xrad_context *ctx, atlas_scatter_pass **out,
                                 xrad_error *err)
{
    *out = NULL;
    atlas_scatter_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "atlas scatter: out of host memory");
    p->ctx = ctx;
    VkDescriptorSetLayoutBinding bindings[3] = {
        {ATLAS_SCATTER_BINDING_ELEMENTS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {ATLAS_SCATTER_BINDING_VALUES, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {ATLAS_SCATTER_BINDING_ATLAS, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    VkDescriptorPoolSize sizes[2] = {
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
        {VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, 1},
    };
    xrad_status s;
    if ((s = gpu_descriptor_layout_create(ctx, bindings, 3, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1,
                                        sizeof(struct atlas_scatter_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, atlas_scatter_comp_spv,
                                         sizeof(atlas_scatter_comp_spv), p->layout, NULL,
                                         &p->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, sizes, 2, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
        atlas_scatter_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void atlas_scatter_destroy(struct xrad_context *ctx, atlas_scatter_pass **pass)
{
    if (!pass || !*pass)
        return;
    atlas_scatter_pass *p = *pass;
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    free(p);
    *pass = NULL;
}

void atlas_scatter_record(atlas_scatter_pass *p, VkCommandBuffer cmd,
                          const atlas_scatter_draw *d)
{
    if (d->element_count == 0)
        return;
    if (p->bound_elements != d->elements->buffer || p->bound_values != d->values->buffer ||
        p->bound_atlas != d->atlas->view) {
        VkDescriptorBufferInfo bi[2] = {
            {d->elements->buffer, 0, VK_WHOLE_SIZE},
            {d->values->buffer, 0, VK_WHOLE_SIZE},
        };
        VkDescriptorImageInfo ii = {VK_NULL_HANDLE, d->atlas->view, VK_IMAGE_LAYOUT_GENERAL};
        VkWriteDescriptorSet w[3];
        for (uint32_t i = 0; i < 3; i++)
            w[i] = (VkWriteDescriptorSet){
                .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                .dstSet = p->set,
                .dstBinding = i,
                .descriptorCount = 1,
                .descriptorType = i == ATLAS_SCATTER_BINDING_ATLAS
                                      ? VK_DESCRIPTOR_TYPE_STORAGE_IMAGE
                                      : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                .pBufferInfo = i < 2 ? &bi[i] : NULL,
                .pImageInfo = i == 2 ? &ii : NULL,
            };
        vkUpdateDescriptorSets(p->ctx->device, 3, w, 0, NULL);
        p->bound_elements = d->elements->buffer;
        p->bound_values = d->values->buffer;
        p->bound_atlas = d->atlas->view;
    }
    struct atlas_scatter_push push = {.element_count = d->element_count};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, (d->element_count + ATLAS_SCATTER_GROUP - 1) / ATLAS_SCATTER_GROUP, 1, 1);
}
