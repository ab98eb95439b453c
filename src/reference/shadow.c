/* Shadow cones and the visible part of a polygon by plane clipping
 * (shadow.h). */
#include "reference/shadow.h"

#include <math.h>
#include <string.h>

/* Smallest sine of the angle an edge subtends at the apex for which the
 * plane through both is trusted. Rounding the cross product (1e-16 of its
 * factors' lengths) tilts that plane by about 1e-16 / sine radians, so at
 * this bound a shadow edge moves by 1e-7 of its distance from the apex at
 * most; the quads of a scene come nowhere near it, only a sliver left of
 * one by the slab clip can. */
#define MIN_EDGE_SINE 1e-9

bool ref_cone_init(ref_cone *cone, const ref_quad *q, vec3 p, vec3 at, vec3 normal, double tol)
{
    cone->count = 0;
    double hq = v3_dot(q->normal, v3_sub(p, q->p[0]));
    if (!(fabs(hq) > tol))
        return true;

    /* The slab: at least tol in front of the plane, and not beyond p. */
    vec3 a[2 * REF_POLY_MAX], b[2 * REF_POLY_MAX], c[2 * REF_POLY_MAX];
    int na = ref_polygon_clip(v3_mad(at, normal, tol), normal, q->p, 4, a);
    int nb = ref_polygon_clip(p, v3_scale(normal, -1), a, na, b);

    /* Vertices closer than tol (a slab plane through a corner) would make
     * edges too short to define a plane through p. */
    int m = 0;
    for (int k = 0; k < nb; k++)
        if (m == 0 || v3_len(v3_sub(b[k], c[m - 1])) > tol)
            c[m++] = b[k];
    while (m > 1 && !(v3_len(v3_sub(c[m - 1], c[0])) > tol))
        m--;
    if (m < 3)
        return true;
    if (m > REF_CONE_MAX)
        return false;
    double longest = 0;
    for (int k = 0; k < m; k++)
        longest = fmax(longest, v3_len(v3_sub(c[(k + 1) % m], c[k])));
    if (!(0.5 * v3_len(ref_polygon_newell(c, m)) > tol * longest))
        return true;

    /* Seen from the side q's normal points to, q winds counter-clockwise,
     * and (b - p) x (a - p) of each edge a -> b points into the cone; from
     * the other side, the opposite. This is the orientation that puts the
     * clipped quad's centroid inside every plane, found without it. */
    double side = hq > 0 ? 1 : -1;
    for (int k = 0; k < m; k++) {
        vec3 ra = v3_sub(c[k], p), rb = v3_sub(c[(k + 1) % m], p);
        vec3 mk = v3_cross(rb, ra);
        double len = v3_len(mk);
        if (!(len > MIN_EDGE_SINE * v3_len(ra) * v3_len(rb)))
            return false;
        cone->m[k] = v3_scale(mk, side / len);
    }
    cone->count = m;
    return true;
}

enum { INSIDE = 1, OUTSIDE = 2 };

/* Signed distances d of the vertices to the plane m . (x - p) = 0, those
 * within tol set to 0; returns which sides (INSIDE, OUTSIDE) have a vertex
 * strictly on them. */
static int classify(const vec3 *poly, int count, vec3 p, vec3 m, double tol, double *d)
{
    int sides = 0;
    for (int k = 0; k < count; k++) {
        double s = v3_dot(m, v3_sub(poly[k], p));
        d[k] = fabs(s) <= tol ? 0 : s;
        sides |= d[k] > 0 ? INSIDE : d[k] < 0 ? OUTSIDE : 0;
    }
    return sides;
}

/* Cuts a convex polygon with vertices on both sides of a plane (d from
 * classify) into its inside and outside parts; vertices on the plane go to
 * both, so the parts tile the polygon. Each part may hold 2 count vertices
 * (a convex one gets count + 1 at most). */
static void cut(const vec3 *poly, int count, const double *d, vec3 *in, int *nin, vec3 *out,
                int *nout)
{
    int a = 0, b = 0;
    for (int k = 0; k < count; k++) {
        int l = (k + 1) % count;
        if (d[k] >= 0)
            in[a++] = poly[k];
        if (d[k] <= 0)
            out[b++] = poly[k];
        if ((d[k] > 0 && d[l] < 0) || (d[k] < 0 && d[l] > 0)) {
            vec3 x = v3_lerp(poly[k], poly[l], d[k] / (d[k] - d[l]));
            in[a++] = x;
            out[b++] = x;
        }
    }
    *nin = a;
    *nout = b;
}

/* Stores a visible piece in slot *slot if that is free (the slot of the
 * piece it comes from), else after the last piece. False past the caps. */
static bool emit(ref_pieces *w, int *slot, const vec3 *poly, int count)
{
    if (count < 3)
        return true;
    if (count > REF_POLY_MAX)
        return false;
    int s = *slot;
    if (s < 0) {
        if (w->count == REF_PIECES_MAX)
            return false;
        s = w->count++;
    }
    *slot = -1;
    w->verts[s] = count;
    memcpy(w->v[s], poly, (size_t)count * sizeof *poly);
    return true;
}

/* Replaces piece i, P, by its parts outside the cone: with the cone's
 * planes m_0 .. m_{k-1}, the disjoint pieces of P outside m_j and inside
 * m_0 .. m_{j-1}; the part inside all of them is in shadow. A piece
 * entirely outside one plane stays whole, one entirely inside all vanishes.
 * Sets *cut_any when the piece changes; returns false past the caps. */
static bool subtract(ref_pieces *w, int i, vec3 p, const ref_cone *cone, double tol, bool *cut_any)
{
    double d[2 * REF_POLY_MAX];
    int n = w->verts[i];
    bool inside = true;
    for (int j = 0; j < cone->count; j++) {
        int sides = classify(w->v[i], n, p, cone->m[j], tol, d);
        if (!(sides & INSIDE))
            return true;
        inside = inside && !(sides & OUTSIDE);
    }
    *cut_any = true;
    w->verts[i] = 0;
    if (inside)
        return true;

    vec3 rem[2 * REF_POLY_MAX], in[2 * REF_POLY_MAX], out[2 * REF_POLY_MAX];
    memcpy(rem, w->v[i], (size_t)n * sizeof *rem);
    int slot = i;
    for (int j = 0; j < cone->count && n >= 3; j++) {
        int sides = classify(rem, n, p, cone->m[j], tol, d);
        if (!(sides & OUTSIDE))
            continue;
        if (!(sides & INSIDE))
            return emit(w, &slot, rem, n);
        int nin, nout;
        cut(rem, n, d, in, &nin, out, &nout);
        /* A convex piece gains one vertex per cut; rounding that bends a
         * nearly degenerate one may add more, within the buffers' 2 n. */
        if (nin > REF_POLY_MAX || !emit(w, &slot, out, nout))
            return false;
        n = nin;
        memcpy(rem, in, (size_t)n * sizeof *rem);
    }
    return true;
}

bool ref_ff_point_visible(vec3 p, vec3 n, const vec3 *poly, int count, double whole,
                          const ref_cone *cones, uint32_t cone_count, double tol,
                          ref_pieces *work, double *f)
{
    if (count < 3 || count > REF_POLY_MAX)
        return false;
    work->count = 1;
    work->verts[0] = count;
    memcpy(work->v[0], poly, (size_t)count * sizeof *poly);
    bool cut_any = false;
    for (uint32_t c = 0; c < cone_count && work->count > 0; c++) {
        if (cones[c].count == 0)
            continue;
        /* Pieces appended while subtracting this cone lie outside it. */
        int before = work->count;
        for (int i = 0; i < before; i++)
            if (!subtract(work, i, p, &cones[c], tol, &cut_any))
                return false;
        int kept = 0;
        for (int i = 0; i < work->count; i++) {
            if (work->verts[i] == 0)
                continue;
            if (kept != i) {
                work->verts[kept] = work->verts[i];
                memcpy(work->v[kept], work->v[i], (size_t)work->verts[i] * sizeof *work->v[i]);
            }
            kept++;
        }
        work->count = kept;
    }
    if (!cut_any) {
        *f = whole;
        return true;
    }
    double sum = 0;
    for (int i = 0; i < work->count; i++)
        sum += ref_ff_point_polygon(p, n, work->v[i], work->verts[i]);
    *f = sum;
    return true;
}
