/*
 * A swapchain on a window surface the caller created (GLFW in xrad view),
 * with a framebuffer per image for one render pass. Recreation (resize,
 * out of date) retires the old swapchain and its framebuffers; they are
 * destroyed once a timeline semaphore passes the last value that used them
 * (gpu_swapchain_collect), never by idling the device.
 */
#ifndef XRAD_GPU_SWAPCHAIN_H
#define XRAD_GPU_SWAPCHAIN_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "xrad.h"

struct xrad_context;

#define GPU_SWAPCHAIN_MAX_IMAGES 8
#define GPU_SWAPCHAIN_MAX_RETIRED 4

typedef struct gpu_swapchain_images {
    VkSwapchainKHR swapchain;
    uint32_t count;
    VkImage images[GPU_SWAPCHAIN_MAX_IMAGES];
    VkImageView views[GPU_SWAPCHAIN_MAX_IMAGES];
    VkFramebuffer framebuffers[GPU_SWAPCHAIN_MAX_IMAGES];
    /* Signalled by the frame that renders image i, waited for by its
     * present: one per image, since a present holds it until the image
     * is acquired again. */
    VkSemaphore rendered[GPU_SWAPCHAIN_MAX_IMAGES];
    uint64_t retire_after; /* retired: destroy once the timeline reaches this */
} gpu_swapchain_images;

typedef struct gpu_swapchain {
    VkSurfaceKHR surface; /* the caller's */
    VkFormat format;
    bool srgb;            /* the format encodes sRGB itself */
    VkPresentModeKHR mode;
    VkExtent2D extent;
    VkRenderPass render_pass; /* the caller's, for the framebuffers */
    gpu_swapchain_images cur;
    gpu_swapchain_images retired[GPU_SWAPCHAIN_MAX_RETIRED];
    uint32_t retired_count;
    uint32_t recreations;
} gpu_swapchain;

/* Whether the device's queue can present to `surface`, and the format a
 * swapchain on it will have (B8G8R8A8 or R8G8B8A8, sRGB preferred). */
xrad_status gpu_swapchain_format(struct xrad_context *ctx, VkSurfaceKHR surface,
                                 VkFormat *format, xrad_error *err);

/* A swapchain of `width` x `height` (clamped to what the surface allows)
 * with framebuffers for `render_pass` (one colour attachment of the
 * gpu_swapchain_format). vsync: FIFO; else MAILBOX or IMMEDIATE where
 * offered. */
xrad_status gpu_swapchain_create(struct xrad_context *ctx, VkSurfaceKHR surface,
                                 VkRenderPass render_pass, uint32_t width, uint32_t height,
                                 bool vsync, gpu_swapchain *out, xrad_error *err);

/* A new swapchain of the new size; the old one is retired until the
 * timeline reaches `retire_after` (the value of the last frame that used
 * it). Collects first, and refuses when GPU_SWAPCHAIN_MAX_RETIRED are
 * still waiting. A zero size (a minimised window) is refused: keep the
 * old one until the window has an area again. */
xrad_status gpu_swapchain_recreate(struct xrad_context *ctx, gpu_swapchain *sc, uint32_t width,
                                   uint32_t height, bool vsync, uint64_t retire_after,
                                   uint64_t reached, xrad_error *err);

/* Destroys the retired swapchains the timeline value `reached` covers. */
void gpu_swapchain_collect(struct xrad_context *ctx, gpu_swapchain *sc, uint64_t reached);

/* Acquires the next image, signalling `acquired`. *out_of_date: the
 * swapchain must be recreated (no image was acquired when *index is
 * UINT32_MAX; a suboptimal one was acquired otherwise). */
xrad_status gpu_swapchain_acquire(struct xrad_context *ctx, gpu_swapchain *sc,
                                  VkSemaphore acquired, uint32_t *index, bool *out_of_date,
                                  xrad_error *err);

/* Presents image `index` after its `rendered` semaphore; *out_of_date as
 * for acquire. Under the context's queue lock. */
xrad_status gpu_swapchain_present(struct xrad_context *ctx, gpu_swapchain *sc, uint32_t index,
                                  bool *out_of_date, xrad_error *err);

/* Everything, retired ones included; the GPU must be done with them.
 * Accepts a zeroed struct; zeroes it. The surface stays the caller's. */
void gpu_swapchain_destroy(struct xrad_context *ctx, gpu_swapchain *sc);

#endif
