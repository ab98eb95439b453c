#include "solvers/dynamic_patches.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "passes/hemicube_geometry.h"
#include "scene/scene_internal.h"

/* Light patches per side of a light as long as the scene's diameter. */
#define LIGHT_BLOCKS 16

/* Cuts every surface with a non-zero count in cx (2 per surface) into
 * cx[2s] x cx[2s + 1] blocks of its elements. */
static xrad_status build_blocks(const xrad_scene *scene, uint32_t *cx, dynamic_patches *out,
                                xrad_error *err)
{
    uint32_t n = 0;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        out->surface_patch[s] = DYNAMIC_PATCH_NONE;
        if (cx[2 * s]) {
            out->surface_patch[s] = n;
            n += cx[2 * s] * cx[2 * s + 1];
        }
    }
    if (n && !(out->patches = calloc(n, sizeof(*out->patches))))
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for patches",
                         scene->path);
    out->count = n;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        if (out->surface_patch[s] == DYNAMIC_PATCH_NONE)
            continue;
        const surface *sf = &scene->surfaces[s];
        uint32_t kx = cx[2 * s], ky = cx[2 * s + 1];
        for (uint32_t cj = 0; cj < ky; cj++) {
            for (uint32_t ci = 0; ci < kx; ci++) {
                uint32_t p = out->surface_patch[s] + cj * kx + ci;
                struct cross_patch *q = &out->patches[p];
                q->surface = s;
                q->i0 = ci * sf->nu / kx;
                q->i1 = (ci + 1) * sf->nu / kx - 1;
                q->j0 = cj * sf->nv / ky;
                q->j1 = (cj + 1) * sf->nv / ky - 1;
                q->ci = ci;
                q->cj = cj;
                q->cx = kx;
                q->cy = ky;
            }
        }
    }
    return XRAD_OK;
}

/* Blocks along a light's side of `fraction` of the scene's diameter and n
 * elements: LIGHT_BLOCKS per diameter, at least 1 and one element each, at
 * most max_patches. By size, not by element count: the lights' hemicubes
 * are memory and time that the element density must not change. */
static uint32_t light_blocks(double fraction, uint32_t n, uint32_t max_patches)
{
    double k = ceil(LIGHT_BLOCKS * fraction - 1e-9);
    uint32_t most = n < max_patches ? n : max_patches;
    return k < 1 ? 1 : k > most ? most : (uint32_t)k;
}

/* A mesh face of a dynamic object, keyed for grouping. */
typedef struct face_key {
    uint32_t object, bin;
    int32_t cell[3];
    uint32_t surface;
} face_key;

/* Cones of normals a group's faces share: the cube face of the normal's
 * largest component, cut into NORMAL_CELLS x NORMAL_CELLS by the other
 * two components over it (a cube map of directions): cells of about 25
 * degrees. A group then faces one way to within about 20 degrees, and
 * each face reads the group's gather hemicube from its own point
 * (spirv/cross_update.comp); on an 80-face ball in quadrant cones of up to
 * 55 degrees, with one value a group, the side faces were 0.87-0.93 of the
 * CPU reference's. */
#define NORMAL_CELLS 4

static uint32_t normal_bin(vec3 n)
{
    double a[3] = {n.x, n.y, n.z};
    int k = fabs(a[0]) >= fabs(a[1]) && fabs(a[0]) >= fabs(a[2]) ? 0
          : fabs(a[1]) >= fabs(a[2])                          ? 1
                                                               : 2;
    double w = fabs(a[k]);
    uint32_t cell[2];
    for (int c = 0; c < 2; c++) {
        double q = 0.5 * (a[(k + 1 + c) % 3] / w + 1) * NORMAL_CELLS; /* [0, cells] */
        cell[c] = q >= NORMAL_CELLS ? NORMAL_CELLS - 1 : q < 0 ? 0 : (uint32_t)q;
    }
    return (2 * (uint32_t)k + (a[k] < 0)) * NORMAL_CELLS * NORMAL_CELLS + cell[0] * NORMAL_CELLS +
           cell[1];
}

static int face_cmp(const void *pa, const void *pb)
{
    const face_key *a = pa, *b = pb;
    uint32_t ka[5] = {a->object, a->bin}, kb[5] = {b->object, b->bin};
    for (int k = 0; k < 3; k++) {
        ka[2 + k] = (uint32_t)a->cell[k] ^ 0x80000000u;
        kb[2 + k] = (uint32_t)b->cell[k] ^ 0x80000000u;
    }
    for (int k = 0; k < 5; k++)
        if (ka[k] != kb[k])
            return ka[k] < kb[k] ? -1 : 1;
    return a->surface < b->surface ? -1 : a->surface > b->surface;
}

static bool same_group(const face_key *a, const face_key *b)
{
    return a->object == b->object && a->bin == b->bin && a->cell[0] == b->cell[0] &&
           a->cell[1] == b->cell[1] && a->cell[2] == b->cell[2];
}

/* Object-space bounding box diagonal of object o's surfaces. */
static double object_diagonal(const xrad_scene *scene, const object *ob)
{
    vec3 lo, hi;
    scene_object_box(scene, (uint32_t)(ob - scene->objects), &lo, &hi);
    return v3_len(v3_sub(hi, lo));
}

/* An object's patch size: 1 / cross_density, or without one a quarter of
 * its diagonal (about 4 blocks a side of a cube, 96 patches: what
 * cornell-large's box has at cross_density 10.5). The default was
 * max_patches blocks a side, which on a small box of few elements made
 * every element a patch (a 0.4 m cube in a 7,831-element room: 5,995 ms a
 * cross frame against 6.3 s for a whole progressive solve). */
#define DEFAULT_PATCHES_PER_DIAGONAL 4.0

static double patch_size(const xrad_scene *scene, const object *ob)
{
    if (ob->cross_density > 0)
        return 1.0 / ob->cross_density;
    double d = object_diagonal(scene, ob);
    return d > 0 ? d / DEFAULT_PATCHES_PER_DIAGONAL : 1.0;
}

/* The mesh faces of the dynamic objects (marked in `grouped`) as group
 * patches after the blocks: faces whose normals share a cone
 * (normal_bin) and whose centroids share a cell of a grid patch_size()
 * apart in object space form one patch. A dynamic mesh of thousands
 * of faces in blocks of its surfaces would need four patches a face, and a
 * device draws a few hundred hemicubes at once. */
static xrad_status build_groups(const xrad_scene *scene, uint32_t max_patches,
                                const bool *grouped, dynamic_patches *out, xrad_error *err)
{
    uint32_t ns = scene->surface_count, nf = 0;
    for (uint32_t s = 0; s < ns; s++)
        nf += grouped[s];
    out->surface_patch_size = ns;
    if (!nf)
        return XRAD_OK;
    face_key *keys = malloc(nf * sizeof *keys);
    uint32_t *sp = realloc(out->surface_patch, ((size_t)ns + nf) * sizeof *sp);
    if (!keys || !sp) {
        free(keys);
        if (sp)
            out->surface_patch = sp;
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for mesh patches",
                         scene->path);
    }
    out->surface_patch = sp;
    uint32_t k = 0, size_object = UINT32_MAX;
    double size = 1;
    for (uint32_t s = 0; s < ns; s++) {
        if (!grouped[s])
            continue;
        const surface *sf = &scene->surfaces[s];
        /* Once per object: its surfaces are contiguous, and the diagonal
         * is a loop over all of them. */
        if (sf->object != size_object) {
            const object *ob = &scene->objects[sf->object];
            size_object = sf->object;
            size = patch_size(scene, ob);
        }
        vec3 c = v3_scale(v3_add(v3_add(sf->p[0], sf->p[1]), v3_add(sf->p[2], sf->p[3])), 0.25);
        keys[k] = (face_key){.object = sf->object, .bin = normal_bin(sf->normal), .surface = s};
        double cc[3] = {c.x, c.y, c.z};
        for (int a = 0; a < 3; a++)
            keys[k].cell[a] = (int32_t)fmax(-1e9, fmin(1e9, floor(cc[a] / size)));
        k++;
    }
    qsort(keys, nf, sizeof *keys, face_cmp);
    uint32_t groups = 0;
    for (uint32_t f = 0; f < nf; f++)
        groups += f == 0 || !same_group(&keys[f], &keys[f - 1]);
    struct cross_patch *pt = realloc(out->patches, ((size_t)out->count + groups) * sizeof *pt);
    if (!pt) {
        free(keys);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for mesh patches",
                         scene->path);
    }
    out->patches = pt;
    uint32_t p = out->count;
    for (uint32_t f = 0; f < nf; f++) {
        if (f == 0 || !same_group(&keys[f], &keys[f - 1])) {
            out->patches[p] = (struct cross_patch){.surface = keys[f].surface, .cx = 1, .cy = 1,
                                                   .member_first = ns + f};
            p++;
        }
        out->patches[p - 1].member_count++;
        out->surface_patch[ns + f] = keys[f].surface;
        out->surface_patch[keys[f].surface] = p - 1;
    }
    out->count = p;
    out->surface_patch_size = ns + nf;
    free(keys);
    return XRAD_OK;
}

/* Which surfaces get blocks: the dynamic ones (with `groups`, the faces of
 * dynamic meshes in groups instead), or (diameter > 0) the static
 * emitters. */
static xrad_status build(const xrad_scene *scene, uint32_t max_patches, double diameter,
                         bool groups, dynamic_patches *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    size_t ns = scene->surface_count ? scene->surface_count : 1;
    uint32_t *cx = calloc(ns, 2 * sizeof(uint32_t));
    bool *grouped = calloc(ns, sizeof(bool));
    out->surface_patch = malloc(ns * sizeof(uint32_t));
    xrad_status st = XRAD_OK;
    if (!cx || !grouped || !out->surface_patch) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for patches",
                       scene->path);
        goto done;
    }
    uint32_t size_object = UINT32_MAX;
    double density = 1;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        const object *ob = &scene->objects[sf->object];
        vec3 e = scene->materials[sf->material].emission;
        uint32_t a = max_patches, b = max_patches;
        if (diameter > 0) {
            if (ob->dynamic || !(e.x > 0 || e.y > 0 || e.z > 0))
                continue;
            double lu, lv;
            scene_quad_edge_lengths(sf, &lu, &lv);
            cx[2 * s] = light_blocks(lu / diameter, sf->nu, max_patches);
            cx[2 * s + 1] = light_blocks(lv / diameter, sf->nv, max_patches);
            continue;
        }
        if (!ob->dynamic)
            continue;
        if (groups && sf->mesh) {
            grouped[s] = true;
            continue;
        }
        /* Once per object: its surfaces are contiguous. */
        if (sf->object != size_object) {
            size_object = sf->object;
            density = 1.0 / patch_size(scene, ob);
        }
        double lu, lv;
        scene_quad_edge_lengths(sf, &lu, &lv);
        a = (uint32_t)scene_samples_along(lu, density);
        b = (uint32_t)scene_samples_along(lv, density);
        a = a < max_patches || ob->cross_density > 0 ? a : max_patches;
        b = b < max_patches || ob->cross_density > 0 ? b : max_patches;
        /* A block holds at least one element; a coarse grid has 2 samples
         * a side where the surface has them (a tiny triangle is one). */
        a = a < sf->nu ? a : sf->nu;
        b = b < sf->nv ? b : sf->nv;
        cx[2 * s] = a < 2 ? (sf->nu < 2 ? 1 : 2) : a;
        cx[2 * s + 1] = b < 2 ? (sf->nv < 2 ? 1 : 2) : b;
    }
    if (!(st = build_blocks(scene, cx, out, err)))
        st = build_groups(scene, max_patches, grouped, out, err);
done:
    free(cx);
    free(grouped);
    if (st)
        dynamic_patches_free(out);
    return st;
}

xrad_status dynamic_patches_build(const xrad_scene *scene, uint32_t max_patches, bool groups,
                                  dynamic_patches *out, xrad_error *err)
{
    return build(scene, max_patches, 0, groups, out, err);
}

xrad_status dynamic_patches_build_lights(const xrad_scene *scene, uint32_t max_patches,
                                         double diameter, dynamic_patches *out,
                                         xrad_error *err)
{
    return build(scene, max_patches, diameter > 0 ? diameter : 1, false, out, err);
}

void dynamic_patches_free(dynamic_patches *dp)
{
    if (!dp)
        return;
    free(dp->patches);
    free(dp->surface_patch);
    memset(dp, 0, sizeof(*dp));
}

xrad_status dynamic_patches_fix(struct xrad_context *ctx, gpu_scene *gs,
                                const dynamic_patches *dp, xrad_error *err)
{
    uint32_t n = gs->surface_count ? gs->surface_count : 1;
    uint32_t *counts = calloc(3 * (size_t)n, sizeof(uint32_t));
    if (!counts)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "patches: out of host memory");
    for (uint32_t s = 0; s < gs->surface_count; s++) {
        uint32_t p = dp->surface_patch[s];
        if (p != DYNAMIC_PATCH_NONE) {
            counts[3 * s] = dp->patches[p].cx;
            counts[3 * s + 1] = dp->patches[p].cy;
            counts[3 * s + 2] = p;
        }
    }
    xrad_status st = gpu_scene_fix_patches(ctx, gs, counts, err);
    free(counts);
    return st;
}

static vec3 bilinear(const vec3 c[4], double u, double v)
{
    return v3_lerp(v3_lerp(c[0], c[1], u), v3_lerp(c[3], c[2], u), v);
}

void fixed_patch_frame(const xrad_scene *scene, uint32_t surface_index, uint32_t i0, uint32_t i1,
                       uint32_t j0, uint32_t j1, uint32_t index, uint32_t seed, double t,
                       struct gpu_shooter *frame, struct cross_quad *quad)
{
    const surface *sf = &scene->surfaces[surface_index];
    vec3 c[4], n;
    scene_surface_world(scene, surface_index, t, c, &n);
    vec3 u = v3_sub(c[1], c[0]);
    vec3 x0 = v3_norm(v3_sub(u, v3_scale(n, v3_dot(u, n))));
    mat3 r = m3_rotation(n, patch_rotation(seed, index));
    double area = 0;
    for (uint32_t j = j0; j <= j1; j++)
        for (uint32_t i = i0; i <= i1; i++)
            area += scene->elements[sf->first_element + j * sf->nu + i].area;
    double s0, s1, t0, t1;
    scene_param_range(i0, i1, sf->nu, &s0, &s1);
    scene_param_range(j0, j1, sf->nv, &t0, &t1);
    *frame = (struct gpu_shooter){
        .pos_area = gpu_vec4(bilinear(c, 0.5 * (s0 + s1), 0.5 * (t0 + t1)), area),
        .normal = gpu_vec4(n, 0),
        .tangent = gpu_vec4(m3_apply(&r, x0), 0),
        .surface = surface_index,
        .i0 = i0,
        .i1 = i1,
        .j0 = j0,
        .j1 = j1,
        .hemicube = index,
    };
    if (quad) {
        const double st[4][2] = {{s0, t0}, {s1, t0}, {s1, t1}, {s0, t1}};
        for (int k = 0; k < 4; k++)
            quad->corner[k] = gpu_vec4(bilinear(c, st[k][0], st[k][1]), 1);
    }
}

/* The frame of group patch `index` (q) at scene time t: area the faces'
 * sum, normal their area-weighted mean n, centre their area centroid
 * raised along n to the highest face vertex (and a thousandth of the
 * group's size beyond), so that the hemicube sees past its own faces and a
 * face of the group lies behind its plane, never in front (the group
 * neither lights nor hides itself); tangent the first face's u edge
 * projected and turned as a block's. Its quad: the faces' extent in that
 * plane along the unturned tangent and n x it, scaled about its middle to
 * the group's area, for the near-field form factor and the projected
 * rays. */
static void group_frame(const xrad_scene *scene, const dynamic_patches *dp,
                        const struct cross_patch *q, uint32_t index, uint32_t seed, double t,
                        struct gpu_shooter *frame, struct cross_quad *quad)
{
    double area = 0;
    vec3 centroid = v3(0, 0, 0), normal = v3(0, 0, 0), u0 = v3(1, 0, 0);
    for (uint32_t m = 0; m < q->member_count; m++) {
        uint32_t s = dp->surface_patch[q->member_first + m];
        vec3 c[4], n;
        scene_surface_world(scene, s, t, c, &n);
        double a = scene->surfaces[s].area;
        /* A triangle's centroid (p2 = p3); a joined pair's corner mean. */
        vec3 mid = scene->surfaces[s].triangle
                       ? v3_scale(v3_add(v3_add(c[0], c[1]), c[2]), 1.0 / 3)
                       : v3_scale(v3_add(v3_add(c[0], c[1]), v3_add(c[2], c[3])), 0.25);
        centroid = v3_mad(centroid, mid, a);
        normal = v3_mad(normal, n, a);
        area += a;
        if (m == 0)
            u0 = v3_sub(c[1], c[0]);
    }
    centroid = v3_scale(centroid, 1.0 / area);
    vec3 n = v3_norm(normal);
    vec3 x0 = v3_sub(u0, v3_scale(n, v3_dot(u0, n)));
    x0 = v3_len(x0) > 0 ? v3_norm(x0) : v3_norm(v3_cross(n, fabs(n.x) < 0.9 ? v3(1, 0, 0)
                                                                           : v3(0, 1, 0)));
    vec3 y0 = v3_cross(n, x0);
    double h = 0, lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (uint32_t m = 0; m < q->member_count; m++) {
        vec3 c[4];
        scene_surface_world(scene, dp->surface_patch[q->member_first + m], t, c, NULL);
        for (int k = 0; k < 4; k++) {
            vec3 d = v3_sub(c[k], centroid);
            h = fmax(h, v3_dot(d, n));
            double uv[2] = {v3_dot(d, x0), v3_dot(d, y0)};
            for (int a = 0; a < 2; a++) {
                lo[a] = fmin(lo[a], uv[a]);
                hi[a] = fmax(hi[a], uv[a]);
            }
        }
    }
    vec3 o = v3_mad(centroid, n, h + 1e-3 * sqrt(area));
    mat3 r = m3_rotation(n, patch_rotation(seed, index));
    *frame = (struct gpu_shooter){
        .pos_area = gpu_vec4(o, area),
        .normal = gpu_vec4(n, 0),
        .tangent = gpu_vec4(m3_apply(&r, x0), 0),
        .surface = q->surface,
        .hemicube = index,
        .group = 1,
    };
    if (quad) {
        double w = fmax(hi[0] - lo[0], 1e-9), l = fmax(hi[1] - lo[1], 1e-9);
        double k = sqrt(area / (w * l));
        double mu = 0.5 * (lo[0] + hi[0]), mv = 0.5 * (lo[1] + hi[1]);
        const double st[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (int c = 0; c < 4; c++) {
            vec3 p = v3_mad(v3_mad(o, x0, mu + 0.5 * k * w * st[c][0]), y0,
                            mv + 0.5 * k * l * st[c][1]);
            quad->corner[c] = gpu_vec4(p, 1);
        }
    }
}

void dynamic_patches_pose(const xrad_scene *scene, const dynamic_patches *dp, double t,
                          uint32_t seed, struct gpu_shooter *front, struct gpu_shooter *back,
                          struct gpu_shooter *gather, struct cross_quad *quads)
{
    for (uint32_t p = 0; p < dp->count; p++) {
        const struct cross_patch *q = &dp->patches[p];
        struct gpu_shooter f;
        /* A group has one frame for all three hemicubes. */
        if (q->member_count)
            group_frame(scene, dp, q, p, seed, t, &f, quads ? &quads[p] : NULL);
        else
            fixed_patch_frame(scene, q->surface, q->i0, q->i1, q->j0, q->j1, p, seed, t, &f,
                              quads ? &quads[p] : NULL);
        if (front)
            front[p] = f;
        if (back) {
            back[p] = f;
            back[p].normal = (vec4){-f.normal.x, -f.normal.y, -f.normal.z, 0};
        }
        if (gather && q->member_count) {
            gather[p] = f;
            gather[p].pos_area.w = 0;
        } else if (gather) {
            vec3 c[4];
            double g0, g1, h0, h1;
            scene_surface_world(scene, q->surface, t, c, NULL);
            scene_param_range(q->ci, q->ci, q->cx, &g0, &g1);
            scene_param_range(q->cj, q->cj, q->cy, &h0, &h1);
            gather[p] = f;
            gather[p].pos_area = gpu_vec4(bilinear(c, 0.5 * (g0 + g1), 0.5 * (h0 + h1)), 0);
        }
    }
}
