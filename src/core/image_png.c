/* Tone-mapped 8-bit sRGB PNG output. Tone mapping is an exposure scale,
 * with XRAD_TONEMAP_REINHARD Reinhard's global operator, a clamp and the
 * sRGB transfer curve (README, "Images"); spirv/present.frag does the same
 * for a window. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

#include "core/error.h"

static uint8_t srgb_encode(double v)
{
    if (!(v > 0)) /* also catches NaN */
        return 0;
    if (v >= 1)
        return 255;
    double s = v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1 / 2.4) - 0.055;
    return (uint8_t)lround(s * 255.0);
}

xrad_status xrad_image_write_png(const char *path, const float *rgba, uint32_t width,
                                 uint32_t height, double exposure, xrad_error *err)
{
    return xrad_image_write_png_tonemapped(path, rgba, width, height, XRAD_TONEMAP_EXPOSURE,
                                           exposure, err);
}

xrad_status xrad_image_write_png_tonemapped(const char *path, const float *rgba, uint32_t width,
                                            uint32_t height, xrad_tonemap tonemap,
                                            double exposure, xrad_error *err)
{
    if (width == 0 || height == 0 || width > 65536 || height > 65536)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot write a %ux%u image", path, width,
                         height);
    if (!xrad_tonemap_name(tonemap))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: unknown tone mapping %d", path,
                         (int)tonemap);
    if (!(exposure > 0) || !isfinite(exposure))
        exposure = xrad_image_tonemap_exposure(tonemap, rgba, width, height);
    size_t n = (size_t)width * height;
    uint8_t *px = malloc(n * 3);
    if (!px)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", path);
    for (size_t i = 0; i < n; i++) {
        double c[3], scale = 1;
        for (int k = 0; k < 3; k++)
            c[k] = rgba[i * 4 + k] * exposure;
        if (tonemap == XRAD_TONEMAP_REINHARD) {
            /* Reinhard et al. 2002, eq. 3, on the Rec. 709 luminance. */
            double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
            scale = 1 / (1 + fmax(l, 0));
        }
        for (int k = 0; k < 3; k++)
            px[i * 3 + k] = srgb_encode(c[k] * scale);
    }

    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    img.width = width;
    img.height = height;
    img.format = PNG_FORMAT_RGB;
    int ok = png_image_write_to_file(&img, path, 0, px, (png_int_32)(width * 3), NULL);
    free(px);
    if (!ok) {
        xrad_status st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot write PNG: %s", path,
                                   img.message);
        png_image_free(&img);
        return st;
    }
    return XRAD_OK;
}

xrad_status xrad_image_read_png(const char *path, float **rgba, uint32_t *width,
                                uint32_t *height, xrad_error *err)
{
    *rgba = NULL;
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot read PNG: %s", path, img.message);
    img.format = PNG_FORMAT_RGBA;
    size_t n = (size_t)img.width * img.height;
    uint8_t *px = malloc(n * 4);
    float *out = malloc(n * 4 * sizeof(float));
    if (!px || !out) {
        png_image_free(&img);
        free(px);
        free(out);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", path);
    }
    if (!png_image_finish_read(&img, NULL, px, 0, NULL)) {
        xrad_status st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot read PNG: %s", path,
                                   img.message);
        png_image_free(&img);
        free(px);
        free(out);
        return st;
    }
    /* The inverse of srgb_encode: linear values in [0, 1]. */
    float lut[256];
    for (int i = 0; i < 256; i++) {
        double s = i / 255.0;
        lut[i] = (float)(s <= 0.04045 ? s / 12.92 : pow((s + 0.055) / 1.055, 2.4));
    }
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            out[i * 4 + c] = lut[px[i * 4 + c]];
        out[i * 4 + 3] = 1.0f;
    }
    free(px);
    *rgba = out;
    *width = img.width;
    *height = img.height;
    return XRAD_OK;
}
