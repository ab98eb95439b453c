#include "gpu/vk_check.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

#define RESULT(name) {name, #name}

static const struct {
    VkResult value;
    const char *name;
} results[] = {
    RESULT(VK_SUCCESS),
    RESULT(VK_NOT_READY),
    RESULT(VK_TIMEOUT),
    RESULT(VK_EVENT_SET),
    RESULT(VK_EVENT_RESET),
    RESULT(VK_INCOMPLETE),
    RESULT(VK_ERROR_OUT_OF_HOST_MEMORY),
    RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY),
    RESULT(VK_ERROR_INITIALIZATION_FAILED),
    RESULT(VK_ERROR_DEVICE_LOST),
    RESULT(VK_ERROR_MEMORY_MAP_FAILED),
    RESULT(VK_ERROR_LAYER_NOT_PRESENT),
    RESULT(VK_ERROR_EXTENSION_NOT_PRESENT),
    RESULT(VK_ERROR_FEATURE_NOT_PRESENT),
    RESULT(VK_ERROR_INCOMPATIBLE_DRIVER),
    RESULT(VK_ERROR_TOO_MANY_OBJECTS),
    RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED),
    RESULT(VK_ERROR_FRAGMENTED_POOL),
    RESULT(VK_ERROR_UNKNOWN),
    RESULT(VK_ERROR_OUT_OF_POOL_MEMORY),
    RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE),
    RESULT(VK_ERROR_FRAGMENTATION),
    RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS),
    RESULT(VK_PIPELINE_COMPILE_REQUIRED),
    RESULT(VK_ERROR_SURFACE_LOST_KHR),
    RESULT(VK_ERROR_NATIVE_WINDOW_IN_USE_KHR),
    RESULT(VK_SUBOPTIMAL_KHR),
    RESULT(VK_ERROR_OUT_OF_DATE_KHR),
    RESULT(VK_ERROR_VALIDATION_FAILED_EXT),
};

const char *gpu_result_name(VkResult r)
{
    for (size_t i = 0; i < sizeof(results) / sizeof(results[0]); i++)
        if (results[i].value == r)
            return results[i].name;
    static _Thread_local char buf[32];
    snprintf(buf, sizeof(buf), "VkResult(%d)", (int)r);
    return buf;
}

bool gpu_result_parse(const char *name, VkResult *out)
{
    for (size_t i = 0; i < sizeof(results) / sizeof(results[0]); i++) {
        if (!strcmp(results[i].name, name)) {
            *out = results[i].value;
            return true;
        }
    }
    return false;
}

/* What a person should take from the three results that end runs. */
static const char *explain(VkResult r)
{
    switch (r) {
    case VK_ERROR_DEVICE_LOST:
        return " (the GPU device was lost: driver reset, hang or crash; this context can no "
               "longer be used)";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return " (out of GPU memory: use a smaller scene, fewer elements or smaller images)";
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return " (out of host memory)";
    case VK_TIMEOUT:
        return " (the GPU did not finish within the wait limit; it may be hung)";
    default:
        return "";
    }
}

/* meson passes __FILE__ relative to the build directory ("../src/gpu/x.c"). */
static const char *source_path(const char *file)
{
    while (!strncmp(file, "../", 3))
        file += 3;
    return file;
}

const char *gpu_call_name(const char *call_text, char *buf, size_t n)
{
    const char *paren = strchr(call_text, '(');
    const char *end = paren ? paren : call_text + strlen(call_text);
    const char *start = end;
    while (start > call_text && (isalnum((unsigned char)start[-1]) || start[-1] == '_'))
        start--;
    size_t len = (size_t)(end - start);
    if (len >= n)
        len = n - 1;
    memcpy(buf, start, len);
    buf[len] = '\0';
    return buf;
}

xrad_status gpu_fault_parse(const char *spec, gpu_fault *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    const char *c1 = strchr(spec, ':');
    const char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!c1 || !c2 || c1 == spec || (size_t)(c1 - spec) >= sizeof(out->function))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "fault '%s': expected <vkFunction>:<nth call>:<VK_ERROR_NAME>", spec);
    memcpy(out->function, spec, (size_t)(c1 - spec));
    out->function[c1 - spec] = '\0';
    char *end;
    errno = 0;
    unsigned long nth = strtoul(c1 + 1, &end, 10);
    if (end != c2 || errno || nth == 0 || nth > UINT32_MAX)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "fault '%s': the call number must be an integer >= 1", spec);
    out->nth = (uint32_t)nth;
    if (!gpu_result_parse(c2 + 1, &out->result) || out->result == VK_SUCCESS)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "fault '%s': unknown or non-error result '%s' (e.g. "
                         "VK_ERROR_DEVICE_LOST, VK_ERROR_OUT_OF_DEVICE_MEMORY)",
                         spec, c2 + 1);
    return XRAD_OK;
}

void gpu_fault_set(struct xrad_context *ctx, const char *function, uint32_t nth, VkResult result)
{
    memset(&ctx->fault, 0, sizeof(ctx->fault));
    if (!function)
        return;
    snprintf(ctx->fault.function, sizeof(ctx->fault.function), "%s", function);
    ctx->fault.nth = nth;
    ctx->fault.result = result;
}

bool gpu_fault_take(struct xrad_context *ctx, const char *call_text)
{
    if (!ctx || !ctx->fault.function[0] || atomic_load(&ctx->fault.fired))
        return false;
    char name[64];
    if (strcmp(gpu_call_name(call_text, name, sizeof(name)), ctx->fault.function))
        return false;
    if (atomic_fetch_add(&ctx->fault.calls, 1) + 1 != ctx->fault.nth)
        return false;
    /* One call fires, whichever thread makes it. */
    return !atomic_exchange(&ctx->fault.fired, true);
}

VkResult gpu_fault_result(const struct xrad_context *ctx)
{
    return ctx->fault.result;
}

xrad_status gpu_vk_report(struct xrad_context *ctx, xrad_error *err, const char *call_text,
                          VkResult result, bool injected, const char *file, int line)
{
    if (result == VK_SUCCESS)
        return XRAD_OK;
    /* xrad waits only with finite timeouts, so a timeout means a hang. */
    if (ctx && (result == VK_ERROR_DEVICE_LOST || result == VK_TIMEOUT))
        atomic_store(&ctx->lost, true);
    if (ctx && result == VK_TIMEOUT)
        atomic_store(&ctx->hung, true);
    char name[64];
    return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: %s%s (%s:%d)%s",
                     gpu_call_name(call_text, name, sizeof(name)), gpu_result_name(result),
                     explain(result), source_path(file), line,
                     injected ? " [injected by XRAD_FAULT]" : "");
}
