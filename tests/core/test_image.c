/* Image I/O and metrics: EXR round trip is lossless for float data (a fifth
 * named channel too), PNG pixels follow the sRGB curve (with Reinhard's
 * operator, worked by hand), NRMSE matches its
 * definition on images built so that the answer is known in closed form. */
#include <png.h>
#include <stdint.h>
#include <string.h>

#include "harness.h"
#include "xrad.h"

static void test_exr_roundtrip(const char *dir)
{
    enum { W = 37, H = 21 };
    static float px[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        px[i * 4 + 0] = (float)i * 0.5f;
        px[i * 4 + 1] = -1e-6f * (float)i;
        px[i * 4 + 2] = 1e6f + (float)i;
        px[i * 4 + 3] = 1.0f;
    }
    char path[512];
    snprintf(path, sizeof(path), "%s/roundtrip.exr", dir);
    xrad_error err = {0};
    CHECK(xrad_image_write_exr(path, px, W, H, &err) == XRAD_OK, "%s", err.message);
    float *back = NULL;
    uint32_t w = 0, h = 0;
    CHECK(xrad_image_read_exr(path, &back, &w, &h, &err) == XRAD_OK, "%s", err.message);
    CHECK(w == W && h == H, "size %ux%u", w, h);
    if (back) {
        int same = 1;
        for (int i = 0; i < W * H * 4; i++)
            same &= back[i] == px[i];
        CHECK(same, "float EXR round trip must be exact");
    }
    free(back);

    /* A file that is not an EXR is bad input, with the path in the message. */
    snprintf(path, sizeof(path), "%s/not-an-exr.exr", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("hello", f);
        fclose(f);
    }
    CHECK(xrad_image_read_exr(path, &back, &w, &h, &err) == XRAD_ERROR_INPUT, "status");
    CHECK(strstr(err.message, "not-an-exr.exr") != NULL, "message: %s", err.message);
}

/* A half-float RGBA file written by another tool (OpenEXRCore, PIZ): pixel
 * 0 is (1, 1.0625, 1.125) by OpenEXR's C++ RgbaInputFile. OpenEXRCore 3.1
 * unpacked four half channels in reverse order (tests/fuzz/README.md). */
static void test_exr_half_rgba(void)
{
    char path[512];
    test_source_path("tests/fuzz/corpus/exr/rgba-half-piz-8x8.exr", path, sizeof(path));
    float *px = NULL;
    uint32_t w = 0, h = 0;
    xrad_error err = {0};
    CHECK(xrad_image_read_exr(path, &px, &w, &h, &err) == XRAD_OK, "%s", err.message);
    if (px) {
        CHECK(px[0] == 1.0f && px[1] == 1.0625f && px[2] == 1.125f && px[3] == 1.0f,
              "pixel 0 = (%g, %g, %g, %g)", px[0], px[1], px[2], px[3]);
    }
    free(px);
}

/* A fifth channel beside RGBA (xrad render's "emitter"): written and read
 * back exactly, RGBA reading unchanged by it, the coverage readable as "A",
 * a missing channel an answer (NULL) rather than an error. */
static void test_exr_channel(const char *dir)
{
    enum { W = 5, H = 3 };
    float px[W * H * 4], mask[W * H];
    for (int i = 0; i < W * H; i++) {
        px[i * 4 + 0] = 0.25f * (float)i;
        px[i * 4 + 1] = 1.0f + (float)i;
        px[i * 4 + 2] = 2.0f * (float)i;
        px[i * 4 + 3] = i % 4 == 0 ? 0.0f : 1.0f; /* some background */
        mask[i] = i % 3 == 1 ? 1.0f : i == 5 ? 0.5f : 0.0f;
    }
    char path[512], plain[512];
    snprintf(path, sizeof(path), "%s/emitter.exr", dir);
    snprintf(plain, sizeof(plain), "%s/plain.exr", dir);
    xrad_error err = {0};
    CHECK(xrad_image_write_exr_channel(path, px, "emitter", mask, W, H, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(xrad_image_write_exr(plain, px, W, H, &err) == XRAD_OK, "%s", err.message);

    float *rgba = NULL, *ch = NULL;
    uint32_t w = 0, h = 0;
    CHECK(xrad_image_read_exr(path, &rgba, &w, &h, &err) == XRAD_OK, "%s", err.message);
    CHECK(w == W && h == H, "size %ux%u", w, h);
    if (rgba) {
        int same = 1;
        for (int i = 0; i < W * H; i++)
            for (int c = 0; c < 4; c++)
                same &= rgba[i * 4 + c] == (c == 3 ? 1.0f : px[i * 4 + c]);
        CHECK(same, "RGB of a file with an extra channel must read as before, alpha 1");
    }
    free(rgba);

    w = h = 0;
    CHECK(xrad_image_read_exr_channel(path, "emitter", &ch, &w, &h, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(ch && w == W && h == H, "emitter channel %p %ux%u", (void *)ch, w, h);
    if (ch) {
        int same = 1;
        for (int i = 0; i < W * H; i++)
            same &= ch[i] == mask[i];
        CHECK(same, "emitter channel round trip must be exact");
    }
    free(ch);
    ch = NULL;
    CHECK(xrad_image_read_exr_channel(path, "A", &ch, &w, &h, &err) == XRAD_OK, "%s",
          err.message);
    if (ch) {
        int same = 1;
        for (int i = 0; i < W * H; i++)
            same &= ch[i] == px[i * 4 + 3];
        CHECK(same, "alpha read as a channel");
    }
    CHECK(ch != NULL, "alpha channel present");
    free(ch);

    /* Absent: OK and NULL, size still given. */
    ch = (float *)1;
    w = h = 0;
    CHECK(xrad_image_read_exr_channel(plain, "emitter", &ch, &w, &h, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(ch == NULL && w == W && h == H, "a file without the channel: %p %ux%u", (void *)ch,
          w, h);

    /* A name that would clash with RGBA: bad input naming the file. */
    CHECK(xrad_image_write_exr_channel(path, px, "G", mask, W, H, &err) == XRAD_ERROR_INPUT,
          "clashing name");
    CHECK(strstr(err.message, "emitter.exr") != NULL, "message: %s", err.message);
    /* Not an EXR: bad input naming the file. */
    snprintf(path, sizeof(path), "%s/junk.exr", dir);
    FILE *f = fopen(path, "w");
    if (f) {
        fputs("junk", f);
        fclose(f);
    }
    CHECK(xrad_image_read_exr_channel(path, "emitter", &ch, &w, &h, &err) == XRAD_ERROR_INPUT,
          "junk");
    CHECK(strstr(err.message, "junk.exr") != NULL, "message: %s", err.message);
}

/* One channel of a half-float file (another tool's): decoded alone, the
 * others into the sink, it is the value OpenEXR's C++ API gives. */
static void test_exr_half_channel(void)
{
    char path[512];
    test_source_path("tests/fuzz/corpus/exr/rgba-half-piz-8x8.exr", path, sizeof(path));
    float *ch = NULL;
    uint32_t w = 0, h = 0;
    xrad_error err = {0};
    CHECK(xrad_image_read_exr_channel(path, "B", &ch, &w, &h, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(ch && w == 8 && h == 8, "B of the half file");
    if (ch)
        CHECK(ch[0] == 1.125f, "pixel 0 B = %g, want 1.125", ch[0]);
    free(ch);
}

/* The first row of 8-bit PNG `path` as RGB bytes (n pixels); 0 on failure. */
static int read_png_rgb(const char *path, uint8_t *rgb, uint32_t n)
{
    png_image img;
    memset(&img, 0, sizeof(img));
    img.version = PNG_IMAGE_VERSION;
    int ok = png_image_begin_read_from_file(&img, path);
    CHECK(ok && img.width == n && img.height == 1, "%s: png header", path);
    if (!ok || img.width != n || img.height != 1) {
        png_image_free(&img);
        return 0;
    }
    img.format = PNG_FORMAT_RGB;
    ok = png_image_finish_read(&img, NULL, rgb, 0, NULL);
    CHECK(ok, "%s: png read", path);
    return ok;
}

static void test_png_srgb(const char *dir)
{
    /* Exposure 1: 0 -> 0, 1 -> 255, 0.5 -> sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.7354 -> 188;
     * 0.002 -> 12.92 * 0.002 = 0.02584 -> 7; values above 1 clamp. */
    float px[5 * 4] = {0, 0, 0, 1, 1, 1, 1, 1, 0.5f, 0.5f, 0.5f, 1, 0.002f, 0.002f, 0.002f, 1,
                       7, 7, 7, 1};
    char path[512];
    snprintf(path, sizeof(path), "%s/srgb.png", dir);
    xrad_error err = {0};
    CHECK(xrad_image_write_png(path, px, 5, 1, 1.0, &err) == XRAD_OK, "%s", err.message);
    uint8_t rgb[5 * 3] = {0};
    const uint8_t want[5] = {0, 255, 188, 7, 255};
    if (read_png_rgb(path, rgb, 5))
        for (int i = 0; i < 5; i++)
            CHECK(rgb[i * 3] == want[i], "pixel %d = %u, want %u", i, rgb[i * 3], want[i]);
}

/* Reinhard et al. 2002's global operator, the answers worked by hand:
 * C / (1 + L), L = 0.2126 R + 0.7152 G + 0.0722 B, then sRGB. Grey 1 ->
 * 0.5 -> 188; grey 3 -> 0.75 -> 225; (0.5, 0, 0): L = 0.1063 -> 0.4520 ->
 * 179; (0, 0.5, 0.25): L = 0.37565 -> (0, 0.3635, 0.1817) -> (0, 162,
 * 118). The key exposure of greys 0.5 and 2 and a zero (left out): the
 * log-average is 1 (eq. 1), so 0.18 (eq. 2), and with it 0.5 -> 0.09 /
 * 1.09 -> 81, 2 -> 0.36 / 1.36 -> 141. */
static void test_png_reinhard(const char *dir)
{
    float px[4 * 4] = {1, 1, 1, 1, 3, 3, 3, 1, 0.5f, 0, 0, 1, 0, 0.5f, 0.25f, 1};
    char path[512];
    snprintf(path, sizeof(path), "%s/reinhard.png", dir);
    xrad_error err = {0};
    CHECK(xrad_image_write_png_tonemapped(path, px, 4, 1, XRAD_TONEMAP_REINHARD, 1.0, &err) ==
              XRAD_OK,
          "%s", err.message);
    uint8_t rgb[4 * 3] = {0};
    const uint8_t want[4 * 3] = {188, 188, 188, 225, 225, 225, 179, 0, 0, 0, 162, 118};
    if (read_png_rgb(path, rgb, 4))
        for (int i = 0; i < 12; i++)
            CHECK(rgb[i] == want[i], "reinhard: pixel %d channel %d = %u, want %u", i / 3, i % 3,
                  rgb[i], want[i]);

    float key[3 * 4] = {0.5f, 0.5f, 0.5f, 1, 0, 0, 0, 0, 2, 2, 2, 1};
    CHECK_REL(xrad_image_key_exposure(key, 3, 1), 0.18, 1e-6);
    CHECK_REL(xrad_image_tonemap_exposure(XRAD_TONEMAP_REINHARD, key, 3, 1), 0.18, 1e-6);
    float zero[4] = {0, 0, 0, 0};
    CHECK(xrad_image_key_exposure(zero, 1, 1) == 1, "an all-zero image's key exposure is not 1");
    snprintf(path, sizeof(path), "%s/reinhard-auto.png", dir);
    CHECK(xrad_image_write_png_tonemapped(path, key, 3, 1, XRAD_TONEMAP_REINHARD, 0, &err) ==
              XRAD_OK,
          "%s", err.message);
    const uint8_t want_auto[3] = {81, 0, 141};
    if (read_png_rgb(path, rgb, 3))
        for (int i = 0; i < 3; i++)
            CHECK(rgb[i * 3] == want_auto[i], "reinhard, automatic: pixel %d = %u, want %u", i,
                  rgb[i * 3], want_auto[i]);
    /* An unknown operator is an error, not an image. */
    CHECK(xrad_image_write_png_tonemapped(path, key, 3, 1, (xrad_tonemap)7, 1, &err) ==
              XRAD_ERROR_INPUT,
          "tone mapping 7 accepted");
    CHECK(!strcmp(xrad_tonemap_name(XRAD_TONEMAP_REINHARD), "reinhard") &&
              xrad_tonemap_name((xrad_tonemap)7) == NULL,
          "tone mapping names");
}

static void test_nrmse(void)
{
    enum { W = 8, H = 4 };
    static float a[W * H * 4], b[W * H * 4];
    /* b spans [0, 2]; a = b + 0.1 everywhere: RMS = 0.1, NRMSE = 0.1 / 2. */
    for (int i = 0; i < W * H; i++)
        for (int c = 0; c < 4; c++) {
            b[i * 4 + c] = 2.0f * (float)i / (W * H - 1);
            a[i * 4 + c] = b[i * 4 + c] + 0.1f;
        }
    CHECK_REL(xrad_image_nrmse(a, b, W, H), 0.05, 1e-5);
    CHECK_ABS(xrad_image_nrmse(b, b, W, H), 0, 0);
    /* Only one channel of one pixel differs by d: RMS = d / sqrt(3 W H). */
    memcpy(a, b, sizeof(a));
    a[5 * 4 + 1] += 1.0f;
    CHECK_REL(xrad_image_nrmse(a, b, W, H), 1.0 / sqrt(3.0 * W * H) / 2.0, 1e-5);
    /* Constant reference: undefined, reported as negative. */
    for (int i = 0; i < W * H * 4; i++)
        b[i] = 1;
    CHECK(xrad_image_nrmse(a, b, W, H) < 0, "constant reference");
}

int main(void)
{
    char dir[] = "/tmp/xrad-test-image-XXXXXX";
    if (!mkdtemp(dir))
        return test_skip("cannot make a temporary directory");
    test_exr_roundtrip(dir);
    test_png_srgb(dir);
    test_png_reinhard(dir);
    test_exr_half_rgba();
    test_exr_channel(dir);
    test_exr_half_channel();
    test_nrmse();
    return test_finish();
}
