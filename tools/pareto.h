/* Pareto front of (time, error) measurements and an SVG plot of them, for
 * `xrad bench --sweep`: which solver settings are worth their time. */
#ifndef XRAD_TOOLS_PARETO_H
#define XRAD_TOOLS_PARETO_H

#include <stdbool.h>
#include <stddef.h>

typedef struct pareto_point {
    double time_ms;     /* x: lower is better, > 0 */
    double error;       /* y: lower is better, >= 0 */
    const char *label;  /* settings that made it, e.g. "hemicube_res=32 cross_grid=2" */
    bool front;         /* output of pareto_mark: no other point is at least as good in both
                         * and better in one */
} pareto_point;

/* Sets .front on every point. Points with non-finite or non-positive time, or
 * non-finite or negative error, are never on the front (and dominate nothing).
 * Exact duplicates do not dominate each other, so both are on the front. */
void pareto_mark(pareto_point *p, size_t n);

/* Writes an SVG (900 x 600 px) of error against time: each axis log-scaled when
 * its data span more than a factor 10, else linear; decade or nice linear ticks;
 * every point as a small grey circle, the front as larger circles joined by a
 * step line in time order, each labelled with its label (staggered where labels
 * would collide). The front is computed here as pareto_mark does, so .front is
 * not read: a plot cannot disagree with the data. Title and labels are XML-escaped.
 * Points with invalid values (see pareto_mark) are left out. Handles n == 0
 * (axes and a note "no points"). Returns 0 on success, -1 with errno set if the
 * file cannot be written. */
int pareto_write_svg(const char *path, const char *title, const pareto_point *p, size_t n);

/* The same with the error axis named `error_name` ("surface_error", ...;
 * XML-escaped) instead of "NRMSE". */
int pareto_write_svg_named(const char *path, const char *title, const char *error_name,
                           const pareto_point *p, size_t n);

#endif
