/*
 * Incremental reconstruct pass (DESIGN.md "Methods"; thesis Algorithm 4.3
 * with the reshooting of 4.4.1): the compute side of one incremental
 * redistribution, one dispatch per step (modes in spirv/
 * incremental_shared.h, what each does in spirv/
 * incremental_reconstruct.comp): capture what each shooter shoots, the
 * per-surface power of C that sizes its shooting patches, the reset of M
 * and of C's unshot radiosity, the negative shot of M at the old pose, and
 * the four-case reconstruction of C's shooters through their old-pose and
 * new-pose ID hemicubes.
 */
#ifndef XRAD_PASSES_INCREMENTAL_RECONSTRUCT_H
#define XRAD_PASSES_INCREMENTAL_RECONSTRUCT_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct incremental_reconstruct_pass incremental_reconstruct_pass;

typedef struct incremental_reconstruct_bindings {
    const gpu_buffer *surfaces, *elements, *materials; /* spirv/radiosity.h */
    const gpu_buffer *B, *Bu;                          /* vec4[element_count], updated */
    const gpu_buffer *shooters;                        /* struct gpu_shooter[] */
    const gpu_buffer *values;                          /* struct incr_value[], same indices */
    const gpu_buffer *power;                           /* float[surface_count] */
    /* struct gpu_surface[surface_count] at the old pose: the occluders the
     * old hemicubes show (surfaces holds the new pose during INCREMENT). */
    const gpu_buffer *old_surfaces;
    /* vec4[element_count]: M's light on each element of C at the new pose
     * (M_LIGHT), which M takes with C's light. */
    const gpu_buffer *m_light;
    /* vec4[element_count], host-written before each RESET where
     * params.luminaires: rho x the luminaires' direct light at the new pose
     * on M, its change from the old pose on C; else any buffer. */
    const gpu_buffer *luminaires;
    /* R32_UINT 2D arrays, layer = hemicube * 5 + face, in
     * SHADER_READ_ONLY_OPTIMAL when the pass runs: the chunk's hemicubes
     * at the old pose and at the new pose. */
    VkImageView ids_old, ids_new;
} incremental_reconstruct_bindings;

typedef struct incremental_reconstruct_params {
    uint32_t element_count, surface_count;
    uint32_t hemicube_res;  /* pixels per face side of the ID hemicubes */
    double subdivide_ratio; /* > 0: exact form factor where A_s / r^2 exceeds it */
    bool exact_texel_only;  /* no nearest-texel check (XRAD_ID_CHECK_EXACT) */
    bool luminaires;        /* RESET adds bindings.luminaires */
} incremental_reconstruct_params;

xrad_status incremental_reconstruct_create(struct xrad_context *ctx,
                                           const incremental_reconstruct_params *params,
                                           incremental_reconstruct_pass **out,
                                           xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void incremental_reconstruct_destroy(struct xrad_context *ctx,
                                     incremental_reconstruct_pass **pass);

/* Points the pass at its resources. No recording that uses the pass may be
 * pending on the GPU. */
void incremental_reconstruct_bind(struct xrad_context *ctx, incremental_reconstruct_pass *pass,
                                  const incremental_reconstruct_bindings *b);

/* Records one step (INCR_MODE_*): CAPTURE over shooters [first, first +
 * count); POWER over the surfaces and RESET over the elements (first and
 * count ignored); NEGATIVE and INCREMENT over the elements, for the chunk
 * of shooters [first, first + count), shooter first + h with its
 * hemicubes at block h of the images. The caller orders what the step
 * reads before it and its readers after it. */
void incremental_reconstruct_record(incremental_reconstruct_pass *pass, VkCommandBuffer cmd,
                                    uint32_t mode, uint32_t first, uint32_t count);

#endif
