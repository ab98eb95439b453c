/*
 * One check for every fallible Vulkan call (libplacebo's VK(), wlroots'
 * wlr_vk_error): a non-success VkResult becomes XRAD_ERROR_SYSTEM with
 * "vkCreateBuffer: VK_ERROR_OUT_OF_DEVICE_MEMORY (out of GPU memory)
 * (src/gpu/buffer.c:42)" in the caller's xrad_error. Callers branch to their
 * cleanup ladder:
 *
 *     if (VK_CHECK(ctx, err, vkCreateBuffer(ctx->device, &info, NULL, &buf)))
 *         goto fail_buffer;
 *
 * Fault injection: the context may hold one rule "the n-th checked call of
 * function F fails with result R" (env XRAD_FAULT=F:n:R, or
 * gpu_fault_set). The injected call is NOT performed, so, exactly as for a
 * real failure, nothing was created or submitted and the normal cleanup
 * ladder is correct. Waits that are skipped leave work in flight; the
 * command module drains it before freeing (gpu_cmd_destroy).
 */
#ifndef XRAD_GPU_VK_CHECK_H
#define XRAD_GPU_VK_CHECK_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "xrad.h"

struct xrad_context;

/* The rule; `function` empty means none. */
typedef struct gpu_fault {
    char function[64];
    uint32_t nth;    /* 1-based */
    VkResult result; /* what the call reports instead */
    /* Calls come from the scheduler's worker and the display thread. */
    atomic_uint calls; /* checked calls of `function` seen so far */
    atomic_bool fired;
} gpu_fault;

/* "VK_ERROR_DEVICE_LOST" for VK_ERROR_DEVICE_LOST; "VkResult(-1234)" style
 * text (in a static buffer) for codes it does not know. */
const char *gpu_result_name(VkResult r);

/* The inverse of gpu_result_name for the codes it knows. */
bool gpu_result_parse(const char *name, VkResult *out);

/* Parses "vkQueueSubmit:2:VK_ERROR_DEVICE_LOST" into a rule (calls and
 * fired zeroed). XRAD_ERROR_INPUT with the reason on a malformed spec. */
xrad_status gpu_fault_parse(const char *spec, gpu_fault *out, xrad_error *err);

/* Installs a rule on the context (function NULL clears it); counting starts
 * from zero. */
void gpu_fault_set(struct xrad_context *ctx, const char *function, uint32_t nth,
                   VkResult result);

/* True when the call whose source text is `call_text` is the one the rule
 * hits; counts the call. NULL ctx never injects. */
bool gpu_fault_take(struct xrad_context *ctx, const char *call_text);

/* The result the rule injects. */
VkResult gpu_fault_result(const struct xrad_context *ctx);

/* XRAD_OK for VK_SUCCESS; otherwise fills err (naming the function taken
 * from call_text, the result and file:line) and returns XRAD_ERROR_SYSTEM.
 * VK_ERROR_DEVICE_LOST and VK_TIMEOUT (a wait ran past the context's
 * finite limit: a hang) mark the context lost. */
xrad_status gpu_vk_report(struct xrad_context *ctx, xrad_error *err, const char *call_text,
                          VkResult result, bool injected, const char *file, int line);

/* The function name in a call's source text: the identifier before the
 * first '(' ("ctx->fn.vkFoo(a, b)" -> "vkFoo"), copied into buf. */
const char *gpu_call_name(const char *call_text, char *buf, size_t n);

#define VK_CHECK(ctx, err, call)                                                         \
    (gpu_fault_take((ctx), #call)                                                        \
         ? gpu_vk_report((ctx), (err), #call, gpu_fault_result(ctx), true, __FILE__,    \
                         __LINE__)                                                       \
         : gpu_vk_report((ctx), (err), #call, (call), false, __FILE__, __LINE__))

#endif
