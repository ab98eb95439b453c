/* Segment-quad visibility and sample patterns (raycast.h). */
#include "reference/raycast.h"

#include <math.h>

#include "reference/ff_kernel.h"

bool ref_quad_init(ref_quad *q, const vec3 corners[4])
{
    for (int k = 0; k < 4; k++)
        q->p[k] = corners[k];
    vec3 n = ref_polygon_newell(corners, 4);
    double len = v3_len(n);
    if (!(len > 0))
        return false;
    q->normal = v3_scale(n, 1 / len);
    return true;
}

bool ref_segment_hits_quad(const ref_quad *q, vec3 a, vec3 b)
{
    vec3 d = v3_sub(b, a);
    double denom = v3_dot(q->normal, d);
    /* A segment parallel to the quad's plane meets it in a set of zero
     * measure at most; it is not blocked. */
    if (!(fabs(denom) > 1e-15 * v3_len(d)))
        return false;
    double t = v3_dot(q->normal, v3_sub(q->p[0], a)) / denom;
    if (!(t > REF_RAY_EPS && t < 1 - REF_RAY_EPS))
        return false;
    vec3 x = v3_mad(a, d, t);
    for (int m = 0; m < 4; m++) {
        vec3 e = v3_sub(q->p[(m + 1) % 4], q->p[m]);
        if (v3_dot(q->normal, v3_cross(e, v3_sub(x, q->p[m]))) < 0)
            return false;
    }
    return true;
}

/* True if every corner of q lies on the far side of the plane through `o`
 * with outward normal `n` (n . (v - o) >= -tol). */
static bool outside_plane(const ref_quad *q, vec3 o, vec3 n, double tol)
{
    for (int k = 0; k < 4; k++)
        if (v3_dot(n, v3_sub(q->p[k], o)) < -tol)
            return false;
    return true;
}

bool ref_quad_may_block(const ref_quad *q, vec3 apex, const vec3 *base, double tol)
{
    vec3 centre = v3_scale(v3_add(v3_add(base[0], base[1]), v3_add(base[2], base[3])), 0.25);

    /* The base plane, outward away from the apex. */
    vec3 nb = v3_norm(ref_polygon_newell(base, 4));
    if (v3_dot(nb, v3_sub(apex, centre)) > 0)
        nb = v3_scale(nb, -1);
    if (outside_plane(q, centre, nb, tol))
        return false;

    /* The side planes through the apex and each base edge, outward. */
    for (int m = 0; m < 4; m++) {
        vec3 ns = v3_cross(v3_sub(base[m], apex), v3_sub(base[(m + 1) % 4], apex));
        double len = v3_len(ns);
        if (!(len > 0))
            continue;
        ns = v3_scale(ns, 1 / len);
        if (v3_dot(ns, v3_sub(centre, apex)) > 0)
            ns = v3_scale(ns, -1);
        if (outside_plane(q, apex, ns, tol))
            return false;
    }

    /* q's own plane: the hull lies on one side of it. */
    double lo = v3_dot(q->normal, v3_sub(apex, q->p[0])), hi = lo;
    for (int k = 0; k < 4; k++) {
        double s = v3_dot(q->normal, v3_sub(base[k], q->p[0]));
        lo = s < lo ? s : lo;
        hi = s > hi ? s : hi;
    }
    if (lo >= -tol || hi <= tol)
        return false;
    return true;
}

static uint64_t splitmix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ull;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
    return x ^ (x >> 31);
}

uint64_t ref_pair_seed(uint32_t a, uint32_t b)
{
    return splitmix64(((uint64_t)a << 32) | b);
}

static double radical_inverse2(uint32_t k)
{
    k = (k << 16) | (k >> 16);
    k = ((k & 0x00ff00ffu) << 8) | ((k & 0xff00ff00u) >> 8);
    k = ((k & 0x0f0f0f0fu) << 4) | ((k & 0xf0f0f0f0u) >> 4);
    k = ((k & 0x33333333u) << 2) | ((k & 0xccccccccu) >> 2);
    k = ((k & 0x55555555u) << 1) | ((k & 0xaaaaaaaau) >> 1);
    return k * (1.0 / 4294967296.0);
}

void ref_sample(uint64_t seed, uint32_t k, uint32_t count, double *s, double *t)
{
    double du = (double)(splitmix64(seed) >> 11) * (1.0 / 9007199254740992.0);
    double dv = (double)(splitmix64(seed ^ 0x5851f42d4c957f2dull) >> 11) * (1.0 / 9007199254740992.0);
    *s = (k + du) / count;
    double v = radical_inverse2(k) + dv;
    *t = v >= 1 ? v - 1 : v;
}
