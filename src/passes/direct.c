#include "passes/direct.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "direct.comp.h"
#include "direct_shared.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "scene/quad_bvh.h"

/* Loop iterations an invocation may run on lavapipe before every loop
 * of it stops after one more (LP_MAX_TGSI_LOOP_ITERATIONS, all loops
 * together); a dispatch takes as many lights as fit in half of it. */
#define LOOP_LIMIT 65535u

struct direct_pass {
    struct xrad_context *ctx;
    uint32_t light_count;
    gpu_buffer lights; /* uint[light_count] (one entry when there are none) */
    gpu_kernel kernel;
    VkBuffer bound[DIRECT_BINDINGS];
};

xrad_status direct_create(struct xrad_context *ctx, const uint32_t *lights, uint32_t light_count,
                          direct_pass **out, xrad_error *err)
{
    *out = NULL;
    direct_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "direct light pass: out of host memory");
    p->ctx = ctx;
    p->light_count = light_count;
    VkDescriptorType types[DIRECT_BINDINGS];
    for (uint32_t b = 0; b < DIRECT_BINDINGS; b++)
        types[b] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc kd = {
        .spv = direct_comp_spv,
        .spv_bytes = sizeof(direct_comp_spv),
        .types = types,
        .binding_count = DIRECT_BINDINGS,
        .push_bytes = sizeof(struct direct_push),
        .name = "direct light pass",
    };
    uint32_t none = 0;
    size_t bytes = (light_count ? light_count : 1) * sizeof(uint32_t);
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, bytes,
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &p->lights, err)) ||
        (s = gpu_upload_buffer(ctx, &p->lights, 0, light_count ? lights : &none, bytes, err)) ||
        (s = gpu_kernel_create(ctx, &kd, &p->kernel, err))) {
        direct_destroy(ctx, &p);
        xrad_error_prefix(err, "direct light pass");
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void direct_destroy(struct xrad_context *ctx, direct_pass **pass)
{
    if (!pass || !*pass)
        return;
    direct_pass *p = *pass;
    gpu_kernel_destroy(ctx, &p->kernel);
    gpu_buffer_destroy(ctx, &p->lights);
    free(p);
    *pass = NULL;
}

void direct_record(direct_pass *p, VkCommandBuffer cmd, const direct_draw *d)
{
    if (d->count == 0)
        return;
    const gpu_kernel_resource r[DIRECT_BINDINGS] = {
        [DIRECT_BINDING_SURFACES] = {d->surfaces}, [DIRECT_BINDING_MATERIALS] = {d->materials},
        [DIRECT_BINDING_FRAMES] = {d->frames},     [DIRECT_BINDING_LIGHTS] = {&p->lights},
        [DIRECT_BINDING_OUT] = {d->out},           [DIRECT_BINDING_BVH_NODES] = {d->bvh_nodes},
        [DIRECT_BINDING_BVH_ITEMS] = {d->bvh_items},
    };
    VkBuffer want[DIRECT_BINDINGS];
    for (uint32_t b = 0; b < DIRECT_BINDINGS; b++)
        want[b] = r[b].buffer->buffer;
    if (memcmp(want, p->bound, sizeof(want))) {
        gpu_kernel_bind(p->ctx, &p->kernel, 0, r);
        memcpy(p->bound, want, sizeof(want));
    }
    uint32_t per_dispatch = direct_lights_per_dispatch(d->bvh_depth);
    uint32_t first = 0;
    do {
        uint32_t n =
            p->light_count - first < per_dispatch ? p->light_count - first : per_dispatch;
        struct direct_push push = {.first = d->first, .count = d->count, .light_first = first,
                                   .light_count = n, .accumulate = first ? 1u : 0u};
        if (first) /* this chunk adds to what the last one wrote */
            gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                               VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                               VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, d->count, DIRECT_GROUP);
        first += n;
    } while (first < p->light_count);
}

uint32_t direct_lights_per_dispatch(uint32_t bvh_depth)
{
    /* A light's segments at most: the (n + 1)^2 corners and n^2 blocks
     * at n = DIRECT_MAX_BLOCKS, and the DIRECT_SPLIT^2 parts of 2 n
     * blocks in a penumbra (a shadow's edge across the light); each a
     * walk of about 4 steps a level of the hierarchy (the boxes the
     * segment meets and their siblings) and a leaf's surfaces. */
    uint32_t n = DIRECT_MAX_BLOCKS;
    uint32_t segments = (n + 1) * (n + 1) + n * n + 2 * n * DIRECT_SPLIT * DIRECT_SPLIT;
    uint32_t per_light = segments * (4 * bvh_depth + QUAD_BVH_LEAF + 1);
    uint32_t k = LOOP_LIMIT / 2 / per_light;
    return k ? k : 1;
}
