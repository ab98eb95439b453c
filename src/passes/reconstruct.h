/*
 * Reconstruct pass (DESIGN.md "GPU passes"; thesis Algorithm 4.2
 * RECONSTRUCTIONSHADER with the improvements of 4.3.3): one compute
 * invocation per receiving element loops over all shooters of a shot. The
 * receiver point is the centroid of the element's cell (see
 * spirv/reconstruct.comp for why not the sample on the edge). An element
 * receives from a shooter when the point lies in front of the shooter and
 * the shooter's centre in front of the point, it belongs to another
 * surface, and its surface's ID (surface + 1) is in the shooter's ID
 * hemicube in the point's direction or in one of the 8 texels around that
 * one. It then receives rho_e B_s F, F the disk approximation of thesis eq.
 * 2.2.7/2.2.8 where A_s / r^2 <= subdivide_ratio, and nearer, the limit of
 * the subdivision of 4.3.3: the exact point-to-quad form factor to the
 * shooter patch. The sum over shooters is added to B and Bu. The dispatch
 * is indirect, sized by the select pass (zero groups when there is nothing
 * to shoot).
 */
#ifndef XRAD_PASSES_RECONSTRUCT_H
#define XRAD_PASSES_RECONSTRUCT_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

typedef struct reconstruct_pass reconstruct_pass;

/* Workgroup size: what select_params.reconstruct_group must say. */
uint32_t reconstruct_group_size(void);

typedef struct reconstruct_bindings {
    const gpu_buffer *surfaces, *elements, *materials; /* spirv/radiosity.h */
    const gpu_buffer *B, *Bu;                          /* vec4[element_count], updated */
    const gpu_buffer *shooters;                        /* struct gpu_shooter[] */
    const gpu_buffer *status;                          /* struct select_status */
    /* R32_UINT 2D array, layer = hemicube * 5 + face, in
     * SHADER_READ_ONLY_OPTIMAL when the pass runs. */
    VkImageView hemicubes;
    /* float[max_shooters * element_count] and float[max_shooters] where
     * params.conserve; any storage buffers otherwise. */
    const gpu_buffer *ff, *norm;
    /* vec4[]: the shot surface's unshot radiosity by element, as select
     * left it (select_buffers.shot) */
    const gpu_buffer *shot;
    /* struct gpu_bvh_node[] and uint[]: the hierarchy over the surfaces
     * (radiosity.h), for the segment tests against every quad */
    const gpu_buffer *bvh_nodes, *bvh_items;
} reconstruct_bindings;

typedef struct reconstruct_params {
    uint32_t element_count;
    uint32_t hemicube_res;  /* pixels per face side of the ID hemicubes */
    double subdivide_ratio; /* > 0: exact form factor where A_s / r^2 exceeds it */
    bool exact_texel_only;  /* true: no nearest-texel check (XRAD_ID_CHECK_EXACT) */
    /* A shooter's receivers take at most its power (spirv/reconstruct.comp,
     * "Conservation"): three dispatches instead of one. */
    bool conserve;
    /* Fixed patches (surfaces with patches_s) are scaled too: the dynamic
     * methods' first solve, before any redistribution removes what they
     * shot. Afterwards removal and insertion must use the same factors. */
    bool conserve_fixed;
    /* The ID hemicubes draw the static surfaces alone (cross's progressive
     * iterations): elements of dynamic surfaces receive nothing. */
    bool static_only;
    /* A redistribution removes these shots again (incremental.c): the
     * receivers see the shooter as spirv/incremental_reconstruct.comp does
     * (the occluder test from the patch's centre, its mean radiosity, no
     * contact flags), or what it removes differs from what was shot and
     * the difference piles up frame after frame (10,000 frames of a
     * sliding box ran to -38 times the emitted power). */
    bool redistributed;
    /* Receivers very near a patch see it block by block, each block's
     * visibility its own (spirv/reconstruct.comp near_cells), not by its
     * centre's. Not for shots of signed changes (cross's iterations after
     * a restart) nor redistributed ones. */
    bool near_blocks;
    uint32_t max_shooters;  /* the shooter table's size */
} reconstruct_params;

/* conserve_far: the pass with XRAD_CONSERVE_FAR compiled in (its own
 * SPIR-V, spirv/reconstruct.comp): with conserve, only the receivers that
 * see a shooter by its centre are scaled; those that see it block by block
 * keep their exact form factors, every quad a candidate occluder of each
 * block. */
xrad_status reconstruct_create(struct xrad_context *ctx, bool conserve_far,
                               reconstruct_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void reconstruct_destroy(struct xrad_context *ctx, reconstruct_pass **pass);

/* Points the pass at its resources. No recording that uses the pass may be
 * pending on the GPU. */
void reconstruct_bind(struct xrad_context *ctx, reconstruct_pass *pass,
                      const reconstruct_bindings *bindings);

/* Records the dispatch, sized by the status's VkDispatchIndirectCommand at
 * `dispatch_offset` bytes. The caller orders it after the select pass and
 * the hemicube render, and the next readers of B and Bu after it. */
void reconstruct_record(reconstruct_pass *pass, VkCommandBuffer cmd,
                        const reconstruct_params *params, const gpu_buffer *status,
                        VkDeviceSize dispatch_offset);

#endif
