#include "gpu/timer.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

xrad_status gpu_timer_create(struct xrad_context *ctx, uint32_t max_intervals,
                             gpu_timer **out, xrad_error *err)
{
    *out = NULL;
    gpu_timer *t = calloc(1, sizeof(*t));
    if (!t)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (timer)");
    t->capacity = max_intervals ? max_intervals : 1;
    t->intervals = calloc(t->capacity, sizeof(*t->intervals));
    if (!t->intervals) {
        free(t);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (timer)");
    }
    t->supported = ctx->features.timestamps;
    t->period_ns = ctx->features.timestamp_period;
    t->mask = ctx->features.timestamp_valid_bits >= 64
                  ? UINT64_MAX
                  : (1ull << ctx->features.timestamp_valid_bits) - 1;
    if (t->supported) {
        VkQueryPoolCreateInfo info = {
            .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
            .queryType = VK_QUERY_TYPE_TIMESTAMP,
            .queryCount = 2 * t->capacity,
        };
        if (VK_CHECK(ctx, err, vkCreateQueryPool(ctx->device, &info, NULL, &t->pool))) {
            free(t->intervals);
            free(t);
            return XRAD_ERROR_SYSTEM;
        }
    }
    *out = t;
    return XRAD_OK;
}

void gpu_timer_destroy(struct xrad_context *ctx, gpu_timer **t)
{
    if (!t || !*t)
        return;
    vkDestroyQueryPool(ctx->device, (*t)->pool, NULL);
    free((*t)->intervals);
    free(*t);
    *t = NULL;
}

void gpu_timer_start(gpu_timer *t, VkCommandBuffer cmd)
{
    t->used = 0;
    t->depth = 0;
    t->skipped_depth = 0;
    if (t->supported)
        vkCmdResetQueryPool(cmd, t->pool, 0, 2 * t->capacity);
}

static int name_index(gpu_timer *t, const char *name)
{
    for (uint32_t i = 0; i < t->name_count; i++)
        if (!strncmp(t->totals[i].name, name, GPU_TIMER_NAME_MAX - 1))
            return (int)i;
    if (t->name_count == GPU_TIMER_NAMES)
        return -1;
    gpu_timer_total *n = &t->totals[t->name_count];
    memset(n, 0, sizeof(*n));
    strncpy(n->name, name, GPU_TIMER_NAME_MAX - 1);
    return (int)t->name_count++;
}

void gpu_timer_begin(gpu_timer *t, VkCommandBuffer cmd, const char *name)
{
    int n = t->supported ? name_index(t, name) : -1;
    if (!t->supported || n < 0 || t->used == t->capacity || t->depth == GPU_TIMER_DEPTH ||
        t->skipped_depth) {
        /* Nested inside a dropped interval, or no room: dropped, but its
         * end must still pair up. */
        t->skipped_depth++;
        t->dropped += t->supported;
        return;
    }
    uint32_t i = t->used++;
    t->intervals[i] = (gpu_timer_interval){.name = (uint32_t)n, .query = 2 * i};
    t->open[t->depth++] = i;
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, t->pool, 2 * i);
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT,
                         VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 0, NULL, 0, NULL, 0, NULL);
}

void gpu_timer_end(gpu_timer *t, VkCommandBuffer cmd)
{
    if (t->skipped_depth) {
        t->skipped_depth--;
        return;
    }
    if (!t->depth)
        return;
    uint32_t i = t->open[--t->depth];
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, t->pool,
                        t->intervals[i].query + 1);
}

xrad_status gpu_timer_collect(struct xrad_context *ctx, gpu_timer *t, xrad_error *err)
{
    if (!t->supported || !t->used)
        return XRAD_OK;
    if (t->depth)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "gpu_timer_collect: %u intervals still open",
                         t->depth);
    uint64_t *ticks = calloc(2 * (size_t)t->used, sizeof(*ticks));
    if (!ticks)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (timer)");
    xrad_status s = VK_CHECK(ctx, err,
                             vkGetQueryPoolResults(ctx->device, t->pool, 0, 2 * t->used,
                                                   2 * (size_t)t->used * sizeof(*ticks), ticks,
                                                   sizeof(*ticks), VK_QUERY_RESULT_64_BIT));
    if (!s) {
        for (uint32_t i = 0; i < t->used; i++) {
            const gpu_timer_interval *in = &t->intervals[i];
            uint64_t d = (ticks[in->query + 1] - ticks[in->query]) & t->mask;
            t->totals[in->name].ms += (double)d * t->period_ns * 1e-6;
            t->totals[in->name].count++;
        }
    }
    t->used = 0;
    free(ticks);
    return s;
}

double gpu_timer_total_ms(const gpu_timer *t, const char *name)
{
    for (uint32_t i = 0; i < t->name_count; i++)
        if (!strncmp(t->totals[i].name, name, GPU_TIMER_NAME_MAX - 1))
            return t->totals[i].ms;
    return 0;
}
