/*
 * Back hemicube mips (issue 16.2; thesis 6.2, "mipmapping for the
 * back-hemicubes will avoid undersampling. The appropriate mipmap level
 * must be selected depending on the distance between the element and the
 * shooter"): the means of 2^k x 2^k texel blocks of every face of cross's
 * back hemicubes, in a buffer the cross projection reads
 * (spirv/back_mips.glsl for the layout, spirv/back_mips.comp for the
 * means). One dispatch; levels made from level 0 directly.
 */
#ifndef XRAD_PASSES_BACK_MIPS_H
#define XRAD_PASSES_BACK_MIPS_H

#include <stdint.h>
#include <vulkan/vulkan.h>

#include "gpu/buffer.h"
#include "xrad.h"

struct xrad_context;

typedef struct back_mips_pass back_mips_pass;

/* Levels above level 0 for faces of side res: as many halvings as leave a
 * whole number of texels (res's factors of 2), at most BACK_MIPS_MAX_LEVELS. */
uint32_t back_mips_levels(uint32_t res);

/* Bytes of the mips of `layers` faces of side res. */
VkDeviceSize back_mips_bytes(uint32_t res, uint32_t layers);

xrad_status back_mips_create(struct xrad_context *ctx, back_mips_pass **out, xrad_error *err);
/* Accepts NULL; sets *pass to NULL. The GPU must be done with it. */
void back_mips_destroy(struct xrad_context *ctx, back_mips_pass **pass);

/* back: the hemicubes (array view, SHADER_READ_ONLY_OPTIMAL when recorded);
 * mips: at least back_mips_bytes. No recording that uses the pass may be
 * pending. */
void back_mips_bind(struct xrad_context *ctx, back_mips_pass *pass, VkImageView back,
                    const gpu_buffer *mips);

/* The caller orders the hemicubes' render before and the readers after. */
void back_mips_record(back_mips_pass *pass, VkCommandBuffer cmd, uint32_t res,
                      uint32_t layers);

#endif
