/* The segment tests' hierarchy over the posed surfaces (surface_bvh.h). */
#include "solvers/surface_bvh.h"

#include <math.h>
#include <stdlib.h>

#include "core/error.h"

/* Depth of node 0's subtree; children follow their parent (quad_bvh.c). */
static uint32_t depth_of(const quad_bvh *bvh, uint32_t at)
{
    const quad_bvh_node *n = &bvh->nodes[at];
    if (n->count || !bvh->node_count)
        return 1;
    uint32_t a = depth_of(bvh, n->first), b = depth_of(bvh, n->first + 1);
    return 1 + (a > b ? a : b);
}

xrad_status surface_bvh_build(const struct gpu_surface *surfaces, uint32_t n, quad_bvh *out,
                              uint32_t *depth_out, xrad_error *err)
{
    vec3 *corners = malloc(4 * (size_t)(n ? n : 1) * sizeof *corners);
    if (!corners)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "surface BVH: out of host memory for %u surfaces",
                         n);
    for (uint32_t s = 0; s < n; s++)
        for (int k = 0; k < 4; k++)
            corners[4 * s + k] = v3(surfaces[s].corner[k].x, surfaces[s].corner[k].y,
                                    surfaces[s].corner[k].z);
    xrad_status st = quad_bvh_build(corners, n, 0, out, err);
    free(corners);
    if (st)
        return st;
    /* The traversal stack holds at most depth + 1 entries. */
    uint32_t depth = out->node_count ? depth_of(out, 0) : 0;
    if (depth + 1 > GPU_BVH_STACK) {
        quad_bvh_free(out);
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "surface BVH: %u levels over %u surfaces, the shaders walk at most %u",
                         depth, n, GPU_BVH_STACK - 1);
    }
    *depth_out = depth;
    return XRAD_OK;
}

void surface_bvh_refit(const quad_bvh *bvh, const struct gpu_surface *surfaces, float pad,
                       struct gpu_bvh_node *out)
{
    if (!bvh->node_count) {
        /* A box out at 3e38 m: no segment reaches it (an inverted box
         * would not do: the slab test's min and max turn it back). */
        out[0] = (struct gpu_bvh_node){.lo = {3e38f, 3e38f, 3e38f, 0},
                                       .hi = {3e38f, 3e38f, 3e38f, 0}};
        return;
    }
    /* Children have larger numbers than their parent: backwards, every
     * child is done before its parent. */
    for (uint32_t i = bvh->node_count; i-- > 0;) {
        const quad_bvh_node *n = &bvh->nodes[i];
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        if (n->count) {
            for (uint32_t k = n->first; k < n->first + n->count; k++) {
                const struct gpu_surface *sf = &surfaces[bvh->items[k]];
                for (int c = 0; c < 4; c++) {
                    const float p[3] = {sf->corner[c].x, sf->corner[c].y, sf->corner[c].z};
                    for (int a = 0; a < 3; a++) {
                        lo[a] = fminf(lo[a], p[a] - pad);
                        hi[a] = fmaxf(hi[a], p[a] + pad);
                    }
                }
            }
        } else {
            const struct gpu_bvh_node *l = &out[n->first], *r = &out[n->first + 1];
            const float llo[3] = {l->lo.x, l->lo.y, l->lo.z}, lhi[3] = {l->hi.x, l->hi.y, l->hi.z};
            const float rlo[3] = {r->lo.x, r->lo.y, r->lo.z}, rhi[3] = {r->hi.x, r->hi.y, r->hi.z};
            for (int a = 0; a < 3; a++) {
                lo[a] = fminf(llo[a], rlo[a]);
                hi[a] = fmaxf(lhi[a], rhi[a]);
            }
        }
        out[i] = (struct gpu_bvh_node){.lo = {lo[0], lo[1], lo[2], 0},
                                       .hi = {hi[0], hi[1], hi[2], 0},
                                       .first = n->first,
                                       .count = n->count};
    }
}
