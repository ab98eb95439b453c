/*
 * Reconstruct pass (src/passes/reconstruct.h) on lavapipe, with shooters
 * and ID hemicubes made on the host:
 *  - two parallel unit squares 1 m apart, every hemicube texel showing the
 *    receiver: each receiver element gets rho B_s F, F the exact
 *    point-to-polygon form factor (Lambert's formula, ground-truth.md) from
 *    the centroid of its cell, and the area-weighted mean over the receiver
 *    is rho B_s times Howell's C-11 (0.19982): closely where the pass takes
 *    the exact near-field form factor (one shooter over the whole plate; 16
 *    shooters in one dispatch with a small subdivide ratio), within the
 *    disk approximation's error where it takes that (16 shooters at the
 *    default ratio; one shooter with subdivision off);
 *  - B and Bu receive the same amount, per channel with the receiver's
 *    albedo; the shooter's own surface and a plate facing away receive
 *    nothing;
 *  - a hemicube showing a plate between shooter and receiver blocks
 *    everything;
 *  - half of every hemicube face showing that plate, with a rotated frame:
 *    an element receives exactly when its texel shows it (exact check), or
 *    when none of its texel and the 8 around it (found with the C
 *    conventions of src/passes/hemicube_geometry.h) shows the plate
 *    (nearest-texel check with the occluder test).
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "gpu/buffer.h"
#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "gpu/image.h"
#include "passes/hemicube_geometry.h"
#include "passes/reconstruct.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "select_shared.h"
#include "solvers/surface_bvh.h"

#define RES 16u
#define SHOOTER 0u
#define RECEIVER 1u
#define AWAY 2u

static const char *plates_json =
    "{\"unit\":\"m\",\"materials\":["
    "{\"name\":\"s\",\"albedo\":[0.5,0.5,0.5]},"
    "{\"name\":\"r\",\"albedo\":[0.5,0.25,0.8]},"
    "{\"name\":\"a\",\"albedo\":[0.9,0.9,0.9]}],"
    "\"objects\":[{\"name\":\"o\",\"surfaces\":["
    "{\"name\":\"shooter\",\"material\":\"s\",\"elements\":[9,9],"
    " \"quad\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0]}},"
    "{\"name\":\"receiver\",\"material\":\"r\",\"elements\":[17,17],"
    " \"quad\":{\"origin\":[0,0,1],\"u\":[0,1,0],\"v\":[1,0,0]}},"
    "{\"name\":\"away\",\"material\":\"a\",\"elements\":[5,5],"
    " \"quad\":{\"origin\":[-1,-1,0.5],\"u\":[3,0,0],\"v\":[0,3,0]}}"
    "]}],\"camera\":{\"position\":[0.5,0.5,3],\"look_at\":[0.5,0.5,0],\"up\":[0,1,0],"
    "\"fov_degrees\":60}}";

static const float shot[3] = {1.0f, 2.0f, 0.5f}; /* radiosity of every shooter */
static const double angle = 0.7;                 /* hemicube rotation about the normal */

typedef struct rig {
    xrad_scene *scene;
    gpu_buffer surfaces, elements, materials, B, Bu, shooters, status;
    gpu_buffer snapshot; /* the shot surface's Bu by element (select's `shot`) */
    gpu_buffer bvh_nodes, bvh_items; /* over the surfaces, as gpu_scene makes it */
    gpu_image ids;
    reconstruct_pass *pass;
    uint32_t count; /* shooters */
} rig;

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

/* The receiver point of an element: the centroid of its cell (scene.h). */
static vec3 cell_centroid(const xrad_scene *sc, uint32_t e)
{
    const element *el = &sc->elements[e];
    const surface *sf = &sc->surfaces[el->surface];
    double h = 1.0 / (sf->nu - 1), g = 1.0 / (sf->nv - 1);
    double s0 = fmax(0, (el->i - 0.5) * h), s1 = fmin(1, (el->i + 0.5) * h);
    double t0 = fmax(0, (el->j - 0.5) * g), t1 = fmin(1, (el->j + 0.5) * g);
    return surface_point(sf, 0.5 * (s0 + s1), 0.5 * (t0 + t1));
}

static vec3 tangent(void) { return v3(cos(angle), sin(angle), 0); }

/* The shooter plate split into kx x ky patches of its elements. */
static void make_shooters(rig *r, uint32_t kx, uint32_t ky)
{
    const xrad_scene *sc = r->scene;
    const surface *sf = &sc->surfaces[SHOOTER];
    struct gpu_shooter *sh = r->shooters.alloc.mapped;
    vec3 t = tangent();
    for (uint32_t py = 0; py < ky; py++) {
        for (uint32_t px = 0; px < kx; px++) {
            uint32_t k = py * kx + px;
            uint32_t i0 = px * sf->nu / kx, i1 = (px + 1) * sf->nu / kx - 1;
            uint32_t j0 = py * sf->nv / ky, j1 = (py + 1) * sf->nv / ky - 1;
            double area = 0;
            for (uint32_t j = j0; j <= j1; j++)
                for (uint32_t i = i0; i <= i1; i++)
                    area += sc->elements[sf->first_element + j * sf->nu + i].area;
            /* The element cells of scene.h: half a spacing around each sample. */
            double h = 1.0 / (sf->nu - 1), g = 1.0 / (sf->nv - 1);
            double s0 = fmax(0, (i0 - 0.5) * h), s1 = fmin(1, (i1 + 0.5) * h);
            double t0 = fmax(0, (j0 - 0.5) * g), t1 = fmin(1, (j1 + 0.5) * g);
            vec3 c = surface_point(sf, 0.5 * (s0 + s1), 0.5 * (t0 + t1));
            sh[k] = (struct gpu_shooter){
                .pos_area = {(float)c.x, (float)c.y, (float)c.z, (float)area},
                .normal = {0, 0, 1, 0},
                .tangent = {(float)t.x, (float)t.y, (float)t.z, 0},
                .radiosity = {shot[0], shot[1], shot[2], 0},
                .surface = SHOOTER,
                .i0 = i0,
                .i1 = i1,
                .j0 = j0,
                .j1 = j1,
                .hemicube = k,
            };
        }
    }
    r->count = kx * ky;
    struct select_status *st = r->status.alloc.mapped;
    memset(st, 0, sizeof(*st));
    st->shooter_count = r->count;
    st->dispatch_x = (sc->element_count + reconstruct_group_size() - 1) / reconstruct_group_size();
    st->dispatch_y = st->dispatch_z = 1;
}

static int rig_create(xrad_context *ctx, uint32_t max_shooters, rig *r)
{
    memset(r, 0, sizeof(*r));
    xrad_error err = {0};
    xrad_status st =
        xrad_scene_parse(plates_json, strlen(plates_json), "plates.json", &r->scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return 0;
    const xrad_scene *sc = r->scene;
    gpu_image_desc ids = {
        .format = VK_FORMAT_R32_UINT,
        .width = RES,
        .height = RES,
        .layers = max_shooters * HEMICUBE_FACES,
        .array = true,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    if ((st = host_buffer(ctx, sc->surface_count * sizeof(struct gpu_surface), &r->surfaces,
                          &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(struct gpu_element), &r->elements,
                          &err)) ||
        (st = host_buffer(ctx, sc->material_count * sizeof(struct gpu_material), &r->materials,
                          &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(vec4), &r->B, &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(vec4), &r->Bu, &err)) ||
        (st = host_buffer(ctx, max_shooters * sizeof(struct gpu_shooter), &r->shooters, &err)) ||
        (st = host_buffer(ctx, sizeof(struct select_status), &r->status, &err)) ||
        (st = host_buffer(ctx, sc->element_count * sizeof(vec4), &r->snapshot, &err)) ||
        (st = gpu_image_create(ctx, &ids, &r->ids, &err)) ||
        (st = reconstruct_create(ctx, false, &r->pass, &err))) {
        CHECK(0, "resources: %s", err.message);
        return 0;
    }
    struct gpu_surface *gs = r->surfaces.alloc.mapped;
    struct gpu_element *ge = r->elements.alloc.mapped;
    struct gpu_material *gm = r->materials.alloc.mapped;
    for (uint32_t m = 0; m < sc->material_count; m++) {
        const material *mt = &sc->materials[m];
        gm[m].albedo = (vec4){(float)mt->albedo.x, (float)mt->albedo.y, (float)mt->albedo.z, 0};
        gm[m].emission =
            (vec4){(float)mt->emission.x, (float)mt->emission.y, (float)mt->emission.z, 0};
    }
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
        for (uint32_t e = sf->first_element; e < sf->first_element + sf->nu * sf->nv; e++) {
            vec3 p = sc->elements[e].pos; /* one static object at rest: world = object */
            float a = (float)sc->elements[e].area;
            ge[e].pos_area = (vec4){(float)p.x, (float)p.y, (float)p.z, a};
            ge[e].normal = (vec4){(float)n.x, (float)n.y, (float)n.z, 0};
            ge[e].surface = s;
            vec3 rho = scene_element_albedo(sc, e);
            ge[e].albedo = (vec4){(float)rho.x, (float)rho.y, (float)rho.z, 0};
        }
    }
    quad_bvh bvh = {0};
    uint32_t depth = 0;
    size_t nodes = 2 * (size_t)(sc->surface_count ? sc->surface_count : 1);
    if ((st = surface_bvh_build(gs, sc->surface_count, &bvh, &depth, &err)) ||
        (st = host_buffer(ctx, nodes * sizeof(struct gpu_bvh_node), &r->bvh_nodes, &err)) ||
        (st = host_buffer(ctx, (sc->surface_count + 1) * sizeof(uint32_t), &r->bvh_items,
                          &err))) {
        CHECK(0, "surface hierarchy: %s", err.message);
        quad_bvh_free(&bvh);
        return 0;
    }
    surface_bvh_refit(&bvh, gs, 1e-5f, r->bvh_nodes.alloc.mapped);
    memcpy(r->bvh_items.alloc.mapped, bvh.items, sc->surface_count * sizeof(uint32_t));
    quad_bvh_free(&bvh);
    reconstruct_bind(ctx, r->pass,
                     &(reconstruct_bindings){&r->surfaces, &r->elements, &r->materials, &r->B,
                                             &r->Bu, &r->shooters, &r->status, r->ids.view,
                                             /* unused without conservation */
                                             &r->B, &r->B, &r->snapshot, &r->bvh_nodes,
                                             &r->bvh_items});
    /* Every element of the shooter shoots `shot`, as every patch does. */
    vec4 *snap = r->snapshot.alloc.mapped;
    for (uint32_t k = 0; k < sc->element_count; k++)
        snap[k] = (vec4){shot[0], shot[1], shot[2], 0};
    return 1;
}

static void rig_destroy(xrad_context *ctx, rig *r)
{
    reconstruct_destroy(ctx, &r->pass);
    gpu_image_destroy(ctx, &r->ids);
    gpu_buffer_destroy(ctx, &r->status);
    gpu_buffer_destroy(ctx, &r->snapshot);
    gpu_buffer_destroy(ctx, &r->bvh_nodes);
    gpu_buffer_destroy(ctx, &r->bvh_items);
    gpu_buffer_destroy(ctx, &r->shooters);
    gpu_buffer_destroy(ctx, &r->Bu);
    gpu_buffer_destroy(ctx, &r->B);
    gpu_buffer_destroy(ctx, &r->materials);
    gpu_buffer_destroy(ctx, &r->elements);
    gpu_buffer_destroy(ctx, &r->surfaces);
    xrad_scene_destroy(&r->scene);
}

/* Fills every hemicube layer with id(face, column, row). */
static int fill_ids(xrad_context *ctx, rig *r, uint32_t (*id)(int face, uint32_t x, uint32_t y))
{
    size_t texels = (size_t)RES * RES * r->ids.layers;
    uint32_t *data = malloc(texels * sizeof(*data));
    if (!data)
        return 0;
    for (uint32_t l = 0; l < r->ids.layers; l++)
        for (uint32_t y = 0; y < RES; y++)
            for (uint32_t x = 0; x < RES; x++)
                data[((size_t)l * RES + y) * RES + x] = id((int)(l % HEMICUBE_FACES), x, y);
    xrad_error err = {0};
    xrad_status st = gpu_upload_image(ctx, &r->ids, data, texels * sizeof(*data),
                                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, &err);
    CHECK(st == XRAD_OK, "upload: %s", err.message);
    free(data);
    return st == XRAD_OK;
}

static int run(xrad_context *ctx, rig *r, double ratio, bool exact_texel_only)
{
    memset(r->B.alloc.mapped, 0, r->B.size);
    memset(r->Bu.alloc.mapped, 0, r->Bu.size);
    xrad_error err = {0};
    gpu_cmd c;
    xrad_status st = gpu_cmd_begin(ctx, &c, &err);
    CHECK(st == XRAD_OK, "begin: %s", err.message);
    if (st)
        return 0;
    reconstruct_params p = {
        .element_count = r->scene->element_count,
        .hemicube_res = RES,
        .subdivide_ratio = ratio,
        .exact_texel_only = exact_texel_only,
    };
    reconstruct_record(r->pass, c.cmd, &p, &r->status,
                       offsetof(struct select_status, dispatch_x));
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

/* Lambert: form factor from a point with unit normal n to a convex polygon
 * (ground-truth.md). */
static double point_to_polygon(vec3 p, vec3 n, const vec3 *v, int count)
{
    double sum = 0;
    for (int k = 0; k < count; k++) {
        vec3 a = v3_sub(v[k], p), b = v3_sub(v[(k + 1) % count], p);
        vec3 c = v3_cross(a, b);
        double cl = v3_len(c);
        if (cl > 0)
            sum += atan2(cl, v3_dot(a, b)) * v3_dot(n, c) / cl;
    }
    return fabs(sum) / (2 * M_PI);
}

/* Howell C-11: identical parallel directly opposed rectangles a x b, c apart. */
static double howell_c11(double a, double b, double c)
{
    double X = a / c, Y = b / c, X2 = X * X, Y2 = Y * Y;
    return 2 / (M_PI * X * Y) *
           (log(sqrt((1 + X2) * (1 + Y2) / (1 + X2 + Y2))) +
            X * sqrt(1 + Y2) * atan(X / sqrt(1 + Y2)) +
            Y * sqrt(1 + X2) * atan(Y / sqrt(1 + X2)) - X * atan(X) - Y * atan(Y));
}

static uint32_t all_receiver(int face, uint32_t x, uint32_t y) { return RECEIVER + 1; }
static uint32_t all_away(int face, uint32_t x, uint32_t y) { return AWAY + 1; }
/* The right half shows the plate between shooter and receiver: an
 * occluder the nearest-texel check must respect (spirv/shooting.glsl). */
static uint32_t left_half(int face, uint32_t x, uint32_t y)
{
    return x < RES / 2 ? RECEIVER + 1 : AWAY + 1;
}

typedef struct result {
    double mean_f;    /* area-weighted mean of dB / (rho B_s) over the receiver (green) */
    double max_rel;   /* largest per-element relative error against Lambert */
    double mean_rel;  /* mean per-element relative error */
} result;

/* Checks the receiver against rho B_s F(point -> plate) and everything else
 * against zero; `visible` says which receiver elements should receive. */
static result check_plates(const rig *r, const bool *visible, const char *what)
{
    const xrad_scene *sc = r->scene;
    const vec4 *B = r->B.alloc.mapped, *Bu = r->Bu.alloc.mapped;
    const surface *rs = &sc->surfaces[RECEIVER];
    vec3 rho = sc->materials[rs->material].albedo;
    vec3 plate[4];
    vec3 pn;
    scene_surface_world(sc, SHOOTER, 0, plate, &pn);
    result out = {0};
    double area = 0;
    uint32_t n = 0, differ = 0, stray = 0, wrong_visibility = 0;
    for (uint32_t e = 0; e < sc->element_count; e++) {
        const element *el = &sc->elements[e];
        differ += memcmp(&B[e], &Bu[e], sizeof(vec4)) != 0;
        if (el->surface != RECEIVER || (visible && !visible[e - rs->first_element])) {
            stray += B[e].x != 0 || B[e].y != 0 || B[e].z != 0;
            continue;
        }
        double f = point_to_polygon(cell_centroid(sc, e), v3(0, 0, -1), plate, 4);
        const double want[3] = {rho.x * shot[0] * f, rho.y * shot[1] * f, rho.z * shot[2] * f};
        const double got[3] = {B[e].x, B[e].y, B[e].z};
        if (got[1] == 0)
            wrong_visibility++;
        for (int c = 0; c < 3; c++) {
            double rel = fabs(got[c] - want[c]) / want[c];
            out.max_rel = fmax(out.max_rel, rel);
            if (c == 1)
                out.mean_rel += rel;
        }
        out.mean_f += got[1] / (rho.y * shot[1]) * el->area;
        area += el->area;
        n++;
    }
    out.mean_f /= area;
    out.mean_rel /= n;
    CHECK(differ == 0, "%s: B and Bu differ on %u elements", what, differ);
    CHECK(stray == 0, "%s: %u elements that must receive nothing received", what, stray);
    CHECK(wrong_visibility == 0, "%s: %u visible elements received nothing", what,
          wrong_visibility);
    return out;
}

static void test_open(xrad_context *ctx)
{
    rig r;
    if (!rig_create(ctx, 16, &r) || !fill_ids(ctx, &r, all_receiver)) {
        rig_destroy(ctx, &r);
        return;
    }
    double c11 = howell_c11(1, 1, 1);
    CHECK_ABS(c11, 0.19982, 1e-5); /* ground-truth.md */

    /* One shooter over the whole plate: A_s / r^2 >= 1/3 everywhere, so
     * every element takes the exact form factor at the default ratio, and
     * the single disk with subdivision off. 4 x 4 shooters: A_s / r^2 <=
     * 1/16, the disk approximation at the default ratio, exact at 0.01. */
    make_shooters(&r, 1, 1);
    result one = {0}, plain = {0}, many = {0}, many_exact = {0};
    if (run(ctx, &r, 0.1, false))
        one = check_plates(&r, NULL, "one shooter");
    if (run(ctx, &r, 1e6, false))
        plain = check_plates(&r, NULL, "one shooter, one disk");
    make_shooters(&r, 4, 4);
    if (run(ctx, &r, 0.1, false))
        many = check_plates(&r, NULL, "16 shooters");
    if (run(ctx, &r, 0.01, false))
        many_exact = check_plates(&r, NULL, "16 shooters, ratio 0.01");
    fprintf(stderr, "C-11 %.6f; mean F, and per element vs Lambert max / mean relative error:\n",
            c11);
    const result *all[4] = {&one, &plain, &many, &many_exact};
    const char *names[4] = {"1 shooter, exact", "1 shooter, one disk", "16 shooters, disks",
                            "16 shooters, exact"};
    for (int k = 0; k < 4; k++)
        fprintf(stderr, "  %-20s %.6f  %.5f / %.5f\n", names[k], all[k]->mean_f, all[k]->max_rel,
                all[k]->mean_rel);
    /* Tolerances. Exact form factors: float rounding only, per element
     * (1e-3 leaves ample room above fp32's 1e-7 and the atan of small
     * angles); the 17 x 17 cells then integrate the point form factor by the
     * midpoint rule, whose error O(h^2 |F''| / 24) with h = 1/16 is about
     * 1e-4 of F here (0.2% allowed). Disks: each of area a at distance r
     * gives a cos cos / (pi r^2 + a), which differs from the exact form
     * factor of a square of that area by a fraction of order a / (pi r^2):
     * 0.0625 / pi = 2% for the 4 x 4 shooters (3% allowed per element, 2% in
     * the mean); a single unit disk is far worse (only required to be). */
    CHECK(one.max_rel < 1e-3 && many_exact.max_rel < 1e-3, "exact: per-element error %g, %g",
          one.max_rel, many_exact.max_rel);
    CHECK_REL(one.mean_f, c11, 0.002);
    CHECK_REL(many_exact.mean_f, c11, 0.002);
    CHECK(many.max_rel < 0.03, "disks: per-element error %g", many.max_rel);
    CHECK_REL(many.mean_f, c11, 0.02);
    CHECK(plain.mean_rel > 10 * one.mean_rel, "one disk (%g) is not worse than exact (%g)",
          plain.mean_rel, one.mean_rel);

    /* Every hemicube shows the plate between shooter and receiver, which
     * every segment from one to the other crosses: the receiver is hidden.
     * Nothing is received anywhere. */
    if (fill_ids(ctx, &r, all_away) && run(ctx, &r, 0.1, false)) {
        uint32_t lit = 0;
        const vec4 *B = r.B.alloc.mapped;
        for (uint32_t e = 0; e < r.scene->element_count; e++)
            lit += B[e].x != 0 || B[e].y != 0 || B[e].z != 0;
        CHECK(lit == 0, "blocked: %u elements received", lit);
    }
    rig_destroy(ctx, &r);
}

/* Half of every face shows the receiver: the lookup agrees with the C
 * conventions, frame rotation included. */
static void test_half(xrad_context *ctx)
{
    rig r;
    if (!rig_create(ctx, 1, &r) || !fill_ids(ctx, &r, left_half)) {
        rig_destroy(ctx, &r);
        return;
    }
    make_shooters(&r, 1, 1);
    const xrad_scene *sc = r.scene;
    const surface *rs = &sc->surfaces[RECEIVER];
    const struct gpu_shooter *sh = r.shooters.alloc.mapped;
    vec3 c = v3(sh->pos_area.x, sh->pos_area.y, sh->pos_area.z);
    vec3 t = tangent(), z = v3(0, 0, 1), y = v3_cross(z, t);
    uint32_t n = rs->nu * rs->nv;
    bool *exact = calloc(n, sizeof(bool)), *near = calloc(n, sizeof(bool)),
         *ambiguous = calloc(n, sizeof(bool));
    uint32_t counts[2] = {0, 0};
    for (uint32_t k = 0; exact && near && ambiguous && k < n; k++) {
        vec3 d = v3_sub(cell_centroid(sc, rs->first_element + k), c);
        vec3 l = v3(v3_dot(d, t), v3_dot(d, y), v3_dot(d, z));
        uint32_t px, py;
        int face = hemicube_lookup(l, RES, &px, &py);
        vec3 fr, fu, ff;
        hemicube_face_axes(face, &fr, &fu, &ff);
        double col = (v3_dot(l, fr) / v3_dot(l, ff) + 1) * 0.5 * RES;
        /* Float on the GPU may round a direction within 1e-3 texel of a
         * column boundary either way. */
        double frac = col - floor(col);
        ambiguous[k] = frac < 1e-3 || frac > 1 - 1e-3;
        exact[k] = px < RES / 2;
        /* Visible where none of the 3 x 3 texels shows the occluder:
         * column px + 1 is in the visible half. */
        near[k] = px + 1 < RES / 2;
        counts[exact[k]]++;
    }
    CHECK(counts[0] > 20 && counts[1] > 20, "the half split leaves %u / %u elements", counts[0],
          counts[1]);
    for (int pass = 0; pass < 2 && exact && near && ambiguous; pass++) {
        const bool *want = pass ? near : exact;
        if (!run(ctx, &r, 0.1, pass == 0))
            break;
        const vec4 *B = r.B.alloc.mapped;
        uint32_t wrong = 0;
        for (uint32_t k = 0; k < n; k++) {
            bool got = B[rs->first_element + k].y != 0;
            wrong += !ambiguous[k] && got != want[k];
        }
        CHECK(wrong == 0, "%s: %u elements disagree with the host lookup",
              pass ? "nearest-texel check" : "exact texel", wrong);
    }
    free(exact);
    free(near);
    free(ambiguous);
    rig_destroy(ctx, &r);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_open(ctx);
    test_half(ctx);
    gpu_test_end(&ctx);
    return test_finish();
}
