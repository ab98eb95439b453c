/*
 * xrad on the application's Vulkan device (issue 17; the shape of
 * libplacebo's pl_vulkan_import and wlroots' wlr_vk_renderer_create_for_*).
 *
 * The application creates its instance (Vulkan 1.2 or newer) and device
 * through the system loader (libvulkan.so.1, which libxrad links), with the
 * features and device extensions xrad_vulkan_get_requirements lists merged
 * into its own, and a queue of a family with graphics and compute. It then
 * hands them to xrad_vulkan_import. xrad records and submits on that queue,
 * taking the application's lock around every use of it when the queue is
 * shared with other threads. xrad_context_destroy frees what xrad made and
 * leaves the instance, the device and the queue to the application, which
 * destroys them after every xrad object on them.
 *
 * Validation messages go to the application's own messenger (the context
 * counts none); xrad's warnings go to the desc's log.
 */
#ifndef XRAD_VULKAN_H
#define XRAD_VULKAN_H

#include <vulkan/vulkan.h>

#include "xrad.h"

#ifdef __cplusplus
extern "C" {
#endif

#define XRAD_VULKAN_MAX_EXTENSIONS 6

/* What xrad needs enabled on a device made from `physical_device`. The
 * features are a chain from `features` whose pNext points into this
 * struct: fill it where it will be used and do not copy it; OR its
 * members into the application's own, or pass `features` (extended with
 * the application's structs) to vkCreateDevice as it is. */
typedef struct xrad_vulkan_requirements {
    uint32_t api_version;  /* the least instance and device version: VK_API_VERSION_1_2 */
    uint32_t queue_family; /* a family with graphics and compute (the first) */
    const char *extensions[XRAD_VULKAN_MAX_EXTENSIONS]; /* device extensions to enable */
    uint32_t extension_count;
    /* Optional features xrad uses where the device offers them (it checks
     * at import which were enabled and chooses its paths by them). */
    VkPhysicalDeviceFeatures2 features;
    VkPhysicalDeviceVulkan11Features vulkan11;
    VkPhysicalDeviceVulkan12Features vulkan12;
    VkPhysicalDeviceSynchronization2Features synchronization2;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float;
} xrad_vulkan_requirements;

/* `instance_api_version`: what the instance was created with. `present`:
 * 1 when the application presents with xrad's help (VK_KHR_swapchain is
 * then listed). XRAD_ERROR_SYSTEM for a device xrad cannot use (below
 * Vulkan 1.2, no graphics and compute queue family). */
XRAD_API xrad_status xrad_vulkan_get_requirements(VkPhysicalDevice physical_device,
                                                  uint32_t instance_api_version, int present,
                                                  xrad_vulkan_requirements *out,
                                                  xrad_error *err);

typedef struct xrad_vulkan_import_desc {
    VkInstance instance;
    uint32_t instance_api_version; /* as created; at least VK_API_VERSION_1_2 */
    VkPhysicalDevice physical_device;
    VkDevice device;
    uint32_t queue_family; /* graphics and compute */
    uint32_t queue_index;
    /* What the device was created with: its VkDeviceCreateInfo's pNext
     * chain (a VkPhysicalDeviceFeatures2 at its head) and its extensions.
     * xrad uses a feature only where both say so. NULL: exactly what
     * xrad_vulkan_get_requirements listed. */
    const VkPhysicalDeviceFeatures2 *enabled_features;
    const char *const *enabled_extensions;
    uint32_t enabled_extension_count;
    /* Around every use of the queue (submit, present, wait idle), where
     * other threads of the application use it too; NULL: xrad's own lock
     * only. */
    void (*lock_queue)(void *user, uint32_t queue_family, uint32_t queue_index);
    void (*unlock_queue)(void *user, uint32_t queue_family, uint32_t queue_index);
    void *queue_user;
    /* As in xrad_context_desc. */
    double memory_limit_mib;
    const char *fault;
    xrad_log_fn log;
    void *log_user;
} xrad_vulkan_import_desc;

/* A context on the application's device. XRAD_ERROR_INPUT for a desc
 * that names no device or queue, XRAD_ERROR_SYSTEM for a device xrad
 * cannot use. */
XRAD_API xrad_status xrad_vulkan_import(const xrad_vulkan_import_desc *desc, xrad_context **out,
                                        xrad_error *err);

/* The context's handles: the application's (xrad_vulkan_import) or the
 * ones xrad made (xrad_context_create), which stay xrad's to destroy. */
XRAD_API VkInstance xrad_vulkan_instance(const xrad_context *ctx);
XRAD_API VkPhysicalDevice xrad_vulkan_physical_device(const xrad_context *ctx);
XRAD_API VkDevice xrad_vulkan_device(const xrad_context *ctx);
XRAD_API VkQueue xrad_vulkan_queue(const xrad_context *ctx, uint32_t *queue_family);

/* Held around the application's own use of the context's queue while
 * xrad may use it from another thread (the scheduler's worker): xrad's
 * lock, then the application's lock_queue of an imported queue. */
XRAD_API void xrad_vulkan_lock_queue(xrad_context *ctx);
XRAD_API void xrad_vulkan_unlock_queue(xrad_context *ctx);

/* ------------------------------------------------- the real-time loop */

/* Redistribution on a worker thread of its own, display on the caller's,
 * meeting at two radiosity atlases (thesis 4.5.3; DESIGN.md
 * "Scheduling"). The application requests scene times, poses and light
 * changes as they happen; per display frame it takes the front atlas,
 * samples it (xrad_surface_info says where each surface lies), waits for
 * `wait` before its reads and signals `signal` when they are done. The
 * worker writes an atlas only once the display has signalled past the
 * last frame that read it: no host wait on either side. */
typedef struct xrad_scheduler xrad_scheduler;

typedef struct xrad_scheduler_desc {
    xrad_solver_desc solver; /* method (default cross) and settings; .time: the first pose */
} xrad_scheduler_desc;

/* Takes `scene` over on success (xrad_scheduler_destroy frees it): the
 * worker poses it. The application draws from a scene of its own (load it
 * twice). Starts the worker, which solves at desc->solver.time. */
XRAD_API xrad_status xrad_scheduler_create(xrad_context *ctx, xrad_scene *scene,
                                           const xrad_scheduler_desc *desc,
                                           xrad_scheduler **out, xrad_error *err);

/* Stops the worker after its current redistribution and waits for the GPU
 * work of both sides. Accepts NULL and *s == NULL; sets *s to NULL. */
XRAD_API void xrad_scheduler_destroy(xrad_scheduler **s);

typedef struct xrad_object_pose {
    uint32_t object;   /* a dynamic object's index */
    int clear;         /* 1: its animation back (matrix unused) */
    double matrix[16]; /* rigid, object space to world, column-major (xrad_scene_set_pose) */
} xrad_object_pose;

typedef struct xrad_emission_change {
    uint32_t material;
    double emission[3]; /* W/m^2: 0 turns a light off */
} xrad_emission_change;

typedef struct xrad_request {
    double time;        /* s, scene time (animations) */
    xrad_method method; /* 0: keep; another: a new solver, solved anew */
    const xrad_object_pose *poses; /* copied; where objects are now */
    uint32_t pose_count;
    /* Copied; the worker solves anew from B = E with its method. */
    const xrad_emission_change *emissions;
    uint32_t emission_count;
} xrad_request;

/* Replaces the request the worker has not started yet (keeping its poses
 * and emissions of objects and materials this one does not name). *serial
 * (may be NULL) receives the request's number, from 1, for
 * xrad_scheduler_wait. XRAD_ERROR_INPUT for a static or unknown object, a
 * pose that is not rigid, an unknown material or an emission out of
 * range: checked here, before the worker sees it. */
XRAD_API xrad_status xrad_scheduler_request(xrad_scheduler *s, const xrad_request *r,
                                            uint64_t *serial, xrad_error *err);

/* What one display frame samples, and how its submission synchronises. */
typedef struct xrad_frame {
    /* The front atlas: RGBA 32-bit float radiosity (W/m^2), in `layout`
     * for sampled reads; VK_NULL_HANDLE before the first solution. */
    VkImage image;
    VkImageView view;
    VkImageLayout layout;
    VkFormat format;
    uint32_t width, height;
    uint64_t serial; /* the front's redistribution, from 1 (0: none yet) */
    double time;     /* s, the scene time of its solution */
    int swapped;     /* 1: this frame shows a newer solution than the last */
    /* The frame's submission waits for `wait` >= wait_value at
     * `wait_stage` and signals `signal` = signal_value (timeline
     * semaphores). */
    VkSemaphore wait;
    uint64_t wait_value;
    VkPipelineStageFlags wait_stage;
    VkSemaphore signal;
    uint64_t signal_value;
} xrad_frame;

/* Once per display frame, before recording what samples the atlas. */
XRAD_API xrad_status xrad_scheduler_begin_frame(xrad_scheduler *s, xrad_frame *f,
                                                xrad_error *err);

/* Once per begin_frame, after submitting: `submitted` 1 when a submission
 * signalling f->signal_value was made; 0 and xrad signals it in queue
 * order itself. */
XRAD_API xrad_status xrad_scheduler_end_frame(xrad_scheduler *s, const xrad_frame *f,
                                              int submitted, xrad_error *err);

/* Blocks until request `serial`, or one that replaced it, is published and
 * complete on the GPU (the next begin_frame shows it), or the worker
 * failed (its error). For screenshots and tests, not the loop. */
XRAD_API xrad_status xrad_scheduler_wait(xrad_scheduler *s, uint64_t serial, xrad_error *err);

typedef struct xrad_scheduler_stats {
    uint64_t requested, published; /* requests made; redistributions published */
    double time;                   /* s, the scene time of the newest publication */
    xrad_method method;            /* of the newest publication */
    int busy;                      /* the worker is redistributing now */
    /* Host ms per publication, means over the last 32: the whole frame (its
     * redistribution and progressive iterations, or a fresh solve) and the
     * redistribution alone (0 for the methods that solve anew). */
    double frame_ms, redistribute_ms;
    /* GPU ms per pass and publication, means over the last 32 (`count`
     * unused). */
    xrad_pass_time passes[XRAD_MAX_PASSES];
    uint32_t pass_count;
    xrad_solver_stats last; /* the solver's, of the newest publication */
} xrad_scheduler_stats;

XRAD_API void xrad_scheduler_get_stats(xrad_scheduler *s, xrad_scheduler_stats *stats);

/* ------------------------------------------------ showing it in a window */

/* xrad's own display of the loop (what `xrad view` shows): each frame
 * draws the scene from a free camera with the front atlas, tone-maps it
 * into a swapchain image of the application's surface and presents it.
 * The context must have been created with .present = 1 (or imported with
 * VK_KHR_swapchain enabled). */
typedef struct xrad_viewer xrad_viewer;

typedef struct xrad_viewer_desc {
    VkSurfaceKHR surface;   /* the application's; it destroys it after the viewer */
    uint32_t width, height; /* the window's framebuffer, pixels */
    int vsync;              /* 1: FIFO; 0: MAILBOX or IMMEDIATE where offered */
} xrad_viewer_desc;

/* `scene` is the display's copy (the scheduler owns another); it outlives
 * the viewer, and poses set on it show in the next frame. */
XRAD_API xrad_status xrad_viewer_create(xrad_context *ctx, const xrad_scene *scene,
                                        const xrad_viewer_desc *desc, xrad_viewer **out,
                                        xrad_error *err);
/* Waits for its GPU work; accepts NULL and *v == NULL; sets *v to NULL. */
XRAD_API void xrad_viewer_destroy(xrad_viewer **v);

typedef struct xrad_viewer_frame_desc {
    xrad_camera_desc camera; /* position, look_at, up, fov_degrees (width, height unused) */
    double time;             /* s, the pose dynamic objects are drawn at */
    double exposure;         /* > 0; <= 0: automatic from the first solution, then kept */
    int nearest;             /* 1: elements as flat squares */
    uint32_t width, height;  /* the framebuffer now; a change recreates the swapchain */
    /* Non-NULL: after the frame, its image: .exr linear, .png tone-mapped
     * as the window shows it. */
    const char *screenshot;
    /* Non-NULL: lines of text ('\n' between them; printable ASCII) drawn
     * on a dark box over the window's top-left corner, not in the
     * screenshot. */
    const char *overlay;
    /* The window's and the PNG screenshot's tone mapping; a change with an
     * automatic exposure measures it again. */
    xrad_tonemap tonemap;
} xrad_viewer_frame_desc;

/* One frame with the scheduler's front atlas (begin_frame and end_frame
 * inside). */
XRAD_API xrad_status xrad_viewer_frame(xrad_viewer *v, xrad_scheduler *s,
                                       const xrad_viewer_frame_desc *d, xrad_error *err);

typedef struct xrad_viewer_stats {
    uint64_t frames;       /* presented */
    uint32_t recreations;  /* swapchain recreations */
    double exposure;       /* in use */
    xrad_tonemap tonemap;  /* in use */
    uint64_t serial;       /* the redistribution the last frame showed */
    double solution_time;  /* s, its scene time */
    double frame_ms;       /* host ms from frame to frame, mean of the last 32 */
    xrad_pass_time passes[XRAD_MAX_PASSES]; /* GPU ms of display and present, means */
    uint32_t pass_count;
} xrad_viewer_stats;

XRAD_API void xrad_viewer_get_stats(const xrad_viewer *v, xrad_viewer_stats *out);

#ifdef __cplusplus
}
#endif

#endif
