/*
 * What xrad asks of a Vulkan device, shared by the context that creates its
 * own device (context.c) and the one that takes the application's
 * (vulkan_import.c, include/xrad_vulkan.h): the queue family, the optional
 * features and extensions it uses where offered, and the chain of feature
 * structs that enables exactly those.
 */
#ifndef XRAD_GPU_DEVICE_FEATURES_H
#define XRAD_GPU_DEVICE_FEATURES_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/context.h"
#include "xrad.h"

#define GPU_DEVICE_MAX_EXTENSIONS 6

/* What a physical device offers of what xrad uses. */
typedef struct gpu_device_offer {
    uint32_t queue_family; /* graphics + compute */
    gpu_features features; /* every optional feature it offers, and its limits */
    bool api13;            /* device and instance at Vulkan 1.3 (synchronization2 is core) */
    bool swapchain;        /* VK_KHR_swapchain offered */
    bool portability;      /* VK_KHR_portability_subset offered: it must be enabled */
} gpu_device_offer;

/* Reads `phys` (an instance of API version `instance_api`).
 * XRAD_ERROR_SYSTEM for a device below Vulkan 1.2 or without a graphics
 * and compute queue family, or without VK_KHR_swapchain when `present`. */
xrad_status gpu_device_query(struct xrad_context *ctx, VkPhysicalDevice phys,
                             uint32_t instance_api, bool present, gpu_device_offer *out,
                             xrad_error *err);

/* The features and device extensions that enable `f` (with `present`:
 * VK_KHR_swapchain): features.pNext chains the structs below, so the
 * struct is used where it lies and never copied. */
typedef struct gpu_device_enable {
    VkPhysicalDeviceFeatures2 features;
    VkPhysicalDeviceVulkan11Features vulkan11;
    VkPhysicalDeviceVulkan12Features vulkan12;
    VkPhysicalDeviceSynchronization2Features synchronization2;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float;
    const char *extensions[GPU_DEVICE_MAX_EXTENSIONS];
    uint32_t extension_count;
} gpu_device_enable;

void gpu_device_enable_chain(const gpu_device_offer *offer, bool present,
                             gpu_device_enable *out);

/* Whether `name` is among names[0 .. n-1]. */
bool gpu_extension_listed(const char *const *names, uint32_t n, const char *name);

/* `offer`'s features narrowed to those a device was created with: the
 * feature chain `enabled` (NULL: what gpu_device_enable_chain gives) and
 * the device extensions `extensions` (NULL: its extensions). */
void gpu_device_narrow(gpu_device_offer *offer, const VkPhysicalDeviceFeatures2 *enabled,
                       const char *const *extensions, uint32_t extension_count);

#endif
