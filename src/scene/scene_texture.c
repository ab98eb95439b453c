/* Albedo and normal maps -> element albedos and normals (scene_texture.h). */
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
                               const char *field, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    if (!d->rgb || d->width == 0 || d->height == 0 || d->width > SCENE_TEXTURE_MAX_SIDE ||
        d->height > SCENE_TEXTURE_MAX_SIDE ||
        (uint64_t)d->width * d->height > SCENE_TEXTURE_MAX_TEXELS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%sfield '%s': %u x %u texels%s: must be 1 to %u on a side, %u "
                         "in all, with texels",
                         where, field, d->width, d->height, d->rgb ? "" : " (rgb NULL)",
                         SCENE_TEXTURE_MAX_SIDE, SCENE_TEXTURE_MAX_TEXELS);
    size_t n = (size_t)d->width * d->height * 3;
    for (size_t k = 0; k < n; k++)
        if (!(d->rgb[k] >= 0 && d->rgb[k] <= 1))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%sfield '%s': texel (%zu, %zu) channel %zu is %g, outside [0, 1]",
                             where, field, k / 3 % d->width, k / 3 / d->width, k % 3, d->rgb[k]);
    out->rgb = malloc(n * sizeof(float));
    if (!out->rgb)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%sfield '%s': out of memory for %u x %u texels",
                         where, field, d->width, d->height);
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

vec3 scene_texture_normal(const surface *sf, const scene_uv *uv, vec3 mean)
{
    vec3 n = sf->normal;
    /* The face's tangent and bitangent: dP/du and dP/dv of the affine map
     * through corners 0, 1 and 3 (the apex, p[3] = p[2], on a triangle). */
    vec3 e1 = v3_sub(sf->p[1], sf->p[0]), e2 = v3_sub(sf->p[3], sf->p[0]);
    double du1 = uv->uv[1][0] - uv->uv[0][0], dv1 = uv->uv[1][1] - uv->uv[0][1];
    double du2 = uv->uv[3][0] - uv->uv[0][0], dv2 = uv->uv[3][1] - uv->uv[0][1];
    double det = du1 * dv2 - du2 * dv1;
    vec3 t = v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), 1 / det);
    vec3 b = v3_scale(v3_sub(v3_scale(e2, du1), v3_scale(e1, du2)), 1 / det);
    t = v3_sub(t, v3_scale(n, v3_dot(n, t)));
    double tl = v3_len(t);
    if (!(fabs(det) > 1e-20 && tl > 0 && isfinite(tl)))
        return n;
    t = v3_scale(t, 1 / tl);
    /* glTF: bitangent = cross(normal, tangent) x w, w the handedness. */
    vec3 bt = v3_cross(n, t);
    if (v3_dot(bt, b) < 0)
        bt = v3_scale(bt, -1);
    vec3 m = v3_add(v3_add(v3_scale(t, 2 * mean.x - 1), v3_scale(bt, 2 * mean.y - 1)),
                    v3_scale(n, 2 * mean.z - 1));
    if (!(v3_len(m) > 0))
        return n;
    m = v3_norm(m);
    double h = v3_dot(m, n);
    if (h < 0.05) {
        /* Lift it to 0.05 above the horizon, keeping its azimuth. */
        vec3 side = v3_sub(m, v3_scale(n, h));
        double sl = v3_len(side);
        side = sl > 0 ? v3_scale(side, 1 / sl) : t;
        m = v3_add(v3_scale(side, sqrt(1 - 0.05 * 0.05)), v3_scale(n, 0.05));
    }
    return m;
}

uint32_t scene_texture_refined(uint32_t n)
{
    return n <= 1 ? 3 : 2 * n - 1;
}

int scene_texture_normals_vary(const scene_texture *tex, const surface *sf, const scene_uv *uv,
                               uint32_t nu, uint32_t nv)
{
    vec3 *n = malloc((size_t)nu * nv * sizeof(vec3));
    if (!n)
        return -1;
    for (uint32_t j = 0; j < nv; j++)
        for (uint32_t i = 0; i < nu; i++) {
            double s0, s1, t0, t1;
            scene_param_range(i, i, nu, &s0, &s1);
            scene_param_range(j, j, nv, &t0, &t1);
            n[j * nu + i] =
                scene_texture_normal(sf, uv, scene_texture_mean(tex, sf, uv, s0, s1, t0, t1));
        }
    const double limit = cos(SCENE_NORMAL_DETAIL_DEGREES * 3.14159265358979323846 / 180);
    int vary = 0;
    for (uint32_t j = 0; j < nv && !vary; j++)
        for (uint32_t i = 0; i < nu && !vary; i++) {
            vec3 a = n[j * nu + i];
            vary = (i + 1 < nu && v3_dot(a, n[j * nu + i + 1]) < limit) ||
                   (j + 1 < nv && v3_dot(a, n[(j + 1) * nu + i]) < limit);
        }
    free(n);
    return vary;
}

xrad_status scene_texture_apply(xrad_scene *scene, const scene_material_maps *maps,
                                uint32_t map_count, const scene_uv *uv, xrad_error *err)
{
    for (uint32_t k = 0; k < map_count && k < scene->material_count; k++) {
        scene->albedo_maps += maps[k].albedo.width > 0;
        scene->normal_maps += maps[k].normal.width > 0;
    }
    bool albedo = scene->albedo_maps > 0, normal = scene->normal_maps > 0;
    size_t n = scene->element_count ? scene->element_count : 1;
    if ((albedo && !(scene->element_albedo = malloc(n * sizeof(vec3)))) ||
        (normal && !(scene->element_normal = malloc(n * sizeof(vec3)))))
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %u element maps",
                         scene->path, scene->element_count);
    for (uint32_t si = 0; si < scene->surface_count; si++) {
        const surface *sf = &scene->surfaces[si];
        const material *m = &scene->materials[sf->material];
        const scene_material_maps *mm = sf->material < map_count ? &maps[sf->material] : NULL;
        for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
            uint32_t e = sf->first_element + k;
            double s0, s1, t0, t1;
            scene_param_range(k % sf->nu, k % sf->nu, sf->nu, &s0, &s1);
            scene_param_range(k / sf->nu, k / sf->nu, sf->nv, &t0, &t1);
            if (albedo) {
                scene->element_albedo[e] = m->albedo;
                if (mm && mm->albedo.width) {
                    scene->mapped_elements++;
                    /* glTF: base colour factor x texture. */
                    scene->element_albedo[e] = v3_mul(
                        m->albedo, scene_texture_mean(&mm->albedo, sf, &uv[si], s0, s1, t0, t1));
                }
            }
            if (normal) {
                scene->element_normal[e] = sf->normal;
                if (mm && mm->normal.width) {
                    scene->normal_mapped_elements++;
                    scene->element_normal[e] = scene_texture_normal(
                        sf, &uv[si], scene_texture_mean(&mm->normal, sf, &uv[si], s0, s1, t0, t1));
                }
            }
        }
    }
    return XRAD_OK;
}
