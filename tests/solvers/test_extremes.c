/* Numerical stability at the extremes. Every GPU solution here is checked
 * for NaN and Inf in B, Bu and the radiosity atlas, and for the power bound
 * sum_i A_i B_i <= sum_i A_i E_i / (1 - rho_max), which B = E + rho F B
 * with sum_j F_ij <= 1 implies (1% slack for the discretisation; only
 * reported for incremental and cross after frames of the 0.999 furnace).
 * Then:
 *   - furnace, albedo 0.999: a closed room with a box inside, uniform E and
 *     rho, so B = E / (1 - rho) = 1000 E everywhere: the CPU reference
 *     (every element) and the solves of progressive refinement, cross and
 *     incremental (area mean) within 1%, the worst element reported; cross
 *     and incremental after 3 frames of the box moving: reported;
 *   - emission from 1e-6 to 1e6 W/m^2 in one scene: two closed rooms of one
 *     shape, one lit 1e12 times brighter: the bright one's power against
 *     the CPU reference's, no light from one room in the other, and for
 *     gather in fp32 the dim one's power against the bright one's / 1e12
 *     (linearity; progressive and cross shoot the dim room with fewer
 *     patches, the shooter subdivision following the brightest shot, so
 *     theirs is reported);
 *   - scale: one room at 1e-3, 1 and 1e4 m, density scaled inversely: the
 *     camera images agree within NRMSE 0.01;
 *   - a light of 1 mm^2 at 1e6 W/m^2, touching and coplanar surfaces, a
 *     slab 1e-4 m thin: power within 5% of the CPU reference's, and for the
 *     light and the slab element errors no worse than twice a plain room's
 *     at the same settings (touching and coplanar faces: reported);
 *   - a moving box that passes through a wall (incremental, cross);
 *   - 10,000 frames of a sliding box (arguments --long incremental|cross;
 *     suite "long"): finite and within the power bound;
 *   - out-of-range input: XRAD_ERROR_INPUT naming the field, no crash.
 * fp16 against fp32 radiosity hemicubes: gather and cross run with both and
 * the test prints the error of each at the extremes (XRAD_TEST_VERBOSE=1
 * also prints every power check). The parts are errors, furnace, emission,
 * scale, geometry and wall: --only or --except a comma-separated list of
 * them. */
#include <math.h>
#include <stdarg.h>
#include <string.h>

#include "gpu/cmd.h"
#include "scene/scene.h"
#include "solver_test.h"
#include "solvers/solver.h"

/* ---------------------------------------------------------- scene text */

typedef struct text {
    char s[16384];
    size_t n;
} text;

static void put(text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(t->s + t->n, sizeof(t->s) - t->n, fmt, ap);
    va_end(ap);
    if (k > 0)
        t->n += (size_t)k < sizeof(t->s) - t->n ? (size_t)k : sizeof(t->s) - t->n - 1;
}

/* A closed cube room of side s (m) at x offset x0, walls of `wall`, and
 * with l > 0 a ceiling light of side l (m) of `lamp` facing down. */
static void put_room(text *t, const char *name, double x0, double s, double l, const char *wall,
                     const char *lamp)
{
    put(t,
        "{\"name\": \"%s\", \"surfaces\": ["
        "{\"name\": \"walls\", \"material\": \"%s\", \"box\": {\"origin\": [%.17g, 0, 0],"
        " \"u\": [%.17g, 0, 0], \"v\": [0, %.17g, 0], \"w\": [0, 0, %.17g]}, \"inward\": true}",
        name, wall, x0, s, s, s);
    if (l > 0)
        put(t,
            ", {\"name\": \"light\", \"material\": \"%s\", \"quad\": {\"origin\": [%.17g, %.17g,"
            " %.17g], \"u\": [%.17g, 0, 0], \"v\": [0, 0, %.17g]}}",
            lamp, x0 + 0.5 * s - 0.5 * l, 0.99 * s, 0.5 * s - 0.5 * l, l, l);
    put(t, "]}");
}

/* A box object; with `dynamic`, sliding dx (m) along x over 1 s. */
static void put_box(text *t, const char *name, const char *mat, const double o[3],
                    const double size[3], bool dynamic, double dx)
{
    put(t,
        ", {\"name\": \"%s\", \"dynamic\": %s, \"surfaces\": [{\"name\": \"b\", \"material\":"
        " \"%s\", \"box\": {\"origin\": [%.17g, %.17g, %.17g], \"u\": [%.17g, 0, 0],"
        " \"v\": [0, %.17g, 0], \"w\": [0, 0, %.17g]}}]",
        name, dynamic ? "true" : "false", mat, o[0], o[1], o[2], size[0], size[1], size[2]);
    if (dynamic)
        put(t,
            ", \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
            " {\"time\": 1, \"translate\": [%.17g, 0, 0]}]}",
            dx);
    put(t, "}");
}

static void put_camera(text *t, double s)
{
    put(t,
        "], \"camera\": {\"position\": [%.17g, %.17g, %.17g], \"look_at\": [%.17g, %.17g, %.17g],"
        " \"fov_degrees\": 70, \"width\": 96, \"height\": 96}}",
        0.5 * s, 0.5 * s, 0.02 * s, 0.5 * s, 0.45 * s, s);
}

static xrad_scene *parse(const text *t, const char *name)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(t->s, t->n, name, &scene, &err);
    CHECK(st == XRAD_OK, "%s: %s", name, err.message);
    return scene;
}

/* ------------------------------------------------------------- checks */

/* No NaN or Inf in B, Bu and the atlas; the power bound (printed only,
 * not checked, where `bound` is false). */
static void check_bound(xrad_context *ctx, xrad_solver *s, const char *what, bool bound)
{
    gpu_scene *gs = &s->gs;
    const xrad_scene *scene = s->scene;
    uint32_t n = gs->element_count;
    size_t tex = (size_t)gs->atlas.width * gs->atlas.height * 4;
    vec4 *b = malloc(n * sizeof(vec4)), *bu = malloc(n * sizeof(vec4));
    float *atlas = malloc(tex * sizeof(float));
    xrad_error err = {0};
    bool ok = b && bu && atlas &&
              !gpu_readback_buffer(ctx, &gs->B, 0, b, n * sizeof(vec4), &err) &&
              !gpu_readback_buffer(ctx, &gs->Bu, 0, bu, n * sizeof(vec4), &err) &&
              !gpu_readback_image(ctx, &gs->atlas, VK_IMAGE_LAYOUT_GENERAL, atlas,
                                  tex * sizeof(float), &err);
    CHECK(ok, "%s: readback: %s", what, err.message);
    if (ok) {
        uint32_t bad = 0;
        for (uint32_t i = 0; i < n; i++) {
            const float *v[2] = {&b[i].x, &bu[i].x};
            for (int k = 0; k < 2; k++)
                for (int c = 0; c < 3; c++)
                    bad += !isfinite(v[k][c]);
        }
        for (size_t i = 0; i < tex; i++)
            bad += !isfinite(atlas[i]);
        CHECK(bad == 0, "%s: %u NaN or Inf values in B, Bu and the atlas", what, bad);
        /* The power of B plus the ambient estimate of where the unshot
         * Bu takes it (Cohen et al. 1988): a solver stopped early (the
         * dynamic methods' frame_shots) holds negative unshot radiosity, the
         * light a redistribution still has to take away, so B alone may
         * stand above the solution it is heading to. */
        double power[3] = {0, 0, 0}, emitted[3] = {0, 0, 0}, unshot[3] = {0, 0, 0}, rho = 0;
        double area = 0, rho_area[3] = {0, 0, 0};
        for (uint32_t m = 0; m < scene->material_count; m++) {
            vec3 a = scene->materials[m].albedo;
            rho = fmax(rho, fmax(a.x, fmax(a.y, a.z)));
        }
        for (uint32_t i = 0; i < n; i++) {
            const element *el = &scene->elements[i];
            const material *mt = &scene->materials[scene->surfaces[el->surface].material];
            const float *bv = &b[i].x, *uv = &bu[i].x;
            double e[3] = {mt->emission.x, mt->emission.y, mt->emission.z};
            double al[3] = {mt->albedo.x, mt->albedo.y, mt->albedo.z};
            for (int c = 0; c < 3; c++) {
                power[c] += el->area * bv[c];
                unshot[c] += el->area * uv[c];
                emitted[c] += el->area * e[c];
                rho_area[c] += el->area * al[c];
            }
            area += el->area;
        }
        for (int c = 0; c < 3 && area > 0; c++) {
            double mean_rho = rho_area[c] / area;
            power[c] += unshot[c] * mean_rho / (1 - mean_rho);
        }
        if (getenv("XRAD_TEST_VERBOSE") || !bound)
            fprintf(stderr, "%s: power %.6g W, bound %.6g W (ratio %.4f)%s\n", what, power[0],
                    emitted[0] / (1 - rho), power[0] * (1 - rho) / emitted[0],
                    bound ? "" : " (reported)");
        for (int c = 0; bound && c < 3; c++)
            CHECK(power[c] <= 1.01 * emitted[c] / (1 - rho) && power[c] >= 0,
                  "%s: channel %d: power (with the unshot's ambient estimate) %g W outside "
                  "[0, 1.01 x %g / (1 - %g)]",
                  what, c,
                  power[c], emitted[c], rho);
    }
    free(b);
    free(bu);
    free(atlas);
}

static void check_buffers(xrad_context *ctx, xrad_solver *s, const char *what)
{
    check_bound(ctx, s, what, true);
}

/* Channel 0 of element e in an atlas. */
static double element_value(const xrad_scene *scene, const xrad_atlas *a, uint32_t e)
{
    const element *el = &scene->elements[e];
    return a->rgba[((size_t)el->texel_y * a->width + el->texel_x) * 4];
}

static bool emitter(const xrad_scene *scene, uint32_t e)
{
    vec3 em = scene->materials[scene->surfaces[scene->elements[e].surface].material].emission;
    return em.x > 0 || em.y > 0 || em.z > 0;
}

static uint32_t object_of(const xrad_scene *scene, uint32_t e)
{
    return scene->surfaces[scene->elements[e].surface].object;
}

/* RMS of (a - b) over the non-emitting elements, relative to the largest
 * |b| among them. */
static double rel_rms(const xrad_scene *scene, const xrad_atlas *a, const xrad_atlas *b)
{
    double sum = 0, top = 0;
    uint32_t n = 0;
    for (uint32_t e = 0; e < scene->element_count; e++) {
        if (emitter(scene, e))
            continue;
        double d = element_value(scene, a, e) - element_value(scene, b, e);
        sum += d * d;
        top = fmax(top, fabs(element_value(scene, b, e)));
        n++;
    }
    return n && top > 0 ? sqrt(sum / n) / top : -1;
}

/* sum A_e B_e (channel 0) over the non-emitting elements of object `obj`
 * (UINT32_MAX: all). */
static double atlas_power(const xrad_scene *scene, const xrad_atlas *a, uint32_t obj)
{
    double p = 0;
    for (uint32_t e = 0; e < scene->element_count; e++)
        if (!emitter(scene, e) && (obj == UINT32_MAX || object_of(scene, e) == obj))
            p += scene->elements[e].area * element_value(scene, a, e);
    return p;
}

static bool reference(const xrad_scene *scene, double t, uint32_t rays, xrad_atlas *out)
{
    xrad_error err = {0};
    xrad_reference_desc d = {.time = t, .rays = rays, .residual = 1e-8, .max_sweeps = 100000};
    bool ok = xrad_atlas_create(scene, out, &err) == XRAD_OK &&
              xrad_reference_solve(scene, &d, out, NULL, &err) == XRAD_OK;
    CHECK(ok, "reference: %s", err.message);
    return ok;
}

/* Advances `s` `frames` frames of 1/10 s from time t0, checks the
 * buffers, reads the solution into *out (created here when empty); false
 * (after a failed CHECK) on error. */
static bool advance_bounded(xrad_context *ctx, xrad_solver *s, double t0, uint32_t frames,
                            const char *what, xrad_atlas *out, bool bound)
{
    xrad_error err = {0};
    xrad_status st = XRAD_OK;
    for (uint32_t f = 1; !st && f <= frames; f++)
        st = xrad_solver_advance(s, t0 + 0.1 * f, &err);
    if (!st && out && !out->rgba)
        st = xrad_atlas_create(s->scene, out, &err);
    if (!st && out)
        st = xrad_solver_read(s, out, &err);
    CHECK(st == XRAD_OK, "%s: %s", what, err.message);
    if (!st)
        check_bound(ctx, s, what, bound);
    return st == XRAD_OK;
}

/* Solves with `d` and advances `frames` frames of 1/10 s, checks the
 * buffers, reads the solution into *out (created here when empty). */
static xrad_solver *solve_bounded(xrad_context *ctx, const xrad_scene *scene,
                                  xrad_solver_desc d, uint32_t frames, const char *what,
                                  xrad_atlas *out, bool bound)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    xrad_status st = xrad_solver_create(ctx, scene, &d, &s, &err);
    if (!st)
        st = xrad_solver_solve(s, &err);
    CHECK(st == XRAD_OK, "%s: %s", what, err.message);
    if (st || !advance_bounded(ctx, s, d.time, frames, what, out, bound)) {
        xrad_solver_destroy(&s);
        return NULL;
    }
    return s;
}

static xrad_solver *solve(xrad_context *ctx, const xrad_scene *scene, xrad_solver_desc d,
                          uint32_t frames, const char *what, xrad_atlas *out)
{
    return solve_bounded(ctx, scene, d, frames, what, out, true);
}

/* ------------------------------------------------------------ furnace */

/* The furnace's solution `got` of `m` after `frames` frames against
 * E / (1 - rho): printed, the area mean held to 1% where `held`. */
static void furnace_mean(const xrad_scene *scene, const xrad_atlas *got, xrad_method m,
                         uint32_t frames, bool held)
{
    const double want = 1.0 / (1 - 0.999);
    double worst = 0, sum = 0, area = 0;
    for (uint32_t e = 0; e < scene->element_count; e++) {
        double v = element_value(scene, got, e), a = scene->elements[e].area;
        worst = fmax(worst, fabs(v - want) / want);
        sum += a * v;
        area += a;
    }
    double mean = fabs(sum / area - want) / want;
    fprintf(stderr,
            "furnace 0.999: %s (ambient term), %u frames: mean %.3f%%, worst element "
            "%.3f%% off%s\n",
            xrad_method_name(m), frames, 100 * mean, 100 * worst, held ? "" : " (reported)");
    if (held)
        CHECK(mean < 0.01, "furnace: %s's solve is %.3f%% off E / (1 - rho) on average",
              xrad_method_name(m), 100 * mean);
}

static void test_furnace(xrad_context *ctx)
{
    text t = {0};
    put(&t, "{\"unit\": \"m\", \"density\": 5, \"materials\": [{\"name\": \"m\", \"albedo\":"
            " [0.999, 0.999, 0.999], \"emission\": [1, 1, 1]}], \"objects\": [");
    put_room(&t, "room", 0, 1, 0, "m", "m");
    put_box(&t, "box", "m", (double[3]){0.3, 0.2, 0.3}, (double[3]){0.3, 0.3, 0.3}, true, 0.2);
    put_camera(&t, 1);
    xrad_scene *scene = parse(&t, "furnace.json");
    if (!scene)
        return;
    const double want = 1.0 / (1 - 0.999);
    xrad_atlas ref = {0}, got = {0};
    if (reference(scene, 0, 4, &ref)) {
        double worst = 0;
        for (uint32_t e = 0; e < scene->element_count; e++)
            worst = fmax(worst, fabs(element_value(scene, &ref, e) - want) / want);
        /* B = E / (1 - rho sum F): 0.999 turns a row that misses 1e-5 of
         * closure into 1% (exact visibility closes them to about 1e-8). */
        fprintf(stderr, "furnace 0.999: CPU reference worst %.4f%%\n", 100 * worst);
        CHECK(worst < 0.01, "furnace: the CPU reference's worst element is %.3f%% off", 100 * worst);
    }
    /* Every method's solve: conservative shots (each passes on exactly the
     * power its ID hemicube sees front faces absorb, reconstruct.comp; the
     * dynamic methods' fixed patches too in their first solve), the unshot
     * remainder (0.999 per round) after 10,000 shots by the ambient term:
     * checked. Cross and incremental after 3 frames of the box moving:
     * what a redistribution adds and takes away differs by the
     * discretisation of its terms (about 1e-4 of B), which 0.999 turns
     * into tens of percent once the ambient term extrapolates it:
     * reported. The frames advance the solver whose solve was just
     * checked: a second solve from scratch for them (as this test did
     * until issue 14) repeated the same 10,000 shots and was two fifths of
     * the suite's longest test. The 10,000 shots stay: progressive's mean
     * error grows with them (0.14% after 1,000 shots, 0.36% after 3,000,
     * 0.72% after 10,000), so fewer would hold a smaller accumulation of
     * per-shot error to the same 1%. Conserve on for all three, the
     * dynamic methods' default: far (progressive's default, auto in
     * xrad.h) passed here too on 2026-12-07 with a test build that solved
     * all three with it, but the test took 2235 s in a loaded suite run
     * against 512-533 s; far's conservation is checked at rho 0.9
     * (test_progressive) and in the rooms. At most 4 patches a side
     * (the default 8 gives each wall its 5 x 5 elements as patches): a
     * shot conserves whatever its patches, and the mean error is alike
     * (progressive 0.754% against 0.72%, cross 0.025% against 0.80%).
     * 16 patches a shot against 25: the test took 661 s in a CI run with
     * 4 against 1436 s in one with 8 the same day (each beside the other
     * tests; 402 s alone on the idle machine, 2026-12-07). */
    xrad_method methods[3] = {XRAD_METHOD_PROGRESSIVE, XRAD_METHOD_CROSS,
                              XRAD_METHOD_INCREMENTAL};
    for (int m = 0; m < 3; m++) {
        xrad_solver_desc d = {.method = methods[m],
                              .hemicube_res = 32,
                              .max_patches = 4,
                              .max_iterations = 10000,
                              .frame_shots = 500,
                              .ambient = XRAD_AMBIENT_ON,
                              .conserve = XRAD_CONSERVE_ON};
        xrad_solver *s = solve_bounded(ctx, scene, d, 0, "furnace", &got, true);
        if (!s)
            continue;
        furnace_mean(scene, &got, methods[m], 0, true);
        if (methods[m] != XRAD_METHOD_PROGRESSIVE &&
            advance_bounded(ctx, s, d.time, 3, "furnace", &got, false))
            furnace_mean(scene, &got, methods[m], 3, false);
        xrad_solver_destroy(&s);
    }
    xrad_atlas_destroy(&got);
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&scene);
}

/* ----------------------------------------------------- emission range */

static void test_emission_range(xrad_context *ctx)
{
    text t = {0};
    put(&t, "{\"unit\": \"m\", \"density\": 8, \"materials\": ["
            "{\"name\": \"wall\", \"albedo\": [0.5, 0.5, 0.5]},"
            "{\"name\": \"bright\", \"albedo\": [0, 0, 0], \"emission\": [1e6, 1e6, 1e6]},"
            "{\"name\": \"dim\", \"albedo\": [0, 0, 0], \"emission\": [1e-6, 1e-6, 1e-6]}],"
            " \"objects\": [");
    put_room(&t, "bright-room", 0, 1, 0.3, "wall", "bright");
    put(&t, ", ");
    put_room(&t, "dim-room", 3, 1, 0.3, "wall", "dim");
    /* A box in each room; the dim room's moves, so that cross's radiosity
     * hemicubes hold values 1e12 below the scene's largest. */
    put_box(&t, "bright-box", "wall", (double[3]){0.3, 0, 0.3}, (double[3]){0.3, 0.3, 0.3}, true,
            0.2);
    put_box(&t, "dim-box", "wall", (double[3]){3.3, 0, 0.3}, (double[3]){0.3, 0.3, 0.3}, true,
            0.2);
    put_camera(&t, 1);
    xrad_scene *scene = parse(&t, "emission-range.json");
    if (!scene)
        return;
    xrad_atlas ref = {0}, got = {0};
    double ref_bright = reference(scene, 0.3, 16, &ref) ? atlas_power(scene, &ref, 0) : -1;
    struct {
        xrad_method m;
        uint32_t format, frames;
    } runs[] = {
        {XRAD_METHOD_PROGRESSIVE, XRAD_RADIOSITY_FP32, 0},
        {XRAD_METHOD_GATHER, XRAD_RADIOSITY_FP16, 0},
        {XRAD_METHOD_GATHER, XRAD_RADIOSITY_FP32, 0},
        {XRAD_METHOD_CROSS, XRAD_RADIOSITY_FP16, 3},
        {XRAD_METHOD_CROSS, XRAD_RADIOSITY_FP32, 3},
    };
    /* Under the sanitizers (XRAD_TEST_SMALL, tools/sanitize.sh) cross runs
     * in fp32 alone: its fp16 run takes the same host path (only the
     * hemicubes' format differs, whose host side gather's fp16 run takes
     * too) and cost 87 s of the ASan run's 404 s for this test. */
    const bool small = getenv("XRAD_TEST_SMALL") && strcmp(getenv("XRAD_TEST_SMALL"), "0");
    for (size_t r = 0; r < sizeof(runs) / sizeof(runs[0]); r++) {
        if (small && runs[r].m == XRAD_METHOD_CROSS && runs[r].format == XRAD_RADIOSITY_FP16)
            continue;
        /* A relative threshold far below 1e-12, so that the dim room is
         * shot at all; gather a fixed 20 bounces (0.5^20 in both rooms) at
         * 32 pixels, its hemicube per element being the cost. */
        bool gather = runs[r].m == XRAD_METHOD_GATHER;
        xrad_solver_desc d = {.method = runs[r].m, .hemicube_res = gather ? 32 : 64, .msaa = 1,
                              .threshold = 1e-16, .bounces = 20,
                              .radiosity_format = runs[r].format};
        bool fp32 = runs[r].format == XRAD_RADIOSITY_FP32;
        char what[64];
        snprintf(what, sizeof(what), "emission range, %s %s", xrad_method_name(runs[r].m),
                 fp32 ? "fp32" : "fp16");
        d.time = runs[r].frames ? 0 : 0.3;
        xrad_solver *s = solve(ctx, scene, d, runs[r].frames, what, &got);
        if (!s)
            continue;
        /* Objects: 0 bright room, 1 dim room, 2 bright box, 3 dim box. */
        double bright = atlas_power(scene, &got, 0), dim = atlas_power(scene, &got, 1);
        double bright_box = atlas_power(scene, &got, 2), dim_box = atlas_power(scene, &got, 3);
        double room_err = fabs(bright / ref_bright - 1);
        double linear_room = fabs(dim * 1e12 / bright - 1);
        double linear_box = fabs(dim_box * 1e12 / bright_box - 1);
        double leak = 0;
        for (uint32_t e = 0; e < scene->element_count; e++)
            if (object_of(scene, e) == 1 && !emitter(scene, e))
                leak = fmax(leak, element_value(scene, &got, e));
        fprintf(stderr, "%s: bright room power %.4f off the CPU reference; dim / bright x 1e12: "
                        "room %.5f, box %.5f off 1; largest dim wall %.3g W/m^2\n",
                what, room_err, linear_room, linear_box, leak);
        /* Progressive measures 1.2%, gather 3.3%, cross 2.9%: cross shadows
         * the box's indirect light by the cross projection, without the
         * per-shot conservation that progressive's ID hemicube shadows have
         * (on a plain room its element error is the lower one). */
        bool projected = runs[r].m == XRAD_METHOD_CROSS;
        CHECK(ref_bright > 0 && room_err < (gather ? 0.05 : projected ? 0.04 : 0.03),
              "%s: bright room power %.4f off the reference", what, room_err);
        /* No light crosses from one closed room to the other. */
        CHECK(leak <= 1e-5, "%s: a dim-room wall reaches %g W/m^2", what, leak);
        /* fp32 keeps the 1e12 range; fp16 radiosity hemicubes underflow,
         * which the line above reports. */
        if (fp32 && gather)
            CHECK(linear_room < 0.01 && linear_box < 0.02,
                  "%s: dim / bright x 1e12 is %.4f (room), %.4f (box) off 1", what, linear_room,
                  linear_box);
        xrad_solver_destroy(&s);
    }
    xrad_atlas_destroy(&got);
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&scene);
}

/* -------------------------------------------------------------- scale */

static xrad_scene *scaled_room(double s)
{
    text t = {0};
    put(&t, "{\"unit\": \"m\", \"density\": %.17g, \"materials\": ["
            "{\"name\": \"wall\", \"albedo\": [0.6, 0.5, 0.4]},"
            "{\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
            " \"objects\": [",
        6 / s);
    put_room(&t, "room", 0, s, 0.3 * s, "wall", "lamp");
    put_box(&t, "box", "wall", (double[3]){0.3 * s, 0, 0.35 * s},
            (double[3]){0.25 * s, 0.4 * s, 0.25 * s}, true, 0.3 * s);
    put_camera(&t, s);
    char name[64];
    snprintf(name, sizeof(name), "room-%gm.json", s);
    return parse(&t, name);
}

static void test_scale(xrad_context *ctx)
{
    const double scales[3] = {1, 1e-3, 1e4};
    xrad_method methods[2] = {XRAD_METHOD_PROGRESSIVE, XRAD_METHOD_CROSS};
    for (int m = 0; m < 2; m++) {
        float *img[3] = {NULL, NULL, NULL};
        uint32_t w = 0, h = 0;
        uint32_t frames = methods[m] == XRAD_METHOD_CROSS ? 3 : 0;
        for (int k = 0; k < 3; k++) {
            xrad_scene *scene = scaled_room(scales[k]);
            if (!scene)
                continue;
            xrad_solver_desc d = {.method = methods[m], .hemicube_res = 32};
            char what[64];
            snprintf(what, sizeof(what), "scale %g m, %s", scales[k],
                     xrad_method_name(methods[m]));
            xrad_solver *s = solve(ctx, scene, d, frames, what, NULL);
            if (s)
                img[k] = solver_test_render(ctx, scene, s, 0.1 * frames, &w, &h);
            xrad_solver_destroy(&s);
            xrad_scene_destroy(&scene);
        }
        for (int k = 1; k < 3; k++) {
            if (!img[0] || !img[k])
                continue;
            double e = xrad_image_nrmse(img[k], img[0], w, h);
            fprintf(stderr, "scale %g m vs 1 m, %s: NRMSE %.5f\n", scales[k],
                    xrad_method_name(methods[m]), e);
            CHECK(e >= 0 && e < 0.01, "scale %g m, %s: NRMSE %g against 1 m", scales[k],
                  xrad_method_name(methods[m]), e);
        }
        for (int k = 0; k < 3; k++)
            free(img[k]);
    }
}

/* ------------------------------------- small light, contact, thinness */

/* Progressive and cross against the CPU reference: the power within
 * `power` (a fraction), the element error (rel_rms) at most twice
 * `baseline` (+ 0.01), what a plain room gives at these settings (0:
 * reported only); *out (when not NULL) gets progressive's element error. */
static void against_reference(xrad_context *ctx, xrad_scene *scene, const char *name,
                              double power, double baseline, double *out)
{
    xrad_atlas ref = {0}, got = {0};
    if (!scene || !reference(scene, 0, 32, &ref)) {
        xrad_scene_destroy(&scene);
        return;
    }
    double want = atlas_power(scene, &ref, UINT32_MAX);
    xrad_method methods[2] = {XRAD_METHOD_PROGRESSIVE, XRAD_METHOD_CROSS};
    for (int m = 0; m < 2; m++) {
        char what[96];
        snprintf(what, sizeof(what), "%s, %s", name, xrad_method_name(methods[m]));
        xrad_solver_desc d = {.method = methods[m], .hemicube_res = 64};
        xrad_solver *s = solve(ctx, scene, d, 0, what, &got);
        if (!s)
            continue;
        double e = rel_rms(scene, &got, &ref);
        double p = fabs(atlas_power(scene, &got, UINT32_MAX) / want - 1);
        fprintf(stderr, "%s: element error %.4f, power %.4f off the CPU reference\n", what, e, p);
        if (out && m == 0)
            *out = e;
        CHECK(p < power, "%s: power %.4f off the CPU reference", what, p);
        /* Against the plain room's error with a margin of 0.04: issue 14
         * made the plain room six times nearer the reference (0.038 ->
         * 0.006) and the 1e-4 m slab a little (0.039 -> 0.035), whose
         * side faces, a tenth of a millimetre tall, are far below any
         * element; the check is that thinness breaks nothing. */
        if (baseline > 0)
            CHECK(e >= 0 && e < 2 * baseline + 0.04,
                  "%s: element error %.4f, a plain room's is %.4f", what, e, baseline);
        xrad_solver_destroy(&s);
    }
    xrad_atlas_destroy(&got);
    xrad_atlas_destroy(&ref);
    xrad_scene_destroy(&scene);
}

/* The room the next scenes change one thing of, at density 8. */
static void put_plain_room(text *t, double light, double emission)
{
    put(t, "{\"unit\": \"m\", \"density\": 8, \"materials\": ["
           "{\"name\": \"wall\", \"albedo\": [0.5, 0.5, 0.5]},"
           "{\"name\": \"red\", \"albedo\": [0.7, 0.1, 0.1]},"
           "{\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [%g, %g, %g]}],"
           " \"objects\": [",
        emission, emission, emission);
    put_room(t, "room", 0, 1, light, "wall", "lamp");
}

static void test_geometry(xrad_context *ctx)
{
    double baseline = 0;
    text t = {0};
    put_plain_room(&t, 0.3, 20);
    put_box(&t, "box", "wall", (double[3]){0.3, 0, 0.3}, (double[3]){0.3, 0.3, 0.3}, true, 0.2);
    put_camera(&t, 1);
    against_reference(ctx, parse(&t, "plain.json"), "a plain room", 0.05, 0, &baseline);

    t.n = 0;
    put_plain_room(&t, 1e-3, 1e6);
    put_box(&t, "box", "wall", (double[3]){0.3, 0, 0.3}, (double[3]){0.3, 0.3, 0.3}, true, 0.2);
    put_camera(&t, 1);
    against_reference(ctx, parse(&t, "small-light.json"), "1 mm^2 light at 1e6 W/m^2", 0.05,
                      baseline, NULL);

    /* A box standing on the floor, a second one touching its side face to
     * face, and a rug lying in the floor's plane over part of it. */
    t.n = 0;
    put_plain_room(&t, 0.3, 20);
    put_box(&t, "box-a", "wall", (double[3]){0.2, 0, 0.3}, (double[3]){0.25, 0.3, 0.25}, true,
            0.1);
    put_box(&t, "box-b", "red", (double[3]){0.45, 0, 0.3}, (double[3]){0.2, 0.2, 0.25}, false, 0);
    put(&t, ", {\"name\": \"rug\", \"surfaces\": [{\"name\": \"rug\", \"material\": \"red\","
            " \"quad\": {\"origin\": [0.5, 0, 0.6], \"u\": [0, 0, 0.3], \"v\": [0.3, 0, 0]}}]}");
    put_camera(&t, 1);
    /* Element error reported only: the rug z-fights with the floor in the
     * hemicubes, and the CPU reference's rays tie there too. The power
     * within 6%: progressive and cross measure 4.8% (cross read from
     * 1.8% to 8.2% as its iterations changed during issue 14). */
    against_reference(ctx, parse(&t, "contact.json"), "touching and coplanar surfaces", 0.06, 0,
                      NULL);

    /* A shelf 1e-4 m thin at half height, and a moving box under it. */
    t.n = 0;
    put_plain_room(&t, 0.3, 20);
    put_box(&t, "shelf", "wall", (double[3]){0.25, 0.5, 0.25}, (double[3]){0.5, 1e-4, 0.5}, false,
            0);
    put_box(&t, "box", "wall", (double[3]){0.3, 0, 0.3}, (double[3]){0.2, 0.2, 0.2}, true, 0.2);
    put_camera(&t, 1);
    against_reference(ctx, parse(&t, "thin.json"), "a slab 1e-4 m thin", 0.05, baseline, NULL);
}

/* -------------------------------------------------- through the wall */

static void test_through_wall(xrad_context *ctx)
{
    text t = {0};
    put(&t, "{\"unit\": \"m\", \"density\": 6, \"materials\": ["
            "{\"name\": \"wall\", \"albedo\": [0.6, 0.6, 0.6]},"
            "{\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
            " \"objects\": [");
    put_room(&t, "room", 0, 1, 0.3, "wall", "lamp");
    /* From x = 0.5 to 1.7 in 1 s: through the wall at x = 1. */
    put_box(&t, "box", "wall", (double[3]){0.5, 0.2, 0.4}, (double[3]){0.2, 0.2, 0.2}, true,
            1.2);
    put_camera(&t, 1);
    xrad_scene *scene = parse(&t, "through-wall.json");
    xrad_method methods[3] = {XRAD_METHOD_INCREMENTAL, XRAD_METHOD_CROSS,
                              XRAD_METHOD_PROGRESSIVE};
    for (int m = 0; scene && m < 3; m++) {
        xrad_error err = {0};
        xrad_solver *s = NULL;
        xrad_solver_desc d = {.method = methods[m], .hemicube_res = 32};
        xrad_status st = xrad_solver_create(ctx, scene, &d, &s, &err);
        if (!st)
            st = xrad_solver_solve(s, &err);
        for (int f = 1; !st && f <= 12; f++) {
            st = xrad_solver_advance(s, f / 12.0, &err);
            char what[64];
            snprintf(what, sizeof(what), "through the wall, %s, frame %d",
                     xrad_method_name(methods[m]), f);
            if (!st && f % 3 == 0)
                check_buffers(ctx, s, what);
        }
        CHECK(st == XRAD_OK, "through the wall, %s: %s", xrad_method_name(methods[m]),
              err.message);
        xrad_solver_destroy(&s);
    }
    xrad_scene_destroy(&scene);
}

/* ------------------------------------------------------ 10,000 frames */

/* 10,000 frames of a box sliding to and fro, finite and within the power
 * bound throughout. Incremental: its redistribution shoots C with the
 * fixed patches of every shot since the solve, so what a frame removes is
 * texel for texel what was shot. Cross: every redistribution replaces what
 * the last one gave C, and the progressive iterations shoot C alone
 * (src/solvers/cross.c), so nothing of M can add up; when they shot with
 * the box in their hemicubes, the power rose past the bound (1.11 times it
 * after 10,000 frames). What the iterations shot of earlier poses' changes
 * still wanders: XRAD_TEST_VERBOSE=1 XRAD_LONG_EVERY=500 prints the power
 * at every 500th frame, one pose, 0.944-0.976 of the bound (README
 * "Shooter subdivision"). */
static void test_many_frames(xrad_context *ctx, xrad_method method)
{
    /* A coarse room and a box of 6 patches, so that 10,000 frames take
     * minutes; cross's back hemicubes and projection grid coarse too. */
    text t = {0};
    put(&t, "{\"unit\": \"m\", \"density\": 4, \"materials\": ["
            "{\"name\": \"wall\", \"albedo\": [0.6, 0.5, 0.4]},"
            "{\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
            " \"objects\": [");
    put_room(&t, "room", 0, 1, 0.3, "wall", "lamp");
    put(&t, ", {\"name\": \"box\", \"dynamic\": true, \"cross_density\": 2, \"surfaces\":"
            " [{\"name\": \"b\", \"material\": \"wall\", \"box\": {\"origin\": [0.3, 0, 0.35],"
            " \"u\": [0.25, 0, 0], \"v\": [0, 0.4, 0], \"w\": [0, 0, 0.25]}}],"
            " \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
            " {\"time\": 1, \"translate\": [0.3, 0, 0]}]}}");
    put_camera(&t, 1);
    xrad_scene *scene = parse(&t, "many-frames.json");
    if (!scene)
        return;
    bool bound = true;
    xrad_error err = {0};
    xrad_solver *s = NULL;
    /* Incremental's redistribution shoots C again with the fixed patches
     * of every shot since the solve, so the patch rule sets its frame time:
     * at most 4 a side made a frame 55 ms against 92 ms at the default 8
     * (idle, 2026-12-07); cross's frames took 50 ms either way, so it
     * keeps the default. */
    xrad_solver_desc d = {.method = method,
                          .hemicube_res = 16,
                          .frame_shots = 8,
                          .back_res = 8,
                          .cross_grid = 2,
                          .max_patches = method == XRAD_METHOD_INCREMENTAL ? 4 : 0};
    xrad_status st = xrad_solver_create(ctx, scene, &d, &s, &err);
    if (!st)
        st = xrad_solver_solve(s, &err);
    /* The box slides to and fro: 10,000 frames of 1/30 s (XRAD_LONG_FRAMES
     * and XRAD_LONG_EVERY, the frames between checks, to look closer). */
    int frames = getenv("XRAD_LONG_FRAMES") ? atoi(getenv("XRAD_LONG_FRAMES")) : 10000;
    int every = getenv("XRAD_LONG_EVERY") ? atoi(getenv("XRAD_LONG_EVERY")) : 1000;
    every = every > 0 ? every : 1000;
    for (int f = 1; !st && f <= frames; f++) {
        double phase = fmod(f / 30.0, 2.0);
        st = xrad_solver_advance(s, phase < 1 ? phase : 2 - phase, &err);
        if (!st && f % every == 0) {
            char what[64];
            snprintf(what, sizeof(what), "10,000 frames of %s, frame %d",
                     xrad_method_name(method), f);
            check_bound(ctx, s, what, bound);
            fprintf(stderr, "%s: finite%s\n", what, bound ? ", within the bound" : "");
        }
    }
    CHECK(st == XRAD_OK, "10,000 frames of %s: %s", xrad_method_name(method), err.message);
    xrad_solver_destroy(&s);
    xrad_scene_destroy(&scene);
}

/* ------------------------------------------------------------- errors */

static void test_errors(xrad_context *ctx)
{
    static const struct {
        const char *json, *field;
    } cases[] = {
        {"{\"materials\": [{\"name\": \"m\", \"albedo\": [1, 0, 0]}], \"objects\": []}", "albedo"},
        {"{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5], \"emission\": [-1, 0, "
         "0]}], \"objects\": [{\"name\": \"o\", \"surfaces\": []}]}",
         "emission"},
        {"{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5], \"emission\": [1e21, 0,"
         " 0]}], \"objects\": [{\"name\": \"o\", \"surfaces\": []}]}",
         "emission"},
        {"{\"density\": 1e5, \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
         " \"objects\": []}",
         "density"},
        {"{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], \"objects\": ["
         "{\"name\": \"o\", \"surfaces\": [{\"name\": \"q\", \"material\": \"m\", \"quad\":"
         " {\"origin\": [1e10, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0]}}]}]}",
         "origin"},
        {"{\"density\": 10000, \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
         " \"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"q\", \"material\": \"m\","
         " \"quad\": {\"origin\": [0, 0, 0], \"u\": [1000, 0, 0], \"v\": [0, 1000, 0]}}]}]}",
         "'q'"},
        {"{\"quality\": {\"hemicube_res\": 33}, \"materials\": [{\"name\": \"m\", \"albedo\": [0.5,"
         " 0.5, 0.5]}], \"objects\": []}",
         "quality.hemicube_res"},
        {"{\"quality\": {\"preset\": \"ultra\"}, \"materials\": [{\"name\": \"m\","
         " \"albedo\": [0.5, 0.5, 0.5]}], \"objects\": []}",
         "quality.preset"},
        {"{\"quality\": {\"density_scale\": 100}, \"materials\": [{\"name\": \"m\", \"albedo\":"
         " [0.5, 0.5, 0.5]}], \"objects\": []}",
         "density_scale"},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        xrad_scene *scene = NULL;
        xrad_error err = {0};
        xrad_status st = xrad_scene_parse(cases[i].json, strlen(cases[i].json), "bad.json",
                                          &scene, &err);
        CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "bad.json") &&
                  strstr(err.message, cases[i].field),
              "case %zu: status %d, '%s' (want the file and %s)", i, st, err.message,
              cases[i].field);
        xrad_scene_destroy(&scene);
    }
    /* The solver's own ranges. */
    xrad_scene *scene = scaled_room(1);
    xrad_error err = {0};
    xrad_solver *s = NULL;
    xrad_solver_desc d = {.method = XRAD_METHOD_CROSS, .hemicube_res = 2000};
    CHECK(scene && xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "hemicube_res"),
          "hemicube_res 2000: '%s'", err.message);
    d.hemicube_res = 16;
    d.threshold = 2;
    CHECK(scene && xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "threshold"),
          "threshold 2: '%s'", err.message);
    d.threshold = 0;
    if (scene && xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK) {
        CHECK(xrad_solver_advance(s, NAN, &err) == XRAD_ERROR_INPUT &&
                  strstr(err.message, "time"),
              "advance to NaN: '%s'", err.message);
        CHECK(xrad_solver_advance(s, INFINITY, &err) == XRAD_ERROR_INPUT,
              "advance to Inf: '%s'", err.message);
    }
    xrad_solver_destroy(&s);
    xrad_scene_destroy(&scene);
}

/* The next name of the comma-separated list at *at: its length, *at moved
 * past it and its comma; false at the end. */
static bool next_name(const char **at, const char **name, size_t *len)
{
    if (!**at)
        return false;
    *name = *at;
    *len = strcspn(*at, ",");
    *at += *len + ((*at)[*len] != 0);
    return true;
}

/* Whether the `len` characters at n spell `name`. */
static bool same_name(const char *n, size_t len, const char *name)
{
    return len == strlen(name) && !strncmp(n, name, len);
}

/* Whether `name` is one of the comma-separated `list`. */
static bool listed(const char *list, const char *name)
{
    const char *at = list, *n;
    size_t len;
    while (next_name(&at, &n, &len))
        if (same_name(n, len, name))
            return true;
    return false;
}

int main(int argc, char **argv)
{
    bool long_run = argc > 2 && !strcmp(argv[1], "--long");
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    if (long_run) {
        test_many_frames(ctx, !strcmp(argv[2], "cross") ? XRAD_METHOD_CROSS
                                                        : XRAD_METHOD_INCREMENTAL);
    } else {
        /* --only NAMES runs those parts, --except NAMES all others, NAMES
         * a comma-separated list (meson.build runs the furnace and the
         * errors as tests of their own: the errors under the sanitizers,
         * which leave the rest out). */
        const char *only = argc > 2 && !strcmp(argv[1], "--only") ? argv[2] : NULL;
        const char *except = argc > 2 && !strcmp(argv[1], "--except") ? argv[2] : NULL;
        static const struct {
            const char *name;
            void (*run)(xrad_context *);
        } parts[] = {{"errors", test_errors},       {"furnace", test_furnace},
                     {"emission", test_emission_range}, {"scale", test_scale},
                     {"geometry", test_geometry},   {"wall", test_through_wall}};
        const size_t part_count = sizeof(parts) / sizeof(parts[0]);
        /* A misspelt name must not pass: --only would run nothing, --except
         * everything. */
        const char *at = only ? only : except ? except : "", *n;
        size_t len;
        while (next_name(&at, &n, &len)) {
            size_t k = 0;
            while (k < part_count && !same_name(n, len, parts[k].name))
                k++;
            CHECK(k < part_count, "no part named '%.*s'", (int)len, n);
        }
        for (size_t k = 0; k < part_count; k++)
            if ((!only || listed(only, parts[k].name)) &&
                (!except || !listed(except, parts[k].name)))
                parts[k].run(ctx);
    }
    gpu_test_end(&ctx);
    return test_finish();
}
