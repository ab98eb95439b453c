/* Buried and enclosed elements (src/scene/scene_contact.c) against answers
 * known by construction: a 2 x 2 m floor with 0.125 m elements (17 x 17
 * samples), on it a closed box over [0.5, 1] x [0.5, 1] (its bottom faces
 * the floor) and a plinth without a bottom face over [1.25, 1.75] x [0.25,
 * 0.75] (four sides facing out and a top). Floor elements whose cell centroid lies
 * strictly inside the box's footprint are buried under it, the box's
 * bottom elements are buried on the floor; floor elements inside the
 * plinth are enclosed; a centroid on a footprint's edge is neither.
 * A moving plinth without a bottom face, over [1.25, 1.75] x [1.25, 1.75]
 * at t = 0 and sliding -1 m along x in 1 s, encloses the floor centroids
 * strictly inside its footprint at each time (scene_find_enclosed_dynamic)
 * and none for the static test. Surfaces back to back in one plane with
 * nothing closed behind (scene_find_flat_slabs): test_slabs. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

static const char *json =
    "{\"unit\": \"m\", \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": ["
    "  {\"name\": \"floor\", \"surfaces\": [{\"name\": \"floor\", \"material\": \"m\","
    "    \"elements\": [17, 17], \"quad\": {\"origin\": [0, 0, 0], \"u\": [0, 0, 2],"
    "    \"v\": [2, 0, 0]}}]},"
    "  {\"name\": \"box\", \"surfaces\": [{\"name\": \"box\", \"material\": \"m\","
    "    \"elements\": [3, 3, 3], \"box\": {\"origin\": [0.5, 0, 0.5], \"u\": [0.5, 0, 0],"
    "    \"v\": [0, 0.5, 0], \"w\": [0, 0, 0.5]}}]},"
    "  {\"name\": \"plinth\", \"surfaces\": ["
    "   {\"name\": \"top\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0.3, 0.25],"
    "    \"u\": [0, 0, 0.5], \"v\": [0.5, 0, 0]}},"
    "   {\"name\": \"s1\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 0.25],"
    "    \"u\": [0, 0.3, 0], \"v\": [0.5, 0, 0]}},"
    "   {\"name\": \"s2\", \"material\": \"m\", \"quad\": {\"origin\": [1.75, 0, 0.25],"
    "    \"u\": [0, 0.3, 0], \"v\": [0, 0, 0.5]}},"
    "   {\"name\": \"s3\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 0.75],"
    "    \"u\": [0.5, 0, 0], \"v\": [0, 0.3, 0]}},"
    "   {\"name\": \"s4\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 0.25],"
    "    \"u\": [0, 0, 0.5], \"v\": [0, 0.3, 0]}}]},"
    "  {\"name\": \"mover\", \"dynamic\": true, \"animation\": {\"keyframes\": ["
    "    {\"time\": 0, \"translate\": [0, 0, 0]}, {\"time\": 1, \"translate\": [-1, 0, 0]}]},"
    "   \"surfaces\": ["
    "   {\"name\": \"m-top\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0.3, 1.25],"
    "    \"u\": [0, 0, 0.5], \"v\": [0.5, 0, 0]}},"
    "   {\"name\": \"m1\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 1.25],"
    "    \"u\": [0, 0.3, 0], \"v\": [0.5, 0, 0]}},"
    "   {\"name\": \"m2\", \"material\": \"m\", \"quad\": {\"origin\": [1.75, 0, 1.25],"
    "    \"u\": [0, 0.3, 0], \"v\": [0, 0, 0.5]}},"
    "   {\"name\": \"m3\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 1.75],"
    "    \"u\": [0.5, 0, 0], \"v\": [0, 0.3, 0]}},"
    "   {\"name\": \"m4\", \"material\": \"m\", \"quad\": {\"origin\": [1.25, 0, 1.25],"
    "    \"u\": [0, 0, 0.5], \"v\": [0, 0.3, 0]}}]}"
    " ]}";

static bool inside(double a, double lo, double hi) { return a > lo + 1e-9 && a < hi - 1e-9; }

/* A closed 2 m room (0.125 m elements), a lamp hung 1 mm below the
 * ceiling over [0.75, 1.25]^2, and a cabinet without bottom or back face
 * standing against the z = 2 wall over x [0.55, 1.05], z [1.45, 2],
 * 0.55 m high: the floor and the wall inside it form a pocket no light
 * reaches, though their rays meet front faces (each other's). */
static const char *pocket_json =
    "{\"unit\": \"m\", \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]},"
    "  {\"name\": \"lamp\", \"albedo\": [0.5, 0.5, 0.5], \"emission\": [10, 10, 10]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "  {\"name\": \"floor\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [0, 0, 0], \"u\": [0, 0, 2], \"v\": [2, 0, 0]}},"
    "  {\"name\": \"ceiling\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [0, 2, 0], \"u\": [2, 0, 0], \"v\": [0, 0, 2]}},"
    "  {\"name\": \"x0\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [0, 0, 0], \"u\": [0, 2, 0], \"v\": [0, 0, 2]}},"
    "  {\"name\": \"x2\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [2, 0, 0], \"u\": [0, 0, 2], \"v\": [0, 2, 0]}},"
    "  {\"name\": \"z0\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [0, 0, 0], \"u\": [2, 0, 0], \"v\": [0, 2, 0]}},"
    "  {\"name\": \"z2\", \"material\": \"m\", \"elements\": [17, 17], \"quad\":"
    "   {\"origin\": [0, 0, 2], \"u\": [0, 2, 0], \"v\": [2, 0, 0]}},"
    "  {\"name\": \"lamp\", \"material\": \"lamp\", \"elements\": [5, 5], \"quad\":"
    "   {\"origin\": [0.75, 1.999, 0.75], \"u\": [0.5, 0, 0], \"v\": [0, 0, 0.5]}}]},"
    "  {\"name\": \"cabinet\", \"surfaces\": ["
    "  {\"name\": \"top\", \"material\": \"m\", \"elements\": [5, 5], \"quad\":"
    "   {\"origin\": [0.55, 0.55, 1.45], \"u\": [0, 0, 0.55], \"v\": [0.5, 0, 0]}},"
    "  {\"name\": \"-x\", \"material\": \"m\", \"elements\": [5, 5], \"quad\":"
    "   {\"origin\": [0.55, 0, 1.45], \"u\": [0, 0, 0.55], \"v\": [0, 0.55, 0]}},"
    "  {\"name\": \"+x\", \"material\": \"m\", \"elements\": [5, 5], \"quad\":"
    "   {\"origin\": [1.05, 0, 1.45], \"u\": [0, 0.55, 0], \"v\": [0, 0, 0.55]}},"
    "  {\"name\": \"-z\", \"material\": \"m\", \"elements\": [5, 5], \"quad\":"
    "   {\"origin\": [0.55, 0, 1.45], \"u\": [0, 0.55, 0], \"v\": [0.5, 0, 0]}}]}"
    " ]}";

/* The pocket: floor centroids strictly inside the cabinet's footprint
 * (x 0.625-1.0, z 1.5-1.96875: 4 x 5), wall z2's strictly inside its back
 * outline (x 0.625-1.0, y 0.03125-0.5: 4 x 5); above the lamp, the ceiling
 * centroids more than a ray's reach (1 mm / tan 15 deg) inside its
 * outline (x, z 0.875-1.125: 3 x 3), whose every ray meets the lamp's
 * back. Nothing else. */
static void test_pocket(void)
{
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(pocket_json, strlen(pocket_json), "pocket.json", &sc, &err);
    CHECK(st == XRAD_OK, "pocket: parse: %s", err.message);
    if (st)
        return;
    uint8_t *enclosed = calloc(sc->element_count, 1);
    uint32_t ne = 0, want = 0, wrong = 0;
    st = scene_find_enclosed(sc, enclosed, &ne, &err);
    CHECK(st == XRAD_OK, "pocket: enclosed: %s", err.message);
    for (uint32_t e = 0; !st && e < sc->element_count; e++) {
        const element *el = &sc->elements[e];
        const surface *sf = &sc->surfaces[el->surface];
        vec3 c = scene_element_centroid(sf, el);
        bool in = (!strcmp(sf->name, "floor") && inside(c.x, 0.55, 1.05) && inside(c.z, 1.45, 2)) ||
                  (!strcmp(sf->name, "z2") && inside(c.x, 0.55, 1.05) && inside(c.y, 0, 0.55)) ||
                  (!strcmp(sf->name, "ceiling") && inside(c.x, 0.76, 1.24) && inside(c.z, 0.76, 1.24));
        want += in;
        if ((enclosed[e] != 0) != in) {
            wrong++;
            fprintf(stderr, "  pocket: %s element (%u, %u) at (%.4f, %.4f, %.4f) %s\n", sf->name,
                    el->i, el->j, c.x, c.y, c.z, in ? "open, want enclosed" : "enclosed, want open");
        }
    }
    CHECK(want == 49, "pocket: construction: %u elements want enclosed, 49 by count", want);
    CHECK(wrong == 0 && ne == want, "pocket: %u elements wrongly enclosed or not (%u found, want %u)",
          wrong, ne, want);
    free(enclosed);
    xrad_scene_destroy(&sc);
}

/* A floor, a closed box standing on it, a table top of zero thickness
 * (two quads back to back at y = 0.7: "top" facing up, "under" facing
 * down) and a slab 1 cm thick ("top2" over "under2"): of the pairs face
 * to face in one plane (the box's bottom on the floor, the table top's
 * two faces) only the table top closes nothing behind it. */
static const char *slab_json =
    "{\"unit\": \"m\", \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5],"
    "  \"emission\": [1, 1, 1]}],"
    " \"objects\": ["
    "  {\"name\": \"floor\", \"surfaces\": [{\"name\": \"floor\", \"material\": \"m\","
    "    \"quad\": {\"origin\": [0, 0, 0], \"u\": [0, 0, 2], \"v\": [2, 0, 0]}}]},"
    "  {\"name\": \"box\", \"surfaces\": [{\"name\": \"box\", \"material\": \"m\","
    "    \"box\": {\"origin\": [1.2, 0, 0.2], \"u\": [0.5, 0, 0], \"v\": [0, 0.5, 0],"
    "    \"w\": [0, 0, 0.5]}}]},"
    "  {\"name\": \"table\", \"surfaces\": ["
    "   {\"name\": \"top\", \"material\": \"m\", \"quad\": {\"origin\": [0.2, 0.7, 0.2],"
    "    \"u\": [0, 0, 0.6], \"v\": [0.6, 0, 0]}},"
    "   {\"name\": \"under\", \"material\": \"m\", \"quad\": {\"origin\": [0.2, 0.7, 0.2],"
    "    \"u\": [0.6, 0, 0], \"v\": [0, 0, 0.6]}},"
    "   {\"name\": \"top2\", \"material\": \"m\", \"quad\": {\"origin\": [0.2, 0.71, 1.2],"
    "    \"u\": [0, 0, 0.6], \"v\": [0.6, 0, 0]}},"
    "   {\"name\": \"under2\", \"material\": \"m\", \"quad\": {\"origin\": [0.2, 0.7, 1.2],"
    "    \"u\": [0.6, 0, 0], \"v\": [0, 0, 0.6]}}]}]}";

static void test_slabs(void)
{
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(slab_json, strlen(slab_json), "slabs.json", &sc, &err);
    CHECK(st == XRAD_OK, "slabs.json: %s", err.message);
    if (st)
        return;
    uint32_t *pairs = NULL, count = 0;
    st = scene_find_flat_slabs(sc, 0, &pairs, &count, &err);
    CHECK(st == XRAD_OK && count == 1, "slabs.json: %u zero-thickness pairs, want 1 (%s)", count,
          st ? err.message : "");
    if (!st && count == 1) {
        const char *a = sc->surfaces[pairs[0]].name, *b = sc->surfaces[pairs[1]].name;
        CHECK((!strcmp(a, "top") && !strcmp(b, "under")) ||
                  (!strcmp(a, "under") && !strcmp(b, "top")),
              "slabs.json: the pair found is '%s' and '%s', not the table top's faces", a, b);
    }
    /* The loader says so, naming both and the file. */
    uint32_t said = 0;
    for (uint32_t w = 0; w < xrad_scene_warning_count(sc); w++) {
        const char *text = xrad_scene_warning(sc, w);
        said += strstr(text, "slabs.json") && strstr(text, "'top'") && strstr(text, "'under'") &&
                strstr(text, "zero thickness");
    }
    CHECK(said == 1, "slabs.json: %u warnings name the table top's faces, want 1", said);
    free(pairs);
    xrad_scene_destroy(&sc);
    /* The box on the floor and the bottomless plinth: none. */
    st = xrad_scene_parse(json, strlen(json), "contact.json", &sc, &err);
    if (!st)
        st = scene_find_flat_slabs(sc, 0, &pairs, &count, &err);
    CHECK(st == XRAD_OK && count == 0, "contact.json: %u zero-thickness pairs, want 0 (%s)", count,
          st ? err.message : "");
    free(pairs);
    xrad_scene_destroy(&sc);
}

int main(void)
{
    test_pocket();
    test_slabs();
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "contact.json", &sc, &err);
    CHECK(st == XRAD_OK, "parse: %s", err.message);
    if (st)
        return test_finish();
    uint8_t *buried = calloc(sc->element_count, 1), *enclosed = calloc(sc->element_count, 1);
    uint32_t nb = 0, ne = 0;
    st = scene_find_buried(sc, 0.0, 1e-6, buried, &nb, &err);
    CHECK(st == XRAD_OK, "buried: %s", err.message);
    st = scene_find_enclosed(sc, enclosed, &ne, &err);
    CHECK(st == XRAD_OK, "enclosed: %s", err.message);
    uint32_t want_b = 0, want_e = 0, wrong_b = 0, wrong_e = 0, edge = 0;
    for (uint32_t e = 0; e < sc->element_count; e++) {
        const element *el = &sc->elements[e];
        const surface *sf = &sc->surfaces[el->surface];
        vec3 c = scene_element_centroid(sf, el);
        bool floor = !strcmp(sf->name, "floor");
        bool box_bottom = !strcmp(sf->name, "box.-v");
        bool b = (floor && inside(c.x, 0.5, 1) && inside(c.z, 0.5, 1)) || box_bottom;
        /* The floor under the closed box is enclosed as well; the box's
         * bottom looks down past the floor's plane, out of the volume. */
        bool under_box = floor && inside(c.x, 0.5, 1) && inside(c.z, 0.5, 1);
        bool in = (floor && inside(c.x, 1.25, 1.75) && inside(c.z, 0.25, 0.75)) || under_box;
        edge += floor && (c.x == 0.5 || c.x == 1.0 || c.z == 0.5 || c.z == 1.0);
        want_b += b;
        want_e += in;
        wrong_b += (buried[e] != 0) != b;
        wrong_e += (enclosed[e] != 0) != in;
    }
    /* The box's footprint holds floor centroids 0.625, 0.75 and 0.875 each
     * way (9), its bottom 3 x 3 elements (9); the plinth's 9 more floor
     * centroids, enclosed with the 9 under the box. Floor cells with a
     * centroid on a footprint's edge exist. */
    CHECK(want_b == 18 && want_e == 18 && edge > 0, "construction: %u buried, %u enclosed, %u edge",
          want_b, want_e, edge);
    CHECK(wrong_b == 0 && nb == want_b, "%u elements wrongly buried or not (%u found, want %u)",
          wrong_b, nb, want_b);
    CHECK(wrong_e == 0 && ne == want_e, "%u elements wrongly enclosed or not (%u found, want %u)",
          wrong_e, ne, want_e);
    /* Buried by a static cover: 1 (scene.h). */
    for (uint32_t e = 0; e < sc->element_count; e++)
        CHECK(buried[e] <= 1, "element %u buried by a moving cover in a static scene", e);
    /* The moving plinth at t = 0 and 0.5: 9 floor centroids each (0.125 m
     * apart, 3 strictly inside a 0.5 m side), nothing else. */
    for (int k = 0; k < 2; k++) {
        double t = 0.5 * k, x0 = 1.25 - t;
        st = scene_find_enclosed_dynamic(sc, t, NULL, enclosed, &ne, &err);
        CHECK(st == XRAD_OK, "enclosed at t = %g: %s", t, err.message);
        uint32_t want = 0, wrong = 0;
        for (uint32_t e = 0; e < sc->element_count; e++) {
            const element *el = &sc->elements[e];
            const surface *sf = &sc->surfaces[el->surface];
            vec3 c = scene_element_centroid(sf, el);
            bool in = !strcmp(sf->name, "floor") && inside(c.x, x0, x0 + 0.5) &&
                      inside(c.z, 1.25, 1.75);
            want += in;
            wrong += (enclosed[e] != 0) != in;
        }
        CHECK(want == 9, "construction: %u floor centroids under the moving plinth at t = %g",
              want, t);
        CHECK(wrong == 0 && ne == want,
              "t = %g: %u elements wrongly enclosed by the moving plinth or not (%u found, want %u)",
              t, wrong, ne, want);
    }
    free(buried);
    free(enclosed);
    xrad_scene_destroy(&sc);
    return test_finish();
}
