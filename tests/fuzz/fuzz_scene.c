/*
 * libFuzzer harness for the scene parser: any byte string given to
 * xrad_scene_parse must end either in a built scene that keeps every
 * invariant the rest of the library relies on (src/scene/scene.h, DESIGN.md
 * "Numerical notes") or in an input error that keeps the error contract of
 * include/xrad.h. Anything else aborts, which libFuzzer reports as a crash,
 * as do the sanitizers for memory errors, undefined behaviour and leaks.
 *
 * The same entry point is linked with replay.c into a plain program, so every
 * build replays the seed corpus and the saved regression inputs.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_check.h"
#include "scene/scene.h"
#include "xrad.h"

#define FUZZ_NAME "fuzz.json"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    xrad_scene *scene = NULL;
    xrad_error err;
    memset(&err, 0, sizeof(err));
    xrad_status st = xrad_scene_parse((const char *)data, size, FUZZ_NAME, &scene, &err);
    if (st != XRAD_OK) {
        check_error(st, &err, FUZZ_NAME);
        return 0;
    }
    REQUIRE(scene != NULL, 0, 0);
    check_scene(scene);
    xrad_scene_destroy(&scene);
    REQUIRE(scene == NULL, 0, 0);
    return 0;
}
