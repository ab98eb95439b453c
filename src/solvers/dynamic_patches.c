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

/* Which surfaces get blocks: the dynamic ones, or (diameter > 0) the
 * static emitters. */
static xrad_status build(const xrad_scene *scene, uint32_t max_patches, double diameter,
                         dynamic_patches *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    size_t ns = scene->surface_count ? scene->surface_count : 1;
    uint32_t *cx = calloc(ns, 2 * sizeof(uint32_t));
    out->surface_patch = malloc(ns * sizeof(uint32_t));
    xrad_status st = XRAD_OK;
    if (!cx || !out->surface_patch) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of host memory for patches",
                       scene->path);
        goto done;
    }
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
        if (ob->cross_density > 0) {
            double lu, lv;
            scene_quad_edge_lengths(sf, &lu, &lv);
            a = (uint32_t)scene_samples_along(lu, ob->cross_density);
            b = (uint32_t)scene_samples_along(lv, ob->cross_density);
        }
        /* A block holds at least one element; a coarse grid has 2 samples a side. */
        a = a < sf->nu ? a : sf->nu;
        b = b < sf->nv ? b : sf->nv;
        cx[2 * s] = a < 2 ? 2 : a;
        cx[2 * s + 1] = b < 2 ? 2 : b;
    }
    st = build_blocks(scene, cx, out, err);
done:
    free(cx);
    if (st)
        dynamic_patches_free(out);
    return st;
}

xrad_status dynamic_patches_build(const xrad_scene *scene, uint32_t max_patches,
                                  dynamic_patches *out, xrad_error *err)
{
    return build(scene, max_patches, 0, out, err);
}

xrad_status dynamic_patches_build_lights(const xrad_scene *scene, uint32_t max_patches,
                                         double diameter, dynamic_patches *out,
                                         xrad_error *err)
{
    return build(scene, max_patches, diameter > 0 ? diameter : 1, out, err);
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

/* The parameter interval covered by samples [i0, i1] of n (scene.h). */
static void param_range(uint32_t i0, uint32_t i1, uint32_t n, double *lo, double *hi)
{
    double h = 1.0 / (n - 1);
    *lo = fmax(0.0, (i0 - 0.5) * h);
    *hi = fmin(1.0, (i1 + 0.5) * h);
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
    param_range(i0, i1, sf->nu, &s0, &s1);
    param_range(j0, j1, sf->nv, &t0, &t1);
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

void dynamic_patches_pose(const xrad_scene *scene, const dynamic_patches *dp, double t,
                          uint32_t seed, struct gpu_shooter *front, struct gpu_shooter *back,
                          struct gpu_shooter *gather, struct cross_quad *quads)
{
    for (uint32_t p = 0; p < dp->count; p++) {
        const struct cross_patch *q = &dp->patches[p];
        struct gpu_shooter f;
        fixed_patch_frame(scene, q->surface, q->i0, q->i1, q->j0, q->j1, p, seed, t, &f,
                          quads ? &quads[p] : NULL);
        if (front)
            front[p] = f;
        if (back) {
            back[p] = f;
            back[p].normal = (vec4){-f.normal.x, -f.normal.y, -f.normal.z, 0};
        }
        if (gather) {
            vec3 c[4];
            double g0, g1, h0, h1;
            scene_surface_world(scene, q->surface, t, c, NULL);
            param_range(q->ci, q->ci, q->cx, &g0, &g1);
            param_range(q->cj, q->cj, q->cy, &h0, &h1);
            gather[p] = f;
            gather[p].pos_area = gpu_vec4(bilinear(c, 0.5 * (g0 + g1), 0.5 * (h0 + h1)), 0);
        }
    }
}
