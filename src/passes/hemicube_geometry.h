/*
 * Hemicube conventions shared by every hemicube pass (render, integrate,
 * reconstruct, cross-project) and mirrored in spirv/hemicube.glsl.
 *
 * A hemicube sits at a shooter (or gathering element) with a local frame:
 * z = surface normal, x = tangent (randomly rotated about z per hemicube,
 * thesis 4.2), y = z cross x. It has 5 faces, each R x R pixels:
 *
 *   face 0: top, looks along +z     right +x, up +y
 *   face 1: looks along +x          right +y, up +z
 *   face 2: looks along -x          right -y, up +z
 *   face 3: looks along +y          right -x, up +z
 *   face 4: looks along -y          right +x, up +z
 *
 * A local direction d maps to face f with forward axis F, right axis Rt and
 * up axis U when dot(d, F) is its largest component; normalised face
 * coordinates a = dot(d, Rt) / dot(d, F), b = dot(d, U) / dot(d, F), both in
 * [-1, 1]; pixel column (a + 1) / 2 * R, row (b + 1) / 2 * R. The render pass
 * writes gl_Position = (dot(d, Rt), dot(d, U), near, dot(d, F)), so Vulkan's
 * rasteriser puts the same direction in the same pixel (NDC y = -1 is row 0).
 * On side faces rows with b < 0 lie below the horizon and get zero weight.
 */
#ifndef XRAD_PASSES_HEMICUBE_GEOMETRY_H
#define XRAD_PASSES_HEMICUBE_GEOMETRY_H

#include <stdint.h>

#include "core/vec.h"

#define HEMICUBE_FACES 5

/* Right, up and forward axes of face f, in the local frame. */
void hemicube_face_axes(int face, vec3 *right, vec3 *up, vec3 *forward);

/* Face and pixel of a local direction with d.z > 0; returns the face. */
int hemicube_lookup(vec3 d, uint32_t res, uint32_t *px, uint32_t *py);

/* Fills table[face * res * res + row * res + col] with each pixel's exact
 * delta form factor: the form factor from the hemicube's centre (normal z)
 * to the pixel's square, by Lambert's formula for a differential area to a
 * polygon (the same integral that dA / (pi (x^2 + y^2 + 1)^2) approximates at
 * the pixel centre, Cohen and Greenberg 1985; thesis 2.2.2). Pixels below the
 * horizon are 0. The pixels partition the visible hemisphere, so the table
 * sums to 1 up to rounding. `res` must be even. */
void hemicube_delta_form_factors(uint32_t res, float *table);

/* Deterministic rotation angle in [0, 2 pi) about the normal for the
 * hemicube with this seed (thesis 4.2: random rotation breaks up aliasing
 * patterns of many hemicubes). */
double hemicube_rotation(uint32_t seed);

/* The rotation of the hemicube of fixed shooting patch `index`
 * (gpu_surface.patch_first + k), the same for every pass that shoots it
 * (spirv/select.comp computes it too). */
double patch_rotation(uint32_t seed, uint32_t index);

#endif
