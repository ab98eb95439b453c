/*
 * xrad: diffuse global illumination by radiosity on Vulkan.
 *
 * This is the whole public interface of libxrad. Everything else lives in
 * src/ and may change. Units throughout: lengths in metres (scene files may
 * declare millimetres; they are converted on load), time in seconds,
 * radiosity and emission in W/m^2 (radiant exitance), albedo dimensionless
 * in [0, 1).
 *
 * Errors are values: every fallible call returns an xrad_status and, when it
 * is not XRAD_OK, fills the caller's xrad_error with a message that names the
 * file, the object and the field (for input) or the failing call and its
 * result (for the system). No call exits the process.
 *
 * Thread-safety: objects are not internally synchronised; use one object from
 * one thread at a time. Distinct objects may be used from distinct threads,
 * also when they share one context (its queue and memory are locked).
 */
#ifndef XRAD_H
#define XRAD_H

#include <stddef.h>
#include <stdint.h>

#include "xrad_version.h"

/* What libxrad exports: the functions declared with it; the shared
 * library hides every other symbol (its objects are built with
 * -fvisibility=hidden). */
#if defined(__GNUC__) || defined(__clang__)
#define XRAD_API __attribute__((visibility("default")))
#else
#define XRAD_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes double as the command line's exit statuses. */
typedef enum xrad_status {
    XRAD_OK = 0,
    XRAD_ERROR_INPUT = 1,  /* bad input: a scene file, an argument, a value out of range */
    XRAD_ERROR_SYSTEM = 2, /* I/O, memory, Vulkan or device failure */
} xrad_status;

typedef struct xrad_error {
    xrad_status status;
    char message[1024];
} xrad_error;

/* The library's version, "MAJOR.MINOR.PATCH" (XRAD_VERSION is the
 * headers'). */
XRAD_API const char *xrad_version(void);

/* ------------------------------------------------------------------ scene */

typedef struct xrad_scene xrad_scene;

/* Parses, validates and builds a scene file (format: scenes/README.md):
 * a JSON scene, or a model file (.gltf, .glb, .obj, .ply) as a scene by
 * itself.
 * On success *out owns the scene; release it with xrad_scene_destroy. */
XRAD_API xrad_status xrad_scene_load(const char *path, xrad_scene **out, xrad_error *err);

/* Adaptive subdivision where shadows fall (Wallner 4; README "Adaptive
 * subdivision"): before the first shot, each static receiving surface is
 * tested from each static emitter (a 3 x 3 grid of points on an emitting
 * surface, or a luminaire's position) with rays from a grid of points on
 * the receiver; where the visible fraction n_v / n_r of the pairs that
 * face each other is below 1 and within [lower, upper], the surface's
 * elements are split 1 -> 4 `levels` times. Surfaces sharing an edge take
 * the same level when coplanar (their boundary samples stay shared: no
 * T-vertex in the element grid) and levels within one of each other
 * otherwise. Zero in a field: the default. */
typedef struct xrad_adaptive_desc {
    uint32_t levels; /* splits at most; 0: off [0] */
    double lower;    /* b_l, in (0, 1] [0.02] */
    double upper;    /* b_u, in (0, 1] [0.98] */
} xrad_adaptive_desc;

typedef struct xrad_scene_load_desc {
    /* Every element density in the file times this; 0: the file's own
     * quality.density_scale, else 1. */
    double density_scale;
    /* Adaptive subdivision; a zero field: the file's own quality
     * (adaptive_levels, adaptive_lower, adaptive_upper), else the default. */
    xrad_adaptive_desc adaptive;
    /* A model file's camera by name; NULL: its first (or, without one,
     * the whole scene from -z). */
    const char *camera;
} xrad_scene_load_desc;

/* xrad_scene_load with options; desc may be NULL. */
XRAD_API xrad_status xrad_scene_load_with(const char *path, const xrad_scene_load_desc *desc,
                                          xrad_scene **out, xrad_error *err);

/* Same, from JSON text in memory; `name` stands for the file in messages. */
XRAD_API xrad_status xrad_scene_parse(const char *json, size_t len, const char *name,
                                      xrad_scene **out, xrad_error *err);
XRAD_API xrad_status xrad_scene_parse_with(const char *json, size_t len, const char *name,
                                           const xrad_scene_load_desc *desc, xrad_scene **out,
                                           xrad_error *err);

/* Accepts NULL and *scene == NULL; sets *scene to NULL. */
XRAD_API void xrad_scene_destroy(xrad_scene **scene);

/* What loading noticed and left out (a model file's textures, metalness,
 * skins, ...: scenes/README.md "Model files"), one line each, valid while
 * the scene lives; NULL past the count. */
XRAD_API uint32_t xrad_scene_warning_count(const xrad_scene *scene);
XRAD_API const char *xrad_scene_warning(const xrad_scene *scene, uint32_t index);

/* ---------------------------------------------------------- scene builder */

/* Builds a scene from arrays, as the scene-file loader does (the loader is
 * written on top of it): materials, then objects, each followed by its
 * quads and triangle meshes, then xrad_scene_builder_finish. Every call
 * validates what it is given and names the builder, the object, the
 * surface and the field in its message; after a failed call the builder
 * can only be destroyed. */
typedef struct xrad_scene_builder xrad_scene_builder;

typedef struct xrad_scene_builder_desc {
    const char *name;     /* stands for the file in messages; default "<builder>" */
    double density;       /* default elements per metre [20] */
    double density_scale; /* every density given (and the default) times this [1] */
    xrad_adaptive_desc adaptive; /* at finish; default off */
} xrad_scene_builder_desc;

/* desc may be NULL. */
XRAD_API xrad_status xrad_scene_builder_create(const xrad_scene_builder_desc *desc,
                                               xrad_scene_builder **out, xrad_error *err);

/* Accepts NULL and *builder == NULL; sets *builder to NULL. */
XRAD_API void xrad_scene_builder_destroy(xrad_scene_builder **builder);

/* An image of linear RGB values (an albedo texture: sRGB decoded). Texel
 * (x, y) is rgb[3 (y width + x) ...]; row 0 is the image's top, at texture
 * coordinate v = 1 (the OpenGL convention OBJ uses and assimp gives glTF
 * in), and coordinates outside [0, 1] repeat (glTF's default wrap). */
typedef struct xrad_image_desc {
    uint32_t width, height;
    const float *rgb; /* 3 per texel, each in [0, 1] */
} xrad_image_desc;

typedef struct xrad_material_desc {
    const char *name;   /* unique among the materials */
    double albedo[3];   /* each channel in [0, 1) */
    double emission[3]; /* W/m^2 radiant exitance, each channel >= 0 */
    /* NULL: none. Else the albedo is albedo x the texture (glTF's base
     * colour factor x baseColorTexture): each element of a surface takes
     * the texture's mean over its area, so that the solve reflects what
     * the surface shows. Copied. Meshes with the material give `uvs`; a
     * quad maps (0, 0) (1, 0) (1, 1) (0, 1) onto p0 p1 p2 p3. */
    const xrad_image_desc *albedo_map;
    /* NULL: none. Else a tangent-space normal map (glTF normalTexture):
     * rgb = (n + 1) / 2, linear, z towards the surface's front, tangent
     * along increasing u and bitangent along increasing v (Wallner 3.3).
     * Each element of a surface takes the normalised mean of the map's
     * normals over its area as the normal of every cosine it takes as a
     * receiver (the shooter's cosine stays the surface's: README
     * "Normal maps"). The tangent frame is the face's (MikkTSpace's
     * per-face tangent, exact on flat faces). Copied; `uvs` as for
     * albedo_map. */
    const xrad_image_desc *normal_map;
    /* With a normal_map, the element resolution follows its detail: a
     * surface whose neighbouring elements' normals differ by more than
     * 5 degrees has every element split 1 -> 4, and again, at most this
     * many times (within the scene's element limits, a warning past
     * them). 0: 1 (the default); XRAD_NORMAL_MAP_LEVELS_NONE: never;
     * at most XRAD_NORMAL_MAP_LEVELS_MAX. */
    int normal_map_levels;
} xrad_material_desc;

#define XRAD_NORMAL_MAP_LEVELS_NONE (-1)
#define XRAD_NORMAL_MAP_LEVELS_MAX 4

/* *index (may be NULL) receives the material's index for the surfaces. */
XRAD_API xrad_status xrad_scene_builder_add_material(xrad_scene_builder *b,
                                                     const xrad_material_desc *m, uint32_t *index,
                                                     xrad_error *err);

typedef struct xrad_keyframe {
    double time;         /* s, >= 0, strictly increasing */
    double translate[3]; /* m, added to the object's base translation */
} xrad_keyframe;

/* Motion of a dynamic object (scenes/README.md "animation"): a spin about
 * an axis through a pivot, then a piecewise linear translation. */
typedef struct xrad_animation_desc {
    int rotates;               /* spin about axis through pivot at degrees_per_second */
    double axis[3];            /* non-zero */
    double pivot[3];           /* m, object space */
    double degrees_per_second;
    const xrad_keyframe *keyframes; /* copied; may be NULL with keyframe_count 0 */
    uint32_t keyframe_count;
    int once;                  /* keyframes play once (else they repeat) */
} xrad_animation_desc;

typedef struct xrad_object_desc {
    const char *name;         /* unique among the objects */
    int dynamic;              /* moves (set M of the thesis); else static */
    double translate[3];      /* m: object space -> world is translate * rotate */
    double rotate_axis[3];    /* used where rotate_degrees is not 0 */
    double rotate_degrees;
    double density;           /* elements per metre; 0: the scene's */
    double cross_density;     /* dynamic only: the cross method's shooters; 0: none */
    const xrad_animation_desc *animation; /* dynamic only; NULL: none */
} xrad_object_desc;

/* Starts an object; the quads and meshes added after it belong to it. */
XRAD_API xrad_status xrad_scene_builder_begin_object(xrad_scene_builder *b,
                                                     const xrad_object_desc *o, xrad_error *err);

typedef struct xrad_quad_desc {
    const char *name;     /* unique within the object */
    uint32_t material;    /* xrad_scene_builder_add_material's index */
    double p[4][3];       /* m, object space: a planar convex quad, counter-clockwise
                             seen from its front (emitting, receiving) side */
    double density;       /* elements per metre; 0: the object's */
    uint32_t samples[2];  /* element samples along p0p1 and p0p3 (each >= 2); 0 0: from
                             the density */
} xrad_quad_desc;

XRAD_API xrad_status xrad_scene_builder_add_quad(xrad_scene_builder *b, const xrad_quad_desc *q,
                                                 xrad_error *err);

typedef struct xrad_mesh_desc {
    const char *name;          /* its surfaces are named NAME.0, NAME.1, ... */
    const float *positions;    /* 3 per vertex, m, object space */
    uint32_t vertex_count;
    const uint32_t *indices;   /* 3 per triangle, counter-clockwise seen from the front */
    uint32_t triangle_count;
    const uint32_t *materials; /* one per triangle; NULL: `material` for all */
    uint32_t material;
    double density;            /* elements per metre; 0: the object's */
    int keep_triangles;        /* do not join coplanar triangle pairs into quads */
    const float *uvs;          /* 2 per vertex, texture coordinates (u, v); needed where a
                                  triangle's material has an albedo_map or a normal_map,
                                  else ignored */
} xrad_mesh_desc;

/* Adds a triangle mesh to the current object. Two triangles that share an
 * edge, a plane (within 1e-6 of their size) and a material and form a
 * convex quad become one quad surface (one chart of the atlas; a quad
 * split in two comes back whole); every other triangle is a surface of
 * its own. Triangles of zero area are skipped and counted in the scene's
 * info. xrad_scene_get_mesh_corners tells where each triangle went. */
XRAD_API xrad_status xrad_scene_builder_add_mesh(xrad_scene_builder *b, const xrad_mesh_desc *m,
                                                 xrad_error *err);

/* A light that is not a surface (issue 18.3): a point emitter with an
 * intensity distribution, placed in world space (static). Its direct
 * light reaches the surfaces it sees (a segment to each element's sample
 * point, every surface blocking) as irradiance I cos(theta) / d^2, which
 * every method and the CPU reference take as the first bounce: each lit
 * element starts as though it emitted rho E (Wallner 3.2: a luminaire
 * shoots first). Photometric files give candela; xrad's radiometric
 * unit is 1/683 of it (683 lm/W, Wallner eq. 10-12). */
typedef struct xrad_luminaire_desc {
    const char *name;      /* unique among the luminaires */
    const char *file;      /* EULUMDAT (.ldt) or IES LM-63 (.ies); NULL: a point or spot
                              light of `intensity` */
    double intensity[3];   /* W/sr per channel (file NULL); with a file, its candela / 683 x
                              `scale` in every channel */
    double scale;          /* a file's intensities times this; 0: 1 */
    double position[3];    /* m, world */
    double aim[3];         /* the distribution's gamma = 0 axis (a luminaire's nadir, a spot's
                              axis); 0 0 0: straight down, -y */
    double up[3];          /* towards its C = 0 plane (file), any direction not along aim;
                              0 0 0: +x, or +z where aim is along x */
    double cone_degrees;   /* spot (file NULL): half-angle of the cone, (0, 180]; 0: all
                              directions (a point light) */
    double falloff_degrees; /* spot: the intensity falls smoothly to 0 over this last part of
                               the cone, [0, cone_degrees] */
} xrad_luminaire_desc;

XRAD_API xrad_status xrad_scene_builder_add_luminaire(xrad_scene_builder *b,
                                                      const xrad_luminaire_desc *l,
                                                      xrad_error *err);

typedef struct xrad_camera_desc {
    double position[3], look_at[3]; /* m, world */
    double up[3];                   /* default (0, 1, 0) */
    double fov_degrees;             /* vertical; default 45 */
    uint32_t width, height;         /* default image size; default 512 x 512 */
} xrad_camera_desc;

/* Without it the camera looks along +z at the whole scene. */
XRAD_API xrad_status xrad_scene_builder_set_camera(xrad_scene_builder *b, const xrad_camera_desc *c,
                                                   xrad_error *err);

/* Checks names, samples the elements and packs the atlas. On success *out
 * owns the scene and the builder is left empty (destroy it). */
XRAD_API xrad_status xrad_scene_builder_finish(xrad_scene_builder *b, xrad_scene **out,
                                               xrad_error *err);

typedef struct xrad_scene_info {
    uint32_t objects, dynamic_objects;
    uint32_t surfaces, materials;
    uint32_t elements, static_elements, dynamic_elements;
    uint32_t atlas_width, atlas_height; /* texels; one texel per element */
    double area;                        /* m^2, all surfaces */
    size_t cpu_bytes;                   /* host memory the scene holds */
    uint32_t planarised;                /* surfaces projected onto their best-fit plane */
    double planarise_max_offset;        /* m, largest vertex move that took */
    uint32_t triangles;                 /* surfaces that are triangles (the rest are quads) */
    uint32_t skipped_triangles;         /* zero-area mesh triangles left out */
    uint32_t meshes;                    /* triangle meshes (xrad_scene_get_mesh) */
    uint32_t albedo_maps;               /* materials with an albedo map */
    uint32_t mapped_elements;           /* elements whose albedo comes from one */
    uint32_t normal_maps;               /* materials with a normal map */
    uint32_t normal_mapped_elements;    /* elements whose normal comes from one */
    uint32_t normal_refined_surfaces;   /* surfaces split finer for their normal map's detail */
    uint32_t adaptive_refined_surfaces; /* split by adaptive subdivision (xrad_adaptive_desc) */
    uint32_t adaptive_partial_surfaces; /* of them, those whose visibility was partial */
    uint32_t luminaires;                /* xrad_scene_builder_add_luminaire, "luminaires" */
} xrad_scene_info;

XRAD_API void xrad_scene_get_info(const xrad_scene *scene, xrad_scene_info *info);

typedef struct xrad_object_info {
    const char *name; /* the file's object name; valid while the scene lives */
    int dynamic;      /* 1 for objects of set M (they move) */
    double offset[3]; /* m, the xrad_scene_set_offset displacement */
} xrad_object_info;

/* The box around every surface at scene time `time` (m, world). */
XRAD_API void xrad_scene_get_bounds(const xrad_scene *scene, double time, double lo[3],
                                    double hi[3]);

/* The scene's camera (the file's, or the builder's default): metres,
 * world; fov_degrees vertical; width x height its image size. */
XRAD_API void xrad_scene_get_camera(const xrad_scene *scene, xrad_camera_desc *out);

/* Object `index` (0 .. info.objects - 1) in file order; XRAD_ERROR_INPUT
 * for an index out of range. */
XRAD_API xrad_status xrad_scene_get_object(const xrad_scene *scene, uint32_t index,
                                           xrad_object_info *info, xrad_error *err);

/* Places dynamic object `index` by a rigid transform at every scene time,
 * in place of its animation and offset: `matrix` is object space to world,
 * column-major 4 x 4 (as xrad_scene_get_object_pose gives it); NULL gives
 * the animation back. A solver sees it at its next pose, as motion.
 * XRAD_ERROR_INPUT for a static object or a matrix that is not a rigid
 * transform (orthonormal within 1e-6, determinant +1, bottom row 0 0 0 1,
 * translation within 1e9 m). */
XRAD_API xrad_status xrad_scene_set_pose(xrad_scene *scene, uint32_t index,
                                         const double matrix[16], xrad_error *err);

/* Material `index`'s emission from now on (W/m^2, each in [0, 1e12]):
 * lights on, off, dimmed. A solver created later solves with it; the
 * real-time scheduler (xrad_vulkan.h) applies it to its running solver. */
XRAD_API xrad_status xrad_scene_set_emission(xrad_scene *scene, uint32_t index,
                                             const double emission[3], xrad_error *err);

/* Object `index`'s pose at scene time `time` (its animation and its
 * xrad_scene_set_offset, or its xrad_scene_set_pose): the object-space to world matrix, column-major
 * 4 x 4 (matrix[12..14] the translation), as GLSL's mat4 takes it. */
XRAD_API xrad_status xrad_scene_get_object_pose(const xrad_scene *scene, uint32_t index,
                                                double time, double matrix[16],
                                                xrad_error *err);

typedef struct xrad_material_info {
    const char *name;   /* valid while the scene lives */
    double albedo[3];   /* each in [0, 1) */
    double emission[3]; /* W/m^2, radiant exitance */
} xrad_material_info;

/* Material `index` (0 .. info.materials - 1); XRAD_ERROR_INPUT out of
 * range. */
XRAD_API xrad_status xrad_scene_get_material(const xrad_scene *scene, uint32_t index,
                                             xrad_material_info *info, xrad_error *err);

/* A surface and where its radiosity lies in the atlas (thesis 4.1).
 *
 * A surface is P(s, t) = (1-s)(1-t) p0 + s(1-t) p1 + s t p2 + (1-s) t p3
 * over s, t in [0, 1] (`corners`); a triangle has p3 == p2, its apex at
 * t = 1. It owns a tile of nu x nv texels from texel (tile_x, tile_y):
 * element (i, j) is texel (tile_x + i, tile_y + j) and samples the
 * surface at s = i / (nu - 1), t = j / (nv - 1), so the texel centres of
 * the outer rows lie on the surface's edges and bilinear filtering inside
 * the tile interpolates between samples. The point at (s, t) reads the
 * atlas (xrad_atlas, or the image a frame of the real-time loop shows) at
 *
 *     uv = (tile + 0.5 + (s, t) * (n - 1)) / atlas_size
 *
 * with tile = (tile_x, tile_y), n = (nu, nv) and atlas_size from
 * xrad_scene_info (a lone element, nu = nv = 1, reads its texel's
 * centre). To draw a surface with xrad's radiosity, give corner k, whose
 * parameters are (s_k, t_k) = (0, 0), (1, 0), (1, 1), (0, 1), the vertex
 * attribute a_k = (s_k w_k, t_k, w_k) with w_k = 1, except a triangle's
 * apex p2: a_2 = (0, 1, 0). Interpolated linearly over the surface's
 * triangles (p0 p1 p2, and p0 p2 p3 for a quad), a gives (s, t) exactly
 * for triangles and parallelogram quads:
 *
 *     layout(location = 1) in vec3 a;
 *     vec2 st = vec2(a.z > 0.0 ? a.x / a.z : 0.5, a.y);
 *     vec2 uv = (tile + 0.5 + st * (n - 1.0)) / atlas_size;
 *     vec3 radiosity = texture(atlas, uv).rgb; // W/m^2
 *
 * (a triangle's a.x / a.z undoes its collapse at the apex: s (1 - t) and
 * 1 - t interpolate linearly, s does not). */
typedef struct xrad_surface_info {
    const char *name;            /* valid while the scene lives */
    uint32_t object;             /* index of its object */
    uint32_t nu, nv;             /* element samples along its u and v edges */
    double length_u, length_v;   /* m, the u edge (p1 - p0) and v edge (p3 - p0); a
                                    triangle's u edge is its longest, v the next from p0 */
    double area;                 /* m^2 */
    int triangle;                /* 1: a triangle (mesh), 0: a quad */
    uint32_t material;           /* index (xrad_scene_get_material) */
    uint32_t tile_x, tile_y;     /* atlas texel of element (0, 0) */
    double corners[4][3];        /* m, object space: p0 .. p3 as drawn */
    double normal[3];            /* object space, unit: the side that emits and receives */
} xrad_surface_info;

/* Surface `index` (0 .. info.surfaces - 1); XRAD_ERROR_INPUT out of range. */
XRAD_API xrad_status xrad_scene_get_surface(const xrad_scene *scene, uint32_t index,
                                            xrad_surface_info *info, xrad_error *err);

/* A triangle mesh as the scene took it (xrad_scene_builder_add_mesh), so
 * that an engine can draw its own copy of it with xrad's radiosity, though
 * xrad joined pairs of its triangles into quads, turned each lone triangle
 * to put its longest edge first and left zero-area ones out. */
typedef struct xrad_mesh_info {
    const char *name;           /* xrad_mesh_desc.name; valid while the scene lives */
    uint32_t object;            /* index of its object */
    uint32_t triangle_count;    /* as given, skipped ones included */
    uint32_t skipped_triangles; /* zero-area triangles, on no surface */
} xrad_mesh_info;

/* Mesh `index` (0 .. info.meshes - 1), in the order they were added;
 * XRAD_ERROR_INPUT out of range. */
XRAD_API xrad_status xrad_scene_get_mesh(const xrad_scene *scene, uint32_t index,
                                         xrad_mesh_info *info, xrad_error *err);

/* One corner of a mesh triangle: the surface the triangle is part of and
 * the vertex attribute `a` of the surface's corner the vertex is (above,
 * xrad_surface_info): (s, t, 1) at a corner (s, t) of a quad or of a
 * triangle's base, (0, 1, 0) at a triangle's apex. A skipped (zero-area)
 * triangle has surface UINT32_MAX and a = 0. */
typedef struct xrad_mesh_corner {
    float a[3];
    uint32_t surface;
} xrad_mesh_corner;

/* Fills corners[3 t + k] for corner k of triangle t of mesh `mesh`, the
 * vertex indices[3 t + k] of the triangles as given; corner_count must be
 * 3 x triangle_count (else XRAD_ERROR_INPUT naming the field, as for a
 * mesh out of range). To draw the mesh with xrad's radiosity, draw its
 * triangles unindexed (or with their vertices split per triangle): a
 * triangle's vertex k takes corners[3 t + k].a as the attribute `a` of the
 * GLSL above, and the triangle, flat, its surface's tile_x, tile_y, nu and
 * nv (xrad_scene_get_surface) as `tile` and `n`; skip the triangles of
 * surface UINT32_MAX. The vertex positions stay the engine's, drawn in
 * its object's pose (xrad_scene_get_object_pose). `a` is exact at the
 * vertices; inside, a lone triangle gets (s, t) exactly, as does a joined
 * pair whose quad is a parallelogram. A joined pair's two triangles split
 * the quad along p1 p3 (not p0 p2 as xrad draws it), so in a quad that is
 * no parallelogram they read slightly different points than xrad's own
 * drawing does, still continuous across every edge.
 *
 * A model file xrad loads (xrad_scene_load of a .gltf, .glb, .obj or .ply,
 * or a scene file's "mesh": {"file": ...}) is added through the same
 * xrad_scene_builder_add_mesh, one mesh per mesh instance of the file's
 * node tree, named NAME.i: i counts the instances of that file from 0,
 * NAME is the scene file surface's "name" (a model loaded by itself: the
 * node's name, "node" if it has none), cut to 40 characters. Instances come
 * in assimp's node order, depth first from the root (or the scene
 * file's "node"): a node's meshes (aiNode.mMeshes in order), then its
 * children in order; scene-file placements in file order. A mesh's triangles are the assimp mesh's
 * three-index faces in face order after aiProcess_Triangulate |
 * aiProcess_JoinIdenticalVertices | aiProcess_SortByPType (a mesh of only
 * points or lines is no instance), corner k the face's mIndices[k], except
 * under a mirroring node transform (negative determinant), where corners
 * 1 and 2 are the face's mIndices[2] and mIndices[1] (the front side
 * kept). */
XRAD_API xrad_status xrad_scene_get_mesh_corners(const xrad_scene *scene, uint32_t mesh,
                                                 xrad_mesh_corner *corners,
                                                 uint32_t corner_count, xrad_error *err);

/* Displaces dynamic object `index` by `offset` (m, world) on top of its
 * animation, at every scene time: moving an object by hand. A solver sees
 * it at its next pose (xrad_solver_advance, xrad_solver_set_time) as motion
 * of the object; solvers keep what they need of the pose in hand, so the
 * offset may change between frames. XRAD_ERROR_INPUT for a static object,
 * an index out of range or a non-finite offset beyond 1e9 m. */
XRAD_API xrad_status xrad_scene_set_offset(xrad_scene *scene, uint32_t index,
                                           const double offset[3], xrad_error *err);

/* A radiosity solution in the scene's atlas layout: atlas_width x
 * atlas_height texels, RGBA float, row-major; texels that belong to no
 * element hold zero. Alpha is unused (1 on element texels). */
typedef struct xrad_atlas {
    uint32_t width, height;
    float *rgba;
} xrad_atlas;

/* Allocates a zeroed atlas of the scene's size. */
XRAD_API xrad_status xrad_atlas_create(const xrad_scene *scene, xrad_atlas *atlas, xrad_error *err);
XRAD_API void xrad_atlas_destroy(xrad_atlas *atlas);

/* ------------------------------------------------------------- photometry */

/* A luminaire's luminous intensity distribution, read from an EULUMDAT
 * (.ldt) or IES LM-63 (.ies, photometric type C) file by xrad's own
 * readers (Wallner 3.2): C-planes about the luminaire's downward axis,
 * gamma from straight down. Symmetric files are mirrored to the whole
 * circle; between samples the intensity is bilinear. Radiant intensity is
 * luminous intensity / 683 (W/sr from cd, Wallner eq. 12). */
typedef struct xrad_photometry xrad_photometry;

/* Errors name the file, the line and the field (XRAD_ERROR_INPUT). */
XRAD_API xrad_status xrad_photometry_load(const char *path, xrad_photometry **out,
                                          xrad_error *err);
/* Accepts NULL and *p == NULL; sets *p to NULL. */
XRAD_API void xrad_photometry_destroy(xrad_photometry **p);

typedef struct xrad_photometry_info {
    uint32_t c_planes;        /* over the whole circle after mirroring; 1: rotationally symmetric */
    uint32_t gamma_angles;
    double gamma_min, gamma_max; /* degrees; no light outside */
    double max_intensity;     /* cd, the largest sample */
    double max_c, max_gamma;  /* degrees, where it is */
    double flux_stated;       /* lm, the file's (LDT: lamps x light output ratio; IES: lamps x
                                 lumens per lamp); 0 where it states none */
    double flux;              /* lm, the integral of the intensity over the sphere */
    int tilt_ignored;         /* 1: an IES file's TILT=INCLUDE factors are not applied */
} xrad_photometry_info;

XRAD_API void xrad_photometry_get_info(const xrad_photometry *p, xrad_photometry_info *out);

/* cd towards (c, gamma), degrees; C wraps around the circle. */
XRAD_API double xrad_photometry_intensity(const xrad_photometry *p, double c_deg,
                                          double gamma_deg);

/* ------------------------------------------------------- reference solver */

/* Progress callback: `stage` names the phase, `fraction` is in [0, 1]. */
typedef void (*xrad_progress_fn)(void *user, const char *stage, double fraction);

/* The CPU reference solver: independent of the GPU code. Zero means default
 * in every field. */
/* How the reference decides what an element sees of another. */
#define XRAD_REFERENCE_CLIP_SURFACES 256
typedef enum xrad_visibility {
    /* Clipping for scenes of up to XRAD_REFERENCE_CLIP_SURFACES surfaces,
     * rays beyond (clipping culls occluders pair by pair, O(elements x
     * surfaces^2)). */
    XRAD_VISIBILITY_AUTO = 0,
    /* Exact: the visible part of each cell cut out by polygon clipping;
     * rays only where clipping gives up. */
    XRAD_VISIBILITY_CLIP,
    /* Every pair's visible fraction from `rays` stratified rays, traced
     * through a BVH (Embree): a Monte Carlo estimate that scales to meshes. */
    XRAD_VISIBILITY_RAYS,
} xrad_visibility;

/* How the reference solves B = E + rho F B. */
typedef enum xrad_reference_solver {
    /* DENSE where its matrix fits in 2 GiB (about 23,000 elements), else
     * GATHER. */
    XRAD_REFERENCE_SOLVER_AUTO = 0,
    /* Every form factor in a dense matrix (visibility as asked), then
     * Gauss-Seidel: exact up to the visibility's estimate, O(elements^2). */
    XRAD_REFERENCE_SOLVER_DENSE,
    /* No matrix, for meshes of 100K triangles and more: light from the
     * emitting surfaces by form factor and `rays` visibility rays per
     * (element, emitting surface); light from everything else by
     * `gather_rays` cosine-distributed rays per element traced through
     * Embree to the element they hit, then Gauss-Seidel over those hits.
     * Visibility is always by rays. Unbiased; each element's indirect
     * light carries Monte Carlo noise of about 1 / sqrt(gather_rays) of
     * its spread. */
    XRAD_REFERENCE_SOLVER_GATHER,
} xrad_reference_solver;

typedef struct xrad_reference_desc {
    double time;            /* s, scene time at which dynamic objects are posed; default 0 */
    xrad_reference_solver solver; /* default AUTO */
    uint32_t gather_rays;   /* GATHER: rays per element for light from non-emitters;
                               default 256 */
    xrad_visibility visibility; /* default AUTO */
    uint32_t rays;          /* clipping: rays per element pair where clipping gives up (a
                               shadow of too many pieces, a nearly edge-on occluder), rare;
                               default 16. Rays: rays per pair, default 64 */
    double residual;        /* stop when, in every RGB channel, max |delta B| / max B of a
                               sweep < this; default 1e-6 */
    uint32_t max_sweeps;    /* Gauss-Seidel sweeps at most; default 100000 */
    uint32_t cell_points;   /* DENSE: receiving points per cell side, at most 8: an element's
                               form factors are their mean over k x k points of its cell, its
                               radiosity the cell's mean (as the shooting methods' conservation
                               gives it); default 1: the cell's centre (README "Accuracy") */
    uint32_t threads;       /* worker threads; default: online cores */
    xrad_progress_fn progress;
    void *progress_user;
} xrad_reference_desc;

typedef struct xrad_reference_stats {
    double form_factor_seconds; /* wall time building the form factor matrix */
    double solve_seconds;       /* wall time in Gauss-Seidel */
    uint32_t sweeps;
    double residual;            /* achieved */
    double max_row_sum;         /* largest sum_j F_ij, a closure check */
    xrad_visibility visibility; /* the one used: CLIP or RAYS */
    uint32_t rays;              /* rays per pair (RAYS), or where clipping gave up (CLIP) */
    xrad_reference_solver solver; /* the one used: DENSE or GATHER */
    uint32_t gather_rays;       /* GATHER: rays per element */
} xrad_reference_stats;

/* Solves B = E + rho F B for all elements; writes B into `atlas` (created
 * with xrad_atlas_create). `stats` may be NULL. */
XRAD_API xrad_status xrad_reference_solve(const xrad_scene *scene, const xrad_reference_desc *desc,
                                          xrad_atlas *atlas, xrad_reference_stats *stats,
                                          xrad_error *err);

/* ------------------------------------------------------------ GPU context */

typedef struct xrad_context xrad_context;

/* Where a context's messages go: validation messages, warnings of the
 * solvers and of cleanup. Called from whichever thread uses the context
 * (the scheduler's worker too), so it must be thread-safe. */
typedef enum xrad_log_level {
    XRAD_LOG_ERROR,
    XRAD_LOG_WARNING,
    XRAD_LOG_INFO,
} xrad_log_level;
typedef void (*xrad_log_fn)(void *user, xrad_log_level level, const char *message);

typedef struct xrad_context_desc {
    /* Substring of the device name to use (case-insensitive); NULL: the
     * first discrete or integrated GPU, else the first device (lavapipe). */
    const char *device;
    /* Enable VK_LAYER_KHRONOS_validation: 1 on, 0 off. Messages are
     * counted (xrad_context_validation_messages) and logged as errors or
     * warnings. Missing layer with validation on is an error. */
    int validation;
    /* Presentation to a window (xrad view, or an application's own):
     * instance extensions to enable besides xrad's, e.g. what
     * glfwGetRequiredInstanceExtensions returns; each must be offered. */
    const char *const *instance_extensions;
    uint32_t instance_extension_count;
    /* 1: enable VK_KHR_swapchain on the device; a device without it is an
     * error (XRAD_ERROR_SYSTEM). */
    int present;
    /* MiB of device memory xrad may hold at once (a failed allocation past
     * it is XRAD_ERROR_SYSTEM, as a full device would be); 0: no limit of
     * its own. */
    double memory_limit_mib;
    /* Testing: make the Nth call of a Vulkan function fail,
     * "vkQueueSubmit:2:VK_ERROR_DEVICE_LOST"; NULL: none. */
    const char *fault;
    /* The hemicube path: NULL or "auto" (multiview where its start-up
     * check passes, else layered), "multiview" or "layered" (only that
     * path, still checked: a device that draws it wrongly is an error).
     * For comparing the two paths on one device. */
    const char *hemicube_path;
    /* NULL: messages go to stderr as "xrad: MESSAGE". */
    xrad_log_fn log;
    void *log_user;
} xrad_context_desc;

/* The environment the command-line tools honour, for an application that
 * wants the same: fills what `desc` leaves unset from XRAD_DEVICE,
 * XRAD_VALIDATION=1, XRAD_GPU_MEMORY_MIB, XRAD_FAULT and
 * XRAD_HEMICUBE_PATH. The library reads no environment variable otherwise.
 * XRAD_ERROR_INPUT names a malformed variable. */
XRAD_API xrad_status xrad_context_desc_from_env(xrad_context_desc *desc, xrad_error *err);

XRAD_API xrad_status xrad_context_create(const xrad_context_desc *desc, xrad_context **out,
                                         xrad_error *err);
/* Frees the context and sets *ctx to NULL. Every GPU wait is bounded (60 s);
 * one that runs out reports the GPU as hung (XRAD_ERROR_SYSTEM), and the
 * context then refuses all work. If the queue still has not finished 5 s
 * later, destroy leaves the device and its objects to process exit rather
 * than block on them (a driver may join its stuck queue thread). */
XRAD_API void xrad_context_destroy(xrad_context **ctx);

/* Validation messages of severity warning or error seen so far. */
XRAD_API uint32_t xrad_context_validation_messages(const xrad_context *ctx);

#define XRAD_MEMORY_CATEGORIES 8

/* GPU memory by what it is for: sizes of the live allocations (what xrad
 * asked for; blocks round them up), and their most since the context was
 * made or the peak was reset. */
typedef struct xrad_memory_stats {
    uint32_t count; /* categories */
    const char *names[XRAD_MEMORY_CATEGORIES]; /* "geometry", "radiosity", "render targets",
                                                  "staging", "redistribution", "other" */
    uint64_t bytes[XRAD_MEMORY_CATEGORIES];
    uint64_t peak[XRAD_MEMORY_CATEGORIES];
    uint64_t total, total_peak;
    uint64_t device_bytes; /* VkDeviceMemory held, all heaps */
} xrad_memory_stats;

XRAD_API void xrad_context_get_memory(xrad_context *ctx, xrad_memory_stats *out);
XRAD_API void xrad_context_reset_memory_peak(xrad_context *ctx);

/* The name of the chosen device. */
XRAD_API const char *xrad_context_device_name(const xrad_context *ctx);

typedef struct xrad_device_info {
    char name[256];
    const char *type; /* "discrete", "integrated", "virtual", "cpu", "other" */
    uint32_t api_version;
    uint64_t device_local_bytes;
} xrad_device_info;

/* Calls `fn` once per Vulkan physical device, in enumeration order. */
XRAD_API xrad_status xrad_devices_list(void (*fn)(void *user, const xrad_device_info *info),
                                       void *user, xrad_error *err);

/* ---------------------------------------------------------------- solvers */

typedef enum xrad_method {
    XRAD_METHOD_GATHER = 1,      /* thesis 4.2, Algorithm 4.1: a radiosity hemicube per element per bounce */
    XRAD_METHOD_PROGRESSIVE = 2, /* thesis 4.3, Algorithm 4.2 with the improvements of 4.3.3 */
    XRAD_METHOD_INCREMENTAL = 3, /* thesis 4.4, Algorithm 4.3 with reshooting (4.4.1) */
    XRAD_METHOD_CROSS = 4,       /* thesis 3.3 and 4.5, Algorithms 4.4 and 4.5 (CRR) */
} xrad_method;

/* "gather", "progressive", "incremental", "cross"; NULL for an unknown method. */
XRAD_API const char *xrad_method_name(xrad_method method);
/* The inverse; 0 for an unknown name. */
XRAD_API xrad_method xrad_method_from_name(const char *name);

/* GPU solver settings. Zero means default in every field. */
typedef struct xrad_solver_desc {
    xrad_method method;
    double time;             /* s, pose of dynamic objects; default 0 */
    uint32_t hemicube_res;   /* pixels per hemicube face side, even, 8..1024; default 64 */
    uint32_t msaa;           /* samples of radiosity hemicubes (gather): 1 or 4; default 4 */
    uint32_t bounces;        /* gather: Jacobi bounces; default 0 = until converged (threshold) */
    double threshold;        /* stop when the largest unshot power (progressive) or the light
                                the bounces still to come would add (gather: the last bounce's
                                power x r / (1 - r), r its ratio to the one before), relative
                                to the emitted power, is below this; default 1e-4 */
    double unshot;           /* progressive, and the dynamic methods' solves from B = E: stop
                                also only once all the unshot power, over every surface, is
                                below this share of the emitted power (1: no such test);
                                default 0.005 */
    uint32_t batch;          /* progressive: shots recorded per submission (one host wait per
                                batch); default 32 */
    uint32_t max_patches;    /* progressive: most shooting patches along a side of a surface
                                (dynamic shooter subdivision, thesis 4.3.3); default 0: 12 for
                                progressive, 8 for incremental and cross */
    double subdivide_ratio;  /* progressive: disk form factor subdivided when shooter area /
                                distance^2 exceeds this (thesis 4.3.3); default 0.01 */
    /* Hard stop of one call: shots (progressive; a frame's iterations
     * where frame_shots is 0) or bounces (gather); default 100000. */
    uint32_t max_iterations;
    uint32_t seed;           /* hemicube rotations (thesis 4.2); default 0 */
    /* Dynamic methods (incremental, cross): after each redistribution,
     * progressive iterations continue until the threshold is met or
     * frame_shots shots were made; default 0 = until the threshold. */
    uint32_t frame_shots;
    /* cross: rays per side over a dynamic patch in PROJECTEDRADIOSITY
     * (thesis 4.5.3 gridSize), 1..16; default 4. */
    uint32_t cross_grid;
    /* cross: the form factor from a receiver to a patch from which it
     * gets all cross_grid x cross_grid rays; a pair of smaller form factor
     * F gets ceil(cross_grid sqrt(F / cross_grid_ff)) a side, at least 1
     * (few rays far away, the full grid near). (0, 1]; default 0.02. */
    double cross_grid_ff;
    /* cross: pairs (receiver of C, patch of M) left out of the projection
     * (issue 16.1): a pair whose term F (B_s - P) can be at most
     * F max(B_s, Pmax) drops out where that is below cross_cut x Rmax,
     * Pmax the largest radiosity of C the back hemicubes show and Rmax the
     * larger of Pmax and every patch's B_s (F <= 1: no pair can carry
     * more). Each element loses at most cross_cut x Rmax x rho per patch.
     * [0, 0.1]; default 0 = no pair left out. */
    double cross_cut;
    /* cross: pixels per face side of the back hemicubes (thesis 4.5.2),
     * even, 8..256; default 16. */
    uint32_t back_res;
    /* cross: samples of the back hemicubes, 1 or 4; default 4 (the most
     * the hemicube pass offers; thesis 4.5.2: the highest available). */
    uint32_t back_msaa;
    /* cross: 1 samples the back hemicubes at the nearest texel instead of
     * bilinearly across the cube's face edges (thesis 4.5.2); default 0. */
    int back_nearest;
    /* cross: elements per submission of the cross projection; the
     * redistribution's hemicubes and gather become submissions of their
     * own too, so that other work on the queue (a display thread's frames,
     * xrad view) gets in between. Default 0: one submission. */
    uint32_t slice_elements;
    /* Visibility of a receiver in a shooter's ID hemicube: XRAD_ID_CHECK_*;
     * default 0 = NEIGHBOURS. */
    uint32_t id_check;
    /* Texel format of radiosity hemicubes (gather; cross's gather and back
     * hemicubes): XRAD_RADIOSITY_*; default 0 = FP16. */
    uint32_t radiosity_format;
    /* XRAD_AMBIENT_ON: xrad_solver_read adds the ambient term of the unshot
     * radiosity (Cohen et al. 1988) to B (progressive, incremental, cross);
     * default 0 = OFF. */
    uint32_t ambient;
    /* progressive shots (all methods but gather): XRAD_CONSERVE_ON (the
     * draft and interactive presets) scales a shooter's form factors so
     * that its receivers take what it sends (point form factors and
     * nearest-texel visibility take more or less). XRAD_CONSERVE_FAR (the
     * high and reference presets) scales only the receivers that see the
     * shooter by its centre's visibility: those that see it block by block
     * (near it, or cut by its plane) keep their exact form factors, each
     * block's visibility tested against every quad; more accurate, and
     * 1.5-1.8 times the shots' time (README "Conservation of a shot").
     * XRAD_CONSERVE_AUTO (default 0): FAR for every method (README "far
     * for every method"). */
    uint32_t conserve;
    /* progressive shots (all methods but gather) and gather's hemicubes:
     * XRAD_CULL_ON leaves out of each draw of hemicubes the clusters of
     * triangles behind every hemicube's base and the clusters of a closed
     * mesh's outside that face away from every origin (the picture does
     * not change; vertex work is the hemicube's cost). Default 0 = AUTO: on
     * for shots where the scene has at least XRAD_CULL_MIN_CLUSTERS
     * clusters of 256 triangles (in a scene of a few boxes the extra
     * dispatch costs more than it saves), off for gather (its batches of
     * neighbouring elements see nearly all of a room). */
    uint32_t cull;
    /* cross: XRAD_CROSS_PAIRS_ON lists, per patch, the elements of C that
     * see it (compaction and indirect dispatch), and traces the projection's
     * rays one invocation per listed pair in patch order; OFF (default 0)
     * loops over every patch per element, tracing where it sees it. The
     * solution is the same to the bit. On lavapipe (8 lanes, atomics on
     * the CPU) listing costs more than the idle lanes it saves: cornell-
     * large's projection took 524 ms a frame against 290 (README). */
    uint32_t cross_pairs;
    /* cross: XRAD_BACK_MIPS_ON reads the back hemicubes through mip levels
     * chosen per ray by the width of the cone it stands for where it meets
     * what lies behind the patch (thesis 6.2: mipmapped back hemicubes
     * against undersampling), so that a far receiver's few rays read the
     * mean of what the patch hides rather than a few texels of it; levels
     * halve back_res while it stays even. OFF: level 0 alone. */
    uint32_t back_mips;
    /* cross: when the moving objects M gather their light from C.
     * XRAD_CROSS_REGATHER_AFTER (default): once a frame, after its
     * progressive iterations, from C as they left it, so that a moving
     * object shows its surroundings of this frame; what M shoots to C in
     * a frame is its light of the last frame's gather, moved with it.
     * OFF: once, before the iterations (the thesis's order): M shows its
     * surroundings a frame late. ON: both, M's light gathered at the new
     * pose for what it shoots to C too (a gather hemicube per patch and
     * M's passes more a frame). */
    uint32_t cross_regather;
    /* Progress of the long parts, on the calling thread: gather's direct
     * light (at create) and its bounces, progressive's shots (per batch;
     * fraction: how far the unshot power has come down, on a log scale,
     * towards the stop), the dynamic methods' first solve; not the frames
     * of xrad_solver_advance. NULL: none. */
    xrad_progress_fn progress;
    void *progress_user;
} xrad_solver_desc;

enum {
    XRAD_CONSERVE_ON = 1,
    XRAD_CONSERVE_OFF = 2,
    XRAD_CONSERVE_FAR = 3,
    XRAD_CONSERVE_AUTO = 4,
};

enum {
    XRAD_CULL_ON = 1,
    XRAD_CULL_OFF = 2,
    XRAD_CULL_AUTO = 3,
};
#define XRAD_CULL_MIN_CLUSTERS 8

enum {
    XRAD_CROSS_PAIRS_OFF = 1,
    XRAD_CROSS_PAIRS_ON = 2,
};

enum {
    XRAD_BACK_MIPS_OFF = 1,
    XRAD_BACK_MIPS_ON = 2,
};

enum {
    XRAD_CROSS_REGATHER_OFF = 1,
    XRAD_CROSS_REGATHER_ON = 2,
    XRAD_CROSS_REGATHER_AFTER = 3,
};

enum {
    XRAD_AMBIENT_OFF = 1,
    XRAD_AMBIENT_ON = 2,
};

enum {
    /* The element's ID in the texel it projects to or one of the 8 around
     * it (thesis 4.3.3: no holes from sampling, shadows about a texel
     * smaller). */
    XRAD_ID_CHECK_NEIGHBOURS = 1,
    /* The projected texel only: sharper shadows, holes where an element is
     * thinner than a texel. */
    XRAD_ID_CHECK_EXACT = 2,
};

enum {
    XRAD_RADIOSITY_FP16 = 1, /* RGBA16F: half the memory and bandwidth, 11-bit mantissa */
    XRAD_RADIOSITY_FP32 = 2, /* RGBA32F */
};

/* ---------------------------------------------------------------- quality */

/* Everything that trades speed for accuracy: the solver's settings and the
 * element density the scene is built with. Zero means default in every
 * field. Each setting has a name (the scene file's "quality" key; on the
 * command line with dashes: --hemicube-res), a default and a range
 * (xrad_setting_info; README "Quality"). */
typedef struct xrad_quality {
    xrad_solver_desc solver;
    /* Every element density of the scene file (scene, object, surface and
     * cross densities) times this, at load (xrad_scene_load_with);
     * default 1. */
    double density_scale;
    /* Adaptive subdivision at load (xrad_scene_load_with); default off. */
    xrad_adaptive_desc adaptive;
} xrad_quality;

typedef enum xrad_setting_kind {
    XRAD_SETTING_INTEGER,
    XRAD_SETTING_REAL,
    XRAD_SETTING_CHOICE, /* one of `choices`, stored as its 1-based position */
} xrad_setting_kind;

typedef struct xrad_setting_info {
    const char *name;
    const char *description;
    xrad_setting_kind kind;
    double def, min, max; /* default and range (CHOICE: positions) */
    const char *choices;  /* CHOICE: "neighbours|exact"; else NULL */
    int min_open;         /* 1: min itself is not allowed, the range is (min, max] */
} xrad_setting_info;

/* The settings, in a fixed order; NULL past the last. */
XRAD_API const xrad_setting_info *xrad_setting_get(uint32_t index);
XRAD_API uint32_t xrad_setting_count(void);

/* Sets setting `name` from text ("128", "1e-3", "exact"). XRAD_ERROR_INPUT
 * naming the setting for an unknown name or a value out of its range. */
XRAD_API xrad_status xrad_quality_set(xrad_quality *q, const char *name, const char *value,
                                      xrad_error *err);

/* The setting's value as text, defaults filled in ("64", "neighbours"). */
XRAD_API xrad_status xrad_quality_format(const xrad_quality *q, const char *name, char *buf,
                                         size_t size, xrad_error *err);

/* Overwrites every setting with preset `name`: "draft", "interactive",
 * "high" or "reference" (README "Quality" lists their values). */
XRAD_API xrad_status xrad_quality_preset(xrad_quality *q, const char *name, xrad_error *err);

/* "draft, interactive, high, reference" */
XRAD_API const char *xrad_quality_preset_list(void);

/* Fills the defaults and checks every range, as xrad_solver_create does. */
XRAD_API xrad_status xrad_quality_resolve(xrad_quality *q, xrad_error *err);

/* The scene file's "quality" object (its preset, then its settings),
 * applied over q. */
XRAD_API void xrad_scene_get_quality(const xrad_scene *scene, xrad_quality *q);

#define XRAD_MAX_PASSES 16

typedef struct xrad_pass_time {
    char name[48];
    double ms;      /* GPU time from timestamp queries, summed */
    uint32_t count; /* intervals summed */
} xrad_pass_time;

typedef struct xrad_solver_stats {
    double gpu_ms;         /* sum of all pass times */
    double wall_ms;        /* host wall time of xrad_solver_solve */
    uint32_t hemicubes;    /* hemicubes rendered */
    uint32_t shots;        /* shooting patches shot (progressive) */
    uint32_t iterations;   /* shots selected (progressive) or bounces (gather) */
    uint32_t submissions;  /* command buffers submitted */
    uint32_t host_waits;   /* times the host waited for the GPU */
    double residual;       /* final unshot power or bounce change, relative */
    double unshot;         /* progressive: all unshot power at the last selection, relative
                              to the emitted */
    uint32_t surfaces_shot; /* progressive: surfaces shot (a shot's group counts each) */
    double redistribute_ms;  /* advance: host wall time of the redistribution alone (incremental,
                                cross); the rest of wall_ms is progressive iterations */
    const char *hemicube_path; /* "multiview" or "layered" */
    /* cross: patches on the dynamic objects (their cross_density, or
     * max_patches blocks a side where none is given; a dynamic mesh's faces
     * in groups) and on the lights, as created; a frame costs hemicubes
     * of each. */
    uint32_t cross_patches, cross_light_patches;
    /* cross: redistributions (and, with cross_regather after or on, the
     * gathers at a frame's end) made twice because the scale of the
     * radiosity hemicubes, taken from the last one, was more than 16x off
     * (C's light changed that much in a frame); a frame's redistribution
     * otherwise has no host wait for it */
    uint32_t cross_rescaled;
    /* cross: (element of C, patch) pairs that see each other, whose rays
     * the cross projection traced, over the call; and those of them the
     * pair list had no room for (their elements looped over every patch) */
    uint64_t cross_pairs, cross_pairs_unlisted;
    uint32_t pass_count;
    xrad_pass_time passes[XRAD_MAX_PASSES];
} xrad_solver_stats;

typedef struct xrad_solver xrad_solver;

XRAD_API xrad_status xrad_solver_create(xrad_context *ctx, const xrad_scene *scene,
                                        const xrad_solver_desc *desc, xrad_solver **out,
                                        xrad_error *err);
/* Accepts NULL and *solver == NULL; sets *solver to NULL. */
XRAD_API void xrad_solver_destroy(xrad_solver **solver);

/* Restarts from B = E and solves to the desc's threshold. */
XRAD_API xrad_status xrad_solver_solve(xrad_solver *solver, xrad_error *err);

/* One frame: poses dynamic objects at scene time `time` (s) and updates the
 * solution in hand to that pose. incremental redistributes from the
 * previous pose (thesis 4.4); cross replaces what the moving objects gave
 * the static ones at the previous pose by what they give at this one
 * (thesis 4.5); both continue with progressive iterations
 * (desc.frame_shots). The first call after create, without a solution,
 * solves instead; gather and progressive solve anew at the new pose. The
 * stats describe this frame. */
XRAD_API xrad_status xrad_solver_advance(xrad_solver *solver, double time, xrad_error *err);

/* Poses dynamic objects at scene time `time` (s) for the following solves;
 * the solution in hand is kept until the next xrad_solver_solve, but no
 * longer counts as a solution at the pose (the next advance solves anew). */
XRAD_API xrad_status xrad_solver_set_time(xrad_solver *solver, double time, xrad_error *err);

/* The current solution B in the scene's atlas layout. */
XRAD_API xrad_status xrad_solver_read(xrad_solver *solver, xrad_atlas *atlas, xrad_error *err);

XRAD_API void xrad_solver_get_stats(const xrad_solver *solver, xrad_solver_stats *stats);

/* ---------------------------------------------------------------- display */

typedef struct xrad_view_desc {
    uint32_t width, height; /* pixels; default: the scene camera's, else 512 x 512 */
    double time;            /* s, pose of dynamic objects; default 0 */
    int nearest;            /* 1: show elements as flat squares instead of bilinear */
} xrad_view_desc;

/* Draws the scene from its camera with `atlas` as surface radiosity and
 * returns the linear image: width x height RGBA float, row 0 at the top,
 * pixel value = B (W/m^2) of the visible surface, 0 where no surface is.
 * `*rgba` is malloc'd; free() it. */
XRAD_API xrad_status xrad_render_view(xrad_context *ctx, const xrad_scene *scene,
                                      const xrad_atlas *atlas, const xrad_view_desc *desc,
                                      float **rgba, uint32_t *width, uint32_t *height,
                                      xrad_error *err);

/* ------------------------------------------------------------------ images */

/* Linear 32-bit float RGBA OpenEXR (ZIP compressed). */
XRAD_API xrad_status xrad_image_write_exr(const char *path, const float *rgba, uint32_t width,
                                          uint32_t height, xrad_error *err);
/* Reads the R, G, B channels of a scanline OpenEXR (half or float) into
 * float RGBA with alpha 1; *rgba is malloc'd. */
XRAD_API xrad_status xrad_image_read_exr(const char *path, float **rgba, uint32_t *width,
                                         uint32_t *height, xrad_error *err);

/* xrad_image_write_exr with a fifth float channel `name` beside R, G, B, A:
 * `channel` holds width x height floats, row 0 at the top. xrad render
 * writes "emitter" this way: non-zero where the pixel shows an emitting
 * surface (xrad_image_compare leaves those pixels out). `name`: 1 to 31
 * printable characters, not R, G, B or A. channel NULL: the file
 * xrad_image_write_exr writes. */
XRAD_API xrad_status xrad_image_write_exr_channel(const char *path, const float *rgba,
                                                  const char *name, const float *channel,
                                                  uint32_t width, uint32_t height, xrad_error *err);
/* Reads channel `name` ("emitter", or "A" for the coverage xrad_image_read_exr
 * does not read) of a scanline OpenEXR (half or float, full resolution) into
 * width x height floats; *channel is malloc'd. A file without that channel
 * (an EXR written before it existed, or by another tool) is not an error:
 * XRAD_OK with *channel NULL; *width and *height are set either way. */
XRAD_API xrad_status xrad_image_read_exr_channel(const char *path, const char *name,
                                                 float **channel, uint32_t *width, uint32_t *height,
                                                 xrad_error *err);

/* How a linear value B becomes a display value in [0, 1] (before the sRGB
 * transfer), in the PNG writer and the window's present pass alike. */
typedef enum xrad_tonemap {
    /* clamp(exposure x B) */
    XRAD_TONEMAP_EXPOSURE = 0,
    /* Reinhard et al. 2002's global operator: C = exposure x B, L its Rec.
     * 709 luminance, then C / (1 + L), clamped (eq. 3 applied to the
     * luminance, the colour kept). Its automatic exposure is the key's,
     * xrad_image_key_exposure (eq. 1-2). */
    XRAD_TONEMAP_REINHARD = 1,
} xrad_tonemap;

/* "exposure" or "reinhard"; NULL for another value. */
XRAD_API const char *xrad_tonemap_name(xrad_tonemap tonemap);

/* 8-bit sRGB PNG of exposure * value, clamped (XRAD_TONEMAP_EXPOSURE).
 * exposure <= 0: automatic, see xrad_image_auto_exposure. */
XRAD_API xrad_status xrad_image_write_png(const char *path, const float *rgba, uint32_t width,
                                          uint32_t height, double exposure, xrad_error *err);

/* The same with either tone mapping; exposure <= 0: the tone mapping's
 * automatic one (xrad_image_tonemap_exposure). */
XRAD_API xrad_status xrad_image_write_png_tonemapped(const char *path, const float *rgba,
                                                     uint32_t width, uint32_t height,
                                                     xrad_tonemap tonemap, double exposure,
                                                     xrad_error *err);

/* Reads an 8-bit PNG (as xrad_image_write_png writes) into float RGBA:
 * sRGB decoded to linear values in [0, 1], alpha 1; *rgba is malloc'd.
 * Comparing two PNGs of one exposure compares exposure x B where B is not
 * clipped. */
XRAD_API xrad_status xrad_image_read_png(const char *path, float **rgba, uint32_t *width,
                                         uint32_t *height, xrad_error *err);

/* The exposure that maps the 95th percentile luminance of the non-zero
 * pixels to 0.8; 1 for an all-zero image. */
XRAD_API double xrad_image_auto_exposure(const float *rgba, uint32_t width, uint32_t height);

/* Reinhard et al. 2002's scale a / L_w (eq. 2) with the key a = 0.18: L_w
 * the log-average luminance of the non-zero pixels (eq. 1; the background
 * around a scene, zero, would otherwise set it); 1 for an all-zero image. */
XRAD_API double xrad_image_key_exposure(const float *rgba, uint32_t width, uint32_t height);

/* xrad_image_auto_exposure or xrad_image_key_exposure, as `tonemap` takes. */
XRAD_API double xrad_image_tonemap_exposure(xrad_tonemap tonemap, const float *rgba,
                                            uint32_t width, uint32_t height);

/* NRMSE of a against b: RMS over all pixels and RGB channels of (a - b),
 * divided by (max - min) of b's RGB values. Returns a negative value when b
 * is constant. */
XRAD_API double xrad_image_nrmse(const float *a, const float *b, uint32_t width, uint32_t height);

/* ----------------------------------------------------------------- metrics */

/* Image-space errors of an image `a` against a reference `b` (README
 * "Accuracy"). The thesis's NRMSE divides by the reference's range, so a
 * light in view hides large errors elsewhere; mean_ratio and rel_rms count
 * only pixels that show a non-emitting surface and say what a reader sees. */
typedef struct xrad_image_metrics {
    double nrmse;      /* xrad_image_nrmse over every pixel; < 0 when b is constant */
    double mean_ratio; /* sum of a / sum of b over the counted pixels, R + G + B */
    double rel_rms;    /* RMS over counted pixels and RGB of (a - b), / the mean of b there */
    uint64_t pixels;   /* counted: b's alpha > 0 and, with a mask, mask == 0 */
} xrad_image_metrics;

/* `emitter` (may be NULL): width x height floats, non-zero where the pixel
 * shows an emitting surface (xrad render writes it as the EXR's "emitter"
 * channel); those pixels are not counted. Background pixels (b's alpha 0)
 * are never counted. XRAD_ERROR_INPUT when no pixel is counted or b is zero
 * over them. */
XRAD_API xrad_status xrad_image_compare(const float *a, const float *b, const float *emitter,
                                        uint32_t width, uint32_t height, xrad_image_metrics *out,
                                        xrad_error *err);

/* Element-space errors of a solution against a reference solution of the
 * same scene (atlases of its layout; no camera). Emitting surfaces and
 * their elements are not counted. */
typedef struct xrad_element_metrics {
    /* Per surface: ratio = 1 + (mean a - mean b) / max(mean b, 1e-3 x the
     * scene's mean b), area-weighted means of R + G + B. */
    double surface_error;   /* max over counted surfaces of |ratio - 1| */
    uint32_t worst_surface; /* its index (xrad_scene_get_surface names it) */
    double worst_ratio;     /* its ratio */
    double mean_ratio;      /* area-weighted over every counted element */
    /* Element relative error |a - b| / max(b, 1e-3 x the scene's mean b),
     * R + G + B, over counted elements: percentiles by count. */
    double p50, p95, max;
    uint32_t surfaces, elements; /* counted */
} xrad_element_metrics;

/* `surface_ratio` (may be NULL): info.surfaces doubles, each surface's
 * ratio (1 for surfaces not counted). XRAD_ERROR_INPUT for atlases of
 * another size or a scene without a non-emitting element. */
XRAD_API xrad_status xrad_atlas_compare(const xrad_scene *scene, const xrad_atlas *a,
                                        const xrad_atlas *b, xrad_element_metrics *out,
                                        double *surface_ratio, xrad_error *err);

#ifdef __cplusplus
}
#endif

#endif
