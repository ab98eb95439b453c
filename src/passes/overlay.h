/*
 * Overlay: lines of text drawn over a window's image (xrad view's figures
 * and keys), from stb_easy_font's quads (libstb-dev): a bitmap font made of
 * rectangles, so no font texture. The text sits on a translucent dark box
 * for legibility over any scene.
 *
 * Building the vertices is host work on the text alone (overlay_build);
 * recording draws them inside a render pass the caller has begun, which
 * must be compatible with the one the pass was created for (one colour
 * attachment, no depth test).
 */
#ifndef XRAD_PASSES_OVERLAY_H
#define XRAD_PASSES_OVERLAY_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

/* stb_easy_font's vertex: pixels (z unused) and a colour in bytes. */
typedef struct overlay_vertex {
    float x, y, z;
    uint8_t rgba[4];
} overlay_vertex;

/* Pixels between the box's edge and the text, at zoom 1. */
#define OVERLAY_PAD 3

/* Text colour and the box's (alpha 0.6). */
#define OVERLAY_TEXT_RGBA {255, 255, 255, 255}
#define OVERLAY_BOX_RGBA {0, 0, 0, 153}

/* The most vertices overlay_build writes for `text`. */
uint32_t overlay_vertex_bound(const char *text);

/* A triangle list for `text` (lines split at '\n'): first the box from
 * (0, 0) to (text width + 2 pad, text height + 2 pad), then the text's
 * quads from (pad, pad), all in pixels at zoom 1 with y down. Returns the
 * vertex count (0 for empty text), at most `max`; XRAD_ERROR_SYSTEM
 * when out of host memory. */
xrad_status overlay_build(const char *text, overlay_vertex *out, uint32_t max,
                          uint32_t *count, xrad_error *err);

typedef struct overlay_pass overlay_pass;

xrad_status overlay_create(struct xrad_context *ctx, VkRenderPass render_pass,
                           overlay_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void overlay_destroy(struct xrad_context *ctx, overlay_pass **pass);

typedef struct overlay_draw {
    const gpu_buffer *vertices; /* overlay_build's, from offset 0 */
    uint32_t vertex_count;
    VkExtent2D extent;          /* the framebuffer's */
    int32_t x, y;               /* pixels: where the box's corner (0, 0) lands */
    uint32_t zoom;              /* >= 1: pixels per font pixel */
} overlay_draw;

/* Records the draw into the render pass begun on `cmd`; sets its own
 * viewport and scissor (the whole extent). Nothing for zero vertices. */
void overlay_record(overlay_pass *pass, VkCommandBuffer cmd, const overlay_draw *draw);

#endif
