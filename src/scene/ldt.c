/*
 * EULUMDAT (.ldt) reader (Wallner 3.2; the format as Ashdown's English
 * translation of the specification lays it out): one field a line, lines
 * 1-26f the header, then 10 direct ratios, Mc C angles, Ng gamma angles
 * and the intensities of the C-planes that the symmetry indicator Isym
 * says are stored, in cd per 1000 lm of the lamps' flux.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/photometry.h"

typedef struct reader {
    photometry_text t;
    char line[512];
    uint32_t at; /* the line number of `line` */
    xrad_error *err;
    xrad_status st;
} reader;

static bool next_line(reader *r, const char *field)
{
    if (r->st)
        return false;
    r->at = r->t.line;
    if (!photometry_text_line(&r->t, r->line, sizeof(r->line))) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT, "%s: line %u (%s): the file ends before it",
                          r->t.name, r->at, field);
        return false;
    }
    return true;
}

/* The next line as a number in [lo, hi]. */
static bool number(reader *r, const char *field, double lo, double hi, double *out)
{
    if (!next_line(r, field))
        return false;
    double v;
    if (!photometry_number(r->line, &v) || v < lo || v > hi) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT,
                          "%s: line %u (%s): '%.40s' is not a number in [%g, %g]", r->t.name,
                          r->at, field, r->line, lo, hi);
        return false;
    }
    *out = v;
    return true;
}

/* The next line as a whole number in [lo, hi]. */
static bool integer(reader *r, const char *field, int lo, int hi, int *out)
{
    double v;
    if (!number(r, field, lo, hi, &v))
        return false;
    if (v != floor(v)) {
        r->st = xrad_fail(r->err, XRAD_ERROR_INPUT, "%s: line %u (%s): %g is not a whole number",
                          r->t.name, r->at, field, v);
        return false;
    }
    *out = (int)v;
    return true;
}

static void skip(reader *r, const char *field, int count)
{
    for (int i = 0; i < count; i++)
        next_line(r, field);
}

xrad_status photometry_parse_ldt(const char *name, const char *text, size_t len, photometry *out,
                                 xrad_error *err)
{
    memset(out, 0, sizeof(*out));
    reader r = {.t = {.name = name, .p = text, .end = text + len, .line = 1}, .err = err};
    int ityp = 0, isym = 0, mc = 0, ng = 0, sets = 0;
    double dummy, lorl = 0, cfli = 1;
    const int max = (int)PHOTOMETRY_MAX_ANGLES;
    skip(&r, "company identification", 1);
    integer(&r, "Ityp, type indicator", 0, 3, &ityp);
    integer(&r, "Isym, symmetry indicator", 0, 4, &isym);
    integer(&r, "Mc, number of C-planes", 1, max, &mc);
    number(&r, "Dc, distance between C-planes", 0, 360, &dummy);
    integer(&r, "Ng, number of gamma angles", 2, max, &ng);
    number(&r, "Dg, distance between gamma angles", 0, 180, &dummy);
    skip(&r, "measurement report, luminaire name and number, file name, date", 5);
    for (int i = 0; i < 9; i++)
        number(&r, "luminaire and luminous area dimensions", -1e9, 1e9, &dummy);
    number(&r, "DFF, downward flux fraction", -1e-9, 100 + 1e-9, &dummy);
    number(&r, "LORL, light output ratio", 0, 100 + 1e-9, &lorl);
    number(&r, "conversion factor for luminous intensities", 0, 1e9, &cfli);
    number(&r, "tilt of luminaire during measurement", -360, 360, &dummy);
    integer(&r, "n, number of standard sets of lamps", 1, 20, &sets);
    /* Lines 26a-f, each over the sets: lamp counts (negative for absolute
     * photometry, the flux then the luminaire's), types, total flux,
     * colour, colour rendering, wattage. */
    double lamp_flux = 0, v;
    for (int s = 0; s < sets; s++)
        number(&r, "26a, number of lamps", -1e6, 1e6, &v);
    skip(&r, "26b, type of lamps", sets);
    for (int s = 0; s < sets; s++)
        if (number(&r, "26c, total luminous flux of lamps", 0, 1e12, &v))
            lamp_flux += v;
    skip(&r, "26d-e, colour appearance and rendering", 2 * sets);
    for (int s = 0; s < sets; s++)
        number(&r, "26f, wattage including ballast", -1e9, 1e12, &v);
    for (int i = 0; i < 10; i++)
        number(&r, "27, direct ratios", -1e9, 1e9, &dummy);
    if (r.st)
        return r.st;
    if ((isym == 3 || isym == 4) && mc % 4 != 0)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: line 4 (Mc): %d C-planes cannot be mirrored as Isym %d says "
                         "(a multiple of 4 is needed)",
                         name, mc, isym);
    if (isym == 2 && mc % 2 != 0)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: line 4 (Mc): %d C-planes cannot be mirrored in C0-C180 (Isym 2)",
                         name, mc);
    /* The stored planes, 1-based Mc1..Mc2 of the Mc angles (Isym 3 wraps
     * past C360: C270 to C90 through C0). */
    int mc1 = 1, mc2 = mc;
    switch (isym) {
    case 1: mc2 = 1; break;
    case 2: mc2 = mc / 2 + 1; break;
    case 3: mc1 = 3 * mc / 4 + 1; mc2 = mc1 + mc / 2; break;
    case 4: mc2 = mc / 4 + 1; break;
    default: break;
    }
    uint32_t ns = (uint32_t)(mc2 - mc1 + 1);
    /* A value a line: counts the text cannot hold are refused before
     * anything is allocated for them. */
    if ((size_t)ns * (size_t)ng > len / 2)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: %u x %d intensities cannot fit in the file's %zu bytes", name, ns,
                         ng, len);
    double *c_all = malloc(sizeof(double) * (size_t)mc);
    double *c_stored = malloc(sizeof(double) * ns);
    double *g = malloc(sizeof(double) * (size_t)ng);
    double *values = malloc(sizeof(double) * ns * (size_t)ng);
    xrad_status st = XRAD_OK;
    if (!c_all || !c_stored || !g || !values) {
        st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
        goto done;
    }
    for (int i = 0; i < mc; i++)
        if (number(&r, "28, C angles", 0, 360, &c_all[i]) && i > 0 && !(c_all[i] > c_all[i - 1]))
            r.st = xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: line %u (28, C angles): %g after %g; they must ascend", name,
                             r.at, c_all[i], c_all[i - 1]);
    for (int i = 0; i < ng; i++)
        if (number(&r, "29, gamma angles", 0, 180, &g[i]) && i > 0 && !(g[i] > g[i - 1]))
            r.st = xrad_fail(err, XRAD_ERROR_INPUT,
                             "%s: line %u (29, gamma angles): %g after %g; they must ascend",
                             name, r.at, g[i], g[i - 1]);
    for (uint32_t s = 0; s < ns; s++)
        c_stored[s] = c_all[(mc1 - 1 + (int)s) % mc];
    /* cd/klm of the lamps' flux to cd (and the file's own factor). */
    double scale = lamp_flux / 1000.0 * cfli;
    for (size_t i = 0; i < (size_t)ns * (size_t)ng; i++)
        if (number(&r, "30, luminous intensities", 0, 1e12, &values[i]))
            values[i] *= scale;
    if ((st = r.st))
        goto done;
    out->ng = (uint32_t)ng;
    out->g = g;
    g = NULL;
    static const photometry_symmetry sym[5] = {PHOTOMETRY_SYM_NONE, PHOTOMETRY_SYM_AXIAL,
                                               PHOTOMETRY_SYM_C0, PHOTOMETRY_SYM_C90,
                                               PHOTOMETRY_SYM_BOTH};
    st = photometry_expand(out, name, "28-30, C-planes", c_stored, ns, values, sym[isym], err);
    /* Wallner 3.2: the luminaire's flux is the lamps' times its light
     * output ratio. */
    out->flux = lamp_flux * lorl / 100.0;

done:
    free(c_all);
    free(c_stored);
    free(g);
    free(values);
    if (st)
        photometry_free(out);
    return st;
}
