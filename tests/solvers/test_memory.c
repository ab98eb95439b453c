/* Cost follows the scene (issue "model only what the scene needs"):
 *   - without dynamic objects, incremental and cross allocate no
 *     redistribution state: the same GPU memory as progressive;
 *   - every surface's element grid is ceil(edge length x density) + 1
 *     samples per side (at least 2), with the density of the surface,
 *     else its object, else the scene, times the load's density scale;
 *   - GPU memory grows linearly with the element count: three densities,
 *     a least-squares line, every point within 2% of the growth over the
 *     range. */
#include "gpu/gpu_test.h"

/* A room (1 x 1 x 1 m), a light, and optionally a box that moves. %d: the
 * scene density; the box's cross_density stays 4, so that the patch count
 * stays fixed while the elements grow. */
static const char *room_fmt =
    "{\"unit\": \"m\", \"density\": %g,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"walls\", \"material\": \"white\", \"box\": {\"origin\": [0, 0, 0],"
    "     \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1]}, \"inward\": true},"
    "   {\"name\": \"light\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.4, 0.99, 0.4],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0, 0.2]}}]}"
    "  %s]}";
static const char *box_json =
    ", {\"name\": \"box\", \"dynamic\": true, \"cross_density\": 4, \"surfaces\": ["
    "   {\"name\": \"b\", \"material\": \"white\", \"box\": {\"origin\": [0.2, 0.0, 0.35],"
    "     \"u\": [0.25, 0, 0], \"v\": [0, 0.3, 0], \"w\": [0, 0, 0.25]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
    "     {\"time\": 1, \"translate\": [0.3, 0, 0]}]}}";

static xrad_scene *room(double density, bool dynamic)
{
    char json[4096];
    snprintf(json, sizeof(json), room_fmt, density, dynamic ? box_json : "");
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "room.json", &scene, &err);
    CHECK(st == XRAD_OK, "room: %s", err.message);
    return scene;
}

/* GPU memory a solver of `method` holds once created, by category. */
static bool solver_memory(xrad_context *ctx, const xrad_scene *scene, xrad_method method,
                          xrad_memory_stats *out)
{
    xrad_error err = {0};
    xrad_solver *s = NULL;
    /* The shooter table and its ID hemicubes hold min(nu, max_patches) x
     * min(nv, max_patches) patches of the scene's largest surface: 8 keeps
     * that at its cap over the densities of test_linear_growth, whose
     * rooms' walls have 9 samples a side and more, so what grows is what
     * follows the elements. */
    xrad_solver_desc d = {.method = method, .hemicube_res = 32, .max_patches = 8};
    xrad_status st = xrad_solver_create(ctx, scene, &d, &s, &err);
    CHECK(st == XRAD_OK, "%s: %s", xrad_method_name(method), err.message);
    if (!st)
        xrad_context_get_memory(ctx, out);
    xrad_solver_destroy(&s);
    return st == XRAD_OK;
}

static uint32_t category(const xrad_memory_stats *m, const char *name)
{
    for (uint32_t c = 0; c < m->count; c++)
        if (!strcmp(m->names[c], name))
            return c;
    CHECK(0, "no memory category '%s'", name);
    return 0;
}

static void test_static_needs_no_redistribution(xrad_context *ctx)
{
    xrad_scene *scene = room(8, false);
    xrad_memory_stats p, m;
    if (!scene || !solver_memory(ctx, scene, XRAD_METHOD_PROGRESSIVE, &p)) {
        xrad_scene_destroy(&scene);
        return;
    }
    uint32_t r = category(&p, "redistribution");
    xrad_method dyn[2] = {XRAD_METHOD_INCREMENTAL, XRAD_METHOD_CROSS};
    for (int k = 0; k < 2; k++) {
        if (!solver_memory(ctx, scene, dyn[k], &m))
            continue;
        CHECK(m.bytes[r] == 0, "%s on a static scene: %llu bytes of redistribution state",
              xrad_method_name(dyn[k]), (unsigned long long)m.bytes[r]);
        CHECK(m.total == p.total, "%s on a static scene: %llu bytes, progressive %llu",
              xrad_method_name(dyn[k]), (unsigned long long)m.total,
              (unsigned long long)p.total);
    }
    xrad_scene_destroy(&scene);
    /* And with a moving box they do keep some. */
    scene = room(8, true);
    for (int k = 0; scene && k < 2; k++)
        if (solver_memory(ctx, scene, dyn[k], &m))
            CHECK(m.bytes[r] > 0, "%s with a moving box keeps no redistribution state",
                  xrad_method_name(dyn[k]));
    xrad_scene_destroy(&scene);
}

/* The documented rule, computed here. */
static uint32_t samples(double length, double density)
{
    double n = ceil(length * density - 1e-9) + 1;
    return n < 2 ? 2 : (uint32_t)n;
}

static void test_element_counts(void)
{
    static const char *json =
        "{\"unit\": \"m\", \"density\": 10, %s"
        " \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
        " \"objects\": [{\"name\": \"a\", \"surfaces\": ["
        "   {\"name\": \"long\", \"material\": \"m\", \"quad\": {\"origin\": [0, 0, 0],"
        "     \"u\": [2.5, 0, 0], \"v\": [0, 0.3, 0]}},"
        "   {\"name\": \"own\", \"material\": \"m\", \"density\": 7, \"quad\": {"
        "     \"origin\": [0, 0, 1], \"u\": [1, 0, 0], \"v\": [0, 0.05, 0]}}]},"
        "  {\"name\": \"b\", \"density\": 4, \"surfaces\": ["
        "   {\"name\": \"sq\", \"material\": \"m\", \"quad\": {\"origin\": [0, 0, 2],"
        "     \"u\": [1.3, 0, 0], \"v\": [0, 1.3, 0]}}]}]}";
    /* Lengths and the density that applies (surface, else object, else scene). */
    const double want[3][3] = {{2.5, 0.3, 10}, {1, 0.05, 7}, {1.3, 1.3, 4}};
    const char *quality[2] = {"", "\"quality\": {\"density_scale\": 2},"};
    for (int q = 0; q < 2; q++) {
        double scale = q ? 2 : 1;
        char text[2048];
        snprintf(text, sizeof(text), json, quality[q]);
        xrad_scene *scene = NULL;
        xrad_error err = {0};
        xrad_status st = xrad_scene_parse(text, strlen(text), "counts.json", &scene, &err);
        CHECK(st == XRAD_OK, "counts: %s", err.message);
        for (uint32_t i = 0; !st && i < 3; i++) {
            xrad_surface_info si;
            st = xrad_scene_get_surface(scene, i, &si, &err);
            CHECK(st == XRAD_OK, "surface %u: %s", i, err.message);
            uint32_t nu = samples(want[i][0], want[i][2] * scale);
            uint32_t nv = samples(want[i][1], want[i][2] * scale);
            CHECK(!st && si.nu == nu && si.nv == nv,
                  "surface '%s', scale %g: %u x %u samples, want %u x %u", si.name, scale,
                  si.nu, si.nv, nu, nv);
        }
        xrad_scene_destroy(&scene);
    }
    /* The loader's scale wins over the file's. */
    char text[2048];
    snprintf(text, sizeof(text), json, quality[1]);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse_with(text, strlen(text), "counts.json",
                                           &(xrad_scene_load_desc){.density_scale = 0.5},
                                           &scene, &err);
    xrad_surface_info si;
    CHECK(st == XRAD_OK && !xrad_scene_get_surface(scene, 0, &si, &err) &&
              si.nu == samples(2.5, 5),
          "loader density scale 0.5: %s, %u samples", err.message, si.nu);
    xrad_scene_destroy(&scene);
}

static void test_linear_growth(xrad_context *ctx, xrad_method method)
{
    const double densities[3] = {10, 16, 22};
    double n[3] = {0}, bytes[3] = {0};
    for (int k = 0; k < 3; k++) {
        xrad_scene *scene = room(densities[k], true);
        xrad_memory_stats m;
        if (!scene || !solver_memory(ctx, scene, method, &m)) {
            xrad_scene_destroy(&scene);
            return;
        }
        xrad_scene_info in;
        xrad_scene_get_info(scene, &in);
        n[k] = in.elements;
        bytes[k] = (double)m.total;
        xrad_scene_destroy(&scene);
    }
    /* Least squares bytes = a + b n. */
    double mn = (n[0] + n[1] + n[2]) / 3, mb = (bytes[0] + bytes[1] + bytes[2]) / 3;
    double sxy = 0, sxx = 0;
    for (int k = 0; k < 3; k++) {
        sxy += (n[k] - mn) * (bytes[k] - mb);
        sxx += (n[k] - mn) * (n[k] - mn);
    }
    /* Deviations relative to the growth over the range, not to the total:
     * the fixed part (hemicube images) would hide a quadratic term. */
    double b = sxy / sxx, a = mb - b * mn, worst = 0, span = bytes[2] - bytes[0];
    for (int k = 0; k < 3; k++)
        worst = fmax(worst, fabs(bytes[k] - (a + b * n[k])) / span);
    fprintf(stderr,
            "%s: %.0f, %.0f, %.0f elements -> %.2f, %.2f, %.2f MiB; %.0f bytes per element + "
            "%.2f MiB; largest deviation from the line %.3f%% of the growth\n",
            xrad_method_name(method), n[0], n[1], n[2], bytes[0] / 1048576, bytes[1] / 1048576,
            bytes[2] / 1048576, b, a / 1048576, 100 * worst);
    CHECK(b > 0, "%s: memory does not grow with the elements (slope %g)",
          xrad_method_name(method), b);
    CHECK(span > 0 && worst < 0.02, "%s: memory is %.2f%% of its growth off a line",
          xrad_method_name(method), 100 * worst);
}

int main(void)
{
    test_element_counts();
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    test_static_needs_no_redistribution(ctx);
    test_linear_growth(ctx, XRAD_METHOD_PROGRESSIVE);
    test_linear_growth(ctx, XRAD_METHOD_CROSS);
    test_linear_growth(ctx, XRAD_METHOD_INCREMENTAL);
    gpu_test_end(&ctx);
    return test_finish();
}
