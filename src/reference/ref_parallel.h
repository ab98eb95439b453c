/*
 * The CPU reference's threads: items 0..n-1 handed out one at a time under
 * a lock, so that threads balance and every item's result depends on its
 * index only, never on scheduling. The calling thread works too and is the
 * one that reports progress.
 */
#ifndef XRAD_REFERENCE_REF_PARALLEL_H
#define XRAD_REFERENCE_REF_PARALLEL_H

#include <stdint.h>

#include "xrad.h"

/* Work on item i by worker `thread` (< threads). */
typedef void (*ref_item_fn)(void *user, uint32_t thread, uint32_t i);

/* Runs fn over 0..n-1 on up to `threads` threads (fewer when creating one
 * fails: the result does not change), reporting `stage` to progress (may
 * be NULL) by whole percents and once at 1.0. */
void ref_parallel_for(uint32_t n, uint32_t threads, ref_item_fn fn, void *user,
                      xrad_progress_fn progress, void *progress_user, const char *stage);

#endif
