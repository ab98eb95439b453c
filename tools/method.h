/* Running one radiosity method to a solution atlas: the CPU reference or a
 * GPU solver, with what each measured, one frame or a sequence of frames.
 * Shared by render and bench. */
#ifndef XRAD_TOOLS_METHOD_H
#define XRAD_TOOLS_METHOD_H

#include "cli.h"
#include "xrad.h"

/* Help lines of the GPU solver options method_solver_option takes. */
#define METHOD_SOLVER_OPTIONS_HELP                                                             \
    "  --hemicube-res N  GPU: hemicube face resolution, even [64]\n"                            \
    "  --msaa N          gather: radiosity hemicube samples, 1 or 4 [4]\n"                      \
    "  --bounces N       gather: fixed bounce count [0 = until --threshold]\n"                  \
    "  --threshold T     GPU: stop when unshot power / bounce change relative to the\n"         \
    "                    emitted power falls below T [1e-4]\n"                                  \
    "  --batch N         progressive: shots per submission (one host wait each) [32]\n"         \
    "  --max-patches N   progressive: shooting patches per surface side [8]\n"                  \
    "  --seed N          GPU: hemicube rotation seed [0]\n"                                     \
    "  --frame-shots N   incremental, cross: progressive shots after each\n"                    \
    "                    redistribution [0 = until --threshold]\n"                              \
    "  --cross-grid N    cross: PROJECTEDRADIOSITY rays per patch side, 1..16 [4]\n"            \
    "  --back-res N      cross: back hemicube face resolution, even [16]\n"                     \
    "  --back-msaa N     cross: back hemicube samples, 1 or 4 [4]\n"                            \
    "  --back-nearest    cross: nearest back hemicube samples (default bilinear)\n"             \
    "  --cross-recompute cross: render all four hemicubes per patch each frame\n"               \
    "                    (thesis) instead of keeping the last frame's\n"                       \
    "  --slice N         cross: elements per submission of the cross projection [0 = all]\n"

/* Takes `opt` (and its value) into `d` if it is one of the options above;
 * returns 0 when it is not. */
int method_solver_option(cli_args *a, const char *opt, xrad_solver_desc *d);

typedef struct method_settings {
    xrad_solver_desc solver;    /* GPU methods; method filled from the name */
    xrad_reference_desc reference;
} method_settings;

typedef struct method_result {
    double wall_ms;             /* host time of the solve (or frame) alone */
    int gpu;                    /* 1 for a GPU solver: `stats` is filled */
    xrad_solver_stats stats;
    xrad_reference_stats ref;
} method_result;

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

/* Prints "  pass  ms (count)" lines for a GPU result. */
void method_print_passes(const method_result *r);

#endif
