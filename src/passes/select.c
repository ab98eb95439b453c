#include "passes/select.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/cmd.h"
#include "gpu/kernel.h"
#include "scene/scene.h"
#include "select.comp.h"
#include "select_shared.h"
#include "select_power.comp.h"

struct select_pass {
    uint32_t surface_count;
    gpu_buffer power; /* float[surface_count] */
    /* Two kernels over the same bindings: the surfaces' unshot power, then
     * the argmax and the shot (select_power.comp, select.comp). */
    gpu_kernel power_kernel, select_kernel;
};

xrad_status select_create(struct xrad_context *ctx, uint32_t surface_count, select_pass **out,
                          xrad_error *err)
{
    *out = NULL;
    if (surface_count == 0)
        return xrad_fail(err, XRAD_ERROR_INPUT, "select pass: the scene has no surfaces");
    select_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "select pass: out of host memory");
    p->surface_count = surface_count;
    VkDescriptorType types[SELECT_BINDING_COUNT];
    for (uint32_t b = 0; b < SELECT_BINDING_COUNT; b++)
        types[b] = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    gpu_kernel_desc power = {
        .spv = select_power_comp_spv,
        .spv_bytes = sizeof(select_power_comp_spv),
        .types = types,
        .binding_count = SELECT_BINDING_COUNT,
        .push_bytes = sizeof(struct select_push),
        .name = "select pass (power)",
    };
    gpu_kernel_desc select = power;
    select.spv = select_comp_spv;
    select.spv_bytes = sizeof(select_comp_spv);
    select.name = "select pass";
    xrad_status s;
    if ((s = gpu_buffer_create(ctx, (VkDeviceSize)surface_count * sizeof(float),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, GPU_MEM_DEVICE,
                               GPU_MEM_RADIOSITY, &p->power, err)) ||
        (s = gpu_kernel_create(ctx, &power, &p->power_kernel, err)) ||
        (s = gpu_kernel_create(ctx, &select, &p->select_kernel, err))) {
        select_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

void select_destroy(struct xrad_context *ctx, select_pass **pass)
{
    if (!pass || !*pass)
        return;
    select_pass *p = *pass;
    gpu_kernel_destroy(ctx, &p->select_kernel);
    gpu_kernel_destroy(ctx, &p->power_kernel);
    gpu_buffer_destroy(ctx, &p->power);
    free(p);
    *pass = NULL;
}

void select_bind(struct xrad_context *ctx, select_pass *p, const select_buffers *b)
{
    const gpu_kernel_resource r[SELECT_BINDING_COUNT] = {
        [SELECT_BINDING_SURFACES] = {b->surfaces}, [SELECT_BINDING_ELEMENTS] = {b->elements},
        [SELECT_BINDING_BU] = {b->Bu},             [SELECT_BINDING_POWER] = {&p->power},
        [SELECT_BINDING_SHOOTERS] = {b->shooters}, [SELECT_BINDING_STATUS] = {b->status},
        [SELECT_BINDING_SHOT] = {b->shot},
    };
    gpu_kernel_bind(ctx, &p->power_kernel, 0, r);
    gpu_kernel_bind(ctx, &p->select_kernel, 0, r);
}

void select_record(select_pass *p, VkCommandBuffer cmd, const select_params *params)
{
    struct select_push push = {
        .surface_count = p->surface_count,
        .element_count = params->element_count,
        .max_patches = params->max_patches ? params->max_patches : 1,
        .max_shooters = params->max_shooters ? params->max_shooters : 1,
        .draw_index_count = params->draw_index_count,
        .instances_per_hemicube = params->instances_per_hemicube,
        .seed = params->seed,
        .reconstruct_group = params->reconstruct_group ? params->reconstruct_group : 1,
        .threshold = (float)params->threshold,
        .linear_rule = params->linear_rule ? 1u : 0u,
        .buried_mask = params->buried_mask,
        .unshot_share = (float)params->unshot_share,
        .group_shooters = params->group_shooters,
        .group_elements = params->group_elements,
        .shot_first = params->shot_first,
    };
    gpu_kernel_dispatch(&p->power_kernel, cmd, 0, &push, p->surface_count, SELECT_POWER_GROUP);
    /* The powers are complete before the argmax reads them. */
    gpu_memory_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_READ_BIT);
    gpu_kernel_dispatch_groups(&p->select_kernel, cmd, 0, &push, 1);
}

uint32_t select_shot_capacity(const xrad_scene *scene)
{
    uint32_t most = 1;
    for (uint32_t k = 0; k < scene->surface_count; k++) {
        uint32_t n = scene->surfaces[k].nu * scene->surfaces[k].nv;
        most = n > most ? n : most;
    }
    return most;
}
