/* What xrad bench's measurement and its sweep (bench_sweep.c) share. */
#ifndef XRAD_TOOLS_BENCH_H
#define XRAD_TOOLS_BENCH_H

#include <cjson/cJSON.h>

#include "method.h"
#include "xrad.h"

typedef struct bench_opts {
    const char *scenes[8];
    int scene_count;
    const char *methods, *json, *cache, *device;
    uint32_t repeat, width, height, ref_rays, max_ref_elements;
    double time, fps;
    method_settings m;
    const char *sweep;          /* NULL, "one" or "grid" */
    const char *sweep_settings; /* "name=v1,v2;name2=..." */
    const char *sweep_out;      /* directory */
} bench_opts;

/* One measured scene x method x settings. */
typedef struct bench_point {
    double frame_ms, p95_ms, gpu_ms; /* median and 95th percentile of the timed frames */
    double nrmse;                    /* of the last frame against the reference image */
    double peak_mib;                 /* most GPU memory held while it ran */
    double hemicubes, host_waits;    /* per frame */
    cJSON *row;                      /* its JSON row (owned by the rows array) */
} bench_point;

/* The reference image at scene time t: cached under o->cache, else made. */
xrad_status bench_reference_image(xrad_context *ctx, const char *path, const xrad_scene *scene,
                                  const bench_opts *o, double t, float **img, uint32_t *w,
                                  uint32_t *h, char *kind, size_t kind_n, xrad_error *err);

/* Converges at o->time, times o->repeat frames, appends a row to `rows`. */
xrad_status bench_one(xrad_context *ctx, const char *path, const xrad_scene *scene,
                      const char *method, const method_settings *settings, const bench_opts *o,
                      const float *ref, uint32_t rw, uint32_t rh, const char *ref_kind,
                      cJSON *rows, bench_point *out, xrad_error *err);

/* --sweep for one scene over o->methods. */
xrad_status bench_sweep(xrad_context *ctx, const char *path, const bench_opts *o,
                        xrad_error *err);

#endif
