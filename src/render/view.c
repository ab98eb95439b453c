#include "render/view.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "gpu/cmd.h"
#include "gpu/context.h"
#include "scene/scene.h"

#define DEFAULT_SIZE 512

/* Image size: the description's, else the camera's; one side given keeps
 * the camera's aspect. */
static void image_size(const xrad_scene *scene, const xrad_view_desc *desc, uint32_t *w,
                       uint32_t *h)
{
    uint32_t cw = scene->cam.width, ch = scene->cam.height;
    if (!cw || !ch)
        cw = ch = DEFAULT_SIZE;
    if (desc->width && desc->height) {
        *w = desc->width;
        *h = desc->height;
    } else if (desc->width) {
        *w = desc->width;
        *h = (uint32_t)fmax(1.0, round((double)desc->width * ch / cw));
    } else if (desc->height) {
        *h = desc->height;
        *w = (uint32_t)fmax(1.0, round((double)desc->height * cw / ch));
    } else {
        *w = cw;
        *h = ch;
    }
}

xrad_status render_view(struct xrad_context *ctx, const xrad_scene *scene,
                        const xrad_atlas *atlas, const xrad_view_desc *desc,
                        const render_view_options *opt, float **rgba, uint32_t *width,
                        uint32_t *height, xrad_error *err)
{
    *rgba = NULL;
    xrad_view_desc zero = {0};
    if (!desc)
        desc = &zero;
    if (!ctx || !scene || !atlas)
        return xrad_fail(err, XRAD_ERROR_INPUT, "render view: no %s",
                         !ctx ? "context" : !scene ? "scene" : "atlas");
    if (atlas->width != scene->atlas_width || atlas->height != scene->atlas_height ||
        (!atlas->rgba && atlas->width && atlas->height))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: the atlas is %u x %u texels, the scene's is %u x %u", scene->path,
                         atlas->width, atlas->height, scene->atlas_width, scene->atlas_height);
    if (!isfinite(desc->time))
        return xrad_fail(err, XRAD_ERROR_INPUT, "render view: time is not finite");
    uint32_t w, h;
    image_size(scene, desc, &w, &h);
    display_camera cam;
    display_mesh mesh;
    xrad_status s = display_camera_make(scene, w, h, desc->time, &cam, err);
    if (s || (s = display_mesh_build(scene, desc->time, cam.origin, &mesh, err)))
        return s;

    /* The atlas image needs at least one texel even for an empty scene. */
    uint32_t aw = atlas->width ? atlas->width : 1, ah = atlas->height ? atlas->height : 1;
    size_t atlas_bytes = (size_t)aw * ah * 4 * sizeof(float);
    size_t image_bytes = (size_t)w * h * 4 * sizeof(float);
    size_t vertex_bytes = (size_t)mesh.vertex_count * sizeof(display_vertex);
    size_t index_bytes = (size_t)mesh.index_count * sizeof(uint32_t);
    /* Refuse before allocating: atlas (and its staging copy), colour and
     * depth targets, readback, geometry. */
    uint64_t need = 2 * (uint64_t)atlas_bytes + image_bytes + (uint64_t)w * h * 4 +
                    image_bytes + vertex_bytes + index_bytes;
    display_pass *pass = NULL;
    display_target target = {0};
    gpu_buffer vertices = {0}, indices = {0}, staging = {0}, readback = {0};
    gpu_image atlas_image = {0};
    gpu_cmd cmd = {0};
    float *out = NULL;
    if ((s = gpu_memory_check_budget(ctx, need, GPU_MEM_DEVICE, "the image", err)) ||
        (s = display_create(ctx, &pass, err)) ||
        (s = display_target_create(ctx, pass, w, h, &target, err)))
        goto done;
    display_filter filter = opt->filter;
    if (opt->auto_filter)
        filter = desc->nearest                       ? DISPLAY_FILTER_NEAREST
                 : display_linear_supported(pass) ? DISPLAY_FILTER_LINEAR
                                                  : DISPLAY_FILTER_LINEAR_SHADER;
    gpu_image_desc ad = {
        .format = DISPLAY_ATLAS_FORMAT,
        .width = aw,
        .height = ah,
        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
        .category = GPU_MEM_RADIOSITY,
    };
    if ((s = gpu_image_create(ctx, &ad, &atlas_image, err)) ||
        (s = gpu_buffer_create(ctx, atlas_bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               GPU_MEM_UPLOAD, GPU_MEM_STAGING, &staging, err)) ||
        (s = gpu_buffer_create(ctx, image_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                               GPU_MEM_READBACK, GPU_MEM_STAGING, &readback, err)))
        goto done;
    if (atlas->width && atlas->height)
        memcpy(staging.alloc.mapped, atlas->rgba, atlas_bytes);
    else
        memset(staging.alloc.mapped, 0, atlas_bytes);
    if (mesh.index_count &&
        ((s = gpu_buffer_create(ctx, vertex_bytes,
                                VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &vertices, err)) ||
         (s = gpu_buffer_create(ctx, index_bytes,
                                VK_BUFFER_USAGE_INDEX_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &indices, err)) ||
         (s = gpu_upload_buffer(ctx, &vertices, 0, mesh.vertices, vertex_bytes, err)) ||
         (s = gpu_upload_buffer(ctx, &indices, 0, mesh.indices, index_bytes, err))))
        goto done;

    if ((s = gpu_cmd_begin(ctx, &cmd, err)))
        goto done;
    if (opt->timer)
        gpu_timer_start(opt->timer, cmd.cmd);
    gpu_image_transition(cmd.cmd, &atlas_image, VK_IMAGE_LAYOUT_UNDEFINED,
                         VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL);
    gpu_cmd_copy_buffer_to_image(cmd.cmd, &staging, 0, &atlas_image, 0);
    gpu_image_transition(cmd.cmd, &atlas_image, VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL,
                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    display_draw draw = {
        .vertices = &vertices,
        .indices = &indices,
        .index_count = mesh.index_count,
        .atlas = &atlas_image,
        .camera = &cam,
        .filter = filter,
    };
    if (opt->timer)
        gpu_timer_begin(opt->timer, cmd.cmd, "display");
    if ((s = display_record(ctx, pass, cmd.cmd, &target, &draw, err)))
        goto done;
    if (opt->timer)
        gpu_timer_end(opt->timer, cmd.cmd);
    gpu_cmd_copy_image_to_buffer(cmd.cmd, &target.color, 0, &readback, 0);
    VkMemoryBarrier host = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_HOST_READ_BIT,
    };
    vkCmdPipelineBarrier(cmd.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0,
                         1, &host, 0, NULL, 0, NULL);
    if ((s = gpu_cmd_run(ctx, &cmd, err)) ||
        (opt->timer && (s = gpu_timer_collect(ctx, opt->timer, err))))
        goto done;
    out = malloc(image_bytes);
    if (!out) {
        s = xrad_fail(err, XRAD_ERROR_SYSTEM, "out of host memory for a %u x %u image", w, h);
        goto done;
    }
    /* Framebuffer row 0 is the top row (the projection flips y). */
    memcpy(out, readback.alloc.mapped, image_bytes);
    *rgba = out;
    *width = w;
    *height = h;

done:
    /* gpu_cmd_destroy waits for a submission a failure left in flight
     * before anything it uses is freed. */
    gpu_cmd_destroy(ctx, &cmd);
    gpu_buffer_destroy(ctx, &readback);
    gpu_buffer_destroy(ctx, &staging);
    gpu_buffer_destroy(ctx, &indices);
    gpu_buffer_destroy(ctx, &vertices);
    gpu_image_destroy(ctx, &atlas_image);
    display_target_destroy(ctx, &target);
    display_destroy(ctx, &pass);
    display_mesh_free(&mesh);
    if (s)
        xrad_error_prefix(err, "render view");
    return s;
}

xrad_status xrad_render_view(xrad_context *ctx, const xrad_scene *scene, const xrad_atlas *atlas,
                             const xrad_view_desc *desc, float **rgba, uint32_t *width,
                             uint32_t *height, xrad_error *err)
{
    render_view_options opt = {.auto_filter = true};
    return render_view(ctx, scene, atlas, desc, &opt, rgba, width, height, err);
}
