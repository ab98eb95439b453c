/*
 * Albedo and normal maps in the solve (issue 18.1, 18.2; Wallner 3.1 gives
 * each element the texture under it, 3.3 the perturbed normal): the
 * builder keeps the materials' maps and the surfaces' texture coordinates,
 * and at finish each element of a mapped surface takes the maps' means
 * over its area (scene.h element_albedo, element_normal).
 */
#ifndef XRAD_SCENE_TEXTURE_H
#define XRAD_SCENE_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "scene/scene.h"

/* Largest map side: 16K texels (glTF files carry up to 8K), and at most
 * 64M texels in all (8K x 8K): the map is held as floats, 768 MB there,
 * so that no file makes the loader allocate gigabytes. */
#define SCENE_TEXTURE_MAX_SIDE 16384u
#define SCENE_TEXTURE_MAX_TEXELS (64u << 20)

/* A copy of xrad_image_desc: linear RGB, row 0 at v = 1. width 0: none. */
typedef struct scene_texture {
    uint32_t width, height;
    float *rgb;
} scene_texture;

/* The texture coordinates of a surface's corners p[0..3] (p[3] = p[2] for
 * a triangle: uv[3] = uv[2]); within the surface they follow its bilinear
 * parametrisation, exact where the coordinates are affine on the plane. */
typedef struct scene_uv {
    float uv[4][2];
} scene_uv;

/* A material's maps; width 0: none. normal_levels: the refinements its
 * normal map may bring (xrad.h normal_map_levels, resolved: 0 none). */
typedef struct scene_material_maps {
    scene_texture albedo, normal;
    uint32_t normal_levels;
} scene_material_maps;

/* Neighbouring elements whose mapped normals differ by more than this
 * make their surface's elements split (xrad.h normal_map_levels). */
#define SCENE_NORMAL_DETAIL_DEGREES 5.0

/* Checks `d` (sizes, finite texels in [0, 1]) and copies it into *out;
 * `where` and `field` name the map in errors. */
xrad_status scene_texture_copy(const xrad_image_desc *d, scene_texture *out, const char *where,
                               const char *field, xrad_error *err);

/* The map's area-weighted mean over the cell [s0, s1] x [t0, t1] of
 * surface `sf` (corner coordinates `uv`): the texels as constant squares,
 * the area element |dP/ds x dP/dt| as weight. */
vec3 scene_texture_mean(const scene_texture *tex, const surface *sf, const scene_uv *uv, double s0,
                        double s1, double t0, double t1);

/* The object-space normal a tangent-space normal map whose mean texel over
 * a cell is `mean` gives there (decoded n = 2 rgb - 1: the decoding is
 * affine and the frame constant over a face, so the mean of the normals
 * is the normal of the mean texel), for surface `sf` with corner
 * coordinates `uv`. The frame is the face's tangent (along increasing u),
 * bitangent (increasing v) and normal, MikkTSpace's per-face frame; it
 * is the surface normal where the coordinates are degenerate. The result
 * is unit and at least 0.05 above the surface's plane: a normal at or
 * below its horizon would take no light at all. */
vec3 scene_texture_normal(const surface *sf, const scene_uv *uv, vec3 mean);

/* The samples along a side after one 1 -> 4 split: every interval
 * halved (2n - 1; a lone triangle's single element, 3). */
uint32_t scene_texture_refined(uint32_t n);

/* Whether two neighbouring cells of surface `sf` with nu x nv samples
 * (scene.h cells) take normals from normal map `tex` (coordinates `uv`)
 * more than SCENE_NORMAL_DETAIL_DEGREES apart. The surface's own nu, nv
 * are not read. Returns -1 out of memory. */
int scene_texture_normals_vary(const scene_texture *tex, const surface *sf, const scene_uv *uv,
                               uint32_t nu, uint32_t nv);

/* Fills scene->element_albedo from maps[material].albedo and
 * scene->element_normal from maps[material].normal (for material <
 * map_count), each allocated where some material has such a map, with
 * uv[surface] for the mapped surfaces, the material's albedo and the
 * surface's normal for the rest. The elements must be built. */
xrad_status scene_texture_apply(xrad_scene *scene, const scene_material_maps *maps,
                                uint32_t map_count, const scene_uv *uv, xrad_error *err);

/* Decodes an image file's `size` bytes (PNG, JPEG, TGA or BMP;
 * texture_load.c) into linear RGB, *rgb (malloc'd) width x height x 3
 * floats, the top row first; `srgb`: 8-bit values are sRGB encoded (a
 * glTF base colour texture, an OBJ map_Kd). Errors name `what`. */
xrad_status scene_texture_decode(const void *data, size_t size, bool srgb, const char *what,
                                 float **rgb, uint32_t *width, uint32_t *height, xrad_error *err);

/* count 8-bit values -> floats in [0, 1], sRGB decoded where `srgb`. */
void scene_texture_from_8bit(const uint8_t *in, size_t count, bool srgb, float *out);

#endif
