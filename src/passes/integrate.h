/*
 * Integrate pass (DESIGN.md "GPU passes"; thesis 2.2.2 and Algorithm 4.1
 * line 8): multiplies each radiosity hemicube by the exact delta form factor
 * table (hemicube_delta_form_factors, uploaded once per resolution) and
 * sums, one workgroup per hemicube with a shared-memory reduction, many
 * hemicubes per dispatch. The sum of hemicube h, sum_j F_j B_j over what it
 * sees, goes to out[out_first + h] (rgb, w = 0).
 */
#ifndef XRAD_PASSES_INTEGRATE_H
#define XRAD_PASSES_INTEGRATE_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct integrate_pass integrate_pass;

/* A pass for hemicubes of res x res pixels per face (even, 8..1024). */
xrad_status integrate_create(struct xrad_context *ctx, uint32_t res, integrate_pass **out,
                             xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void integrate_destroy(struct xrad_context *ctx, integrate_pass **pass);

/* The delta form factor table on the GPU: float[5 * res * res], index
 * face * res * res + row * res + col. */
const gpu_buffer *integrate_table(const integrate_pass *pass);

typedef struct integrate_draw {
    VkImageView hemicubes;  /* float 2D array (hemicube_image), layer = hemicube * 5 + face,
                               in SHADER_READ_ONLY_OPTIMAL */
    uint32_t count;         /* hemicubes 0 .. count - 1 of the image */
    const gpu_buffer *out;  /* vec4[], STORAGE usage */
    uint32_t out_first;
    float scale;            /* the image holds B x scale (hemicube_draw.scale); 0 means 1 */
    bool ring;              /* also the horizon ring's mean radiosity (integrate_shared.h) */
    uint32_t ring_first;
} integrate_draw;

/* Records the dispatch outside any render pass. Points the descriptor set
 * at the draw's image and buffer when they differ from the last
 * recording's; that needs the last recording with others to have
 * completed. The caller orders the hemicube render before it and the
 * readers of `out` after it. */
void integrate_record(integrate_pass *pass, VkCommandBuffer cmd, const integrate_draw *draw);

#endif
