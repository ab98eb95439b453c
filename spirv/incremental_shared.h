/*
 * Incremental radiosity layouts shared by C (src/passes/
 * incremental_reconstruct.c, src/solvers/incremental.c) and GLSL
 * (spirv/incremental_reconstruct.comp). Same rules as shared.h.
 *
 * Buffers:
 *   shooters[k]  gpu_shooter      one table: the patches of M at the old pose
 *                                 first, then the shooting patches of C
 *                                 (written by the host; `radiosity` unused)
 *   values[k]    incr_value       what shooter k shoots, captured before any
 *                                 of the redistribution's shots changes it;
 *                                 for C also `lit`, what M takes from it
 *   m_light[e]   vec4             M's light on element e of C at the new
 *                                 pose, from M's radiosity of the old (what
 *                                 the iterations will shoot anew), and after
 *                                 INCREMENT that reflected once more by C:
 *                                 what M takes with C's light
 *   power[s]     float            per surface: |luminance(sum_e B_e A_e)| on
 *                                 C, 0 on M (host-visible, read once per solve
 *                                 to fix C's patches)
 *   ids_old/new  R32_UINT arrays  the chunk's ID hemicubes at the old and the
 *                                 new pose; shooter first + h in layers h*5..
 *   luminaires[e] vec4            host-written per pose where the scene has
 *                                 luminaires (push `luminaires`): rho x their
 *                                 direct light at the new pose on M, its
 *                                 change from the old pose on C (RESET)
 */
#ifndef XRAD_SPIRV_INCREMENTAL_SHARED_H
#define XRAD_SPIRV_INCREMENTAL_SHARED_H

#include "shared.h"

struct incr_value {
    vec4 shot;   /* area mean of B - Bu over the patch */
    vec4 unshot; /* area mean of Bu */
    vec4 total;  /* area mean of B */
    vec4 lit;    /* C: area mean of B + m_light after INCREMENT: what M takes */
};

/* incremental_reconstruct.comp modes */
#define INCR_MODE_CAPTURE 0u   /* per shooter in [first, first + count): values = means */
#define INCR_MODE_POWER 1u     /* per surface: power = |luminance(sum B A)| on C, 0 on M */
#define INCR_MODE_RESET 2u     /* per element: M: B = Bu = E + luminaires; C: Bu = luminaires */
#define INCR_MODE_NEGATIVE 3u  /* per element of C: -shot of the chunk's M shooters, old pose */
#define INCR_MODE_INCREMENT 4u /* per element of C: lines 22-37 for the chunk's C shooters */
#define INCR_MODE_CAPTURE_LIT 5u /* per shooter in [first, first + count): mean(B + m_light) */
#define INCR_MODE_CLEAR 6u       /* per element: m_light = 0 */
#define INCR_MODE_M_LIGHT 7u     /* per element of C: m_light += the chunk's M shooters, new pose */
#define INCR_MODE_RECEIVE_M 8u   /* per element of M: lines 13-18 for the chunk's C shooters */

#define INCR_BINDING_SURFACES 0
#define INCR_BINDING_ELEMENTS 1
#define INCR_BINDING_MATERIALS 2
#define INCR_BINDING_B 3
#define INCR_BINDING_BU 4
#define INCR_BINDING_SHOOTERS 5
#define INCR_BINDING_VALUES 6
#define INCR_BINDING_POWER 7
#define INCR_BINDING_OLD_SURFACES 8 /* the surfaces at the old pose */
#define INCR_BINDING_M_LIGHT 9      /* vec4[element_count]: M's light on C, new pose */
#define INCR_BINDING_LUMINAIRES 10  /* vec4[element_count] (any buffer without luminaires) */
#define INCR_BINDING_IDS_OLD 11     /* images from here on */
#define INCR_BINDING_IDS_NEW 12
#define INCR_BINDING_COUNT 13

#define INCR_GROUP 64u

struct incr_push {
    uint mode;
    uint count;         /* invocations (CAPTURE, POWER, RESET) or shooters in the chunk */
    uint first;         /* first shooter of the chunk / of the captured range */
    uint element_count;
    uint hemicube_res;  /* pixels per face side of the ID hemicubes */
    uint neighbours;    /* 1: nearest-texel visibility check (thesis 4.3.3) */
    float subdivide_ratio; /* exact form factor where A_s / r^2 exceeds this (4.3.3) */
    uint luminaires;       /* 1: RESET adds the luminaires buffer */
};

#endif
