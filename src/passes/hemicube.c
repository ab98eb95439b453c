#include "passes/hemicube.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "hemicube_ids.frag.h"
#include "hemicube_layered.vert.h"
#include "hemicube_multiview.vert.h"
#include "hemicube_radiosity.frag.h"
#include "hemicube_shared.h"
#include "passes/hemicube_geometry.h"
#include "radiosity.h"

#define VIEW_MASK ((1u << HEMICUBE_FACES) - 1u)

struct hemicube_pass {
    struct xrad_context *ctx;
    hemicube_desc desc;
    hemicube_path path; /* resolved: MULTIVIEW or LAYERED */
    hemicube_check_result check;
    float near, hair;
    bool shader_bilinear;

    VkRenderPass render_pass;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkSampler sampler;
    VkDescriptorPool pool;
    VkDescriptorSet set;

    gpu_image target; /* the result, one sample */
    gpu_image msaa;   /* radiosity with 4 samples: drawn here, resolved into target */
    gpu_image depth;
    VkImageView *views; /* multiview: per hemicube, colour then depth */
    VkFramebuffer *framebuffers;
    uint32_t framebuffer_count;

    /* What the descriptor set points at. */
    VkBuffer bound_frames, bound_counts, bound_triangles, bound_vertices, bound_indices;
    VkImageView bound_atlas;
};

const char *hemicube_path_label(hemicube_path path)
{
    switch (path) {
    case HEMICUBE_PATH_MULTIVIEW:
        return "multiview";
    case HEMICUBE_PATH_LAYERED:
        return "layered";
    default:
        return "auto";
    }
}

bool hemicube_path_supported(const struct xrad_context *ctx, hemicube_path path)
{
    if (path == HEMICUBE_PATH_MULTIVIEW)
        return ctx->features.multiview && ctx->features.multiview_max_views >= HEMICUBE_FACES;
    if (path == HEMICUBE_PATH_LAYERED)
        return ctx->features.shader_output_layer;
    return false;
}

/* ------------------------------------------------------------- objects */

static xrad_status create_render_pass(hemicube_pass *p, xrad_error *err)
{
    bool rad = p->desc.kind == HEMICUBE_RADIOSITY;
    bool resolve = rad && p->desc.msaa > 1;
    /* MSAA colour is resolved by vkCmdResolveImage (lavapipe's render-pass
     * resolve ignores the view's base layer); single-sampled colour is
     * sampled or read by compute directly. */
    gpu_render_pass_desc desc = {
        .color_format = rad ? hemicube_radiosity_format(p->desc.fp32) : HEMICUBE_ID_FORMAT,
        .depth_format = HEMICUBE_DEPTH_FORMAT,
        .samples = resolve ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT,
        .color_final_layout = resolve ? VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL
                                      : VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
        .view_mask = p->path == HEMICUBE_PATH_MULTIVIEW ? VIEW_MASK : 0,
    };
    return gpu_render_pass_create(p->ctx, &desc, &p->render_pass, err);
}

static xrad_status create_pipeline(hemicube_pass *p, xrad_error *err)
{
    struct xrad_context *ctx = p->ctx;
    bool rad = p->desc.kind == HEMICUBE_RADIOSITY;
    const VkShaderStageFlags v = VK_SHADER_STAGE_VERTEX_BIT, f = VK_SHADER_STAGE_FRAGMENT_BIT;
    const VkDescriptorType sb = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    /* The ID variant's two, then the radiosity variant's four more. */
    VkDescriptorSetLayoutBinding bindings[6] = {
        {HEMICUBE_BINDING_FRAMES, sb, 1, v, NULL},
        {HEMICUBE_BINDING_COUNTS, sb, 1, v, NULL},
        {HEMICUBE_BINDING_ATLAS, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1, f, NULL},
        {HEMICUBE_BINDING_TRIANGLES, sb, 1, f, NULL},
        {HEMICUBE_BINDING_VERTICES, sb, 1, f, NULL},
        {HEMICUBE_BINDING_INDICES, sb, 1, f, NULL},
    };
    uint32_t nb = rad ? 6 : 2;
    VkDescriptorPoolSize sizes[2] = {
        {sb, rad ? 5 : 2},
        {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1},
    };
    xrad_status s;
    if ((s = gpu_descriptor_layout_create(ctx, bindings, nb, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct hemicube_push),
                                        VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT,
                                        &p->layout, err)) ||
        (s = gpu_descriptor_pool_create(ctx, sizes, rad ? 2 : 1, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err)))
        return s;
    if (rad) {
        VkFormatProperties fp;
        vkGetPhysicalDeviceFormatProperties(ctx->phys, VK_FORMAT_R32G32B32A32_SFLOAT, &fp);
        p->shader_bilinear =
            !(fp.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT);
        VkFilter filter = p->shader_bilinear ? VK_FILTER_NEAREST : VK_FILTER_LINEAR;
        if ((s = gpu_sampler_create(ctx, filter, &p->sampler, err)))
            return s;
    }

    VkVertexInputBindingDescription vb = {0, sizeof(struct gpu_hemicube_vertex),
                                          VK_VERTEX_INPUT_RATE_VERTEX};
    VkVertexInputAttributeDescription attrs[2] = {
        {HEMICUBE_ATTR_POS, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(struct gpu_hemicube_vertex, x)},
        {HEMICUBE_ATTR_IDS, 0, VK_FORMAT_R32G32_UINT,
         offsetof(struct gpu_hemicube_vertex, surface)},
    };
    const uint32_t consts[4] = {p->shader_bilinear ? 1u : 0u, p->desc.cells ? 1u : 0u,
                                p->desc.own_black ? 1u : 0u, p->desc.open_only ? 1u : 0u};
    const VkSpecializationMapEntry entries[4] = {{0, 0, sizeof(uint32_t)},
                                                 {1, sizeof(uint32_t), sizeof(uint32_t)},
                                                 {2, 2 * sizeof(uint32_t), sizeof(uint32_t)},
                                                 {3, 3 * sizeof(uint32_t), sizeof(uint32_t)}};
    VkSpecializationInfo spec = {4, entries, sizeof(consts), consts};
    bool mv = p->path == HEMICUBE_PATH_MULTIVIEW;
    gpu_graphics_desc gd = {
        .vert = mv ? hemicube_multiview_vert_spv : hemicube_layered_vert_spv,
        .vert_bytes = mv ? sizeof(hemicube_multiview_vert_spv) : sizeof(hemicube_layered_vert_spv),
        .frag = rad ? hemicube_radiosity_frag_spv : hemicube_ids_frag_spv,
        .frag_bytes = rad ? sizeof(hemicube_radiosity_frag_spv) : sizeof(hemicube_ids_frag_spv),
        .frag_spec = rad ? &spec : NULL,
        .bindings = &vb,
        .binding_count = 1,
        .attributes = attrs,
        .attribute_count = 2,
        /* Surfaces occlude from both sides; back sides are black (radiosity). */
        .cull = VK_CULL_MODE_NONE,
        .front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .depth_test = true,
        .depth_write = true,
        .depth_compare = VK_COMPARE_OP_GREATER, /* reversed Z */
        .samples = rad && p->desc.msaa > 1 ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT,
        .color_attachments = 1,
        .layout = p->layout,
        .render_pass = p->render_pass,
    };
    return gpu_graphics_pipeline_create(ctx, &gd, &p->pipeline, err);
}

static xrad_status create_targets(hemicube_pass *p, xrad_error *err)
{
    struct xrad_context *ctx = p->ctx;
    bool rad = p->desc.kind == HEMICUBE_RADIOSITY;
    bool resolve = rad && p->desc.msaa > 1;
    uint32_t res = p->desc.res, layers = p->desc.max_hemicubes * HEMICUBE_FACES;
    VkSampleCountFlagBits samples = resolve ? VK_SAMPLE_COUNT_4_BIT : VK_SAMPLE_COUNT_1_BIT;
    gpu_image_desc td = {
        .format = rad ? hemicube_radiosity_format(p->desc.fp32) : HEMICUBE_ID_FORMAT,
        .width = res,
        .height = res,
        .layers = layers,
        .array = true,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                 (resolve ? VK_IMAGE_USAGE_TRANSFER_DST_BIT
                          : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT),
        .category = p->desc.redistribution ? GPU_MEM_REDISTRIBUTION : GPU_MEM_RENDER_TARGET,
    };
    gpu_image_desc md = {
        .format = hemicube_radiosity_format(p->desc.fp32),
        .width = res,
        .height = res,
        .layers = layers,
        .array = true,
        .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
        .samples = samples,
        .category = p->desc.redistribution ? GPU_MEM_REDISTRIBUTION : GPU_MEM_RENDER_TARGET,
    };
    gpu_image_desc dd = {
        .format = HEMICUBE_DEPTH_FORMAT,
        .width = res,
        .height = res,
        .layers = layers,
        .array = true,
        .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
        .samples = samples,
        .category = p->desc.redistribution ? GPU_MEM_REDISTRIBUTION : GPU_MEM_RENDER_TARGET,
    };
    xrad_status s;
    if ((s = gpu_image_create(ctx, &td, &p->target, err)) ||
        (resolve && (s = gpu_image_create(ctx, &md, &p->msaa, err))) ||
        (s = gpu_image_create(ctx, &dd, &p->depth, err)))
        return s;
    const gpu_image *color = resolve ? &p->msaa : &p->target;

    bool mv = p->path == HEMICUBE_PATH_MULTIVIEW;
    p->framebuffer_count = mv ? p->desc.max_hemicubes : 1;
    p->framebuffers = calloc(p->framebuffer_count, sizeof(*p->framebuffers));
    if (mv)
        p->views = calloc(2 * (size_t)p->framebuffer_count, sizeof(*p->views));
    if (!p->framebuffers || (mv && !p->views))
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube: out of host memory");
    for (uint32_t k = 0; k < p->framebuffer_count; k++) {
        VkImageView att[2] = {color->view, p->depth.view};
        if (mv) {
            /* A view of this hemicube's 5 layers; views are the faces. */
            if ((s = gpu_image_view_create(ctx, color, VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                                           k * HEMICUBE_FACES, HEMICUBE_FACES,
                                           &p->views[2 * k], err)) ||
                (s = gpu_image_view_create(ctx, &p->depth, VK_IMAGE_VIEW_TYPE_2D_ARRAY,
                                           k * HEMICUBE_FACES, HEMICUBE_FACES,
                                           &p->views[2 * k + 1], err)))
                return s;
            att[0] = p->views[2 * k];
            att[1] = p->views[2 * k + 1];
        }
        VkFramebufferCreateInfo fi = {
            .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
            .renderPass = p->render_pass,
            .attachmentCount = 2,
            .pAttachments = att,
            .width = res,
            .height = res,
            .layers = mv ? 1 : layers,
        };
        if ((s = VK_CHECK(ctx, err,
                          vkCreateFramebuffer(ctx->device, &fi, NULL, &p->framebuffers[k]))))
            return s;
    }
    return XRAD_OK;
}

void hemicube_destroy(struct xrad_context *ctx, hemicube_pass **pass)
{
    if (!pass || !*pass)
        return;
    hemicube_pass *p = *pass;
    VkDevice dev = ctx->device;
    if (p->framebuffers)
        for (uint32_t k = 0; k < p->framebuffer_count; k++)
            vkDestroyFramebuffer(dev, p->framebuffers[k], NULL);
    if (p->views)
        for (uint32_t k = 0; k < 2 * p->framebuffer_count; k++)
            vkDestroyImageView(dev, p->views[k], NULL);
    free(p->framebuffers);
    free(p->views);
    gpu_image_destroy(ctx, &p->depth);
    gpu_image_destroy(ctx, &p->msaa);
    gpu_image_destroy(ctx, &p->target);
    vkDestroyDescriptorPool(dev, p->pool, NULL);
    vkDestroySampler(dev, p->sampler, NULL);
    vkDestroyPipeline(dev, p->pipeline, NULL);
    vkDestroyPipelineLayout(dev, p->layout, NULL);
    vkDestroyDescriptorSetLayout(dev, p->set_layout, NULL);
    vkDestroyRenderPass(dev, p->render_pass, NULL);
    free(p);
    *pass = NULL;
}

VkFormat hemicube_radiosity_format(bool fp32)
{
    return fp32 ? VK_FORMAT_R32G32B32A32_SFLOAT : VK_FORMAT_R16G16B16A16_SFLOAT;
}

static xrad_status check_desc(struct xrad_context *ctx, const hemicube_desc *d, xrad_error *err)
{
    const VkPhysicalDeviceLimits *lim = &ctx->props.limits;
    if (d->res < 8 || d->res > 1024 || d->res % 2)
        return xrad_fail(err, XRAD_ERROR_INPUT, "hemicube: resolution must be even and in "
                         "[8, 1024], got %u", d->res);
    if (d->kind == HEMICUBE_RADIOSITY ? (d->msaa != 1 && d->msaa != 4) : d->msaa > 1)
        return xrad_fail(err, XRAD_ERROR_INPUT, "hemicube: %u samples are not available for "
                         "%s hemicubes", d->msaa, d->kind == HEMICUBE_RADIOSITY ? "radiosity" : "ID");
    if (!(d->diameter > 0) || !isfinite(d->diameter))
        return xrad_fail(err, XRAD_ERROR_INPUT, "hemicube: scene diameter %g is not positive",
                         d->diameter);
    if (d->max_hemicubes == 0 || d->max_hemicubes > lim->maxImageArrayLayers / HEMICUBE_FACES ||
        d->max_hemicubes > lim->maxFramebufferLayers / HEMICUBE_FACES)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "hemicube: %u hemicubes per recording; the device allows 1 to %u",
                         d->max_hemicubes,
                         (lim->maxImageArrayLayers < lim->maxFramebufferLayers
                              ? lim->maxImageArrayLayers
                              : lim->maxFramebufferLayers) / HEMICUBE_FACES);
    if (d->res > lim->maxFramebufferWidth || d->res > lim->maxFramebufferHeight)
        return xrad_fail(err, XRAD_ERROR_INPUT, "hemicube: %u pixels exceed the framebuffer "
                         "limit %u", d->res, lim->maxFramebufferWidth);
    if (d->kind == HEMICUBE_RADIOSITY && d->msaa > 1 &&
        !(lim->framebufferColorSampleCounts & lim->framebufferDepthSampleCounts &
          VK_SAMPLE_COUNT_4_BIT))
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube: device '%s' has no 4x MSAA",
                         ctx->props.deviceName);
    return XRAD_OK;
}

/* Builds a pass for a resolved path. */
static xrad_status create_for_path(struct xrad_context *ctx, const hemicube_desc *desc,
                                   hemicube_path path, hemicube_pass **out, xrad_error *err)
{
    *out = NULL;
    if (!hemicube_path_supported(ctx, path))
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube: device '%s' has no %s path",
                         ctx->props.deviceName, hemicube_path_label(path));
    hemicube_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube: out of host memory");
    p->ctx = ctx;
    p->desc = *desc;
    if (!p->desc.msaa)
        p->desc.msaa = 1;
    p->path = path;
    p->near = (float)(HEMICUBE_NEAR_FRACTION * desc->diameter);
    p->hair = (float)(HEMICUBE_HAIR_FRACTION * desc->diameter);
    xrad_status s;
    if ((s = create_render_pass(p, err)) || (s = create_pipeline(p, err)) ||
        (s = create_targets(p, err))) {
        hemicube_destroy(ctx, &p);
        return s;
    }
    *out = p;
    return XRAD_OK;
}

xrad_status hemicube_create_desc(struct xrad_context *ctx, const hemicube_desc *desc,
                                 hemicube_pass **out, xrad_error *err)
{
    *out = NULL;
    xrad_status s = check_desc(ctx, desc, err);
    if (s)
        return s;
    if (desc->path != HEMICUBE_PATH_AUTO)
        return create_for_path(ctx, desc, desc->path, out, err);
    /* The device draws as it drew at the last check (issue 16: a cross
     * solver makes six passes, and a method switch all of them again). */
    unsigned known = atomic_load(&ctx->hemicube_path);
    if (known) {
        if ((s = create_for_path(ctx, desc, (hemicube_path)(known - 1), out, err)))
            return s;
        (*out)->check = (hemicube_check_result){ctx->hemicube_check[0], ctx->hemicube_check[1],
                                                ctx->hemicube_check[2], true};
        return XRAD_OK;
    }
    const hemicube_path order[2] = {HEMICUBE_PATH_MULTIVIEW, HEMICUBE_PATH_LAYERED};
    hemicube_check_result results[2] = {{0}};
    /* xrad_context_desc.hemicube_path may allow only one of the two. */
    const unsigned only[2] = {GPU_HEMICUBE_ONLY_MULTIVIEW, GPU_HEMICUBE_ONLY_LAYERED};
    for (int i = 0; i < 2; i++) {
        if (!hemicube_path_supported(ctx, order[i]) ||
            (ctx->hemicube_path_only && ctx->hemicube_path_only != only[i]))
            continue;
        if ((s = hemicube_check_path(ctx, order[i], &results[i], err)))
            return s;
        if (!results[i].ok)
            continue;
        if ((s = create_for_path(ctx, desc, order[i], out, err)))
            return s;
        (*out)->check = results[i];
        ctx->hemicube_check[0] = results[i].pixels;
        ctx->hemicube_check[1] = results[i].edge;
        ctx->hemicube_check[2] = results[i].wrong;
        atomic_store(&ctx->hemicube_path, (unsigned)order[i] + 1);
        return XRAD_OK;
    }
    const char *state[2];
    for (int i = 0; i < 2; i++)
        state[i] = !hemicube_path_supported(ctx, order[i]) ? "unsupported"
                   : ctx->hemicube_path_only && ctx->hemicube_path_only != only[i]
                       ? "not allowed by xrad_context_desc.hemicube_path"
                       : "checked";
    return xrad_fail(err, XRAD_ERROR_SYSTEM,
                     "hemicube: device '%s' draws no hemicube path correctly%s (multiview: %s, "
                     "%u of %u pixels wrong; layered: %s, %u of %u pixels wrong)",
                     ctx->props.deviceName, ctx->hemicube_path_only ? " of those allowed" : "",
                     state[0], results[0].wrong + results[0].edge, results[0].pixels, state[1],
                     results[1].wrong + results[1].edge, results[1].pixels);
}

xrad_status hemicube_create(struct xrad_context *ctx, double diameter, uint32_t res,
                            uint32_t max_hemicubes, hemicube_pass **out, xrad_error *err)
{
    hemicube_desc d = {
        .kind = HEMICUBE_IDS,
        .res = res,
        .max_hemicubes = max_hemicubes,
        .msaa = 1,
        .path = HEMICUBE_PATH_AUTO,
        .diameter = diameter > 0 ? diameter : 1.0,
    };
    return hemicube_create_desc(ctx, &d, out, err);
}

const char *hemicube_path_name(const hemicube_pass *pass) { return hemicube_path_label(pass->path); }
hemicube_path hemicube_pass_path(const hemicube_pass *pass) { return pass->path; }
hemicube_check_result hemicube_pass_check(const hemicube_pass *pass) { return pass->check; }
uint32_t hemicube_instances_per_hemicube(const hemicube_pass *pass)
{
    return pass->path == HEMICUBE_PATH_MULTIVIEW ? 1 : HEMICUBE_FACES;
}
gpu_image *hemicube_image(hemicube_pass *pass) { return &pass->target; }
VkImageView hemicube_ids_view(const hemicube_pass *pass) { return pass->target.view; }
uint32_t hemicube_res(const hemicube_pass *pass) { return pass->desc.res; }
uint32_t hemicube_max(const hemicube_pass *pass) { return pass->desc.max_hemicubes; }

/* ------------------------------------------------------------- record */

static void bind(hemicube_pass *p, const hemicube_draw *d)
{
    const gpu_buffer *counts = d->indirect ? d->indirect : d->frames;
    bool rad = p->desc.kind == HEMICUBE_RADIOSITY;
    VkImageView atlas = rad && d->atlas ? d->atlas->view : VK_NULL_HANDLE;
    VkBuffer triangles = rad ? d->mesh.triangles->buffer : VK_NULL_HANDLE;
    VkBuffer vertices = rad ? d->mesh.vertices->buffer : VK_NULL_HANDLE;
    VkBuffer indices = rad ? d->mesh.indices->buffer : VK_NULL_HANDLE;
    if (p->bound_frames == d->frames->buffer && p->bound_counts == counts->buffer &&
        p->bound_atlas == atlas && p->bound_triangles == triangles &&
        p->bound_vertices == vertices && p->bound_indices == indices)
        return;
    const uint32_t binding[6] = {HEMICUBE_BINDING_FRAMES,    HEMICUBE_BINDING_COUNTS,
                                 HEMICUBE_BINDING_TRIANGLES, HEMICUBE_BINDING_VERTICES,
                                 HEMICUBE_BINDING_INDICES,   HEMICUBE_BINDING_ATLAS};
    VkDescriptorBufferInfo bi[5] = {
        {d->frames->buffer, 0, VK_WHOLE_SIZE}, {counts->buffer, 0, VK_WHOLE_SIZE},
        {triangles, 0, VK_WHOLE_SIZE},         {vertices, 0, VK_WHOLE_SIZE},
        {indices, 0, VK_WHOLE_SIZE},
    };
    VkDescriptorImageInfo ii = {p->sampler, atlas, VK_IMAGE_LAYOUT_GENERAL};
    VkWriteDescriptorSet w[6];
    for (uint32_t i = 0; i < 6; i++)
        w[i] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = p->set,
            .dstBinding = binding[i],
            .descriptorCount = 1,
            .descriptorType = i == 5 ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                                     : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
            .pBufferInfo = i < 5 ? &bi[i] : NULL,
            .pImageInfo = i == 5 ? &ii : NULL,
        };
    vkUpdateDescriptorSets(p->ctx->device, rad ? 6 : 2, w, 0, NULL);
    p->bound_frames = d->frames->buffer;
    p->bound_counts = counts->buffer;
    p->bound_triangles = triangles;
    p->bound_vertices = vertices;
    p->bound_indices = indices;
    p->bound_atlas = atlas;
}

static void begin(hemicube_pass *p, VkCommandBuffer cmd, uint32_t framebuffer)
{
    VkClearValue clear[2] = {
        {.color = {.uint32 = {HEMICUBE_ID_NONE, 0, 0, 0}}},
        {.depthStencil = {.depth = 0.0f}}, /* reversed Z: 0 is infinitely far */
    };
    if (p->desc.kind == HEMICUBE_RADIOSITY)
        clear[0].color = (VkClearColorValue){.float32 = {0, 0, 0, 0}};
    VkRenderPassBeginInfo info = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = p->render_pass,
        .framebuffer = p->framebuffers[framebuffer],
        .renderArea = {.extent = {p->desc.res, p->desc.res}},
        .clearValueCount = 2,
        .pClearValues = clear,
    };
    vkCmdBeginRenderPass(cmd, &info, VK_SUBPASS_CONTENTS_INLINE);
}

/* The draw of one render pass instance: the cull pass's commands (one
 * multi-draw where the device has it), or the indirect command, or the
 * host's count (range by range where the mesh has them). */
static void draw(const hemicube_pass *p, VkCommandBuffer cmd, const hemicube_draw *d,
                 uint32_t instances)
{
    const uint32_t stride = sizeof(VkDrawIndexedIndirectCommand);
    if (d->commands && p->ctx->features.multi_draw_indirect &&
        d->command_count <= p->ctx->props.limits.maxDrawIndirectCount) {
        vkCmdDrawIndexedIndirect(cmd, d->commands->buffer, 0, d->command_count, stride);
    } else if (d->commands) {
        for (uint32_t k = 0; k < d->command_count; k++)
            vkCmdDrawIndexedIndirect(cmd, d->commands->buffer, (VkDeviceSize)k * stride, 1,
                                     stride);
    } else if (d->indirect && instances == 0) {
        vkCmdDrawIndexedIndirect(cmd, d->indirect->buffer, d->indirect_offset, 1, stride);
    } else if (d->mesh.ranges) {
        for (uint32_t k = 0; k < d->mesh.range_count; k++) {
            uint32_t first = d->mesh.ranges[k], end = d->mesh.ranges[k + 1];
            if (end > d->index_count || end == first)
                break;
            vkCmdDrawIndexed(cmd, end - first, instances ? instances : 1, first, 0, 0);
        }
    } else if (d->index_count) {
        vkCmdDrawIndexed(cmd, d->index_count, instances ? instances : 1, 0, 0, 0);
    }
}

void hemicube_record(hemicube_pass *p, VkCommandBuffer cmd, const hemicube_draw *d)
{
    bind(p, d);
    uint32_t n = d->indirect ? p->desc.max_hemicubes
                             : (d->count < p->desc.max_hemicubes ? d->count : p->desc.max_hemicubes);
    struct hemicube_push push = {
        .first = d->first,
        .count_word = d->indirect ? (uint32_t)(d->indirect_offset / 4) + 1 : HEMICUBE_NO_COUNT,
        .near = p->near,
        .hair = p->hair,
        .scale = d->scale > 0 ? d->scale : 1.0f,
        .depth_scale = (float)(1.0 / p->desc.diameter),
    };
    VkViewport viewport = {0, 0, (float)p->desc.res, (float)p->desc.res, 0, 1};
    VkRect2D scissor = {.extent = {p->desc.res, p->desc.res}};
    VkDeviceSize zero = 0;
    const VkShaderStageFlags stages = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
    if (p->path == HEMICUBE_PATH_MULTIVIEW) {
        for (uint32_t k = 0; k < n; k++) {
            begin(p, cmd, k);
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->layout, 0, 1,
                                    &p->set, 0, NULL);
            vkCmdSetViewport(cmd, 0, 1, &viewport);
            vkCmdSetScissor(cmd, 0, 1, &scissor);
            vkCmdBindVertexBuffers(cmd, 0, 1, &d->mesh.vertices->buffer, &zero);
            vkCmdBindIndexBuffer(cmd, d->mesh.indices->buffer, 0, VK_INDEX_TYPE_UINT32);
            push.hemicube = k;
            vkCmdPushConstants(cmd, p->layout, stages, 0, sizeof(push), &push);
            /* One instance: the count word in the push constants says
             * which hemicubes are live. */
            draw(p, cmd, d, 1);
            vkCmdEndRenderPass(cmd);
        }
    } else if (n) {
        begin(p, cmd, 0);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, p->layout, 0, 1, &p->set,
                                0, NULL);
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindVertexBuffers(cmd, 0, 1, &d->mesh.vertices->buffer, &zero);
        vkCmdBindIndexBuffer(cmd, d->mesh.indices->buffer, 0, VK_INDEX_TYPE_UINT32);
        vkCmdPushConstants(cmd, p->layout, stages, 0, sizeof(push), &push);
        draw(p, cmd, d, d->indirect ? 0 : n * HEMICUBE_FACES);
        vkCmdEndRenderPass(cmd);
    }
    bool resolve = p->desc.kind == HEMICUBE_RADIOSITY && p->desc.msaa > 1;
    uint32_t total = p->desc.max_hemicubes * HEMICUBE_FACES;
    if (!resolve || n == 0) {
        /* Layers no render pass instance touched (multiview with fewer
         * hemicubes than the image holds, or nothing drawn) join the rest
         * in SHADER_READ_ONLY_OPTIMAL, so the whole array can be bound;
         * their contents are undefined. */
        uint32_t done = resolve ? 0
                        : p->path == HEMICUBE_PATH_MULTIVIEW ? n * HEMICUBE_FACES
                        : n                                   ? total
                                                              : 0;
        if (done < total) {
            VkImageMemoryBarrier b = {
                .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
                .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT,
                .oldLayout = VK_IMAGE_LAYOUT_UNDEFINED,
                .newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                .image = p->target.image,
                .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, done, total - done},
            };
            vkCmdPipelineBarrier(cmd,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                                     VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT |
                                     VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                                     VK_PIPELINE_STAGE_TRANSFER_BIT,
                                 0, 0, NULL, 0, NULL, 1, &b);
        }
        return;
    }
    /* The previous contents are discarded; whoever read them (integrate)
     * has finished. */
    gpu_image_barrier(cmd, &p->target, VK_IMAGE_LAYOUT_UNDEFINED,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                          VK_PIPELINE_STAGE_TRANSFER_BIT,
                      0, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT);
    VkImageResolve region = {
        .srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, n * HEMICUBE_FACES},
        .dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, n * HEMICUBE_FACES},
        .extent = {p->desc.res, p->desc.res, 1},
    };
    vkCmdResolveImage(cmd, p->msaa.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, p->target.image,
                      VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    gpu_image_barrier(cmd, &p->target, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                      VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_TRANSFER_WRITE_BIT,
                      VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT |
                          VK_PIPELINE_STAGE_TRANSFER_BIT,
                      VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT);
}

void hemicube_record_ids(hemicube_pass *pass, VkCommandBuffer cmd, const hemicube_mesh *mesh,
                         uint32_t index_count,
                         const gpu_buffer *frames, const gpu_buffer *indirect,
                         VkDeviceSize indirect_offset, const gpu_buffer *commands,
                         uint32_t count)
{
    hemicube_draw d = {
        .mesh = *mesh,
        .index_count = index_count,
        .frames = frames,
        .indirect = indirect,
        .indirect_offset = indirect_offset,
        .commands = commands,
        .command_count = commands ? count : 0,
    };
    hemicube_record(pass, cmd, &d);
}

/* ---------------------------------------------------------- path check */

#define CHECK_RES 32
#define CHECK_CUBES 3
#define CHECK_QUADS 7

/* The check scene: the box [-1, 1]^3 with inward normals, one surface per
 * wall, and a tilted quad inside it. */
static void check_scene(vec3 quads[CHECK_QUADS][4])
{
    static const double q[CHECK_QUADS][4][3] = {
        {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}},       /* floor z = -1 */
        {{-1, -1, 1}, {-1, 1, 1}, {1, 1, 1}, {1, -1, 1}},           /* ceiling */
        {{-1, -1, -1}, {-1, 1, -1}, {-1, 1, 1}, {-1, -1, 1}},       /* x = -1 */
        {{1, -1, -1}, {1, -1, 1}, {1, 1, 1}, {1, 1, -1}},           /* x = 1 */
        {{-1, -1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, -1, -1}},       /* y = -1 */
        {{-1, 1, -1}, {1, 1, -1}, {1, 1, 1}, {-1, 1, 1}},           /* y = 1 */
        {{-0.5, -0.6, 0.1}, {0.4, -0.6, 0.3}, {0.4, 0.3, 0.3}, {-0.5, 0.3, 0.1}}, /* tilted */
    };
    for (int i = 0; i < CHECK_QUADS; i++)
        for (int k = 0; k < 4; k++)
            quads[i][k] = v3(q[i][k][0], q[i][k][1], q[i][k][2]);
}

typedef struct check_frame {
    vec3 origin, x, y, z;
} check_frame;

/* Off-centre frames, one tilted, each rotated about its normal. */
static void check_frames(check_frame f[CHECK_CUBES])
{
    const vec3 origin[CHECK_CUBES] = {v3(0.2, -0.3, -1), v3(-0.45, 0.35, -0.2), v3(1, 0.1, -0.25)};
    const vec3 normal[CHECK_CUBES] = {v3(0, 0, 1), v3_norm(v3(0.3, -0.5, 0.8)), v3(-1, 0, 0)};
    for (int h = 0; h < CHECK_CUBES; h++) {
        vec3 z = normal[h];
        vec3 a = fabs(z.x) < 0.9 ? v3(1, 0, 0) : v3(0, 1, 0);
        vec3 x0 = v3_norm(v3_sub(a, v3_scale(z, v3_dot(a, z))));
        mat3 r = m3_rotation(z, hemicube_rotation((uint32_t)h + 7u));
        f[h].origin = origin[h];
        f[h].z = z;
        f[h].x = m3_apply(&r, x0);
        f[h].y = v3_cross(z, f[h].x);
    }
}

/* Nearest quad hit by the ray o + t d with t > tmin (d need not be unit);
 * 0 for none, else quad + 1. Quads are convex and planar. */
static uint32_t cast(vec3 quads[CHECK_QUADS][4], vec3 o, vec3 d, double tmin)
{
    uint32_t best = 0;
    double best_t = INFINITY;
    for (uint32_t i = 0; i < CHECK_QUADS; i++) {
        const vec3 *q = quads[i];
        vec3 n = v3_cross(v3_sub(q[1], q[0]), v3_sub(q[3], q[0]));
        double dn = v3_dot(d, n);
        if (dn == 0)
            continue;
        double t = v3_dot(v3_sub(q[0], o), n) / dn;
        if (!(t > tmin) || t >= best_t)
            continue;
        vec3 x = v3_mad(o, d, t);
        bool inside = true;
        for (int k = 0; k < 4 && inside; k++)
            inside = v3_dot(v3_cross(v3_sub(q[(k + 1) % 4], q[k]), v3_sub(x, q[k])), n) >= 0;
        if (inside) {
            best = i + 1;
            best_t = t;
        }
    }
    return best;
}

xrad_status hemicube_check_path(struct xrad_context *ctx, hemicube_path path,
                                hemicube_check_result *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    vec3 quads[CHECK_QUADS][4];
    check_frame frames[CHECK_CUBES];
    check_scene(quads);
    check_frames(frames);
    const double diameter = 2.0 * sqrt(3.0);
    hemicube_desc desc = {
        .kind = HEMICUBE_IDS,
        .res = CHECK_RES,
        .max_hemicubes = CHECK_CUBES,
        .msaa = 1,
        .path = path,
        .diameter = diameter,
    };
    /* Quads as the scene's are drawn: two triangles over four vertices,
     * each naming its provoking vertex first (0 1 2, then 2 3 0). The two
     * corners that provoke nothing carry a surface no pixel may show. */
    struct gpu_hemicube_vertex verts[CHECK_QUADS * 4];
    uint32_t idx[CHECK_QUADS * 6];
    static const uint32_t order[6] = {0, 1, 2, 2, 3, 0};
    for (uint32_t i = 0; i < CHECK_QUADS; i++) {
        for (uint32_t k = 0; k < 4; k++)
            verts[i * 4 + k] = (struct gpu_hemicube_vertex){
                .x = (float)quads[i][k].x, .y = (float)quads[i][k].y, .z = (float)quads[i][k].z,
                .surface = k % 2 ? CHECK_QUADS + 1 : i,
                .triangle = 2 * i + k / 2,
            };
        for (int k = 0; k < 6; k++)
            idx[i * 6 + k] = i * 4 + order[k];
    }
    struct gpu_shooter sh[CHECK_CUBES];
    memset(sh, 0, sizeof(sh));
    for (int h = 0; h < CHECK_CUBES; h++) {
        const check_frame *f = &frames[h];
        sh[h].pos_area = (vec4){(float)f->origin.x, (float)f->origin.y, (float)f->origin.z, 0};
        sh[h].normal = (vec4){(float)f->z.x, (float)f->z.y, (float)f->z.z, 0};
        sh[h].tangent = (vec4){(float)f->x.x, (float)f->x.y, (float)f->x.z, 0};
        sh[h].hemicube = (uint32_t)h;
    }
    /* Two words a texel (HEMICUBE_ID_FORMAT): the ID, then the distance. */
    size_t texels = (size_t)CHECK_CUBES * HEMICUBE_FACES * CHECK_RES * CHECK_RES;
    size_t image_bytes = texels * 4;
    uint32_t *ids = malloc(2 * image_bytes);
    if (!ids)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube check: out of host memory");
    hemicube_pass *p = NULL;
    gpu_buffer vb = {0}, ib = {0}, fb = {0};
    gpu_cmd c = {0};
    xrad_status s;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    if ((s = create_for_path(ctx, &desc, path, &p, err)) ||
        (s = gpu_buffer_create(ctx, sizeof(verts), VK_BUFFER_USAGE_VERTEX_BUFFER_BIT,
                               GPU_MEM_UPLOAD, GPU_MEM_GEOMETRY, &vb, err)) ||
        (s = gpu_buffer_create(ctx, sizeof(idx), VK_BUFFER_USAGE_INDEX_BUFFER_BIT,
                               GPU_MEM_UPLOAD, GPU_MEM_GEOMETRY, &ib, err)) ||
        (s = gpu_buffer_create(ctx, sizeof(sh), storage, GPU_MEM_UPLOAD, GPU_MEM_GEOMETRY, &fb,
                               err)) ||
        (s = gpu_upload_buffer(ctx, &vb, 0, verts, sizeof(verts), err)) ||
        (s = gpu_upload_buffer(ctx, &ib, 0, idx, sizeof(idx), err)) ||
        (s = gpu_upload_buffer(ctx, &fb, 0, sh, sizeof(sh), err)) ||
        (s = gpu_cmd_begin(ctx, &c, err)))
        goto done;
    hemicube_draw d = {
        .mesh = {&vb, &ib, NULL, NULL, 0},
        .index_count = CHECK_QUADS * 6,
        .frames = &fb,
        .count = CHECK_CUBES,
    };
    hemicube_record(p, c.cmd, &d);
    if ((s = gpu_cmd_run(ctx, &c, err)) ||
        (s = gpu_readback_image(ctx, &p->target, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, ids,
                                2 * image_bytes, err)))
        goto done;
    for (size_t i = 0; i < texels; i++)
        ids[i] = ids[2 * i];

    /* The CPU picture: a ray through each pixel centre from the same
     * offset origin, hits nearer than the near plane (along the face axis,
     * which is the ray parameter for these unnormalised directions)
     * ignored. */
    uint32_t *cpu = malloc(image_bytes);
    if (!cpu) {
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "hemicube check: out of host memory");
        goto done;
    }
    const uint32_t R = CHECK_RES;
    for (int h = 0; h < CHECK_CUBES; h++) {
        const check_frame *f = &frames[h];
        vec3 o = v3_mad(f->origin, f->z, p->hair);
        for (int face = 0; face < HEMICUBE_FACES; face++) {
            vec3 rt, up, fw;
            hemicube_face_axes(face, &rt, &up, &fw);
            for (uint32_t row = 0; row < R; row++) {
                for (uint32_t col = 0; col < R; col++) {
                    double a = -1 + (col + 0.5) * 2.0 / R, b = -1 + (row + 0.5) * 2.0 / R;
                    vec3 l = v3_add(fw, v3_add(v3_scale(rt, a), v3_scale(up, b)));
                    vec3 w = v3_add(v3_scale(f->x, l.x),
                                    v3_add(v3_scale(f->y, l.y), v3_scale(f->z, l.z)));
                    cpu[((size_t)(h * HEMICUBE_FACES + face) * R + row) * R + col] =
                        cast(quads, o, w, p->near);
                }
            }
        }
    }
    for (uint32_t layer = 0; layer < CHECK_CUBES * HEMICUBE_FACES; layer++) {
        for (uint32_t row = 0; row < R; row++) {
            for (uint32_t col = 0; col < R; col++) {
                size_t i = ((size_t)layer * R + row) * R + col;
                out->pixels++;
                if (ids[i] == cpu[i])
                    continue;
                bool edge = false;
                for (int dy = -1; dy <= 1 && !edge; dy++)
                    for (int dx = -1; dx <= 1 && !edge; dx++) {
                        int y = (int)row + dy, x = (int)col + dx;
                        if (x >= 0 && y >= 0 && x < (int)R && y < (int)R)
                            edge = cpu[((size_t)layer * R + y) * R + x] == ids[i];
                    }
                if (edge)
                    out->edge++;
                else
                    out->wrong++;
            }
        }
    }
    free(cpu);
    out->ok = out->wrong == 0 && out->edge * 200 <= out->pixels;

done:
    gpu_cmd_destroy(ctx, &c);
    gpu_buffer_destroy(ctx, &fb);
    gpu_buffer_destroy(ctx, &ib);
    gpu_buffer_destroy(ctx, &vb);
    hemicube_destroy(ctx, &p);
    free(ids);
    if (s)
        xrad_error_prefix(err, "hemicube %s path check", hemicube_path_label(path));
    return s;
}
