/*
 * xrad on the application's own Vulkan device (include/xrad_vulkan.h,
 * issue 17.1), through the public API only. The test plays the
 * application: its own instance with the validation layer and a messenger
 * that counts every warning and error, its own device made with what
 * xrad_vulkan_get_requirements lists, a queue lock of its own. Checks:
 *  - the handles xrad reports are the application's;
 *  - a progressive solve of cornell-lowq on the imported device equals,
 *    element by element, the same solve on a context xrad made itself
 *    (one device, one code path: the import changes nothing);
 *  - xrad took the application's queue lock, as often as it released it;
 *  - after xrad_context_destroy the device still works and holds nothing
 *    of xrad's: the layer reports every object left at vkDestroyDevice,
 *    and no message came at all;
 *  - a desc without a device, or with a queue family the device lacks, is
 *    refused as input.
 */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "xrad.h"
#include "xrad_vulkan.h"

static unsigned messages;

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT type,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data,
                                                 void *user)
{
    (void)type;
    (void)user;
    if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT)) {
        messages++;
        fprintf(stderr, "validation: %s\n", data && data->pMessage ? data->pMessage : "?");
    }
    return VK_FALSE;
}

typedef struct app {
    VkInstance instance;
    uint32_t api;
    VkDebugUtilsMessengerEXT messenger;
    VkPhysicalDevice phys;
    VkDevice device;
    uint32_t family;
    int locked, unlocked, depth, max_depth;
} app;

static void lock_queue(void *user, uint32_t family, uint32_t index)
{
    app *a = user;
    CHECK(family == a->family && index == 0, "lock of queue %u/%u", family, index);
    a->locked++;
    a->depth++;
    a->max_depth = a->depth > a->max_depth ? a->depth : a->max_depth;
}

static void unlock_queue(void *user, uint32_t family, uint32_t index)
{
    app *a = user;
    (void)family;
    (void)index;
    a->unlocked++;
    a->depth--;
}

static int app_create(app *a)
{
    memset(a, 0, sizeof(*a));
    a->api = VK_API_VERSION_1_2;
    uint32_t loader = 0;
    if (vkEnumerateInstanceVersion(&loader) == VK_SUCCESS && loader >= VK_API_VERSION_1_3)
        a->api = VK_API_VERSION_1_3;
    const char *layer = "VK_LAYER_KHRONOS_validation";
    const char *ext = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    VkDebugUtilsMessengerCreateInfoEXT mi = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_message,
    };
    VkInstanceCreateInfo ii = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = &mi,
        .pApplicationInfo = &(VkApplicationInfo){.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                                                 .pApplicationName = "test_vulkan_import",
                                                 .apiVersion = a->api},
        .enabledLayerCount = 1,
        .ppEnabledLayerNames = &layer,
        .enabledExtensionCount = 1,
        .ppEnabledExtensionNames = &ext,
    };
    VkResult r = vkCreateInstance(&ii, NULL, &a->instance);
    CHECK(r == VK_SUCCESS, "vkCreateInstance with the validation layer: %d", (int)r);
    if (r)
        return 0;
    PFN_vkCreateDebugUtilsMessengerEXT create_messenger =
        (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
            a->instance, "vkCreateDebugUtilsMessengerEXT");
    CHECK(create_messenger && create_messenger(a->instance, &mi, NULL, &a->messenger) == 0,
          "debug messenger");
    uint32_t n = 1;
    r = vkEnumeratePhysicalDevices(a->instance, &n, &a->phys);
    CHECK((r == VK_SUCCESS || r == VK_INCOMPLETE) && n == 1, "a physical device: %d", (int)r);
    if (n != 1)
        return 0;

    xrad_vulkan_requirements req;
    xrad_error err = {0};
    CHECK(xrad_vulkan_get_requirements(a->phys, a->api, 0, &req, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(req.api_version == VK_API_VERSION_1_2 && req.features.pNext == &req.vulkan11,
          "requirements: api %u, chain from features", req.api_version);
    a->family = req.queue_family;
    float priority = 1;
    VkDeviceCreateInfo di = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &req.features,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &(VkDeviceQueueCreateInfo){
            .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
            .queueFamilyIndex = req.queue_family,
            .queueCount = 1,
            .pQueuePriorities = &priority,
        },
        .enabledExtensionCount = req.extension_count,
        .ppEnabledExtensionNames = req.extensions,
    };
    r = vkCreateDevice(a->phys, &di, NULL, &a->device);
    CHECK(r == VK_SUCCESS, "vkCreateDevice with xrad's requirements: %d", (int)r);
    return r == VK_SUCCESS;
}

static void app_destroy(app *a)
{
    if (a->device)
        vkDestroyDevice(a->device, NULL);
    if (a->messenger) {
        PFN_vkDestroyDebugUtilsMessengerEXT destroy =
            (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                a->instance, "vkDestroyDebugUtilsMessengerEXT");
        destroy(a->instance, a->messenger, NULL);
    }
    if (a->instance)
        vkDestroyInstance(a->instance, NULL);
}

/* Progressive on `scene` at default settings; the solution in *atlas. */
static xrad_status solve(xrad_context *ctx, const xrad_scene *scene, xrad_atlas *atlas,
                         xrad_error *err)
{
    xrad_solver *solver = NULL;
    xrad_status st = xrad_atlas_create(scene, atlas, err);
    if (!st)
        st = xrad_solver_create(ctx, scene,
                                &(xrad_solver_desc){.method = XRAD_METHOD_PROGRESSIVE}, &solver,
                                err);
    if (!st)
        st = xrad_solver_solve(solver, err);
    if (!st)
        st = xrad_solver_read(solver, atlas, err);
    xrad_solver_destroy(&solver);
    return st;
}

int main(void)
{
    char path[1024];
    xrad_error err = {0};
    xrad_scene *scene = NULL;
    xrad_status st = xrad_scene_load(test_source_path("scenes/cornell-lowq.json", path,
                                                      sizeof(path)),
                                     &scene, &err);
    CHECK(st == XRAD_OK, "scene: %s", err.message);
    app a;
    if (st || !app_create(&a)) {
        xrad_scene_destroy(&scene);
        return test_finish();
    }

    /* Refused as input. */
    xrad_context *ctx = NULL;
    CHECK(xrad_vulkan_import(&(xrad_vulkan_import_desc){.instance = a.instance}, &ctx, &err) ==
                  XRAD_ERROR_INPUT &&
              !ctx,
          "import without a device: %s", err.message);
    xrad_vulkan_import_desc d = {
        .instance = a.instance,
        .instance_api_version = a.api,
        .physical_device = a.phys,
        .device = a.device,
        .queue_family = 1000,
    };
    CHECK(xrad_vulkan_import(&d, &ctx, &err) == XRAD_ERROR_INPUT && !ctx &&
              strstr(err.message, "1000"),
          "import of family 1000: %s", err.message);

    d.queue_family = a.family;
    d.lock_queue = lock_queue;
    d.unlock_queue = unlock_queue;
    d.queue_user = &a;
    st = xrad_vulkan_import(&d, &ctx, &err);
    CHECK(st == XRAD_OK, "import: %s", err.message);
    xrad_atlas mine = {0}, own = {0};
    if (!st) {
        uint32_t family = 99;
        VkQueue q = xrad_vulkan_queue(ctx, &family);
        VkQueue app_q;
        vkGetDeviceQueue(a.device, a.family, 0, &app_q);
        CHECK(xrad_vulkan_instance(ctx) == a.instance && xrad_vulkan_device(ctx) == a.device &&
                  xrad_vulkan_physical_device(ctx) == a.phys && q == app_q &&
                  family == a.family,
              "the handles are the application's");
        st = solve(ctx, scene, &mine, &err);
        CHECK(st == XRAD_OK, "progressive on the imported device: %s", err.message);
        xrad_context_destroy(&ctx);
        CHECK(a.locked > 0 && a.locked == a.unlocked && a.depth == 0 && a.max_depth == 1,
              "queue lock: %d locks, %d unlocks, nested %d", a.locked, a.unlocked, a.max_depth);
        /* The device is the application's still. */
        CHECK(vkDeviceWaitIdle(a.device) == VK_SUCCESS, "the device after xrad");
    }

    /* The same solve on a context xrad makes itself. */
    xrad_context *self = NULL;
    st = xrad_context_create(&(xrad_context_desc){.validation = 1}, &self, &err);
    CHECK(st == XRAD_OK, "own context: %s", err.message);
    if (!st && mine.rgba) {
        st = solve(self, scene, &own, &err);
        CHECK(st == XRAD_OK, "progressive on xrad's device: %s", err.message);
        CHECK(xrad_vulkan_device(self) && xrad_vulkan_device(self) != a.device,
              "xrad's own device is its own");
        CHECK(xrad_context_validation_messages(self) == 0, "%u validation messages",
              xrad_context_validation_messages(self));
    }
    if (mine.rgba && own.rgba) {
        xrad_element_metrics m;
        st = xrad_atlas_compare(scene, &mine, &own, &m, NULL, &err);
        CHECK(st == XRAD_OK, "compare: %s", err.message);
        fprintf(stderr, "imported vs own device: surface_error %.3g, element max %.3g\n",
                m.surface_error, m.max);
        CHECK(m.elements > 0 && m.surface_error < 1e-5 && m.max < 1e-4,
              "imported differs from own: surface_error %.3g, element max %.3g over %u",
              m.surface_error, m.max, m.elements);
    }
    xrad_context_destroy(&self);
    xrad_atlas_destroy(&mine);
    xrad_atlas_destroy(&own);
    xrad_scene_destroy(&scene);
    app_destroy(&a);
    CHECK(messages == 0, "%u validation messages on the application's instance", messages);
    return test_finish();
}
