/* Buried elements: receivers that lie on another surface's front face,
 * face to face (the bottom of a box standing on a floor, the floor under
 * it). */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

#define SCENE_PI 3.14159265358979323846

/* The parameter interval of sample i of n along a side (scene.h: the part
 * of the surface within half a sample spacing of the sample). */
static void cell_interval(uint32_t i, uint32_t n, double *lo, double *hi)
{
    double h = 1.0 / (n - 1), c = i * h;
    *lo = fmax(0.0, c - 0.5 * h);
    *hi = fmin(1.0, c + 0.5 * h);
}

vec3 scene_element_centroid(const surface *s, const element *e)
{
    double s0, s1, t0, t1;
    cell_interval(e->i, s->nu, &s0, &s1);
    cell_interval(e->j, s->nv, &t0, &t1);
    return surface_point(s, 0.5 * (s0 + s1), 0.5 * (t0 + t1));
}

/* x inside the convex planar quad c (normal n) by at least `margin` m
 * from every edge (a negative margin admits points that far outside). */
static bool inside_quad(const vec3 c[4], vec3 n, vec3 x, double margin)
{
    for (int k = 0; k < 4; k++) {
        vec3 a = c[k], b = c[(k + 1) & 3];
        if (v3_dot(v3_cross(v3_sub(b, a), v3_sub(x, a)), n) < margin * v3_len(v3_sub(b, a)))
            return false;
    }
    return true;
}

/* Every surface's world corners (4 each) and normal at time t, malloc'd
 * into *corners and *normals (free both). */
static xrad_status world_quads(const xrad_scene *scene, double t, vec3 **corners,
                               vec3 **normals, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    *corners = malloc((ns ? ns : 1) * sizeof(vec3[4]));
    *normals = malloc((ns ? ns : 1) * sizeof(vec3));
    if (!*corners || !*normals) {
        free(*corners);
        free(*normals);
        *corners = *normals = NULL;
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %u surfaces' contact",
                         scene->path, ns);
    }
    for (uint32_t s = 0; s < ns; s++)
        scene_surface_world(scene, s, t, &(*corners)[4 * s], &(*normals)[s]);
    return XRAD_OK;
}

xrad_status scene_find_buried(const xrad_scene *scene, double time, double tol,
                              uint8_t *buried, uint32_t *count, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    *count = 0;
    for (uint32_t e = 0; e < scene->element_count; e++)
        buried[e] = 0;
    vec3 *corners, *normals;
    xrad_status st = world_quads(scene, time, &corners, &normals, err);
    if (st)
        return st;
    /* Pairs first: a cover must face the receiver's surface (normals
     * opposed) and lie in its plane (every corner within tol), which few
     * pairs do; only their elements are tested one by one. */
    for (uint32_t r = 0; r < ns; r++) {
        const surface *sr = &scene->surfaces[r];
        vec3 nr = normals[r], pr = corners[4 * r];
        xform pose = scene_object_pose(scene, sr->object, time);
        for (uint32_t c = 0; c < ns; c++) {
            if (c == r || !(v3_dot(normals[c], nr) < -0.999))
                continue;
            /* In front of the receiver's plane by at most tol, behind it by
             * no more than rounding: face to face. A cover behind it (the
             * two faces of a slab 1e-4 m thin, back to back) is not one. */
            bool coplanar = true;
            for (int k = 0; k < 4 && coplanar; k++) {
                double d = v3_dot(v3_sub(corners[4 * c + k], pr), nr);
                coplanar = d <= tol && d >= -1e-3 * tol;
            }
            if (!coplanar)
                continue;
            for (uint32_t k = 0; k < sr->nu * sr->nv; k++) {
                uint32_t e = sr->first_element + k;
                vec3 x = xf_point(&pose, scene_element_centroid(sr, &scene->elements[e]));
                uint8_t by = scene->objects[scene->surfaces[c].object].dynamic ? 2 : 1;
                if ((!buried[e] || by < buried[e]) && inside_quad(&corners[4 * c], normals[c], x, tol)) {
                    *count += !buried[e];
                    buried[e] = by;
                }
            }
        }
    }
    free(corners);
    free(normals);
    return XRAD_OK;
}

/* The nearest surface the ray o + t dir (t > tmin) meets, or -1; *back is
 * set when the ray meets its back face. Only static surfaces count. */
static int32_t nearest_static_hit(const xrad_scene *scene, const vec3 *corners,
                                  const vec3 *normals, vec3 o, vec3 dir, double tmin, bool *back)
{
    int32_t best = -1;
    double best_t = INFINITY;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        if (scene->objects[scene->surfaces[s].object].dynamic)
            continue;
        vec3 n = normals[s];
        double along = v3_dot(n, dir);
        if (along == 0)
            continue;
        double t = v3_dot(n, v3_sub(corners[4 * s], o)) / along;
        if (!(t > tmin && t < best_t))
            continue;
        if (!inside_quad(&corners[4 * s], n, v3_mad(o, dir, t), 0.0))
            continue;
        best = (int32_t)s;
        best_t = t;
        *back = along > 0;
    }
    return best;
}

xrad_status scene_find_enclosed(const xrad_scene *scene, uint8_t *enclosed, uint32_t *count,
                                xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    *count = 0;
    for (uint32_t e = 0; e < scene->element_count; e++)
        enclosed[e] = 0;
    /* Every element casts 25 rays at every surface: past this much work
     * (seconds on one core) a scene goes without the test. */
    if ((double)scene->element_count * ns > SCENE_ENCLOSED_MAX_WORK)
        return XRAD_OK;
    vec3 *corners, *normals;
    xrad_status st = world_quads(scene, 0.0, &corners, &normals, err);
    if (st)
        return st;
    vec3 lo, hi;
    scene_bounds(scene, 0.0, &lo, &hi);
    double diameter = v3_len(v3_sub(hi, lo));
    for (uint32_t r = 0; r < ns; r++) {
        const surface *sr = &scene->surfaces[r];
        if (scene->objects[sr->object].dynamic)
            continue;
        vec3 n = normals[r];
        /* A frame about the normal for the ray directions. */
        vec3 t = fabs(n.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
        t = v3_norm(v3_sub(t, v3_scale(n, v3_dot(t, n))));
        vec3 b = v3_cross(n, t);
        xform pose = scene_object_pose(scene, sr->object, 0.0);
        for (uint32_t k = 0; k < sr->nu * sr->nv; k++) {
            uint32_t e = sr->first_element + k;
            vec3 x = xf_point(&pose, scene_element_centroid(sr, &scene->elements[e]));
            vec3 o = v3_mad(x, n, 1e-7 * diameter);
            bool closed = true;
            /* The normal and 4 rings of 6 azimuths (elevations 15-75
             * degrees): a point sees out through any gap a ray finds. */
            for (int ring = -1; ring < 4 && closed; ring++) {
                int az_count = ring < 0 ? 1 : 6;
                for (int az = 0; az < az_count && closed; az++) {
                    double el = ring < 0 ? SCENE_PI / 2 : (15.0 + 20.0 * ring) * SCENE_PI / 180.0;
                    double phi = (az + 0.5 * (ring & 1)) * 2.0 * SCENE_PI / az_count;
                    vec3 dir = v3_add(v3_scale(n, sin(el)),
                                      v3_add(v3_scale(t, cos(el) * cos(phi)),
                                             v3_scale(b, cos(el) * sin(phi))));
                    bool back = false;
                    closed = nearest_static_hit(scene, corners, normals, o, dir,
                                                1e-7 * diameter, &back) >= 0 && back;
                }
            }
            if (closed) {
                enclosed[e] = 1;
                (*count)++;
            }
        }
    }
    free(corners);
    free(normals);
    return XRAD_OK;
}
