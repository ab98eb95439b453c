/*
 * The progressive refinement engine (thesis 4.3, Algorithm 4.2) as a part
 * other solvers build on: the progressive method itself, and the dynamic
 * methods, which continue with progressive iterations after each
 * redistribution (thesis 4.4.2, 4.5.3). It works on the solver's gpu_scene
 * (B, Bu) and adds its counters to the solver's stats.
 */
#ifndef XRAD_SOLVERS_PROGRESSIVE_H
#define XRAD_SOLVERS_PROGRESSIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "xrad.h"

struct xrad_solver;

typedef struct progressive progressive;

/* What the engine's shots are for (progressive_create's flags). */
enum {
    /* The shots' hemicubes draw the static set C alone and a restart
     * leaves the dynamic set M nothing unshot, so that shots neither reach
     * M nor come from it, nor are blocked by it (the cross method, which
     * adds what M does to C itself). */
    PROGRESSIVE_STATIC_ONLY = 1u << 0,
    /* A redistribution removes the shots again frame after frame
     * (incremental radiosity): those after a restart see as its pass sees
     * (the occluder test from the patch's centre, the patch's mean
     * radiosity near it, contact left to the hemicubes;
     * reconstruct_params.redistributed); a restart shoots as without the
     * flag. */
    PROGRESSIVE_REDISTRIBUTED = 1u << 1,
};

/* Passes and buffers for the solver's scene and settings (hemicube_res,
 * batch, max_patches, subdivide_ratio, threshold, seed). May grow the
 * solver's timer. flags: PROGRESSIVE_*. */
xrad_status progressive_create(struct xrad_solver *s, uint32_t flags, progressive **out,
                               xrad_error *err);
/* Accepts NULL and *p == NULL; sets *p to NULL. The GPU must be done with it. */
void progressive_destroy(struct xrad_solver *s, progressive **p);

/* restart: B = Bu = E (Bu = 0 on M where static_only), then shoot, fixed patches conserving too
 * (reconstruct_params.conserve_fixed). Otherwise continue from the B and Bu
 * in hand, with the threshold still relative to the largest power of the
 * last restart (the emitted power). Shoots until the largest unshot power
 * falls to the threshold, or max_shots selections (0: no limit but
 * desc.max_iterations in all since the restart). */
xrad_status progressive_run(struct xrad_solver *s, progressive *p, bool restart,
                            uint32_t max_shots, xrad_error *err);

/* Where a static_only engine's continuations (restart false) take their
 * patch counts from: the linear rule (the default: a dynamic method's
 * frames, select.comp says why) or, with square_root, the square root of
 * the power share, as a restart does (cross's first solve: its rounds
 * settle one pose and repeat no frame). */
void progressive_set_square_root_rule(progressive *p, bool square_root);

/* Tests, after a completed progressive_run: the index count the last
 * shot's ID hemicubes were recorded with on the host (what the multiview
 * path draws) and the one the select pass wrote into their indirect
 * command (what the layered path draws). */
void progressive_draw_counts(const progressive *p, uint32_t *host, uint32_t *command);

#endif
