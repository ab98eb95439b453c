/* Analytic point-to-polygon form factor and its area average (ff_kernel.h). */
#include "reference/ff_kernel.h"

#include <math.h>

/* Relative size below which a length is treated as zero: well above the
 * rounding of a few double operations (1e-16), far below any geometric
 * feature a scene describes. */
#define REL_EPS 1e-12

vec3 ref_polygon_newell(const vec3 *poly, int count)
{
    vec3 n = v3(0, 0, 0);
    for (int k = 0; k < count; k++) {
        vec3 a = poly[k], b = poly[(k + 1) % count];
        n.x += (a.y - b.y) * (a.z + b.z);
        n.y += (a.z - b.z) * (a.x + b.x);
        n.z += (a.x - b.x) * (a.y + b.y);
    }
    return n;
}

int ref_polygon_clip(vec3 p, vec3 n, const vec3 *in, int count, vec3 *out)
{
    int m = 0;
    for (int k = 0; k < count; k++) {
        vec3 a = in[k], b = in[(k + 1) % count];
        double da = v3_dot(n, v3_sub(a, p)), db = v3_dot(n, v3_sub(b, p));
        if (da >= 0)
            out[m++] = a;
        if ((da >= 0) != (db >= 0)) {
            double t = da / (da - db);
            out[m++] = v3_lerp(a, b, t);
        }
    }
    return m;
}

double ref_ff_point_polygon(vec3 p, vec3 n, const vec3 *poly, int count)
{
    if (count < 3 || count > REF_POLY_MAX)
        return 0;
    vec3 big = ref_polygon_newell(poly, count);
    double big_len = v3_len(big);
    vec3 centre = v3(0, 0, 0);
    for (int k = 0; k < count; k++)
        centre = v3_add(centre, poly[k]);
    centre = v3_scale(centre, 1.0 / count);
    double radius = 0;
    for (int k = 0; k < count; k++) {
        double r = v3_len(v3_sub(poly[k], centre));
        radius = r > radius ? r : radius;
    }
    if (!(big_len > 0) || !(radius > 0))
        return 0;

    /* Only the front side emits: p must lie strictly above the polygon's
     * plane. A point in the plane sees the polygon edge-on (cos phi_j = 0
     * everywhere), so 0 is the exact value there too. */
    double height = v3_dot(v3_scale(big, 1.0 / big_len), v3_sub(p, centre));
    double scale = radius + v3_len(v3_sub(p, centre));
    if (height <= REL_EPS * scale)
        return 0;

    vec3 clipped[2 * REF_POLY_MAX];
    int m = ref_polygon_clip(p, n, poly, count, clipped);
    if (m < 3)
        return 0;

    /* Lambert's formula: F = 1/(2 pi) sum_k gamma_k n . (R_k x R_{k+1}) /
     * |R_k x R_{k+1}|. Seen from a point in front of it, a polygon winds
     * clockwise about its own normal, which makes that sum negative; summing
     * R_{k+1} x R_k instead gives F >= 0 for a polygon facing p. */
    double sum = 0;
    for (int k = 0; k < m; k++) {
        vec3 a = v3_sub(clipped[k], p), b = v3_sub(clipped[(k + 1) % m], p);
        double la = v3_len(a), lb = v3_len(b);
        vec3 c = v3_cross(b, a);
        double lc = v3_len(c);
        /* A vertex at p, or an edge whose line passes through p, subtends
         * no solid angle: the edge's plane through p is undefined and its
         * contribution vanishes in the limit. */
        if (!(lc > REL_EPS * la * lb))
            continue;
        double gamma = atan2(lc, v3_dot(a, b));
        sum += gamma * v3_dot(n, c) / lc;
    }
    double f = sum / (2 * REF_PI);
    return f > 0 ? f : 0;
}

int ref_gauss_legendre(int n, double *x, double *w)
{
    if (n < 1 || n > REF_GL_MAX)
        return 0;
    /* Newton iteration on P_n from the Tricomi initial guesses; the roots
     * are symmetric, so half of them suffice (Numerical Recipes 4.6). */
    for (int i = 0; i < (n + 1) / 2; i++) {
        double z = cos(REF_PI * (i + 0.75) / (n + 0.5)), pp = 1;
        for (int iter = 0; iter < 100; iter++) {
            double p1 = 1, p2 = 0;
            for (int j = 1; j <= n; j++) {
                double p3 = p2;
                p2 = p1;
                p1 = ((2.0 * j - 1) * z * p2 - (j - 1.0) * p3) / j;
            }
            pp = n * (z * p1 - p2) / (z * z - 1);
            double z1 = z;
            z = z1 - p1 / pp;
            if (fabs(z - z1) < 1e-15)
                break;
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = w[n - 1 - i] = 2 / ((1 - z * z) * pp * pp);
    }
    return 1;
}

/* Composite Gauss-Legendre rule on [0, 1], graded geometrically towards
 * both ends. Returns the number of nodes written to s and ws. */
static int graded_rule(int order, int levels, const double *gx, const double *gw, double *s,
                       double *ws)
{
    double cuts[2 * REF_GRADE_MAX + 3];
    int nc = 0;
    cuts[nc++] = 0;
    if (levels > 0) {
        for (int l = levels; l >= 1; l--)
            cuts[nc++] = 0.5 * pow(REF_GRADE_RATIO, l);
        cuts[nc++] = 0.5;
        for (int l = 1; l <= levels; l++)
            cuts[nc++] = 1 - 0.5 * pow(REF_GRADE_RATIO, l);
    }
    cuts[nc++] = 1;
    int m = 0;
    for (int c = 0; c + 1 < nc; c++) {
        double a = cuts[c], h = cuts[c + 1] - cuts[c];
        for (int k = 0; k < order; k++) {
            s[m] = a + 0.5 * h * (gx[k] + 1);
            ws[m] = 0.5 * h * gw[k];
            m++;
        }
    }
    return m;
}

double ref_ff_area_polygon(const vec3 *recv, int recv_count, const vec3 *poly, int count,
                           int order, int levels)
{
    double gx[REF_GL_MAX], gw[REF_GL_MAX];
    if (recv_count < 3 || recv_count > REF_POLY_MAX || count < 3 || count > REF_POLY_MAX ||
        levels < 0 || levels > REF_GRADE_MAX || !ref_gauss_legendre(order, gx, gw))
        return -1;
    vec3 big = ref_polygon_newell(recv, recv_count);
    double area = 0.5 * v3_len(big);
    if (!(area > 0))
        return 0;
    vec3 n = v3_scale(big, 0.5 / area);

    /* Receiver points behind the emitter's plane get nothing. */
    vec3 en = v3_norm(ref_polygon_newell(poly, count));
    vec3 part[2 * REF_POLY_MAX];
    int m = ref_polygon_clip(poly[0], en, recv, recv_count, part);
    if (m < 3)
        return 0;

    double s[REF_GL_MAX * (2 * REF_GRADE_MAX + 2)], ws[REF_GL_MAX * (2 * REF_GRADE_MAX + 2)];
    int q = graded_rule(order, levels, gx, gw, s, ws);
    double sum = 0;
    for (int k = 1; k + 1 < m; k++) {
        /* Duffy map of the unit square onto triangle (a, b, c):
         * x = a + u (b - a) + u v (c - b), Jacobian 2 |abc| u. */
        vec3 a = part[0], ab = v3_sub(part[k], a), bc = v3_sub(part[k + 1], part[k]);
        double twice = v3_len(v3_cross(ab, bc));
        if (!(twice > 0))
            continue;
        for (int iu = 0; iu < q; iu++) {
            double u = s[iu];
            for (int iv = 0; iv < q; iv++) {
                vec3 x = v3_add(a, v3_add(v3_scale(ab, u), v3_scale(bc, u * s[iv])));
                sum += ws[iu] * ws[iv] * twice * u * ref_ff_point_polygon(x, n, poly, count);
            }
        }
    }
    return sum / area;
}
