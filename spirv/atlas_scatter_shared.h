/*
 * Atlas scatter pass layouts shared by C (src/passes/atlas_scatter.c) and
 * GLSL (spirv/atlas_scatter.comp). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_ATLAS_SCATTER_SHARED_H
#define XRAD_SPIRV_ATLAS_SCATTER_SHARED_H

#include "shared.h"

#define ATLAS_SCATTER_BINDING_ELEMENTS 0 /* struct gpu_element[]: texel of each element */
#define ATLAS_SCATTER_BINDING_VALUES 1   /* vec4[]: what to write, per element */
#define ATLAS_SCATTER_BINDING_ATLAS 2    /* rgba32f storage image, GENERAL */

#define ATLAS_SCATTER_GROUP 64u

struct atlas_scatter_push {
    uint element_count;
    uint pad0, pad1, pad2;
};

#endif
