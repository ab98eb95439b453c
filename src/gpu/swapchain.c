#include "gpu/swapchain.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"

xrad_status gpu_swapchain_format(struct xrad_context *ctx, VkSurfaceKHR surface,
                                 VkFormat *format, xrad_error *err)
{
    if (!ctx->present)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "swapchain: the context was created without presentation "
                         "(xrad_context_desc.present)");
    VkBool32 supported = VK_FALSE;
    xrad_status s = VK_CHECK(ctx, err,
                             vkGetPhysicalDeviceSurfaceSupportKHR(ctx->phys, ctx->queue_family,
                                                                  surface, &supported));
    if (s)
        return s;
    if (!supported)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "device '%s' cannot present to this window",
                         ctx->props.deviceName);
    uint32_t n = 0;
    if ((s = VK_CHECK(ctx, err,
                      vkGetPhysicalDeviceSurfaceFormatsKHR(ctx->phys, surface, &n, NULL))))
        return s;
    VkSurfaceFormatKHR *f = calloc(n ? n : 1, sizeof(*f));
    if (!f)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (surface formats)");
    if ((s = VK_CHECK(ctx, err, vkGetPhysicalDeviceSurfaceFormatsKHR(ctx->phys, surface, &n, f)))) {
        free(f);
        return s;
    }
    static const VkFormat preferred[] = {VK_FORMAT_B8G8R8A8_SRGB, VK_FORMAT_R8G8B8A8_SRGB,
                                         VK_FORMAT_B8G8R8A8_UNORM, VK_FORMAT_R8G8B8A8_UNORM};
    *format = VK_FORMAT_UNDEFINED;
    for (size_t p = 0; p < sizeof(preferred) / sizeof(preferred[0]) && !*format; p++)
        for (uint32_t i = 0; i < n; i++)
            if (f[i].format == preferred[p] &&
                f[i].colorSpace == VK_COLOR_SPACE_SRGB_NONLINEAR_KHR)
                *format = preferred[p];
    free(f);
    if (!*format)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "the window offers none of the 8-bit RGBA/BGRA sRGB formats (%u "
                         "formats)",
                         n);
    return XRAD_OK;
}

static void images_destroy(struct xrad_context *ctx, gpu_swapchain_images *im)
{
    for (uint32_t i = 0; i < im->count; i++) {
        vkDestroyFramebuffer(ctx->device, im->framebuffers[i], NULL);
        vkDestroyImageView(ctx->device, im->views[i], NULL);
        vkDestroySemaphore(ctx->device, im->rendered[i], NULL);
    }
    vkDestroySwapchainKHR(ctx->device, im->swapchain, NULL);
    memset(im, 0, sizeof(*im));
}

static VkPresentModeKHR pick_mode(struct xrad_context *ctx, VkSurfaceKHR surface, bool vsync)
{
    if (vsync)
        return VK_PRESENT_MODE_FIFO_KHR; /* always offered */
    VkPresentModeKHR modes[16];
    uint32_t n = 16;
    VkResult r = vkGetPhysicalDeviceSurfacePresentModesKHR(ctx->phys, surface, &n, modes);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE)
        return VK_PRESENT_MODE_FIFO_KHR;
    VkPresentModeKHR best = VK_PRESENT_MODE_FIFO_KHR;
    for (uint32_t i = 0; i < n; i++) {
        if (modes[i] == VK_PRESENT_MODE_MAILBOX_KHR)
            return modes[i];
        if (modes[i] == VK_PRESENT_MODE_IMMEDIATE_KHR)
            best = modes[i];
    }
    return best;
}

static xrad_status images_create(struct xrad_context *ctx, gpu_swapchain *sc, uint32_t width,
                                 uint32_t height, bool vsync, VkSwapchainKHR old,
                                 gpu_swapchain_images *im, xrad_error *err)
{
    memset(im, 0, sizeof(*im));
    VkSurfaceCapabilitiesKHR caps;
    xrad_status s = VK_CHECK(ctx, err,
                             vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx->phys, sc->surface,
                                                                       &caps));
    if (s)
        return s;
    VkExtent2D e = caps.currentExtent;
    if (e.width == UINT32_MAX) {
        e.width = width < caps.minImageExtent.width    ? caps.minImageExtent.width
                  : width > caps.maxImageExtent.width  ? caps.maxImageExtent.width
                                                       : width;
        e.height = height < caps.minImageExtent.height   ? caps.minImageExtent.height
                   : height > caps.maxImageExtent.height ? caps.maxImageExtent.height
                                                         : height;
    }
    if (!e.width || !e.height)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "swapchain: the window has no area");
    uint32_t count = caps.minImageCount + 1;
    if (caps.maxImageCount && count > caps.maxImageCount)
        count = caps.maxImageCount;
    if (count > GPU_SWAPCHAIN_MAX_IMAGES)
        count = GPU_SWAPCHAIN_MAX_IMAGES;
    if (!(caps.supportedUsageFlags & VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT))
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "swapchain: the window's images cannot be rendered to");
    sc->mode = pick_mode(ctx, sc->surface, vsync);
    VkSwapchainCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = sc->surface,
        .minImageCount = count,
        .imageFormat = sc->format,
        .imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR,
        .imageExtent = e,
        .imageArrayLayers = 1,
        .imageUsage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
        .imageSharingMode = VK_SHARING_MODE_EXCLUSIVE,
        .preTransform = caps.currentTransform,
        .compositeAlpha = (caps.supportedCompositeAlpha & VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR)
                              ? VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR
                              : (VkCompositeAlphaFlagBitsKHR)(caps.supportedCompositeAlpha &
                                                              -caps.supportedCompositeAlpha),
        .presentMode = sc->mode,
        .clipped = VK_TRUE,
        .oldSwapchain = old,
    };
    if ((s = VK_CHECK(ctx, err, vkCreateSwapchainKHR(ctx->device, &info, NULL, &im->swapchain))))
        return s;
    uint32_t n = 0;
    if ((s = VK_CHECK(ctx, err, vkGetSwapchainImagesKHR(ctx->device, im->swapchain, &n, NULL))))
        goto fail;
    if (n > GPU_SWAPCHAIN_MAX_IMAGES) {
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "swapchain: %u images, at most %d handled", n,
                      GPU_SWAPCHAIN_MAX_IMAGES);
        goto fail;
    }
    if ((s = VK_CHECK(ctx, err,
                      vkGetSwapchainImagesKHR(ctx->device, im->swapchain, &n, im->images))))
        goto fail;
    for (uint32_t i = 0; i < n; i++) {
        im->count = i + 1; /* what images_destroy frees on failure */
        VkImageViewCreateInfo view = {
            .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
            .image = im->images[i],
            .viewType = VK_IMAGE_VIEW_TYPE_2D,
            .format = sc->format,
            .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
        };
        VkSemaphoreCreateInfo sem = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
        if ((s = VK_CHECK(ctx, err, vkCreateImageView(ctx->device, &view, NULL, &im->views[i]))) ||
            (s = VK_CHECK(ctx, err, vkCreateSemaphore(ctx->device, &sem, NULL, &im->rendered[i]))))
            goto fail;
        VkFramebufferCreateInfo fb = {
            .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
            .renderPass = sc->render_pass,
            .attachmentCount = 1,
            .pAttachments = &im->views[i],
            .width = e.width,
            .height = e.height,
            .layers = 1,
        };
        if ((s = VK_CHECK(ctx, err,
                          vkCreateFramebuffer(ctx->device, &fb, NULL, &im->framebuffers[i]))))
            goto fail;
    }
    sc->extent = e;
    return XRAD_OK;

fail:
    images_destroy(ctx, im);
    return s;
}

xrad_status gpu_swapchain_create(struct xrad_context *ctx, VkSurfaceKHR surface,
                                 VkRenderPass render_pass, uint32_t width, uint32_t height,
                                 bool vsync, gpu_swapchain *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    out->surface = surface;
    out->render_pass = render_pass;
    xrad_status s = gpu_swapchain_format(ctx, surface, &out->format, err);
    if (s)
        return s;
    out->srgb = out->format == VK_FORMAT_B8G8R8A8_SRGB || out->format == VK_FORMAT_R8G8B8A8_SRGB;
    return images_create(ctx, out, width, height, vsync, VK_NULL_HANDLE, &out->cur, err);
}

void gpu_swapchain_collect(struct xrad_context *ctx, gpu_swapchain *sc, uint64_t reached)
{
    uint32_t kept = 0;
    for (uint32_t i = 0; i < sc->retired_count; i++) {
        if (sc->retired[i].retire_after <= reached)
            images_destroy(ctx, &sc->retired[i]);
        else
            sc->retired[kept++] = sc->retired[i];
    }
    sc->retired_count = kept;
}

xrad_status gpu_swapchain_recreate(struct xrad_context *ctx, gpu_swapchain *sc, uint32_t width,
                                   uint32_t height, bool vsync, uint64_t retire_after,
                                   uint64_t reached, xrad_error *err)
{
    gpu_swapchain_collect(ctx, sc, reached);
    if (sc->retired_count == GPU_SWAPCHAIN_MAX_RETIRED)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "swapchain: %d retired swapchains are still in use by the GPU",
                         GPU_SWAPCHAIN_MAX_RETIRED);
    gpu_swapchain_images next;
    xrad_status s = images_create(ctx, sc, width, height, vsync, sc->cur.swapchain, &next, err);
    if (s)
        return s;
    sc->cur.retire_after = retire_after;
    sc->retired[sc->retired_count++] = sc->cur;
    sc->cur = next;
    sc->recreations++;
    return XRAD_OK;
}

xrad_status gpu_swapchain_acquire(struct xrad_context *ctx, gpu_swapchain *sc,
                                  VkSemaphore acquired, uint32_t *index, bool *out_of_date,
                                  xrad_error *err)
{
    *index = UINT32_MAX;
    *out_of_date = false;
    VkResult r = vkAcquireNextImageKHR(ctx->device, sc->cur.swapchain, ctx->wait_timeout_ns,
                                       acquired, VK_NULL_HANDLE, index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        *index = UINT32_MAX;
        *out_of_date = true;
        return XRAD_OK;
    }
    if (r == VK_SUBOPTIMAL_KHR) {
        *out_of_date = true;
        return XRAD_OK;
    }
    if (r != VK_SUCCESS)
        *index = UINT32_MAX;
    return VK_CHECK(ctx, err, r);
}

xrad_status gpu_swapchain_present(struct xrad_context *ctx, gpu_swapchain *sc, uint32_t index,
                                  bool *out_of_date, xrad_error *err)
{
    *out_of_date = false;
    VkPresentInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &sc->cur.rendered[index],
        .swapchainCount = 1,
        .pSwapchains = &sc->cur.swapchain,
        .pImageIndices = &index,
    };
    gpu_queue_lock(ctx);
    VkResult r = vkQueuePresentKHR(ctx->queue, &info);
    gpu_queue_unlock(ctx);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        *out_of_date = true;
        return XRAD_OK;
    }
    return VK_CHECK(ctx, err, r);
}

void gpu_swapchain_destroy(struct xrad_context *ctx, gpu_swapchain *sc)
{
    if (!sc)
        return;
    for (uint32_t i = 0; i < sc->retired_count; i++)
        images_destroy(ctx, &sc->retired[i]);
    images_destroy(ctx, &sc->cur);
    memset(sc, 0, sizeof(*sc));
}
