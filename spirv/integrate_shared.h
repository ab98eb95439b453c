/*
 * Integrate pass layouts shared by C (src/passes/integrate.c) and GLSL
 * (spirv/integrate.comp). Same rules as shared.h.
 */
#ifndef XRAD_SPIRV_INTEGRATE_SHARED_H
#define XRAD_SPIRV_INTEGRATE_SHARED_H

#include "shared.h"

#define INTEGRATE_BINDING_HEMICUBES 0 /* 2D array, layer = hemicube * 5 + face, sampled */
#define INTEGRATE_BINDING_TABLE 1     /* float[5 * res * res]: delta form factors */
#define INTEGRATE_BINDING_OUT 2       /* vec4[]: one sum per hemicube */

#define INTEGRATE_GROUP 256u /* one workgroup per hemicube */

struct integrate_push {
    uint res;       /* pixels per face side */
    uint out_first; /* sum of hemicube h goes to out[out_first + h] */
    uint count;     /* hemicubes */
    float inv_scale; /* the hemicubes hold B x scale: sums are multiplied by 1 / scale */
    /* Non-zero: also the horizon ring's mean radiosity (solid-angle
     * weighted, directions within about 15 degrees above the horizon) to
     * out[ring_first + h]. */
    uint ring;
    uint ring_first;
    uint pad0, pad1;
};

#endif
