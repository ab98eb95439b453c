#include "gpu/image.h"

#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

uint32_t gpu_format_bytes(VkFormat format)
{
    switch (format) {
    case VK_FORMAT_R32G32B32A32_SFLOAT:
    case VK_FORMAT_R32G32B32A32_UINT:
        return 16;
    case VK_FORMAT_R16G16B16A16_SFLOAT:
    case VK_FORMAT_R32G32_SFLOAT:
    case VK_FORMAT_R32G32_UINT:
        return 8;
    case VK_FORMAT_R32_SFLOAT:
    case VK_FORMAT_R32_UINT:
    case VK_FORMAT_R8G8B8A8_UNORM:
    case VK_FORMAT_R8G8B8A8_SRGB:
    case VK_FORMAT_B8G8R8A8_UNORM:
    case VK_FORMAT_B8G8R8A8_SRGB:
    case VK_FORMAT_D32_SFLOAT:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
        return 4;
    case VK_FORMAT_R16_SFLOAT:
    case VK_FORMAT_D16_UNORM:
        return 2;
    default:
        return 0;
    }
}

VkImageAspectFlags gpu_format_aspect(VkFormat format)
{
    switch (format) {
    case VK_FORMAT_D16_UNORM:
    case VK_FORMAT_X8_D24_UNORM_PACK32:
    case VK_FORMAT_D32_SFLOAT:
        return VK_IMAGE_ASPECT_DEPTH_BIT;
    case VK_FORMAT_S8_UINT:
        return VK_IMAGE_ASPECT_STENCIL_BIT;
    case VK_FORMAT_D16_UNORM_S8_UINT:
    case VK_FORMAT_D24_UNORM_S8_UINT:
    case VK_FORMAT_D32_SFLOAT_S8_UINT:
        return VK_IMAGE_ASPECT_DEPTH_BIT | VK_IMAGE_ASPECT_STENCIL_BIT;
    default:
        return VK_IMAGE_ASPECT_COLOR_BIT;
    }
}

xrad_status gpu_image_view_create(struct xrad_context *ctx, const gpu_image *img,
                                  VkImageViewType type, uint32_t base_layer, uint32_t count,
                                  VkImageView *out, xrad_error *err)
{
    *out = VK_NULL_HANDLE;
    VkImageViewCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = img->image,
        .viewType = type,
        .format = img->format,
        .subresourceRange = {
            .aspectMask = img->aspect,
            .levelCount = 1,
            .baseArrayLayer = base_layer,
            .layerCount = count,
        },
    };
    return VK_CHECK(ctx, err, vkCreateImageView(ctx->device, &info, NULL, out));
}

xrad_status gpu_image_create(struct xrad_context *ctx, const gpu_image_desc *desc,
                             gpu_image *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    uint32_t layers = desc->layers ? desc->layers : 1;
    VkSampleCountFlagBits samples = desc->samples ? desc->samples : VK_SAMPLE_COUNT_1_BIT;
    const VkPhysicalDeviceLimits *lim = &ctx->props.limits;
    if (desc->width == 0 || desc->height == 0 || desc->width > lim->maxImageDimension2D ||
        desc->height > lim->maxImageDimension2D || layers > lim->maxImageArrayLayers)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "image %u x %u x %u layers is outside the device's limits "
                         "(%u x %u, %u layers)",
                         desc->width, desc->height, layers, lim->maxImageDimension2D,
                         lim->maxImageDimension2D, lim->maxImageArrayLayers);
    VkImageCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = desc->format,
        .extent = {desc->width, desc->height, 1},
        .mipLevels = 1,
        .arrayLayers = layers,
        .samples = samples,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = desc->usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
    };
    if (VK_CHECK(ctx, err, vkCreateImage(ctx->device, &info, NULL, &out->image)))
        return XRAD_ERROR_SYSTEM;
    out->format = desc->format;
    out->aspect = gpu_format_aspect(desc->format);
    out->width = desc->width;
    out->height = desc->height;
    out->layers = layers;
    out->samples = samples;
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(ctx->device, out->image, &req);
    xrad_status s = gpu_memory_alloc(ctx, &req, GPU_MEM_DEVICE, false, desc->category,
                                     &out->alloc, err);
    if (s)
        goto fail_memory;
    if ((s = VK_CHECK(ctx, err, vkBindImageMemory(ctx->device, out->image, out->alloc.memory,
                                                  out->alloc.offset))))
        goto fail_bind;
    VkImageViewType type = (layers > 1 || desc->array) ? VK_IMAGE_VIEW_TYPE_2D_ARRAY
                                                        : VK_IMAGE_VIEW_TYPE_2D;
    if ((s = gpu_image_view_create(ctx, out, type, 0, layers, &out->view, err)))
        goto fail_bind;
    return XRAD_OK;

fail_bind:
    gpu_memory_free(ctx, &out->alloc);
fail_memory:
    vkDestroyImage(ctx->device, out->image, NULL);
    memset(out, 0, sizeof(*out));
    return s;
}

void gpu_image_destroy(struct xrad_context *ctx, gpu_image *img)
{
    if (!img || !img->image)
        return;
    vkDestroyImageView(ctx->device, img->view, NULL);
    vkDestroyImage(ctx->device, img->image, NULL);
    gpu_memory_free(ctx, &img->alloc);
    memset(img, 0, sizeof(*img));
}

void gpu_image_barrier(VkCommandBuffer cmd, const gpu_image *img, VkImageLayout old_layout,
                       VkImageLayout new_layout, VkPipelineStageFlags src_stage,
                       VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                       VkAccessFlags dst_access)
{
    VkImageMemoryBarrier b = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
        .oldLayout = old_layout,
        .newLayout = new_layout,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = img->image,
        .subresourceRange = {
            .aspectMask = img->aspect,
            .levelCount = 1,
            .layerCount = img->layers,
        },
    };
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 0, NULL, 0, NULL, 1, &b);
}

/* Stages and accesses that use an image in `layout`; `dst` picks the side
 * of the barrier (for UNDEFINED only the source side is meaningful). */
static void layout_use(VkImageLayout layout, bool dst, VkPipelineStageFlags *stage,
                       VkAccessFlags *access)
{
    const VkPipelineStageFlags shaders =
        VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    switch (layout) {
    case VK_IMAGE_LAYOUT_UNDEFINED:
    case VK_IMAGE_LAYOUT_PREINITIALIZED:
        *stage = dst ? VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT : VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT;
        *access = 0;
        break;
    case VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL:
        *stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        *access = VK_ACCESS_TRANSFER_WRITE_BIT;
        break;
    case VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL:
        *stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
        *access = VK_ACCESS_TRANSFER_READ_BIT;
        break;
    case VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL:
        *stage = shaders;
        *access = VK_ACCESS_SHADER_READ_BIT;
        break;
    case VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL:
        *stage = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
        *access = VK_ACCESS_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
        break;
    case VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL:
        *stage = VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                 VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
        *access = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT |
                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT;
        break;
    case VK_IMAGE_LAYOUT_GENERAL:
    default:
        *stage = VK_PIPELINE_STAGE_ALL_COMMANDS_BIT;
        *access = VK_ACCESS_MEMORY_READ_BIT | VK_ACCESS_MEMORY_WRITE_BIT;
        break;
    }
}

void gpu_image_transition(VkCommandBuffer cmd, const gpu_image *img,
                          VkImageLayout old_layout, VkImageLayout new_layout)
{
    VkPipelineStageFlags src_stage, dst_stage;
    VkAccessFlags src_access, dst_access;
    layout_use(old_layout, false, &src_stage, &src_access);
    layout_use(new_layout, true, &dst_stage, &dst_access);
    /* Reads need no flush: only writes are made available. */
    src_access &= VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                  VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_MEMORY_WRITE_BIT |
                  VK_ACCESS_SHADER_WRITE_BIT;
    gpu_image_barrier(cmd, img, old_layout, new_layout, src_stage, src_access, dst_stage,
                      dst_access);
}

xrad_status gpu_sampler_create(struct xrad_context *ctx, VkFilter filter, VkSampler *out,
                               xrad_error *err)
{
    VkSamplerCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
        .magFilter = filter,
        .minFilter = filter,
        .mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST,
        .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
        .maxLod = 0,
    };
    return VK_CHECK(ctx, err, vkCreateSampler(ctx->device, &info, NULL, out));
}
