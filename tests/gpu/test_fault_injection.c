/*
 * Injected Vulkan failures during a render end in XRAD_ERROR_SYSTEM with a
 * message naming the call and the result, and leave no GPU memory, no
 * Vulkan object (the validation layer reports leaks at vkDestroyDevice) and
 * no validation message behind; nothing crashes or hangs. An out-of-memory
 * failure leaves the context usable; a lost device does not.
 */
#include <stdlib.h>
#include <string.h>

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
    test_env_rule();
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
    return test_finish();
}
