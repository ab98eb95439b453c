#include "passes/overlay.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "overlay.frag.h"
#include "overlay.vert.h"
#include "shared.h"

/* The header defines its functions static (not every one is used here)
 * and writes its initialisers in its own style. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wmissing-braces"
#include <stb_easy_font.h>
#pragma GCC diagnostic pop

struct overlay_pass {
    VkPipelineLayout layout;
    VkPipeline pipeline;
};

/* stb_easy_font indexes its tables by character - 32 without a check:
 * anything outside printable ASCII draws as '?'. */
static char printable(char c)
{
    return c == '\n' || (c >= 32 && c < 127) ? c : '?';
}

/* Quads character c can produce: its segments (zero-length ones draw
 * nothing). */
static uint32_t segments(char c)
{
    int i = printable(c) - 32;
    if (i < 0)
        return 0; /* '\n' */
    const struct stb_easy_font_info_struct *ci = stb_easy_font_charinfo;
    return (uint32_t)(ci[i + 1].h_seg - ci[i].h_seg) + (uint32_t)(ci[i + 1].v_seg - ci[i].v_seg);
}

uint32_t overlay_vertex_bound(const char *text)
{
    uint64_t quads = 1; /* the box */
    for (const char *c = text; c && *c; c++)
        quads += segments(*c);
    return quads > UINT32_MAX / 6 ? UINT32_MAX : (uint32_t)(6 * quads);
}

/* Quad a b c d (stb's order: top left, top right, bottom right, bottom
 * left) as two triangles that cover it once. */
static void quad_triangles(const overlay_vertex q[4], overlay_vertex *out)
{
    static const int order[6] = {0, 1, 2, 0, 2, 3};
    for (int k = 0; k < 6; k++)
        out[k] = q[order[k]];
}

xrad_status overlay_build(const char *text, overlay_vertex *out, uint32_t max, uint32_t *count,
                          xrad_error *err)
{
    *count = 0;
    size_t len = text ? strlen(text) : 0;
    if (!len)
        return XRAD_OK;
    char *clean = malloc(len + 1);
    uint32_t quads_max = overlay_vertex_bound(text) / 6 - 1;
    overlay_vertex *quads = malloc(((size_t)quads_max + 1) * 4 * sizeof(overlay_vertex));
    if (!clean || !quads) {
        free(clean);
        free(quads);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (overlay text)");
    }
    for (size_t i = 0; i < len; i++)
        clean[i] = printable(text[i]);
    clean[len] = 0;
    static unsigned char text_rgba[4] = OVERLAY_TEXT_RGBA;
    int n = stb_easy_font_print(OVERLAY_PAD, OVERLAY_PAD, clean, text_rgba, quads,
                                (int)(((size_t)quads_max + 1) * 4 * sizeof(overlay_vertex)));
    float w = (float)stb_easy_font_width(clean) + 2 * OVERLAY_PAD;
    float h = (float)stb_easy_font_height(clean) + 2 * OVERLAY_PAD;
    free(clean);
    uint32_t need = 6 * (uint32_t)(n + 1);
    if (need > max) {
        free(quads);
        return xrad_fail(err, XRAD_ERROR_INPUT, "overlay: %u vertices do not fit in %u", need,
                         max);
    }
    const overlay_vertex box[4] = {
        {0, 0, 0, OVERLAY_BOX_RGBA},
        {w, 0, 0, OVERLAY_BOX_RGBA},
        {w, h, 0, OVERLAY_BOX_RGBA},
        {0, h, 0, OVERLAY_BOX_RGBA},
    };
    quad_triangles(box, out);
    for (int q = 0; q < n; q++)
        quad_triangles(&quads[4 * q], out + 6 * (q + 1));
    free(quads);
    *count = need;
    return XRAD_OK;
}

xrad_status overlay_create(struct xrad_context *ctx, VkRenderPass render_pass,
                           overlay_pass **out, xrad_error *err)
{
    *out = NULL;
    overlay_pass *p = calloc(1, sizeof(*p));
    if (!p)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory (overlay pass)");
    const VkVertexInputBindingDescription binding = {0, sizeof(overlay_vertex),
                                                     VK_VERTEX_INPUT_RATE_VERTEX};
    const VkVertexInputAttributeDescription attributes[2] = {
        {0, 0, VK_FORMAT_R32G32_SFLOAT, offsetof(overlay_vertex, x)},
        {1, 0, VK_FORMAT_R8G8B8A8_UNORM, offsetof(overlay_vertex, rgba)},
    };
    gpu_graphics_desc gd = {
        .vert = overlay_vert_spv,
        .vert_bytes = sizeof(overlay_vert_spv),
        .frag = overlay_frag_spv,
        .frag_bytes = sizeof(overlay_frag_spv),
        .bindings = &binding,
        .binding_count = 1,
        .attributes = attributes,
        .attribute_count = 2,
        .cull = VK_CULL_MODE_NONE,
        .front_face = VK_FRONT_FACE_CLOCKWISE,
        .color_attachments = 1,
        .blend = true,
        .render_pass = render_pass,
    };
    xrad_status s;
    if ((s = gpu_pipeline_layout_create(ctx, NULL, 0, sizeof(struct overlay_push),
                                        VK_SHADER_STAGE_VERTEX_BIT, &p->layout, err)))
        goto fail;
    gd.layout = p->layout;
    if ((s = gpu_graphics_pipeline_create(ctx, &gd, &p->pipeline, err)))
        goto fail;
    *out = p;
    return XRAD_OK;

fail:
    overlay_destroy(ctx, &p);
    xrad_error_prefix(err, "overlay pass");
    return s;
}

void overlay_destroy(struct xrad_context *ctx, overlay_pass **pass)
{
    if (!pass || !*pass)
        return;
    overlay_pass *p = *pass;
    vkDestroyPipeline(ctx->device, p->pipeline, NULL);
    vkDestroyPipelineLayout(ctx->device, p->layout, NULL);
    free(p);
    *pass = NULL;
}

void overlay_record(overlay_pass *pass, VkCommandBuffer cmd, const overlay_draw *draw)
{
    if (!draw->vertex_count)
        return;
    float zoom = (float)(draw->zoom ? draw->zoom : 1);
    float w = (float)draw->extent.width, h = (float)draw->extent.height;
    struct overlay_push push = {
        .scale_x = 2 * zoom / w,
        .scale_y = 2 * zoom / h,
        .offset_x = -1 + 2 * (float)draw->x / w,
        .offset_y = -1 + 2 * (float)draw->y / h,
    };
    VkViewport viewport = {0, 0, w, h, 0, 1};
    VkRect2D scissor = {.extent = draw->extent};
    VkDeviceSize offset = 0;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pass->pipeline);
    vkCmdPushConstants(cmd, pass->layout, VK_SHADER_STAGE_VERTEX_BIT, 0, sizeof(push), &push);
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindVertexBuffers(cmd, 0, 1, &draw->vertices->buffer, &offset);
    vkCmdDraw(cmd, draw->vertex_count, 1, 0, 0);
}
