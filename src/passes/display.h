/*
 * Display pass: draws the scene from its camera with the radiosity atlas
 * (DESIGN.md "GPU passes"). Per surface a grid of nu x nv vertices at the
 * element samples (a one-element triangle's value at its three corners,
 * drawn flat), each with its element's texel centre as texture
 * coordinate, so bilinear filtering interpolates exactly between element
 * samples and, since adjacent coplanar surfaces share boundary samples,
 * shows no seam across surfaces (thesis 4.1); nearest filtering shows the
 * elements as squares. A surface planarised on load is drawn through its
 * file vertices at the same sample parameters, so that it still meets its
 * neighbours (display.c, drawn_point).
 *
 * Output: the linear B of the visible surface in an RGBA32F image (alpha 1
 * where a surface is, 0 elsewhere), D32 depth, both cleared to 0 (reversed
 * Z). No face culling: a surface seen from behind shows its own B, which is
 * the radiosity of its front side (back sides receive and emit nothing, so
 * in a closed scene they are never visible from inside).
 */
#ifndef XRAD_PASSES_DISPLAY_H
#define XRAD_PASSES_DISPLAY_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "core/vec.h"
#include "gpu/buffer.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

#define DISPLAY_COLOR_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT
#define DISPLAY_DEPTH_FORMAT VK_FORMAT_D32_SFLOAT
#define DISPLAY_ATLAS_FORMAT VK_FORMAT_R32G32B32A32_SFLOAT

typedef enum display_filter {
    DISPLAY_FILTER_NEAREST,       /* element squares */
    DISPLAY_FILTER_LINEAR,        /* bilinear by the sampler */
    DISPLAY_FILTER_LINEAR_SHADER, /* bilinear in the shader (texelFetch) */
} display_filter;

typedef struct display_vertex {
    float pos[3];     /* m, world relative to the camera position */
    float uv[2];      /* ((texel_x + 0.5) / W, (texel_y + 0.5) / H) of the element */
    uint32_t tile[4]; /* first and last texel (x0, y0, x1, y1) of the surface's tile */
} display_vertex;

typedef struct display_mesh {
    display_vertex *vertices;
    uint32_t vertex_count;
    uint32_t *indices; /* triangle list, two triangles per element cell */
    uint32_t index_count;
} display_mesh;

/* The mesh of every surface posed at `time`, positions relative to
 * `origin` (world, m; the camera, so that float positions keep their
 * precision in large scenes). */
xrad_status display_mesh_build(const xrad_scene *scene, double time, vec3 origin,
                               display_mesh *mesh, xrad_error *err);
/* Accepts a zeroed mesh; zeroes it. */
void display_mesh_free(display_mesh *mesh);

typedef struct display_camera {
    vec3 origin;              /* m, world: the camera position */
    float clip_from_view[16]; /* column-major; input is world - origin */
    double near, far;         /* m, along the view direction */
} display_camera;

/* Perspective projection from scene->cam for a width x height image (the
 * aspect follows the image), near and far planes from the bounding box of
 * the scene at `time`: far just beyond the farthest corner, near half the
 * distance to the box (a millionth of far when the camera is inside).
 * Reversed Z: depth 1 at near, 0 at far. XRAD_ERROR_INPUT for a degenerate
 * camera (look_at at the position, up along the view, fov outside (0, pi)). */
xrad_status display_camera_make(const xrad_scene *scene, uint32_t width, uint32_t height,
                                double time, display_camera *cam, xrad_error *err);

/* The same from another camera than the scene's (xrad view's fly camera);
 * its width and height are not used. */
struct camera;
xrad_status display_camera_from(const xrad_scene *scene, const struct camera *c, uint32_t width,
                                uint32_t height, double time, display_camera *cam,
                                xrad_error *err);

typedef struct display_pass display_pass;

xrad_status display_create(struct xrad_context *ctx, display_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. */
void display_destroy(struct xrad_context *ctx, display_pass **pass);

/* Whether the sampler can filter DISPLAY_ATLAS_FORMAT linearly
 * (VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT); otherwise
 * DISPLAY_FILTER_LINEAR is refused and LINEAR_SHADER is the bilinear path. */
bool display_linear_supported(const display_pass *pass);

typedef struct display_target {
    gpu_image color, depth;
    VkFramebuffer framebuffer;
} display_target;

xrad_status display_target_create(struct xrad_context *ctx, const display_pass *pass,
                                  uint32_t width, uint32_t height, display_target *out,
                                  xrad_error *err);
/* Accepts a zeroed target; zeroes it. */
void display_target_destroy(struct xrad_context *ctx, display_target *t);

typedef struct display_draw {
    const gpu_buffer *vertices; /* display_vertex[]; may be NULL when index_count is 0 */
    const gpu_buffer *indices;
    uint32_t index_count;
    const gpu_image *atlas; /* DISPLAY_ATLAS_FORMAT, in SHADER_READ_ONLY_OPTIMAL */
    const display_camera *camera;
    display_filter filter;
} display_draw;

/* Records the pass into `cmd` (outside any render pass): clears the target,
 * draws, and leaves the colour image in TRANSFER_SRC_OPTIMAL. It rewrites
 * the pass's descriptor set, so a previous recording must have completed. */
xrad_status display_record(struct xrad_context *ctx, display_pass *pass, VkCommandBuffer cmd,
                           const display_target *target, const display_draw *draw,
                           xrad_error *err);

#endif
