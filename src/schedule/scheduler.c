#include "schedule/scheduler.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "passes/atlas_scatter.h"
#include "scene/scene.h"
#include "solvers/solver.h"

struct scheduler {
    struct xrad_context *ctx;
    xrad_scene *scene; /* owned; posed by the worker only */
    xrad_solver_desc desc;
    xrad_solver *solver; /* worker only */
    /* One per atlas, so that neither rewrites its descriptor set. */
    atlas_scatter_pass *scatter[2];
    gpu_image atlas[2];
    VkSemaphore redistributed; /* value n: redistribution n is in its atlas */
    VkSemaphore displayed;     /* value v: display frame v is done with its atlas */
    gpu_cmd publishing;        /* worker only: the last publication's submission */
    uint64_t publish_value;    /* worker only: the last n */
    pthread_t thread;
    bool thread_started;

    /* Everything below is shared and guarded by `lock`. */
    pthread_mutex_t lock;
    pthread_cond_t wake;      /* the worker: a request or quit */
    pthread_cond_t published; /* waiters: a publication or a failure */
    bool quit, failed;
    xrad_error error;
    scheduler_request pending;
    uint64_t pending_serial, taken_serial, published_serial;
    uint64_t published_value; /* n of the publication of published_serial */
    int front, ready;               /* atlas indices; ready -1: none waiting */
    uint64_t front_value, ready_value;
    double front_time, ready_time;
    uint64_t last_read[2];          /* `displayed` value of the last frame that read it */
    uint64_t display_value;         /* the last value handed out */
    scheduler_stats stats;
};

/* ------------------------------------------------------------- worker */

static xrad_status publish(scheduler *s, double time, uint64_t serial, xrad_error *err)
{
    struct xrad_context *ctx = s->ctx;
    /* The previous publication has long completed (the GPU ran a whole
     * redistribution after it); its fence is waited for only to free it. */
    xrad_status st = s->publishing.submitted ? gpu_cmd_wait(ctx, &s->publishing, err) : XRAD_OK;
    gpu_cmd_destroy(ctx, &s->publishing);
    if (st)
        return st;

    pthread_mutex_lock(&s->lock);
    int target = 1 - s->front;
    /* A publication the display has not swapped to is overwritten by this
     * newer one: withdraw it first, so the display cannot swap to it while
     * it is written. */
    if (s->ready == target)
        s->ready = -1;
    uint64_t after = s->last_read[target];
    pthread_mutex_unlock(&s->lock);

    gpu_cmd c;
    if ((st = gpu_cmd_begin(ctx, &c, err)))
        return st;
    /* The solver's last writes of B (earlier submissions on this queue)
     * before the scatter reads it. */
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    /* The display's reads end at the semaphore wait (compute stage). */
    gpu_image_barrier(c.cmd, &s->atlas[target], VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_IMAGE_LAYOUT_GENERAL, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, 0,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    atlas_scatter_draw draw = solver_atlas_scatter(s->solver, &s->atlas[target]);
    atlas_scatter_record(s->scatter[target], c.cmd, &draw);
    gpu_image_barrier(c.cmd, &s->atlas[target], VK_IMAGE_LAYOUT_GENERAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                      VK_ACCESS_SHADER_READ_BIT);
    uint64_t n = s->publish_value + 1;
    gpu_sync sync = {
        .wait = after ? s->displayed : VK_NULL_HANDLE,
        .wait_value = after,
        .wait_stage = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
        .signal = s->redistributed,
        .signal_value = n,
    };
    if ((st = gpu_cmd_submit_sync(ctx, &c, &sync, err))) {
        gpu_cmd_destroy(ctx, &c);
        return st;
    }
    s->publishing = c;
    s->publish_value = n;

    xrad_solver_stats ss;
    xrad_solver_get_stats(s->solver, &ss);
    pthread_mutex_lock(&s->lock);
    s->ready = target;
    s->ready_value = n;
    s->ready_time = time;
    s->published_serial = serial;
    s->published_value = n;
    scheduler_stats *t = &s->stats;
    t->published = n;
    t->time = time;
    t->method = s->desc.method;
    t->busy = false;
    t->last = ss;
    t->frame_last_ms = ss.wall_ms;
    for (uint32_t i = 0; i < ss.pass_count; i++)
        sliding_table_add(&t->passes, ss.passes[i].name, ss.passes[i].ms);
    sliding_add(&t->frame_window, ss.wall_ms);
    sliding_add(&t->redistribute_window, ss.redistribute_ms);
    t->frame_ms = sliding_mean(&t->frame_window);
    t->redistribute_ms = sliding_mean(&t->redistribute_window);
    pthread_cond_broadcast(&s->published);
    pthread_mutex_unlock(&s->lock);
    return XRAD_OK;
}

static xrad_status apply_offsets(scheduler *s, const scheduler_request *r, xrad_error *err)
{
    for (uint32_t i = 0; i < r->offset_count && i < s->scene->object_count; i++) {
        if (!s->scene->objects[i].dynamic)
            continue;
        xrad_status st = xrad_scene_set_offset(s->scene, i, r->offsets[i], err);
        if (st)
            return st;
    }
    return XRAD_OK;
}

static xrad_status new_solver(scheduler *s, xrad_method method, double time, xrad_error *err)
{
    xrad_solver_destroy(&s->solver);
    s->desc.method = method;
    s->desc.time = time;
    xrad_status st = xrad_solver_create(s->ctx, s->scene, &s->desc, &s->solver, err);
    return st ? st : xrad_solver_solve(s->solver, err);
}

/* The request's poses and emissions applied to the worker's scene. */
static xrad_status apply_changes(scheduler *s, const scheduler_request *r, xrad_error *err)
{
    xrad_status st = XRAD_OK;
    for (uint32_t i = 0; i < r->pose_count && !st; i++)
        st = xrad_scene_set_pose(s->scene, r->poses[i].object,
                                 r->poses[i].clear ? NULL : r->poses[i].matrix, err);
    for (uint32_t i = 0; i < r->emission_count && !st; i++)
        st = xrad_scene_set_emission(s->scene, r->emissions[i].material,
                                     r->emissions[i].emission, err);
    return st;
}

static xrad_status frame(scheduler *s, const scheduler_request *r, uint64_t serial,
                         xrad_error *err)
{
    xrad_status st = apply_offsets(s, r, err);
    if (!st)
        st = apply_changes(s, r, err);
    if (st)
        return st;
    if ((r->method && r->method != s->desc.method) || r->emission_count)
        st = new_solver(s, r->method ? r->method : s->desc.method, r->time, err);
    else
        st = xrad_solver_advance(s->solver, r->time, err);
    return st ? st : publish(s, r->time, serial, err);
}

static void *worker_main(void *arg)
{
    scheduler *s = arg;
    xrad_error err = {0};
    xrad_status st = new_solver(s, s->desc.method, s->desc.time, &err);
    if (!st)
        st = publish(s, s->desc.time, 0, &err);
    while (!st) {
        pthread_mutex_lock(&s->lock);
        while (!s->quit && s->pending_serial == s->taken_serial)
            pthread_cond_wait(&s->wake, &s->lock);
        if (s->quit) {
            pthread_mutex_unlock(&s->lock);
            break;
        }
        scheduler_request r = s->pending;
        uint64_t serial = s->pending_serial;
        s->taken_serial = serial;
        s->stats.busy = true;
        pthread_mutex_unlock(&s->lock);
        st = frame(s, &r, serial, &err);
    }
    if (st) {
        pthread_mutex_lock(&s->lock);
        s->failed = true;
        s->error = err;
        xrad_error_prefix(&s->error, "redistribution thread");
        s->stats.busy = false;
        pthread_cond_broadcast(&s->published);
        pthread_mutex_unlock(&s->lock);
    }
    return NULL;
}

/* ------------------------------------------------------------ display */

xrad_status scheduler_frame_begin(scheduler *s, scheduler_frame *f, xrad_error *err)
{
    memset(f, 0, sizeof(*f));
    uint64_t reached = 0;
    xrad_status st = gpu_timeline_value(s->ctx, s->redistributed, &reached, err);
    if (st)
        return st;
    pthread_mutex_lock(&s->lock);
    if (s->ready >= 0 && reached >= s->ready_value) {
        s->front = s->ready;
        s->front_value = s->ready_value;
        s->front_time = s->ready_time;
        s->ready = -1;
        f->swapped = true;
    }
    f->atlas = s->front_value ? &s->atlas[s->front] : NULL;
    f->serial = s->front_value;
    f->time = s->front_time;
    f->wait = s->redistributed;
    f->wait_value = s->front_value;
    f->signal = s->displayed;
    f->signal_value = ++s->display_value;
    pthread_mutex_unlock(&s->lock);
    return XRAD_OK;
}

xrad_status scheduler_frame_end(scheduler *s, const scheduler_frame *f, bool submitted,
                                xrad_error *err)
{
    xrad_status st = XRAD_OK;
    if (!submitted) {
        /* An empty submission keeps the value's signal in queue order
         * (a host signal could overtake an earlier frame's). */
        VkTimelineSemaphoreSubmitInfo tl = {
            .sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
            .signalSemaphoreValueCount = 1,
            .pSignalSemaphoreValues = &f->signal_value,
        };
        VkSubmitInfo submit = {
            .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
            .pNext = &tl,
            .signalSemaphoreCount = 1,
            .pSignalSemaphores = &s->displayed,
        };
        st = gpu_queue_submit(s->ctx, &submit, VK_NULL_HANDLE, err);
    }
    if (f->atlas) {
        pthread_mutex_lock(&s->lock);
        s->last_read[f->atlas == &s->atlas[1]] = f->signal_value;
        pthread_mutex_unlock(&s->lock);
    }
    return st;
}

/* --------------------------------------------------------------- API */

/* Keeps the poses and emissions of `old` (a request the worker has not
 * started) that `r` does not replace. */
static void merge_changes(scheduler_request *r, const scheduler_request *old)
{
    for (uint32_t i = 0; i < old->pose_count; i++) {
        bool named = false;
        for (uint32_t k = 0; k < r->pose_count && !named; k++)
            named = r->poses[k].object == old->poses[i].object;
        if (!named && r->pose_count < SCHEDULER_MAX_OBJECTS)
            r->poses[r->pose_count++] = old->poses[i];
    }
    for (uint32_t i = 0; i < old->emission_count; i++) {
        bool named = false;
        for (uint32_t k = 0; k < r->emission_count && !named; k++)
            named = r->emissions[k].material == old->emissions[i].material;
        if (!named && r->emission_count < SCHEDULER_MAX_MATERIALS)
            r->emissions[r->emission_count++] = old->emissions[i];
    }
}

void scheduler_request_frame(scheduler *s, const scheduler_request *r)
{
    pthread_mutex_lock(&s->lock);
    scheduler_request next = *r;
    if (next.offset_count > SCHEDULER_MAX_OBJECTS)
        next.offset_count = SCHEDULER_MAX_OBJECTS;
    if (next.pose_count > SCHEDULER_MAX_OBJECTS)
        next.pose_count = SCHEDULER_MAX_OBJECTS;
    if (next.emission_count > SCHEDULER_MAX_MATERIALS)
        next.emission_count = SCHEDULER_MAX_MATERIALS;
    if (s->pending_serial != s->taken_serial)
        merge_changes(&next, &s->pending);
    s->pending = next;
    s->pending_serial++;
    s->stats.requested = s->pending_serial;
    pthread_cond_signal(&s->wake);
    pthread_mutex_unlock(&s->lock);
}

xrad_status scheduler_wait_published(scheduler *s, uint64_t request_serial, xrad_error *err)
{
    pthread_mutex_lock(&s->lock);
    while (!s->failed && s->published_serial < request_serial)
        pthread_cond_wait(&s->published, &s->lock);
    xrad_status st = XRAD_OK;
    if (s->failed) {
        *err = s->error;
        st = s->error.status ? s->error.status : XRAD_ERROR_SYSTEM;
    }
    uint64_t value = s->published_value;
    pthread_mutex_unlock(&s->lock);
    /* ... and completed on the GPU, so that the next frame_begin swaps. */
    return st ? st : gpu_timeline_wait(s->ctx, s->redistributed, value, err);
}

const xrad_scene *scheduler_scene(const scheduler *s) { return s->scene; }

const gpu_image *scheduler_atlas_of(const scheduler *s, VkImage image)
{
    for (int i = 0; i < 2; i++)
        if (image && s->atlas[i].image == image)
            return &s->atlas[i];
    return NULL;
}

void scheduler_get_stats(scheduler *s, scheduler_stats *out)
{
    pthread_mutex_lock(&s->lock);
    *out = s->stats;
    pthread_mutex_unlock(&s->lock);
}

xrad_status scheduler_status(scheduler *s, xrad_error *err)
{
    pthread_mutex_lock(&s->lock);
    xrad_status st = XRAD_OK;
    if (s->failed) {
        *err = s->error;
        st = s->error.status ? s->error.status : XRAD_ERROR_SYSTEM;
    }
    pthread_mutex_unlock(&s->lock);
    return st;
}

/* Both atlases zero (texels of no element stay so) and in the layout the
 * display samples. */
static xrad_status clear_atlases(scheduler *s, xrad_error *err)
{
    gpu_cmd c;
    xrad_status st = gpu_cmd_begin(s->ctx, &c, err);
    if (st)
        return st;
    VkClearColorValue zero = {.float32 = {0, 0, 0, 0}};
    VkImageSubresourceRange range = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    for (int i = 0; i < 2; i++) {
        gpu_image_transition(c.cmd, &s->atlas[i], VK_IMAGE_LAYOUT_UNDEFINED,
                             VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
        vkCmdClearColorImage(c.cmd, s->atlas[i].image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, &zero,
                             1, &range);
        gpu_image_transition(c.cmd, &s->atlas[i], VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                             VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    }
    st = gpu_cmd_run(s->ctx, &c, err);
    gpu_cmd_destroy(s->ctx, &c);
    return st;
}

xrad_status scheduler_create(struct xrad_context *ctx, xrad_scene *scene,
                             const scheduler_desc *desc, scheduler **out, xrad_error *err)
{
    *out = NULL;
    if (!desc->solver.method || !xrad_method_name(desc->solver.method))
        return xrad_fail(err, XRAD_ERROR_INPUT, "scheduler: unknown method %d",
                         (int)desc->solver.method);
    scheduler *s = calloc(1, sizeof(*s));
    if (!s)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (scheduler)");
    s->ctx = ctx;
    s->desc = desc->solver;
    s->ready = -1;
    if (pthread_mutex_init(&s->lock, NULL) || pthread_cond_init(&s->wake, NULL) ||
        pthread_cond_init(&s->published, NULL)) {
        free(s);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "scheduler: pthread init failed");
    }
    gpu_image_desc ad = gpu_scene_atlas_desc(scene);
    xrad_status st;
    for (int i = 0; i < 2; i++)
        if ((st = gpu_image_create(ctx, &ad, &s->atlas[i], err)) ||
            (st = atlas_scatter_create(ctx, &s->scatter[i], err)))
            goto fail;
    if ((st = gpu_timeline_create(ctx, &s->redistributed, err)) ||
        (st = gpu_timeline_create(ctx, &s->displayed, err)) || (st = clear_atlases(s, err)))
        goto fail;
    s->scene = scene;
    if (pthread_create(&s->thread, NULL, worker_main, s)) {
        s->scene = NULL;
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "scheduler: could not start its thread");
        goto fail;
    }
    s->thread_started = true;
    *out = s;
    return XRAD_OK;

fail:
    scheduler_destroy(&s);
    return st;
}

void scheduler_destroy(scheduler **ps)
{
    if (!ps || !*ps)
        return;
    scheduler *s = *ps;
    struct xrad_context *ctx = s->ctx;
    if (s->thread_started) {
        pthread_mutex_lock(&s->lock);
        s->quit = true;
        pthread_cond_signal(&s->wake);
        pthread_mutex_unlock(&s->lock);
        pthread_join(s->thread, NULL);
    }
    /* Teardown: the display's last frames and the last publication. */
    if (!atomic_load(&ctx->lost)) {
        gpu_queue_lock(ctx);
        vkQueueWaitIdle(ctx->queue);
        gpu_queue_unlock(ctx);
    }
    gpu_cmd_destroy(ctx, &s->publishing);
    xrad_solver_destroy(&s->solver);
    for (int i = 0; i < 2; i++) {
        atlas_scatter_destroy(ctx, &s->scatter[i]);
        gpu_image_destroy(ctx, &s->atlas[i]);
    }
    vkDestroySemaphore(ctx->device, s->redistributed, NULL);
    vkDestroySemaphore(ctx->device, s->displayed, NULL);
    xrad_scene_destroy(&s->scene);
    pthread_cond_destroy(&s->published);
    pthread_cond_destroy(&s->wake);
    pthread_mutex_destroy(&s->lock);
    free(s);
    *ps = NULL;
}
