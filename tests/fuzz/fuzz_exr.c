/*
 * libFuzzer harness for the OpenEXR reader (xrad_image_read_exr, what
 * `xrad compare` feeds user files to): any file must end either in an RGBA
 * float image of the size the reader promises or in an error that keeps the
 * error contract of include/xrad.h. The reader takes a path, so each input
 * is written to one temporary file first (in $TMPDIR, else /tmp; removed at
 * exit).
 *
 * Only xrad's side is instrumented for coverage; OpenEXRCore is the system
 * library, so its bugs show up only through the sanitizers' interceptors and
 * through what it hands back to xrad.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "xrad.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char tmp_path[4096];

static void violated(const char *what)
{
    fprintf(stderr, "fuzz_exr: invariant violated: %s\n", what);
    abort();
}

#define REQUIRE(cond)                                                        \
    do {                                                                     \
        if (!(cond))                                                         \
            violated(#cond);                                                 \
    } while (0)

static void remove_tmp(void)
{
    if (tmp_path[0])
        unlink(tmp_path);
}

/* The input's file, created on first use. */
static const char *input_path(void)
{
    if (tmp_path[0])
        return tmp_path;
    const char *dir = getenv("TMPDIR");
    snprintf(tmp_path, sizeof(tmp_path), "%s/xrad-fuzz-exr-XXXXXX", dir && *dir ? dir : "/tmp");
    int fd = mkstemp(tmp_path);
    if (fd < 0) {
        perror("fuzz_exr: mkstemp");
        abort();
    }
    close(fd);
    atexit(remove_tmp);
    return tmp_path;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = input_path();
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, size, f) != size || fclose(f) != 0) {
        perror("fuzz_exr: writing the input");
        abort();
    }

    float *rgba = NULL;
    uint32_t w = 0, h = 0;
    xrad_error err;
    memset(&err, 0, sizeof(err));
    xrad_status st = xrad_image_read_exr(path, &rgba, &w, &h, &err);
    if (st != XRAD_OK) {
        REQUIRE(st == XRAD_ERROR_INPUT || st == XRAD_ERROR_SYSTEM);
        REQUIRE(err.status == st);
        REQUIRE(memchr(err.message, '\0', sizeof(err.message)) != NULL);
        REQUIRE(strstr(err.message, path) != NULL);
        REQUIRE(rgba == NULL);
        return 0;
    }
    REQUIRE(rgba != NULL);
    REQUIRE(w >= 1 && h >= 1);
    /* Every promised texel is there: reading them all lets the sanitizers
     * and valgrind catch a short buffer. The sum is only there to keep the
     * reads from being optimised away. */
    volatile float sum = 0;
    for (size_t i = 0; i < (size_t)w * h * 4; i++)
        sum += rgba[i];
    (void)sum;
    free(rgba);
    return 0;
}
