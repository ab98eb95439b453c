/*
 * One-shot command buffers: begin, record, submit, wait. Each submission
 * signals a fence (what the host waits on, with the context's finite
 * timeout) and, where timeline semaphores exist, the next value of the
 * context's timeline (what later passes order work and deferred frees by).
 * Staging helpers upload to and read back from buffers and images.
 */
#ifndef XRAD_GPU_CMD_H
#define XRAD_GPU_CMD_H

#include <stdbool.h>
#include <stddef.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

typedef struct gpu_cmd {
    VkCommandBuffer cmd;
    VkCommandPool pool; /* the recording thread's (gpu_thread_pool): free it in that thread */
    VkFence fence;
    uint64_t value; /* timeline value signalled on completion; 0 until submitted */
    bool submitted, done;
} gpu_cmd;

/* A command buffer in the recording state. On failure *c is zeroed. */
xrad_status gpu_cmd_begin(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err);

/* Ends recording and submits. Refuses on a lost context. */
xrad_status gpu_cmd_submit(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err);

/* Semaphores a submission waits for and signals besides the context's
 * timeline: timeline semaphores with their values; VK_NULL_HANDLE: none. */
typedef struct gpu_sync {
    VkSemaphore wait;
    uint64_t wait_value;
    VkPipelineStageFlags wait_stage;
    VkSemaphore signal;
    uint64_t signal_value;
} gpu_sync;

/* gpu_cmd_submit with `sync` (may be NULL). */
xrad_status gpu_cmd_submit_sync(struct xrad_context *ctx, gpu_cmd *c, const gpu_sync *sync,
                                xrad_error *err);

/* vkQueueSubmit under the context's queue lock, for command buffers of
 * other pools (a display thread's). */
xrad_status gpu_queue_submit(struct xrad_context *ctx, const VkSubmitInfo *submit, VkFence fence,
                             xrad_error *err);

/* A timeline semaphore at value 0. */
xrad_status gpu_timeline_create(struct xrad_context *ctx, VkSemaphore *out, xrad_error *err);
/* Its current value (no wait). */
xrad_status gpu_timeline_value(struct xrad_context *ctx, VkSemaphore sem, uint64_t *value,
                               xrad_error *err);
/* Waits until it reaches `value`, at most ctx->wait_timeout_ns. */
xrad_status gpu_timeline_wait(struct xrad_context *ctx, VkSemaphore sem, uint64_t value,
                              xrad_error *err);

/* Waits for a submitted command buffer, at most ctx->wait_timeout_ns; a
 * timeout is XRAD_ERROR_SYSTEM and marks the context lost (a hang). */
xrad_status gpu_cmd_wait(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err);

/* Submit, then wait. */
xrad_status gpu_cmd_run(struct xrad_context *ctx, gpu_cmd *c, xrad_error *err);

/* Frees the command buffer and fence. When it was submitted and not seen
 * complete (an error path), first waits for it, with the finite timeout, so
 * that resources it uses may be freed next; if the device hangs even then,
 * the two objects are left to the context's destruction rather than freed
 * under the GPU. Accepts a zeroed gpu_cmd; zeroes it. */
void gpu_cmd_destroy(struct xrad_context *ctx, gpu_cmd *c);

/* Records a global memory barrier: what `src` stages wrote with
 * `src_access` is visible to `dst` stages' `dst_access`. */
void gpu_memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src, VkAccessFlags src_access,
                        VkPipelineStageFlags dst, VkAccessFlags dst_access);

/* Records a copy of tightly packed texels at `offset` in src into layer
 * `layer` of dst, which must be in TRANSFER_DST_OPTIMAL. */
void gpu_cmd_copy_buffer_to_image(VkCommandBuffer cmd, const gpu_buffer *src,
                                  VkDeviceSize offset, const gpu_image *dst, uint32_t layer);

/* Records the opposite copy; src must be in TRANSFER_SRC_OPTIMAL. */
void gpu_cmd_copy_image_to_buffer(VkCommandBuffer cmd, const gpu_image *src, uint32_t layer,
                                  const gpu_buffer *dst, VkDeviceSize offset);

/* Writes `size` bytes at `offset` of dst: directly when dst is mapped,
 * else through a staging buffer and a one-shot copy that is waited for.
 * The GPU must not be using that range. */
xrad_status gpu_upload_buffer(struct xrad_context *ctx, gpu_buffer *dst, VkDeviceSize offset,
                              const void *data, VkDeviceSize size, xrad_error *err);

/* Fills all layers of dst (tightly packed texels, layer after layer) and
 * leaves it in `final_layout`. Its previous contents are discarded. */
xrad_status gpu_upload_image(struct xrad_context *ctx, gpu_image *dst, const void *data,
                             size_t bytes, VkImageLayout final_layout, xrad_error *err);

/* Copies all layers of src, currently in `layout` (left so), to data. */
xrad_status gpu_readback_image(struct xrad_context *ctx, gpu_image *src, VkImageLayout layout,
                               void *data, size_t bytes, xrad_error *err);

/* Copies `size` bytes at `offset` of src to data. */
xrad_status gpu_readback_buffer(struct xrad_context *ctx, gpu_buffer *src, VkDeviceSize offset,
                                void *data, VkDeviceSize size, xrad_error *err);

#endif
