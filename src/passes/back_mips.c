#include "passes/back_mips.h"

#include <stdlib.h>

#include "back_mips.comp.h"
#include "core/error.h"
#include "cross_shared.h"
#include "gpu/kernel.h"

struct back_mips_pass {
    gpu_kernel kernel;
};

uint32_t back_mips_levels(uint32_t res)
{
    uint32_t k = 0;
    while (k < BACK_MIPS_MAX_LEVELS && res && !(res & 1u)) {
        res >>= 1;
        k++;
    }
    return k;
}

/* spirv/back_mips.glsl's back_mip_layer_texels. */
static uint32_t layer_texels(uint32_t res, uint32_t levels)
{
    uint32_t n = 0;
    for (uint32_t k = 1; k <= levels; k++)
        n += (res >> k) * (res >> k);
    return n;
}

VkDeviceSize back_mips_bytes(uint32_t res, uint32_t layers)
{
    return (VkDeviceSize)layer_texels(res, back_mips_levels(res)) * layers * sizeof(vec4);
}

xrad_status back_mips_create(struct xrad_context *ctx, back_mips_pass **out, xrad_error *err)
{
    *out = NULL;
    back_mips_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "back mips pass: out of host memory");
    VkDescriptorType types[BACK_MIPS_BINDING_COUNT] = {
        [BACK_MIPS_BINDING_BACK] = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE,
        [BACK_MIPS_BINDING_MIPS] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
    };
    gpu_kernel_desc d = {
        .spv = back_mips_comp_spv,
        .spv_bytes = sizeof(back_mips_comp_spv),
        .types = types,
        .binding_count = BACK_MIPS_BINDING_COUNT,
        .push_bytes = sizeof(struct back_mips_push),
        .name = "back mips pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void back_mips_destroy(struct xrad_context *ctx, back_mips_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void back_mips_bind(struct xrad_context *ctx, back_mips_pass *p, VkImageView back,
                    const gpu_buffer *mips)
{
    gpu_kernel_resource r[BACK_MIPS_BINDING_COUNT] = {
        [BACK_MIPS_BINDING_BACK] = {NULL, back},
        [BACK_MIPS_BINDING_MIPS] = {mips, 0},
    };
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void back_mips_record(back_mips_pass *p, VkCommandBuffer cmd, uint32_t res, uint32_t layers)
{
    uint32_t levels = back_mips_levels(res);
    struct back_mips_push push = {
        .res = res,
        .levels = levels,
        .count = layer_texels(res, levels) * layers,
    };
    gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, push.count, BACK_MIPS_GROUP);
}
