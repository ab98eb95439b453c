/* Surface parametrisation and object poses (scenes/README.md "Poses"). */
#include <math.h>

#include "scene/scene.h"
#include "scene/scene_internal.h"

vec3 surface_point(const surface *s, double u, double v)
{
    vec3 a = v3_lerp(s->p[0], s->p[1], u);
    vec3 b = v3_lerp(s->p[3], s->p[2], u);
    return v3_lerp(a, b, v);
}

/* Piecewise linear keyframe translation at time t. Looping repeats with
 * the period of the last key's time; within a period, the stretch before
 * the first key runs from the last key's value (time 0 of the period is the
 * end of the previous one) to the first key's. */
static vec3 keyframe_translation(const animation *a, double t)
{
    const keyframe *k = a->keyframes;
    uint32_t n = a->keyframe_count;
    double period = k[n - 1].time;
    if (a->loop && period > 0) {
        t = fmod(t, period);
        if (t < 0)
            t += period;
        if (t < k[0].time)
            return v3_lerp(k[n - 1].translation, k[0].translation, t / k[0].time);
    }
    if (!(t > k[0].time))
        return k[0].translation;
    if (t >= k[n - 1].time)
        return k[n - 1].translation;
    /* Binary search for the segment k[lo].time <= t < k[lo + 1].time. */
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (k[mid].time <= t)
            lo = mid;
        else
            hi = mid;
    }
    double f = (t - k[lo].time) / (k[hi].time - k[lo].time);
    return v3_lerp(k[lo].translation, k[hi].translation, f);
}

xform scene_object_pose(const xrad_scene *scene, uint32_t object_index, double t)
{
    const object *o = &scene->objects[object_index];
    xform pose = o->base;
    if (!o->dynamic)
        return pose;
    const animation *a = &o->anim;
    if (a->rotates) {
        /* x -> pivot + R (x - pivot), in object space, before the rest pose. */
        mat3 r = m3_rotation(a->axis, a->rate * t);
        xform spin = {r, v3_sub(a->pivot, m3_apply(&r, a->pivot))};
        pose = xf_compose(&o->base, &spin);
    }
    if (a->keyframe_count)
        pose.t = v3_add(pose.t, keyframe_translation(a, t));
    return pose;
}

void scene_surface_world(const xrad_scene *scene, uint32_t surface_index, double t,
                         vec3 corners[4], vec3 *normal)
{
    const surface *s = &scene->surfaces[surface_index];
    xform pose = scene_object_pose(scene, s->object, t);
    for (int k = 0; k < 4; k++)
        corners[k] = xf_point(&pose, s->p[k]);
    if (normal)
        *normal = v3_norm(xf_dir(&pose, s->normal));
}

void scene_bounds(const xrad_scene *scene, double t, vec3 *lo, vec3 *hi)
{
    *lo = v3(INFINITY, INFINITY, INFINITY);
    *hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t i = 0; i < scene->surface_count; i++) {
        vec3 c[4];
        scene_surface_world(scene, i, t, c, NULL);
        for (int k = 0; k < 4; k++) {
            *lo = v3(fmin(lo->x, c[k].x), fmin(lo->y, c[k].y), fmin(lo->z, c[k].z));
            *hi = v3(fmax(hi->x, c[k].x), fmax(hi->y, c[k].y), fmax(hi->z, c[k].z));
        }
    }
}
