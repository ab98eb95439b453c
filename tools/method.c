#include "method.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* The option's value as an index into names[0..count-1]; a usage error
 * listing them when it is none. */
static bool pick_name(cli_args *a, const char *const *names, int count, int *out)
{
    const char *v = cli_value(a);
    if (!v)
        return false;
    for (int k = 0; k < count; k++) {
        if (!strcmp(v, names[k])) {
            *out = k;
            return true;
        }
    }
    char list[96] = "";
    for (int k = 0; k < count; k++)
        snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s%s", k ? ", " : "",
                 names[k]);
    cli_usage_error(a->command, "--%s: '%s' is none of %s", a->opt, v, list);
    a->failed = true;
    return false;
}

bool method_visibility_option(cli_args *a, xrad_visibility *out)
{
    static const char *const names[] = {"auto", "clip", "rays"};
    int k;
    if (!pick_name(a, names, 3, &k))
        return false;
    *out = (xrad_visibility)k;
    return true;
}

const char *method_visibility_name(xrad_visibility v)
{
    return v == XRAD_VISIBILITY_CLIP ? "clip" : v == XRAD_VISIBILITY_RAYS ? "rays" : "auto";
}

bool method_tonemap_option(cli_args *a, xrad_tonemap *out)
{
    static const char *const names[] = {"exposure", "reinhard"};
    int k;
    if (!pick_name(a, names, 2, &k))
        return false;
    *out = (xrad_tonemap)k;
    return true;
}

bool method_reference_solver_option(cli_args *a, xrad_reference_solver *out)
{
    static const char *const names[] = {"auto", "dense", "gather"};
    int k;
    if (!pick_name(a, names, 3, &k))
        return false;
    *out = (xrad_reference_solver)k;
    return true;
}

const char *method_reference_solver_name(xrad_reference_solver s)
{
    return s == XRAD_REFERENCE_SOLVER_DENSE    ? "dense"
           : s == XRAD_REFERENCE_SOLVER_GATHER ? "gather"
                                               : "auto";
}

const char *method_list(void) { return "reference, gather, progressive, incremental, cross"; }

int method_known(const char *name)
{
    return !strcmp(name, "reference") || xrad_method_from_name(name) != 0;
}

xrad_status method_open(xrad_context *ctx, const xrad_scene *scene, const char *name,
                        const method_settings *settings, method_run_state *run,
                        xrad_error *err)
{
    memset(run, 0, sizeof(*run));
    run->ctx = ctx;
    run->scene = scene;
    run->name = name;
    run->settings = *settings;
    if (!strcmp(name, "reference"))
        return XRAD_OK;
    xrad_solver_desc desc = settings->solver;
    desc.method = xrad_method_from_name(name);
    return xrad_solver_create(ctx, scene, &desc, &run->solver, err);
}

xrad_status method_frame(method_run_state *run, double t, xrad_atlas *atlas,
                         method_result *result, xrad_error *err)
{
    memset(result, 0, sizeof(*result));
    double t0 = cli_now();
    xrad_status st;
    if (!run->solver) {
        xrad_reference_desc d = run->settings.reference;
        d.time = t;
        st = xrad_reference_solve(run->scene, &d, atlas, &result->ref, err);
        result->wall_ms = (cli_now() - t0) * 1e3;
    } else {
        /* The first frame solves (there is no solution to advance yet). */
        st = xrad_solver_advance(run->solver, t, err);
        result->wall_ms = (cli_now() - t0) * 1e3;
        if (!st)
            st = xrad_solver_read(run->solver, atlas, err);
        result->gpu = 1;
        xrad_solver_get_stats(run->solver, &result->stats);
    }
    if (!st)
        run->frames++;
    return st;
}

void method_close(method_run_state *run)
{
    xrad_solver_destroy(&run->solver);
    memset(run, 0, sizeof(*run));
}

xrad_status method_run(xrad_context *ctx, const xrad_scene *scene, const char *name,
                       const method_settings *settings, xrad_atlas *atlas,
                       method_result *result, xrad_error *err)
{
    method_run_state run;
    memset(result, 0, sizeof(*result));
    xrad_status st = method_open(ctx, scene, name, settings, &run, err);
    if (!st)
        st = method_frame(&run, run.solver ? settings->solver.time : settings->reference.time,
                          atlas, result, err);
    method_close(&run);
    return st;
}

/* `text` from column 24, wrapped before column 80. */
static void print_wrapped(const char *text)
{
    const int indent = 24, width = 79;
    int col = indent;
    while (*text) {
        int word = (int)strcspn(text, " ");
        if (col > indent && col + 1 + word > width) {
            printf("\n%*s", indent, "");
            col = indent;
        } else if (col > indent) {
            putchar(' ');
            col++;
        }
        printf("%.*s", word, text);
        col += word;
        text += word;
        text += strspn(text, " ");
    }
    putchar('\n');
}

void method_print_options(void)
{
    printf("  --preset NAME         quality preset: %s; the\n"
           "                        scene file's \"quality\" applies first, these options\n"
           "                        after (README \"Quality\")\n",
           xrad_quality_preset_list());
    for (uint32_t i = 0; i < xrad_setting_count(); i++) {
        const xrad_setting_info *in = xrad_setting_get(i);
        char opt[64], def[32], text[512];
        snprintf(opt, sizeof(opt), "--%s %s", in->name,
                 in->kind == XRAD_SETTING_CHOICE ? "C" : in->kind == XRAD_SETTING_REAL ? "X" : "N");
        for (char *c = opt; *c && *c != ' '; c++)
            *c = *c == '_' ? '-' : *c;
        xrad_quality q = {0};
        xrad_quality_format(&q, in->name, def, sizeof(def), NULL);
        if (in->kind == XRAD_SETTING_CHOICE)
            snprintf(text, sizeof(text), "%s: %s [%s]", in->description, in->choices, def);
        else if (in->min_open)
            snprintf(text, sizeof(text), "%s; (%g, %g] [%s]", in->description, in->min,
                     in->max, def);
        else
            snprintf(text, sizeof(text), "%s; %g .. %g [%s]", in->description, in->min,
                     in->max, def);
        printf("  %-21s ", opt);
        print_wrapped(text);
    }
    printf("  --camera NAME         a model file's (.gltf, .glb) camera by name [its first]\n"
           "  --bounces N           gather: fixed bounce count [0 = until --threshold]\n"
           "  --seed N              GPU: hemicube rotation seed [0]\n"
           "  --back-nearest        cross: nearest back hemicube samples (default bilinear)\n"
           "  --slice N             cross: elements per submission of the cross projection\n"
           "                        [0 = all]\n");
}

/* "hemicube-res" -> "hemicube_res" when that is a setting. */
static const char *setting_name(const char *opt, char *buf, size_t n)
{
    snprintf(buf, n, "%s", opt);
    for (char *c = buf; *c; c++)
        *c = *c == '-' ? '_' : *c;
    for (uint32_t i = 0; i < xrad_setting_count(); i++)
        if (!strcmp(xrad_setting_get(i)->name, buf))
            return buf;
    return NULL;
}

int method_solver_option(cli_args *a, const char *opt, method_settings *m)
{
    xrad_solver_desc *d = &m->solver;
    char name[48];
    if (!strcmp(opt, "preset")) {
        m->preset = cli_value(a);
    } else if (!strcmp(opt, "camera")) {
        m->camera = cli_value(a);
    } else if (setting_name(opt, name, sizeof(name))) {
        const char *v = cli_value(a);
        if (!v)
            return 1;
        if (m->override_count == METHOD_MAX_OVERRIDES) {
            cli_usage_error(a->command, "more than %d quality options", METHOD_MAX_OVERRIDES);
            a->failed = true;
            return 1;
        }
        /* Checked here, so that a bad value is an argument error now. */
        xrad_quality scratch = {0};
        xrad_error err;
        if (xrad_quality_set(&scratch, name, v, &err)) {
            cli_usage_error(a->command, "--%s: %s", opt, err.message);
            a->failed = true;
            return 1;
        }
        uint32_t k = m->override_count++;
        snprintf(m->override_names[k], sizeof(m->override_names[k]), "%s", name);
        m->override_name[k] = m->override_names[k];
        m->override_value[k] = v;
    } else if (!strcmp(opt, "bounces")) {
        cli_uint(a, 0, 100000, &d->bounces);
    } else if (!strcmp(opt, "seed")) {
        cli_uint(a, 0, UINT32_MAX, &d->seed);
    } else if (!strcmp(opt, "back-nearest")) {
        d->back_nearest = 1;
    } else if (!strcmp(opt, "slice")) {
        cli_uint(a, 0, UINT32_MAX, &d->slice_elements);
    } else {
        return 0;
    }
    return 1;
}

/* The command line's quality over q: --preset, then the overrides. */
static xrad_status command_line_quality(const method_settings *m, xrad_quality *q,
                                        xrad_error *err)
{
    xrad_status st = m->preset ? xrad_quality_preset(q, m->preset, err) : XRAD_OK;
    if (st) {
        char msg[sizeof(err->message)];
        snprintf(msg, sizeof(msg), "--preset: %s", err->message);
        snprintf(err->message, sizeof(err->message), "%s", msg);
    }
    for (uint32_t k = 0; !st && k < m->override_count; k++)
        st = xrad_quality_set(q, m->override_name[k], m->override_value[k], err);
    return st;
}

xrad_status method_load_scene(const char *path, method_settings *m, xrad_scene **out,
                              xrad_error *err)
{
    *out = NULL;
    /* The density is the scene's at load: only the command line's is
     * passed, the file's own quality.density_scale the parser applies. */
    xrad_quality cli = {0};
    xrad_status st = command_line_quality(m, &cli, err);
    if (st)
        return st;
    xrad_scene_load_desc ld = {
        .density_scale = cli.density_scale, .adaptive = cli.adaptive, .camera = m->camera};
    if ((st = xrad_scene_load_with(path, &ld, out, err)))
        return st;
    /* What the file has that xrad leaves out, never silently. */
    for (uint32_t k = 0; k < xrad_scene_warning_count(*out); k++)
        fprintf(stderr, "xrad: warning: %s\n", xrad_scene_warning(*out, k));
    xrad_quality q = {.solver = m->solver};
    xrad_scene_get_quality(*out, &q);
    if (!(st = command_line_quality(m, &q, err)) && !(st = xrad_quality_resolve(&q, err))) {
        m->resolved = q;
        /* Only the quality fields come from q; the rest stays m's. */
        xrad_quality into = {.solver = m->solver};
        for (uint32_t i = 0; !st && i < xrad_setting_count(); i++) {
            char v[64];
            const char *name = xrad_setting_get(i)->name;
            if (!(st = xrad_quality_format(&q, name, v, sizeof(v), err)))
                st = xrad_quality_set(&into, name, v, err);
        }
        m->solver = into.solver;
    }
    if (st)
        xrad_scene_destroy(out);
    return st;
}

void method_print_passes(const method_result *r, const char *what)
{
    if (!r->gpu)
        return;
    const xrad_solver_stats *s = &r->stats;
    printf("gpu passes of %s (timestamp queries, hemicube path %s):\n", what,
           s->hemicube_path ? s->hemicube_path : "-");
    for (uint32_t i = 0; i < s->pass_count; i++)
        printf("  %-14s %10.2f ms  (%u)\n", s->passes[i].name, s->passes[i].ms,
               s->passes[i].count);
    printf("  %-14s %10.2f ms\n", "total", s->gpu_ms);
    printf("hemicubes %u, shots %u, iterations %u, submissions %u, host waits %u, "
           "residual %.3g\n",
           s->hemicubes, s->shots, s->iterations, s->submissions, s->host_waits, s->residual);
    if (s->surfaces_shot)
        printf("surfaces shot %u, unshot at the stop %.3g of the emitted power\n",
               s->surfaces_shot, s->unshot);
    if (s->redistribute_ms > 0)
        printf("redistribution %.1f ms of %.1f ms (host wall time)\n", s->redistribute_ms,
               s->wall_ms);
    if (s->cross_pairs)
        printf("cross projection: %llu (element, patch) pairs listed and traced, %llu left to "
               "loops (the list was full)\n",
               (unsigned long long)s->cross_pairs, (unsigned long long)s->cross_pairs_unlisted);
    if (s->cross_rescaled)
        printf("cross: %u redistributions made again at a new hemicube scale\n",
               s->cross_rescaled);
}

int method_surface_emits(const xrad_scene *scene, uint32_t index)
{
    xrad_surface_info s;
    xrad_material_info m;
    if (xrad_scene_get_surface(scene, index, &s, NULL) ||
        xrad_scene_get_material(scene, s.material, &m, NULL))
        return 0;
    return m.emission[0] > 0 || m.emission[1] > 0 || m.emission[2] > 0;
}

xrad_status method_emitter_mask(xrad_context *ctx, const xrad_scene *scene,
                                const xrad_view_desc *view, float **mask, xrad_error *err)
{
    *mask = NULL;
    xrad_atlas atlas = {0};
    xrad_status st = xrad_atlas_create(scene, &atlas, err);
    if (st)
        return st;
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    /* Every texel of an emitter's tile is one of its elements. */
    for (uint32_t i = 0; i < info.surfaces; i++) {
        xrad_surface_info sf;
        if (!method_surface_emits(scene, i) || xrad_scene_get_surface(scene, i, &sf, NULL))
            continue;
        for (uint32_t y = sf.tile_y; y < sf.tile_y + sf.nv; y++)
            for (uint32_t x = sf.tile_x; x < sf.tile_x + sf.nu; x++) {
                float *t = atlas.rgba + ((size_t)y * atlas.width + x) * 4;
                t[0] = t[1] = t[2] = t[3] = 1;
            }
    }
    float *img = NULL;
    uint32_t w = 0, h = 0;
    st = xrad_render_view(ctx, scene, &atlas, view, &img, &w, &h, err);
    xrad_atlas_destroy(&atlas);
    if (st)
        return st;
    /* One float per pixel, in place: pixel i's R is read before it is
     * overwritten (i <= 4 i). */
    for (size_t i = 0; i < (size_t)w * h; i++)
        img[i] = img[i * 4];
    *mask = img;
    return XRAD_OK;
}

xrad_status method_read_image(const char *path, method_image *img, xrad_error *err)
{
    memset(img, 0, sizeof(*img));
    if (cli_has_ext(path, ".png"))
        return xrad_image_read_png(path, &img->rgba, &img->width, &img->height, err);
    xrad_status st = xrad_image_read_exr(path, &img->rgba, &img->width, &img->height, err);
    float *alpha = NULL;
    uint32_t w = 0, h = 0;
    if (!st)
        st = xrad_image_read_exr_channel(path, "A", &alpha, &w, &h, err);
    if (!st)
        st = xrad_image_read_exr_channel(path, "emitter", &img->emitter, &w, &h, err);
    /* Coverage: xrad_image_read_exr leaves alpha 1; the file's own marks
     * the background (xrad_image_compare never counts it). */
    if (!st && alpha)
        for (size_t i = 0; i < (size_t)w * h; i++)
            img->rgba[i * 4 + 3] = alpha[i];
    free(alpha);
    if (st)
        method_image_free(img);
    return st;
}

void method_image_free(method_image *img)
{
    free(img->rgba);
    free(img->emitter);
    memset(img, 0, sizeof(*img));
}

void method_surface_label(const xrad_scene *scene, uint32_t index, char *buf, size_t n)
{
    xrad_surface_info s;
    if (xrad_scene_get_surface(scene, index, &s, NULL)) {
        snprintf(buf, n, "#%u", index);
        return;
    }
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    bool unique = true;
    for (uint32_t i = 0; i < info.surfaces && unique; i++) {
        xrad_surface_info o;
        if (i != index && !xrad_scene_get_surface(scene, i, &o, NULL))
            unique = strcmp(o.name, s.name) != 0;
    }
    xrad_object_info obj;
    if (unique || xrad_scene_get_object(scene, s.object, &obj, NULL))
        snprintf(buf, n, "%s", s.name);
    else
        snprintf(buf, n, "%s/%s", obj.name, s.name);
}
