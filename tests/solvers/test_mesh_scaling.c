/*
 * Scaling with triangles (issue 15): one room with a displaced sphere made
 * by tools/gen_displaced_sphere at four tessellations (320 to 11,520
 * triangles). For each: load time, elements, host memory, the GPU memory
 * a progressive solve (to 40% unshot) holds at its peak, and the times of
 * creating the solver and of the solve, printed.
 * Memory must be linear in triangles and elements: a least-squares fit
 * mem = a + b T + c E over the four leaves no point more than 2% off, for
 * the host's scene and the GPU's peak alike; and it must grow.
 * Usage: test_mesh_scaling GENERATOR BUILD_DIR
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "gpu/gpu_test.h"

#define SIZES 4
static const unsigned frequency[SIZES] = {4, 8, 16, 24};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int generate(const char *gen, const char *out, unsigned f)
{
    char freq[16];
    snprintf(freq, sizeof freq, "%u", f);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        execl(gen, gen, "--out", out, "--frequency", freq, "--radius", "0.2", "--amplitude",
              "0.03", "--waves", "5", (char *)NULL);
        _exit(127);
    }
    int status = 0;
    if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status))
        return -1;
    return WEXITSTATUS(status);
}

/* Least squares y = a + b t + c e over n points; returns the largest
 * |residual| / y. */
static double fit(const double *t, const double *e, const double *y, int n, double coef[3])
{
    double m[3][4] = {{0}};
    for (int i = 0; i < n; i++) {
        double x[3] = {1, t[i], e[i]};
        for (int r = 0; r < 3; r++) {
            for (int c = 0; c < 3; c++)
                m[r][c] += x[r] * x[c];
            m[r][3] += x[r] * y[i];
        }
    }
    /* Gaussian elimination with partial pivoting. */
    for (int c = 0; c < 3; c++) {
        int p = c;
        for (int r = c + 1; r < 3; r++)
            if (fabs(m[r][c]) > fabs(m[p][c]))
                p = r;
        for (int k = 0; k < 4; k++) {
            double tmp = m[c][k];
            m[c][k] = m[p][k];
            m[p][k] = tmp;
        }
        for (int r = 0; r < 3; r++) {
            if (r == c || m[c][c] == 0)
                continue;
            double f = m[r][c] / m[c][c];
            for (int k = c; k < 4; k++)
                m[r][k] -= f * m[c][k];
        }
    }
    for (int c = 0; c < 3; c++)
        coef[c] = m[c][c] != 0 ? m[c][3] / m[c][c] : 0;
    double worst = 0;
    for (int i = 0; i < n; i++)
        worst = fmax(worst, fabs(coef[0] + coef[1] * t[i] + coef[2] * e[i] - y[i]) / y[i]);
    return worst;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        CHECK(0, "usage: test_mesh_scaling GENERATOR BUILD_DIR");
        return test_finish();
    }
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    double tri[SIZES], elem[SIZES], host[SIZES], gpu[SIZES];
    int done = 0;
    fprintf(stderr, "%9s %9s %8s %10s %12s %9s %9s\n", "triangles", "elements", "load s",
            "host MiB", "GPU peak MiB", "create s", "solve s");
    for (int k = 0; k < SIZES; k++) {
        char ply[1024], json[4096];
        snprintf(ply, sizeof ply, "%s/scaling-%u.ply", argv[2], frequency[k]);
        CHECK(generate(argv[1], ply, frequency[k]) == 0, "%s: the generator failed", ply);
        snprintf(json, sizeof json,
                 "{\"unit\": \"m\", \"density\": 10, \"materials\": ["
                 "{\"name\": \"wall\", \"albedo\": [0.6, 0.6, 0.6]},"
                 "{\"name\": \"lamp\", \"albedo\": [0.1, 0.1, 0.1], \"emission\": [5, 5, 5]}],"
                 " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
                 "{\"name\": \"walls\", \"material\": \"wall\", \"inward\": true, \"box\": "
                 "{\"origin\": [0, 0, 0], \"u\": [1.2, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1.2]}},"
                 "{\"name\": \"lamp\", \"material\": \"lamp\", \"quad\": {\"origin\": "
                 "[0.45, 0.99, 0.45], \"u\": [0.3, 0, 0], \"v\": [0, 0, 0.3]}}]},"
                 " {\"name\": \"sphere\", \"translate\": [0.6, 0.3, 0.6], \"density\": 1,"
                 "  \"surfaces\": [{\"name\": \"sphere\", \"material\": \"wall\", \"mesh\": "
                 "{\"file\": \"%s\"}}]}],"
                 " \"camera\": {\"position\": [0.6, 0.5, 0.05], \"look_at\": [0.6, 0.4, 1]}}",
                 ply);
        double t0 = now();
        xrad_scene *scene = NULL;
        xrad_error err = {0};
        xrad_status st = xrad_scene_parse(json, strlen(json), "scaling.json", &scene, &err);
        double load = now() - t0;
        CHECK(st == XRAD_OK, "frequency %u: %s", frequency[k], err.message);
        if (st)
            break;
        xrad_scene_info info;
        xrad_scene_get_info(scene, &info);
        xrad_context_reset_memory_peak(ctx);
        xrad_solver *s = NULL;
        xrad_solver_desc d = {.method = XRAD_METHOD_PROGRESSIVE, .threshold = 0.4, .unshot = 1};
        double t1 = now(), t2 = t1;
        if (!(st = xrad_solver_create(ctx, scene, &d, &s, &err))) {
            t2 = now();
            st = xrad_solver_solve(s, &err);
        }
        double create = t2 - t1, solve = now() - t2;
        CHECK(st == XRAD_OK, "frequency %u: solve: %s", frequency[k], err.message);
        xrad_memory_stats mem;
        xrad_context_get_memory(ctx, &mem);
        xrad_solver_destroy(&s);
        tri[k] = info.triangles;
        elem[k] = info.elements;
        host[k] = (double)info.cpu_bytes;
        gpu[k] = (double)mem.total_peak;
        fprintf(stderr, "%9u %9u %8.3f %10.2f %12.2f %9.2f %9.2f\n", info.triangles,
                info.elements, load, host[k] / 1048576, gpu[k] / 1048576, create, solve);
        CHECK(info.triangles >= 20 * frequency[k] * frequency[k] - 40,
              "frequency %u: %u triangles, want about %u", frequency[k], info.triangles,
              20 * frequency[k] * frequency[k]);
        xrad_scene_destroy(&scene);
        unlink(ply);
        if (st)
            break;
        done++;
    }
    if (done == SIZES) {
        const char *what[2] = {"host scene memory", "GPU peak memory"};
        double *y[2] = {host, gpu};
        for (int m = 0; m < 2; m++) {
            double c[3];
            double worst = fit(tri, elem, y[m], SIZES, c);
            fprintf(stderr, "%s = %.0f B + %.1f B a triangle + %.1f B an element; worst point "
                    "%.2f%% off\n", what[m], c[0], c[1], c[2], 100 * worst);
            CHECK(worst <= 0.02, "%s is not linear in triangles and elements: a point %.2f%% "
                  "off the fit", what[m], 100 * worst);
            for (int k = 1; k < SIZES; k++)
                CHECK(y[m][k] > y[m][k - 1], "%s does not grow with the mesh", what[m]);
        }
    }
    gpu_test_end(&ctx);
    return test_finish();
}
