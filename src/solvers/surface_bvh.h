/*
 * The hierarchy over the posed surfaces that the shaders' segment tests
 * walk (struct gpu_bvh_node, spirv/shooting.glsl SHOOTING_BVH): the tree of
 * scene/quad_bvh.h, built once from the surfaces at the scene's first
 * pose, its boxes refitted to the surfaces at every pose (rigid motions
 * keep every surface, so the tree stays valid; a moving object only makes
 * the boxes over it and its neighbours at the first pose larger, which
 * costs steps, not answers).
 */
#ifndef XRAD_SOLVERS_SURFACE_BVH_H
#define XRAD_SOLVERS_SURFACE_BVH_H

#include <stdint.h>

#include "radiosity.h"
#include "scene/quad_bvh.h"
#include "xrad.h"

/* Over surfaces[0, n) as posed there; *depth its levels. Fails where the
 * tree is deeper than a shader's traversal stack (GPU_BVH_STACK; median
 * splits never are). */
xrad_status surface_bvh_build(const struct gpu_surface *surfaces, uint32_t n, quad_bvh *out,
                              uint32_t *depth, xrad_error *err);

/* out[bvh->node_count]: the tree's nodes with boxes over the surfaces as
 * posed in `surfaces`, each grown by `pad` (m) so that a flat quad's box
 * has a thickness and float rounding in the slab test loses no hit. With
 * no node (no surfaces), out[0] is a node no segment meets. */
void surface_bvh_refit(const quad_bvh *bvh, const struct gpu_surface *surfaces, float pad,
                       struct gpu_bvh_node *out);

#endif
