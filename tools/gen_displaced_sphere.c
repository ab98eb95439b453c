/* gen_displaced_sphere: writes a closed triangle mesh of a bumpy sphere as
 * binary little-endian PLY, for scenes that need a heavy model
 * (scenes/models/heavy-sphere.ply, scenes/README.md).
 *
 * The mesh is a class I geodesic sphere: every face of an icosahedron is cut
 * into N x N triangles (N, the frequency, segments along each edge), the
 * lattice points are pushed out onto the unit sphere and then moved
 * radially by a sum of three sines of the position. 20 N^2 triangles and
 * 10 N^2 + 2 vertices; N = 2^L gives the usual icosphere of L midpoint
 * subdivisions (20 x 4^L triangles). Vertices on the icosahedron's edges
 * and corners are shared by the faces that meet there, so every edge of the
 * mesh belongs to exactly two triangles (tests/cli/test_gen_sphere.c).
 *
 * The output is the same bytes on every IEEE 754 machine: the sine is
 * computed here from + and x alone (libm's sin may differ in the last bit
 * between versions), and the test compares the shipped file byte for byte. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FREQUENCY 1000u /* 20 million triangles, about 250 MB */
#define MAX_LEVEL 9u        /* 2^9 = 512 */

static const char *prog = "gen_displaced_sphere";

static void usage(FILE *f)
{
    fprintf(f,
            "usage: %s --out FILE.ply [--frequency N | --level L] [--radius R]\n"
            "                            [--amplitude A] [--waves W]\n"
            "\n"
            "Writes a closed triangle mesh of a displaced sphere as binary little-endian\n"
            "PLY (float x, y, z; uchar-counted uint indices, counter-clockwise seen from\n"
            "outside): an icosahedron whose faces are each cut into N x N triangles, on\n"
            "the sphere of radius R, every vertex moved along its radius to\n"
            "R (1 + A d) with d = (sin(W (x + 0.5 y)) + sin(W (y - 0.6 z) + 1)\n"
            "+ sin(W (z + 0.7 x) + 2)) / 3 at the unit direction (x, y, z).\n"
            "20 N^2 triangles, 10 N^2 + 2 vertices. The same arguments give the same\n"
            "bytes on any machine.\n"
            "\n"
            "  --out FILE       where to write the PLY (required)\n"
            "  --frequency N    segments along each icosahedron edge, 1 .. %u [71]\n"
            "  --level L        instead of N: N = 2^L (L midpoint subdivisions,\n"
            "                   20 x 4^L triangles), 0 .. %u\n"
            "  --radius R       metres (PLY has no unit; xrad reads metres), > 0 [0.15]\n"
            "  --amplitude A    relative displacement, 0 .. 0.9 [0.08]\n"
            "  --waves W        angular frequency of the sines, 0 .. 1000 [7]\n"
            "  --help           this text\n"
            "\n"
            "Exit status: 0 written, 1 bad arguments, 2 the file could not be written.\n",
            prog, MAX_FREQUENCY, MAX_LEVEL);
}

/* A number from argv[i + 1] for option argv[i], in [lo, hi]; integral if
 * `integer`. Returns 0, or prints why and returns 1. */
static int parse_number(int argc, char **argv, int i, double lo, double hi, int integer,
                        double *out)
{
    if (i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value (see --help)\n", prog, argv[i]);
        return 1;
    }
    const char *s = argv[i + 1];
    char *end = NULL;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v)) {
        fprintf(stderr, "%s: %s: '%s' is not a number\n", prog, argv[i], s);
        return 1;
    }
    if (integer && v != floor(v)) {
        fprintf(stderr, "%s: %s: must be an integer, got %s\n", prog, argv[i], s);
        return 1;
    }
    if (!(v >= lo && v <= hi)) {
        fprintf(stderr, "%s: %s: must be in [%g, %g], got %s\n", prog, argv[i], lo, hi, s);
        return 1;
    }
    *out = v;
    return 0;
}

/* sin(x) from + and x only, so that the mesh is bit-identical wherever
 * doubles are IEEE 754 (libm's sin is not required to round the same on
 * every system). Reduced to [-pi/2, pi/2], then its Taylor polynomial to
 * x^15: error below 1e-12 there, far under the float the PLY stores. */
static double det_sin(double x)
{
    const double two_pi = 6.283185307179586, pi = 3.141592653589793, half_pi = 1.5707963267948966;
    x -= two_pi * floor(x / two_pi + 0.5); /* [-pi, pi] */
    if (x > half_pi)
        x = pi - x;
    else if (x < -half_pi)
        x = -pi - x;
    double x2 = x * x, term = x, sum = x;
    for (int k = 1; k <= 7; k++) {
        term *= -x2 / ((2.0 * k) * (2.0 * k + 1));
        sum += term;
    }
    return sum;
}

/* The icosahedron: corners (0, +-1, +-t) and their cyclic permutations,
 * faces counter-clockwise seen from outside. */
static const double ico_corner[12][3] = {
    {-1, 1.618033988749895, 0}, {1, 1.618033988749895, 0}, {-1, -1.618033988749895, 0},
    {1, -1.618033988749895, 0}, {0, -1, 1.618033988749895}, {0, 1, 1.618033988749895},
    {0, -1, -1.618033988749895}, {0, 1, -1.618033988749895}, {1.618033988749895, 0, -1},
    {1.618033988749895, 0, 1}, {-1.618033988749895, 0, -1}, {-1.618033988749895, 0, 1},
};
static const uint32_t ico_face[20][3] = {
    {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
    {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1},
};

typedef struct mesh {
    uint32_t n;             /* frequency */
    uint32_t edge[30][2];   /* icosahedron edges, lo < hi */
    float *pos;             /* 3 per vertex */
    uint32_t vertex_count;
    double radius, amplitude, waves;
} mesh;

/* Writes vertex v at the point a + (b - a) i / n + (c - a) j / n of the
 * flat face, pushed onto the sphere and displaced. */
static void put_vertex(mesh *m, uint32_t v, const double *a, const double *b, const double *c,
                       uint32_t i, uint32_t j)
{
    double p[3], len2 = 0;
    for (int k = 0; k < 3; k++) {
        p[k] = a[k] + (b[k] - a[k]) * i / m->n + (c[k] - a[k]) * j / m->n;
        len2 += p[k] * p[k];
    }
    double inv = 1.0 / sqrt(len2);
    double x = p[0] * inv, y = p[1] * inv, z = p[2] * inv, w = m->waves;
    double d = (det_sin(w * (x + 0.5 * y)) + det_sin(w * (y - 0.6 * z) + 1.0) +
                det_sin(w * (z + 0.7 * x) + 2.0)) /
               3.0;
    double r = m->radius * (1.0 + m->amplitude * d);
    m->pos[3 * v] = (float)(x * r);
    m->pos[3 * v + 1] = (float)(y * r);
    m->pos[3 * v + 2] = (float)(z * r);
}

/* Vertex numbering: the 12 corners, then the n - 1 inner points of each
 * edge (from its lower corner), then the inner points of each face. */
static uint32_t edge_index(const mesh *m, uint32_t u, uint32_t v)
{
    uint32_t lo = u < v ? u : v, hi = u < v ? v : u;
    for (uint32_t e = 0; e < 30; e++)
        if (m->edge[e][0] == lo && m->edge[e][1] == hi)
            return e;
    return UINT32_MAX; /* not reached: the table holds every face's edges */
}

/* The point t steps from corner u towards corner v. */
static uint32_t edge_vertex(const mesh *m, uint32_t u, uint32_t v, uint32_t t)
{
    if (t == 0)
        return u;
    if (t == m->n)
        return v;
    uint32_t e = edge_index(m, u, v), step = u < v ? t : m->n - t;
    return 12 + e * (m->n - 1) + step - 1;
}

/* Lattice point (i, j) of face f: i steps along a->b, j along a->c. */
static uint32_t face_vertex(const mesh *m, uint32_t f, uint32_t i, uint32_t j)
{
    uint32_t a = ico_face[f][0], b = ico_face[f][1], c = ico_face[f][2], n = m->n;
    if (j == 0)
        return edge_vertex(m, a, b, i);
    if (i == 0)
        return edge_vertex(m, a, c, j);
    if (i + j == n)
        return edge_vertex(m, b, c, j);
    /* Inner points row by row: row j (1 .. n - 2) holds i = 1 .. n - 1 - j. */
    uint32_t before = (j - 1) * (n - 1) - (j - 1) * j / 2;
    uint32_t inner = (n - 1) * (n - 2) / 2;
    return 12 + 30 * (n - 1) + f * inner + before + i - 1;
}

static void put_u32(unsigned char *out, uint32_t v)
{
    for (int k = 0; k < 4; k++)
        out[k] = (unsigned char)(v >> (8 * k));
}

static int write_ply(const mesh *m, const char *path)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        fprintf(stderr, "%s: %s: cannot create: %s\n", prog, path, strerror(errno));
        return 2;
    }
    uint32_t n = m->n, tri_count = 20 * n * n;
    fprintf(f,
            "ply\nformat binary_little_endian 1.0\n"
            "comment gen_displaced_sphere frequency %u radius %.9g amplitude %.9g waves %.9g\n"
            "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %u\nproperty list uchar uint vertex_indices\nend_header\n",
            n, m->radius, m->amplitude, m->waves, m->vertex_count, tri_count);
    unsigned char buf[13];
    for (uint32_t v = 0; v < m->vertex_count; v++)
        for (int k = 0; k < 3; k++) {
            uint32_t bits;
            memcpy(&bits, &m->pos[3 * v + k], 4);
            put_u32(buf, bits);
            fwrite(buf, 1, 4, f);
        }
    /* Each face's n^2 triangles: per lattice cell (i, j) the upright one
     * and, where the cell is whole, the inverted one beside it; both keep
     * the icosahedron face's counter-clockwise order. */
    buf[0] = 3;
    for (uint32_t fc = 0; fc < 20; fc++)
        for (uint32_t j = 0; j < n; j++)
            for (uint32_t i = 0; i + j < n; i++) {
                uint32_t t[2][3] = {
                    {face_vertex(m, fc, i, j), face_vertex(m, fc, i + 1, j),
                     face_vertex(m, fc, i, j + 1)},
                    {0, 0, 0}};
                int count = 1;
                if (i + j + 1 < n) {
                    t[1][0] = face_vertex(m, fc, i + 1, j);
                    t[1][1] = face_vertex(m, fc, i + 1, j + 1);
                    t[1][2] = face_vertex(m, fc, i, j + 1);
                    count = 2;
                }
                for (int k = 0; k < count; k++) {
                    for (int c = 0; c < 3; c++)
                        put_u32(buf + 1 + 4 * c, t[k][c]);
                    fwrite(buf, 1, 13, f);
                }
            }
    int bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        fprintf(stderr, "%s: %s: write failed: %s\n", prog, path, strerror(errno));
        return 2;
    }
    return 0;
}

int main(int argc, char **argv)
{
    double frequency = 71, level = -1, radius = 0.15, amplitude = 0.08, waves = 7;
    const char *out = NULL;
    int have_frequency = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        int bad = 0;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--out")) {
            if (i + 1 >= argc || !argv[i + 1][0]) {
                fprintf(stderr, "%s: --out needs a file name (see --help)\n", prog);
                return 1;
            }
            out = argv[++i];
            continue;
        } else if (!strcmp(a, "--frequency")) {
            bad = parse_number(argc, argv, i, 1, MAX_FREQUENCY, 1, &frequency);
            have_frequency = 1;
        } else if (!strcmp(a, "--level")) {
            bad = parse_number(argc, argv, i, 0, MAX_LEVEL, 1, &level);
        } else if (!strcmp(a, "--radius")) {
            bad = parse_number(argc, argv, i, 0, 1e6, 0, &radius);
            if (!bad && !(radius > 0)) {
                fprintf(stderr, "%s: --radius: must be greater than 0, got %s\n", prog,
                        argv[i + 1]);
                bad = 1;
            }
        } else if (!strcmp(a, "--amplitude")) {
            bad = parse_number(argc, argv, i, 0, 0.9, 0, &amplitude);
        } else if (!strcmp(a, "--waves")) {
            bad = parse_number(argc, argv, i, 0, 1000, 0, &waves);
        } else {
            fprintf(stderr, "%s: unknown argument '%s' (see --help)\n", prog, a);
            return 1;
        }
        if (bad)
            return 1;
        i++;
    }
    if (!out) {
        fprintf(stderr, "%s: --out FILE.ply is required (see --help)\n", prog);
        return 1;
    }
    if (have_frequency && level >= 0) {
        fprintf(stderr, "%s: give --frequency or --level, not both\n", prog);
        return 1;
    }
    mesh m = {.n = level >= 0 ? 1u << (uint32_t)level : (uint32_t)frequency,
              .radius = radius,
              .amplitude = amplitude,
              .waves = waves};
    uint32_t n = m.n, ne = 0;
    for (uint32_t f = 0; f < 20; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t u = ico_face[f][k], v = ico_face[f][(k + 1) % 3];
            uint32_t lo = u < v ? u : v, hi = u < v ? v : u;
            uint32_t e = 0;
            while (e < ne && !(m.edge[e][0] == lo && m.edge[e][1] == hi))
                e++;
            if (e == ne) {
                m.edge[ne][0] = lo;
                m.edge[ne][1] = hi;
                ne++;
            }
        }
    m.vertex_count = 10 * n * n + 2;
    m.pos = malloc((size_t)m.vertex_count * 3 * sizeof(float));
    if (!m.pos) {
        fprintf(stderr, "%s: out of memory for %u vertices\n", prog, m.vertex_count);
        return 2;
    }
    for (uint32_t v = 0; v < 12; v++)
        put_vertex(&m, v, ico_corner[v], ico_corner[v], ico_corner[v], 0, 0);
    for (uint32_t e = 0; e < 30; e++)
        for (uint32_t t = 1; t < n; t++)
            put_vertex(&m, edge_vertex(&m, m.edge[e][0], m.edge[e][1], t),
                       ico_corner[m.edge[e][0]], ico_corner[m.edge[e][1]],
                       ico_corner[m.edge[e][1]], t, 0);
    for (uint32_t f = 0; f < 20; f++)
        for (uint32_t j = 1; j + 1 < n; j++)
            for (uint32_t i = 1; i + j < n; i++)
                put_vertex(&m, face_vertex(&m, f, i, j), ico_corner[ico_face[f][0]],
                           ico_corner[ico_face[f][1]], ico_corner[ico_face[f][2]], i, j);
    int st = write_ply(&m, out);
    free(m.pos);
    if (!st)
        printf("%s: %u triangles, %u vertices\n", out, 20 * n * n, m.vertex_count);
    return st;
}
