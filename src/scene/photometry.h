/*
 * Photometric luminaire data (Wallner 3.2): the luminous intensity
 * distribution of a luminaire in the C-plane system (type C: C the azimuth
 * about the luminaire's downward axis, 0-360 degrees; gamma the angle from
 * straight down, 0-180), read from EULUMDAT (scene/ldt.c) and IES
 * LM-63-2002 (scene/ies.c) files by xrad's own readers.
 *
 * A reader hands over the planes its file stores and the file's symmetry;
 * photometry_expand() mirrors them into a table over the whole circle, so
 * that a lookup is one bilinear interpolation whatever the symmetry.
 */
#ifndef XRAD_SCENE_PHOTOMETRY_H
#define XRAD_SCENE_PHOTOMETRY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "xrad.h"

/* Wallner eq. 10-12: at 555 nm a watt of radiant flux is 683 lm, so a
 * radiant intensity is the luminous intensity / 683 (W/sr from cd). */
#define PHOTOMETRY_LM_PER_W 683.0

/* Limits that keep a file from allocating more than a few MB. */
#define PHOTOMETRY_MAX_FILE_BYTES (8u << 20)
#define PHOTOMETRY_MAX_ANGLES 3601u /* C-planes or gamma angles, each */

typedef struct photometry {
    uint32_t nc, ng;    /* C-planes over the whole circle (1: rotationally symmetric), gammas */
    double *c;          /* nc angles, degrees, ascending in [0, 360) */
    double *g;          /* ng angles, degrees, ascending in [0, 180] */
    double *cd;         /* nc x ng intensities, candela: cd[k * ng + j] at (c[k], g[j]) */
    double flux;        /* the luminaire's luminous flux the file states, lm (0: none) */
    bool tilt_ignored;  /* IES TILT=INCLUDE: its lamp tilt factors are not applied */
} photometry;

/* How the stored planes repeat around the circle. */
typedef enum photometry_symmetry {
    PHOTOMETRY_SYM_NONE,  /* every plane stored */
    PHOTOMETRY_SYM_AXIAL, /* one plane for all C */
    PHOTOMETRY_SYM_C0,    /* mirrored in the C0-C180 plane: I(C) = I(360 - C) */
    PHOTOMETRY_SYM_C90,   /* mirrored in the C90-C270 plane: I(C) = I(180 - C) */
    PHOTOMETRY_SYM_BOTH,  /* both: the quadrant 0-90 stored */
} photometry_symmetry;

/* Reads a .ldt or .ies file (by extension, case-insensitive). Errors name
 * the file, the line and the field; nothing is left allocated on error. */
xrad_status photometry_load(const char *path, photometry *out, xrad_error *err);

/* The readers on a buffer (NUL not required); `name` stands for the file
 * in messages. */
xrad_status photometry_parse_ldt(const char *name, const char *text, size_t len, photometry *out,
                                 xrad_error *err);
xrad_status photometry_parse_ies(const char *name, const char *text, size_t len, photometry *out,
                                 xrad_error *err);

void photometry_free(photometry *p);

/* Intensity in candela towards (c, gamma) in degrees: bilinear in the
 * table, C wrapping around the circle; 0 outside the file's gamma range
 * (an IES downlight measured 0-90 sends nothing up). */
double photometry_intensity(const photometry *p, double c_deg, double gamma_deg);

/* The integral of the intensity over the sphere, lm: exact for the
 * bilinear interpolant (its C part linear, sin(gamma) integrated in closed
 * form per cell). */
double photometry_flux(const photometry *p);

/* For the readers: p->c, p->g (ng angles already set, ascending), p->cd
 * from `stored` planes at angles c_stored[0, ns) (degrees, in the file's
 * order) with ns x ng values in cd. Every plane of the table is a stored
 * plane or its mirror image under `sym`. Errors name `name` and `field`. */
xrad_status photometry_expand(photometry *p, const char *name, const char *field,
                              const double *c_stored, uint32_t ns, const double *values,
                              photometry_symmetry sym, xrad_error *err);

/* A cursor over a file's text for the readers: lines (LDT) or numbers
 * separated by white space, commas or line ends (IES). */
typedef struct photometry_text {
    const char *name;
    const char *p, *end;
    uint32_t line; /* 1-based, of the text at p */
} photometry_text;

/* The next line without its end (\n, \r\n or \r), at most n - 1 bytes of
 * it in out; false at the end of the text. */
bool photometry_text_line(photometry_text *t, char *out, size_t n);
/* The next token (separated by white space or commas) as a finite
 * number; false if there is none or it is not a number (t->line then
 * says where it stood). */
bool photometry_text_number(photometry_text *t, double *out);
/* A line or a token as a finite number; a decimal comma is taken as a
 * point (EULUMDAT files from European tools). */
bool photometry_number(const char *s, double *out);

#endif
