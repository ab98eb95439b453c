/* Luminaires and their direct light (scene_luminaire.h). */
#include "scene/scene_luminaire.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/photometry.h"
#include "scene/scene_internal.h"

#define PI 3.14159265358979323846

static bool finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

xrad_status scene_luminaire_setup(const xrad_luminaire_desc *d, const char *where, luminaire *out,
                                  xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    snprintf(out->name, sizeof(out->name), "%s", d->name ? d->name : "");
    if (!finite3(d->position) || fabs(d->position[0]) > SCENE_MAX_COORD ||
        fabs(d->position[1]) > SCENE_MAX_COORD || fabs(d->position[2]) > SCENE_MAX_COORD)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'position': must be finite, within %g m",
                         where, SCENE_MAX_COORD);
    out->position = v3(d->position[0], d->position[1], d->position[2]);
    vec3 aim = v3(d->aim[0], d->aim[1], d->aim[2]);
    if (!finite3(d->aim))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'aim': must be finite", where);
    if (v3_len(aim) == 0)
        aim = v3(0, -1, 0);
    out->aim = v3_norm(aim);
    vec3 up = v3(d->up[0], d->up[1], d->up[2]);
    if (!finite3(d->up))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'up': must be finite", where);
    bool given = v3_len(up) > 0;
    if (!given)
        up = fabs(out->aim.x) > 0.9 ? v3(0, 0, 1) : v3(1, 0, 0);
    vec3 c0 = v3_sub(up, v3_scale(out->aim, v3_dot(up, out->aim)));
    if (!(v3_len(c0) > 1e-6 * v3_len(up)))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'up': (%g, %g, %g) lies along aim", where,
                         up.x, up.y, up.z);
    out->c0 = v3_norm(c0);
    /* C counterclockwise seen from above (against aim): C90 = C0 x aim. */
    out->c90 = v3_cross(out->c0, out->aim);
    double scale = d->scale == 0 ? 1 : d->scale;
    if (!(scale > 0 && scale <= 1e6))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'scale': must be in (0, 1e6], got %g",
                         where, d->scale);
    out->cos_outer = -2;
    out->cos_inner = -2;
    if (d->file) {
        out->photometry = calloc(1, sizeof(photometry));
        if (!out->photometry)
            return xrad_fail(err, XRAD_ERROR_SYSTEM, "%sout of memory", where);
        xrad_status st = photometry_load(d->file, out->photometry, err);
        if (st) {
            free(out->photometry);
            out->photometry = NULL;
            xrad_error_prefix(err, "%sfield 'file'", where);
            return st;
        }
        /* Wallner eq. 10-12: cd / 683 is W/sr at 555 nm, white. */
        double w = scale / PHOTOMETRY_LM_PER_W;
        out->intensity = v3(w, w, w);
        return XRAD_OK;
    }
    for (int k = 0; k < 3; k++)
        if (!(d->intensity[k] >= 0 && d->intensity[k] <= SCENE_MAX_EMISSION))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%sfield 'intensity': must be in [0, %g] W/sr per channel, got %g",
                             where, SCENE_MAX_EMISSION, d->intensity[k]);
    if (!(d->intensity[0] + d->intensity[1] + d->intensity[2] > 0))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%sfield 'intensity': missing or zero (W/sr, 3 values)", where);
    out->intensity = v3_scale(v3(d->intensity[0], d->intensity[1], d->intensity[2]), scale);
    if (d->cone_degrees != 0) {
        if (!(d->cone_degrees > 0 && d->cone_degrees <= 180))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%sfield 'cone': must be in (0, 180] degrees, got %g", where,
                             d->cone_degrees);
        if (!(d->falloff_degrees >= 0 && d->falloff_degrees <= d->cone_degrees))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%sfield 'falloff': must be in [0, cone = %g] degrees, got %g", where,
                             d->cone_degrees, d->falloff_degrees);
        out->cos_outer = cos(d->cone_degrees * PI / 180);
        out->cos_inner = cos((d->cone_degrees - d->falloff_degrees) * PI / 180);
    } else if (d->falloff_degrees != 0) {
        return xrad_fail(err, XRAD_ERROR_INPUT, "%sfield 'falloff': a spot's, given without a cone",
                         where);
    }
    return XRAD_OK;
}

void scene_luminaire_free(luminaire *l)
{
    if (l->photometry)
        photometry_free(l->photometry);
    free(l->photometry);
    l->photometry = NULL;
}

vec3 scene_luminaire_intensity(const luminaire *l, vec3 dir)
{
    double cg = fmax(-1.0, fmin(1.0, v3_dot(dir, l->aim)));
    if (l->photometry) {
        double gamma = acos(cg) * 180 / PI;
        double c = atan2(v3_dot(dir, l->c90), v3_dot(dir, l->c0)) * 180 / PI;
        return v3_scale(l->intensity, photometry_intensity(l->photometry, c < 0 ? c + 360 : c,
                                                           gamma));
    }
    if (l->cos_outer < -1 || cg >= l->cos_inner)
        return l->intensity;
    if (cg <= l->cos_outer)
        return v3(0, 0, 0);
    /* smoothstep across the falloff, in the cosine */
    double x = (cg - l->cos_outer) / (l->cos_inner - l->cos_outer);
    return v3_scale(l->intensity, x * x * (3 - 2 * x));
}

xrad_status scene_luminaire_irradiance(const xrad_scene *scene, double time, bool dynamic_too,
                                       vec3 *out, xrad_error *err)
{
    if (!scene->luminaire_count)
        return XRAD_OK;
    scene_rays rs;
    xrad_status st = scene_rays_init(&rs, scene, time, dynamic_too, err);
    if (st)
        return st;
    /* An element face to face with another surface takes no light (a
     * box's bottom on the floor): its sample point lies in the contact,
     * where no segment can tell. The solvers' own rule and tolerance
     * (gpu_scene.h GPU_SCENE_CONTACT). */
    uint8_t *buried = calloc(scene->element_count ? scene->element_count : 1, 1);
    uint32_t nb = 0;
    if (!buried)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for the luminaires' light",
                       scene->path);
    if (!st)
        st = scene_find_buried(scene, time, 1e-4 * rs.diameter, buried, &nb, err);
    if (st) {
        free(buried);
        scene_rays_free(&rs);
        return st;
    }
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        xform pose = scene_object_pose(scene, sf->object, time);
        vec3 n = rs.normals[s];
        for (uint32_t k = 0; k < sf->nu * sf->nv; k++) {
            uint32_t e = sf->first_element + k;
            /* 1: a static surface covers it, 2: a dynamic one. */
            if (buried[e] == 1 || (buried[e] && dynamic_too))
                continue;
            /* The sample point just off the surface: a luminaire on a
             * surface lights what its segment reaches. */
            vec3 x = v3_mad(xf_point(&pose, scene->elements[e].pos), n, 1e-7 * rs.diameter);
            /* The receiver's cosine takes its normal map's normal (Wallner
             * 3.3); light from behind its surface's plane stays out. */
            vec3 nr = scene->element_normal ? v3_norm(xf_dir(&pose, scene->element_normal[e])) : n;
            vec3 sum = v3(0, 0, 0);
            for (uint32_t i = 0; i < scene->luminaire_count; i++) {
                const luminaire *l = &scene->luminaires[i];
                vec3 d = v3_sub(l->position, x);
                double r2 = v3_dot(d, d);
                if (!(r2 > 0))
                    continue;
                vec3 w = v3_scale(d, 1 / sqrt(r2));
                double cr = v3_dot(nr, w); /* the receiver's cosine */
                if (cr <= 0 || v3_dot(n, w) <= 0)
                    continue;
                vec3 I = scene_luminaire_intensity(l, v3_scale(w, -1));
                if (I.x + I.y + I.z <= 0 || scene_rays_blocked(&rs, x, l->position, s))
                    continue;
                sum = v3_mad(sum, I, cr / r2); /* E = I cos(theta) / d^2 */
            }
            out[e] = v3_add(out[e], sum);
        }
    }
    free(buried);
    scene_rays_free(&rs);
    return XRAD_OK;
}

xrad_status scene_luminaire_reflected(const xrad_scene *scene, double time, bool dynamic_too,
                                      vec3 *out, xrad_error *err)
{
    memset(out, 0, (size_t)scene->element_count * sizeof(*out));
    xrad_status st = scene_luminaire_irradiance(scene, time, dynamic_too, out, err);
    for (uint32_t e = 0; !st && e < scene->element_count; e++)
        out[e] = v3_mul(scene_element_albedo(scene, e), out[e]);
    return st;
}
