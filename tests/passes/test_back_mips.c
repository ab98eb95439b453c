/*
 * Back hemicube mips (src/passes/back_mips.h, spirv/back_mips.comp): on
 * random faces, every texel of every level k >= 1 is the mean of the
 * 2^k x 2^k level-0 texels it covers, in the layout spirv/back_mips.glsl
 * states (per layer, levels one after another, rows of res >> k), computed
 * here on the CPU. A side face's lower half (below the hemicube's base,
 * never drawn) is filled with 1e6, so any mean that takes it in is off by
 * far more than the 1e-5 allowed; a block wholly there takes the lowest
 * drawn rows. Sides of 16 (4 levels, down to 1 x 1) and 24 (3 levels, to
 * 3 x 3: halving stops where the side turns odd).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cross_shared.h"
#include "gpu/cmd.h"
#include "gpu/gpu_test.h"
#include "gpu/image.h"
#include "passes/back_mips.h"
#include "passes/hemicube_geometry.h"

#define LAYERS (2 * HEMICUBE_FACES)

static uint32_t rng = 12345;

static float next_random(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / (float)(1u << 24);
}

/* The CPU mean of level k's texel (x, y) of `layer`. */
static void cpu_mean(const float *texels, uint32_t res, uint32_t layer, uint32_t k, uint32_t x,
                     uint32_t y, double out[4])
{
    uint32_t block = 1u << k, x0 = x * block, y0 = y * block, y1 = y0 + block;
    if (layer % HEMICUBE_FACES) {
        uint32_t half = res / 2;
        if (y0 < half)
            y0 = half;
        if (y0 >= y1) {
            y0 = half;
            y1 = half + (block < half ? block : half);
        }
    }
    for (int c = 0; c < 4; c++)
        out[c] = 0;
    for (uint32_t v = y0; v < y1; v++)
        for (uint32_t u = x0; u < x0 + block; u++)
            for (int c = 0; c < 4; c++)
                out[c] += texels[(((size_t)layer * res + v) * res + u) * 4 + c];
    for (int c = 0; c < 4; c++)
        out[c] /= (double)((y1 - y0) * block);
}

static void check_res(xrad_context *ctx, uint32_t res, uint32_t want_levels)
{
    xrad_error err = {0};
    uint32_t levels = back_mips_levels(res);
    CHECK(levels == want_levels, "side %u: %u levels, want %u", res, levels, want_levels);
    size_t count = (size_t)LAYERS * res * res * 4;
    float *texels = malloc(count * sizeof(float));
    size_t layer_texels = 0;
    for (uint32_t k = 1; k <= levels; k++)
        layer_texels += (size_t)(res >> k) * (res >> k);
    CHECK(back_mips_bytes(res, LAYERS) == layer_texels * LAYERS * 16,
          "side %u: %llu bytes, want %zu", res, (unsigned long long)back_mips_bytes(res, LAYERS),
          layer_texels * LAYERS * 16);
    float *mips = malloc(layer_texels * LAYERS * 16);
    if (!texels || !mips) {
        CHECK(0, "out of host memory");
        free(texels);
        free(mips);
        return;
    }
    for (uint32_t l = 0; l < LAYERS; l++)
        for (uint32_t y = 0; y < res; y++)
            for (uint32_t x = 0; x < res; x++)
                for (int c = 0; c < 4; c++)
                    texels[(((size_t)l * res + y) * res + x) * 4 + c] =
                        (l % HEMICUBE_FACES && y < res / 2) ? 1e6f : next_random();
    gpu_image img = {0};
    gpu_buffer buf = {0};
    back_mips_pass *pass = NULL;
    gpu_cmd cmd = {0};
    gpu_image_desc d = {.format = VK_FORMAT_R32G32B32A32_SFLOAT, .width = res, .height = res,
                        .layers = LAYERS, .array = true,
                        .usage = VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT,
                        .category = GPU_MEM_OTHER};
    bool ok = gpu_image_create(ctx, &d, &img, &err) == XRAD_OK &&
                        gpu_upload_image(ctx, &img, texels, count * sizeof(float),
                                         VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                                         &err) == XRAD_OK &&
                        gpu_buffer_create(ctx, back_mips_bytes(res, LAYERS),
                                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                                          GPU_MEM_DEVICE, GPU_MEM_OTHER, &buf, &err) == XRAD_OK &&
                        back_mips_create(ctx, &pass, &err) == XRAD_OK &&
                        gpu_cmd_begin(ctx, &cmd, &err) == XRAD_OK;
    CHECK(ok, "side %u: %s", res, err.message);
    if (ok) {
        back_mips_bind(ctx, pass, img.view, &buf);
        back_mips_record(pass, cmd.cmd, res, LAYERS);
        ok = gpu_cmd_run(ctx, &cmd, &err) == XRAD_OK &&
             gpu_readback_buffer(ctx, &buf, 0, mips, layer_texels * LAYERS * 16, &err) ==
                 XRAD_OK;
        CHECK(ok, "side %u: %s", res, err.message);
    }
    double worst = 0;
    size_t checked = 0, at = 0;
    for (uint32_t l = 0; ok && l < LAYERS; l++)
        for (uint32_t k = 1; k <= levels; k++) {
            uint32_t r = res >> k;
            for (uint32_t y = 0; y < r; y++)
                for (uint32_t x = 0; x < r; x++, at++) {
                    double want[4];
                    cpu_mean(texels, res, l, k, x, y, want);
                    for (int c = 0; c < 4; c++) {
                        double e = fabs(mips[at * 4 + c] - want[c]) / fmax(fabs(want[c]), 1e-3);
                        worst = fmax(worst, e);
                    }
                    checked++;
                }
        }
    printf("side %u: %u levels, %zu mip texels checked, largest relative error %.2e\n", res,
           levels, checked, worst);
    CHECK(!ok || checked == layer_texels * LAYERS, "side %u: %zu texels checked", res, checked);
    CHECK(worst < 1e-5, "side %u: a mip texel off the mean of what it covers by %.2e", res,
          worst);
    gpu_cmd_destroy(ctx, &cmd);
    back_mips_destroy(ctx, &pass);
    gpu_buffer_destroy(ctx, &buf);
    gpu_image_destroy(ctx, &img);
    free(texels);
    free(mips);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    check_res(ctx, 16, 4);
    check_res(ctx, 24, 3);
    gpu_test_end(&ctx);
    return test_finish();
}
