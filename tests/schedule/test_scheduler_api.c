/*
 * The real-time loop through the public API alone (include/xrad_vulkan.h,
 * issue 17.2), as an engine would drive it: requests with poses and light
 * changes, and per frame the front atlas as a VkImage that the test copies
 * to host memory with its own commands, waiting on and signalling the
 * frame's timeline values. cornell-lowq, progressive (a pose or a light
 * change is a fresh solve: the solution is determined, so the checks can
 * be tight). Checks:
 *  - bad requests are refused before the worker sees them, naming what is
 *    wrong: a static object, a pose that is not rigid, an unknown material,
 *    a negative emission;
 *  - a pose (the box rotated a quarter turn and moved) gives the solution
 *    a solver of a second copy of the scene with xrad_scene_set_pose gives;
 *  - the light off gives B = 0 on every element (nothing emits);
 *  - the light at twice its emission gives twice the first solution
 *    (radiosity is linear in E);
 *  - no validation message.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "xrad.h"
#include "xrad_vulkan.h"

typedef struct readback {
    VkDevice device;
    VkCommandPool pool;
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    void *map;
} readback;

static int readback_create(xrad_context *ctx, uint32_t w, uint32_t h, readback *rb)
{
    memset(rb, 0, sizeof(*rb));
    rb->device = xrad_vulkan_device(ctx);
    uint32_t family;
    xrad_vulkan_queue(ctx, &family);
    rb->size = (VkDeviceSize)w * h * 16;
    VkCommandPoolCreateInfo pi = {.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
                                  .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
                                  .queueFamilyIndex = family};
    VkBufferCreateInfo bi = {.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
                             .size = rb->size,
                             .usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT};
    if (vkCreateCommandPool(rb->device, &pi, NULL, &rb->pool) ||
        vkCreateBuffer(rb->device, &bi, NULL, &rb->buffer))
        return 0;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(rb->device, rb->buffer, &req);
    VkPhysicalDeviceMemoryProperties mp;
    vkGetPhysicalDeviceMemoryProperties(xrad_vulkan_physical_device(ctx), &mp);
    const VkMemoryPropertyFlags want =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    uint32_t type = UINT32_MAX;
    for (uint32_t i = 0; i < mp.memoryTypeCount && type == UINT32_MAX; i++)
        if ((req.memoryTypeBits & (1u << i)) && (mp.memoryTypes[i].propertyFlags & want) == want)
            type = i;
    VkMemoryAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                               .allocationSize = req.size,
                               .memoryTypeIndex = type};
    return type != UINT32_MAX && !vkAllocateMemory(rb->device, &ai, NULL, &rb->memory) &&
           !vkBindBufferMemory(rb->device, rb->buffer, rb->memory, 0) &&
           !vkMapMemory(rb->device, rb->memory, 0, rb->size, 0, &rb->map);
}

static void readback_destroy(readback *rb)
{
    if (rb->memory)
        vkFreeMemory(rb->device, rb->memory, NULL);
    vkDestroyBuffer(rb->device, rb->buffer, NULL);
    vkDestroyCommandPool(rb->device, rb->pool, NULL);
}

/* One display frame that copies the front atlas into `out` (w x h RGBA):
 * what an engine's frame does, with a copy in place of its draw. */
static int frame_copy(xrad_context *ctx, xrad_scheduler *sch, readback *rb, float *out,
                      uint64_t *serial)
{
    xrad_error err = {0};
    xrad_frame f;
    CHECK(xrad_scheduler_begin_frame(sch, &f, &err) == XRAD_OK, "begin_frame: %s", err.message);
    if (!f.image) {
        CHECK(xrad_scheduler_end_frame(sch, &f, 0, &err) == XRAD_OK, "%s", err.message);
        return 0;
    }
    CHECK(f.format == VK_FORMAT_R32G32B32A32_SFLOAT &&
              f.layout == VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL && f.view,
          "frame: format %d, layout %d", (int)f.format, (int)f.layout);
    VkCommandBuffer cmd;
    VkCommandBufferAllocateInfo ai = {.sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
                                      .commandPool = rb->pool,
                                      .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
                                      .commandBufferCount = 1};
    vkAllocateCommandBuffers(rb->device, &ai, &cmd);
    vkBeginCommandBuffer(cmd, &(VkCommandBufferBeginInfo){
                                  .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
                                  .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT});
    VkImageMemoryBarrier to_src = {
        .sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER,
        .srcAccessMask = 0,
        .dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT,
        .oldLayout = f.layout,
        .newLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .image = f.image,
        .subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1},
    };
    VkImageMemoryBarrier back = to_src;
    back.srcAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
    back.dstAccessMask = 0;
    back.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    back.newLayout = f.layout;
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 0, NULL, 0, NULL, 1, &to_src);
    VkBufferImageCopy region = {
        .imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1},
        .imageExtent = {f.width, f.height, 1},
    };
    vkCmdCopyImageToBuffer(cmd, f.image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, rb->buffer, 1,
                           &region);
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, 0, 0, NULL, 0, NULL, 1, &back);
    VkBufferMemoryBarrier host = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_HOST_READ_BIT,
        .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
        .buffer = rb->buffer,
        .size = VK_WHOLE_SIZE,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 0,
                         NULL, 1, &host, 0, NULL);
    vkEndCommandBuffer(cmd);
    /* The frame's wait (the front's redistribution) before the copy, its
     * signal after it: the worker will not rewrite this atlas before. */
    VkPipelineStageFlags stage = VK_PIPELINE_STAGE_TRANSFER_BIT;
    VkTimelineSemaphoreSubmitInfo tl = {
        .sType = VK_STRUCTURE_TYPE_TIMELINE_SEMAPHORE_SUBMIT_INFO,
        .waitSemaphoreValueCount = 1,
        .pWaitSemaphoreValues = &f.wait_value,
        .signalSemaphoreValueCount = 1,
        .pSignalSemaphoreValues = &f.signal_value,
    };
    VkSubmitInfo si = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .pNext = &tl,
        .waitSemaphoreCount = 1,
        .pWaitSemaphores = &f.wait,
        .pWaitDstStageMask = &stage,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
        .signalSemaphoreCount = 1,
        .pSignalSemaphores = &f.signal,
    };
    uint32_t family;
    VkQueue queue = xrad_vulkan_queue(ctx, &family);
    xrad_vulkan_lock_queue(ctx);
    VkResult r = vkQueueSubmit(queue, 1, &si, VK_NULL_HANDLE);
    xrad_vulkan_unlock_queue(ctx);
    CHECK(r == VK_SUCCESS, "vkQueueSubmit %d", (int)r);
    CHECK(xrad_scheduler_end_frame(sch, &f, r == VK_SUCCESS, &err) == XRAD_OK, "end_frame: %s",
          err.message);
    VkSemaphoreWaitInfo wi = {.sType = VK_STRUCTURE_TYPE_SEMAPHORE_WAIT_INFO,
                              .semaphoreCount = 1,
                              .pSemaphores = &f.signal,
                              .pValues = &f.signal_value};
    CHECK(vkWaitSemaphores(rb->device, &wi, 60ull * 1000000000ull) == VK_SUCCESS,
          "the frame's copy did not finish");
    vkFreeCommandBuffers(rb->device, rb->pool, 1, &cmd);
    memcpy(out, rb->map, (size_t)rb->size);
    *serial = f.serial;
    return 1;
}

/* Requests `r`, waits for it, copies the front atlas into `atlas`. */
static int solve_frame(xrad_context *ctx, xrad_scheduler *sch, readback *rb,
                       const xrad_request *r, xrad_atlas *atlas)
{
    xrad_error err = {0};
    uint64_t serial = 0, shown = 0;
    xrad_status st = xrad_scheduler_request(sch, r, &serial, &err);
    CHECK(st == XRAD_OK, "request: %s", err.message);
    if (!st)
        st = xrad_scheduler_wait(sch, serial, &err);
    CHECK(st == XRAD_OK, "wait: %s", err.message);
    return !st && frame_copy(ctx, sch, rb, atlas->rgba, &shown) && shown > 0;
}

static void compare(const xrad_scene *scene, const xrad_atlas *a, const xrad_atlas *b,
                    double scale, double tol, const char *what)
{
    xrad_atlas scaled = {0};
    xrad_error err = {0};
    if (xrad_atlas_create(scene, &scaled, &err))
        return;
    for (size_t i = 0; i < (size_t)b->width * b->height * 4; i++)
        scaled.rgba[i] = (float)(b->rgba[i] * ((i & 3) == 3 ? 1 : scale));
    xrad_element_metrics m;
    xrad_status st = xrad_atlas_compare(scene, a, &scaled, &m, NULL, &err);
    CHECK(st == XRAD_OK, "%s: %s", what, err.message);
    fprintf(stderr, "%s: surface_error %.3g, element max %.3g\n", what, m.surface_error, m.max);
    CHECK(!st && m.elements > 0 && m.surface_error < tol && m.max < 10 * tol,
          "%s: surface_error %.3g (worst surface %u), element max %.3g", what, m.surface_error,
          m.worst_surface, m.max);
    xrad_atlas_destroy(&scaled);
}

int main(void)
{
    char path[1024];
    test_source_path("scenes/cornell-lowq.json", path, sizeof(path));
    xrad_error err = {0};
    xrad_scene *scene = NULL, *mine = NULL;
    xrad_context *ctx = NULL;
    xrad_scheduler *sch = NULL;
    xrad_status st = xrad_scene_load(path, &scene, &err);
    if (!st)
        st = xrad_scene_load(path, &mine, &err);
    if (!st)
        st = xrad_context_create(&(xrad_context_desc){.validation = 1}, &ctx, &err);
    CHECK(st == XRAD_OK, "setup: %s", err.message);
    if (st)
        return test_finish();

    /* The box (the dynamic object), the light's material. */
    xrad_scene_info info;
    xrad_scene_get_info(mine, &info);
    uint32_t box = UINT32_MAX, light = UINT32_MAX, room = UINT32_MAX;
    for (uint32_t i = 0; i < info.objects; i++) {
        xrad_object_info o;
        xrad_scene_get_object(mine, i, &o, NULL);
        if (o.dynamic && box == UINT32_MAX)
            box = i;
        if (!o.dynamic && room == UINT32_MAX)
            room = i;
    }
    double e0[3] = {0};
    for (uint32_t i = 0; i < info.materials; i++) {
        xrad_material_info m;
        xrad_scene_get_material(mine, i, &m, NULL);
        if (m.emission[0] > 0 && light == UINT32_MAX) {
            light = i;
            memcpy(e0, m.emission, sizeof(e0));
        }
    }
    CHECK(box != UINT32_MAX && room != UINT32_MAX && light != UINT32_MAX,
          "cornell-lowq: a dynamic box, a static room and a light");

    xrad_solver_desc sd = {.method = XRAD_METHOD_PROGRESSIVE};
    st = xrad_scheduler_create(ctx, scene, &(xrad_scheduler_desc){.solver = sd}, &sch, &err);
    CHECK(st == XRAD_OK, "scheduler: %s", err.message);
    if (!st)
        scene = NULL; /* the scheduler's now */
    readback rb;
    xrad_atlas first = {0}, got = {0}, want = {0};
    if (st || !readback_create(ctx, info.atlas_width, info.atlas_height, &rb) ||
        xrad_atlas_create(mine, &first, &err) || xrad_atlas_create(mine, &got, &err)) {
        CHECK(0, "readback and atlases");
        goto done;
    }

    /* Refused before the worker sees them. */
    double m[16];
    xrad_scene_get_object_pose(mine, box, 0, m, NULL);
    xrad_object_pose bad = {.object = room};
    memcpy(bad.matrix, m, sizeof(m));
    CHECK(xrad_scheduler_request(sch, &(xrad_request){.poses = &bad, .pose_count = 1}, NULL,
                                 &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "static"),
          "pose of the static room: %s", err.message);
    bad.object = box;
    for (int k = 0; k < 3; k++)
        bad.matrix[k * 5] *= 2; /* scaled: not rigid */
    CHECK(xrad_scheduler_request(sch, &(xrad_request){.poses = &bad, .pose_count = 1}, NULL,
                                 &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "rigid"),
          "scaled pose: %s", err.message);
    xrad_emission_change dark = {.material = info.materials, .emission = {1, 1, 1}};
    CHECK(xrad_scheduler_request(sch, &(xrad_request){.emissions = &dark, .emission_count = 1},
                                 NULL, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "does not exist"),
          "unknown material: %s", err.message);
    dark = (xrad_emission_change){.material = light, .emission = {-1, 0, 0}};
    CHECK(xrad_scheduler_request(sch, &(xrad_request){.emissions = &dark, .emission_count = 1},
                                 NULL, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "emission"),
          "negative emission: %s", err.message);

    /* The first solution, at t = 0. */
    CHECK(solve_frame(ctx, sch, &rb, &(xrad_request){.time = 0}, &first), "first frame");

    /* A quarter turn about the box's own vertical axis and 5 cm along x,
     * against a solver of the same pose: turn = T(5 cm x) pose(0) R_y. */
    xrad_object_pose turn = {.object = box};
    const double rot[16] = {0, 0, -1, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1};
    for (int col = 0; col < 4; col++)
        for (int row = 0; row < 4; row++) {
            double v = 0;
            for (int k = 0; k < 4; k++)
                v += m[k * 4 + row] * rot[col * 4 + k];
            turn.matrix[col * 4 + row] = v;
        }
    turn.matrix[12] += 0.05;
    CHECK(solve_frame(ctx, sch, &rb, &(xrad_request){.poses = &turn, .pose_count = 1}, &got),
          "posed frame");
    xrad_solver *solver = NULL;
    st = xrad_scene_set_pose(mine, box, turn.matrix, &err);
    if (!st)
        st = xrad_atlas_create(mine, &want, &err);
    if (!st)
        st = xrad_solver_create(ctx, mine, &sd, &solver, &err);
    if (!st)
        st = xrad_solver_solve(solver, &err);
    if (!st)
        st = xrad_solver_read(solver, &want, &err);
    xrad_solver_destroy(&solver);
    CHECK(st == XRAD_OK, "solver at the pose: %s", err.message);
    if (!st)
        compare(mine, &got, &want, 1, 1e-4, "posed box vs a solver of the pose");
    xrad_scene_set_pose(mine, box, NULL, NULL);

    /* Back to the animation; the light off: nothing emits, B = 0. */
    xrad_object_pose back = {.object = box, .clear = 1};
    dark = (xrad_emission_change){.material = light};
    CHECK(solve_frame(ctx, sch, &rb,
                      &(xrad_request){.poses = &back,
                                      .pose_count = 1,
                                      .emissions = &dark,
                                      .emission_count = 1},
                      &got),
          "dark frame");
    double brightest = 0;
    for (size_t i = 0; i < (size_t)got.width * got.height; i++)
        for (int k = 0; k < 3; k++)
            brightest = fmax(brightest, fabs(got.rgba[i * 4 + k]));
    CHECK(brightest == 0, "light off: largest radiosity %.3g, want 0", brightest);

    /* Twice the emission: twice the first solution. */
    xrad_emission_change twice = {.material = light};
    for (int k = 0; k < 3; k++)
        twice.emission[k] = 2 * e0[k];
    CHECK(solve_frame(ctx, sch, &rb, &(xrad_request){.emissions = &twice, .emission_count = 1},
                      &got),
          "bright frame");
    compare(mine, &got, &first, 2, 1e-4, "twice the emission vs twice the first solution");

    xrad_scheduler_stats ss;
    xrad_scheduler_get_stats(sch, &ss);
    /* Four requests made (the refused ones never reach the worker), each
     * waited for: published after the first solve's publication. */
    CHECK(ss.last.hemicubes > 0 && ss.published == 5 && ss.requested == 4,
          "the worker's stats: %u hemicubes, %llu published, %llu requested", ss.last.hemicubes,
          (unsigned long long)ss.published, (unsigned long long)ss.requested);
    readback_destroy(&rb);
done:
    xrad_scheduler_destroy(&sch);
    CHECK(sch == NULL, "destroy clears the handle");
    CHECK(xrad_context_validation_messages(ctx) == 0, "%u validation messages",
          xrad_context_validation_messages(ctx));
    xrad_context_destroy(&ctx);
    xrad_atlas_destroy(&first);
    xrad_atlas_destroy(&got);
    xrad_atlas_destroy(&want);
    xrad_scene_destroy(&mine);
    xrad_scene_destroy(&scene);
    return test_finish();
}
