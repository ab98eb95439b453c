/*
 * The built scene: what parse -> validate -> build produces, and what every
 * solver, the reference and the display read. Host-side, double precision,
 * metres. Nothing here knows about Vulkan.
 *
 * Element atlas (thesis 4.1, figure 4.1.2; DESIGN.md "Data model"): a surface
 * of nu x nv elements owns a tile of nu x nv texels. Element (i, j) samples
 * the surface at parameters s = i / (nu - 1), t = j / (nv - 1), so the texel
 * centres of the outer rows lie on the surface edges and adjacent coplanar
 * surfaces share boundary samples. Each element stands for the part of the
 * surface within half a sample spacing of its sample (clipped to the
 * surface): edge elements carry half, corner elements a quarter of an inner
 * element's area, and the areas of a surface sum to its area.
 *
 * A triangle is the quad collapsed at its apex, p[3] == p[2] (a Duffy
 * map): s runs along its longest edge p0 p1, t towards the apex. Its tile
 * is nu x nv texels like a quad's, every texel an element (the cells of
 * the apex row are thin slivers), so the bilinear display finds a value
 * in every texel it reads and no gap needs filling (Wallner 3.1 fills the
 * texels a rasterised triangle leaves out). The areas are exact: the
 * Jacobian is linear in t, constant in s.
 *
 * A triangle no longer than one sample spacing either way (a tiny mesh
 * face) has nu = nv = 1: one element, one texel, sampled and evaluated
 * at its centroid (s = 1/2, t = 1/3), standing for the whole triangle.
 * Quads always have at least 2 x 2.
 */
#ifndef XRAD_SCENE_H
#define XRAD_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "core/vec.h"
#include "xrad.h"

#define SCENE_NAME_MAX 64
#define SCENE_MAX_QUALITY 16

typedef struct material {
    char name[SCENE_NAME_MAX];
    vec3 albedo;   /* each channel in [0, 1) */
    vec3 emission; /* W/m^2 radiant exitance, each channel >= 0 */
} material;

typedef struct keyframe {
    double time;      /* s, strictly increasing within an animation */
    vec3 translation; /* m, added to the object's base translation */
} keyframe;

/* Pose at time t: translate(keys(t)) * base * rotate_about_pivot(axis, rate t).
 * The rotation acts in object space about `pivot` (object space, m); the
 * keyframed translation is piecewise linear and, with `loop`, repeats with
 * the period of the last key's time. Without keys there is no translation. */
typedef struct animation {
    bool rotates;
    vec3 axis;  /* unit */
    vec3 pivot; /* m, object space */
    double rate; /* rad/s */
    uint32_t keyframe_count;
    keyframe *keyframes;
    bool loop;
} animation;

typedef struct object {
    char name[SCENE_NAME_MAX];
    bool dynamic; /* set M of thesis 3.1; static objects form set C */
    xform base;   /* object space -> world at rest */
    animation anim;
    uint32_t first_surface, surface_count;
    uint32_t first_element, element_count;
    /* Element density (per metre) the cross-redistribution method uses for
     * this object's shooters (thesis 5.1: CRR uses fewer elements on the box
     * than the other methods); 0: not given, use the object's elements. */
    double cross_density;
    /* Elements the object would have at cross_density (same counting rule
     * as its own elements); 0 when cross_density is 0. */
    uint32_t cross_element_count;
    double density; /* elements per metre its surfaces default to */
    /* m, world: added to the pose at every time (xrad_scene_set_offset: an
     * application moving the object by hand); zero from the file. */
    vec3 offset;
    /* xrad_scene_set_pose: object space -> world at every time, in place of
     * the animation and the offset. */
    bool posed;
    xform pose;
} object;

/* A planar convex quad with a bilinear parametrisation
 * P(s, t) = (1-s)(1-t) p[0] + s(1-t) p[1] + s t p[2] + (1-s) t p[3].
 * p[1] - p[0] is the "u" edge, p[3] - p[0] the "v" edge; the front side is
 * along normal = normalize((p[1] - p[0]) x (p[3] - p[0])) (for a non-
 * parallelogram, the Newell normal, same orientation). Light is emitted and
 * received on the front side only. */
typedef struct surface {
    char name[SCENE_NAME_MAX];
    uint32_t object;
    uint32_t material;
    vec3 p[4];     /* m, object space */
    vec3 normal;   /* object space, unit */
    double area;   /* m^2 */
    uint32_t nu, nv; /* element samples along s and t, each >= 2, or 1 x 1 (a tiny triangle) */
    uint32_t first_element;
    uint32_t tile_x, tile_y; /* atlas texel of element (0, 0) */
    double planarise_offset; /* m moved to make the quad planar; 0 if it was */
    /* m: the file's vertex k is p[k] + planarise_dist[k] * normal (all 0
     * when it was planar). The display pass draws the file's vertices so
     * that a planarised quad still meets its neighbours (display.c). */
    double planarise_dist[4];
    bool triangle; /* p[3] == p[2], the apex (see the top of this file) */
    bool mesh;     /* from a triangle mesh (xrad_scene_builder_add_mesh): a triangle or a
                      joined pair; cross groups a dynamic mesh's faces into patches */
    bool closed;   /* a face of a closed mesh with its fronts outside (every edge shared by
                      two of its triangles, walked opposite ways; positive volume): seen from
                      outside, its back faces lie behind its front faces (the hemicube cull
                      pass, solvers/hemicube_clusters.h) */
} surface;

/* Where the corners of a mesh's triangle went (xrad_scene_get_mesh_corners):
 * the surface it became (UINT32_MAX: skipped, zero area) and, for its
 * corner k (the vertex indices[3 t + k] as given), the surface's corner
 * slot 0..3 (p[slot]) at that vertex. */
typedef struct mesh_triangle {
    uint32_t surface;
    uint8_t slot[3];
} mesh_triangle;

/* A triangle mesh as xrad_scene_builder_add_mesh took it. */
typedef struct scene_mesh {
    char name[SCENE_NAME_MAX];
    uint32_t object;
    uint32_t triangle_count, skipped_triangles;
    mesh_triangle *triangles; /* triangle_count */
} scene_mesh;

/* Elements are stored surface by surface, object by object, row-major
 * within a surface: index = surface.first_element + j * nu + i. */
typedef struct element {
    vec3 pos;          /* m, object space sample point (corner samples moved inward slightly) */
    double area;       /* m^2 */
    uint32_t surface;
    uint16_t i, j;     /* sample index within the surface */
    uint32_t texel_x, texel_y; /* atlas texel */
} element;

/* A luminaire (xrad_luminaire_desc): a point emitter, world space. */
typedef struct luminaire {
    char name[SCENE_NAME_MAX];
    vec3 position;         /* m, world */
    vec3 aim, c0, c90;     /* unit frame: gamma = 0, the C = 0 and C = 90 planes */
    vec3 intensity;        /* W/sr (point, spot), or the file's cd / 683 x scale per channel */
    struct photometry *photometry; /* NULL: point or spot */
    double cos_outer, cos_inner; /* spot: 0 beyond the outer cone, full within the inner;
                                    cos_outer -2: a point light */
} luminaire;

typedef struct camera {
    vec3 position, look_at, up; /* m, world */
    double fov_y;               /* radians, vertical */
    uint32_t width, height;     /* default image size, pixels */
} camera;

struct xrad_scene {
    char path[512]; /* the file it came from, for messages */
    double unit;    /* metres per file unit */
    double density; /* default elements per metre */

    uint32_t material_count;
    material *materials;
    uint32_t object_count;
    object *objects;
    uint32_t surface_count;
    surface *surfaces;
    uint32_t element_count;
    element *elements;
    /* Per element, where a surface's material has an albedo map (xrad.h
     * xrad_material_desc.albedo_map): the material's albedo times the
     * texture's mean over the element (scene_texture.c); NULL in a scene
     * without one. Read it through scene_element_albedo. */
    vec3 *element_albedo;
    uint32_t albedo_maps, mapped_elements; /* xrad_scene_info */
    /* Per element, where a surface's material has a normal map (xrad.h
     * xrad_material_desc.normal_map): the unit object-space normal of
     * every cosine the element takes as a receiver (Wallner 3.3;
     * scene_texture.c); NULL in a scene without one. Read it through
     * scene_element_normal. */
    vec3 *element_normal;
    uint32_t normal_maps, normal_mapped_elements;
    uint32_t normal_refined_surfaces; /* split for their map's detail (scene_builder.c) */
    /* Split by adaptive subdivision, and of them those whose visibility
     * from an emitter was partial (scene_adaptive.c). */
    uint32_t adaptive_refined_surfaces, adaptive_partial_surfaces;
    uint32_t luminaire_count;
    luminaire *luminaires;

    uint32_t atlas_width, atlas_height;
    camera cam;

    char name[SCENE_NAME_MAX]; /* the file's "name"; empty if none */

    /* The file's "quality" (xrad_scene_get_quality): its preset and its
     * settings as text, in file order. */
    char quality_preset[16];
    uint32_t quality_count;
    char quality_name[SCENE_MAX_QUALITY][48];
    char quality_value[SCENE_MAX_QUALITY][64];
    double density_scale; /* what the densities were multiplied by */
    uint32_t skipped_triangles; /* zero-area mesh triangles left out */
    uint32_t mesh_count;
    scene_mesh *meshes; /* every xrad_scene_builder_add_mesh, in order */
    uint32_t warning_count;
    char **warnings; /* xrad_scene_warning */
};

/* The albedo element `e` reflects with: its texture's mean where its
 * material has an albedo map, else its material's. */
static inline vec3 scene_element_albedo(const xrad_scene *scene, uint32_t e)
{
    if (scene->element_albedo)
        return scene->element_albedo[e];
    return scene->materials[scene->surfaces[scene->elements[e].surface].material].albedo;
}

/* The receiver normal of element `e`, object space: its normal map's
 * where its material has one, else its surface's. */
static inline vec3 scene_element_normal(const xrad_scene *scene, uint32_t e)
{
    if (scene->element_normal)
        return scene->element_normal[e];
    return scene->surfaces[scene->elements[e].surface].normal;
}

/* The bilinear parametrisation of a surface, object space. */
vec3 surface_point(const surface *s, double u, double v);

/* Object space -> world for `object` at scene time `t` (see animation). */
xform scene_object_pose(const xrad_scene *scene, uint32_t object, double t);

/* The object-space bounds of `object`'s surfaces (every corner). */
void scene_object_box(const xrad_scene *scene, uint32_t object, vec3 *lo, vec3 *hi);

/* What xrad_scene_set_pose and xrad_scene_set_emission accept, checked
 * without changing the scene (the scheduler checks requests on the
 * application's thread while its worker poses the scene): *out receives
 * the pose (may be NULL). */
xrad_status scene_check_pose(const xrad_scene *scene, uint32_t index, const double matrix[16],
                             xform *out, xrad_error *err);
xrad_status scene_check_emission(const xrad_scene *scene, uint32_t index,
                                 const double emission[3], xrad_error *err);

/* World-space corners and normal of a surface at time t. */
void scene_surface_world(const xrad_scene *scene, uint32_t surface, double t,
                         vec3 corners[4], vec3 *normal);

/* The parameter interval [lo, hi] of samples i0..i1 of n along a side:
 * within half a spacing of them, clipped to [0, 1]; a lone sample (n = 1)
 * stands for the whole side. */
void scene_param_range(uint32_t i0, uint32_t i1, uint32_t n, double *lo, double *hi);

/* The parameters (s, t) of element (i, j)'s receiver point: the midpoint
 * of its cell, and a tiny triangle's centroid for its one element. */
void scene_cell_centre(const surface *sf, uint32_t i, uint32_t j, double *s, double *t);

/* The receiver point of element e of surface s, object space: the
 * centroid of its cell (the part of the surface it stands for). Every
 * solver, GPU and CPU, evaluates an element there. */
vec3 scene_element_centroid(const surface *s, const element *e);

/* Contact: sets buried[e] (element_count bytes) for every element whose
 * receiver point lies on the front face of another surface facing it, face
 * to face within `tol` m and more than `tol` inside its edges (a point on
 * the edge sees out on one side) at scene time `time` (the bottom of a box standing
 * on a floor, and the floor under it): 1 where a surface of a static object
 * covers it, else 2 where a dynamic one does, else 0. Such a receiver sees
 * the cover edge-on and nothing past it: no light reaches it. `count`
 * receives how many are buried. */
xrad_status scene_find_buried(const xrad_scene *scene, double time, double tol,
                              uint8_t *buried, uint32_t *count, xrad_error *err);

/* Contact that closes nothing: pairs of quads (not mesh faces, whose
 * winding and cracks rays cannot judge) face to face in one plane
 * (scene_find_buried's rule, at the solvers' tolerance) where neither
 * side of a covered point is closed (most of 25 rays about either normal
 * meet something other than a back face first): a slab of zero thickness (a table top of two quads back to back,
 * one room's floor and another's ceiling in one plane) rather than a solid
 * standing on a surface, whose volume lies behind one of them. The GPU
 * methods take both as a contact and light neither there; the CPU
 * reference lights both. *pairs (malloc'd, free it) receives 2 surface
 * indices per pair, lower first; *count the pairs. */
xrad_status scene_find_flat_slabs(const xrad_scene *scene, double time, uint32_t **pairs,
                                  uint32_t *count, xrad_error *err);

/* Enclosure: sets enclosed[e] (element_count bytes) for every element of
 * a static object that no light reaches: 25 rays spread over its
 * hemisphere (the normal and 4 rings of 6) find what it sees, and light
 * spreads from the emitters' elements and from rays that leave the scene
 * along rays that meet a front face, both ways, until nothing changes.
 * What stays dark lies inside a closed volume, no face touching it
 * (scene_find_buried): the floor under a plinth without a bottom face, the
 * floor and wall inside a cabinet standing against the wall without a
 * back face. Only static surfaces count. With no static emitter (a
 * moving lamp) only elements whose every ray meets a back face count as
 * enclosed. The rays go through a BVH of the surfaces (quad_bvh.h), so
 * the cost follows the elements: scenes of more than
 * SCENE_ENCLOSED_MAX_ELEMENTS are not tested (every element open; the
 * 406,135 elements heavy-sphere had before its triangles became one
 * element each took 35 s). `count` receives how many are
 * enclosed. */
#define SCENE_ENCLOSED_MAX_ELEMENTS 100000u
xrad_status scene_find_enclosed(const xrad_scene *scene, uint8_t *enclosed, uint32_t *count,
                                xrad_error *err);

/* The same at scene time `time` for what moving objects close in: sets
 * enclosed[e] for every element of a static object, within a dynamic
 * object's bounds and not in static_enclosed (scene_find_enclosed's
 * result, or NULL), that no light reaches with the dynamic surfaces posed
 * at `time` among what the rays meet (the floor under a moving box
 * without a bottom face). A patch shooting from there would see only the
 * box's inside: its light was lost (room 1 of tests/solvers/rooms.c). */
xrad_status scene_find_enclosed_dynamic(const xrad_scene *scene, double time,
                                        const uint8_t *static_enclosed, uint8_t *enclosed,
                                        uint32_t *count, xrad_error *err);

#endif
