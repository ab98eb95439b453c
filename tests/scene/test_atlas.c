/* Elements and the atlas (thesis 4.1, figure 4.1.2; scene.h): areas add up
 * to the surface, edge and corner elements carry a half and a quarter,
 * samples sit on the documented parameters, adjacent coplanar quads share
 * their boundary samples, and the atlas gives every element its own texel. */
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

static const char *const shipped[] = {
    "scenes/cornell-box.json",   "scenes/cornell-large.json", "scenes/cornell-small.json",
    "scenes/cornell-lowq.json",  "scenes/indirect-light.json",
};

static xrad_scene *parse(const char *json)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "atlas-test.json", &scene, &err);
    CHECK(st == XRAD_OK, "%s", err.message);
    return scene;
}

static double quad_area(const surface *s)
{
    return 0.5 * v3_len(v3_cross(v3_sub(s->p[2], s->p[0]), v3_sub(s->p[3], s->p[1])));
}

/* Per surface: element areas sum to the quad's area. */
static void check_area_sums(const char *label, const xrad_scene *sc)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < sc->surface_count; i++) {
        const surface *s = &sc->surfaces[i];
        double sum = 0;
        for (uint32_t e = 0; e < s->nu * s->nv; e++)
            sum += sc->elements[s->first_element + e].area;
        double want = quad_area(s);
        if (!(fabs(sum - want) <= 1e-9 * want)) {
            bad++;
            fprintf(stderr, "%s: surface %s: elements sum to %.15g, area %.15g\n", label,
                    s->name, sum, want);
        }
    }
    CHECK(bad == 0, "%s: %u surfaces whose element areas do not sum to their area", label, bad);
}

/* Every element has its own texel inside the atlas and inside its
 * surface's tile, at (tile + (i, j)); element order is row-major. */
static void check_atlas(const char *label, const xrad_scene *sc)
{
    CHECK(sc->atlas_width >= 1 && sc->atlas_width <= 4096, "%s: atlas width %u", label,
          sc->atlas_width);
    size_t texels = (size_t)sc->atlas_width * sc->atlas_height;
    unsigned char *used = calloc(texels, 1);
    CHECK(used != NULL, "out of memory");
    if (!used)
        return;
    uint32_t bad = 0, shared = 0;
    for (uint32_t i = 0; i < sc->surface_count; i++) {
        const surface *s = &sc->surfaces[i];
        for (uint32_t j = 0; j < s->nv; j++)
            for (uint32_t k = 0; k < s->nu; k++) {
                const element *e = &sc->elements[s->first_element + j * s->nu + k];
                bad += e->surface != i || e->i != k || e->j != j ||
                       e->texel_x != s->tile_x + k || e->texel_y != s->tile_y + j ||
                       e->texel_x >= sc->atlas_width || e->texel_y >= sc->atlas_height;
                if (e->texel_x < sc->atlas_width && e->texel_y < sc->atlas_height)
                    shared += used[(size_t)e->texel_y * sc->atlas_width + e->texel_x]++ != 0;
            }
    }
    free(used);
    CHECK(bad == 0, "%s: %u elements with a wrong index or texel", label, bad);
    CHECK(shared == 0, "%s: %u texels hold two elements", label, shared);
    /* "As small as reasonable": shelf packing of a few dozen tiles leaves
     * less than a third empty. */
    CHECK(sc->element_count >= 0.66 * texels, "%s: atlas %u x %u holds %u elements", label,
          sc->atlas_width, sc->atlas_height, sc->element_count);

    xrad_atlas atlas;
    xrad_error err = {0};
    CHECK(xrad_atlas_create(sc, &atlas, &err) == XRAD_OK, "%s", err.message);
    CHECK(atlas.width == sc->atlas_width && atlas.height == sc->atlas_height, "atlas size");
    uint32_t nonzero = 0;
    for (size_t t = 0; t < 4 * texels && atlas.rgba; t++)
        nonzero += atlas.rgba[t] != 0.0f;
    CHECK(nonzero == 0, "%s: new atlas has %u non-zero floats", label, nonzero);
    xrad_atlas_destroy(&atlas);
    CHECK(atlas.rgba == NULL, "destroy clears the atlas");
}

int main(void)
{
    for (size_t k = 0; k < sizeof(shipped) / sizeof(shipped[0]); k++) {
        char path[512];
        xrad_scene *sc = NULL;
        xrad_error err = {0};
        CHECK(xrad_scene_load(test_source_path(shipped[k], path, sizeof(path)), &sc, &err) ==
                  XRAD_OK,
              "%s", err.message);
        if (!sc)
            continue;
        check_area_sums(shipped[k], sc);
        check_atlas(shipped[k], sc);
        xrad_scene_destroy(&sc);
    }

    /* A trapezoid with parallel sides 4 and 2, height 2: area 6. */
    xrad_scene *sc = parse(
        "{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], \"objects\": [{"
        "\"name\": \"o\", \"surfaces\": [{\"name\": \"trapezoid\", \"material\": \"m\", "
        "\"density\": 7, \"vertices\": [[0, 0, 0], [4, 0, 0], [3, 2, 0], [1, 2, 0]]}]}]}");
    if (sc) {
        CHECK_REL(sc->surfaces[0].area, 6.0, 1e-12);
        double sum = 0;
        for (uint32_t e = 0; e < sc->element_count; e++)
            sum += sc->elements[e].area;
        CHECK_REL(sum, 6.0, 1e-9);
        /* Longer of the opposite edges: 4 m along u, sqrt(5) m along v. */
        CHECK(sc->surfaces[0].nu == 29 && sc->surfaces[0].nv == 17, "trapezoid %u x %u",
              sc->surfaces[0].nu, sc->surfaces[0].nv);
        check_atlas("trapezoid", sc);
        xrad_scene_destroy(&sc);
    }

    /* A parallelogram u = (2, 0, 0), v = (0.5, 1, 0) (area 2) with 5 x 4
     * samples: interior elements hold A / ((nu - 1)(nv - 1)), edge elements
     * half, corner elements a quarter; sample (i, j) sits at
     * origin + i/(nu-1) u + j/(nv-1) v, corners 1% of a spacing inward. */
    sc = parse("{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], "
               "\"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"p\", "
               "\"material\": \"m\", \"elements\": [5, 4], \"quad\": {\"origin\": [1, 2, 3], "
               "\"u\": [2, 0, 0], \"v\": [0.5, 1, 0]}}]}]}");
    if (sc) {
        const surface *s = &sc->surfaces[0];
        CHECK(s->nu == 5 && s->nv == 4, "explicit counts %u x %u", s->nu, s->nv);
        double inner = 2.0 / (4 * 3);
        vec3 o = v3(1, 2, 3), u = v3(2, 0, 0), v = v3(0.5, 1, 0);
        for (uint32_t j = 0; j < 4; j++)
            for (uint32_t i = 0; i < 5; i++) {
                const element *e = &sc->elements[j * 5 + i];
                int edges = (i == 0 || i == 4) + (j == 0 || j == 3);
                CHECK_REL(e->area, inner / (1 << edges), 1e-12);
                double si = i / 4.0, tj = j / 3.0;
                if (edges == 2) {
                    si = i == 0 ? 0.01 / 4 : 1 - 0.01 / 4;
                    tj = j == 0 ? 0.01 / 3 : 1 - 0.01 / 3;
                }
                vec3 want = v3_add(o, v3_add(v3_scale(u, si), v3_scale(v, tj)));
                CHECK(v3_len(v3_sub(e->pos, want)) < 1e-12, "sample (%u, %u) at (%g %g %g)", i,
                      j, e->pos.x, e->pos.y, e->pos.z);
            }
        CHECK_REL(s->area, 2.0, 1e-12);
        CHECK(fabs(s->normal.z - 1) < 1e-12, "normal along u x v");
        xrad_scene_destroy(&sc);
    }

    /* Two adjacent coplanar quads in different objects, one of them
     * dynamic and placed by its rest pose (rotate 90 degrees about z, then
     * translate): the samples on the shared edge (corners excepted, they
     * are pulled inward) coincide in world space. Quad a spans x, y in
     * [0, 1]; b's corners land on (2.5, 0), (2.5, 1), (1, 1), (1, 0), so its
     * t = 1 row runs along a's s = 1 column. */
    sc = parse("{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], "
               "\"density\": 10, \"objects\": ["
               "{\"name\": \"a\", \"surfaces\": [{\"name\": \"q\", \"material\": \"m\", "
               "\"quad\": {\"origin\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0]}}]},"
               "{\"name\": \"b\", \"dynamic\": true, \"translate\": [1, 0, 0], "
               "\"rotate\": {\"axis\": [0, 0, 1], \"degrees\": 90}, "
               "\"surfaces\": [{\"name\": \"q\", \"material\": \"m\", "
               "\"quad\": {\"origin\": [0, -1.5, 0], \"u\": [1, 0, 0], \"v\": [0, 1.5, 0]}}]}]}");
    if (sc) {
        const surface *a = &sc->surfaces[0], *b = &sc->surfaces[1];
        xform pa = scene_object_pose(sc, 0, 0.0), pb = scene_object_pose(sc, 1, 0.0);
        vec3 cb[4], nb;
        scene_surface_world(sc, 1, 0.0, cb, &nb);
        CHECK(fabs(nb.z - 1) < 1e-12, "b faces +z in the world (%g %g %g)", nb.x, nb.y, nb.z);
        CHECK(v3_len(v3_sub(cb[3], v3(1, 0, 0))) < 1e-12 &&
                  v3_len(v3_sub(cb[2], v3(1, 1, 0))) < 1e-12,
              "b's t = 1 edge at x = 1: (%g %g) (%g %g)", cb[3].x, cb[3].y, cb[2].x, cb[2].y);
        CHECK(a->nv == b->nu, "shared edge sampled alike: %u vs %u", a->nv, b->nu);
        uint32_t matched = 0;
        for (uint32_t j = 1; j + 1 < a->nv && a->nv == b->nu; j++) {
            vec3 wa = xf_point(&pa, sc->elements[a->first_element + j * a->nu + a->nu - 1].pos);
            vec3 wb = xf_point(&pb, sc->elements[b->first_element + (b->nv - 1) * b->nu + j].pos);
            CHECK(v3_len(v3_sub(wa, wb)) < 1e-12, "sample %u: a (%g %g %g), b (%g %g %g)", j,
                  wa.x, wa.y, wa.z, wb.x, wb.y, wb.z);
            matched++;
        }
        CHECK(matched == 9, "edge samples compared: %u", matched);
        xrad_scene_destroy(&sc);
    }
    /* Boxes: six faces named <name>.-u ... <name>.+w, normals out of the
     * box (into it with "inward"), whatever the handedness of u, v, w;
     * total area 2 (ab + bc + ca); explicit counts follow the edges. */
    for (int variant = 0; variant < 3; variant++) {
        static const char *const boxes[] = {
            "\"box\": {\"origin\": [1, 2, 3], \"u\": [2, 0, 0], \"v\": [0, 3, 0], \"w\": [0, 0, 4]}",
            "\"box\": {\"origin\": [1, 2, 3], \"u\": [2, 0, 0], \"v\": [0, 0, 4], \"w\": [0, 3, 0]}",
            "\"inward\": true, \"box\": {\"origin\": [1, 2, 3], \"u\": [2, 0, 0], "
            "\"v\": [0, 3, 0], \"w\": [0, 0, 4]}",
        };
        char json[1024];
        snprintf(json, sizeof(json),
                 "{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], "
                 "\"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"b\", "
                 "\"material\": \"m\", \"elements\": [3, 4, 5], %s}]}]}",
                 boxes[variant]);
        sc = parse(json);
        if (!sc)
            continue;
        CHECK(sc->surface_count == 6, "box: %u faces", sc->surface_count);
        vec3 centre = v3(2, 3.5, 5);
        double area = 0;
        static const char *const names[] = {"b.-u", "b.+u", "b.-v", "b.+v", "b.-w", "b.+w"};
        for (uint32_t i = 0; i < sc->surface_count && i < 6; i++) {
            const surface *s = &sc->surfaces[i];
            CHECK(!strcmp(s->name, names[i]), "face %u named %s, want %s", i, s->name, names[i]);
            vec3 mid = surface_point(s, 0.5, 0.5);
            double out = v3_dot(s->normal, v3_sub(mid, centre));
            CHECK(variant == 2 ? out < 0 : out > 0, "box %d face %s: normal (%g %g %g) %s", variant,
                  s->name, s->normal.x, s->normal.y, s->normal.z,
                  variant == 2 ? "points out" : "points in");
            area += s->area;
            /* Samples along an edge of length 2, 3, 4 (u, v, w of the first
             * variant; the second swaps v and w): 3, 4, 5 as given. */
            double lu = v3_len(v3_sub(s->p[1], s->p[0])), lv = v3_len(v3_sub(s->p[3], s->p[0]));
            uint32_t want_u = (uint32_t)lu + 1, want_v = (uint32_t)lv + 1;
            if (variant == 1) {
                want_u = lu == 2 ? 3 : lu == 4 ? 4 : 5;
                want_v = lv == 2 ? 3 : lv == 4 ? 4 : 5;
            }
            CHECK(s->nu == want_u && s->nv == want_v, "box %d face %s: %u x %u, edges %g x %g",
                  variant, s->name, s->nu, s->nv, lu, lv);
        }
        CHECK_REL(area, 2 * (2 * 3 + 3 * 4 + 2 * 4), 1e-12);
        check_area_sums("box", sc);
        xrad_scene_destroy(&sc);
    }
    return test_finish();
}
