/* Running one radiosity method to a solution atlas: the CPU reference or a
 * GPU solver, with what each measured. Shared by render and bench. */
#ifndef XRAD_TOOLS_METHOD_H
#define XRAD_TOOLS_METHOD_H

#include "xrad.h"

typedef struct method_settings {
    xrad_solver_desc solver;    /* GPU methods; method filled from the name */
    xrad_reference_desc reference;
} method_settings;

typedef struct method_result {
    double wall_ms;             /* host time of the solve alone */
    int gpu;                    /* 1 for a GPU solver: `stats` is filled */
    xrad_solver_stats stats;
    xrad_reference_stats ref;
} method_result;

/* "reference, gather, progressive" */
const char *method_list(void);
/* 1 if `name` is a method this build has. */
int method_known(const char *name);

/* Solves `scene` with the named method into `atlas` (xrad_atlas_create'd). */
xrad_status method_run(xrad_context *ctx, const xrad_scene *scene, const char *name,
                       const method_settings *settings, xrad_atlas *atlas,
                       method_result *result, xrad_error *err);

/* Prints "  pass  ms (count)" lines for a GPU result. */
void method_print_passes(const method_result *r);

#endif
