/*
 * Injected Vulkan failures during a render end in XRAD_ERROR_SYSTEM with a
 * message naming the call and the result, and leave no GPU memory, no
 * Vulkan object (the validation layer reports leaks at vkDestroyDevice) and
 * no validation message behind; nothing crashes or hangs. An out-of-memory
 * failure leaves the context usable; a lost device does not.
 */
#include <stdlib.h>
#include <string.h>

#include "gpu/cmd.h"
#include "gpu_test.h"
#include "scene/scene.h"

static const char *scene_json =
    "{\"unit\": \"m\","
    " \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": [{\"name\": \"o\", \"surfaces\": ["
    "  {\"name\": \"q\", \"material\": \"grey\", \"elements\": [4, 4],"
    "   \"quad\": {\"origin\": [-1, -1, 0], \"u\": [2, 0, 0], \"v\": [0, 2, 0]}}]}],"
    " \"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0],"
    "  \"fov_degrees\": 40, \"width\": 32, \"height\": 32}}";

static xrad_scene *scene;
static xrad_atlas atlas;

static xrad_status render(xrad_context *ctx, xrad_error *err)
{
    float *img = NULL;
    uint32_t w, h;
    xrad_status s = xrad_render_view(ctx, scene, &atlas, NULL, &img, &w, &h, err);
    CHECK((s == XRAD_OK) == (img != NULL), "image returned with status %d", (int)s);
    free(img);
    return s;
}

static void check_clean(xrad_context *ctx, const char *what)
{
    gpu_memory_stats st;
    gpu_memory_get_stats(ctx, &st);
    CHECK(st.allocations == 0 && st.blocks == 0, "%s: %u allocations in %u blocks left", what,
          st.allocations, st.blocks);
    CHECK(xrad_context_validation_messages(ctx) == 0, "%s: validation messages", what);
}

/* Every checked call of these functions in a render fails in turn (the
 * 1st, the 2nd, ... until a render no longer reaches the n-th call): each
 * failure path's cleanup runs. Out-of-memory leaves the context usable. */
static void test_every_failure_point(void)
{
    static const char *const functions[] = {
        "vkAllocateMemory",      "vkMapMemory",           "vkCreateBuffer",
        "vkBindBufferMemory",    "vkCreateImage",         "vkBindImageMemory",
        "vkCreateImageView",     "vkCreateRenderPass",    "vkCreateFramebuffer",
        "vkCreateShaderModule",  "vkCreateGraphicsPipelines", "vkCreateSampler",
        "vkCreateDescriptorSetLayout", "vkCreatePipelineLayout", "vkCreateDescriptorPool",
        "vkAllocateDescriptorSets", "vkAllocateCommandBuffers", "vkCreateFence",
        "vkBeginCommandBuffer",  "vkEndCommandBuffer",
    };
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return;
    uint32_t failures = 0;
    for (size_t f = 0; f < sizeof(functions) / sizeof(functions[0]); f++) {
        for (uint32_t n = 1; n < 64; n++) {
            gpu_fault_set(ctx, functions[f], n, VK_ERROR_OUT_OF_DEVICE_MEMORY);
            xrad_error err = {0};
            xrad_status s = render(ctx, &err);
            if (!ctx->fault.fired) {
                CHECK(s == XRAD_OK, "%s: render failed without a fault: %s", functions[f],
                      err.message);
                CHECK(n > 1, "%s is never called in a render", functions[f]);
                break;
            }
            failures++;
            CHECK(s == XRAD_ERROR_SYSTEM, "%s #%u: status %d", functions[f], n, (int)s);
            CHECK(strstr(err.message, functions[f]) &&
                      strstr(err.message, "VK_ERROR_OUT_OF_DEVICE_MEMORY"),
                  "%s #%u: message does not name call and result: %s", functions[f], n,
                  err.message);
            char what[96];
            snprintf(what, sizeof(what), "%s #%u", functions[f], n);
            check_clean(ctx, what);
        }
    }
    gpu_fault_set(ctx, NULL, 0, VK_SUCCESS);
    xrad_error err = {0};
    CHECK(render(ctx, &err) == XRAD_OK, "render after the faults: %s", err.message);
    fprintf(stderr, "%u injected failure points, each cleaned up\n", failures);
    gpu_test_end(&ctx);
}

/* A lost device at submission or at the fence wait, or a wait that runs
 * past its limit (a hang): a clear error, every resource freed (after a
 * failed wait, only once the real work ended), and later work refused. */
static void test_device_lost(const char *function, VkResult result, const char *explanation)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return;
    gpu_fault_set(ctx, function, 1, result);
    xrad_error err = {0};
    xrad_status s = render(ctx, &err);
    CHECK(s == XRAD_ERROR_SYSTEM, "%s lost: status %d", function, (int)s);
    CHECK(strstr(err.message, function) && strstr(err.message, gpu_result_name(result)) &&
              strstr(err.message, explanation),
          "%s %s: %s", function, gpu_result_name(result), err.message);
    fprintf(stderr, "message: %s\n", err.message);
    check_clean(ctx, function);
    memset(&err, 0, sizeof(err));
    CHECK(render(ctx, &err) == XRAD_ERROR_SYSTEM && strstr(err.message, "lost earlier"),
          "render on a lost context: %s", err.message);
    check_clean(ctx, "after loss");
    gpu_test_end(&ctx);
}

/* A submission that waits on a semaphore nobody signals: the queue stops as
 * a hung one does (a real hang, not an injected result). */
static bool submit_stuck(xrad_context *ctx, VkSemaphore *never, gpu_cmd *c, xrad_error *err)
{
    ctx->wait_timeout_ns = 1000000000ull; /* 1 s: the test need not wait 60 */
    if (gpu_timeline_create(ctx, never, err) || gpu_cmd_begin(ctx, c, err))
        return false;
    gpu_sync sync = {
        .wait = *never, .wait_value = 1, .wait_stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT};
    return gpu_cmd_submit_sync(ctx, c, &sync, err) == XRAD_OK;
}

/* Lets the stuck submission of submit_stuck run. The cleanup after it may
 * take the whole grace (5 s), not the test's 1 s wait limit: a loaded
 * machine must not turn it into a leak. */
static void release(xrad_context *ctx, VkSemaphore never)
{
    ctx->wait_timeout_ns = 60000000000ull;
    VkSemaphoreSignalInfo go = {
        .sType = VK_STRUCTURE_TYPE_SEMAPHORE_SIGNAL_INFO, .semaphore = never, .value = 1};
    CHECK(vkSignalSemaphore(ctx->device, &go) == VK_SUCCESS, "vkSignalSemaphore failed");
}

/* A real hang: the wait gives up with the context's limit and says so, the
 * context refuses later work and knows its queue has not drained; once the
 * queue moves again, everything is freed cleanly. Then a hang that never
 * ends: xrad_context_destroy returns (lavapipe's vkDestroyDevice would
 * block on the stuck queue forever: the CI run of stop 36 was killed so),
 * leaving the context to process exit. */
static void test_real_hang(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return;
    VkSemaphore never = VK_NULL_HANDLE;
    gpu_cmd c = {0};
    xrad_error err = {0};
    bool submitted = submit_stuck(ctx, &never, &c, &err);
    CHECK(submitted, "stuck submission: %s", err.message);
    if (submitted) {
        xrad_status s = gpu_cmd_wait(ctx, &c, &err);
        CHECK(s == XRAD_ERROR_SYSTEM && strstr(err.message, "VK_TIMEOUT") &&
                  strstr(err.message, "did not finish"),
              "a hung wait: status %d, %s", (int)s, err.message);
        CHECK(atomic_load(&ctx->hung) && !gpu_context_drained(ctx, 0),
              "a hung queue counts as drained");
        memset(&err, 0, sizeof(err));
        CHECK(render(ctx, &err) == XRAD_ERROR_SYSTEM && strstr(err.message, "lost earlier"),
              "render on a hung context: %s", err.message);
        release(ctx, never);
    }
    gpu_cmd_destroy(ctx, &c); /* waits (at most the grace) for the work now running */
    CHECK(gpu_context_drained(ctx, GPU_HANG_GRACE_NS), "the queue did not drain once released");
    vkDestroySemaphore(ctx->device, never, NULL);
    check_clean(ctx, "after a hang");
    gpu_test_end(&ctx);

    /* The hang that does not end (until the test ends it). */
    xrad_context *left = gpu_test_context();
    if (!left)
        return;
    memset(&err, 0, sizeof(err));
    if (!submit_stuck(left, &never, &c, &err)) {
        CHECK(0, "stuck submission: %s", err.message);
        return;
    }
    CHECK(gpu_cmd_wait(left, &c, &err) == XRAD_ERROR_SYSTEM, "the second hang was not reported");
    gpu_cmd stuck = c;
    gpu_cmd_destroy(left, &c); /* gives up after the grace */
    /* The premise of what follows: the work is still stuck when destroy
     * is called. */
    CHECK(vkGetFenceStatus(left->device, stuck.fence) == VK_NOT_READY,
          "the stuck submission finished");
    xrad_context *doomed = left;
    xrad_context_destroy(&doomed);
    CHECK(doomed == NULL, "xrad_context_destroy kept the pointer");
    /* Release the queue, then free what destroy left (the process would
     * exit here; the test checks that nothing else was leaked). */
    release(left, never);
    gpu_cmd_destroy(left, &stuck);
    vkDestroySemaphore(left->device, never, NULL);
    CHECK(xrad_context_validation_messages(left) == 0, "validation messages after a hang");
    gpu_context_free(left);
    left = NULL;
    CHECK(gpu_validation_messages_total() == 0, "%u validation messages in this process",
          gpu_validation_messages_total());
    fprintf(stderr, "a hung queue: reported, refused, freed once it moved; destroy returned "
                    "while it was stuck\n");
}

/* The environment variable reaches the same hook. */
static void test_env_rule(void)
{
    setenv("XRAD_FAULT", "vkAllocateMemory:1:VK_ERROR_OUT_OF_HOST_MEMORY", 1);
    xrad_context *ctx = gpu_test_context();
    unsetenv("XRAD_FAULT");
    if (!ctx)
        return;
    xrad_error err = {0};
    CHECK(render(ctx, &err) == XRAD_ERROR_SYSTEM &&
              strstr(err.message, "vkAllocateMemory: VK_ERROR_OUT_OF_HOST_MEMORY"),
          "XRAD_FAULT: %s", err.message);
    check_clean(ctx, "XRAD_FAULT");
    memset(&err, 0, sizeof(err));
    CHECK(render(ctx, &err) == XRAD_OK, "the rule fires once: %s", err.message);
    gpu_test_end(&ctx);
}

int main(void)
{
    xrad_error err = {0};
    if (xrad_scene_parse(scene_json, strlen(scene_json), "fault scene", &scene, &err) ||
        xrad_atlas_create(scene, &atlas, &err)) {
        CHECK(0, "scene: %s", err.message);
        return test_finish();
    }
    for (size_t i = 0; i < (size_t)atlas.width * atlas.height * 4; i++)
        atlas.rgba[i] = 1.0f;
    test_every_failure_point();
    test_device_lost("vkQueueSubmit", VK_ERROR_DEVICE_LOST, "device was lost");
    test_device_lost("vkWaitForFences", VK_ERROR_DEVICE_LOST, "device was lost");
    test_device_lost("vkWaitForFences", VK_TIMEOUT, "did not finish");
    test_real_hang();
    test_env_rule();
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
    return test_finish();
}
