/*
 * xrad in someone else's renderer: a minimal GLFW + Vulkan program that
 * owns its instance, device and swapchain, hands the device to xrad
 * (include/xrad_vulkan.h), and draws the scene with a pipeline of its own
 * that samples xrad's front radiosity atlas per frame (embed.vert,
 * embed.frag: the snippet of include/xrad.h). The real-time loop runs on
 * xrad's worker thread; this program only requests scene times and poses
 * and waits on / signals the frame's timeline values.
 *
 *   embed SCENE [--method cross|incremental|progressive] [--exposure E]
 *         [--frames N --fps F --screenshot OUT.exr]
 *
 * Without --frames it runs until the window closes: the scene's animation
 * plays, and the arrow keys move the first dynamic object (a rigid pose on
 * top of its animation). With --frames it advances N frames of 1/F s, waits
 * for the last one's solution, and writes the linear radiosity image of
 * that frame (the view of the scene's camera, exposure 1) to OUT.exr:
 * tests/cli/test_embed.sh compares it with `xrad render` of the same time.
 * XRAD_VALIDATION=1 turns on the validation layer on the program's own
 * instance; any message makes the exit status 1.
 *
 * Only the public headers are used; error handling is the example's own
 * (a message and exit status 1 or 2, as the xrad tool's).
 */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "embed.frag.h"
#include "embed.vert.h"
#include "xrad.h"
#include "xrad_vulkan.h"

typedef struct options {
    const char *scene, *screenshot;
    xrad_method method;
    double exposure, fps;
    uint32_t frames;
} options;

typedef struct vertex {
    float pos[3];    /* object space */
    float a[3];      /* (s w, t, w): include/xrad.h */
    float tile_n[4]; /* tile_x, tile_y, nu, nv */
} vertex;

typedef struct target_image {
    VkImage image;
    VkDeviceMemory memory;
    VkImageView view;
} target_image;

typedef struct app {
    GLFWwindow *window;
    VkInstance instance;
    uint32_t api;
    VkDebugUtilsMessengerEXT messenger;
    VkSurfaceKHR surface;
    VkPhysicalDevice phys;
    VkDevice device;
    uint32_t family;
    VkQueue queue;
    xrad_context *ctx;
    /* The swapchain, blitted to from the offscreen colour image. */
    VkSwapchainKHR swapchain;
    VkFormat swap_format;
    VkExtent2D extent;
    uint32_t swap_count;
    VkImage swap_images[8];
    /* Drawing. */
    uint32_t width, height;
    target_image color, depth;
    VkRenderPass pass;
    VkFramebuffer framebuffer;
    VkDescriptorSetLayout set_layout;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkSampler sampler;
    VkBuffer vertices;
    VkDeviceMemory vertex_memory;
    VkCommandPool cmd_pool;
    VkCommandBuffer cmd;
    VkFence fence;
    VkSemaphore acquired, rendered;
    /* The scene as this program draws it. */
    xrad_scene *scene; /* a copy of its own: the scheduler owns the other */
    uint32_t objects;
    uint32_t *first, *count; /* vertices of each object */
    double atlas_w, atlas_h;
    double view_proj[16];
} app;

static unsigned validation_messages;

static int fail(int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "embed: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n");
    va_end(ap);
    return status;
}

#define VK(call)                                                                                  \
    do {                                                                                          \
        VkResult r_ = (call);                                                                     \
        if (r_ != VK_SUCCESS)                                                                     \
            return fail(2, "%s failed: VkResult %d (%s:%d)", #call, (int)r_, __FILE__,             \
                        __LINE__);                                                                \
    } while (0)

static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                                 VkDebugUtilsMessageTypeFlagsEXT type,
                                                 const VkDebugUtilsMessengerCallbackDataEXT *data,
                                                 void *user)
{
    (void)type;
    (void)user;
    if (severity & (VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                    VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT)) {
        validation_messages++;
        fprintf(stderr, "embed: vulkan validation: %s\n", data->pMessage);
    }
    return VK_FALSE;
}

static void on_log(void *user, xrad_log_level level, const char *message)
{
    (void)user;
    fprintf(stderr, "embed: xrad %s: %s\n", level == XRAD_LOG_ERROR ? "error" : "warning",
            message);
}

/* ------------------------------------------------------------- matrices */

/* c = a b, column-major 4 x 4. */
static void mat_mul(const double *a, const double *b, double *c)
{
    double t[16];
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double v = 0;
            for (int k = 0; k < 4; k++)
                v += a[k * 4 + row] * b[col * 4 + k];
            t[col * 4 + row] = v;
        }
    memcpy(c, t, sizeof(t));
}

/* The scene camera's projection * view, Vulkan clip space (y down, depth
 * 0 at `near` to 1 at infinity reversed: 1 near, 0 far). */
static void camera_matrix(const xrad_camera_desc *c, double aspect, double *out)
{
    double f[3], r[3], u[3], len = 0;
    for (int k = 0; k < 3; k++) {
        f[k] = c->look_at[k] - c->position[k];
        len += f[k] * f[k];
    }
    for (int k = 0; k < 3; k++)
        f[k] /= sqrt(len);
    r[0] = f[1] * c->up[2] - f[2] * c->up[1];
    r[1] = f[2] * c->up[0] - f[0] * c->up[2];
    r[2] = f[0] * c->up[1] - f[1] * c->up[0];
    len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int k = 0; k < 3; k++)
        r[k] /= len;
    u[0] = r[1] * f[2] - r[2] * f[1];
    u[1] = r[2] * f[0] - r[0] * f[2];
    u[2] = r[0] * f[1] - r[1] * f[0];
    double view[16] = {0};
    for (int k = 0; k < 3; k++) {
        view[k * 4 + 0] = r[k];
        view[k * 4 + 1] = -u[k]; /* Vulkan's y points down */
        view[k * 4 + 2] = f[k];
    }
    view[12] = -(r[0] * c->position[0] + r[1] * c->position[1] + r[2] * c->position[2]);
    view[13] = u[0] * c->position[0] + u[1] * c->position[1] + u[2] * c->position[2];
    view[14] = -(f[0] * c->position[0] + f[1] * c->position[1] + f[2] * c->position[2]);
    view[15] = 1;
    double sy = 1.0 / tan(0.5 * c->fov_degrees * M_PI / 180.0), sx = sy / aspect;
    const double near = 1e-3; /* m; reversed infinite depth keeps precision far away */
    double proj[16] = {0};
    proj[0] = sx;
    proj[5] = sy;
    proj[11] = 1;     /* w = view depth */
    proj[14] = near;  /* z = near: depth near / d */
    mat_mul(proj, view, out);
}

/* --------------------------------------------------------------- Vulkan */

static int memory_type(app *a, uint32_t bits, VkMemoryPropertyFlags want, uint32_t *out)
{
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(a->phys, &mp);
    for (uint32_t i = 0; i < mp.memoryTypeCount; i++)
        if ((bits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want) {
            *out = i;
            return 0;
        }
    return fail(2, "no memory type with properties 0x%x", (unsigned)want);
}

static int image_create(app *a, VkFormat format, VkImageUsageFlags usage,
                        VkImageAspectFlags aspect, target_image *out)
{
    VkImageCreateInfo ii = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO,
        .imageType = VK_IMAGE_TYPE_2D,
        .format = format,
        .extent = {a->width, a->height, 1},
        .mipLevels = 1,
        .arrayLayers = 1,
        .samples = VK_SAMPLE_COUNT_1_BIT,
        .tiling = VK_IMAGE_TILING_OPTIMAL,
        .usage = usage,
    };
    VK(vkCreateImage(a->device, &ii, NULL, &out->image));
    VkMemoryRequirements req;
    vkGetImageMemoryRequirements(a->device, out->image, &req);
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size};
    if (memory_type(a, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT,
                    &ai.memoryTypeIndex))
        return 2;
    VK(vkAllocateMemory(a->device, &ai, NULL, &out->memory));
    VK(vkBindImageMemory(a->device, out->image, out->memory, 0));
    VkImageViewCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO,
        .image = out->image,
        .viewType = VK_IMAGE_VIEW_TYPE_2D,
        .format = format,
        .subresourceRange = {aspect, 0, 1, 0, 1},
    };
    VK(vkCreateImageView(a->device, &vi, NULL, &out->view));
    return 0;
}

static void image_destroy(app *a, target_image *im)
{
    vkDestroyImageView(a->device, im->view, NULL);
    vkDestroyImage(a->device, im->image, NULL);
    vkFreeMemory(a->device, im->memory, NULL);
}

static int create_instance(app *a)
{
    uint32_t n = 0;
    const char **glfw = glfwGetRequiredInstanceExtensions(&n);
    if (!glfw)
        return fail(2, "GLFW finds no Vulkan presentation support");
    const char *ext[16];
    uint32_t count = 0;
    for (uint32_t i = 0; i < n && count < 15; i++)
        ext[count++] = glfw[i];
    const char *env = getenv("XRAD_VALIDATION");
    int validation = env && !strcmp(env, "1");
    if (validation)
        ext[count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
    const char *layer = "VK_LAYER_KHRONOS_validation";
    a->api = VK_API_VERSION_1_2;
    uint32_t loader = 0;
    if (vkEnumerateInstanceVersion(&loader) == VK_SUCCESS && loader >= VK_API_VERSION_1_3)
        a->api = VK_API_VERSION_1_3;
    VkDebugUtilsMessengerCreateInfoEXT mi = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT,
        .pfnUserCallback = on_message,
    };
    VkApplicationInfo app_info = {.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
                                  .pApplicationName = "xrad embed example",
                                  .apiVersion = a->api};
    VkInstanceCreateInfo ii = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = validation ? &mi : NULL,
        .pApplicationInfo = &app_info,
        .enabledLayerCount = validation ? 1 : 0,
        .ppEnabledLayerNames = &layer,
        .enabledExtensionCount = count,
        .ppEnabledExtensionNames = ext,
    };
    VK(vkCreateInstance(&ii, NULL, &a->instance));
    if (validation) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                a->instance, "vkCreateDebugUtilsMessengerEXT");
        VK(create(a->instance, &mi, NULL, &a->messenger));
    }
    VK(glfwCreateWindowSurface(a->instance, a->window, NULL, &a->surface));
    return 0;
}

/* The first device xrad can use whose xrad queue family presents. */
static int create_device(app *a)
{
    VkPhysicalDevice devs[16];
    uint32_t n = 16;
    VkResult r = vkEnumeratePhysicalDevices(a->instance, &n, devs);
    if (r != VK_SUCCESS && r != VK_INCOMPLETE)
        return fail(2, "vkEnumeratePhysicalDevices: %d", (int)r);
    xrad_vulkan_requirements req;
    xrad_error err = {0};
    for (uint32_t i = 0; i < n && !a->phys; i++) {
        VkBool32 present = VK_FALSE;
        if (xrad_vulkan_get_requirements(devs[i], a->api, 1, &req, &err) == XRAD_OK &&
            vkGetPhysicalDeviceSurfaceSupportKHR(devs[i], req.queue_family, a->surface,
                                                 &present) == VK_SUCCESS &&
            present)
            a->phys = devs[i];
    }
    if (!a->phys)
        return fail(2, "no Vulkan device that xrad can use presents to this window (%s)",
                    err.message[0] ? err.message : "none offered");
    /* req is the chosen device's: the loop ended right after filling it. */
    a->family = req.queue_family;
    float priority = 1;
    VkDeviceQueueCreateInfo qi = {.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
                                  .queueFamilyIndex = req.queue_family,
                                  .queueCount = 1,
                                  .pQueuePriorities = &priority};
    VkDeviceCreateInfo di = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = &req.features,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &qi,
        .enabledExtensionCount = req.extension_count,
        .ppEnabledExtensionNames = req.extensions,
    };
    VK(vkCreateDevice(a->phys, &di, NULL, &a->device));
    vkGetDeviceQueue(a->device, a->family, 0, &a->queue);
    xrad_vulkan_import_desc d = {
        .instance = a->instance,
        .instance_api_version = a->api,
        .physical_device = a->phys,
        .device = a->device,
        .queue_family = a->family,
        .enabled_features = &req.features,
        .enabled_extensions = req.extensions,
        .enabled_extension_count = req.extension_count,
        .log = on_log,
    };
    if (xrad_vulkan_import(&d, &a->ctx, &err))
        return fail(err.status, "%s", err.message);
    return 0;
}

static int create_swapchain(app *a)
{
    VkSurfaceCapabilitiesKHR caps;
    VK(vkGetPhysicalDeviceSurfaceCapabilitiesKHR(a->phys, a->surface, &caps));
    VkSurfaceFormatKHR formats[32];
    uint32_t n = 32;
    VkResult r = vkGetPhysicalDeviceSurfaceFormatsKHR(a->phys, a->surface, &n, formats);
    if ((r != VK_SUCCESS && r != VK_INCOMPLETE) || !n)
        return fail(2, "the surface offers no format");
    a->swap_format = formats[0].format;
    for (uint32_t i = 0; i < n; i++)
        if (formats[i].format == VK_FORMAT_B8G8R8A8_UNORM)
            a->swap_format = formats[i].format;
    int w, h;
    glfwGetFramebufferSize(a->window, &w, &h);
    a->extent = caps.currentExtent.width != UINT32_MAX
                    ? caps.currentExtent
                    : (VkExtent2D){(uint32_t)w, (uint32_t)h};
    VkSwapchainKHR old = a->swapchain;
    VkSwapchainCreateInfoKHR si = {
        .sType = VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR,
        .surface = a->surface,
        .minImageCount = caps.minImageCount + 1 <= caps.maxImageCount || !caps.maxImageCount
                             ? caps.minImageCount + 1
                             : caps.minImageCount,
        .imageFormat = a->swap_format,
        .imageColorSpace = VK_COLOR_SPACE_SRGB_NONLINEAR_KHR,
        .imageExtent = a->extent,
        .imageArrayLayers = 1,
        .imageUsage = VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .preTransform = caps.currentTransform,
        .compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR,
        .presentMode = VK_PRESENT_MODE_FIFO_KHR,
        .clipped = VK_TRUE,
        .oldSwapchain = old,
    };
    VK(vkCreateSwapchainKHR(a->device, &si, NULL, &a->swapchain));
    if (old)
        vkDestroySwapchainKHR(a->device, old, NULL);
    a->swap_count = 8;
    VK(vkGetSwapchainImagesKHR(a->device, a->swapchain, &a->swap_count, a->swap_images));
    return 0;
}

/* After a resize: the queue idle (xrad's worker shares it, hence the
 * lock), then a new swapchain. */
static int recreate_swapchain(app *a)
{
    xrad_vulkan_lock_queue(a->ctx);
    VkResult r = vkQueueWaitIdle(a->queue);
    xrad_vulkan_unlock_queue(a->ctx);
    VK(r);
    return create_swapchain(a);
}

static int create_drawing(app *a)
{
    int st;
    if ((st = image_create(a, VK_FORMAT_R32G32B32A32_SFLOAT,
                           VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                           VK_IMAGE_ASPECT_COLOR_BIT, &a->color)) ||
        (st = image_create(a, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                           VK_IMAGE_ASPECT_DEPTH_BIT, &a->depth)))
        return st;
    VkAttachmentDescription att[2] = {
        {.format = VK_FORMAT_R32G32B32A32_SFLOAT,
         .samples = VK_SAMPLE_COUNT_1_BIT,
         .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
         .storeOp = VK_ATTACHMENT_STORE_OP_STORE,
         .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
         .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
         .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
         .finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL},
        {.format = VK_FORMAT_D32_SFLOAT,
         .samples = VK_SAMPLE_COUNT_1_BIT,
         .loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR,
         .storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
         .stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE,
         .stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE,
         .initialLayout = VK_IMAGE_LAYOUT_UNDEFINED,
         .finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL},
    };
    VkAttachmentReference cref = {0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference dref = {1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub = {.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS,
                                .colorAttachmentCount = 1,
                                .pColorAttachments = &cref,
                                .pDepthStencilAttachment = &dref};
    /* The last frame's copy out of the colour image before this clear. */
    VkSubpassDependency dep = {
        .srcSubpass = VK_SUBPASS_EXTERNAL,
        .dstSubpass = 0,
        .srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT,
        .dstStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                        VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT,
        .srcAccessMask = 0,
        .dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT |
                         VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT,
    };
    VkRenderPassCreateInfo pi = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO,
                                 .attachmentCount = 2,
                                 .pAttachments = att,
                                 .subpassCount = 1,
                                 .pSubpasses = &sub,
                                 .dependencyCount = 1,
                                 .pDependencies = &dep};
    VK(vkCreateRenderPass(a->device, &pi, NULL, &a->pass));
    VkImageView views[2] = {a->color.view, a->depth.view};
    VkFramebufferCreateInfo fi = {.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
                                  .renderPass = a->pass,
                                  .attachmentCount = 2,
                                  .pAttachments = views,
                                  .width = a->width,
                                  .height = a->height,
                                  .layers = 1};
    VK(vkCreateFramebuffer(a->device, &fi, NULL, &a->framebuffer));

    VkDescriptorSetLayoutBinding b = {.binding = 0,
                                      .descriptorType =
                                          VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                                      .descriptorCount = 1,
                                      .stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT};
    VkDescriptorSetLayoutCreateInfo li = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = 1,
        .pBindings = &b};
    VK(vkCreateDescriptorSetLayout(a->device, &li, NULL, &a->set_layout));
    VkDescriptorPoolSize ps = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    VkDescriptorPoolCreateInfo dpi = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
                                      .maxSets = 1,
                                      .poolSizeCount = 1,
                                      .pPoolSizes = &ps};
    VK(vkCreateDescriptorPool(a->device, &dpi, NULL, &a->pool));
    VkDescriptorSetAllocateInfo dai = {.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
                                       .descriptorPool = a->pool,
                                       .descriptorSetCount = 1,
                                       .pSetLayouts = &a->set_layout};
    VK(vkAllocateDescriptorSets(a->device, &dai, &a->set));
    /* Bilinear between the element samples; the snippet keeps reads inside
     * each surface's tile. */
    VkSamplerCreateInfo si = {.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO,
                              .magFilter = VK_FILTER_LINEAR,
                              .minFilter = VK_FILTER_LINEAR,
                              .addressModeU = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                              .addressModeV = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE,
                              .addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE};
    VK(vkCreateSampler(a->device, &si, NULL, &a->sampler));
    VkPushConstantRange range = {VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                 80};
    VkPipelineLayoutCreateInfo pli = {.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
                                      .setLayoutCount = 1,
                                      .pSetLayouts = &a->set_layout,
                                      .pushConstantRangeCount = 1,
                                      .pPushConstantRanges = &range};
    VK(vkCreatePipelineLayout(a->device, &pli, NULL, &a->layout));

    VkShaderModule vs, fs;
    VkShaderModuleCreateInfo vsi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                    .codeSize = sizeof(embed_vert_spv),
                                    .pCode = embed_vert_spv};
    VkShaderModuleCreateInfo fsi = {.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
                                    .codeSize = sizeof(embed_frag_spv),
                                    .pCode = embed_frag_spv};
    VK(vkCreateShaderModule(a->device, &vsi, NULL, &vs));
    VK(vkCreateShaderModule(a->device, &fsi, NULL, &fs));
    VkPipelineShaderStageCreateInfo stages[2] = {
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_VERTEX_BIT,
         .module = vs,
         .pName = "main"},
        {.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
         .stage = VK_SHADER_STAGE_FRAGMENT_BIT,
         .module = fs,
         .pName = "main"},
    };
    VkVertexInputBindingDescription vb = {0, sizeof(vertex), VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription va[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, pos)},
        {1, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(vertex, a)},
        {2, 0, VK_FORMAT_R32G32B32A32_SFLOAT, offsetof(vertex, tile_n)},
    };
    VkPipelineVertexInputStateCreateInfo vi = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO,
        .vertexBindingDescriptionCount = 1,
        .pVertexBindingDescriptions = &vb,
        .vertexAttributeDescriptionCount = 3,
        .pVertexAttributeDescriptions = va};
    VkPipelineInputAssemblyStateCreateInfo ia = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO,
        .topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST};
    VkViewport viewport = {0, 0, (float)a->width, (float)a->height, 0, 1};
    VkRect2D scissor = {{0, 0}, {a->width, a->height}};
    VkPipelineViewportStateCreateInfo vps = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO,
        .viewportCount = 1,
        .pViewports = &viewport,
        .scissorCount = 1,
        .pScissors = &scissor};
    /* Light leaves a surface's front only: its back is not drawn. */
    VkPipelineRasterizationStateCreateInfo rs = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO,
        .polygonMode = VK_POLYGON_MODE_FILL,
        .cullMode = VK_CULL_MODE_NONE,
        .frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .lineWidth = 1};
    VkPipelineMultisampleStateCreateInfo ms = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO,
        .rasterizationSamples = VK_SAMPLE_COUNT_1_BIT};
    VkPipelineDepthStencilStateCreateInfo ds = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO,
        .depthTestEnable = VK_TRUE,
        .depthWriteEnable = VK_TRUE,
        .depthCompareOp = VK_COMPARE_OP_GREATER};
    VkPipelineColorBlendAttachmentState cb = {.colorWriteMask = 0xf};
    VkPipelineColorBlendStateCreateInfo cbs = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO,
        .attachmentCount = 1,
        .pAttachments = &cb};
    VkGraphicsPipelineCreateInfo gi = {
        .sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO,
        .stageCount = 2,
        .pStages = stages,
        .pVertexInputState = &vi,
        .pInputAssemblyState = &ia,
        .pViewportState = &vps,
        .pRasterizationState = &rs,
        .pMultisampleState = &ms,
        .pDepthStencilState = &ds,
        .pColorBlendState = &cbs,
        .layout = a->layout,
        .renderPass = a->pass};
    VkResult r = vkCreateGraphicsPipelines(a->device, VK_NULL_HANDLE, 1, &gi, NULL, &a->pipeline);
    vkDestroyShaderModule(a->device, vs, NULL);
    vkDestroyShaderModule(a->device, fs, NULL);
    VK(r);

    VkCommandPoolCreateInfo cpi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                   .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                   .queueFamilyIndex = a->family};
    VK(vkCreateCommandPool(a->device, &cpi, NULL, &a->cmd_pool));
    VkCommandBufferAllocateInfo cai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                       .commandPool = a->cmd_pool,
                                       .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                       .commandBufferCount = 1};
    VK(vkAllocateCommandBuffers(a->device, &cai, &a->cmd));
    VkFenceCreateInfo fci = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO,
                             .flags = VK_FENCE_CREATE_SIGNALED_BIT};
    VK(vkCreateFence(a->device, &fci, NULL, &a->fence));
    VkSemaphoreCreateInfo sci = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    VK(vkCreateSemaphore(a->device, &sci, NULL, &a->acquired));
    VK(vkCreateSemaphore(a->device, &sci, NULL, &a->rendered));
    return 0;
}

/* Every surface as triangles in object space, object by object, with the
 * atlas attributes of include/xrad.h. */
static int create_geometry(app *a)
{
    xrad_scene_info info;
    xrad_scene_get_info(a->scene, &info);
    a->objects = info.objects;
    a->atlas_w = info.atlas_width;
    a->atlas_h = info.atlas_height;
    a->first = calloc(info.objects, sizeof(uint32_t));
    a->count = calloc(info.objects, sizeof(uint32_t));
    vertex *v = calloc((size_t)info.surfaces * 6, sizeof(vertex));
    if (!a->first || !a->count || !v)
        return fail(2, "out of memory");
    uint32_t n = 0;
    static const double st[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    static const int quad[6] = {0, 1, 2, 0, 2, 3};
    for (uint32_t o = 0; o < info.objects; o++) {
        a->first[o] = n;
        for (uint32_t s = 0; s < info.surfaces; s++) {
            xrad_surface_info sf;
            xrad_scene_get_surface(a->scene, s, &sf, NULL);
            if (sf.object != o)
                continue;
            for (int k = 0; k < (sf.triangle ? 3 : 6); k++) {
                int c = quad[k];
                double w = sf.triangle && c == 2 ? 0 : 1;
                vertex *x = &v[n++];
                for (int i = 0; i < 3; i++)
                    x->pos[i] = (float)sf.corners[c][i];
                x->a[0] = (float)(st[c][0] * w);
                x->a[1] = (float)st[c][1];
                x->a[2] = (float)w;
                x->tile_n[0] = (float)sf.tile_x;
                x->tile_n[1] = (float)sf.tile_y;
                x->tile_n[2] = (float)sf.nu;
                x->tile_n[3] = (float)sf.nv;
            }
        }
        a->count[o] = n - a->first[o];
    }
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                             .size = (VkDeviceSize)(n ? n : 1) * sizeof(vertex),
                             .usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT};
    VK(vkCreateBuffer(a->device, &bi, NULL, &a->vertices));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(a->device, a->vertices, &req);
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size};
    if (memory_type(a, req.memoryTypeBits,
                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                    &ai.memoryTypeIndex))
        return 2;
    VK(vkAllocateMemory(a->device, &ai, NULL, &a->vertex_memory));
    VK(vkBindBufferMemory(a->device, a->vertices, a->vertex_memory, 0));
    void *map;
    VK(vkMapMemory(a->device, a->vertex_memory, 0, bi.size, 0, &map));
    memcpy(map, v, (size_t)n * sizeof(vertex));
    vkUnmapMemory(a->device, a->vertex_memory);
    free(v);
    return 0;
}

static void barrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                    VkPipelineStageFlags src, VkAccessFlags src_access, VkPipelineStageFlags dst,
                    VkAccessFlags dst_access)
{
    VkImageMemoryBarrier b = {.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                              .srcAccessMask = src_access,
                              .dstAccessMask = dst_access,
                              .oldLayout = from,
                              .newLayout = to,
                              .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                              .image = image,
                              .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1}};
    vkCmdPipelineBarrier(cmd, src, dst, 0, 0, NULL, 0, NULL, 1, &b);
}

/* One frame: the scene drawn with the front atlas into the colour image at
 * `scale`, then blitted to the window (and, with `readback`, copied to
 * it: width x height RGBA floats). */
static int draw_frame(app *a, xrad_scheduler *sch, double scale, VkBuffer readback)
{
    xrad_error err = {0};
    xrad_frame f;
    if (xrad_scheduler_begin_frame(sch, &f, &err))
        return fail(err.status, "%s", err.message);
    VK(vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX));
    if (!f.image) { /* nothing solved yet */
        if (xrad_scheduler_end_frame(sch, &f, 0, &err))
            return fail(err.status, "%s", err.message);
        return 0;
    }
    uint32_t index;
    VkResult r = vkAcquireNextImageKHR(a->device, a->swapchain, UINT64_MAX, a->acquired,
                                       VK_NULL_HANDLE, &index);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        xrad_scheduler_end_frame(sch, &f, 0, &err);
        return recreate_swapchain(a);
    }
    if (r != VK_SUCCESS && r != VK_SUBOPTIMAL_KHR)
        return fail(2, "vkAcquireNextImageKHR: %d", (int)r);
    VK(vkResetFences(a->device, 1, &a->fence));
    VkDescriptorImageInfo img = {a->sampler, f.view, f.layout};
    VkWriteDescriptorSet w = {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
                              .dstSet = a->set,
                              .descriptorCount = 1,
                              .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                              .pImageInfo = &img};
    vkUpdateDescriptorSets(a->device, 1, &w, 0, NULL);

    VkCommandBuffer cmd = a->cmd;
    VK(vkResetCommandBuffer(cmd, 0));
    VkCommandBufferBeginInfo bi = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                   .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT};
    VK(vkBeginCommandBuffer(cmd, &bi));
    VkClearValue clear[2] = {{.color = {{0, 0, 0, 0}}}, {.depthStencil = {0, 0}}};
    VkRenderPassBeginInfo rp = {.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
                                .renderPass = a->pass,
                                .framebuffer = a->framebuffer,
                                .renderArea = {{0, 0}, {a->width, a->height}},
                                .clearValueCount = 2,
                                .pClearValues = clear};
    vkCmdBeginRenderPass(cmd, &rp, VK_SUBPASS_CONTENTS_INLINE);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, a->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, a->layout, 0, 1, &a->set, 0,
                            NULL);
    VkDeviceSize zero = 0;
    vkCmdBindVertexBuffers(cmd, 0, 1, &a->vertices, &zero);
    for (uint32_t o = 0; o < a->objects; o++) {
        if (!a->count[o])
            continue;
        /* Each object where the shown solution had it. */
        double pose[16], clip[16];
        xrad_scene_get_object_pose(a->scene, o, f.time, pose, NULL);
        mat_mul(a->view_proj, pose, clip);
        struct {
            float clip[16];
            float atlas[4];
        } push;
        for (int k = 0; k < 16; k++)
            push.clip[k] = (float)clip[k];
        push.atlas[0] = (float)a->atlas_w;
        push.atlas[1] = (float)a->atlas_h;
        push.atlas[2] = (float)scale;
        push.atlas[3] = 0;
        vkCmdPushConstants(cmd, a->layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                           0, sizeof(push), &push);
        vkCmdDraw(cmd, a->count[o], 1, a->first[o], 0);
    }
    vkCmdEndRenderPass(cmd);
    /* The colour image is in TRANSFER_SRC (the render pass's final layout). */
    VkImage target = a->swap_images[index];
    barrier(cmd, target, VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
            VK_PIPELINE_STAGE_TRANSFER_BIT, 0, VK_PIPELINE_STAGE_TRANSFER_BIT,
            VK_ACCESS_TRANSFER_WRITE_BIT);
    VkImageBlit blit = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .srcOffsets = {{0, 0, 0}, {(int32_t)a->width, (int32_t)a->height, 1}},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .dstOffsets = {{0, 0, 0}, {(int32_t)a->extent.width, (int32_t)a->extent.height, 1}},
    };
    vkCmdBlitImage(cmd, a->color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, target,
                   VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, VK_FILTER_NEAREST);
    barrier(cmd, target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR,
            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
            VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0);
    if (readback) {
        VkBufferImageCopy region = {.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
                                    .imageExtent = {a->width, a->height, 1}};
        vkCmdCopyImageToBuffer(cmd, a->color.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                               readback, 1, &region);
        VkMemoryBarrier mb = {.sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
                              .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
                              .dstAccessMask = VK_ACCESS_HOST_READ_BIT};
        vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                             1, &mb, 0, NULL, 0, NULL);
    }
    VK(vkEndCommandBuffer(cmd));

    /* Waits: the swapchain image, and the front atlas's redistribution
     * (xrad's timeline). Signals: the present, and xrad's timeline that
     * this frame is done reading the atlas. */
    VkSemaphore waits[2] = {a->acquired, f.wait};
    uint64_t wait_values[2] = {0, f.wait_value};
    VkPipelineStageFlags stages[2] = {VK_PIPELINE_STAGE_TRANSFER_BIT, f.wait_stage};
    VkSemaphore signals[2] = {a->rendered, f.signal};
    uint64_t signal_values[2] = {0, f.signal_value};
    VkTimelineSemaphoreSubmitInfo tl = {.sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
                                        .waitSemaphoreValueCount = 2,
                                        .pWaitSemaphoreValues = wait_values,
                                        .signalSemaphoreValueCount = 2,
                                        .pSignalSemaphoreValues = signal_values};
    VkSubmitInfo si = {.sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
                       .pNext = &tl,
                       .waitSemaphoreCount = 2,
                       .pWaitSemaphores = waits,
                       .pWaitDstStageMask = stages,
                       .commandBufferCount = 1,
                       .pCommandBuffers = &cmd,
                       .signalSemaphoreCount = 2,
                       .pSignalSemaphores = signals};
    /* xrad's worker submits on the same queue from its thread. */
    xrad_vulkan_lock_queue(a->ctx);
    r = vkQueueSubmit(a->queue, 1, &si, a->fence);
    VkResult pr = VK_SUCCESS;
    if (r == VK_SUCCESS) {
        VkPresentInfoKHR pi = {.sType = VK_STRUCTURE_TYPE_PRESENT_INFO_KHR,
                               .waitSemaphoreCount = 1,
                               .pWaitSemaphores = &a->rendered,
                               .swapchainCount = 1,
                               .pSwapchains = &a->swapchain,
                               .pImageIndices = &index};
        pr = vkQueuePresentKHR(a->queue, &pi);
    }
    xrad_vulkan_unlock_queue(a->ctx);
    if (xrad_scheduler_end_frame(sch, &f, r == VK_SUCCESS, &err))
        return fail(err.status, "%s", err.message);
    if (r != VK_SUCCESS)
        return fail(2, "vkQueueSubmit: %d", (int)r);
    if (pr == VK_ERROR_OUT_OF_DATE_KHR || pr == VK_SUBOPTIMAL_KHR)
        return recreate_swapchain(a);
    if (pr != VK_SUCCESS)
        return fail(2, "vkQueuePresentKHR: %d", (int)pr);
    return 0;
}

/* The final frame's linear image to `path`. */
static int screenshot(app *a, xrad_scheduler *sch, const char *path)
{
    VkDeviceSize size = (VkDeviceSize)a->width * a->height * 16;
    VkBuffer buf;
    VkDeviceMemory mem;
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                             .size = size,
                             .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT};
    VK(vkCreateBuffer(a->device, &bi, NULL, &buf));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(a->device, buf, &req);
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size};
    if (memory_type(a, req.memoryTypeBits,
                    VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                    &ai.memoryTypeIndex))
        return 2;
    VK(vkAllocateMemory(a->device, &ai, NULL, &mem));
    VK(vkBindBufferMemory(a->device, buf, mem, 0));
    int st = draw_frame(a, sch, 1.0, buf);
    if (!st) {
        VK(vkWaitForFences(a->device, 1, &a->fence, VK_TRUE, UINT64_MAX));
        void *map;
        VK(vkMapMemory(a->device, mem, 0, size, 0, &map));
        xrad_error err = {0};
        if (xrad_image_write_exr(path, map, a->width, a->height, &err))
            st = fail(err.status, "%s", err.message);
        vkUnmapMemory(a->device, mem);
    }
    vkDestroyBuffer(a->device, buf, NULL);
    vkFreeMemory(a->device, mem, NULL);
    return st;
}

static void destroy(app *a)
{
    if (a->device)
        vkDeviceWaitIdle(a->device);
    xrad_context_destroy(&a->ctx);
    if (a->device) {
        vkDestroySemaphore(a->device, a->acquired, NULL);
        vkDestroySemaphore(a->device, a->rendered, NULL);
        vkDestroyFence(a->device, a->fence, NULL);
        vkDestroyCommandPool(a->device, a->cmd_pool, NULL);
        vkDestroyBuffer(a->device, a->vertices, NULL);
        vkFreeMemory(a->device, a->vertex_memory, NULL);
        vkDestroySampler(a->device, a->sampler, NULL);
        vkDestroyPipeline(a->device, a->pipeline, NULL);
        vkDestroyPipelineLayout(a->device, a->layout, NULL);
        vkDestroyDescriptorPool(a->device, a->pool, NULL);
        vkDestroyDescriptorSetLayout(a->device, a->set_layout, NULL);
        vkDestroyFramebuffer(a->device, a->framebuffer, NULL);
        vkDestroyRenderPass(a->device, a->pass, NULL);
        image_destroy(a, &a->color);
        image_destroy(a, &a->depth);
        vkDestroySwapchainKHR(a->device, a->swapchain, NULL);
        vkDestroyDevice(a->device, NULL);
    }
    if (a->instance) {
        vkDestroySurfaceKHR(a->instance, a->surface, NULL);
        if (a->messenger) {
            PFN_vkDestroyDebugUtilsMessengerEXT d =
                (PFN_vkDestroyDebugUtilsMessengerEXT)vkGetInstanceProcAddr(
                    a->instance, "vkDestroyDebugUtilsMessengerEXT");
            d(a->instance, a->messenger, NULL);
        }
        vkDestroyInstance(a->instance, NULL);
    }
    if (a->window)
        glfwDestroyWindow(a->window);
    free(a->first);
    free(a->count);
    xrad_scene_destroy(&a->scene);
}

static int usage(void)
{
    fprintf(stderr, "usage: embed SCENE [--method cross|incremental|progressive] [--exposure E]\n"
                    "             [--frames N --fps F --screenshot OUT.exr]\n");
    return 1;
}

static int parse(int argc, char **argv, options *o)
{
    *o = (options){.method = XRAD_METHOD_CROSS, .exposure = 1, .fps = 30};
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--method") && v) {
            o->method = xrad_method_from_name(v);
            if (!o->method)
                return fail(1, "--method: unknown method '%s'", v);
            i++;
        } else if (!strcmp(argv[i], "--exposure") && v) {
            o->exposure = atof(v);
            i++;
        } else if (!strcmp(argv[i], "--frames") && v) {
            o->frames = (uint32_t)strtoul(v, NULL, 10);
            i++;
        } else if (!strcmp(argv[i], "--fps") && v) {
            o->fps = atof(v);
            i++;
        } else if (!strcmp(argv[i], "--screenshot") && v) {
            o->screenshot = v;
            i++;
        } else if (argv[i][0] == '-' || o->scene) {
            return usage();
        } else {
            o->scene = argv[i];
        }
    }
    if (!o->scene || !(o->fps > 0) || !(o->exposure > 0) || (o->screenshot && !o->frames))
        return usage();
    return 0;
}

int main(int argc, char **argv)
{
    options o;
    int st = parse(argc, argv, &o);
    if (st)
        return st;
    app a = {0};
    xrad_error err = {0};
    xrad_scene *solved = NULL;
    xrad_scheduler *sch = NULL;
    if (xrad_scene_load(o.scene, &solved, &err) || xrad_scene_load(o.scene, &a.scene, &err)) {
        xrad_scene_destroy(&solved);
        return fail(err.status, "%s", err.message);
    }
    xrad_camera_desc cam;
    xrad_scene_get_camera(a.scene, &cam);
    a.width = cam.width ? cam.width : 512;
    a.height = cam.height ? cam.height : 512;
    camera_matrix(&cam, (double)a.width / a.height, a.view_proj);

    if (!glfwInit()) {
        const char *why = NULL;
        glfwGetError(&why);
        st = fail(2, "no display: %s", why ? why : "glfwInit failed");
        goto done;
    }
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    a.window = glfwCreateWindow((int)a.width, (int)a.height, "xrad embed example", NULL, NULL);
    if (!a.window) {
        st = fail(2, "cannot open a window");
        goto done;
    }
    if ((st = create_instance(&a)) || (st = create_device(&a)) || (st = create_swapchain(&a)) ||
        (st = create_drawing(&a)) || (st = create_geometry(&a)))
        goto done;

    xrad_scheduler_desc sd = {.solver = {.method = o.method}};
    if (xrad_scheduler_create(a.ctx, solved, &sd, &sch, &err)) {
        st = fail(err.status, "%s", err.message);
        goto done;
    }
    solved = NULL; /* the scheduler's */

    /* The first dynamic object moves with the arrow keys. */
    uint32_t mover = UINT32_MAX;
    for (uint32_t i = 0; i < a.objects && mover == UINT32_MAX; i++) {
        xrad_object_info oi;
        if (!xrad_scene_get_object(a.scene, i, &oi, NULL) && oi.dynamic)
            mover = i;
    }
    double shift[2] = {0, 0}, last[2] = {0, 0}, start = glfwGetTime();
    uint64_t serial = 0;
    for (uint32_t frame = 1; !glfwWindowShouldClose(a.window); frame++) {
        glfwPollEvents();
        double t = o.frames ? frame / o.fps : glfwGetTime() - start;
        const double step = 0.005; /* m per frame */
        shift[0] += step * ((glfwGetKey(a.window, GLFW_KEY_RIGHT) == GLFW_PRESS) -
                            (glfwGetKey(a.window, GLFW_KEY_LEFT) == GLFW_PRESS));
        shift[1] += step * ((glfwGetKey(a.window, GLFW_KEY_DOWN) == GLFW_PRESS) -
                            (glfwGetKey(a.window, GLFW_KEY_UP) == GLFW_PRESS));
        xrad_object_pose pose = {.object = mover, .clear = 1};
        uint32_t poses = 0;
        if (mover != UINT32_MAX && (shift[0] != last[0] || shift[1] != last[1])) {
            /* The animation's pose at t, moved: a rigid transform. */
            xrad_scene_get_object_pose(a.scene, mover, t, pose.matrix, NULL);
            pose.matrix[12] += shift[0];
            pose.matrix[14] += shift[1];
            pose.clear = 0;
            poses = 1;
            xrad_scene_set_pose(a.scene, mover, pose.matrix, NULL);
            last[0] = shift[0];
            last[1] = shift[1];
        }
        if (xrad_scheduler_request(sch, &(xrad_request){.time = t, .poses = &pose, .pose_count = poses},
                                   &serial, &err)) {
            st = fail(err.status, "%s", err.message);
            break;
        }
        if ((st = draw_frame(&a, sch, o.exposure, VK_NULL_HANDLE)))
            break;
        if (o.frames && frame == o.frames) {
            /* The last request's solution, shown and written. */
            if (xrad_scheduler_wait(sch, serial, &err)) {
                st = fail(err.status, "%s", err.message);
                break;
            }
            if (o.screenshot && (st = screenshot(&a, sch, o.screenshot)))
                break;
            xrad_scheduler_stats ss;
            xrad_scheduler_get_stats(sch, &ss);
            printf("embed: %u frames, last solution at t = %.3f s, %s, %u hemicubes\n", frame,
                   t, xrad_method_name(o.method), ss.last.hemicubes);
            break;
        }
    }
done:
    xrad_scheduler_destroy(&sch);
    xrad_scene_destroy(&solved);
    destroy(&a);
    glfwTerminate();
    if (!st && validation_messages)
        st = fail(1, "%u validation messages", validation_messages);
    return st;
}
