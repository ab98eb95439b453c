/* Buried elements: receivers that lie on another surface's front face,
 * face to face (the bottom of a box standing on a floor, the floor under
 * it). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/quad_bvh.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

#define SCENE_PI 3.14159265358979323846

/* x inside the convex planar quad c (normal n) by at least `margin` m
 * from every edge (a negative margin admits points that far outside). */
static bool inside_quad(const vec3 c[4], vec3 n, vec3 x, double margin)
{
    for (int k = 0; k < 4; k++) {
        vec3 a = c[k], b = c[(k + 1) & 3];
        if (v3_dot(v3_cross(v3_sub(b, a), v3_sub(x, a)), n) < margin * v3_len(v3_sub(b, a)))
            return false;
    }
    return true;
}

/* Every surface's world corners (4 each) and normal at time t, malloc'd
 * into *corners and *normals (free both). */
static xrad_status world_quads(const xrad_scene *scene, double t, vec3 **corners,
                               vec3 **normals, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    *corners = malloc((ns ? ns : 1) * sizeof(vec3[4]));
    *normals = malloc((ns ? ns : 1) * sizeof(vec3));
    if (!*corners || !*normals) {
        free(*corners);
        free(*normals);
        *corners = *normals = NULL;
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for %u surfaces' contact",
                         scene->path, ns);
    }
    for (uint32_t s = 0; s < ns; s++)
        scene_surface_world(scene, s, t, &(*corners)[4 * s], &(*normals)[s]);
    return XRAD_OK;
}

/* Whether surface c covers elements of surface r (face to face, in r's
 * plane) and which: marks them in `buried`. */
static void cover_pair(const xrad_scene *scene, uint32_t r, uint32_t c, const vec3 *corners,
                       const vec3 *normals, double time, double tol, uint8_t *buried,
                       uint32_t *count)
{
    const surface *sr = &scene->surfaces[r];
    vec3 nr = normals[r], pr = corners[4 * r];
    if (!(v3_dot(normals[c], nr) < -0.999))
        return;
    /* In front of the receiver's plane by at most tol, behind it by no
     * more than rounding: face to face. A cover behind it (the two faces
     * of a slab 1e-4 m thin, back to back) is not one. */
    for (int k = 0; k < 4; k++) {
        double d = v3_dot(v3_sub(corners[4 * c + k], pr), nr);
        if (!(d <= tol && d >= -1e-3 * tol))
            return;
    }
    xform pose = scene_object_pose(scene, sr->object, time);
    uint8_t by = scene->objects[scene->surfaces[c].object].dynamic ? 2 : 1;
    for (uint32_t k = 0; k < sr->nu * sr->nv; k++) {
        uint32_t e = sr->first_element + k;
        vec3 x = xf_point(&pose, scene_element_centroid(sr, &scene->elements[e]));
        if ((!buried[e] || by < buried[e]) && inside_quad(&corners[4 * c], normals[c], x, tol)) {
            *count += !buried[e];
            buried[e] = by;
        }
    }
}

/* A surface's world box, for the sweep over pairs. */
typedef struct swept {
    double lo[3], hi[3];
    uint32_t surface;
} swept;

static int swept_cmp(const void *a, const void *b)
{
    double x = ((const swept *)a)->lo[0], y = ((const swept *)b)->lo[0];
    return x < y ? -1 : x > y;
}

/* Calls visit(user, a, b) for every pair of surfaces whose world boxes,
 * grown by tol, overlap: a cover lies in its receiver's plane over the
 * receiver, so their boxes overlap. A sweep over x rather than every
 * pair, which a mesh of 100,000 faces made 10^10 and 15 s before every
 * solve. */
static xrad_status contact_pairs(const xrad_scene *scene, const vec3 *corners, double tol,
                                 void (*visit)(void *, uint32_t, uint32_t), void *user,
                                 xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    swept *box = malloc((ns ? ns : 1) * sizeof *box);
    if (!box)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for contact", scene->path);
    for (uint32_t s = 0; s < ns; s++) {
        box[s].surface = s;
        for (int a = 0; a < 3; a++) {
            box[s].lo[a] = INFINITY;
            box[s].hi[a] = -INFINITY;
        }
        for (int k = 0; k < 4; k++) {
            double p[3] = {corners[4 * s + k].x, corners[4 * s + k].y, corners[4 * s + k].z};
            for (int a = 0; a < 3; a++) {
                box[s].lo[a] = fmin(box[s].lo[a], p[a] - tol);
                box[s].hi[a] = fmax(box[s].hi[a], p[a] + tol);
            }
        }
    }
    qsort(box, ns, sizeof *box, swept_cmp);
    for (uint32_t i = 0; i < ns; i++) {
        for (uint32_t j = i + 1; j < ns && box[j].lo[0] <= box[i].hi[0]; j++) {
            if (box[j].lo[1] > box[i].hi[1] || box[i].lo[1] > box[j].hi[1] ||
                box[j].lo[2] > box[i].hi[2] || box[i].lo[2] > box[j].hi[2])
                continue;
            visit(user, box[i].surface, box[j].surface);
        }
    }
    free(box);
    return XRAD_OK;
}

typedef struct bury_job {
    const xrad_scene *scene;
    const vec3 *corners, *normals;
    double time, tol;
    uint8_t *buried;
    uint32_t *count;
} bury_job;

static void bury_pair(void *user, uint32_t a, uint32_t b)
{
    bury_job *j = user;
    cover_pair(j->scene, a, b, j->corners, j->normals, j->time, j->tol, j->buried, j->count);
    cover_pair(j->scene, b, a, j->corners, j->normals, j->time, j->tol, j->buried, j->count);
}

xrad_status scene_find_buried(const xrad_scene *scene, double time, double tol, uint8_t *buried,
                              uint32_t *count, xrad_error *err)
{
    *count = 0;
    for (uint32_t e = 0; e < scene->element_count; e++)
        buried[e] = 0;
    vec3 *corners, *normals;
    xrad_status st = world_quads(scene, time, &corners, &normals, err);
    if (st)
        return st;
    bury_job job = {scene, corners, normals, time, tol, buried, count};
    st = contact_pairs(scene, corners, tol, bury_pair, &job, err);
    free(corners);
    free(normals);
    return st;
}

/* Whether the line o + t d meets the quad c (normal n) at a t within
 * (tmin, tmax); *t receives it. */
static bool quad_hit(const vec3 c[4], vec3 n, vec3 o, vec3 d, double tmin, double tmax,
                     double *t)
{
    double along = v3_dot(n, d);
    if (along == 0)
        return false;
    *t = v3_dot(n, v3_sub(c[0], o)) / along;
    return *t > tmin && *t < tmax && inside_quad(c, n, v3_mad(o, d, *t), 0.0);
}

/* The parameters (u, v) of y on the planar quad c (surface_point's
 * bilinear map), by Newton's method, clamped to [0, 1]. */
static void quad_params(const vec3 c[4], vec3 y, double *u, double *v)
{
    double s = 0.5, t = 0.5;
    for (int it = 0; it < 8; it++) {
        vec3 a = v3_lerp(c[0], c[1], s), b = v3_lerp(c[3], c[2], s);
        vec3 r = v3_sub(y, v3_lerp(a, b, t));
        vec3 ds = v3_lerp(v3_sub(c[1], c[0]), v3_sub(c[2], c[3]), t), dt = v3_sub(b, a);
        double a11 = v3_dot(ds, ds), a12 = v3_dot(ds, dt), a22 = v3_dot(dt, dt);
        double b1 = v3_dot(ds, r), b2 = v3_dot(dt, r), det = a11 * a22 - a12 * a12;
        if (!(det > 0))
            break;
        s += (a22 * b1 - a12 * b2) / det;
        t += (a11 * b2 - a12 * b1) / det;
    }
    *u = fmin(fmax(s, 0.0), 1.0);
    *v = fmin(fmax(t, 0.0), 1.0);
}

/* What a ray of an element meets (enclosure): the element it sees, or: */
#define RAY_OPEN UINT32_MAX         /* nothing: it leaves the scene */
#define RAY_BACK (UINT32_MAX - 1)   /* a back face */
#define RAY_HIDDEN (UINT32_MAX - 2) /* a front face whose elements it cannot see */
#define RAY_SEES(h) ((h) < RAY_HIDDEN)
#define RAY_COUNT 25

/* A ray's query through the BVH: the nearest hit, or any hit but `skip`'s. */
typedef struct ray_query {
    const scene_rays *rs;
    vec3 o, d;
    double tmin, tmax;
    uint32_t skip;
    int32_t best;
    double best_t;
} ray_query;

static bool counts(const scene_rays *rs, uint32_t s)
{
    return rs->dynamic_too || !rs->scene->objects[rs->scene->surfaces[s].object].dynamic;
}

static bool visit_nearest(void *user, uint32_t s, double *tmax)
{
    ray_query *q = user;
    double t;
    /* Up to and including the best so far: at equal t the lower index
     * wins, as a loop over the surfaces in order finds it. */
    if (!counts(q->rs, s) || !quad_hit(&q->rs->corners[4 * s], q->rs->normals[s], q->o, q->d,
                                       q->tmin, nextafter(q->best_t, INFINITY), &t))
        return false;
    if (t < q->best_t || (t == q->best_t && (int32_t)s < q->best)) {
        q->best = (int32_t)s;
        q->best_t = t;
        *tmax = t;
    }
    return false;
}

/* The nearest surface the ray o + t dir (t > tmin) meets, or -1; *back is
 * set when the ray meets its back face, *at to the point met. Dynamic
 * surfaces count only with rs->dynamic_too. */
static int32_t nearest_hit(const scene_rays *rs, vec3 o, vec3 dir, double tmin, bool *back,
                           vec3 *at)
{
    ray_query q = {.rs = rs, .o = o, .d = dir, .tmin = tmin, .best = -1, .best_t = INFINITY};
    quad_bvh_ray(&rs->bvh, o, dir, tmin, INFINITY, visit_nearest, &q);
    if (q.best >= 0) {
        *back = v3_dot(rs->normals[q.best], dir) > 0;
        *at = v3_mad(o, dir, q.best_t);
    }
    return q.best;
}

static bool visit_blocking(void *user, uint32_t s, double *tmax)
{
    (void)tmax;
    ray_query *q = user;
    double t;
    return s != q->skip && counts(q->rs, s) &&
           quad_hit(&q->rs->corners[4 * s], q->rs->normals[s], q->o, q->d, q->tmin, q->tmax, &t);
}

bool scene_rays_blocked(const scene_rays *rs, vec3 a, vec3 b, uint32_t skip)
{
    ray_query q = {.rs = rs, .o = a, .d = v3_sub(b, a), .tmin = 1e-9, .tmax = 1 - 1e-9,
                   .skip = skip};
    return quad_bvh_ray(&rs->bvh, a, q.d, q.tmin, q.tmax, visit_blocking, &q);
}

/* The element of surface s whose receiver point y (on s, world) can see:
 * of the samples around y, nearest first, the first whose cell centroid
 * no surface hides from y (just off the surface, so that a block standing
 * on it hides the cells on its far side: a cabinet against a wall without
 * a back face closes a pocket of wall and floor, whose cells straddling
 * its edge lie outside). RAY_HIDDEN if none. */
static uint32_t element_seen(const scene_rays *rs, uint32_t s, vec3 y)
{
    const xrad_scene *scene = rs->scene;
    const surface *sf = &scene->surfaces[s];
    double u, v;
    quad_params(&rs->corners[4 * s], y, &u, &v);
    double fu = u * (sf->nu - 1), fv = v * (sf->nv - 1);
    uint32_t i0 = (uint32_t)fu, j0 = (uint32_t)fv;
    uint32_t cand[4], nc = 0;
    /* Nearest sample first, then the other three around y. */
    uint32_t in = (uint32_t)(fu + 0.5), jn = (uint32_t)(fv + 0.5);
    cand[nc++] = jn * sf->nu + in;
    for (uint32_t dj = 0; dj < 2; dj++)
        for (uint32_t di = 0; di < 2; di++) {
            uint32_t i = i0 + di < sf->nu ? i0 + di : sf->nu - 1;
            uint32_t j = j0 + dj < sf->nv ? j0 + dj : sf->nv - 1;
            uint32_t k = j * sf->nu + i;
            bool have = false;
            for (uint32_t m = 0; m < nc; m++)
                have |= cand[m] == k;
            if (!have && nc < 4)
                cand[nc++] = k;
        }
    xform pose = scene_object_pose(scene, sf->object, rs->time);
    vec3 off = v3_scale(rs->normals[s], 1e-6 * rs->diameter);
    for (uint32_t m = 0; m < nc; m++) {
        uint32_t e = sf->first_element + cand[m];
        vec3 c = xf_point(&pose, scene_element_centroid(sf, &scene->elements[e]));
        if (!scene_rays_blocked(rs, v3_add(y, off), v3_add(c, off), s))
            return e;
    }
    return RAY_HIDDEN;
}

/* The RAY_COUNT rays of the point x (normal n): the normal and 4 rings of
 * 6 azimuths (elevations 15-75 degrees); out[k] is what ray k meets. */
static void trace_rays(const scene_rays *rs, vec3 x, vec3 n, uint32_t out[RAY_COUNT])
{
    vec3 t = fabs(n.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
    t = v3_norm(v3_sub(t, v3_scale(n, v3_dot(t, n))));
    vec3 b = v3_cross(n, t);
    vec3 o = v3_mad(x, n, 1e-7 * rs->diameter);
    int k = 0;
    for (int ring = -1; ring < 4; ring++) {
        int az_count = ring < 0 ? 1 : 6;
        for (int az = 0; az < az_count; az++, k++) {
            double el = ring < 0 ? SCENE_PI / 2 : (15.0 + 20.0 * ring) * SCENE_PI / 180.0;
            double phi = (az + 0.5 * (ring & 1)) * 2.0 * SCENE_PI / az_count;
            vec3 dir = v3_add(v3_scale(n, sin(el)), v3_add(v3_scale(t, cos(el) * cos(phi)),
                                                           v3_scale(b, cos(el) * sin(phi))));
            bool back = false;
            vec3 at = x;
            int32_t hit = nearest_hit(rs, o, dir, 1e-7 * rs->diameter, &back, &at);
            out[k] = hit < 0 ? RAY_OPEN : back ? RAY_BACK : element_seen(rs, (uint32_t)hit, at);
        }
    }
}

static bool emits(const xrad_scene *scene, uint32_t s)
{
    vec3 e = scene->materials[scene->surfaces[s].material].emission;
    return e.x > 0 || e.y > 0 || e.z > 0;
}

/* Light's reach over the rays: lit[e] for every element e of `cand`
 * (ncand of them, rays[k * RAY_COUNT ...] theirs) that a ray leaving the
 * scene, or one meeting a lit element, reaches, repeated until nothing
 * changes. Light runs both ways along a ray that meets a front face (each
 * side sees the other's front). Elements outside cand keep lit[] as it is. */
static void spread_light(const uint32_t *cand, uint32_t ncand, const uint32_t *rays, uint8_t *lit)
{
    for (bool changed = true; changed;) {
        changed = false;
        for (uint32_t k = 0; k < ncand; k++) {
            for (int r = 0; r < RAY_COUNT && !lit[cand[k]]; r++) {
                uint32_t h = rays[(size_t)k * RAY_COUNT + r];
                if (h == RAY_OPEN || (RAY_SEES(h) && lit[h]))
                    lit[cand[k]] = changed = true;
            }
            for (int r = 0; r < RAY_COUNT && lit[cand[k]]; r++) {
                uint32_t h = rays[(size_t)k * RAY_COUNT + r];
                if (RAY_SEES(h) && !lit[h])
                    lit[h] = changed = true;
            }
        }
    }
}

xrad_status scene_rays_init(scene_rays *rs, const xrad_scene *scene, double time,
                            bool dynamic_too, xrad_error *err)
{
    rs->scene = scene;
    rs->time = time;
    rs->dynamic_too = dynamic_too;
    xrad_status st = world_quads(scene, time, &rs->corners, &rs->normals, err);
    if (st)
        return st;
    vec3 lo, hi;
    scene_bounds(scene, time, &lo, &hi);
    rs->diameter = v3_len(v3_sub(hi, lo));
    /* Boxes a hair larger than the quads: the exact tests decide. */
    return quad_bvh_build(rs->corners, scene->surface_count, 1e-6 * rs->diameter, &rs->bvh, err);
}

void scene_rays_free(scene_rays *rs)
{
    free(rs->corners);
    free(rs->normals);
    quad_bvh_free(&rs->bvh);
}

/* Enclosure of the elements with within[e] set, at scene time `time`
 * (dynamic surfaces among the rays' targets with dynamic_too): enclosed[e]
 * where no light reaches e (spread_light), static_enclosed[e] (NULL: none)
 * left out; *count of them. */
static xrad_status enclosure(const xrad_scene *scene, double time, bool dynamic_too,
                             const uint8_t *within, const uint8_t *static_enclosed,
                             uint8_t *enclosed, uint32_t *count, xrad_error *err)
{
    uint32_t ne = scene->element_count;
    *count = 0;
    for (uint32_t e = 0; e < ne; e++)
        enclosed[e] = 0;
    /* Every element casts 25 rays: past this many (seconds on one core)
     * a scene goes without the test. */
    if (ne > SCENE_ENCLOSED_MAX_ELEMENTS)
        return XRAD_OK;
    uint32_t ncand = 0;
    for (uint32_t e = 0; e < ne; e++)
        ncand += within[e] != 0;
    if (!ncand)
        return XRAD_OK;
    uint32_t *cand = malloc(ncand * sizeof(uint32_t));
    uint32_t *rays = malloc((size_t)ncand * RAY_COUNT * sizeof(uint32_t));
    uint8_t *lit = malloc(ne ? ne : 1);
    scene_rays rs = {0};
    xrad_status st = !cand || !rays || !lit
                         ? xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for enclosure",
                                     scene->path)
                         : scene_rays_init(&rs, scene, time, dynamic_too, err);
    if (st)
        goto done;
    /* Light starts at the emitters; with none static (a moving lamp) the
     * static test cannot tell where it will be, and only what sees no
     * front face at all is closed in. Elements outside cand are lit unless
     * the static test closed them in. */
    bool static_light = false;
    for (uint32_t s = 0; s < scene->surface_count; s++)
        static_light |= emits(scene, s) && !scene->objects[scene->surfaces[s].object].dynamic;
    ncand = 0;
    for (uint32_t e = 0; e < ne; e++) {
        const element *el = &scene->elements[e];
        const surface *sf = &scene->surfaces[el->surface];
        lit[e] = within[e] ? emits(scene, el->surface) : !(static_enclosed && static_enclosed[e]);
        if (!within[e])
            continue;
        xform pose = scene_object_pose(scene, sf->object, time);
        vec3 x = xf_point(&pose, scene_element_centroid(sf, el));
        uint32_t *r = &rays[(size_t)ncand * RAY_COUNT];
        trace_rays(&rs, x, rs.normals[el->surface], r);
        if (!dynamic_too && !static_light)
            for (int k = 0; k < RAY_COUNT; k++)
                lit[e] |= r[k] != RAY_BACK;
        cand[ncand++] = e;
    }
    spread_light(cand, ncand, rays, lit);
    for (uint32_t k = 0; k < ncand; k++) {
        uint32_t e = cand[k];
        /* Every ray on a back face (a ceiling element above a lamp hung 1
         * cm below it; a gap's grazing rays reach out) counts as closed in
         * whatever the light: shooting from there, a patch saw the lamp's
         * back over half its hemicube. */
        bool backs = true;
        for (int r = 0; r < RAY_COUNT; r++)
            backs &= rays[(size_t)k * RAY_COUNT + r] == RAY_BACK;
        if ((!lit[e] || backs) && !(static_enclosed && static_enclosed[e])) {
            enclosed[e] = 1;
            (*count)++;
        }
    }
done:
    scene_rays_free(&rs);
    free(cand);
    free(rays);
    free(lit);
    return st;
}

xrad_status scene_find_enclosed(const xrad_scene *scene, uint8_t *enclosed, uint32_t *count,
                                xrad_error *err)
{
    uint8_t *within = malloc(scene->element_count ? scene->element_count : 1);
    if (!within)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for enclosure", scene->path);
    for (uint32_t e = 0; e < scene->element_count; e++)
        within[e] = !scene->objects[scene->surfaces[scene->elements[e].surface].object].dynamic;
    xrad_status st = enclosure(scene, 0.0, false, within, NULL, enclosed, count, err);
    free(within);
    return st;
}

xrad_status scene_find_enclosed_dynamic(const xrad_scene *scene, double time,
                                        const uint8_t *static_enclosed, uint8_t *enclosed,
                                        uint32_t *count, xrad_error *err)
{
    uint32_t ns = scene->surface_count;
    uint8_t *within = calloc(scene->element_count ? scene->element_count : 1, 1);
    vec3 *corners = NULL, *normals = NULL;
    xrad_status st = within ? world_quads(scene, time, &corners, &normals, err)
                            : xrad_fail(err, XRAD_ERROR_SYSTEM,
                                        "%s: out of memory for enclosure", scene->path);
    /* A point a dynamic object closes in lies within the object's bounds
     * at this pose: only static elements there cast rays. */
    size_t nobj = scene->object_count ? scene->object_count : 1;
    vec3 *lo = st ? NULL : malloc(2 * nobj * sizeof(vec3));
    if (!st && !lo)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for enclosure", scene->path);
    vec3 *hi = lo ? lo + scene->object_count : NULL;
    for (uint32_t o = 0; !st && o < scene->object_count; o++) {
        lo[o] = v3(INFINITY, INFINITY, INFINITY);
        hi[o] = v3(-INFINITY, -INFINITY, -INFINITY);
    }
    for (uint32_t s = 0; !st && s < ns; s++) {
        uint32_t o = scene->surfaces[s].object;
        for (int k = 0; k < 4 && scene->objects[o].dynamic; k++) {
            vec3 c = corners[4 * s + k];
            lo[o] = v3(fmin(lo[o].x, c.x), fmin(lo[o].y, c.y), fmin(lo[o].z, c.z));
            hi[o] = v3(fmax(hi[o].x, c.x), fmax(hi[o].y, c.y), fmax(hi[o].z, c.z));
        }
    }
    bool any = false;
    for (uint32_t e = 0; !st && e < scene->element_count; e++) {
        const element *el = &scene->elements[e];
        const surface *sf = &scene->surfaces[el->surface];
        if (scene->objects[sf->object].dynamic)
            continue;
        xform pose = scene_object_pose(scene, sf->object, time);
        vec3 x = xf_point(&pose, scene_element_centroid(sf, el));
        for (uint32_t o = 0; o < scene->object_count && !within[e]; o++) {
            double pad = 1e-6 * v3_len(v3_sub(hi[o], lo[o]));
            if (scene->objects[o].dynamic && x.x >= lo[o].x - pad && x.y >= lo[o].y - pad &&
                x.z >= lo[o].z - pad && x.x <= hi[o].x + pad && x.y <= hi[o].y + pad &&
                x.z <= hi[o].z + pad)
                within[e] = any = true;
        }
    }
    free(lo);
    free(corners);
    free(normals);
    if (!st && any)
        st = enclosure(scene, time, true, within, static_enclosed, enclosed, count, err);
    else if (!st) {
        *count = 0;
        memset(enclosed, 0, scene->element_count);
    }
    free(within);
    return st;
}

typedef struct slab_job {
    const xrad_scene *scene;
    const vec3 *corners, *normals;
    double time, tol;
    uint32_t *pairs; /* 2 surfaces per pair */
    vec3 *points;    /* per pair, a point of the first that the second covers */
    uint32_t count, capacity;
    bool failed; /* out of memory */
} slab_job;

/* Whether the side of x that n faces is closed: most of x's RAY_COUNT
 * rays about n (trace_rays) meet a back face first. One ray along n
 * decided wrongly on a mesh, slipping out between two faces of the closed
 * model it started in (wuson-room's sheets inside the Wuson). */
static bool closed_side(const scene_rays *rs, vec3 x, vec3 n)
{
    uint32_t out[RAY_COUNT], back = 0;
    trace_rays(rs, x, n, out);
    for (int k = 0; k < RAY_COUNT; k++)
        back += out[k] == RAY_BACK;
    return 2 * back > RAY_COUNT;
}

/* Pairs face to face in one plane, each with a point that both cover. */
static void slab_pair(void *user, uint32_t a, uint32_t b)
{
    slab_job *j = user;
    const xrad_scene *scene = j->scene;
    vec3 na = j->normals[a];
    /* Quads only: a model's faces can be wound either way and leave cracks,
     * so rays cannot tell its inside (wuson-room's Wuson: faces of sheets
     * inside the model, dark in the CPU reference too, and its feet on the
     * floor came out as slabs). */
    if (scene->surfaces[a].mesh || scene->surfaces[b].mesh ||
        !(v3_dot(j->normals[b], na) < -0.999))
        return;
    for (int k = 0; k < 4; k++)
        if (!(fabs(v3_dot(v3_sub(j->corners[4 * b + k], j->corners[4 * a]), na)) <= j->tol))
            return;
    /* An element centroid of a inside b, as cover_pair tests. */
    const surface *sa = &scene->surfaces[a];
    xform pose = scene_object_pose(scene, sa->object, j->time);
    for (uint32_t k = 0; k < sa->nu * sa->nv; k++) {
        const element *el = &scene->elements[sa->first_element + k];
        vec3 x = xf_point(&pose, scene_element_centroid(sa, el));
        if (!inside_quad(&j->corners[4 * b], j->normals[b], x, j->tol))
            continue;
        if (j->count == j->capacity) {
            uint32_t cap = j->capacity ? 2 * j->capacity : 8;
            uint32_t *p = realloc(j->pairs, 2 * (size_t)cap * sizeof *p);
            vec3 *q = p ? realloc(j->points, cap * sizeof *q) : NULL;
            if (p)
                j->pairs = p;
            if (q)
                j->points = q;
            if (!p || !q) {
                j->failed = true;
                return;
            }
            j->capacity = cap;
        }
        j->pairs[2 * j->count] = a;
        j->pairs[2 * j->count + 1] = b;
        j->points[j->count++] = x;
        return;
    }
}

xrad_status scene_find_flat_slabs(const xrad_scene *scene, double time, uint32_t **pairs,
                                  uint32_t *count, xrad_error *err)
{
    *pairs = NULL;
    *count = 0;
    vec3 *corners, *normals, lo, hi;
    xrad_status st = world_quads(scene, time, &corners, &normals, err);
    if (st)
        return st;
    /* The solvers' contact tolerance (gpu_scene.h GPU_SCENE_CONTACT). */
    scene_bounds(scene, time, &lo, &hi);
    slab_job job = {.scene = scene,
                    .corners = corners,
                    .normals = normals,
                    .time = time,
                    .tol = 1e-4 * v3_len(v3_sub(hi, lo))};
    st = contact_pairs(scene, corners, job.tol, slab_pair, &job, err);
    free(corners);
    free(normals);
    if (!st && job.failed)
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for contact", scene->path);
    /* A solid standing on a surface closes a volume behind one of the two:
     * rays to either side (only where a pair was found: most scenes have
     * none). */
    scene_rays rs;
    if (!st && job.count && !(st = scene_rays_init(&rs, scene, time, true, err))) {
        uint32_t kept = 0;
        for (uint32_t k = 0; k < job.count; k++) {
            uint32_t a = job.pairs[2 * k], b = job.pairs[2 * k + 1];
            vec3 x = job.points[k], na = rs.normals[a];
            if (closed_side(&rs, x, na) || closed_side(&rs, x, v3_scale(na, -1)))
                continue;
            job.pairs[2 * kept] = a < b ? a : b;
            job.pairs[2 * kept + 1] = a < b ? b : a;
            kept++;
        }
        job.count = kept;
        scene_rays_free(&rs);
    }
    free(job.points);
    if (st) {
        free(job.pairs);
        return st;
    }
    *pairs = job.pairs;
    *count = job.count;
    return XRAD_OK;
}
