/* The error figures of README "Accuracy" (xrad_image_compare,
 * xrad_atlas_compare) against answers known by construction: a solution
 * scaled by 1.05, one surface off by 10%, emitters and background left out,
 * percentiles of a hand-made distribution, the floor under a black element.
 * The expected values come from how the inputs were made, never from the
 * code under test. */
#include <stdbool.h>
#include <stdint.h>

#include "harness.h"
#include "scene/scene.h"
#include "xrad.h"

/* ------------------------------------------------------------ image space */

enum { W = 6, H = 4 };

/* Pixel i of an RGBA image. */
static void set_px(float *img, int i, float r, float g, float b, float alpha)
{
    img[i * 4 + 0] = r;
    img[i * 4 + 1] = g;
    img[i * 4 + 2] = b;
    img[i * 4 + 3] = alpha;
}

static void test_image_scaled(void)
{
    static float a[W * H * 4], b[W * H * 4];
    xrad_error err = {0};
    xrad_image_metrics m;

    /* A uniform reference: RMS of 0.05 b over its mean b is 0.05. */
    for (int i = 0; i < W * H; i++) {
        set_px(b, i, 2, 2, 2, 1);
        set_px(a, i, 2.1f, 2.1f, 2.1f, 1);
    }
    CHECK(xrad_image_compare(a, b, NULL, W, H, &m, &err) == XRAD_OK, "%s", err.message);
    CHECK_REL(m.mean_ratio, 1.05, 1e-6);
    CHECK_REL(m.rel_rms, 0.05, 1e-5);
    CHECK(m.pixels == W * H, "pixels %llu", (unsigned long long)m.pixels);

    /* Half the values 1, half 3 (grey): a = 1.05 b gives mean ratio 1.05
     * and RMS(0.05 b) / mean b = 0.05 sqrt((1 + 9) / 2) / 2. 1.05 is
     * rounded to float once per value; 1.05f x b is what a holds, so the
     * figures are those of 1.05f. */
    const double k = 1.05f;
    for (int i = 0; i < W * H; i++) {
        float v = i % 2 ? 3.0f : 1.0f;
        set_px(b, i, v, v, v, 1);
        set_px(a, i, (float)(k * v), (float)(k * v), (float)(k * v), 1);
    }
    CHECK(xrad_image_compare(a, b, NULL, W, H, &m, &err) == XRAD_OK, "%s", err.message);
    CHECK_REL(m.mean_ratio, k, 1e-7);
    CHECK_REL(m.rel_rms, (k - 1) * sqrt(5.0) / 2.0, 1e-5);
    CHECK(m.pixels == W * H, "pixels %llu", (unsigned long long)m.pixels);
    /* NRMSE is still the thesis's figure over every pixel: RMS of 0.05f b
     * over the range 3 - 1. */
    CHECK_REL(m.nrmse, (k - 1) * sqrt(5.0) / 2.0, 1e-5);
}

/* An emitter pixel wildly off and a background pixel (alpha 0 in the
 * reference) with junk in the compared image must not move the figures. */
static void test_image_masked(void)
{
    static float a[W * H * 4], b[W * H * 4], emitter[W * H];
    xrad_error err = {0};
    xrad_image_metrics base, m;
    for (int i = 0; i < W * H; i++) {
        float v = 0.5f + 0.25f * (float)(i % 5);
        set_px(b, i, v, 0.5f * v, 0.25f * v, 1);
        set_px(a, i, 1.1f * v, 0.5f * v, 0.25f * v, 1);
        emitter[i] = 0;
    }
    /* Pixel 3 shows an emitter, pixel 7 the background: the figures of
     * the other 22. */
    enum { EMIT = 3, BACK = 7 };
    emitter[EMIT] = 1;
    set_px(b, BACK, 0, 0, 0, 0);
    set_px(a, BACK, 0, 0, 0, 0);
    CHECK(xrad_image_compare(a, b, emitter, W, H, &base, &err) == XRAD_OK, "%s", err.message);
    CHECK(base.pixels == W * H - 2, "pixels %llu, want %d", (unsigned long long)base.pixels,
          W * H - 2);

    /* Now make both wildly different: nothing counted may change. */
    set_px(b, EMIT, 50, 50, 50, 1);
    set_px(a, EMIT, 1e4f, 0, 1e4f, 1);
    set_px(a, BACK, 300, 300, 300, 1);
    CHECK(xrad_image_compare(a, b, emitter, W, H, &m, &err) == XRAD_OK, "%s", err.message);
    CHECK(m.mean_ratio == base.mean_ratio, "mean_ratio %.9g moved from %.9g", m.mean_ratio,
          base.mean_ratio);
    CHECK(m.rel_rms == base.rel_rms, "rel_rms %.9g moved from %.9g", m.rel_rms, base.rel_rms);
    CHECK(m.pixels == base.pixels, "pixels");
    /* The emitter pixel is counted without a mask (an old EXR): then the
     * figures do move, so the mask is what held them. */
    CHECK(xrad_image_compare(a, b, NULL, W, H, &m, &err) == XRAD_OK, "%s", err.message);
    CHECK(m.pixels == W * H - 1, "without a mask every covered pixel counts: %llu",
          (unsigned long long)m.pixels);
    CHECK(m.mean_ratio > 10 * base.mean_ratio, "the emitter pixel counts without a mask: %g",
          m.mean_ratio);

    /* Nothing counted, or a black reference: bad input, not a number. */
    for (int i = 0; i < W * H; i++)
        emitter[i] = 1;
    CHECK(xrad_image_compare(a, b, emitter, W, H, &m, &err) == XRAD_ERROR_INPUT,
          "all emitters");
    for (int i = 0; i < W * H; i++)
        set_px(b, i, 0, 0, 0, 1);
    CHECK(xrad_image_compare(a, b, NULL, W, H, &m, &err) == XRAD_ERROR_INPUT, "black");
}

/* ---------------------------------------------------------- element space */

/* The light comes first so that surface index 0 is one that is not
 * counted. 4 + 20 + 9 elements; 29 counted. */
static const char scene_json[] =
    "{\"unit\": \"m\","
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.5, 0.5, 0.5]},"
    "                {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [5, 5, 5]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"light\", \"material\": \"lamp\", \"elements\": [2, 2],"
    "    \"quad\": {\"origin\": [0.4, 0.9, 0.4], \"u\": [0, 0, 0.2], \"v\": [0.2, 0, 0]}},"
    "   {\"name\": \"floor\", \"material\": \"white\", \"elements\": [5, 4],"
    "    \"quad\": {\"origin\": [0, 0, 0], \"u\": [0, 0, 1], \"v\": [1, 0, 0]}},"
    "   {\"name\": \"wall\", \"material\": \"white\", \"elements\": [3, 3],"
    "    \"quad\": {\"origin\": [0, 0, 0], \"u\": [1, 0, 0], \"v\": [0, 1, 0]}}]}]}";

enum { LIGHT = 0, FLOOR = 1, WALL = 2, COUNTED = 29 };

typedef struct fixture {
    xrad_scene *scene;
    xrad_atlas a, b;
} fixture;

static size_t texel(const xrad_scene *s, uint32_t e)
{
    return ((size_t)s->elements[e].texel_y * s->atlas_width + s->elements[e].texel_x) * 4;
}

/* Element e of atlas t to grey v (R + G + B = 3 v). */
static void set_el(const xrad_scene *s, xrad_atlas *t, uint32_t e, double v)
{
    size_t i = texel(s, e);
    t->rgba[i] = t->rgba[i + 1] = t->rgba[i + 2] = (float)v;
    t->rgba[i + 3] = 1;
}

static int setup(fixture *f)
{
    memset(f, 0, sizeof(*f));
    xrad_error err = {0};
    if (xrad_scene_parse(scene_json, strlen(scene_json), "metrics-test.json", &f->scene,
                         &err) ||
        xrad_atlas_create(f->scene, &f->a, &err) || xrad_atlas_create(f->scene, &f->b, &err)) {
        CHECK(0, "setup: %s", err.message);
        return 0;
    }
    CHECK(f->scene->surface_count == 3 && f->scene->element_count == 33,
          "the scene has %u surfaces, %u elements", f->scene->surface_count,
          f->scene->element_count);
    return f->scene->surface_count == 3 && f->scene->element_count == 33;
}

static void teardown(fixture *f)
{
    xrad_atlas_destroy(&f->a);
    xrad_atlas_destroy(&f->b);
    xrad_scene_destroy(&f->scene);
}

static void test_atlas_scaled(void)
{
    fixture f;
    if (!setup(&f))
        goto done;
    xrad_error err = {0};
    xrad_element_metrics m;
    double ratio[3];
    /* Varied positive values: every element and surface is 1.05 x; the
     * light is wildly off and must not count. */
    for (uint32_t e = 0; e < f.scene->element_count; e++) {
        double v = 0.2 + 0.1 * (e % 7);
        bool light = f.scene->elements[e].surface == LIGHT;
        set_el(f.scene, &f.b, e, v);
        set_el(f.scene, &f.a, e, light ? 40 * v : 1.05 * v);
    }
    CHECK(xrad_atlas_compare(f.scene, &f.a, &f.b, &m, ratio, &err) == XRAD_OK, "%s",
          err.message);
    CHECK_REL(m.surface_error, 0.05, 1e-5);
    CHECK_REL(m.mean_ratio, 1.05, 1e-6);
    CHECK_REL(m.p50, 0.05, 1e-5);
    CHECK_REL(m.p95, 0.05, 1e-5);
    CHECK_REL(m.max, 0.05, 1e-5);
    CHECK(m.surfaces == 2 && m.elements == COUNTED, "counted %u surfaces, %u elements",
          m.surfaces, m.elements);
    CHECK(ratio[LIGHT] == 1, "the light's ratio is 1 (not counted): %g", ratio[LIGHT]);
    CHECK_REL(ratio[FLOOR], 1.05, 1e-6);
    CHECK_REL(ratio[WALL], 1.05, 1e-6);

    /* The same solution twice: nothing is wrong, and the worst surface is
     * still a compared one, not the light at index 0. */
    CHECK(xrad_atlas_compare(f.scene, &f.b, &f.b, &m, NULL, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(m.surface_error == 0 && m.max == 0 && m.mean_ratio == 1, "identical: %g %g %g",
          m.surface_error, m.max, m.mean_ratio);
    CHECK(m.worst_surface != LIGHT, "identical solutions name the light as worst");
done:
    teardown(&f);
}

static void test_atlas_one_surface(void)
{
    fixture f;
    if (!setup(&f))
        goto done;
    xrad_error err = {0};
    xrad_element_metrics m;
    /* The wall 10% brighter, the floor exact. */
    for (uint32_t e = 0; e < f.scene->element_count; e++) {
        double v = 0.3 + 0.05 * (e % 5);
        uint32_t s = f.scene->elements[e].surface;
        set_el(f.scene, &f.b, e, v);
        set_el(f.scene, &f.a, e, s == WALL ? 1.1 * v : s == LIGHT ? 0 : v);
    }
    CHECK(xrad_atlas_compare(f.scene, &f.a, &f.b, &m, NULL, &err) == XRAD_OK, "%s",
          err.message);
    CHECK_REL(m.surface_error, 0.10, 1e-5);
    CHECK_REL(m.worst_ratio, 1.10, 1e-6);
    CHECK(m.worst_surface == WALL, "worst surface %u, want %u", m.worst_surface, WALL);
    xrad_surface_info si;
    CHECK(xrad_scene_get_surface(f.scene, m.worst_surface, &si, &err) == XRAD_OK, "%s",
          err.message);
    CHECK(si.name && !strcmp(si.name, "wall"), "worst surface is '%s'", si.name);
    /* 9 of 29 elements are off by 0.1: the median is exact, p95 and the
     * maximum see the wall. */
    CHECK_ABS(m.p50, 0, 1e-7);
    CHECK_REL(m.p95, 0.10, 1e-5);
    CHECK_REL(m.max, 0.10, 1e-5);

    /* A compared atlas of another size: bad input. */
    xrad_atlas wrong = {f.a.width + 1, f.a.height, f.a.rgba};
    CHECK(xrad_atlas_compare(f.scene, &wrong, &f.b, &m, NULL, &err) == XRAD_ERROR_INPUT,
          "another size");
done:
    teardown(&f);
}

/* Relative errors 0.01 .. 0.29 on the 29 counted elements, in a shuffled
 * order: nearest rank gives p50 = the 15th = 0.15, p95 = the
 * ceil(27.55) = 28th = 0.28, max 0.29. */
static void test_atlas_percentiles(void)
{
    fixture f;
    if (!setup(&f))
        goto done;
    xrad_error err = {0};
    xrad_element_metrics m;
    uint32_t k = 0;
    for (uint32_t e = 0; e < f.scene->element_count; e++) {
        double v = 1 + 0.5 * (e % 3);
        set_el(f.scene, &f.b, e, v);
        if (f.scene->elements[e].surface == LIGHT) {
            set_el(f.scene, &f.a, e, v);
            continue;
        }
        /* k -> 7k mod 29 is a permutation of 0..28 (29 is prime). */
        double rel = (double)((7 * k++) % COUNTED + 1) / 100.0;
        set_el(f.scene, &f.a, e, (e % 2 ? 1 + rel : 1 - rel) * v);
    }
    CHECK(k == COUNTED, "%u counted elements", k);
    CHECK(xrad_atlas_compare(f.scene, &f.a, &f.b, &m, NULL, &err) == XRAD_OK, "%s",
          err.message);
    CHECK_REL(m.p50, 0.15, 1e-5);
    CHECK_REL(m.p95, 0.28, 1e-5);
    CHECK_REL(m.max, 0.29, 1e-5);
done:
    teardown(&f);
}

/* A black element in the reference: its error is measured against 1e-3 x
 * the area-weighted mean of the reference over counted elements, not
 * against its own zero. */
static void test_atlas_floor(void)
{
    fixture f;
    if (!setup(&f))
        goto done;
    xrad_error err = {0};
    xrad_element_metrics m;
    const surface *fl = &f.scene->surfaces[FLOOR];
    uint32_t black = fl->first_element + 1 * fl->nu + 2; /* an inner element */
    double sum = 0, area = 0;
    for (uint32_t e = 0; e < f.scene->element_count; e++) {
        const element *el = &f.scene->elements[e];
        double v = e == black ? 0 : 2;
        set_el(f.scene, &f.b, e, v);
        set_el(f.scene, &f.a, e, v);
        if (el->surface != LIGHT) {
            sum += el->area * 3 * v; /* R + G + B */
            area += el->area;
        }
    }
    double floor_b = 1e-3 * sum / area;
    /* R + G + B of the black element in a: 3 x the floor. */
    set_el(f.scene, &f.a, black, floor_b);
    CHECK(xrad_atlas_compare(f.scene, &f.a, &f.b, &m, NULL, &err) == XRAD_OK, "%s",
          err.message);
    CHECK_REL(m.max, 3.0, 1e-5);
    CHECK_ABS(m.p95, 0, 1e-7);
    CHECK(isfinite(m.surface_error), "surface_error %g", m.surface_error);

    /* Every counted element black: nothing to measure against. */
    for (uint32_t e = 0; e < f.scene->element_count; e++)
        if (f.scene->elements[e].surface != LIGHT)
            set_el(f.scene, &f.b, e, 0);
    CHECK(xrad_atlas_compare(f.scene, &f.a, &f.b, &m, NULL, &err) == XRAD_ERROR_INPUT,
          "a black reference");
done:
    teardown(&f);
}

int main(void)
{
    test_image_scaled();
    test_image_masked();
    test_atlas_scaled();
    test_atlas_one_surface();
    test_atlas_percentiles();
    test_atlas_floor();
    return test_finish();
}
