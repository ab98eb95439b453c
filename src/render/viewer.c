#include "render/viewer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/swapchain.h"
#include "gpu/timer.h"
#include "passes/display.h"
#include "passes/overlay.h"
#include "passes/present.h"

#define SLOTS PRESENT_SLOTS

typedef struct viewer_slot {
    VkCommandBuffer cmd;
    VkFence fence;
    bool pending;          /* submitted, not yet seen complete */
    VkSemaphore acquired;  /* the swapchain image this slot renders */
    display_pass *display; /* its descriptor set is rewritten every frame */
    display_target target;
    gpu_buffer vertices, indices;
    gpu_buffer text;       /* the overlay's vertices */
    uint32_t text_vertices;
    gpu_timer *timer;
    gpu_buffer readback;   /* the linear image, when read (screenshot, auto exposure) */
    bool read;             /* this slot's frame copies the image to `readback` */
    uint32_t read_w, read_h;
    double read_exposure;
    xrad_tonemap read_tonemap;
    char screenshot[1024]; /* where to write it; empty: auto exposure only */
} viewer_slot;

struct viewer {
    struct xrad_context *ctx;
    const xrad_scene *scene;
    VkCommandPool pool;
    present_pass *present;
    overlay_pass *overlay;
    gpu_swapchain sc;
    bool vsync, recreate;
    viewer_slot slots[SLOTS];
    uint32_t next;
    gpu_image empty;        /* 1 x 1 zero atlas: frames before the first publication */
    double exposure;        /* 0: automatic, not measured yet */
    bool exposure_measured;
    xrad_tonemap tonemap;   /* the frames' (an automatic exposure is its own) */
    VkSemaphore displayed;  /* the scheduler's, learned from the first frame */
    uint64_t last_signal;   /* its value of the last frame submitted */
    double last_start_ms;
    viewer_stats stats;
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static void slot_destroy(struct xrad_context *ctx, viewer *v, viewer_slot *sl)
{
    gpu_timer_destroy(ctx, &sl->timer);
    gpu_buffer_destroy(ctx, &sl->readback);
    gpu_buffer_destroy(ctx, &sl->indices);
    gpu_buffer_destroy(ctx, &sl->text);
    gpu_buffer_destroy(ctx, &sl->vertices);
    display_target_destroy(ctx, &sl->target);
    display_destroy(ctx, &sl->display);
    vkDestroySemaphore(ctx->device, sl->acquired, NULL);
    vkDestroyFence(ctx->device, sl->fence, NULL);
    if (sl->cmd)
        vkFreeCommandBuffers(ctx->device, v->pool, 1, &sl->cmd);
    memset(sl, 0, sizeof(*sl));
}

static xrad_status slot_create(struct xrad_context *ctx, viewer *v, viewer_slot *sl,
                               xrad_error *err)
{
    VkCommandBufferAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
        .commandPool = v->pool,
        .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
        .commandBufferCount = 1,
    };
    VkFenceCreateInfo fence = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkSemaphoreCreateInfo sem = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    xrad_status s;
    if ((s = VK_CHECK(ctx, err, vkAllocateCommandBuffers(ctx->device, &alloc, &sl->cmd))) ||
        (s = VK_CHECK(ctx, err, vkCreateFence(ctx->device, &fence, NULL, &sl->fence))) ||
        (s = VK_CHECK(ctx, err, vkCreateSemaphore(ctx->device, &sem, NULL, &sl->acquired))) ||
        (s = display_create(ctx, &sl->display, err)) ||
        (s = gpu_timer_create(ctx, 4, &sl->timer, err)))
        return s;
    return XRAD_OK;
}

xrad_status viewer_create(struct xrad_context *ctx, const xrad_scene *scene,
                          const viewer_desc *desc, viewer **out, xrad_error *err)
{
    *out = NULL;
    viewer *v = calloc(1, sizeof(*v));
    if (!v)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (viewer)");
    v->ctx = ctx;
    v->scene = scene;
    v->vsync = desc->vsync;
    VkFormat format;
    xrad_status s;
    if ((s = gpu_swapchain_format(ctx, desc->surface, &format, err)) ||
        (s = gpu_thread_pool(ctx, &v->pool, err)) ||
        (s = present_create(ctx, format, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, &v->present, err)) ||
        (s = overlay_create(ctx, present_render_pass(v->present), &v->overlay, err)) ||
        (s = gpu_swapchain_create(ctx, desc->surface, present_render_pass(v->present),
                                  desc->width, desc->height, desc->vsync, &v->sc, err)))
        goto fail;
    for (uint32_t i = 0; i < SLOTS; i++)
        if ((s = slot_create(ctx, v, &v->slots[i], err)))
            goto fail;
    gpu_image_desc ed = {
        .format = DISPLAY_ATLAS_FORMAT,
        .width = 1,
        .height = 1,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .category = GPU_MEM_RADIOSITY,
    };
    float zero[4] = {0, 0, 0, 0};
    if ((s = gpu_image_create(ctx, &ed, &v->empty, err)) ||
        (s = gpu_upload_image(ctx, &v->empty, zero, sizeof(zero),
                              VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, err)))
        goto fail;
    *out = v;
    return XRAD_OK;

fail:
    viewer_destroy(&v);
    xrad_error_prefix(err, "view");
    return s;
}

void viewer_destroy(viewer **pv)
{
    if (!pv || !*pv)
        return;
    viewer *v = *pv;
    struct xrad_context *ctx = v->ctx;
    for (uint32_t i = 0; i < SLOTS; i++)
        if (v->slots[i].pending && !atomic_load(&ctx->lost))
            vkWaitForFences(ctx->device, 1, &v->slots[i].fence, VK_TRUE, ctx->wait_timeout_ns);
    /* Presents hold the swapchains' semaphores: teardown waits for the queue. */
    if (!atomic_load(&ctx->lost)) {
        gpu_queue_lock(ctx);
        vkQueueWaitIdle(ctx->queue);
        gpu_queue_unlock(ctx);
    }
    for (uint32_t i = 0; i < SLOTS; i++)
        slot_destroy(ctx, v, &v->slots[i]);
    gpu_image_destroy(ctx, &v->empty);
    gpu_swapchain_destroy(ctx, &v->sc);
    overlay_destroy(ctx, &v->overlay);
    present_destroy(ctx, &v->present);
    free(v);
    *pv = NULL;
}

/* After the slot's frame completed: its pass times, and the image it read
 * back (a screenshot, or the automatic exposure). */
static xrad_status slot_finish(viewer *v, viewer_slot *sl, xrad_error *err)
{
    struct xrad_context *ctx = v->ctx;
    xrad_status s = VK_CHECK(ctx, err,
                             vkWaitForFences(ctx->device, 1, &sl->fence, VK_TRUE,
                                             ctx->wait_timeout_ns));
    if (s)
        return s;
    sl->pending = false;
    gpu_timer *t = sl->timer;
    if ((s = gpu_timer_collect(ctx, t, err)))
        return s;
    for (uint32_t i = 0; i < t->name_count; i++) {
        sliding_table_add(&v->stats.passes, t->totals[i].name, t->totals[i].ms);
        t->totals[i].ms = 0;
        t->totals[i].count = 0;
    }
    if (!sl->read)
        return XRAD_OK;
    sl->read = false;
    const float *rgba = sl->readback.alloc.mapped;
    if (!v->exposure_measured && v->exposure <= 0) {
        v->exposure = xrad_image_tonemap_exposure(v->tonemap, rgba, sl->read_w, sl->read_h);
        v->exposure_measured = true;
    }
    if (!sl->screenshot[0])
        return XRAD_OK;
    size_t n = strlen(sl->screenshot);
    bool exr = n >= 4 && !strcmp(sl->screenshot + n - 4, ".exr");
    s = exr ? xrad_image_write_exr(sl->screenshot, rgba, sl->read_w, sl->read_h, err)
            : xrad_image_write_png_tonemapped(sl->screenshot, rgba, sl->read_w, sl->read_h,
                                             sl->read_tonemap, sl->read_exposure, err);
    sl->screenshot[0] = 0;
    return s;
}

/* Host-visible geometry of at least `bytes`; the slot's GPU work is done. */
static xrad_status ensure_buffer(struct xrad_context *ctx, gpu_buffer *b, size_t bytes,
                                 VkBufferUsageFlags usage, xrad_error *err)
{
    if (b->buffer && b->size >= bytes)
        return XRAD_OK;
    gpu_buffer_destroy(ctx, b);
    return gpu_buffer_create(ctx, bytes + bytes / 2, usage, GPU_MEM_UPLOAD, GPU_MEM_GEOMETRY, b,
                             err);
}

static xrad_status upload_mesh(viewer *v, viewer_slot *sl, const display_mesh *mesh,
                               xrad_error *err)
{
    size_t vb = (size_t)mesh->vertex_count * sizeof(display_vertex);
    size_t ib = (size_t)mesh->index_count * sizeof(uint32_t);
    if (!mesh->index_count)
        return XRAD_OK;
    xrad_status s;
    if ((s = ensure_buffer(v->ctx, &sl->vertices, vb, VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, err)) ||
        (s = ensure_buffer(v->ctx, &sl->indices, ib, VK_BUFFER_USAGE_INDEX_BUFFER_BIT, err)))
        return s;
    memcpy(sl->vertices.alloc.mapped, mesh->vertices, vb);
    memcpy(sl->indices.alloc.mapped, mesh->indices, ib);
    return XRAD_OK;
}

/* The overlay's vertices for this slot's frame. */
static xrad_status upload_text(viewer *v, viewer_slot *sl, const char *text, xrad_error *err)
{
    sl->text_vertices = 0;
    if (!text || !text[0])
        return XRAD_OK;
    uint32_t bound = overlay_vertex_bound(text);
    xrad_status s = ensure_buffer(v->ctx, &sl->text, (size_t)bound * sizeof(overlay_vertex),
                                  VK_BUFFER_USAGE_VERTEX_BUFFER_BIT, err);
    if (s)
        return s;
    return overlay_build(text, sl->text.alloc.mapped, (uint32_t)(sl->text.size / sizeof(overlay_vertex)),
                         &sl->text_vertices, err);
}

static xrad_status record(viewer *v, viewer_slot *sl, uint32_t image, const scheduler_frame *f,
                          const display_mesh *mesh, const display_camera *cam,
                          const viewer_frame_desc *d, xrad_error *err)
{
    struct xrad_context *ctx = v->ctx;
    xrad_status s;
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    if ((s = VK_CHECK(ctx, err, vkResetCommandBuffer(sl->cmd, 0))) ||
        (s = VK_CHECK(ctx, err, vkBeginCommandBuffer(sl->cmd, &begin))))
        return s;
    VkCommandBuffer cmd = sl->cmd;
    /* This slot's geometry and readback may sit in memory that a freed
     * resource of earlier submissions (another thread's) wrote. */
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, VK_ACCESS_MEMORY_WRITE_BIT,
                       VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT |
                           VK_ACCESS_TRANSFER_WRITE_BIT);
    gpu_timer_start(sl->timer, cmd);
    display_draw draw = {
        .vertices = &sl->vertices,
        .indices = &sl->indices,
        .index_count = mesh->index_count,
        .atlas = f->atlas ? f->atlas : &v->empty,
        .camera = cam,
        .filter = d->nearest                                  ? DISPLAY_FILTER_NEAREST
                  : display_linear_supported(sl->display) ? DISPLAY_FILTER_LINEAR
                                                          : DISPLAY_FILTER_LINEAR_SHADER,
    };
    gpu_timer_begin(sl->timer, cmd, "display");
    if ((s = display_record(ctx, sl->display, cmd, &sl->target, &draw, err)))
        return s;
    gpu_timer_end(sl->timer, cmd);
    if (sl->read) {
        gpu_cmd_copy_image_to_buffer(cmd, &sl->target.color, 0, &sl->readback, 0);
        gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                           VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    }
    gpu_image_transition(cmd, &sl->target.color, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    /* The font at 2x from 720 lines up, 3x from 1220: legible, not huge. */
    overlay_draw text = {
        .vertices = &sl->text,
        .vertex_count = sl->text_vertices,
        .extent = v->sc.extent,
        .x = 8,
        .y = 8,
        .zoom = 1 + v->sc.extent.height / 500,
    };
    gpu_timer_begin(sl->timer, cmd, "present");
    present_record(ctx, v->present, cmd,
                   &(present_draw){
                       .source = &sl->target.color,
                       .framebuffer = v->sc.cur.framebuffers[image],
                       .extent = v->sc.extent,
                       .exposure = v->exposure > 0 ? v->exposure : 1.0,
                       .tonemap = v->tonemap,
                       .slot = (uint32_t)(sl - v->slots),
                       .overlay = v->overlay,
                       .text = &text,
                   });
    gpu_timer_end(sl->timer, cmd);
    return VK_CHECK(ctx, err, vkEndCommandBuffer(cmd));
}

static xrad_status submit(viewer *v, viewer_slot *sl, uint32_t image, const scheduler_frame *f,
                          xrad_error *err)
{
    VkSemaphore waits[2] = {sl->acquired, f->wait};
    uint64_t wait_values[2] = {0, f->wait_value};
    VkPipelineStageFlags stages[2] = {VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT,
                                      VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT};
    VkSemaphore signals[2] = {v->sc.cur.rendered[image], f->signal};
    uint64_t signal_values[2] = {0, f->signal_value};
    VkTimelineSemaphoreSubmitInfo tl = {
        .sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
        .waitSemaphoreValueCount = f->wait_value ? 2 : 1,
        .pWaitSemaphoreValues = wait_values,
        .signalSemaphoreValueCount = 2,
        .pSignalSemaphoreValues = signal_values,
    };
    VkSubmitInfo info = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .pNext = &tl,
        .waitSemaphoreCount = f->wait_value ? 2 : 1,
        .pWaitSemaphores = waits,
        .pWaitDstStageMask = stages,
        .commandBufferCount = 1,
        .pCommandBuffers = &sl->cmd,
        .signalSemaphoreCount = 2,
        .pSignalSemaphores = signals,
    };
    xrad_status s = VK_CHECK(v->ctx, err, vkResetFences(v->ctx->device, 1, &sl->fence));
    return s ? s : gpu_queue_submit(v->ctx, &info, sl->fence, err);
}

xrad_status viewer_frame(viewer *v, scheduler *sched, const viewer_frame_desc *d,
                         xrad_error *err)
{
    struct xrad_context *ctx = v->ctx;
    double t0 = now_ms();
    if (v->last_start_ms > 0)
        sliding_add(&v->stats.frame_ms, t0 - v->last_start_ms);
    v->last_start_ms = t0;
    if (d->exposure > 0) {
        v->exposure = d->exposure;
        v->exposure_measured = true;
    } else if (d->tonemap != v->tonemap) {
        /* An automatic exposure is measured again for the new operator:
         * Reinhard's key scale is not the exposure mapping's. */
        v->exposure = 0;
        v->exposure_measured = false;
    }
    v->tonemap = d->tonemap;
    viewer_slot *sl = &v->slots[v->next];
    xrad_status s = XRAD_OK;
    if (sl->pending && (s = slot_finish(v, sl, err)))
        return s;
    uint64_t reached = 0;
    if (v->displayed && (s = gpu_timeline_value(ctx, v->displayed, &reached, err)))
        return s;
    gpu_swapchain_collect(ctx, &v->sc, reached);
    if (!d->width || !d->height)
        return XRAD_OK; /* minimised: nothing to show, keep the swapchain */
    if (v->recreate || d->width != v->sc.extent.width || d->height != v->sc.extent.height) {
        if ((s = gpu_swapchain_recreate(ctx, &v->sc, d->width, d->height, v->vsync,
                                        v->last_signal, reached, err)))
            return s;
        v->recreate = false;
        v->stats.recreations = v->sc.recreations;
    }
    uint32_t image;
    bool stale;
    if ((s = gpu_swapchain_acquire(ctx, &v->sc, sl->acquired, &image, &stale, err)))
        return s;
    v->recreate = stale;
    if (image == UINT32_MAX)
        return XRAD_OK; /* out of date: recreated next frame */

    uint32_t w = v->sc.extent.width, h = v->sc.extent.height;
    if (sl->target.color.width != w || sl->target.color.height != h) {
        display_target_destroy(ctx, &sl->target);
        if ((s = display_target_create(ctx, sl->display, w, h, &sl->target, err)))
            return s;
    }
    display_camera cam;
    display_mesh mesh = {0};
    if ((s = display_camera_from(v->scene, &d->cam, w, h, d->time, &cam, err)) ||
        (s = display_mesh_build(v->scene, d->time, cam.origin, &mesh, err)) ||
        (s = upload_mesh(v, sl, &mesh, err)) || (s = upload_text(v, sl, d->overlay, err)))
        goto done;

    scheduler_frame f;
    if ((s = scheduler_frame_begin(sched, &f, err)))
        goto done;
    v->displayed = f.signal;
    sl->read = f.atlas && (d->screenshot || !v->exposure_measured);
    if (sl->read) {
        size_t bytes = (size_t)w * h * 4 * sizeof(float);
        if (sl->readback.size < bytes) {
            gpu_buffer_destroy(ctx, &sl->readback);
            s = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_READBACK,
                                  GPU_MEM_STAGING, &sl->readback, err);
        }
        sl->read_w = w;
        sl->read_h = h;
        sl->read_exposure = v->exposure;
        sl->read_tonemap = v->tonemap;
        snprintf(sl->screenshot, sizeof(sl->screenshot), "%s", d->screenshot ? d->screenshot : "");
    }
    if (!s)
        s = record(v, sl, image, &f, &mesh, &cam, d, err);
    if (!s)
        s = submit(v, sl, image, &f, err);
    bool submitted = !s;
    xrad_status end = scheduler_frame_end(sched, &f, submitted, err);
    if (!s)
        s = end;
    if (s)
        goto done;
    sl->pending = true;
    v->last_signal = f.signal_value;
    v->stats.serial = f.serial;
    v->stats.solution_time = f.time;
    if ((s = gpu_swapchain_present(ctx, &v->sc, image, &stale, err)))
        goto done;
    v->recreate |= stale;
    v->stats.frames++;
    v->next = (v->next + 1) % SLOTS;
    if (d->screenshot && sl->read)
        s = slot_finish(v, sl, err);

done:
    display_mesh_free(&mesh);
    return s;
}

void viewer_get_stats(const viewer *v, viewer_stats *out)
{
    *out = v->stats;
    out->exposure = v->exposure;
    out->tonemap = v->tonemap;
}
