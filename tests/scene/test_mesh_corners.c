/* Per-corner atlas coordinates of triangle meshes (xrad.h,
 * xrad_scene_get_mesh_corners; issue 17.3):
 *  - a builder mesh of a square split in two and of a convex quad that is
 *    no parallelogram (each given with its vertex orders rotated and its
 *    diagonal's vertices repeated), two lone triangles off the plane whose
 *    longest edge is their second and their third, and a zero-area
 *    triangle; the same square again with keep_triangles. Every corner's
 *    `a` gives, through the documented rule st = (a.z > 0 ? a.x / a.z :
 *    0.5, a.y), the point P(st) of its surface's bilinear map (corners
 *    from xrad_scene_get_surface) that is the vertex as given, within
 *    1e-6 m; each `a` is (s, t, 1) at a corner or (0, 1, 0) at a
 *    triangle's apex; a pair shares one quad, the lone triangles have a
 *    surface each, the zero-area one none (UINT32_MAX, a = 0);
 *  - the meshes of model files as xrad loads them (scenes/wuson-room.json:
 *    Debian's Wuson.ply at scale 0.13, joined quads among its triangles;
 *    scenes/ball-room.json: an 80-triangle ball): each triangle's corners
 *    are three distinct corners of one surface of the mesh's object, wound
 *    as the surface's front, and the triangles on a surface (one on a
 *    triangle, two on a quad) cover its area: their areas from P(st) sum
 *    to the surface's within 1e-6;
 *  - errors name the field: a mesh index out of range ('index', 'mesh')
 *    and a corner_count that is not 3 x the triangles ('corner_count').
 */
#include <stdbool.h>
#include <string.h>

#include "harness.h"
#include "xrad.h"

typedef struct v3d {
    double x, y, z;
} v3d;

static v3d sub(v3d a, v3d b)
{
    return (v3d){a.x - b.x, a.y - b.y, a.z - b.z};
}

static v3d cross(v3d a, v3d b)
{
    return (v3d){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

static double len(v3d a)
{
    return sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
}

/* The documented reading of `a`, then the surface's bilinear map. */
static v3d corner_point(const xrad_surface_info *sf, const xrad_mesh_corner *c)
{
    double s = c->a[2] > 0 ? c->a[0] / c->a[2] : 0.5, t = c->a[1];
    double w[4] = {(1 - s) * (1 - t), s * (1 - t), s * t, (1 - s) * t};
    double p[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++)
            p[i] += w[k] * sf->corners[k][i];
    return (v3d){p[0], p[1], p[2]};
}

/* `a` is one of the corner attributes: (s, t, 1) with s, t in {0, 1}, or
 * the apex's (0, 1, 0) on a triangle. */
static bool corner_attribute(const xrad_surface_info *sf, const xrad_mesh_corner *c)
{
    const float *a = c->a;
    if (a[2] == 0)
        return sf->triangle && a[0] == 0 && a[1] == 1;
    return a[2] == 1 && (a[0] == 0 || a[0] == 1) && (a[1] == 0 || a[1] == 1) &&
           !(sf->triangle && a[1] == 1);
}

/* Mesh `mesh` of a builder scene: every corner reproduces its vertex. */
static void check_given(const xrad_scene *sc, uint32_t mesh, const float *pos,
                        const uint32_t *idx, uint32_t nt, const uint32_t *want_surface)
{
    xrad_mesh_corner corners[64];
    xrad_error err = {0};
    CHECK(xrad_scene_get_mesh_corners(sc, mesh, corners, 3 * nt, &err) == XRAD_OK, "%s",
          err.message);
    for (uint32_t t = 0; t < nt; t++) {
        uint32_t s = corners[3 * t].surface;
        CHECK(s == want_surface[t], "mesh %u triangle %u: surface %u, want %u", mesh, t, s,
              want_surface[t]);
        int apexes = 0;
        for (int k = 0; k < 3; k++) {
            const xrad_mesh_corner *c = &corners[3 * t + k];
            CHECK(c->surface == s, "mesh %u triangle %u: corners on surfaces %u and %u", mesh,
                  t, s, c->surface);
            if (s == UINT32_MAX) {
                CHECK(c->a[0] == 0 && c->a[1] == 0 && c->a[2] == 0,
                      "mesh %u triangle %u (skipped): a = (%g, %g, %g)", mesh, t, c->a[0],
                      c->a[1], c->a[2]);
                continue;
            }
            xrad_surface_info sf;
            if (xrad_scene_get_surface(sc, s, &sf, &err)) {
                CHECK(0, "%s", err.message);
                continue;
            }
            CHECK(corner_attribute(&sf, c), "mesh %u triangle %u corner %d: a = (%g, %g, %g)",
                  mesh, t, k, c->a[0], c->a[1], c->a[2]);
            apexes += c->a[2] == 0;
            const float *v = &pos[3 * idx[3 * t + k]];
            v3d p = corner_point(&sf, c);
            double d = len(sub(p, (v3d){v[0], v[1], v[2]}));
            CHECK(d <= 1e-6,
                  "mesh %u triangle %u corner %d: P(st) = (%g, %g, %g) is %g m from the vertex "
                  "(%g, %g, %g)", mesh, t, k, p.x, p.y, p.z, d, v[0], v[1], v[2]);
        }
        if (s != UINT32_MAX) {
            xrad_surface_info sf;
            xrad_scene_get_surface(sc, s, &sf, &err);
            CHECK(apexes == (sf.triangle ? 1 : 0), "mesh %u triangle %u: %d apex corners", mesh,
                  t, apexes);
        }
    }
}

static void builder_mesh(void)
{
    /* 0-5: the unit square in z = 0 facing +z, split along 0 2 (= 3 4),
     * the second triangle's vertices repeated. 6-11: a convex quad that
     * is no parallelogram, in z = 0, split along 6 8 (= 10 11). 12-14: a
     * triangle off the plane whose longest edge is 13 14 (its second);
     * 15-17: one whose longest edge is 17 15 (its third). 18-20:
     * collinear. */
    const float pos[] = {
        0, 0, 0,   1, 0, 0,   1, 1, 0,   0, 0, 0,   1, 1, 0,   0, 1, 0,
        2, 0, 0,   4, 0, 0,   3.5f, 1, 0,   2.2f, 1.3f, 0,   2, 0, 0,   3.5f, 1, 0,
        0, 0, 1,   1, 0, 1.2f,   -0.2f, 1, 1.1f,
        1, 0, 2,   1.2f, 0.2f, 2,   3, 1.5f, 2.4f,
        0, 0, 3,   1, 1, 3,   2, 2, 3,
    };
    /* Each triangle counter-clockwise seen from +z, its vertex order
     * rotated: the square's 1 2 0 and 5 3 4, the quad's 8 6 7 and 9 10 11
     * given as 10 11 9. */
    const uint32_t idx[] = {1, 2, 0, 5, 3, 4, 8, 6, 7, 10, 11, 9, 12, 13, 14, 15, 16, 17,
                            18, 19, 20};
    const uint32_t nt = 7;
    xrad_scene_builder *b = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "corners-test", .density = 10}, &b, &err);
    if (!st)
        st = xrad_scene_builder_add_material(b,
                                             &(xrad_material_desc){.name = "white",
                                                                   .albedo = {0.5, 0.5, 0.5},
                                                                   .emission = {1, 1, 1}},
                                             NULL, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "obj"}, &err);
    if (!st)
        st = xrad_scene_builder_add_mesh(b,
                                         &(xrad_mesh_desc){.name = "mesh",
                                                           .positions = pos,
                                                           .vertex_count = 21,
                                                           .indices = idx,
                                                           .triangle_count = nt},
                                         &err);
    /* The square kept as triangles, in a second object. */
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "kept"}, &err);
    if (!st)
        st = xrad_scene_builder_add_mesh(b,
                                         &(xrad_mesh_desc){.name = "square",
                                                           .positions = pos,
                                                           .vertex_count = 6,
                                                           .indices = idx,
                                                           .triangle_count = 2,
                                                           .keep_triangles = 1},
                                         &err);
    xrad_scene *sc = NULL;
    if (!st)
        st = xrad_scene_builder_finish(b, &sc, &err);
    xrad_scene_builder_destroy(&b);
    CHECK(st == XRAD_OK, "builder: %s", err.message);
    if (!sc)
        return;
    xrad_scene_info in;
    xrad_scene_get_info(sc, &in);
    /* mesh: the square (0), the quad (1), two triangles (2, 3); square:
     * two triangles (4, 5). */
    CHECK(in.meshes == 2 && in.surfaces == 6 && in.triangles == 4 && in.skipped_triangles == 1,
          "%u meshes, %u surfaces, %u triangles, %u skipped; want 2, 6, 4, 1", in.meshes,
          in.surfaces, in.triangles, in.skipped_triangles);
    xrad_mesh_info mi;
    CHECK(xrad_scene_get_mesh(sc, 0, &mi, &err) == XRAD_OK, "%s", err.message);
    CHECK(!strcmp(mi.name, "mesh") && mi.object == 0 && mi.triangle_count == nt &&
              mi.skipped_triangles == 1,
          "mesh 0: '%s', object %u, %u triangles, %u skipped", mi.name, mi.object,
          mi.triangle_count, mi.skipped_triangles);
    CHECK(xrad_scene_get_mesh(sc, 1, &mi, &err) == XRAD_OK, "%s", err.message);
    CHECK(!strcmp(mi.name, "square") && mi.object == 1 && mi.triangle_count == 2 &&
              mi.skipped_triangles == 0,
          "mesh 1: '%s', object %u, %u triangles, %u skipped", mi.name, mi.object,
          mi.triangle_count, mi.skipped_triangles);
    const uint32_t want0[] = {0, 0, 1, 1, 2, 3, UINT32_MAX}, want1[] = {4, 5};
    check_given(sc, 0, pos, idx, nt, want0);
    check_given(sc, 1, pos, idx, 2, want1);

    /* Errors name the field. */
    xrad_mesh_corner corners[3 * 7];
    memset(&err, 0, sizeof(err));
    CHECK(xrad_scene_get_mesh(sc, 2, &mi, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "field 'index'") && strstr(err.message, "mesh 2") &&
              mi.name == NULL,
          "mesh 2 of 2: %s", err.message);
    memset(&err, 0, sizeof(err));
    CHECK(xrad_scene_get_mesh_corners(sc, 2, corners, 6, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "field 'mesh'"),
          "corners of mesh 2 of 2: %s", err.message);
    memset(&err, 0, sizeof(err));
    CHECK(xrad_scene_get_mesh_corners(sc, 0, corners, 3 * nt - 1, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "field 'corner_count'") && strstr(err.message, "'mesh'"),
          "corner_count 20 for 7 triangles: %s", err.message);
    memset(&err, 0, sizeof(err));
    CHECK(xrad_scene_get_mesh_corners(sc, 1, corners, 3 * nt, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "field 'corner_count'"),
          "corner_count 21 for 2 triangles: %s", err.message);
    xrad_scene_destroy(&sc);
}

/* The meshes of a loaded scene: each triangle's corners are three corners
 * of one surface, wound as its front, and they cover the surfaces. */
static void loaded(const char *rel, const char *mesh_name, uint32_t triangles)
{
    char path[1024];
    test_source_path(rel, path, sizeof(path));
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_load(path, &sc, &err) == XRAD_OK, "%s: %s", rel, err.message);
    if (!sc)
        return;
    xrad_scene_info in;
    xrad_scene_get_info(sc, &in);
    CHECK(in.meshes == 1, "%s: %u meshes, want 1", rel, in.meshes);
    double *covered = calloc(in.surfaces, sizeof(double));
    uint32_t *hits = calloc(in.surfaces, sizeof(uint32_t));
    uint32_t skipped = 0, all = 0, bad_corner = 0, bad_surface = 0, bad_wind = 0;
    for (uint32_t m = 0; m < in.meshes && covered && hits; m++) {
        xrad_mesh_info mi;
        CHECK(xrad_scene_get_mesh(sc, m, &mi, &err) == XRAD_OK, "%s", err.message);
        CHECK(!strcmp(mi.name, mesh_name) && mi.triangle_count == triangles,
              "%s: mesh '%s' of %u triangles, want '%s' of %u", rel, mi.name,
              mi.triangle_count, mesh_name, triangles);
        xrad_mesh_corner *c = malloc(3ull * mi.triangle_count * sizeof(*c));
        if (!c || xrad_scene_get_mesh_corners(sc, m, c, 3 * mi.triangle_count, &err)) {
            CHECK(0, "%s: %s", rel, err.message);
            free(c);
            continue;
        }
        all += mi.triangle_count;
        skipped += mi.skipped_triangles;
        for (uint32_t t = 0; t < mi.triangle_count; t++) {
            uint32_t s = c[3 * t].surface;
            if (s == UINT32_MAX) {
                skipped--; /* counted back to 0 when every skipped one is found */
                continue;
            }
            xrad_surface_info sf;
            if (s >= in.surfaces || xrad_scene_get_surface(sc, s, &sf, &err) ||
                sf.object != mi.object || c[3 * t + 1].surface != s ||
                c[3 * t + 2].surface != s) {
                bad_surface++;
                continue;
            }
            v3d p[3];
            for (int k = 0; k < 3; k++) {
                bad_corner += !corner_attribute(&sf, &c[3 * t + k]);
                p[k] = corner_point(&sf, &c[3 * t + k]);
            }
            double size = fmax(sf.length_u, sf.length_v);
            for (int k = 0; k < 3; k++)
                bad_corner += !(len(sub(p[k], p[(k + 1) % 3])) > 1e-6 * size);
            v3d n = cross(sub(p[1], p[0]), sub(p[2], p[0]));
            bad_wind += !(n.x * sf.normal[0] + n.y * sf.normal[1] + n.z * sf.normal[2] > 0);
            covered[s] += 0.5 * len(n);
            hits[s]++;
        }
        free(c);
    }
    CHECK(skipped == 0 && bad_corner == 0 && bad_surface == 0 && bad_wind == 0,
          "%s: %u skipped triangles unaccounted, %u bad corners, %u on a wrong surface, %u "
          "wound backwards", rel, skipped, bad_corner, bad_surface, bad_wind);
    uint32_t mesh_surfaces = 0, bad_cover = 0, quads = 0;
    double worst = 0;
    for (uint32_t s = 0; s < in.surfaces && covered && hits; s++) {
        if (!hits[s])
            continue;
        xrad_surface_info sf;
        xrad_scene_get_surface(sc, s, &sf, &err);
        mesh_surfaces++;
        quads += !sf.triangle;
        bad_cover += hits[s] != (sf.triangle ? 1u : 2u);
        worst = fmax(worst, fabs(covered[s] - sf.area) / sf.area);
    }
    CHECK(bad_cover == 0 && worst <= 1e-6,
          "%s: %u surfaces with the wrong number of triangles; coverage off by %.3g of the "
          "area", rel, bad_cover, worst);
    CHECK(mesh_surfaces + quads + in.skipped_triangles == all &&
              mesh_surfaces - quads == in.triangles,
          "%s: %u mesh surfaces (%u quads), %u skipped, %u triangles given", rel, mesh_surfaces,
          quads, in.skipped_triangles, all);
    fprintf(stderr, "%s: %u triangles on %u surfaces (%u joined quads), %u skipped\n", rel, all,
            mesh_surfaces, quads, in.skipped_triangles);
    free(covered);
    free(hits);
    xrad_scene_destroy(&sc);
}

int main(void)
{
    builder_mesh();
    loaded("scenes/wuson-room.json", "wuson.0", 3732);
    loaded("scenes/ball-room.json", "ball.0", 80);
    return test_finish();
}
