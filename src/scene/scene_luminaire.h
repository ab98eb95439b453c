/*
 * Luminaires (issue 18.3, xrad_luminaire_desc): point emitters with an
 * intensity distribution (a photometric file, or a point or spot light),
 * and the direct light they give the elements, which every method and
 * the CPU reference start from (Wallner 3.2: the luminaire shoots first).
 */
#ifndef XRAD_SCENE_LUMINAIRE_H
#define XRAD_SCENE_LUMINAIRE_H

#include "core/error.h"
#include "scene/scene.h"

#define SCENE_MAX_LUMINAIRES 1000u

/* Checks `d` (where: "luminaire 'NAME': ") and fills *out, loading its
 * file; errors name the field. */
xrad_status scene_luminaire_setup(const xrad_luminaire_desc *d, const char *where, luminaire *out,
                                  xrad_error *err);
void scene_luminaire_free(luminaire *l);

/* W/sr per channel that `l` sends along the unit direction `dir`. */
vec3 scene_luminaire_intensity(const luminaire *l, vec3 dir);

/* Adds to out[e] (vec3 per element, W/m^2) the luminaires' direct
 * irradiance at element e's sample point at scene time `time`: the sum
 * over the luminaires of I cos(theta) / d^2, where the segment from the
 * point to the luminaire crosses no surface; nothing at a buried element
 * (scene_find_buried). Without `dynamic_too` only the static objects'
 * surfaces block and bury (the light of the static scene alone, which
 * the cross method solves). A scene without luminaires adds nothing. The
 * element reflects rho_e times it. */
xrad_status scene_luminaire_irradiance(const xrad_scene *scene, double time, bool dynamic_too,
                                       vec3 *out, xrad_error *err);

/* out[e] = rho_e x the irradiance above, for every element: the light an
 * element reflects of the luminaires', what it starts a solve with. */
xrad_status scene_luminaire_reflected(const xrad_scene *scene, double time, bool dynamic_too,
                                      vec3 *out, xrad_error *err);

#endif
