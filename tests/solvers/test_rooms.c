/*
 * The GPU methods on generic rooms against the CPU reference (issue 14):
 * every room of tests/solvers/rooms.c (seed ROOMS_SEED) and every GPU
 * method at default settings (a zeroed xrad_solver_desc with only .method
 * and .time set). A room with a moving box is solved at ROOMS_T0 and
 * advanced ROOMS_FRAMES frames of 1 / ROOMS_FPS s (gather, whose advance is
 * a fresh solve, is solved once at the last frame's pose); the reference is
 * solved at the last frame's time. Held to the thresholds:
 *  - element space (xrad_atlas_compare, no camera): surface_error <= 0.02
 *    (the worst surface's area-weighted mean off by at most 2%) and the
 *    element relative error's 95th percentile <= 0.05;
 *  - image space (xrad_image_compare, the room's camera: a corner looking
 *    at the far corner): |mean ratio - 1| <= 0.01 over the pixels that show
 *    a non-emitting surface (the emitters masked by rendering an atlas of 1
 *    on their elements).
 * One table row per (room, method): nrmse, rel_rms, image mean ratio,
 * surface_error with the worst surface, p95, the method's wall time.
 *
 * Usage: test_rooms [METHOD] [FIRST-LAST]: one method (all four without
 * it), rooms FIRST to LAST (all without it). Validation on; any message
 * fails the test.
 */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "gpu/gpu_test.h"
#include "scene/scene.h"
#include "solvers/rooms.h"

/* Issue 14's thresholds: every row is measured against them and the
 * summary says which rows meet them. */
#define SURFACE_ERROR_MAX 0.02
#define P95_MAX 0.05
#define IMAGE_RATIO_TOL 0.01
/* What the checks hold every row to while the dynamic methods do not meet
 * the thresholds above everywhere (issue 14 open: the cabinet beside room
 * 2's wall light and room 5's moving box 2.9-3.4% off at their 8 patches
 * a side, see README "Accuracy"). Each bound fails what an earlier fix
 * removed, so that its return fails the test:
 *  - progressive (issue 14's own 0.02, 0.05, image 0.01; measured at its
 *    default 12 patches a side 0.0060-0.0182, 0.008-0.032, image
 *    0.9926-1.0003): 8 patches a side (room 2's back wall beside its
 *    flush light 0.0203, README "12 shooting patches a side"), patches
 *    shooting from inside a box without a bottom or a cabinet's pocket
 *    (0.14 and 0.10 in rooms 1 and 2 before), near patches seen by their
 *    centre (room 4: p95 0.110, 0.300), patches within two sizes by their
 *    mean (rooms 2 and 4: 0.051, 0.066), a light cut by a box side's plane
 *    seen from its centre (room 3: 0.087), a side seen edge-on drawn in no
 *    texel (room 3: 0.045);
 *  - incremental (0.045, 0.05; measured 0.011-0.034 and 0.014-0.041): the
 *    same, its first solve with its redistribution's visibility (p95 0.17
 *    in room 3), its moving box taking C's light by the patches' centres
 *    (0.14 in room 5); and in rooms 1 and 3 issue 14's own 0.02
 *    (INCREMENTAL_MOVER_ROOMS; measured 0.0129, 0.0113), which the moving
 *    box met once it took C's light after C's changes, with its own light
 *    on C (incremental_reconstruct.comp c_light; 0.0329 and 0.0203
 *    before: its sides at 0.967 and 0.980);
 *  - cross (0.03, 0.05; measured 0.013-0.029 and 0.014-0.042): its
 *    restart without the near patches' blocks (p95 0.087, room 1), the
 *    light cut by the floating box's side (room 3: 0.106), the gather
 *    hemicubes that light M reading the floor at the box's foot bilinearly
 *    towards the buried samples under it (room 1: 0.045, then 0.034), M
 *    gathering before the frame's iterations (cross_regather off), its
 *    sides a frame late (room 1: 0.034, now 0.015);
 *  - gather (issue 14's own 0.02, 0.05, image 0.01; measured 0.0013-0.0092,
 *    0.004-0.011, image 0.998-1.000): its stop after 3 bounces in a dark
 *    hall (ceiling 0.97), hemicubes reading the atlas bilinearly (a box
 *    side's bottom row 0.89-0.93), a small lamp in hemicube texels (p95
 *    0.136), all three before the direct pass and the cells (gather.c). */
#define GUARD_SURFACE_ERROR_MAX(m)                                                                 \
    ((m) == XRAD_METHOD_CROSS         ? 0.03                                                       \
     : (m) == XRAD_METHOD_GATHER      ? 0.02                                                       \
     : (m) == XRAD_METHOD_INCREMENTAL ? 0.045                                                      \
                                      : 0.02)
#define GUARD_P95_MAX(m) 0.05
/* Rooms whose moving box incremental holds to SURFACE_ERROR_MAX (above). */
#define INCREMENTAL_MOVER_ROOMS(room) ((room) == 1 || (room) == 3)
/* The worst element, relative to max(B_ref, 1e-3 x the scene's mean B_ref):
 * an element the reference leaves dark (closed in by a moving box) that a
 * method lights at the scene's mean is 1000 off. Cross's floor under room
 * 5's bottomless box (3.3 W/m^2, 614) and under room 1's box (830) before
 * cross took the light of what a moving object closes in; 0.06-1.63 now,
 * progressive and gather 0-1.00. Incremental's frames took too much
 * there, shot by shot: the floor element under room 5's box ended at
 * -0.41 W/m^2 against the reference's 0 (74; room 1: 43) before such an
 * element was set to its emission (incremental_reconstruct.comp reset());
 * 0.06-1.06 now. */
#define GUARD_ELEMENT_MAX(m) 10.0
#define GUARD_IMAGE_RATIO_TOL(m)                                                                   \
    ((m) == XRAD_METHOD_GATHER || (m) == XRAD_METHOD_PROGRESSIVE ? 0.01 : 0.015)

typedef struct row {
    uint32_t room;
    xrad_method method;
    xrad_image_metrics im;
    xrad_element_metrics em;
    char worst[64];
    double seconds;
    int ok;
} row;

#define MAX_ROWS (ROOMS_COUNT * 4)
static row rows[MAX_ROWS];
static uint32_t nrows;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double frame_time(uint32_t k)
{
    return ROOMS_T0 + (double)k / ROOMS_FPS;
}

/* Non-zero where the view shows an emitting surface: an atlas of 1 on the
 * emitters' elements, drawn from the same view. NULL after a failed CHECK. */
static float *emitter_mask(xrad_context *ctx, const xrad_scene *scene,
                           const xrad_view_desc *view, uint32_t w, uint32_t h)
{
    xrad_error err = {0};
    xrad_atlas a = {0};
    float *img = NULL, *mask = NULL;
    uint32_t iw = 0, ih = 0;
    if (xrad_atlas_create(scene, &a, &err) == XRAD_OK) {
        for (uint32_t e = 0; e < scene->element_count; e++) {
            const element *el = &scene->elements[e];
            vec3 em = scene->materials[scene->surfaces[el->surface].material].emission;
            if (em.x > 0 || em.y > 0 || em.z > 0) {
                float *t = &a.rgba[((size_t)el->texel_y * a.width + el->texel_x) * 4];
                t[0] = t[1] = t[2] = t[3] = 1;
            }
        }
        if (xrad_render_view(ctx, scene, &a, view, &img, &iw, &ih, &err) == XRAD_OK &&
            iw == w && ih == h) {
            mask = malloc((size_t)w * h * sizeof(float));
            for (size_t i = 0; mask && i < (size_t)w * h; i++)
                mask[i] = img[i * 4] > 0 ? 1.0f : 0.0f;
        }
    }
    CHECK(mask != NULL, "emitter mask: %s", err.message);
    free(img);
    xrad_atlas_destroy(&a);
    return mask;
}

static void print_row(const row *r)
{
    fprintf(stderr,
            "%4u  %-11s  %8.5f  %7.4f  %7.4f  %7.4f %-18s %6.4f  %6.4f  %7.2f  %7.1f  %s\n",
            r->room, xrad_method_name(r->method), r->im.nrmse, r->im.rel_rms, r->im.mean_ratio,
            r->em.surface_error, r->worst, r->em.worst_ratio, r->em.p95, r->em.max, r->seconds,
            r->ok ? "ok" : "FAIL");
}

/* The surfaces whose mean is off by more than SURFACE_ERROR_MAX, worst
 * first (8 at most): where a method's error lies. */
static void print_surfaces(const xrad_scene *scene, const double *ratio, uint32_t n)
{
    uint32_t shown[8], nshown = 0;
    while (nshown < 8) {
        uint32_t best = UINT32_MAX;
        for (uint32_t k = 0; k < n; k++) {
            int taken = 0;
            for (uint32_t j = 0; j < nshown; j++)
                taken |= shown[j] == k;
            if (!taken && fabs(ratio[k] - 1) > SURFACE_ERROR_MAX &&
                (best == UINT32_MAX || fabs(ratio[k] - 1) > fabs(ratio[best] - 1)))
                best = k;
        }
        if (best == UINT32_MAX)
            break;
        shown[nshown++] = best;
    }
    if (!nshown)
        return;
    fprintf(stderr, "      surfaces off by more than %.0f%%:", 100 * SURFACE_ERROR_MAX);
    for (uint32_t j = 0; j < nshown; j++)
        fprintf(stderr, " %s %.3f", scene->surfaces[shown[j]].name, ratio[shown[j]]);
    fprintf(stderr, "\n");
}

static void print_header(void)
{
    fprintf(stderr, "room  method          nrmse  rel_rms  img_mean  surf_err worst surface      "
                    "ratio     p95   el_max   time_s\n");
}

/* The method's solution at the room's comparison time, or NULL. */
static xrad_solver *solve(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                          int dynamic, double *seconds)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    double t0 = now();
    xrad_solver_desc d = {.method = m, .time = dynamic ? ROOMS_T0 : 0};
    xrad_status st = xrad_solver_create(ctx, scene, &d, &s, &err);
    if (m == XRAD_METHOD_GATHER) {
        /* gather has no redistribution: an advance poses the scene and
         * solves anew (xrad_solver_advance), so the frames before the last
         * would be solved for nothing (a minute each on lavapipe). Posed at
         * the last frame and solved once. */
        if (!st && dynamic)
            st = xrad_solver_set_time(s, frame_time(ROOMS_FRAMES), &err);
        if (!st)
            st = xrad_solver_solve(s, &err);
    } else {
        if (!st)
            st = xrad_solver_solve(s, &err);
        for (uint32_t k = 1; dynamic && !st && k <= ROOMS_FRAMES; k++)
            st = xrad_solver_advance(s, frame_time(k), &err);
    }
    *seconds = now() - t0;
    CHECK(st == XRAD_OK, "%s: %s", xrad_method_name(m), err.message);
    if (st)
        xrad_solver_destroy(&s);
    return s;
}

static void room_test(xrad_context *ctx, uint32_t index, const xrad_method *methods,
                      size_t nmethods)
{
    rooms_room room;
    CHECK(rooms_make(index, ROOMS_SEED, &room) == 0, "room %u: generator failed", index);
    if (!room.json)
        return;
    fprintf(stderr, "\nroom %u: %s%s\n  %s\n", index, room.name,
            room.dynamic ? " (dynamic)" : "", room.description);
    xrad_error err = {0};
    xrad_scene *scene = NULL;
    char name[32];
    snprintf(name, sizeof name, "room-%u.json", index);
    CHECK(xrad_scene_parse(room.json, strlen(room.json), name, &scene, &err) == XRAD_OK,
          "%s", err.message);
    if (!scene) {
        fprintf(stderr, "%s", room.json);
        rooms_free(&room);
        return;
    }
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    CHECK(info.elements == room.elements, "room %u: %u elements, the generator counted %u",
          index, info.elements, room.elements);

    double *ratios = calloc(info.surfaces, sizeof(double));
    CHECK(ratios != NULL, "room %u: no memory", index);
    double t = room.dynamic ? frame_time(ROOMS_FRAMES) : 0;
    xrad_atlas ref = {0}, got = {0};
    xrad_reference_stats rst = {0};
    float *ref_img = NULL, *mask = NULL;
    uint32_t w = 0, h = 0;
    xrad_view_desc view = {.time = t};
    double t0 = now();
    xrad_status st = xrad_atlas_create(scene, &ref, &err);
    if (!st)
        st = xrad_atlas_create(scene, &got, &err);
    if (!st)
        st = xrad_reference_solve(scene, &(xrad_reference_desc){.time = t}, &ref, &rst, &err);
    double ref_seconds = now() - t0;
    if (!st)
        st = xrad_render_view(ctx, scene, &ref, &view, &ref_img, &w, &h, &err);
    CHECK(st == XRAD_OK, "room %u: reference: %s", index, err.message);
    if (!st && ratios)
        mask = emitter_mask(ctx, scene, &view, w, h);
    if (!st && mask) {
        fprintf(stderr, "  %u elements (%u dynamic), atlas %u x %u; compared at t = %.4f s; "
                        "CPU reference %.1f s (%u sweeps, residual %.2g)\n",
                info.elements, info.dynamic_elements, info.atlas_width, info.atlas_height, t,
                ref_seconds, rst.sweeps, rst.residual);
        print_header();
    }
    for (size_t k = 0; !st && mask && k < nmethods; k++) {
        row r = {.room = index, .method = methods[k]};
        xrad_solver *s = solve(ctx, scene, methods[k], room.dynamic, &r.seconds);
        float *img = NULL;
        uint32_t iw = 0, ih = 0;
        xrad_status rs = XRAD_ERROR_SYSTEM;
        if (s) {
            rs = xrad_solver_read(s, &got, &err);
            if (!rs)
                rs = xrad_atlas_compare(scene, &got, &ref, &r.em, ratios, &err);
            if (!rs)
                rs = xrad_render_view(ctx, scene, &got, &view, &img, &iw, &ih, &err);
            if (!rs && (iw != w || ih != h))
                rs = XRAD_ERROR_SYSTEM;
            if (!rs)
                rs = xrad_image_compare(img, ref_img, mask, w, h, &r.im, &err);
            CHECK(rs == XRAD_OK, "room %u %s: %s", index, xrad_method_name(methods[k]),
                  err.message);
        }
        if (!rs) {
            xrad_surface_info si = {0};
            xrad_error e2 = {0};
            snprintf(r.worst, sizeof r.worst, "%s",
                     xrad_scene_get_surface(scene, r.em.worst_surface, &si, &e2) == XRAD_OK
                         ? si.name
                         : "?");
            r.ok = r.em.surface_error <= SURFACE_ERROR_MAX && r.em.p95 <= P95_MAX &&
                   fabs(r.im.mean_ratio - 1) <= IMAGE_RATIO_TOL;
            print_row(&r);
            print_surfaces(scene, ratios, info.surfaces);
            const char *mn = xrad_method_name(methods[k]);
            CHECK(r.em.surface_error <= GUARD_SURFACE_ERROR_MAX(methods[k]),
                  "room %u %s: surface_error %.4f (%s at %.4f of the reference), allowed %.2f",
                  index, mn, r.em.surface_error, r.worst, r.em.worst_ratio,
                  GUARD_SURFACE_ERROR_MAX(methods[k]));
            if (methods[k] == XRAD_METHOD_INCREMENTAL && INCREMENTAL_MOVER_ROOMS(index))
                CHECK(r.em.surface_error <= SURFACE_ERROR_MAX,
                      "room %u %s: surface_error %.4f (%s at %.4f of the reference), allowed %.2f",
                      index, mn, r.em.surface_error, r.worst, r.em.worst_ratio, SURFACE_ERROR_MAX);
            CHECK(r.em.p95 <= GUARD_P95_MAX(methods[k]), "room %u %s: element p95 %.4f, allowed %.2f",
                  index, mn, r.em.p95, GUARD_P95_MAX(methods[k]));
            CHECK(r.em.max <= GUARD_ELEMENT_MAX(methods[k]),
                  "room %u %s: an element %.1f off the reference, relative to max(B_ref, 1e-3 "
                  "x the mean), allowed %.0f",
                  index, mn, r.em.max, GUARD_ELEMENT_MAX(methods[k]));
            CHECK(fabs(r.im.mean_ratio - 1) <= GUARD_IMAGE_RATIO_TOL(methods[k]),
                  "room %u %s: image mean ratio %.4f, allowed 1 +- %.2f", index, mn,
                  r.im.mean_ratio, GUARD_IMAGE_RATIO_TOL(methods[k]));
            if (nrows < MAX_ROWS)
                rows[nrows++] = r;
        }
        free(img);
        xrad_solver_destroy(&s);
    }
    free(ratios);
    free(mask);
    free(ref_img);
    xrad_atlas_destroy(&ref);
    xrad_atlas_destroy(&got);
    xrad_scene_destroy(&scene);
    rooms_free(&room);
}

int main(int argc, char **argv)
{
    xrad_method methods[4] = {XRAD_METHOD_GATHER, XRAD_METHOD_PROGRESSIVE,
                              XRAD_METHOD_INCREMENTAL, XRAD_METHOD_CROSS};
    size_t nmethods = 4;
    uint32_t first = 0, last = ROOMS_COUNT - 1;
    /* --write DIR: the rooms as scene files (DIR/room-N.json), for xrad
     * bench and the README's tables; no test. */
    if (argc == 3 && !strcmp(argv[1], "--write")) {
        for (uint32_t i = 0; i < ROOMS_COUNT; i++) {
            rooms_room room = {0};
            char path[1024];
            snprintf(path, sizeof(path), "%s/room-%u.json", argv[2], i);
            FILE *f = rooms_make(i, ROOMS_SEED, &room) ? NULL : fopen(path, "w");
            int ok = f && fputs(room.json, f) >= 0;
            ok = (f && fclose(f) == 0) && ok;
            rooms_free(&room);
            if (!ok) {
                fprintf(stderr, "%s: cannot write\n", path);
                return 2;
            }
            printf("wrote %s: %s\n", path, room.name);
        }
        return 0;
    }
    for (int i = 1; i < argc; i++) {
        unsigned a, b;
        if (sscanf(argv[i], "%u-%u", &a, &b) == 2 && a <= b && b < ROOMS_COUNT) {
            first = a;
            last = b;
        } else if (xrad_method_from_name(argv[i])) {
            methods[0] = xrad_method_from_name(argv[i]);
            nmethods = 1;
        } else {
            fprintf(stderr,
                    "usage: %s [gather|progressive|incremental|cross] [FIRST-LAST]\n"
                    "       %s --write DIR\n",
                    argv[0], argv[0]);
            return 2;
        }
    }
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    double t0 = now();
    for (uint32_t i = first; i <= last; i++)
        room_test(ctx, i, methods, nmethods);
    uint32_t want = (last - first + 1) * (uint32_t)nmethods;
    fprintf(stderr, "\nsummary (thresholds: surface_error <= %.2f, p95 <= %.2f, |image mean - 1| "
                    "<= %.2f), %.1f s in all\n",
            SURFACE_ERROR_MAX, P95_MAX, IMAGE_RATIO_TOL, now() - t0);
    print_header();
    uint32_t passed = 0;
    for (uint32_t k = 0; k < nrows; k++) {
        print_row(&rows[k]);
        passed += rows[k].ok;
    }
    fprintf(stderr,
            "%u of %u (room, method) pairs within issue 14's thresholds (checked: the guard "
            "bounds, GUARD_* in test_rooms.c)\n",
            passed, want);
    /* A run that compared nothing (or less than it should) is no pass. */
    CHECK(nrows == want, "%u (room, method) pairs compared, want %u", nrows, want);
    gpu_test_end(&ctx);
    return test_finish();
}
