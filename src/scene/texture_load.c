/* Image files -> albedo maps (scene_texture.h): PNG, JPEG, TGA and BMP
 * through stb_image (Debian libstb-dev, the header built here, its
 * functions private to this file), sRGB decoded to linear RGB. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_texture.h"

#if defined(__GNUC__)
/* For the whole file: GCC reports stb_image's static declarations that
 * no definition follows (gif, per-thread settings) at its end. */
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wpedantic"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#endif
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_ONLY_TGA
#define STBI_ONLY_BMP
/* stb_image's own ceiling, as large as the maps xrad takes. */
#define STBI_MAX_DIMENSIONS 16384
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

void scene_texture_from_8bit(const uint8_t *in, size_t count, bool srgb, float *out)
{
    /* IEC 61966-2-1 (sRGB) decoding of each 8-bit value. */
    float table[256];
    for (int v = 0; v < 256; v++) {
        double c = v / 255.0;
        table[v] = (float)(!srgb ? c : c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
    }
    for (size_t k = 0; k < count; k++)
        out[k] = table[in[k]];
}

xrad_status scene_texture_decode(const void *data, size_t size, bool srgb, const char *what,
                                 float **rgb, uint32_t *width, uint32_t *height, xrad_error *err)
{
    *rgb = NULL;
    *width = *height = 0;
    int w = 0, h = 0, n = 0;
    if (size > INT32_MAX)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %zu bytes, more than an image xrad reads",
                         what, size);
    if (!stbi_info_from_memory(data, (int)size, &w, &h, &n))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: not an image xrad reads (%s)", what,
                         stbi_failure_reason());
    /* Before stb_image allocates for it. */
    if (w <= 0 || h <= 0 || (uint32_t)w > SCENE_TEXTURE_MAX_SIDE ||
        (uint32_t)h > SCENE_TEXTURE_MAX_SIDE || (uint64_t)w * h > SCENE_TEXTURE_MAX_TEXELS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: %d x %d pixels, more than %u on a side or %u in all", what, w, h,
                         SCENE_TEXTURE_MAX_SIDE, SCENE_TEXTURE_MAX_TEXELS);
    uint8_t *px = stbi_load_from_memory(data, (int)size, &w, &h, &n, 3);
    if (!px)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot decode: %s", what,
                         stbi_failure_reason());
    size_t count = (size_t)w * h * 3;
    float *out = malloc(count * sizeof(float));
    if (!out) {
        stbi_image_free(px);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %d x %d texels", what,
                         w, h);
    }
    scene_texture_from_8bit(px, count, srgb, out);
    stbi_image_free(px);
    *rgb = out;
    *width = (uint32_t)w;
    *height = (uint32_t)h;
    return XRAD_OK;
}
