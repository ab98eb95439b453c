/* Context creation with validation, device naming and listing, device
 * selection errors, the XRAD_FAULT syntax. */
#include <stdlib.h>
#include <string.h>

#include "gpu/vk_check.h"
#include "gpu_test.h"

typedef struct listing {
    int count;
    int found_chosen;
    const char *chosen;
} listing;

static void on_device(void *user, const xrad_device_info *info)
{
    listing *l = user;
    l->count++;
    CHECK(info->name[0] != '\0', "device %d has no name", l->count);
    CHECK(info->type && info->type[0], "device type");
    CHECK(info->api_version >= VK_API_VERSION_1_0, "api version");
    if (l->chosen && !strcmp(info->name, l->chosen))
        l->found_chosen = 1;
}

static void test_devices_and_names(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return;
    const char *name = xrad_context_device_name(ctx);
    CHECK(name && name[0], "device name empty");
    fprintf(stderr, "device: %s\n", name);
    const gpu_features *f = &ctx->features;
    fprintf(stderr,
            "features: timeline %d multiview %d (%u views) output_layer %d sync2 %d "
            "host_query_reset %d atomic_float_add %d memory_budget %d timestamps %d "
            "(%.3g ns/tick, %u bits) subgroup %u\n",
            f->timeline_semaphore, f->multiview, f->multiview_max_views, f->shader_output_layer,
            f->synchronization2, f->host_query_reset, f->shader_float32_atomic_add,
            f->memory_budget, f->timestamps, f->timestamp_period, f->timestamp_valid_bits,
            f->subgroup_size);
    CHECK(ctx->validation, "validation requested but not on");

    listing l = {.chosen = name};
    xrad_error err = {0};
    CHECK(xrad_devices_list(on_device, &l, &err) == XRAD_OK, "xrad_devices_list: %s",
          err.message);
    CHECK(l.count >= 1, "no devices listed");
    CHECK(l.found_chosen, "the chosen device '%s' is not in the list", name);

    /* Asking for the chosen device by a substring of its name finds it. */
    char part[8];
    snprintf(part, sizeof(part), "%s", name);
    xrad_context *again = NULL;
    CHECK(xrad_context_create(&(xrad_context_desc){.device = part, .validation = 1}, &again,
                              &err) == XRAD_OK,
          "by name '%s': %s", part, err.message);
    if (again) {
        CHECK(!strcmp(xrad_context_device_name(again), name), "by name picked %s",
              xrad_context_device_name(again));
        CHECK(xrad_context_validation_messages(again) == 0, "validation messages");
        xrad_context_destroy(&again);
    }
    gpu_test_end(&ctx);
}

/* xrad_context_create as the tools make it: the XRAD_* environment
 * applied. */
static xrad_status create_from_env(xrad_context **ctx, xrad_error *err)
{
    xrad_context_desc d = {.validation = 1};
    xrad_status s = xrad_context_desc_from_env(&d, err);
    return s ? s : xrad_context_create(&d, ctx, err);
}

static void test_unknown_device(void)
{
    xrad_context *ctx = NULL;
    xrad_error err = {0};
    xrad_status s = xrad_context_create(
        &(xrad_context_desc){.device = "no-such-device-xyz", .validation = 1}, &ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT, "unknown device: status %d (%s)", (int)s, err.message);
    CHECK(ctx == NULL, "context returned on failure");
    CHECK(strstr(err.message, "no-such-device-xyz") && strstr(err.message, "available"),
          "message should name the request and the available devices: %s", err.message);

    /* The same through the environment, where the caller applies it; the
     * library itself reads none. */
    setenv("XRAD_DEVICE", "no-such-device-xyz", 1);
    memset(&err, 0, sizeof(err));
    s = create_from_env(&ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT, "XRAD_DEVICE unknown: status %d (%s)", (int)s, err.message);
    s = xrad_context_create(&(xrad_context_desc){.validation = 1}, &ctx, &err);
    CHECK(s == XRAD_OK, "XRAD_DEVICE read by the library itself: %s", err.message);
    gpu_test_end(&ctx);
    unsetenv("XRAD_DEVICE");
    /* A desc's own device wins over the environment. */
    setenv("XRAD_DEVICE", "no-such-device-xyz", 1);
    xrad_context_desc d = {.device = "llvmpipe-or-any", .validation = 1};
    CHECK(xrad_context_desc_from_env(&d, &err) == XRAD_OK && !strcmp(d.device, "llvmpipe-or-any"),
          "from_env replaced the desc's device: %s", d.device);
    unsetenv("XRAD_DEVICE");
    /* A malformed memory limit is named. */
    setenv("XRAD_GPU_MEMORY_MIB", "lots", 1);
    d = (xrad_context_desc){0};
    s = xrad_context_desc_from_env(&d, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "XRAD_GPU_MEMORY_MIB") &&
              strstr(err.message, "lots"),
          "status %d: %s", (int)s, err.message);
    unsetenv("XRAD_GPU_MEMORY_MIB");
    s = xrad_context_create(&(xrad_context_desc){.memory_limit_mib = -1}, &ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "memory_limit_mib") && !ctx,
          "negative memory limit: status %d: %s", (int)s, err.message);
}

/* Messages go to the context's log callback. */
typedef struct log_seen {
    int calls;
    xrad_log_level level;
    char text[128];
} log_seen;

static void on_log(void *user, xrad_log_level level, const char *message)
{
    log_seen *seen = user;
    seen->calls++;
    seen->level = level;
    snprintf(seen->text, sizeof(seen->text), "%s", message);
}

static void test_log(void)
{
    log_seen seen = {0};
    xrad_context *ctx = NULL;
    xrad_error err = {0};
    xrad_status s = xrad_context_create(
        &(xrad_context_desc){.validation = 1, .log = on_log, .log_user = &seen}, &ctx, &err);
    CHECK(s == XRAD_OK, "context with a log: %s", err.message);
    if (s)
        return;
    gpu_log(ctx, XRAD_LOG_WARNING, "test %d", 42);
    CHECK(seen.calls == 1 && seen.level == XRAD_LOG_WARNING && !strcmp(seen.text, "test 42"),
          "log callback: %d calls, level %d, '%s'", seen.calls, (int)seen.level, seen.text);
    gpu_test_end(&ctx);
    CHECK(seen.calls == 1, "%d messages logged while the context lived and ended", seen.calls);
}

static void test_fault_syntax(void)
{
    gpu_fault f;
    xrad_error err = {0};
    CHECK(gpu_fault_parse("vkQueueSubmit:2:VK_ERROR_DEVICE_LOST", &f, &err) == XRAD_OK,
          "valid spec: %s", err.message);
    CHECK(!strcmp(f.function, "vkQueueSubmit") && f.nth == 2 &&
              f.result == VK_ERROR_DEVICE_LOST,
          "parsed %s %u %d", f.function, f.nth, (int)f.result);
    const char *bad[] = {"vkQueueSubmit", "vkQueueSubmit:0:VK_ERROR_DEVICE_LOST",
                         "vkQueueSubmit:x:VK_ERROR_DEVICE_LOST", ":1:VK_ERROR_DEVICE_LOST",
                         "vkQueueSubmit:1:VK_SUCCESS", "vkQueueSubmit:1:VK_ERROR_NOPE"};
    for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
        CHECK(gpu_fault_parse(bad[i], &f, &err) == XRAD_ERROR_INPUT, "accepted '%s'", bad[i]);

    char name[64];
    CHECK(!strcmp(gpu_call_name("ctx->fn.vkFoo(a, b(c))", name, sizeof(name)), "vkFoo"),
          "call name %s", name);

    /* A malformed XRAD_FAULT is an input error naming it; the desc's own
     * fault one naming the spec. */
    setenv("XRAD_FAULT", "garbage", 1);
    xrad_context *ctx = NULL;
    memset(&err, 0, sizeof(err));
    xrad_status s = create_from_env(&ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "XRAD_FAULT"), "status %d: %s", (int)s,
          err.message);
    s = xrad_context_create(&(xrad_context_desc){.fault = "garbage"}, &ctx, &err);
    CHECK(s == XRAD_ERROR_INPUT && strstr(err.message, "garbage") && !ctx, "status %d: %s",
          (int)s, err.message);
    /* One in context creation itself is reported as a system error. */
    setenv("XRAD_FAULT", "vkCreateDevice:1:VK_ERROR_INITIALIZATION_FAILED", 1);
    memset(&err, 0, sizeof(err));
    s = create_from_env(&ctx, &err);
    CHECK(s == XRAD_ERROR_SYSTEM && strstr(err.message, "vkCreateDevice") &&
              strstr(err.message, "VK_ERROR_INITIALIZATION_FAILED"),
          "status %d: %s", (int)s, err.message);
    CHECK(ctx == NULL, "context returned on failure");
    unsetenv("XRAD_FAULT");
}

int main(void)
{
    if (!getenv("XRAD_VALIDATION"))
        fprintf(stderr, "note: XRAD_VALIDATION unset; the test enables validation itself\n");
    test_devices_and_names();
    test_unknown_device();
    test_fault_syntax();
    test_log();
    CHECK(gpu_validation_messages_total() == 0, "%u validation messages in total",
          gpu_validation_messages_total());
    return test_finish();
}
