/* Clusters of hemicube vertices (hemicube_clusters.h). */
#include "solvers/hemicube_clusters.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

/* Cones wider than this are no use (nothing faces away from every origin
 * outside a half-space) and are left out. */
#define MAX_CONE_ANGLE 1.4 /* rad, 80 degrees */

typedef struct keyed {
    uint64_t key;
    uint32_t surface;
} keyed;

static int by_key(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    return x->key < y->key ? -1 : x->key > y->key ? 1 : (x->surface > y->surface) - (x->surface < y->surface);
}

/* Spreads the low 10 bits of v to every third bit. */
static uint64_t spread3(uint32_t v)
{
    uint64_t x = v & 0x3ff;
    x = (x | x << 16) & 0x30000ff;
    x = (x | x << 8) & 0x300f00f;
    x = (x | x << 4) & 0x30c30c3;
    x = (x | x << 2) & 0x9249249;
    return x;
}

static vec3 centroid(const surface *sf)
{
    int n = sf->triangle ? 3 : 4;
    vec3 c = v3(0, 0, 0);
    for (int k = 0; k < n; k++)
        c = v3_add(c, sf->p[k]);
    return v3_scale(c, 1.0 / n);
}

void hemicube_clusters_free(hemicube_clusters *c)
{
    free(c->order);
    free(c->first_index);
    free(c->indices);
    free(c->corners);
    free(c->triangle_surface);
    free(c->vertex_source);
    free(c->vertex_triangle);
    free(c->start);
    free(c->first);
    free(c->closed);
    memset(c, 0, sizeof(*c));
}

/* The vertices and the indices. Corners at one model position are one
 * vertex within a cluster, numbered in drawing order (open addressing
 * over the corners; sharing within an object instead measured the same
 * on lavapipe, and a cluster's vertices are then a run of their own).
 * Then each
 * triangle, in drawing order, takes one of its vertices that no triangle
 * has taken as its provoking vertex and names it first (a rotation keeps
 * the winding); where all three are taken, a copy of its first corner is
 * made for it. Closed meshes have about twice as many triangles as
 * vertices, so about half the triangles get a copy: one vertex a
 * triangle in all, against three unindexed. */
#define NO_TRIANGLE UINT32_MAX
#define NO_CLUSTER UINT32_MAX

static xrad_status share_vertices(const xrad_scene *scene, hemicube_clusters *c, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    size_t cap = 16, most = 6 * (size_t)ns + 1; /* 4 corners and 2 copies a surface */
    while (cap < 8 * (size_t)ns)
        cap *= 2;
    uint32_t *slot = malloc(cap * sizeof *slot);      /* vertex + 1, 0: empty */
    uint32_t *cluster = malloc(most * sizeof *cluster); /* vertex -> its cluster */
    c->vertex_source = malloc(most * sizeof *c->vertex_source);
    c->vertex_triangle = malloc(most * sizeof *c->vertex_triangle);
    if (!slot || !cluster || !c->vertex_source || !c->vertex_triangle) {
        free(slot);
        free(cluster);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube vertices: out of host memory");
    }
    memset(slot, 0, cap * sizeof *slot);
    uint32_t count = 0;
    for (uint32_t q = 0; q < c->count; q++) {
        for (uint32_t i = c->start[q]; i < c->start[q + 1]; i++) {
            uint32_t s = c->order[i];
            const surface *sf = &scene->surfaces[s];
            uint32_t corner_vertex[4];
            for (int k = 0; k < 4; k++) {
                vec3 p = sf->p[k];
                uint64_t h = q * 0x9e3779b97f4a7c15ull;
                double xyz[3] = {p.x + 0.0, p.y + 0.0, p.z + 0.0}; /* -0 and 0 alike */
                for (int a = 0; a < 3; a++) {
                    uint64_t b;
                    memcpy(&b, &xyz[a], sizeof b);
                    h = (h ^ b) * 0x100000001b3ull;
                    h ^= h >> 29;
                }
                size_t at = h & (cap - 1);
                for (;; at = (at + 1) & (cap - 1)) {
                    if (!slot[at]) {
                        c->vertex_source[count] = 4 * s + (uint32_t)k;
                        c->vertex_triangle[count] = NO_TRIANGLE;
                        cluster[count] = q;
                        slot[at] = ++count;
                        break;
                    }
                    uint32_t v = slot[at] - 1, src = c->vertex_source[v];
                    vec3 o = scene->surfaces[src / 4].p[src % 4];
                    if (cluster[v] == q && o.x == p.x && o.y == p.y && o.z == p.z)
                        break;
                }
                corner_vertex[k] = slot[at] - 1;
            }
            for (uint32_t k = 0; k < hemicube_surface_triangles(sf); k++) {
                uint32_t t = c->first_index[s] / 3 + k, v[3];
                int first = -1;
                for (int j = 0; j < 3; j++) {
                    v[j] = corner_vertex[hemicube_triangle_corner(k, j)];
                    if (first < 0 && c->vertex_triangle[v[j]] == NO_TRIANGLE)
                        first = j;
                }
                if (first < 0) {
                    first = 0;
                    c->vertex_source[count] = 4 * s + (uint32_t)hemicube_triangle_corner(k, 0);
                    cluster[count] = NO_CLUSTER; /* found by no corner */
                    v[0] = count++;
                }
                c->vertex_triangle[v[first]] = t;
                c->triangle_surface[t] = s;
                for (int j = 0; j < 3; j++) {
                    int r = (first + j) % 3;
                    c->indices[3 * t + j] = v[r];
                    c->corners[3 * t + j] = (uint8_t)hemicube_triangle_corner(k, r);
                }
            }
        }
    }
    c->vertex_count = count;
    free(slot);
    free(cluster);
    return XRAD_OK;
}

xrad_status hemicube_clusters_build(const xrad_scene *scene, hemicube_clusters *out,
                                    xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    uint32_t ns = scene->surface_count, no = scene->object_count;
    size_t sa = ns ? ns : 1;
    keyed *keys = malloc(sa * sizeof *keys);
    out->order = malloc(sa * sizeof *out->order);
    out->first_index = malloc(sa * sizeof *out->first_index);
    out->indices = malloc(6 * sa * sizeof *out->indices);
    out->corners = malloc(6 * sa);
    out->triangle_surface = malloc(2 * sa * sizeof *out->triangle_surface);
    out->start = malloc((sa + 1) * sizeof *out->start);
    out->first = malloc((sa + 1) * sizeof *out->first);
    out->closed = calloc(no ? no : 1, 1);
    vec3 *lo = malloc((no ? no : 1) * sizeof *lo), *hi = malloc((no ? no : 1) * sizeof *hi);
    if (!keys || !out->order || !out->first_index || !out->indices || !out->corners ||
        !out->triangle_surface || !out->start || !out->first || !out->closed || !lo || !hi) {
        free(keys);
        free(lo);
        free(hi);
        hemicube_clusters_free(out);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube clusters: out of host memory");
    }
    for (uint32_t o = 0; o < no; o++) {
        lo[o] = v3(INFINITY, INFINITY, INFINITY);
        hi[o] = v3(-INFINITY, -INFINITY, -INFINITY);
    }
    for (uint32_t s = 0; s < ns; s++) {
        const surface *sf = &scene->surfaces[s];
        for (int k = 0; k < 4; k++) {
            vec3 p = sf->p[k];
            lo[sf->object] = v3(fmin(lo[sf->object].x, p.x), fmin(lo[sf->object].y, p.y),
                                fmin(lo[sf->object].z, p.z));
            hi[sf->object] = v3(fmax(hi[sf->object].x, p.x), fmax(hi[sf->object].y, p.y),
                                fmax(hi[sf->object].z, p.z));
        }
    }
    /* Key: static before dynamic, then the object, then the Morton code
     * of the centre in the object's box (10 bits an axis). */
    for (uint32_t s = 0; s < ns; s++) {
        const surface *sf = &scene->surfaces[s];
        uint32_t o = sf->object;
        vec3 c = centroid(sf), size = v3_sub(hi[o], lo[o]);
        double q[3] = {size.x > 0 ? (c.x - lo[o].x) / size.x : 0,
                       size.y > 0 ? (c.y - lo[o].y) / size.y : 0,
                       size.z > 0 ? (c.z - lo[o].z) / size.z : 0};
        uint64_t morton = 0;
        for (int a = 0; a < 3; a++)
            morton |= spread3((uint32_t)fmin(1023.0, fmax(0.0, q[a] * 1024))) << a;
        uint64_t dynamic = scene->objects[o].dynamic ? 1 : 0;
        keys[s] = (keyed){dynamic << 62 | (uint64_t)o << 30 | morton, s};
    }
    free(lo);
    free(hi);
    qsort(keys, ns, sizeof *keys, by_key);
    uint32_t index = 0, triangles = 0;
    for (uint32_t k = 0; k < ns; k++) {
        uint32_t s = keys[k].surface;
        const surface *sf = &scene->surfaces[s];
        out->order[k] = s;
        out->first_index[s] = index;
        index += 3 * hemicube_surface_triangles(sf);
        if (!scene->objects[sf->object].dynamic)
            out->static_index_count = index;
        /* A new cluster at a new object or a full one. */
        uint32_t tris = hemicube_surface_triangles(sf);
        bool new_object = k == 0 || scene->surfaces[out->order[k - 1]].object != sf->object;
        if (new_object || triangles + tris > HEMICUBE_CLUSTER_TRIANGLES) {
            out->first[out->count] = out->first_index[s];
            out->start[out->count++] = k;
            triangles = 0;
            if (!scene->objects[sf->object].dynamic)
                out->static_count = out->count;
        }
        triangles += tris;
    }
    out->start[out->count] = ns;
    out->first[out->count] = index;
    out->index_count = index;
    free(keys);
    xrad_status st = share_vertices(scene, out, err);
    if (st) {
        hemicube_clusters_free(out);
        return st;
    }
    /* Closed objects: every surface a face of a closed mesh facing out
     * (scene.h surface.closed). */
    for (uint32_t o = 0; o < no; o++)
        out->closed[o] = 1;
    for (uint32_t s = 0; s < ns; s++)
        out->closed[scene->surfaces[s].object] &= scene->surfaces[s].closed ? 1 : 0;
    for (uint32_t o = 0; o < no; o++)
        out->closed[o] &= scene->objects[o].surface_count > 0 ? 1 : 0;
    return XRAD_OK;
}

void hemicube_clusters_bounds(const hemicube_clusters *c, const xrad_scene *scene,
                              const struct gpu_surface *surfaces, struct gpu_cluster *out)
{
    for (uint32_t k = 0; k < c->count; k++) {
        vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
        vec3 axis = v3(0, 0, 0);
        uint32_t triangles = 0;
        for (uint32_t i = c->start[k]; i < c->start[k + 1]; i++) {
            uint32_t s = c->order[i];
            const struct gpu_surface *g = &surfaces[s];
            for (int q = 0; q < 4; q++) {
                vec3 p = v3(g->corner[q].x, g->corner[q].y, g->corner[q].z);
                lo = v3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
                hi = v3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
            }
            axis = v3_mad(axis, v3(g->normal_area.x, g->normal_area.y, g->normal_area.z),
                          g->normal_area.w);
            triangles += hemicube_surface_triangles(&scene->surfaces[s]);
        }
        uint32_t first = c->order[c->start[k]];
        uint32_t obj = scene->surfaces[first].object;
        double theta = -1;
        if (c->closed[obj] && v3_len(axis) > 0) {
            axis = v3_norm(axis);
            theta = 0;
            for (uint32_t i = c->start[k]; i < c->start[k + 1]; i++) {
                const struct gpu_surface *g = &surfaces[c->order[i]];
                double d = v3_dot(axis, v3(g->normal_area.x, g->normal_area.y, g->normal_area.z));
                theta = fmax(theta, acos(fmin(1.0, fmax(-1.0, d))));
            }
            if (theta > MAX_CONE_ANGLE)
                theta = -1;
        }
        vec3 centre = v3_scale(v3_add(lo, hi), 0.5), half = v3_scale(v3_sub(hi, lo), 0.5);
        out[k] = (struct gpu_cluster){
            .center = {(float)centre.x, (float)centre.y, (float)centre.z, (float)v3_len(half)},
            .half_size = {(float)half.x, (float)half.y, (float)half.z, (float)theta},
            .cone_axis = {(float)axis.x, (float)axis.y, (float)axis.z, 0},
            .first_index = c->first_index[first],
            .index_count = 3 * triangles,
        };
    }
    /* Each closed object's box, over its clusters. */
    for (uint32_t k = 0; k < c->count;) {
        uint32_t obj = scene->surfaces[c->order[c->start[k]]].object, n = 0;
        vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
        while (k + n < c->count &&
               scene->surfaces[c->order[c->start[k + n]]].object == obj) {
            const struct gpu_cluster *g = &out[k + n];
            vec3 m = v3(g->center.x, g->center.y, g->center.z);
            vec3 h = v3(g->half_size.x, g->half_size.y, g->half_size.z);
            lo = v3(fmin(lo.x, m.x - h.x), fmin(lo.y, m.y - h.y), fmin(lo.z, m.z - h.z));
            hi = v3(fmax(hi.x, m.x + h.x), fmax(hi.y, m.y + h.y), fmax(hi.z, m.z + h.z));
            n++;
        }
        for (uint32_t i = k; i < k + n; i++) {
            out[i].object_lo = (vec4){(float)lo.x, (float)lo.y, (float)lo.z, 0};
            out[i].object_hi = (vec4){(float)hi.x, (float)hi.y, (float)hi.z, 0};
        }
        k += n;
    }
}
