/* The real-time scheduler (schedule/scheduler.h), driven by a display loop
 * of the test's own that reads the front atlas back every frame:
 *   - the front atlas is never written while displayed: its checksum is the
 *     same in every frame between two swaps;
 *   - publications arrive and change it (the box moves);
 *   - a slow redistribution does not block display frames: frames keep
 *     completing while the worker redistributes, several per publication;
 *   - a request's offsets move the object: the published solution matches
 *     a fresh progressive solve with the same offset;
 *   - a request's method switch solves anew with that method;
 *   - the worker's failure reaches the display as an error, not a hang. */
#include <time.h>

#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "scene/scene.h"
#include "schedule/scheduler.h"

/* A room with a ceiling light and a box sliding 0.3 m along x in 1 s. */
static const char *scene_json =
    "{\"unit\": \"m\", \"density\": 8,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"walls\", \"material\": \"white\", \"box\": {\"origin\": [0, 0, 0],"
    "     \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1]}, \"inward\": true},"
    "   {\"name\": \"light\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.4, 0.99, 0.4],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0, 0.2]}}]},"
    "  {\"name\": \"box\", \"dynamic\": true, \"surfaces\": ["
    "   {\"name\": \"b\", \"material\": \"white\", \"box\": {\"origin\": [0.2, 0.0, 0.35],"
    "     \"u\": [0.25, 0, 0], \"v\": [0, 0.3, 0], \"w\": [0, 0, 0.25]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
    "     {\"time\": 1, \"translate\": [0.3, 0, 0]}], \"loop\": false}}],"
    " \"camera\": {\"position\": [0.5, 0.5, 0.02], \"look_at\": [0.5, 0.5, 1],"
    "   \"fov_degrees\": 70, \"width\": 64, \"height\": 64}}";

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static uint64_t fnv1a(const void *data, size_t n)
{
    const unsigned char *p = data;
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

/* One display frame: reads the front atlas back (when there is one) in a
 * submission synchronised as the scheduler says; returns its checksum. */
static xrad_status display_frame(xrad_context *ctx, scheduler *sch, gpu_buffer *readback,
                                 scheduler_frame *f, float *texels, size_t bytes,
                                 uint64_t *sum, xrad_error *err)
{
    xrad_status st = scheduler_frame_begin(sch, f, err);
    if (st)
        return st;
    if (!f->atlas)
        return scheduler_frame_end(sch, f, false, err);
    gpu_cmd c;
    if ((st = gpu_cmd_begin(ctx, &c, err)))
        return st;
    gpu_image_transition(c.cmd, f->atlas, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                         VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    gpu_cmd_copy_image_to_buffer(c.cmd, f->atlas, 0, readback, 0);
    gpu_image_transition(c.cmd, f->atlas, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    gpu_memory_barrier(c.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    gpu_sync sync = {
        .wait = f->wait,
        .wait_value = f->wait_value,
        .wait_stage = VK_PIPELINE_STAGE_TRANSFER_BIT,
        .signal = f->signal,
        .signal_value = f->signal_value,
    };
    st = gpu_cmd_submit_sync(ctx, &c, &sync, err);
    if (!st)
        st = gpu_cmd_wait(ctx, &c, err);
    gpu_cmd_destroy(ctx, &c);
    if (st)
        return st;
    memcpy(texels, readback->alloc.mapped, bytes);
    *sum = fnv1a(texels, bytes);
    return scheduler_frame_end(sch, f, true, err);
}

static void test_loop(xrad_context *ctx)
{
    xrad_error err = {0};
    xrad_scene *scene = NULL, *copy = NULL;
    xrad_status st = xrad_scene_parse(scene_json, strlen(scene_json), "slide.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    st = xrad_scene_parse(scene_json, strlen(scene_json), "slide.json", &copy, &err);
    if (st)
        return;
    uint32_t aw = scene->atlas_width, ah = scene->atlas_height;
    size_t bytes = (size_t)aw * ah * 4 * sizeof(float);
    gpu_buffer readback = {0};
    st = gpu_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_READBACK,
                           GPU_MEM_STAGING, &readback, &err);
    CHECK(st == XRAD_OK, "readback buffer: %s", err.message);
    float *texels = malloc(bytes);
    scheduler *sch = NULL;
    scheduler_desc desc = {.solver = {.method = XRAD_METHOD_CROSS, .hemicube_res = 32}};
    if (!st)
        st = scheduler_create(ctx, scene, &desc, &sch, &err);
    CHECK(st == XRAD_OK, "scheduler_create: %s", err.message);
    if (st) {
        xrad_scene_destroy(&scene);
        xrad_scene_destroy(&copy);
        gpu_buffer_destroy(ctx, &readback);
        free(texels);
        return;
    }

    /* Once the first solution shows, 1 s of animation in 30 requests, one
     * per display frame, then frames until the last request is shown. */
    /* A hang fails the test instead of stalling it. */
    double deadline = now_ms() + 120e3;
    uint64_t serial_prev = 0, sum_prev = 0, requests = 0;
    uint32_t frames = 0, swaps = 0, unstable = 0, unchanged_swaps = 0;
    uint32_t in_interval = 0, max_in_interval = 0, frames_shown = 0;
    double last_time = -1, max_frame_ms = 0;
    while (now_ms() < deadline) {
        /* From the first publication on: the animation clock runs. */
        if (serial_prev && requests < 30) {
            scheduler_request r = {.time = (double)(requests + 1) / 30.0};
            scheduler_request_frame(sch, &r);
            requests++;
        }
        scheduler_frame f;
        uint64_t sum = 0;
        double t0 = now_ms();
        st = display_frame(ctx, sch, &readback, &f, texels, bytes, &sum, &err);
        double ms = now_ms() - t0;
        CHECK(st == XRAD_OK, "display frame %u: %s", frames, err.message);
        if (st)
            break;
        frames++;
        if (!f.atlas)
            continue;
        frames_shown++;
        max_frame_ms = ms > max_frame_ms ? ms : max_frame_ms;
        if (f.serial == serial_prev) {
            unstable += sum != sum_prev;
            in_interval++;
        } else {
            swaps++;
            unchanged_swaps += serial_prev && sum == sum_prev;
            max_in_interval = in_interval > max_in_interval ? in_interval : max_in_interval;
            in_interval = 1;
            CHECK(f.swapped, "the serial changed without a swap");
        }
        serial_prev = f.serial;
        sum_prev = sum;
        last_time = f.time;
        if (requests == 30 && f.time == 1.0)
            break;
    }
    max_in_interval = in_interval > max_in_interval ? in_interval : max_in_interval;
    scheduler_stats stats;
    scheduler_get_stats(sch, &stats);
    fprintf(stderr,
            "loop: %u display frames (%u showing a solution), %u swaps, %llu publications, "
            "redistribution %.1f ms (mean), longest display frame %.1f ms, at most %u frames "
            "per publication\n",
            frames, frames_shown, swaps, (unsigned long long)stats.published,
            stats.frame_ms, max_frame_ms, max_in_interval);
    CHECK(unstable == 0, "the front atlas changed in %u frames without a swap", unstable);
    CHECK(last_time == 1.0, "the last request (t = 1 s) was never shown (last %g)", last_time);
    CHECK(swaps >= 3, "only %u swaps", swaps);
    CHECK(unchanged_swaps == 0, "%u swaps showed the same atlas as before", unchanged_swaps);
    /* Not blocked: while one redistribution ran, the display went on. */
    CHECK(max_in_interval >= 3, "at most %u display frames per publication", max_in_interval);
    CHECK(frames_shown > stats.published, "%u display frames for %llu publications", frames_shown,
          (unsigned long long)stats.published);
    CHECK(stats.published <= requests + 1, "%llu publications for %llu requests",
          (unsigned long long)stats.published, (unsigned long long)requests);

    /* An offset request at the same time: the box moves 0.2 m along z. */
    scheduler_request moved = {.time = 1.0, .offset_count = 2};
    moved.offsets[1][2] = 0.2;
    scheduler_request_frame(sch, &moved);
    st = scheduler_wait_published(sch, requests + 1, &err);
    CHECK(st == XRAD_OK, "wait: %s", err.message);
    scheduler_frame f;
    uint64_t sum = 0;
    for (int i = 0; i < 2 && !st; i++) /* the swap, then a frame after it */
        st = display_frame(ctx, sch, &readback, &f, texels, bytes, &sum, &err);
    CHECK(st == XRAD_OK && f.serial == stats.published + 1, "the offset frame: %s (serial %llu)",
          err.message, (unsigned long long)f.serial);

    xrad_atlas fresh = {0};
    xrad_solver *solver = NULL;
    double offset[3] = {0, 0, 0.2};
    xrad_solver_desc pd = {.method = XRAD_METHOD_PROGRESSIVE, .time = 1.0, .hemicube_res = 32};
    if (!(st = xrad_scene_set_offset(copy, 1, offset, &err)) &&
        !(st = xrad_atlas_create(copy, &fresh, &err)) &&
        !(st = xrad_solver_create(ctx, copy, &pd, &solver, &err)) &&
        !(st = xrad_solver_solve(solver, &err)))
        st = xrad_solver_read(solver, &fresh, &err);
    CHECK(st == XRAD_OK, "fresh solve: %s", err.message);
    if (!st) {
        double e = xrad_image_nrmse(texels, fresh.rgba, aw, ah);
        fprintf(stderr, "offset: published vs fresh progressive NRMSE %.5f\n", e);
        CHECK(e >= 0 && e < 0.02, "published solution with the offset: NRMSE %g vs fresh", e);
    }

    /* A method switch: the worker solves anew with progressive, which is
     * then exactly the fresh solve above (same settings, same pose). */
    scheduler_request restart = moved;
    restart.method = XRAD_METHOD_PROGRESSIVE;
    scheduler_request_frame(sch, &restart);
    st = scheduler_wait_published(sch, requests + 2, &err);
    for (int i = 0; i < 2 && !st; i++)
        st = display_frame(ctx, sch, &readback, &f, texels, bytes, &sum, &err);
    scheduler_get_stats(sch, &stats);
    CHECK(st == XRAD_OK && stats.method == XRAD_METHOD_PROGRESSIVE,
          "method switch: %s (method %d)", err.message, (int)stats.method);
    if (!st && fresh.rgba) {
        double e = xrad_image_nrmse(texels, fresh.rgba, aw, ah);
        CHECK(e >= 0 && e < 1e-6, "after the switch to progressive: NRMSE %g vs fresh", e);
    }
    xrad_solver_destroy(&solver);
    xrad_atlas_destroy(&fresh);
    scheduler_destroy(&sch);
    xrad_scene_destroy(&copy);
    gpu_buffer_destroy(ctx, &readback);
    free(texels);
}

/* A worker that fails (an input error only the solver sees: an odd
 * hemicube resolution) reports it to waiters and the display. */
static void test_failure(xrad_context *ctx)
{
    xrad_error err = {0};
    xrad_scene *scene = NULL;
    xrad_status st = xrad_scene_parse(scene_json, strlen(scene_json), "slide.json", &scene, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    scheduler *sch = NULL;
    scheduler_desc desc = {.solver = {.method = XRAD_METHOD_CROSS, .hemicube_res = 33}};
    st = scheduler_create(ctx, scene, &desc, &sch, &err);
    CHECK(st == XRAD_OK, "scheduler_create: %s", err.message);
    if (st) {
        xrad_scene_destroy(&scene);
        return;
    }
    st = scheduler_wait_published(sch, 1, &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "hemicube"),
          "a failing worker: status %d, '%s'", st, err.message);
    xrad_error e2 = {0};
    CHECK(scheduler_status(sch, &e2) == st && !strcmp(e2.message, err.message),
          "scheduler_status: '%s'", e2.message);
    scheduler_destroy(&sch);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_loop(ctx);
    test_failure(ctx);
    gpu_test_end(&ctx);
    return test_finish();
}
