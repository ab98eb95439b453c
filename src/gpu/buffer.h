/* Buffers with their memory (sub-allocated, src/gpu/memory.h). */
#ifndef XRAD_GPU_BUFFER_H
#define XRAD_GPU_BUFFER_H

#include <vulkan/vulkan.h>

#include "gpu/memory.h"
#include "xrad.h"

struct xrad_context;

typedef struct gpu_buffer {
    VkBuffer buffer;
    VkDeviceSize size;
    gpu_allocation alloc; /* alloc.mapped: host pointer when host-visible and coherent */
} gpu_buffer;

/* A buffer of `size` bytes (> 0). On failure *out is zeroed. */
xrad_status gpu_buffer_create(struct xrad_context *ctx, VkDeviceSize size,
                              VkBufferUsageFlags usage, gpu_mem_usage mem,
                              gpu_mem_category category, gpu_buffer *out, xrad_error *err);

/* Accepts a zeroed buffer; zeroes it. The GPU must be done with it. */
void gpu_buffer_destroy(struct xrad_context *ctx, gpu_buffer *b);

#endif
