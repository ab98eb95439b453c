/*
 * The CPU reference without a matrix (XRAD_REFERENCE_SOLVER_GATHER,
 * xrad.h): the dense solver's N^2 form factors are 2 GiB at 23,000
 * elements, and a 100K-triangle mesh has hundreds of thousands. Here each
 * element's row of B = E + rho F B (thesis eq. 2.2.2) is split where the
 * light comes from:
 *
 *  - from emitters (next-event estimation): for every emitting surface S,
 *    F(x_i -> S) by the analytic point-to-polygon kernel (ff_kernel.h)
 *    times its visible fraction from g->rays integrand-weighted rays
 *    (ref_visible_fraction), times S's exitance: D_i. The lights are few
 *    surfaces, so this is exact where nothing occludes and low-noise where
 *    something does;
 *  - from everything else: gather_rays rays from x_i, cosine-distributed
 *    about its normal (so each stands for F / gather_rays: the estimator of
 *    sum_j F_ij R_j is the mean of R over the hits), traced through
 *    Embree to the first surface; a front-side hit counts the reflected
 *    radiosity R = B - E of the element whose cell holds the hit point, a
 *    back side or nothing counts 0 (back sides are black, scene.h).
 *
 * Emission reaches a receiver through D only, reflection through the hits
 * only, so nothing is counted twice. The hits are traced once and kept
 * (4 bytes a ray); Gauss-Seidel then iterates
 *   B_i = E_i + rho_i (D_i + (1 / K) sum_k (B - E)_hit(i, k))
 * to the residual. Every sample pattern is seeded by the element's index:
 * the result does not depend on threads.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "reference/ff_kernel.h"
#include "reference/ref_parallel.h"
#include "reference/reference.h"

#define PI 3.14159265358979323846
#define NO_HIT UINT32_MAX
/* The kept hits may take this much memory. */
#define MAX_HIT_BYTES ((uint64_t)2 << 30)

typedef struct gather {
    const xrad_scene *scene;
    const ref_geometry *g;
    uint32_t rays; /* gather rays per element */
    uint32_t *emitters, emitter_count; /* surfaces with emission */
    uint32_t *hits; /* element_count x rays: the element hit, or NO_HIT */
    double *direct; /* 3 per element: D_i */
    uint32_t *front; /* per element: rays that met a surface's front */
} gather;

static const material *material_of(const xrad_scene *scene, uint32_t s)
{
    return &scene->materials[scene->surfaces[s].material];
}

/* Surface parameters (s, t) of world point x on surface S (scene.h): a
 * triangle's in closed form (t is the apex's barycentric coordinate, s
 * divides the rest), a quad's by Newton on its bilinear map, in the
 * quad's plane. Clamped to [0, 1]. */
static void surface_params(const xrad_scene *scene, const ref_quad *q, uint32_t S, vec3 x,
                           double *s, double *t)
{
    const vec3 *p = q->p;
    if (scene->surfaces[S].triangle) {
        vec3 n = q->normal;
        double area = v3_dot(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])), n);
        double b1 = v3_dot(v3_cross(v3_sub(p[2], x), v3_sub(p[0], x)), n) / area;
        double b2 = v3_dot(v3_cross(v3_sub(p[0], x), v3_sub(p[1], x)), n) / area;
        double b0 = 1 - b1 - b2;
        *t = b2;
        *s = b0 + b1 > 1e-12 ? b1 / (b0 + b1) : 0.5;
    } else {
        /* Plane axes: u along the first edge, w = n x u. */
        vec3 u = v3_norm(v3_sub(p[1], p[0])), w = v3_cross(q->normal, u);
        double ss = 0.5, tt = 0.5;
        for (int it = 0; it < 12; it++) {
            vec3 a = v3_lerp(p[0], p[1], ss), b = v3_lerp(p[3], p[2], ss);
            vec3 f = v3_sub(v3_lerp(a, b, tt), x);
            vec3 ds = v3_lerp(v3_sub(p[1], p[0]), v3_sub(p[2], p[3]), tt);
            vec3 dt = v3_sub(b, a);
            double j00 = v3_dot(ds, u), j01 = v3_dot(dt, u), j10 = v3_dot(ds, w),
                   j11 = v3_dot(dt, w), fu = v3_dot(f, u), fw = v3_dot(f, w);
            double det = j00 * j11 - j01 * j10;
            if (!(fabs(det) > 0))
                break;
            ss -= (j11 * fu - j01 * fw) / det;
            tt -= (j00 * fw - j10 * fu) / det;
            ss = fmin(1.5, fmax(-0.5, ss));
            tt = fmin(1.5, fmax(-0.5, tt));
        }
        *s = ss;
        *t = tt;
    }
    *s = fmin(1.0, fmax(0.0, *s));
    *t = fmin(1.0, fmax(0.0, *t));
}

/* The element of surface S whose cell holds parameters (s, t): the
 * nearest sample (scene.h: samples at i / (nu - 1)). */
static uint32_t element_at(const surface *sf, double s, double t)
{
    uint32_t i = (uint32_t)lround(s * (sf->nu - 1)), j = (uint32_t)lround(t * (sf->nv - 1));
    i = i < sf->nu ? i : sf->nu - 1;
    j = j < sf->nv ? j : sf->nv - 1;
    return sf->first_element + j * sf->nu + i;
}

static void trace_element(void *user, uint32_t thread, uint32_t i)
{
    (void)thread;
    gather *G = user;
    const ref_geometry *g = G->g;
    const xrad_scene *scene = G->scene;
    uint32_t own = g->surface_of[i];
    vec3 p = g->recv[i], n = g->normal[i], o = g->origin[i];
    ref_receiver rc = ref_receiver_of(g, i);
    if (ref_receiver_pressed(g, &rc)) {
        memset(&G->direct[3 * i], 0, 3 * sizeof G->direct[0]);
        for (uint32_t k = 0; k < G->rays; k++)
            G->hits[(size_t)i * G->rays + k] = NO_HIT;
        G->front[i] = 0;
        return;
    }

    /* Light from the emitters (next-event estimation). */
    double d[3] = {0, 0, 0};
    for (uint32_t k = 0; k < G->emitter_count; k++) {
        uint32_t S = G->emitters[k];
        const ref_quad *q = &g->quads[S];
        if (S == own || !(v3_dot(q->normal, v3_sub(p, q->p[0])) > 0))
            continue;
        double f = ref_ff_point_polygon(p, n, q->p, 4);
        if (!(f > 0))
            continue;
        f *= ref_visible_fraction(g, &rc, S, q->p, q->normal, ref_pair_seed(i, UINT32_MAX - S),
                                  NULL, 0);
        vec3 e = material_of(scene, S)->emission;
        d[0] += f * e.x;
        d[1] += f * e.y;
        d[2] += f * e.z;
    }
    memcpy(&G->direct[3 * i], d, sizeof d);

    /* Everything else: cosine-distributed rays about n (Malley: uniform
     * points of the unit disc lifted to the hemisphere), stratified. */
    vec3 a = fabs(n.x) < 0.6 ? v3(1, 0, 0) : v3(0, 1, 0);
    vec3 tx = v3_norm(v3_cross(a, n)), ty = v3_cross(n, tx);
    uint64_t seed = ref_pair_seed(i, i ^ 0x5bd1e995u);
    uint32_t *hits = G->hits + (size_t)i * G->rays, front = 0;
    for (uint32_t k0 = 0; k0 < G->rays; k0 += REF_RAYS_BATCH) {
        uint32_t m = G->rays - k0 < REF_RAYS_BATCH ? G->rays - k0 : REF_RAYS_BATCH;
        vec3 dir[REF_RAYS_BATCH];
        uint32_t quad[REF_RAYS_BATCH];
        double t[REF_RAYS_BATCH];
        for (uint32_t k = 0; k < m; k++) {
            double u1, u2;
            ref_sample(seed, k0 + k, G->rays, &u1, &u2);
            double r = sqrt(u1), phi = 2 * PI * u2;
            dir[k] = v3_add(v3_add(v3_scale(tx, r * cos(phi)), v3_scale(ty, r * sin(phi))),
                            v3_scale(n, sqrt(fmax(0.0, 1 - u1))));
        }
        ref_rays_closest(g->bvh, own, o, dir, m, quad, t);
        for (uint32_t k = 0; k < m; k++) {
            uint32_t S = quad[k];
            hits[k0 + k] = NO_HIT;
            if (S == NO_HIT || !(v3_dot(dir[k], g->quads[S].normal) < 0))
                continue; /* nothing, or a back side: black */
            double s, tt;
            surface_params(scene, &g->quads[S], S, v3_mad(o, dir[k], t[k]), &s, &tt);
            hits[k0 + k] = element_at(&scene->surfaces[S], s, tt);
            front++;
        }
    }
    G->front[i] = front;
}

/* Gauss-Seidel over the kept hits, from B = E + rho D. The residual as
 * the dense solver's (reference_solve.c): max |delta B| / max |B| per
 * channel, the largest of the three. */
static void solve(const gather *G, const xrad_reference_desc *d, double *b,
                  xrad_reference_stats *stats)
{
    const xrad_scene *scene = G->scene;
    uint32_t n = scene->element_count;
    for (uint32_t i = 0; i < n; i++) {
        const material *m = material_of(scene, scene->elements[i].surface);
        vec3 rho = scene_element_albedo(scene, i);
        b[3 * i + 0] = m->emission.x + rho.x * G->direct[3 * i + 0];
        b[3 * i + 1] = m->emission.y + rho.y * G->direct[3 * i + 1];
        b[3 * i + 2] = m->emission.z + rho.z * G->direct[3 * i + 2];
    }
    double residual = 0, reported = -1;
    uint32_t sweep = 0;
    while (sweep < d->max_sweeps) {
        sweep++;
        double max_delta[3] = {0, 0, 0}, max_b[3] = {0, 0, 0};
        for (uint32_t i = 0; i < n; i++) {
            const material *m = material_of(scene, scene->elements[i].surface);
            const uint32_t *hits = G->hits + (size_t)i * G->rays;
            double r[3] = {0, 0, 0};
            for (uint32_t k = 0; k < G->rays; k++) {
                uint32_t j = hits[k];
                if (j == NO_HIT)
                    continue;
                vec3 e = material_of(scene, scene->elements[j].surface)->emission;
                r[0] += b[3 * j + 0] - e.x;
                r[1] += b[3 * j + 1] - e.y;
                r[2] += b[3 * j + 2] - e.z;
            }
            vec3 rho = scene_element_albedo(scene, i);
            double albedo[3] = {rho.x, rho.y, rho.z};
            double emission[3] = {m->emission.x, m->emission.y, m->emission.z};
            for (int c = 0; c < 3; c++) {
                double nb = emission[c] + albedo[c] * (G->direct[3 * i + c] + r[c] / G->rays);
                max_delta[c] = fmax(max_delta[c], fabs(nb - b[3 * i + c]));
                max_b[c] = fmax(max_b[c], fabs(nb));
                b[3 * i + c] = nb;
            }
        }
        residual = ref_sweep_residual(d, max_delta, max_b, &reported);
        if (residual < d->residual)
            break;
    }
    stats->sweeps = sweep;
    stats->residual = residual;
}

xrad_status ref_gather_solve(const xrad_scene *scene, const xrad_reference_desc *d,
                             const vec3 *lum, double *b, xrad_reference_stats *stats,
                             xrad_error *err)
{
    uint64_t n = scene->element_count;
    uint64_t hit_bytes = n * d->gather_rays * sizeof(uint32_t);
    if (hit_bytes > MAX_HIT_BYTES)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: %llu elements x %u gather rays need %.2f GiB of hits; the "
                         "reference holds at most %.0f GiB (fewer gather rays, or a lower "
                         "element density)",
                         scene->path, (unsigned long long)n, d->gather_rays,
                         hit_bytes / 1073741824.0, MAX_HIT_BYTES / 1073741824.0);
    double t0 = ref_seconds();
    ref_geometry *g = NULL;
    xrad_status st = ref_geometry_create(scene, d->time, d->rays, true, &g, err);
    if (st)
        return st;
    gather G = {.scene = scene, .g = g, .rays = d->gather_rays};
    size_t na = n ? n : 1;
    G.emitters = malloc((scene->surface_count ? scene->surface_count : 1) * sizeof *G.emitters);
    G.hits = malloc(hit_bytes ? hit_bytes : 1);
    G.direct = malloc(3 * na * sizeof *G.direct);
    G.front = malloc(na * sizeof *G.front);
    if (!G.emitters || !G.hits || !G.direct || !G.front) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM,
                       "reference: out of memory for %llu elements x %u gather rays (%.1f MiB)",
                       (unsigned long long)n, d->gather_rays, hit_bytes / 1048576.0);
        goto done;
    }
    for (uint32_t S = 0; S < scene->surface_count; S++) {
        vec3 e = material_of(scene, S)->emission;
        if (e.x > 0 || e.y > 0 || e.z > 0)
            G.emitters[G.emitter_count++] = S;
    }
    ref_parallel_for((uint32_t)n, d->threads, trace_element, &G, d->progress, d->progress_user,
                     "gather rays");
    for (uint64_t i = 0; lum && i < n; i++) {
        G.direct[3 * i + 0] += lum[i].x;
        G.direct[3 * i + 1] += lum[i].y;
        G.direct[3 * i + 2] += lum[i].z;
    }
    stats->max_row_sum = 0;
    for (uint64_t i = 0; i < n; i++)
        stats->max_row_sum = fmax(stats->max_row_sum, (double)G.front[i] / G.rays);
    stats->form_factor_seconds = ref_seconds() - t0;
    stats->visibility = XRAD_VISIBILITY_RAYS;
    stats->rays = d->rays;
    stats->gather_rays = d->gather_rays;
    double t1 = ref_seconds();
    solve(&G, d, b, stats);
    stats->solve_seconds = ref_seconds() - t1;
done:
    free(G.emitters);
    free(G.hits);
    free(G.direct);
    free(G.front);
    ref_geometry_destroy(&g);
    return st;
}
