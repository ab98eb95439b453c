/*
 * The layout of every struct C shares with GLSL (the headers in spirv/), held to the
 * std430 rules the shaders read them by (Vulkan spec 15.6.4, "Offset and
 * Stride Assignment"): scalars at multiples of 4, vec4 and mat4 at
 * multiples of 16, arrays of vec4 with a stride of 16, a struct's size
 * rounded up to its largest member alignment (an array of them in a
 * buffer has that stride). C lays out vec4 (shared.h) as four floats
 * aligned to 4, so a vec4 after an odd number of scalars would sit 16
 * bytes off where the shader reads it: these assertions stop the build
 * instead. The offsets below were worked out by those rules from the
 * declarations; a changed struct needs them worked out again.
 */
#include <stddef.h>

#include "atlas_scatter_shared.h"
#include "cross_shared.h"
#include "direct_shared.h"
#include "hemicube_cull_shared.h"
#include "hemicube_shared.h"
#include "incremental_shared.h"
#include "integrate_shared.h"
#include "radiosity.h"
#include "reconstruct_shared.h"
#include "select_shared.h"
#include "shared.h"

#define LAYOUT(s, m, off)                                                                         \
    _Static_assert(offsetof(struct s, m) == (off), #s "." #m ": std430 puts it at " #off)
#define SIZE(s, n) _Static_assert(sizeof(struct s) == (n), #s ": std430 size " #n)

/* spirv/atlas_scatter_shared.h */
LAYOUT(atlas_scatter_push, element_count, 0);
LAYOUT(atlas_scatter_push, pad0, 4);
LAYOUT(atlas_scatter_push, pad1, 8);
LAYOUT(atlas_scatter_push, pad2, 12);
SIZE(atlas_scatter_push, 16);

/* spirv/cross_shared.h */
LAYOUT(cross_patch, surface, 0);
LAYOUT(cross_patch, i0, 4);
LAYOUT(cross_patch, i1, 8);
LAYOUT(cross_patch, j0, 12);
LAYOUT(cross_patch, j1, 16);
LAYOUT(cross_patch, ci, 20);
LAYOUT(cross_patch, cj, 24);
LAYOUT(cross_patch, cx, 28);
LAYOUT(cross_patch, cy, 32);
LAYOUT(cross_patch, member_first, 36);
LAYOUT(cross_patch, member_count, 40);
LAYOUT(cross_patch, pad0, 44);
SIZE(cross_patch, 48);
LAYOUT(cross_value, total, 0);
SIZE(cross_value, 16);
LAYOUT(cross_quad, corner, 0);
SIZE(cross_quad, 64);
LAYOUT(cross_pair, element, 0);
LAYOUT(cross_pair, patch_index, 4);
LAYOUT(cross_pair, ff, 8);
LAYOUT(cross_pair, value, 16);
SIZE(cross_pair, 32);
LAYOUT(cross_pair_state, count, 0);
LAYOUT(cross_pair_state, listed, 4);
LAYOUT(cross_pair_state, scatter, 16);
LAYOUT(cross_pair_state, eval, 32);
SIZE(cross_pair_state, 48);
LAYOUT(cross_update_push, mode, 0);
LAYOUT(cross_update_push, count, 4);
LAYOUT(cross_update_push, element_count, 8);
LAYOUT(cross_update_push, patch_count, 12);
LAYOUT(cross_update_push, res, 16);
LAYOUT(cross_update_push, inv_scale, 20);
LAYOUT(cross_update_push, diameter, 24);
SIZE(cross_update_push, 32);
LAYOUT(cross_reconstruct_push, element_count, 0);
LAYOUT(cross_reconstruct_push, patch_count, 4);
LAYOUT(cross_reconstruct_push, hemicube_res, 8);
LAYOUT(cross_reconstruct_push, back_res, 12);
LAYOUT(cross_reconstruct_push, grid, 16);
LAYOUT(cross_reconstruct_push, bilinear, 20);
LAYOUT(cross_reconstruct_push, phase, 24);
LAYOUT(cross_reconstruct_push, neighbours, 28);
LAYOUT(cross_reconstruct_push, subdivide_ratio, 32);
LAYOUT(cross_reconstruct_push, inv_scale, 36);
LAYOUT(cross_reconstruct_push, diameter, 40);
LAYOUT(cross_reconstruct_push, first, 44);
LAYOUT(cross_reconstruct_push, count, 48);
LAYOUT(cross_reconstruct_push, light_count, 52);
LAYOUT(cross_reconstruct_push, grid_ff, 56);
LAYOUT(cross_reconstruct_push, pair_capacity, 60);
LAYOUT(cross_reconstruct_push, cut, 64);
LAYOUT(cross_reconstruct_push, back_levels, 68);
LAYOUT(cross_reconstruct_push, luminaires, 72);
SIZE(cross_reconstruct_push, 76);
LAYOUT(back_mips_push, res, 0);
LAYOUT(back_mips_push, levels, 4);
LAYOUT(back_mips_push, count, 8);
SIZE(back_mips_push, 16);

/* spirv/direct_shared.h */
LAYOUT(direct_push, first, 0);
LAYOUT(direct_push, count, 4);
LAYOUT(direct_push, light_first, 8);
LAYOUT(direct_push, light_count, 12);
LAYOUT(direct_push, accumulate, 16);
LAYOUT(direct_push, pad0, 20);
LAYOUT(direct_push, pad1, 24);
LAYOUT(direct_push, pad2, 28);
SIZE(direct_push, 32);

/* spirv/hemicube_cull_shared.h */
LAYOUT(gpu_cluster, center, 0);
LAYOUT(gpu_cluster, half_size, 16);
LAYOUT(gpu_cluster, cone_axis, 32);
LAYOUT(gpu_cluster, object_lo, 48);
LAYOUT(gpu_cluster, object_hi, 64);
LAYOUT(gpu_cluster, first_index, 80);
LAYOUT(gpu_cluster, index_count, 84);
LAYOUT(gpu_cluster, pad0, 88);
LAYOUT(gpu_cluster, pad1, 92);
SIZE(gpu_cluster, 96);
LAYOUT(cull_push, cluster_count, 0);
LAYOUT(cull_push, first, 4);
LAYOUT(cull_push, count_word, 8);
LAYOUT(cull_push, instances, 12);
LAYOUT(cull_push, instance_word, 16);
LAYOUT(cull_push, margin, 20);
LAYOUT(cull_push, count, 24);
LAYOUT(cull_push, pad0, 28);
SIZE(cull_push, 32);

/* spirv/hemicube_shared.h */
LAYOUT(gpu_hemicube_vertex, x, 0);
LAYOUT(gpu_hemicube_vertex, y, 4);
LAYOUT(gpu_hemicube_vertex, z, 8);
LAYOUT(gpu_hemicube_vertex, surface, 12);
LAYOUT(gpu_hemicube_vertex, triangle, 16);
SIZE(gpu_hemicube_vertex, 20);
LAYOUT(gpu_hemicube_triangle, uvw, 0);
LAYOUT(gpu_hemicube_triangle, tile, 48);
LAYOUT(gpu_hemicube_triangle, sign, 64);
LAYOUT(gpu_hemicube_triangle, pad0, 68);
LAYOUT(gpu_hemicube_triangle, pad1, 72);
LAYOUT(gpu_hemicube_triangle, pad2, 76);
SIZE(gpu_hemicube_triangle, 80);
LAYOUT(hemicube_push, first, 0);
LAYOUT(hemicube_push, hemicube, 4);
LAYOUT(hemicube_push, count_word, 8);
LAYOUT(hemicube_push, pad0, 12);
LAYOUT(hemicube_push, near, 16);
LAYOUT(hemicube_push, hair, 20);
LAYOUT(hemicube_push, scale, 24);
LAYOUT(hemicube_push, depth_scale, 28);
SIZE(hemicube_push, 32);

/* spirv/incremental_shared.h */
LAYOUT(incr_value, shot, 0);
LAYOUT(incr_value, unshot, 16);
LAYOUT(incr_value, total, 32);
LAYOUT(incr_value, lit, 48);
SIZE(incr_value, 64);
LAYOUT(incr_push, mode, 0);
LAYOUT(incr_push, count, 4);
LAYOUT(incr_push, first, 8);
LAYOUT(incr_push, element_count, 12);
LAYOUT(incr_push, hemicube_res, 16);
LAYOUT(incr_push, neighbours, 20);
LAYOUT(incr_push, subdivide_ratio, 24);
LAYOUT(incr_push, luminaires, 28);
SIZE(incr_push, 32);

/* spirv/integrate_shared.h */
LAYOUT(integrate_push, res, 0);
LAYOUT(integrate_push, out_first, 4);
LAYOUT(integrate_push, count, 8);
LAYOUT(integrate_push, inv_scale, 12);
LAYOUT(integrate_push, ring, 16);
LAYOUT(integrate_push, ring_first, 20);
LAYOUT(integrate_push, pad0, 24);
LAYOUT(integrate_push, pad1, 28);
SIZE(integrate_push, 32);

/* spirv/radiosity.h */
LAYOUT(gpu_surface, corner, 0);
LAYOUT(gpu_surface, normal_area, 64);
LAYOUT(gpu_surface, first_element, 80);
LAYOUT(gpu_surface, nu, 84);
LAYOUT(gpu_surface, nv, 88);
LAYOUT(gpu_surface, material, 92);
LAYOUT(gpu_surface, object, 96);
LAYOUT(gpu_surface, dynamic, 100);
LAYOUT(gpu_surface, tile_x, 104);
LAYOUT(gpu_surface, tile_y, 108);
LAYOUT(gpu_surface, patches_s, 112);
LAYOUT(gpu_surface, patches_t, 116);
LAYOUT(gpu_surface, patch_first, 120);
LAYOUT(gpu_surface, mesh, 124);
SIZE(gpu_surface, 128);
LAYOUT(gpu_element, pos_area, 0);
LAYOUT(gpu_element, normal, 16);
LAYOUT(gpu_element, surface, 32);
LAYOUT(gpu_element, texel_x, 36);
LAYOUT(gpu_element, texel_y, 40);
LAYOUT(gpu_element, flags, 44);
LAYOUT(gpu_element, albedo, 48);
SIZE(gpu_element, 64);
LAYOUT(gpu_bvh_node, lo, 0);
LAYOUT(gpu_bvh_node, hi, 16);
LAYOUT(gpu_bvh_node, first, 32);
LAYOUT(gpu_bvh_node, count, 36);
LAYOUT(gpu_bvh_node, pad0, 40);
LAYOUT(gpu_bvh_node, pad1, 44);
SIZE(gpu_bvh_node, 48);
LAYOUT(gpu_material, albedo, 0);
LAYOUT(gpu_material, emission, 16);
SIZE(gpu_material, 32);
LAYOUT(gpu_shooter, pos_area, 0);
LAYOUT(gpu_shooter, normal, 16);
LAYOUT(gpu_shooter, tangent, 32);
LAYOUT(gpu_shooter, radiosity, 48);
LAYOUT(gpu_shooter, surface, 64);
LAYOUT(gpu_shooter, i0, 68);
LAYOUT(gpu_shooter, i1, 72);
LAYOUT(gpu_shooter, j0, 76);
LAYOUT(gpu_shooter, j1, 80);
LAYOUT(gpu_shooter, hemicube, 84);
LAYOUT(gpu_shooter, group, 88);
LAYOUT(gpu_shooter, shot_first, 92);
SIZE(gpu_shooter, 96);

/* spirv/reconstruct_shared.h */
LAYOUT(reconstruct_push, element_count, 0);
LAYOUT(reconstruct_push, hemicube_res, 4);
LAYOUT(reconstruct_push, neighbours, 8);
LAYOUT(reconstruct_push, mode, 12);
LAYOUT(reconstruct_push, subdivide_ratio, 16);
LAYOUT(reconstruct_push, max_shooters, 20);
LAYOUT(reconstruct_push, conserve_fixed, 24);
LAYOUT(reconstruct_push, static_only, 28);
LAYOUT(reconstruct_push, redistributed, 32);
LAYOUT(reconstruct_push, near_blocks, 36);
SIZE(reconstruct_push, 40);

/* spirv/select_shared.h */
LAYOUT(select_status, draw_index_count, 0);
LAYOUT(select_status, draw_instance_count, 4);
LAYOUT(select_status, draw_first_index, 8);
LAYOUT(select_status, draw_vertex_offset, 12);
LAYOUT(select_status, draw_first_instance, 16);
LAYOUT(select_status, dispatch_x, 20);
LAYOUT(select_status, dispatch_y, 24);
LAYOUT(select_status, dispatch_z, 28);
LAYOUT(select_status, shooter_count, 32);
LAYOUT(select_status, surface, 36);
LAYOUT(select_status, kx, 40);
LAYOUT(select_status, ky, 44);
LAYOUT(select_status, converged, 48);
LAYOUT(select_status, power, 52);
LAYOUT(select_status, max_power, 56);
LAYOUT(select_status, unshot, 60);
LAYOUT(select_status, max_unshot, 64);
LAYOUT(select_status, selections, 68);
LAYOUT(select_status, patches, 72);
LAYOUT(select_status, surfaces, 76);
SIZE(select_status, 80);
LAYOUT(select_push, surface_count, 0);
LAYOUT(select_push, element_count, 4);
LAYOUT(select_push, max_patches, 8);
LAYOUT(select_push, max_shooters, 12);
LAYOUT(select_push, draw_index_count, 16);
LAYOUT(select_push, instances_per_hemicube, 20);
LAYOUT(select_push, seed, 24);
LAYOUT(select_push, reconstruct_group, 28);
LAYOUT(select_push, threshold, 32);
LAYOUT(select_push, linear_rule, 36);
LAYOUT(select_push, buried_mask, 40);
LAYOUT(select_push, unshot_share, 44);
LAYOUT(select_push, group_shooters, 48);
LAYOUT(select_push, group_elements, 52);
LAYOUT(select_push, shot_first, 56);
LAYOUT(select_push, pad0, 60);
SIZE(select_push, 64);

/* spirv/shared.h */
LAYOUT(display_push, clip_from_view, 0);
LAYOUT(display_push, atlas_size, 64);
LAYOUT(display_push, mode, 80);
LAYOUT(display_push, pad0, 84);
LAYOUT(display_push, pad1, 88);
LAYOUT(display_push, pad2, 92);
SIZE(display_push, 96);
LAYOUT(present_push, exposure, 0);
LAYOUT(present_push, encode, 4);
LAYOUT(present_push, tonemap, 8);
LAYOUT(present_push, pad0, 12);
SIZE(present_push, 16);
LAYOUT(overlay_push, scale_x, 0);
LAYOUT(overlay_push, scale_y, 4);
LAYOUT(overlay_push, offset_x, 8);
LAYOUT(overlay_push, offset_y, 12);
SIZE(overlay_push, 16);
