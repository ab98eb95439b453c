/*
 * The one device wrapper (libplacebo's vk_ctx, wlroots' wlr_vk_device):
 * instance, debug messenger, physical device, device, the single
 * graphics+compute queue, command pool, submission timeline, memory
 * allocator, and what the device can do. Everything Vulkan stays in src/gpu
 * and src/passes; xrad.h only sees the opaque xrad_context.
 */
#ifndef XRAD_GPU_CONTEXT_H
#define XRAD_GPU_CONTEXT_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/vk_check.h"
#include "xrad.h"

struct gpu_memory;

#define GPU_MAX_THREADS 8

/* Optional capabilities, each enabled on the device when supported. */
typedef struct gpu_features {
    bool timeline_semaphore;
    bool multiview;
    uint32_t multiview_max_views; /* 0 without multiview */
    bool shader_output_layer;     /* gl_Layer from vertex shaders (Vulkan 1.2) */
    bool synchronization2;
    bool host_query_reset;
    bool shader_float32_atomic_add; /* VK_EXT_shader_atomic_float, buffers */
    bool memory_budget;             /* VK_EXT_memory_budget */
    bool fragment_stores_and_atomics;
    bool vertex_pipeline_stores_and_atomics;
    bool multi_draw_indirect;
    bool draw_indirect_first_instance;
    bool timestamps;        /* timestamp queries on the queue */
    double timestamp_period; /* ns per tick */
    uint32_t timestamp_valid_bits;
    uint32_t subgroup_size;
    VkSubgroupFeatureFlags subgroup_ops; /* in compute shaders */
} gpu_features;

enum { GPU_HEMICUBE_ONLY_MULTIVIEW = 1, GPU_HEMICUBE_ONLY_LAYERED = 2 };

struct xrad_context {
    VkInstance instance;
    uint32_t instance_api;
    VkDebugUtilsMessengerEXT messenger;
    PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger;
    bool validation;
    atomic_uint validation_messages;
    /* The hemicube path check's verdict (passes/hemicube.h), found once
     * per context: 0 until then, else 1 + the path; hemicube_check its
     * counts (pixels, edge, wrong), written before the verdict. */
    atomic_uint hemicube_path;
    uint32_t hemicube_check[3];
    /* xrad_context_desc.hemicube_path: the only path the check may
     * choose (GPU_HEMICUBE_ONLY_*), 0: either. */
    unsigned hemicube_path_only;

    VkPhysicalDevice phys;
    VkPhysicalDeviceProperties props;
    VkPhysicalDeviceMemoryProperties mem_props;
    gpu_features features;

    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    /* A command pool per thread that records (gpu_thread_pool): command
     * buffers of one pool must not be recorded in two threads at once. */
    struct {
        pthread_t thread;
        VkCommandPool pool;
    } pools[GPU_MAX_THREADS];
    uint32_t pool_count;
    /* Held around every use of the queue (submit, present), of `pools`
     * and of timeline_value, so that a redistribution thread and a display
     * thread may share the context (schedule/scheduler.h). */
    pthread_mutex_t queue_lock;
    bool present; /* VK_KHR_swapchain is enabled */
    /* Every submission signals the next value (gpu_cmd_submit). */
    VkSemaphore timeline;
    uint64_t timeline_value;
    /* Upper bound for any wait on the GPU; a longer wait is reported as a
     * hang (XRAD_ERROR_SYSTEM) instead of blocking forever. */
    uint64_t wait_timeout_ns;

    struct gpu_memory *mem;
    uint64_t memory_limit; /* bytes, xrad_context_desc.memory_limit_mib; 0: none */
    gpu_fault fault;
    xrad_log_fn log; /* xrad_context_desc.log; NULL: stderr */
    void *log_user;
    /* The application's instance and device (include/xrad_vulkan.h):
     * xrad destroys neither, and takes the application's queue lock
     * around its own (gpu_queue_lock). */
    struct {
        bool imported;
        uint32_t queue_index;
        void (*lock_queue)(void *user, uint32_t family, uint32_t index);
        void (*unlock_queue)(void *user, uint32_t family, uint32_t index);
        void *queue_user;
    } import;
    /* Set by VK_ERROR_DEVICE_LOST (real or injected) and by wait timeouts:
     * later submissions refuse, and destroy does not wait on the device.
     * Atomic: the scheduler's worker sets it, the display thread reads it. */
    atomic_bool lost;
    /* Set by a wait timeout alone (a hang, real or injected): the queue may
     * never drain, so a cleanup wait takes at most GPU_HANG_GRACE_NS, and
     * destroy leaves the device to process exit while work is still
     * pending (lavapipe joins its queue thread in vkDestroyDevice). */
    atomic_bool hung;
};

/* Messages (warnings and errors) seen by every context of this process,
 * including those delivered while a context was being destroyed: the tests'
 * leak check. */
uint32_t gpu_validation_messages_total(void);

/* A message to the context's log (xrad_context_desc.log), or to stderr
 * as "xrad: MESSAGE" without one or without a context. */
void gpu_log(const struct xrad_context *ctx, xrad_log_level level, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Held around every use of the queue: the context's lock, then the
 * application's for an imported queue. */
void gpu_queue_lock(struct xrad_context *ctx);
void gpu_queue_unlock(struct xrad_context *ctx);

/* What every context takes from its desc, before a device: a context
 * with its lock, log, memory limit and fault rule, and nothing of Vulkan
 * yet; xrad_context_destroy frees it. */
typedef struct gpu_context_settings {
    double memory_limit_mib;
    const char *fault;
    xrad_log_fn log;
    void *log_user;
} gpu_context_settings;
xrad_status gpu_context_alloc(const gpu_context_settings *settings, struct xrad_context **out,
                              xrad_error *err);

/* Once the device and queue are in place: the context's timeline
 * semaphore and memory allocator. */
xrad_status gpu_context_finish(struct xrad_context *ctx, xrad_error *err);

/* The calling thread's command pool, created on its first use; freed with
 * the context. */
xrad_status gpu_thread_pool(struct xrad_context *ctx, VkCommandPool *out, xrad_error *err);

/* After a hang (ctx->hung) the cleanup waits no longer than this: the
 * work a wait gave up on has had the whole wait limit already. */
#define GPU_HANG_GRACE_NS 5000000000ull

/* Whether every submission so far has ended, waiting at most `timeout_ns`
 * (false without a timeline semaphore to tell). */
bool gpu_context_drained(struct xrad_context *ctx, uint64_t timeout_ns);

/* What xrad_context_destroy does once the queue has drained: waits for it
 * (unless lost) and frees everything. The test of a hang that outlives
 * xrad_context_destroy frees with it what destroy left. */
void gpu_context_free(struct xrad_context *ctx);

/* XRAD_ERROR_SYSTEM naming `what` when the context was lost earlier. */
xrad_status gpu_context_check_alive(struct xrad_context *ctx, const char *what,
                                    xrad_error *err);

#endif
