/*
 * Helpers for GPU tests: a context with validation on, and the end check
 * every GPU test finishes with: no validation message while the context
 * lived, none while it was destroyed (the layer reports leaked objects at
 * vkDestroyDevice), no GPU memory left allocated.
 */
#ifndef XRAD_TESTS_GPU_TEST_H
#define XRAD_TESTS_GPU_TEST_H

#include "gpu/context.h"
#include "gpu/memory.h"
#include "harness.h"
#include "xrad.h"

/* A validated context on the default device, or the one XRAD_DEVICE names
 * (the XRAD_* environment, as the tools apply it); NULL (after a failed
 * CHECK) when none can be made. */
static inline xrad_context *gpu_test_context(void)
{
    xrad_context *ctx = NULL;
    xrad_error err = {0};
    xrad_context_desc d = {.validation = 1};
    xrad_status s = xrad_context_desc_from_env(&d, &err);
    if (!s)
        s = xrad_context_create(&d, &ctx, &err);
    CHECK(s == XRAD_OK, "xrad_context_create: %s", err.message);
    return ctx;
}

/* Destroys *ctx and checks the three conditions above. */
static inline void gpu_test_end(xrad_context **ctx)
{
    if (*ctx) {
        gpu_memory_stats st;
        gpu_memory_get_stats(*ctx, &st);
        CHECK(st.allocations == 0 && st.blocks == 0,
              "%u GPU allocations in %u blocks left at the end", st.allocations, st.blocks);
        CHECK(xrad_context_validation_messages(*ctx) == 0, "%u validation messages",
              xrad_context_validation_messages(*ctx));
    }
    xrad_context_destroy(ctx);
    CHECK(gpu_validation_messages_total() == 0,
          "%u validation messages in this process, destruction included",
          gpu_validation_messages_total());
}

#endif
