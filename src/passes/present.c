#include "passes/present.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "present.frag.h"
#include "present.vert.h"
#include "shared.h"

struct present_pass {
    VkRenderPass render_pass;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkDescriptorPool pool;
    VkDescriptorSet sets[PRESENT_SLOTS];
    VkSampler sampler;
    VkPipeline pipeline;
    bool encode; /* the format stores the values as given (UNORM) */
};

xrad_status present_create(struct xrad_context *ctx, VkFormat format, VkImageLayout final_layout,
                           present_pass **out, xrad_error *err)
{
    *out = NULL;
    present_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (present pass)");
    p->encode = format != VK_FORMAT_B8G8R8A8_SRGB && format != VK_FORMAT_R8G8B8A8_SRGB;
    gpu_render_pass_desc rp = {
        .color_format = format,
        .color_final_layout = final_layout,
    };
    VkDescriptorSetLayoutBinding binding = {
        .binding = PRESENT_BINDING_SOURCE,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .descriptorCount = 1,
        .stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT,
    };
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, PRESENT_SLOTS};
    xrad_status s;
    if ((s = gpu_render_pass_create(ctx, &rp, &p->render_pass, err)) ||
        (s = gpu_descriptor_layout_create(ctx, &binding, 1, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct present_push),
                                        VK_SHADER_STAGE_FRAGMENT_BIT, &p->layout, err)) ||
        (s = gpu_descriptor_pool_create(ctx, &size, 1, PRESENT_SLOTS, &p->pool, err)) ||
        (s = gpu_sampler_create(ctx, VK_FILTER_NEAREST, &p->sampler, err)))
        goto fail;
    for (uint32_t i = 0; i < PRESENT_SLOTS; i++)
        if ((s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->sets[i], err)))
            goto fail;
    gpu_graphics_desc gd = {
        .vert = present_vert_spv,
        .vert_bytes = sizeof(present_vert_spv),
        .frag = present_frag_spv,
        .frag_bytes = sizeof(present_frag_spv),
        .cull = VK_CULL_MODE_NONE,
        .front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .color_attachments = 1,
        .layout = p->layout,
        .render_pass = p->render_pass,
    };
    if ((s = gpu_graphics_pipeline_create(ctx, &gd, &p->pipeline, err)))
        goto fail;
    *out = p;
    return XRAD_OK;

fail:
    present_destroy(ctx, &p);
    xrad_error_prefix(err, "present pass");
    return s;
}

void present_destroy(struct xrad_context *ctx, present_pass **pass)
{
    if (!pass || !*pass)
        return;
    present_pass *p = *pass;
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroySampler(ctx->device, p->sampler, NULL);
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    vkDestroyRenderPass(ctx->device, p->render_pass, NULL);
    free(p);
    *pass = NULL;
}

VkRenderPass present_render_pass(const present_pass *pass)
{
    return pass->render_pass;
}

void present_record(struct xrad_context *ctx, present_pass *pass, VkCommandBuffer cmd,
                    const present_draw *draw)
{
    VkDescriptorSet set = pass->sets[draw->slot % PRESENT_SLOTS];
    VkDescriptorImageInfo image = {
        .sampler = pass->sampler,
        .imageView = draw->source->view,
        .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
    };
    VkWriteDescriptorSet write = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = set,
        .dstBinding = PRESENT_BINDING_SOURCE,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .pImageInfo = &image,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &write, 0, NULL);
    VkClearValue clear = {.color = {.float32 = {0, 0, 0, 1}}};
    VkRenderPassBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = pass->render_pass,
        .framebuffer = draw->framebuffer,
        .renderArea = {.extent = draw->extent},
        .clearValueCount = 1,
        .pClearValues = &clear,
    };
    struct present_push push = {
        .exposure = (float)draw->exposure,
        .encode = pass->encode ? 1u : 0u,
        .tonemap = (uint32_t)draw->tonemap,
    };
    VkViewport viewport = {0, 0, (float)draw->extent.width, (float)draw->extent.height, 0, 1};
    VkRect2D scissor = {.extent = draw->extent};
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass->layout, 0, 1, &set, 0,
                            NULL);
    vkCmdPushConstants(cmd, pass->layout, VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof(push), &push);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdDraw(cmd, 3, 1, 0, 0);
    if (draw->overlay && draw->text)
        overlay_record(draw->overlay, cmd, draw->text);
    vkCmdEndRenderPass(cmd);
}
