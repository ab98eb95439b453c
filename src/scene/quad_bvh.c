/* Bounding volume hierarchy over quads (quad_bvh.h). */
#include "scene/quad_bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define MAX_DEPTH 64

typedef struct keyed {
    double key;
    uint32_t q;
} keyed;

typedef struct build {
    const double (*lo)[3], (*hi)[3]; /* per quad box */
    double (*centre)[3];
    keyed *scratch; /* one per quad */
    uint32_t *items;
    quad_bvh_node *nodes;
    uint32_t node_count;
} build;

static int by_key(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    return x->key < y->key ? -1 : x->key > y->key ? 1 : (x->q > y->q) - (x->q < y->q);
}

/* Node `at` over items[first, first + count). */
static void split(build *b, uint32_t at, uint32_t first, uint32_t count, int depth)
{
    quad_bvh_node *n = &b->nodes[at];
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int a = 0; a < 3; a++) {
        n->lo[a] = INFINITY;
        n->hi[a] = -INFINITY;
    }
    for (uint32_t k = first; k < first + count; k++) {
        uint32_t q = b->items[k];
        for (int a = 0; a < 3; a++) {
            n->lo[a] = fmin(n->lo[a], b->lo[q][a]);
            n->hi[a] = fmax(n->hi[a], b->hi[q][a]);
            clo[a] = fmin(clo[a], b->centre[q][a]);
            chi[a] = fmax(chi[a], b->centre[q][a]);
        }
    }
    /* A scene of a few dozen quads is one leaf: a loop over them costs
     * less than boxes. */
    if (count <= QUAD_BVH_LEAF || depth >= MAX_DEPTH || (depth == 0 && count <= 32)) {
        n->first = first;
        n->count = count;
        return;
    }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (chi[a] - clo[a] > chi[axis] - clo[axis])
            axis = a;
    for (uint32_t k = 0; k < count; k++) {
        uint32_t q = b->items[first + k];
        b->scratch[k] = (keyed){b->centre[q][axis], q};
    }
    qsort(b->scratch, count, sizeof(keyed), by_key);
    for (uint32_t k = 0; k < count; k++)
        b->items[first + k] = b->scratch[k].q;
    uint32_t child = b->node_count;
    b->node_count += 2;
    n->first = child;
    n->count = 0;
    uint32_t half = count / 2;
    split(b, child, first, half, depth + 1);
    split(b, child + 1, first + half, count - half, depth + 1);
}

void quad_bvh_free(quad_bvh *bvh)
{
    free(bvh->nodes);
    free(bvh->items);
    memset(bvh, 0, sizeof(*bvh));
}

xrad_status quad_bvh_build(const vec3 *corners, uint32_t n, double pad, quad_bvh *out,
                           xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    size_t na = n ? n : 1;
    double(*lo)[3] = malloc(na * sizeof *lo), (*hi)[3] = malloc(na * sizeof *hi);
    double(*centre)[3] = malloc(na * sizeof *centre);
    keyed *scratch = malloc(na * sizeof *scratch);
    out->items = malloc(na * sizeof *out->items);
    out->nodes = malloc(2 * na * sizeof *out->nodes);
    if (!lo || !hi || !centre || !scratch || !out->items || !out->nodes) {
        free(lo);
        free(hi);
        free(centre);
        free(scratch);
        quad_bvh_free(out);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "quad BVH: out of memory for %u quads", n);
    }
    for (uint32_t q = 0; q < n; q++) {
        for (int a = 0; a < 3; a++) {
            lo[q][a] = INFINITY;
            hi[q][a] = -INFINITY;
        }
        for (int k = 0; k < 4; k++) {
            const double p[3] = {corners[4 * q + k].x, corners[4 * q + k].y,
                                 corners[4 * q + k].z};
            for (int a = 0; a < 3; a++) {
                lo[q][a] = fmin(lo[q][a], p[a] - pad);
                hi[q][a] = fmax(hi[q][a], p[a] + pad);
            }
        }
        for (int a = 0; a < 3; a++)
            centre[q][a] = 0.5 * (lo[q][a] + hi[q][a]);
        out->items[q] = q;
    }
    build b = {.lo = (const double(*)[3])lo, .hi = (const double(*)[3])hi, .centre = centre,
               .scratch = scratch, .items = out->items, .nodes = out->nodes, .node_count = 1};
    if (n)
        split(&b, 0, 0, n, 0);
    out->node_count = n ? b.node_count : 0; /* none: nothing to visit */
    free(lo);
    free(hi);
    free(centre);
    free(scratch);
    return XRAD_OK;
}

/* The slab test: whether o + t d meets the box at some t in [tmin, tmax]. */
static bool box_hit(const quad_bvh_node *n, vec3 o, vec3 inv, double tmin, double tmax)
{
    const double org[3] = {o.x, o.y, o.z}, iv[3] = {inv.x, inv.y, inv.z};
    for (int a = 0; a < 3; a++) {
        if (isinf(iv[a])) {
            /* Parallel to the slab: inside it or never. */
            if (org[a] < n->lo[a] || org[a] > n->hi[a])
                return false;
            continue;
        }
        double t0 = (n->lo[a] - org[a]) * iv[a], t1 = (n->hi[a] - org[a]) * iv[a];
        if (t0 > t1) {
            double s = t0;
            t0 = t1;
            t1 = s;
        }
        tmin = fmax(tmin, t0);
        tmax = fmin(tmax, t1);
        if (tmin > tmax)
            return false;
    }
    return true;
}

bool quad_bvh_ray(const quad_bvh *bvh, vec3 o, vec3 d, double tmin, double tmax,
                  bool (*visit)(void *user, uint32_t q, double *tmax), void *user)
{
    if (!bvh->node_count)
        return false;
    vec3 inv = v3(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
    uint32_t stack[2 * MAX_DEPTH + 2], top = 0;
    stack[top++] = 0;
    while (top) {
        const quad_bvh_node *n = &bvh->nodes[stack[--top]];
        if (!box_hit(n, o, inv, tmin, tmax))
            continue;
        if (n->count) {
            for (uint32_t k = n->first; k < n->first + n->count; k++)
                if (visit(user, bvh->items[k], &tmax))
                    return true;
        } else {
            stack[top++] = n->first + 1;
            stack[top++] = n->first;
        }
    }
    return false;
}
