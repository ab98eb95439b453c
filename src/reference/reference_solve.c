/* The CPU reference solver: analytic form factors, visibility by polygon
 * clipping (ray-cast where clipping gives up), Gauss-Seidel (thesis
 * 2.2.1-2.2.2; reference.h). */
#include "reference/reference.h"

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "reference/ff_kernel.h"
#include "reference/ref_parallel.h"
#include "scene/scene_luminaire.h"

#define DEFAULT_RAYS 16
/* Rays visibility: every pair's visible fraction is this many rays'. */
#define DEFAULT_RAYS_EVERY_PAIR 64
/* Gather solver: rays per element for light from non-emitters. */
#define DEFAULT_GATHER_RAYS 256
#define DEFAULT_RESIDUAL 1e-6
#define DEFAULT_MAX_SWEEPS 100000
#define MAX_RAYS 65536
#define MAX_CELL_POINTS 8
#define MAX_THREADS 256

double ref_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Bilinear map of scene.h over world corners c[0..3]. */
static vec3 bilinear(const vec3 c[4], double s, double t)
{
    return v3_lerp(v3_lerp(c[0], c[1], s), v3_lerp(c[3], c[2], s), t);
}

void ref_geometry_destroy(ref_geometry **geometry)
{
    if (!geometry || !*geometry)
        return;
    ref_geometry *g = *geometry;
    free(g->quads);
    free(g->surface_first);
    free(g->surface_elements);
    free(g->surface_of);
    free(g->recv);
    free(g->origin);
    free(g->normal);
    free(g->cell);
    ref_rays_destroy(&g->bvh);
    free(g);
    *geometry = NULL;
}

xrad_status ref_geometry_create(const xrad_scene *scene, double time, uint32_t rays, bool bvh,
                                ref_geometry **out, xrad_error *err)
{
    *out = NULL;
    ref_geometry *g = calloc(1, sizeof *g);
    if (!g)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reference: out of memory");
    uint32_t ns = scene->surface_count, ne = scene->element_count;
    g->surface_count = ns;
    g->element_count = ne;
    g->rays = rays;
    size_t sa = ns ? ns : 1, ea = ne ? ne : 1;
    g->quads = malloc(sa * sizeof *g->quads);
    g->surface_first = malloc(sa * sizeof *g->surface_first);
    g->surface_elements = malloc(sa * sizeof *g->surface_elements);
    g->surface_of = malloc(ea * sizeof *g->surface_of);
    g->recv = malloc(ea * sizeof *g->recv);
    g->origin = malloc(ea * sizeof *g->origin);
    g->normal = malloc(ea * sizeof *g->normal);
    g->cell = malloc(ea * sizeof *g->cell);
    if (!g->quads || !g->surface_first || !g->surface_elements || !g->surface_of || !g->recv ||
        !g->origin || !g->normal || !g->cell) {
        ref_geometry_destroy(&g);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reference: out of memory for %u elements", ne);
    }

    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t s = 0; s < ns; s++) {
        const surface *sf = &scene->surfaces[s];
        vec3 corners[4];
        scene_surface_world(scene, s, time, corners, NULL);
        if (!ref_quad_init(&g->quads[s], corners)) {
            ref_geometry_destroy(&g);
            return xrad_fail(err, XRAD_ERROR_INPUT, "%s: surface '%s' has zero area at time %g",
                             scene->path, sf->name, time);
        }
        for (int k = 0; k < 4; k++) {
            lo = v3(fmin(lo.x, corners[k].x), fmin(lo.y, corners[k].y), fmin(lo.z, corners[k].z));
            hi = v3(fmax(hi.x, corners[k].x), fmax(hi.y, corners[k].y), fmax(hi.z, corners[k].z));
        }
        g->surface_first[s] = sf->first_element;
        g->surface_elements[s] = sf->nu * sf->nv;
    }
    g->scale = ns ? v3_len(v3_sub(hi, lo)) : 1;
    /* Occluder culling treats a quad within this of a visibility pyramid as
     * touching it, and clipping a vertex within this of a shadow plane as on
     * it: far above the rounding of the plane tests (1e-16 of the scene),
     * far below any feature of a scene, so a form factor moves by about
     * 1e-9 of itself at most. */
    g->tol = 1e-9 * g->scale;

    for (uint32_t e = 0; e < ne; e++) {
        const element *el = &scene->elements[e];
        const surface *sf = &scene->surfaces[el->surface];
        const ref_quad *q = &g->quads[el->surface];
        double s0, s1, t0, t1;
        scene_param_range(el->i, el->i, sf->nu, &s0, &s1);
        scene_param_range(el->j, el->j, sf->nv, &t0, &t1);
        /* The receiver point is the centroid of the element's cell, as
         * in the GPU methods (spirv/shooting.glsl): an element's value is
         * the mean over its cell by the midpoint rule, the quantity every
         * method shoots from and the metrics compare. The sample point
         * itself lies on the surface's edge for the outer rows, where the
         * point value is discontinuous at a concave corner (the
         * neighbour's form factor drops from 1/2 just inside to 0 in its
         * plane) and, on a planarised quad, may sit a hair behind the
         * neighbour (cornell-box's floor along the red wall read 0). */
        double sc, tc;
        scene_cell_centre(sf, el->i, el->j, &sc, &tc);
        vec3 p = bilinear(q->p, sc, tc);
        g->surface_of[e] = el->surface;
        g->recv[e] = p;
        /* The receiver normal: a normal map's where there is one (Wallner
         * 3.3); rays still leave from the surface's front. */
        g->normal[e] = q->normal;
        if (scene->element_normal) {
            xform pose = scene_object_pose(scene, sf->object, time);
            g->normal[e] = v3_norm(xf_dir(&pose, scene->element_normal[e]));
        }
        g->origin[e] = v3_mad(p, q->normal, REF_RAY_HAIR * g->scale);
        g->cell[e][0] = bilinear(q->p, s0, t0);
        g->cell[e][1] = bilinear(q->p, s1, t0);
        g->cell[e][2] = bilinear(q->p, s1, t1);
        g->cell[e][3] = bilinear(q->p, s0, t1);
    }
    xrad_status st;
    if (bvh && (st = ref_rays_create(g->quads, ns, g->scale, &g->bvh, err))) {
        ref_geometry_destroy(&g);
        return st;
    }
    *out = g;
    return XRAD_OK;
}

double ref_visible_fraction(const ref_geometry *g, const ref_receiver *r, uint32_t target,
                            const vec3 *poly, vec3 poly_normal, uint64_t seed, const uint32_t *cand,
                            uint32_t count)
{
    vec3 p = r->p, n = r->n;
    double seen = 0, total = 0;
    uint32_t open = 0;
    for (uint32_t k0 = 0; k0 < g->rays; k0 += REF_RAYS_BATCH) {
        uint32_t m = g->rays - k0 < REF_RAYS_BATCH ? g->rays - k0 : REF_RAYS_BATCH;
        vec3 to[REF_RAYS_BATCH];
        bool blocked[REF_RAYS_BATCH];
        for (uint32_t k = 0; k < m; k++) {
            double s, t;
            ref_sample(seed, k0 + k, g->rays, &s, &t);
            to[k] = bilinear(poly, s, t);
        }
        if (g->bvh) {
            ref_rays_occluded(g->bvh, r->surface, target, r->o, to, m, blocked);
        } else {
            for (uint32_t k = 0; k < m; k++) {
                blocked[k] = false;
                for (uint32_t c = 0; c < count && !blocked[k]; c++)
                    blocked[k] = ref_segment_hits_quad(&g->quads[cand[c]], r->o, to[k]);
            }
        }
        for (uint32_t k = 0; k < m; k++) {
            vec3 d = v3_sub(to[k], p);
            double r2 = v3_dot(d, d);
            double w =
                r2 > 0 ? fmax(0.0, v3_dot(n, d)) * fmax(0.0, -v3_dot(poly_normal, d)) / (r2 * r2)
                       : 0;
            total += w;
            seen += blocked[k] ? 0 : w;
            open += !blocked[k];
        }
    }
    /* No sample where the integrand is positive (a sliver of the polygon
     * above the tangent plane): fall back to the plain fraction. */
    return total > 0 ? seen / total : (double)open / g->rays;
}

bool ref_receiver_pressed(const ref_geometry *g, const ref_receiver *r)
{
    /* A segment across the surface's plane at r->p, REF_CONTACT_TOL of the
     * scene either side: it meets a face pressed against r->p. */
    vec3 n = g->quads[r->surface].normal;
    double h = REF_CONTACT_TOL * g->scale;
    vec3 a = v3_mad(r->p, n, -h), b = v3_mad(r->p, n, h);
    if (g->bvh)
        return ref_rays_touching(g->bvh, r->surface, n, a, v3_sub(b, a));
    for (uint32_t k = 0; k < g->surface_count; k++)
        if (k != r->surface && v3_dot(g->quads[k].normal, n) < -REF_CONTACT_COS &&
            ref_segment_hits_quad(&g->quads[k], a, b))
            return true;
    return false;
}

/* Where clipping gives up, and every pair with rays visibility. */
static double visibility(const ref_geometry *g, const ref_receiver *r, uint32_t j,
                         const uint32_t *cand, uint32_t count)
{
    /* The shooter's cosine is its surface's (xrad.h normal_map). */
    return ref_visible_fraction(g, r, g->surface_of[j], g->cell[j],
                                g->quads[g->surface_of[j]].normal, ref_pair_seed(r->element, j),
                                cand, count);
}

void ref_row_scratch_finish(ref_row_scratch *s)
{
    free(s->cand);
    free(s->cell_cand);
    free(s->cone);
    free(s->pieces);
    free(s->row);
    *s = (ref_row_scratch){0};
}

bool ref_row_scratch_init(ref_row_scratch *s, const ref_geometry *g)
{
    size_t ns = g->surface_count ? g->surface_count : 1;
    s->cand = malloc(ns * sizeof *s->cand);
    s->cell_cand = malloc(ns * sizeof *s->cell_cand);
    s->cone = malloc(ns * sizeof *s->cone);
    s->pieces = malloc(sizeof *s->pieces);
    s->row = malloc((g->element_count ? g->element_count : 1) * sizeof *s->row);
    if (!s->cand || !s->cell_cand || !s->cone || !s->pieces || !s->row) {
        ref_row_scratch_finish(s);
        return false;
    }
    return true;
}

double ref_form_factor_row(const ref_geometry *g, const ref_receiver *r, float *row,
                           ref_row_scratch *scratch)
{
    memset(row, 0, (size_t)g->element_count * sizeof *row);
    if (ref_receiver_pressed(g, r))
        return 0;
    uint32_t own = r->surface;
    vec3 p = r->p, n = r->n, o = r->o;
    uint32_t *cand = scratch->cand, *cell_cand = scratch->cell_cand;
    ref_cone *cone = scratch->cone;
    double sum = 0;
    for (uint32_t S = 0; S < g->surface_count; S++) {
        const ref_quad *qs = &g->quads[S];
        /* Same surface: planar, F = 0. A surface whose front does not face
         * p, or that lies wholly below p's tangent plane, gives 0 for every
         * cell; the kernel would find the same, cell by cell. */
        if (S == own || !(v3_dot(qs->normal, v3_sub(p, qs->p[0])) > 0))
            continue;
        bool above = false;
        for (int k = 0; k < 4; k++)
            above = above || v3_dot(n, v3_sub(qs->p[k], p)) > 0;
        if (!above)
            continue;
        uint32_t first = g->surface_first[S], last = first + g->surface_elements[S];
        if (g->bvh) {
            /* Rays: every cell through the BVH, no candidate culling (which
             * loops over every quad for every surface, O(S^2) a row). */
            for (uint32_t j = first; j < last; j++) {
                double f = ref_ff_point_polygon(p, n, g->cell[j], 4);
                if (!(f > 0))
                    continue;
                row[j] = (float)(f * visibility(g, r, j, NULL, 0));
                sum += row[j];
            }
            continue;
        }
        /* Occluders: quads that may meet some segment from the origin to S.
         * Neither i's own planar surface nor S itself can block such a
         * segment (it leaves one and ends on the other). */
        uint32_t nc = 0;
        for (uint32_t k = 0; k < g->surface_count; k++)
            if (k != own && k != S && ref_quad_may_block(&g->quads[k], o, qs->p, g->tol))
                cand[nc++] = k;
        /* Every cell of S lies in S's plane, so one cone per candidate
         * serves them all. */
        bool clip = true;
        for (uint32_t c = 0; c < nc; c++)
            if (!ref_cone_init(&cone[c], &g->quads[cand[c]], p, qs->p[0], qs->normal, g->tol))
                clip = false;
        for (uint32_t j = first; j < last; j++) {
            double f = ref_ff_point_polygon(p, n, g->cell[j], 4);
            if (!(f > 0))
                continue;
            if (nc && !(clip && ref_ff_point_visible(p, n, g->cell[j], 4, f, cone, nc, g->tol,
                                                     scratch->pieces, &f))) {
                /* Clipping gave up: rays, against the candidates that may
                 * block this cell. */
                uint32_t m = 0;
                for (uint32_t c = 0; c < nc; c++)
                    if (ref_quad_may_block(&g->quads[cand[c]], o, g->cell[j], g->tol))
                        cell_cand[m++] = cand[c];
                if (m)
                    f *= visibility(g, r, j, cell_cand, m);
            }
            row[j] = (float)f;
            sum += row[j];
        }
    }
    return sum;
}

typedef struct build_job {
    const ref_geometry *g;
    float *F;
    double *row_sum;
    ref_row_scratch *scratch; /* per thread */
    uint32_t cell_points;     /* xrad_reference_desc.cell_points */
} build_job;

/* Row i: the form factors from its cell's centre, or with cell_points k
 * > 1 their mean over k x k points of its cell (the midpoints of a k x k
 * split of its parameters), so that B_i is its cell's mean by that rule
 * rather than its centre's value: the quantity conservation gives the
 * shooting methods (README "Accuracy"). */
static void build_row(void *user, uint32_t thread, uint32_t i)
{
    build_job *job = user;
    const ref_geometry *g = job->g;
    float *row = job->F + (size_t)i * g->element_count;
    ref_row_scratch *scratch = &job->scratch[thread];
    ref_receiver r = ref_receiver_of(g, i);
    uint32_t k = job->cell_points;
    if (k <= 1) {
        job->row_sum[i] = ref_form_factor_row(g, &r, row, scratch);
        return;
    }
    double sum = 0;
    for (uint32_t e = 0; e < g->element_count; e++)
        row[e] = 0;
    vec3 lift = v3_scale(g->quads[r.surface].normal, REF_RAY_HAIR * g->scale);
    for (uint32_t b = 0; b < k; b++)
        for (uint32_t a = 0; a < k; a++) {
            r.p = bilinear(g->cell[i], (a + 0.5) / k, (b + 0.5) / k);
            r.o = v3_add(r.p, lift);
            sum += ref_form_factor_row(g, &r, scratch->row, scratch);
            for (uint32_t e = 0; e < g->element_count; e++)
                row[e] += scratch->row[e] / (float)(k * k);
        }
    job->row_sum[i] = sum / (k * k);
}

static uint32_t default_threads(void)
{
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    return cores > 0 ? (uint32_t)cores : 1;
}

static xrad_status check_desc(const xrad_scene *scene, const xrad_reference_desc *in,
                              xrad_reference_desc *d, xrad_error *err)
{
    *d = in ? *in : (xrad_reference_desc){0};
    if (!isfinite(d->time))
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: time is not finite");
    if (!(d->residual >= 0) || !isfinite(d->residual))
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: residual %g is not a finite value >= 0",
                         d->residual);
    if (d->rays > MAX_RAYS)
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: %u rays per pair (at most %u)", d->rays,
                         MAX_RAYS);
    if ((unsigned)d->visibility > XRAD_VISIBILITY_RAYS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "reference: visibility %d is none of auto, clip, rays",
                         (int)d->visibility);
    if ((unsigned)d->solver > XRAD_REFERENCE_SOLVER_GATHER)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "reference: solver %d is none of auto, dense, gather", (int)d->solver);
    if (d->gather_rays > MAX_RAYS)
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: %u gather rays per element (at "
                         "most %u)", d->gather_rays, MAX_RAYS);
    if (d->cell_points > MAX_CELL_POINTS)
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: cell_points %u is more than %u a side",
                         d->cell_points, MAX_CELL_POINTS);
    uint64_t n = scene->element_count;
    if (d->solver == XRAD_REFERENCE_SOLVER_AUTO)
        d->solver = n * n * sizeof(float) > REF_MATRIX_MAX_BYTES ? XRAD_REFERENCE_SOLVER_GATHER
                                                                 : XRAD_REFERENCE_SOLVER_DENSE;
    if (d->solver == XRAD_REFERENCE_SOLVER_GATHER && d->visibility == XRAD_VISIBILITY_CLIP)
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: the gather solver sees by rays "
                         "only (visibility clip needs the dense solver)");
    if (d->solver == XRAD_REFERENCE_SOLVER_GATHER && d->cell_points > 1)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "reference: cell_points %u needs the dense "
                         "solver (the gather solver takes each cell's centre)",
                         d->cell_points);
    d->cell_points = d->cell_points ? d->cell_points : 1;
    d->gather_rays = d->gather_rays ? d->gather_rays : DEFAULT_GATHER_RAYS;
    bool rays = d->visibility == XRAD_VISIBILITY_RAYS ||
                d->solver == XRAD_REFERENCE_SOLVER_GATHER ||
                (d->visibility == XRAD_VISIBILITY_AUTO &&
                 scene->surface_count > XRAD_REFERENCE_CLIP_SURFACES);
    d->visibility = rays ? XRAD_VISIBILITY_RAYS : XRAD_VISIBILITY_CLIP;
    d->rays = d->rays ? d->rays : rays ? DEFAULT_RAYS_EVERY_PAIR : DEFAULT_RAYS;
    d->residual = d->residual > 0 ? d->residual : DEFAULT_RESIDUAL;
    d->max_sweeps = d->max_sweeps ? d->max_sweeps : DEFAULT_MAX_SWEEPS;
    d->threads = d->threads ? d->threads : default_threads();
    d->threads = d->threads < MAX_THREADS ? d->threads : MAX_THREADS;
    return XRAD_OK;
}

xrad_status ref_form_factor_matrix(const xrad_scene *scene, const xrad_reference_desc *desc,
                                   float **F, xrad_reference_stats *stats, xrad_error *err)
{
    *F = NULL;
    xrad_reference_desc d;
    xrad_status st = check_desc(scene, desc, &d, err);
    if (st)
        return st;
    uint64_t n = scene->element_count;
    uint64_t bytes = n * n * sizeof(float);
    if (bytes > REF_MATRIX_MAX_BYTES)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: %llu elements need a %.2f GiB form factor matrix; the reference "
                         "solver holds at most %.0f GiB (lower the element density)",
                         scene->path, (unsigned long long)n, bytes / 1073741824.0,
                         REF_MATRIX_MAX_BYTES / 1073741824.0);
    double t0 = ref_seconds();
    ref_geometry *g = NULL;
    st = ref_geometry_create(scene, d.time, d.rays, d.visibility == XRAD_VISIBILITY_RAYS, &g, err);
    if (st)
        return st;

    uint32_t threads = d.threads < n ? d.threads : (uint32_t)(n ? n : 1);
    build_job job = {.g = g, .cell_points = d.cell_points};
    job.F = malloc(bytes ? bytes : 1);
    job.row_sum = malloc((n ? n : 1) * sizeof *job.row_sum);
    job.scratch = calloc(threads, sizeof *job.scratch);
    bool scratch_ok = job.scratch != NULL;
    for (uint32_t t = 0; scratch_ok && t < threads; t++)
        scratch_ok = ref_row_scratch_init(&job.scratch[t], g);
    if (!job.F || !job.row_sum || !scratch_ok) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM,
                       "reference: out of memory for the %llu x %llu form factor matrix (%.1f MiB)",
                       (unsigned long long)n, (unsigned long long)n, bytes / 1048576.0);
        goto done;
    }
    ref_parallel_for((uint32_t)n, threads, build_row, &job, d.progress, d.progress_user,
                     "form factors");

    if (stats) {
        stats->max_row_sum = 0;
        for (uint64_t i = 0; i < n; i++)
            stats->max_row_sum = fmax(stats->max_row_sum, job.row_sum[i]);
        stats->form_factor_seconds = ref_seconds() - t0;
        stats->visibility = d.visibility;
        stats->rays = d.rays;
    }
    *F = job.F;
    job.F = NULL;
done:
    free(job.F);
    free(job.row_sum);
    for (uint32_t t = 0; job.scratch && t < threads; t++)
        ref_row_scratch_finish(&job.scratch[t]);
    free(job.scratch);
    ref_geometry_destroy(&g);
    return st;
}

double ref_sweep_residual(const xrad_reference_desc *d, const double max_delta[3],
                          const double max_b[3], double *reported)
{
    double residual = 0;
    for (int c = 0; c < 3; c++)
        if (max_b[c] > 0)
            residual = fmax(residual, max_delta[c] / max_b[c]);
    if (d->progress) {
        double f =
            residual > 0 ? fmin(1.0, fmax(0.0, log(residual) / log(d->residual))) : 1.0;
        if (f >= *reported + 0.01 || (f == 1.0 && *reported < 1.0)) {
            *reported = f;
            d->progress(d->progress_user, "solve", f);
        }
    }
    return residual;
}

/* E_i: element i's emission, and what it reflects of the luminaires'
 * direct irradiance lum[i] (lum NULL: none; scene_luminaire.h). */
static vec3 source(const xrad_scene *scene, const vec3 *lum, uint32_t i)
{
    vec3 e = scene->materials[scene->surfaces[scene->elements[i].surface].material].emission;
    return lum ? v3_add(e, v3_mul(scene_element_albedo(scene, i), lum[i])) : e;
}

/* Gauss-Seidel on B_i = E_i + rho_i sum_j F_ij B_j (thesis eq. 2.2.2; 2.2.2
 * "Global exchange"), RGB, starting from B = E. b holds 3 n doubles. The
 * residual of a sweep is max |delta B| / max |B| taken per channel, and the
 * largest of the three: a channel whose values are small next to another's
 * (emission spans many orders of magnitude) still converges relative to
 * its own scale. */
static void gauss_seidel(const xrad_scene *scene, const float *F, const xrad_reference_desc *d,
                         const vec3 *lum, double *b, xrad_reference_stats *stats)
{
    uint32_t n = scene->element_count;
    for (uint32_t i = 0; i < n; i++) {
        b[3 * i + 0] = source(scene, lum, i).x;
        b[3 * i + 1] = source(scene, lum, i).y;
        b[3 * i + 2] = source(scene, lum, i).z;
    }
    double residual = 0, reported = -1;
    uint32_t sweep = 0;
    while (sweep < d->max_sweeps) {
        sweep++;
        double max_delta[3] = {0, 0, 0}, max_b[3] = {0, 0, 0};
        for (uint32_t i = 0; i < n; i++) {
            const vec3 e = source(scene, lum, i);
            const float *row = F + (size_t)i * n;
            double r = 0, gr = 0, bl = 0;
            for (uint32_t j = 0; j < n; j++) {
                double f = row[j];
                r += f * b[3 * j + 0];
                gr += f * b[3 * j + 1];
                bl += f * b[3 * j + 2];
            }
            vec3 rho = scene_element_albedo(scene, i);
            double nb[3] = {e.x + rho.x * r, e.y + rho.y * gr, e.z + rho.z * bl};
            for (int c = 0; c < 3; c++) {
                max_delta[c] = fmax(max_delta[c], fabs(nb[c] - b[3 * i + c]));
                max_b[c] = fmax(max_b[c], fabs(nb[c]));
                b[3 * i + c] = nb[c];
            }
        }
        residual = ref_sweep_residual(d, max_delta, max_b, &reported);
        if (residual < d->residual)
            break;
    }
    if (stats) {
        stats->sweeps = sweep;
        stats->residual = residual;
    }
}

xrad_status xrad_reference_solve(const xrad_scene *scene, const xrad_reference_desc *desc,
                                 xrad_atlas *atlas, xrad_reference_stats *stats,
                                 xrad_error *err)
{
    if (!scene || !atlas)
        return xrad_fail(err, XRAD_ERROR_INPUT, "reference: scene and atlas are required");
    if (atlas->width != scene->atlas_width || atlas->height != scene->atlas_height ||
        !atlas->rgba)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "reference: atlas is %ux%u, the scene's is %ux%u (use xrad_atlas_create)",
                         atlas->width, atlas->height, scene->atlas_width, scene->atlas_height);
    xrad_reference_desc d;
    xrad_status st = check_desc(scene, desc, &d, err);
    if (st)
        return st;
    xrad_reference_stats local = {.solver = d.solver};
    uint32_t n = scene->element_count;
    double *b = malloc(3 * (size_t)(n ? n : 1) * sizeof *b);
    /* The luminaires' direct light: analytic point-source irradiance with
     * ray-cast visibility (scene_luminaire.h). */
    vec3 *lum = scene->luminaire_count ? calloc(n ? n : 1, sizeof(vec3)) : NULL;
    if (!b || (scene->luminaire_count && !lum)) {
        free(b);
        free(lum);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reference: out of memory for %u elements", n);
    }
    if (lum)
        st = scene_luminaire_irradiance(scene, d.time, true, lum, err);
    if (!st && d.solver == XRAD_REFERENCE_SOLVER_GATHER) {
        st = ref_gather_solve(scene, &d, lum, b, &local, err);
    } else if (!st) {
        float *F = NULL;
        st = ref_form_factor_matrix(scene, &d, &F, &local, err);
        if (!st) {
            double t0 = ref_seconds();
            gauss_seidel(scene, F, &d, lum, b, &local);
            local.solve_seconds = ref_seconds() - t0;
        }
        free(F);
    }
    free(lum);
    if (st) {
        free(b);
        return st;
    }

    memset(atlas->rgba, 0, (size_t)atlas->width * atlas->height * 4 * sizeof *atlas->rgba);
    for (uint32_t i = 0; i < n; i++) {
        const element *e = &scene->elements[i];
        float *px = atlas->rgba + ((size_t)e->texel_y * atlas->width + e->texel_x) * 4;
        px[0] = (float)b[3 * i + 0];
        px[1] = (float)b[3 * i + 1];
        px[2] = (float)b[3 * i + 2];
        px[3] = 1;
    }
    free(b);
    if (stats)
        *stats = local;
    return XRAD_OK;
}
