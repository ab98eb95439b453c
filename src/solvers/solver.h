/*
 * What every GPU solver shares: the context, the scene on the GPU, the
 * pass timer and the statistics; and the table of operations each method
 * file (gather.c, progressive.c, ...) provides. DESIGN.md "Layers": solvers
 * sit above passes, each method in its own file.
 */
#ifndef XRAD_SOLVERS_SOLVER_H
#define XRAD_SOLVERS_SOLVER_H

#include <stdbool.h>

#include "gpu/timer.h"
#include "passes/atlas_scatter.h"
#include "solvers/gpu_scene.h"
#include "xrad.h"

typedef struct solver_ops {
    /* Builds the method's passes and state in s->impl. */
    xrad_status (*create)(struct xrad_solver *s, xrad_error *err);
    /* From B = E to convergence; fills the counters of s->stats. */
    xrad_status (*solve)(struct xrad_solver *s, xrad_error *err);
    /* Releases s->impl; the GPU must be done with it. */
    void (*destroy)(struct xrad_solver *s);
    /* Redistributes the solution in hand from the current pose to scene
     * time `time` and continues it (dynamic methods); NULL: pose and solve
     * anew. Called only once a solution exists. */
    xrad_status (*advance)(struct xrad_solver *s, double time, xrad_error *err);
} solver_ops;

struct gpu_cmd;

struct xrad_solver {
    struct xrad_context *ctx;
    const xrad_scene *scene;
    xrad_solver_desc desc; /* defaults filled in */
    gpu_scene gs;
    gpu_timer *timer;
    xrad_solver_stats stats;
    const solver_ops *ops;
    void *impl;
    bool solved; /* B holds a solution at the current pose (advance may redistribute it) */
    bool reporting; /* in create or solve: desc.progress is called (solver_progress) */
};

extern const solver_ops gather_ops;
extern const solver_ops progressive_ops;
extern const solver_ops incremental_ops;
extern const solver_ops cross_ops;

/* Submits c, waits for it, counts both in s->stats, frees c and collects
 * the timer's intervals. */
xrad_status solver_submit_wait(struct xrad_solver *s, struct gpu_cmd *c, xrad_error *err);

/* Whether hemicubes drawing `clusters` clusters of the scene are culled
 * (passes/hemicube_cull.h): desc.cull, AUTO by the cluster count. */
static inline bool solver_culls(const struct xrad_solver *s, uint32_t clusters)
{
    return clusters > 0 &&
           (s->desc.cull == XRAD_CULL_ON ||
            (s->desc.cull != XRAD_CULL_OFF && clusters >= XRAD_CULL_MIN_CLUSTERS));
}

/* For the layers above (the scheduler): the scatter of the solver's B
 * into `atlas`, whose readers and writers they order themselves. They use
 * a solver through this and the public API, never its fields. */
static inline atlas_scatter_draw solver_atlas_scatter(const struct xrad_solver *s,
                                                      const gpu_image *atlas)
{
    return (atlas_scatter_draw){&s->gs.elements, &s->gs.B, s->gs.element_count, atlas};
}

/* Host monotonic clock, ms. */
double solver_now_ms(void);
/* desc.progress(stage, fraction) where there is one, in create and solve. */
void solver_progress(const xrad_solver *s, const char *stage, double fraction);

/* Clears the per-call statistics and pass times (keeps the hemicube path). */
void solver_stats_begin(struct xrad_solver *s);

/* Adds the timer's per-pass totals into s->stats.passes and gpu_ms. */
void solver_collect_times(struct xrad_solver *s);

#endif
