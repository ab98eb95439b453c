/*
 * The segment tests' hierarchy (src/solvers/surface_bvh.h), on the host:
 * built over 2,000 random quads, then half of them moved rigidly (turned
 * and shifted, as a dynamic object's surfaces are at a later pose) and
 * the boxes refitted. A walk as spirv/shooting.glsl's shooting_bvh_hidden
 * makes it (float slab test, the same margins) reaches every quad that
 * each of 3,000 random segments crosses (a double-precision test, the
 * truth), at the first pose and after the move; every parent's box holds
 * its children's, every leaf's its quads' corners; the walk takes far
 * fewer steps than the quads; no surfaces give a node no segment meets.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "harness.h"
#include "solvers/surface_bvh.h"

#define N 2000u
#define SEGMENTS 3000

static uint64_t rng = 0x2545f4914f6cdd1dull;

static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (rng >> 11) * (1.0 / 9007199254740992.0);
}

static vec3 corner(const struct gpu_surface *s, int k)
{
    return v3(s->corner[k].x, s->corner[k].y, s->corner[k].z);
}

/* Where the segment a -> b crosses parallelogram s, as a fraction of it,
 * or -1 (double precision: the truth). */
static double crossing(const struct gpu_surface *s, vec3 a, vec3 b)
{
    vec3 c0 = corner(s, 0), e1 = v3_sub(corner(s, 1), c0), e2 = v3_sub(corner(s, 3), c0);
    vec3 d = v3_sub(b, a), p = v3_cross(d, e2);
    double det = v3_dot(e1, p);
    if (fabs(det) < 1e-12)
        return -1;
    vec3 o = v3_sub(a, c0), q = v3_cross(o, e1);
    double u = v3_dot(o, p) / det, v = v3_dot(d, q) / det, t = v3_dot(e2, q) / det;
    return u >= 0 && u <= 1 && v >= 0 && v <= 1 && t >= 0 && t <= 1 ? t : -1;
}

/* shooting_box_crossed in float, as the shader has it. */
static int box_crossed(const struct gpu_bvh_node *n, const float c[3], const float inv[3])
{
    const float lo[3] = {n->lo.x, n->lo.y, n->lo.z}, hi[3] = {n->hi.x, n->hi.y, n->hi.z};
    float enter = -1e-4f, leave = 1.0f + 1e-4f;
    for (int a = 0; a < 3; a++) {
        float t0 = (lo[a] - c[a]) * inv[a], t1 = (hi[a] - c[a]) * inv[a];
        enter = fmaxf(enter, fminf(t0, t1));
        leave = fminf(leave, fmaxf(t0, t1));
    }
    return enter <= leave;
}

/* Marks reached[q] for every quad the walk tests; returns its steps. */
static uint32_t walk(const struct gpu_bvh_node *nodes, const uint32_t *items, vec3 a, vec3 b,
                     uint8_t *reached)
{
    const float c[3] = {(float)a.x, (float)a.y, (float)a.z};
    const float d[3] = {(float)(b.x - a.x), (float)(b.y - a.y), (float)(b.z - a.z)};
    float inv[3];
    for (int k = 0; k < 3; k++)
        inv[k] = 1.0f / (fabsf(d[k]) < 1e-30f ? 1e-30f : d[k]);
    uint32_t stack[GPU_BVH_STACK], top = 1, steps = 0;
    stack[0] = 0;
    while (top) {
        const struct gpu_bvh_node *n = &nodes[stack[--top]];
        steps++;
        if (!box_crossed(n, c, inv))
            continue;
        if (!n->count) {
            if (top + 2 > GPU_BVH_STACK) {
                CHECK(0, "the walk's stack overflows");
                return steps;
            }
            stack[top++] = n->first + 1;
            stack[top++] = n->first;
            continue;
        }
        for (uint32_t k = n->first; k < n->first + n->count; k++) {
            reached[items[k]] = 1;
            steps++;
        }
    }
    return steps;
}

/* The boxes hold what they must: each leaf its quads' corners, each
 * parent its children. */
static void check_boxes(const quad_bvh *bvh, const struct gpu_bvh_node *nodes,
                        const struct gpu_surface *s, const char *when)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < bvh->node_count; i++) {
        const struct gpu_bvh_node *n = &nodes[i];
        const float lo[3] = {n->lo.x, n->lo.y, n->lo.z}, hi[3] = {n->hi.x, n->hi.y, n->hi.z};
        if (n->count) {
            for (uint32_t k = n->first; k < n->first + n->count; k++)
                for (int c = 0; c < 4; c++) {
                    const float p[3] = {s[bvh->items[k]].corner[c].x,
                                        s[bvh->items[k]].corner[c].y,
                                        s[bvh->items[k]].corner[c].z};
                    for (int a = 0; a < 3; a++)
                        bad += p[a] < lo[a] || p[a] > hi[a];
                }
        } else {
            for (uint32_t ch = n->first; ch < n->first + 2; ch++) {
                const float clo[3] = {nodes[ch].lo.x, nodes[ch].lo.y, nodes[ch].lo.z};
                const float chi[3] = {nodes[ch].hi.x, nodes[ch].hi.y, nodes[ch].hi.z};
                for (int a = 0; a < 3; a++)
                    bad += clo[a] < lo[a] || chi[a] > hi[a];
            }
        }
    }
    CHECK(bad == 0, "%s: %u box bounds do not hold what they must", when, bad);
}

static void segments(const quad_bvh *bvh, const struct gpu_bvh_node *nodes,
                     const struct gpu_surface *s, const char *when, uint32_t max_steps)
{
    uint8_t *reached = malloc(N);
    if (!reached) {
        CHECK(0, "out of memory");
        return;
    }
    uint32_t missed = 0, crossed = 0;
    uint64_t steps = 0;
    for (int r = 0; r < SEGMENTS; r++) {
        vec3 a = v3(12 * uniform() - 1, 12 * uniform() - 1, 12 * uniform() - 1);
        vec3 b = v3(12 * uniform() - 1, 12 * uniform() - 1, 12 * uniform() - 1);
        if (r % 10 == 0)
            b = v3(a.x, a.y, b.z); /* along an axis: parallel to two slabs */
        for (uint32_t q = 0; q < N; q++)
            reached[q] = 0;
        steps += walk(nodes, bvh->items, a, b, reached);
        for (uint32_t q = 0; q < N; q++) {
            /* Crossings at the segment's very ends are not the tests'
             * (shooting_blocks: within (1e-4, 1 - 1e-5)). */
            double t = crossing(&s[q], a, b);
            if (t > 1e-4 && t < 1 - 1e-5) {
                crossed++;
                missed += !reached[q];
            }
        }
    }
    fprintf(stderr, "%s: %u crossings of %d segments, %u missed, %.1f steps a segment\n", when,
            crossed, SEGMENTS, missed, (double)steps / SEGMENTS);
    CHECK(crossed > 1000, "%s: only %u crossings: the test tests little", when, crossed);
    CHECK(missed == 0, "%s: the walk missed %u crossings", when, missed);
    CHECK(steps < (uint64_t)SEGMENTS * max_steps, "%s: %.1f steps a segment, want below %u",
          when, (double)steps / SEGMENTS, max_steps);
    free(reached);
}

/* A random parallelogram in [0, 10]^3, sides up to 1.5 m. */
static void random_quad(struct gpu_surface *s)
{
    vec3 o = v3(10 * uniform(), 10 * uniform(), 10 * uniform());
    vec3 u = v3_scale(v3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5), 3 * uniform());
    vec3 v = v3_scale(v3(uniform() - 0.5, uniform() - 0.5, uniform() - 0.5), 3 * uniform());
    vec3 p[4] = {o, v3_add(o, u), v3_add(v3_add(o, u), v), v3_add(o, v)};
    for (int k = 0; k < 4; k++)
        s->corner[k] = (vec4){(float)p[k].x, (float)p[k].y, (float)p[k].z, 1};
}

int main(void)
{
    struct gpu_surface *s = calloc(N, sizeof *s);
    struct gpu_bvh_node *nodes = calloc(2 * N, sizeof *nodes);
    if (!s || !nodes) {
        CHECK(0, "out of memory");
        return test_finish();
    }
    for (uint32_t q = 0; q < N; q++)
        random_quad(&s[q]);
    quad_bvh bvh;
    uint32_t depth = 0;
    xrad_error err = {0};
    CHECK(surface_bvh_build(s, N, &bvh, &depth, &err) == XRAD_OK, "build: %s", err.message);
    CHECK(depth >= 8 && depth + 1 <= GPU_BVH_STACK, "%u levels over %u quads", depth, N);
    surface_bvh_refit(&bvh, s, 1e-4f, nodes);
    check_boxes(&bvh, nodes, s, "first pose");
    segments(&bvh, nodes, s, "first pose", N / 10);
    /* Every other quad turned 0.7 rad about z through (5, 5, 5) and
     * shifted 2 m along x: what a moving object's surfaces do. */
    const double ca = cos(0.7), sa = sin(0.7);
    for (uint32_t q = 0; q < N; q += 2)
        for (int k = 0; k < 4; k++) {
            double x = s[q].corner[k].x - 5, y = s[q].corner[k].y - 5;
            s[q].corner[k].x = (float)(ca * x - sa * y + 5 + 2);
            s[q].corner[k].y = (float)(sa * x + ca * y + 5);
        }
    surface_bvh_refit(&bvh, s, 1e-4f, nodes);
    check_boxes(&bvh, nodes, s, "moved");
    /* Half the quads moved widens every box over both halves: more
     * steps, still well below a loop over the quads. */
    segments(&bvh, nodes, s, "moved", N / 4);
    quad_bvh_free(&bvh);
    /* No surfaces: one node that no segment meets. */
    CHECK(surface_bvh_build(s, 0, &bvh, &depth, &err) == XRAD_OK, "empty: %s", err.message);
    surface_bvh_refit(&bvh, s, 1e-4f, nodes);
    uint8_t none = 0;
    walk(nodes, bvh.items, v3(-1, -1, -1), v3(1, 1, 1), &none);
    CHECK(!none && nodes[0].count == 0 && nodes[0].lo.x > 1e37f,
          "an empty hierarchy has a box a segment meets");
    quad_bvh_free(&bvh);
    free(nodes);
    free(s);
    return test_finish();
}
