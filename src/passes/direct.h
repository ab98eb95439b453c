/*
 * Direct light pass: the light each receiver point takes straight from the
 * emitting surfaces, sum over lights of emission x form factor with
 * visibility, computed exactly per light block rather than read from
 * hemicube pixels (spirv/direct.comp has the method and why). gather uses
 * it for the first bounce; its hemicubes then carry the reflected light
 * alone. One invocation per receiver and chunk of the lights.
 */
#ifndef XRAD_PASSES_DIRECT_H
#define XRAD_PASSES_DIRECT_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct direct_pass direct_pass;

/* A pass for the emitting surfaces lights[0 .. light_count - 1] (surface
 * indices; light_count may be 0: every receiver then gets 0). */
xrad_status direct_create(struct xrad_context *ctx, const uint32_t *lights, uint32_t light_count,
                          direct_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void direct_destroy(struct xrad_context *ctx, direct_pass **pass);

typedef struct direct_draw {
    const gpu_buffer *surfaces;  /* struct gpu_surface[]: the scene at the receivers' pose */
    const gpu_buffer *materials; /* struct gpu_material[] */
    const gpu_buffer *frames;    /* struct gpu_shooter[]: pos_area.xyz the receiver
                                    point, normal, surface */
    uint32_t first, count;       /* the receivers frames[first, first + count) */
    const gpu_buffer *out;       /* vec4[], STORAGE usage: rgb the direct light, at the
                                    frames' numbers; w > 0 where the invocation came near
                                    lavapipe's loop limit (DIRECT_STEP_ALARM) */
    const gpu_buffer *bvh_nodes; /* struct gpu_bvh_node[]: over `surfaces` (radiosity.h) */
    const gpu_buffer *bvh_items; /* uint[] */
    uint32_t bvh_depth;          /* its levels: how many lights a dispatch takes */
} direct_draw;

/* Records the dispatch outside any render pass. Points the descriptor set
 * at the draw's buffers when they differ from the last recording's; that
 * needs the last recording with others to have completed. The caller
 * orders the writes of the inputs before it and the readers of `out` after
 * it. */
void direct_record(direct_pass *pass, VkCommandBuffer cmd, const direct_draw *draw);

/* Lights per dispatch over a hierarchy of bvh_depth levels: as many as
 * keep an invocation within half of lavapipe's 65,535 loop iterations
 * (spirv/direct.comp), at least 1. */
uint32_t direct_lights_per_dispatch(uint32_t bvh_depth);

#endif
