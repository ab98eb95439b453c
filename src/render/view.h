/* xrad_render_view and its internal form, which tests and tools use to pick
 * the filter path and to time the pass. */
#ifndef XRAD_RENDER_VIEW_H
#define XRAD_RENDER_VIEW_H

#include "gpu/timer.h"
#include "passes/display.h"
#include "xrad.h"

typedef struct render_view_options {
    /* Filter path; DISPLAY_FILTER_NEAREST is also what desc->nearest asks
     * for. `auto_filter`: nearest if desc->nearest, else the sampler's
     * bilinear where the device has it, else the shader's. */
    bool auto_filter;
    display_filter filter;
    /* When non-NULL, the pass is timed under "display". */
    gpu_timer *timer;
} render_view_options;

xrad_status render_view(struct xrad_context *ctx, const xrad_scene *scene,
                        const xrad_atlas *atlas, const xrad_view_desc *desc,
                        const render_view_options *opt, float **rgba, uint32_t *width,
                        uint32_t *height, xrad_error *err);

#endif
