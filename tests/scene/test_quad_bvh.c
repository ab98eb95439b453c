/*
 * The quads' BVH (src/scene/quad_bvh.h) against a loop over every quad:
 * for 3,000 random rays among 2,000 random quads (and among 12, one leaf),
 * the quads whose boxes the BVH visits include every quad a ray meets
 * within its interval, so the nearest hit found through it is the loop's;
 * a visit that stops ends the walk; an empty BVH visits nothing.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "scene/quad_bvh.h"

static uint64_t rng = 0x9e3779b97f4a7c15ull;

static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (rng >> 11) * (1.0 / 9007199254740992.0);
}

/* A random planar parallelogram in [0, 10]^3, sides up to 1.5. */
static void random_quad(vec3 c[4])
{
    vec3 o = v3(10 * uniform(), 10 * uniform(), 10 * uniform());
    vec3 u = v3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5);
    vec3 v = v3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5);
    u = v3_scale(u, 3 * uniform());
    v = v3_scale(v, 3 * uniform());
    c[0] = o;
    c[1] = v3_add(o, u);
    c[2] = v3_add(v3_add(o, u), v);
    c[3] = v3_add(o, v);
}

/* The parameter t where o + t d crosses the parallelogram c, or -1. */
static double cross_at(const vec3 c[4], vec3 o, vec3 d)
{
    vec3 e1 = v3_sub(c[1], c[0]), e2 = v3_sub(c[3], c[0]);
    vec3 p = v3_cross(d, e2);
    double det = v3_dot(e1, p);
    if (fabs(det) < 1e-15)
        return -1;
    vec3 s = v3_sub(o, c[0]);
    double a = v3_dot(s, p) / det;
    vec3 q = v3_cross(s, e1);
    double b = v3_dot(d, q) / det;
    if (a < 0 || a > 1 || b < 0 || b > 1)
        return -1;
    return v3_dot(e2, q) / det;
}

typedef struct query {
    const vec3 *corners;
    vec3 o, d;
    int best;
    double best_t;
    uint32_t visits, stop_after;
} query;

static bool visit(void *user, uint32_t q, double *tmax)
{
    query *x = user;
    x->visits++;
    double t = cross_at(&x->corners[4 * q], x->o, x->d);
    if (t > 0 && t < x->best_t) {
        x->best = (int)q;
        x->best_t = t;
        *tmax = t;
    }
    return x->stop_after && x->visits >= x->stop_after;
}

static void against_loop(uint32_t n)
{
    vec3 *c = malloc(4 * (size_t)n * sizeof *c);
    if (!c)
        return;
    for (uint32_t q = 0; q < n; q++)
        random_quad(&c[4 * q]);
    quad_bvh bvh;
    xrad_error err = {0};
    CHECK(quad_bvh_build(c, n, 1e-9, &bvh, &err) == XRAD_OK, "build: %s", err.message);
    uint32_t wrong = 0, hits = 0;
    uint64_t visits = 0;
    for (int r = 0; r < 3000; r++) {
        vec3 o = v3(12 * uniform() - 1, 12 * uniform() - 1, 12 * uniform() - 1);
        vec3 d = v3_norm(v3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5));
        if (r % 10 == 0)
            d = v3(0, 0, uniform() < 0.5 ? 1 : -1); /* parallel to two slabs */
        int best = -1;
        double best_t = INFINITY;
        for (uint32_t q = 0; q < n; q++) {
            double t = cross_at(&c[4 * q], o, d);
            if (t > 0 && t < best_t) {
                best = (int)q;
                best_t = t;
            }
        }
        query x = {c, o, d, -1, INFINITY, 0, 0};
        quad_bvh_ray(&bvh, o, d, 0, INFINITY, visit, &x);
        wrong += x.best != best || (best >= 0 && x.best_t != best_t);
        hits += best >= 0;
        visits += x.visits;
    }
    fprintf(stderr, "%u quads: %u of 3000 rays hit, %u differ from the loop, %.1f visits a ray\n",
            n, hits, wrong, visits / 3000.0);
    CHECK(wrong == 0, "%u quads: %u rays found another nearest hit than the loop", n, wrong);
    CHECK(hits > (n > 100 ? 100u : 5u), "%u quads: only %u rays hit anything", n, hits);
    if (n > 100)
        CHECK(visits < 3000ull * n / 10, "%u quads: %.1f visits a ray, not far below %u", n,
              visits / 3000.0, n);
    /* A visit that stops ends the walk. */
    query x = {c, v3(5, 5, -1), v3(0, 0, 1), -1, INFINITY, 0, 1};
    CHECK(!quad_bvh_ray(&bvh, x.o, x.d, 0, INFINITY, visit, &x) || x.visits == 1,
          "a stopping visit did not end the walk (%u visits)", x.visits);
    quad_bvh_free(&bvh);
    free(c);
}

int main(void)
{
    against_loop(2000);
    against_loop(12);
    quad_bvh bvh;
    xrad_error err = {0};
    CHECK(quad_bvh_build(NULL, 0, 0, &bvh, &err) == XRAD_OK, "empty: %s", err.message);
    query x = {NULL, v3(0, 0, 0), v3(1, 0, 0), -1, INFINITY, 0, 0};
    quad_bvh_ray(&bvh, x.o, x.d, 0, INFINITY, visit, &x);
    CHECK(x.visits == 0, "an empty BVH visited %u quads", x.visits);
    quad_bvh_free(&bvh);
    return test_finish();
}
