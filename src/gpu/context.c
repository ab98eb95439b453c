#include "gpu/context.h"

#include <ctype.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/device_features.h"
#include "gpu/driver_pin.h"
#include "gpu/memory.h"

#define VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"
#define DEFAULT_WAIT_TIMEOUT_NS 60000000000ull /* 60 s: far above any single xrad submission */

static atomic_uint validation_total;

uint32_t gpu_validation_messages_total(void)
{
    return atomic_load(&validation_total);
}

xrad_status gpu_context_check_alive(struct xrad_context *ctx, const char *what, xrad_error *err)
{
    if (!atomic_load(&ctx->lost))
        return XRAD_OK;
    return xrad_fail(err, XRAD_ERROR_SYSTEM,
                     "%s: the GPU device was lost earlier (VK_ERROR_DEVICE_LOST or a wait "
                     "timeout); create a new context",
                     what);
}

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT type,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data,
                                                 void *user)
{
    struct xrad_context *ctx = user;
    bool error = severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    if (!error && !(severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT))
        return VK_FALSE;
    if (ctx)
        atomic_fetch_add(&ctx->validation_messages, 1);
    atomic_fetch_add(&validation_total, 1);
    gpu_log(ctx, error ? XRAD_LOG_ERROR : XRAD_LOG_WARNING, "vulkan validation %s: %s",
            error ? "error" : "warning", data && data->pMessage ? data->pMessage : "(no message)");
    return VK_FALSE;
}

static bool has_extension(const VkExtensionProperties *ext, uint32_t n, const char *name)
{
    for (uint32_t i = 0; i < n; i++)
        if (!strcmp(ext[i].extensionName, name))
            return true;
    return false;
}

static bool contains_nocase(const char *hay, const char *needle)
{
    size_t n = strlen(needle);
    for (; *hay; hay++) {
        size_t i = 0;
        while (i < n && hay[i] &&
               tolower((unsigned char)hay[i]) == tolower((unsigned char)needle[i]))
            i++;
        if (i == n)
            return true;
    }
    return n == 0;
}

static const char *device_type_name(VkPhysicalDeviceType t)
{
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "cpu";
    default:
        return "other";
    }
}

/* Instance extensions: portability enumeration where the loader has it (so
 * that MoltenVK-style drivers are listed), debug utils for validation. */
static xrad_status create_instance(struct xrad_context *ctx, bool validation,
                                   const xrad_context_desc *desc, xrad_error *err)
{
    /* Keeps the drivers loaded past vkDestroyInstance (see driver_pin.c:
     * no false leaks under LeakSanitizer). */
    gpu_pin_driver();
    uint32_t loader_api = VK_API_VERSION_1_0;
    if (VK_CHECK(ctx, err, vkEnumerateInstanceVersion(&loader_api)))
        return XRAD_ERROR_SYSTEM;
    if (loader_api < VK_API_VERSION_1_2)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "the Vulkan loader supports Vulkan %u.%u; xrad needs 1.2 or newer",
                         VK_API_VERSION_MAJOR(loader_api), VK_API_VERSION_MINOR(loader_api));
    ctx->instance_api = loader_api < VK_API_VERSION_1_3 ? loader_api : VK_API_VERSION_1_3;

    uint32_t n = 0;
    if (VK_CHECK(ctx, err, vkEnumerateInstanceExtensionProperties(NULL, &n, NULL)))
        return XRAD_ERROR_SYSTEM;
    VkExtensionProperties *ext = calloc(n ? n : 1, sizeof(*ext));
    if (!ext)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (instance extensions)");
    xrad_status s = XRAD_OK;
    const char **enable = NULL;
    if ((s = VK_CHECK(ctx, err, vkEnumerateInstanceExtensionProperties(NULL, &n, ext))))
        goto done;
    uint32_t extra = desc ? desc->instance_extension_count : 0;
    enable = calloc(2 + extra, sizeof(*enable));
    if (!enable) {
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (instance extensions)");
        goto done;
    }
    uint32_t enable_count = 0;
    for (uint32_t i = 0; i < extra; i++) {
        const char *name = desc->instance_extensions[i];
        if (!name || !has_extension(ext, n, name)) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM,
                          "the Vulkan loader does not offer the instance extension %s that "
                          "presentation needs",
                          name ? name : "(null)");
            goto done;
        }
        enable[enable_count++] = name;
    }
    VkInstanceCreateFlags flags = 0;
    if (has_extension(ext, n, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
        enable[enable_count++] = VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME;
        flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
    }
    const char *layers[1] = {VALIDATION_LAYER};
    VkDebugUtilsMessengerCreateInfoEXT messenger_info = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message,
        .pUserData = ctx,
    };
    if (validation) {
        uint32_t ln = 0;
        if ((s = VK_CHECK(ctx, err, vkEnumerateInstanceLayerProperties(&ln, NULL))))
            goto done;
        VkLayerProperties *lp = calloc(ln ? ln : 1, sizeof(*lp));
        if (!lp) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (instance layers)");
            goto done;
        }
        bool found = false;
        if (!(s = VK_CHECK(ctx, err, vkEnumerateInstanceLayerProperties(&ln, lp))))
            for (uint32_t i = 0; i < ln; i++)
                found |= !strcmp(lp[i].layerName, VALIDATION_LAYER);
        free(lp);
        if (s)
            goto done;
        if (!found) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM,
                          "validation was requested (XRAD_VALIDATION=1 or desc.validation) but "
                          "the layer " VALIDATION_LAYER " is not installed (Debian: "
                          "vulkan-validationlayers)");
            goto done;
        }
        if (!has_extension(ext, n, VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM,
                          "validation was requested but the Vulkan loader lacks "
                          VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            goto done;
        }
        enable[enable_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    }
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "xrad",
        .pEngineName = "xrad",
        .apiVersion = ctx->instance_api,
    };
    VkInstanceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        /* Chained, the messenger also sees instance creation and destruction. */
        .pNext = validation ? &messenger_info : NULL,
        .flags = flags,
        .pApplicationInfo = &app,
        .enabledLayerCount = validation ? 1 : 0,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = enable_count,
        .ppEnabledExtensionNames = enable,
    };
    if ((s = VK_CHECK(ctx, err, vkCreateInstance(&info, NULL, &ctx->instance))))
        goto done;
    if (validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create = (PFN_vkCreateDebugUtilsMessengerEXT)
            vkGetInstanceProcAddr(ctx->instance, "vkCreateDebugUtilsMessengerEXT");
        ctx->destroy_messenger = (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (!create || !ctx->destroy_messenger) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM,
                          "vkGetInstanceProcAddr: no vkCreateDebugUtilsMessengerEXT");
            goto done;
        }
        if ((s = VK_CHECK(ctx, err, create(ctx->instance, &messenger_info, NULL, &ctx->messenger))))
            goto done;
        ctx->validation = true;
    }
done:
    free(enable);
    free(ext);
    return s;
}

static xrad_status enumerate_devices(struct xrad_context *ctx, VkInstance instance,
                                     VkPhysicalDevice **out, uint32_t *count, xrad_error *err)
{
    *out = NULL;
    *count = 0;
    uint32_t n = 0;
    if (VK_CHECK(ctx, err, vkEnumeratePhysicalDevices(instance, &n, NULL)))
        return XRAD_ERROR_SYSTEM;
    if (n == 0)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "no Vulkan device found (for a software device install Mesa's lavapipe, "
                         "Debian: mesa-vulkan-drivers)");
    VkPhysicalDevice *d = calloc(n, sizeof(*d));
    if (!d)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (device list)");
    if (VK_CHECK(ctx, err, vkEnumeratePhysicalDevices(instance, &n, d))) {
        free(d);
        return XRAD_ERROR_SYSTEM;
    }
    *out = d;
    *count = n;
    return XRAD_OK;
}

static xrad_status choose_device(struct xrad_context *ctx, const char *wanted, xrad_error *err)
{
    VkPhysicalDevice *devs;
    uint32_t n;
    xrad_status s = enumerate_devices(ctx, ctx->instance, &devs, &n, err);
    if (s)
        return s;
    int pick = -1;
    if (wanted) {
        char names[768] = "";
        for (uint32_t i = 0; i < n; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devs[i], &p);
            if (pick < 0 && contains_nocase(p.deviceName, wanted))
                pick = (int)i;
            size_t len = strlen(names);
            snprintf(names + len, sizeof(names) - len, "%s'%s'", i ? ", " : "", p.deviceName);
        }
        if (pick < 0) {
            free(devs);
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "no Vulkan device name contains '%s'; available: %s", wanted, names);
        }
    } else {
        /* Discrete first, then integrated, then whatever there is (lavapipe);
         * devices below Vulkan 1.2 only if nothing else exists. */
        static const VkPhysicalDeviceType order[] = {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU,
                                                     VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU};
        for (size_t o = 0; o < 2 && pick < 0; o++) {
            for (uint32_t i = 0; i < n && pick < 0; i++) {
                VkPhysicalDeviceProperties p;
                vkGetPhysicalDeviceProperties(devs[i], &p);
                if (p.deviceType == order[o] && p.apiVersion >= VK_API_VERSION_1_2)
                    pick = (int)i;
            }
        }
        for (uint32_t i = 0; i < n && pick < 0; i++) {
            VkPhysicalDeviceProperties p;
            vkGetPhysicalDeviceProperties(devs[i], &p);
            if (p.apiVersion >= VK_API_VERSION_1_2)
                pick = (int)i;
        }
        if (pick < 0)
            pick = 0;
    }
    ctx->phys = devs[pick];
    free(devs);
    vkGetPhysicalDeviceProperties(ctx->phys, &ctx->props);
    vkGetPhysicalDeviceMemoryProperties(ctx->phys, &ctx->mem_props);
    if (ctx->props.apiVersion < VK_API_VERSION_1_2)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' supports Vulkan %u.%u; xrad needs 1.2 or newer",
                         ctx->props.deviceName, VK_API_VERSION_MAJOR(ctx->props.apiVersion),
                         VK_API_VERSION_MINOR(ctx->props.apiVersion));
    return XRAD_OK;
}

static xrad_status create_device(struct xrad_context *ctx, bool present, xrad_error *err)
{
    gpu_device_offer offer;
    xrad_status s = gpu_device_query(ctx, ctx->phys, ctx->instance_api, present, &offer, err);
    if (s)
        return s;
    ctx->queue_family = offer.queue_family;
    ctx->features = offer.features;
    /* What is enabled: exactly the recorded features, nothing else. */
    gpu_device_enable e;
    gpu_device_enable_chain(&offer, present, &e);
    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = offer.queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    VkDeviceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &e.features,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
        .enabledExtensionCount = e.extension_count,
        .ppEnabledExtensionNames = e.extensions,
    };
    if (VK_CHECK(ctx, err, vkCreateDevice(ctx->phys, &info, NULL, &ctx->device)))
        return XRAD_ERROR_SYSTEM;
    vkGetDeviceQueue(ctx->device, offer.queue_family, 0, &ctx->queue);
    return gpu_context_finish(ctx, err);
}

xrad_status gpu_context_finish(struct xrad_context *ctx, xrad_error *err)
{
    xrad_status s;
    if (ctx->features.timeline_semaphore && (s = gpu_timeline_create(ctx, &ctx->timeline, err)))
        return s;
    return gpu_memory_create(ctx, &ctx->mem, err);
}

xrad_status gpu_context_alloc(const gpu_context_settings *settings, struct xrad_context **out,
                              xrad_error *err)
{
    *out = NULL;
    if (!(settings->memory_limit_mib >= 0 && settings->memory_limit_mib < 1e9))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "context: memory_limit_mib %g is not a size in MiB in [0, 1e9)",
                         settings->memory_limit_mib);
    gpu_fault fault = {0};
    xrad_status s;
    if (settings->fault && *settings->fault && (s = gpu_fault_parse(settings->fault, &fault, err)))
        return s;
    struct xrad_context *ctx = calloc(1, sizeof(*ctx));
    if (!ctx)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (context)");
    atomic_init(&ctx->validation_messages, 0);
    if (pthread_mutex_init(&ctx->queue_lock, NULL) != 0) {
        free(ctx);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "context: pthread_mutex_init failed");
    }
    if (fault.function[0])
        gpu_fault_set(ctx, fault.function, fault.nth, fault.result);
    ctx->wait_timeout_ns = DEFAULT_WAIT_TIMEOUT_NS;
    ctx->memory_limit = (uint64_t)(settings->memory_limit_mib * 1048576.0);
    ctx->log = settings->log;
    ctx->log_user = settings->log_user;
    *out = ctx;
    return XRAD_OK;
}

xrad_status xrad_context_create(const xrad_context_desc *desc, xrad_context **out,
                                xrad_error *err)
{
    *out = NULL;
    xrad_context_desc zero = {0};
    if (!desc)
        desc = &zero;
    struct xrad_context *ctx;
    xrad_status s = gpu_context_alloc(&(gpu_context_settings){desc->memory_limit_mib, desc->fault,
                                                               desc->log, desc->log_user},
                                      &ctx, err);
    if (s)
        return s;
    ctx->present = desc->present == 1;
    const char *hp = desc->hemicube_path;
    if (hp && !strcmp(hp, "multiview"))
        ctx->hemicube_path_only = GPU_HEMICUBE_ONLY_MULTIVIEW;
    else if (hp && !strcmp(hp, "layered"))
        ctx->hemicube_path_only = GPU_HEMICUBE_ONLY_LAYERED;
    else if (hp && *hp && strcmp(hp, "auto")) {
        xrad_context_destroy(&ctx);
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "xrad_context_desc.hemicube_path '%s': want auto, multiview or "
                         "layered", hp);
    }
    const char *wanted = desc->device && *desc->device ? desc->device : NULL;
    if ((s = create_instance(ctx, desc->validation == 1, desc, err)) ||
        (s = choose_device(ctx, wanted, err)) || (s = create_device(ctx, ctx->present, err))) {
        xrad_context_destroy(&ctx);
        return s;
    }
    *out = ctx;
    return XRAD_OK;
}

void gpu_queue_lock(struct xrad_context *ctx)
{
    pthread_mutex_lock(&ctx->queue_lock);
    if (ctx->import.lock_queue)
        ctx->import.lock_queue(ctx->import.queue_user, ctx->queue_family, ctx->import.queue_index);
}

void gpu_queue_unlock(struct xrad_context *ctx)
{
    if (ctx->import.unlock_queue)
        ctx->import.unlock_queue(ctx->import.queue_user, ctx->queue_family,
                                 ctx->import.queue_index);
    pthread_mutex_unlock(&ctx->queue_lock);
}

bool gpu_context_drained(struct xrad_context *ctx, uint64_t timeout_ns)
{
    if (!ctx->timeline)
        return false;
    gpu_queue_lock(ctx);
    uint64_t value = ctx->timeline_value;
    gpu_queue_unlock(ctx);
    VkSemaphoreWaitInfo info = {
        .sType = VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO,
        .semaphoreCount = 1,
        .pSemaphores = &ctx->timeline,
        .pValues = &value,
    };
    return vkWaitSemaphores(ctx->device, &info, timeout_ns) == VK_SUCCESS;
}

void xrad_context_destroy(xrad_context **pctx)
{
    if (!pctx || !*pctx)
        return;
    struct xrad_context *ctx = *pctx;
    /* A queue that hangs may never let its device go: lavapipe joins its
     * queue thread in vkDestroyDevice, and freeing memory that pending
     * work still uses is unsafe. So the whole context is left to process
     * exit, and the caller gets control back (the failure was reported
     * where the wait gave up). */
    *pctx = NULL;
    if (ctx->device && atomic_load(&ctx->hung) && !gpu_context_drained(ctx, GPU_HANG_GRACE_NS)) {
        gpu_log(ctx, XRAD_LOG_ERROR,
                "the GPU queue still has not finished after a hang: the context's device and "
                "objects are left to process exit");
        return;
    }
    gpu_context_free(ctx);
}

void gpu_context_free(struct xrad_context *ctx)
{
    if (ctx->device) {
        /* After a loss or a hang the device may never go idle; its objects
         * may still be destroyed (Vulkan spec, "Lost Device"). An imported
         * device's other queues are the application's: wait for xrad's. */
        if (!atomic_load(&ctx->lost)) {
            gpu_queue_lock(ctx);
            vkQueueWaitIdle(ctx->queue);
            gpu_queue_unlock(ctx);
        }
        if (ctx->mem) {
            gpu_memory_stats st;
            gpu_memory_get_stats(ctx, &st);
            if (st.allocations)
                gpu_log(ctx, XRAD_LOG_WARNING, "%u GPU memory allocations were not freed",
                        st.allocations);
        }
        gpu_memory_destroy(ctx, &ctx->mem);
        vkDestroySemaphore(ctx->device, ctx->timeline, NULL);
        for (uint32_t i = 0; i < ctx->pool_count; i++)
            vkDestroyCommandPool(ctx->device, ctx->pools[i].pool, NULL);
        if (!ctx->import.imported)
            vkDestroyDevice(ctx->device, NULL);
    }
    if (ctx->messenger)
        ctx->destroy_messenger(ctx->instance, ctx->messenger, NULL);
    if (ctx->instance && !ctx->import.imported)
        vkDestroyInstance(ctx->instance, NULL);
    pthread_mutex_destroy(&ctx->queue_lock);
    free(ctx);
}

void gpu_log(const struct xrad_context *ctx, xrad_log_level level, const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    if (ctx && ctx->log)
        ctx->log(ctx->log_user, level, msg);
    else
        fprintf(stderr, "xrad: %s\n", msg);
}

/* Reads variable `name`: NULL when unset or empty. */
static const char *env(const char *name)
{
    const char *v = getenv(name);
    return v && *v ? v : NULL;
}

xrad_status xrad_context_desc_from_env(xrad_context_desc *desc, xrad_error *err)
{
    const char *v;
    if (!desc->device)
        desc->device = env("XRAD_DEVICE");
    if (!desc->validation && (v = env("XRAD_VALIDATION")))
        desc->validation = !strcmp(v, "1");
    if (!desc->memory_limit_mib && (v = env("XRAD_GPU_MEMORY_MIB"))) {
        char *end;
        double mib = strtod(v, &end);
        if (*end || !(mib > 0 && mib < 1e9))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "XRAD_GPU_MEMORY_MIB: '%s' is not a size in MiB in (0, 1e9)", v);
        desc->memory_limit_mib = mib;
    }
    if (!desc->fault && (v = env("XRAD_FAULT"))) {
        gpu_fault f;
        xrad_error e;
        if (gpu_fault_parse(v, &f, &e))
            return xrad_fail(err, XRAD_ERROR_INPUT, "XRAD_FAULT: %s", e.message);
        desc->fault = v;
    }
    if (!desc->hemicube_path && (v = env("XRAD_HEMICUBE_PATH"))) {
        if (strcmp(v, "auto") && strcmp(v, "multiview") && strcmp(v, "layered"))
            return xrad_fail(err, XRAD_ERROR_INPUT,
                             "XRAD_HEMICUBE_PATH: '%s' is not auto, multiview or layered", v);
        desc->hemicube_path = v;
    }
    return XRAD_OK;
}

xrad_status gpu_thread_pool(struct xrad_context *ctx, VkCommandPool *out, xrad_error *err)
{
    pthread_t self = pthread_self();
    xrad_status s = XRAD_OK;
    pthread_mutex_lock(&ctx->queue_lock);
    uint32_t i = 0;
    while (i < ctx->pool_count && !pthread_equal(ctx->pools[i].thread, self))
        i++;
    if (i == ctx->pool_count) {
        if (i == GPU_MAX_THREADS) {
            s = xrad_fail(err, XRAD_ERROR_SYSTEM,
                          "more than %d threads record GPU commands on one context",
                          GPU_MAX_THREADS);
            goto done;
        }
        /* Short-lived one-shot command buffers. */
        VkCommandPoolCreateInfo info = {
            .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
            .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT |
                     VK_COMMAND_POOL_CREATE_TRANSIENT_BIT,
            .queueFamilyIndex = ctx->queue_family,
        };
        if ((s = VK_CHECK(ctx, err,
                          vkCreateCommandPool(ctx->device, &info, NULL, &ctx->pools[i].pool))))
            goto done;
        ctx->pools[i].thread = self;
        ctx->pool_count++;
    }
    *out = ctx->pools[i].pool;
done:
    pthread_mutex_unlock(&ctx->queue_lock);
    return s;
}

uint32_t xrad_context_validation_messages(const xrad_context *ctx)
{
    return ctx ? atomic_load(&((xrad_context *)ctx)->validation_messages) : 0;
}

const char *xrad_context_device_name(const xrad_context *ctx)
{
    return ctx->props.deviceName;
}

xrad_status xrad_devices_list(void (*fn)(void *user, const xrad_device_info *info), void *user,
                              xrad_error *err)
{
    /* A bare instance: listing must work where the validation layer or the
     * chosen device would not. */
    struct xrad_context tmp = {0};
    xrad_status s = create_instance(&tmp, false, NULL, err);
    VkPhysicalDevice *devs = NULL;
    uint32_t n = 0;
    if (!s)
        s = enumerate_devices(NULL, tmp.instance, &devs, &n, err);
    for (uint32_t i = 0; i < n; i++) {
        VkPhysicalDeviceProperties p;
        VkPhysicalDeviceMemoryProperties mp;
        vkGetPhysicalDeviceProperties(devs[i], &p);
        vkGetPhysicalDeviceMemoryProperties(devs[i], &mp);
        xrad_device_info info = {
            .type = device_type_name(p.deviceType),
            .api_version = p.apiVersion,
        };
        snprintf(info.name, sizeof(info.name), "%s", p.deviceName);
        for (uint32_t h = 0; h < mp.memoryHeapCount; h++)
            if (mp.memoryHeaps[h].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
                info.device_local_bytes += mp.memoryHeaps[h].size;
        fn(user, &info);
    }
    free(devs);
    if (tmp.instance)
        vkDestroyInstance(tmp.instance, NULL);
    return s;
}
