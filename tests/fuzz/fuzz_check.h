/*
 * What every fuzz harness over scene input asserts (fuzz_scene.c,
 * fuzz_import.c): a built scene keeps every invariant the rest of the
 * library relies on (src/scene/scene.h, DESIGN.md "Numerical notes"), and
 * a refusal keeps the error contract of include/xrad.h. A violation
 * aborts, which libFuzzer reports as a crash. Static functions: each
 * harness is one translation unit.
 */
#ifndef XRAD_FUZZ_CHECK_H
#define XRAD_FUZZ_CHECK_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "xrad.h"

static void violated(const char *what, unsigned a, unsigned b)
{
    fprintf(stderr, "fuzz: invariant violated: %s (%u, %u)\n", what, a, b);
    abort();
}

#define REQUIRE(cond, a, b)                                                  \
    do {                                                                     \
        if (!(cond))                                                         \
            violated(#cond, (unsigned)(a), (unsigned)(b));                   \
    } while (0)

static int unit_length(vec3 v)
{
    return v3_finite(v) && fabs(v3_len(v) - 1.0) < 1e-9;
}

static int xform_finite(const xform *x)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(x->r.m[i][0]) || !isfinite(x->r.m[i][1]) || !isfinite(x->r.m[i][2]))
            return 0;
    return v3_finite(x->t);
}

/* `name`: the input's file name, which a message about bad input must
 * carry; NULL: not checked (the input has been accepted already). */
static void check_error(xrad_status st, const xrad_error *err, const char *name)
{
    REQUIRE(st == XRAD_ERROR_INPUT || st == XRAD_ERROR_SYSTEM, st, 0);
    REQUIRE(err->status == st, err->status, st);
    const char *end = memchr(err->message, '\0', sizeof(err->message));
    REQUIRE(end != NULL && end != err->message, 0, 0);
    /* xrad.h: a message about bad input names the file. */
    REQUIRE(!name || st != XRAD_ERROR_INPUT || strstr(err->message, name), st, 0);
}

static void check_materials(const xrad_scene *s)
{
    for (uint32_t m = 0; m < s->material_count; m++) {
        const double *a = &s->materials[m].albedo.x, *e = &s->materials[m].emission.x;
        for (int c = 0; c < 3; c++) {
            REQUIRE(isfinite(a[c]) && a[c] >= 0 && a[c] < 1, m, c);
            REQUIRE(isfinite(e[c]) && e[c] >= 0, m, c);
        }
    }
}

static void check_objects(const xrad_scene *s)
{
    for (uint32_t o = 0; o < s->object_count; o++) {
        const object *ob = &s->objects[o];
        REQUIRE(ob->first_surface <= s->surface_count, o, ob->first_surface);
        REQUIRE(ob->surface_count <= s->surface_count - ob->first_surface, o, ob->surface_count);
        REQUIRE(ob->first_element <= s->element_count, o, ob->first_element);
        REQUIRE(ob->element_count <= s->element_count - ob->first_element, o, ob->element_count);
        REQUIRE(xform_finite(&ob->base), o, 0);
        const animation *an = &ob->anim;
        if (an->rotates) {
            REQUIRE(unit_length(an->axis), o, 0);
            REQUIRE(v3_finite(an->pivot) && isfinite(an->rate), o, 0);
        }
        REQUIRE(an->keyframe_count == 0 || an->keyframes != NULL, o, an->keyframe_count);
        for (uint32_t k = 0; k < an->keyframe_count; k++) {
            REQUIRE(isfinite(an->keyframes[k].time), o, k);
            REQUIRE(v3_finite(an->keyframes[k].translation), o, k);
            REQUIRE(k == 0 || an->keyframes[k].time > an->keyframes[k - 1].time, o, k);
        }
        /* Poses at the start and one second in: finite input must not
         * produce a non-finite transform (DESIGN.md: no NaN or Inf may reach
         * any buffer). */
        for (int t = 0; t <= 1; t++) {
            xform x = scene_object_pose(s, o, (double)t);
            REQUIRE(xform_finite(&x), o, t);
        }
    }
}

static void check_surfaces(const xrad_scene *s, uint64_t *element_total)
{
    *element_total = 0;
    for (uint32_t i = 0; i < s->surface_count; i++) {
        const surface *sf = &s->surfaces[i];
        REQUIRE(sf->object < s->object_count, i, sf->object);
        REQUIRE(sf->material < s->material_count, i, sf->material);
        for (int k = 0; k < 4; k++)
            REQUIRE(v3_finite(sf->p[k]), i, k);
        REQUIRE(unit_length(sf->normal), i, 0);
        REQUIRE(isfinite(sf->area) && sf->area > 0, i, 0);
        REQUIRE(isfinite(sf->planarise_offset) && sf->planarise_offset >= 0, i, 0);
        /* At least 2 x 2, or a tiny triangle's one element (scene.h). */
        REQUIRE((sf->nu >= 2 && sf->nv >= 2) || (sf->triangle && sf->nu == 1 && sf->nv == 1),
                sf->nu, sf->nv);
        uint64_t n = (uint64_t)sf->nu * sf->nv;
        REQUIRE(sf->first_element <= s->element_count, i, sf->first_element);
        REQUIRE(n <= s->element_count - sf->first_element, i, n);
        REQUIRE((uint64_t)sf->tile_x + sf->nu <= s->atlas_width, i, sf->tile_x);
        REQUIRE((uint64_t)sf->tile_y + sf->nv <= s->atlas_height, i, sf->tile_y);
        *element_total += n;

        double area = 0;
        for (uint32_t j = 0; j < sf->nv; j++) {
            for (uint32_t k = 0; k < sf->nu; k++) {
                const element *e = &s->elements[sf->first_element + j * sf->nu + k];
                REQUIRE(e->surface == i, i, e->surface);
                REQUIRE(e->i == k && e->j == j, e->i, e->j);
                REQUIRE(v3_finite(e->pos), i, k);
                REQUIRE(isfinite(e->area) && e->area > 0, i, k);
                REQUIRE(e->texel_x < s->atlas_width && e->texel_y < s->atlas_height, e->texel_x,
                        e->texel_y);
                area += e->area;
            }
        }
        /* scene.h: the element areas of a surface sum to its area. */
        REQUIRE(fabs(area - sf->area) <= 1e-6 * sf->area, i, 0);

        vec3 corners[4], normal;
        scene_surface_world(s, i, 0.0, corners, &normal);
        for (int k = 0; k < 4; k++)
            REQUIRE(v3_finite(corners[k]), i, k);
        REQUIRE(unit_length(normal), i, 0);
    }
}

/* No two elements share an atlas texel; checked only where the bitmap is
 * small enough to keep the fuzzer fast. */
static void check_texels_unique(const xrad_scene *s)
{
    uint64_t n = (uint64_t)s->atlas_width * s->atlas_height;
    if (n == 0 || n > (1u << 24))
        return;
    uint8_t *used = calloc((size_t)(n + 7) / 8, 1);
    if (!used)
        return;
    for (uint32_t i = 0; i < s->element_count; i++) {
        uint64_t t = (uint64_t)s->elements[i].texel_y * s->atlas_width + s->elements[i].texel_x;
        if (used[t / 8] & (1u << (t % 8))) {
            free(used);
            violated("texel shared by two elements", s->elements[i].texel_x,
                     s->elements[i].texel_y);
        }
        used[t / 8] |= (uint8_t)(1u << (t % 8));
    }
    free(used);
}

static void check_scene(const xrad_scene *s)
{
    REQUIRE(s->material_count == 0 || s->materials, s->material_count, 0);
    REQUIRE(s->object_count == 0 || s->objects, s->object_count, 0);
    REQUIRE(s->surface_count == 0 || s->surfaces, s->surface_count, 0);
    REQUIRE(s->element_count == 0 || s->elements, s->element_count, 0);
    REQUIRE(isfinite(s->unit) && s->unit > 0, 0, 0);
    check_materials(s);
    check_objects(s);
    uint64_t elements;
    check_surfaces(s, &elements);
    REQUIRE(elements == s->element_count, elements, s->element_count);
    check_texels_unique(s);

    xrad_scene_info info;
    xrad_scene_get_info(s, &info);
    REQUIRE(info.objects == s->object_count, info.objects, s->object_count);
    REQUIRE(info.surfaces == s->surface_count, info.surfaces, s->surface_count);
    REQUIRE(info.materials == s->material_count, info.materials, s->material_count);
    REQUIRE(info.elements == s->element_count, info.elements, s->element_count);
    REQUIRE(info.static_elements + info.dynamic_elements == info.elements, info.static_elements,
            info.dynamic_elements);
    REQUIRE(info.dynamic_objects <= info.objects, info.dynamic_objects, info.objects);
    REQUIRE(info.atlas_width == s->atlas_width && info.atlas_height == s->atlas_height,
            info.atlas_width, info.atlas_height);
    REQUIRE(isfinite(info.area) && info.area >= 0, 0, 0);
    REQUIRE(isfinite(info.planarise_max_offset) && info.planarise_max_offset >= 0, 0, 0);

    xrad_atlas atlas;
    xrad_error err;
    xrad_status st = xrad_atlas_create(s, &atlas, &err);
    if (st != XRAD_OK) {
        check_error(st, &err, NULL);
        return;
    }
    REQUIRE(atlas.width == s->atlas_width && atlas.height == s->atlas_height, atlas.width,
            atlas.height);
    xrad_atlas_destroy(&atlas);
}

#endif
