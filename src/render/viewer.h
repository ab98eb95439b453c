/*
 * The display side of the real-time loop (xrad view): each frame draws the
 * scene from a free camera with the scheduler's front atlas
 * (passes/display.h), tone-maps it into a swapchain image
 * (passes/present.h) with an optional text overlay (passes/overlay.h) and
 * presents it. Two frame slots are in flight; each
 * has its own command buffer, fence, display pass, target and geometry, so
 * a slot is rewritten only after its own previous frame completed. A
 * resize recreates the swapchain, retiring the old one against the
 * scheduler's `displayed` timeline; targets follow the window size slot by
 * slot.
 *
 * The window (GLFW) stays the caller's: it passes the VkSurfaceKHR in and
 * destroys it after viewer_destroy.
 */
#ifndef XRAD_RENDER_VIEWER_H
#define XRAD_RENDER_VIEWER_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "core/sliding.h"
#include "scene/scene.h"
#include "schedule/scheduler.h"
#include "xrad.h"

struct xrad_context;

typedef struct viewer_desc {
    VkSurfaceKHR surface;
    uint32_t width, height; /* the window's framebuffer, pixels */
    bool vsync;             /* FIFO presentation; else MAILBOX or IMMEDIATE where offered */
} viewer_desc;

typedef struct viewer_frame_desc {
    camera cam;             /* position, look_at, up, fov_y */
    double time;            /* s, the pose dynamic objects are drawn at */
    double exposure;        /* > 0; <= 0: automatic from the first frame showing a
                               solution (xrad_image_tonemap_exposure), then kept
                               while the tone mapping stays */
    xrad_tonemap tonemap;
    bool nearest;           /* elements as flat squares instead of interpolated */
    uint32_t width, height; /* the window's framebuffer now; a change recreates */
    /* When non-NULL: after this frame completes, its linear image (before
     * tone mapping) is written here, .exr as is, .png tone-mapped with the
     * frame's exposure exactly as the window shows it. */
    const char *screenshot;
    /* Non-NULL: text over the window's top-left corner (passes/overlay.h);
     * it is not in the screenshot, which is the scene's image. */
    const char *overlay;
} viewer_frame_desc;

typedef struct viewer_stats {
    uint64_t frames;          /* frames presented */
    uint32_t recreations;     /* swapchain recreations */
    double exposure;          /* in use */
    xrad_tonemap tonemap;     /* in use */
    uint64_t serial;          /* redistribution the last frame showed (0: none yet) */
    double solution_time;     /* s, its scene time */
    sliding_window frame_ms;  /* host time from one frame's start to the next's */
    sliding_table passes;     /* GPU ms of "display" and "present" */
} viewer_stats;

typedef struct viewer viewer;

/* `scene` is the display's copy (the scheduler has its own); it must
 * outlive the viewer and may be changed between frames (offsets). */
xrad_status viewer_create(struct xrad_context *ctx, const xrad_scene *scene,
                          const viewer_desc *desc, viewer **out, xrad_error *err);
/* Waits for the viewer's GPU work (teardown), frees everything. Accepts
 * NULL; sets *v to NULL. */
void viewer_destroy(viewer **v);

/* One frame with the scheduler's front atlas. */
xrad_status viewer_frame(viewer *v, scheduler *sched, const viewer_frame_desc *d,
                         xrad_error *err);

void viewer_get_stats(const viewer *v, viewer_stats *out);

#endif
