/* Cross's radiosity hemicubes are fp16, scaled so that the largest shot
 * radiosity of C reads 256 (src/solvers/cross.c). A frame's redistribution
 * takes that scale from the last one instead of waiting for its own
 * measure, and makes itself again where the two differ by more than 16x.
 * Here a dynamic lamp comes down from 40 m to 0.5 m above a floor in one
 * frame, the floor lit before by a faint static glow alone. The hemicubes
 * show C's light as the last frames left it, so the first frame at 0.5 m
 * still shows the floor as it was; the next one shows it about 3e5 times
 * brighter, past fp16's largest value at the old scale. That frame must be
 * made again (stats.cross_rescaled), stay finite and agree with a solve
 * made at that pose from the start; the frames after it (one still, one a
 * 5 cm move) must not be made again. Not made again (at the new scale
 * from then on), that frame's lamp reflected 0.0045 W/m^2 of the floor's
 * light against 2.67. With cross_regather after or on, M gathers again
 * after the iterations of the frame at t = 1, which lit the floor: that
 * regather is the one made again (cross.c regather_m), and the frame at
 * t = 2 then has the right scale; without its check, the lamp's light
 * gathered at the old scale reached the floor in the next frame, 2.6%
 * low. */
#include "gpu/gpu_test.h"

static const char *scene_json =
    "{\"unit\": \"m\", \"density\": 8,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"lamp\", \"albedo\": [0.5, 0.5, 0.5], \"emission\": [100, 100, 100]},"
    "   {\"name\": \"glow\", \"albedo\": [0, 0, 0], \"emission\": [0.05, 0.05, 0.05]}],"
    " \"objects\": [{\"name\": \"ground\", \"surfaces\": ["
    "   {\"name\": \"floor\", \"material\": \"white\", \"quad\": {\"origin\": [-1, 0, 1],"
    "     \"u\": [2, 0, 0], \"v\": [0, 0, -2]}},"
    "   {\"name\": \"glow\", \"material\": \"glow\", \"quad\": {\"origin\": [0.5, 3, 0.5],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0, 0.2]}}]},"
    "  {\"name\": \"lamp\", \"dynamic\": true, \"cross_density\": 4, \"surfaces\": ["
    "   {\"name\": \"panel\", \"material\": \"lamp\", \"quad\": {\"origin\": [-0.25, 0, -0.25],"
    "     \"u\": [0.5, 0, 0], \"v\": [0, 0, 0.5]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 40, 0]},"
    "     {\"time\": 1, \"translate\": [0, 0.5, 0]}, {\"time\": 3, \"translate\": [0, 0.5, 0]},"
    "     {\"time\": 4, \"translate\": [0, 0.45, 0]}],"
    "     \"loop\": false}}],"
    " \"camera\": {\"position\": [0, 3, 3], \"look_at\": [0, 0, 0],"
    "   \"fov_degrees\": 60, \"width\": 32, \"height\": 32}}";

static xrad_solver *make(xrad_context *ctx, const xrad_scene *scene, double t, uint32_t regather,
                         xrad_error *err)
{
    xrad_solver_desc d = {.method = XRAD_METHOD_CROSS,
                          .time = t,
                          .hemicube_res = 32,
                          .msaa = 1,
                          .cross_regather = regather};
    xrad_solver *s = NULL;
    if (xrad_solver_create(ctx, scene, &d, &s, err) || xrad_solver_solve(s, err)) {
        xrad_solver_destroy(&s);
        return NULL;
    }
    return s;
}

/* Surface `index`'s area-mean red radiosity less `emission` (what it
 * reflects) in atlas a; counts its non-finite elements into *bad. */
static double reflected(const xrad_scene *scene, uint32_t index, double emission,
                        const xrad_atlas *a, size_t *bad)
{
    xrad_surface_info in;
    xrad_error err = {0};
    if (xrad_scene_get_surface(scene, index, &in, &err))
        return NAN;
    double sum = 0;
    for (uint32_t j = 0; j < in.nv; j++)
        for (uint32_t i = 0; i < in.nu; i++) {
            float r = a->rgba[4 * ((size_t)(in.tile_y + j) * a->width + in.tile_x + i)];
            if (!isfinite(r))
                (*bad)++;
            sum += r;
        }
    return sum / ((double)in.nu * in.nv) - emission;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_parse(scene_json, strlen(scene_json), "cross_scale.json", &scene, &err) ==
              XRAD_OK,
          "%s", err.message);
    if (!ctx || !scene)
        return test_finish();
    xrad_atlas moved = {0}, direct = {0};
    CHECK(xrad_atlas_create(scene, &moved, &err) == XRAD_OK &&
              xrad_atlas_create(scene, &direct, &err) == XRAD_OK,
          "%s", err.message);

    static const struct {
        const char *name;
        uint32_t regather, want[4];
    } modes[] = {
        {"off", XRAD_CROSS_REGATHER_OFF, {0, 1, 0, 0}},
        {"after", XRAD_CROSS_REGATHER_AFTER, {1, 0, 0, 0}},
        {"on", XRAD_CROSS_REGATHER_ON, {1, 0, 0, 0}},
    };
    xrad_solver *ref = make(ctx, scene, 3.0, XRAD_CROSS_REGATHER_OFF, &err);
    CHECK(ref, "solve at 0.5 m: %s", err.message);
    bool solved = ref && xrad_solver_read(ref, &direct, &err) == XRAD_OK;
    CHECK(!ref || solved, "%s", err.message);
    xrad_solver_destroy(&ref);
    for (size_t m = 0; solved && m < sizeof(modes) / sizeof(modes[0]); m++) {
        xrad_solver *s = make(ctx, scene, 0.0, modes[m].regather, &err);
        CHECK(s, "regather %s: solve at 40 m: %s", modes[m].name, err.message);
        if (!s)
            continue;
        const double times[4] = {1.0, 2.0, 3.0, 4.0};
        xrad_solver_stats st = {0};
        for (int f = 0; f < 4; f++) {
            CHECK(xrad_solver_advance(s, times[f], &err) == XRAD_OK, "advance to t = %g: %s",
                  times[f], err.message);
            xrad_solver_get_stats(s, &st);
            CHECK(st.cross_rescaled == modes[m].want[f],
                  "regather %s: the frame at t = %g was made %u times again, want %u",
                  modes[m].name, times[f], st.cross_rescaled, modes[m].want[f]);
            if (f == 1)
                CHECK(xrad_solver_read(s, &moved, &err) == XRAD_OK, "%s", err.message);
        }
        xrad_solver_destroy(&s);
        /* The floor's light, and what the lamp reflects of it (its B less
         * its emission): with the old scale the gather hemicubes would
         * show the floor clipped at fp16's largest value. */
        const char *names[2] = {"floor", "lamp"};
        const uint32_t surface[2] = {0, 2};
        const double emission[2] = {0, 100};
        /* What M reflects of C's light comes a frame late without the
         * regather: 2.6% here. */
        const double tolerance[2] = {0.01, 0.05};
        for (uint32_t k = 0; k < 2; k++) {
            size_t bad = 0;
            double a = reflected(scene, surface[k], emission[k], &moved, &bad);
            double b = reflected(scene, surface[k], emission[k], &direct, &bad);
            CHECK(bad == 0, "%s: %zu non-finite elements", names[k], bad);
            printf("regather %-5s %s reflects %.5f moved 40 m -> 0.5 m, %.5f solved at 0.5 m\n",
                   modes[m].name, names[k], a, b);
            CHECK(b > 0.1 && fabs(a / b - 1) < tolerance[k],
                  "regather %s: %s: moved %.5f against solved %.5f", modes[m].name, names[k], a, b);
        }
    }
    xrad_atlas_destroy(&moved);
    xrad_atlas_destroy(&direct);
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
