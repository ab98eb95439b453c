/* Hemicube cull pass (hemicube_cull.h). */
#include "passes/hemicube_cull.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "hemicube_cull.comp.h"
#include "hemicube_cull_shared.h"

#define BINDINGS 4

struct hemicube_cull_pass {
    gpu_kernel kernel;
};

xrad_status hemicube_cull_create(struct xrad_context *ctx, hemicube_cull_pass **out,
                                 xrad_error *err)
{
    *out = NULL;
    hemicube_cull_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube cull pass: out of host memory");
    VkDescriptorType types[BINDINGS];
    for (uint32_t b = 0; b < BINDINGS; b++)
        types[b] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc d = {
        .spv = hemicube_cull_comp_spv,
        .spv_bytes = sizeof(hemicube_cull_comp_spv),
        .types = types,
        .binding_count = BINDINGS,
        .push_bytes = sizeof(struct cull_push),
        .name = "hemicube cull pass",
    };
    xrad_status s = gpu_kernel_create(ctx, &d, &p->kernel, err);
    if (s) {
        free(p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void hemicube_cull_destroy(struct xrad_context *ctx, hemicube_cull_pass **pass)
{
    if (!pass || !*pass)
        return;
    gpu_kernel_destroy(ctx, &(*pass)->kernel);
    free(*pass);
    *pass = NULL;
}

void hemicube_cull_bind(struct xrad_context *ctx, hemicube_cull_pass *p,
                        const hemicube_cull_buffers *b)
{
    const gpu_kernel_resource r[BINDINGS] = {
        [CULL_BINDING_CLUSTERS] = {b->clusters}, [CULL_BINDING_FRAMES] = {b->frames},
        [CULL_BINDING_STATUS] = {b->status},     [CULL_BINDING_COMMANDS] = {b->commands},
    };
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
}

void hemicube_cull_record(hemicube_cull_pass *p, VkCommandBuffer cmd,
                          const hemicube_cull_params *params)
{
    if (params->cluster_count == 0)
        return;
    struct cull_push push = {
        .cluster_count = params->cluster_count,
        .first = params->first,
        .count_word = params->count_word,
        .count = params->count,
        .instances = params->instances,
        .instance_word = params->instance_word,
        .margin = (float)params->margin,
    };
    gpu_kernel_dispatch(&p->kernel, cmd, 0, &push, params->cluster_count, CULL_GROUP);
}
