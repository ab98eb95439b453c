/*
 * The present pass (src/passes/present.c, spirv/present.frag) against the
 * tone mapping's formulas computed here in double precision: every pixel
 * of a linear image (greys and colours from 0 to 60, a negative value) drawn
 * into an RGBA8 image, with XRAD_TONEMAP_EXPOSURE (clamp(e B)) and
 * XRAD_TONEMAP_REINHARD (Reinhard et al. 2002, eq. 3 on the Rec. 709
 * luminance: e B / (1 + L)), each then sRGB-encoded, at two exposures, into
 * a UNORM image (the shader encodes) and an SRGB one (the format does):
 * every channel within 1/255 of the formula's byte. The PNG writer's bytes
 * for the same image and settings too, so that a window and its screenshot
 * agree. No validation message (gpu_test.h).
 */
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "gpu/image.h"
#include "gpu/pipeline.h"
#include "passes/present.h"

#define W 64
#define H 4

/* The display byte the formulas give for channel k of pixel p. */
static double want_byte(const float *p, int k, xrad_tonemap tm, double exposure)
{
    double c = p[k] * exposure;
    if (tm == XRAD_TONEMAP_REINHARD) {
        double l = exposure * (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]);
        c /= 1 + fmax(l, 0);
    }
    c = fmin(fmax(c, 0), 1);
    double s = c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1 / 2.4) - 0.055;
    return s * 255;
}

/* A linear image: row 0 greys from 0 to 60 in geometric steps, rows 1-3
 * colours of those magnitudes, one pixel negative. */
static void make_source(float *px)
{
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float *p = px + 4 * (y * W + x);
            double m = x == 0 ? 0 : 1e-3 * pow(6e4, (x - 1) / (double)(W - 2));
            double rgb[4][3] = {{1, 1, 1}, {1, 0.2, 0.05}, {0.1, 0.9, 0.3}, {0.3, 0.4, 1.0}};
            for (int k = 0; k < 3; k++)
                p[k] = (float)(m * rgb[y][k]);
            p[3] = 1;
        }
    px[4 * (2 * W + 5)] = -0.5f; /* a red below zero: clamped, not wrapped */
}

typedef struct target {
    VkFormat format;
    gpu_image image;
    VkFramebuffer fb;
    present_pass *present;
} target;

static xrad_status target_create(xrad_context *ctx, VkFormat format, target *t,
                                 xrad_error *err)
{
    t->format = format;
    gpu_image_desc id = {
        .format = format,
        .width = W,
        .height = H,
        .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    xrad_status s;
    if ((s = gpu_image_create(ctx, &id, &t->image, err)) ||
        (s = present_create(ctx, format, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, &t->present, err)))
        return s;
    VkFramebufferCreateInfo fb = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = present_render_pass(t->present),
        .attachmentCount = 1,
        .pAttachments = &t->image.view,
        .width = W,
        .height = H,
        .layers = 1,
    };
    return VK_CHECK(ctx, err, vkCreateFramebuffer(ctx->device, &fb, NULL, &t->fb));
}

static void target_destroy(xrad_context *ctx, target *t)
{
    if (t->fb)
        vkDestroyFramebuffer(ctx->device, t->fb, NULL);
    present_destroy(ctx, &t->present);
    gpu_image_destroy(ctx, &t->image);
}

/* Draws the source into t; rgba receives W x H x 4 bytes. */
static xrad_status draw(xrad_context *ctx, target *t, const gpu_image *source, xrad_tonemap tm,
                        double exposure, uint8_t *rgba, xrad_error *err)
{
    gpu_cmd c = {0};
    xrad_status s = gpu_cmd_begin(ctx, &c, err);
    if (!s) {
        present_record(ctx, t->present, c.cmd,
                       &(present_draw){.source = source,
                                       .framebuffer = t->fb,
                                       .extent = {W, H},
                                       .exposure = exposure,
                                       .tonemap = tm,
                                       .slot = 0});
        s = gpu_cmd_run(ctx, &c, err);
    }
    if (!s)
        s = gpu_readback_image(ctx, &t->image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rgba,
                               (size_t)W * H * 4, err);
    gpu_cmd_destroy(ctx, &c);
    return s;
}

/* Every channel of `got` (stride 3 or 4 bytes) within 1/255 of the formula. */
static void compare(const char *label, const uint8_t *got, int stride, const float *src,
                    xrad_tonemap tm, double exposure)
{
    uint32_t bad = 0, mid = 0;
    double worst = 0;
    for (int i = 0; i < W * H; i++)
        for (int k = 0; k < 3; k++) {
            double want = want_byte(src + 4 * i, k, tm, exposure);
            double d = fabs(got[stride * i + k] - want);
            worst = fmax(worst, d);
            bad += d > 1.0;
            mid += want > 8 && want < 247;
        }
    CHECK(bad == 0, "%s: %u channels more than 1/255 from the formula (worst %.2f / 255)", label,
          bad, worst);
    /* The image spans the curve, not only its clamped ends. */
    CHECK(mid > W, "%s: only %u channels between 8 and 247", label, mid);
}

/* The PNG writer's bytes of the same image, as the formula wants them. */
static void check_png(const float *src, xrad_tonemap tm, double exposure)
{
    char dir[] = "/tmp/xrad-test-present-XXXXXX", path[64];
    if (!mkdtemp(dir)) {
        CHECK(0, "mkdtemp failed");
        return;
    }
    snprintf(path, sizeof(path), "%s/p.png", dir);
    xrad_error err = {0};
    xrad_status s = xrad_image_write_png_tonemapped(path, src, W, H, tm, exposure, &err);
    CHECK(s == XRAD_OK, "png: %s", err.message);
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    static uint8_t rgb[W * H * 3];
    if (!s && png_image_begin_read_from_file(&img, path)) {
        img.format = PNG_FORMAT_RGB;
        if (png_image_finish_read(&img, NULL, rgb, 0, NULL)) {
            char label[64];
            snprintf(label, sizeof(label), "PNG writer, %s x %g", xrad_tonemap_name(tm),
                     exposure);
            compare(label, rgb, 3, src, tm, exposure);
        } else {
            CHECK(0, "%s: %s", path, img.message);
        }
    } else if (!s) {
        CHECK(0, "%s: %s", path, img.message);
    }
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    static float src[W * H * 4];
    static uint8_t rgba[W * H * 4];
    make_source(src);
    xrad_error err = {0};
    gpu_image source = {0};
    gpu_image_desc sd = {
        .format = VK_FORMAT_R32G32B32A32_SFLOAT,
        .width = W,
        .height = H,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    xrad_status s = gpu_image_create(ctx, &sd, &source, &err);
    if (!s)
        s = gpu_upload_image(ctx, &source, src, sizeof(src),
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, &err);
    CHECK(s == XRAD_OK, "source: %s", err.message);
    const VkFormat formats[2] = {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_R8G8B8A8_SRGB};
    const double exposures[2] = {1.0, 7.5};
    for (int f = 0; f < 2 && !s; f++) {
        target t = {0};
        s = target_create(ctx, formats[f], &t, &err);
        CHECK(s == XRAD_OK, "target %s: %s", f ? "SRGB" : "UNORM", err.message);
        for (int tm = 0; tm < 2 && !s; tm++)
            for (int e = 0; e < 2 && !s; e++) {
                s = draw(ctx, &t, &source, (xrad_tonemap)tm, exposures[e], rgba, &err);
                CHECK(s == XRAD_OK, "draw: %s", err.message);
                char label[64];
                snprintf(label, sizeof(label), "present into %s, %s x %g",
                         f ? "SRGB" : "UNORM", xrad_tonemap_name((xrad_tonemap)tm),
                         exposures[e]);
                if (!s)
                    compare(label, rgba, 4, src, (xrad_tonemap)tm, exposures[e]);
            }
        target_destroy(ctx, &t);
    }
    for (int tm = 0; tm < 2; tm++)
        for (int e = 0; e < 2; e++)
            check_png(src, (xrad_tonemap)tm, exposures[e]);
    gpu_image_destroy(ctx, &source);
    gpu_test_end(&ctx);
    return test_finish();
}
