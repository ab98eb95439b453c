/*
 * Shared between the scene module's files only: the limits that keep any
 * input from allocating gigabytes, and the steps after parsing (geometry
 * checks, element sampling, atlas packing).
 */
#ifndef XRAD_SCENE_INTERNAL_H
#define XRAD_SCENE_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/error.h"
#include "scene/quad_bvh.h"
#include "scene/scene.h"

/* Limits (documented in scenes/README.md). */
#define SCENE_MAX_FILE_BYTES (64u << 20)
#define SCENE_MAX_MATERIALS 10000u
#define SCENE_MAX_OBJECTS 10000u
/* 2^20: the Gobbetti seed's 100K-triangle meshes and the mission's 150K
 * with room to spare; a surface costs about 250 bytes of host memory and
 * 112 of GPU memory (the 4M elements bound first). */
#define SCENE_MAX_SURFACES 1048576u
#define SCENE_MAX_KEYFRAMES 100000u
#define SCENE_MAX_SAMPLES 4096u       /* per surface edge; the atlas is at most this wide */
#define SCENE_MAX_ELEMENTS 4000000u   /* whole scene */
#define SCENE_MAX_ATLAS_HEIGHT 16384u
#define SCENE_MAX_DENSITY 10000.0     /* elements per metre */
#define SCENE_MAX_COORD 1e9           /* m, any coordinate or length */
#define SCENE_MAX_EMISSION 1e20       /* W/m^2: radiosity stays far from fp32 overflow */

/* Corner samples sit this fraction of a sample spacing inside the surface,
 * along the diagonal (thesis 4.1: the corner is a singularity). */
#define SCENE_CORNER_OFFSET 0.01

/* The whole of file `path` (at most max_bytes), NUL-terminated, in *out
 * (malloc'd; free it) with its length in *size. Errors name the file: a
 * file that is missing, unreadable or a directory is XRAD_ERROR_INPUT. */
xrad_status scene_read_file(const char *path, size_t max_bytes, char **out, size_t *size,
                            xrad_error *err);

/* Samples along an edge of length `len` (m) at `density` elements per
 * metre: max(2, ceil(len * density) + 1), with a relative 1e-9 slack on the
 * product so that an edge of exactly k spacings gets k + 1 samples despite
 * rounding. Returns a double so that absurd inputs can be detected before
 * any cast. */
double scene_samples_along(double len, double density);

/* Validates four object-space vertices (m) as a planar convex quad and fills
 * s->p, normal, area, planarise_offset and planarise_dist. Vertices within
 * 1% of the longest diagonal of their best-fit plane (Newell normal through
 * the centroid) are projected onto it. On failure returns false and writes
 * the reason to why. */
bool scene_quad_setup(surface *s, const vec3 in[4], char *why, size_t why_len);

/* The longer of each pair of opposite edges: along u (p0p1, p3p2) and v
 * (p0p3, p1p2), in m. */
void scene_quad_edge_lengths(const surface *s, double *lu, double *lv);

/* Validates three object-space vertices (m, counter-clockwise seen from
 * the front) as a triangle and fills s as a quad collapsed at its apex
 * (scene.h): p0 p1 its longest edge, p2 = p3 the opposite vertex. On
 * failure returns false and writes the reason to why. */
bool scene_triangle_setup(surface *s, const vec3 in[3], char *why, size_t why_len);

/* |dP/ds x dP/dt| of surface sf's bilinear parametrisation at (s, t),
 * signed along its normal (exactly bilinear in s, t for a planar quad). */
double scene_surface_jacobian(const surface *sf, double s, double t);

/* The surfaces in world space at a time, for segment and ray tests
 * (scene_contact.c): exact quad tests behind a BVH. */
typedef struct scene_rays {
    const xrad_scene *scene;
    double time, diameter;
    bool dynamic_too;        /* dynamic surfaces block too */
    vec3 *corners, *normals; /* world, at `time` */
    quad_bvh bvh;            /* over the corners: candidates for the exact tests */
} scene_rays;

xrad_status scene_rays_init(scene_rays *rs, const xrad_scene *scene, double time,
                            bool dynamic_too, xrad_error *err);
void scene_rays_free(scene_rays *rs);
/* Whether a surface other than `skip` crosses the segment a-b (ends
 * excluded). */
bool scene_rays_blocked(const scene_rays *rs, vec3 a, vec3 b, uint32_t skip);

/* Names are checked for duplicates through sorted lists, so that large
 * scenes cost n log n, not n^2. */
typedef struct name_ref {
    const char *name;
    uint32_t index;
} name_ref;

/* Sorts refs; returns the position in refs of the second of the first
 * duplicate pair (by index order of the pairs found), or n if none. */
uint32_t scene_find_duplicate(name_ref *refs, uint32_t n);

/* The scene-file loader's access to the builder: the scene under
 * construction (its quality, unit, name), the density scale once the
 * file's quality is known, the duplicate-material check before the
 * objects that name them, and a quad whose messages name the file's
 * field (`field`) at `where` ("object 'o': surface 's': "), at a density
 * already resolved. */
xrad_scene *scene_builder_scene(xrad_scene_builder *b);
xrad_status scene_builder_set_density(xrad_scene_builder *b, double scale, double density,
                                      xrad_error *err);
xrad_status scene_builder_set_adaptive(xrad_scene_builder *b, const xrad_adaptive_desc *d,
                                       xrad_error *err);
/* The current object's density, or the surface's own (`given`, 0: none),
 * scaled. */
xrad_status scene_builder_surface_density(xrad_scene_builder *b, const char *where,
                                          double given, double *out, xrad_error *err);
xrad_status scene_builder_check_materials(xrad_scene_builder *b, xrad_error *err);
xrad_status scene_builder_quad(xrad_scene_builder *b, const xrad_quad_desc *q, const char *where,
                               const char *field, double density, xrad_error *err);

/* A note for the user about the input (what a model file has that xrad
 * ignores): kept in the scene, xrad_scene_warning. */
void scene_builder_warn(xrad_scene_builder *b, const char *fmt, ...) XRAD_PRINTF(2, 3);

/* Adaptive subdivision (xrad_adaptive_desc, scene_adaptive.c). check:
 * *out = d with its defaults filled in, or XRAD_ERROR_INPUT naming `name`
 * and the field. refine: raises the nu, nv of the scene's surfaces (before
 * its elements are built), *elements counting the scene's elements for its
 * limit; the builder keeps the warnings. */
xrad_status scene_adaptive_check(const xrad_adaptive_desc *d, const char *name,
                                 xrad_adaptive_desc *out, xrad_error *err);
xrad_status scene_adaptive_refine(xrad_scene_builder *b, const xrad_adaptive_desc *d,
                                  uint64_t *elements, xrad_error *err);

/* Model files (scene_import.c, assimp). */
typedef struct scene_import_desc {
    const char *prefix;  /* material names are PREFIX/NAME */
    const char *node;    /* only this node's subtree; NULL: the whole file */
    const char *name;    /* surfaces are NAME.i.k (mesh instance i); NULL: NODE.i.k */
    bool take_camera;    /* the file's first camera (or `camera`) becomes the scene's */
    const char *camera;
    uint32_t material;   /* every triangle's material; UINT32_MAX: the file's */
    double density;      /* as given (0: the object's) */
} scene_import_desc;

/* Whether the file name ends in an extension scene_import_model reads. */
bool scene_import_supported(const char *path);

/* Adds the file's triangle meshes to the builder's current object. Bad
 * input (what assimp refuses, non-finite or out-of-range vertices and
 * indices, counts that cannot fit, no triangles) is XRAD_ERROR_INPUT naming
 * the file and, where there is one, the node and mesh (a glTF primitive);
 * what assimp repairs (faces dropped) and what xrad ignores (points, lines,
 * zero-area triangles) become warnings. Imports run one at a time in the
 * process (assimp's logger and last error are global). */
xrad_status scene_import_model(xrad_scene_builder *b, const char *path,
                               const scene_import_desc *desc, xrad_error *err);

/* The same from `size` bytes at `data` (tests/fuzz/fuzz_import.c): `name`
 * stands for the file in messages and its extension picks the format;
 * files the model refers to (a glTF's .bin, an OBJ's .mtl) are not found,
 * so that memory input never reaches the file system. */
xrad_status scene_import_memory(xrad_scene_builder *b, const char *name, const void *data,
                                size_t size, const scene_import_desc *desc, xrad_error *err);

/* A model in memory as a scene by itself, as xrad_scene_load makes one of
 * a model file (scene_load.c). */
xrad_status scene_load_model_memory(const char *name, const void *data, size_t size,
                                    xrad_scene **out, xrad_error *err);

/* Allocates and fills the elements of every surface (whose nu, nv are set),
 * the objects' element ranges, and packs the atlas. */
xrad_status scene_build_elements(xrad_scene *scene, xrad_error *err);
/* Splitting every element of sf 1 -> 4 (scene_texture_refined): fits
 * gives the new grid in *nu, *nv and whether the scene, `elements` so
 * far, stays within SCENE_MAX_ELEMENTS and SCENE_MAX_SAMPLES; take
 * applies it and counts the new elements. */
bool scene_split_fits(const surface *sf, uint64_t elements, uint32_t *nu, uint32_t *nv);
void scene_split_take(surface *sf, uint32_t nu, uint32_t nv, uint64_t *elements);

/* Shelf-packs the surfaces' nu x nv tiles into an atlas of width <= 4096:
 * sets tile_x/tile_y and scene->atlas_width/height. */
xrad_status scene_pack_atlas(xrad_scene *scene, xrad_error *err);

/* World-space bounds of every surface at time t. */
void scene_bounds(const xrad_scene *scene, double t, vec3 *lo, vec3 *hi);

#endif
