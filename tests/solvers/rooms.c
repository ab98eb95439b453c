/*
 * Generic rooms (issue 14): scenes that are not thesis scenes, drawn from a
 * fixed seed, so that the GPU methods are held to the CPU reference on
 * rooms nobody tuned them for.
 *
 * Every room is a box of six inward-facing quads, x from 0 to W, y (up)
 * from 0 to H, z from 0 to D, metres. A light "on" a ceiling or a wall is
 * flush with it: the surface is cut into quads around the light's hole and
 * the light fills the hole (no coincident surfaces). Boxes standing on the
 * floor have no bottom face, a box against a wall no face on the wall (as
 * the Cornell Box's blocks); a floating box has all six. The six kinds, by
 * index (odd indices hold a moving box, object "mover", with a
 * cross_density of half the scene's density):
 *
 *  0  small bright room: W, D in [2, 3.5], H in [2, 2.8]; one flush ceiling
 *     light of [0.25, 0.45] x W by [0.25, 0.45] x D; a table on the floor;
 *     albedos in [0.6, 0.9].
 *  1  the room: W in [3.5, 5], D in [2.8, 4], H in [2.6, 3.2]; a
 *     light of [0.8, 1.4] x [0.6, 1.0] m 1 cm below the ceiling; a table on
 *     the floor; a cube sliding on the floor; albedos in [0.1, 0.9].
 *  2  wall light: W, D in [3, 6], H in [2.4, 3.5]; a flush light of [0.4,
 *     1.0] x [0.3, 0.6] m on the back wall (z = D), its centre [1.5, 2.0] m
 *     high; a floating box; a box on the floor against the back wall; floor
 *     albedo in [0.1, 0.3], the rest in [0.6, 0.9].
 *  3  two lights: W in [4, 7], D in [3, 5], H in [2.5, 3.5]; two flush
 *     ceiling lights, [0.8, 1.5] x [0.5, 1.0] m and [0.2, 0.4] m square; a
 *     box against the back wall; a floating box moving across the room;
 *     albedos in [0.1, 0.9].
 *  4  dark hall: W in [8, 10], D in [6, 10], H in [3, 5]; one flush
 *     ceiling light [0.3, 0.6] m square; two boxes on the floor; albedos in
 *     [0.1, 0.35].
 *  5  tall room: W, D in [2, 4], H in [4, 10]; a flush ceiling light of
 *     [0.3, 0.5] x W by [0.3, 0.5] x D and a flush light of [0.3, 0.8] x
 *     [0.3, 0.6] m on the wall x = W, its centre [1.2, 2.0] m high;
 *     a table; a box on the floor sliding and turning ([30, 60] degrees/s);
 *     albedos in [0.1, 0.9].
 *
 * Boxes: a table [0.12, 0.24] x min(W, D) square, [0.4, 0.9] m high (at
 * most 0.4 H); a floating box [0.1, 0.2] x min(W, D) a side (at most 0.25 H
 * high), its bottom [0.3, 0.5] H up; a box against the back wall [0.12,
 * 0.22] x min(W, D) wide, [0.08, 0.15] x min(W, D) deep, [0.5, 1.2] m high
 * (at most 0.4 H); a floor box or cube [0.1, 0.16] x min(W, D) a side. Each
 * kind has its own zone of the floor, so they never meet. A moving box
 * travels 0.3 W along x per second (the floating one also rises 0.05 H).
 * Materials: floor, ceiling, walls and the wall x = W each their own
 * (surfaces floor, ceiling, wall-x0, wall-xW, wall-z0, wall-zD; a surface
 * cut around a light adds .2, .3 ...); the wall x = W and the boxes coloured (each channel the grey
 * albedo times [0.7, 1.3], kept in [0.1, 0.9]); lights of albedo [0.1,
 * 0.9] and exitance [10, 60] W/m^2 times a tint of [0.8, 1] per channel.
 * Element density: the least multiple of 0.01 per metre that gives the
 * room at least its target count, drawn in [ROOMS_MIN_ELEMENTS,
 * ROOMS_MAX_ELEMENTS]. The camera stands near the corner (0, ., 0), 1.6 m
 * high at most, and looks at the far corner (W, ., D), 75 degrees
 * vertically, 128 x 128.
 */
#include "solvers/rooms.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ROOMS_MIN_ELEMENTS 1600
#define ROOMS_MAX_ELEMENTS 2200

#define MAX_MATS 12
#define MAX_OBJS 8
#define MAX_QUADS 96

/* splitmix64 (Steele, Lea and Flood 2014): tiny, and the same everywhere. */
typedef struct rng {
    uint64_t s;
} rng;

static uint64_t rng_next(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double uni(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * (double)(rng_next(r) >> 11) * 0x1.0p-53;
}

/* Millimetres: every coordinate the generator writes is a multiple of them. */
static double mm(double x)
{
    return round(x * 1000.0) / 1000.0;
}

typedef struct gmat {
    char name[16];
    double albedo[3], emission[3];
} gmat;

typedef struct gobj {
    char name[16];
    int dynamic;
    char animation[256];
} gobj;

typedef struct gquad {
    char name[24];
    int obj, mat;
    double o[3], u[3], v[3];
} gquad;

typedef struct room_builder {
    gmat mats[MAX_MATS];
    int nmats;
    gobj objs[MAX_OBJS];
    int nobjs;
    gquad quads[MAX_QUADS];
    int nquads;
    int overflow;
} room_builder;

static int add_mat(room_builder *b, const char *name, const double albedo[3],
                   const double emission[3])
{
    if (b->nmats == MAX_MATS) {
        b->overflow = 1;
        return 0;
    }
    gmat *m = &b->mats[b->nmats];
    snprintf(m->name, sizeof m->name, "%s", name);
    for (int c = 0; c < 3; c++) {
        m->albedo[c] = round(albedo[c] * 1000.0) / 1000.0;
        m->emission[c] = emission ? round(emission[c] * 1000.0) / 1000.0 : 0;
    }
    return b->nmats++;
}

static int add_obj(room_builder *b, const char *name, int dynamic)
{
    if (b->nobjs == MAX_OBJS) {
        b->overflow = 1;
        return 0;
    }
    gobj *o = &b->objs[b->nobjs];
    snprintf(o->name, sizeof o->name, "%s", name);
    o->dynamic = dynamic;
    o->animation[0] = 0;
    return b->nobjs++;
}

/* A parallelogram o, o + u, o + u + v, o + v facing n: u and v swap when
 * u x v points away from n. */
static void add_quad(room_builder *b, int obj, int mat, const char *name, const double o[3],
                     const double u[3], const double v[3], const double n[3])
{
    if (b->nquads == MAX_QUADS) {
        b->overflow = 1;
        return;
    }
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                   u[0] * v[1] - u[1] * v[0]};
    int swap = c[0] * n[0] + c[1] * n[1] + c[2] * n[2] < 0;
    gquad *q = &b->quads[b->nquads++];
    snprintf(q->name, sizeof q->name, "%s", name);
    q->obj = obj;
    q->mat = mat;
    for (int k = 0; k < 3; k++) {
        q->o[k] = mm(o[k]);
        q->u[k] = mm(swap ? v[k] : u[k]);
        q->v[k] = mm(swap ? u[k] : v[k]);
    }
}

/* The rectangle o + x a + y b (x in [0, la], y in [0, lb]; a, b unit axes)
 * facing n, less the rectangular holes {x0, x1, y0, y1}: cut into bands at
 * the holes' y edges, each band into the runs between the holes crossing it.
 * Names: `name`, then `name`.2, .3 ... */
static void add_plane(room_builder *b, int obj, int mat, const char *name, const double o[3],
                      const double a[3], double la, const double bb[3], double lb,
                      const double n[3], const double (*holes)[4], int nholes)
{
    double ys[2 + 2 * 4];
    int ny = 0;
    ys[ny++] = 0;
    ys[ny++] = lb;
    for (int h = 0; h < nholes; h++) {
        ys[ny++] = holes[h][2];
        ys[ny++] = holes[h][3];
    }
    for (int i = 1; i < ny; i++) /* insertion sort: a handful of values */
        for (int j = i; j > 0 && ys[j - 1] > ys[j]; j--) {
            double t = ys[j];
            ys[j] = ys[j - 1];
            ys[j - 1] = t;
        }
    int part = 0;
    for (int i = 0; i + 1 < ny; i++) {
        double y0 = ys[i], y1 = ys[i + 1];
        if (y1 - y0 < 1e-6)
            continue;
        /* Holes crossing this band, by x0 (they do not overlap). */
        double xs[2 * 4];
        int nx = 0;
        for (int h = 0; h < nholes; h++)
            if (holes[h][2] <= y0 + 1e-9 && holes[h][3] >= y1 - 1e-9) {
                int k = nx;
                while (k >= 2 && xs[k - 2] > holes[h][0]) {
                    xs[k] = xs[k - 2];
                    xs[k + 1] = xs[k - 1];
                    k -= 2;
                }
                xs[k] = holes[h][0];
                xs[k + 1] = holes[h][1];
                nx += 2;
            }
        double x = 0;
        for (int k = 0; k <= nx; k += 2) {
            double x1 = k < nx ? xs[k] : la;
            if (x1 - x > 1e-6) {
                double p[3], u[3], v[3];
                for (int c = 0; c < 3; c++) {
                    p[c] = o[c] + x * a[c] + y0 * bb[c];
                    u[c] = (x1 - x) * a[c];
                    v[c] = (y1 - y0) * bb[c];
                }
                char nm[24];
                if (part++ == 0)
                    snprintf(nm, sizeof nm, "%s", name);
                else
                    snprintf(nm, sizeof nm, "%s.%d", name, part);
                add_quad(b, obj, mat, nm, p, u, v, n);
            }
            if (k < nx)
                x = xs[k + 1];
        }
    }
}

enum { BOX_NO_BOTTOM = 1, BOX_NO_BACK = 2 /* the +z face, against the back wall */ };

/* An axis-aligned box from corner lo, sizes s, faces pointing out. */
static void add_box(room_builder *b, int obj, int mat, const char *name, const double lo[3],
                    const double s[3], int omit)
{
    static const double X[3] = {1, 0, 0}, Y[3] = {0, 1, 0}, Z[3] = {0, 0, 1};
    static const double nX[3] = {-1, 0, 0}, nY[3] = {0, -1, 0}, nZ[3] = {0, 0, -1};
    double hi[3] = {lo[0] + s[0], lo[1] + s[1], lo[2] + s[2]};
    double ux[3] = {s[0], 0, 0}, uy[3] = {0, s[1], 0}, uz[3] = {0, 0, s[2]};
    double p[3];
    char nm[24];
#define FACE(suffix, px, py, pz, u, v, n)                                                       \
    do {                                                                                        \
        p[0] = (px), p[1] = (py), p[2] = (pz);                                                  \
        snprintf(nm, sizeof nm, "%s.%s", name, suffix);                                         \
        add_quad(b, obj, mat, nm, p, u, v, n);                                                  \
    } while (0)
    FACE("top", lo[0], hi[1], lo[2], ux, uz, Y);
    if (!(omit & BOX_NO_BOTTOM))
        FACE("bottom", lo[0], lo[1], lo[2], ux, uz, nY);
    FACE("-x", lo[0], lo[1], lo[2], uy, uz, nX);
    FACE("+x", hi[0], lo[1], lo[2], uy, uz, X);
    FACE("-z", lo[0], lo[1], lo[2], ux, uy, nZ);
    if (!(omit & BOX_NO_BACK))
        FACE("+z", lo[0], lo[1], hi[2], ux, uy, Z);
#undef FACE
}

static double len3(const double v[3])
{
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
}

/* scenes/README.md "Counts from a density": max(2, ceil(L d) + 1) per edge. */
static uint32_t edge_samples(double length, double d)
{
    double n = ceil(length * d * (1 - 1e-9)) + 1;
    return n < 2 ? 2 : (uint32_t)n;
}

static uint32_t count_elements(const room_builder *b, double d)
{
    uint32_t n = 0;
    for (int q = 0; q < b->nquads; q++)
        n += edge_samples(len3(b->quads[q].u), d) * edge_samples(len3(b->quads[q].v), d);
    return n;
}

typedef struct sbuf {
    char *p;
    size_t n, cap;
    int failed;
} sbuf;

static void put(sbuf *s, const char *fmt, ...)
{
    if (s->failed)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(s->p ? s->p + s->n : NULL, s->p ? s->cap - s->n : 0, fmt, ap);
        va_end(ap);
        if (k < 0) {
            s->failed = 1;
            return;
        }
        if (s->p && s->n + (size_t)k < s->cap) {
            s->n += (size_t)k;
            return;
        }
        size_t cap = (s->cap ? s->cap * 2 : 4096) + (size_t)k;
        char *p = realloc(s->p, cap);
        if (!p) {
            s->failed = 1;
            return;
        }
        s->p = p;
        s->cap = cap;
    }
}

static void put_vec(sbuf *s, const double v[3])
{
    put(s, "[%.3f, %.3f, %.3f]", v[0], v[1], v[2]);
}

static char *write_json(const room_builder *b, const char *name, double density,
                        double cross_density, const double cam_pos[3], const double cam_at[3])
{
    sbuf s = {0};
    put(&s, "{\"name\": \"%s\", \"unit\": \"m\", \"density\": %.2f,\n \"materials\": [", name,
        density);
    for (int m = 0; m < b->nmats; m++) {
        put(&s, "%s\n  {\"name\": \"%s\", \"albedo\": ", m ? "," : "", b->mats[m].name);
        put(&s, "[%.3f, %.3f, %.3f]", b->mats[m].albedo[0], b->mats[m].albedo[1],
            b->mats[m].albedo[2]);
        const double *e = b->mats[m].emission;
        if (e[0] > 0 || e[1] > 0 || e[2] > 0)
            put(&s, ", \"emission\": [%.3f, %.3f, %.3f]", e[0], e[1], e[2]);
        put(&s, "}");
    }
    put(&s, "],\n \"objects\": [");
    for (int o = 0; o < b->nobjs; o++) {
        const gobj *ob = &b->objs[o];
        put(&s, "%s\n  {\"name\": \"%s\"", o ? "," : "", ob->name);
        if (ob->dynamic)
            put(&s, ", \"dynamic\": true, \"cross_density\": %.2f", cross_density);
        if (ob->animation[0])
            put(&s, ",\n   \"animation\": %s", ob->animation);
        put(&s, ",\n   \"surfaces\": [");
        int first = 1;
        for (int q = 0; q < b->nquads; q++) {
            const gquad *g = &b->quads[q];
            if (g->obj != o)
                continue;
            put(&s, "%s\n    {\"name\": \"%s\", \"material\": \"%s\", \"quad\": {\"origin\": ",
                first ? "" : ",", g->name, b->mats[g->mat].name);
            put_vec(&s, g->o);
            put(&s, ", \"u\": ");
            put_vec(&s, g->u);
            put(&s, ", \"v\": ");
            put_vec(&s, g->v);
            put(&s, "}}");
            first = 0;
        }
        put(&s, "]}");
    }
    put(&s, "],\n \"camera\": {\"position\": ");
    put_vec(&s, cam_pos);
    put(&s, ", \"look_at\": ");
    put_vec(&s, cam_at);
    put(&s, ", \"up\": [0, 1, 0], \"fov_degrees\": 75, \"width\": 128, \"height\": 128}}\n");
    if (s.failed) {
        free(s.p);
        return NULL;
    }
    return s.p;
}

/* A grey albedo in [lo, hi], or a coloured one: each channel that grey
 * times [0.7, 1.3], kept in [0.1, 0.9]. */
static void albedo(rng *r, double lo, double hi, int coloured, double out[3])
{
    double g = uni(r, lo, hi);
    for (int c = 0; c < 3; c++) {
        double v = coloured ? g * uni(r, 0.7, 1.3) : g;
        out[c] = fmin(0.9, fmax(0.1, v));
    }
}

static void emission(rng *r, double out[3])
{
    double e = uni(r, 10, 60);
    for (int c = 0; c < 3; c++)
        out[c] = e * uni(r, 0.8, 1.0);
}

/* Appends to the description. */
static void describe(rooms_room *room, const char *fmt, ...)
{
    size_t n = strlen(room->description);
    if (n + 1 >= sizeof room->description)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(room->description + n, sizeof room->description - n, fmt, ap);
    va_end(ap);
}

static const double down[3] = {0, -1, 0};

/* A light of sx x sz m centred at (cx, cz) under the ceiling (y = H),
 * `below` m under it; flush (below 0): a hole in the ceiling too. */
static void ceiling_light(room_builder *b, rng *r, rooms_room *out, int room, double H,
                          double cx, double cz, double sx, double sz, double below,
                          double (*holes)[4], int *nholes, int *nlights)
{
    double x0 = mm(cx - sx / 2), x1 = mm(cx + sx / 2), z0 = mm(cz - sz / 2),
           z1 = mm(cz + sz / 2);
    double e[3], la[3];
    emission(r, e);
    la[0] = la[1] = la[2] = uni(r, 0.1, 0.9);
    char mn[24], sn[24];
    snprintf(mn, sizeof mn, "lamp%d", *nlights + 1);
    snprintf(sn, sizeof sn, "light%d", *nlights + 1);
    int lm = add_mat(b, mn, la, e);
    double p[3] = {x0, H - below, z0}, u[3] = {x1 - x0, 0, 0}, v[3] = {0, 0, z1 - z0};
    add_quad(b, room, lm, sn, p, u, v, down);
    if (below == 0) {
        holes[*nholes][0] = x0;
        holes[*nholes][1] = x1;
        holes[*nholes][2] = z0;
        holes[*nholes][3] = z1;
        (*nholes)++;
    }
    describe(out, "; %s %.2f x %.2f m at (%.2f, %.2f) %s, exitance (%.1f, %.1f, %.1f), albedo "
                  "%.2f",
             sn, x1 - x0, z1 - z0, (x0 + x1) / 2, (z0 + z1) / 2,
             below == 0 ? "flush in the ceiling" : "1 cm below the ceiling", e[0], e[1], e[2],
             la[0]);
    (*nlights)++;
}

static const char *const room_names[ROOMS_COUNT] = {
    "small bright room, large flush ceiling light, table",
    "ceiling light 1 cm below the ceiling, table, cube sliding on the floor",
    "flush light on the back wall, floating box, box against the back wall, dark floor",
    "two flush ceiling lights of different sizes, box against the wall, floating box moving",
    "dark hall, small flush ceiling light, two boxes on the floor",
    "tall room, flush ceiling and wall lights, table, box sliding and turning on the floor",
};

int rooms_make(uint32_t index, uint32_t seed, rooms_room *out)
{
    memset(out, 0, sizeof *out);
    if (index >= ROOMS_COUNT)
        return -1;
    room_builder *b = calloc(1, sizeof *b);
    if (!b)
        return -1;
    rng r = {((uint64_t)seed << 32) ^ (0x5851f42d4c957f2dull * (index + 1))};
    rng_next(&r);
    snprintf(out->name, sizeof out->name, "%s", room_names[index]);
    out->dynamic = index % 2 == 1;

    /* Room size and albedo ranges. */
    static const double size_lo[ROOMS_COUNT][3] = {
        {2, 2, 2}, {3.5, 2.6, 2.8}, {3, 2.4, 3}, {4, 2.5, 3}, {8, 3, 6}, {2, 4, 2}};
    static const double size_hi[ROOMS_COUNT][3] = {
        {3.5, 2.8, 3.5}, {5, 3.2, 4}, {6, 3.5, 6}, {7, 3.5, 5}, {10, 5, 10}, {4, 10, 4}};
    static const double alb_lo[ROOMS_COUNT] = {0.6, 0.1, 0.6, 0.1, 0.1, 0.1};
    static const double alb_hi[ROOMS_COUNT] = {0.9, 0.9, 0.9, 0.9, 0.35, 0.9};
    double W = mm(uni(&r, size_lo[index][0], size_hi[index][0]));
    double H = mm(uni(&r, size_lo[index][1], size_hi[index][1]));
    double D = mm(uni(&r, size_lo[index][2], size_hi[index][2]));
    double m = fmin(W, D);
    double lo = alb_lo[index], hi = alb_hi[index];

    double a_floor[3], a_ceil[3], a_walls[3], a_right[3];
    albedo(&r, index == 2 ? 0.1 : lo, index == 2 ? 0.3 : hi, 0, a_floor);
    albedo(&r, lo, hi, 0, a_ceil);
    albedo(&r, lo, hi, 0, a_walls);
    albedo(&r, lo, hi, 1, a_right);
    int mat_floor = add_mat(b, "floor", a_floor, NULL);
    int mat_ceil = add_mat(b, "ceiling", a_ceil, NULL);
    int mat_walls = add_mat(b, "walls", a_walls, NULL);
    int mat_right = add_mat(b, "wall-xW", a_right, NULL);
    describe(out, "%.2f x %.2f x %.2f m (W x H x D); albedo floor %.2f, ceiling %.2f, walls "
                  "%.2f, x = W wall (%.2f, %.2f, %.2f)",
             W, H, D, a_floor[0], a_ceil[0], a_walls[0], a_right[0], a_right[1], a_right[2]);

    int room = add_obj(b, "room", 0);
    static const double X[3] = {1, 0, 0}, Y[3] = {0, 1, 0}, Z[3] = {0, 0, 1};
    static const double nX[3] = {-1, 0, 0}, nY[3] = {0, -1, 0}, nZ[3] = {0, 0, -1};

    /* Lights: holes {x0, x1, y0, y1} in the ceiling (x, z) and in a wall. */
    double ceil_holes[2][4], wall_holes[1][4];
    int n_ceil_holes = 0, n_wall_holes = 0;
    int wall_light_on = 0; /* 1: back wall z = D (x, y), 2: wall x = W (z, y) */
    int nlights = 0;
    /* Ceiling lights: centre (lcx, lcz) and sizes (lsx, lsz), drawn one after
     * the other (C leaves the order of a call's arguments open). */
    double lcx, lcz, lsx, lsz;
    switch (index) {
    case 0:
        lcx = W * uni(&r, 0.4, 0.6);
        lcz = D * uni(&r, 0.4, 0.6);
        lsx = W * uni(&r, 0.25, 0.45);
        lsz = D * uni(&r, 0.25, 0.45);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.0, ceil_holes,
                      &n_ceil_holes, &nlights);
        break;
    case 1:
        lcx = W * uni(&r, 0.4, 0.6);
        lcz = D * uni(&r, 0.4, 0.6);
        lsx = uni(&r, 0.8, 1.4);
        lsz = uni(&r, 0.6, 1.0);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.01, ceil_holes,
                      &n_ceil_holes, &nlights);
        break;
    case 3:
        lcx = W * uni(&r, 0.3, 0.4);
        lcz = D * uni(&r, 0.4, 0.6);
        lsx = uni(&r, 0.8, 1.5);
        lsz = uni(&r, 0.5, 1.0);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.0, ceil_holes,
                      &n_ceil_holes, &nlights);
        lcx = W * uni(&r, 0.7, 0.8);
        lcz = D * uni(&r, 0.3, 0.7);
        lsx = lsz = uni(&r, 0.2, 0.4);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.0, ceil_holes,
                      &n_ceil_holes, &nlights);
        break;
    case 4:
        lcx = W * uni(&r, 0.4, 0.6);
        lcz = D * uni(&r, 0.4, 0.6);
        lsx = lsz = uni(&r, 0.3, 0.6);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.0, ceil_holes,
                      &n_ceil_holes, &nlights);
        break;
    case 5:
        lcx = W * uni(&r, 0.45, 0.55);
        lcz = D * uni(&r, 0.45, 0.55);
        lsx = W * uni(&r, 0.3, 0.5);
        lsz = D * uni(&r, 0.3, 0.5);
        ceiling_light(b, &r, out, room, H, lcx, lcz, lsx, lsz, 0.0, ceil_holes,
                      &n_ceil_holes, &nlights);
        break;
    default:
        break;
    }
    if (index == 2 || index == 5) {
        /* A flush wall light: on the back wall z = D (x, y) or the wall x = W (z, y). */
        int back = index == 2;
        double c = back ? W * uni(&r, 0.25, 0.4) : D * uni(&r, 0.3, 0.5);
        double s = back ? uni(&r, 0.4, 1.0) : uni(&r, 0.3, 0.8);
        double t = uni(&r, 0.3, 0.6);
        double y = back ? uni(&r, 1.5, 2.0) : uni(&r, 1.2, 2.0);
        y = fmin(y, H - 0.5);
        double h0 = mm(c - s / 2), h1 = mm(c + s / 2), v0 = mm(y - t / 2), v1 = mm(y + t / 2);
        wall_holes[0][0] = h0, wall_holes[0][1] = h1, wall_holes[0][2] = v0,
        wall_holes[0][3] = v1;
        n_wall_holes = 1;
        wall_light_on = back ? 1 : 2;
        double e[3], la[3];
        emission(&r, e);
        la[0] = la[1] = la[2] = uni(&r, 0.1, 0.9);
        char mn[24], sn[24];
        snprintf(mn, sizeof mn, "lamp%d", nlights + 1);
        snprintf(sn, sizeof sn, "light%d", nlights + 1);
        int lm = add_mat(b, mn, la, e);
        if (back) {
            double p[3] = {h0, v0, D}, u[3] = {h1 - h0, 0, 0}, v[3] = {0, v1 - v0, 0};
            add_quad(b, room, lm, sn, p, u, v, nZ);
        } else {
            double p[3] = {W, v0, h0}, u[3] = {0, 0, h1 - h0}, v[3] = {0, v1 - v0, 0};
            add_quad(b, room, lm, sn, p, u, v, nX);
        }
        describe(out, "; %s %.2f x %.2f m flush in the %s wall, centre %.2f m along it and "
                      "%.2f m high, exitance (%.1f, %.1f, %.1f), albedo %.2f",
                 sn, h1 - h0, v1 - v0, back ? "back (z = D)" : "x = W", (h0 + h1) / 2,
                 (v0 + v1) / 2, e[0], e[1], e[2], la[0]);
        nlights++;
    }

    /* The six inward quads. */
    {
        double o0[3] = {0, 0, 0}, oc[3] = {0, H, 0}, ob[3] = {0, 0, D}, orw[3] = {W, 0, 0};
        add_plane(b, room, mat_floor, "floor", o0, X, W, Z, D, Y, NULL, 0);
        add_plane(b, room, mat_ceil, "ceiling", oc, X, W, Z, D, nY,
                  (const double(*)[4])ceil_holes, n_ceil_holes);
        add_plane(b, room, mat_walls, "wall-x0", o0, Z, D, Y, H, X, NULL, 0);
        add_plane(b, room, mat_right, "wall-xW", orw, Z, D, Y, H, nX,
                  wall_light_on == 2 ? (const double(*)[4])wall_holes : NULL,
                  wall_light_on == 2 ? n_wall_holes : 0);
        add_plane(b, room, mat_walls, "wall-z0", o0, X, W, Y, H, Z, NULL, 0);
        add_plane(b, room, mat_walls, "wall-zD", ob, X, W, Y, H, nZ,
                  wall_light_on == 1 ? (const double(*)[4])wall_holes : NULL,
                  wall_light_on == 1 ? n_wall_holes : 0);
    }

    /* Boxes, each kind in its own zone of the floor. */
    double a_box[3];
    int has_table = index == 0 || index == 1 || index == 4 || index == 5;
    if (has_table) {
        double s = m * uni(&r, 0.12, 0.24), h = fmin(uni(&r, 0.4, 0.9), 0.4 * H);
        double cx = W * uni(&r, 0.6, 0.7), cz = D * uni(&r, 0.35, 0.45);
        albedo(&r, lo, hi, 1, a_box);
        int mt = add_mat(b, "table", a_box, NULL);
        int ot = add_obj(b, "table", 0);
        double p[3] = {mm(cx - s / 2), 0, mm(cz - s / 2)}, sz[3] = {mm(s), mm(h), mm(s)};
        add_box(b, ot, mt, "table", p, sz, BOX_NO_BOTTOM);
        describe(out, "; table %.2f x %.2f x %.2f m on the floor at (%.2f, %.2f), albedo "
                      "(%.2f, %.2f, %.2f)",
                 sz[0], sz[1], sz[2], p[0] + sz[0] / 2, p[2] + sz[2] / 2, a_box[0], a_box[1],
                 a_box[2]);
    }
    if (index == 2 || index == 3) {
        double sx = m * uni(&r, 0.12, 0.22), sz = m * uni(&r, 0.08, 0.15);
        double h = fmin(uni(&r, 0.5, 1.2), 0.4 * H);
        double cx = W * uni(&r, 0.6, 0.75);
        albedo(&r, lo, hi, 1, a_box);
        int mt = add_mat(b, "cabinet", a_box, NULL);
        int ot = add_obj(b, "cabinet", 0);
        double p[3] = {mm(cx - sx / 2), 0, mm(D - sz)}, s[3] = {mm(sx), mm(h), 0};
        s[2] = mm(D - p[2]);
        add_box(b, ot, mt, "cabinet", p, s, BOX_NO_BOTTOM | BOX_NO_BACK);
        describe(out, "; cabinet %.2f x %.2f x %.2f m on the floor against the back wall at "
                      "x = %.2f, albedo (%.2f, %.2f, %.2f)",
                 s[0], s[1], s[2], p[0] + s[0] / 2, a_box[0], a_box[1], a_box[2]);
    }
    if (index == 2 || index == 3) {
        double sx = m * uni(&r, 0.1, 0.2), sz = m * uni(&r, 0.1, 0.2);
        double h = fmin(m * uni(&r, 0.1, 0.2), 0.25 * H);
        double y0 = H * uni(&r, 0.3, 0.5);
        double cx = W * uni(&r, 0.4, 0.5), cz = D * uni(&r, 0.45, 0.55);
        int moving = index == 3;
        albedo(&r, lo, hi, 1, a_box);
        int mt = add_mat(b, moving ? "mover" : "floater", a_box, NULL);
        int ot = add_obj(b, moving ? "mover" : "floater", moving);
        double p[3] = {mm(cx - sx / 2), mm(y0), mm(cz - sz / 2)}, s[3] = {mm(sx), mm(h), mm(sz)};
        add_box(b, ot, mt, moving ? "mover" : "floater", p, s, 0);
        describe(out, "; %s %.2f x %.2f x %.2f m floating %.2f m above the floor at (%.2f, "
                      "%.2f), albedo (%.2f, %.2f, %.2f)",
                 moving ? "moving box" : "floating box", s[0], s[1], s[2], p[1],
                 p[0] + s[0] / 2, p[2] + s[2] / 2, a_box[0], a_box[1], a_box[2]);
        if (moving) {
            double dx = mm(0.3 * W), dy = mm(0.05 * H);
            snprintf(b->objs[ot].animation, sizeof b->objs[ot].animation,
                     "{\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]}, {\"time\": 1, "
                     "\"translate\": [%.3f, %.3f, 0]}], \"loop\": false}",
                     dx, dy);
            describe(out, ", moving (%.2f, %.2f, 0) m in 1 s", dx, dy);
        }
    }
    if (index == 1 || index == 4 || index == 5) {
        /* A floor box (4) or a cube sliding on the floor (1, 5; turning in 5). */
        double s = m * uni(&r, 0.1, 0.16);
        double h = index == 4 ? fmin(uni(&r, 0.3, 1.5), 0.4 * H) : s;
        double cx = W * uni(&r, 0.3, 0.35), cz = D * uni(&r, 0.7, 0.78);
        int moving = index != 4;
        albedo(&r, lo, hi, 1, a_box);
        int mt = add_mat(b, moving ? "mover" : "crate", a_box, NULL);
        int ot = add_obj(b, moving ? "mover" : "crate", moving);
        double p[3] = {mm(cx - s / 2), 0, mm(cz - s / 2)}, sz[3] = {mm(s), mm(h), mm(s)};
        add_box(b, ot, mt, moving ? "mover" : "crate", p, sz, BOX_NO_BOTTOM);
        describe(out, "; %s %.2f x %.2f x %.2f m on the floor at (%.2f, %.2f), albedo (%.2f, "
                      "%.2f, %.2f)",
                 moving ? "moving box" : "crate", sz[0], sz[1], sz[2], p[0] + sz[0] / 2,
                 p[2] + sz[2] / 2, a_box[0], a_box[1], a_box[2]);
        if (moving) {
            double dx = mm(0.3 * W);
            if (index == 5) {
                double rate = uni(&r, 30, 60);
                snprintf(b->objs[ot].animation, sizeof b->objs[ot].animation,
                         "{\"rotate\": {\"axis\": [0, 1, 0], \"pivot\": [%.3f, 0, %.3f], "
                         "\"degrees_per_second\": %.1f}, \"keyframes\": [{\"time\": 0, "
                         "\"translate\": [0, 0, 0]}, {\"time\": 1, \"translate\": [%.3f, 0, "
                         "0]}], \"loop\": false}",
                         p[0] + sz[0] / 2, p[2] + sz[2] / 2, rate, dx);
                describe(out, ", sliding %.2f m along x in 1 s and turning %.1f degrees/s", dx,
                         rate);
            } else {
                snprintf(b->objs[ot].animation, sizeof b->objs[ot].animation,
                         "{\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]}, {\"time\": "
                         "1, \"translate\": [%.3f, 0, 0]}], \"loop\": false}",
                         dx);
                describe(out, ", sliding %.2f m along x in 1 s", dx);
            }
        }
    }

    /* Density: the least multiple of 0.01 per metre reaching the target. */
    uint32_t target = (uint32_t)uni(&r, ROOMS_MIN_ELEMENTS, ROOMS_MAX_ELEMENTS + 1);
    uint32_t klo = 10, khi = 100000; /* density x 100 */
    while (klo < khi) {
        uint32_t k = (klo + khi) / 2;
        if (count_elements(b, k / 100.0) >= target)
            khi = k;
        else
            klo = k + 1;
    }
    out->density = klo / 100.0;
    out->elements = count_elements(b, out->density);
    double cross = round(50.0 * out->density) / 100.0;
    if (cross < 1)
        cross = 1;
    describe(out, "; density %.2f/m%s, %u elements", out->density, "", out->elements);
    if (out->dynamic)
        describe(out, " (mover cross_density %.2f/m)", cross);

    double cam[3] = {mm(fmax(0.3, 0.12 * W)), mm(fmin(1.6, 0.55 * H)), mm(fmax(0.3, 0.12 * D))};
    double at[3] = {mm(0.9 * W), mm(fmin(1.0, 0.35 * H)), mm(0.9 * D)};
    char name[32];
    snprintf(name, sizeof name, "room-%u", index);
    out->json = b->overflow ? NULL : write_json(b, name, out->density, cross, cam, at);
    free(b);
    return out->json ? 0 : -1;
}

void rooms_free(rooms_room *room)
{
    free(room->json);
    room->json = NULL;
}
