/* What xrad bench's measurement and its sweep (bench_sweep.c) share. */
#ifndef XRAD_TOOLS_BENCH_H
#define XRAD_TOOLS_BENCH_H

#include <cjson/cJSON.h>

#include "cli.h"
#include "method.h"
#include "xrad.h"

typedef struct bench_opts {
    const char *scenes[CLI_POSITIONAL_MAX];
    int scene_count;
    const char *methods, *json, *cache, *device;
    uint32_t repeat, width, height, ref_rays, max_ref_elements, ref_gather_rays, ref_cell_points;
    xrad_visibility ref_visibility; /* --reference-visibility */
    bool ref_rays_set;              /* --reference-rays given */
    double time, fps;
    method_settings m;
    const char *sweep;          /* NULL, "one" or "grid" */
    const char *sweep_settings; /* "name=v1,v2;name2=..." */
    const char *sweep_out;      /* directory */
    const char *metric;         /* the sweep's Pareto error: a BENCH_METRICS name */
} bench_opts;

/* What --metric may name; "surface_error" is the default. */
#define BENCH_METRICS "nrmse|rel_rms|surface_error|element_p95"

/* What a point is measured against: the image at the pose, with its
 * coverage (alpha) and emitter mask, and the element solution it was drawn
 * from, in the layout of the scene it was made for. */
typedef struct bench_reference {
    float *image;   /* RGBA, alpha 0 where no surface is */
    float *emitter; /* one float per pixel, non-zero where an emitter shows */
    uint32_t width, height;
    xrad_atlas atlas;
    uint32_t elements;          /* the layout's element count */
    char kind[32];              /* "cpu-reference" or "gather-high" */
} bench_reference;

/* One measured scene x method x settings. Figures a point cannot have (an
 * image with no counted pixel) are NaN, written as null / empty. */
typedef struct bench_point {
    double frame_ms, p95_ms, gpu_ms; /* median and 95th percentile of the timed frames */
    double nrmse;                    /* of the last frame against the reference image */
    double mean_ratio, rel_rms;      /* image space, non-emitter pixels (xrad_image_compare) */
    double surface_error, element_p50, element_p95, element_max; /* xrad_atlas_compare */
    char worst_surface[128];
    double peak_mib;                 /* most GPU memory held while it ran */
    double hemicubes, host_waits;    /* per frame */
    cJSON *row;                      /* its JSON row (owned by the rows array) */
} bench_point;

/* The reference for `scene` (loaded as the caller measures it: its layout is
 * the atlas's) at scene time t: cached under o->cache, else made and cached.
 * Release with bench_reference_free. */
xrad_status bench_reference_get(xrad_context *ctx, const char *path, const xrad_scene *scene,
                                const bench_opts *o, double t, bench_reference *ref,
                                xrad_error *err);
void bench_reference_free(bench_reference *ref);

/* 1 if ref's atlas is in scene's element layout. */
int bench_reference_fits(const bench_reference *ref, const xrad_scene *scene);

/* Converges at o->time, times o->repeat frames, appends a row to `rows`.
 * Image figures against `image_ref`, element figures against `element_ref`
 * (the same reference, or one made for this scene's layout when the point's
 * settings change it; `element_note` then says so in the row). */
xrad_status bench_one(xrad_context *ctx, const char *path, const xrad_scene *scene,
                      const char *method, const method_settings *settings, const bench_opts *o,
                      const bench_reference *image_ref, const bench_reference *element_ref,
                      const char *element_note, cJSON *rows, bench_point *out,
                      xrad_error *err);

/* The figure --metric names, of a point. */
double bench_metric(const bench_point *p, const char *metric);

/* --sweep for one scene over o->methods. */
xrad_status bench_sweep(xrad_context *ctx, const char *path, const bench_opts *o,
                        xrad_error *err);

#endif
