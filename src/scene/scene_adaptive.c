/*
 * Adaptive subdivision where shadows fall (Wallner 4; xrad.h
 * xrad_adaptive_desc). Wallner renders the scene from each shooter and
 * compares occlusion-query counts: n_r fragments rasterised without depth
 * test, n_v visible with it; a triangle with n_v != n_r and
 * b_l <= n_v / n_r <= b_u has a shadow boundary long enough to pay for
 * splitting it 1 -> 4, before the shooter's first shot. Here the same
 * fraction is counted with rays at build time, over pairs of points on the
 * receiver and on the emitter that face each other: every emitter of a
 * scene is known before its first shot, and a shot into an element grid
 * that has been split needs no reshooting (Wallner: "no reshooting ... is
 * performed"; the parent's radiosity, zero before the first shot, is what
 * the children start from).
 *
 * xrad's unit of refinement is the surface's element grid (nu x nv samples
 * -> 2 nu - 1 x 2 nv - 1, each element split in four), as Wallner's is the
 * triangle with its radiosity texture. Surfaces sharing an edge are
 * balanced (Wallner after Baum et al.): coplanar ones take the same level,
 * so that their boundary samples stay shared and the display meets no
 * T-vertex; others differ by at most one level.
 *
 * Only what stands still is tested: static receivers lit by static
 * emitters (and luminaires) past static occluders. A moving object's
 * shadow moves over the elements; the grid, fixed at build, cannot follow
 * it.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene_internal.h"

#define ADAPTIVE_MAX_LEVELS 4
#define ADAPTIVE_LOWER 0.02
#define ADAPTIVE_UPPER 0.98
/* Points per side: a receiver's at most (its sample grid, else fewer), an
 * emitting surface's always. */
#define RECEIVER_POINTS 8u
#define EMITTER_POINTS 3u
/* Rays past which the test is not made (about a minute on one core). */
#define ADAPTIVE_MAX_RAYS (1ull << 27)

xrad_status scene_adaptive_check(const xrad_adaptive_desc *d, const char *name,
                                 xrad_adaptive_desc *out, xrad_error *err)
{
    xrad_adaptive_desc a = *d;
    if (a.levels > ADAPTIVE_MAX_LEVELS)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: adaptive levels %u is more than %u", name,
                         a.levels, ADAPTIVE_MAX_LEVELS);
    if (a.lower != 0 && !(a.lower > 0 && a.lower <= 1))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: adaptive lower %g is outside (0, 1]", name,
                         a.lower);
    if (a.upper != 0 && !(a.upper > 0 && a.upper <= 1))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: adaptive upper %g is outside (0, 1]", name,
                         a.upper);
    a.lower = a.lower > 0 ? a.lower : ADAPTIVE_LOWER;
    a.upper = a.upper > 0 ? a.upper : ADAPTIVE_UPPER;
    *out = a;
    return XRAD_OK;
}

/* The points that light comes from: an emitting surface's grid of
 * EMITTER_POINTS^2 cell centres with its normal, or a luminaire's
 * position. */
typedef struct light {
    uint32_t surface; /* UINT32_MAX: a luminaire */
    uint32_t count;
    vec3 p[EMITTER_POINTS * EMITTER_POINTS];
    vec3 normal;
    const luminaire *lum;
} light;

static bool emits(const xrad_scene *sc, uint32_t s)
{
    vec3 e = sc->materials[sc->surfaces[s].material].emission;
    return e.x > 0 || e.y > 0 || e.z > 0;
}

/* P(s, t) of a world-space quad (scene.h: bilinear; a triangle's p3 is p2). */
static vec3 quad_point(const vec3 c[4], double s, double t)
{
    return v3_lerp(v3_lerp(c[0], c[1], s), v3_lerp(c[3], c[2], s), t);
}

static void grid_points(const vec3 c[4], uint32_t mu, uint32_t mv, vec3 *out)
{
    for (uint32_t j = 0; j < mv; j++)
        for (uint32_t i = 0; i < mu; i++)
            out[j * mu + i] = quad_point(c, (i + 0.5) / mu, (j + 0.5) / mv);
}

static bool is_static(const xrad_scene *sc, uint32_t s)
{
    return !sc->objects[sc->surfaces[s].object].dynamic;
}

/* Whether light from `l` reaches the point x (normal n) at all, visibility
 * aside: the pair faces each other, and a spot's cone holds x. */
static bool faces(const light *l, vec3 q, vec3 x, vec3 n)
{
    vec3 d = v3_sub(x, q);
    if (v3_dot(n, d) >= 0)
        return false;
    if (l->lum) {
        double len = v3_len(d);
        return !(l->lum->cos_outer > -2 && v3_dot(l->lum->aim, d) < l->lum->cos_outer * len);
    }
    return v3_dot(l->normal, d) > 0;
}

/* Receiver points along a side of n samples. */
static uint32_t receiver_side(uint32_t n)
{
    return n < 2 ? 2 : n > RECEIVER_POINTS ? RECEIVER_POINTS : n;
}

/* Whether surface r's visibility from some light is partial in Wallner's
 * sense: n_v < n_r and lower <= n_v / n_r <= upper. */
static bool partial(const scene_rays *rs, uint32_t r, const light *lights, uint32_t nl,
                    const xrad_adaptive_desc *d)
{
    const xrad_scene *sc = rs->scene;
    const surface *sf = &sc->surfaces[r];
    uint32_t mu = receiver_side(sf->nu), mv = receiver_side(sf->nv);
    vec3 x[RECEIVER_POINTS * RECEIVER_POINTS];
    grid_points(&rs->corners[4 * r], mu, mv, x);
    vec3 n = rs->normals[r];
    double eps = 1e-6 * rs->diameter;
    for (uint32_t k = 0; k < nl; k++) {
        const light *l = &lights[k];
        if (l->surface == r)
            continue;
        uint64_t n_r = 0, n_v = 0;
        for (uint32_t a = 0; a < mu * mv; a++)
            for (uint32_t b = 0; b < l->count; b++) {
                if (!faces(l, l->p[b], x[a], n))
                    continue;
                n_r++;
                vec3 q = l->lum ? l->p[b] : v3_mad(l->p[b], l->normal, eps);
                n_v += !scene_rays_blocked(rs, v3_mad(x[a], n, eps), q, r);
            }
        double f = n_r ? (double)n_v / n_r : 1;
        if (n_v < n_r && f >= d->lower && f <= d->upper)
            return true;
    }
    return false;
}

/* An edge of a surface in its object's space, its ends rounded to a grid
 * of `tol` and ordered, so that neighbours' edges compare equal. */
typedef struct edge {
    uint32_t object, surface;
    int64_t a[3], b[3];
} edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const edge *x = pa, *y = pb;
    if (x->object != y->object)
        return x->object < y->object ? -1 : 1;
    int c = memcmp(x->a, y->a, sizeof(x->a));
    return c ? c : memcmp(x->b, y->b, sizeof(x->b));
}

static void round_point(vec3 p, double tol, int64_t out[3])
{
    out[0] = llround(p.x / tol);
    out[1] = llround(p.y / tol);
    out[2] = llround(p.z / tol);
}

/* Raises levels until surfaces sharing an edge agree (coplanar: equal,
 * else within one). Levels only grow, so it ends. */
static xrad_status balance(const xrad_scene *sc, double tol, uint8_t *level, xrad_error *err)
{
    uint32_t ns = sc->surface_count;
    edge *edges = malloc((size_t)4 * (ns ? ns : 1) * sizeof(*edges));
    if (!edges)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for adaptive subdivision",
                         sc->path);
    uint32_t ne = 0;
    for (uint32_t s = 0; s < ns; s++) {
        const surface *sf = &sc->surfaces[s];
        for (int k = 0; k < 4; k++) {
            edge e = {.object = sf->object, .surface = s};
            round_point(sf->p[k], tol, e.a);
            round_point(sf->p[(k + 1) & 3], tol, e.b);
            int c = memcmp(e.a, e.b, sizeof(e.a));
            if (!c)
                continue; /* a triangle's collapsed edge */
            if (c > 0) {
                int64_t t[3];
                memcpy(t, e.a, sizeof(t));
                memcpy(e.a, e.b, sizeof(t));
                memcpy(e.b, t, sizeof(t));
            }
            edges[ne++] = e;
        }
    }
    qsort(edges, ne, sizeof(*edges), edge_cmp);
    for (bool changed = true; changed;) {
        changed = false;
        for (uint32_t i = 0; i < ne; i++)
            for (uint32_t j = i + 1; j < ne && !edge_cmp(&edges[i], &edges[j]); j++) {
                uint32_t s = edges[i].surface, t = edges[j].surface;
                bool coplanar = v3_dot(sc->surfaces[s].normal, sc->surfaces[t].normal) > 1 - 1e-9;
                uint8_t want_s = coplanar ? level[t] : level[t] ? level[t] - 1 : 0;
                uint8_t want_t = coplanar ? level[s] : level[s] ? level[s] - 1 : 0;
                if (level[s] < want_s) {
                    level[s] = want_s;
                    changed = true;
                }
                if (level[t] < want_t) {
                    level[t] = want_t;
                    changed = true;
                }
            }
    }
    free(edges);
    return XRAD_OK;
}

xrad_status scene_adaptive_refine(xrad_scene_builder *b, const xrad_adaptive_desc *d,
                                  uint64_t *elements, xrad_error *err)
{
    xrad_scene *sc = scene_builder_scene(b);
    uint32_t ns = sc->surface_count;
    uint32_t nl = 0;
    for (uint32_t s = 0; s < ns; s++)
        nl += emits(sc, s) && is_static(sc, s);
    nl += sc->luminaire_count;
    if (!nl || !ns)
        return XRAD_OK;
    light *lights = malloc(nl * sizeof(*lights));
    uint8_t *level = calloc(ns, 1);
    scene_rays rs = {0};
    xrad_status st = !lights || !level
                         ? xrad_fail(err, XRAD_ERROR_SYSTEM,
                                     "%s: out of memory for adaptive subdivision", sc->path)
                         : scene_rays_init(&rs, sc, 0, false, err);
    if (st)
        goto done;
    nl = 0;
    uint64_t light_points = 0, receiver_points = 0;
    for (uint32_t s = 0; s < ns; s++)
        if (emits(sc, s) && is_static(sc, s)) {
            light *l = &lights[nl++];
            *l = (light){
                .surface = s, .count = EMITTER_POINTS * EMITTER_POINTS, .normal = rs.normals[s]};
            grid_points(&rs.corners[4 * s], EMITTER_POINTS, EMITTER_POINTS, l->p);
            light_points += l->count;
        }
    for (uint32_t k = 0; k < sc->luminaire_count; k++, light_points++)
        lights[nl++] = (light){.surface = UINT32_MAX,
                               .count = 1,
                               .p = {sc->luminaires[k].position},
                               .lum = &sc->luminaires[k]};
    for (uint32_t s = 0; s < ns; s++)
        if (is_static(sc, s) && !emits(sc, s)) {
            const surface *sf = &sc->surfaces[s];
            receiver_points += (uint64_t)receiver_side(sf->nu) * receiver_side(sf->nv);
        }
    if (receiver_points * light_points > ADAPTIVE_MAX_RAYS) {
        scene_builder_warn(b,
                           "%s: adaptive subdivision left out: its test would cast %.3g rays "
                           "(%llu receiver points x %llu emitter points; at most %.3g)",
                           sc->path, (double)(receiver_points * light_points),
                           (unsigned long long)receiver_points, (unsigned long long)light_points,
                           (double)ADAPTIVE_MAX_RAYS);
        goto done;
    }
    for (uint32_t s = 0; s < ns; s++)
        if (is_static(sc, s) && !emits(sc, s) && partial(&rs, s, lights, nl, d)) {
            level[s] = (uint8_t)d->levels;
            sc->adaptive_partial_surfaces++;
        }
    if ((st = balance(sc, 1e-6 * rs.diameter, level, err)))
        goto done;
    uint32_t capped = 0;
    for (uint32_t s = 0; s < ns; s++) {
        surface *sf = &sc->surfaces[s];
        uint32_t k = 0;
        for (; k < level[s]; k++) {
            uint32_t nu, nv;
            if (!scene_split_fits(sf, *elements, &nu, &nv)) {
                capped++;
                break;
            }
            scene_split_take(sf, nu, nv, elements);
        }
        sc->adaptive_refined_surfaces += k > 0;
    }
    if (capped)
        scene_builder_warn(b,
                           "%s: %u surface(s) split less than adaptive subdivision asks: the "
                           "scene's element limits (%u, %u along an edge)",
                           sc->path, capped, SCENE_MAX_ELEMENTS, SCENE_MAX_SAMPLES);
done:
    scene_rays_free(&rs);
    free(lights);
    free(level);
    return st;
}
