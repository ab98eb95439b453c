/* Model files through assimp (scene_import.c):
 *  - tests/data/lamp-room.obj, a room of quads written as OBJ faces with
 *    a lamp of Ke = 10 / pi, loads as a scene by itself and placed by a
 *    JSON scene; it comes back as the same seven quads (assimp's
 *    triangles joined), the lamp's exitance pi Ke = 10 W/m^2 (the
 *    radiance reading of emission, scenes/README.md), and the CPU
 *    reference of the placed OBJ gives the same area-weighted radiosity
 *    as the same room written as JSON quads (tests/data/lamp-room.json),
 *    within 0.5% (two element layouts of one room);
 *  - a glTF binary of assimp's test models (BoxTextured.glb) loads, and
 *    its texture and its clamped base colour are listed as warnings;
 *  - bad input names the scene file, the object, the surface and the
 *    model file: a missing file, a node that is not there, a format
 *    xrad does not read.
 */
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

static xrad_scene *load(const char *rel)
{
    char path[1024];
    test_source_path(rel, path, sizeof(path));
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_load(path, &scene, &err);
    CHECK(st == XRAD_OK, "%s: %s", rel, err.message);
    return scene;
}

/* Area-weighted mean of R + G + B over the elements of non-emitting
 * materials. */
static double mean_b(const xrad_scene *sc, const xrad_atlas *a)
{
    double sum = 0, area = 0;
    for (uint32_t e = 0; e < sc->element_count; e++) {
        const element *el = &sc->elements[e];
        const material *m = &sc->materials[sc->surfaces[el->surface].material];
        if (m->emission.x + m->emission.y + m->emission.z > 0)
            continue;
        const float *t = &a->rgba[4 * ((size_t)el->texel_y * a->width + el->texel_x)];
        sum += el->area * (t[0] + t[1] + t[2]);
        area += el->area;
    }
    return area > 0 ? sum / area : -1;
}

static double reference_mean(const xrad_scene *sc)
{
    xrad_atlas a = {0};
    xrad_error err = {0};
    xrad_status st = xrad_atlas_create(sc, &a, &err);
    if (!st)
        st = xrad_reference_solve(sc, &(xrad_reference_desc){.threads = 2}, &a, NULL, &err);
    CHECK(st == XRAD_OK, "reference: %s", err.message);
    double m = st ? -1 : mean_b(sc, &a);
    xrad_atlas_destroy(&a);
    return m;
}

static void obj_room(void)
{
    xrad_scene *own = load("tests/data/lamp-room.obj");
    xrad_scene *placed = load("tests/data/lamp-room-obj.json");
    xrad_scene *quads = load("tests/data/lamp-room.json");
    if (own) {
        CHECK(own->surface_count == 7 && own->object_count == 1 &&
                  !strcmp(own->objects[0].name, "lamp-room"),
              "lamp-room.obj: %u surfaces, object '%s'", own->surface_count,
              own->objects[0].name);
        uint32_t lamps = 0;
        for (uint32_t s = 0; s < own->surface_count; s++) {
            CHECK(!own->surfaces[s].triangle, "surface %s: a triangle, not joined",
                  own->surfaces[s].name);
            const material *m = &own->materials[own->surfaces[s].material];
            if (m->emission.x > 0) {
                lamps++;
                CHECK_REL(m->emission.x, 10.0, 1e-6);
                CHECK_REL(own->surfaces[s].area, 0.3, 1e-6);
            }
        }
        CHECK(lamps == 1, "%u emitting surfaces, want 1", lamps);
    }
    if (placed && quads) {
        CHECK(placed->surface_count == quads->surface_count, "placed %u surfaces, quads %u",
              placed->surface_count, quads->surface_count);
        double a = reference_mean(placed), b = reference_mean(quads);
        fprintf(stderr, "lamp room: placed OBJ %.5f, JSON quads %.5f (ratio %.5f)\n", a, b,
                a / b);
        CHECK(b > 0 && fabs(a / b - 1) <= 0.005,
              "the placed OBJ's mean radiosity %.5f against the JSON room's %.5f", a, b);
    }
    xrad_scene_destroy(&own);
    xrad_scene_destroy(&placed);
    xrad_scene_destroy(&quads);
}

static void gltf_box(void)
{
    const char *path = "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb";
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_load(path, &sc, &err);
    CHECK(st == XRAD_OK, "%s (package assimp-testmodels, tools/setup.sh): %s", path,
          err.message);
    if (st)
        return;
    CHECK(sc->surface_count == 6, "BoxTextured: %u surfaces, want its 6 faces",
          sc->surface_count);
    int textures = 0, clamped = 0;
    for (uint32_t k = 0; k < xrad_scene_warning_count(sc); k++) {
        textures |= strstr(xrad_scene_warning(sc, k), "textures") != NULL;
        clamped |= strstr(xrad_scene_warning(sc, k), "clamped") != NULL;
    }
    CHECK(textures && clamped, "warnings: textures %d, clamped base colour %d", textures,
          clamped);
    CHECK(xrad_scene_warning(sc, xrad_scene_warning_count(sc)) == NULL, "NULL past the count");
    xrad_scene_destroy(&sc);
}

static void bad(const char *label, const char *mesh, const char *const *want)
{
    char json[1024];
    snprintf(json, sizeof(json),
             "{\"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}],"
             "\"objects\": [{\"name\": \"room\", \"surfaces\": [{\"name\": \"model\", "
             "\"mesh\": %s}]}]}",
             mesh);
    char name[1024];
    test_source_path("tests/data/bad.json", name, sizeof(name));
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), name, &sc, &err);
    CHECK(st == XRAD_ERROR_INPUT && !sc, "%s: status %d", label, st);
    for (int k = 0; want[k]; k++)
        CHECK(strstr(err.message, want[k]), "%s: '%s' not in: %s", label, want[k], err.message);
    xrad_scene_destroy(&sc);
}

static void errors(void)
{
    bad("missing file", "{\"file\": \"nothere.glb\"}",
        (const char *const[]){"bad.json", "object 'room'", "surface 'model'", "nothere.glb",
                              NULL});
    bad("no such node", "{\"file\": \"lamp-room.obj\", \"node\": \"attic\"}",
        (const char *const[]){"bad.json", "surface 'model'", "no node named 'attic'", NULL});
    bad("format", "{\"file\": \"room.fbx\"}",
        (const char *const[]){"field 'mesh.file'", "room.fbx", ".gltf", NULL});
    bad("no file", "{\"node\": \"x\"}",
        (const char *const[]){"field 'mesh.file'", "missing", NULL});
    bad("extra key", "{\"file\": \"lamp-room.obj\", \"scale\": 2}",
        (const char *const[]){"field 'mesh.scale'", "unknown key", NULL});
}

int main(void)
{
    obj_room();
    gltf_box();
    errors();
    return test_finish();
}
