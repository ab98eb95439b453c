/* xrad_atlas_compare: the element-space error figures of two solutions of
 * one scene, surface by surface (core/metrics.c computes them). */
#include <stdlib.h>

#include "core/error.h"
#include "core/metrics.h"
#include "scene/scene.h"

xrad_status xrad_atlas_compare(const xrad_scene *scene, const xrad_atlas *a,
                               const xrad_atlas *b, xrad_element_metrics *out,
                               double *surface_ratio, xrad_error *err)
{
    *out = (xrad_element_metrics){0};
    for (int k = 0; k < 2; k++) {
        const xrad_atlas *t = k ? b : a;
        if (t->width != scene->atlas_width || t->height != scene->atlas_height || !t->rgba)
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: the %s atlas is %ux%u, the scene's is %ux%u", scene->path,
                             k ? "reference" : "compared", t->width, t->height,
                             scene->atlas_width, scene->atlas_height);
    }
    metrics_element *e = malloc(scene->element_count * sizeof(*e) + 1);
    unsigned char *skip = calloc(scene->surface_count + 1, 1);
    if (!e || !skip) {
        free(e);
        free(skip);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of memory comparing %u elements",
                         scene->element_count);
    }
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        vec3 em = scene->materials[scene->surfaces[s].material].emission;
        skip[s] = em.x > 0 || em.y > 0 || em.z > 0;
    }
    for (uint32_t i = 0; i < scene->element_count; i++) {
        const element *el = &scene->elements[i];
        size_t t = ((size_t)el->texel_y * scene->atlas_width + el->texel_x) * 4;
        e[i] = (metrics_element){
            .a = (double)a->rgba[t] + a->rgba[t + 1] + a->rgba[t + 2],
            .b = (double)b->rgba[t] + b->rgba[t + 1] + b->rgba[t + 2],
            .area = el->area,
            .group = el->surface,
        };
    }
    xrad_status st = metrics_elements(e, scene->element_count, scene->surface_count, skip, out,
                                      surface_ratio, err);
    free(e);
    free(skip);
    return st;
}
