/*
 * Present pass: the display target's linear B (passes/display.h) to a
 * window's swapchain image, with the PNG writer's tone mapping (exposure,
 * Reinhard's operator where asked, clamp, sRGB), leaving the image ready to
 * present. One descriptor set per
 * frame slot, so that frames in flight do not share one.
 */
#ifndef XRAD_PASSES_PRESENT_H
#define XRAD_PASSES_PRESENT_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/image.h"
#include "passes/overlay.h"
#include "xrad.h"

struct xrad_context;

#define PRESENT_SLOTS 2

typedef struct present_pass present_pass;

/* For images of `format` (8-bit UNORM or SRGB) left in `final_layout`
 * (PRESENT_SRC_KHR for a swapchain's). */
xrad_status present_create(struct xrad_context *ctx, VkFormat format, VkImageLayout final_layout,
                           present_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void present_destroy(struct xrad_context *ctx, present_pass **pass);

/* The render pass swapchain framebuffers are made for. */
VkRenderPass present_render_pass(const present_pass *pass);

typedef struct present_draw {
    const gpu_image *source;   /* RGBA32F, in SHADER_READ_ONLY_OPTIMAL, the framebuffer's size */
    VkFramebuffer framebuffer; /* a swapchain image's, of present_render_pass */
    VkExtent2D extent;
    double exposure;           /* > 0 */
    xrad_tonemap tonemap;
    uint32_t slot;             /* < PRESENT_SLOTS: the frame slot, whose last recording has
                                  completed */
    /* Non-NULL: text drawn over the image (an overlay made for
     * present_render_pass). */
    overlay_pass *overlay;
    const overlay_draw *text;
} present_draw;

/* Records the pass; the image ends in the pass's final layout. */
void present_record(struct xrad_context *ctx, present_pass *pass, VkCommandBuffer cmd,
                    const present_draw *draw);

#endif
