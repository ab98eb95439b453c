#include "passes/cross_update.h"

#include <stdlib.h>

#include "core/error.h"
#include "cross_shared.h"
#include "cross_update.comp.h"
#include "gpu/kernel.h"

struct cross_update_pass {
    gpu_kernel kernel;
};

xrad_status cross_update_create(struct xrad_context *ctx, cross_update_pass **out,
                                xrad_error *err)
{
    *out = NULL;
    cross_update_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "cross update pass: out of host memory");
    VkDescriptorType types[CROSS_UPDATE_BINDING_COUNT];
    for (uint32_t b = 0; b < CROSS_UPDATE_BINDING_COUNT; b++)
        types[b] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    types[CROSS_UPDATE_BINDING_GATHER_HEMICUBES] = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    gpu_kernel_desc d = {
        .spv = cross_update_comp_spv,
        .spv_bytes = sizeof(cross_update_comp_spv),
        .types = types,
        .binding_count = CROSS_UPDATE_BINDING_COUNT,
        .push_bytes = sizeof(struct cross_update_push),
        .name = "cross update pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void cross_update_destroy(struct xrad_context *ctx, cross_update_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void cross_update_bind(struct xrad_context *ctx, cross_update_pass *p,
                       const cross_update_bindings *b)
{
    gpu_kernel_resource r[CROSS_UPDATE_BINDING_COUNT] = {
        [CROSS_UPDATE_BINDING_SURFACES] = {b->surfaces, 0},
        [CROSS_UPDATE_BINDING_ELEMENTS] = {b->elements, 0},
        [CROSS_UPDATE_BINDING_MATERIALS] = {b->materials, 0},
        [CROSS_UPDATE_BINDING_B] = {b->B, 0},
        [CROSS_UPDATE_BINDING_BU] = {b->Bu, 0},
        [CROSS_UPDATE_BINDING_PATCHES] = {b->patches, 0},
        [CROSS_UPDATE_BINDING_VALUES] = {b->values, 0},
        [CROSS_UPDATE_BINDING_GATHERED] = {b->gathered, 0},
        [CROSS_UPDATE_BINDING_OUT] = {b->out, 0},
        [CROSS_UPDATE_BINDING_SURFACE_PATCH] = {b->surface_patch, 0},
        [CROSS_UPDATE_BINDING_PEAK] = {b->peak, 0},
        [CROSS_UPDATE_BINDING_FRAMES] = {b->frames, 0},
        [CROSS_UPDATE_BINDING_GATHER_HEMICUBES] = {NULL, b->gather_hemicubes},
    };
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void cross_update_record(cross_update_pass *p, VkCommandBuffer cmd, uint32_t mode,
                         uint32_t patch_count, uint32_t element_count,
                         const cross_update_gather *gather)
{
    bool per_patch = mode == CROSS_UPDATE_TOTAL;
    struct cross_update_push push = {
        .mode = mode,
        /* GROUPS: a workgroup per patch */
        .count = mode == CROSS_UPDATE_GROUPS ? patch_count * CROSS_UPDATE_GROUP
                 : per_patch                 ? patch_count
                                             : element_count,
        .element_count = element_count,
        .patch_count = patch_count,
    };
    if (gather) {
        push.res = gather->res;
        push.inv_scale = gather->scale > 0 ? 1.0f / gather->scale : 1.0f;
        push.diameter = gather->diameter;
    }
    gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, push.count, CROSS_UPDATE_GROUP);
}
