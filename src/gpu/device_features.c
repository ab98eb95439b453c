/* What xrad asks of a device (device_features.h). */
#include "gpu/device_features.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/vk_check.h"

static bool has_extension(const VkExtensionProperties *ext, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(ext[i].extensionName, name))
            return true;
    return false;
}

xrad_status gpu_device_query(struct xrad_context *ctx, VkPhysicalDevice phys,
                             uint32_t instance_api, bool present, gpu_device_offer *out,
                             xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(phys, &props);
    if (props.apiVersion < VK_API_VERSION_1_2 || instance_api < VK_API_VERSION_1_2)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' (Vulkan %u.%u, instance %u.%u): xrad needs Vulkan 1.2 or "
                         "newer",
                         props.deviceName, VK_API_VERSION_MAJOR(props.apiVersion),
                         VK_API_VERSION_MINOR(props.apiVersion),
                         VK_API_VERSION_MAJOR(instance_api), VK_API_VERSION_MINOR(instance_api));

    uint32_t qn = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(phys, &qn, NULL);
    VkQueueFamilyProperties *qf = calloc(qn ? qn : 1, sizeof(*qf));
    if (!qf)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (queue families)");
    vkGetPhysicalDeviceQueueFamilyProperties(phys, &qn, qf);
    uint32_t family = UINT32_MAX;
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    for (uint32_t i = 0; i < qn && family == UINT32_MAX; i++)
        if ((qf[i].queueFlags & need) == need)
            family = i;
    uint32_t ts_bits = family != UINT32_MAX ? qf[family].timestampValidBits : 0;
    free(qf);
    if (family == UINT32_MAX)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' has no queue family with both graphics and compute",
                         props.deviceName);
    out->queue_family = family;

    uint32_t en = 0;
    if (VK_CHECK(ctx, err, vkEnumerateDeviceExtensionProperties(phys, NULL, &en, NULL)))
        return XRAD_ERROR_SYSTEM;
    VkExtensionProperties *ext = calloc(en ? en : 1, sizeof(*ext));
    if (!ext)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (device extensions)");
    if (VK_CHECK(ctx, err, vkEnumerateDeviceExtensionProperties(phys, NULL, &en, ext))) {
        free(ext);
        return XRAD_ERROR_SYSTEM;
    }
    out->api13 = props.apiVersion >= VK_API_VERSION_1_3 && instance_api >= VK_API_VERSION_1_3;
    bool has_atomic_float = has_extension(ext, en, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
    bool has_sync2 = has_extension(ext, en, VK_KHR_SYNCHRONIZATION_2_EXTENSION_NAME);
    bool has_budget = has_extension(ext, en, VK_EXT_MEMORY_BUDGET_EXTENSION_NAME);
    /* The spec requires enabling it wherever it is offered (MoltenVK). */
    out->portability = has_extension(ext, en, "VK_KHR_portability_subset");
    out->swapchain = has_extension(ext, en, VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    free(ext);
    if (present && !out->swapchain)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' cannot present to a window (no "
                         VK_KHR_SWAPCHAIN_EXTENSION_NAME ")",
                         props.deviceName);

    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT q_atomic = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
    };
    VkPhysicalDeviceSynchronization2Features q_sync2 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES,
        .pNext = has_atomic_float ? &q_atomic : NULL,
    };
    VkPhysicalDeviceVulkan12Features q12 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
        .pNext = (out->api13 || has_sync2) ? (void *)&q_sync2
                                            : (has_atomic_float ? &q_atomic : NULL),
    };
    VkPhysicalDeviceVulkan11Features q11 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
        .pNext = &q12,
    };
    VkPhysicalDeviceFeatures2 q = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
        .pNext = &q11,
    };
    vkGetPhysicalDeviceFeatures2(phys, &q);

    VkPhysicalDeviceVulkan11Properties p11 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_PROPERTIES,
    };
    VkPhysicalDeviceProperties2 p = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
        .pNext = &p11,
    };
    vkGetPhysicalDeviceProperties2(phys, &p);

    gpu_features *f = &out->features;
    f->timeline_semaphore = q12.timelineSemaphore;
    f->multiview = q11.multiview;
    f->multiview_max_views = q11.multiview ? p11.maxMultiviewViewCount : 0;
    f->shader_output_layer = q12.shaderOutputLayer;
    f->synchronization2 = (out->api13 || has_sync2) && q_sync2.synchronization2;
    f->host_query_reset = q12.hostQueryReset;
    f->shader_float32_atomic_add = has_atomic_float && q_atomic.shaderBufferFloat32AtomicAdd;
    f->memory_budget = has_budget;
    f->fragment_stores_and_atomics = q.features.fragmentStoresAndAtomics;
    f->vertex_pipeline_stores_and_atomics = q.features.vertexPipelineStoresAndAtomics;
    f->multi_draw_indirect = q.features.multiDrawIndirect;
    f->draw_indirect_first_instance = q.features.drawIndirectFirstInstance;
    f->timestamp_valid_bits = ts_bits;
    f->timestamps = ts_bits > 0 && props.limits.timestampPeriod > 0;
    f->timestamp_period = props.limits.timestampPeriod;
    f->subgroup_size = p11.subgroupSize;
    f->subgroup_ops = (p11.subgroupSupportedStages & VK_SHADER_STAGE_COMPUTE_BIT)
                          ? p11.subgroupSupportedOperations
                          : 0;
    return XRAD_OK;
}

void gpu_device_enable_chain(const gpu_device_offer *offer, bool present,
                             gpu_device_enable *out)
{
    const gpu_features *f = &offer->features;
    memset(out, 0, sizeof(*out));
    out->atomic_float = (VkPhysicalDeviceShaderAtomicFloatFeaturesEXT){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT,
        .shaderBufferFloat32AtomicAdd = f->shader_float32_atomic_add,
    };
    out->synchronization2 = (VkPhysicalDeviceSynchronization2Features){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES,
        .pNext = f->shader_float32_atomic_add ? &out->atomic_float : NULL,
        .synchronization2 = VK_TRUE,
    };
    void *after12 = f->synchronization2 ? (void *)&out->synchronization2
                    : f->shader_float32_atomic_add ? (void *)&out->atomic_float
                                                   : NULL;
    out->vulkan12 = (VkPhysicalDeviceVulkan12Features){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
        .pNext = after12,
        .timelineSemaphore = f->timeline_semaphore,
        .shaderOutputLayer = f->shader_output_layer,
        .hostQueryReset = f->host_query_reset,
    };
    out->vulkan11 = (VkPhysicalDeviceVulkan11Features){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES,
        .pNext = &out->vulkan12,
        .multiview = f->multiview,
    };
    out->features = (VkPhysicalDeviceFeatures2){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
        .pNext = &out->vulkan11,
        .features = {
            .fragmentStoresAndAtomics = f->fragment_stores_and_atomics,
            .vertexPipelineStoresAndAtomics = f->vertex_pipeline_stores_and_atomics,
            .multiDrawIndirect = f->multi_draw_indirect,
            .drawIndirectFirstInstance = f->draw_indirect_first_instance,
        },
    };
    uint32_t n = 0;
    if (present)
        out->extensions[n++] = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
    if (f->shader_float32_atomic_add)
        out->extensions[n++] = VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME;
    if (f->synchronization2 && !offer->api13)
        out->extensions[n++] = VK_KHR_SYNCHRONIZATION_2_EXTENSION_NAME;
    if (f->memory_budget)
        out->extensions[n++] = VK_EXT_MEMORY_BUDGET_EXTENSION_NAME;
    if (offer->portability)
        out->extensions[n++] = "VK_KHR_portability_subset";
    out->extension_count = n;
}

bool gpu_extension_listed(const char *const *names, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (names[i] && !strcmp(names[i], name))
            return true;
    return false;
}

void gpu_device_narrow(gpu_device_offer *offer, const VkPhysicalDeviceFeatures2 *enabled,
                       const char *const *extensions, uint32_t extension_count)
{
    gpu_features *f = &offer->features;
    if (extensions) {
        f->shader_float32_atomic_add =
            f->shader_float32_atomic_add &&
            gpu_extension_listed(extensions, extension_count, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
        f->memory_budget = f->memory_budget &&
                           gpu_extension_listed(extensions, extension_count, VK_EXT_MEMORY_BUDGET_EXTENSION_NAME);
        if (!offer->api13)
            f->synchronization2 =
                f->synchronization2 &&
                gpu_extension_listed(extensions, extension_count, VK_KHR_SYNCHRONIZATION_2_EXTENSION_NAME);
    }
    if (!enabled)
        return;
    /* Walk the application's chain: a feature xrad would use counts only
     * where the struct that enables it is there and says so. */
    bool v11 = false, v12 = false, v13 = false, sync2 = false, atomic = false;
    const VkPhysicalDeviceFeatures *core = &enabled->features;
    for (const VkBaseInStructure *s = enabled->pNext; s; s = s->pNext) {
        switch (s->sType) {
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_1_FEATURES: {
            const VkPhysicalDeviceVulkan11Features *x = (const void *)s;
            v11 = true;
            f->multiview = f->multiview && x->multiview;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES: {
            const VkPhysicalDeviceVulkan12Features *x = (const void *)s;
            v12 = true;
            f->timeline_semaphore = f->timeline_semaphore && x->timelineSemaphore;
            f->shader_output_layer = f->shader_output_layer && x->shaderOutputLayer;
            f->host_query_reset = f->host_query_reset && x->hostQueryReset;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES: {
            const VkPhysicalDeviceVulkan13Features *x = (const void *)s;
            v13 = v13 || x->synchronization2;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SYNCHRONIZATION_2_FEATURES: {
            const VkPhysicalDeviceSynchronization2Features *x = (const void *)s;
            sync2 = sync2 || x->synchronization2;
            break;
        }
        case VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT: {
            const VkPhysicalDeviceShaderAtomicFloatFeaturesEXT *x = (const void *)s;
            atomic = atomic || x->shaderBufferFloat32AtomicAdd;
            break;
        }
        default:
            break;
        }
    }
    if (!v11)
        f->multiview = false;
    if (!v12) {
        f->timeline_semaphore = false;
        f->shader_output_layer = false;
        f->host_query_reset = false;
    }
    f->multiview_max_views = f->multiview ? f->multiview_max_views : 0;
    f->synchronization2 = f->synchronization2 && (sync2 || v13);
    f->shader_float32_atomic_add = f->shader_float32_atomic_add && atomic;
    f->fragment_stores_and_atomics = f->fragment_stores_and_atomics && core->fragmentStoresAndAtomics;
    f->vertex_pipeline_stores_and_atomics =
        f->vertex_pipeline_stores_and_atomics && core->vertexPipelineStoresAndAtomics;
    f->multi_draw_indirect = f->multi_draw_indirect && core->multiDrawIndirect;
    f->draw_indirect_first_instance =
        f->draw_indirect_first_instance && core->drawIndirectFirstInstance;
}
