#include "gpu/cmd.h"

#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

xrad_status gpu_cmd_begin(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err)
{
    memset(c, 0, sizeof(*c));
    xrad_status s = gpu_context_check_alive(ctx, "recording GPU commands", err);
    if (s)
        return s;
    if ((s = gpu_thread_pool(ctx, &c->pool, err)))
        return s;
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = c->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    if ((s = VK_CHECK(ctx, err, vkAllocateCommandBuffers(ctx->device, &alloc, &c->cmd))))
        return s;
    VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if ((s = VK_CHECK(ctx, err, vkCreateFence(ctx->device, &fence, NULL, &c->fence))))
        goto fail;
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    if ((s = VK_CHECK(ctx, err, vkBeginCommandBuffer(c->cmd, &begin))))
        goto fail;
    /* Memory this recording uses may have belonged to a freed resource
     * that earlier submissions wrote (suballocation, gpu/memory.h): order
     * it after them. */
    gpu_memory_barrier(c->cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                       VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT);
    return XRAD_OK;

fail:
    gpu_cmd_destroy(ctx, c);
    return s;
}

xrad_status gpu_queue_submit(struct xrad_context *ctx, const VkSubmitInfo *submit, VkFence fence,
                             xrad_error *err)
{
    xrad_status s = gpu_context_check_alive(ctx, "submitting GPU commands", err);
    if (s)
        return s;
    gpu_queue_lock(ctx);
    s = VK_CHECK(ctx, err, vkQueueSubmit(ctx->queue, 1, submit, fence));
    gpu_queue_unlock(ctx);
    return s;
}

xrad_status gpu_cmd_submit_sync(struct xrad_context *ctx, gpu_cmd *c, const gpu_sync *sync,
                                xrad_error *err)
{
    xrad_status s = gpu_context_check_alive(ctx, "submitting GPU commands", err);
    if (s)
        return s;
    if ((s = VK_CHECK(ctx, err, vkEndCommandBuffer(c->cmd))))
        return s;
    bool has_timeline = ctx->timeline != VK_NULL_HANDLE;
    bool wait = sync && sync->wait, signal = sync && sync->signal;
    gpu_queue_lock(ctx);
    uint64_t value = ctx->timeline_value + 1;
    VkSemaphore signals[2];
    uint64_t signal_values[2];
    uint32_t signal_count = 0;
    if (has_timeline) {
        signals[signal_count] = ctx->timeline;
        signal_values[signal_count++] = value;
    }
    if (signal) {
        signals[signal_count] = sync->signal;
        signal_values[signal_count++] = sync->signal_value;
    }
    VkTimelineSemaphoreSubmitInfo timeline = {
        .sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
        .waitSemaphoreValueCount = wait ? 1 : 0,
        .pWaitSemaphoreValues = wait ? &sync->wait_value : NULL,
        .signalSemaphoreValueCount = signal_count,
        .pSignalSemaphoreValues = signal_values,
    };
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .pNext = signal_count || wait ? &timeline : NULL,
        .waitSemaphoreCount = wait ? 1 : 0,
        .pWaitSemaphores = wait ? &sync->wait : NULL,
        .pWaitDstStageMask = wait ? &sync->wait_stage : NULL,
        .commandBufferCount = 1,
        .pCommandBuffers = &c->cmd,
        .signalSemaphoreCount = signal_count,
        .pSignalSemaphores = signals,
    };
    s = VK_CHECK(ctx, err, vkQueueSubmit(ctx->queue, 1, &submit, c->fence));
    if (!s)
        ctx->timeline_value = value;
    gpu_queue_unlock(ctx);
    if (s)
        return s;
    c->value = value;
    c->submitted = true;
    return XRAD_OK;
}

xrad_status gpu_cmd_submit(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err)
{
    return gpu_cmd_submit_sync(ctx, c, NULL, err);
}

xrad_status gpu_timeline_create(struct xrad_context *ctx, VkSemaphore *out, xrad_error *err)
{
    VkSemaphoreTypeCreateInfo type = {
        .sType = VK_STRUCTURE_TYPE_SEMAPHORE_TYPE_CREATE_INFO,
        .semaphoreType = VK_SEMAPHORE_TYPE_TIMELINE,
        .initialValue = 0,
    };
    VkSemaphoreCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO,
        .pNext = &type,
    };
    *out = VK_NULL_HANDLE;
    if (!ctx->features.timeline_semaphore)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "device '%s' has no timeline semaphores",
                         ctx->props.deviceName);
    return VK_CHECK(ctx, err, vkCreateSemaphore(ctx->device, &info, NULL, out));
}

xrad_status gpu_timeline_value(struct xrad_context *ctx, VkSemaphore sem, uint64_t *value,
                               xrad_error *err)
{
    return VK_CHECK(ctx, err, vkGetSemaphoreCounterValue(ctx->device, sem, value));
}

xrad_status gpu_timeline_wait(struct xrad_context *ctx, VkSemaphore sem, uint64_t value,
                              xrad_error *err)
{
    VkSemaphoreWaitInfo info = {
        .sType = VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO,
        .semaphoreCount = 1,
        .pSemaphores = &sem,
        .pValues = &value,
    };
    return VK_CHECK(ctx, err, vkWaitSemaphores(ctx->device, &info, ctx->wait_timeout_ns));
}

xrad_status gpu_cmd_wait(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err)
{
    if (c->done)
        return XRAD_OK;
    if (!c->submitted)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gpu_cmd_wait: nothing was submitted");
    xrad_status s = VK_CHECK(ctx, err,
                             vkWaitForFences(ctx->device, 1, &c->fence, VK_TRUE,
                                             ctx->wait_timeout_ns));
    if (!s)
        c->done = true;
    return s;
}

xrad_status gpu_cmd_run(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err)
{
    xrad_status s = gpu_cmd_submit(ctx, c, err);
    return s ? s : gpu_cmd_wait(ctx, c, err);
}

void gpu_cmd_destroy(struct xrad_context *ctx, gpu_cmd *c)
{
    if (!c || (!c->cmd && !c->fence))
        return;
    if (c->submitted && !c->done) {
        /* Unchecked on purpose: this wait is the cleanup after a failure,
         * not an operation of its own; DEVICE_LOST also ends it (objects of
         * a lost device may be destroyed). */
        uint64_t limit = ctx->wait_timeout_ns;
        if (atomic_load(&ctx->hung) && limit > GPU_HANG_GRACE_NS)
            limit = GPU_HANG_GRACE_NS;
        VkResult r = vkWaitForFences(ctx->device, 1, &c->fence, VK_TRUE, limit);
        if (r == VK_TIMEOUT) {
            atomic_store(&ctx->lost, true);
            atomic_store(&ctx->hung, true);
            gpu_log(ctx, XRAD_LOG_ERROR,
                    "a GPU submission did not finish within %.0f s; its command buffer is left "
                    "to the context's destruction",
                    (double)limit * 1e-9);
            memset(c, 0, sizeof(*c));
            return;
        }
    }
    vkDestroyFence(ctx->device, c->fence, NULL);
    if (c->cmd)
        vkFreeCommandBuffers(ctx->device, c->pool, 1, &c->cmd);
    memset(c, 0, sizeof(*c));
}

void gpu_cmd_copy_buffer_to_image(VkCommandBuffer cmd, const gpu_buffer *src,
                                  VkDeviceSize offset, const gpu_image *dst, uint32_t layer)
{
    VkBufferImageCopy region = {
        .bufferOffset = offset,
        .imageSubresource = {.aspectMask = dst->aspect, .baseArrayLayer = layer, .layerCount = 1},
        .imageExtent = {dst->width, dst->height, 1},
    };
    vkCmdCopyBufferToImage(cmd, src->buffer, dst->image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1,
                           &region);
}

void gpu_cmd_copy_image_to_buffer(VkCommandBuffer cmd, const gpu_image *src, uint32_t layer,
                                  const gpu_buffer *dst, VkDeviceSize offset)
{
    VkBufferImageCopy region = {
        .bufferOffset = offset,
        .imageSubresource = {.aspectMask = src->aspect, .baseArrayLayer = layer, .layerCount = 1},
        .imageExtent = {src->width, src->height, 1},
    };
    vkCmdCopyImageToBuffer(cmd, src->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst->buffer, 1,
                           &region);
}

xrad_status gpu_upload_buffer(struct xrad_context *ctx, gpu_buffer *dst, VkDeviceSize offset,
                              const void *data, VkDeviceSize size, xrad_error *err)
{
    if (offset > dst->size || size > dst->size - offset)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "gpu_upload_buffer: %llu bytes at %llu overrun a %llu-byte buffer",
                         (unsigned long long)size, (unsigned long long)offset,
                         (unsigned long long)dst->size);
    if (dst->alloc.mapped) {
        memcpy((char *)dst->alloc.mapped + offset, data, size);
        return XRAD_OK;
    }
    gpu_buffer staging;
    gpu_cmd c;
    xrad_status s = gpu_buffer_create(ctx, size, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_UPLOAD,
                                      GPU_MEM_STAGING, &staging, err);
    if (s)
        return s;
    memcpy(staging.alloc.mapped, data, size);
    if ((s = gpu_cmd_begin(ctx, &c, err)))
        goto fail_cmd;
    VkBufferCopy region = {.srcOffset = 0, .dstOffset = offset, .size = size};
    vkCmdCopyBuffer(c.cmd, staging.buffer, dst->buffer, 1, &region);
    s = gpu_cmd_run(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
fail_cmd:
    gpu_buffer_destroy(ctx, &staging);
    return s;
}

static xrad_status image_bytes_check(const gpu_image *img, size_t bytes, const char *what,
                                     xrad_error *err)
{
    size_t want = (size_t)gpu_format_bytes(img->format) * img->width * img->height * img->layers;
    if (want == 0 || bytes != want)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: %zu bytes given, the image holds %zu",
                         what, bytes, want);
    return XRAD_OK;
}

xrad_status gpu_upload_image(struct xrad_context *ctx, gpu_image *dst, const void *data,
                             size_t bytes, VkImageLayout final_layout, xrad_error *err)
{
    xrad_status s = image_bytes_check(dst, bytes, "gpu_upload_image", err);
    if (s)
        return s;
    gpu_buffer staging;
    gpu_cmd c;
    if ((s = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, GPU_MEM_UPLOAD,
                               GPU_MEM_STAGING, &staging, err)))
        return s;
    memcpy(staging.alloc.mapped, data, bytes);
    if ((s = gpu_cmd_begin(ctx, &c, err)))
        goto fail_cmd;
    size_t layer_bytes = bytes / dst->layers;
    gpu_image_transition(c.cmd, dst, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    for (uint32_t l = 0; l < dst->layers; l++)
        gpu_cmd_copy_buffer_to_image(c.cmd, &staging, l * layer_bytes, dst, l);
    gpu_image_transition(c.cmd, dst, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, final_layout);
    s = gpu_cmd_run(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
fail_cmd:
    gpu_buffer_destroy(ctx, &staging);
    return s;
}

xrad_status gpu_readback_image(struct xrad_context *ctx, gpu_image *src, VkImageLayout layout,
                               void *data, size_t bytes, xrad_error *err)
{
    xrad_status s = image_bytes_check(src, bytes, "gpu_readback_image", err);
    if (s)
        return s;
    gpu_buffer staging;
    gpu_cmd c;
    if ((s = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_READBACK,
                               GPU_MEM_STAGING, &staging, err)))
        return s;
    if ((s = gpu_cmd_begin(ctx, &c, err)))
        goto fail_cmd;
    size_t layer_bytes = bytes / src->layers;
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
        gpu_image_transition(c.cmd, src, layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    for (uint32_t l = 0; l < src->layers; l++)
        gpu_cmd_copy_image_to_buffer(c.cmd, src, l, &staging, l * layer_bytes);
    if (layout != VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL)
        gpu_image_transition(c.cmd, src, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, layout);
    /* Make the copy's writes visible to the host read below. */
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    if (!(s = gpu_cmd_run(ctx, &c, err)))
        memcpy(data, staging.alloc.mapped, bytes);
    gpu_cmd_destroy(ctx, &c);
fail_cmd:
    gpu_buffer_destroy(ctx, &staging);
    return s;
}

xrad_status gpu_readback_buffer(struct xrad_context *ctx, gpu_buffer *src, VkDeviceSize offset,
                                void *data, VkDeviceSize size, xrad_error *err)
{
    if (offset > src->size || size > src->size - offset)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "gpu_readback_buffer: %llu bytes at %llu overrun a %llu-byte buffer",
                         (unsigned long long)size, (unsigned long long)offset,
                         (unsigned long long)src->size);
    gpu_buffer staging;
    gpu_cmd c;
    xrad_status s = gpu_buffer_create(ctx, size, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                      GPU_MEM_READBACK, GPU_MEM_STAGING, &staging, err);
    if (s)
        return s;
    if ((s = gpu_cmd_begin(ctx, &c, err)))
        goto fail_cmd;
    VkBufferCopy region = {.srcOffset = offset, .dstOffset = 0, .size = size};
    vkCmdCopyBuffer(c.cmd, src->buffer, staging.buffer, 1, &region);
    /* Make the copy's writes visible to the host read below. */
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    if (!(s = gpu_cmd_run(ctx, &c, err)))
        memcpy(data, staging.alloc.mapped, size);
    gpu_cmd_destroy(ctx, &c);
fail_cmd:
    gpu_buffer_destroy(ctx, &staging);
    return s;
}

void gpu_memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                        VkPipelineStageFlags dst, VkAccessFlags dst_access)
{
    VkMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
    };
    vkCmdPipelineBarrier(cmd, src, dst, 0, 1, &b, 0, NULL, 0, NULL);
}
