#include "core/sliding.h"

#include <stdio.h>
#include <string.h>

void sliding_add(sliding_window *w, double v)
{
    w->v[w->next] = v;
    w->next = (w->next + 1) % SLIDING_WINDOW;
    if (w->count < SLIDING_WINDOW)
        w->count++;
}

double sliding_mean(const sliding_window *w)
{
    double sum = 0;
    for (uint32_t i = 0; i < w->count; i++)
        sum += w->v[i];
    return w->count ? sum / w->count : 0;
}

void sliding_table_add(sliding_table *t, const char *name, double v)
{
    uint32_t i = 0;
    while (i < t->count && strcmp(t->names[i], name))
        i++;
    if (i == t->count) {
        if (t->count == SLIDING_SERIES)
            return;
        snprintf(t->names[i], SLIDING_NAME_MAX, "%s", name);
        memset(&t->series[i], 0, sizeof(t->series[i]));
        t->count++;
    }
    sliding_add(&t->series[i], v);
}

uint32_t sliding_table_means(const sliding_table *t, xrad_pass_time *out, uint32_t max)
{
    uint32_t n = t->count < max ? t->count : max;
    for (uint32_t i = 0; i < n; i++) {
        snprintf(out[i].name, sizeof(out[i].name), "%s", t->names[i]);
        out[i].ms = sliding_mean(&t->series[i]);
    }
    return n;
}
