/* Albedo maps -> element albedos (scene_texture.h). */
#include "scene/scene_texture.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_internal.h"

/* Samples per cell side: 8 per texel the coordinates cross and 2 more,
 * an even count, so that no sample falls on a seam through the cell's
 * middle (the mean of a texture of squares by the midpoint rule: 0.05% off
 * on a triangle across three texels, test_textures), at most this. */
#define TEXTURE_MAX_SAMPLES 48

xrad_status scene_texture_copy(const xrad_image_desc *d, scene_texture *out, const char *where,
                               xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    if (!d->rgb || d->width == 0 || d->height == 0 || d->width > SCENE_TEXTURE_MAX_SIDE ||
        d->height > SCENE_TEXTURE_MAX_SIDE ||
        (uint64_t)d->width * d->height > SCENE_TEXTURE_MAX_TEXELS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%sfield 'albedo_map': %u x %u texels%s: must be 1 to %u on a side, %u "
                         "in all, with texels",
                         where, d->width, d->height, d->rgb ? "" : " (rgb NULL)",
                         SCENE_TEXTURE_MAX_SIDE, SCENE_TEXTURE_MAX_TEXELS);
    size_t n = (size_t)d->width * d->height * 3;
    for (size_t k = 0; k < n; k++)
        if (!(d->rgb[k] >= 0 && d->rgb[k] <= 1))
            return xrad_fail(
                err, XRAD_ERROR_INPUT,
                "%sfield 'albedo_map': texel (%zu, %zu) channel %zu is %g, outside [0, 1]", where,
                k / 3 % d->width, k / 3 / d->width, k % 3, d->rgb[k]);
    out->rgb = malloc(n * sizeof(float));
    if (!out->rgb)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "%sfield 'albedo_map': out of memory for %u x %u texels", where, d->width,
                         d->height);
    memcpy(out->rgb, d->rgb, n * sizeof(float));
    out->width = d->width;
    out->height = d->height;
    return XRAD_OK;
}

static void uv_at(const scene_uv *uv, double s, double t, double out[2])
{
    for (int c = 0; c < 2; c++)
        out[c] = (1 - s) * (1 - t) * uv->uv[0][c] + s * (1 - t) * uv->uv[1][c] +
                 s * t * uv->uv[2][c] + (1 - s) * t * uv->uv[3][c];
}

/* Texel index of coordinate x (texels) on a side of n, repeating. */
static uint32_t wrap(double x, uint32_t n)
{
    double f = floor(x);
    double m = fmod(f, (double)n);
    if (m < 0)
        m += n;
    return (uint32_t)m < n ? (uint32_t)m : n - 1;
}

/* Samples along one side of a cell whose coordinates change by `texels`. */
static int samples_for(double texels)
{
    double n = 2 * ceil(4 * texels + 1);
    return n > TEXTURE_MAX_SAMPLES ? TEXTURE_MAX_SAMPLES : (int)n;
}

vec3 scene_texture_mean(const scene_texture *tex, const surface *sf, const scene_uv *uv, double s0,
                        double s1, double t0, double t1)
{
    /* How far the coordinates move along s and t over the cell, in texels
     * (the larger of the two opposite sides). */
    double c[4][2];
    uv_at(uv, s0, t0, c[0]);
    uv_at(uv, s1, t0, c[1]);
    uv_at(uv, s1, t1, c[2]);
    uv_at(uv, s0, t1, c[3]);
    double along_s = 0, along_t = 0;
    for (int e = 0; e < 2; e++) {
        const double *a = c[e == 0 ? 0 : 3], *b = c[e == 0 ? 1 : 2];
        along_s = fmax(along_s, hypot((b[0] - a[0]) * tex->width, (b[1] - a[1]) * tex->height));
        const double *p = c[e == 0 ? 0 : 1], *q = c[e == 0 ? 3 : 2];
        along_t = fmax(along_t, hypot((q[0] - p[0]) * tex->width, (q[1] - p[1]) * tex->height));
    }
    int ns = samples_for(along_s), nt = samples_for(along_t);
    double sum[3] = {0, 0, 0}, weight = 0;
    for (int j = 0; j < nt; j++) {
        double t = t0 + (t1 - t0) * (j + 0.5) / nt;
        for (int i = 0; i < ns; i++) {
            double s = s0 + (s1 - s0) * (i + 0.5) / ns;
            double w = scene_surface_jacobian(sf, s, t);
            if (!(w > 0))
                continue;
            double p[2];
            uv_at(uv, s, t, p);
            /* Row 0 is the top, v = 1 (xrad.h xrad_image_desc). */
            uint32_t x = wrap(p[0] * tex->width, tex->width);
            uint32_t y = wrap((1 - p[1]) * tex->height, tex->height);
            const float *texel = &tex->rgb[3 * ((size_t)y * tex->width + x)];
            for (int k = 0; k < 3; k++)
                sum[k] += w * texel[k];
            weight += w;
        }
    }
    if (!(weight > 0))
        return v3(0, 0, 0);
    return v3(sum[0] / weight, sum[1] / weight, sum[2] / weight);
}

xrad_status scene_texture_albedos(xrad_scene *scene, const scene_texture *maps,
                                  uint32_t map_count, const scene_uv *uv, xrad_error *err)
{
    scene->element_albedo = malloc((size_t)(scene->element_count ? scene->element_count : 1) *
                                   sizeof(vec3));
    if (!scene->element_albedo)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %u element albedos",
                         scene->path, scene->element_count);
    for (uint32_t k = 0; k < map_count && k < scene->material_count; k++)
        scene->albedo_maps += maps[k].width > 0;
    for (uint32_t si = 0; si < scene->surface_count; si++) {
        const surface *sf = &scene->surfaces[si];
        const material *m = &scene->materials[sf->material];
        const scene_texture *tex = sf->material < map_count ? &maps[sf->material] : NULL;
        for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
            uint32_t e = sf->first_element + k;
            if (!tex || !tex->width) {
                scene->element_albedo[e] = m->albedo;
                continue;
            }
            scene->mapped_elements++;
            double s0, s1, t0, t1;
            scene_param_range(k % sf->nu, k % sf->nu, sf->nu, &s0, &s1);
            scene_param_range(k / sf->nu, k / sf->nu, sf->nv, &t0, &t1);
            /* glTF: base colour factor x texture. */
            scene->element_albedo[e] =
                v3_mul(m->albedo, scene_texture_mean(tex, sf, &uv[si], s0, s1, t0, t1));
        }
    }
    return XRAD_OK;
}
