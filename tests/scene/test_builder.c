/* The scene builder (xrad.h) and triangle surfaces (scene.h):
 *  - a triangle's element areas sum to its area (|e1 x e2| / 2, a closed
 *    form), every element has a positive area, its longest edge is p0 p1;
 *  - a triangle within one spacing (1 / density) is one element: its
 *    area, at its centroid ((a + b + c) / 3), where its receiver point is
 *    too; one just over a spacing has 2 x 2 or more;
 *  - a quad split along a diagonal comes back as one quad of the same
 *    corners and area, also when the mesh repeats the shared vertices
 *    (welding); a fan of four triangles around a centre stays four
 *    triangles; two triangles of opposite orientation, of different
 *    materials, or not coplanar are not joined;
 *  - zero-area triangles are left out and counted;
 *  - bad input: every message names the builder, the object, the mesh
 *    or surface and the field, and the builder refuses to go on after it.
 */
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

static xrad_scene_builder *start(uint32_t materials)
{
    xrad_scene_builder *b = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = "builder-test", .density = 10}, &b, &err);
    for (uint32_t k = 0; k < materials && !st; k++) {
        char name[16];
        snprintf(name, sizeof(name), "m%u", k);
        st = xrad_scene_builder_add_material(
            b,
            &(xrad_material_desc){.name = name, .albedo = {0.5, 0.5, 0.5}, .emission = {0, 0, 0}},
            NULL, &err);
    }
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "obj"}, &err);
    CHECK(st == XRAD_OK, "start: %s", err.message);
    return b;
}

static xrad_scene *mesh_scene(const float *pos, uint32_t nv, const uint32_t *idx, uint32_t nt,
                              const uint32_t *mats, int keep)
{
    xrad_scene_builder *b = start(2);
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_mesh_desc m = {.name = "mesh",
                        .positions = pos,
                        .vertex_count = nv,
                        .indices = idx,
                        .triangle_count = nt,
                        .materials = mats,
                        .keep_triangles = keep};
    xrad_status st = xrad_scene_builder_add_mesh(b, &m, &err);
    if (!st)
        st = xrad_scene_builder_finish(b, &scene, &err);
    CHECK(st == XRAD_OK, "mesh scene: %s", err.message);
    xrad_scene_builder_destroy(&b);
    return scene;
}

static void tiny_triangle(void)
{
    /* Density 10, a spacing of 0.1 m: the first triangle's longest edge
     * is 0.099 m, the second's 0.101 m. */
    const float pos[12] = {0, 0, 0, 0.07f, 0.01f, 0, 0.02f, 0.07f, 0.05f, 0.101f, 0, 0};
    const uint32_t idx[6] = {0, 1, 2, 0, 3, 2};
    xrad_scene *sc = mesh_scene(pos, 4, idx, 2, NULL, 1);
    if (!sc)
        return;
    CHECK(sc->surface_count == 2, "%u surfaces, want 2", sc->surface_count);
    const surface *s = &sc->surfaces[0];
    vec3 a = v3(0, 0, 0), b = v3(0.07, 0.01, 0), c = v3(0.02, 0.07, 0.05);
    CHECK(s->nu == 1 && s->nv == 1, "tiny triangle: %u x %u elements, want 1 x 1", s->nu, s->nv);
    const element *e = &sc->elements[s->first_element];
    vec3 centroid = v3_scale(v3_add(v3_add(a, b), c), 1.0 / 3.0);
    CHECK_REL(e->area, 0.5 * v3_len(v3_cross(v3_sub(b, a), v3_sub(c, a))), 1e-6);
    CHECK(v3_len(v3_sub(e->pos, centroid)) < 1e-7, "tiny triangle: sample %g m from the centroid",
          v3_len(v3_sub(e->pos, centroid)));
    vec3 r = scene_element_centroid(s, e);
    CHECK(v3_len(v3_sub(r, centroid)) < 1e-7,
          "tiny triangle: receiver point %g m from the centroid", v3_len(v3_sub(r, centroid)));
    const surface *t = &sc->surfaces[1];
    CHECK(t->nu >= 2 && t->nv >= 2, "a triangle over a spacing: %u x %u elements", t->nu, t->nv);
    xrad_scene_destroy(&sc);
}

static void triangle_elements(void)
{
    /* A scalene triangle: edges 0.707, 0.990 (vertex 1 to 2), 0.970 m. */
    const float pos[9] = {0, 0, 0, 0.7f, 0.1f, 0, 0.2f, 0.9f, 0.3f};
    const uint32_t idx[3] = {0, 1, 2};
    xrad_scene *sc = mesh_scene(pos, 3, idx, 1, NULL, 1);
    if (!sc)
        return;
    CHECK(sc->surface_count == 1 && sc->surfaces[0].triangle, "one triangle surface");
    const surface *s = &sc->surfaces[0];
    vec3 a = v3(0, 0, 0), b = v3(0.7, 0.1, 0), c = v3(0.2, 0.9, 0.3);
    double want = 0.5 * v3_len(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    double sum = 0, smallest = 1;
    for (uint32_t e = 0; e < s->nu * s->nv; e++) {
        sum += sc->elements[s->first_element + e].area;
        smallest = fmin(smallest, sc->elements[s->first_element + e].area);
    }
    CHECK_REL(s->area, want, 1e-6);
    CHECK_REL(sum, want, 1e-6);
    CHECK(smallest > 0, "an element of zero area (%g)", smallest);
    /* Base: the longest edge, b -> c (cyclic order kept: b, c, a). */
    CHECK(v3_len(v3_sub(s->p[0], b)) < 1e-6 && v3_len(v3_sub(s->p[1], c)) < 1e-6 &&
              v3_len(v3_sub(s->p[2], a)) < 1e-6 && v3_len(v3_sub(s->p[3], a)) < 1e-6,
          "corners: the longest edge first, the apex twice");
    vec3 n = v3_norm(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    CHECK(v3_dot(n, s->normal) > 0.999999, "normal: the counter-clockwise side");
    /* Density 10: the base (0.99 m) gets ceil(9.9) + 1 = 11 samples. */
    CHECK(s->nu == 11, "nu = %u, want 11", s->nu);
    xrad_scene_info info;
    xrad_scene_get_info(sc, &info);
    CHECK(info.triangles == 1 && info.skipped_triangles == 0, "info: %u triangles, %u skipped",
          info.triangles, info.skipped_triangles);
    xrad_scene_destroy(&sc);
}

static void joining(void)
{
    /* The unit square in z = 0, facing +z: split along a diagonal, with the
     * diagonal's vertices repeated (as exporters write split normals). */
    const float split[18] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 0, 1, 1, 0, 0, 1, 0};
    const uint32_t split_idx[6] = {0, 1, 2, 3, 4, 5};
    xrad_scene *sc = mesh_scene(split, 6, split_idx, 2, NULL, 0);
    if (sc) {
        CHECK(sc->surface_count == 1 && !sc->surfaces[0].triangle,
              "a split square: %u surfaces, want one quad", sc->surface_count);
        CHECK_REL(sc->surfaces[0].area, 1.0, 1e-9);
        CHECK(sc->surfaces[0].normal.z > 0.999999, "joined quad faces +z");
        CHECK(!strcmp(sc->surfaces[0].name, "mesh.0"), "name %s", sc->surfaces[0].name);
        xrad_scene_destroy(&sc);
    }
    /* The same kept as triangles. */
    sc = mesh_scene(split, 6, split_idx, 2, NULL, 1);
    if (sc) {
        CHECK(sc->surface_count == 2 && sc->surfaces[0].triangle && sc->surfaces[1].triangle,
              "keep_triangles: %u surfaces", sc->surface_count);
        xrad_scene_destroy(&sc);
    }
    /* Different materials: not joined. */
    const uint32_t mats[2] = {0, 1};
    sc = mesh_scene(split, 6, split_idx, 2, mats, 0);
    if (sc) {
        CHECK(sc->surface_count == 2, "two materials: %u surfaces, want 2", sc->surface_count);
        xrad_scene_destroy(&sc);
    }
    /* Opposite orientation (the second triangle faces -z): not joined. */
    const uint32_t flip_idx[6] = {0, 1, 2, 3, 5, 4};
    sc = mesh_scene(split, 6, flip_idx, 2, NULL, 0);
    if (sc) {
        CHECK(sc->surface_count == 2, "opposite faces: %u surfaces, want 2", sc->surface_count);
        xrad_scene_destroy(&sc);
    }
    /* A fold of 90 degrees along the diagonal: not joined. */
    const float fold[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 0, 1};
    const uint32_t fold_idx[6] = {0, 1, 2, 0, 2, 3};
    sc = mesh_scene(fold, 4, fold_idx, 2, NULL, 0);
    if (sc) {
        CHECK(sc->surface_count == 2, "a fold: %u surfaces, want 2", sc->surface_count);
        xrad_scene_destroy(&sc);
    }
    /* A fan of four around the centre: no pair makes a convex quad. */
    const float fan[15] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5f, 0.5f, 0};
    const uint32_t fan_idx[12] = {0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0, 4};
    sc = mesh_scene(fan, 5, fan_idx, 4, NULL, 0);
    if (sc) {
        CHECK(sc->surface_count == 4, "a fan: %u surfaces, want 4", sc->surface_count);
        double area = 0;
        for (uint32_t s = 0; s < sc->surface_count; s++)
            area += sc->surfaces[s].area;
        CHECK_REL(area, 1.0, 1e-6);
        xrad_scene_destroy(&sc);
    }
    /* A zero-area triangle (collinear) among them: left out, counted. */
    const float deg[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
    const uint32_t deg_idx[6] = {0, 1, 2, 0, 1, 3};
    sc = mesh_scene(deg, 4, deg_idx, 2, NULL, 0);
    if (sc) {
        xrad_scene_info info;
        xrad_scene_get_info(sc, &info);
        CHECK(info.surfaces == 1 && info.skipped_triangles == 1,
              "degenerate: %u surfaces, %u skipped", info.surfaces, info.skipped_triangles);
        xrad_scene_destroy(&sc);
    }
}

/* One bad mesh; the message must hold every one of `want`. */
static void bad_mesh(const char *label, const xrad_mesh_desc *m, const char *const *want)
{
    xrad_scene_builder *b = start(1);
    if (!b)
        return;
    xrad_error err = {0};
    xrad_status st = xrad_scene_builder_add_mesh(b, m, &err);
    CHECK(st == XRAD_ERROR_INPUT, "%s: status %d", label, st);
    for (int k = 0; want[k]; k++)
        CHECK(strstr(err.message, want[k]), "%s: '%s' not in: %s", label, want[k], err.message);
    /* A failed builder goes no further. */
    xrad_scene *sc = NULL;
    st = xrad_scene_builder_finish(b, &sc, &err);
    CHECK(st == XRAD_ERROR_INPUT && !sc && strstr(err.message, "destroy"),
          "%s: finish after a failure: %d %s", label, st, err.message);
    xrad_scene_builder_destroy(&b);
}

static void errors(void)
{
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const float nan_pos[9] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    const uint32_t idx[3] = {0, 1, 2}, far_idx[3] = {0, 1, 7}, mats[1] = {3};
    bad_mesh("index out of range",
             &(xrad_mesh_desc){.name = "chair", .positions = pos, .vertex_count = 3,
                               .indices = far_idx, .triangle_count = 1},
             (const char *const[]){"builder-test", "object 'obj'", "mesh 'chair'",
                                   "field 'indices'", "triangle 0", "7", NULL});
    bad_mesh("material out of range",
             &(xrad_mesh_desc){.name = "chair", .positions = pos, .vertex_count = 3,
                               .indices = idx, .triangle_count = 1, .materials = mats},
             (const char *const[]){"mesh 'chair'", "field 'materials'", "material 3", NULL});
    bad_mesh("not finite",
             &(xrad_mesh_desc){.name = "chair", .positions = nan_pos, .vertex_count = 3,
                               .indices = idx, .triangle_count = 1},
             (const char *const[]){"mesh 'chair'", "field 'positions[2]'", "finite", NULL});
    bad_mesh("empty",
             &(xrad_mesh_desc){.name = "chair", .positions = pos, .vertex_count = 3},
             (const char *const[]){"mesh 'chair'", "field 'indices'", "empty", NULL});
    bad_mesh("no name",
             &(xrad_mesh_desc){.positions = pos, .vertex_count = 3, .indices = idx,
                               .triangle_count = 1},
             (const char *const[]){"object 'obj'", "field 'name'", "missing", NULL});

    /* A surface before any object; an object without surfaces; a duplicate
     * object; a material out of range on a quad; no objects at all. */
    xrad_scene_builder *b = NULL;
    xrad_error err = {0};
    xrad_scene *sc = NULL;
    CHECK(xrad_scene_builder_create(NULL, &b, &err) == XRAD_OK, "%s", err.message);
    xrad_quad_desc q = {.name = "q", .p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
    CHECK(xrad_scene_builder_add_quad(b, &q, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "<builder>") && strstr(err.message, "begin_object"),
          "quad before an object: %s", err.message);
    xrad_scene_builder_destroy(&b);

    b = start(1);
    CHECK(xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "next"}, &err) ==
                  XRAD_ERROR_INPUT &&
              strstr(err.message, "object 'obj'") && strstr(err.message, "no surfaces"),
          "empty object: %s", err.message);
    xrad_scene_builder_destroy(&b);

    b = start(1);
    q.material = 5;
    CHECK(xrad_scene_builder_add_quad(b, &q, &err) == XRAD_ERROR_INPUT &&
              strstr(err.message, "surface 'q'") && strstr(err.message, "field 'material'"),
          "quad material: %s", err.message);
    xrad_scene_builder_destroy(&b);

    b = start(1);
    q.material = 0;
    xrad_status st = xrad_scene_builder_add_quad(b, &q, &err);
    if (!st)
        st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "obj"}, &err);
    if (!st)
        st = xrad_scene_builder_add_quad(b, &q, &err);
    CHECK(st == XRAD_OK, "%s", err.message);
    CHECK(xrad_scene_builder_finish(b, &sc, &err) == XRAD_ERROR_INPUT && !sc &&
              strstr(err.message, "duplicate object name 'obj'"),
          "duplicate object: %s", err.message);
    xrad_scene_builder_destroy(&b);

    CHECK(xrad_scene_builder_create(NULL, &b, &err) == XRAD_OK, "%s", err.message);
    CHECK(xrad_scene_builder_finish(b, &sc, &err) == XRAD_ERROR_INPUT && !sc,
          "nothing: %s", err.message);
    xrad_scene_builder_destroy(&b);
    CHECK(xrad_scene_builder_create(&(xrad_scene_builder_desc){.density_scale = 40}, &b,
                                    &err) == XRAD_ERROR_INPUT &&
              !b && strstr(err.message, "density_scale"),
          "density scale: %s", err.message);
}

/* The builder and the loader are one path: the same room from both. */
static void same_as_file(void)
{
    static const char *json =
        "{\"density\": 10, \"materials\": [{\"name\": \"m0\", \"albedo\": [0.5, 0.5, 0.5]}],"
        "\"objects\": [{\"name\": \"obj\", \"surfaces\": [{\"name\": \"q\", \"material\": "
        "\"m0\", \"vertices\": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]]}]}]}";
    xrad_scene *a = NULL, *c = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_parse(json, strlen(json), "same.json", &a, &err) == XRAD_OK, "%s",
          err.message);
    xrad_scene_builder *b = start(1);
    xrad_quad_desc q = {.name = "q", .p = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}};
    CHECK(b && xrad_scene_builder_add_quad(b, &q, &err) == XRAD_OK &&
              xrad_scene_builder_finish(b, &c, &err) == XRAD_OK,
          "%s", err.message);
    xrad_scene_builder_destroy(&b);
    if (a && c) {
        CHECK(a->element_count == c->element_count && a->surfaces[0].nu == c->surfaces[0].nu,
              "file %u elements, builder %u", a->element_count, c->element_count);
        CHECK(!memcmp(&a->cam, &c->cam, sizeof(a->cam)), "the same default camera");
    }
    xrad_scene_destroy(&a);
    xrad_scene_destroy(&c);
}

int main(void)
{
    triangle_elements();
    tiny_triangle();
    joining();
    errors();
    same_as_file();
    return test_finish();
}
