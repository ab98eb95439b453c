#include "passes/atlas_scatter.h"

#include <stdlib.h>

#include "atlas_scatter.comp.h"
#include "atlas_scatter_shared.h"
#include "core/error.h"
#include "gpu/context.h"
#include "gpu/kernel.h"

struct atlas_scatter_pass {
    struct xrad_context *ctx;
    gpu_kernel kernel;
    VkBuffer bound_elements, bound_values;
    VkImageView bound_atlas;
};

xrad_status atlas_scatter_create(struct xrad_context *ctx, atlas_scatter_pass **out,
                                 xrad_error *err)
{
    *out = NULL;
    atlas_scatter_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "atlas scatter: out of host memory");
    p->ctx = ctx;
    VkDescriptorType types[3];
    types[ATLAS_SCATTER_BINDING_ELEMENTS] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    types[ATLAS_SCATTER_BINDING_VALUES] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    types[ATLAS_SCATTER_BINDING_ATLAS] = VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    gpu_kernel_desc d = {
        .spv = atlas_scatter_comp_spv,
        .spv_bytes = sizeof(atlas_scatter_comp_spv),
        .types = types,
        .binding_count = 3,
        .push_bytes = sizeof(struct atlas_scatter_push),
        .name = "atlas scatter",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void atlas_scatter_destroy(struct xrad_context *ctx, atlas_scatter_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void atlas_scatter_record(atlas_scatter_pass *p, VkCommandBuffer cmd,
                          const atlas_scatter_draw *d)
{
    if (d->element_count == 0)
        return;
    if (p->bound_elements != d->elements->buffer || p->bound_values != d->values->buffer ||
        p->bound_atlas != d->atlas->view) {
        gpu_kernel_resource r[3];
        r[ATLAS_SCATTER_BINDING_ELEMENTS] = (gpu_kernel_resource){.buffer = d->elements};
        r[ATLAS_SCATTER_BINDING_VALUES] = (gpu_kernel_resource){.buffer = d->values};
        r[ATLAS_SCATTER_BINDING_ATLAS] = (gpu_kernel_resource){.view = d->atlas->view};
        gpu_kernel_bind(p->ctx, &p->kernel, 0, r);
        p->bound_elements = d->elements->buffer;
        p->bound_values = d->values->buffer;
        p->bound_atlas = d->atlas->view;
    }
    struct atlas_scatter_push push = {.element_count = d->element_count};
    gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, d->element_count, ATLAS_SCATTER_GROUP);
}
