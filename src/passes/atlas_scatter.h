/*
 * Atlas scatter pass: writes one value per element (B) into the element's
 * texel of the radiosity atlas (alpha 1), the image the radiosity
 * hemicubes and the display sample (thesis 4.1: texel centres of a tile are
 * the element samples). One invocation per element.
 */
#ifndef XRAD_PASSES_ATLAS_SCATTER_H
#define XRAD_PASSES_ATLAS_SCATTER_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "gpu/image.h"
#include "xrad.h"

struct xrad_context;

typedef struct atlas_scatter_pass atlas_scatter_pass;

xrad_status atlas_scatter_create(struct xrad_context *ctx, atlas_scatter_pass **out,
                                 xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void atlas_scatter_destroy(struct xrad_context *ctx, atlas_scatter_pass **pass);

typedef struct atlas_scatter_draw {
    const gpu_buffer *elements; /* struct gpu_element[element_count]: texels */
    const gpu_buffer *values;   /* vec4[element_count]: rgb written */
    uint32_t element_count;
    const gpu_image *atlas;     /* RGBA32F with STORAGE usage, in VK_IMAGE_LAYOUT_GENERAL */
} atlas_scatter_draw;

/* Records the dispatch outside any render pass. Points the descriptor set
 * at the draw's resources when they differ from the last recording's; that
 * needs the last recording with others to have completed. The caller
 * orders the writes of the values before it and the atlas's readers after
 * it. Texels of no element are left as they are. */
void atlas_scatter_record(atlas_scatter_pass *pass, VkCommandBuffer cmd,
                          const atlas_scatter_draw *draw);

#endif
