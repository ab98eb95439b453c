#include "passes/integrate.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "integrate.comp.h"
#include "integrate_shared.h"
#include "passes/hemicube_geometry.h"

struct integrate_pass {
    struct xrad_context *ctx;
    uint32_t res;
    gpu_buffer table;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkImageView bound_image;
    VkBuffer bound_out;
};

xrad_status integrate_create(struct xrad_context *ctx, uint32_t res, integrate_pass **out,
                             xrad_error *err)
{
    *out = NULL;
    if (res < 8 || res > 1024 || res % 2)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "integrate: resolution must be even and in [8, 1024], got %u", res);
    integrate_pass *p = calloc(1, sizeof(*p));
    size_t n = (size_t)HEMICUBE_FACES * res * res;
    float *table = malloc(n * sizeof(float));
    if (!p || !table) {
        free(p);
        free(table);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "integrate: out of host memory");
    }
    p->ctx = ctx;
    p->res = res;
    hemicube_delta_form_factors(res, table);
    VkDescriptorSetLayoutBinding bindings[3] = {
        {INTEGRATE_BINDING_HEMICUBES, VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {INTEGRATE_BINDING_TABLE, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
        {INTEGRATE_BINDING_OUT, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_COMPUTE_BIT, NULL},
    };
    VkDescriptorPoolSize sizes[2] = {
        {VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE, 1},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
    };
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, n * sizeof(float),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               GPU_MEM_DEVICE, GPU_MEM_OTHER, &p->table, err)) ||
        (s = gpu_upload_buffer(ctx, &p->table, 0, table, n * sizeof(float), err)) ||
        (s = gpu_descriptor_layout_create(ctx, bindings, 3, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct integrate_push),
                                        VK_SHADER_STAGE_COMPUTE_BIT, &p->layout, err)) ||
        (s = gpu_compute_pipeline_create(ctx, integrate_comp_spv, sizeof(integrate_comp_spv),
                                         p->layout, NULL, &p->pipeline, err)) ||
        (s = gpu_descriptor_pool_create(ctx, sizes, 2, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err))) {
        free(table);
        integrate_destroy(ctx, &p);
        return s;
    }
    free(table);
    VkDescriptorBufferInfo bi = {p->table.buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet w = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = p->set,
        .dstBinding = INTEGRATE_BINDING_TABLE,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        .pBufferInfo = &bi,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &w, 0, NULL);
    *out = p;
    return XRAD_OK;
}

void integrate_destroy(struct xrad_context *ctx, integrate_pass **pass)
{
    if (!pass || !*pass)
        return;
    integrate_pass *p = *pass;
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    gpu_buffer_destroy(ctx, &p->table);
    free(p);
    *pass = NULL;
}

const gpu_buffer *integrate_table(const integrate_pass *pass) { return &pass->table; }

void integrate_record(integrate_pass *p, VkCommandBuffer cmd, const integrate_draw *d)
{
    if (d->count == 0)
        return;
    if (p->bound_image != d->hemicubes || p->bound_out != d->out->buffer) {
        VkDescriptorImageInfo ii = {VK_NULL_HANDLE, d->hemicubes,
                                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
        VkDescriptorBufferInfo bi = {d->out->buffer, 0, VK_WHOLE_SIZE};
        VkWriteDescriptorSet w[2] = {
            {
                .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                .dstSet = p->set,
                .dstBinding = INTEGRATE_BINDING_HEMICUBES,
                .descriptorCount = 1,
                .descriptorType = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE,
                .pImageInfo = &ii,
            },
            {
                .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                .dstSet = p->set,
                .dstBinding = INTEGRATE_BINDING_OUT,
                .descriptorCount = 1,
                .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                .pBufferInfo = &bi,
            },
        };
        vkUpdateDescriptorSets(p->ctx->device, 2, w, 0, NULL);
        p->bound_image = d->hemicubes;
        p->bound_out = d->out->buffer;
    }
    struct integrate_push push = {
        .res = p->res,
        .out_first = d->out_first,
        .count = d->count,
        .inv_scale = d->scale > 0 ? 1.0f / d->scale : 1.0f,
        .moments = d->moments,
        .moments_first = d->moments_first,
    };
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, p->layout, 0, 1, &p->set, 0,
                            NULL);
    vkCmdPushConstants(cmd, p->layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(push), &push);
    vkCmdDispatch(cmd, d->count, 1, 1);
}
