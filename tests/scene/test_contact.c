/* Buried and enclosed elements (src/scene/scene_contact.c) against answers
 * known by construction: a 2 x 2 m floor with 0.125 m elements (17 x 17
 * samples), on it a closed box over [0.5, 1] x [0.5, 1] (its bottom faces
 * the floor) and a plinth without a bottom face over [1.25, 1.75] x [0.25,
 * 0.75] (four sides facing out and a top). Floor elements whose cell centroid lies
 * strictly inside the box's footprint are buried under it, the box's
 * bottom elements are buried on the floor; floor elements inside the
 * plinth are enclosed; a centroid on a footprint's edge is neither. */
#include <stdio.h>
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
    "    \"u\": [0, 0, 0.5], \"v\": [0, 0.3, 0]}}]}"
    " ]}";

static bool inside(double a, double lo, double hi) { return a > lo + 1e-9 && a < hi - 1e-9; }

int main(void)
{
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
    free(buried);
    free(enclosed);
    xrad_scene_destroy(&sc);
    return test_finish();
}
