/*
 * The fixed shooting patches of the dynamic set M (thesis 4.5.1: the cross
 * method does not substructure M; thesis 5.1: it uses fewer elements on
 * the moving object than the other methods), shared by the dynamic
 * methods. Each dynamic surface is cut into cx x cy blocks of its
 * elements, cx x cy the sample counts its object's cross_density gives
 * (scene.h; without one, the counts of a density of 4 per object diagonal,
 * at most max_patches), at most the element counts, each block one patch; patch (ci, cj) also owns the coarse
 * sample (ci, cj) of the surface (spirv/cross_shared.h). Host only: the
 * layout is fixed at build, the frames are made per pose.
 */
#ifndef XRAD_SOLVERS_DYNAMIC_PATCHES_H
#define XRAD_SOLVERS_DYNAMIC_PATCHES_H

#include <stdint.h>

#include "cross_shared.h"
#include "radiosity.h"
#include "scene/scene.h"
#include "solvers/gpu_scene.h"
#include "xrad.h"

#define DYNAMIC_PATCH_NONE 0xffffffffu

typedef struct dynamic_patches {
    uint32_t count;
    /* [count]: blocks surface by surface, row-major in (ci, cj); then the
     * groups (cross_shared.h) */
    struct cross_patch *patches;
    /* [surface_patch_size]: per surface, patch (0, 0) of a dynamic surface
     * (a grouped face: its group), else NONE; then the groups' members */
    uint32_t *surface_patch;
    uint32_t surface_patch_size;
} dynamic_patches;

/* The layout for `scene`; max_patches (>= 1) bounds the sides of surfaces
 * whose object has no cross_density. With `groups` (cross), the faces of
 * dynamic meshes (surface.mesh) are grouped instead, about 1 /
 * cross_density a side, faces of one cone of normals together (without
 * cross_density, a quarter of the object's diagonal): a group's one
 * patch shoots the area mean of its faces from a hemicube above them all
 * (dynamic_patches_pose). Incremental keeps blocks: its select pass cuts
 * surfaces, not groups. A scene without dynamic surfaces has count 0 (and
 * allocates nothing). */
xrad_status dynamic_patches_build(const xrad_scene *scene, uint32_t max_patches, bool groups,
                                  dynamic_patches *out, xrad_error *err);
/* The same kind of layout for the static emitters (the lights of C;
 * cross.c's direct light): each surface with emission cut into blocks by
 * its size against the scene's diameter (m), 16 per diameter, at least one
 * and at most max_patches and one element per block a side. ci, cj, cx, cy
 * as above; no coarse samples. */
xrad_status dynamic_patches_build_lights(const xrad_scene *scene, uint32_t max_patches,
                                         double diameter, dynamic_patches *out,
                                         xrad_error *err);
/* Accepts a zeroed struct; zeroes it. */
void dynamic_patches_free(dynamic_patches *dp);

/* Incremental: shoots M with this layout in progressive iterations too (cross
 * leaves M out of them): the select pass
 * then cuts every dynamic surface into the same blocks, so that what a
 * redistribution removes with these patches is what was shot, block for
 * block (gpu_scene_fix_patches). Call before progressive_create. */
xrad_status dynamic_patches_fix(struct xrad_context *ctx, gpu_scene *gs,
                                const dynamic_patches *dp, xrad_error *err);

/* The hemicube frame of the fixed patch numbered `index` (its rotation,
 * patch_rotation) covering elements [i0, i1] x [j0, j1] of a surface at
 * scene time t, built as spirv/select.comp builds a shooter: centre
 * bilinear at the middle of the block's parameter range, area the block's
 * element areas summed, tangent the u edge projected onto the surface's
 * plane and turned; `hemicube` = index. With quad, also the block's world
 * corners. The dynamic methods make every shooter of a fixed layout here. */
void fixed_patch_frame(const xrad_scene *scene, uint32_t surface, uint32_t i0, uint32_t i1,
                       uint32_t j0, uint32_t j1, uint32_t index, uint32_t seed, double t,
                       struct gpu_shooter *frame, struct cross_quad *quad);

/* The patches posed at scene time t, each array [count] (any may be
 * NULL): front hemicube frames (patch centre, surface normal; tangent the
 * u edge turned by a fixed angle per patch, thesis 4.2, so that a pose
 * renders the same hemicubes whenever it is rendered), back frames (same
 * centre and tangent, normal reversed), gather frames (the centroid of the
 * coarse sample's cell, as the gather method places its hemicubes) and the
 * patch quads. Frames' `hemicube` is the patch index, `radiosity` 0. */
void dynamic_patches_pose(const xrad_scene *scene, const dynamic_patches *dp, double t,
                          uint32_t seed, struct gpu_shooter *front, struct gpu_shooter *back,
                          struct gpu_shooter *gather, struct cross_quad *quads);

#endif
