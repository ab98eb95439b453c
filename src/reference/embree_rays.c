/* Visibility rays through Embree 3 (embree_rays.h). */
#include "reference/embree_rays.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "core/error.h"

/* Planes within this fraction of the scene's diagonal of each other (and
 * normals within 1e-6 rad) are one plane: far above float rounding of the
 * vertices (about 1e-7 of the coordinates), far below any gap a scene
 * models. */
#define COPLANAR_TOL 1e-6

/* Rays start and stop this fraction of the scene's diagonal short of their
 * ends, beyond the rounding of the receiver's hair (REF_RAY_HAIR). */
#define END_TOL 1e-6

struct ref_rays {
    RTCDevice device;
    RTCScene scene;
    const ref_quad *quads;
    uint32_t count;
    double plane_tol, end_tol;
};

/* What the filter needs of one call: the context first, so that Embree's
 * pointer to it is a pointer to this. */
typedef struct occlusion_ctx {
    struct RTCIntersectContext rtc;
    const ref_rays *rays;
    uint32_t own, target;
    bool touch;  /* a contact test (ref_rays_touching), not occlusion */
    vec3 facing; /* with touch: the normal a pressed face turns away from */
} occlusion_ctx;

static bool coplanar(const ref_rays *r, uint32_t a, uint32_t b)
{
    const ref_quad *qa = &r->quads[a], *qb = &r->quads[b];
    return fabs(v3_dot(qa->normal, qb->normal)) > 1 - 1e-12 &&
           fabs(v3_dot(qa->normal, v3_sub(qb->p[0], qa->p[0]))) < r->plane_tol;
}

/* Whether a hit on quad q counts. Occlusion: not on the segment's own two
 * quads or a quad in the plane of either (embree_rays.h). Contact
 * (ref_rays_touching, c->touch): only on a quad other than the own one
 * that faces against it. */
static bool counts(const occlusion_ctx *c, uint32_t q)
{
    if (c->touch)
        return q != c->own && v3_dot(c->rays->quads[q].normal, c->facing) < -REF_CONTACT_COS;
    return !(q == c->own || q == c->target || coplanar(c->rays, q, c->own) ||
             coplanar(c->rays, q, c->target));
}

/* Embree's C API has no accessor for RTCHitN: primID is its sixth SoA
 * array (rtcore_ray.h). */
static void filter(const struct RTCFilterFunctionNArguments *args)
{
    const occlusion_ctx *c = (const occlusion_ctx *)args->context;
    const unsigned *prim = (const unsigned *)args->hit + 5 * args->N;
    for (unsigned i = 0; i < args->N; i++)
        if (args->valid[i] && !counts(c, prim[i]))
            args->valid[i] = 0;
}

static const char *device_error(RTCDevice device)
{
    switch (rtcGetDeviceError(device)) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "unknown error";
    }
}

xrad_status ref_rays_create(const ref_quad *quads, uint32_t count, double scale, ref_rays **out,
                            xrad_error *err)
{
    *out = NULL;
    ref_rays *r = calloc(1, sizeof *r);
    if (!r)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reference: out of memory for the ray BVH");
    r->quads = quads;
    r->count = count;
    r->plane_tol = COPLANAR_TOL * scale;
    r->end_tol = END_TOL * scale;
    /* One build thread: the reference's own threads trace. */
    r->device = rtcNewDevice("threads=1");
    if (!r->device) {
        free(r);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "reference: Embree: rtcNewDevice failed (%s)",
                         device_error(NULL));
    }
    r->scene = rtcNewScene(r->device);
    rtcSetSceneFlags(r->scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(r->scene, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry geom = rtcNewGeometry(r->device, RTC_GEOMETRY_TYPE_QUAD);
    float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                       3 * sizeof(float), 4 * (size_t)count);
    unsigned *ix = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT4,
                                           4 * sizeof(unsigned), count);
    if (!v || !ix) {
        xrad_status st = xrad_fail(err, XRAD_ERROR_SYSTEM,
                                   "reference: Embree: no buffers for %u quads (%s)", count,
                                   device_error(r->device));
        rtcReleaseGeometry(geom);
        ref_rays_destroy(&r);
        return st;
    }
    /* A triangle (p2 = p3) is a quad Embree splits into (p0, p1, p3) and a
     * degenerate (p2, p3, p1) that no ray hits. */
    for (uint32_t q = 0; q < count; q++) {
        for (int k = 0; k < 4; k++) {
            v[12 * q + 3 * k + 0] = (float)quads[q].p[k].x;
            v[12 * q + 3 * k + 1] = (float)quads[q].p[k].y;
            v[12 * q + 3 * k + 2] = (float)quads[q].p[k].z;
            ix[4 * q + k] = 4 * q + k;
        }
    }
    rtcCommitGeometry(geom);
    rtcAttachGeometry(r->scene, geom);
    rtcReleaseGeometry(geom);
    rtcCommitScene(r->scene);
    if (rtcGetDeviceError(r->device) != RTC_ERROR_NONE) {
        xrad_status st = xrad_fail(err, XRAD_ERROR_SYSTEM,
                                   "reference: Embree: building the BVH of %u quads failed (%s)",
                                   count, device_error(r->device));
        ref_rays_destroy(&r);
        return st;
    }
    *out = r;
    return XRAD_OK;
}

void ref_rays_destroy(ref_rays **rays)
{
    if (!rays || !*rays)
        return;
    ref_rays *r = *rays;
    if (r->scene)
        rtcReleaseScene(r->scene);
    if (r->device)
        rtcReleaseDevice(r->device);
    free(r);
    *rays = NULL;
}

void ref_rays_occluded(const ref_rays *rays, uint32_t own, uint32_t target, vec3 from,
                       const vec3 *to, uint32_t count, bool *blocked)
{
    occlusion_ctx c = {.rays = rays, .own = own, .target = target};
    rtcInitIntersectContext(&c.rtc);
    c.rtc.filter = filter;
    struct RTCRay ray[REF_RAYS_BATCH];
    count = count < REF_RAYS_BATCH ? count : REF_RAYS_BATCH;
    for (uint32_t k = 0; k < count; k++) {
        vec3 d = v3_sub(to[k], from);
        double len = v3_len(d);
        /* The segment's ends less END_TOL of the scene: t in units of d. */
        double margin = len > 0 ? rays->end_tol / len : 1;
        ray[k] = (struct RTCRay){
            .org_x = (float)from.x, .org_y = (float)from.y, .org_z = (float)from.z,
            .dir_x = (float)d.x, .dir_y = (float)d.y, .dir_z = (float)d.z,
            .tnear = (float)margin, .tfar = (float)(1 - margin),
            .mask = 0xffffffffu, .flags = 0,
        };
        if (!(ray[k].tfar > ray[k].tnear)) {
            ray[k].tnear = 0;
            ray[k].tfar = -1; /* empty: never blocked */
        }
    }
    rtcOccluded1M(rays->scene, &c.rtc, ray, count, sizeof ray[0]);
    /* Embree sets tfar to -inf where the segment is blocked. */
    for (uint32_t k = 0; k < count; k++)
        blocked[k] = ray[k].tfar == -INFINITY;
}

void ref_rays_closest(const ref_rays *rays, uint32_t own, vec3 from, const vec3 *dirs,
                      uint32_t count, uint32_t *hit, double *t)
{
    /* The occlusion filter with both ends the ray's own quad. */
    occlusion_ctx c = {.rays = rays, .own = own, .target = own};
    rtcInitIntersectContext(&c.rtc);
    c.rtc.filter = filter;
    struct RTCRayHit rh[REF_RAYS_BATCH];
    count = count < REF_RAYS_BATCH ? count : REF_RAYS_BATCH;
    for (uint32_t k = 0; k < count; k++) {
        double len = v3_len(dirs[k]);
        rh[k] = (struct RTCRayHit){
            .ray = {.org_x = (float)from.x, .org_y = (float)from.y, .org_z = (float)from.z,
                    .dir_x = (float)dirs[k].x, .dir_y = (float)dirs[k].y,
                    .dir_z = (float)dirs[k].z,
                    .tnear = len > 0 ? (float)(rays->end_tol / len) : 0,
                    .tfar = len > 0 ? INFINITY : -1, .mask = 0xffffffffu, .flags = 0},
            .hit = {.geomID = RTC_INVALID_GEOMETRY_ID, .primID = RTC_INVALID_GEOMETRY_ID},
        };
    }
    rtcIntersect1M(rays->scene, &c.rtc, rh, count, sizeof rh[0]);
    for (uint32_t k = 0; k < count; k++) {
        bool found = rh[k].hit.geomID != RTC_INVALID_GEOMETRY_ID;
        hit[k] = found ? rh[k].hit.primID : UINT32_MAX;
        t[k] = found ? rh[k].ray.tfar : INFINITY;
    }
}

bool ref_rays_touching(const ref_rays *rays, uint32_t own, vec3 n, vec3 from, vec3 dir)
{
    occlusion_ctx c = {.rays = rays, .own = own, .target = own, .touch = true, .facing = n};
    rtcInitIntersectContext(&c.rtc);
    c.rtc.filter = filter;
    struct RTCRay ray = {
        .org_x = (float)from.x,
        .org_y = (float)from.y,
        .org_z = (float)from.z,
        .dir_x = (float)dir.x,
        .dir_y = (float)dir.y,
        .dir_z = (float)dir.z,
        .tnear = 0,
        .tfar = 1,
        .mask = 0xffffffffu,
        .flags = 0,
    };
    rtcOccluded1(rays->scene, &c.rtc, &ray);
    return ray.tfar == -INFINITY;
}
