/*
 * Cross reconstruct pass (DESIGN.md "GPU passes", "Cross-project"; thesis
 * Algorithm 4.4 lines 15-20 and Algorithm 4.5). Elements of M receive the
 * patches' total radiosity through the ID hemicubes (R_p(M, M) by
 * reshooting), one invocation per element looping over the patches;
 * elements of C receive eq. 3.3.1, R_p(M, C) + R_x(C, C), with
 * PROJECTEDRADIOSITY over up to grid x grid rays REPROJECTed through the
 * back hemicubes, in place of what the last redistribution gave them: the
 * (element, patch) pairs that see each other are listed first and the rays
 * are traced per pair, one invocation each (spirv/cross_reconstruct.comp
 * says how).
 */
#ifndef XRAD_PASSES_CROSS_RECONSTRUCT_H
#define XRAD_PASSES_CROSS_RECONSTRUCT_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct cross_reconstruct_pass cross_reconstruct_pass;

typedef struct cross_reconstruct_bindings {
    const gpu_buffer *surfaces, *elements, *materials; /* spirv/radiosity.h, at the pose */
    const gpu_buffer *B, *Bu;                          /* vec4[element_count], updated */
    const gpu_buffer *values;                          /* struct cross_value[patch_count] */
    const gpu_buffer *frames;                          /* gpu_shooter, spirv/cross_shared.h */
    const gpu_buffer *quads;                           /* struct cross_quad[patch_count] */
    /* ID hemicubes (R32_UINT array) and back hemicubes (RGBA16F array),
     * patch p in layers 5p..5p+4, SHADER_READ_ONLY_OPTIMAL. */
    VkImageView ids, back;
    /* vec4[element_count]: what the last phase C added. */
    const gpu_buffer *inserted;
    /* The lights of C: gpu_shooter and cross_quad [light_count], their ID
     * hemicubes of C alone and of C and M (as ids). Where there are no
     * lights, any buffer and ID image: light_count 0 reads none. */
    const gpu_buffer *lights, *light_quads;
    VkImageView light_ids_c, light_ids;
    /* The hierarchy over the surfaces at the pose (gpu_bvh_node[], uint[];
     * radiosity.h) for segment tests against every surface. */
    const gpu_buffer *bvh_nodes, *bvh_items;
    /* Phase C's pair list: struct cross_pair[pair_capacity], uvec2[element_count]
     * and struct cross_pair_state (STORAGE, INDIRECT; its count zeroed
     * before each C_PAIRS). */
    const gpu_buffer *pairs, *ranges, *pair_state;
    /* uint[pair_capacity] and uint[3 patch_count] (zeroed before each
     * C_PAIRS): the pairs in patch order. */
    const gpu_buffer *order, *patch_lists;
    /* uint: the largest |B - Bu - E| of C (float bits), for params.cut. */
    const gpu_buffer *peak;
    /* The back hemicubes' mips (passes/back_mips.h); any buffer where
     * params.back_levels is 0. */
    const gpu_buffer *back_mips;
    /* uint[light_count]: each light's hemicube in light_ids or
     * CROSS_LIGHT_UNREACHED (cross_shared.h); any buffer without lights. */
    const gpu_buffer *light_layers;
    /* vec4[element_count] (solvers/luminaire_change.h): rho x the
     * luminaires' light at the pose on M, its change from C's alone on C;
     * any buffer where params.luminaires is off. */
    const gpu_buffer *luminaires;
} cross_reconstruct_bindings;

typedef struct cross_reconstruct_params {
    uint32_t phase; /* CROSS_RECONSTRUCT_* */
    uint32_t element_count, patch_count, light_count;
    uint32_t hemicube_res, back_res;
    uint32_t grid;          /* PROJECTEDRADIOSITY rays per side, at most */
    double grid_ff;         /* the form factor from which a pair gets all of them */
    bool bilinear;          /* back hemicubes filtered across face edges */
    double subdivide_ratio; /* exact form factor where A_s / r^2 exceeds it */
    double back_scale;      /* the back hemicubes hold shot radiosity x this */
    double diameter;        /* m, the back hemicubes' alpha x this = distance */
    /* Elements [first, first + count) (count 0: all): a redistribution
     * may be cut into several submissions. */
    uint32_t first, count;
    bool exact_texel_only; /* no nearest-texel check (XRAD_ID_CHECK_EXACT) */
    uint32_t pair_capacity; /* entries of the pair list */
    double cut;             /* pairs of C left out below this bound (xrad.h cross_cut) */
    uint32_t back_levels;   /* mip levels of the back hemicubes to read above 0 */
    bool luminaires;        /* M_DIRECT and phase C add bindings.luminaires */
} cross_reconstruct_params;

/* full: the back mips and the contribution bound compiled in, as
 * params.back_levels and params.cut need (without, both are ignored). */
xrad_status cross_reconstruct_create(struct xrad_context *ctx, bool full,
                                     cross_reconstruct_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void cross_reconstruct_destroy(struct xrad_context *ctx, cross_reconstruct_pass **pass);

/* Writes the set. No recording that uses the pass may be pending. */
void cross_reconstruct_bind(struct xrad_context *ctx, cross_reconstruct_pass *pass,
                            const cross_reconstruct_bindings *b);

/* The caller orders the hemicube renders and the value updates before it
 * and the readers of B and Bu after it. Phase C is five dispatches with
 * barriers between: C_PAIRS (the state's count and the patch lists zeroed
 * before), C_ARGS, C_SCATTER and C_EVAL (indirect, from the state) and C. */
void cross_reconstruct_record(cross_reconstruct_pass *pass, VkCommandBuffer cmd,
                              const cross_reconstruct_params *params);

#endif
