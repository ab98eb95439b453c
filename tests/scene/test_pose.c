/* Object poses against closed forms (scenes/README.md "Poses"): rest pose
 * = rotate then translate; the animation rotates about an axis through a
 * pivot in object space before the rest pose, and adds a piecewise linear
 * keyframe translation in world space. */
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

#define SCENE_HEAD                                                                       \
    "{\"unit\": \"mm\", \"materials\": [{\"name\": \"m\", \"albedo\": [0.5, 0.5, 0.5]}], " \
    "\"objects\": ["
#define QUAD                                                                               \
    "\"surfaces\": [{\"name\": \"q\", \"material\": \"m\", \"quad\": {\"origin\": [0, 0, 0], " \
    "\"u\": [1000, 0, 0], \"v\": [0, 1000, 0]}}]"

static xrad_scene *parse(const char *json)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), "pose-test.json", &scene, &err);
    CHECK(st == XRAD_OK, "%s", err.message);
    return scene;
}

#define CHECK_V3(got, x_, y_, z_)                                                         \
    do {                                                                                  \
        vec3 g_ = (got);                                                                  \
        CHECK(fabs(g_.x - (x_)) < 1e-12 && fabs(g_.y - (y_)) < 1e-12 && fabs(g_.z - (z_)) < 1e-12, \
              "%s = (%.15g %.15g %.15g), want (%.15g %.15g %.15g)", #got, g_.x, g_.y, g_.z,  \
              (double)(x_), (double)(y_), (double)(z_));                                   \
    } while (0)

int main(void)
{
    /* 0: spins 90 deg/s about y through the origin.
     * 1: spins 90 deg/s about y through the pivot (1000, 0, 0) mm.
     * 2: rest pose only: rotate 90 deg about z, then translate (10, 0, 0) m.
     * 3: rest pose rotate 90 deg about z + translate, spinning 90 deg/s about y.
     * 4: keyframes (0 s, 0) -> (2 s, 100 mm along x) -> (3 s, 100 mm along x and y), looping.
     * 5: the same keys without looping.
     * 6: static, with a rest pose: ignores time.
     * 7: keys starting at 1 s, looping with period 2 s. */
    xrad_scene *sc = parse(
        SCENE_HEAD
        "{\"name\": \"spin\", \"dynamic\": true, \"animation\": {\"rotate\": "
        "{\"axis\": [0, 2, 0], \"degrees_per_second\": 90}}, " QUAD "},"
        "{\"name\": \"pivot\", \"dynamic\": true, \"animation\": {\"rotate\": "
        "{\"axis\": [0, 1, 0], \"pivot\": [1000, 0, 0], \"degrees_per_second\": 90}}, " QUAD "},"
        "{\"name\": \"rest\", \"dynamic\": true, \"translate\": [10000, 0, 0], "
        "\"rotate\": {\"axis\": [0, 0, 1], \"degrees\": 90}, " QUAD "},"
        "{\"name\": \"both\", \"dynamic\": true, \"translate\": [10000, 0, 0], "
        "\"rotate\": {\"axis\": [0, 0, 1], \"degrees\": 90}, \"animation\": {\"rotate\": "
        "{\"axis\": [0, 1, 0], \"degrees_per_second\": 90}}, " QUAD "},"
        "{\"name\": \"keys\", \"dynamic\": true, \"animation\": {\"keyframes\": ["
        "{\"time\": 0, \"translate\": [0, 0, 0]}, {\"time\": 2, \"translate\": [100, 0, 0]}, "
        "{\"time\": 3, \"translate\": [100, 100, 0]}]}, " QUAD "},"
        "{\"name\": \"once\", \"dynamic\": true, \"animation\": {\"loop\": false, \"keyframes\": ["
        "{\"time\": 0, \"translate\": [0, 0, 0]}, {\"time\": 2, \"translate\": [100, 0, 0]}, "
        "{\"time\": 3, \"translate\": [100, 100, 0]}]}, " QUAD "},"
        "{\"name\": \"static\", \"translate\": [0, 5000, 0], " QUAD "},"
        "{\"name\": \"late\", \"dynamic\": true, \"animation\": {\"keyframes\": ["
        "{\"time\": 1, \"translate\": [0, 0, 0]}, {\"time\": 2, \"translate\": [0, 0, 100]}]}, "
        QUAD "}"
        "]}");
    if (!sc)
        return test_finish();

    /* Rotating 90 degrees about +y maps +x to -z. */
    xform p = scene_object_pose(sc, 0, 1.0);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), 0, 0, -1);
    p = scene_object_pose(sc, 0, 2.0);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), -1, 0, 0);
    p = scene_object_pose(sc, 0, 0.0);
    CHECK_V3(xf_point(&p, v3(1, 2, 3)), 1, 2, 3);

    /* About the pivot (1, 0, 0) m: (2, 0, 0) -> pivot + (0, 0, -1); the
     * pivot itself stays. */
    p = scene_object_pose(sc, 1, 1.0);
    CHECK_V3(xf_point(&p, v3(2, 0, 0)), 1, 0, -1);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), 1, 0, 0);

    /* Rest pose: (1, 0, 0) -> rotate about z -> (0, 1, 0) -> + (10, 0, 0). */
    p = scene_object_pose(sc, 2, 7.0);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), 10, 1, 0);

    /* Spin first (object space), then the rest pose: at 1 s (1, 0, 0) ->
     * (0, 0, -1) -> unchanged by z rotation -> (10, 0, -1); (0, 1, 0) is on
     * the spin axis -> (-1, 0, 0) -> (9, 0, 0). */
    p = scene_object_pose(sc, 3, 1.0);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), 10, 0, -1);
    CHECK_V3(xf_point(&p, v3(0, 1, 0)), 9, 0, 0);

    /* Keyframes: linear between keys, looping with period 3 s. */
    p = scene_object_pose(sc, 4, 1.0);
    CHECK_V3(p.t, 0.05, 0, 0);
    p = scene_object_pose(sc, 4, 2.5);
    CHECK_V3(p.t, 0.1, 0.05, 0);
    p = scene_object_pose(sc, 4, 4.0);
    CHECK_V3(p.t, 0.05, 0, 0);
    p = scene_object_pose(sc, 4, 3.0 * 10 + 0.5);
    CHECK_V3(p.t, 0.025, 0, 0);
    p = scene_object_pose(sc, 4, -2.0);
    CHECK_V3(p.t, 0.05, 0, 0);
    /* Without looping the ends hold. */
    p = scene_object_pose(sc, 5, 4.0);
    CHECK_V3(p.t, 0.1, 0.1, 0);
    p = scene_object_pose(sc, 5, -1.0);
    CHECK_V3(p.t, 0, 0, 0);
    p = scene_object_pose(sc, 5, 1.5);
    CHECK_V3(p.t, 0.075, 0, 0);

    /* A static object keeps its rest pose at any time. */
    p = scene_object_pose(sc, 6, 123.0);
    CHECK_V3(xf_point(&p, v3(1, 0, 0)), 1, 5, 0);

    /* Looping keys that start late: within a period, before the first key
     * the translation runs from the last key's value to the first's. */
    p = scene_object_pose(sc, 7, 0.5);
    CHECK_V3(p.t, 0, 0, 0.05);
    p = scene_object_pose(sc, 7, 1.5);
    CHECK_V3(p.t, 0, 0, 0.05);
    p = scene_object_pose(sc, 7, 2.0 + 0.25);
    CHECK_V3(p.t, 0, 0, 0.075);

    /* World corners and normal follow the pose; surface_point is bilinear
     * through the corners. */
    vec3 c[4], n;
    scene_surface_world(sc, 0, 1.0, c, &n);
    CHECK_V3(c[1], 0, 0, -1);
    CHECK_V3(c[2], 0, 1, -1);
    CHECK_V3(n, 1, 0, 0);
    const surface *s = &sc->surfaces[0];
    CHECK_V3(surface_point(s, 0, 0), 0, 0, 0);
    CHECK_V3(surface_point(s, 1, 1), 1, 1, 0);
    CHECK_V3(surface_point(s, 0.25, 0.5), 0.25, 0.5, 0);

    xrad_scene_destroy(&sc);
    return test_finish();
}
