/* Pipelines from embedded SPIR-V words (spirv/meson.build makes each shader
 * a `const uint32_t name_spv[]`), descriptor set layouts, pipeline layouts
 * with push constants, descriptor pools. Every function returns a status
 * and leaves its output VK_NULL_HANDLE on failure. */
#ifndef XRAD_GPU_PIPELINE_H
#define XRAD_GPU_PIPELINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "xrad.h"

struct xrad_context;

/* `bytes`: sizeof the word array (a multiple of 4). */
xrad_status gpu_shader_module_create(struct xrad_context *ctx, const uint32_t *words,
                                     size_t bytes, VkShaderModule *out, xrad_error *err);

xrad_status gpu_descriptor_layout_create(struct xrad_context *ctx,
                                         const VkDescriptorSetLayoutBinding *bindings,
                                         uint32_t count, VkDescriptorSetLayout *out,
                                         xrad_error *err);

/* push_bytes 0: no push constants. */
xrad_status gpu_pipeline_layout_create(struct xrad_context *ctx,
                                       const VkDescriptorSetLayout *sets, uint32_t set_count,
                                       uint32_t push_bytes, VkShaderStageFlags push_stages,
                                       VkPipelineLayout *out, xrad_error *err);

/* A pool for `max_sets` sets drawing on `sizes`. */
xrad_status gpu_descriptor_pool_create(struct xrad_context *ctx,
                                       const VkDescriptorPoolSize *sizes, uint32_t count,
                                       uint32_t max_sets, VkDescriptorPool *out,
                                       xrad_error *err);

/* One set of `layout` from `pool`. */
xrad_status gpu_descriptor_set_allocate(struct xrad_context *ctx, VkDescriptorPool pool,
                                        VkDescriptorSetLayout layout, VkDescriptorSet *out,
                                        xrad_error *err);

xrad_status gpu_compute_pipeline_create(struct xrad_context *ctx, const uint32_t *words,
                                        size_t bytes, VkPipelineLayout layout,
                                        const VkSpecializationInfo *spec, VkPipeline *out,
                                        xrad_error *err);

/* A render pass of one subpass with one colour and one depth attachment
 * (none where depth_format is VK_FORMAT_UNDEFINED), both cleared on load; the colour is stored and left in
 * `color_final_layout`, the depth is not stored. Its dependencies order it
 * after earlier draws and after earlier readers of the images (compute,
 * fragment, transfer), and before later readers. view_mask != 0 makes it a
 * multiview pass over those views. */
typedef struct gpu_render_pass_desc {
    VkFormat color_format, depth_format;
    VkSampleCountFlagBits samples; /* 0 means 1 */
    VkImageLayout color_final_layout;
    uint32_t view_mask;
} gpu_render_pass_desc;

xrad_status gpu_render_pass_create(struct xrad_context *ctx, const gpu_render_pass_desc *desc,
                                   VkRenderPass *out, xrad_error *err);

/* A graphics pipeline for one subpass: triangle lists unless `topology`
 * says otherwise, no blending unless `blend`, viewport and scissor
 * dynamic. */
typedef struct gpu_graphics_desc {
    const uint32_t *vert;
    size_t vert_bytes;
    const VkSpecializationInfo *vert_spec;
    const uint32_t *frag;
    size_t frag_bytes;
    const VkSpecializationInfo *frag_spec;
    const VkVertexInputBindingDescription *bindings;
    uint32_t binding_count;
    const VkVertexInputAttributeDescription *attributes;
    uint32_t attribute_count;
    VkPrimitiveTopology topology; /* 0 (POINT_LIST, which xrad never draws): triangle list */
    VkCullModeFlags cull;
    VkFrontFace front_face;
    bool depth_test, depth_write;
    VkCompareOp depth_compare;
    VkSampleCountFlagBits samples; /* 0 means 1 */
    uint32_t color_attachments;
    bool blend; /* colour over the attachment by its alpha: src a + dst (1 - a) */
    VkPipelineLayout layout;
    VkRenderPass render_pass;
    uint32_t subpass;
} gpu_graphics_desc;

xrad_status gpu_graphics_pipeline_create(struct xrad_context *ctx, const gpu_graphics_desc *desc,
                                         VkPipeline *out, xrad_error *err);

#endif
