/*
 * GPU timestamps per pass: one query pool, intervals opened and closed in
 * command buffers, read after the submission completed, accumulated per name
 * in milliseconds. Where the queue has no timestamps the timer records
 * nothing and every total stays 0 (t->supported says so).
 *
 * Usage per command buffer: gpu_timer_start (resets the queries), then
 * begin/end pairs (nested up to GPU_TIMER_DEPTH) outside render passes,
 * submit, wait, gpu_timer_collect.
 */
#ifndef XRAD_GPU_TIMER_H
#define XRAD_GPU_TIMER_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "xrad.h"

struct xrad_context;

#define GPU_TIMER_NAME_MAX 48
#define GPU_TIMER_NAMES 32
#define GPU_TIMER_DEPTH 8

typedef struct gpu_timer_total {
    char name[GPU_TIMER_NAME_MAX];
    double ms;      /* summed over collected intervals */
    uint32_t count; /* intervals collected */
} gpu_timer_total;

typedef struct gpu_timer_interval {
    uint32_t name; /* index into totals */
    uint32_t query; /* begin; end is query + 1 */
} gpu_timer_interval;

typedef struct gpu_timer {
    VkQueryPool pool;
    bool supported;
    double period_ns;
    uint64_t mask; /* valid timestamp bits */
    uint32_t capacity; /* intervals */
    uint32_t used;     /* intervals recorded since gpu_timer_start */
    uint32_t dropped;  /* intervals not recorded: capacity, depth or names ran out */
    gpu_timer_interval *intervals;
    uint32_t open[GPU_TIMER_DEPTH];
    uint32_t depth;
    uint32_t skipped_depth; /* begins past GPU_TIMER_DEPTH awaiting their end */
    gpu_timer_total totals[GPU_TIMER_NAMES];
    uint32_t name_count;
} gpu_timer;

/* Room for `max_intervals` begin/end pairs per command buffer. */
xrad_status gpu_timer_create(struct xrad_context *ctx, uint32_t max_intervals,
                             gpu_timer **out, xrad_error *err);
/* Accepts NULL; sets *t to NULL. */
void gpu_timer_destroy(struct xrad_context *ctx, gpu_timer **t);

/* Records the query reset; first thing in a command buffer that times. */
void gpu_timer_start(gpu_timer *t, VkCommandBuffer cmd);

/* Opens an interval named `name` (copied). Outside render passes: it
 * records a full execution barrier after the timestamp, because lavapipe
 * (Mesa 22.3) lets following compute work run ahead of a timestamp and so
 * under-reports compute passes. */
void gpu_timer_begin(gpu_timer *t, VkCommandBuffer cmd, const char *name);

/* Closes the innermost open interval. */
void gpu_timer_end(gpu_timer *t, VkCommandBuffer cmd);

/* After the submission that recorded the intervals has completed: reads
 * them and adds them to the totals. */
xrad_status gpu_timer_collect(struct xrad_context *ctx, gpu_timer *t, xrad_error *err);

/* Total for `name` in ms; 0 when never seen. */
double gpu_timer_total_ms(const gpu_timer *t, const char *name);

#endif
