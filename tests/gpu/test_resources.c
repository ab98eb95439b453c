/* Buffers, images, staging round trips, memory sub-allocation and budget
 * accounting, and the timestamp timer, on the device. */
#include <stdlib.h>
#include <string.h>

#include "gpu/buffer.h"
#include "gpu/cmd.h"
#include "gpu/image.h"
#include "gpu/timer.h"
#include "gpu_test.h"

static void test_buffers(xrad_context *ctx)
{
    xrad_error err = {0};
    gpu_buffer a = {0}, b = {0}, big = {0};
    const VkBufferUsageFlags usage = VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                                     VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    CHECK(gpu_buffer_create(ctx, 1000, usage, GPU_MEM_DEVICE, GPU_MEM_GEOMETRY, &a, &err) ==
              XRAD_OK,
          "a: %s", err.message);
    CHECK(gpu_buffer_create(ctx, 3000, usage, GPU_MEM_DEVICE, GPU_MEM_RADIOSITY, &b, &err) ==
              XRAD_OK,
          "b: %s", err.message);
    gpu_memory_stats st;
    gpu_memory_get_stats(ctx, &st);
    /* Two small buffers of one memory type share one block, without overlap. */
    CHECK(st.allocations == 2 && st.blocks == 1, "%u allocations in %u blocks", st.allocations,
          st.blocks);
    CHECK(a.alloc.memory != b.alloc.memory ||
              a.alloc.offset + a.alloc.size <= b.alloc.offset ||
              b.alloc.offset + b.alloc.size <= a.alloc.offset,
          "a and b overlap");
    CHECK(st.category_bytes[GPU_MEM_GEOMETRY] >= 1000 &&
              st.category_bytes[GPU_MEM_RADIOSITY] >= 3000 &&
              st.category_bytes[GPU_MEM_STAGING] == 0,
          "category bytes %llu %llu", (unsigned long long)st.category_bytes[GPU_MEM_GEOMETRY],
          (unsigned long long)st.category_bytes[GPU_MEM_RADIOSITY]);
    /* A large buffer gets memory of its own. */
    CHECK(gpu_buffer_create(ctx, 20u << 20, usage, GPU_MEM_DEVICE, GPU_MEM_OTHER, &big, &err) ==
              XRAD_OK,
          "big: %s", err.message);
    gpu_memory_get_stats(ctx, &st);
    CHECK(st.blocks == 2 && big.alloc.offset == 0, "dedicated: %u blocks", st.blocks);

    /* Round trip through staging (or a mapping) and back. */
    unsigned char in[3000], out[3000];
    for (int i = 0; i < 3000; i++)
        in[i] = (unsigned char)(i * 7 + 3);
    memset(out, 0, sizeof(out));
    CHECK(gpu_upload_buffer(ctx, &b, 0, in, sizeof(in), &err) == XRAD_OK, "upload: %s",
          err.message);
    CHECK(gpu_readback_buffer(ctx, &b, 0, out, sizeof(out), &err) == XRAD_OK, "readback: %s",
          err.message);
    CHECK(!memcmp(in, out, sizeof(in)), "buffer round trip differs");
    CHECK(gpu_upload_buffer(ctx, &a, 500, in, 501, &err) == XRAD_ERROR_SYSTEM,
          "overrunning upload accepted");

    /* Refusal before allocating: far more than any heap. */
    CHECK(gpu_memory_check_budget(ctx, UINT64_MAX / 2, GPU_MEM_DEVICE, "huge", &err) ==
                  XRAD_ERROR_SYSTEM &&
              strstr(err.message, "huge"),
          "budget: %s", err.message);
    CHECK(gpu_memory_check_budget(ctx, 1 << 20, GPU_MEM_DEVICE, "small", &err) == XRAD_OK,
          "1 MiB refused: %s", err.message);

    gpu_buffer_destroy(ctx, &big);
    gpu_buffer_destroy(ctx, &a);
    gpu_buffer_destroy(ctx, &b);
    gpu_buffer_destroy(ctx, &b); /* zeroed: accepted */
    gpu_memory_get_stats(ctx, &st);
    CHECK(st.allocations == 0 && st.blocks == 0 && st.category_bytes[GPU_MEM_GEOMETRY] == 0,
          "after destroy: %u allocations, %u blocks", st.allocations, st.blocks);
}

static void test_images(xrad_context *ctx)
{
    xrad_error err = {0};
    gpu_image img = {0};
    gpu_image_desc d = {
        .format = VK_FORMAT_R32G32B32A32_SFLOAT,
        .width = 7,
        .height = 5,
        .layers = 3,
        .usage = VK_IMAGE_USAGE_TRANSFER_SRC_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                 VK_IMAGE_USAGE_SAMPLED_BIT,
        .category = GPU_MEM_RENDER_TARGET,
    };
    CHECK(gpu_image_create(ctx, &d, &img, &err) == XRAD_OK, "image: %s", err.message);
    if (!img.image)
        return;
    enum { N = 7 * 5 * 3 * 4 };
    float in[N], out[N];
    for (int i = 0; i < N; i++)
        in[i] = (float)i * 0.5f - 3.0f;
    CHECK(gpu_upload_image(ctx, &img, in, sizeof(in), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                           &err) == XRAD_OK,
          "upload: %s", err.message);
    CHECK(gpu_readback_image(ctx, &img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, out,
                             sizeof(out), &err) == XRAD_OK,
          "readback: %s", err.message);
    CHECK(!memcmp(in, out, sizeof(in)), "layered image round trip differs");
    CHECK(gpu_readback_image(ctx, &img, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, out, 16,
                             &err) == XRAD_ERROR_SYSTEM,
          "wrong size accepted");
    VkImageView face;
    CHECK(gpu_image_view_create(ctx, &img, VK_IMAGE_VIEW_TYPE_2D, 2, 1, &face, &err) == XRAD_OK,
          "layer view: %s", err.message);
    vkDestroyImageView(ctx->device, face, NULL);
    gpu_image_destroy(ctx, &img);
    d.width = ctx->props.limits.maxImageDimension2D + 1;
    CHECK(gpu_image_create(ctx, &d, &img, &err) == XRAD_ERROR_SYSTEM && !img.image,
          "oversized image accepted");
}

/* Nested intervals around transfer work: each collected once; the outer
 * one lasts at least as long as the inner one. */
static void test_timer(xrad_context *ctx)
{
    xrad_error err = {0};
    gpu_timer *t = NULL;
    gpu_buffer buf = {0};
    gpu_cmd c = {0};
    CHECK(gpu_timer_create(ctx, 4, &t, &err) == XRAD_OK, "timer: %s", err.message);
    CHECK(gpu_buffer_create(ctx, 8u << 20, VK_BUFFER_USAGE_TRANSFER_DST_BIT, GPU_MEM_DEVICE,
                            GPU_MEM_OTHER, &buf, &err) == XRAD_OK,
          "buffer: %s", err.message);
    if (!t || !buf.buffer)
        goto done;
    for (int round = 0; round < 2; round++) {
        CHECK(gpu_cmd_begin(ctx, &c, &err) == XRAD_OK, "begin: %s", err.message);
        gpu_timer_start(t, c.cmd);
        gpu_timer_begin(t, c.cmd, "outer");
        gpu_timer_begin(t, c.cmd, "fill");
        vkCmdFillBuffer(c.cmd, buf.buffer, 0, VK_WHOLE_SIZE, 0x3f800000u);
        gpu_timer_end(t, c.cmd);
        gpu_timer_end(t, c.cmd);
        CHECK(gpu_cmd_run(ctx, &c, &err) == XRAD_OK, "run: %s", err.message);
        CHECK(c.value > 0, "no timeline value");
        CHECK(gpu_timer_collect(ctx, t, &err) == XRAD_OK, "collect: %s", err.message);
        gpu_cmd_destroy(ctx, &c);
    }
    if (t->supported) {
        double outer = gpu_timer_total_ms(t, "outer"), fill = gpu_timer_total_ms(t, "fill");
        CHECK(t->name_count == 2 && t->totals[0].count == 2 && t->totals[1].count == 2,
              "interval counts");
        CHECK(fill > 0 && outer >= fill, "outer %.4g ms, fill %.4g ms", outer, fill);
        CHECK(gpu_timer_total_ms(t, "never") == 0, "unknown name");
        fprintf(stderr, "fill 8 MiB twice: %.3f ms (outer %.3f ms)\n", fill, outer);
    }
done:
    gpu_buffer_destroy(ctx, &buf);
    gpu_timer_destroy(ctx, &t);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_buffers(ctx);
    test_images(ctx);
    test_timer(ctx);
    gpu_test_end(&ctx);
    return test_finish();
}
