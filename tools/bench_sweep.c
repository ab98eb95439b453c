/* xrad bench --sweep: the speed/accuracy trade of the quality settings.
 * For a scene and method, every point is a set of settings measured as
 * xrad bench measures (converged start, timed frames, the error figures of
 * README "Accuracy" of the last frame against the reference, GPU memory
 * peak); the points go to CSV, JSON and an SVG of frame time against the
 * --metric figure (surface_error by default) whose Pareto front
 * (tools/pareto.h) is labelled with the settings. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#include "cli.h"
#include "pareto.h"

#define SWEEP_MAX_AXES 16
#define SWEEP_MAX_VALUES 8
#define SWEEP_MAX_POINTS 256
/* Element layouts besides the base's with a reference of their own: the
 * densities of the one-at-a-time sweep and the presets, with room. */
#define SWEEP_MAX_LAYOUTS 8

enum { M_GATHER = 1, M_PROGRESSIVE = 2, M_INCREMENTAL = 4, M_CROSS = 8 };
#define M_SHOOT (M_PROGRESSIVE | M_INCREMENTAL | M_CROSS)
#define M_ALL (M_GATHER | M_SHOOT)

/* One-at-a-time values per setting, and the methods it matters to. */
static const struct {
    const char *name, *values;
    unsigned methods;
} defaults[] = {
    {"hemicube_res", "16,32,64,128", M_ALL},
    {"msaa", "1,4", M_GATHER},
    {"id_check", "neighbours,exact", M_SHOOT},
    {"subdivide_ratio", "0.001,0.01,0.1", M_SHOOT},
    {"max_patches", "2,4,8,16", M_SHOOT},
    {"threshold", "1e-2,1e-3,1e-4,1e-5", M_ALL},
    {"batch", "8,32,128", M_SHOOT},
    {"frame_shots", "8,32,0", M_INCREMENTAL | M_CROSS},
    {"cross_grid", "1,2,4,8", M_CROSS},
    {"cross_grid_ff", "0.005,0.05,0.2", M_CROSS},
    {"cross_cut", "0.001,0.01", M_CROSS},
    {"cross_pairs", "off,on", M_CROSS},
    {"back_mips", "off,on", M_CROSS},
    {"cross_regather", "off,after,on", M_CROSS},
    {"back_res", "8,16,32", M_CROSS},
    {"back_msaa", "1,4", M_CROSS},
    {"radiosity_format", "fp16,fp32", M_GATHER | M_CROSS},
    {"ambient", "off,on", M_SHOOT},
    {"conserve", "on,off,far", M_SHOOT},
    {"density_scale", "0.5,1,1.5", M_ALL},
    {"adaptive_levels", "0,1,2", M_ALL},
    {"adaptive_upper", "0.9,0.98", M_ALL},
};

static const char *const presets[] = {"draft", "interactive", "high"};

typedef struct axis {
    char name[48];
    uint32_t count;
    char values[SWEEP_MAX_VALUES][32];
} axis;

typedef struct point {
    char label[256];
    uint32_t count; /* overrides */
    const char *names[SWEEP_MAX_AXES];
    const char *values[SWEEP_MAX_AXES];
    const char *preset;
} point;

static unsigned method_bit(xrad_method m)
{
    return m == XRAD_METHOD_GATHER ? M_GATHER : m == XRAD_METHOD_PROGRESSIVE ? M_PROGRESSIVE
           : m == XRAD_METHOD_INCREMENTAL                                  ? M_INCREMENTAL
                                                                            : M_CROSS;
}

/* "a,b,c" into an axis. */
static xrad_status parse_values(const char *name, const char *list, axis *ax, xrad_error *err)
{
    snprintf(ax->name, sizeof(ax->name), "%s", name);
    ax->count = 0;
    char buf[256];
    snprintf(buf, sizeof(buf), "%s", list);
    for (char *save = NULL, *v = strtok_r(buf, ",", &save); v; v = strtok_r(NULL, ",", &save)) {
        if (ax->count == SWEEP_MAX_VALUES)
            return cli_fail(err, XRAD_ERROR_INPUT, "--sweep-settings: %s: more than %d values",
                            name, SWEEP_MAX_VALUES);
        xrad_quality scratch = {0};
        if (xrad_quality_set(&scratch, name, v, err))
            return XRAD_ERROR_INPUT;
        snprintf(ax->values[ax->count++], sizeof(ax->values[0]), "%s", v);
    }
    if (!ax->count)
        return cli_fail(err, XRAD_ERROR_INPUT, "--sweep-settings: %s has no values", name);
    return XRAD_OK;
}

/* "name=v1,v2;name2=..." */
static xrad_status parse_spec(const char *spec, axis *axes, uint32_t *n, xrad_error *err)
{
    *n = 0;
    char buf[1024];
    snprintf(buf, sizeof(buf), "%s", spec);
    for (char *save = NULL, *it = strtok_r(buf, ";", &save); it; it = strtok_r(NULL, ";", &save)) {
        char *eq = strchr(it, '=');
        if (!eq)
            return cli_fail(err, XRAD_ERROR_INPUT,
                            "--sweep-settings: '%s' is not NAME=VALUE,VALUE", it);
        *eq = 0;
        if (*n == SWEEP_MAX_AXES)
            return cli_fail(err, XRAD_ERROR_INPUT, "--sweep-settings: more than %d settings",
                            SWEEP_MAX_AXES);
        xrad_status st = parse_values(it, eq + 1, &axes[*n], err);
        if (st)
            return st;
        (*n)++;
    }
    return XRAD_OK;
}

/* The points: one at a time from the base (with the presets), or the grid. */
static xrad_status make_points(const bench_opts *o, xrad_method method, const axis *axes,
                               uint32_t naxes, point *pts, uint32_t *n, xrad_error *err)
{
    *n = 0;
    bool grid = !strcmp(o->sweep, "grid");
    if (grid) {
        uint64_t total = 1;
        for (uint32_t a = 0; a < naxes; a++)
            total *= axes[a].count;
        if (!naxes || total > SWEEP_MAX_POINTS)
            return cli_fail(err, XRAD_ERROR_INPUT,
                            "--sweep grid: %llu points (give --sweep-settings; at most %d)",
                            (unsigned long long)total, SWEEP_MAX_POINTS);
        for (uint64_t k = 0; k < total; k++) {
            point *p = &pts[(*n)++];
            memset(p, 0, sizeof(*p));
            uint64_t r = k;
            size_t len = 0;
            for (uint32_t a = 0; a < naxes; a++) {
                uint32_t v = (uint32_t)(r % axes[a].count);
                r /= axes[a].count;
                p->names[p->count] = axes[a].name;
                p->values[p->count++] = axes[a].values[v];
                size_t room = len < sizeof(p->label) ? sizeof(p->label) - len : 0;
                len += (size_t)snprintf(p->label + len, room, "%s%s=%s", a ? " " : "",
                                        axes[a].name, axes[a].values[v]);
            }
        }
        return XRAD_OK;
    }
    point *base = &pts[(*n)++];
    memset(base, 0, sizeof(*base));
    snprintf(base->label, sizeof(base->label), "base");
    for (size_t k = 0; k < sizeof(presets) / sizeof(presets[0]); k++) {
        point *p = &pts[(*n)++];
        memset(p, 0, sizeof(*p));
        p->preset = presets[k];
        snprintf(p->label, sizeof(p->label), "preset=%s", presets[k]);
    }
    for (uint32_t a = 0; a < naxes; a++)
        for (uint32_t v = 0; v < axes[a].count && *n < SWEEP_MAX_POINTS; v++) {
            point *p = &pts[(*n)++];
            memset(p, 0, sizeof(*p));
            p->names[0] = axes[a].name;
            p->values[0] = axes[a].values[v];
            p->count = 1;
            snprintf(p->label, sizeof(p->label), "%s=%s", axes[a].name, axes[a].values[v]);
        }
    (void)method;
    return XRAD_OK;
}

static void csv_text(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* A figure for the CSV: empty where the point has none (NaN). */
static void csv_number(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, ",%.7g", v);
    else
        fputc(',', f);
}

static xrad_status write_outputs(const char *stem, const char *scene, const char *method,
                                 const bench_opts *o, xrad_context *ctx, point *pts,
                                 bench_point *res, method_settings *settings, uint32_t n,
                                 xrad_error *err)
{
    pareto_point *pp = calloc(n ? n : 1, sizeof(*pp));
    if (!pp)
        return cli_fail(err, XRAD_ERROR_SYSTEM, "bench: out of memory");
    /* A point without the figure (NaN) is never on the front. */
    for (uint32_t k = 0; k < n; k++)
        pp[k] = (pareto_point){res[k].frame_ms, bench_metric(&res[k], o->metric), pts[k].label,
                               false};
    pareto_mark(pp, n);

    char path[1100];
    snprintf(path, sizeof(path), "%s.csv", stem);
    FILE *f = cli_make_parent_dirs(path) ? fopen(path, "w") : NULL;
    xrad_status st = XRAD_OK;
    if (!f) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot write", path);
        goto done;
    }
    fprintf(f, "label");
    for (uint32_t i = 0; i < xrad_setting_count(); i++)
        fprintf(f, ",%s", xrad_setting_get(i)->name);
    fprintf(f, ",frame_ms,frame_ms_p95,gpu_ms,nrmse,mean_ratio,rel_rms,surface_error,"
               "worst_surface,element_p50,element_p95,element_max,reference,element_reference,"
               "peak_gpu_mib,hemicubes_per_frame,host_waits_per_frame,pareto,passes\n");
    for (uint32_t k = 0; k < n; k++) {
        csv_text(f, pts[k].label);
        for (uint32_t i = 0; i < xrad_setting_count(); i++) {
            char v[64];
            xrad_quality_format(&settings[k].resolved, xrad_setting_get(i)->name, v, sizeof(v),
                                NULL);
            fprintf(f, ",%s", v);
        }
        fprintf(f, ",%.3f,%.3f,%.3f", res[k].frame_ms, res[k].p95_ms, res[k].gpu_ms);
        csv_number(f, res[k].nrmse);
        csv_number(f, res[k].mean_ratio);
        csv_number(f, res[k].rel_rms);
        csv_number(f, res[k].surface_error);
        fputc(',', f);
        csv_text(f, res[k].worst_surface);
        csv_number(f, res[k].element_p50);
        csv_number(f, res[k].element_p95);
        csv_number(f, res[k].element_max);
        const cJSON *ref = cJSON_GetObjectItemCaseSensitive(res[k].row, "reference");
        const cJSON *el_ref = cJSON_GetObjectItemCaseSensitive(res[k].row, "element_reference");
        fputc(',', f);
        csv_text(f, cJSON_IsString(ref) ? ref->valuestring : "");
        fputc(',', f);
        csv_text(f, cJSON_IsString(el_ref) ? el_ref->valuestring : "");
        fprintf(f, ",%.3f,%.1f,%.1f,%d,", res[k].peak_mib, res[k].hemicubes,
                res[k].host_waits, pp[k].front ? 1 : 0);
        char passes[1024] = "";
        size_t len = 0;
        const cJSON *ps = cJSON_GetObjectItemCaseSensitive(res[k].row, "passes");
        for (const cJSON *it = ps ? ps->child : NULL; it; it = it->next)
            len += (size_t)snprintf(passes + len, len < sizeof(passes) ? sizeof(passes) - len : 0,
                                    "%s%s=%.3f", len ? ";" : "", it->string, it->valuedouble);
        csv_text(f, passes);
        fputc('\n', f);
    }
    if (fclose(f)) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot write", path);
        goto done;
    }
    printf("wrote %s\n", path);

    cJSON *out = cJSON_CreateObject(), *rows = cJSON_AddArrayToObject(out, "points");
    cJSON_AddStringToObject(out, "scene", scene);
    cJSON_AddStringToObject(out, "method", method);
    cJSON_AddStringToObject(out, "device", xrad_context_device_name(ctx));
    cJSON_AddStringToObject(out, "pareto_metric", o->metric);
    for (uint32_t k = 0; k < n; k++) {
        cJSON *row = cJSON_Duplicate(res[k].row, 1);
        cJSON_AddStringToObject(row, "label", pts[k].label);
        cJSON_AddBoolToObject(row, "pareto", pp[k].front);
        cJSON *set = cJSON_AddObjectToObject(row, "settings");
        for (uint32_t i = 0; i < xrad_setting_count(); i++) {
            char v[64];
            xrad_quality_format(&settings[k].resolved, xrad_setting_get(i)->name, v, sizeof(v),
                                NULL);
            cJSON_AddStringToObject(set, xrad_setting_get(i)->name, v);
        }
        cJSON_AddItemToArray(rows, row);
    }
    char *text = cJSON_Print(out);
    cJSON_Delete(out);
    snprintf(path, sizeof(path), "%s.json", stem);
    f = text ? fopen(path, "w") : NULL;
    if (!f || fputs(text, f) < 0 || fclose(f)) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot write", path);
        free(text);
        goto done;
    }
    free(text);
    printf("wrote %s\n", path);

    snprintf(path, sizeof(path), "%s.svg", stem);
    char title[512];
    snprintf(title, sizeof(title), "%s, %s on %s: frame time against %s", scene, method,
             xrad_context_device_name(ctx), o->metric);
    if (pareto_write_svg_named(path, title, o->metric, pp, n)) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot write", path);
        goto done;
    }
    printf("wrote %s\nPareto front (frame ms, %s):\n", path, o->metric);
    for (uint32_t k = 0; k < n; k++)
        if (pp[k].front)
            printf("  %10.1f  %.5f  %s\n", pp[k].time_ms, pp[k].error, pp[k].label);
done:
    free(pp);
    return st;
}

xrad_status bench_sweep(xrad_context *ctx, const char *path, const bench_opts *o,
                        xrad_error *err)
{
    axis axes[SWEEP_MAX_AXES];
    uint32_t nspec = 0;
    xrad_status st = o->sweep_settings ? parse_spec(o->sweep_settings, axes, &nspec, err)
                                       : XRAD_OK;
    if (st)
        return st;
    /* The reference: the scene as the base settings load it. Points whose
     * settings change the element layout (density_scale, a preset's) are
     * compared in image space against it as they are; their element
     * figures need a reference of their own layout, made (or read from the
     * cache) once per layout. */
    method_settings base = o->m;
    xrad_scene *ref_scene = NULL;
    double t_ref = o->time + o->repeat / o->fps;
    bench_reference ref = {0}, layouts[SWEEP_MAX_LAYOUTS];
    uint32_t nlayouts = 0;
    if ((st = method_load_scene(path, &base, &ref_scene, err)) ||
        (st = bench_reference_get(ctx, path, ref_scene, o, t_ref, &ref, err))) {
        xrad_scene_destroy(&ref_scene);
        return st;
    }
    xrad_scene_destroy(&ref_scene);
    printf("sweep: %s: reference %s (image; element figures against it at the base "
           "element layout, else against one of the point's layout)\n",
           path, ref.kind);
    point *pts = calloc(SWEEP_MAX_POINTS, sizeof(*pts));
    bench_point *res = calloc(SWEEP_MAX_POINTS, sizeof(*res));
    method_settings *ms = calloc(SWEEP_MAX_POINTS, sizeof(*ms));
    cJSON *rows = cJSON_CreateArray();
    if (!pts || !res || !ms || !rows) {
        st = cli_fail(err, XRAD_ERROR_SYSTEM, "bench: out of memory");
        goto done;
    }
    char list[512];
    snprintf(list, sizeof(list), "%s", o->methods);
    for (char *save = NULL, *m = strtok_r(list, ",", &save); m && !st;
         m = strtok_r(NULL, ",", &save)) {
        xrad_method id = xrad_method_from_name(m);
        if (!id) {
            st = cli_fail(err, XRAD_ERROR_INPUT, "--sweep: '%s' is not a GPU method", m);
            break;
        }
        axis own[SWEEP_MAX_AXES];
        uint32_t naxes = nspec;
        memcpy(own, axes, sizeof(axes[0]) * nspec);
        if (!o->sweep_settings)
            for (size_t d = 0; d < sizeof(defaults) / sizeof(defaults[0]) && !st; d++)
                if (defaults[d].methods & method_bit(id))
                    st = parse_values(defaults[d].name, defaults[d].values, &own[naxes++], err);
        uint32_t n = 0;
        if (st || (st = make_points(o, id, own, naxes, pts, &n, err)))
            break;
        printf("sweep: %s, %s: %u points\n", path, m, n);
        for (uint32_t k = 0; k < n && !st; k++) {
            ms[k] = o->m;
            if (pts[k].preset)
                ms[k].preset = pts[k].preset;
            for (uint32_t i = 0; i < pts[k].count && ms[k].override_count < METHOD_MAX_OVERRIDES;
                 i++) {
                uint32_t j = ms[k].override_count++;
                snprintf(ms[k].override_names[j], sizeof(ms[k].override_names[j]), "%s",
                         pts[k].names[i]);
                ms[k].override_name[j] = ms[k].override_names[j];
                ms[k].override_value[j] = pts[k].values[i];
            }
            xrad_scene *scene = NULL;
            printf("[%u/%u] %s\n", k + 1, n, pts[k].label);
            fflush(stdout);
            const bench_reference *el_ref = &ref;
            const char *note = NULL;
            if (!(st = method_load_scene(path, &ms[k], &scene, err)) &&
                !bench_reference_fits(&ref, scene)) {
                note = "at this point's element layout";
                uint32_t l = 0;
                while (l < nlayouts && !bench_reference_fits(&layouts[l], scene))
                    l++;
                if (l == nlayouts && nlayouts < SWEEP_MAX_LAYOUTS &&
                    !(st = bench_reference_get(ctx, path, scene, o, t_ref, &layouts[l], err)))
                    nlayouts++;
                /* More layouts than kept: the element figures are NaN. */
                el_ref = l < nlayouts ? &layouts[l] : &ref;
                if (l == nlayouts)
                    note = "none of this point's element layout (too many layouts)";
            }
            if (!st)
                st = bench_one(ctx, path, scene, m, &ms[k], o, &ref, el_ref, note, rows,
                               &res[k], err);
            xrad_scene_destroy(&scene);
        }
        char stem[1024], name[256];
        snprintf(stem, sizeof(stem), "%s/%s-%s", o->sweep_out,
                 cli_basename_noext(path, name, sizeof(name)), m);
        if (!st)
            st = write_outputs(stem, path, m, o, ctx, pts, res, ms, n, err);
    }
done:
    cJSON_Delete(rows);
    free(ms);
    free(res);
    free(pts);
    bench_reference_free(&ref);
    for (uint32_t l = 0; l < nlayouts; l++)
        bench_reference_free(&layouts[l]);
    return st;
}
