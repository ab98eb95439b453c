/* Image comparison and exposure. */
#include <math.h>
#include <stdlib.h>

#include "xrad.h"

double xrad_image_nrmse(const float *a, const float *b, uint32_t width, uint32_t height)
{
    size_t n = (size_t)width * height;
    double lo = INFINITY, hi = -INFINITY, sum = 0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++) {
            double bv = b[i * 4 + c], d = (double)a[i * 4 + c] - bv;
            lo = fmin(lo, bv);
            hi = fmax(hi, bv);
            sum += d * d;
        }
    }
    if (n == 0 || !(hi > lo))
        return -1;
    return sqrt(sum / (double)(n * 3)) / (hi - lo);
}

static int cmp_float(const void *x, const void *y)
{
    float a = *(const float *)x, b = *(const float *)y;
    return (a > b) - (a < b);
}

/* Rec. 709 luminance of pixel i. */
static float luminance(const float *rgba, size_t i)
{
    return 0.2126f * rgba[i * 4] + 0.7152f * rgba[i * 4 + 1] + 0.0722f * rgba[i * 4 + 2];
}

double xrad_image_auto_exposure(const float *rgba, uint32_t width, uint32_t height)
{
    size_t n = (size_t)width * height, count = 0;
    float *lum = malloc(n * sizeof(float) + 1);
    if (!lum)
        return 1;
    for (size_t i = 0; i < n; i++) {
        float y = luminance(rgba, i);
        if (y > 0 && isfinite(y))
            lum[count++] = y;
    }
    double exposure = 1;
    if (count > 0) {
        qsort(lum, count, sizeof(float), cmp_float);
        double p95 = lum[(size_t)((double)(count - 1) * 0.95)];
        if (p95 > 0)
            exposure = 0.8 / p95;
    }
    free(lum);
    return exposure;
}

double xrad_image_key_exposure(const float *rgba, uint32_t width, uint32_t height)
{
    /* Reinhard et al. 2002, eq. 1: exp of the mean log luminance; their
     * delta against log(0) is not needed where the zeros are left out. */
    size_t n = (size_t)width * height, count = 0;
    double sum = 0;
    for (size_t i = 0; i < n; i++) {
        double y = luminance(rgba, i);
        if (y > 0 && isfinite(y)) {
            sum += log(y);
            count++;
        }
    }
    if (count == 0)
        return 1;
    return 0.18 / exp(sum / (double)count); /* eq. 2, key a = 0.18 */
}

double xrad_image_tonemap_exposure(xrad_tonemap tonemap, const float *rgba, uint32_t width,
                                   uint32_t height)
{
    return tonemap == XRAD_TONEMAP_REINHARD ? xrad_image_key_exposure(rgba, width, height)
                                            : xrad_image_auto_exposure(rgba, width, height);
}

const char *xrad_tonemap_name(xrad_tonemap tonemap)
{
    switch (tonemap) {
    case XRAD_TONEMAP_EXPOSURE: return "exposure";
    case XRAD_TONEMAP_REINHARD: return "reinhard";
    }
    return NULL;
}
