/*
 * Hemicube cull pass (issue 15: the hemicube's cost is its vertex work):
 * one compute dispatch per shot that turns the scene's clusters of
 * hemicube triangles (gpu_scene.h: runs of whole surfaces of one object,
 * laid out near to near, with their bounds) into one indexed indirect
 * draw each,
 * emptied where none of the shot's hemicubes can see the cluster: its box
 * lies behind every hemicube's base, or it is the outside of a closed mesh
 * and faces away from every origin (spirv/hemicube_cull.comp says why the
 * picture does not change). The hemicube pass then draws the commands
 * (hemicube_draw.commands). The host reads nothing.
 */
#ifndef XRAD_PASSES_HEMICUBE_CULL_H
#define XRAD_PASSES_HEMICUBE_CULL_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "hemicube_cull_shared.h"
#include "xrad.h"

struct xrad_context;

typedef struct hemicube_cull_pass hemicube_cull_pass;

typedef struct hemicube_cull_buffers {
    const gpu_buffer *clusters; /* struct gpu_cluster[] (gpu_scene.clusters) */
    const gpu_buffer *frames;   /* struct gpu_shooter[]: the hemicubes' frames */
    const gpu_buffer *status;   /* the uints holding the hemicube count (and instanceCount); any
                                   buffer where the host gives both */
    const gpu_buffer *commands; /* VkDrawIndexedIndirectCommand[cluster_count]: INDIRECT,
                                   STORAGE */
} hemicube_cull_buffers;

typedef struct hemicube_cull_params {
    uint32_t cluster_count;  /* the first clusters of the table: all, or the static ones */
    uint32_t first;          /* frame of hemicube 0 */
    uint32_t count_word;     /* uint of status: the number of hemicubes; CULL_NO_COUNT: count */
    uint32_t count;
    uint32_t instances;      /* each command's instanceCount; 0: status's instance_word */
    uint32_t instance_word;
    double margin;           /* m: a test culls only by more than this */
} hemicube_cull_params;

xrad_status hemicube_cull_create(struct xrad_context *ctx, hemicube_cull_pass **out,
                                 xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void hemicube_cull_destroy(struct xrad_context *ctx, hemicube_cull_pass **pass);

/* Points the pass at its buffers; no recording using it may be pending. */
void hemicube_cull_bind(struct xrad_context *ctx, hemicube_cull_pass *pass,
                        const hemicube_cull_buffers *buffers);

/* Records the dispatch outside any render pass. The caller orders the
 * writes of frames and status before it, and the indirect draw after. */
void hemicube_cull_record(hemicube_cull_pass *pass, VkCommandBuffer cmd,
                          const hemicube_cull_params *params);

#endif
