/*
 * The cross solver's hooks for tests (src/solvers/cross.c,
 * spirv/cross_reconstruct.comp): the pair list read back (the (element,
 * patch) pairs the last cross projection listed, each element's range in
 * them, the patches at that pose and what the contribution bound used),
 * and every light drawn at every pose. Internal; the method itself is
 * reached through xrad_solver_*.
 */
#ifndef XRAD_SOLVERS_CROSS_H
#define XRAD_SOLVERS_CROSS_H

#include <stdint.h>

#include "cross_shared.h"
#include "radiosity.h"
#include "xrad.h"

typedef struct cross_pair_readback {
    uint32_t patch_count, element_count;
    uint32_t pair_count;        /* listed by the last submission of step 5 */
    struct cross_pair *pairs;   /* [pair_count] */
    uint32_t *ranges;           /* [2 element_count]: first pair, count or CROSS_RANGE_*
                                   (elements of M: not written) */
    struct cross_quad *quads;   /* [patch_count]: world corners at that pose */
    struct gpu_shooter *fronts; /* [patch_count]: centre and normal */
    struct cross_value *values; /* [patch_count]: the totals step 5 used */
    float peak;                 /* the largest |B - Bu - E| of C it used (cross_cut) */
} cross_pair_readback;

/* A cross solver made with cross_pairs on, after a solve or an advance. */
xrad_status cross_read_pairs(xrad_solver *s, cross_pair_readback *out, xrad_error *err);
/* Accepts a zeroed struct; zeroes it. */
void cross_pair_readback_free(cross_pair_readback *r);

/* Tests: every light's hemicube with M drawn and read at every pose, as
 * if M could reach them all (what the cut by the lights' planes must equal). */
void cross_draw_every_light(xrad_solver *s);

/* Tests: progressive_draw_counts of the solver's shots (C alone: both
 * must be the static scene's index count, not the whole scene's). */
void cross_shot_draw_counts(xrad_solver *s, uint32_t *host, uint32_t *command);

#endif
