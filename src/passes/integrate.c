#include "passes/integrate.h"

#include <stdlib.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/kernel.h"
#include "integrate.comp.h"
#include "integrate_shared.h"
#include "passes/hemicube_geometry.h"

struct integrate_pass {
    struct xrad_context *ctx;
    uint32_t res;
    gpu_buffer table;
    gpu_kernel kernel;
    VkImageView bound_image;
    VkBuffer bound_out;
};

xrad_status integrate_create(struct xrad_context *ctx, uint32_t res, integrate_pass **out,
                             xrad_error *err)
{
    *out = NULL;
    if (res < 8 || res > 1024 || res % 2)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "integrate: resolution must be even and in [8, 1024], got %u", res);
    integrate_pass *p = calloc(1, sizeof(*p));
    size_t n = (size_t)HEMICUBE_FACES * res * res;
    float *table = malloc(n * sizeof(float));
    if (!p || !table) {
        free(p);
        free(table);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "integrate: out of host memory");
    }
    p->ctx = ctx;
    p->res = res;
    hemicube_delta_form_factors(res, table);
    VkDescriptorType types[3];
    types[INTEGRATE_BINDING_HEMICUBES] = VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
    types[INTEGRATE_BINDING_TABLE] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    types[INTEGRATE_BINDING_OUT] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc kd = {
        .spv = integrate_comp_spv,
        .spv_bytes = sizeof(integrate_comp_spv),
        .types = types,
        .binding_count = 3,
        .push_bytes = sizeof(struct integrate_push),
        .name = "integrate",
    };
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, n * sizeof(float),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               GPU_MEM_DEVICE, GPU_MEM_OTHER, &p->table, err)) ||
        (s = gpu_upload_buffer(ctx, &p->table, 0, table, n * sizeof(float), err)) ||
        (s = gpu_kernel_create(ctx, &kd, &p->kernel, err))) {
        free(table);
        integrate_destroy(ctx, &p);
        return s;
    }
    free(table);
    gpu_kernel_resource r[3] = {{0}};
    r[INTEGRATE_BINDING_TABLE].buffer = &p->table;
    gpu_kernel_bind(ctx, &p->kernel, 0, r);
    *out = p;
    return XRAD_OK;
}

void integrate_destroy(struct xrad_context *ctx, integrate_pass **pass)
{
    if (!pass || !*pass)
        return;
    integrate_pass *p = *pass;
    gpu_kernel_destroy(ctx, &p->kernel);
    gpu_buffer_destroy(ctx, &p->table);
    free(p);
    *pass = NULL;
}

const gpu_buffer *integrate_table(const integrate_pass *pass) { return &pass->table; }

void integrate_record(integrate_pass *p, VkCommandBuffer cmd, const integrate_draw *d)
{
    if (d->count == 0)
        return;
    if (p->bound_image != d->hemicubes || p->bound_out != d->out->buffer) {
        gpu_kernel_resource r[3] = {{0}};
        r[INTEGRATE_BINDING_HEMICUBES].view = d->hemicubes;
        r[INTEGRATE_BINDING_OUT].buffer = d->out;
        gpu_kernel_bind(p->ctx, &p->kernel, 0, r);
        p->bound_image = d->hemicubes;
        p->bound_out = d->out->buffer;
    }
    struct integrate_push push = {
        .res = p->res,
        .out_first = d->out_first,
        .count = d->count,
        .inv_scale = d->scale > 0 ? 1.0f / d->scale : 1.0f,
        .ring = d->ring,
        .ring_first = d->ring_first,
    };
    /* One workgroup per hemicube. */
    gpu_kernel_dispatch_groups(&p->kernel, cmd, 0, &push, d->count);
}
