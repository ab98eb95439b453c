/* Error figures a reader can act on (README "Accuracy"): image-space mean
 * ratio and relative RMS over non-emitter pixels, element-space per-surface
 * mean ratios and element error percentiles. The thesis's NRMSE
 * (image_metrics.c) is kept beside them for comparison with its tables. */
#include <math.h>
#include <stdlib.h>

#include "core/error.h"
#include "core/metrics.h"

xrad_status xrad_image_compare(const float *a, const float *b, const float *emitter,
                               uint32_t width, uint32_t height, xrad_image_metrics *out,
                               xrad_error *err)
{
    *out = (xrad_image_metrics){0};
    out->nrmse = xrad_image_nrmse(a, b, width, height);
    size_t n = (size_t)width * height;
    double sa = 0, sb = 0, sd2 = 0;
    uint64_t count = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(b[i * 4 + 3] > 0) || (emitter && emitter[i] != 0))
            continue;
        for (int c = 0; c < 3; c++) {
            double av = a[i * 4 + c], bv = b[i * 4 + c];
            sa += av;
            sb += bv;
            sd2 += (av - bv) * (av - bv);
        }
        count++;
    }
    out->pixels = count;
    if (count == 0)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "no pixel shows a non-emitting surface in the reference");
    if (!(sb > 0))
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "the reference is black on every non-emitting surface");
    double mean_b = sb / (double)(count * 3);
    out->mean_ratio = sa / sb;
    out->rel_rms = sqrt(sd2 / (double)(count * 3)) / mean_b;
    return XRAD_OK;
}

static int cmp_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* Percentile by count of sorted values (nearest rank). */
static double percentile(const double *sorted, size_t n, double p)
{
    size_t k = (size_t)ceil(p * (double)n);
    return sorted[k > 0 ? k - 1 : 0];
}

xrad_status metrics_elements(const metrics_element *e, size_t n, uint32_t groups,
                             const unsigned char *skip, xrad_element_metrics *out,
                             double *group_ratio, xrad_error *err)
{
    *out = (xrad_element_metrics){0};
    double *ga = calloc((size_t)groups * 3 + 1, sizeof(double));
    double *rel = malloc(n * sizeof(double) + 1);
    if (!ga || !rel) {
        free(ga);
        free(rel);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "out of memory for %zu element errors", n);
    }
    double *gb = ga + groups, *garea = gb + groups;
    double area = 0, suma = 0, sumb = 0;
    for (size_t i = 0; i < n; i++) {
        if (e[i].group >= groups || skip[e[i].group])
            continue;
        ga[e[i].group] += e[i].area * e[i].a;
        gb[e[i].group] += e[i].area * e[i].b;
        garea[e[i].group] += e[i].area;
        suma += e[i].area * e[i].a;
        sumb += e[i].area * e[i].b;
        area += e[i].area;
        out->elements++;
    }
    xrad_status st = XRAD_OK;
    if (out->elements == 0 || !(area > 0)) {
        st = xrad_fail(err, XRAD_ERROR_INPUT, "no non-emitting element to compare");
        goto done;
    }
    /* The floor of every denominator: a surface or an element the light
     * never reaches would otherwise turn a tiny absolute error into an
     * unbounded relative one. */
    double floor_b = 1e-3 * sumb / area;
    if (!(floor_b > 0)) {
        st = xrad_fail(err, XRAD_ERROR_INPUT, "the reference is black on every non-emitting surface");
        goto done;
    }
    out->mean_ratio = suma / sumb;
    out->worst_ratio = 1;
    for (uint32_t g = 0; g < groups; g++) {
        double ratio = 1;
        if (!skip[g] && garea[g] > 0) {
            double ma = ga[g] / garea[g], mb = gb[g] / garea[g];
            ratio = 1 + (ma - mb) / fmax(mb, floor_b);
            /* The first counted surface stands until one is worse, so that
             * a perfect match names a compared surface, not an emitter. */
            if (out->surfaces++ == 0 || fabs(ratio - 1) > out->surface_error) {
                out->surface_error = fabs(ratio - 1);
                out->worst_surface = g;
                out->worst_ratio = ratio;
            }
        }
        if (group_ratio)
            group_ratio[g] = ratio;
    }
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (e[i].group < groups && !skip[e[i].group])
            rel[m++] = fabs(e[i].a - e[i].b) / fmax(e[i].b, floor_b);
    qsort(rel, m, sizeof(double), cmp_double);
    out->p50 = percentile(rel, m, 0.50);
    out->p95 = percentile(rel, m, 0.95);
    out->max = rel[m - 1];
done:
    free(ga);
    free(rel);
    return st;
}
