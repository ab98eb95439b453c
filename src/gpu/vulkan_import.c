/*
 * A context on the application's Vulkan device (include/xrad_vulkan.h):
 * its requirements, the import, and the handles out.
 */
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/device_features.h"
#include "gpu/driver_pin.h"
#include "xrad_vulkan.h"

_Static_assert(XRAD_VULKAN_MAX_EXTENSIONS == GPU_DEVICE_MAX_EXTENSIONS,
               "the public requirements hold every extension xrad may enable");

xrad_status xrad_vulkan_get_requirements(VkPhysicalDevice physical_device,
                                         uint32_t instance_api_version, int present,
                                         xrad_vulkan_requirements *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    if (!physical_device)
        return xrad_fail(err, XRAD_ERROR_INPUT, "vulkan requirements: no physical device given");
    gpu_device_offer offer;
    xrad_status s =
        gpu_device_query(NULL, physical_device, instance_api_version, present == 1, &offer, err);
    if (s)
        return s;
    gpu_device_enable e;
    gpu_device_enable_chain(&offer, present == 1, &e);
    out->api_version = VK_API_VERSION_1_2;
    out->queue_family = offer.queue_family;
    for (uint32_t i = 0; i < e.extension_count; i++)
        out->extensions[i] = e.extensions[i];
    out->extension_count = e.extension_count;
    /* The same chain, relinked inside `out`. */
    out->atomic_float = e.atomic_float;
    out->synchronization2 = e.synchronization2;
    out->vulkan12 = e.vulkan12;
    out->vulkan11 = e.vulkan11;
    out->features = e.features;
    out->atomic_float.pNext = NULL;
    out->synchronization2.pNext =
        offer.features.shader_float32_atomic_add ? &out->atomic_float : NULL;
    out->vulkan12.pNext = offer.features.synchronization2    ? (void *)&out->synchronization2
                          : offer.features.shader_float32_atomic_add ? (void *)&out->atomic_float
                                                                      : NULL;
    out->vulkan11.pNext = &out->vulkan12;
    out->features.pNext = &out->vulkan11;
    return XRAD_OK;
}

xrad_status xrad_vulkan_import(const xrad_vulkan_import_desc *desc, xrad_context **out,
                               xrad_error *err)
{
    *out = NULL;
    if (!desc || !desc->instance || !desc->physical_device || !desc->device)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "vulkan import: the instance, physical device and device are required");
    if (!desc->lock_queue != !desc->unlock_queue)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "vulkan import: lock_queue and unlock_queue come together");
    gpu_device_offer offer;
    xrad_status s = gpu_device_query(NULL, desc->physical_device, desc->instance_api_version,
                                     false, &offer, err);
    if (s)
        return s;
    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(desc->physical_device, &qn, NULL);
    VkQueueFamilyProperties qf[64];
    qn = qn < 64 ? qn : 64;
    vkGetPhysicalDeviceQueueFamilyProperties(desc->physical_device, &qn, qf);
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if (desc->queue_family >= qn || (qf[desc->queue_family].queueFlags & need) != need ||
        desc->queue_index >= qf[desc->queue_family].queueCount)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "vulkan import: queue %u of family %u is not a graphics and compute "
                         "queue of the device (%u families)",
                         desc->queue_index, desc->queue_family, qn);
    gpu_device_narrow(&offer, desc->enabled_features, desc->enabled_extensions,
                      desc->enabled_extension_count);
    offer.features.timestamp_valid_bits = qf[desc->queue_family].timestampValidBits;
    offer.features.timestamps =
        offer.features.timestamp_valid_bits > 0 && offer.features.timestamp_period > 0;

    struct xrad_context *ctx;
    if ((s = gpu_context_alloc(&(gpu_context_settings){desc->memory_limit_mib, desc->fault,
                                                        desc->log, desc->log_user},
                               &ctx, err)))
        return s;
    /* Keeps the drivers loaded past the application's vkDestroyInstance,
     * as for xrad's own instance (driver_pin.c). */
    gpu_pin_driver();
    ctx->import.imported = true;
    ctx->import.queue_index = desc->queue_index;
    ctx->import.lock_queue = desc->lock_queue;
    ctx->import.unlock_queue = desc->unlock_queue;
    ctx->import.queue_user = desc->queue_user;
    ctx->instance = desc->instance;
    ctx->instance_api = desc->instance_api_version;
    ctx->phys = desc->physical_device;
    vkGetPhysicalDeviceProperties(ctx->phys, &ctx->props);
    vkGetPhysicalDeviceMemoryProperties(ctx->phys, &ctx->mem_props);
    ctx->device = desc->device;
    ctx->queue_family = desc->queue_family;
    vkGetDeviceQueue(ctx->device, desc->queue_family, desc->queue_index, &ctx->queue);
    ctx->features = offer.features;
    ctx->present = offer.swapchain && (!desc->enabled_extensions ||
                                       gpu_extension_listed(desc->enabled_extensions,
                                                            desc->enabled_extension_count,
                                                            VK_KHR_SWAPCHAIN_EXTENSION_NAME));
    if ((s = gpu_context_finish(ctx, err))) {
        xrad_context_destroy(&ctx);
        return s;
    }
    *out = ctx;
    return XRAD_OK;
}

VkInstance xrad_vulkan_instance(const xrad_context *ctx) { return ctx ? ctx->instance : NULL; }

VkPhysicalDevice xrad_vulkan_physical_device(const xrad_context *ctx)
{
    return ctx ? ctx->phys : NULL;
}

VkDevice xrad_vulkan_device(const xrad_context *ctx) { return ctx ? ctx->device : NULL; }

VkQueue xrad_vulkan_queue(const xrad_context *ctx, uint32_t *queue_family)
{
    if (queue_family)
        *queue_family = ctx ? ctx->queue_family : 0;
    return ctx ? ctx->queue : NULL;
}

void xrad_vulkan_lock_queue(xrad_context *ctx) { gpu_queue_lock(ctx); }

void xrad_vulkan_unlock_queue(xrad_context *ctx) { gpu_queue_unlock(ctx); }
