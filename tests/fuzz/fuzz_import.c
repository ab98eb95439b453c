/*
 * libFuzzer harness for model files through assimp (src/scene/scene_import.c):
 * the first byte of the input picks the format, the rest is the file, loaded
 * from memory as xrad_scene_load loads a model file (scene_load_model_memory:
 * the same import, the same builder). It must end either in a scene that
 * keeps every invariant fuzz_check.h checks, its warnings naming the file, or
 * in an error that keeps the contract of include/xrad.h and names the file.
 *
 * First byte: 'o' OBJ, 'p' PLY, 'b' glTF binary, 'g' glTF JSON (readable
 * seeds); any other byte picks by its value modulo 4, so that every mutation
 * of it still tries some format. Files the model refers to (a .bin, a .mtl)
 * are not found: memory input never reaches the file system.
 *
 * Crashes inside assimp itself cannot be fixed here: README.md says what to
 * do with one.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_check.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "xrad.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *format_name(uint8_t first)
{
    static const char *const names[] = {"fuzz.obj", "fuzz.ply", "fuzz.glb", "fuzz.gltf"};
    switch (first) {
    case 'o':
        return names[0];
    case 'p':
        return names[1];
    case 'b':
        return names[2];
    case 'g':
        return names[3];
    default:
        return names[first % 4];
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    const char *name = format_name(data[0]);
    xrad_scene *scene = NULL;
    xrad_error err;
    memset(&err, 0, sizeof(err));
    xrad_status st = scene_load_model_memory(name, data + 1, size - 1, &scene, &err);
    if (st != XRAD_OK) {
        REQUIRE(scene == NULL, st, 0);
        check_error(st, &err, name);
        return 0;
    }
    REQUIRE(scene != NULL, 0, 0);
    REQUIRE(scene->object_count == 1 && scene->surface_count > 0, scene->object_count,
            scene->surface_count);
    check_scene(scene);
    /* Warnings are about the file and say so. */
    uint32_t warnings = xrad_scene_warning_count(scene);
    for (uint32_t k = 0; k < warnings; k++) {
        const char *w = xrad_scene_warning(scene, k);
        REQUIRE(w && w[0] && strstr(w, name), k, warnings);
        for (const char *p = w; *p; p++)
            REQUIRE((unsigned char)*p >= 0x20, k, (unsigned char)*p);
    }
    REQUIRE(xrad_scene_warning(scene, warnings) == NULL, warnings, 0);
    xrad_scene_destroy(&scene);
    REQUIRE(scene == NULL, 0, 0);
    return 0;
}
