#include "pareto.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* Plot geometry in SVG user units (px). The right margin is narrow because
 * labels that would run off it are flipped to the left of their marker. */
#define SVG_W 900.0
#define SVG_H 600.0
#define PLOT_L 90.0
#define PLOT_R 870.0
#define PLOT_T 56.0
#define PLOT_B 530.0
#define LABEL_FONT 10.0
/* Rough advance of one character at LABEL_FONT in a sans-serif face: wider than
 * the average so estimated boxes err on the side of staggering. */
#define LABEL_CHAR_W 6.0
#define LABEL_STEP 12.0
#define MAX_TICKS 128

static bool valid(const pareto_point *q)
{
    return isfinite(q->time_ms) && q->time_ms > 0.0 && isfinite(q->error) && q->error >= 0.0;
}

/* a dominates b: at least as good in both, better in one. */
static bool dominates(const pareto_point *a, const pareto_point *b)
{
    return a->time_ms <= b->time_ms && a->error <= b->error &&
           (a->time_ms < b->time_ms || a->error < b->error);
}

static bool on_front(const pareto_point *p, size_t n, size_t i)
{
    if (!valid(&p[i]))
        return false;
    for (size_t j = 0; j < n; j++)
        if (j != i && valid(&p[j]) && dominates(&p[j], &p[i]))
            return false;
    return true;
}

void pareto_mark(pareto_point *p, size_t n)
{
    /* O(n^2), but a sweep has tens to hundreds of points and this needs no
     * allocation; the test reads only time and error, so setting .front as it
     * goes cannot affect later points. */
    for (size_t i = 0; i < n; i++)
        p[i].front = on_front(p, n, i);
}

/* ---- axes ---- */

typedef struct axis {
    bool log;
    double lo, hi;      /* range shown; both > 0 when log */
    double step;        /* linear tick spacing */
    double px0, px1;    /* pixel positions of lo and hi */
} axis;

typedef struct tick {
    double v;
    bool major;         /* labelled, with a grid line */
    char text[32];
} tick;

/* Only finite numbers ever reach the file: anything else becomes 0, and huge
 * values are clamped so a coordinate cannot print as an absurd string. */
static double fin(double v)
{
    if (!isfinite(v))
        return 0.0;
    if (v > 1e6)
        return 1e6;
    if (v < -1e6)
        return -1e6;
    return v;
}

static double nice_step(double raw)
{
    double mag = pow(10.0, floor(log10(raw)));
    double f = raw / mag;
    double m = f < 1.5 ? 1.0 : f < 3.0 ? 2.0 : f < 7.0 ? 5.0 : 10.0;
    return m * mag;
}

static void axis_linear(axis *a, double lo, double hi, bool nonneg)
{
    a->log = false;
    if (!(hi > lo)) {
        /* One distinct value: show it in the middle of a range around it. */
        double pad = lo == 0.0 ? 1.0 : fabs(lo) * 0.25;
        lo -= pad;
        hi += pad;
    } else {
        /* Keep points off the frame where the nice rounding would not. */
        double pad = (hi - lo) * 0.04;
        lo -= pad;
        hi += pad;
    }
    if (nonneg && lo < 0.0)
        lo = 0.0;
    double step = nice_step((hi - lo) / 6.0);
    a->lo = floor(lo / step) * step;
    a->hi = ceil(hi / step) * step;
    a->step = step;
    if (!isfinite(a->lo) || !isfinite(a->hi) || !isfinite(step) || !(a->hi > a->lo) ||
        !(step > 0.0) || (a->hi - a->lo) / step > 40.0) {
        a->lo = 0.0;
        a->hi = 1.0;
        a->step = 0.2;
    }
}

/* count: valid values; lo_pos: smallest value > 0 (INFINITY if none). Values
 * <= 0 on a log axis (an error of exactly 0) are drawn on its lower edge. */
static void axis_fit(axis *a, size_t count, double lo, double lo_pos, double hi, bool nonneg)
{
    if (count == 0) {
        a->log = false;
        a->lo = 0.0;
        a->hi = 1.0;
        a->step = 0.2;
        return;
    }
    if (isfinite(lo_pos) && hi / lo_pos > 10.0) {
        a->log = true;
        a->lo = pow(10.0, floor(log10(lo_pos)));
        a->hi = pow(10.0, ceil(log10(hi)));
        if (!isfinite(a->hi))
            a->hi = hi;
        if (!(a->lo > 0.0))
            a->lo = lo_pos;
        a->step = 0.0;
        return;
    }
    axis_linear(a, lo, hi, nonneg);
}

static double axis_px(const axis *a, double v)
{
    double t;
    if (a->log)
        t = v > 0.0 ? (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo)) : 0.0;
    else
        t = (v - a->lo) / (a->hi - a->lo);
    if (!isfinite(t))
        t = 0.0;
    if (t < 0.0)
        t = 0.0;
    if (t > 1.0)
        t = 1.0;
    return a->px0 + t * (a->px1 - a->px0);
}

static void decade_text(char *buf, size_t size, int e)
{
    /* Plain numbers where they are short, powers of ten where they are not. */
    if (e >= -1 && e <= 3)
        snprintf(buf, size, "%g", pow(10.0, e));
    else
        snprintf(buf, size, "1e%d", e);
}

static void linear_text(char *buf, size_t size, double v, double step)
{
    int decimals = step >= 1.0 ? 0 : (int)ceil(-log10(step) - 1e-9);
    if (decimals > 12)
        decimals = 12;
    if (fabs(v) < step * 1e-6)
        v = 0.0;    /* no "-0" or 1e-17 from k * step */
    if (fabs(v) >= 1e6 || decimals > 6)
        snprintf(buf, size, "%g", v);
    else
        snprintf(buf, size, "%.*f", decimals, v);
}

static size_t axis_ticks(const axis *a, tick *t, size_t cap)
{
    size_t n = 0;
    if (a->log) {
        int e0 = (int)floor(log10(a->lo) + 1e-9), e1 = (int)ceil(log10(a->hi) - 1e-9);
        int decades = e1 - e0;
        /* At most about ten labelled decades, and minor ticks only while they
         * are far enough apart to read. */
        int every = decades > 10 ? (decades + 9) / 10 : 1;
        bool minor = decades <= 6;
        for (int e = e0; e <= e1 && n < cap; e++) {
            double d = pow(10.0, e);
            if (!isfinite(d) || d <= 0.0)
                continue;
            if ((e - e0) % every == 0 && d >= a->lo * (1 - 1e-9) && d <= a->hi * (1 + 1e-9)) {
                t[n].v = d;
                t[n].major = true;
                decade_text(t[n].text, sizeof(t[n].text), e);
                n++;
            }
            for (int m = 2; minor && m <= 9 && n < cap; m++) {
                double v = d * m;
                if (v > a->hi * (1 + 1e-9))
                    break;
                if (v < a->lo)
                    continue;
                t[n].v = v;
                t[n].major = false;
                t[n].text[0] = '\0';
                n++;
            }
        }
        return n;
    }
    long k0 = lround(a->lo / a->step), k1 = lround(a->hi / a->step);
    for (long k = k0; k <= k1 && n < cap; k++) {
        t[n].v = (double)k * a->step;
        t[n].major = true;
        linear_text(t[n].text, sizeof(t[n].text), t[n].v, a->step);
        n++;
    }
    return n;
}

/* ---- text ---- */

/* Length of a well-formed UTF-8 sequence at s, or 0: invalid bytes would make
 * the whole document ill-formed, so they are replaced rather than copied. */
static size_t utf8_len(const unsigned char *s)
{
    size_t len;
    unsigned cp;
    if (s[0] < 0x80)
        return 1;
    if ((s[0] & 0xe0) == 0xc0) {
        len = 2;
        cp = s[0] & 0x1fu;
    } else if ((s[0] & 0xf0) == 0xe0) {
        len = 3;
        cp = s[0] & 0x0fu;
    } else if ((s[0] & 0xf8) == 0xf0) {
        len = 4;
        cp = s[0] & 0x07u;
    } else {
        return 0;
    }
    for (size_t i = 1; i < len; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;
        cp = (cp << 6) | (s[i] & 0x3fu);
    }
    static const unsigned min_cp[5] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < min_cp[len] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff) || cp == 0xfffe ||
        cp == 0xffff)
        return 0;
    return len;
}

static void put_escaped(FILE *f, const char *s)
{
    const unsigned char *u = (const unsigned char *)(s ? s : "");
    while (*u) {
        size_t len = utf8_len(u);
        if (len == 0) {
            fputc('?', f);
            u++;
            continue;
        }
        if (len > 1) {
            fwrite(u, 1, len, f);
            u += len;
            continue;
        }
        switch (*u) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&apos;", f); break;
        default:
            /* XML 1.0 allows no control characters but tab, LF and CR. */
            fputc(*u < 0x20 && *u != '\t' && *u != '\n' && *u != '\r' ? '?' : *u, f);
        }
        u++;
    }
}

static size_t utf8_chars(const char *s)
{
    size_t n = 0;
    for (const unsigned char *u = (const unsigned char *)(s ? s : ""); *u; u++)
        if ((*u & 0xc0) != 0x80)
            n++;
    return n;
}

/* ---- label placement ---- */

typedef struct box {
    double x0, y0, x1, y1;
} box;

static bool overlaps(const box *a, const box *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

static size_t hit_count(const box *b, const box *obst, size_t n)
{
    size_t c = 0;
    for (size_t i = 0; i < n; i++)
        c += overlaps(b, &obst[i]);
    return c;
}

/* ---- the plot ---- */

static int cmp_time(const void *a, const void *b)
{
    const pareto_point *x = *(const pareto_point *const *)a;
    const pareto_point *y = *(const pareto_point *const *)b;
    if (x->time_ms != y->time_ms)
        return x->time_ms < y->time_ms ? -1 : 1;
    if (x->error != y->error)
        return x->error < y->error ? -1 : 1;
    return 0;
}

static void put_line(FILE *f, double x1, double y1, double x2, double y2, const char *stroke)
{
    fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n",
            fin(x1), fin(y1), fin(x2), fin(y2), stroke);
}

static void write_axes(FILE *f, const axis *ax, const axis *ay, const char *error_name)
{
    tick t[MAX_TICKS];
    size_t nt = axis_ticks(ax, t, MAX_TICKS);
    for (size_t i = 0; i < nt; i++) {
        double x = fin(axis_px(ax, t[i].v));
        if (t[i].major)
            put_line(f, x, PLOT_T, x, PLOT_B, "#e4e4e4");
        put_line(f, x, PLOT_B, x, PLOT_B + (t[i].major ? 6.0 : 3.0), "#444");
        if (t[i].major)
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", x,
                    PLOT_B + 19.0, t[i].text);
    }
    nt = axis_ticks(ay, t, MAX_TICKS);
    for (size_t i = 0; i < nt; i++) {
        double y = fin(axis_px(ay, t[i].v));
        if (t[i].major)
            put_line(f, PLOT_L, y, PLOT_R, y, "#e4e4e4");
        put_line(f, PLOT_L - (t[i].major ? 6.0 : 3.0), y, PLOT_L, y, "#444");
        if (t[i].major)
            fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n", PLOT_L - 9.0,
                    y + 4.0, t[i].text);
    }
    fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
               "stroke=\"#444\"/>\n",
            PLOT_L, PLOT_T, PLOT_R - PLOT_L, PLOT_B - PLOT_T);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"13\">"
               "time per frame (ms)%s</text>\n",
            (PLOT_L + PLOT_R) / 2.0, SVG_H - 22.0, ax->log ? ", log scale" : "");
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"13\" "
               "transform=\"rotate(-90 %.1f %.1f)\">",
            22.0, (PLOT_T + PLOT_B) / 2.0, 22.0, (PLOT_T + PLOT_B) / 2.0);
    put_escaped(f, error_name);
    fprintf(f, " against the reference%s</text>\n", ay->log ? ", log scale" : "");
}

/* Labels of the front, in time order. Each goes right of and above its marker
 * if that is clear of the labels already placed and of every front marker;
 * otherwise left of it, then a row lower, a row higher and so on, both sides
 * each time; if nothing in the plot is clear, the candidate with the fewest
 * collisions. A moved label gets a leader line so it still reads as belonging
 * to its point. */
static void write_labels(FILE *f, const pareto_point *const *fr, const double *fx,
                         const double *fy, size_t nf, box *obst)
{
    size_t nobst = 0;
    for (size_t i = 0; i < nf; i++)
        obst[nobst++] = (box){fx[i] - 5.0, fy[i] - 5.0, fx[i] + 5.0, fy[i] + 5.0};
    int rows = (int)ceil((PLOT_B - PLOT_T) / LABEL_STEP);
    fprintf(f, "<g font-size=\"%.0f\" fill=\"#222\">\n", LABEL_FONT);
    for (size_t i = 0; i < nf; i++) {
        const char *label = fr[i]->label ? fr[i]->label : "";
        if (!*label)
            continue;
        double w = (double)utf8_chars(label) * LABEL_CHAR_W, base = fy[i] - 7.0;
        box best = {fx[i] + 7.0, base - 9.0, fx[i] + 7.0 + w, base + 2.0};
        bool best_right = true, found = false;
        size_t best_hits = SIZE_MAX;
        for (int k = 0; k <= 2 * rows && !found; k++) {
            /* Rows 0, +1, -1, +2, -2 ...: down first, since the front falls to
             * the right and the space above is the previous label's. */
            int row = (k + 1) / 2 * (k % 2 ? 1 : -1);
            double cy = base + row * LABEL_STEP;
            if (cy - 9.0 < PLOT_T - 4.0 || cy + 2.0 > PLOT_B - 2.0)
                continue;
            for (int side = 0; side < 2 && !found; side++) {
                bool right = side == 0;
                double x0 = right ? fx[i] + 7.0 : fx[i] - 7.0 - w;
                if (x0 < 2.0 || x0 + w > SVG_W - 2.0)
                    continue;
                box b = {x0, cy - 9.0, x0 + w, cy + 2.0};
                size_t hits = hit_count(&b, obst, nobst);
                if (hits < best_hits) {
                    best = b;
                    best_right = right;
                    best_hits = hits;
                    found = hits == 0;
                }
            }
        }
        obst[nobst++] = best;
        double y = best.y1 - 2.0;
        if (y != base)
            fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#aaa\" "
                       "stroke-width=\"0.6\"/>\n",
                    fin(fx[i]), fin(fy[i]), fin(best_right ? best.x0 : best.x1), fin(y - 4.0));
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\"%s>", fin(best_right ? best.x0 : best.x1), fin(y),
                best_right ? "" : " text-anchor=\"end\"");
        put_escaped(f, label);
        fputs("</text>\n", f);
    }
    fputs("</g>\n", f);
}

static void write_plot(FILE *f, const char *title, const char *error_name,
                       const pareto_point *p, size_t n, const pareto_point **fr, double *fx,
                       double *fy, box *obst)
{
    size_t count = 0, nf = 0, zeros = 0;
    double tlo = INFINITY, thi = -INFINITY, elo = INFINITY, elo_pos = INFINITY, ehi = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        if (!valid(&p[i]))
            continue;
        count++;
        tlo = fmin(tlo, p[i].time_ms);
        thi = fmax(thi, p[i].time_ms);
        elo = fmin(elo, p[i].error);
        ehi = fmax(ehi, p[i].error);
        if (p[i].error > 0.0)
            elo_pos = fmin(elo_pos, p[i].error);
        else
            zeros++;
        if (on_front(p, n, i))
            fr[nf++] = &p[i];
    }
    qsort(fr, nf, sizeof(*fr), cmp_time);

    axis ax, ay;
    axis_fit(&ax, count, tlo, tlo, thi, true);
    axis_fit(&ay, count, elo, elo_pos, ehi, true);
    ax.px0 = PLOT_L;
    ax.px1 = PLOT_R;
    ay.px0 = PLOT_B;
    ay.px1 = PLOT_T;

    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
               "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
               "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"11\">\n"
               "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
            SVG_W, SVG_H, SVG_W, SVG_H);
    fprintf(f, "<text x=\"%.1f\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">", SVG_W / 2.0);
    put_escaped(f, title);
    fputs("</text>\n", f);
    fprintf(f, "<text x=\"%.1f\" y=\"42\" text-anchor=\"middle\" fill=\"#666\">%zu point%s, "
               "%zu on the Pareto front",
            SVG_W / 2.0, count, count == 1 ? "" : "s", nf);
    if (count < n)
        fprintf(f, "; %zu with non-finite or out-of-range values not shown", n - count);
    if (zeros && ay.log)
        fprintf(f, "; error 0 drawn on the lower edge");
    fputs("</text>\n", f);

    write_axes(f, &ax, &ay, error_name);
    if (count == 0) {
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" font-size=\"16\" "
                   "fill=\"#888\">no points</text>\n",
                (PLOT_L + PLOT_R) / 2.0, (PLOT_T + PLOT_B) / 2.0);
    }

    fputs("<g fill=\"#9a9a9a\">\n", f);
    for (size_t i = 0; i < n; i++) {
        if (!valid(&p[i]))
            continue;
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\"/>\n", fin(axis_px(&ax, p[i].time_ms)),
                fin(axis_px(&ay, p[i].error)));
    }
    fputs("</g>\n", f);

    for (size_t i = 0; i < nf; i++) {
        fx[i] = fin(axis_px(&ax, fr[i]->time_ms));
        fy[i] = fin(axis_px(&ay, fr[i]->error));
    }
    if (nf > 1) {
        /* Horizontal then vertical: between two front times the best error
         * attainable is still the earlier point's. */
        fputs("<polyline fill=\"none\" stroke=\"#c0392b\" stroke-width=\"1.5\" points=\"", f);
        for (size_t i = 0; i < nf; i++) {
            if (i > 0)
                fprintf(f, " %.1f,%.1f", fx[i], fy[i - 1]);
            fprintf(f, "%s%.1f,%.1f", i ? " " : "", fx[i], fy[i]);
        }
        fputs("\"/>\n", f);
    }
    fputs("<g fill=\"#c0392b\">\n", f);
    for (size_t i = 0; i < nf; i++)
        fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"4.5\"/>\n", fx[i], fy[i]);
    fputs("</g>\n", f);
    write_labels(f, fr, fx, fy, nf, obst);
    fputs("</svg>\n", f);
}

int pareto_write_svg(const char *path, const char *title, const pareto_point *p, size_t n)
{
    return pareto_write_svg_named(path, title, "NRMSE", p, n);
}

int pareto_write_svg_named(const char *path, const char *title, const char *error_name,
                           const pareto_point *p, size_t n)
{
    /* Scratch for the front (pointers, pixel positions) and label obstacles
     * (front markers plus labels, so up to 2n boxes), taken before the file is
     * opened so a failed allocation leaves no half-written plot. */
    size_t cap = n ? n : 1;
    if (cap > SIZE_MAX / 2 / sizeof(box)) {
        errno = ENOMEM;
        return -1;
    }
    const pareto_point **fr = malloc(cap * sizeof(*fr));
    double *fx = malloc(cap * sizeof(*fx));
    double *fy = malloc(cap * sizeof(*fy));
    box *obst = malloc(2 * cap * sizeof(*obst));
    if (!fr || !fx || !fy || !obst) {
        free(fr);
        free(fx);
        free(fy);
        free(obst);
        errno = ENOMEM;
        return -1;
    }
    FILE *f = fopen(path, "w");
    if (!f) {
        int e = errno;
        free(fr);
        free(fx);
        free(fy);
        free(obst);
        errno = e;
        return -1;
    }
    /* stdio need not set errno on a failed write; clear it so a stale value is
     * not reported, and fall back to EIO below. */
    errno = 0;
    write_plot(f, title, error_name, p, n, fr, fx, fy, obst);
    bool failed = ferror(f) != 0;
    int e = errno;
    free(fr);
    free(fx);
    free(fy);
    free(obst);
    if (fclose(f) != 0) {
        failed = true;
        if (e == 0)
            e = errno;
    }
    if (failed) {
        errno = e ? e : EIO;
        return -1;
    }
    return 0;
}
