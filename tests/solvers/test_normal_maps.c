/*
 * Normal maps in the solve (issue 18.2, xrad.h xrad_material_desc.
 * normal_map; Wallner 3.3), against truths the code under test does not
 * give:
 *
 *  - element normals (host): a flat map (0, 0, 1) gives the surface's
 *    normal; a constant map (sin a, 0, cos a) on a quad gives the normal
 *    tilted by a towards the quad's u edge, (0, sin a, cos a) towards its
 *    v edge; on a mesh whose texture coordinates turn or mirror the
 *    texture, the tilt follows the coordinates (the tangent along
 *    increasing u, the bitangent along increasing v: glTF's frame); a
 *    normal on the horizon (1, 0, 0) is lifted to 0.05 above it; a map
 *    with a seam splits a quad's elements 1 -> 4 per level asked, a
 *    constant one does not (refine_part); bad
 *    maps and missing coordinates are errors naming the field; a point
 *    light over the tilted quad lights each element with albedo x I cos /
 *    d^2, the cosine the tilted normal's (CPU reference).
 *  - a floor under a small square emitter, nothing else in the scene: a
 *    floor element's radiosity is albedo x emission x the point-to-
 *    polygon form factor from its cell centre with the map's normal
 *    (Lambert's contour integral, computed here), within 1% in the CPU
 *    reference and every GPU method (the shooting ones without
 *    conservation, which scales to the cells' integral), for a map tilted
 *    by 25 degrees; with conservation, the tilted floor over the untilted
 *    one is the ratio of the two factors within 1%; and the flat map
 *    gives the unmapped solution within fp32 rounding.
 *
 * Suite 'scene' runs the host part (`normals`, also under the
 * sanitizers), suite 'accuracy' the solves (`solves`, a few seconds).
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "solvers/solver_test.h"
#include "xrad.h"

#define PI_D 3.14159265358979323846
#define TILT (25.0 * PI_D / 180.0)

/* A 1 x 1 texel map holding tangent-space normal t, encoded (t + 1) / 2. */
static xrad_image_desc encoded(float rgb[3], vec3 t)
{
    rgb[0] = (float)((t.x + 1) / 2);
    rgb[1] = (float)((t.y + 1) / 2);
    rgb[2] = (float)((t.z + 1) / 2);
    return (xrad_image_desc){1, 1, rgb};
}

/* One object on the z = 0 plane, front +z: the unit quad (u along +x) or
 * a mesh of two triangles over it with texture coordinates `uvs`. */
static xrad_status build(const xrad_image_desc *map, const float *uvs, bool mesh, int levels,
                         xrad_scene **out, xrad_error *err)
{
    static const float pos[] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
    static const uint32_t idx[] = {0, 1, 2, 0, 2, 3};
    xrad_scene_builder *b = NULL;
    uint32_t m = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "normal-mapped", .density = 4}, &b, err);
    if (!st)
        st = xrad_scene_builder_add_material(b,
                                             &(xrad_material_desc){.name = "paint",
                                                                   .albedo = {0.5, 0.5, 0.5},
                                                                   .normal_map = map,
                                                                   .normal_map_levels = levels},
                                             &m, err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "lamp", .emission = {1, 1, 1}}, NULL, err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "o"}, err);
    if (!st && !mesh)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){
                .name = "q", .material = m, .p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
            err);
    if (!st && mesh)
        st = xrad_scene_builder_add_mesh(b,
                                         &(xrad_mesh_desc){.name = "mesh",
                                                           .positions = pos,
                                                           .vertex_count = 4,
                                                           .indices = idx,
                                                           .triangle_count = 2,
                                                           .material = m,
                                                           .uvs = uvs},
                                         err);
    if (!st)
        st = xrad_scene_builder_finish(b, out, err);
    xrad_scene_builder_destroy(&b);
    return st;
}

/* The largest distance of any element normal of `sc` from `want`. */
static double normal_off(const xrad_scene *sc, vec3 want)
{
    double worst = 0;
    for (uint32_t e = 0; e < sc->element_count; e++)
        worst = fmax(worst, v3_len(v3_sub(scene_element_normal(sc, e), want)));
    return worst;
}

static void check_normals(const char *what, const xrad_image_desc *map, const float *uvs, bool mesh,
                          vec3 want)
{
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = build(map, uvs, mesh, 0, &sc, &err);
    CHECK(st == XRAD_OK, "%s: %s", what, err.message);
    if (st)
        return;
    double off = normal_off(sc, want);
    fprintf(stderr, "%-34s %u elements, normals %.1e from (%.4f, %.4f, %.4f)\n", what,
            sc->element_count, off, want.x, want.y, want.z);
    CHECK(sc->element_count >= 4 && off <= 1e-6, "%s: element normals %.3g from the truth", what,
          off);
    xrad_scene_info info;
    xrad_scene_get_info(sc, &info);
    CHECK(info.normal_maps == 1 && info.normal_mapped_elements == sc->element_count,
          "%s: info says %u normal maps over %u elements", what, info.normal_maps,
          info.normal_mapped_elements);
    xrad_scene_destroy(&sc);
}

static void expect_error(const char *what, const xrad_image_desc *map, const float *uvs, bool mesh,
                         int levels, const char *field)
{
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = build(map, uvs, mesh, levels, &sc, &err);
    CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, field),
          "%s: want an input error naming %s, got %d '%s'", what, field, st, err.message);
    xrad_scene_destroy(&sc);
}

/* A point light of 2 W/sr at (0.3, 0.6, 0.8) over the unit quad with the
 * map tilted towards u (build()'s, z = 0, u along +x), in the CPU
 * reference: each element's radiosity is albedo x I cos / d^2 with the
 * tilted normal's cosine at its sample point (closed form). */
static void luminaire_part(const xrad_image_desc *tilt_u, vec3 n_tilt)
{
    xrad_scene_builder *b = NULL;
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    uint32_t m = 0;
    const vec3 at = v3(0.3, 0.6, 0.8);
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "lamp-over-map", .density = 4}, &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){.name = "paint", .albedo = {0.5, 0.5, 0.5}, .normal_map = tilt_u},
            &m, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "o"}, &err);
    if (!st)
        st = xrad_scene_builder_add_quad(
            b,
            &(xrad_quad_desc){
                .name = "q", .material = m, .p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}},
            &err);
    if (!st)
        st = xrad_scene_builder_add_luminaire(
            b,
            &(xrad_luminaire_desc){
                .name = "bulb", .intensity = {2, 2, 2}, .position = {at.x, at.y, at.z}},
            &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    xrad_scene_builder_destroy(&b);
    xrad_atlas a = {0};
    if (!st && !(st = xrad_atlas_create(sc, &a, &err)))
        st = xrad_reference_solve(sc, &(xrad_reference_desc){.threads = 2}, &a, NULL, &err);
    CHECK(st == XRAD_OK, "point light over a tilted map: %s", err.message);
    if (!st) {
        double worst = 0;
        for (uint32_t e = 0; e < sc->element_count; e++) {
            const element *el = &sc->elements[e];
            vec3 d = v3_sub(at, el->pos);
            double r2 = v3_dot(d, d);
            double want = 0.5 * 2 * v3_dot(n_tilt, v3_scale(d, 1 / sqrt(r2))) / r2;
            worst = fmax(
                worst, fabs(a.rgba[4 * ((size_t)el->texel_y * a.width + el->texel_x)] / want - 1));
        }
        fprintf(stderr, "point light over a tilted map: worst element %.1e off rho I cos / d^2\n",
                worst);
        CHECK(worst <= 1e-4, "point light over a tilted map: an element %.3g off", worst);
    }
    xrad_atlas_destroy(&a);
    xrad_scene_destroy(&sc);
}

/* Element resolution that follows the map's detail (xrad.h
 * normal_map_levels): a 2 x 1 map, flat on the left half and tilted on the
 * right, keeps a seam of 25 degrees at every resolution, so the quad's 5 x
 * 5 samples split to 2n - 1 per level, up to the level asked; a constant
 * map has no detail and stays 5 x 5. Elements wholly on one side of the
 * seam (u = 1/2) take that side's normal. */
static void refine_part(double s, double c)
{
    float rgb[6], tilt_rgb[3];
    encoded(rgb, v3(0, 0, 1));
    encoded(rgb + 3, v3(s, 0, c));
    xrad_image_desc halves = {2, 1, rgb};
    xrad_image_desc tilt = encoded(tilt_rgb, v3(s, 0, c));
    static const struct {
        int levels;
        bool constant;
        uint32_t side, refined;
    } cases[] = {
        {0, false, 9, 1},                           /* the default, one level */
        {XRAD_NORMAL_MAP_LEVELS_NONE, false, 5, 0}, /* never */
        {3, false, 33, 1},                          /* 5 -> 9 -> 17 -> 33 */
        {3, true, 5, 0},                            /* no detail */
    };
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        xrad_scene *sc = NULL;
        xrad_error err = {0};
        xrad_status st =
            build(cases[k].constant ? &tilt : &halves, NULL, false, cases[k].levels, &sc, &err);
        CHECK(st == XRAD_OK, "refine case %zu: %s", k, err.message);
        if (st)
            continue;
        const surface *sf = &sc->surfaces[0];
        xrad_scene_info info;
        xrad_scene_get_info(sc, &info);
        double off = 0;
        for (uint32_t e = 0; e < sf->nu * sf->nv; e++) {
            double s0, s1, t0, t1;
            scene_param_range(e % sf->nu, e % sf->nu, sf->nu, &s0, &s1);
            scene_param_range(e / sf->nu, e / sf->nu, sf->nv, &t0, &t1);
            vec3 want = cases[k].constant || s0 >= 0.5 ? v3(s, 0, c) : v3(0, 0, 1);
            if (cases[k].constant || s1 <= 0.5 || s0 >= 0.5)
                off = fmax(off,
                           v3_len(v3_sub(scene_element_normal(sc, sf->first_element + e), want)));
        }
        fprintf(stderr,
                "refine: levels %2d, %s map: %u x %u elements (%u surface split), one-sided "
                "elements %.1e off\n",
                cases[k].levels, cases[k].constant ? "constant" : "two-half", sf->nu, sf->nv,
                info.normal_refined_surfaces, off);
        CHECK(sf->nu == cases[k].side && sf->nv == cases[k].side &&
                  info.normal_refined_surfaces == cases[k].refined && off <= 1e-6,
              "refine case %zu: %u x %u elements, %u split, %.3g off; want %u x %u, %u", k, sf->nu,
              sf->nv, info.normal_refined_surfaces, off, cases[k].side, cases[k].side,
              cases[k].refined);
        xrad_scene_destroy(&sc);
    }
}

/* A scene file's "normal_map" and "normal_map_levels": tests/data/
 * normal-halves.png (8-bit: flat, then tilted 25 degrees towards u) on a
 * quad; the right half's elements lean towards +x by sin 25 (within the
 * 8-bit step), the left's do not; bad values are errors naming the field. */
static void json_part(void)
{
    char name[1024];
    test_source_path("tests/data/normal-maps.json", name, sizeof(name));
    const char *fmt =
        "{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5], \"normal_map\": %s%s},"
        " {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [1, 1, 1]}],"
        " \"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"q\", \"material\": \"m\","
        " \"quad\": {\"origin\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0]}, \"density\": "
        "4}]}]}";
    static const struct {
        const char *map, *extra, *field; /* field NULL: loads */
    } cases[] = {
        {"\"normal-halves.png\"", ", \"normal_map_levels\": 0", NULL},
        {"\"normal-halves.png\"", ", \"normal_map_levels\": 5", "'normal_map_levels'"},
        {"\"normal-halves.png\"", ", \"normal_map_levels\": 1.5", "'normal_map_levels'"},
        {"3", "", "'normal_map'"},
        {"\"no-such-map.png\"", "", "no-such-map.png"},
    };
    for (size_t k = 0; k < sizeof(cases) / sizeof(cases[0]); k++) {
        char json[1024];
        snprintf(json, sizeof(json), fmt, cases[k].map, cases[k].extra);
        xrad_scene *sc = NULL;
        xrad_error err = {0};
        xrad_status st = xrad_scene_parse(json, strlen(json), name, &sc, &err);
        if (cases[k].field) {
            CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, cases[k].field),
                  "scene file case %zu: want an error naming %s, got %d '%s'", k, cases[k].field,
                  st, err.message);
        } else {
            CHECK(st == XRAD_OK, "scene file case %zu: %s", k, err.message);
        }
        if (st == XRAD_OK && !cases[k].field) {
            const surface *sf = &sc->surfaces[0];
            double worst = 0;
            for (uint32_t e = 0; e < sf->nu * sf->nv; e++) {
                double s0, s1, t0, t1;
                scene_param_range(e % sf->nu, e % sf->nu, sf->nu, &s0, &s1);
                scene_param_range(e / sf->nu, e / sf->nu, sf->nv, &t0, &t1);
                if (s1 > 0.5 && s0 < 0.5)
                    continue;
                double want = s0 >= 0.5 ? sin(TILT) : 0;
                worst = fmax(worst, fabs(scene_element_normal(sc, sf->first_element + e).x - want));
            }
            fprintf(stderr, "scene file: %u x %u elements, one-sided normals' x %.4f off\n", sf->nu,
                    sf->nv, worst);
            /* levels 0 in a file: never split. */
            CHECK(sf->nu == 5 && worst <= 0.01, "scene file: %u x %u elements, x %.4f off", sf->nu,
                  sf->nv, worst);
        }
        xrad_scene_destroy(&sc);
    }
}

static void normals_part(void)
{
    double s = sin(TILT), c = cos(TILT);
    float flat_rgb[3], tu_rgb[3], tv_rgb[3], horizon_rgb[3];
    xrad_image_desc flat = encoded(flat_rgb, v3(0, 0, 1));
    xrad_image_desc tilt_u = encoded(tu_rgb, v3(s, 0, c));
    xrad_image_desc tilt_v = encoded(tv_rgb, v3(0, s, c));
    xrad_image_desc horizon = encoded(horizon_rgb, v3(1, 0, 0));

    check_normals("quad, flat map", &flat, NULL, false, v3(0, 0, 1));
    check_normals("quad, tilted towards u", &tilt_u, NULL, false, v3(s, 0, c));
    check_normals("quad, tilted towards v", &tilt_v, NULL, false, v3(0, s, c));
    /* The quad's own coordinates on the mesh: u along +x, v along +y. */
    static const float plain[] = {0, 0, 1, 0, 1, 1, 0, 1};
    check_normals("mesh, tilted towards u", &tilt_u, plain, true, v3(s, 0, c));
    /* Turned a quarter: u grows along -y, v along +x. */
    static const float turned[] = {1, 0, 1, 1, 0, 1, 0, 0};
    check_normals("mesh turned, tilted towards u", &tilt_u, turned, true, v3(0, -s, c));
    check_normals("mesh turned, tilted towards v", &tilt_v, turned, true, v3(s, 0, c));
    /* Mirrored: u grows along -x, v along +y (the other handedness). */
    static const float mirrored[] = {1, 0, 0, 0, 0, 1, 1, 1};
    check_normals("mesh mirrored, tilted towards u", &tilt_u, mirrored, true, v3(-s, 0, c));
    check_normals("mesh mirrored, tilted towards v", &tilt_v, mirrored, true, v3(0, s, c));
    /* On the horizon: lifted to 0.05 above it, its azimuth kept. */
    check_normals("quad, normal on the horizon", &horizon, NULL, false,
                  v3(sqrt(1 - 0.05 * 0.05), 0, 0.05));

    float bad_rgb[3] = {0.5f, 1.5f, 1};
    xrad_image_desc bad = {1, 1, bad_rgb};
    expect_error("texel outside [0, 1]", &bad, NULL, false, 0, "'normal_map'");
    expect_error("mesh without uvs", &tilt_u, NULL, true, 0, "'uvs'");
    expect_error("levels -2", &tilt_u, NULL, false, -2, "'normal_map_levels'");
    expect_error("levels 5", &tilt_u, NULL, false, XRAD_NORMAL_MAP_LEVELS_MAX + 1,
                 "'normal_map_levels'");
    refine_part(s, c);
    json_part();
    luminaire_part(&tilt_u, v3(s, 0, c));
}

/* Lambert's contour integral: the form factor from the point x with unit
 * normal n to the convex polygon q[0..3] lying wholly above x's tangent
 * plane (Cohen and Wallace, eq. 4.14). */
static double lambert(vec3 x, vec3 n, const vec3 q[4])
{
    double sum = 0;
    for (int k = 0; k < 4; k++) {
        vec3 a = v3_norm(v3_sub(q[k], x)), b = v3_norm(v3_sub(q[(k + 1) % 4], x));
        vec3 g = v3_cross(a, b);
        double gl = v3_len(g);
        if (gl > 0)
            sum += acos(fmax(-1.0, fmin(1.0, v3_dot(a, b)))) * v3_dot(n, v3_scale(g, 1 / gl));
    }
    return fabs(sum) / (2 * PI_D);
}

/* The floor (1 x 1 m at y = 0, u along +z, front +y, albedo 0.5 with
 * `map`) under a 0.1 x 0.1 m emitter of 10 W/m^2 facing down, its centre
 * at (0.5, 0.6, 0.5); density 4. */
static const vec3 lamp_corners[4] = {
    {0.45, 0.6, 0.45}, {0.55, 0.6, 0.45}, {0.55, 0.6, 0.55}, {0.45, 0.6, 0.55}};

static xrad_scene *lit_floor(const xrad_image_desc *map)
{
    xrad_error err = {0};
    xrad_scene_builder *b = NULL;
    xrad_scene *sc = NULL;
    uint32_t fl = 0, lamp = 0;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "lit-floor", .density = 4}, &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "floor", .albedo = {0.5, 0.5, 0.5}, .normal_map = map},
            &fl, &err);
    if (!st)
        st = xrad_scene_builder_add_material(
            b, &(xrad_material_desc){.name = "lamp", .emission = {10, 10, 10}}, &lamp, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "o"}, &err);
    xrad_quad_desc q[2] = {
        {.name = "floor", .material = fl, .p = {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}},
        {.name = "lamp", .material = lamp, .density = 10},
    };
    for (int k = 0; k < 4; k++) {
        q[1].p[k][0] = lamp_corners[k].x;
        q[1].p[k][1] = lamp_corners[k].y;
        q[1].p[k][2] = lamp_corners[k].z;
    }
    for (int k = 0; k < 2 && !st; k++)
        st = xrad_scene_builder_add_quad(b, &q[k], &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    CHECK(st == XRAD_OK, "lit floor: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return sc;
}

static const float *texel(const xrad_atlas *a, const element *el)
{
    return &a->rgba[4 * ((size_t)el->texel_y * a->width + el->texel_x)];
}

static void solves_part(xrad_context *ctx)
{
    /* Tilted towards the floor's u edge (+z): n = (0, cos a, sin a). */
    float tilt_rgb[3], flat_rgb[3];
    xrad_image_desc tilt = encoded(tilt_rgb, v3(sin(TILT), 0, cos(TILT)));
    xrad_image_desc flat = encoded(flat_rgb, v3(0, 0, 1));
    const vec3 n_tilt = v3(0, cos(TILT), sin(TILT));
    xrad_scene *tilted = lit_floor(&tilt), *flat_sc = lit_floor(&flat), *plain = lit_floor(NULL);
    if (!tilted || !flat_sc || !plain)
        goto done;
    const surface *fl = &tilted->surfaces[0];
    /* The truth differs from the untilted floor's: the test can fail. */
    double moved = 0;
    for (uint32_t k = 0; k < fl->nu * fl->nv; k++) {
        double s, t;
        scene_cell_centre(fl, k % fl->nu, k / fl->nu, &s, &t);
        vec3 x = surface_point(fl, s, t);
        moved = fmax(
            moved,
            fabs(lambert(x, n_tilt, lamp_corners) / lambert(x, v3(0, 1, 0), lamp_corners) - 1));
    }
    CHECK(moved > 0.1, "the tilt moves the floor's form factors by %.3f only", moved);
    for (size_t m = 0; m < SOLVER_TEST_METHODS; m++) {
        const char *name = solver_test_methods[m].name;
        xrad_method method = solver_test_methods[m].method;
        bool shoots = method && method != XRAD_METHOD_GATHER;
        xrad_solver_desc d = {.method = method};
        /* Conservation scales each shot to what its hemicube sends, the
         * area integral over the receivers' cells, where the analytic
         * factor here (and the CPU reference) is the cell centre's: 2%
         * apart on this coarse floor, tilted or not. The point factors
         * themselves are checked without it, the tilt with it. */
        xrad_solver_desc exact = {.method = method, .conserve = XRAD_CONSERVE_OFF};
        xrad_atlas a = {0}, f = {0}, p = {0}, o = {0};
        xrad_error err = {0};
        xrad_status st = solver_test_solve(ctx, tilted, &d, &a, &err);
        if (!st)
            st = solver_test_solve(ctx, flat_sc, &d, &f, &err);
        if (!st)
            st = solver_test_solve(ctx, plain, &d, &p, &err);
        if (!st && shoots)
            st = solver_test_solve(ctx, tilted, &exact, &o, &err);
        CHECK(st == XRAD_OK, "%s: %s", name, err.message);
        if (!st) {
            const xrad_atlas *point = shoots ? &o : &a;
            double worst = 0, tilted_off = 0, same = solver_test_atlas_diff(&f, &p);
            for (uint32_t k = 0; k < fl->nu * fl->nv; k++) {
                const element *el = &tilted->elements[fl->first_element + k];
                double s, t;
                scene_cell_centre(fl, el->i, el->j, &s, &t);
                vec3 x = surface_point(fl, s, t);
                double want = 0.5 * 10 * lambert(x, n_tilt, lamp_corners);
                double ratio =
                    lambert(x, n_tilt, lamp_corners) / lambert(x, v3(0, 1, 0), lamp_corners);
                for (int c = 0; c < 3; c++) {
                    worst = fmax(worst, fabs(texel(point, el)[c] / want - 1));
                    tilted_off =
                        fmax(tilted_off, fabs(texel(&a, el)[c] / texel(&p, el)[c] / ratio - 1));
                }
            }
            fprintf(stderr,
                    "lit floor %-11s tilted map: worst element %.1e off the analytic form "
                    "factor%s, %.1e off its ratio to the untilted; flat map %.1e off unmapped\n",
                    name, worst, shoots ? " (conserve off)" : "", tilted_off, same);
            CHECK(worst <= 0.01, "%s: a floor element tilted by 25 degrees is %.4f off", name,
                  worst);
            CHECK(tilted_off <= 0.01, "%s: tilted / untilted is %.4f off the analytic ratio", name,
                  tilted_off);
            CHECK(same <= 1e-5, "%s: the flat map is %.2e off the unmapped floor", name, same);
        }
        xrad_atlas_destroy(&a);
        xrad_atlas_destroy(&f);
        xrad_atlas_destroy(&p);
        xrad_atlas_destroy(&o);
    }
done:
    xrad_scene_destroy(&tilted);
    xrad_scene_destroy(&flat_sc);
    xrad_scene_destroy(&plain);
}

int main(int argc, char **argv)
{
    const char *only = argc > 1 ? argv[1] : NULL;
    if (only && strcmp(only, "normals") && strcmp(only, "solves")) {
        fprintf(stderr, "usage: test_normal_maps [normals|solves]\n");
        return 2;
    }
    if (!only || !strcmp(only, "normals"))
        normals_part();
    if (!only || !strcmp(only, "solves")) {
        xrad_context *ctx = gpu_test_context();
        if (!ctx)
            return test_finish();
        solves_part(ctx);
        gpu_test_end(&ctx);
    }
    return test_finish();
}
