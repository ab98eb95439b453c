/* Buried elements: receivers that lie on another surface's front face,
 * face to face (the bottom of a box standing on a floor, the floor under
 * it). */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

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

/* x inside the convex planar quad c (normal n), edges included. */
static bool inside_quad(const vec3 c[4], vec3 n, vec3 x)
{
    for (int k = 0; k < 4; k++) {
        vec3 a = c[k], b = c[(k + 1) & 3];
        if (v3_dot(v3_cross(v3_sub(b, a), v3_sub(x, a)), n) < 0)
            return false;
    }
    return true;
}

xrad_status scene_find_buried(const xrad_scene *scene, double time, double tol,
                              uint8_t *buried, uint32_t *count, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    *count = 0;
    for (uint32_t e = 0; e < scene->element_count; e++)
        buried[e] = 0;
    vec3 *corners = malloc((ns ? ns : 1) * sizeof(vec3[4]));
    vec3 *normals = malloc((ns ? ns : 1) * sizeof(vec3));
    if (!corners || !normals) {
        free(corners);
        free(normals);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory finding buried elements",
                         scene->path);
    }
    for (uint32_t s = 0; s < ns; s++)
        scene_surface_world(scene, s, time, &corners[4 * s], &normals[s]);
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
            bool coplanar = true;
            for (int k = 0; k < 4 && coplanar; k++)
                coplanar = fabs(v3_dot(v3_sub(corners[4 * c + k], pr), nr)) <= tol;
            if (!coplanar)
                continue;
            for (uint32_t k = 0; k < sr->nu * sr->nv; k++) {
                uint32_t e = sr->first_element + k;
                vec3 x = xf_point(&pose, scene_element_centroid(sr, &scene->elements[e]));
                uint8_t by = scene->objects[scene->surfaces[c].object].dynamic ? 2 : 1;
                if ((!buried[e] || by < buried[e]) && inside_quad(&corners[4 * c], normals[c], x)) {
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
