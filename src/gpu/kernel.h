/*
 * A compute kernel: one pipeline over one descriptor set layout of storage
 * buffers, sampled images and storage images, with push constants, and a
 * few descriptor sets to switch between (e.g. one per pose slot). What
 * every compute pass owns ("these buffers, these images, this shader");
 * the pass file keeps its own binding table and record().
 */
#ifndef XRAD_GPU_KERNEL_H
#define XRAD_GPU_KERNEL_H

#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

#define GPU_KERNEL_MAX_BINDINGS 32
#define GPU_KERNEL_MAX_SETS 4

typedef struct gpu_kernel {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet sets[GPU_KERNEL_MAX_SETS];
    uint32_t binding_count, set_count, push_bytes;
    VkDescriptorType types[GPU_KERNEL_MAX_BINDINGS];
} gpu_kernel;

typedef struct gpu_kernel_desc {
    const uint32_t *spv;
    size_t spv_bytes;
    /* Binding b has types[b]: STORAGE_BUFFER, SAMPLED_IMAGE (read in
     * SHADER_READ_ONLY_OPTIMAL) or STORAGE_IMAGE (in GENERAL). */
    const VkDescriptorType *types;
    uint32_t binding_count; /* 1..GPU_KERNEL_MAX_BINDINGS */
    uint32_t set_count;     /* 1..GPU_KERNEL_MAX_SETS; 0 means 1 */
    uint32_t push_bytes;
    const char *name;       /* for messages */
} gpu_kernel_desc;

/* Fills a caller-owned kernel. On failure it is left zeroed. */
xrad_status gpu_kernel_create(struct xrad_context *ctx, const gpu_kernel_desc *desc,
                              gpu_kernel *k, xrad_error *err);
/* Accepts a zeroed kernel; zeroes it. The GPU must be done with it. */
void gpu_kernel_destroy(struct xrad_context *ctx, gpu_kernel *k);

/* What one binding points at: a whole buffer, or an image view in the
 * layout its type reads it in. */
typedef struct gpu_kernel_resource {
    const gpu_buffer *buffer;
    VkImageView view;
} gpu_kernel_resource;

/* Points set `set` at resources[0..binding_count); a binding with neither
 * buffer nor view is left as it is. No recording that uses the set may be
 * pending on the GPU. */
void gpu_kernel_bind(struct xrad_context *ctx, gpu_kernel *k, uint32_t set,
                     const gpu_kernel_resource *resources);

/* Binds the pipeline and set `set`, pushes `push` (push_bytes) and
 * dispatches ceil(invocations / group) x 1 x 1 workgroups (none for 0). */
void gpu_kernel_dispatch(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set, const void *push,
                         uint32_t invocations, uint32_t group);

/* The same with `groups` x 1 x 1 workgroups (none for 0). */
void gpu_kernel_dispatch_groups(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set,
                                const void *push, uint32_t groups);

/* The same with the VkDispatchIndirectCommand at `offset` of `indirect`
 * (INDIRECT usage), written on the GPU. */
void gpu_kernel_dispatch_indirect(gpu_kernel *k, VkCommandBuffer cmd, uint32_t set,
                                  const void *push, const gpu_buffer *indirect,
                                  VkDeviceSize offset);

#endif
