/*
 * The real-time loop's scheduler (thesis 4.5.3, DESIGN.md "Scheduling"):
 * redistribution runs on a worker thread of its own, display on the
 * caller's, and the two meet at two radiosity atlases.
 *
 *   - The worker owns the solver. It takes the newest requested scene time
 *     (and object offsets, and method) when it is free, redistributes to it
 *     (xrad_solver_advance: incremental and cross redistribute, the others
 *     solve anew), then publishes: scatters B into the back atlas in a
 *     submission that signals the `redistributed` timeline with the number
 *     n of the redistribution. Only a complete redistribution is published.
 *   - The display calls scheduler_frame_begin once per frame. Where a
 *     published value has been reached on the GPU (a host query, no wait)
 *     it swaps: that atlas becomes the front. It samples only the front
 *     atlas, waits for `redistributed` >= the front's n and signals
 *     `displayed` with the value frame_begin handed out.
 *   - The worker writes an atlas only once it is the back one, and its
 *     publishing submission waits on the GPU for `displayed` to pass the
 *     last frame that read it: no host wait, no device idle. A request the
 *     worker has not started is replaced by a newer one, so redistribution
 *     may span any number of display frames and the two rates are
 *     independent; both are measured.
 *
 * The scheduler takes the scene over: the worker poses it (with the offsets
 * of the requests), so the display needs a copy of its own.
 */
#ifndef XRAD_SCHEDULE_SCHEDULER_H
#define XRAD_SCHEDULE_SCHEDULER_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "core/sliding.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

#define SCHEDULER_MAX_OBJECTS 64

typedef struct scheduler_desc {
    xrad_solver_desc solver; /* method and settings; .time: the first solve's pose */
} scheduler_desc;

#define SCHEDULER_MAX_MATERIALS 64

/* An object placed by a rigid transform (xrad_scene_set_pose), or given
 * its animation back (`clear`). */
typedef struct scheduler_pose {
    uint32_t object;
    bool clear;
    double matrix[16];
} scheduler_pose;

/* A material's new emission (xrad_scene_set_emission). */
typedef struct scheduler_emission {
    uint32_t material;
    double emission[3];
} scheduler_emission;

/* What the worker is asked for. A request that replaces one the worker
 * has not started keeps that one's poses and emissions of objects and
 * materials it does not name itself, so no change is lost. */
typedef struct scheduler_request {
    double time;          /* s, scene time */
    xrad_method method;   /* 0: keep; another method: a new solver, solved anew */
    uint32_t offset_count; /* objects whose offsets follow; at most SCHEDULER_MAX_OBJECTS */
    double offsets[SCHEDULER_MAX_OBJECTS][3]; /* xrad_scene_set_offset of object i (dynamic ones) */
    uint32_t pose_count;
    scheduler_pose poses[SCHEDULER_MAX_OBJECTS];
    /* Any emission change makes the worker solve anew with its method
     * (from B = E: the light changed everywhere). */
    uint32_t emission_count;
    scheduler_emission emissions[SCHEDULER_MAX_MATERIALS];
} scheduler_request;

/* What one display frame samples and how its submission synchronises. */
typedef struct scheduler_frame {
    const gpu_image *atlas;  /* front atlas, SHADER_READ_ONLY_OPTIMAL; NULL before the first
                                publication (nothing to show yet) */
    uint64_t serial;         /* n of the front's redistribution (0: none) */
    double time;             /* s, the scene time of the front's solution */
    bool swapped;            /* this frame_begin swapped */
    /* The display submission waits for `wait` >= wait_value (stage: fragment
     * shader) and signals `signal` = signal_value. */
    VkSemaphore wait, signal;
    uint64_t wait_value, signal_value;
} scheduler_frame;

typedef struct scheduler_stats {
    uint64_t published;       /* redistributions published so far */
    uint64_t requested;       /* requests made so far */
    double time;              /* s, scene time of the newest publication */
    xrad_method method;       /* of the newest publication */
    bool busy;                /* the worker is redistributing */
    /* Sliding means over publications of the worker's host time: a whole
     * frame (the redistribution and its progressive iterations, or a
     * restart's solve), and the redistribution alone (solver stats'
     * redistribute_ms; 0 for the restarting methods). */
    double frame_ms, redistribute_ms;
    double frame_last_ms;
    sliding_window frame_window, redistribute_window;
    xrad_solver_stats last;   /* the solver's stats of the newest publication */
    sliding_table passes;     /* per-pass GPU ms of publications, sliding */
} scheduler_stats;

typedef struct scheduler scheduler;

/* Creates the atlases and semaphores and starts the worker, which solves at
 * desc->solver.time and publishes that as redistribution 1. Takes `scene`
 * over on success (scheduler_destroy frees it). */
xrad_status scheduler_create(struct xrad_context *ctx, xrad_scene *scene,
                             const scheduler_desc *desc, scheduler **out, xrad_error *err);

/* Stops the worker (after its current redistribution), waits for the
 * GPU work of both sides (teardown, not the loop), frees everything.
 * Accepts NULL; sets *s to NULL. */
void scheduler_destroy(scheduler **s);

/* Replaces the pending request. */
void scheduler_request_frame(scheduler *s, const scheduler_request *r);

/* Display frame start: swaps to the newest published atlas whose
 * redistribution completed on the GPU, and hands out the frame's values. */
xrad_status scheduler_frame_begin(scheduler *s, scheduler_frame *f, xrad_error *err);

/* Display frame end: `submitted` says whether a submission signalling
 * f->signal_value was made; if not, the value is signalled from the host
 * (the worker may wait for it). Call once per frame_begin. */
xrad_status scheduler_frame_end(scheduler *s, const scheduler_frame *f, bool submitted,
                                xrad_error *err);

/* Blocks until request `serial` (scheduler_request_frame's n-th call,
 * counting from 1), or a later one that replaced it, has been published
 * and its publication completed on the GPU (the next frame_begin swaps to
 * it), or the worker failed. For tests and screenshots. */
xrad_status scheduler_wait_published(scheduler *s, uint64_t request_serial, xrad_error *err);

/* The scene it took over: its objects and materials may be read (not
 * their poses, offsets and emissions, which the worker writes). */
const xrad_scene *scheduler_scene(const scheduler *s);

/* The scheduler inside the public one (scheduler_api.c), for the public
 * viewer (render/viewer_api.c). */
struct xrad_scheduler;
scheduler *scheduler_api_inner(struct xrad_scheduler *x);

/* Which of its atlases `image` is (a frame's, handed out as a handle);
 * NULL for none. */
const gpu_image *scheduler_atlas_of(const scheduler *s, VkImage image);

/* A copy of the statistics. */
void scheduler_get_stats(scheduler *s, scheduler_stats *out);

/* The worker's error (XRAD_OK while it runs), copied into err. */
xrad_status scheduler_status(scheduler *s, xrad_error *err);

#endif
