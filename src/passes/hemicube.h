/*
 * Hemicube render pass (DESIGN.md "GPU passes"; thesis 2.2.2, 4.2, 4.3):
 * draws the scene (whole surfaces, gpu_scene's indexed triangles) into the 5 used faces
 * of many hemicubes per recording, into one 2D-array image with layer =
 * hemicube * 5 + face. Faces, axes, clip positions and pixel lookup follow
 * src/passes/hemicube_geometry.h and spirv/hemicube.glsl. The frame of
 * hemicube h is entry `first + h` of a struct gpu_shooter buffer (origin
 * pos_area.xyz, z = normal, x = tangent, y = z x x; whoever builds the
 * frames applies the random rotation about the normal, thesis 4.2); the
 * origin is moved a hair along the normal so that its own surface lies
 * below the horizon. The number of hemicubes is given by the host or read
 * by the GPU from an indirect draw command (instanceCount = hemicubes x
 * hemicube_instances_per_hemicube), so no host work is needed per
 * hemicube.
 *
 * Variants:
 *  - IDs: R32G32_UINT colour = surface + 1 (0: nothing) and the distance of
 *    the point drawn (m, float bits), + D32 depth, reversed Z
 *    (clear 0, GREATER) with an infinite far plane and a near plane at a
 *    small fraction of the scene's diameter.
 *  - radiosity: RGBA16F (or RGBA32F, desc.fp32) colour = B x scale of the visible front side, from
 *    the atlas (bilinear between element samples, as the display), 1 or 4
 *    samples, resolved with vkCmdResolveImage (lavapipe's render-pass
 *    resolve ignores the view's base layer), + depth. The scale keeps large
 *    emissions inside fp16's range; the integrate pass divides it out.
 *    Alpha holds the distance from the hemicube's origin / diameter (0
 *    where nothing was drawn), resolved with the colour: the depth the
 *    cross method's reprojection samples (thesis 4.5.2).
 *
 * Two paths draw the same thing:
 *  - multiview (VK_KHR_multiview): one render pass instance per hemicube,
 *    5 views, gl_ViewIndex is the face;
 *  - layered (shaderOutputLayer): one render pass instance, one instanced
 *    draw, instance = hemicube * 5 + face written to gl_Layer.
 * Mesa lavapipe 22.3 routes the views of a 5-view multiview pass into the
 * wrong layers without any validation message, so HEMICUBE_PATH_AUTO checks
 * each path against a CPU ray cast of a small known scene
 * (hemicube_check_path) and takes multiview where that check passes, else
 * layered.
 *
 * Results: after a recording, the result image (hemicube_image) is in
 * SHADER_READ_ONLY_OPTIMAL and the pass's dependencies make its writes
 * visible to compute and fragment shaders and transfers that follow.
 */
#ifndef XRAD_PASSES_HEMICUBE_H
#define XRAD_PASSES_HEMICUBE_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

#define HEMICUBE_ID_FORMAT VK_FORMAT_R32G32_UINT
#define HEMICUBE_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT

/* Near plane and origin offset along the normal, as fractions of the
 * scene's diameter: far below any element spacing, far above float
 * rounding at that scale (the vertex stage adds a few float steps of the
 * origin's coordinates to the offset). */
#define HEMICUBE_NEAR_FRACTION 1e-4
#define HEMICUBE_HAIR_FRACTION 1e-5

typedef enum hemicube_kind {
    HEMICUBE_IDS,
    HEMICUBE_RADIOSITY,
} hemicube_kind;

typedef enum hemicube_path {
    HEMICUBE_PATH_AUTO,      /* the path check decides: multiview if it passes, else layered */
    HEMICUBE_PATH_MULTIVIEW,
    HEMICUBE_PATH_LAYERED,
} hemicube_path;

/* "multiview", "layered" ("auto" for HEMICUBE_PATH_AUTO). */
const char *hemicube_path_label(hemicube_path path);

/* Whether the device has what the path needs (multiview with 5 views;
 * shaderOutputLayer), not whether it draws it correctly. */
bool hemicube_path_supported(const struct xrad_context *ctx, hemicube_path path);

typedef struct hemicube_check_result {
    uint32_t pixels; /* compared */
    uint32_t edge;   /* differing pixels whose GPU ID the CPU finds in a neighbouring pixel */
    uint32_t wrong;  /* other differing pixels */
    bool ok;         /* wrong == 0 and edge <= pixels / 200 */
} hemicube_check_result;

/* Renders ID hemicubes of a known scene (a closed box of 6 differently
 * numbered walls and a tilted quad inside; 3 hemicubes with off-centre,
 * tilted and rotated frames, 32 x 32) with `path` (not AUTO) and compares
 * every pixel with a CPU ray cast through its centre. XRAD_ERROR_SYSTEM
 * when the device lacks the path or a Vulkan call fails; a wrong picture
 * is a result (out->ok false), not an error. */
xrad_status hemicube_check_path(struct xrad_context *ctx, hemicube_path path,
                                hemicube_check_result *out, xrad_error *err);

typedef struct hemicube_desc {
    hemicube_kind kind;
    uint32_t res;           /* pixels per face side, even, 8..1024 */
    uint32_t max_hemicubes; /* most hemicubes one recording draws, >= 1 */
    uint32_t msaa;          /* radiosity: 1 or 4 samples; IDs: 0 or 1 */
    hemicube_path path;
    double diameter;        /* m, scene size: near plane and origin offset scale with it; > 0 */
    bool fp32;              /* radiosity: RGBA32F texels instead of RGBA16F */
    bool cells;             /* radiosity: each element's cell value (hemicube_radiosity.frag)
                               instead of bilinear between element samples */
    bool open_only;         /* radiosity, bilinear: the cell value wherever one of the
                               four samples is a buried element's (the atlas's alpha 0,
                               atlas_scatter.comp; hemicube_radiosity.frag) */
    bool redistribution;    /* images count as GPU_MEM_REDISTRIBUTION, not render targets */
    bool own_black;         /* radiosity: a hemicube's own surface (its frame's `surface`,
                               not a group's) is drawn black: gather, whose hemicubes tilt
                               to normal-mapped receivers' normals (hemicube_radiosity.frag) */
} hemicube_desc;

/* The radiosity texel format for desc->fp32. */
VkFormat hemicube_radiosity_format(bool fp32);

typedef struct hemicube_pass hemicube_pass;

/* A pass with its images (max_hemicubes x 5 layers). With
 * HEMICUBE_PATH_AUTO it runs hemicube_check_path first (multiview, then
 * layered if multiview fails), once per context: later passes take the
 * path it chose. Fails when no path draws correctly. */
xrad_status hemicube_create_desc(struct xrad_context *ctx, const hemicube_desc *desc,
                                 hemicube_pass **out, xrad_error *err);

/* The ID variant, path AUTO, for a scene of `diameter` (its bounds'
 * diagonal: the depth range; <= 0 means 1). */
xrad_status hemicube_create(struct xrad_context *ctx, double diameter, uint32_t res,
                            uint32_t max_hemicubes, hemicube_pass **out, xrad_error *err);

/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void hemicube_destroy(struct xrad_context *ctx, hemicube_pass **pass);

/* "multiview" or "layered": the path this pass draws with. */
const char *hemicube_path_name(const hemicube_pass *pass);
hemicube_path hemicube_pass_path(const hemicube_pass *pass);

/* What the check found for the chosen path (all zero when the path was
 * forced rather than checked). */
hemicube_check_result hemicube_pass_check(const hemicube_pass *pass);

/* Draw instances per hemicube in an indirect draw command: 5 (layered) or
 * 1 (multiview). */
uint32_t hemicube_instances_per_hemicube(const hemicube_pass *pass);

/* The result: R32_UINT (IDs) or RGBA16F/32F (radiosity, resolved), 2D array,
 * max_hemicubes x 5 layers, res x res, usable as sampled image and transfer
 * source. */
gpu_image *hemicube_image(hemicube_pass *pass);
/* Its view of all layers (2D array). */
VkImageView hemicube_ids_view(const hemicube_pass *pass);

uint32_t hemicube_res(const hemicube_pass *pass);
uint32_t hemicube_max(const hemicube_pass *pass);

/* The indexed triangles a hemicube draws (spirv/hemicube_shared.h). */
typedef struct hemicube_mesh {
    const gpu_buffer *vertices;  /* struct gpu_hemicube_vertex[]: VERTEX and STORAGE usage */
    const gpu_buffer *indices;   /* uint32_t, 3 per triangle: INDEX and STORAGE usage */
    const gpu_buffer *triangles; /* struct gpu_hemicube_triangle per triangle, STORAGE */
    /* Host: range_count + 1 index offsets, or NULL. A draw of the host's
     * count draws range by range (hemicube_clusters.h says why). */
    const uint32_t *ranges;
    uint32_t range_count;
} hemicube_mesh;

typedef struct hemicube_draw {
    hemicube_mesh mesh;
    /* Without commands: indices [0, index_count) (whole triangles; with
     * ranges, at the end of one). With `indirect`, the multiview path draws
     * these (one render pass instance per hemicube, the command's count
     * word saying which are live) while the layered path draws the
     * command's own indexCount: the two must be equal. */
    uint32_t index_count;
    const gpu_buffer *frames;   /* struct gpu_shooter[], STORAGE usage */
    uint32_t first;             /* frame of hemicube 0 */
    /* Either the host's count (indirect NULL; at most max_hemicubes) or a
     * VkDrawIndexedIndirectCommand at `indirect_offset` (a multiple of 4) of
     * `indirect` (INDIRECT and STORAGE usage), whose instanceCount is
     * hemicubes x hemicube_instances_per_hemicube, at most max_hemicubes. */
    uint32_t count;
    const gpu_buffer *indirect;
    VkDeviceSize indirect_offset;
    const gpu_image *atlas; /* radiosity: RGBA32F, in VK_IMAGE_LAYOUT_GENERAL */
    float scale;            /* radiosity: image = B x scale; 0 means 1 */
    /* Instead of one draw of index_count indices: command_count
     * VkDrawIndexedIndirectCommands from offset 0 of `commands` (INDIRECT
     * and STORAGE usage; the cull pass's, passes/hemicube_cull.h), each
     * with the instance count the path needs (layered: hemicubes x 5,
     * multiview: 1). */
    const gpu_buffer *commands;
    uint32_t command_count;
} hemicube_draw;

/* Records the hemicubes into `cmd` outside any render pass (and, with 4
 * samples, the resolve). Points the pass's descriptor set at the draw's
 * buffers when they differ from the last recording's; that needs the last
 * recording with other buffers to have completed. The caller orders the
 * writes of frames, indirect command and atlas before it. */
void hemicube_record(hemicube_pass *pass, VkCommandBuffer cmd, const hemicube_draw *draw);

/* The ID variant of `mesh` (indices [0, index_count), the indexCount of
 * the indirect command too) with the indirect count at `indirect_offset`
 * of `indirect`: what the progressive solver records per shot. With
 * `commands` (else NULL), the cull pass's `count` commands instead of one
 * draw of every triangle. */
void hemicube_record_ids(hemicube_pass *pass, VkCommandBuffer cmd, const hemicube_mesh *mesh,
                         uint32_t index_count,
                         const gpu_buffer *frames, const gpu_buffer *indirect,
                         VkDeviceSize indirect_offset, const gpu_buffer *commands,
                         uint32_t count);

#endif
