/*
 * Select pass (DESIGN.md "GPU passes"; thesis 4.3.2 FINDSHOOTINGQUAD and
 * GENERATESHOOTINGPATCHES, 4.3.3 dynamic shooter subdivision): two compute
 * dispatches per shot. The first computes every surface's area-weighted
 * unshot power |luminance(sum_e Bu_e A_e)|; the second, one workgroup,
 * takes the argmax, tests convergence (power <= threshold x the largest
 * power seen this solve, which is the first shot's: the largest emitted
 * power), splits the chosen surface into kx x ky patches of elements
 * (about max_patches^2 x power / max_power patches, shaped to the surface,
 * at most max_patches and the element count per side, at most
 * max_shooters), fills a gpu_shooter per patch (centre, area, mean unshot
 * radiosity, hemicube frame randomly rotated about the normal, hemicube
 * index = patch index), zeroes the chosen surface's Bu, and writes the
 * struct select_status (spirv/select_shared.h): the indirect draw of the ID
 * hemicubes, the indirect dispatch of the reconstruct pass, the counters
 * and the sticky converged flag. Once converged, later shots write zero
 * counts and change nothing. The host reads nothing per shot.
 *
 * With group_shooters, surfaces of one patch and few elements that hold at
 * least SELECT_GROUP_SHARE of the chosen one's power join its shot, one
 * shooter each after its patches (a mesh's faces go many a shot). The pass
 * also sums all the powers (status.unshot); with unshot_share it does not
 * converge while that sum exceeds the share of the first sum, whatever the
 * largest surface holds.
 */
#ifndef XRAD_PASSES_SELECT_H
#define XRAD_PASSES_SELECT_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct select_pass select_pass;

/* What the pass reads and writes; the pass keeps the per-surface powers
 * itself. Buffers need STORAGE usage; `status` also INDIRECT for the
 * passes it drives. */
typedef struct select_buffers {
    const gpu_buffer *surfaces; /* struct gpu_surface[surface_count] */
    const gpu_buffer *elements; /* struct gpu_element[element_count] */
    const gpu_buffer *Bu;       /* vec4[element_count], read and cleared */
    const gpu_buffer *shooters; /* struct gpu_shooter[max_shooters], written */
    const gpu_buffer *status;   /* struct select_status, read and written */
    const gpu_buffer *shot;     /* vec4[shot_first + group_shooters x group_elements]: the
                                   shot surfaces' Bu by element, written before it is cleared */
} select_buffers;

/* Elements of the scene's largest surface: the entries `shot` needs. */
uint32_t select_shot_capacity(const xrad_scene *scene);

typedef struct select_params {
    uint32_t element_count;
    uint32_t max_patches;  /* >= 1 */
    uint32_t max_shooters; /* >= 1, entries in the shooter table */
    uint32_t draw_index_count;       /* copied into the indexed indirect draw */
    uint32_t instances_per_hemicube; /* draw instances per shooter */
    uint32_t reconstruct_group;      /* workgroup size of the indirect dispatch */
    uint32_t seed;                   /* hemicube rotations */
    double threshold;                /* in [0, 1) */
    /* Also unconverged while the sum of the powers exceeds this share of
     * the largest such sum this solve (0: no such test). */
    double unshot_share;
    /* Shooters of a shot with the surfaces that join the chosen one (0: it
     * shoots alone); surfaces of at most group_elements elements join,
     * their unshot radiosity in `shot` from shot_first on (the entries of
     * the scene's largest surface, select_shot_capacity()). */
    uint32_t group_shooters;
    uint32_t group_elements;
    uint32_t shot_first;
    /* Patches follow the power share itself (thesis 4.3.3), not its square
     * root: cross's progressive iterations after its restart
     * (spirv/select.comp says why). */
    bool linear_rule;
    /* GPU_ELEMENT_* flags of the elements no light reaches in these shots:
     * a patch shoots from the others (spirv/select.comp). */
    uint32_t buried_mask;
} select_params;

/* A pass for scenes of `surface_count` (>= 1) surfaces. */
xrad_status select_create(struct xrad_context *ctx, uint32_t surface_count, select_pass **out,
                          xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void select_destroy(struct xrad_context *ctx, select_pass **pass);

/* Points the pass at its buffers. No recording that uses the pass may be
 * pending on the GPU. */
void select_bind(struct xrad_context *ctx, select_pass *pass, const select_buffers *buffers);

/* Records one shot's selection (both dispatches and the barrier between
 * them) outside any render pass. The caller orders it after whatever last
 * wrote Bu and the status, and orders the readers of the shooters, the
 * status and Bu after it. */
void select_record(select_pass *pass, VkCommandBuffer cmd, const select_params *params);

#endif
