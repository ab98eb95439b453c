/* Surface parametrisation and object poses (scenes/README.md "Poses"). */
#include <math.h>
#include <string.h>

#include "core/error.h"
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
    if (o->posed)
        return o->pose;
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
    pose.t = v3_add(pose.t, o->offset);
    return pose;
}

void scene_object_box(const xrad_scene *scene, uint32_t object_index, vec3 *lo, vec3 *hi)
{
    const object *ob = &scene->objects[object_index];
    *lo = v3(INFINITY, INFINITY, INFINITY);
    *hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t s = ob->first_surface; s < ob->first_surface + ob->surface_count; s++)
        for (int k = 0; k < 4; k++) {
            vec3 p = scene->surfaces[s].p[k];
            *lo = v3(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
            *hi = v3(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
        }
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

xrad_status xrad_scene_get_object(const xrad_scene *scene, uint32_t index,
                                  xrad_object_info *info, xrad_error *err)
{
    memset(info, 0, sizeof(*info));
    if (!scene || index >= scene->object_count)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: object %u does not exist (%u objects)",
                         index, scene ? scene->object_count : 0);
    const object *o = &scene->objects[index];
    info->name = o->name;
    info->dynamic = o->dynamic;
    info->offset[0] = o->offset.x;
    info->offset[1] = o->offset.y;
    info->offset[2] = o->offset.z;
    return XRAD_OK;
}

xrad_status xrad_scene_set_offset(xrad_scene *scene, uint32_t index, const double offset[3],
                                  xrad_error *err)
{
    if (!scene || index >= scene->object_count)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: object %u does not exist (%u objects)",
                         index, scene ? scene->object_count : 0);
    object *o = &scene->objects[index];
    if (!o->dynamic)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: object '%s' is static; only dynamic objects may be moved",
                         scene->path, o->name);
    for (int k = 0; k < 3; k++)
        if (!(fabs(offset[k]) <= 1e9))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: object '%s': offset %g is not a finite distance within 1e9 m",
                             scene->path, o->name, offset[k]);
    o->offset = v3(offset[0], offset[1], offset[2]);
    return XRAD_OK;
}

xrad_status xrad_scene_get_surface(const xrad_scene *scene, uint32_t index,
                                   xrad_surface_info *info, xrad_error *err)
{
    memset(info, 0, sizeof(*info));
    if (!scene || index >= scene->surface_count)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: surface %u does not exist (%u surfaces)",
                         index, scene ? scene->surface_count : 0);
    const surface *s = &scene->surfaces[index];
    info->name = s->name;
    info->object = s->object;
    info->nu = s->nu;
    info->nv = s->nv;
    info->length_u = v3_len(v3_sub(s->p[1], s->p[0]));
    info->length_v = v3_len(v3_sub(s->p[3], s->p[0]));
    info->area = s->area;
    info->triangle = s->triangle;
    info->material = s->material;
    info->tile_x = s->tile_x;
    info->tile_y = s->tile_y;
    /* As the display draws it: a planarised quad's file vertices, so that
     * it meets its neighbours (scene.h). */
    for (int k = 0; k < 4; k++) {
        vec3 p = v3_mad(s->p[k], s->normal, s->planarise_dist[k]);
        info->corners[k][0] = p.x;
        info->corners[k][1] = p.y;
        info->corners[k][2] = p.z;
    }
    info->normal[0] = s->normal.x;
    info->normal[1] = s->normal.y;
    info->normal[2] = s->normal.z;
    return XRAD_OK;
}

xrad_status xrad_scene_get_mesh(const xrad_scene *scene, uint32_t index, xrad_mesh_info *info,
                                xrad_error *err)
{
    memset(info, 0, sizeof(*info));
    if (!scene || index >= scene->mesh_count)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: field 'index': mesh %u does not exist (%u meshes)",
                         scene ? scene->path : "scene", index, scene ? scene->mesh_count : 0);
    const scene_mesh *m = &scene->meshes[index];
    info->name = m->name;
    info->object = m->object;
    info->triangle_count = m->triangle_count;
    info->skipped_triangles = m->skipped_triangles;
    return XRAD_OK;
}

xrad_status xrad_scene_get_mesh_corners(const xrad_scene *scene, uint32_t mesh,
                                        xrad_mesh_corner *corners, uint32_t corner_count,
                                        xrad_error *err)
{
    if (!scene || mesh >= scene->mesh_count)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: field 'mesh': mesh %u does not exist (%u meshes)",
                         scene ? scene->path : "scene", mesh, scene ? scene->mesh_count : 0);
    const scene_mesh *m = &scene->meshes[mesh];
    if (corner_count != 3ull * m->triangle_count)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: mesh '%s': field 'corner_count': must be 3 x %u triangles = %llu, "
                         "got %u",
                         scene->path, m->name, m->triangle_count,
                         3ull * m->triangle_count, corner_count);
    if (!corners)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: mesh '%s': field 'corners': NULL",
                         scene->path, m->name);
    /* Corner slot k of a surface: (s, t) = (0, 0), (1, 0), (1, 1), (0, 1)
     * (xrad.h, before xrad_surface_info). */
    static const float st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const mesh_triangle *mt = &m->triangles[t];
        bool triangle = mt->surface != UINT32_MAX && scene->surfaces[mt->surface].triangle;
        for (int k = 0; k < 3; k++) {
            xrad_mesh_corner *c = &corners[3 * t + k];
            *c = (xrad_mesh_corner){.surface = mt->surface};
            if (mt->surface == UINT32_MAX)
                continue;
            uint8_t slot = mt->slot[k];
            if (triangle && slot == 2) {
                c->a[1] = 1; /* the apex: w = 0 */
                continue;
            }
            c->a[0] = st[slot][0];
            c->a[1] = st[slot][1];
            c->a[2] = 1;
        }
    }
    return XRAD_OK;
}

xrad_status scene_check_pose(const xrad_scene *scene, uint32_t index, const double matrix[16],
                             xform *out, xrad_error *err)
{
    if (!scene || index >= scene->object_count)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: object %u does not exist (%u objects)",
                         index, scene ? scene->object_count : 0);
    const object *o = &scene->objects[index];
    if (!o->dynamic)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: object '%s' is static; only dynamic objects may be moved",
                         scene->path, o->name);
    if (!matrix)
        return XRAD_OK;
    xform x;
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            x.r.m[r][c] = matrix[c * 4 + r];
    x.t = v3(matrix[12], matrix[13], matrix[14]);
    /* Rigid: orthonormal columns, determinant +1, no projective row; a
     * scaled or sheared object would change its elements' areas. */
    double worst = 0;
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double dot = 0;
            for (int r = 0; r < 3; r++)
                dot += x.r.m[r][a] * x.r.m[r][b];
            worst = fmax(worst, fabs(dot - (a == b)));
        }
    vec3 c0 = v3(x.r.m[0][0], x.r.m[1][0], x.r.m[2][0]);
    vec3 c1 = v3(x.r.m[0][1], x.r.m[1][1], x.r.m[2][1]);
    vec3 c2 = v3(x.r.m[0][2], x.r.m[1][2], x.r.m[2][2]);
    double det = v3_dot(v3_cross(c0, c1), c2);
    bool finite = true;
    for (int k = 0; k < 16; k++)
        finite = finite && fabs(matrix[k]) <= 1e9;
    if (!finite || !(worst < 1e-6) || !(det > 0) || matrix[3] != 0 || matrix[7] != 0 ||
        matrix[11] != 0 || matrix[15] != 1)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: object '%s': the pose is not a rigid transform (rotation off "
                         "orthonormal by %.3g, determinant %.6g, bottom row %g %g %g %g)",
                         scene->path, o->name, worst, det, matrix[3], matrix[7], matrix[11],
                         matrix[15]);
    if (out)
        *out = x;
    return XRAD_OK;
}

xrad_status xrad_scene_set_pose(xrad_scene *scene, uint32_t index, const double matrix[16],
                                xrad_error *err)
{
    xform x;
    xrad_status st = scene_check_pose(scene, index, matrix, &x, err);
    if (st)
        return st;
    scene->objects[index].posed = matrix != NULL;
    if (matrix)
        scene->objects[index].pose = x;
    return XRAD_OK;
}

xrad_status scene_check_emission(const xrad_scene *scene, uint32_t index,
                                 const double emission[3], xrad_error *err)
{
    if (!scene || index >= scene->material_count)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "scene: material %u does not exist (%u materials)", index,
                         scene ? scene->material_count : 0);
    for (int c = 0; c < 3; c++)
        if (!(emission[c] >= 0 && emission[c] <= 1e12))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: material '%s': emission %g is not in [0, 1e12] W/m^2",
                             scene->path, scene->materials[index].name, emission[c]);
    return XRAD_OK;
}

xrad_status xrad_scene_set_emission(xrad_scene *scene, uint32_t index, const double emission[3],
                                    xrad_error *err)
{
    xrad_status st = scene_check_emission(scene, index, emission, err);
    if (!st)
        scene->materials[index].emission = v3(emission[0], emission[1], emission[2]);
    return st;
}

void xrad_scene_get_bounds(const xrad_scene *scene, double time, double lo[3], double hi[3])
{
    vec3 l, h;
    scene_bounds(scene, time, &l, &h);
    lo[0] = l.x, lo[1] = l.y, lo[2] = l.z;
    hi[0] = h.x, hi[1] = h.y, hi[2] = h.z;
}

void xrad_scene_get_camera(const xrad_scene *scene, xrad_camera_desc *out)
{
    const camera *c = &scene->cam;
    *out = (xrad_camera_desc){
        .position = {c->position.x, c->position.y, c->position.z},
        .look_at = {c->look_at.x, c->look_at.y, c->look_at.z},
        .up = {c->up.x, c->up.y, c->up.z},
        .fov_degrees = c->fov_y * 180.0 / M_PI,
        .width = c->width,
        .height = c->height,
    };
}

xrad_status xrad_scene_get_material(const xrad_scene *scene, uint32_t index,
                                    xrad_material_info *info, xrad_error *err)
{
    memset(info, 0, sizeof(*info));
    if (!scene || index >= scene->material_count)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "scene: material %u does not exist (%u materials)", index,
                         scene ? scene->material_count : 0);
    const material *m = &scene->materials[index];
    info->name = m->name;
    info->albedo[0] = m->albedo.x;
    info->albedo[1] = m->albedo.y;
    info->albedo[2] = m->albedo.z;
    info->emission[0] = m->emission.x;
    info->emission[1] = m->emission.y;
    info->emission[2] = m->emission.z;
    return XRAD_OK;
}

xrad_status xrad_scene_get_object_pose(const xrad_scene *scene, uint32_t index, double time,
                                       double matrix[16], xrad_error *err)
{
    if (!scene || index >= scene->object_count)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: object %u does not exist (%u objects)",
                         index, scene ? scene->object_count : 0);
    if (!isfinite(time))
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene: pose time is not finite");
    xform x = scene_object_pose(scene, index, time);
    const double t[3] = {x.t.x, x.t.y, x.t.z};
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++)
            matrix[c * 4 + r] = x.r.m[r][c];
        matrix[c * 4 + 3] = 0;
        matrix[12 + c] = t[c];
    }
    matrix[15] = 1;
    return XRAD_OK;
}
