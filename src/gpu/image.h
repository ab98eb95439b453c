/* 2D and 2D-array images with their memory and a default view, and layout
 * transitions by pipeline barriers. */
#ifndef XRAD_GPU_IMAGE_H
#define XRAD_GPU_IMAGE_H

#include <stdbool.h>
#include <vulkan/vulkan.h>

#include "gpu/memory.h"
#include "xrad.h"

struct xrad_context;

typedef struct gpu_image_desc {
    VkFormat format;
    uint32_t width, height;
    uint32_t layers;             /* 0 means 1 */
    bool array;                  /* view as VK_IMAGE_VIEW_TYPE_2D_ARRAY even with one layer */
    VkImageUsageFlags usage;
    VkSampleCountFlagBits samples; /* 0 means 1 */
    gpu_mem_category category;
} gpu_image_desc;

typedef struct gpu_image {
    VkImage image;
    VkImageView view; /* all layers; 2D or 2D_ARRAY as desc.array and layers say */
    VkFormat format;
    VkImageAspectFlags aspect;
    uint32_t width, height, layers;
    VkSampleCountFlagBits samples;
    gpu_allocation alloc;
} gpu_image;

/* Creates image, memory and view. On failure *out is zeroed. */
xrad_status gpu_image_create(struct xrad_context *ctx, const gpu_image_desc *desc,
                             gpu_image *out, xrad_error *err);

/* The one sampler kind xrad reads images with: `filter` (NEAREST, or
 * LINEAR where the format can filter), clamped to the edge, one mip level.
 * Destroy with vkDestroySampler. */
xrad_status gpu_sampler_create(struct xrad_context *ctx, VkFilter filter, VkSampler *out,
                               xrad_error *err);

/* Accepts a zeroed image; zeroes it. The GPU must be done with it. */
void gpu_image_destroy(struct xrad_context *ctx, gpu_image *img);

/* A further view of layers [base, base + count) (e.g. one hemicube face). */
xrad_status gpu_image_view_create(struct xrad_context *ctx, const gpu_image *img,
                                  VkImageViewType type, uint32_t base_layer, uint32_t count,
                                  VkImageView *out, xrad_error *err);

/* Bytes per texel of the formats xrad uses; 0 for others. */
uint32_t gpu_format_bytes(VkFormat format);

/* The aspect a format has: depth, stencil or colour. */
VkImageAspectFlags gpu_format_aspect(VkFormat format);

/* One image memory barrier over all layers with explicit stages/accesses. */
void gpu_image_barrier(VkCommandBuffer cmd, const gpu_image *img, VkImageLayout old_layout,
                       VkImageLayout new_layout, VkPipelineStageFlags src_stage,
                       VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                       VkAccessFlags dst_access);

/* The same with stages and accesses implied by the layouts: what wrote the
 * image in old_layout must finish before what uses it in new_layout. For
 * SHADER_READ_ONLY and GENERAL, fragment and compute shaders. */
void gpu_image_transition(VkCommandBuffer cmd, const gpu_image *img,
                          VkImageLayout old_layout, VkImageLayout new_layout);

#endif
