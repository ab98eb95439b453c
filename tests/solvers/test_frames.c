/* Moving objects between solves (xrad_solver_set_time): a solver created at
 * pose 0 and moved to time T solves exactly what a solver created at T
 * solves, for every GPU method; and the move changes the solution (the box
 * really moved, so a stale pose cannot pass). Frames after a solve that
 * max_iterations stopped still shoot their frame_shots: the limit is a
 * call's, not the solver's lifetime's. */
#include "gpu/gpu_test.h"

/* A room with a ceiling light (facing down) and a box sliding 0.3 m along x in 1 s. */
static const char *scene_json =
    "{\"unit\": \"m\", \"density\": 6,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"walls\", \"material\": \"white\", \"box\": {\"origin\": [0, 0, 0],"
    "     \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1]}, \"inward\": true},"
    "   {\"name\": \"light\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.4, 0.99, 0.4],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0, 0.2]}}]},"
    "  {\"name\": \"box\", \"dynamic\": true, \"surfaces\": ["
    "   {\"name\": \"b\", \"material\": \"white\", \"box\": {\"origin\": [0.2, 0.0, 0.35],"
    "     \"u\": [0.25, 0, 0], \"v\": [0, 0.3, 0], \"w\": [0, 0, 0.25]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
    "     {\"time\": 1, \"translate\": [0.3, 0, 0]}], \"loop\": false}}],"
    " \"camera\": {\"position\": [0.5, 0.5, 0.02], \"look_at\": [0.5, 0.5, 1],"
    "   \"fov_degrees\": 70, \"width\": 64, \"height\": 64}}";

static xrad_status solve_at(xrad_context *ctx, const xrad_scene *scene, xrad_method m,
                            double create_time, double solve_time, xrad_atlas *out,
                            xrad_error *err)
{
    xrad_solver_desc d = {.method = m, .time = create_time, .hemicube_res = 16, .msaa = 1};
    xrad_solver *s = NULL;
    xrad_status st = xrad_solver_create(ctx, scene, &d, &s, err);
    if (!st && create_time != solve_time)
        st = xrad_solver_solve(s, err); /* a solution at the old pose first */
    if (!st && create_time != solve_time)
        st = xrad_solver_set_time(s, solve_time, err);
    if (!st)
        st = xrad_solver_solve(s, err);
    if (!st)
        st = xrad_solver_read(s, out, err);
    xrad_solver_destroy(&s);
    return st;
}

static double max_abs_diff(const xrad_atlas *a, const xrad_atlas *b, double *max_b)
{
    double d = 0;
    *max_b = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++) {
        d = fmax(d, fabs((double)a->rgba[i] - b->rgba[i]));
        *max_b = fmax(*max_b, fabs((double)b->rgba[i]));
    }
    return d;
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_parse(scene_json, strlen(scene_json), "frames.json", &scene, &err) ==
              XRAD_OK,
          "%s", err.message);
    if (!ctx || !scene)
        return test_finish();
    const xrad_method methods[] = {XRAD_METHOD_PROGRESSIVE, XRAD_METHOD_GATHER};
    for (size_t k = 0; k < sizeof(methods) / sizeof(methods[0]); k++) {
        xrad_atlas direct = {0}, moved = {0}, rest = {0};
        CHECK(xrad_atlas_create(scene, &direct, &err) == XRAD_OK &&
                  xrad_atlas_create(scene, &moved, &err) == XRAD_OK &&
                  xrad_atlas_create(scene, &rest, &err) == XRAD_OK,
              "%s", err.message);
        const char *name = xrad_method_name(methods[k]);
        CHECK(solve_at(ctx, scene, methods[k], 0.8, 0.8, &direct, &err) == XRAD_OK, "%s: %s",
              name, err.message);
        CHECK(solve_at(ctx, scene, methods[k], 0.0, 0.8, &moved, &err) == XRAD_OK, "%s: %s",
              name, err.message);
        CHECK(solve_at(ctx, scene, methods[k], 0.0, 0.0, &rest, &err) == XRAD_OK, "%s: %s",
              name, err.message);
        double max_b;
        double same = max_abs_diff(&moved, &direct, &max_b);
        double change = max_abs_diff(&rest, &direct, &max_b);
        /* The same work on the same pose: equal up to float summation order. */
        CHECK(same <= 1e-5 * max_b, "%s: moved vs created at T differ by %g (max B %g)", name,
              same, max_b);
        /* The box moved 0.24 m: its shadow moves (about 0.1 W/m^2 of direct
         * light on the floor; max B is the lamp's 20), a stale pose gives 0. */
        CHECK(change > 1e-3 * max_b, "%s: pose 0 and T differ by only %g (max B %g)", name,
              change, max_b);
        xrad_atlas_destroy(&direct);
        xrad_atlas_destroy(&moved);
        xrad_atlas_destroy(&rest);
    }
    /* The shots of a frame are its own: the progressive iterations once
     * stopped on the count since the solve, so that a solve that used up
     * max_iterations, or any solver past 100,000 selections in all
     * (incremental on cornell-lowq selects 48 a frame: about 2,000 frames,
     * a minute of xrad view at 30 fps; cross 3), left every later frame one
     * batch of 4 shots, its redistribution's unshot light never shot (a
     * 0.999 furnace's ambient term then read 8 times the power bound).
     * FRAME_SHOTS of a box sliding 0.03 m do not all come to nothing: the
     * threshold is 1e-7. */
    enum { SOLVE_SHOTS = 12, FRAME_SHOTS = 24 };
    const xrad_method dynamic[] = {XRAD_METHOD_INCREMENTAL, XRAD_METHOD_CROSS};
    for (size_t k = 0; k < sizeof(dynamic) / sizeof(dynamic[0]); k++) {
        const char *name = xrad_method_name(dynamic[k]);
        xrad_solver_desc d = {.method = dynamic[k], .hemicube_res = 16, .msaa = 1,
                              .max_iterations = SOLVE_SHOTS, .frame_shots = FRAME_SHOTS,
                              .threshold = 1e-7};
        xrad_solver *s = NULL;
        xrad_solver_stats st = {0};
        CHECK(xrad_solver_create(ctx, scene, &d, &s, &err) == XRAD_OK &&
                  xrad_solver_solve(s, &err) == XRAD_OK,
              "%s: %s", name, err.message);
        if (s) {
            xrad_solver_get_stats(s, &st);
            /* Cross's solve is rounds of runs, each up to the limit. */
            CHECK(st.iterations >= SOLVE_SHOTS, "%s: the solve selected %u shots, not %d",
                  name, st.iterations, SOLVE_SHOTS);
        }
        for (int f = 1; s && f <= 2; f++) {
            CHECK(xrad_solver_advance(s, 0.1 * f, &err) == XRAD_OK, "%s: frame %d: %s", name,
                  f, err.message);
            xrad_solver_get_stats(s, &st);
            CHECK(st.iterations == FRAME_SHOTS, "%s: frame %d selected %u shots, not %d", name,
                  f, st.iterations, FRAME_SHOTS);
        }
        xrad_solver_destroy(&s);
    }
    {
        xrad_solver *s = NULL;
        CHECK(xrad_solver_create(ctx, scene, &(xrad_solver_desc){.method = XRAD_METHOD_PROGRESSIVE},
                                 &s, &err) == XRAD_OK,
              "%s", err.message);
        if (s)
            CHECK(xrad_solver_set_time(s, NAN, &err) == XRAD_ERROR_INPUT, "NaN time accepted");
        xrad_solver_destroy(&s);
    }
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
