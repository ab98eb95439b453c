/* Linear RGBA images as OpenEXR, through the library's C core API. */
#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include <openexr.h>

#include "core/error.h"

/* 2^26 texels, 1 GiB of RGBA float: far above any image xrad writes. */
#define MAX_TEXELS (1 << 26)

static xrad_status exr_fail(xrad_error *err, const char *path, const char *what, exr_result_t r)
{
    xrad_status st = r == EXR_ERR_FILE_ACCESS || r == EXR_ERR_MISSING_CONTEXT_ARG ||
                             r == EXR_ERR_OUT_OF_MEMORY || r == EXR_ERR_WRITE_IO
                         ? XRAD_ERROR_SYSTEM
                         : XRAD_ERROR_INPUT;
    return xrad_fail(err, st, "%s: %s: %s (%s)", path, what, exr_get_default_error_message(r),
                     exr_get_error_code_as_string(r));
}

/* The channel list is kept sorted by name (A, B, G, R); map a name to its
 * offset in our interleaved RGBA pixel. */
static int rgba_offset(const char *name)
{
    switch (name[0]) {
    case 'R': return 0;
    case 'G': return 1;
    case 'B': return 2;
    case 'A': return 3;
    default: return -1;
    }
}

/* A channel name xrad can write beside R, G, B and A: printable, no
 * clash with those four. */
static bool extra_name_ok(const char *name)
{
    size_t n = name ? strlen(name) : 0;
    if (n == 0 || n > 31 || (n == 1 && rgba_offset(name) >= 0))
        return false;
    for (size_t i = 0; i < n; i++)
        if (name[i] <= ' ' || name[i] > '~')
            return false;
    return true;
}

/* R, G, B, A from rgba and, when `extra` is given, a fifth float channel
 * `name` from it (one float per pixel). */
static xrad_status write_exr(const char *path, const float *rgba, const char *name,
                             const float *extra, uint32_t width, uint32_t height,
                             xrad_error *err)
{
    if (width == 0 || height == 0 || width > INT32_MAX / 16)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot write a %ux%u image", path, width,
                         height);
    if (extra && !extra_name_ok(name))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: '%s' cannot name an extra channel (1-31 printable characters, "
                         "not R, G, B or A)",
                         path, name ? name : "(null)");
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_result_t r = exr_start_write(&ctx, path, EXR_INTERMEDIATE_TEMP_FILE, &init);
    if (r != EXR_ERR_SUCCESS)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot create: %s (errno: %s)", path,
                         exr_get_default_error_message(r), strerror(errno));

    const char *what = "header";
    int part = 0;
    if ((r = exr_add_part(ctx, "rgba", EXR_STORAGE_SCANLINE, &part)) ||
        (r = exr_initialize_required_attr_simple(ctx, part, (int32_t)width, (int32_t)height,
                                                 EXR_COMPRESSION_ZIP)))
        goto fail;
    static const char *const names[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++)
        if ((r = exr_add_channel(ctx, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR,
                                 1, 1)))
            goto fail;
    if (extra && (r = exr_add_channel(ctx, part, name, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR,
                                      1, 1)))
        goto fail;
    if ((r = exr_write_header(ctx)))
        goto fail;

    what = "pixels";
    int32_t lines = 1;
    if ((r = exr_get_scanlines_per_chunk(ctx, part, &lines)))
        goto fail;
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool have_pipe = false;
    for (int32_t y = 0; y < (int32_t)height; y += lines) {
        exr_chunk_info_t chunk;
        if ((r = exr_write_scanline_chunk_info(ctx, part, y, &chunk)))
            break;
        if (!have_pipe) {
            if ((r = exr_encoding_initialize(ctx, part, &chunk, &enc)))
                break;
            have_pipe = true;
        } else if ((r = exr_encoding_update(ctx, part, &chunk, &enc))) {
            break;
        }
        for (int c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            ch->user_bytes_per_element = sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            /* The channel list comes back sorted by name: match by name. */
            int off = strlen(ch->channel_name) == 1 ? rgba_offset(ch->channel_name) : -1;
            if (off < 0) {
                ch->user_pixel_stride = sizeof(float);
                ch->user_line_stride = (int32_t)(width * sizeof(float));
                ch->encode_from_ptr = (const uint8_t *)(extra + (size_t)y * width);
                continue;
            }
            ch->user_pixel_stride = 4 * sizeof(float);
            ch->user_line_stride = (int32_t)(width * 4 * sizeof(float));
            ch->encode_from_ptr = (const uint8_t *)(rgba + ((size_t)y * width * 4 + (size_t)off));
        }
        if (y == 0 && (r = exr_encoding_choose_default_routines(ctx, part, &enc)))
            break;
        if ((r = exr_encoding_run(ctx, part, &enc)))
            break;
    }
    if (have_pipe)
        exr_encoding_destroy(ctx, &enc);
    if (r)
        goto fail;
    if ((r = exr_finish(&ctx)))
        return exr_fail(err, path, "finishing", r);
    return XRAD_OK;

fail:
    exr_finish(&ctx);
    return exr_fail(err, path, what, r);
}

xrad_status xrad_image_write_exr(const char *path, const float *rgba, uint32_t width,
                                 uint32_t height, xrad_error *err)
{
    return write_exr(path, rgba, NULL, NULL, width, height, err);
}

xrad_status xrad_image_write_exr_channel(const char *path, const float *rgba, const char *name,
                                         const float *channel, uint32_t width, uint32_t height,
                                         xrad_error *err)
{
    return write_exr(path, rgba, name, channel, width, height, err);
}

/* Opens `path` for reading and checks what every reader needs: one
 * scanline part, a data window of sane size whose last scanline the chunk
 * table reaches. On success *ctx is open (exr_finish it). */
static xrad_status open_read(const char *path, exr_context_t *ctx, exr_attr_box2i_t *dw,
                             int64_t *width, int64_t *height, xrad_error *err)
{
    *ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_result_t r = exr_start_read(ctx, path, &init);
    if (r != EXR_ERR_SUCCESS) {
        exr_finish(ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: cannot read as OpenEXR: %s", path,
                         exr_get_default_error_message(r));
    }
    exr_storage_t storage;
    if ((r = exr_get_data_window(*ctx, 0, dw)) || (r = exr_get_storage(*ctx, 0, &storage))) {
        exr_finish(ctx);
        return exr_fail(err, path, "header", r);
    }
    if (storage != EXR_STORAGE_SCANLINE) {
        exr_finish(ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: only scanline OpenEXR images are read",
                         path);
    }
    int64_t w = (int64_t)dw->max.x - dw->min.x + 1, h = (int64_t)dw->max.y - dw->min.y + 1;
    if (w <= 0 || h <= 0 || w > 65536 || h > 65536) {
        exr_finish(ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: data window %lldx%lld is out of range",
                         path, (long long)w, (long long)h);
    }
    /* Before allocating for the data window, check that the file's chunk
     * table really reaches its last scanline: a few hundred bytes must not
     * make us allocate gigabytes (found by the fuzzer, tests/fuzz). */
    if (w * h > MAX_TEXELS) {
        exr_finish(ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %lldx%lld pixels is more than %d", path,
                         (long long)w, (long long)h, MAX_TEXELS);
    }
    exr_chunk_info_t last;
    if ((r = exr_read_scanline_chunk_info(*ctx, 0, dw->max.y, &last))) {
        exr_finish(ctx);
        return exr_fail(err, path, "header", r);
    }
    *width = w;
    *height = h;
    return XRAD_OK;
}

/* A channel not asked for decodes into a sink rather than being skipped
 * with NULL: OpenEXRCore 3.1's specialised unpackers write through every
 * channel's pointer (a crafted file crashed it; tests/fuzz). */
static void decode_to_sink(exr_coding_channel_info_t *ch, float *sink)
{
    ch->decode_to_ptr = (uint8_t *)sink;
    ch->user_pixel_stride = 0;
    ch->user_line_stride = 0;
    ch->user_bytes_per_element = sizeof(float);
    ch->user_data_type = EXR_PIXEL_FLOAT;
}

xrad_status xrad_image_read_exr(const char *path, float **out, uint32_t *width, uint32_t *height,
                                xrad_error *err)
{
    *out = NULL;
    exr_context_t ctx = NULL;
    exr_attr_box2i_t dw;
    int64_t w, h;
    xrad_status st = open_read(path, &ctx, &dw, &w, &h, err);
    if (st)
        return st;
    const char *what = "pixels";
    exr_result_t r;
    float *px = calloc((size_t)(w * h * 4), sizeof(float));
    if (!px) {
        exr_finish(&ctx);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %lldx%lld pixels", path,
                         (long long)w, (long long)h);
    }

    int32_t lines = 1;
    if ((r = exr_get_scanlines_per_chunk(ctx, 0, &lines)))
        goto fail_px;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    float sink[4];
    bool have_pipe = false;
    int found = 0;
    for (int32_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t chunk;
        if ((r = exr_read_scanline_chunk_info(ctx, 0, y, &chunk)))
            break;
        if (!have_pipe) {
            if ((r = exr_decoding_initialize(ctx, 0, &chunk, &dec)))
                break;
            have_pipe = true;
        } else if ((r = exr_decoding_update(ctx, 0, &chunk, &dec))) {
            break;
        }
        found = 0;
        for (int c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            int off = strlen(ch->channel_name) == 1 ? rgba_offset(ch->channel_name) : -1;
            /* Alpha is not read: xrad does not use it, and OpenEXRCore 3.1's
             * four-channel half unpacker returns half RGBA reversed (ABGR),
             * while three channels come back right. */
            if (off < 0 || off == 3 || ch->x_samples != 1 || ch->y_samples != 1) {
                decode_to_sink(ch, sink);
                continue;
            }
            found |= 1 << off;
            ch->user_pixel_stride = 4 * sizeof(float);
            ch->user_line_stride = (int32_t)(w * 4 * sizeof(float));
            ch->user_bytes_per_element = sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->decode_to_ptr =
                (uint8_t *)(px + ((size_t)(chunk.start_y - dw.min.y) * (size_t)w * 4 + (size_t)off));
        }
        if ((found & 7) != 7) {
            r = EXR_ERR_SUCCESS;
            break;
        }
        if (y == dw.min.y && (r = exr_decoding_choose_default_routines(ctx, 0, &dec)))
            break;
        if ((r = exr_decoding_run(ctx, 0, &dec)))
            break;
    }
    if (have_pipe)
        exr_decoding_destroy(ctx, &dec);
    if (r)
        goto fail_px;
    exr_finish(&ctx);
    for (int64_t i = 0; i < w * h; i++)
        px[i * 4 + 3] = 1.0f;
    if ((found & 7) != 7) {
        free(px);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: no full-resolution R, G and B channels",
                         path);
    }
    *out = px;
    *width = (uint32_t)w;
    *height = (uint32_t)h;
    return XRAD_OK;

fail_px:
    free(px);
    exr_finish(&ctx);
    return exr_fail(err, path, what, r);
}

xrad_status xrad_image_read_exr_channel(const char *path, const char *name, float **out,
                                        uint32_t *width, uint32_t *height, xrad_error *err)
{
    *out = NULL;
    exr_context_t ctx = NULL;
    exr_attr_box2i_t dw;
    int64_t w, h;
    xrad_status st = open_read(path, &ctx, &dw, &w, &h, err);
    if (st)
        return st;
    *width = (uint32_t)w;
    *height = (uint32_t)h;
    const exr_attr_chlist_t *list = NULL;
    exr_result_t r = exr_get_channels(ctx, 0, &list);
    if (r) {
        exr_finish(&ctx);
        return exr_fail(err, path, "channel list", r);
    }
    const exr_attr_chlist_entry_t *entry = NULL;
    for (int c = 0; c < list->num_channels; c++)
        if (list->entries[c].name.str && !strcmp(list->entries[c].name.str, name))
            entry = &list->entries[c];
    /* Absent is an answer, not an error: files written before the channel
     * existed are still good images. */
    if (!entry) {
        exr_finish(&ctx);
        return XRAD_OK;
    }
    if (entry->x_sampling != 1 || entry->y_sampling != 1) {
        exr_finish(&ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: channel %s is subsampled (%dx%d)", path,
                         name, entry->x_sampling, entry->y_sampling);
    }
    float *px = calloc((size_t)(w * h), sizeof(float));
    if (!px) {
        exr_finish(&ctx);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %lldx%lld pixels", path,
                         (long long)w, (long long)h);
    }
    int32_t lines = 1;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    float sink[4];
    bool have_pipe = false, found = false;
    if ((r = exr_get_scanlines_per_chunk(ctx, 0, &lines)))
        goto fail;
    for (int32_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t chunk;
        if ((r = exr_read_scanline_chunk_info(ctx, 0, y, &chunk)))
            break;
        if (!have_pipe) {
            if ((r = exr_decoding_initialize(ctx, 0, &chunk, &dec)))
                break;
            have_pipe = true;
        } else if ((r = exr_decoding_update(ctx, 0, &chunk, &dec))) {
            break;
        }
        found = false;
        for (int c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            if (found || strcmp(ch->channel_name, name) || ch->x_samples != 1 ||
                ch->y_samples != 1) {
                decode_to_sink(ch, sink);
                continue;
            }
            found = true;
            ch->user_pixel_stride = sizeof(float);
            ch->user_line_stride = (int32_t)(w * sizeof(float));
            ch->user_bytes_per_element = sizeof(float);
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->decode_to_ptr = (uint8_t *)(px + (size_t)(chunk.start_y - dw.min.y) * (size_t)w);
        }
        if (!found)
            break;
        if (y == dw.min.y && (r = exr_decoding_choose_default_routines(ctx, 0, &dec)))
            break;
        if ((r = exr_decoding_run(ctx, 0, &dec)))
            break;
    }
    if (have_pipe)
        exr_decoding_destroy(ctx, &dec);
    if (r)
        goto fail;
    exr_finish(&ctx);
    if (!found) {
        free(px);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: channel %s is listed but not decodable",
                         path, name);
    }
    *out = px;
    return XRAD_OK;

fail:
    free(px);
    exr_finish(&ctx);
    return exr_fail(err, path, "pixels", r);
}
