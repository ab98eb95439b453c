/* xrad bench: per scene and method, frame time, per-pass GPU time, work
 * counters and NRMSE against a reference image (thesis tables 5.1 and 5.2). */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bench.h"
#include "cli.h"
#include "method.h"

static void help(void)
{
    printf("usage: xrad bench SCENE.json... [--methods LIST] [--json FILE] [options]\n\n"
           "Per scene and method (thesis tables 5.1 and 5.2): converges at --time, then\n"
           "times --repeat frames of the scene's animation, 1/--fps apart. A frame is a\n"
           "whole solve for gather and progressive, a redistribution and its progressive\n"
           "iterations for incremental and cross. Prints the median frame time, GPU time per\n"
           "pass (timestamp queries), hemicubes, shots, host waits per frame, and the error\n"
           "of the last frame against a reference at that pose (README \"Accuracy\"): in the\n"
           "camera image nrmse, mean_ratio and rel_rms (non-emitter pixels), in the element\n"
           "solution surface_error with its worst surface and element_p50/p95/max; then the\n"
           "frame-time ratios progressive/cross and incremental/cross. The JSON also has\n"
           "every frame's time, the 95th percentile (nearest rank) and each pass's median.\n"
           "Each row's \"reference\" and \"element_reference\" say what it was measured\n"
           "against: the CPU reference (\"cpu-reference\", the dense solver), or above\n"
           "--max-reference-elements its gather solver (\"cpu-gather\"), for the image and\n"
           "the elements alike.\n\n"
           "  --methods LIST     comma-separated: %s\n"
           "                     [progressive,cross: the real-time ones; gather takes\n"
           "                     minutes a frame on a CPU device]\n"
           "  --json FILE        also write the rows and ratios as JSON\n"
           "  --repeat N         timed frames per scene and method; the median is reported [3]\n"
           "  --time T, --fps F  start pose (s) and frame rate of scene time [0, 30]\n"
           "  --width N, --height N   image size for the image figures [the scene camera's]\n"
           "  --reference-rays N CPU reference rays where clipping gives up [32]; with rays\n"
           "                     visibility, per pair [64]\n"
           "  --reference-visibility V  auto, clip or rays (xrad render --help) [auto]\n"
           "  --cache DIR        where references are kept [out/bench-cache]\n"
           "  --max-reference-elements N  above this element count the CPU reference\n"
           "                     gathers by Monte Carlo rays (xrad render --reference-solver\n"
           "                     gather) instead of building the dense matrix [12000]\n"
           "  --reference-gather-rays N  rays per element of that gather [256]\n"
           "  --reference-cell-points N  the dense reference's points per cell side: its\n"
           "                     elements are their cells' means (xrad render --help) [1]\n"
           "  --device NAME      Vulkan device\n"
           "  --sweep one|grid   instead: per scene and method, vary the quality settings\n"
           "                     one at a time from the base (and the presets draft,\n"
           "                     interactive, high) or over their whole grid; writes\n"
           "                     DIR/SCENE-METHOD.csv, .json and an .svg of frame time\n"
           "                     against --metric with the Pareto front labelled\n"
           "  --metric NAME      the sweep's error for its Pareto front: %s\n"
           "                     [surface_error]\n"
           "  --sweep-settings S which settings and values: \"hemicube_res=16,32,64;\n"
           "                     cross_grid=1,4\" [one: a list per method; grid: needed]\n"
           "  --sweep-out DIR    where the sweep's files go [out/sweep]\n",
           method_list(), BENCH_METRICS);
    method_print_options();
    printf("\nReferences (the image with its emitter mask, and the element solution) are\n"
           "cached in the cache directory under a name that hashes the scene file, the\n"
           "reference settings (and the reference solver's visibility method), the image\n"
           "size, the pose's time, the element layout and the cache's version. A sweep\n"
           "point whose settings change the element layout (density_scale, the draft\n"
           "preset) has its element figures against a reference of its own layout.\n");
}

/* FNV-1a, to name cached references by what made them. */
static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 0x100000001b3ULL;
    return h;
}

static uint64_t hash_file(uint64_t h, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return h;
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof(buf), f)) > 0)
        h = fnv1a(h, buf, n);
    fclose(f);
    return h;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v[n] and returns its median (the upper one for even n). */
static double median(double *v, uint32_t n)
{
    qsort(v, n, sizeof(double), cmp_double);
    return v[n / 2];
}

/* Nearest-rank percentile q (0..1] of sorted v[n]. */
static double percentile(const double *v, uint32_t n, double q)
{
    uint32_t k = (uint32_t)ceil(q * n);
    return v[k ? k - 1 : 0];
}

/* Per-pass GPU ms of each timed frame: the passes' names as they first
 * appear, their times by frame (0 in a frame without the pass). */
typedef struct pass_frames {
    char names[XRAD_MAX_PASSES][48];
    uint32_t count;
    double *ms[XRAD_MAX_PASSES]; /* [repeat] each */
} pass_frames;

static bool pass_frames_add(pass_frames *pf, const xrad_solver_stats *st, uint32_t frame,
                            uint32_t repeat)
{
    for (uint32_t i = 0; i < st->pass_count; i++) {
        uint32_t k = 0;
        while (k < pf->count && strcmp(pf->names[k], st->passes[i].name))
            k++;
        if (k == pf->count) {
            if (k == XRAD_MAX_PASSES)
                continue;
            snprintf(pf->names[k], sizeof(pf->names[k]), "%s", st->passes[i].name);
            if (!(pf->ms[k] = calloc(repeat, sizeof(double))))
                return false;
            pf->count++;
        }
        pf->ms[k][frame] = st->passes[i].ms;
    }
    return true;
}

static void pass_frames_free(pass_frames *pf)
{
    for (uint32_t k = 0; k < pf->count; k++)
        free(pf->ms[k]);
}

/* Bumped when what is cached or how it is measured changes, so that
 * files of an older bench are made again rather than read: 1 added the
 * element atlas and the emitter mask beside the image; 2: the reference's
 * faces pressed against others see nothing (ref_receiver_pressed). */
#define BENCH_CACHE_VERSION 2

void bench_reference_free(bench_reference *ref)
{
    free(ref->image);
    free(ref->emitter);
    xrad_atlas_destroy(&ref->atlas);
    memset(ref, 0, sizeof(*ref));
}

int bench_reference_fits(const bench_reference *ref, const xrad_scene *scene)
{
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    return ref->atlas.rgba && ref->elements == info.elements &&
           ref->atlas.width == info.atlas_width && ref->atlas.height == info.atlas_height;
}

/* The cached files: <stem>.exr is the image with its "A" coverage and
 * "emitter" channel, <stem>-atlas.exr the element solution. Returns 0 when
 * any is missing or not of this version. */
static int reference_read(const char *stem, const xrad_scene *scene, bench_reference *ref)
{
    char image[1100], atlas[1100];
    snprintf(image, sizeof(image), "%s.exr", stem);
    snprintf(atlas, sizeof(atlas), "%s-atlas.exr", stem);
    if (access(image, R_OK) || access(atlas, R_OK))
        return 0;
    xrad_error ignored;
    method_image img;
    if (method_read_image(image, &img, &ignored))
        return 0;
    ref->image = img.rgba;
    ref->emitter = img.emitter;
    ref->width = img.width;
    ref->height = img.height;
    if (xrad_image_read_exr(atlas, &ref->atlas.rgba, &ref->atlas.width, &ref->atlas.height,
                            &ignored) ||
        !ref->emitter)
        return 0;
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    ref->elements = info.elements;
    return bench_reference_fits(ref, scene);
}

xrad_status bench_reference_get(xrad_context *ctx, const char *path, const xrad_scene *scene,
                                const bench_opts *o, double t, bench_reference *ref,
                                xrad_error *err)
{
    memset(ref, 0, sizeof(*ref));
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    /* Up to --max-reference-elements the dense solver, beyond it the
     * gather solver (no matrix; Monte Carlo, rays visibility). */
    bool dense = info.elements <= o->max_ref_elements;
    char settings[256];
    /* The visibility as the solver will resolve it (xrad.h), in the cache
     * key: images of one are not reused for the other. Rays visibility
     * takes the library's rays per pair unless --reference-rays says. */
    xrad_visibility vis = o->ref_visibility;
    if (vis == XRAD_VISIBILITY_AUTO || !dense)
        vis = info.surfaces > XRAD_REFERENCE_CLIP_SURFACES || !dense ? XRAD_VISIBILITY_RAYS
                                                                     : XRAD_VISIBILITY_CLIP;
    uint32_t rays = vis == XRAD_VISIBILITY_RAYS && !o->ref_rays_set ? 64 : o->ref_rays;
    /* cell_points only where asked: the default's key stays what caches hold. */
    char cells[32] = "";
    if (o->ref_cell_points > 1)
        snprintf(cells, sizeof(cells), " cell_points=%u", o->ref_cell_points);
    if (dense)
        snprintf(settings, sizeof(settings), "cpu-reference rays=%u residual=1e-7 visibility=%s%s",
                 rays, method_visibility_name(vis), cells);
    else
        snprintf(settings, sizeof(settings), "cpu-gather rays=%u gather_rays=%u residual=1e-7",
                 rays, o->ref_gather_rays);
    const char *kind = dense ? "cpu-reference" : "cpu-gather";
    snprintf(ref->kind, sizeof(ref->kind), "%s", kind);
    uint64_t hash = hash_file(0xcbf29ce484222325ULL, path);
    hash = fnv1a(hash, settings, strlen(settings));
    uint32_t size[2] = {o->width, o->height};
    hash = fnv1a(hash, size, sizeof(size));
    hash = fnv1a(hash, &t, sizeof(t));
    /* The element layout (the density the scene was loaded with) and the
     * cache's version. */
    uint32_t layout[4] = {info.elements, info.atlas_width, info.atlas_height,
                          BENCH_CACHE_VERSION};
    hash = fnv1a(hash, layout, sizeof(layout));
    char name[256], stem[1024];
    snprintf(stem, sizeof(stem), "%s/%s-%016llx", o->cache,
             cli_basename_noext(path, name, sizeof(name)), (unsigned long long)hash);
    if (reference_read(stem, scene, ref)) {
        fprintf(stderr, "bench: %s: reference from %s.exr\n", path, stem);
        return XRAD_OK;
    }
    bench_reference_free(ref);
    snprintf(ref->kind, sizeof(ref->kind), "%s", kind);
    fprintf(stderr, "bench: %s: making the reference (%s, %u elements)\n", path, settings,
            info.elements);
    xrad_status st = xrad_atlas_create(scene, &ref->atlas, err);
    if (st)
        return st;
    ref->elements = info.elements;
    method_settings m = {0};
    m.reference.rays = rays;
    m.reference.visibility = vis;
    m.reference.residual = 1e-7;
    m.reference.solver = dense ? XRAD_REFERENCE_SOLVER_DENSE : XRAD_REFERENCE_SOLVER_GATHER;
    m.reference.gather_rays = o->ref_gather_rays;
    m.reference.cell_points = dense ? o->ref_cell_points : 0;
    m.reference.time = t;
    method_result r;
    st = method_run(ctx, scene, "reference", &m, &ref->atlas, &r, err);
    xrad_view_desc view = {.width = o->width, .height = o->height, .time = t};
    if (!st)
        st = xrad_render_view(ctx, scene, &ref->atlas, &view, &ref->image, &ref->width,
                              &ref->height, err);
    if (!st)
        st = method_emitter_mask(ctx, scene, &view, &ref->emitter, err);
    if (st) {
        bench_reference_free(ref);
        return st;
    }
    char image[1100], atlas[1100];
    snprintf(image, sizeof(image), "%s.exr", stem);
    snprintf(atlas, sizeof(atlas), "%s-atlas.exr", stem);
    xrad_error ignored;
    /* A cache that cannot be written costs time, not results. */
    if (cli_make_parent_dirs(image) &&
        xrad_image_write_exr_channel(image, ref->image, "emitter", ref->emitter, ref->width,
                                     ref->height, &ignored) == XRAD_OK &&
        xrad_image_write_exr(atlas, ref->atlas.rgba, ref->atlas.width, ref->atlas.height,
                             &ignored) == XRAD_OK) {
        char meta[1100];
        snprintf(meta, sizeof(meta), "%s.txt", stem);
        FILE *f = fopen(meta, "w");
        if (f) {
            fprintf(f,
                    "scene %s\nsettings %s\nsize %ux%u\ntime %.17g\nelements %u\n"
                    "atlas %ux%u\nversion %d\n",
                    path, settings, ref->width, ref->height, t, info.elements,
                    info.atlas_width, info.atlas_height, BENCH_CACHE_VERSION);
            fclose(f);
        }
    }
    return XRAD_OK;
}

double bench_metric(const bench_point *p, const char *metric)
{
    if (!strcmp(metric, "nrmse"))
        return p->nrmse;
    if (!strcmp(metric, "rel_rms"))
        return p->rel_rms;
    if (!strcmp(metric, "element_p95"))
        return p->element_p95;
    return p->surface_error;
}

static int parse(int argc, char **argv, bench_opts *o)
{
    cli_args a;
    cli_init(&a, argc, argv);
    o->methods = "progressive,cross";
    o->cache = "out/bench-cache";
    o->repeat = 3;
    o->ref_rays = 32;
    o->max_ref_elements = 12000;
    o->ref_gather_rays = 256;
    o->fps = 30;
    o->sweep_out = "out/sweep";
    o->metric = "surface_error";
    const char *opt;
    while ((opt = cli_next(&a)) && !a.failed) {
        if (cli_is_help(opt)) {
            help();
            return -1;
        } else if (!strcmp(opt, "methods")) {
            o->methods = cli_value(&a);
        } else if (!strcmp(opt, "json")) {
            o->json = cli_value(&a);
        } else if (!strcmp(opt, "cache")) {
            o->cache = cli_value(&a);
        } else if (!strcmp(opt, "repeat")) {
            cli_uint(&a, 1, 1000, &o->repeat);
        } else if (!strcmp(opt, "width")) {
            cli_uint(&a, 1, 16384, &o->width);
        } else if (!strcmp(opt, "height")) {
            cli_uint(&a, 1, 16384, &o->height);
        } else if (!strcmp(opt, "reference-rays")) {
            o->ref_rays_set = cli_uint(&a, 1, 4096, &o->ref_rays);
        } else if (!strcmp(opt, "reference-visibility")) {
            method_visibility_option(&a, &o->ref_visibility);
        } else if (!strcmp(opt, "reference-gather-rays")) {
            cli_uint(&a, 1, 65536, &o->ref_gather_rays);
        } else if (!strcmp(opt, "reference-cell-points")) {
            cli_uint(&a, 1, 8, &o->ref_cell_points);
        } else if (!strcmp(opt, "max-reference-elements")) {
            cli_uint(&a, 0, 100000, &o->max_ref_elements);
        } else if (!strcmp(opt, "time")) {
            cli_double(&a, -1e6, 1e6, &o->time);
        } else if (!strcmp(opt, "fps")) {
            cli_double(&a, 1e-3, 1e6, &o->fps);
        } else if (!strcmp(opt, "sweep")) {
            o->sweep = cli_value(&a);
            if (o->sweep && strcmp(o->sweep, "one") && strcmp(o->sweep, "grid"))
                return cli_usage_error("bench", "--sweep: '%s' is neither 'one' nor 'grid'",
                                       o->sweep);
        } else if (!strcmp(opt, "sweep-settings")) {
            o->sweep_settings = cli_value(&a);
        } else if (!strcmp(opt, "sweep-out")) {
            o->sweep_out = cli_value(&a);
        } else if (!strcmp(opt, "metric")) {
            o->metric = cli_value(&a);
            if (o->metric && strcmp(o->metric, "nrmse") && strcmp(o->metric, "rel_rms") &&
                strcmp(o->metric, "surface_error") && strcmp(o->metric, "element_p95"))
                return cli_usage_error("bench", "--metric: '%s' is not one of %s", o->metric,
                                       BENCH_METRICS);
        } else if (method_solver_option(&a, opt, &o->m)) {
            continue;
        } else if (!strcmp(opt, "device")) {
            o->device = cli_value(&a);
        } else {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count < 1)
        return cli_usage_error("bench", "needs at least one scene file (see xrad bench --help)");
    for (int i = 0; i < a.positional_count; i++)
        o->scenes[o->scene_count++] = a.positional[i];
    char list[512];
    snprintf(list, sizeof(list), "%s", o->methods);
    for (char *save = NULL, *m = strtok_r(list, ",", &save); m; m = strtok_r(NULL, ",", &save))
        if (!method_known(m))
            return cli_usage_error("bench", "--methods: unknown method '%s' (available: %s)", m,
                                   method_list());
    return 0;
}

/* One scene x method: converge at o->time, then `repeat` timed frames; the
 * last one's image for NRMSE. Returns the median frame time in *frame_ms. */
xrad_status bench_one(xrad_context *ctx, const char *path, const xrad_scene *scene,
                      const char *method, const method_settings *settings, const bench_opts *o,
                      const bench_reference *image_ref, const bench_reference *element_ref,
                      const char *element_note, cJSON *rows, bench_point *out,
                      xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    xrad_context_reset_memory_peak(ctx);
    method_run_state run = {0};
    xrad_atlas atlas = {0};
    xrad_status st = xrad_atlas_create(scene, &atlas, err);
    if (st)
        return st;
    double *wall = calloc(o->repeat, sizeof(double)), *gpu = calloc(o->repeat, sizeof(double));
    /* Work per timed frame: hemicubes, host waits, submissions, cross's
     * listed pairs. */
    double work[4] = {0, 0, 0, 0};
    pass_frames pf = {0};
    method_result r = {0};
    float *img = NULL;
    uint32_t w = 0, h = 0;
    if (!wall || !gpu) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "bench: out of memory");
        goto done;
    }
    method_settings m = *settings;
    m.solver.time = m.reference.time = o->time;
    /* The dynamic methods start from a converged solution; the others
     * solve every frame from scratch and need none. */
    xrad_method id = xrad_method_from_name(method);
    bool dynamic = id == XRAD_METHOD_INCREMENTAL || id == XRAD_METHOD_CROSS;
    if ((st = method_open(ctx, scene, method, &m, &run, err)) ||
        (dynamic && (st = method_frame(&run, o->time, &atlas, &r, err))))
        goto done;
    double t = o->time;
    for (uint32_t k = 0; k < o->repeat && !st; k++) {
        t = o->time + (k + 1) / o->fps;
        st = method_frame(&run, t, &atlas, &r, err);
        wall[k] = r.wall_ms;
        gpu[k] = r.gpu ? r.stats.gpu_ms : r.wall_ms;
        if (!st && r.gpu) {
            work[0] += r.stats.hemicubes;
            work[1] += r.stats.host_waits;
            work[2] += r.stats.submissions;
            work[3] += (double)r.stats.cross_pairs;
            if (!pass_frames_add(&pf, &r.stats, k, o->repeat))
                st = cli_fail(err, XRAD_ERROR_SYSTEM, "bench: out of memory");
        }
    }
    if (st)
        goto done;
    xrad_view_desc view = {.width = image_ref->width, .height = image_ref->height, .time = t};
    if ((st = xrad_render_view(ctx, scene, &atlas, &view, &img, &w, &h, err)))
        goto done;
    /* README "Accuracy": NaN where a figure does not exist for this point
     * (no counted pixel, an element reference of another layout). */
    xrad_image_metrics im = {.nrmse = NAN, .mean_ratio = NAN, .rel_rms = NAN};
    xrad_error ignored;
    if (xrad_image_compare(img, image_ref->image, image_ref->emitter, w, h, &im, &ignored))
        im.mean_ratio = im.rel_rms = NAN;
    xrad_element_metrics em;
    char worst[128] = "";
    if (bench_reference_fits(element_ref, scene) &&
        xrad_atlas_compare(scene, &atlas, &element_ref->atlas, &em, NULL, &ignored) == XRAD_OK)
        method_surface_label(scene, em.worst_surface, worst, sizeof(worst));
    else
        em = (xrad_element_metrics){.surface_error = NAN, .p50 = NAN, .p95 = NAN, .max = NAN,
                                    .mean_ratio = NAN, .worst_ratio = NAN};
    cJSON *row = cJSON_CreateObject();
    cJSON_AddStringToObject(row, "scene", path);
    cJSON_AddStringToObject(row, "method", method);
    cJSON *frames = cJSON_AddArrayToObject(row, "frames_ms");
    for (uint32_t k = 0; k < o->repeat; k++)
        cJSON_AddItemToArray(frames, cJSON_CreateNumber(wall[k]));
    double frame_median = median(wall, o->repeat), gpu_median = median(gpu, o->repeat);
    double nrmse = xrad_image_nrmse(img, image_ref->image, w, h);
    cJSON_AddNumberToObject(row, "frame_ms", frame_median);
    cJSON_AddNumberToObject(row, "frame_ms_p95", percentile(wall, o->repeat, 0.95));
    cJSON_AddNumberToObject(row, "redistribute_ms", r.gpu ? r.stats.redistribute_ms : 0);
    cJSON_AddNumberToObject(row, "gpu_ms", gpu_median);
    /* Median GPU ms per frame of each pass. */
    cJSON *passes = cJSON_AddObjectToObject(row, "passes");
    for (uint32_t k = 0; k < pf.count; k++)
        cJSON_AddNumberToObject(passes, pf.names[k], median(pf.ms[k], o->repeat));
    cJSON_AddNumberToObject(row, "hemicubes_per_frame", work[0] / o->repeat);
    cJSON_AddNumberToObject(row, "host_waits_per_frame", work[1] / o->repeat);
    cJSON_AddNumberToObject(row, "submissions_per_frame", work[2] / o->repeat);
    /* cross with cross_pairs on: the (element, patch) pairs traced; 0 without the list */
    cJSON_AddNumberToObject(row, "cross_pairs_per_frame", work[3] / o->repeat);
    cJSON_AddNumberToObject(row, "hemicubes", r.gpu ? r.stats.hemicubes : 0);
    cJSON_AddNumberToObject(row, "shots", r.gpu ? r.stats.shots : 0);
    cJSON_AddNumberToObject(row, "iterations", r.gpu ? r.stats.iterations : r.ref.sweeps);
    cJSON_AddNumberToObject(row, "submissions", r.gpu ? r.stats.submissions : 0);
    cJSON_AddNumberToObject(row, "host_waits", r.gpu ? r.stats.host_waits : 0);
    cJSON_AddNumberToObject(row, "nrmse", nrmse);
    cJSON_AddNumberToObject(row, "mean_ratio", im.mean_ratio);
    cJSON_AddNumberToObject(row, "rel_rms", im.rel_rms);
    cJSON_AddNumberToObject(row, "pixels", (double)im.pixels);
    cJSON_AddNumberToObject(row, "surface_error", em.surface_error);
    cJSON_AddStringToObject(row, "worst_surface", worst);
    cJSON_AddNumberToObject(row, "worst_surface_ratio", em.worst_ratio);
    cJSON_AddNumberToObject(row, "element_p50", em.p50);
    cJSON_AddNumberToObject(row, "element_p95", em.p95);
    cJSON_AddNumberToObject(row, "element_max", em.max);
    cJSON_AddNumberToObject(row, "element_mean_ratio", em.mean_ratio);
    cJSON_AddStringToObject(row, "reference", image_ref->kind);
    char el_kind[160];
    snprintf(el_kind, sizeof(el_kind), "%s%s%s", element_ref->kind,
             element_note ? ", " : "", element_note ? element_note : "");
    cJSON_AddStringToObject(row, "element_reference", el_kind);
    cJSON_AddStringToObject(row, "hemicube_path",
                            r.gpu && r.stats.hemicube_path ? r.stats.hemicube_path : "-");
    cJSON_AddStringToObject(row, "device", xrad_context_device_name(ctx));
    cJSON_AddNumberToObject(row, "repeat", o->repeat);
    cJSON_AddNumberToObject(row, "time", t);
    xrad_memory_stats mem;
    xrad_context_get_memory(ctx, &mem);
    cJSON_AddNumberToObject(row, "peak_gpu_mib", (double)mem.total_peak / 1048576.0);
    cJSON_AddItemToArray(rows, row);
    *out = (bench_point){
        .frame_ms = frame_median,
        .p95_ms = percentile(wall, o->repeat, 0.95),
        .gpu_ms = gpu_median,
        .nrmse = nrmse,
        .mean_ratio = im.mean_ratio,
        .rel_rms = im.rel_rms,
        .surface_error = em.surface_error,
        .element_p50 = em.p50,
        .element_p95 = em.p95,
        .element_max = em.max,
        .peak_mib = (double)mem.total_peak / 1048576.0,
        .hemicubes = work[0] / o->repeat,
        .host_waits = work[1] / o->repeat,
        .row = row,
    };

    snprintf(out->worst_surface, sizeof(out->worst_surface), "%s", worst);
    printf("%-28s %-12s %12.1f %12.1f %12.1f %10.1f %8u %7.1f %10.5f %10.5f %10.5f %10.5f %s\n",
           path, method, frame_median, percentile(wall, o->repeat, 0.95), gpu_median,
           work[0] / o->repeat, r.gpu ? r.stats.shots : 0, work[1] / o->repeat, nrmse,
           im.rel_rms, em.surface_error, em.p95, worst[0] ? worst : "-");
    for (uint32_t k = 0; k < pf.count; k++)
        printf("%-28s   %-20s %10.2f ms\n", "", pf.names[k], median(pf.ms[k], o->repeat));
    fflush(stdout);
done:
    pass_frames_free(&pf);
    method_close(&run);
    free(img);
    free(wall);
    free(gpu);
    xrad_atlas_destroy(&atlas);
    return st;
}

int cmd_bench(int argc, char **argv)
{
    bench_opts o = {0};
    int rc = parse(argc, argv, &o);
    if (rc)
        return rc < 0 ? 0 : rc;
    xrad_error err = {0};
    xrad_context *ctx = NULL;
    if (cli_context_create((xrad_context_desc){.device = o.device}, &ctx, &err))
        return cli_report(&err);
    cJSON *out = cJSON_CreateObject();
    cJSON *rows = cJSON_AddArrayToObject(out, "rows");
    cJSON *ratios = cJSON_AddArrayToObject(out, "ratios");
    printf("device: %s\n", xrad_context_device_name(ctx));
    printf("%-28s %-12s %12s %12s %12s %10s %8s %7s %10s %10s %10s %10s %s\n", "scene",
           "method", "frame_ms", "p95_ms", "gpu_ms", "hemicubes", "shots", "waits", "nrmse",
           "rel_rms", "surf_err", "el_p95", "worst_surface");
    xrad_status st = XRAD_OK;
    for (int i = 0; i < o.scene_count && !st; i++) {
        const char *path = o.scenes[i];
        xrad_scene *scene = NULL;
        method_settings settings = o.m;
        if (o.sweep) {
            st = bench_sweep(ctx, path, &o, &err);
            continue;
        }
        if ((st = method_load_scene(path, &settings, &scene, &err)))
            break;
        bench_reference ref;
        st = bench_reference_get(ctx, path, scene, &o, o.time + o.repeat / o.fps, &ref, &err);
        if (!st)
            printf("%-28s reference: %s, for the image and the element figures\n", path,
                   ref.kind);
        char list[512];
        snprintf(list, sizeof(list), "%s", o.methods);
        double ms[5] = {0}; /* by xrad_method; 0 unused */
        for (char *save = NULL, *m = strtok_r(list, ",", &save); m && !st;
             m = strtok_r(NULL, ",", &save)) {
            bench_point pt;
            st = bench_one(ctx, path, scene, m, &settings, &o, &ref, &ref, NULL, rows, &pt, &err);
            double f = pt.frame_ms;
            if (xrad_method_from_name(m) < 5)
                ms[xrad_method_from_name(m)] = f;
        }
        bench_reference_free(&ref);
        if (!st && ms[XRAD_METHOD_CROSS] > 0) {
            cJSON *ratio = cJSON_CreateObject();
            cJSON_AddStringToObject(ratio, "scene", path);
            if (ms[XRAD_METHOD_PROGRESSIVE] > 0) {
                double q = ms[XRAD_METHOD_PROGRESSIVE] / ms[XRAD_METHOD_CROSS];
                printf("%-28s progressive/cross frame time %.2fx\n", path, q);
                cJSON_AddNumberToObject(ratio, "progressive_over_cross", q);
            }
            if (ms[XRAD_METHOD_INCREMENTAL] > 0) {
                double q = ms[XRAD_METHOD_INCREMENTAL] / ms[XRAD_METHOD_CROSS];
                printf("%-28s incremental/cross frame time %.2fx\n", path, q);
                cJSON_AddNumberToObject(ratio, "incremental_over_cross", q);
            }
            cJSON_AddItemToArray(ratios, ratio);
        }
        xrad_scene_destroy(&scene);
    }
    if (!st && o.json) {
        char *text = cJSON_Print(out);
        FILE *f = text && cli_make_parent_dirs(o.json) ? fopen(o.json, "w") : NULL;
        if (f) {
            fputs(text, f);
            fputc('\n', f);
            fclose(f);
            printf("wrote %s\n", o.json);
        } else {
            st = cli_fail(&err, XRAD_ERROR_SYSTEM, "%s: cannot write", o.json);
        }
        free(text);
    }
    cJSON_Delete(out);
    xrad_context_destroy(&ctx);
    return st ? cli_report(&err) : 0;
}
