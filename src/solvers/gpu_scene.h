/*
 * The scene on the GPU, as every radiosity solver's passes see it: the
 * buffers of spirv/radiosity.h (surfaces, elements, materials at the current
 * pose, a hierarchy over the surfaces for segment tests), total and unshot radiosity B and Bu per element (fp32, DESIGN.md
 * "Data model"), the indexed triangles hemicubes draw (whole surfaces, not
 * elements: vertex work is the cost on lavapipe; spirv/hemicube_shared.h),
 * and the radiosity atlas image the radiosity hemicubes and the display
 * sample.
 *
 * Ownership: gpu_scene_create fills a caller-owned struct; gpu_scene_destroy
 * releases what it holds. The xrad_scene must outlive it.
 */
#ifndef XRAD_SOLVERS_GPU_SCENE_H
#define XRAD_SOLVERS_GPU_SCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "gpu/buffer.h"
#include "gpu/cmd.h"
#include "gpu/image.h"
#include "passes/hemicube.h"
#include "scene/scene.h"
#include "shared.h"
#include "scene/quad_bvh.h"
#include "solvers/hemicube_clusters.h"
#include "xrad.h"

/* A host vector as the GPU tables store it. */
static inline vec4 gpu_vec4(vec3 v, double w)
{
    return (vec4){(float)v.x, (float)v.y, (float)v.z, (float)w};
}

struct xrad_context;

typedef struct gpu_scene {
    const xrad_scene *scene;
    double time; /* pose the buffers hold */
    uint32_t surface_count, element_count, material_count;
    uint32_t vertex_count;     /* hemicube vertices, shared by the triangles */
    uint32_t index_count;      /* 6 per quad, 3 per triangle: static surfaces first, then
                                  dynamic ones */
    uint32_t static_index_count; /* those of static surfaces (set C) */
    gpu_buffer surfaces;       /* struct gpu_surface[surface_count] */
    gpu_buffer elements;       /* struct gpu_element[element_count] */
    gpu_buffer materials;      /* struct gpu_material[material_count] */
    gpu_buffer B, Bu;          /* vec4[element_count] */
    gpu_buffer vertices;       /* struct gpu_hemicube_vertex[vertex_count], world at `time`:
                                  VERTEX, STORAGE */
    gpu_buffer indices;        /* uint32_t[index_count] in layout's order: INDEX, STORAGE */
    gpu_buffer triangles;      /* struct gpu_hemicube_triangle[index_count / 3] */
    hemicube_clusters layout;  /* the triangles' order, vertices and clusters
                                  (hemicube_clusters.h) */
    uint32_t cluster_count, static_cluster_count;
    gpu_buffer clusters;       /* struct gpu_cluster[cluster_count] at `time` */
    quad_bvh bvh;              /* the segment tests' tree (surface_bvh.h), built at create */
    gpu_buffer bvh_nodes;      /* struct gpu_bvh_node[bvh.node_count] (at least 1), boxes at
                                  `time` */
    gpu_buffer bvh_items;      /* uint[surface_count]: bvh.items */
    uint32_t bvh_depth;        /* the tree's levels */
    gpu_image atlas;           /* RGBA32F, atlas_width x atlas_height: B by element texel,
                                  written by the atlas scatter pass (passes/atlas_scatter.h);
                                  always in VK_IMAGE_LAYOUT_GENERAL (zero after create) */
    double diameter;           /* m, bounding-box diagonal of the scene at `time` */
    uint32_t *fixed_patches;   /* NULL, or 3 per surface: gpu_surface.patches_s, patches_t,
                                  patch_first */
    uint8_t *buried;           /* element_count: scene_find_buried at `time` (1: under a
                                  static surface, 2: under a moving one; gpu_element.flags) */
    uint8_t *enclosed;         /* element_count: scene_find_enclosed, found once (static) */
    uint8_t *enclosed_m;       /* element_count: scene_find_enclosed_dynamic at `time`, with
                                  GPU_SCENE_ENCLOSE_MOVING (else all 0) */
    uint32_t flags;            /* GPU_SCENE_* */
    /* A pose's uploads: one host-visible staging buffer, kept from pose to
     * pose, and the one submission of their copies, which nothing waits for
     * (gpu_scene_pose, gpu_scene_collect_pose); zeroed when none is pending. */
    gpu_buffer pose_staging;
    gpu_cmd pose_cmd;
} gpu_scene;

/* Contact distance for buried elements, a fraction of the scene's
 * diameter: as cross's covered() test (cross_reconstruct.comp). */
#define GPU_SCENE_CONTACT 1e-4

/* A radiosity atlas image of the scene's size (at least 1 x 1), RGBA32F,
 * usable for scatter, sampling and copies: the gpu_scene's, and the
 * scheduler's two display atlases. */
gpu_image_desc gpu_scene_atlas_desc(const xrad_scene *scene);

/* gpu_scene_create flags. ENCLOSE_MOVING: at every pose, the static
 * elements that moving objects close in (scene_find_enclosed_dynamic) are
 * buried under a moving cover (2 in `buried`, GPU_ELEMENT_BURIED_M): the
 * solves that see M take them out (progressive, gather, incremental's
 * first solve), cross's reconstruction takes their light away. */
#define GPU_SCENE_ENCLOSE_MOVING 1u

/* Uploads the scene posed at `time`, with B = Bu = E. */
xrad_status gpu_scene_create(struct xrad_context *ctx, const xrad_scene *scene, double time,
                             uint32_t flags, gpu_scene *out, xrad_error *err);

/* Accepts a zeroed struct; zeroes it. The GPU must be done with it. */
void gpu_scene_destroy(struct xrad_context *ctx, gpu_scene *gs);

/* Re-uploads the geometry (surfaces, elements, hemicube vertices,
 * clusters, hierarchy boxes) posed at `time`. B and Bu are kept. The GPU
 * must not be using those buffers. The copies are one submission that the
 * host does not wait for: every later recording starts with a full barrier
 * (gpu_cmd_begin), so whatever is submitted after it sees the new pose. */
xrad_status gpu_scene_pose(struct xrad_context *ctx, gpu_scene *gs, double time,
                           xrad_error *err);

/* Frees the last pose's copy submission once it is complete, waiting for
 * it if need be (after any later submission was waited for it is done
 * already). The solvers call it after each of their waits, in the thread
 * that posed (a command buffer goes back to its thread's pool). */
xrad_status gpu_scene_collect_pose(struct xrad_context *ctx, gpu_scene *gs, xrad_error *err);

/* Fixes the shooting patches the select pass uses for each surface, from
 * now on and at every pose: 3 per surface, the counts along s and t (0 0:
 * by power) and the number of its first patch (gpu_surface.patch_first). */
xrad_status gpu_scene_fix_patches(struct xrad_context *ctx, gpu_scene *gs,
                                  const uint32_t *patches, xrad_error *err);

/* B = Bu = E for every element, E with the luminaires' light reflected
 * (scene_luminaire_reflected); with static_only, Bu = 0 on the dynamic
 * surfaces (whose light the cross method shoots itself) and only the
 * static objects shadow the luminaires (the static scene alone, which
 * cross solves: what M hides is its redistribution's). */
xrad_status gpu_scene_reset(struct xrad_context *ctx, gpu_scene *gs, bool static_only,
                            xrad_error *err);

/* The scene's hemicube triangles, at the pose its vertices hold, by
 * clusters. */
static inline hemicube_mesh gpu_scene_hemicube_mesh(const gpu_scene *gs)
{
    return (hemicube_mesh){&gs->vertices, &gs->indices, &gs->triangles, gs->layout.first,
                           gs->layout.count};
}

/* Reads B back into a host atlas (xrad_atlas_create of the same scene);
 * with `ambient`, plus the ambient term of the unshot radiosity Bu. */
xrad_status gpu_scene_read(struct xrad_context *ctx, gpu_scene *gs, xrad_atlas *atlas,
                           bool ambient, xrad_error *err);

#endif
