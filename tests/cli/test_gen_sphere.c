/* tools/gen_displaced_sphere against the shipped scenes/models/heavy-sphere.ply:
 * the generator run with the shipped arguments remakes the file (and
 * scenes/models/ball-80.ply) byte for byte, and the file itself is a closed, consistently oriented surface
 * of sphere topology with the triangle count the frequency gives. The
 * mesh checks read the PLY here, with no code of the generator.
 * Usage: test_gen_sphere GENERATOR SOURCE_ROOT BUILD_DIR */
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"

/* The arguments scenes/README.md gives for the shipped file. */
#define FREQUENCY 71u
static const char *const shipped_args[] = {"--frequency", "71",         "--radius", "0.15",
                                           "--amplitude", "0.08",       "--waves",  "7"};

/* Runs argv; returns its exit status, or -1 if it did not exit normally. */
static int run(char *const argv[])
{
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        execv(argv[0], argv);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

static unsigned char *read_all(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        CHECK(0, "%s: %s", path, strerror(errno));
        return NULL;
    }
    unsigned char *data = NULL;
    size_t cap = 0, n = 0;
    for (;;) {
        if (n == cap) {
            cap = cap ? 2 * cap : 1 << 20;
            unsigned char *grown = realloc(data, cap);
            if (!grown) {
                free(data);
                fclose(f);
                CHECK(0, "%s: out of memory", path);
                return NULL;
            }
            data = grown;
        }
        size_t got = fread(data + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    fclose(f);
    *size = n;
    return data;
}

static uint32_t get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

/* The mesh of a binary little-endian PLY of float x, y, z vertices and
 * uchar-counted uint faces: closed (every edge in exactly two triangles,
 * walked in opposite directions, so that the orientation is consistent),
 * outward (positive volume), Euler characteristic 2 (a sphere). */
static void check_mesh(const char *what, const unsigned char *data, size_t size)
{
    const char *end_tag = "end_header\n";
    const unsigned char *body = NULL;
    for (size_t k = 0; k + strlen(end_tag) <= size && k < 4096 && !body; k++)
        if (!memcmp(data + k, end_tag, strlen(end_tag)))
            body = data + k + strlen(end_tag);
    CHECK(body != NULL, "%s: no end_header", what);
    if (!body)
        return;
    char header[4096];
    size_t hlen = (size_t)(body - data);
    memcpy(header, data, hlen);
    header[hlen] = 0;
    unsigned vertices = 0, faces = 0;
    const char *v = strstr(header, "element vertex "), *f = strstr(header, "element face ");
    CHECK(strstr(header, "format binary_little_endian 1.0\n") != NULL, "%s: not binary LE",
          what);
    CHECK(v && sscanf(v, "element vertex %u", &vertices) == 1, "%s: no vertex count", what);
    CHECK(f && sscanf(f, "element face %u", &faces) == 1, "%s: no face count", what);
    CHECK(strstr(header, "property list uchar uint vertex_indices\n") != NULL,
          "%s: faces are not uchar/uint lists", what);
    /* Class I geodesic sphere: each of 20 faces cut into N^2 triangles. */
    CHECK(faces == 20 * FREQUENCY * FREQUENCY, "%s: %u triangles, want 20 x %u^2 = %u", what,
          faces, FREQUENCY, 20 * FREQUENCY * FREQUENCY);
    CHECK(faces >= 100000, "%s: %u triangles, the heavy mesh has at least 100000", what, faces);
    size_t need = hlen + 12ull * vertices + 13ull * faces;
    CHECK(size == need, "%s: %zu bytes, header says %zu", what, size, need);
    if (size != need || faces == 0)
        return;

    const unsigned char *fp = body + 12ull * vertices;
    uint64_t *edges = malloc(3ull * faces * sizeof(uint64_t));
    CHECK(edges != NULL, "out of memory");
    if (!edges)
        return;
    unsigned bad_count = 0, bad_index = 0, degenerate = 0;
    double volume6 = 0;
    for (uint32_t t = 0; t < faces; t++) {
        const unsigned char *r = fp + 13ull * t;
        bad_count += r[0] != 3;
        uint32_t idx[3] = {get_u32(r + 1), get_u32(r + 5), get_u32(r + 9)};
        float p[3][3];
        for (int k = 0; k < 3; k++) {
            if (idx[k] >= vertices) {
                bad_index++;
                idx[k] = 0;
            }
            memcpy(p[k], body + 12ull * idx[k], 12);
        }
        degenerate += idx[0] == idx[1] || idx[1] == idx[2] || idx[0] == idx[2];
        /* Signed volume of the tetrahedron (origin, p0, p1, p2), times 6. */
        volume6 += (double)p[0][0] * ((double)p[1][1] * p[2][2] - (double)p[1][2] * p[2][1]) -
                   (double)p[0][1] * ((double)p[1][0] * p[2][2] - (double)p[1][2] * p[2][0]) +
                   (double)p[0][2] * ((double)p[1][0] * p[2][1] - (double)p[1][1] * p[2][0]);
        for (int k = 0; k < 3; k++)
            edges[3ull * t + k] = (uint64_t)idx[k] << 32 | idx[(k + 1) % 3];
    }
    CHECK(bad_count == 0 && bad_index == 0 && degenerate == 0,
          "%s: %u faces not triangles, %u indices out of range, %u degenerate", what, bad_count,
          bad_index, degenerate);
    qsort(edges, 3ull * faces, sizeof(uint64_t), cmp_u64);
    /* Every directed edge once, and its reverse present: each undirected
     * edge in exactly two triangles, which walk it in opposite directions. */
    uint64_t repeated = 0, unmatched = 0;
    for (uint64_t k = 0; k < 3ull * faces; k++) {
        if (k > 0 && edges[k] == edges[k - 1])
            repeated++;
        uint64_t rev = (edges[k] & 0xffffffffu) << 32 | edges[k] >> 32;
        if (!bsearch(&rev, edges, 3ull * faces, sizeof(uint64_t), cmp_u64))
            unmatched++;
    }
    CHECK(repeated == 0, "%s: %llu directed edges repeated (an edge in more than two "
          "triangles, or two triangles the same way round)", what, (unsigned long long)repeated);
    CHECK(unmatched == 0, "%s: %llu edges without a triangle on their other side (open)", what,
          (unsigned long long)unmatched);
    uint64_t e = 3ull * faces / 2;
    long long euler = (long long)vertices - (long long)e + (long long)faces;
    CHECK(euler == 2, "%s: V - E + F = %u - %llu + %u = %lld, a sphere has 2", what, vertices,
          (unsigned long long)e, faces, euler);
    /* Radius 0.15 m, displaced by at most 8%: the volume of a ball near it. */
    double volume = volume6 / 6, ball = 4.0 / 3.0 * 3.14159265358979 * 0.15 * 0.15 * 0.15;
    CHECK(volume > 0.75 * ball && volume < 1.3 * ball,
          "%s: enclosed volume %g m^3 (a ball of 0.15 m: %g): not outward, or not that sphere",
          what, volume, ball);
    fprintf(stderr, "%s: %u vertices, %u triangles, %llu edges, each in two triangles; "
            "volume %.6g m^3 (ball %.6g)\n", what, vertices, faces, (unsigned long long)e,
            volume, ball);
    free(edges);
}

/* Runs the generator with `args` into `made` and checks that it wrote the
 * bytes of `shipped`; returns those (the caller frees them), or NULL. */
static unsigned char *remake(char *gen, const char *shipped, char *made,
                             const char *const *args, size_t nargs, size_t *size)
{
    char *gen_argv[16] = {gen, "--out", made};
    size_t n = 3;
    for (size_t k = 0; k < nargs && n + 1 < 16; k++)
        gen_argv[n++] = (char *)args[k];
    gen_argv[n] = NULL;
    int status = run(gen_argv);
    CHECK(status == 0, "%s exited %d", gen, status);
    size_t b_size = 0;
    unsigned char *a = read_all(shipped, size), *b = status == 0 ? read_all(made, &b_size) : NULL;
    if (a && b) {
        size_t first = 0;
        while (first < *size && first < b_size && a[first] == b[first])
            first++;
        CHECK(*size == b_size && first == *size,
              "%s (%zu bytes) and %s (%zu bytes) differ from byte %zu", shipped, *size, made,
              b_size, first);
    }
    free(b);
    return a;
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: test_gen_sphere GENERATOR SOURCE_ROOT BUILD_DIR\n");
        return 1;
    }
    char shipped[1024], made[1024];
    snprintf(shipped, sizeof(shipped), "%s/scenes/models/heavy-sphere.ply", argv[2]);
    snprintf(made, sizeof(made), "%s/heavy-sphere.ply", argv[3]);

    size_t a_size = 0;
    unsigned char *a = remake(argv[1], shipped, made, shipped_args,
                              sizeof(shipped_args) / sizeof(shipped_args[0]), &a_size);
    if (a)
        check_mesh(shipped, a, a_size);
    free(a);
    /* scenes/ball-room.json's ball, as scenes/README.md makes it. */
    static const char *const ball_args[] = {"--frequency", "2", "--radius", "0.08",
                                            "--amplitude", "0"};
    snprintf(shipped, sizeof(shipped), "%s/scenes/models/ball-80.ply", argv[2]);
    free(remake(argv[1], shipped, made, ball_args, sizeof(ball_args) / sizeof(ball_args[0]),
                &a_size));

    /* Bad arguments are exit status 1, an unwritable output 2. */
    char *bad1[] = {argv[1], "--out", made, "--frequency", "0", NULL};
    char *bad2[] = {argv[1], "--out", made, "--level", "3", "--frequency", "8", NULL};
    char *bad3[] = {argv[1], "--frequency", "4", NULL};
    char *bad4[] = {argv[1], "--out", made, "--radius", "-1", NULL};
    char *bad5[] = {argv[1], "--out", "/nonexistent-dir/x.ply", "--frequency", "2", NULL};
    CHECK(run(bad1) == 1, "--frequency 0 accepted");
    CHECK(run(bad2) == 1, "--level with --frequency accepted");
    CHECK(run(bad3) == 1, "no --out accepted");
    CHECK(run(bad4) == 1, "--radius -1 accepted");
    CHECK(run(bad5) == 2, "an unwritable --out is not exit status 2");
    remove(made);
    return test_finish();
}
