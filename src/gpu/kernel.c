#include "gpu/kernel.h"

#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"

xrad_status gpu_kernel_create(struct xrad_context *ctx, const gpu_kernel_desc *d, gpu_kernel *k,
                              xrad_error *err)
{
    memset(k, 0, sizeof(*k));
    uint32_t sets = d->set_count ? d->set_count : 1;
    if (d->binding_count == 0 || d->binding_count > GPU_KERNEL_MAX_BINDINGS ||
        sets > GPU_KERNEL_MAX_SETS)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: %u bindings, %u sets are out of range",
                         d->name, d->binding_count, sets);
    VkDescriptorSetLayoutBinding bindings[GPU_KERNEL_MAX_BINDINGS];
    uint32_t buffers = 0, images = 0;
    for (uint32_t b = 0; b < d->binding_count; b++) {
        bindings[b] = (VkDescriptorSetLayoutBinding){
            .binding = b,
            .descriptorType = d->types[b],
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
        k->types[b] = d->types[b];
        if (d->types[b] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER)
            buffers++;
        else
            images++;
    }
    VkDescriptorPoolSize sizes[2];
    uint32_t nsizes = 0;
    if (buffers)
        sizes[nsizes++] = (VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers * sets};
    if (images)
        sizes[nsizes++] = (VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, images * sets};
    k->binding_count = d->binding_count;
    k->set_count = sets;
    k->push_bytes = d->push_bytes;
    xrad_status s;
    if ((s = gpu_descriptor_layout_create(ctx, bindings, d->binding_count, &k->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &k->set_layout, 1, d->push_bytes,
                                        VK_SHADER_STAGE_COMPUTE_BIT, &k->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, d->spv, d->spv_bytes, k->layout, NULL,
                                         &k->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, sizes, nsizes, sets, &k->pool, err)))
        goto fail;
    for (uint32_t i = 0; i < sets; i++)
        if ((s = gpu_descriptor_set_allocate(ctx, k->pool, k->set_layout, &k->sets[i], err)))
            goto fail;
    return XRAD_OK;

fail:
    gpu_kernel_destroy(ctx, k);
    xrad_error_prefix(err, "%s", d->name);
    return s;
}

void gpu_kernel_destroy(struct xrad_context *ctx, gpu_kernel *k)
{
    if (!k)
        return;
    vkDestroyDescriptorPool(ctx->device, k->pool, NULL);
    vkDestroyPipeline(ctx->device, k->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, k->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, k->set_layout, NULL);
    memset(k, 0, sizeof(*k));
}

void gpu_kernel_bind(struct xrad_context *ctx, gpu_kernel *k, uint32_t set,
                     const gpu_kernel_resource *r)
{
    VkDescriptorBufferInfo bi[GPU_KERNEL_MAX_BINDINGS];
    VkDescriptorImageInfo ii[GPU_KERNEL_MAX_BINDINGS];
    VkWriteDescriptorSet w[GPU_KERNEL_MAX_BINDINGS];
    for (uint32_t b = 0; b < k->binding_count; b++) {
        w[b] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = k->sets[set],
            .dstBinding = b,
            .descriptorCount = 1,
            .descriptorType = k->types[b],
        };
        if (k->types[b] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER) {
            bi[b] = (VkDescriptorBufferInfo){r[b].buffer->buffer, 0, VK_WHOLE_SIZE};
            w[b].pBufferInfo = &bi[b];
        } else {
            ii[b] = (VkDescriptorImageInfo){VK_NULL_HANDLE, r[b].view,
                                            VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            w[b].pImageInfo = &ii[b];
        }
    }
    vkUpdateDescriptorSets(ctx->device, k->binding_count, w, 0, NULL);
}

void gpu_kernel_dispatch(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set, const void *push,
                         uint32_t invocations, uint32_t group)
{
    if (!invocations)
        return;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->layout, 0, 1, &k->sets[set],
                            0, NULL);
    if (k->push_bytes)
        vkCmdPushConstants(cmd, k->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, k->push_bytes, push);
    vkCmdDispatch(cmd, (invocations + group - 1) / group, 1, 1);
}
