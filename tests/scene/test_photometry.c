/*
 * The EULUMDAT and IES readers (src/scene/ldt.c, ies.c, photometry.c)
 * against distributions known in closed form:
 *  - the shipped asymmetric files (tools/gen_photometry.py: I = I0 cos(g)
 *    (1 + 0.5 cos C + 0.3 sin C) below the horizon, 1000 lm): the integral
 *    of I over the sphere equals the file's luminous flux within 1% (and
 *    over 683, its radiant flux in W, Wallner eq. 12); C0, C90, C180 and
 *    C270 each read as their own plane (1.5, 1.3, 0.5, 0.7 I0 straight
 *    down), every stored (C, gamma) to the file's rounding, between them
 *    within the bilinear interpolation's error, nothing above the horizon;
 *  - every symmetry of both formats, files written here with only the
 *    planes the format stores for it, from a function with that symmetry:
 *    every 15 degrees of C and 5 of gamma reads the function;
 *  - bad files: errors that name the file, the line and the field.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "scene/photometry.h"

#define I0 (1000.0 / M_PI)
#define DEG (M_PI / 180.0)

/* Memory for the test's own texts; none is a failure of the machine. */
static void *must(void *p)
{
    if (!p) {
        fprintf(stderr, "test_photometry: out of memory\n");
        exit(1);
    }
    return p;
}

static double asym(double c, double g)
{
    return g > 90 ? 0 : I0 * cos(g * DEG) * (1 + 0.5 * cos(c * DEG) + 0.3 * sin(c * DEG));
}

static void check_asymmetric(const char *rel)
{
    char path[1024];
    test_source_path(rel, path, sizeof(path));
    photometry p;
    xrad_error err = {0};
    xrad_status st = photometry_load(path, &p, &err);
    CHECK(st == XRAD_OK, "%s: %s", rel, err.message);
    if (st)
        return;
    double flux = photometry_flux(&p);
    CHECK_REL(flux, 1000.0, 0.01);
    CHECK_REL(flux, p.flux, 0.01);
    CHECK_REL(flux / PHOTOMETRY_LM_PER_W, 1000.0 / 683.0, 0.01);
    /* The four main planes straight down: each its own. */
    const double down[4] = {1.5, 1.3, 0.5, 0.7};
    for (int k = 0; k < 4; k++)
        CHECK(fabs(photometry_intensity(&p, 90.0 * k, 0) - down[k] * I0) < 1e-3,
              "%s: C%d straight down %.4f cd, want %.4f", rel, 90 * k,
              photometry_intensity(&p, 90.0 * k, 0), down[k] * I0);
    /* Every stored sample, and points between them. */
    double worst = 0, worst_mid = 0;
    for (int c = 0; c < 360; c += 15)
        for (int g = 0; g <= 90; g += 5)
            worst = fmax(worst, fabs(photometry_intensity(&p, c, g) - asym(c, g)));
    for (double c = 7.5; c < 360; c += 15)
        for (double g = 2.5; g < 90; g += 5)
            worst_mid = fmax(worst_mid, fabs(photometry_intensity(&p, c, g) - asym(c, g)) / I0);
    CHECK(worst < 1e-3, "%s: a stored sample read %.2e cd off", rel, worst);
    CHECK(worst_mid < 0.01, "%s: between samples %.4f of I0 off", rel, worst_mid);
    CHECK(photometry_intensity(&p, 30, 120) == 0 && photometry_intensity(&p, 200, 179) == 0,
          "%s: light above the horizon", rel);
    /* C wraps: -90 is C270, 450 is C90. */
    CHECK(fabs(photometry_intensity(&p, -90, 0) - 0.7 * I0) < 1e-3 &&
              fabs(photometry_intensity(&p, 450, 0) - 1.3 * I0) < 1e-3,
          "%s: C does not wrap around the circle", rel);
    photometry_free(&p);
}

/* Functions of C with each symmetry (gamma: cos below the horizon), each
 * integrating to 2 pi over C so that the flux is 1000 lm. */
static double sym_f(int sym, double c)
{
    switch (sym) {
    case PHOTOMETRY_SYM_AXIAL: return 1;
    case PHOTOMETRY_SYM_C0: return 1 + 0.5 * cos(c * DEG);       /* f(360 - C) = f(C) */
    case PHOTOMETRY_SYM_C90: return 1 + 0.3 * sin(c * DEG);      /* f(180 - C) = f(C) */
    case PHOTOMETRY_SYM_BOTH: return 1 + 0.4 * cos(2 * c * DEG); /* both */
    default: return 1 + 0.5 * cos(c * DEG) + 0.3 * sin(c * DEG);
    }
}

static double sym_i(int sym, double c, double g)
{
    return g > 90 ? 0 : I0 * cos(g * DEG) * sym_f(sym, c);
}

/* An EULUMDAT text with Isym `isym`: 24 C-planes, 37 gammas, the planes
 * the specification stores for it (Mc1..Mc2), lamps of 1000 lm, LORL 100. */
static char *write_ldt(int isym, int sym)
{
    size_t cap = 1 << 16, n = 0;
    char *s = must(malloc(cap));
#define PUT(...) n += (size_t)snprintf(s + n, cap - n, __VA_ARGS__)
    PUT("test\n1\n%d\n24\n15\n37\n5\nr\nname\nnumber\nfile\ndate\n", isym);
    for (int i = 0; i < 9; i++)
        PUT("0\n");
    PUT("100\n100\n1\n0\n1\n1\nLED\n1000\n3000\n1A\n10\n");
    for (int i = 0; i < 10; i++)
        PUT("0.5\n");
    for (int i = 0; i < 24; i++)
        PUT("%d\n", 15 * i);
    for (int i = 0; i < 37; i++)
        PUT("%d\n", 5 * i);
    int mc1 = 1, mc2 = 24;
    switch (isym) {
    case 1: mc2 = 1; break;
    case 2: mc2 = 13; break;
    case 3: mc1 = 19; mc2 = 31; break;
    case 4: mc2 = 7; break;
    }
    for (int k = mc1; k <= mc2; k++)
        for (int j = 0; j < 37; j++)
            PUT("%.9f\n", sym_i(sym, 15.0 * ((k - 1) % 24), 5.0 * j));
#undef PUT
    return s;
}

/* An IES text whose horizontal angles run first..last in 15 degree steps. */
static char *write_ies(int first, int last, int sym)
{
    size_t cap = 1 << 16, n = 0;
    char *s = must(malloc(cap));
    int nh = (last - first) / 15 + 1;
#define PUT(...) n += (size_t)snprintf(s + n, cap - n, __VA_ARGS__)
    PUT("IESNA:LM-63-2002\r\n[TEST] symmetric\r\nTILT=NONE\r\n1 1000 1 19 %d 1 2 0 0 0\r\n1 1 "
        "10\r\n",
        nh);
    for (int j = 0; j < 19; j++)
        PUT("%d ", 5 * j);
    PUT("\r\n");
    for (int h = 0; h < nh; h++)
        PUT("%d%s", first + 15 * h, h + 1 < nh ? ", " : "\r\n");
    for (int h = 0; h < nh; h++)
        for (int j = 0; j < 19; j++)
            PUT("%.9f%s", sym_i(sym, first + 15.0 * h, 5.0 * j), j % 7 == 6 ? "\r\n" : " ");
#undef PUT
    return s;
}

static void check_symmetric(const char *label, const char *text, bool ldt, int sym)
{
    photometry p;
    xrad_error err = {0};
    xrad_status st = ldt ? photometry_parse_ldt(label, text, strlen(text), &p, &err)
                         : photometry_parse_ies(label, text, strlen(text), &p, &err);
    CHECK(st == XRAD_OK, "%s: %s", label, err.message);
    if (st)
        return;
    double worst = 0;
    for (int c = 0; c < 360; c += 15)
        for (int g = 0; g <= 90; g += 5)
            worst = fmax(worst, fabs(photometry_intensity(&p, c, g) - sym_i(sym, c, g)));
    CHECK(worst < 1e-6, "%s: a plane reads %.3g cd off its mirror image", label, worst);
    CHECK(p.nc == (sym == PHOTOMETRY_SYM_AXIAL ? 1u : 24u), "%s: %u C-planes", label, p.nc);
    CHECK_REL(photometry_flux(&p), 1000.0, 0.01);
    CHECK_REL(p.flux, 1000.0, 1e-12);
    photometry_free(&p);
}

/* A reader's error on `text`: XRAD_ERROR_INPUT, every `want` in it. */
static void check_error(const char *label, const char *text, bool ldt, const char *want1,
                        const char *want2)
{
    photometry p;
    xrad_error err = {0};
    xrad_status st = ldt ? photometry_parse_ldt("bad.file", text, strlen(text), &p, &err)
                         : photometry_parse_ies("bad.file", text, strlen(text), &p, &err);
    CHECK(st == XRAD_ERROR_INPUT, "%s: status %d", label, st);
    CHECK(strstr(err.message, "bad.file") && strstr(err.message, want1) &&
              (!want2 || strstr(err.message, want2)),
          "%s: '%s' does not name '%s' and '%s'", label, err.message, want1, want2 ? want2 : "");
    CHECK(p.c == NULL && p.g == NULL && p.cd == NULL, "%s: tables left allocated", label);
}

int main(void)
{
    check_asymmetric("tests/data/photometry/asymmetric.ldt");
    check_asymmetric("tests/data/photometry/asymmetric.ies");

    const int ldt_sym[5] = {PHOTOMETRY_SYM_NONE, PHOTOMETRY_SYM_AXIAL, PHOTOMETRY_SYM_C0,
                            PHOTOMETRY_SYM_C90, PHOTOMETRY_SYM_BOTH};
    for (int isym = 0; isym <= 4; isym++) {
        char label[32];
        snprintf(label, sizeof(label), "ldt Isym %d", isym);
        char *t = write_ldt(isym, ldt_sym[isym]);
        check_symmetric(label, t, true, ldt_sym[isym]);
        free(t);
    }
    const struct {
        int first, last, sym;
    } ies[5] = {{0, 0, PHOTOMETRY_SYM_AXIAL},
                {0, 90, PHOTOMETRY_SYM_BOTH},
                {0, 180, PHOTOMETRY_SYM_C0},
                {90, 270, PHOTOMETRY_SYM_C90},
                {0, 360, PHOTOMETRY_SYM_NONE}};
    for (int k = 0; k < 5; k++) {
        char label[32];
        snprintf(label, sizeof(label), "ies %d-%d", ies[k].first, ies[k].last);
        char *t = write_ies(ies[k].first, ies[k].last, ies[k].sym);
        check_symmetric(label, t, false, ies[k].sym);
        free(t);
    }

    /* Bad files. */
    char *t = write_ldt(0, PHOTOMETRY_SYM_NONE);
    char *cut = must(strdup(t));
    *(char *)must(strstr(cut, "LED\n")) = 0; /* ends in the lamp sets */
    check_error("truncated ldt", cut, true, "the file ends", "26b, type of lamps");
    free(cut);
    char *bad = must(strdup(t));
    memcpy((char *)must(strstr(bad, "\n24\n")) + 1, "2x", 2); /* line 4, Mc */
    check_error("ldt Mc not a number", bad, true, "line 4", "Mc, number of C-planes");
    free(bad);
    free(t);
    t = write_ldt(3, PHOTOMETRY_SYM_C90);
    memcpy((char *)must(strstr(t, "\n24\n")) + 1, "06", 2);
    check_error("ldt Isym 3 of 6 planes", t, true, "line 4", "multiple of 4");
    free(t);
    t = write_ies(0, 360, PHOTOMETRY_SYM_NONE);
    char *tilt = must(strstr(t, "TILT=NONE"));
    size_t before = (size_t)(tilt - t), n = strlen(t);
    char *other = must(malloc(n + 16));
    memcpy(other, t, before);
    memcpy(other + before, "TILT=lamp.tlt", 13);
    memcpy(other + before + 13, tilt + 9, n - before - 9 + 1); /* with its NUL */
    check_error("ies tilt file", other, false, "line 3", "lamp.tlt");
    free(other);
    char *type_b = must(strdup(t));
    memcpy((char *)must(strstr(type_b, " 25 1 2 ")) + 4, "2", 1);
    check_error("ies type B", type_b, false, "photometric type 2", "only type C");
    free(type_b);
    char *cut_ies = must(strdup(t));
    cut_ies[strlen(cut_ies) / 2] = 0;
    check_error("truncated ies", cut_ies, false, "candela values", "the file ends");
    free(cut_ies);
    char *no_tilt = must(strdup("IESNA:LM-63-2002\n[TEST] x\n1 1000 1 2 1 1 2 0 0 0\n"));
    check_error("ies without TILT", no_tilt, false, "no TILT= line", NULL);
    free(no_tilt);
    free(t);
    t = write_ies(0, 45, PHOTOMETRY_SYM_NONE);
    check_error("ies horizontal 0-45", t, false, "0 to 45", "5.13");
    free(t);

    photometry p;
    xrad_error err = {0};
    CHECK(photometry_load("/nonexistent/lamp.ldt", &p, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "/nonexistent/lamp.ldt"),
          "missing file: '%s'", err.message);
    CHECK(photometry_load("lamp.txt", &p, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, ".ldt or .ies"),
          "wrong extension: '%s'", err.message);
    return test_finish();
}
