/* Element-space error figures from plain arrays (the scene layer gathers
 * them: src/scene/scene_metrics.c). Definitions: include/xrad.h,
 * xrad_element_metrics. */
#ifndef XRAD_CORE_METRICS_H
#define XRAD_CORE_METRICS_H

#include "xrad.h"

typedef struct metrics_element {
    double a, b;    /* the two solutions at the element, R + G + B */
    double area;    /* m^2 */
    uint32_t group; /* surface */
} metrics_element;

/* Fills `out` over `n` elements of `groups` groups; elements of groups with
 * skip[group] set (emitters) are not counted. group_ratio (may be NULL)
 * receives each group's ratio (1 where nothing was counted). Returns
 * XRAD_ERROR_INPUT when nothing is counted, XRAD_ERROR_SYSTEM out of
 * memory. */
xrad_status metrics_elements(const metrics_element *e, size_t n, uint32_t groups,
                             const unsigned char *skip, xrad_element_metrics *out,
                             double *group_ratio, xrad_error *err);

#endif
