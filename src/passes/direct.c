#include "passes/direct.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "direct.comp.h"
#include "direct_shared.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "scene/quad_bvh.h"

/* Loop iterations an invocation may run on lavapipe before every loop
 * of it stops after one more (LP_MAX_TGSI_LOOP_ITERATIONS, all loops
 * together); a dispatch takes as many lights as fit in half of it. */
#define LOOP_LIMIT 65535u

struct direct_pass {
    struct xrad_context *ctx;
    uint32_t light_count;
    gpu_buffer lights; /* uint[light_count] (one entry when there are none) */
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
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
    VkDescriptorSetLayoutBinding bindings[DIRECT_BINDINGS];
    for (uint32_t b = 0; b < DIRECT_BINDINGS; b++)
        bindings[b] = (VkDescriptorSetLayoutBinding){b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
                                                     VK_SHADER_STAGE_COMPUTE_BIT, NULL};
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, DIRECT_BINDINGS};
    uint32_t none = 0;
    size_t bytes = (light_count ? light_count : 1) * sizeof(uint32_t);
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, bytes,
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &p->lights, err)) ||
        (s = gpu_upload_buffer(ctx, &p->lights, 0, light_count ? lights : &none, bytes, err)) ||
        (s = gpu_descriptor_layout_create(ctx, bindings, DIRECT_BINDINGS, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct direct_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, direct_comp_spv, sizeof(direct_comp_spv),
                                         p->layout, NULL, &p->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, &size, 1, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
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
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    gpu_buffer_destroy(ctx, &p->lights);
    free(p);
    *pass = NULL;
}

void direct_record(direct_pass *p, VkCommandBuffer cmd, const direct_draw *d)
{
    if (d->count == 0)
        return;
    const VkBuffer want[DIRECT_BINDINGS] = {
        [DIRECT_BINDING_SURFACES] = d->surfaces->buffer,
        [DIRECT_BINDING_MATERIALS] = d->materials->buffer,
        [DIRECT_BINDING_FRAMES] = d->frames->buffer,
        [DIRECT_BINDING_LIGHTS] = p->lights.buffer,
        [DIRECT_BINDING_OUT] = d->out->buffer,
        [DIRECT_BINDING_BVH_NODES] = d->bvh_nodes->buffer,
        [DIRECT_BINDING_BVH_ITEMS] = d->bvh_items->buffer,
    };
    if (memcmp(want, p->bound, sizeof(want))) {
        VkDescriptorBufferInfo bi[DIRECT_BINDINGS];
        VkWriteDescriptorSet w[DIRECT_BINDINGS];
        for (uint32_t b = 0; b < DIRECT_BINDINGS; b++) {
            bi[b] = (VkDescriptorBufferInfo){want[b], 0, VK_WHOLE_SIZE};
            w[b] = (VkWriteDescriptorSet){
                .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                .dstSet = p->set,
                .dstBinding = b,
                .descriptorCount = 1,
                .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                .pBufferInfo = &bi[b],
            };
        }
        vkUpdateDescriptorSets(p->ctx->device, DIRECT_BINDINGS, w, 0, NULL);
        memcpy(p->bound, want, sizeof(want));
    }
    uint32_t per_dispatch = direct_lights_per_dispatch(d->bvh_depth);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
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
        vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
        vkCmdDispatch(cmd, (d->count + DIRECT_GROUP - 1) / DIRECT_GROUP, 1, 1);
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
