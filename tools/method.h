/* Running one radiosity method to a solution atlas: the CPU reference or a
 * GPU solver, with what each measured, one frame or a sequence of frames.
 * Shared by render and bench. */
#ifndef XRAD_TOOLS_METHOD_H
#define XRAD_TOOLS_METHOD_H

#include "cli.h"
#include "xrad.h"

#define METHOD_MAX_OVERRIDES 32

typedef struct method_settings {
    xrad_solver_desc solver;    /* GPU methods; method filled from the name */
    xrad_reference_desc reference;
    /* Quality from the command line, applied over the scene file's own
     * (method_load_scene): --preset, then each --SETTING VALUE in order. */
    const char *preset;
    uint32_t override_count;
    const char *override_name[METHOD_MAX_OVERRIDES]; /* setting names (underscores) */
    const char *override_value[METHOD_MAX_OVERRIDES];
    char override_names[METHOD_MAX_OVERRIDES][48];
    const char *camera; /* --camera: a model file's camera by name */
    /* Set by method_load_scene: every quality setting as resolved. */
    xrad_quality resolved;
} method_settings;

/* Prints the help lines of the options method_solver_option takes: every
 * quality setting with its default and range, --preset, and the GPU
 * options that are not quality. */
void method_print_options(void);

/* Takes `opt` (and its value) into `m` if it is one of those options;
 * returns 0 when it is not. */
int method_solver_option(cli_args *a, const char *opt, method_settings *m);

/* Loads the scene with the command line's density scale, then resolves the
 * quality into m->solver: the scene file's quality, --preset, the
 * overrides. Messages name the file or the option. */
xrad_status method_load_scene(const char *path, method_settings *m, xrad_scene **out,
                              xrad_error *err);

typedef struct method_result {
    double wall_ms;             /* host time of the solve (or frame) alone */
    int gpu;                    /* 1 for a GPU solver: `stats` is filled */
    xrad_solver_stats stats;
    xrad_reference_stats ref;
} method_result;

/* --visibility's value (auto, clip, rays) into *out; a usage error
 * otherwise. */
bool method_visibility_option(cli_args *a, xrad_visibility *out);
/* "clip" or "rays" (the resolved modes), "auto". */
const char *method_visibility_name(xrad_visibility v);
/* --reference-solver's value (auto, dense, gather) into *out; a usage
 * error otherwise. */
bool method_reference_solver_option(cli_args *a, xrad_reference_solver *out);
/* --tonemap exposure|reinhard. */
bool method_tonemap_option(cli_args *a, xrad_tonemap *out);
/* "dense" or "gather" (the resolved solvers), "auto". */
const char *method_reference_solver_name(xrad_reference_solver s);

/* "reference, gather, progressive, incremental, cross" */
const char *method_list(void);
/* 1 if `name` is a method this build has. */
int method_known(const char *name);

/* A method kept across frames: the GPU solver stays alive, so that dynamic
 * methods redistribute from frame to frame. */
typedef struct method_run_state {
    xrad_context *ctx;
    const xrad_scene *scene;
    const char *name;
    method_settings settings;
    xrad_solver *solver; /* NULL for the reference */
    int frames;          /* frames done */
} method_run_state;

xrad_status method_open(xrad_context *ctx, const xrad_scene *scene, const char *name,
                        const method_settings *settings, method_run_state *run,
                        xrad_error *err);
/* The solution at scene time t into `atlas` (xrad_atlas_create'd): the
 * first frame solves; later ones advance (xrad_solver_advance: dynamic
 * methods redistribute, the others solve anew; the reference solves anew). */
xrad_status method_frame(method_run_state *run, double t, xrad_atlas *atlas,
                         method_result *result, xrad_error *err);
void method_close(method_run_state *run);

/* One solve at settings->solver.time / reference.time: open, frame, close. */
xrad_status method_run(xrad_context *ctx, const xrad_scene *scene, const char *name,
                       const method_settings *settings, xrad_atlas *atlas,
                       method_result *result, xrad_error *err);

/* Prints "  pass  ms (count)" lines for a GPU result; `what` says whose
 * ("the first solve", "the last frame"). */
void method_print_passes(const method_result *r, const char *what);

/* ------------------------------------------------ accuracy (README "Accuracy") */

/* The emitter mask of a view: width x height floats (the size
 * xrad_render_view gives for `view`), non-zero where a pixel shows an
 * emitting surface, partly covered edge pixels included. Drawn by
 * xrad_render_view from an atlas holding 1 on the texels of elements whose
 * material emits, so it is the same camera, pose and coverage as the image.
 * *mask is malloc'd. */
xrad_status method_emitter_mask(xrad_context *ctx, const xrad_scene *scene,
                                const xrad_view_desc *view, float **mask, xrad_error *err);

/* An image to compare: EXR (RGB; alpha from its "A" channel, 1 where it has
 * none; the "emitter" channel when it has one) or PNG (alpha 1, no mask:
 * PNGs carry neither). */
typedef struct method_image {
    float *rgba;
    float *emitter; /* NULL: the file has no emitter channel */
    uint32_t width, height;
} method_image;

xrad_status method_read_image(const char *path, method_image *img, xrad_error *err);
void method_image_free(method_image *img);

/* A surface's name for messages and tables: its own name when no other
 * surface of the scene has it, else "object/surface". */
void method_surface_label(const xrad_scene *scene, uint32_t index, char *buf, size_t n);

/* 1 if surface `index`'s material emits (the metrics leave it out). */
int method_surface_emits(const xrad_scene *scene, uint32_t index);

#endif
