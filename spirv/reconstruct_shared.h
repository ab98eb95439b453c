/*
 * Reconstruct pass layouts shared by C (src/passes/reconstruct.c) and GLSL
 * (spirv/reconstruct.comp). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_RECONSTRUCT_SHARED_H
#define XRAD_SPIRV_RECONSTRUCT_SHARED_H

#include "shared.h"

#define RECONSTRUCT_BINDING_SURFACES 0
#define RECONSTRUCT_BINDING_ELEMENTS 1
#define RECONSTRUCT_BINDING_MATERIALS 2
#define RECONSTRUCT_BINDING_B 3
#define RECONSTRUCT_BINDING_BU 4
#define RECONSTRUCT_BINDING_SHOOTERS 5
#define RECONSTRUCT_BINDING_STATUS 6     /* struct select_status: shooter_count */
#define RECONSTRUCT_BINDING_HEMICUBES 7  /* R32_UINT 2D array, layer = hemicube * 5 + face */
#define RECONSTRUCT_BINDING_COUNT 8

#define RECONSTRUCT_GROUP 64u /* one invocation per receiving element */

struct reconstruct_push {
    uint element_count;
    uint hemicube_res;    /* pixels per face side */
    uint neighbours;      /* 1: nearest-texel visibility check (thesis 4.3.3) */
    uint pad0;
    float subdivide_ratio; /* exact form factor where A_s / r^2 exceeds this (4.3.3) */
    float pad1, pad2, pad3;
};

#endif
