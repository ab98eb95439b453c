/* Model files through assimp (scene_import.c):
 *  - tests/data/lamp-room.obj, a room of quads written as OBJ faces with
 *    a lamp of Ke = 10 / pi, loads as a scene by itself and placed by a
 *    JSON scene; it comes back as the same seven quads (assimp's
 *    triangles joined), the lamp's exitance pi Ke = 10 W/m^2 (the
 *    radiance reading of emission, scenes/README.md), and the CPU
 *    reference of the placed OBJ gives the same area-weighted radiosity
 *    as the same room written as JSON quads (tests/data/lamp-room.json),
 *    within 0.5% (two element layouts of one room);
 *  - a glTF binary of assimp's test models (BoxTextured.glb) loads, its
 *    base colour texture an albedo map (issue 18.1): the same element
 *    albedos from the .glb, the .gltf with the PNG beside it and the one
 *    with it embedded as a data URI; its clamped base colour a warning;
 *  - a quad's glTF with a 2 x 1 PNG (pixels 50 100 200 and 220 160 40),
 *    factor 0.5: the elements' area mean is 0.5 x the sRGB-decoded mean
 *    of the two pixels (IEC 61966-2-1, computed here), every element
 *    between the two colours; from memory (data URIs) and from a file
 *    with the PNG beside it; a PNG that is missing or not a PNG is a
 *    warning naming the texture, and the factor alone is used;
 *  - bad input names the scene file, the object, the surface and the
 *    model file: a missing file, a node that is not there, a format
 *    xrad does not read;
 *  - the broken glTF files of assimp-testmodels (issue 15): each is
 *    refused with XRAD_ERROR_INPUT naming the file and, where the fault is
 *    in one, the node, mesh or buffer, or, where assimp repairs it, loads
 *    with warnings saying what was dropped;
 *  - the import harness's seeds (tests/fuzz/corpus/import/, loaded from
 *    memory as the harness does): NaN and Inf vertices, vertices beyond
 *    the coordinate limit, indices out of range, zero-area triangles,
 *    points and lines, PLY counts that cannot fit, a missing buffer.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "xrad.h"

static int has_warning(const xrad_scene *sc, const char *const *want);

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
        textures |= strstr(xrad_scene_warning(sc, k), "texture") != NULL;
        clamped |= strstr(xrad_scene_warning(sc, k), "clamped") != NULL;
    }
    CHECK(!textures && clamped, "warnings: texture %d (want none), clamped base colour %d",
          textures, clamped);
    CHECK(xrad_scene_warning(sc, xrad_scene_warning_count(sc)) == NULL, "NULL past the count");
    CHECK(sc->element_albedo != NULL, "BoxTextured.glb: no element albedos from its texture");
    /* The same box with the PNG beside it and embedded as a data URI. */
    static const char *const others[] = {
        "/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf",
        "/usr/share/assimp/models/glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"};
    double lo = 1, hi = 0;
    for (uint32_t e = 0; sc->element_albedo && e < sc->element_count; e++) {
        lo = fmin(lo, sc->element_albedo[e].x);
        hi = fmax(hi, sc->element_albedo[e].x);
    }
    fprintf(stderr, "BoxTextured.glb: element albedos (red) %.3f to %.3f\n", lo, hi);
    CHECK(sc->element_albedo && lo >= 0 && hi < 1 && hi - lo > 0.2,
          "BoxTextured.glb: element albedos %.3f to %.3f, want the logo's contrast", lo, hi);
    for (int k = 0; k < 2 && sc->element_albedo; k++) {
        xrad_scene *o = NULL;
        st = xrad_scene_load(others[k], &o, &err);
        CHECK(st == XRAD_OK && o->element_albedo && o->element_count == sc->element_count,
              "%s: %s", others[k], st ? err.message : "no element albedos, or another count");
        double worst = 0;
        for (uint32_t e = 0; !st && o->element_albedo && e < o->element_count &&
                             o->element_count == sc->element_count;
             e++)
            worst = fmax(worst, v3_len(v3_sub(o->element_albedo[e], sc->element_albedo[e])));
        CHECK(worst == 0, "%s: element albedos up to %.3g off the .glb's", others[k], worst);
        xrad_scene_destroy(&o);
    }
    xrad_scene_destroy(&sc);
}

#define PAINT_MATERIAL                                                                             \
    "{\"name\": \"paint\", \"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.5, 0.5, 1], " \
    "\"baseColorTexture\": {\"index\": 0}, \"metallicFactor\": 0}}"

/* A unit quad of two triangles in z = 0, TEXCOORD_0 over the whole image,
 * its material `mat` (glTF JSON; texture 0 is the image); `image` the
 * glTF image's uri. */
static void quad_gltf_with(char *out, size_t n, const char *mat, const char *image)
{
    snprintf(
        out, n,
        "{\"asset\": {\"version\": \"2.0\"}, \"scene\": 0, \"scenes\": [{\"nodes\": [0]}],\n"
        " \"nodes\": [{\"mesh\": 0, \"name\": \"quad\"}],\n"
        " \"meshes\": [{\"primitives\": [{\"attributes\": {\"POSITION\": 0, \"TEXCOORD_0\": 1},"
        " \"indices\": 2, \"material\": 0}]}],\n"
        " \"materials\": [%s],\n"
        " \"textures\": [{\"source\": 0}], \"images\": [{\"uri\": \"%s\"}],\n"
        " \"buffers\": [{\"byteLength\": 94, \"uri\": \"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAACAPwAAgD8AAAAAAAAAAAAAgD8AAAAAAAAAAAAAgD8AAIA/AACAPwAA"
        "gD8AAAAAAAAAAAAAAAAAAAEAAgAAAAIAAwAAAA==\"}],\n"
        " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": 48},"
        " {\"buffer\": 0, \"byteOffset\": 48, \"byteLength\": 32},"
        " {\"buffer\": 0, \"byteOffset\": 80, \"byteLength\": 12}],\n"
        " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": 4, \"type\":"
        " \"VEC3\", \"min\": [0, 0, 0], \"max\": [1, 1, 0]},"
        " {\"bufferView\": 1, \"componentType\": 5126, \"count\": 4, \"type\": \"VEC2\"},"
        " {\"bufferView\": 2, \"componentType\": 5123, \"count\": 6, \"type\": \"SCALAR\"}]}\n",
        mat, image);
}

/* The quad with base colour factor 0.5 x the image. */
static void quad_gltf(char *out, size_t n, const char *image)
{
    quad_gltf_with(out, n, PAINT_MATERIAL, image);
}

/* The 2 x 1 PNG: pixels (50, 100, 200) and (220, 160, 40). */
static const char two_pixels_png[] = "iVBORw0KGgoAAAANSUhEUgAAAAIAAAABCAIAAAB7QOjdAAAAD0lEQVR4nGMwS"
                                     "jlxZ4EGAApDAwNVlaTGAAAAAElFTkSuQmCC";

static double srgb_decode(double v)
{
    double c = v / 255;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The quad's element albedos against the two pixels. */
static void check_two_pixels(const char *label, const xrad_scene *sc)
{
    static const double px[2][3] = {{50, 100, 200}, {220, 160, 40}};
    CHECK(sc->element_albedo != NULL, "%s: no element albedos", label);
    if (!sc->element_albedo)
        return;
    double sum[3] = {0, 0, 0}, area = 0, outside = 0;
    for (uint32_t e = 0; e < sc->element_count; e++) {
        const double a[3] = {sc->element_albedo[e].x, sc->element_albedo[e].y,
                             sc->element_albedo[e].z};
        for (int c = 0; c < 3; c++) {
            sum[c] += sc->elements[e].area * a[c];
            double x = 0.5 * srgb_decode(px[0][c]), y = 0.5 * srgb_decode(px[1][c]);
            outside = fmax(outside, fmax(fmin(x, y) - a[c], a[c] - fmax(x, y)));
        }
        area += sc->elements[e].area;
    }
    double worst = 0;
    for (int c = 0; c < 3; c++)
        worst = fmax(worst, fabs(sum[c] / area -
                                 0.25 * (srgb_decode(px[0][c]) + srgb_decode(px[1][c]))));
    fprintf(stderr, "%s: area mean %.2e off 0.5 x the pixels' mean, %u elements\n", label, worst,
            sc->element_count);
    CHECK(worst <= 1e-5, "%s: area mean albedo %.3g off 0.5 x the two pixels' mean", label,
          worst);
    CHECK(outside <= 1e-6, "%s: an element %.3g outside the two pixels' colours", label,
          outside);
}

static void gltf_maps(void)
{
    static char gltf[4096], uri[256];
    snprintf(uri, sizeof(uri), "data:image/png;base64,%s", two_pixels_png);
    quad_gltf(gltf, sizeof(gltf), uri);
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = scene_load_model_memory("quad.gltf", gltf, strlen(gltf), &sc, &err);
    CHECK(st == XRAD_OK, "quad.gltf, PNG as a data URI: %s", err.message);
    if (!st)
        check_two_pixels("quad.gltf, PNG as a data URI", sc);
    xrad_scene_destroy(&sc);

    /* The PNG beside the .gltf; then missing, then not a PNG. */
    char dir[] = "/tmp/xrad-maps-XXXXXX";
    CHECK(mkdtemp(dir) != NULL, "mkdtemp");
    char path[512], png[512];
    snprintf(path, sizeof(path), "%s/quad.gltf", dir);
    snprintf(png, sizeof(png), "%s/two.png", dir);
    quad_gltf(gltf, sizeof(gltf), "two.png");
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(gltf, f);
        fclose(f);
    }
    static const char b64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    unsigned char bytes[128];
    size_t nb = 0;
    uint32_t acc = 0;
    int bits = 0;
    for (const char *c = two_pixels_png; *c && *c != '='; c++) {
        acc = acc << 6 | (uint32_t)(strchr(b64, *c) - b64);
        if ((bits += 6) >= 8) {
            bits -= 8;
            bytes[nb++] = (unsigned char)(acc >> bits);
        }
    }
    for (int pass = 0; pass < 4; pass++) {
        remove(png);
        if (pass != 1 && (f = fopen(png, "wb"))) {
            /* pass 2: the PNG cut short, not an image; pass 3: its header
             * says 10000 x 10000 (IHDR width and height, big-endian, at
             * bytes 16-23), more texels than a map may have, refused
             * before anything is allocated for them. */
            unsigned char big[128];
            memcpy(big, bytes, nb);
            for (int k = 0; k < 8; k++)
                big[16 + k] = (unsigned char[]){0, 0, 0x27, 0x10}[k % 4];
            fwrite(pass == 3 ? big : bytes, 1, pass == 2 ? 20 : nb, f);
            fclose(f);
        }
        st = xrad_scene_load(path, &sc, &err);
        CHECK(st == XRAD_OK, "quad.gltf, PNG beside it (pass %d): %s", pass, err.message);
        if (!st && pass == 0)
            check_two_pixels("quad.gltf, PNG beside it", sc);
        if (!st && pass > 0) {
            const char *const want[] = {"two.png", "not read", pass == 3 ? "in all" : NULL,
                                        NULL};
            CHECK(has_warning(sc, want) && !sc->element_albedo,
                  "quad.gltf, PNG %s: no warning naming it, or element albedos",
                  pass == 1 ? "missing" : pass == 2 ? "cut short" : "of 10000 x 10000");
        }
        xrad_scene_destroy(&sc);
    }
    /* A scene file's material with the PNG as its albedo_map on a quad
     * (the quad's corners take (0, 0) (1, 0) (1, 1) (0, 1)), and the same
     * map on the glTF's quad in place of its own material. */
    if ((f = fopen(png, "wb"))) {
        fwrite(bytes, 1, nb, f);
        fclose(f);
    }
    char json[512];
    snprintf(json, sizeof(json), "%s/scene.json", dir);
    static const char scene_text[] =
        "{\"materials\": [{\"name\": \"paint\", \"albedo\": [0.5, 0.5, 0.5], \"albedo_map\": "
        "\"two.png\"}],\n \"objects\": [{\"name\": \"o\", \"surfaces\": [{\"name\": \"q\", "
        "\"material\": \"paint\", \"density\": 20, \"quad\": {\"origin\": [0, 0, 0], \"u\": "
        "[1, 0, 0], \"v\": [0, 1, 0]}}%s]}]}\n";
    for (int pass = 0; pass < 3; pass++) {
        if ((f = fopen(json, "wb"))) {
            char text[1024];
            snprintf(text, sizeof(text), scene_text,
                     pass == 1 ? ", {\"name\": \"m\", \"material\": \"paint\", \"mesh\": "
                                 "{\"file\": \"quad.gltf\"}}"
                               : "");
            if (pass == 2) /* the map missing */
                remove(png);
            fputs(text, f);
            fclose(f);
        }
        st = xrad_scene_load(json, &sc, &err);
        if (pass < 2) {
            CHECK(st == XRAD_OK, "scene.json with an albedo_map (pass %d): %s", pass,
                  err.message);
            if (!st)
                check_two_pixels(pass ? "scene.json: quad and glTF quad, its albedo_map"
                                      : "scene.json: a quad's albedo_map",
                                 sc);
        } else {
            CHECK(st == XRAD_ERROR_INPUT && strstr(err.message, "scene.json") &&
                      strstr(err.message, "material 'paint'") &&
                      strstr(err.message, "albedo_map") && strstr(err.message, "two.png"),
                  "a missing albedo_map: %d '%s'", st, err.message);
        }
        xrad_scene_destroy(&sc);
    }
    remove(json);
    remove(png);
    remove(path);
    rmdir(dir);
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
    bad("extra key", "{\"file\": \"lamp-room.obj\", \"frobnicate\": 2}",
        (const char *const[]){"field 'mesh.frobnicate'", "unknown key", NULL});
}

#define GLTF2 "/usr/share/assimp/models/glTF2/"

/* Whether a warning of sc holds every string of want. */
static int has_warning(const xrad_scene *sc, const char *const *want)
{
    for (uint32_t k = 0; k < xrad_scene_warning_count(sc); k++) {
        int all = 1;
        for (int i = 0; want[i] && all; i++)
            all = strstr(xrad_scene_warning(sc, k), want[i]) != NULL;
        if (all)
            return 1;
    }
    return 0;
}

/* xrad_scene_load(path) must return `status`; want: strings of the
 * message (an error) or of one warning (a load), the path always. */
static void broken(const char *rel, xrad_status status, const char *const *want)
{
    char path[512];
    snprintf(path, sizeof(path), GLTF2 "%s", rel);
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_load(path, &sc, &err);
    CHECK(st == status, "%s: status %d, want %d: %s", rel, st, status, st ? err.message : "");
    if (st == XRAD_OK) {
        const char *const with_path[] = {path, NULL};
        CHECK(has_warning(sc, with_path), "%s: no warning names the file", rel);
        CHECK(has_warning(sc, want), "%s: no warning with '%s'...", rel, want[0]);
        for (uint32_t k = 0; k < xrad_scene_warning_count(sc); k++)
            fprintf(stderr, "  %s: warning: %s\n", rel, xrad_scene_warning(sc, k));
    } else {
        CHECK(!sc, "%s: a scene with an error", rel);
        CHECK(strstr(err.message, path), "%s: the path is not in: %s", rel, err.message);
        for (int k = 0; want[k]; k++)
            CHECK(strstr(err.message, want[k]), "%s: '%s' not in: %s", rel, want[k],
                  err.message);
        fprintf(stderr, "  %s: %s\n", rel, err.message);
    }
    xrad_scene_destroy(&sc);
}

/* The broken files of assimp-testmodels (Debian 12: assimp 5.2.5; the
 * quoted words of "cannot import: ..." are assimp's). */
static void broken_files(void)
{
    /* Six faces from a 0..23 range, one index 255: assimp drops that
     * triangle and says so; the rest is a sound box missing half a face,
     * so it loads, with assimp's warning passed on. */
    broken("IndexOutOfRange/IndexOutOfRange.gltf", XRAD_OK,
           (const char *const[]){"assimp: ", "out-of-range indices", "dropped", NULL});
    /* Every index out of range: assimp refuses the mesh it emptied. */
    broken("IndexOutOfRange/AllIndicesOutOfRange.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"cannot import", "Mesh \"Mesh\" has no faces", NULL});
    /* Infinite positions pass assimp; xrad refuses them, naming the node
     * and the mesh (the glTF primitive) and the vertex. */
    broken("BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", XRAD_ERROR_INPUT,
           (const char *const[]){"node 'nodes_1'", "mesh 'Mesh'", "vertex 0", "not finite",
                                 NULL});
    /* The .bin the buffer names is not there. */
    broken("MissingBin/BoxTextured.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"cannot import", "BoxTextured0.bin", NULL});
    broken("SchemaFailures/sceneWrongType.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"cannot import", "\"scene\"", NULL});
    broken("wrongTypes/badArray.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"\"primitives\"", "meshes[0]", NULL});
    broken("wrongTypes/badString.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"\"name\"", "scenes[0]", NULL});
    broken("RecursiveNodes/RecursiveNodes.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"\"nodes\"", "recursive", NULL});
    broken("TestNoRootNode/NoScene.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"No scene", NULL});
    /* A valid file with nothing in it: nothing to light. */
    broken("TestNoRootNode/SceneWithoutNodes.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"no triangles", NULL});
    /* Vertex counts not a multiple of 3 (triangles) or 2 (lines): assimp
     * drops the rest and says so; the line meshes are ignored, the first
     * named. */
    broken("IncorrectVertexArrays/Cube.gltf", XRAD_OK,
           (const char *const[]){"TRIANGLES mode", "dropped", NULL});
    broken("IncorrectVertexArrays/Cube.gltf", XRAD_OK,
           (const char *const[]){"4 mesh(es) of points or lines", "node 'Lines'", NULL});

    /* Placed by a scene file: its file, object and surface, then the model
     * file's node and mesh. */
    bad("placed infinities",
        "{\"file\": \"" GLTF2 "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb\"}",
        (const char *const[]){"bad.json", "surface 'model'", "BoxWithInfinites.glb",
                              "node 'nodes_1'", "mesh 'Mesh'", "not finite", NULL});
}

/* `data` loaded from memory as model file `name`; want as in broken(). */
static void in_memory(const char *label, const char *name, const char *data, size_t n,
                      xrad_status status, const char *const *want)
{
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = scene_load_model_memory(name, data, n, &sc, &err);
    CHECK(st == status, "%s: status %d, want %d: %s", label, st, status, st ? err.message : "");
    if (st == XRAD_OK) {
        CHECK(want[0] == NULL || has_warning(sc, want), "%s: no warning with '%s'...", label,
              want[0]);
    } else {
        CHECK(!sc, "%s: a scene with an error", label);
        CHECK(strstr(err.message, name), "%s: '%s' not in: %s", label, name, err.message);
        for (int k = 0; want[k]; k++)
            CHECK(strstr(err.message, want[k]), "%s: '%s' not in: %s", label, want[k],
                  err.message);
    }
    xrad_scene_destroy(&sc);
}

/* A fuzz input (first byte: the format), loaded from memory as
 * fuzz_import.c does; want as in broken(). */
static void fuzz_input(const char *dir, const char *file, xrad_status status,
                       const char *const *want)
{
    char path[1024];
    snprintf(path, sizeof(path), "tests/fuzz/%s/import/%s", dir, file);
    char full[1024];
    test_source_path(path, full, sizeof(full));
    FILE *f = fopen(full, "rb");
    static char buf[1 << 16];
    size_t n = f ? fread(buf, 1, sizeof(buf), f) : 0;
    if (f)
        fclose(f);
    CHECK(n > 1, "%s: cannot read", full);
    if (n <= 1)
        return;
    static const char *const names[] = {"seed.obj", "seed.ply", "seed.glb", "seed.gltf"};
    const char *name = buf[0] == 'o'   ? names[0]
                       : buf[0] == 'p' ? names[1]
                       : buf[0] == 'b' ? names[2]
                       : buf[0] == 'g' ? names[3]
                                       : names[(unsigned char)buf[0] % 4];
    in_memory(file, name, buf + 1, n - 1, status, want);
}

static void seed(const char *file, xrad_status status, const char *const *want)
{
    fuzz_input("corpus", file, status, want);
}

/* assimp offers a file its glTF importers decline to all of its other
 * importers: what is not glTF 2.0 never reaches assimp as a .glb/.gltf. */
static void wrong_content(void)
{
    /* The fuzzer's hang: a PLY with a broken header, named .glb. */
    fuzz_input("regressions", "glb-holding-ply-hangs-assimp", XRAD_ERROR_INPUT,
               (const char *const[]){"not a binary glTF", NULL});
    /* An STL assimp reads, named .glb and .gltf: refused, not loaded. */
    FILE *f = fopen("/usr/share/assimp/models/STL/triangle_with_two_solids.stl", "rb");
    static char stl[1 << 16];
    size_t n = f ? fread(stl, 1, sizeof(stl), f) : 0;
    if (f)
        fclose(f);
    CHECK(n > 0, "assimp-testmodels' STL/triangle_with_two_solids.stl: cannot read");
    in_memory("stl as glb", "stl.glb", stl, n, XRAD_ERROR_INPUT,
              (const char *const[]){"does not begin with \"glTF\"", NULL});
    in_memory("stl as gltf", "stl.gltf", stl, n, XRAD_ERROR_INPUT,
              (const char *const[]){"not a JSON object", NULL});
    /* GLB headers: version 1, a first chunk not JSON, a chunk past the end. */
    static const char v1[] = "glTF\1\0\0\0\40\0\0\0\4\0\0\0JSON{}  ";
    in_memory("glb version 1", "v1.glb", v1, sizeof(v1) - 1, XRAD_ERROR_INPUT,
              (const char *const[]){"version 1", "glTF 2.0", NULL});
    static const char bin[] = "glTF\2\0\0\0\40\0\0\0\4\0\0\0BIN\0{}  ";
    in_memory("glb bin first", "bin.glb", bin, sizeof(bin) - 1, XRAD_ERROR_INPUT,
              (const char *const[]){"not a JSON chunk", NULL});
    static const char past[] = "glTF\2\0\0\0\40\0\0\0\377\0\0\0JSON{}  ";
    in_memory("glb chunk past the end", "past.glb", past, sizeof(past) - 1, XRAD_ERROR_INPUT,
              (const char *const[]){"fits in the file", NULL});
    static const char noasset[] = "{\"scenes\": []}";
    in_memory("gltf without asset", "a.gltf", noasset, sizeof(noasset) - 1, XRAD_ERROR_INPUT,
              (const char *const[]){"\"asset\"", NULL});
    /* assimp's PLY magic ignores case: the header check must too (this
     * header has no end_header, which hangs assimp's reader). */
    static const char upper[] = "PLY\nformat ascii 1.0\nelement vertex 1\nproperty float x\n";
    in_memory("PLY in capitals", "upper.ply", upper, sizeof(upper) - 1, XRAD_ERROR_INPUT,
              (const char *const[]){"no end_header", NULL});
    /* The fixed-seed fuzzer's hang: end_header, a vertical tab and the
     * first vertex on one line; blanks after end_header are fine. */
    fuzz_input("regressions", "ply-end-header-vtab-hangs-assimp", XRAD_ERROR_INPUT,
               (const char *const[]){"line 9", "end_header must end its line", NULL});
    static const char blanks[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                 "property float y\nproperty float z\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header \t\r\n"
                                 "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    in_memory("PLY end_header and blanks", "blanks.ply", blanks, sizeof(blanks) - 1, XRAD_OK,
              (const char *const[]){NULL});
    /* glTF 1.0 (assimp has a reader for it): refused, saying why. */
    broken("../glTF/BoxTextured-glTF/BoxTextured.gltf", XRAD_ERROR_INPUT,
           (const char *const[]){"asset.version is \"1.0\"", "glTF 2.0", NULL});
}

/* A glTF camera wider than high: its yfov, and an image of its aspect. */
static void camera_aspect(void)
{
    static const char gltf[] =
        "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0,1]}],"
        "\"nodes\":[{\"mesh\":0},{\"camera\":0,\"translation\":[0,0,5]}],"
        "\"cameras\":[{\"type\":\"perspective\",\"perspective\":{\"yfov\":0.8,"
        "\"aspectRatio\":2.0,\"znear\":0.1}}],"
        "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
        "\"buffers\":[{\"byteLength\":42,\"uri\":\"data:application/octet-stream;base64,"
        "AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA\"}],"
        "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},"
        "{\"buffer\":0,\"byteOffset\":36,\"byteLength\":6}],"
        "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,"
        "\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[1,1,0]},{\"bufferView\":1,"
        "\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}]}";
    xrad_scene *sc = NULL;
    xrad_error err = {0};
    xrad_status st = scene_load_model_memory("camera.gltf", gltf, sizeof(gltf) - 1, &sc, &err);
    CHECK(st == XRAD_OK, "camera.gltf: %s", err.message);
    if (st)
        return;
    CHECK_REL(sc->cam.fov_y, 0.8, 1e-6);
    CHECK(sc->cam.width == 512 && sc->cam.height == 256, "image %u x %u, want 512 x 256",
          sc->cam.width, sc->cam.height);
    CHECK_ABS(sc->cam.position.z, 5, 1e-6);
    CHECK(sc->cam.look_at.z < sc->cam.position.z, "looks along +z");
    xrad_scene_destroy(&sc);
}

static void seeds(void)
{
    seed("obj-quad-lamp-line-point.obj", XRAD_OK,
         (const char *const[]){"2 mesh(es) of points or lines: ignored", "node 'wire'", NULL});
    seed("obj-zero-area.obj", XRAD_OK,
         (const char *const[]){"1 zero-area triangle(s) left out", "mesh 'defaultobject'",
                               NULL});
    seed("obj-all-zero-area.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"all 1 triangle(s) have zero area", NULL});
    seed("obj-inf.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"mesh 'defaultobject'", "vertex 2 is not finite", NULL});
    /* 1e39 overflows a float: infinite too. */
    seed("obj-overflow.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"vertex 2 is not finite", NULL});
    seed("obj-far.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"vertex 2 lies at", "beyond 1e+09 m", NULL});
    seed("obj-index-out-of-range.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"index out of range", NULL});
    seed("obj-lines-only.obj", XRAD_ERROR_INPUT,
         (const char *const[]){"no triangles (points or lines only)", NULL});
    /* In memory, the .mtl is not found: default material, said. */
    seed("obj-mtl-missing.obj", XRAD_OK, (const char *const[]){"room.mtl", NULL});
    seed("ply-ascii-quad.ply", XRAD_OK, (const char *const[]){NULL});
    seed("ply-binary-two-triangles.ply", XRAD_OK, (const char *const[]){NULL});
    seed("ply-ascii-count-too-large.ply", XRAD_ERROR_INPUT,
         (const char *const[]){"element 'vertex': 300000", "do not fit", NULL});
    seed("ply-binary-truncated.ply", XRAD_ERROR_INPUT,
         (const char *const[]){"PLY header", "need at least 50 bytes", NULL});
    seed("gltf-triangle.gltf", XRAD_OK, (const char *const[]){NULL});
    seed("gltf-camera-mirror.gltf", XRAD_OK, (const char *const[]){NULL});
    /* Two materials of one name: both kept, the second renamed. */
    seed("gltf-duplicate-material-names.gltf", XRAD_OK, (const char *const[]){NULL});
    seed("glb-triangle.glb", XRAD_OK, (const char *const[]){NULL});
    seed("glb-infinite.glb", XRAD_ERROR_INPUT,
         (const char *const[]){"node 'tri'", "mesh 'Tri'", "vertex 1 is not finite", NULL});
    seed("gltf-matrix-overflow.gltf", XRAD_ERROR_INPUT,
         (const char *const[]){"node 'huge'", "transform", "not finite", NULL});
    /* From memory no other file is opened. */
    seed("gltf-missing-bin.gltf", XRAD_ERROR_INPUT, (const char *const[]){"missing.bin", NULL});
    seed("gltf-lines.gltf", XRAD_ERROR_INPUT, (const char *const[]){"no triangles", NULL});
    seed("gltf-count-too-large.gltf", XRAD_ERROR_INPUT,
         (const char *const[]){"out of range", NULL});
}

/* The 1 x 1 PNG: pixel (230, 128, 180), a normal tilted 63 degrees. */
static const char tilted_png[] = "iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGN41rAFAA"
                                 "RqAhsI539vAAAAAElFTkSuQmCC";

/* glTF normalTexture.scale: the quad with the tilted pixel as its normal
 * texture at scales 1, 0.5 and 0 (and none given: 1). Every element's
 * normal makes the angle with the quad's normal that the glTF spec's
 * normalize((2 rgb - 1) x (scale, scale, 1)) makes with z. */
static void gltf_normal_scale(void)
{
    static const char *const scales[] = {"", ", \"scale\": 1", ", \"scale\": 0.5",
                                         ", \"scale\": 0"};
    static const double value[] = {1, 1, 0.5, 0};
    for (int k = 0; k < 4; k++) {
        char mat[256], uri[256];
        static char gltf[4096];
        snprintf(mat, sizeof(mat),
                 "{\"name\": \"bumpy\", \"normalTexture\": {\"index\": 0%s}, "
                 "\"pbrMetallicRoughness\": {\"baseColorFactor\": [0.5, 0.5, 0.5, 1], "
                 "\"metallicFactor\": 0}}",
                 scales[k]);
        snprintf(uri, sizeof(uri), "data:image/png;base64,%s", tilted_png);
        quad_gltf_with(gltf, sizeof(gltf), mat, uri);
        xrad_scene *sc = NULL;
        xrad_error err = {0};
        xrad_status st = scene_load_model_memory("bumpy.gltf", gltf, strlen(gltf), &sc, &err);
        CHECK(st == XRAD_OK && sc->element_normal, "bumpy.gltf, scale %g: %s", value[k],
              st ? err.message : "no element normals");
        double x = (2 * 230 / 255.0 - 1) * value[k], y = (2 * 128 / 255.0 - 1) * value[k],
               z = 2 * 180 / 255.0 - 1;
        double want = z / sqrt(x * x + y * y + z * z), worst = 0;
        for (uint32_t e = 0; !st && sc->element_normal && e < sc->element_count; e++) {
            vec3 n = sc->surfaces[sc->elements[e].surface].normal;
            worst = fmax(worst, fabs(v3_dot(v3_norm(sc->element_normal[e]), n) - want));
        }
        fprintf(stderr, "bumpy.gltf, scale %g: cosine of the tilt %.4f, %.2e off\n", value[k],
                want, worst);
        CHECK(worst <= 1e-5, "bumpy.gltf, scale %g: an element's tilt cosine %.3g off %.4f",
              value[k], worst, want);
        xrad_scene_destroy(&sc);
    }
}

int main(void)
{
    obj_room();
    gltf_box();
    gltf_maps();
    gltf_normal_scale();
    errors();
    broken_files();
    seeds();
    wrong_content();
    camera_aspect();
    return test_finish();
}
