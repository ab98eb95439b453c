#include "solvers/luminaire_change.h"

#include <stdlib.h>
#include <string.h>

#include "scene/scene_luminaire.h"

xrad_status luminaire_change_create(struct xrad_context *ctx, const xrad_scene *scene,
                                    luminaire_change *lc, xrad_error *err)
{
    memset(lc, 0, sizeof(*lc));
    lc->active = scene->luminaire_count > 0 && scene->element_count > 0;
    size_t n = lc->active ? scene->element_count : 1;
    if (lc->active) {
        lc->base = calloc(n, sizeof(vec3));
        lc->now = calloc(n, sizeof(vec3));
        if (!lc->base || !lc->now)
            return xrad_fail(err, XRAD_ERROR_SYSTEM,
                             "%s: out of host memory for the luminaires' light", scene->path);
    }
    xrad_status st = gpu_buffer_create(ctx, (VkDeviceSize)n * 4 * sizeof(float),
                                       VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_UPLOAD,
                                       GPU_MEM_REDISTRIBUTION, &lc->buffer, err);
    if (st)
        return st;
    if (!lc->buffer.alloc.mapped)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "%s: the luminaires' light buffer is not host-visible", scene->path);
    memset(lc->buffer.alloc.mapped, 0, n * 4 * sizeof(float));
    return XRAD_OK;
}

void luminaire_change_destroy(struct xrad_context *ctx, luminaire_change *lc)
{
    gpu_buffer_destroy(ctx, &lc->buffer);
    free(lc->base);
    free(lc->now);
    memset(lc, 0, sizeof(*lc));
}

xrad_status luminaire_change_set_base(luminaire_change *lc, const xrad_scene *scene, double time,
                                      bool dynamic_too, xrad_error *err)
{
    return lc->active ? scene_luminaire_reflected(scene, time, dynamic_too, lc->base, err)
                      : XRAD_OK;
}

xrad_status luminaire_change_pose(luminaire_change *lc, const xrad_scene *scene, double time,
                                  bool advance, xrad_error *err)
{
    if (!lc->active)
        return XRAD_OK;
    xrad_status st = scene_luminaire_reflected(scene, time, true, lc->now, err);
    if (st)
        return st;
    float *out = lc->buffer.alloc.mapped;
    for (uint32_t e = 0; e < scene->element_count; e++) {
        const surface *sf = &scene->surfaces[scene->elements[e].surface];
        vec3 v = scene->objects[sf->object].dynamic ? lc->now[e] : v3_sub(lc->now[e], lc->base[e]);
        out[4 * e + 0] = (float)v.x;
        out[4 * e + 1] = (float)v.y;
        out[4 * e + 2] = (float)v.z;
        out[4 * e + 3] = 0;
        if (advance)
            lc->base[e] = lc->now[e];
    }
    return XRAD_OK;
}
