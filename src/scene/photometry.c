/* Photometric distributions: the table over the circle, lookup, flux, and
 * the text cursor the readers share (scene/photometry.h). */
#include "scene/photometry.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "core/error.h"
#include "scene/scene_internal.h"

#define DEG (M_PI / 180.0)

void photometry_free(photometry *p)
{
    free(p->c);
    free(p->g);
    free(p->cd);
    memset(p, 0, sizeof(*p));
}

xrad_status photometry_load(const char *path, photometry *out, xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    size_t n = strlen(path);
    bool ldt = n >= 4 && !strcasecmp(path + n - 4, ".ldt");
    bool ies = n >= 4 && !strcasecmp(path + n - 4, ".ies");
    if (!ldt && !ies)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: not a photometric file (the extension must be .ldt or .ies)",
                         path);
    char *text;
    size_t len;
    xrad_status st = scene_read_file(path, PHOTOMETRY_MAX_FILE_BYTES, &text, &len, err);
    if (st)
        return st;
    st = ldt ? photometry_parse_ldt(path, text, len, out, err)
             : photometry_parse_ies(path, text, len, out, err);
    free(text);
    return st;
}

/* ------------------------------------------------------------- the table */

/* a in [0, 360). */
static double wrap360(double a)
{
    a = fmod(a, 360.0);
    if (a < 0)
        a += 360.0;
    return a >= 360.0 ? 0.0 : a;
}

static bool same_angle(double a, double b)
{
    double d = fabs(wrap360(a) - wrap360(b));
    return d < 1e-6 || d > 360.0 - 1e-6;
}

/* The images of C under sym (C itself first). */
static uint32_t images(double c, photometry_symmetry sym, double out[4])
{
    out[0] = c;
    switch (sym) {
    case PHOTOMETRY_SYM_C0: out[1] = 360.0 - c; return 2;
    case PHOTOMETRY_SYM_C90: out[1] = 180.0 - c; return 2;
    case PHOTOMETRY_SYM_BOTH:
        out[1] = 360.0 - c;
        out[2] = 180.0 - c;
        out[3] = 180.0 + c;
        return 4;
    default: return 1;
    }
}

/* A plane of the table and the stored plane whose values it takes. */
typedef struct plane_ref {
    double c;   /* degrees, in [0, 360) */
    uint32_t s; /* index into the stored planes */
} plane_ref;

static int cmp_plane(const void *a, const void *b)
{
    double x = ((const plane_ref *)a)->c, y = ((const plane_ref *)b)->c;
    return (x > y) - (x < y);
}

xrad_status photometry_expand(photometry *p, const char *name, const char *field,
                              const double *c_stored, uint32_t ns, const double *values,
                              photometry_symmetry sym, xrad_error *err)
{
    if (ns == 0)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %s: no C-plane", name, field);
    uint32_t ng = p->ng;
    if (sym == PHOTOMETRY_SYM_AXIAL)
        ns = 1; /* one plane is all there is to it */
    /* Every stored plane at each of its images, each image remembering its
     * stored plane; sorted, duplicates (and 360 = 0) once. */
    plane_ref *r = malloc(sizeof(plane_ref) * 4 * ns);
    if (!r)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
    uint32_t nc = 0;
    for (uint32_t s = 0; s < ns; s++) {
        if (!isfinite(c_stored[s]) || c_stored[s] < -360.0 || c_stored[s] > 720.0) {
            free(r);
            return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %s: C angle %g out of range", name,
                             field, c_stored[s]);
        }
        double im[4] = {0};
        uint32_t n = sym == PHOTOMETRY_SYM_AXIAL ? 1 : images(c_stored[s], sym, im);
        for (uint32_t k = 0; k < n; k++)
            r[nc++] = (plane_ref){wrap360(im[k]), s};
    }
    qsort(r, nc, sizeof(plane_ref), cmp_plane);
    uint32_t unique = 0;
    for (uint32_t k = 0; k < nc; k++)
        if (unique == 0 || !same_angle(r[k].c, r[unique - 1].c))
            r[unique++] = r[k];
    if (unique > 1 && same_angle(r[unique - 1].c, r[0].c))
        unique--;
    nc = unique;
    double *c = malloc(sizeof(double) * nc);
    double *cd = malloc(sizeof(double) * (size_t)nc * ng);
    if (!c || !cd) {
        free(r);
        free(c);
        free(cd);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
    }
    for (uint32_t k = 0; k < nc; k++) {
        c[k] = r[k].c;
        memcpy(cd + (size_t)k * ng, values + (size_t)r[k].s * ng, sizeof(double) * ng);
    }
    free(r);
    p->nc = nc;
    p->c = c;
    p->cd = cd;
    return XRAD_OK;
}

/* The index i with a[i] <= x < a[i + 1] in ascending a[0, n), n >= 2,
 * a[0] <= x < a[n - 1]. */
static uint32_t segment(const double *a, uint32_t n, double x)
{
    uint32_t lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        uint32_t mid = (lo + hi) / 2;
        if (a[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Plane k's intensity at gamma, linear between the gammas; 0 outside. */
static double plane_at(const photometry *p, uint32_t k, double gamma)
{
    const double *g = p->g, *v = p->cd + (size_t)k * p->ng;
    uint32_t ng = p->ng;
    if (gamma < g[0] || gamma > g[ng - 1])
        return 0;
    if (ng == 1 || gamma == g[ng - 1])
        return v[ng - 1];
    uint32_t j = segment(g, ng, gamma);
    double t = (gamma - g[j]) / (g[j + 1] - g[j]);
    return v[j] * (1 - t) + v[j + 1] * t;
}

double photometry_intensity(const photometry *p, double c_deg, double gamma_deg)
{
    if (!p->nc || !p->ng || !isfinite(c_deg) || !isfinite(gamma_deg))
        return 0;
    if (p->nc == 1)
        return plane_at(p, 0, gamma_deg);
    double c = wrap360(c_deg);
    uint32_t k0, k1;
    double t;
    if (c >= p->c[0] && c < p->c[p->nc - 1]) {
        k0 = segment(p->c, p->nc, c);
        k1 = k0 + 1;
        t = (c - p->c[k0]) / (p->c[k1] - p->c[k0]);
    } else { /* between the last plane and the first, across 360 */
        k0 = p->nc - 1;
        k1 = 0;
        double span = p->c[0] + 360.0 - p->c[k0];
        t = ((c < p->c[0] ? c + 360.0 : c) - p->c[k0]) / span;
    }
    return plane_at(p, k0, gamma_deg) * (1 - t) + plane_at(p, k1, gamma_deg) * t;
}

double photometry_flux(const photometry *p)
{
    if (!p->nc || p->ng < 2)
        return 0;
    double sum = 0;
    for (uint32_t k = 0; k < p->nc; k++) {
        /* The C part of the bilinear cell integrates to the width times the
         * mean of its two planes; each plane's share is half of each
         * neighbouring width. */
        double width;
        if (p->nc == 1)
            width = 2 * M_PI;
        else {
            double prev = k ? p->c[k - 1] : p->c[p->nc - 1] - 360.0;
            double next = k + 1 < p->nc ? p->c[k + 1] : p->c[0] + 360.0;
            width = 0.5 * (next - prev) * DEG;
        }
        const double *v = p->cd + (size_t)k * p->ng;
        for (uint32_t j = 0; j + 1 < p->ng; j++) {
            /* Linear in gamma over [g0, g1]: with t = (gamma - g0) / h,
             * int t sin = (sin g1 - sin g0) / h - cos g1 and
             * int (1 - t) sin = cos g0 - cos g1 - that. */
            double g0 = p->g[j] * DEG, g1 = p->g[j + 1] * DEG, h = g1 - g0;
            if (!(h > 0))
                continue;
            double t1 = (sin(g1) - sin(g0)) / h - cos(g1);
            double t0 = cos(g0) - cos(g1) - t1;
            sum += width * (v[j] * t0 + v[j + 1] * t1);
        }
    }
    return sum;
}

/* -------------------------------------------------------- the text cursor */

bool photometry_text_line(photometry_text *t, char *out, size_t n)
{
    if (t->p >= t->end)
        return false;
    const char *s = t->p;
    while (t->p < t->end && *t->p != '\n' && *t->p != '\r')
        t->p++;
    size_t len = (size_t)(t->p - s);
    if (len > n - 1)
        len = n - 1;
    memcpy(out, s, len);
    out[len] = 0;
    if (t->p < t->end) /* the line's end: \n, \r\n or \r */
        t->p += *t->p == '\r' && t->p + 1 < t->end && t->p[1] == '\n' ? 2 : 1;
    t->line++;
    return true;
}

bool photometry_number(const char *s, double *out)
{
    char buf[64];
    while (isspace((unsigned char)*s))
        s++;
    size_t n = 0;
    for (; s[n] && !isspace((unsigned char)s[n]); n++) {
        if (n + 1 >= sizeof(buf))
            return false;
        buf[n] = s[n] == ',' ? '.' : s[n];
    }
    buf[n] = 0;
    for (size_t k = n; s[k]; k++) /* nothing but white space after it */
        if (!isspace((unsigned char)s[k]))
            return false;
    if (n == 0)
        return false;
    char *e;
    double v = strtod(buf, &e);
    if (*e || !isfinite(v))
        return false;
    *out = v;
    return true;
}

bool photometry_text_number(photometry_text *t, double *out)
{
    /* Skip white space and commas, counting lines. */
    while (t->p < t->end && (isspace((unsigned char)*t->p) || *t->p == ',')) {
        if (*t->p == '\n')
            t->line++;
        t->p++;
    }
    if (t->p >= t->end)
        return false;
    char buf[64];
    size_t n = 0;
    while (t->p < t->end && !isspace((unsigned char)*t->p) && *t->p != ',') {
        if (n + 1 < sizeof(buf))
            buf[n++] = *t->p;
        else
            return false;
        t->p++;
    }
    buf[n] = 0;
    char *e;
    double v = strtod(buf, &e);
    if (*e || !isfinite(v))
        return false;
    *out = v;
    return true;
}

/* ------------------------------------------------------------- public API */

struct xrad_photometry {
    photometry p;
};

xrad_status xrad_photometry_load(const char *path, xrad_photometry **out, xrad_error *err)
{
    *out = NULL;
    xrad_photometry *x = calloc(1, sizeof(*x));
    if (!x)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", path);
    xrad_status st = photometry_load(path, &x->p, err);
    if (st) {
        free(x);
        return st;
    }
    *out = x;
    return XRAD_OK;
}

void xrad_photometry_destroy(xrad_photometry **p)
{
    if (!p || !*p)
        return;
    photometry_free(&(*p)->p);
    free(*p);
    *p = NULL;
}

void xrad_photometry_get_info(const xrad_photometry *x, xrad_photometry_info *out)
{
    const photometry *p = &x->p;
    memset(out, 0, sizeof(*out));
    out->c_planes = p->nc;
    out->gamma_angles = p->ng;
    out->gamma_min = p->g[0];
    out->gamma_max = p->g[p->ng - 1];
    for (uint32_t k = 0; k < p->nc; k++)
        for (uint32_t j = 0; j < p->ng; j++)
            if (p->cd[(size_t)k * p->ng + j] > out->max_intensity) {
                out->max_intensity = p->cd[(size_t)k * p->ng + j];
                out->max_c = p->c[k];
                out->max_gamma = p->g[j];
            }
    out->flux_stated = p->flux;
    out->flux = photometry_flux(p);
    out->tilt_ignored = p->tilt_ignored;
}

double xrad_photometry_intensity(const xrad_photometry *x, double c_deg, double gamma_deg)
{
    return photometry_intensity(&x->p, c_deg, gamma_deg);
}
