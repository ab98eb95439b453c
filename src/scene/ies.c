/*
 * IES LM-63 (.ies) reader, the 2002 revision and the earlier ones alike:
 * keyword lines up to TILT=, then numbers separated by white space or
 * commas wherever the lines break: lamps, lumens per lamp, candela
 * multiplier, vertical and horizontal angle counts, photometric type (1:
 * type C, the only one read), units, dimensions, ballast factor, ballast-
 * lamp factor, watts, the vertical angles, the horizontal angles and the
 * candela values plane by plane. The horizontal angles' range says the
 * symmetry (LM-63-2002 section 5.13): 0 alone, 0-90, 0-180, 90-270, 0-360.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/photometry.h"

typedef struct reader {
    photometry_text t;
    xrad_error *err;
    xrad_status st;
} reader;

static bool number(reader *r, const char *field, double lo, double hi, double *out)
{
    if (r->st)
        return false;
    double v;
    if (!photometry_text_number(&r->t, &v)) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT, "%s: line %u (%s): %s", r->t.name,
                          r->t.line, field,
                          r->t.p >= r->t.end ? "the file ends before it" : "not a number");
        return false;
    }
    if (v < lo || v > hi) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT, "%s: line %u (%s): %g is not in [%g, %g]",
                          r->t.name, r->t.line, field, v, lo, hi);
        return false;
    }
    *out = v;
    return true;
}

static bool count(reader *r, const char *field, uint32_t lo, uint32_t hi, uint32_t *out)
{
    double v;
    if (!number(r, field, lo, hi, &v))
        return false;
    if (v != floor(v)) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT, "%s: line %u (%s): %g is not a whole number",
                          r->t.name, r->t.line, field, v);
        return false;
    }
    *out = (uint32_t)v;
    return true;
}

/* Reads n ascending angles in [lo, hi]. */
static void angles(reader *r, const char *field, double lo, double hi, double *a, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (number(r, field, lo, hi, &a[i]) && i > 0 && !(a[i] > a[i - 1]))
            r->st = xrad_fail(r->err, XRAD_ERROR_INPUT,
                              "%s: line %u (%s): %g after %g; they must ascend", r->t.name,
                              r->t.line, field, a[i], a[i - 1]);
}

xrad_status photometry_parse_ies(const char *name, const char *text, size_t len, photometry *out,
                                 xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    reader r = {.t = {.name = name, .p = text, .end = text + len, .line = 1}, .err = err};
    /* The first line (IESNA:LM-63-2002, or older) and the keywords, up to
     * the TILT line. */
    char line[512];
    bool tilt = false;
    while (photometry_text_line(&r.t, line, sizeof(line))) {
        if (!strncmp(line, "TILT=", 5)) {
            tilt = true;
            break;
        }
    }
    if (!tilt)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: no TILT= line (not an IES LM-63 file)",
                         name);
    double v;
    uint32_t tilt_line = r.t.line - 1;
    if (!strcmp(line + 5, "INCLUDE")) {
        /* Lamp tilt factors, for a lamp burned at another angle than it
         * was measured at: read past, not applied (photometry.h). */
        uint32_t n = 0;
        number(&r, "TILT lamp-to-luminaire geometry", 1, 3, &v);
        count(&r, "TILT angle count", 0, PHOTOMETRY_MAX_ANGLES, &n);
        for (uint32_t i = 0; i < 2 * n; i++)
            number(&r, i < n ? "TILT angles" : "TILT multiplying factors", -1e9, 1e9, &v);
        out->tilt_ignored = true;
    } else if (strcmp(line + 5, "NONE") != 0) {
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: line %u (TILT): '%.40s': tilt data in another file is not read; "
                         "NONE or INCLUDE",
                         name, tilt_line, line + 5);
    }
    double lamps = 0, lumens = 0, multiplier = 1, type = 0, ballast = 1, lamp_factor = 1;
    uint32_t nv = 0, nh = 0;
    number(&r, "number of lamps", 0, 1e6, &lamps);
    number(&r, "lumens per lamp", -1, 1e12, &lumens);
    number(&r, "candela multiplier", 0, 1e12, &multiplier);
    count(&r, "number of vertical angles", 2, PHOTOMETRY_MAX_ANGLES, &nv);
    count(&r, "number of horizontal angles", 1, PHOTOMETRY_MAX_ANGLES, &nh);
    number(&r, "photometric type", 1, 3, &type);
    number(&r, "units type", 1, 2, &v);
    for (int i = 0; i < 3; i++)
        number(&r, "luminous opening width, length, height", -1e9, 1e9, &v);
    number(&r, "ballast factor", 0, 1e6, &ballast);
    number(&r, "ballast-lamp photometric factor", 0, 1e6, &lamp_factor);
    number(&r, "input watts", -1e9, 1e12, &v);
    if (r.st)
        return r.st;
    if (type != 1)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: photometric type %g (%s): only type C (1) is read", name, type,
                         type == 2 ? "B" : "A");
    /* Each value takes two bytes at least: counts the text cannot hold are
     * refused before anything is allocated for them. */
    if ((size_t)nv * nh > len / 2)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: %u x %u candela values cannot fit in the file's %zu bytes", name,
                         nv, nh, len);
    double *g = malloc(sizeof(double) * nv);
    double *h = malloc(sizeof(double) * nh);
    double *values = malloc(sizeof(double) * (size_t)nv * nh);
    xrad_status st = XRAD_OK;
    if (!g || !h || !values) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
        goto done;
    }
    angles(&r, "vertical angles", 0, 180, g, nv);
    angles(&r, "horizontal angles", 0, 360, h, nh);
    double scale = multiplier * ballast * lamp_factor;
    for (size_t i = 0; i < (size_t)nv * nh; i++)
        if (number(&r, "candela values", 0, 1e12, &values[i]))
            values[i] *= scale;
    if ((st = r.st))
        goto done;
    photometry_symmetry sym;
    double first = h[0], last = h[nh - 1];
    if (nh == 1 && first == 0)
        sym = PHOTOMETRY_SYM_AXIAL;
    else if (first == 0 && last == 90)
        sym = PHOTOMETRY_SYM_BOTH;
    else if (first == 0 && last == 180)
        sym = PHOTOMETRY_SYM_C0;
    else if (first == 90 && last == 270)
        sym = PHOTOMETRY_SYM_C90;
    else if (first == 0 && last == 360)
        sym = PHOTOMETRY_SYM_NONE;
    else {
        st = xrad_fail(err, XRAD_ERROR_INPUT,
                       "%s: horizontal angles %g to %g: none of 0, 0-90, 0-180, 90-270, 0-360 "
                       "(LM-63-2002 5.13)",
                       name, first, last);
        goto done;
    }
    out->ng = nv;
    out->g = g;
    g = NULL;
    st = photometry_expand(out, name, "horizontal angles", h, nh, values, sym, err);
    /* The lamps' rated flux; -1 lumens per lamp marks absolute photometry,
     * which states none. */
    out->flux = lumens > 0 ? lamps * lumens : 0;

done:
    free(g);
    free(h);
    free(values);
    if (st)
        photometry_free(out);
    return st;
}
