/* xrad render SCENE: solve the radiosity of a scene and write the camera's
 * view as linear EXR and/or tone-mapped PNG. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "method.h"

static void help(void)
{
    printf("usage: xrad render SCENE.json [options]\n\n"
           "Solves the scene and writes the image seen by its camera.\n\n"
           "  --method NAME     reference: CPU ground truth (analytic form factors,\n"
           "                    exact visibility by clipping, Gauss-Seidel);\n"
           "                    gather: GPU radiosity hemicube per element per bounce (thesis 4.2);\n"
           "                    progressive: GPU progressive refinement (thesis 4.3);\n"
           "                    incremental: GPU incremental radiosity (thesis 4.4);\n"
           "                    cross: GPU cross redistribution radiosity (thesis 4.5)\n"
           "                    [default: reference]\n"
           "  --out FILE        output image; .png (tone-mapped sRGB) or .exr (linear)\n"
           "  --png FILE        write a PNG here (may be given with --exr)\n"
           "  --exr FILE        write an EXR here: R, G, B, A (0 where no surface is) and\n"
           "                    \"emitter\" (non-zero where the pixel shows an emitting surface)\n"
           "                    [default: out/<scene>-<method>.png and .exr]\n"
           "  --atlas FILE.exr  also write the element solution: the scene's atlas, one texel\n"
           "                    per element, RGBA float (for xrad compare --scene)\n"
           "  --width N, --height N   image size [default: the scene camera's]\n"
           "  --time T          seconds of scene animation to pose dynamic objects [0]\n"
           "  --exposure E      PNG scale factor; 0 = auto: the 95th percentile luminance\n"
           "                    -> 0.8, with reinhard the log-average -> 0.18 [0]\n"
           "  --tonemap T       PNG tone mapping: exposure (exposure x B, clamped), reinhard\n"
           "                    (Reinhard 2002's global operator, C / (1 + L)) [exposure]\n"
           "  --frames N        advance N frames of the scene's animation after the first\n"
           "                    and write the last [0]\n"
           "  --fps F           frames per second of scene time [30]\n"
           "  --frame-out DIR   also write every frame as DIR/frame-NNNN.png\n"
           "  --nearest         show elements as flat squares (no interpolation)\n"
           "  --check           GPU methods: also solve the CPU reference at the last\n"
           "                    frame's pose and print the error against it (README\n"
           "                    \"Accuracy\": surface_error, element p50/p95, mean ratio)\n"
           "  --visibility V    reference: clip (exact polygon clipping), rays (every pair\n"
           "                    by --rays rays through an Embree BVH: meshes), auto (clip up\n"
           "                    to 256 surfaces) [auto]\n"
           "  --rays N          reference: rays per element pair where clipping gives up\n"
           "                    [16]; with rays visibility, per pair [64]\n"
           "  --reference-solver S  reference: dense (every form factor in a matrix), gather\n"
           "                    (no matrix: lights by form factor and rays, the rest by\n"
           "                    --gather-rays Monte Carlo rays per element; meshes of 100K\n"
           "                    triangles), auto (dense up to about 23,000 elements) [auto]\n"
           "  --gather-rays N   reference, gather: rays per element [256]\n"
           "  --cell-points N   reference, dense solver: an element's form factors are their\n"
           "                    mean over N x N points of its cell, its radiosity the cell's\n"
           "                    mean, as conservation gives the shooting methods [1: the\n"
           "                    cell's centre]\n"
           "  --residual R      reference: Gauss-Seidel stop, max|dB|/max B per sweep [1e-6]\n"
           "  --threads N       reference: worker threads [online cores]\n"
           "  --device NAME     Vulkan device (substring; see xrad devices)\n"
           "  --quiet           no progress on stderr\n");
    method_print_options();
    printf("\nThe EXR holds the radiosity B (W/m^2) of the surface seen in each pixel;\n"
           "xrad compare leaves out the pixels its emitter channel marks.\n");
}

typedef struct render_opts {
    const char *scene, *method, *png, *exr, *atlas, *device;
    uint32_t width, height;
    double time, exposure, fps;
    xrad_tonemap tonemap;
    uint32_t frames;
    const char *frame_out;
    int nearest, quiet, check;
    method_settings m;
} render_opts;

static void progress(void *user, const char *stage, double fraction)
{
    (void)user;
    fprintf(stderr, "\r  %-18s %5.1f%%", stage, 100.0 * fraction);
    if (fraction >= 1.0)
        fputc('\n', stderr);
    fflush(stderr);
}

static int parse(int argc, char **argv, render_opts *o)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *opt;
    o->method = "reference";
    o->fps = 30;
    while ((opt = cli_next(&a)) && !a.failed) {
        if (cli_is_help(opt)) {
            help();
            return -1;
        } else if (!strcmp(opt, "method")) {
            o->method = cli_value(&a);
        } else if (!strcmp(opt, "out")) {
            const char *v = cli_value(&a);
            if (v && cli_has_ext(v, ".png"))
                o->png = v;
            else if (v && cli_has_ext(v, ".exr"))
                o->exr = v;
            else if (v)
                a.failed = cli_usage_error("render", "--out %s: the extension must be .png or .exr", v);
        } else if (!strcmp(opt, "png")) {
            o->png = cli_value(&a);
        } else if (!strcmp(opt, "exr")) {
            o->exr = cli_value(&a);
        } else if (!strcmp(opt, "atlas")) {
            o->atlas = cli_value(&a);
            if (o->atlas && !cli_has_ext(o->atlas, ".exr"))
                a.failed = cli_usage_error("render", "--atlas %s: the extension must be .exr",
                                           o->atlas);
        } else if (!strcmp(opt, "width")) {
            cli_uint(&a, 1, 16384, &o->width);
        } else if (!strcmp(opt, "height")) {
            cli_uint(&a, 1, 16384, &o->height);
        } else if (!strcmp(opt, "time")) {
            cli_double(&a, -1e9, 1e9, &o->time);
        } else if (!strcmp(opt, "frames")) {
            cli_uint(&a, 0, 1000000, &o->frames);
        } else if (!strcmp(opt, "fps")) {
            cli_double(&a, 1e-3, 1e6, &o->fps);
        } else if (!strcmp(opt, "frame-out")) {
            o->frame_out = cli_value(&a);
        } else if (!strcmp(opt, "exposure")) {
            cli_double(&a, 0, 1e30, &o->exposure);
        } else if (!strcmp(opt, "tonemap")) {
            method_tonemap_option(&a, &o->tonemap);
        } else if (!strcmp(opt, "nearest")) {
            o->nearest = 1;
        } else if (!strcmp(opt, "rays")) {
            cli_uint(&a, 1, 4096, &o->m.reference.rays);
        } else if (!strcmp(opt, "visibility")) {
            method_visibility_option(&a, &o->m.reference.visibility);
        } else if (!strcmp(opt, "reference-solver")) {
            method_reference_solver_option(&a, &o->m.reference.solver);
        } else if (!strcmp(opt, "gather-rays")) {
            cli_uint(&a, 1, 65536, &o->m.reference.gather_rays);
        } else if (!strcmp(opt, "cell-points")) {
            cli_uint(&a, 1, 8, &o->m.reference.cell_points);
        } else if (!strcmp(opt, "residual")) {
            cli_double(&a, 1e-15, 1, &o->m.reference.residual);
        } else if (!strcmp(opt, "threads")) {
            cli_uint(&a, 1, 1024, &o->m.reference.threads);
        } else if (method_solver_option(&a, opt, &o->m)) {
            continue;
        } else if (!strcmp(opt, "device")) {
            o->device = cli_value(&a);
        } else if (!strcmp(opt, "quiet")) {
            o->quiet = 1;
        } else if (!strcmp(opt, "check")) {
            o->check = 1;
        } else {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 1)
        return cli_usage_error("render", "needs one scene file (see xrad render --help)");
    o->scene = a.positional[0];
    if (!method_known(o->method))
        return cli_usage_error("render", "--method %s: unknown method (available: %s)",
                               o->method, method_list());
    return 0;
}

/* --check: the CPU reference at time t, and the GPU solution's error
 * against it per surface and per element (xrad_atlas_compare). */
static xrad_status check_reference(const render_opts *o, const xrad_scene *scene,
                                   const xrad_atlas *got, double t, xrad_error *err)
{
    xrad_atlas ref = {0};
    xrad_reference_desc d = o->m.reference;
    d.time = t;
    if (!o->quiet)
        d.progress = progress;
    xrad_reference_stats rr;
    double t0 = cli_now();
    xrad_element_metrics m;
    xrad_status st = xrad_atlas_create(scene, &ref, err);
    if (!st && !(st = xrad_reference_solve(scene, &d, &ref, &rr, err)) &&
        !(st = xrad_atlas_compare(scene, got, &ref, &m, NULL, err))) {
        char worst[256];
        method_surface_label(scene, m.worst_surface, worst, sizeof(worst));
        printf("against the CPU reference at t = %.3f s (%.1f s): surface_error %.4f (%s, "
               "ratio %.4f), element p50 %.4f, p95 %.4f, mean ratio %.4f\n",
               t, cli_now() - t0, m.surface_error, worst, m.worst_ratio, m.p50, m.p95,
               m.mean_ratio);
    }
    xrad_atlas_destroy(&ref);
    return st;
}

int cmd_render(int argc, char **argv)
{
    render_opts o = {0};
    int rc = parse(argc, argv, &o);
    if (rc)
        return rc < 0 ? 0 : rc;

    char name[256], png_default[600], exr_default[600];
    if (!o.png && !o.exr) {
        cli_basename_noext(o.scene, name, sizeof(name));
        snprintf(png_default, sizeof(png_default), "out/%s-%s.png", name, o.method);
        snprintf(exr_default, sizeof(exr_default), "out/%s-%s.exr", name, o.method);
        o.png = png_default;
        o.exr = exr_default;
    }

    xrad_error err = {0};
    /* Outputs that cannot be written are said before the solve, not after. */
    char first_frame[1024] = "";
    if (o.frame_out)
        snprintf(first_frame, sizeof(first_frame), "%s/frame-0000.png", o.frame_out);
    const char *outputs[] = {o.exr, o.png, o.atlas, o.frame_out ? first_frame : NULL};
    for (size_t k = 0; k < sizeof(outputs) / sizeof(outputs[0]); k++)
        if (outputs[k] && cli_check_writable(outputs[k], &err))
            return cli_report(&err);
    xrad_scene *scene = NULL;
    xrad_context *ctx = NULL;
    xrad_atlas atlas = {0};
    float *image = NULL, *emitter = NULL;
    method_run_state run = {0};
    double t0 = cli_now();
    if (method_load_scene(o.scene, &o.m, &scene, &err))
        return cli_report(&err);
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    double t_load = cli_now();

    /* The device first: a missing GPU is reported before a long solve. */
    if (cli_context_create((xrad_context_desc){.device = o.device}, &ctx, &err) ||
        xrad_atlas_create(scene, &atlas, &err))
        goto fail;
    double t_ctx = cli_now();

    if (!o.quiet) {
        fprintf(stderr, "xrad: %s: %u elements (%u static, %u dynamic), method %s, device %s\n",
                o.scene, info.elements, info.static_elements, info.dynamic_elements, o.method,
                xrad_context_device_name(ctx));
        o.m.reference.progress = progress;
        o.m.solver.progress = progress;
    }
    /* Frame 0 at --time, converged; then --frames more, 1/--fps apart:
     * incremental and cross redistribute from the previous frame (thesis
     * 4.4, 4.5), gather, progressive and the reference solve every frame
     * anew (thesis 5.2). The last frame is the image written. */
    method_result res;
    uint32_t w = 0, h = 0;
    double t_solve = 0, t_display = 0, exposure = o.exposure, frame_ms = 0;
    xrad_view_desc view = {0};
    o.m.reference.time = o.time;
    o.m.solver.time = o.time;
    if (method_open(ctx, scene, o.method, &o.m, &run, &err))
        goto fail;
    for (uint32_t f = 0; f <= o.frames; f++) {
        double t = o.time + (double)f / o.fps;
        double tf0 = cli_now();
        if (method_frame(&run, t, &atlas, &res, &err))
            goto fail;
        t_solve = cli_now();
        if (f > 0)
            frame_ms += (t_solve - tf0) * 1e3;
        if (f == 0 && !o.quiet && res.gpu && res.stats.cross_patches)
            fprintf(stderr,
                    "xrad: cross: %u patches on the dynamic objects, %u on the lights (an "
                    "object's cross_density sets its own; xrad info --method cross)\n",
                    res.stats.cross_patches, res.stats.cross_light_patches);
        free(image);
        image = NULL;
        view = (xrad_view_desc){.width = o.width, .height = o.height, .time = t,
                                .nearest = o.nearest};
        if (xrad_render_view(ctx, scene, &atlas, &view, &image, &w, &h, &err))
            goto fail;
        t_display = cli_now();
        /* One exposure for all frames, so that they compare. */
        if (!(exposure > 0))
            exposure = xrad_image_tonemap_exposure(o.tonemap, image, w, h);
        if (o.frame_out) {
            char path[1024];
            snprintf(path, sizeof(path), "%s/frame-%04u.png", o.frame_out, f);
            if (!cli_make_parent_dirs(path)) {
                cli_fail(&err, XRAD_ERROR_SYSTEM, "%s: cannot create its directory", path);
                goto fail;
            }
            if (xrad_image_write_png_tonemapped(path, image, w, h, o.tonemap, exposure, &err))
                goto fail;
        }
        if (o.frames && !o.quiet)
            fprintf(stderr, "\r  frame %u/%u (t = %.3f s)", f, o.frames, t);
    }
    if (o.frames && !o.quiet)
        fputc('\n', stderr);
    if (o.frames)
        printf("frames: %u after the first, %.1f ms per frame (solve only), %s\n", o.frames,
               frame_ms / o.frames, o.frame_out ? o.frame_out : "last frame written below");

    /* The last frame's view again, of where the emitters are: the mask
     * xrad compare leaves out of its figures (README "Accuracy"). */
    if (o.exr && method_emitter_mask(ctx, scene, &view, &emitter, &err))
        goto fail;
    for (int k = 0; k < 3; k++) {
        const char *path = k == 0 ? o.exr : k == 1 ? o.png : o.atlas;
        if (!path)
            continue;
        if (!cli_make_parent_dirs(path)) {
            cli_fail(&err, XRAD_ERROR_SYSTEM, "%s: cannot create its directory", path);
            goto fail;
        }
        xrad_status st =
            k == 0   ? xrad_image_write_exr_channel(path, image, "emitter", emitter, w, h, &err)
            : k == 1 ? xrad_image_write_png_tonemapped(path, image, w, h, o.tonemap, exposure, &err)
                     : xrad_image_write_exr(path, atlas.rgba, atlas.width, atlas.height, &err);
        if (st)
            goto fail;
        if (k == 2)
            printf("wrote %s (element atlas %ux%u, %u elements)\n", path, atlas.width,
                   atlas.height, info.elements);
        else
            printf("wrote %s (%ux%u)\n", path, w, h);
    }
    if (res.gpu) {
        method_print_passes(&res, o.frames ? "the last frame" : "the solve");
        if (o.check && check_reference(&o, scene, &atlas, view.time, &err))
            goto fail;
    } else if (res.ref.solver == XRAD_REFERENCE_SOLVER_GATHER)
        printf("reference: gather (%u rays an element, lights by %u rays), rays %.3f s, "
               "Gauss-Seidel %.3f s, %u sweeps, residual %.2g\n",
               res.ref.gather_rays, res.ref.rays, res.ref.form_factor_seconds,
               res.ref.solve_seconds, res.ref.sweeps, res.ref.residual);
    else
        printf("reference: visibility %s (%u rays%s), form factors %.3f s, Gauss-Seidel %.3f s, "
               "%u sweeps, residual %.2g\n",
               method_visibility_name(res.ref.visibility), res.ref.rays,
               res.ref.visibility == XRAD_VISIBILITY_RAYS ? " a pair" : " where clipping gives up",
               res.ref.form_factor_seconds, res.ref.solve_seconds, res.ref.sweeps,
               res.ref.residual);
    printf("time: load %.3f s, device %.3f s, solve %.3f s, display %.3f s, total %.3f s\n",
           t_load - t0, t_ctx - t_load, t_solve - t_ctx, t_display - t_solve, cli_now() - t0);
    rc = 0;
    goto done;

fail:
    rc = cli_report(&err);
done:
    method_close(&run);
    free(image);
    free(emitter);
    xrad_atlas_destroy(&atlas);
    xrad_context_destroy(&ctx);
    xrad_scene_destroy(&scene);
    return rc;
}
