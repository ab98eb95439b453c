/*
 * The overlay pass (src/passes/overlay.c) against a raster computed here:
 * stb_easy_font's own quads for the text (asked of the library directly,
 * not through overlay_build) and the box its documented size gives, each
 * an axis-aligned rectangle of whole pixels, so a pixel is inside exactly
 * when its centre is. Drawn into an RGBA8 image cleared to a colour:
 *  (a) every pixel equals the raster: clear colour, the box blended over
 *      it at alpha 0.6 (src a + dst (1 - a)), text opaque white on top,
 *      within 1.5 / 255; at zoom 1 and 2, at an offset, and cut by the
 *      image's edge;
 *  (b) a character outside printable ASCII draws as '?';
 *  (c) no text draws nothing;
 *  and no validation message (gpu_test.h).
 * OVERLAY_PNG=FILE writes the zoom-2 image, to look at.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/buffer.h"
#include "gpu/cmd.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "gpu/gpu_test.h"
#include "passes/overlay.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-braces"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

#define W 240
#define H 96

static const float clear_rgb[3] = {0.25f, 0.5f, 0.75f};

typedef struct target {
    gpu_image image;
    VkRenderPass pass;
    VkFramebuffer fb;
    overlay_pass *overlay;
} target;

/* Draws `text` at (x, y) with `zoom`; rgba receives W x H x 4 bytes. */
static int draw(xrad_context *ctx, target *t, const char *text, int x, int y, uint32_t zoom,
                uint8_t *rgba)
{
    xrad_error err = {0};
    gpu_buffer vb = {0};
    gpu_cmd c = {0};
    uint32_t bound = overlay_vertex_bound(text), count = 0;
    xrad_status s = gpu_buffer_create(ctx, (bound ? bound : 1) * sizeof(overlay_vertex),
                                      VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, GPU_MEM_UPLOAD,
                                      GPU_MEM_GEOMETRY, &vb, &err);
    if (!s)
        s = overlay_build(text, vb.alloc.mapped, bound, &count, &err);
    if (!s)
        s = gpu_cmd_begin(ctx, &c, &err);
    if (!s) {
        VkClearValue clear = {.color = {.float32 = {clear_rgb[0], clear_rgb[1], clear_rgb[2], 1}}};
        VkRenderPassBeginInfo begin = {
            .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
            .renderPass = t->pass,
            .framebuffer = t->fb,
            .renderArea = {.extent = {W, H}},
            .clearValueCount = 1,
            .pClearValues = &clear,
        };
        vkCmdBeginRenderPass(c.cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
        overlay_record(t->overlay, c.cmd,
                       &(overlay_draw){.vertices = &vb,
                                       .vertex_count = count,
                                       .extent = {W, H},
                                       .x = x,
                                       .y = y,
                                       .zoom = zoom});
        vkCmdEndRenderPass(c.cmd);
        s = gpu_cmd_run(ctx, &c, &err);
    }
    if (!s)
        s = gpu_readback_image(ctx, &t->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rgba,
                               (size_t)W * H * 4, &err);
    gpu_cmd_destroy(ctx, &c);
    gpu_buffer_destroy(ctx, &vb);
    CHECK(s == XRAD_OK, "draw '%s': %s", text, err.message);
    return s == XRAD_OK;
}

/* Pixels whose centre lies in [x0, x1) x [y0, y1) take `rgb` at `a`. */
static void fill(float *img, double x0, double y0, double x1, double y1, const float *rgb,
                 float a)
{
    for (int py = 0; py < H; py++)
        for (int px = 0; px < W; px++) {
            double cx = px + 0.5, cy = py + 0.5;
            if (cx < x0 || cx >= x1 || cy < y0 || cy >= y1)
                continue;
            float *p = img + 3 * ((size_t)py * W + px);
            for (int k = 0; k < 3; k++)
                p[k] = rgb[k] * a + p[k] * (1 - a);
        }
}

/* The image the overlay must draw, from stb_easy_font itself. */
static void raster(const char *text, int x, int y, uint32_t zoom, float *img)
{
    for (size_t i = 0; i < (size_t)W * H; i++)
        memcpy(img + 3 * i, clear_rgb, sizeof(clear_rgb));
    if (!text[0])
        return;
    char *t = strdup(text);
    double z = zoom;
    double bw = stb_easy_font_width(t) + 2 * OVERLAY_PAD;
    double bh = stb_easy_font_height(t) + 2 * OVERLAY_PAD;
    static const float black[3] = {0, 0, 0}, white[3] = {1, 1, 1};
    fill(img, x, y, x + z * bw, y + z * bh, black, 153.0f / 255.0f);
    static float quads[4 * 4 * 4096];
    int n = stb_easy_font_print(OVERLAY_PAD, OVERLAY_PAD, t, NULL, quads, sizeof(quads));
    for (int q = 0; q < n; q++) {
        const float *v = quads + 16 * q; /* 4 vertices of x, y, z, colour */
        double qx0 = fmin(v[0], v[8]), qx1 = fmax(v[0], v[8]);
        double qy0 = fmin(v[1], v[9]), qy1 = fmax(v[1], v[9]);
        fill(img, x + z * qx0, y + z * qy0, x + z * qx1, y + z * qy1, white, 1);
    }
    free(t);
}

static void check_case(xrad_context *ctx, target *t, const char *label, const char *text, int x,
                       int y, uint32_t zoom, uint8_t *rgba, float *want)
{
    if (!draw(ctx, t, text, x, y, zoom, rgba))
        return;
    raster(text, x, y, zoom, want);
    uint32_t bad = 0, text_px = 0, box_px = 0;
    double worst = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        for (int k = 0; k < 3; k++) {
            double d = fabs(rgba[4 * i + k] / 255.0 - want[3 * i + k]);
            worst = fmax(worst, d);
            bad += d > 1.5 / 255;
        }
        text_px += want[3 * i] == 1 && want[3 * i + 1] == 1;
        box_px += want[3 * i + 2] < 0.5f;
    }
    CHECK(bad == 0, "%s: %u channels differ from the raster (worst %.4f)", label, bad, worst);
    if (text[0])
        CHECK(text_px > 0 && box_px > text_px, "%s: the raster has %u text and %u box pixels",
              label, text_px, box_px);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    target t = {0};
    xrad_error err = {0};
    gpu_image_desc id = {
        .format = VK_FORMAT_R8G8B8A8_UNORM,
        .width = W,
        .height = H,
        .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    gpu_render_pass_desc rp = {.color_format = id.format,
                               .color_final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL};
    xrad_status s = gpu_image_create(ctx, &id, &t.image, &err);
    if (!s)
        s = gpu_render_pass_create(ctx, &rp, &t.pass, &err);
    if (!s) {
        VkFramebufferCreateInfo fb = {
            .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
            .renderPass = t.pass,
            .attachmentCount = 1,
            .pAttachments = &t.image.view,
            .width = W,
            .height = H,
            .layers = 1,
        };
        s = VK_CHECK(ctx, &err, vkCreateFramebuffer(ctx->device, &fb, NULL, &t.fb));
    }
    if (!s)
        s = overlay_create(ctx, t.pass, &t.overlay, &err);
    CHECK(s == XRAD_OK, "set-up: %s", err.message);

    uint8_t *rgba = malloc((size_t)W * H * 4), *rgba2 = malloc((size_t)W * H * 4);
    float *want = malloc((size_t)W * H * 3 * sizeof(float));
    if (!s && rgba && rgba2 && want) {
        const char *lines = "cornell-large   method cross\ndisplay 59.8 fps (16.7 ms)\n"
                            "GPU ms: cross_update 12.5, select 0.4";
        check_case(ctx, &t, "zoom 1", lines, 0, 0, 1, rgba, want);
        check_case(ctx, &t, "zoom 2 at (8, 8)", "xrad view\nH: overlay off", 8, 8, 2, rgba,
                   want);
        const char *png = getenv("OVERLAY_PNG");
        if (png) {
            float *lin = malloc((size_t)W * H * 4 * sizeof(float));
            for (size_t i = 0; lin && i < (size_t)W * H * 4; i++) /* sRGB bytes to linear */
                lin[i] = (float)pow(rgba[i] / 255.0, 2.2);
            if (lin)
                xrad_image_write_png(png, lin, W, H, 1.0, &err);
            free(lin);
        }
        check_case(ctx, &t, "cut by the edge", lines, W - 60, H - 20, 2, rgba, want);
        check_case(ctx, &t, "empty", "", 4, 4, 1, rgba, want);

        /* (b) tab, DEL and a byte above 127 draw as '?'. */
        if (draw(ctx, &t, "a\tb\x7f" "c\xe9", 2, 2, 1, rgba) &&
            draw(ctx, &t, "a?b?c?", 2, 2, 1, rgba2))
            CHECK(!memcmp(rgba, rgba2, (size_t)W * H * 4),
                  "unprintable characters do not draw as '?'");
        /* The bound covers what the build writes, for the longest glyphs. */
        uint32_t count = 0, bound = overlay_vertex_bound("@@@WWWmmm%%%");
        overlay_vertex *v = malloc(bound * sizeof(*v));
        CHECK(v && overlay_build("@@@WWWmmm%%%", v, bound, &count, &err) == XRAD_OK &&
                  count > 6 && count <= bound,
              "build: %u of the bound %u: %s", count, bound, err.message);
        /* Too small an array is refused, not overrun. */
        CHECK(v && overlay_build("@@@WWWmmm%%%", v, 6, &count, &err) == XRAD_ERROR_INPUT &&
                  count == 0,
              "6 vertices for 12 characters: accepted (%u)", count);
        free(v);
    }
    free(rgba);
    free(rgba2);
    free(want);
    overlay_destroy(ctx, &t.overlay);
    if (t.fb)
        vkDestroyFramebuffer(ctx->device, t.fb, NULL);
    if (t.pass)
        vkDestroyRenderPass(ctx->device, t.pass, NULL);
    gpu_image_destroy(ctx, &t.image);
    gpu_test_end(&ctx);
    return test_finish();
}
