/* Scene files by their name: JSON scenes (scene_parse.c) and model files
 * (scene_import.c), which are a scene by themselves: one static object
 * named after the file, its camera the file's first (or
 * xrad_scene_load_desc.camera). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

/* A model file as a scene; from `data` (size bytes) when not NULL, `path`
 * then naming it. */
static xrad_status load_model(const char *path, const void *data, size_t size,
                              const xrad_scene_load_desc *desc, xrad_scene **out,
                              xrad_error *err)
{
    /* The object is the file's name without its directory and extension. */
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    char name[SCENE_NAME_MAX];
    const char *dot = strrchr(base, '.');
    int len = dot && dot > base ? (int)(dot - base) : (int)strlen(base);
    snprintf(name, sizeof(name), "%.*s", len < SCENE_NAME_MAX - 1 ? len : SCENE_NAME_MAX - 1,
             base);
    xrad_scene_builder *b = NULL;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = path,
                                   .density_scale = desc ? desc->density_scale : 0,
                                   .adaptive = desc ? desc->adaptive : (xrad_adaptive_desc){0}},
        &b, err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = name}, err);
    scene_import_desc id = {.prefix = name,
                            .take_camera = true,
                            .camera = desc ? desc->camera : NULL,
                            .material = UINT32_MAX};
    if (!st)
        st = data ? scene_import_memory(b, path, data, size, &id, err)
                  : scene_import_model(b, path, &id, err);
    if (!st)
        st = xrad_scene_builder_finish(b, out, err);
    xrad_scene_builder_destroy(&b);
    return st;
}

xrad_status scene_load_model_memory(const char *name, const void *data, size_t size,
                                    xrad_scene **out, xrad_error *err)
{
    *out = NULL;
    return load_model(name, data ? data : "", size, NULL, out, err);
}

xrad_status xrad_scene_load(const char *path, xrad_scene **out, xrad_error *err)
{
    return xrad_scene_load_with(path, NULL, out, err);
}

xrad_status scene_read_file(const char *path, size_t max_bytes, char **out, size_t *size,
                            xrad_error *err)
{
    *out = NULL;
    *size = 0;
    FILE *f = fopen(path, "rb");
    if (!f)
        /* A file that is not there or not ours to read is the caller's bad
         * input; anything else (EIO, EMFILE, ...) is the system's. */
        return xrad_fail(err,
                         errno == ENOENT || errno == ENOTDIR || errno == EACCES ||
                                 errno == EISDIR || errno == ENAMETOOLONG || errno == ELOOP
                             ? XRAD_ERROR_INPUT
                             : XRAD_ERROR_SYSTEM,
                         "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap + 1);
    xrad_status st = XRAD_OK;
    while (buf) {
        if (len == cap) {
            if (cap >= max_bytes) {
                st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: larger than the %zu byte limit", path,
                               max_bytes);
                break;
            }
            char *grown = realloc(buf, cap * 2 + 1);
            if (!grown) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = grown;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            /* A directory opens and fails its first read (scenes/README.md:
             * what may not be read is the user's error). */
            if (ferror(f))
                st = xrad_fail(err, errno == EISDIR ? XRAD_ERROR_INPUT : XRAD_ERROR_SYSTEM,
                               "%s: cannot read: %s", path, strerror(errno));
            break;
        }
    }
    fclose(f);
    if (!buf)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory reading it", path);
    if (st) {
        free(buf);
        return st;
    }
    buf[len] = 0;
    *out = buf;
    *size = len;
    return XRAD_OK;
}

xrad_status xrad_scene_load_with(const char *path, const xrad_scene_load_desc *desc,
                                 xrad_scene **out, xrad_error *err)
{
    *out = NULL;
    if (scene_import_supported(path))
        return load_model(path, NULL, 0, desc, out, err);
    char *buf;
    size_t len;
    xrad_status st = scene_read_file(path, SCENE_MAX_FILE_BYTES, &buf, &len, err);
    if (!st)
        st = xrad_scene_parse_with(buf, len, path, desc, out, err);
    free(buf);
    return st;
}

