/*
 * Select pass (src/passes/select.h) on lavapipe, against the host:
 *  - the chosen surface is the CPU argmax of |luminance(sum_e Bu_e A_e)| over
 *    random unshot radiosities, on a scene of 300 surfaces (more than one
 *    workgroup's 256 invocations, so the strided scan and the tree both
 *    count);
 *  - the patches partition the chosen surface's elements, their areas sum
 *    to the surface's area and area x radiosity to its unshot power per
 *    channel (what is shot is exactly what was unshot), their frames are
 *    orthonormal, their centres lie on the surface;
 *  - the patch counts follow the documented rule (about max_patches^2 x
 *    power / max_power patches shaped to the surface, capped per side by
 *    max_patches and the element counts, in all by max_shooters);
 *  - Bu of the chosen surface is zero afterwards and every other Bu is
 *    untouched; the indirect parameters are sized from the patch count;
 *  - below threshold x the largest power the converged flag is set, the
 *    counts are zero and nothing changes, also in the shots after;
 *  - a shot's group: the surfaces that join the chosen one are, in surface
 *    order, the first that hold at least SELECT_GROUP_SHARE of its power,
 *    have at most group_elements elements and one patch by the rule, as
 *    many as the room leaves; each shoots its own power from its own
 *    `shot` entries and is cleared; status.unshot is the host's sum of all
 *    powers, and while it exceeds unshot_share of the first the solve does
 *    not converge, whatever the largest surface holds.
 */
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "gpu/buffer.h"
#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "passes/select.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "select_shared.h"

#define GROUP 64u
#define INDICES 123u
#define INSTANCES 5u

static const double luma[3] = {0.2126, 0.7152, 0.0722};

typedef struct rig {
    xrad_scene *scene;
    gpu_buffer surfaces, elements, Bu, shooters, status;
    gpu_buffer snapshot; /* select's `shot`: the shot surface's Bu by element */
    select_pass *pass;
    uint32_t max_shooters;
    uint32_t group_shooters, group_elements; /* select_params' (0: no group) */
    double unshot_share;
} rig;

static uint32_t lcg(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return *state >> 8;
}

static xrad_status host_buffer(xrad_context *ctx, VkDeviceSize size, gpu_buffer *b,
                               xrad_error *err)
{
    xrad_status s = gpu_buffer_create(ctx, size,
                                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                          VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT,
                                      GPU_MEM_READBACK, GPU_MEM_OTHER, b, err);
    if (!s)
        memset(b->alloc.mapped, 0, size);
    return s;
}

/* The scene's world geometry in the layouts of spirv/radiosity.h. */
static int rig_create_group(xrad_context *ctx, const char *json, uint32_t max_shooters,
                            uint32_t group_shooters, uint32_t group_elements, rig *r)
{
    memset(r, 0, sizeof(*r));
    r->group_shooters = group_shooters;
    r->group_elements = group_elements;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "select.json", &r->scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return 0;
    const xrad_scene *sc = r->scene;
    r->max_shooters = max_shooters;
    if ((st = host_buffer(ctx, sc->surface_count * sizeof(struct gpu_surface), &r->surfaces,
                          &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(struct gpu_element), &r->elements,
                          &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(vec4), &r->Bu, &err)) ||
        (st = host_buffer(ctx, max_shooters * sizeof(struct gpu_shooter), &r->shooters, &err)) ||
        (st = host_buffer(ctx, sizeof(struct select_status), &r->status, &err)) ||
        (st = host_buffer(ctx,
                          (select_shot_capacity(sc) + group_shooters * group_elements) *
                              sizeof(vec4),
                          &r->snapshot, &err)) ||
        (st = select_create(ctx, sc->surface_count, &r->pass, &err))) {
        CHECK(0, "buffers: %s", err.message);
        return 0;
    }
    struct gpu_surface *gs = r->surfaces.alloc.mapped;
    struct gpu_element *ge = r->elements.alloc.mapped;
    for (uint32_t s = 0; s < sc->surface_count; s++) {
        const surface *sf = &sc->surfaces[s];
        vec3 c[4], n;
        scene_surface_world(sc, s, 0, c, &n);
        for (int k = 0; k < 4; k++)
            gs[s].corner[k] = (vec4){(float)c[k].x, (float)c[k].y, (float)c[k].z, 0};
        gs[s].normal_area = (vec4){(float)n.x, (float)n.y, (float)n.z, (float)sf->area};
        gs[s].first_element = sf->first_element;
        gs[s].nu = sf->nu;
        gs[s].nv = sf->nv;
        gs[s].material = sf->material;
        gs[s].object = sf->object;
        xform pose = scene_object_pose(sc, sf->object, 0);
        for (uint32_t e = sf->first_element; e < sf->first_element + sf->nu * sf->nv; e++) {
            vec3 p = xf_point(&pose, sc->elements[e].pos);
            float a = (float)sc->elements[e].area;
            ge[e].pos_area = (vec4){(float)p.x, (float)p.y, (float)p.z, a};
            ge[e].normal = (vec4){(float)n.x, (float)n.y, (float)n.z, 0};
            ge[e].surface = s;
        }
    }
    select_bind(ctx, r->pass,
                &(select_buffers){&r->surfaces, &r->elements, &r->Bu, &r->shooters, &r->status,
                                  &r->snapshot});
    return 1;
}

static int rig_create(xrad_context *ctx, const char *json, uint32_t max_shooters, rig *r)
{
    return rig_create_group(ctx, json, max_shooters, 0, 0, r);
}

static void rig_destroy(xrad_context *ctx, rig *r)
{
    select_destroy(ctx, &r->pass);
    gpu_buffer_destroy(ctx, &r->status);
    gpu_buffer_destroy(ctx, &r->snapshot);
    gpu_buffer_destroy(ctx, &r->shooters);
    gpu_buffer_destroy(ctx, &r->Bu);
    gpu_buffer_destroy(ctx, &r->elements);
    gpu_buffer_destroy(ctx, &r->surfaces);
    xrad_scene_destroy(&r->scene);
}

/* One shot in one submission, elements flagged `buried_mask` left out of
 * the patches; the results are in the mapped buffers. */
static int shoot_masked(xrad_context *ctx, rig *r, uint32_t max_patches, double threshold,
                        uint32_t buried_mask)
{
    xrad_error err = {0};
    gpu_cmd c;
    xrad_status st = gpu_cmd_begin(ctx, &c, &err);
    CHECK(st == XRAD_OK, "begin: %s", err.message);
    if (st)
        return 0;
    select_params p = {
        .element_count = r->scene->element_count,
        .max_patches = max_patches,
        .max_shooters = r->max_shooters,
        .draw_index_count = INDICES,
        .instances_per_hemicube = INSTANCES,
        .reconstruct_group = GROUP,
        .seed = 7,
        .threshold = threshold,
        .buried_mask = buried_mask,
        .unshot_share = r->unshot_share,
        .group_shooters = r->group_shooters,
        .group_elements = r->group_elements,
        .shot_first = select_shot_capacity(r->scene),
    };
    select_record(r->pass, c.cmd, &p);
    VkMemoryBarrier host = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_HOST_READ_BIT,
    };
    vkCmdPipelineBarrier(c.cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT,
                         0, 1, &host, 0, NULL, 0, NULL);
    st = gpu_cmd_run(ctx, &c, &err);
    CHECK(st == XRAD_OK, "run: %s", err.message);
    gpu_cmd_destroy(ctx, &c);
    return st == XRAD_OK;
}

static int shoot(xrad_context *ctx, rig *r, uint32_t max_patches, double threshold)
{
    return shoot_masked(ctx, r, max_patches, threshold, 0);
}

/* Whether the select pass's copy of an element's unshot radiosity
 * (select.comp `shot`) is what the element held: its Bu in rgb, its area
 * in w (a buried element's copy, w = -1, is not what these shots make:
 * they mask nothing). */
static bool shot_kept(vec4 snap, vec4 bu, double area)
{
    return snap.x == bu.x && snap.y == bu.y && snap.z == bu.z && snap.w == (float)area;
}

static double surface_power(const rig *r, const vec4 *bu, uint32_t s)
{
    const surface *sf = &r->scene->surfaces[s];
    double sum[3] = {0, 0, 0};
    for (uint32_t e = sf->first_element; e < sf->first_element + sf->nu * sf->nv; e++) {
        double a = r->scene->elements[e].area;
        sum[0] += bu[e].x * a;
        sum[1] += bu[e].y * a;
        sum[2] += bu[e].z * a;
    }
    return fabs(luma[0] * sum[0] + luma[1] * sum[1] + luma[2] * sum[2]);
}

static void set_uniform(rig *r, uint32_t s, float v)
{
    const surface *sf = &r->scene->surfaces[s];
    vec4 *bu = r->Bu.alloc.mapped;
    for (uint32_t e = sf->first_element; e < sf->first_element + sf->nu * sf->nv; e++)
        bu[e] = (vec4){v, v, v, 0};
}

/* Everything a shot of surface `s` must satisfy, whatever the counts. */
static void check_shot(const rig *r, uint32_t s, const vec4 *bu_before, double power)
{
    const xrad_scene *sc = r->scene;
    const surface *sf = &sc->surfaces[s];
    const struct select_status *st = r->status.alloc.mapped;
    const struct gpu_shooter *sh = r->shooters.alloc.mapped;
    const struct gpu_surface *gs = r->surfaces.alloc.mapped;
    const vec4 *bu = r->Bu.alloc.mapped;
    uint32_t n = st->kx * st->ky;
    CHECK(st->surface == s, "chose surface %u, want %u", st->surface, s);
    CHECK(st->shooter_count == n && n >= 1 && n <= r->max_shooters, "%u shooters, %u x %u",
          st->shooter_count, st->kx, st->ky);
    CHECK(st->draw_index_count == INDICES && st->draw_instance_count == n * INSTANCES &&
              st->draw_first_index == 0 && st->draw_vertex_offset == 0 &&
              st->draw_first_instance == 0,
          "draw %u %u %u %u %u", st->draw_index_count, st->draw_instance_count,
          st->draw_first_index, st->draw_vertex_offset, st->draw_first_instance);
    CHECK(st->dispatch_x == (sc->element_count + GROUP - 1) / GROUP && st->dispatch_y == 1 &&
              st->dispatch_z == 1,
          "dispatch %u %u %u", st->dispatch_x, st->dispatch_y, st->dispatch_z);
    CHECK(st->converged == 0, "converged");
    CHECK_REL(st->power, power, 1e-5);
    if (st->surface != s || n == 0 || n > r->max_shooters)
        return;

    double before[3] = {0, 0, 0}, shot[3] = {0, 0, 0}, area = 0;
    uint32_t *covered = calloc(sf->nu * sf->nv, sizeof(*covered));
    uint32_t *hemicube = calloc(n, sizeof(*hemicube));
    for (uint32_t e = sf->first_element; e < sf->first_element + sf->nu * sf->nv; e++) {
        double a = sc->elements[e].area;
        before[0] += bu_before[e].x * a;
        before[1] += bu_before[e].y * a;
        before[2] += bu_before[e].z * a;
    }
    vec3 nrm = v3(gs[s].normal_area.x, gs[s].normal_area.y, gs[s].normal_area.z);
    vec3 p0 = v3(gs[s].corner[0].x, gs[s].corner[0].y, gs[s].corner[0].z);
    vec3 eu = v3_sub(v3(gs[s].corner[1].x, gs[s].corner[1].y, gs[s].corner[1].z), p0);
    vec3 ev = v3_sub(v3(gs[s].corner[3].x, gs[s].corner[3].y, gs[s].corner[3].z), p0);
    for (uint32_t k = 0; k < n && covered && hemicube; k++) {
        const struct gpu_shooter *p = &sh[k];
        CHECK(p->surface == s, "shooter %u on surface %u", k, p->surface);
        CHECK(p->i0 <= p->i1 && p->i1 < sf->nu && p->j0 <= p->j1 && p->j1 < sf->nv,
              "shooter %u range [%u %u] x [%u %u]", k, p->i0, p->i1, p->j0, p->j1);
        if (p->hemicube < n)
            hemicube[p->hemicube]++;
        double pa = 0;
        for (uint32_t j = p->j0; j <= p->j1 && p->j1 < sf->nv; j++)
            for (uint32_t i = p->i0; i <= p->i1 && p->i1 < sf->nu; i++) {
                covered[j * sf->nu + i]++;
                pa += sc->elements[sf->first_element + j * sf->nu + i].area;
            }
        CHECK_REL(p->pos_area.w, pa, 1e-5);
        area += p->pos_area.w;
        shot[0] += (double)p->radiosity.x * p->pos_area.w;
        shot[1] += (double)p->radiosity.y * p->pos_area.w;
        shot[2] += (double)p->radiosity.z * p->pos_area.w;
        vec3 pn = v3(p->normal.x, p->normal.y, p->normal.z);
        vec3 pt = v3(p->tangent.x, p->tangent.y, p->tangent.z);
        CHECK(v3_len(v3_sub(pn, nrm)) < 1e-6, "shooter %u normal differs from the surface's", k);
        CHECK(fabs(v3_len(pt) - 1) < 1e-5 && fabs(v3_dot(pt, pn)) < 1e-5,
              "shooter %u tangent not a unit vector in the plane", k);
        /* The centre lies on the (parallelogram) surface: s, t in [0, 1], on the plane. */
        vec3 d = v3_sub(v3(p->pos_area.x, p->pos_area.y, p->pos_area.z), p0);
        double scale = v3_len(eu) + v3_len(ev);
        CHECK(fabs(v3_dot(d, nrm)) < 1e-5 * scale, "shooter %u centre off the plane", k);
        double uu = v3_dot(eu, eu), vv = v3_dot(ev, ev), uv = v3_dot(eu, ev);
        double du = v3_dot(d, eu), dv = v3_dot(d, ev), det = uu * vv - uv * uv;
        double ps = (du * vv - dv * uv) / det, pt2 = (dv * uu - du * uv) / det;
        CHECK(ps > 0 && ps < 1 && pt2 > 0 && pt2 < 1, "shooter %u centre at (%g, %g)", k, ps,
              pt2);
    }
    uint32_t bad = 0;
    for (uint32_t e = 0; covered && e < sf->nu * sf->nv; e++)
        bad += covered[e] != 1;
    CHECK(covered && bad == 0, "%u elements covered by no or several patches", bad);
    uint32_t bad_h = 0;
    for (uint32_t k = 0; hemicube && k < n; k++)
        bad_h += hemicube[k] != 1;
    CHECK(hemicube && bad_h == 0, "hemicube indices are not 0..%u once each", n - 1);
    free(covered);
    free(hemicube);
    CHECK_REL(area, sf->area, 1e-5);
    for (int c = 0; c < 3; c++)
        CHECK(fabs(shot[c] - before[c]) <= 1e-5 * fabs(before[c]) + 1e-12,
              "channel %d: patches shoot %.9g, the surface held %.9g", c, shot[c], before[c]);
    uint32_t changed = 0, not_zero = 0, not_kept = 0;
    const vec4 *snap = r->snapshot.alloc.mapped;
    for (uint32_t e = 0; e < sc->element_count; e++) {
        bool own = sc->elements[e].surface == s;
        if (own) {
            not_zero += bu[e].x != 0 || bu[e].y != 0 || bu[e].z != 0;
            /* The reconstruct pass's near field reads what was shot. */
            not_kept += !shot_kept(snap[e - sf->first_element], bu_before[e], sc->elements[e].area);
        } else {
            changed += memcmp(&bu[e], &bu_before[e], sizeof(vec4)) != 0;
        }
    }
    CHECK(not_zero == 0, "%u elements of the chosen surface keep unshot radiosity", not_zero);
    CHECK(not_kept == 0, "%u elements of the chosen surface are not in the shot snapshot",
          not_kept);
    CHECK(changed == 0, "%u elements of other surfaces changed", changed);
}

/* 300 small quads in a grid, random unshot radiosity: the argmax. */
static void test_argmax(xrad_context *ctx)
{
    char *json = malloc(64 * 1024);
    if (!json)
        return;
    size_t len = (size_t)snprintf(json, 4096,
                                  "{\"unit\":\"m\",\"materials\":[{\"name\":\"m\",\"albedo\":"
                                  "[0.5,0.5,0.5]}],\"objects\":[{\"name\":\"o\",\"surfaces\":[");
    for (int k = 0; k < 300; k++)
        len += (size_t)snprintf(json + len, 64 * 1024 - len,
                                "%s{\"name\":\"q%d\",\"material\":\"m\",\"elements\":[%d,%d],"
                                "\"quad\":{\"origin\":[%d,%d,0],\"u\":[0.%d,0,0],\"v\":[0,0.9,0]}}",
                                k ? "," : "", k, 2 + k % 3, 2 + k % 4, k % 20, k / 20, 5 + k % 5);
    snprintf(json + len, 64 * 1024 - len,
             "]}],\"camera\":{\"position\":[0,0,5],\"look_at\":[0,0,0],\"up\":[0,1,0],"
             "\"fov_degrees\":60}}");
    rig r;
    if (rig_create(ctx, json, 64, &r)) {
        uint32_t seed = 12345;
        for (int trial = 0; trial < 5; trial++) {
            vec4 *bu = r.Bu.alloc.mapped;
            for (uint32_t e = 0; e < r.scene->element_count; e++)
                bu[e] = (vec4){(float)(lcg(&seed) % 1000) / 1000.0f,
                               (float)(lcg(&seed) % 1000) / 1000.0f,
                               (float)(lcg(&seed) % 1000) / 1000.0f, 0};
            memset(r.status.alloc.mapped, 0, sizeof(struct select_status));
            double best = -1;
            uint32_t arg = 0;
            for (uint32_t s = 0; s < r.scene->surface_count; s++) {
                double p = surface_power(&r, bu, s);
                if (p > best) {
                    best = p;
                    arg = s;
                }
            }
            size_t bytes = r.scene->element_count * sizeof(vec4);
            vec4 *before = malloc(bytes);
            if (!before)
                break;
            memcpy(before, bu, bytes);
            if (shoot(ctx, &r, 8, 1e-4)) {
                const struct select_status *st = r.status.alloc.mapped;
                /* Float sums may order two near-equal powers differently. */
                if (st->surface != arg && st->surface < r.scene->surface_count) {
                    double got = surface_power(&r, before, st->surface);
                    CHECK(got >= best * (1 - 1e-6),
                          "trial %d: chose %u (power %.9g), CPU %u (%.9g)", trial, st->surface,
                          got, arg, best);
                    arg = st->surface;
                    best = got;
                }
                check_shot(&r, arg, before, best);
                CHECK(st->selections == 1 && st->patches == st->shooter_count,
                      "counters %u %u", st->selections, st->patches);
                CHECK_REL(st->max_power, best, 1e-5);
            }
            free(before);
        }
    }
    rig_destroy(ctx, &r);
    free(json);
}

/* The patch-count rule: n = max_patches^2 x power / max_power patches,
 * kx = ceil(sqrt(n lu / lv)), ky = ceil(sqrt(n lv / lu)), each in
 * [1, min(elements, max_patches)]. */
static void expect_counts(const surface *sf, double lu, double lv, double ratio, uint32_t mp,
                          uint32_t *kx, uint32_t *ky)
{
    double n = (double)mp * mp * sqrt(ratio);
    double x = ceil(sqrt(n * lu / lv) - 1e-3), y = ceil(sqrt(n * lv / lu) - 1e-3);
    double cx = sf->nu < mp ? sf->nu : mp, cy = sf->nv < mp ? sf->nv : mp;
    *kx = (uint32_t)fmax(1, fmin(x, cx));
    *ky = (uint32_t)fmax(1, fmin(y, cy));
}

static void test_rule(xrad_context *ctx)
{
    static const char *json =
        "{\"unit\":\"m\",\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5]}],"
        "\"objects\":[{\"name\":\"o\",\"surfaces\":["
        "{\"name\":\"square\",\"material\":\"m\",\"elements\":[9,9],"
        " \"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}},"
        "{\"name\":\"wide\",\"material\":\"m\",\"elements\":[17,5],"
        " \"quad\":{\"origin\":[2,0,0],\"u\":[2,0,0],\"v\":[0,1,0]}},"
        "{\"name\":\"small\",\"material\":\"m\",\"elements\":[3,3],"
        " \"quad\":{\"origin\":[5,0,0],\"u\":[0.5,0,0],\"v\":[0,0.5,0]}},"
        "{\"name\":\"coarse\",\"material\":\"m\",\"elements\":[2,2],"
        " \"quad\":{\"origin\":[6,0,0],\"u\":[0,1,0],\"v\":[0,0,1]}},"
        "{\"name\":\"strip\",\"material\":\"m\",\"elements\":[40,4],"
        " \"quad\":{\"origin\":[0,3,0],\"u\":[3,0,0],\"v\":[0,0.2,0]}}"
        "]}],\"camera\":{\"position\":[0,0,5],\"look_at\":[0,0,0],\"up\":[0,1,0],"
        "\"fov_degrees\":60}}";
    rig r;
    if (!rig_create(ctx, json, 64, &r)) {
        rig_destroy(ctx, &r);
        return;
    }
    const surface *sfs = r.scene->surfaces;
    /* Uniform Bu chosen so that the powers are P, P/4, P/64, P/2, 1e-5 P:
     * power = luminance(1) x v x area, and luminance(1, 1, 1) = 1. */
    const double P = 2.0;
    set_uniform(&r, 0, (float)(P / sfs[0].area));
    set_uniform(&r, 1, (float)(P / 4 / sfs[1].area));
    set_uniform(&r, 2, (float)(P / 64 / sfs[2].area));
    set_uniform(&r, 3, (float)(P / 2 / sfs[3].area));
    set_uniform(&r, 4, (float)(1e-5 * P / sfs[4].area));
    static const uint32_t order[4] = {0, 3, 1, 2};
    static const double ratio[4] = {1, 0.5, 0.25, 1.0 / 64};
    static const double lu[4] = {1, 1, 2, 0.5}, lv[4] = {1, 1, 1, 0.5};
    /* By hand, with max_patches^2 sqrt(power / largest) patches: the
     * square 9 x 9 surface at full power 8 x 8 (max_patches); the 2 x 2 one
     * at half power 2 x 2 (its element counts); the 2:1 one at a quarter 32
     * patches as ceil(sqrt(64)) x ceil(sqrt(16)) = 8 x 4; the dimmest, at
     * 1/64, 8 patches as 3 x 3 (ceil(sqrt(8)) each way; 3 elements a side). */
    static const uint32_t by_hand[4][2] = {{8, 8}, {2, 2}, {8, 4}, {3, 3}};
    size_t bytes = r.scene->element_count * sizeof(vec4);
    vec4 *before = malloc(bytes);
    uint32_t patches = 0;
    for (int k = 0; k < 4 && before; k++) {
        uint32_t s = order[k];
        memcpy(before, r.Bu.alloc.mapped, bytes);
        double power = surface_power(&r, before, s);
        if (!shoot(ctx, &r, 8, 1e-4))
            break;
        const struct select_status *st = r.status.alloc.mapped;
        check_shot(&r, s, before, power);
        uint32_t kx, ky;
        expect_counts(&sfs[s], lu[k], lv[k], ratio[k], 8, &kx, &ky);
        CHECK(st->kx == kx && st->ky == ky, "%s: %u x %u patches, want %u x %u", sfs[s].name,
              st->kx, st->ky, kx, ky);
        CHECK(kx == by_hand[k][0] && ky == by_hand[k][1], "%s: the rule gives %u x %u", sfs[s].name,
              kx, ky);
        CHECK_REL(st->max_power, P, 1e-5);
        patches += kx * ky;
        CHECK(st->selections == (uint32_t)k + 1 && st->patches == patches, "counters %u %u",
              st->selections, st->patches);
    }
    /* Left: the strip, at 1e-5 of the largest power, below the threshold. */
    for (int again = 0; again < 2 && before; again++) {
        memcpy(before, r.Bu.alloc.mapped, bytes);
        if (!shoot(ctx, &r, 8, 1e-4))
            break;
        const struct select_status *st = r.status.alloc.mapped;
        CHECK(st->converged == 1, "not converged at 1e-5 of the largest power");
        CHECK(st->shooter_count == 0 && st->draw_instance_count == 0 && st->dispatch_x == 0 &&
                  st->surface == SELECT_NONE,
              "converged shot: %u shooters, %u instances, %u groups, surface %u",
              st->shooter_count, st->draw_instance_count, st->dispatch_x, st->surface);
        CHECK(memcmp(before, r.Bu.alloc.mapped, bytes) == 0, "a converged shot changed Bu");
        CHECK(st->selections == 4 && st->patches == patches, "counters moved: %u %u",
              st->selections, st->patches);
    }
    free(before);
    rig_destroy(ctx, &r);

    /* A cap of 10 shooters: the first shot of the square stays within it. */
    if (rig_create(ctx, json, 10, &r)) {
        set_uniform(&r, 0, 1.0f);
        if (shoot(ctx, &r, 8, 1e-4)) {
            const struct select_status *st = r.status.alloc.mapped;
            CHECK(st->surface == 0 && st->kx * st->ky <= 10 && st->kx * st->ky >= 6,
                  "capped: %u x %u", st->kx, st->ky);
        }
    }
    rig_destroy(ctx, &r);
}

/* A floor whose middle lies under a block (its elements flagged buried):
 * one patch over the whole floor shoots from the open elements, and its
 * centre, under the block, moves to the open element nearest it (by
 * brute force here), so that its hemicube does not look out from under
 * the block. Without the mask the patch is the whole floor about its
 * centre. Third case: the block covers the samples i <= 4, j = 3..7 (its
 * edge at x = 4/9 + half a step = 1/2); the centre (x = 1/2) lies between
 * samples 4 and 5, the nearer sample (5) open: a neighbour buried, it
 * moves too (from inside a box without a bottom a hemicube saw only back
 * faces). */
static void test_buried_centre(xrad_context *ctx)
{
    static const char *json =
        "{\"unit\":\"m\",\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5]}],"
        "\"objects\":[{\"name\":\"o\",\"surfaces\":["
        "{\"name\":\"floor\",\"material\":\"m\",\"elements\":[10,11],"
        " \"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}}"
        "]}],\"camera\":{\"position\":[0,0,5],\"look_at\":[0,0,0],\"up\":[0,1,0],"
        "\"fov_degrees\":60}}";
    for (int variant = 0; variant < 3; variant++) {
        int masked = variant > 0;
        rig r;
        if (!rig_create(ctx, json, 4, &r)) {
            rig_destroy(ctx, &r);
            return;
        }
        const xrad_scene *sc = r.scene;
        struct gpu_element *ge = r.elements.alloc.mapped;
        set_uniform(&r, 0, 1.0f);
        /* Elements (3..5, 2..7) under the block, the centre (0.5, 0.5) among
         * them; the open element nearest it is (6, 5), at (2/3, 1/2). */
        double open_area = 0, best = 1e30;
        vec3 want = v3(0.5, 0.5, 0);
        for (uint32_t e = 0; e < sc->element_count; e++) {
            const element *el = &sc->elements[e];
            bool under = variant == 2 ? el->i <= 4 && el->j >= 3 && el->j <= 7
                                      : el->i >= 3 && el->i <= 5 && el->j >= 2 && el->j <= 7;
            ge[e].flags = under ? GPU_ELEMENT_BURIED : 0u;
            if (under)
                continue;
            open_area += el->area;
            /* The nearest open element's cell centroid (samples at
             * i / (n - 1), cells half a step either side, cut at 0 and 1). */
            vec3 p = v3(ge[e].pos_area.x, ge[e].pos_area.y, 0);
            double d = v3_len(v3_sub(p, v3(0.5, 0.5, 0)));
            if (d < best) {
                best = d;
                double hu = 1.0 / 9, hv = 1.0 / 10;
                double x0 = fmax(0, (el->i - 0.5) * hu), x1 = fmin(1, (el->i + 0.5) * hu);
                double y0 = fmax(0, (el->j - 0.5) * hv), y1 = fmin(1, (el->j + 0.5) * hv);
                want = v3(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0);
            }
        }
        if (!masked)
            want = v3(0.5, 0.5, 0), open_area = sc->surfaces[0].area;
        if (shoot_masked(ctx, &r, 1, 1e-4, masked ? GPU_ELEMENT_BURIED : 0u)) {
            const struct select_status *st = r.status.alloc.mapped;
            const struct gpu_shooter *sh = r.shooters.alloc.mapped;
            CHECK(st->shooter_count == 1, "%s: %u shooters", masked ? "masked" : "plain",
                  st->shooter_count);
            vec3 got = v3(sh[0].pos_area.x, sh[0].pos_area.y, sh[0].pos_area.z);
            CHECK(v3_len(v3_sub(got, want)) < 1e-5,
                  "%s: the patch shoots from (%.4f, %.4f, %.4f), want (%.4f, %.4f, %.4f)",
                  variant == 2 ? "half" : masked ? "masked" : "plain", got.x, got.y, got.z,
                  want.x, want.y, want.z);
            CHECK_REL(sh[0].pos_area.w, open_area, 1e-5);
            /* The copy the reconstruct pass's blocks read: the buried
             * elements as (0, 0, 0, -1), the open ones' radiosity (1, set
             * above) and area. */
            const vec4 *snap = r.snapshot.alloc.mapped;
            uint32_t wrong = 0;
            for (uint32_t e = 0; e < sc->element_count; e++) {
                vec4 v = snap[e];
                wrong += (ge[e].flags & GPU_ELEMENT_BURIED) && masked
                             ? !(v.x == 0 && v.y == 0 && v.z == 0 && v.w == -1.0f)
                             : !(v.y == 1.0f && v.w == (float)sc->elements[e].area);
            }
            CHECK(wrong == 0,
                  "%s: %u elements' copies in `shot` are not their radiosity and area "
                  "(or (0, 0, 0, -1) buried)",
                  masked ? "masked" : "plain", wrong);
        }
        rig_destroy(ctx, &r);
    }
}

/* A shot's group. Surface 0 (4 x 4 elements) holds the largest power P;
 * tiles 1..24 (one element each, or 3 x 3 for every fifth) hold P x
 * share, the share cycling through 0.5, 0.2, 0.13, 0.1, 0.05, 0; tiles
 * of 2 x 2 elements, every fifth of 3 x 3, more than group_elements = 4.
 * With room for 12 shooters in all, the group is, in surface order, the
 * first tiles of 2 x 2 holding at least P / 8. Then the unshot test:
 * with the threshold above every surface's share, the solve still does
 * not converge while the sum exceeds unshot_share of the first sum. */
static void test_group(xrad_context *ctx)
{
    enum { TILES = 24, GE = 4, ROOM = 12 };
    char *json = malloc(16 * 1024);
    if (!json)
        return;
    size_t len = (size_t)snprintf(
        json, 16 * 1024,
        "{\"unit\":\"m\",\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5]}],"
        "\"objects\":[{\"name\":\"o\",\"surfaces\":["
        "{\"name\":\"big\",\"material\":\"m\",\"elements\":[4,4],"
        " \"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}}");
    for (int k = 1; k <= TILES; k++)
        len += (size_t)snprintf(json + len, 16 * 1024 - len,
                                ",{\"name\":\"t%d\",\"material\":\"m\",\"elements\":[%d,%d],"
                                "\"quad\":{\"origin\":[%d,3,0],\"u\":[0.5,0,0],\"v\":[0,0.5,0]}}",
                                k, k % 5 ? 2 : 3, k % 5 ? 2 : 3, k);
    snprintf(json + len, 16 * 1024 - len,
             "]}],\"camera\":{\"position\":[0,0,5],\"look_at\":[0,0,0],\"up\":[0,1,0],"
             "\"fov_degrees\":60}}");
    rig r;
    if (!rig_create_group(ctx, json, 64, ROOM, GE, &r)) {
        rig_destroy(ctx, &r);
        free(json);
        return;
    }
    const xrad_scene *sc = r.scene;
    static const double shares[6] = {0.5, 0.2, 0.13, 0.1, 0.05, 0};
    const double P = 1.0;
    set_uniform(&r, 0, (float)(P / sc->surfaces[0].area));
    double sum = P;
    for (uint32_t k = 1; k <= TILES; k++) {
        double q = P * shares[k % 6];
        set_uniform(&r, k, (float)(q / sc->surfaces[k].area));
        sum += q;
    }
    size_t bytes = sc->element_count * sizeof(vec4);
    vec4 *before = malloc(bytes);
    if (before)
        memcpy(before, r.Bu.alloc.mapped, bytes);
    /* Late in a solve: the largest power seen (the emitted) is 1e5 P, so
     * that the patch rule gives every surface here one patch (64 x
     * sqrt(1e-5) < 1). By hand: the tiles of 2 x 2 elements (k not a
     * multiple of 5) whose share is at least 1/8 (k mod 6 in 0..2), in
     * order. */
    const double M = 1e5 * P;
    struct select_status *status = r.status.alloc.mapped;
    status->max_power = (float)M;
    status->max_unshot = (float)M;
    uint32_t want[TILES], nwant = 0;
    for (uint32_t k = 1; k <= TILES; k++)
        if (k % 5 && k % 6 <= 2)
            want[nwant++] = k;
    if (before && shoot(ctx, &r, 8, 1e-7)) {
        const struct select_status *st = r.status.alloc.mapped;
        const struct gpu_shooter *sh = r.shooters.alloc.mapped;
        const vec4 *bu = r.Bu.alloc.mapped, *snap = r.snapshot.alloc.mapped;
        uint32_t own = st->kx * st->ky;
        uint32_t joined = ROOM - own < nwant ? ROOM - own : nwant;
        CHECK(st->surface == 0 && own == 1, "chose %u, %u x %u", st->surface, st->kx, st->ky);
        CHECK(st->shooter_count == own + joined && st->surfaces == 1 + joined &&
                  st->draw_instance_count == (own + joined) * INSTANCES && st->patches == own + joined,
              "%u shooters, %u surfaces, %u instances, want %u + %u", st->shooter_count,
              st->surfaces, st->draw_instance_count, own, joined);
        CHECK_REL(st->unshot, sum, 1e-5);
        CHECK_REL(st->max_unshot, M, 1e-5);
        uint32_t first = select_shot_capacity(sc);
        for (uint32_t j = 0; j < joined && st->shooter_count == own + joined; j++) {
            const struct gpu_shooter *g = &sh[own + j];
            uint32_t k = want[j];
            const surface *sf = &sc->surfaces[k];
            CHECK(g->surface == k && g->hemicube == own + j && g->i0 == 0 && g->j0 == 0 &&
                      g->i1 == sf->nu - 1 && g->j1 == sf->nv - 1 &&
                      g->shot_first == first + j * GE,
                  "joined %u: surface %u (want %u), hemicube %u, shot_first %u", j, g->surface, k,
                  g->hemicube, g->shot_first);
            CHECK_REL((double)g->pos_area.w, sf->area, 1e-5);
            CHECK_REL((double)g->radiosity.y * g->pos_area.w, P * shares[k % 6], 1e-5);
            uint32_t n = sf->nu * sf->nv;
            uint32_t lost = 0;
            for (uint32_t q = 0; q < n; q++)
                lost += !shot_kept(snap[g->shot_first + q], before[sf->first_element + q],
                                   sc->elements[sf->first_element + q].area);
            CHECK(lost == 0,
                  "joined %u: the unshot radiosity of %u of its elements is not in `shot`", j,
                  lost);
            for (uint32_t e = sf->first_element; e < sf->first_element + n; e++)
                CHECK(bu[e].x == 0 && bu[e].y == 0 && bu[e].z == 0,
                      "joined %u keeps its unshot radiosity", j);
        }
        /* Every surface that did not shoot keeps its Bu. */
        uint32_t changed = 0;
        for (uint32_t e = 0; e < sc->element_count; e++) {
            uint32_t s = sc->elements[e].surface;
            bool shot = s == 0;
            for (uint32_t j = 0; j < joined; j++)
                shot = shot || s == want[j];
            changed += !shot && memcmp(&bu[e], &before[e], sizeof(vec4)) != 0;
        }
        CHECK(changed == 0, "%u elements of surfaces that did not shoot changed", changed);

        /* Left: every tile below 0.6 P, 6e-6 of the largest power seen
         * (threshold 6e-6 is met); unshot_share 0 converges, 1e-6 (of M)
         * shoots on. */
        double left = 0;
        for (uint32_t k = 1; k <= TILES; k++)
            left += surface_power(&r, bu, k);
        CHECK(left > 0.1 * sum, "too little left (%g of %g) for the unshot test", left, sum);
        r.unshot_share = 1e-6;
        uint32_t selections = st->selections;
        if (shoot(ctx, &r, 8, 6e-6)) {
            CHECK(st->converged == 0 && st->selections == selections + 1 && st->shooter_count > 0,
                  "the largest surface below the threshold stopped a solve with %g of %g unshot",
                  left, sum);
            CHECK_REL(st->unshot, left, 1e-5);
        }
        r.unshot_share = 0;
        if (shoot(ctx, &r, 8, 6e-6))
            CHECK(st->converged == 1 && st->shooter_count == 0,
                  "without the unshot test the threshold did not stop the solve");
    }
    free(before);
    rig_destroy(ctx, &r);
    free(json);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_argmax(ctx);
    test_rule(ctx);
    test_buried_centre(ctx);
    test_group(ctx);
    gpu_test_end(&ctx);
    return test_finish();
}
