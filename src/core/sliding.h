/*
 * Sliding-window averages of named series: the real-time loop's display
 * and redistribution times and per-pass GPU times (DESIGN.md "Scheduling"),
 * averaged over the last SLIDING_WINDOW samples of each.
 */
#ifndef XRAD_CORE_SLIDING_H
#define XRAD_CORE_SLIDING_H

#include <stdint.h>

#include "xrad.h"

#define SLIDING_WINDOW 32
#define SLIDING_SERIES 32
#define SLIDING_NAME_MAX 48

typedef struct sliding_window {
    double v[SLIDING_WINDOW];
    uint32_t count; /* samples held, at most SLIDING_WINDOW */
    uint32_t next;  /* where the next sample goes */
} sliding_window;

void sliding_add(sliding_window *w, double v);
/* Mean of the samples held; 0 without any. */
double sliding_mean(const sliding_window *w);

typedef struct sliding_table {
    char names[SLIDING_SERIES][SLIDING_NAME_MAX];
    sliding_window series[SLIDING_SERIES];
    uint32_t count;
} sliding_table;

/* Adds v to the series `name`, creating it; a name past SLIDING_SERIES
 * distinct ones is dropped. */
void sliding_table_add(sliding_table *t, const char *name, double v);

/* The table's means as the public statistics give them, at most `max`;
 * returns how many. */
uint32_t sliding_table_means(const sliding_table *t, xrad_pass_time *out, uint32_t max);

#endif
