/*
 * GPU radiosity state shared by C and GLSL: the scene as the solvers' passes
 * see it, and the tables that pass shooters between them. std430; every
 * struct is a multiple of 16 bytes made of vec4s and 4-byte scalars, so C
 * and GLSL agree without padding rules.
 *
 * Buffers (one each, indexed by the ids below):
 *   surfaces[surface]   gpu_surface     world-space geometry at the current pose
 *   elements[element]   gpu_element     world-space sample points
 *   materials[material] gpu_material
 *   B[element], Bu[element]  vec4       total and unshot radiosity, rgb, fp32
 *   shooters[k]         gpu_shooter     the patches being shot (select pass output)
 *   bvh_nodes, bvh_items  gpu_bvh_node, uint  a hierarchy over the surfaces
 */
#ifndef XRAD_SPIRV_RADIOSITY_H
#define XRAD_SPIRV_RADIOSITY_H

#include "shared.h"

/* Quad ids written into ID hemicubes are surface index + 1; 0 is "nothing". */
#define HEMICUBE_ID_NONE 0u

struct gpu_surface {
    vec4 corner[4];   /* world xyz of the bilinear corners p0..p3 (scene.h) */
    vec4 normal_area; /* world unit normal, area m^2 */
    uint first_element, nu, nv, material;
    uint object, dynamic, tile_x, tile_y;
    /* Shooting patches along s and t when this surface shoots (select
     * pass); 0: the power decides (dynamic shooter subdivision, thesis
     * 4.3.3). The dynamic methods fix them to the layout their
     * redistribution removes with (solvers/dynamic_patches.h), and
     * patch_first numbers the surface's first patch in that layout: patch
     * k of the surface turns its hemicube by patch_rotation(seed,
     * patch_first + k) whoever shoots it, so that removal and insertion
     * see through the same hemicube texels. */
    uint patches_s, patches_t, patch_first;
    uint mesh; /* GPU_SURFACE_MESH: a face of a triangle mesh (scene.h surface.mesh);
                  GPU_SURFACE_TRIANGLE as well where it is a triangle */
};

#define GPU_SURFACE_MESH 1u
#define GPU_SURFACE_TRIANGLE 2u

struct gpu_element {
    vec4 pos_area; /* world sample point (corner samples moved inward), area m^2 */
    vec4 normal;   /* world unit normal of its surface, w = 0 */
    uint surface, texel_x, texel_y, flags; /* GPU_ELEMENT_* */
    vec4 albedo;   /* rgb the element reflects with: its material's, or its albedo map's
                      mean over it (scene.h element_albedo); w = 0 */
};

/* The element's receiver point lies on another surface's front face, face
 * to face (scene_find_buried): no light reaches it, it keeps its emission.
 * BURIED: under a surface of a static object; BURIED_M: under a moving one
 * at the pose the buffers hold (cross takes such light away itself). */
#define GPU_ELEMENT_BURIED 1u
#define GPU_ELEMENT_BURIED_M 2u
#define GPU_ELEMENT_BURIED_ANY 3u

/* A node of the bounding volume hierarchy over the surfaces at the
 * buffers' pose (solvers/gpu_scene.h), for segment tests against every
 * surface (spirv/shooting.glsl, SHOOTING_BVH): a loop over the surfaces
 * made each such test thousands of iterations on a mesh scene, and
 * lavapipe ends every loop of an invocation once 65,535 iterations have
 * run in all, silently (gather's direct light on a 192-light furnace came
 * out 46% low). A leaf: count items from items[first]; an inner node:
 * count 0, children first and first + 1. */
struct gpu_bvh_node {
    vec4 lo; /* xyz: box corner, grown by a margin; w unused */
    vec4 hi;
    uint first, count, pad0, pad1;
};

/* Entries of a traversal stack: the hierarchy's depth (median splits:
 * at most log2 of the surface count, 17 at 100K surfaces) plus one. */
#define GPU_BVH_STACK 40u

struct gpu_material {
    vec4 albedo;   /* rgb in [0, 1) */
    vec4 emission; /* rgb W/m^2 */
};

/* A shooting patch (thesis 4.3.3): a rectangle of elements [i0, i1] x
 * [j0, j1] of one surface, its centre and frame, and what it shoots. */
struct gpu_shooter {
    vec4 pos_area;   /* world centre, patch area m^2 */
    vec4 normal;     /* world unit normal */
    vec4 tangent;    /* world unit tangent, randomly rotated about the normal (thesis 4.2) */
    vec4 radiosity;  /* rgb radiosity shot (area-weighted mean over the patch) */
    uint surface, i0, i1, j0;
    uint j1, hemicube; /* hemicube: layer block of its ID hemicube */
    uint group;        /* 1: a group of a dynamic mesh's faces (cross; solvers/
                          dynamic_patches.h), not a block of surface's elements */
    uint shot_first;   /* where its surface's unshot radiosity starts in the select
                          pass's `shot` (progressive; 0 elsewhere) */
};

#endif
