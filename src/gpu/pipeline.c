#include "gpu/pipeline.h"

#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

#define MAX_COLOR_ATTACHMENTS 8

xrad_status gpu_shader_module_create(struct xrad_context *ctx, const uint32_t *words,
                                     size_t bytes, VkShaderModule *out, xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    if (bytes == 0 || bytes % 4 || words[0] != 0x07230203u)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "embedded shader is not SPIR-V (%zu bytes)",
                         bytes);
    VkShaderModuleCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = bytes,
        .pCode = words,
    };
    return VK_CHECK(ctx, err, vkCreateShaderModule(ctx->device, &info, NULL, out));
}

xrad_status gpu_descriptor_layout_create(struct xrad_context *ctx,
                                         const VkDescriptorSetLayoutBinding *bindings,
                                         uint32_t count, VkDescriptorSetLayout *out,
                                         xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkDescriptorSetLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = count,
        .pBindings = bindings,
    };
    return VK_CHECK(ctx, err, vkCreateDescriptorSetLayout(ctx->device, &info, NULL, out));
}

xrad_status gpu_pipeline_layout_create(struct xrad_context *ctx,
                                       const VkDescriptorSetLayout *sets, uint32_t set_count,
                                       uint32_t push_bytes, VkShaderStageFlags push_stages,
                                       VkPipelineLayout *out, xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    if (push_bytes > ctx->props.limits.maxPushConstantsSize)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "push constants of %u bytes exceed the device limit of %u", push_bytes,
                         ctx->props.limits.maxPushConstantsSize);
    VkPushConstantRange push = {.stageFlags = push_stages, .offset = 0, .size = push_bytes};
    VkPipelineLayoutCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = set_count,
        .pSetLayouts = sets,
        .pushConstantRangeCount = push_bytes ? 1 : 0,
        .pPushConstantRanges = &push,
    };
    return VK_CHECK(ctx, err, vkCreatePipelineLayout(ctx->device, &info, NULL, out));
}

xrad_status gpu_descriptor_pool_create(struct xrad_context *ctx,
                                       const VkDescriptorPoolSize *sizes, uint32_t count,
                                       uint32_t max_sets, VkDescriptorPool *out,
                                       xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkDescriptorPoolCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = max_sets,
        .poolSizeCount = count,
        .pPoolSizes = sizes,
    };
    return VK_CHECK(ctx, err, vkCreateDescriptorPool(ctx->device, &info, NULL, out));
}

xrad_status gpu_descriptor_set_allocate(struct xrad_context *ctx, VkDescriptorPool pool,
                                        VkDescriptorSetLayout layout, VkDescriptorSet *out,
                                        xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkDescriptorSetAllocateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &layout,
    };
    return VK_CHECK(ctx, err, vkAllocateDescriptorSets(ctx->device, &info, out));
}

xrad_status gpu_compute_pipeline_create(struct xrad_context *ctx, const uint32_t *words,
                                        size_t bytes, VkPipelineLayout layout,
                                        const VkSpecializationInfo *spec, VkPipeline *out,
                                        xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkShaderModule module;
    xrad_status s = gpu_shader_module_create(ctx, words, bytes, &module, err);
    if (s)
        return s;
    VkComputePipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage = {
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = VK_SHADER_STAGE_COMPUTE_BIT,
            .module = module,
            .pName = "main",
            .pSpecializationInfo = spec,
        },
        .layout = layout,
    };
    s = VK_CHECK(ctx, err,
                 vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &info, NULL, out));
    vkDestroyShaderModule(ctx->device, module, NULL);
    return s;
}

xrad_status gpu_graphics_pipeline_create(struct xrad_context *ctx, const gpu_graphics_desc *d,
                                         VkPipeline *out, xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    if (d->color_attachments > MAX_COLOR_ATTACHMENTS)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "graphics pipeline: %u colour attachments",
                         d->color_attachments);
    VkShaderModule vert, frag = VK_NULL_HANDLE;
    xrad_status s = gpu_shader_module_create(ctx, d->vert, d->vert_bytes, &vert, err);
    if (s)
        return s;
    if (d->frag && (s = gpu_shader_module_create(ctx, d->frag, d->frag_bytes, &frag, err)))
        goto fail_frag;
    VkPipelineShaderStageCreateInfo stages[2] = {
        {
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = VK_SHADER_STAGE_VERTEX_BIT,
            .module = vert,
            .pName = "main",
            .pSpecializationInfo = d->vert_spec,
        },
        {
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
            .module = frag,
            .pName = "main",
            .pSpecializationInfo = d->frag_spec,
        },
    };
    VkPipelineVertexInputStateCreateInfo vertex = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = d->binding_count,
        .pVertexBindingDescriptions = d->bindings,
        .vertexAttributeDescriptionCount = d->attribute_count,
        .pVertexAttributeDescriptions = d->attributes,
    };
    VkPipelineInputAssemblyStateCreateInfo assembly = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = d->topology ? d->topology : VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST,
    };
    VkPipelineViewportStateCreateInfo viewport = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .scissorCount = 1,
    };
    VkPipelineRasterizationStateCreateInfo raster = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = d->cull,
        .frontFace = d->front_face,
        .lineWidth = 1.0f,
    };
    VkPipelineMultisampleStateCreateInfo multisample = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = d->samples ? d->samples : VK_SAMPLE_COUNT_1_BIT,
    };
    VkPipelineDepthStencilStateCreateInfo depth = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = d->depth_test,
        .depthWriteEnable = d->depth_write,
        .depthCompareOp = d->depth_compare,
    };
    VkPipelineColorBlendAttachmentState attachments[MAX_COLOR_ATTACHMENTS];
    for (uint32_t i = 0; i < d->color_attachments; i++)
        attachments[i] = (VkPipelineColorBlendAttachmentState){
            .blendEnable = d->blend,
            .srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA,
            .dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
            .colorBlendOp = VK_BLEND_OP_ADD,
            .srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE,
            .dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA,
            .alphaBlendOp = VK_BLEND_OP_ADD,
            .colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT |
                              VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT,
        };
    VkPipelineColorBlendStateCreateInfo blend = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = d->color_attachments,
        .pAttachments = attachments,
    };
    const VkDynamicState dynamic_states[] = {VK_DYNAMIC_STATE_VIEWPORT,
                                             VK_DYNAMIC_STATE_SCISSOR};
    VkPipelineDynamicStateCreateInfo dynamic = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO,
        .dynamicStateCount = 2,
        .pDynamicStates = dynamic_states,
    };
    VkGraphicsPipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .stageCount = d->frag ? 2 : 1,
        .pStages = stages,
        .pVertexInputState = &vertex,
        .pInputAssemblyState = &assembly,
        .pViewportState = &viewport,
        .pRasterizationState = &raster,
        .pMultisampleState = &multisample,
        .pDepthStencilState = &depth,
        .pColorBlendState = &blend,
        .pDynamicState = &dynamic,
        .layout = d->layout,
        .renderPass = d->render_pass,
        .subpass = d->subpass,
    };
    s = VK_CHECK(ctx, err,
                 vkCreateGraphicsPipelines(ctx->device, VK_NULL_HANDLE, 1, &info, NULL, out));
    vkDestroyShaderModule(ctx->device, frag, NULL);
fail_frag:
    vkDestroyShaderModule(ctx->device, vert, NULL);
    return s;
}

xrad_status gpu_render_pass_create(struct xrad_context *ctx, const gpu_render_pass_desc *desc,
                                   VkRenderPass *out, xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkSampleCountFlagBits samples = desc->samples ? desc->samples : VK_SAMPLE_COUNT_1_BIT;
    VkAttachmentDescription att[2] = {
        {
            .format = desc->color_format,
            .samples = samples,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
            .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
            .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .finalLayout = desc->color_final_layout,
        },
        {
            .format = desc->depth_format,
            .samples = samples,
            .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
            .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
            .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
            .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
            .finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        },
    };
    VkAttachmentReference color = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription subpass = {
        .pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
        .colorAttachmentCount = 1,
        .pColorAttachments = &color,
        .pDepthStencilAttachment = desc->depth_format ? &depth : NULL,
    };
    const VkPipelineStageFlags attach = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                        VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    const VkPipelineStageFlags readers = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                         VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                                         VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkSubpassDependency deps[2] = {
        /* Earlier draws into the targets, and everyone who read them
         * (integrate, reconstruct, resolves, copies), come first. */
        {
            .srcSubpass = VK_SUBPASS_EXTERNAL,
            .dstSubpass = 0,
            .srcStageMask = attach | readers,
            .dstStageMask = attach,
            .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                             VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                             VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                             VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                             VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT,
        },
        /* The images are read next: sampled, resolved or copied. */
        {
            .srcSubpass = 0,
            .dstSubpass = VK_SUBPASS_EXTERNAL,
            .srcStageMask = attach,
            .dstStageMask = readers,
            .srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                             VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
            .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT,
        },
    };
    VkRenderPassMultiviewCreateInfo multiview = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_MULTIVIEW_CREATE_INFO,
        .subpassCount = 1,
        .pViewMasks = &desc->view_mask,
        .correlationMaskCount = 1,
        .pCorrelationMasks = &desc->view_mask,
    };
    VkRenderPassCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
        .pNext = desc->view_mask ? &multiview : NULL,
        .attachmentCount = desc->depth_format ? 2 : 1,
        .pAttachments = att,
        .subpassCount = 1,
        .pSubpasses = &subpass,
        .dependencyCount = 2,
        .pDependencies = deps,
    };
    return VK_CHECK(ctx, err, vkCreateRenderPass(ctx->device, &info, NULL, out));
}
