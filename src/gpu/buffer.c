#include "gpu/buffer.h"

#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

xrad_status gpu_buffer_create(struct xrad_context *ctx, VkDeviceSize size,
                              VkBufferUsageFlags usage, gpu_mem_usage mem,
                              gpu_mem_category category, gpu_buffer *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    if (size == 0)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gpu_buffer_create: size 0");
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    if (VK_CHECK(ctx, err, vkCreateBuffer(ctx->device, &info, NULL, &out->buffer)))
        return XRAD_ERROR_SYSTEM;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
    xrad_status s = gpu_memory_alloc(ctx, &req, mem, true, category, &out->alloc, err);
    if (s)
        goto fail_memory;
    if ((s = VK_CHECK(ctx, err, vkBindBufferMemory(ctx->device, out->buffer, out->alloc.memory,
                                                   out->alloc.offset))))
        goto fail_bind;
    out->size = size;
    return XRAD_OK;

fail_bind:
    gpu_memory_free(ctx, &out->alloc);
fail_memory:
    vkDestroyBuffer(ctx->device, out->buffer, NULL);
    memset(out, 0, sizeof(*out));
    return s;
}

void gpu_buffer_destroy(struct xrad_context *ctx, gpu_buffer *b)
{
    if (!b || !b->buffer)
        return;
    vkDestroyBuffer(ctx->device, b->buffer, NULL);
    gpu_memory_free(ctx, &b->alloc);
    memset(b, 0, sizeof(*b));
}
