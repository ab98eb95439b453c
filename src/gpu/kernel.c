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
    uint32_t buffers = 0, images = 0, storage_images = 0;
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
        else if (d->types[b] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE)
            storage_images++;
        else
            images++;
    }
    VkDescriptorPoolSize sizes[3];
    uint32_t nsizes = 0;
    if (buffers)
        sizes[nsizes++] = (VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, buffers * sets};
    if (images)
        sizes[nsizes++] = (VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, images * sets};
    if (storage_images)
        sizes[nsizes++] =
            (VkDescriptorPoolSize){VK_DESCRIPTOR_TYPE_STORAGE_IMAGE, storage_images * sets};
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
    uint32_t n = 0;
    for (uint32_t b = 0; b < k->binding_count; b++) {
        int buffer = k->types[b] == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        if (buffer ? !r[b].buffer : !r[b].view)
            continue;
        w[n] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = k->sets[set],
            .dstBinding = b,
            .descriptorCount = 1,
            .descriptorType = k->types[b],
        };
        if (buffer) {
            bi[n] = (VkDescriptorBufferInfo){r[b].buffer->buffer, 0, VK_WHOLE_SIZE};
            w[n].pBufferInfo = &bi[n];
        } else {
            ii[n] = (VkDescriptorImageInfo){VK_NULL_HANDLE, r[b].view,
                                            k->types[b] == VK_DESCRIPTOR_TYPE_STORAGE_IMAGE
                                                ? VK_IMAGE_LAYOUT_GENERAL
                                                : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
            w[n].pImageInfo = &ii[n];
        }
        n++;
    }
    if (n)
        vkUpdateDescriptorSets(ctx->device, n, w, 0, NULL);
}

/* The pipeline, set `set` and the push constants. */
static void kernel_begin(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set, const void *push)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, k->layout, 0, 1, &k->sets[set],
                            0, NULL);
    if (k->push_bytes)
        vkCmdPushConstants(cmd, k->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, k->push_bytes, push);
}

void gpu_kernel_dispatch_groups(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set,
                                const void *push, uint32_t groups)
{
    if (!groups)
        return;
    kernel_begin(k, cmd, set, push);
    vkCmdDispatch(cmd, groups, 1, 1);
}

void gpu_kernel_dispatch_indirect(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set,
                                  const void *push, const gpu_buffer *indirect,
                                  VkDeviceSize offset)
{
    kernel_begin(k, cmd, set, push);
    vkCmdDispatchIndirect(cmd, indirect->buffer, offset);
}

void gpu_kernel_dispatch(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set, const void *push,
                         uint32_t invocations, uint32_t group)
{
    gpu_kernel_dispatch_groups(k, cmd, set, push, (invocations + group - 1) / group);
}
