/* Surfaces and elements: quad validation, element sampling and areas
 * (thesis 4.1; scene.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "scene/scene_texture.h"

/* Relative tolerance below which a corner or an area counts as degenerate. */
#define DEGENERATE_EPS 1e-9
/* Vertices farther than this fraction of the longest diagonal from their
 * best-fit plane are rejected rather than projected. */
#define PLANAR_TOLERANCE 0.01

double scene_samples_along(double len, double density)
{
    double n = ceil(len * density * (1.0 - 1e-9)) + 1.0;
    return n < 2.0 ? 2.0 : n;
}

void scene_quad_edge_lengths(const surface *s, double *lu, double *lv)
{
    *lu = fmax(v3_len(v3_sub(s->p[1], s->p[0])), v3_len(v3_sub(s->p[2], s->p[3])));
    *lv = fmax(v3_len(v3_sub(s->p[3], s->p[0])), v3_len(v3_sub(s->p[2], s->p[1])));
}

bool scene_quad_setup(surface *s, const vec3 in[4], char *why, size_t why_len)
{
    vec3 p[4];
    vec3 centroid = v3(0, 0, 0);
    for (int k = 0; k < 4; k++) {
        p[k] = in[k];
        centroid = v3_add(centroid, v3_scale(p[k], 0.25));
    }
    double diag = fmax(v3_len(v3_sub(p[2], p[0])), v3_len(v3_sub(p[3], p[1])));
    if (!isfinite(diag)) {
        snprintf(why, why_len, "coordinates too large");
        return false;
    }
    /* Newell's normal, relative to the centroid for precision: twice the
     * vector area of the polygon, exact for planar polygons and the
     * least-squares plane orientation for slightly warped ones. */
    vec3 q[4], newell = v3(0, 0, 0);
    for (int k = 0; k < 4; k++)
        q[k] = v3_sub(p[k], centroid);
    for (int k = 0; k < 4; k++)
        newell = v3_add(newell, v3_cross(q[k], q[(k + 1) % 4]));
    double nl = v3_len(newell);
    if (!(diag > 0) || !(nl > DEGENERATE_EPS * diag * diag)) {
        snprintf(why, why_len, "degenerate: zero area (coincident or collinear vertices)");
        return false;
    }
    vec3 n = v3_scale(newell, 1.0 / nl);

    double dist[4], max_dist = 0;
    int worst = 0;
    for (int k = 0; k < 4; k++) {
        dist[k] = v3_dot(n, q[k]);
        if (fabs(dist[k]) > max_dist) {
            max_dist = fabs(dist[k]);
            worst = k;
        }
    }
    if (max_dist > PLANAR_TOLERANCE * diag) {
        snprintf(why, why_len,
                 "vertices not coplanar: vertex %d is %.6g m from the best-fit plane, more than "
                 "1%% of the longest diagonal (%.6g m)",
                 worst, max_dist, diag);
        return false;
    }
    s->planarise_offset = 0;
    memset(s->planarise_dist, 0, sizeof(s->planarise_dist));
    /* Rounding noise (relative to the size and the distance from the
     * origin) is not a warp worth reporting. */
    if (max_dist > 1e-9 * (diag + v3_len(centroid))) {
        for (int k = 0; k < 4; k++)
            p[k] = v3_mad(p[k], n, -dist[k]);
        s->planarise_offset = max_dist;
        memcpy(s->planarise_dist, dist, sizeof(dist));
    }

    for (int k = 0; k < 4; k++) {
        vec3 e1 = v3_sub(p[(k + 1) % 4], p[k]);
        vec3 e2 = v3_sub(p[(k + 2) % 4], p[(k + 1) % 4]);
        double scale = v3_len(e1) * v3_len(e2);
        double turn = v3_dot(n, v3_cross(e1, e2));
        if (!(scale > 0) || fabs(turn) <= DEGENERATE_EPS * scale) {
            snprintf(why, why_len, "degenerate: vertices %d, %d, %d coincide or are collinear",
                     k, (k + 1) % 4, (k + 2) % 4);
            return false;
        }
        if (turn < 0) {
            snprintf(why, why_len, "not convex (or self-intersecting) at vertex %d", (k + 1) % 4);
            return false;
        }
    }

    for (int k = 0; k < 4; k++)
        s->p[k] = p[k];
    s->normal = n;
    /* A planar quad's area is half the cross product of its diagonals. */
    s->area = 0.5 * v3_len(v3_cross(v3_sub(p[2], p[0]), v3_sub(p[3], p[1])));
    if (!isfinite(s->area) || !(s->area > 0)) {
        snprintf(why, why_len, "degenerate: zero area");
        return false;
    }
    return true;
}

bool scene_triangle_setup(surface *s, const vec3 in[3], char *why, size_t why_len)
{
    double len[3];
    int base = 0;
    for (int k = 0; k < 3; k++) {
        len[k] = v3_len(v3_sub(in[(k + 1) % 3], in[k]));
        if (!isfinite(len[k])) {
            snprintf(why, why_len, "coordinates too large");
            return false;
        }
        if (len[k] > len[base])
            base = k;
    }
    /* The longest edge is the base: the apex row is then as short as it
     * gets, and the cyclic order (the front side) is kept. */
    vec3 p0 = in[base], p1 = in[(base + 1) % 3], apex = in[(base + 2) % 3];
    vec3 n = v3_cross(v3_sub(p1, p0), v3_sub(apex, p0));
    double nl = v3_len(n);
    if (!(len[base] > 0) || !(nl > DEGENERATE_EPS * len[base] * len[base])) {
        snprintf(why, why_len, "degenerate: zero area (coincident or collinear vertices)");
        return false;
    }
    s->p[0] = p0;
    s->p[1] = p1;
    s->p[2] = apex;
    s->p[3] = apex;
    s->normal = v3_scale(n, 1.0 / nl);
    s->area = 0.5 * nl;
    s->planarise_offset = 0;
    memset(s->planarise_dist, 0, sizeof(s->planarise_dist));
    s->triangle = true;
    return true;
}

double scene_surface_jacobian(const surface *sf, double s, double t)
{
    vec3 ds = v3_lerp(v3_sub(sf->p[1], sf->p[0]), v3_sub(sf->p[2], sf->p[3]), t);
    vec3 dt = v3_lerp(v3_sub(sf->p[3], sf->p[0]), v3_sub(sf->p[2], sf->p[1]), s);
    return v3_dot(sf->normal, v3_cross(ds, dt));
}

void scene_param_range(uint32_t i0, uint32_t i1, uint32_t n, double *lo, double *hi)
{
    if (n < 2) {
        *lo = 0.0;
        *hi = 1.0;
        return;
    }
    double h = 1.0 / (n - 1);
    *lo = fmax(0.0, (i0 - 0.5) * h);
    *hi = fmin(1.0, (i1 + 0.5) * h);
}

void scene_cell_centre(const surface *sf, uint32_t i, uint32_t j, double *s, double *t)
{
    double s0, s1, t0, t1;
    scene_param_range(i, i, sf->nu, &s0, &s1);
    scene_param_range(j, j, sf->nv, &t0, &t1);
    *s = 0.5 * (s0 + s1);
    /* A lone row of a triangle is the whole triangle: its Jacobian is
     * proportional to 1 - t, so its centroid lies at t = 1/3. */
    *t = sf->triangle && sf->nv < 2 ? 1.0 / 3.0 : 0.5 * (t0 + t1);
}

vec3 scene_element_centroid(const surface *s, const element *e)
{
    double u, v;
    scene_cell_centre(s, e->i, e->j, &u, &v);
    return surface_point(s, u, v);
}

/* Sample parameter of index i of n, corners pulled inward along the
 * diagonal by SCENE_CORNER_OFFSET of a spacing (thesis 4.1). */
static double sample_param(uint32_t i, uint32_t n, bool corner)
{
    double h = 1.0 / (n - 1);
    if (!corner)
        return i * h;
    return i == 0 ? SCENE_CORNER_OFFSET * h : 1.0 - SCENE_CORNER_OFFSET * h;
}

static void fill_surface_elements(const xrad_scene *scene, uint32_t si)
{
    const surface *sf = &scene->surfaces[si];
    for (uint32_t j = 0; j < sf->nv; j++) {
        double t0, t1;
        scene_param_range(j, j, sf->nv, &t0, &t1);
        bool edge_j = j == 0 || j == sf->nv - 1;
        for (uint32_t i = 0; i < sf->nu; i++) {
            double s0, s1;
            scene_param_range(i, i, sf->nu, &s0, &s1);
            bool corner = edge_j && (i == 0 || i == sf->nu - 1);
            element *e = &scene->elements[sf->first_element + j * sf->nu + i];
            e->i = (uint16_t)i;
            e->j = (uint16_t)j;
            /* A tiny triangle's one element is sampled where it is
             * evaluated, at its centroid. */
            e->pos = sf->nu < 2 ? scene_element_centroid(sf, e)
                                : surface_point(sf, sample_param(i, sf->nu, corner),
                                                sample_param(j, sf->nv, corner));
            /* The Jacobian is bilinear on a planar quad, so its value at the
             * clipped cell's midpoint times the cell's size is the exact
             * integral. */
            e->area = scene_surface_jacobian(sf, 0.5 * (s0 + s1), 0.5 * (t0 + t1)) *
                      (s1 - s0) * (t1 - t0);
            e->surface = si;
            e->texel_x = sf->tile_x + i;
            e->texel_y = sf->tile_y + j;
        }
    }
}

bool scene_split_fits(const surface *sf, uint64_t elements, uint32_t *nu, uint32_t *nv)
{
    *nu = scene_texture_refined(sf->nu);
    *nv = scene_texture_refined(sf->nv);
    uint64_t more = (uint64_t)*nu * *nv - (uint64_t)sf->nu * sf->nv;
    return *nu <= SCENE_MAX_SAMPLES && *nv <= SCENE_MAX_SAMPLES &&
           elements + more <= SCENE_MAX_ELEMENTS;
}

void scene_split_take(surface *sf, uint32_t nu, uint32_t nv, uint64_t *elements)
{
    *elements += (uint64_t)nu * nv - (uint64_t)sf->nu * sf->nv;
    sf->nu = nu;
    sf->nv = nv;
}

xrad_status scene_build_elements(xrad_scene *scene, xrad_error *err)
{
    uint64_t total = 0;
    for (uint32_t i = 0; i < scene->surface_count; i++) {
        scene->surfaces[i].first_element = (uint32_t)total;
        total += (uint64_t)scene->surfaces[i].nu * scene->surfaces[i].nv;
    }
    /* The parser enforces the limit surface by surface; this is the last
     * line of defence before the allocation. */
    if (total > SCENE_MAX_ELEMENTS)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %llu elements, more than %u", scene->path,
                         (unsigned long long)total, SCENE_MAX_ELEMENTS);
    for (uint32_t o = 0; o < scene->object_count; o++) {
        object *ob = &scene->objects[o];
        ob->first_element = scene->surfaces[ob->first_surface].first_element;
        ob->element_count = 0;
        for (uint32_t k = 0; k < ob->surface_count; k++) {
            const surface *sf = &scene->surfaces[ob->first_surface + k];
            ob->element_count += sf->nu * sf->nv;
        }
    }
    xrad_status st = scene_pack_atlas(scene, err);
    if (st)
        return st;
    scene->element_count = (uint32_t)total;
    scene->elements = calloc(total, sizeof(element));
    if (!scene->elements)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %llu elements",
                         scene->path, (unsigned long long)total);
    for (uint32_t i = 0; i < scene->surface_count; i++)
        fill_surface_elements(scene, i);
    return XRAD_OK;
}

void xrad_scene_get_info(const xrad_scene *scene, xrad_scene_info *info)
{
    memset(info, 0, sizeof(*info));
    if (!scene)
        return;
    info->objects = scene->object_count;
    info->surfaces = scene->surface_count;
    info->materials = scene->material_count;
    info->elements = scene->element_count;
    info->atlas_width = scene->atlas_width;
    info->atlas_height = scene->atlas_height;
    size_t bytes = sizeof(*scene) + scene->material_count * sizeof(material) +
                   scene->object_count * sizeof(object) +
                   scene->surface_count * sizeof(surface) +
                   (size_t)scene->element_count * sizeof(element);
    for (uint32_t o = 0; o < scene->object_count; o++) {
        const object *ob = &scene->objects[o];
        if (ob->dynamic) {
            info->dynamic_objects++;
            info->dynamic_elements += ob->element_count;
        } else {
            info->static_elements += ob->element_count;
        }
        bytes += ob->anim.keyframe_count * sizeof(keyframe);
    }
    for (uint32_t i = 0; i < scene->surface_count; i++) {
        const surface *sf = &scene->surfaces[i];
        info->area += sf->area;
        info->triangles += sf->triangle;
        if (sf->planarise_offset > 0) {
            info->planarised++;
            info->planarise_max_offset = fmax(info->planarise_max_offset, sf->planarise_offset);
        }
    }
    info->skipped_triangles = scene->skipped_triangles;
    info->meshes = scene->mesh_count;
    info->albedo_maps = scene->albedo_maps;
    info->normal_maps = scene->normal_maps;
    info->normal_mapped_elements = scene->normal_mapped_elements;
    info->normal_refined_surfaces = scene->normal_refined_surfaces;
    info->adaptive_refined_surfaces = scene->adaptive_refined_surfaces;
    info->adaptive_partial_surfaces = scene->adaptive_partial_surfaces;
    info->mapped_elements = scene->mapped_elements;
    info->luminaires = scene->luminaire_count;
    if (scene->element_albedo)
        bytes += (size_t)scene->element_count * sizeof(vec3);
    if (scene->element_normal)
        bytes += (size_t)scene->element_count * sizeof(vec3);
    bytes += scene->mesh_count * sizeof(scene_mesh);
    for (uint32_t k = 0; k < scene->mesh_count; k++)
        bytes += scene->meshes[k].triangle_count * sizeof(mesh_triangle);
    info->cpu_bytes = bytes;
}
