/* xrad compare A B: the error of image A against the reference B, as the
 * thesis's NRMSE (table 5.1) and as the figures of README "Accuracy" (mean
 * ratio and relative RMS over pixels that show a non-emitting surface);
 * with --scene, the element-space figures of two solutions of one scene
 * (atlases written by xrad render --atlas). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "method.h"

static void help(void)
{
    printf("usage: xrad compare A.exr|A.png B.exr|B.png [--diff FILE.exr|FILE.png]\n"
           "       xrad compare --scene SCENE.json A.exr B.exr [--surfaces] [--elements FILE.csv]\n\n"
           "B is the reference. Images (EXR or PNG; PNG values are compared linear, sRGB\n"
           "decoded, so compare PNGs of one exposure) print, in this order:\n"
           "  nrmse <v>       RMS over all pixels and RGB channels of (A - B), divided by\n"
           "                  (max - min) of B's RGB values (the thesis's figure; a light in\n"
           "                  view makes it small whatever the rest does)\n"
           "  mean_ratio <v>  sum of A / sum of B over the counted pixels, R + G + B\n"
           "  rel_rms <v>     RMS of (A - B) over the counted pixels and RGB, divided by\n"
           "                  the mean of B there\n"
           "  pixels <n>      counted: covered in B (its alpha > 0) and not showing an\n"
           "                  emitter by the mask\n"
           "  mask <source>   the emitter mask used: B's \"emitter\" channel (xrad render\n"
           "                  writes it), else A's, else none: an EXR without one (written\n"
           "                  before it existed, or a PNG) counts every covered pixel\n\n"
           "With --scene, A and B are element atlases of SCENE (xrad render --atlas) and\n"
           "it prints the element-space figures (emitting surfaces not counted):\n"
           "  surface_error <v> (<surface>, ratio <r>)   max over surfaces of |ratio - 1|,\n"
           "                  ratio = 1 + (mean A - mean B) / max(mean B, 1e-3 x the\n"
           "                  scene's mean B), area-weighted means of R + G + B\n"
           "  element_p50, element_p95, element_max <v>   percentiles by count of\n"
           "                  |A - B| / max(B, 1e-3 x the scene's mean B) per element\n"
           "  element_mean_ratio <v>   area-weighted sum of A / sum of B\n"
           "  elements <n>, surfaces <n>   counted\n\n"
           "  --diff FILE        also write |A - B| per channel (EXR linear, PNG auto-exposed)\n"
           "  --scene SCENE      compare element atlases of this scene\n"
           "  --surfaces         with --scene: one line per surface, 'surface <name> ratio <r>'\n"
           "  --elements FILE    with --scene: write every counted element as CSV, worst\n"
           "                     first: surface, i, j, x, y, z (its sample in object space,\n"
           "                     m), a, b (R + G + B), rel (as element_p95 ranks it)\n"
           "  --preset NAME, --density-scale X   with --scene: as given to xrad render, when\n"
           "                     they changed the element layout\n"
           "\nExit status 1 for unreadable files or sizes that do not match (both named).\n");
}

typedef struct compare_opts {
    const char *a, *b, *diff, *scene, *elements;
    int surfaces;
    method_settings m;
} compare_opts;

static int compare_images(const compare_opts *o)
{
    xrad_error err = {0};
    method_image img[2] = {{0}};
    const char *path[2] = {o->a, o->b};
    int rc = 0;
    for (int i = 0; i < 2 && rc == 0; i++)
        if (method_read_image(path[i], &img[i], &err))
            rc = cli_report(&err);
    if (rc == 0 && (img[0].width != img[1].width || img[0].height != img[1].height)) {
        fprintf(stderr, "xrad compare: %s is %ux%u but %s is %ux%u\n", o->a, img[0].width,
                img[0].height, o->b, img[1].width, img[1].height);
        rc = 1;
    }
    uint32_t w = img[0].width, h = img[0].height;
    if (rc == 0) {
        double e = xrad_image_nrmse(img[0].rgba, img[1].rgba, w, h);
        if (e < 0) {
            fprintf(stderr, "xrad compare: %s is constant; NRMSE is undefined\n", o->b);
            rc = 1;
        } else {
            printf("nrmse %.7f\n", e);
        }
    }
    if (rc == 0) {
        /* The reference's mask first: it says what the reference shows. */
        const char *mask_from = img[1].emitter ? o->b : img[0].emitter ? o->a : NULL;
        const float *mask = img[1].emitter ? img[1].emitter : img[0].emitter;
        xrad_image_metrics m;
        if (xrad_image_compare(img[0].rgba, img[1].rgba, mask, w, h, &m, &err)) {
            fprintf(stderr, "xrad compare: %s against %s: %s\n", o->a, o->b, err.message);
            rc = 1;
        } else {
            printf("mean_ratio %.7f\nrel_rms %.7f\npixels %llu\n", m.mean_ratio, m.rel_rms,
                   (unsigned long long)m.pixels);
            if (mask_from)
                printf("mask %s\n", mask_from);
            else
                printf("mask none (no emitter channel: every covered pixel counted)\n");
        }
    }
    if (rc == 0 && o->diff) {
        size_t n = (size_t)w * h * 4;
        for (size_t i = 0; i < n; i++)
            img[0].rgba[i] = (i % 4 == 3) ? 1.0f : fabsf(img[0].rgba[i] - img[1].rgba[i]);
        xrad_status st = cli_has_ext(o->diff, ".png")
                             ? xrad_image_write_png(o->diff, img[0].rgba, w, h, 0, &err)
                             : xrad_image_write_exr(o->diff, img[0].rgba, w, h, &err);
        if (st)
            rc = cli_report(&err);
    }
    method_image_free(&img[0]);
    method_image_free(&img[1]);
    return rc;
}

typedef struct element_row {
    uint32_t surface, i, j;
    double x[3]; /* the sample, object space */
    double a, b, rel;
} element_row;

/* Sample (i, j) of surface si at parameters (s, t) = (i, j) / (n - 1) on
 * the corners as drawn: bilinear on a quad, collapsed to the apex p2 on a
 * triangle (xrad_surface_info). */
static void sample_position(const xrad_surface_info *si, uint32_t i, uint32_t j, double x[3])
{
    double s = si->nu > 1 ? (double)i / (si->nu - 1) : 0.5;
    double t = si->nv > 1 ? (double)j / (si->nv - 1) : 0.5;
    const double *p3 = si->triangle ? si->corners[2] : si->corners[3];
    for (int c = 0; c < 3; c++)
        x[c] = (1 - t) * ((1 - s) * si->corners[0][c] + s * si->corners[1][c]) +
               t * ((1 - s) * p3[c] + s * si->corners[2][c]);
}

static int worst_first(const void *x, const void *y)
{
    double a = ((const element_row *)x)->rel, b = ((const element_row *)y)->rel;
    return (a < b) - (a > b);
}

static double texel_sum(const xrad_atlas *at, uint32_t x, uint32_t y)
{
    const float *t = at->rgba + 4 * ((size_t)y * at->width + x);
    return (double)t[0] + t[1] + t[2];
}

/* Every counted element of atlases at[0] (a) and at[1] (b) as CSV rows,
 * worst first: what element_p95 ranks, with where it is. The 1e-3 floor
 * takes b's mean over the elements weighted by their surface's area per
 * element, close to the library's exact cell areas. */
static int write_elements(const char *path, const xrad_scene *scene, const xrad_scene_info *info,
                          const xrad_atlas at[2])
{
    xrad_error err = {0};
    element_row *rows = calloc(info->elements ? info->elements : 1, sizeof(*rows));
    if (!rows) {
        fprintf(stderr, "xrad compare: out of memory\n");
        return 2;
    }
    size_t n = 0;
    double sum = 0, area = 0;
    for (uint32_t s = 0; s < info->surfaces; s++) {
        xrad_surface_info si;
        if (xrad_scene_get_surface(scene, s, &si, &err) || method_surface_emits(scene, s))
            continue;
        double w = si.area / ((double)si.nu * si.nv);
        for (uint32_t j = 0; j < si.nv; j++)
            for (uint32_t i = 0; i < si.nu && n < info->elements; i++, n++) {
                rows[n] = (element_row){.surface = s, .i = i, .j = j,
                                        .a = texel_sum(&at[0], si.tile_x + i, si.tile_y + j),
                                        .b = texel_sum(&at[1], si.tile_x + i, si.tile_y + j)};
                sample_position(&si, i, j, rows[n].x);
                sum += w * rows[n].b;
                area += w;
            }
    }
    double floor_b = area > 0 ? 1e-3 * sum / area : 0;
    for (size_t k = 0; k < n; k++) {
        double d = rows[k].b > floor_b ? rows[k].b : floor_b;
        rows[k].rel = d > 0 ? fabs(rows[k].a - rows[k].b) / d : 0;
    }
    qsort(rows, n, sizeof(*rows), worst_first);
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "xrad compare: %s: cannot write: %s\n", path, strerror(errno));
        free(rows);
        return 1;
    }
    fprintf(f, "surface,i,j,x,y,z,a,b,rel\n");
    char name[256];
    for (size_t k = 0; k < n; k++) {
        method_surface_label(scene, rows[k].surface, name, sizeof(name));
        fprintf(f, "\"%s\",%u,%u,%.6g,%.6g,%.6g,%.7g,%.7g,%.7g\n", name, rows[k].i, rows[k].j,
                rows[k].x[0], rows[k].x[1], rows[k].x[2], rows[k].a, rows[k].b, rows[k].rel);
    }
    int rc = 0;
    if (fclose(f)) {
        fprintf(stderr, "xrad compare: %s: write failed: %s\n", path, strerror(errno));
        rc = 1;
    }
    free(rows);
    return rc;
}

static int compare_atlases(compare_opts *o)
{
    xrad_error err = {0};
    xrad_scene *scene = NULL;
    xrad_atlas at[2] = {{0}};
    double *ratio = NULL;
    const char *path[2] = {o->a, o->b};
    int rc = 0;
    if (method_load_scene(o->scene, &o->m, &scene, &err))
        return cli_report(&err);
    xrad_scene_info info;
    xrad_scene_get_info(scene, &info);
    for (int i = 0; i < 2 && rc == 0; i++) {
        if (xrad_image_read_exr(path[i], &at[i].rgba, &at[i].width, &at[i].height, &err)) {
            rc = cli_report(&err);
        } else if (at[i].width != info.atlas_width || at[i].height != info.atlas_height) {
            fprintf(stderr,
                    "xrad compare: %s is %ux%u but %s's element atlas is %ux%u (%u elements); "
                    "write it with xrad render --atlas for this scene, with the same "
                    "--preset/--density-scale\n",
                    path[i], at[i].width, at[i].height, o->scene, info.atlas_width,
                    info.atlas_height, info.elements);
            rc = 1;
        }
    }
    xrad_element_metrics m;
    if (rc == 0 && !(ratio = calloc(info.surfaces + 1, sizeof(double)))) {
        fprintf(stderr, "xrad compare: out of memory\n");
        rc = 2;
    }
    if (rc == 0 && xrad_atlas_compare(scene, &at[0], &at[1], &m, ratio, &err)) {
        fprintf(stderr, "xrad compare: %s against %s: %s\n", o->a, o->b, err.message);
        rc = err.status ? (int)err.status : 1;
    }
    if (rc == 0) {
        char name[256];
        method_surface_label(scene, m.worst_surface, name, sizeof(name));
        printf("surface_error %.7f (%s, ratio %.7f)\n", m.surface_error, name, m.worst_ratio);
        printf("element_p50 %.7f\nelement_p95 %.7f\nelement_max %.7f\n", m.p50, m.p95, m.max);
        printf("element_mean_ratio %.7f\nelements %u\nsurfaces %u\n", m.mean_ratio, m.elements,
               m.surfaces);
        if (o->surfaces) {
            /* An emitter's ratio is 1 by definition: say it was left out
             * rather than print a ratio nobody measured. */
            for (uint32_t s = 0; s < info.surfaces; s++) {
                method_surface_label(scene, s, name, sizeof(name));
                if (method_surface_emits(scene, s))
                    printf("surface %s emitter (not counted)\n", name);
                else
                    printf("surface %s ratio %.7f\n", name, ratio[s]);
            }
        }
    }
    if (rc == 0 && o->elements)
        rc = write_elements(o->elements, scene, &info, at);
    free(ratio);
    free(at[0].rgba);
    free(at[1].rgba);
    xrad_scene_destroy(&scene);
    return rc;
}

int cmd_compare(int argc, char **argv)
{
    cli_args a;
    cli_init(&a, argc, argv);
    compare_opts o = {0};
    const char *opt;
    while ((opt = cli_next(&a)) && !a.failed) {
        if (cli_is_help(opt)) {
            help();
            return 0;
        } else if (!strcmp(opt, "diff")) {
            o.diff = cli_value(&a);
        } else if (!strcmp(opt, "scene")) {
            o.scene = cli_value(&a);
        } else if (!strcmp(opt, "surfaces")) {
            o.surfaces = 1;
        } else if (!strcmp(opt, "elements")) {
            o.elements = cli_value(&a);
        } else if (!strcmp(opt, "preset") || !strcmp(opt, "density-scale")) {
            method_solver_option(&a, opt, &o.m);
        } else {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 2)
        return cli_usage_error("compare", "needs two %s (see xrad compare --help)",
                               o.scene ? "atlases" : "images");
    o.a = a.positional[0];
    o.b = a.positional[1];
    if (o.scene && o.diff)
        return cli_usage_error("compare", "--diff compares images; it does not go with --scene");
    if (!o.scene && (o.surfaces || o.elements || o.m.preset || o.m.override_count))
        return cli_usage_error("compare", "--surfaces, --elements, --preset and "
                                          "--density-scale need --scene");
    return o.scene ? compare_atlases(&o) : compare_images(&o);
}
