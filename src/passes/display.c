#include "passes/display.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "display.frag.h"
#include "display.vert.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "scene/scene.h"
#include "../../spirv/shared.h" /* spirv/ is not on the include path */

#define PI 3.14159265358979323846

struct display_pass {
    VkRenderPass render_pass;
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkSampler nearest, linear;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    bool linear_supported;
};

/* ------------------------------------------------------------ mesh */

/* The drawn point (m, object space) of surface parameters (s, t).
 *
 * A quad whose file vertices were not coplanar was moved onto its best-fit
 * plane on load (scene_quad_setup, up to 1% of its diagonal), and its edges
 * moved with it: drawn so, it no longer meets the walls that share its file
 * edges, and the background shows through the crack (the Cornell box's red
 * wall left 77 pixels along the ceiling, the back wall and the floor at
 * 512 x 512). So the bilinear patch through the file's vertices is drawn,
 * at the same (s, t) as the planar quad: its edges are the file's straight
 * edges, which the neighbours' drawn edges follow wherever the file shares
 * them, and every element still shows at its own sample's (s, t), within
 * planarise_offset of where the solve put it. The solve keeps the planar
 * quad, which its form factors and hemicubes need; so a neighbour's edge
 * samples that the planar quad puts outside the room are solved dark, and
 * show so (the Cornell back wall's edge near the ceiling). */
static vec3 drawn_point(const surface *sf, double s, double t)
{
    const double *d = sf->planarise_dist;
    double lift = (1 - s) * (1 - t) * d[0] + s * (1 - t) * d[1] + s * t * d[2] + (1 - s) * t * d[3];
    return v3_mad(surface_point(sf, s, t), sf->normal, lift);
}

/* Drawn vertices along a side of n samples: one a sample, and a lone
 * sample (a tiny triangle's one element, scene.h) drawn from both ends of
 * the side. */
static uint32_t drawn_along(uint32_t n)
{
    return n < 2 ? 2 : n;
}

xrad_status display_mesh_build(const xrad_scene *scene, double time, vec3 origin,
                               display_mesh *mesh, xrad_error *err)
{
    memset(mesh, 0, sizeof(*mesh));
    uint64_t nv = 0, ni = 0;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        uint64_t du = drawn_along(sf->nu), dv = drawn_along(sf->nv);
        nv += du * dv;
        ni += 6 * (du - 1) * (dv - 1);
    }
    if (nv > UINT32_MAX || ni > UINT32_MAX)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %llu element samples are too many to draw",
                         scene->path, (unsigned long long)nv);
    if (nv == 0)
        return XRAD_OK;
    mesh->vertices = malloc(nv * sizeof(*mesh->vertices));
    mesh->indices = malloc((ni ? ni : 1) * sizeof(*mesh->indices));
    if (!mesh->vertices || !mesh->indices) {
        display_mesh_free(mesh);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory for a %llu-vertex mesh",
                         scene->path, (unsigned long long)nv);
    }
    /* A scene's atlas is at least one texel wide wherever it has surfaces. */
    double inv_w = 1.0 / scene->atlas_width, inv_h = 1.0 / scene->atlas_height;
    uint32_t v = 0, k = 0;
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        xform pose = scene_object_pose(scene, sf->object, time);
        const element *el = &scene->elements[sf->first_element];
        uint32_t n = sf->nu * sf->nv;
        uint32_t tile[4] = {el[0].texel_x, el[0].texel_y, el[0].texel_x, el[0].texel_y};
        for (uint32_t e = 1; e < n; e++) {
            tile[0] = el[e].texel_x < tile[0] ? el[e].texel_x : tile[0];
            tile[1] = el[e].texel_y < tile[1] ? el[e].texel_y : tile[1];
            tile[2] = el[e].texel_x > tile[2] ? el[e].texel_x : tile[2];
            tile[3] = el[e].texel_y > tile[3] ? el[e].texel_y : tile[3];
        }
        uint32_t base = v, du = drawn_along(sf->nu), dw = drawn_along(sf->nv);
        for (uint32_t j = 0; j < dw; j++) {
            for (uint32_t i = 0; i < du; i++) {
                /* The element sample parameters of scene.h; the displayed
                 * vertex sits on the exact sample, not on the inward-moved
                 * corner point used for radiosity. A lone sample's value
                 * is drawn over its whole side. */
                vec3 p = drawn_point(sf, (double)i / (du - 1), (double)j / (dw - 1));
                vec3 w = v3_sub(xf_point(&pose, p), origin);
                const element *e = &el[(j < sf->nv ? j : 0) * sf->nu + (i < sf->nu ? i : 0)];
                display_vertex *dv = &mesh->vertices[v++];
                dv->pos[0] = (float)w.x;
                dv->pos[1] = (float)w.y;
                dv->pos[2] = (float)w.z;
                dv->uv[0] = (float)((e->texel_x + 0.5) * inv_w);
                dv->uv[1] = (float)((e->texel_y + 0.5) * inv_h);
                memcpy(dv->tile, tile, sizeof(tile));
            }
        }
        for (uint32_t j = 0; j + 1 < dw; j++) {
            for (uint32_t i = 0; i + 1 < du; i++) {
                uint32_t a = base + j * du + i, b = a + 1, c = a + du + 1, d = a + du;
                uint32_t *q = &mesh->indices[k];
                q[0] = a, q[1] = b, q[2] = c, q[3] = a, q[4] = c, q[5] = d;
                k += 6;
            }
        }
    }
    mesh->vertex_count = v;
    mesh->index_count = k;
    return XRAD_OK;
}

void display_mesh_free(display_mesh *mesh)
{
    if (!mesh)
        return;
    free(mesh->vertices);
    free(mesh->indices);
    memset(mesh, 0, sizeof(*mesh));
}

/* ---------------------------------------------------------- camera */

xrad_status display_camera_make(const xrad_scene *scene, uint32_t width, uint32_t height,
                                double time, display_camera *cam, xrad_error *err)
{
    return display_camera_from(scene, &scene->cam, width, height, time, cam, err);
}

xrad_status display_camera_from(const xrad_scene *scene, const camera *c, uint32_t width,
                                uint32_t height, double time, display_camera *cam,
                                xrad_error *err)
{
    memset(cam, 0, sizeof(*cam));
    vec3 fwd = v3_sub(c->look_at, c->position);
    double dist = v3_len(fwd);
    if (!(dist > 0) || !v3_finite(fwd))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: camera: look_at equals position",
                         scene->path);
    fwd = v3_scale(fwd, 1.0 / dist);
    vec3 right = v3_cross(fwd, c->up);
    double rl = v3_len(right);
    if (!(rl > 1e-9 * v3_len(c->up)) || !(rl > 0))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: camera: up is zero or along the view",
                         scene->path);
    right = v3_scale(right, 1.0 / rl);
    vec3 up = v3_cross(right, fwd);
    if (!(c->fov_y > 0 && c->fov_y < PI))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: camera: vertical field of view %g degrees is outside (0, 180)",
                         scene->path, c->fov_y * 180.0 / PI);

    /* Near and far from the world bounding box at this time, of the drawn
     * corners (drawn_point). */
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        const surface *sf = &scene->surfaces[s];
        xform pose = scene_object_pose(scene, sf->object, time);
        vec3 corners[4];
        for (int k = 0; k < 4; k++)
            corners[k] = xf_point(&pose, drawn_point(sf, k == 1 || k == 2, k >= 2));
        for (int k = 0; k < 4; k++) {
            lo = v3(fmin(lo.x, corners[k].x), fmin(lo.y, corners[k].y), fmin(lo.z, corners[k].z));
            hi = v3(fmax(hi.x, corners[k].x), fmax(hi.y, corners[k].y), fmax(hi.z, corners[k].z));
        }
    }
    double dmax = 0, dmin = 0;
    if (scene->surface_count) {
        for (int k = 0; k < 8; k++) {
            vec3 corner = v3(k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z);
            dmax = fmax(dmax, v3_len(v3_sub(corner, c->position)));
        }
        vec3 nearest = v3(fmin(fmax(c->position.x, lo.x), hi.x),
                          fmin(fmax(c->position.y, lo.y), hi.y),
                          fmin(fmax(c->position.z, lo.z), hi.z));
        dmin = v3_len(v3_sub(nearest, c->position));
    }
    if (!(dmax > 0))
        dmax = 1; /* nothing to draw; any valid planes do */
    double far = dmax * 1.01;
    double near = fmax(0.5 * dmin, 1e-6 * far);

    double sy = 1.0 / tan(0.5 * c->fov_y), sx = sy * height / width;
    double a = -near / (far - near), b = near * far / (far - near);
    /* Rows of the world-relative -> clip matrix: x right, y down (Vulkan
     * framebuffer row 0 at the top), z reversed, w the view depth. */
    double rows[4][4] = {
        {sx * right.x, sx * right.y, sx * right.z, 0},
        {-sy * up.x, -sy * up.y, -sy * up.z, 0},
        {a * fwd.x, a * fwd.y, a * fwd.z, b},
        {fwd.x, fwd.y, fwd.z, 0},
    };
    for (int r = 0; r < 4; r++)
        for (int col = 0; col < 4; col++)
            cam->clip_from_view[col * 4 + r] = (float)rows[r][col];
    cam->origin = c->position;
    cam->near = near;
    cam->far = far;
    return XRAD_OK;
}

/* ------------------------------------------------------------ pass */

static xrad_status create_render_pass(struct xrad_context *ctx, VkRenderPass *out,
                                      xrad_error *err)
{
    /* The colour image is copied out after the pass. */
    gpu_render_pass_desc desc = {
        .color_format = DISPLAY_COLOR_FORMAT,
        .depth_format = DISPLAY_DEPTH_FORMAT,
        .color_final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
    };
    return gpu_render_pass_create(ctx, &desc, out, err);
}


static xrad_status check_formats(struct xrad_context *ctx, bool *linear, xrad_error *err)
{
    VkFormatProperties p;
    vkGetPhysicalDeviceFormatProperties(ctx->phys, DISPLAY_COLOR_FORMAT, &p);
    if (!(p.optimalTilingFeatures & VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT))
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' cannot render to RGBA32F images (display pass)",
                         ctx->props.deviceName);
    vkGetPhysicalDeviceFormatProperties(ctx->phys, DISPLAY_ATLAS_FORMAT, &p);
    if (!(p.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT))
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' cannot sample RGBA32F images (display pass)",
                         ctx->props.deviceName);
    *linear = p.optimalTilingFeatures & VK_FORMAT_FEATURE_SAMPLED_IMAGE_FILTER_LINEAR_BIT;
    vkGetPhysicalDeviceFormatProperties(ctx->phys, DISPLAY_DEPTH_FORMAT, &p);
    if (!(p.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT))
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "device '%s' has no D32_SFLOAT depth attachments (display pass)",
                         ctx->props.deviceName);
    return XRAD_OK;
}

xrad_status display_create(struct xrad_context *ctx, display_pass **out, xrad_error *err)
{
    *out = NULL;
    display_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (display pass)");
    xrad_status s;
    if ((s = check_formats(ctx, &p->linear_supported, err)) ||
        (s = create_render_pass(ctx, &p->render_pass, err)))
        goto fail;
    VkDescriptorSetLayoutBinding binding = {
        .binding = DISPLAY_BINDING_ATLAS,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .descriptorCount = 1,
        .stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT,
    };
    VkDescriptorPoolSize size = {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 1};
    if ((s = gpu_descriptor_layout_create(ctx, &binding, 1, &p->set_layout, err)) ||
        (s = gpu_pipeline_layout_create(ctx, &p->set_layout, 1, sizeof(struct display_push),
                                        VK_SHADER_STAGE_VERTEX_BIT |
                                            VK_SHADER_STAGE_FRAGMENT_BIT,
                                        &p->layout, err)) ||
        (s = gpu_descriptor_pool_create(ctx, &size, 1, 1, &p->pool, err)) ||
        (s = gpu_descriptor_set_allocate(ctx, p->pool, p->set_layout, &p->set, err)) ||
        (s = gpu_sampler_create(ctx, VK_FILTER_NEAREST, &p->nearest, err)) ||
        (p->linear_supported &&
         (s = gpu_sampler_create(ctx, VK_FILTER_LINEAR, &p->linear, err))))
        goto fail;
    VkVertexInputBindingDescription vb = {
        .binding = 0,
        .stride = sizeof(display_vertex),
        .inputRate = VK_VERTEX_INPUT_RATE_VERTEX,
    };
    VkVertexInputAttributeDescription attrs[3] = {
        {0, 0, VK_FORMAT_R32G32B32_SFLOAT, offsetof(display_vertex, pos)},
        {1, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(display_vertex, uv)},
        {2, 0, VK_FORMAT_R32G32B32A32_UINT, offsetof(display_vertex, tile)},
    };
    gpu_graphics_desc gd = {
        .vert = display_vert_spv,
        .vert_bytes = sizeof(display_vert_spv),
        .frag = display_frag_spv,
        .frag_bytes = sizeof(display_frag_spv),
        .bindings = &vb,
        .binding_count = 1,
        .attributes = attrs,
        .attribute_count = 3,
        .cull = VK_CULL_MODE_NONE,
        .front_face = VK_FRONT_FACE_COUNTER_CLOCKWISE,
        .depth_test = true,
        .depth_write = true,
        .depth_compare = VK_COMPARE_OP_GREATER, /* reversed Z */
        .color_attachments = 1,
        .layout = p->layout,
        .render_pass = p->render_pass,
    };
    if ((s = gpu_graphics_pipeline_create(ctx, &gd, &p->pipeline, err)))
        goto fail;
    *out = p;
    return XRAD_OK;

fail:
    display_destroy(ctx, &p);
    return s;
}

void display_destroy(struct xrad_context *ctx, display_pass **pass)
{
    if (!pass || !*pass)
        return;
    display_pass *p = *pass;
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroySampler(ctx->device, p->linear, NULL);
    vkDestroySampler(ctx->device, p->nearest, NULL);
    vkDestroyDescriptorPool(ctx->device, p->pool, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    vkDestroyDescriptorSetLayout(ctx->device, p->set_layout, NULL);
    vkDestroyRenderPass(ctx->device, p->render_pass, NULL);
    free(p);
    *pass = NULL;
}

bool display_linear_supported(const display_pass *pass)
{
    return pass->linear_supported;
}

xrad_status display_target_create(struct xrad_context *ctx, const display_pass *pass,
                                  uint32_t width, uint32_t height, display_target *out,
                                  xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    const VkPhysicalDeviceLimits *lim = &ctx->props.limits;
    if (width == 0 || height == 0 || width > lim->maxFramebufferWidth ||
        height > lim->maxFramebufferHeight)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "image size %u x %u is outside 1 .. %u x %u (device limit)", width,
                         height, lim->maxFramebufferWidth, lim->maxFramebufferHeight);
    gpu_image_desc color = {
        .format = DISPLAY_COLOR_FORMAT,
        .width = width,
        .height = height,
        /* Sampled: xrad view's present pass reads it. */
        .usage = VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                 VK_IMAGE_USAGE_SAMPLED_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    gpu_image_desc depth = {
        .format = DISPLAY_DEPTH_FORMAT,
        .width = width,
        .height = height,
        .usage = VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    xrad_status s;
    if ((s = gpu_image_create(ctx, &color, &out->color, err)) ||
        (s = gpu_image_create(ctx, &depth, &out->depth, err)))
        goto fail;
    VkImageView views[2] = {out->color.view, out->depth.view};
    VkFramebufferCreateInfo fb = {
        .sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO,
        .renderPass = pass->render_pass,
        .attachmentCount = 2,
        .pAttachments = views,
        .width = width,
        .height = height,
        .layers = 1,
    };
    if ((s = VK_CHECK(ctx, err, vkCreateFramebuffer(ctx->device, &fb, NULL, &out->framebuffer))))
        goto fail;
    return XRAD_OK;

fail:
    display_target_destroy(ctx, out);
    return s;
}

void display_target_destroy(struct xrad_context *ctx, display_target *t)
{
    if (!t)
        return;
    vkDestroyFramebuffer(ctx->device, t->framebuffer, NULL);
    gpu_image_destroy(ctx, &t->depth);
    gpu_image_destroy(ctx, &t->color);
    memset(t, 0, sizeof(*t));
}

xrad_status display_record(struct xrad_context *ctx, display_pass *pass, VkCommandBuffer cmd,
                           const display_target *target, const display_draw *draw,
                           xrad_error *err)
{
    if (draw->filter == DISPLAY_FILTER_LINEAR && !pass->linear_supported)
        return xrad_fail(err, XRAD_ERROR_SYSTEM,
                         "display: device '%s' cannot filter RGBA32F linearly; use the shader "
                         "filter",
                         ctx->props.deviceName);
    if (draw->atlas->format != DISPLAY_ATLAS_FORMAT)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "display: the atlas must be RGBA32F");
    VkDescriptorImageInfo image = {
        .sampler = draw->filter == DISPLAY_FILTER_LINEAR ? pass->linear : pass->nearest,
        .imageView = draw->atlas->view,
        .imageLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
    };
    VkWriteDescriptorSet write = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = pass->set,
        .dstBinding = DISPLAY_BINDING_ATLAS,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
        .pImageInfo = &image,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &write, 0, NULL);

    uint32_t w = target->color.width, h = target->color.height;
    VkClearValue clear[2] = {
        {.color = {.float32 = {0, 0, 0, 0}}},
        {.depthStencil = {.depth = 0.0f}}, /* reversed Z: 0 is infinitely far */
    };
    VkRenderPassBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO,
        .renderPass = pass->render_pass,
        .framebuffer = target->framebuffer,
        .renderArea = {.extent = {w, h}},
        .clearValueCount = 2,
        .pClearValues = clear,
    };
    vkCmdBeginRenderPass(cmd, &begin, VK_SUBPASS_CONTENTS_INLINE);
    if (draw->index_count) {
        struct display_push push = {
            .atlas_size = {(float)draw->atlas->width, (float)draw->atlas->height,
                           1.0f / draw->atlas->width, 1.0f / draw->atlas->height},
            .mode = draw->filter == DISPLAY_FILTER_NEAREST  ? DISPLAY_MODE_NEAREST
                    : draw->filter == DISPLAY_FILTER_LINEAR ? DISPLAY_MODE_LINEAR
                                                            : DISPLAY_MODE_LINEAR_SHADER,
        };
        memcpy(push.clip_from_view.m, draw->camera->clip_from_view, sizeof(push.clip_from_view));
        VkViewport viewport = {0, 0, (float)w, (float)h, 0, 1};
        VkRect2D scissor = {.extent = {w, h}};
        VkDeviceSize offset = 0;
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass->pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass->layout, 0, 1,
                                &pass->set, 0, NULL);
        vkCmdPushConstants(cmd, pass->layout,
                           VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           sizeof(push), &push);
        vkCmdSetViewport(cmd, 0, 1, &viewport);
        vkCmdSetScissor(cmd, 0, 1, &scissor);
        vkCmdBindVertexBuffers(cmd, 0, 1, &draw->vertices->buffer, &offset);
        vkCmdBindIndexBuffer(cmd, draw->indices->buffer, 0, VK_INDEX_TYPE_UINT32);
        vkCmdDrawIndexed(cmd, draw->index_count, 1, 0, 0, 0);
    }
    vkCmdEndRenderPass(cmd);
    return XRAD_OK;
}
