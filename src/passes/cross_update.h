/*
 * Cross update pass (thesis Algorithm 4.4 lines 5 and 12-14, Algorithm
 * 4.5 GATHERRADIOSITY): the bookkeeping of one redistribution on the
 * patches and elements of the dynamic set M, one compute dispatch per step
 * (modes in spirv/cross_shared.h, what each does in spirv/
 * cross_update.comp): reset M to its emission, write the shot radiosity
 * of C less its emission for the hemicubes (and its peak), set M from the
 * gathered sums (a mesh group's faces from its gather hemicube, read from
 * each face), and take the patches' total radiosity.
 */
#ifndef XRAD_PASSES_CROSS_UPDATE_H
#define XRAD_PASSES_CROSS_UPDATE_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct cross_update_pass cross_update_pass;

typedef struct cross_update_bindings {
    const gpu_buffer *surfaces, *elements, *materials; /* spirv/radiosity.h */
    const gpu_buffer *B, *Bu;                          /* vec4[element_count] */
    const gpu_buffer *patches;                         /* struct cross_patch[patch_count] */
    const gpu_buffer *values;                          /* struct cross_value[patch_count] */
    const gpu_buffer *gathered;                        /* vec4[2 patch_count] (cross.c) */
    const gpu_buffer *out;                             /* vec4[element_count] (INDIRECT_C) */
    const gpu_buffer *surface_patch;                   /* uint[surface_count], members */
    const gpu_buffer *peak;                            /* uint (INDIRECT_C) */
    const gpu_buffer *frames;                          /* gpu_shooter[3][patch_count] */
    VkImageView gather_hemicubes; /* the gather hemicubes (CROSS_UPDATE_BINDING_GATHER_HEMICUBES) */
} cross_update_bindings;

/* GROUPS' view of the gather hemicubes: their resolution, the scale
 * they hold B by, and the scene diameter their alpha is a fraction of. */
typedef struct cross_update_gather {
    uint32_t res;
    float scale;
    float diameter;
} cross_update_gather;

xrad_status cross_update_create(struct xrad_context *ctx, cross_update_pass **out,
                                xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void cross_update_destroy(struct xrad_context *ctx, cross_update_pass **pass);

/* No recording that uses the pass may be pending on the GPU. */
void cross_update_bind(struct xrad_context *ctx, cross_update_pass *pass,
                       const cross_update_bindings *b);

/* Records one step (CROSS_UPDATE_*) over the scene's patch_count patches or
 * element_count elements; `gather` for GROUPS (else NULL). The caller
 * orders what it reads before it and its readers after it. */
void cross_update_record(cross_update_pass *pass, VkCommandBuffer cmd, uint32_t mode,
                         uint32_t patch_count, uint32_t element_count,
                         const cross_update_gather *gather);

#endif
