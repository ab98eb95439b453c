/* Threads of the CPU reference (ref_parallel.h). */
#include "reference/ref_parallel.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>

typedef struct job {
    uint32_t n, next, done;
    ref_item_fn fn;
    void *user;
    pthread_mutex_t lock;
    xrad_progress_fn progress;
    void *progress_user;
    const char *stage;
    uint32_t reported; /* percent last reported */
} job;

typedef struct worker {
    job *job;
    uint32_t index;
} worker;

static void *work(void *arg)
{
    worker *w = arg;
    job *j = w->job;
    for (;;) {
        pthread_mutex_lock(&j->lock);
        uint32_t i = j->next < j->n ? j->next++ : j->n;
        uint32_t done = j->done;
        pthread_mutex_unlock(&j->lock);
        if (w->index == 0 && j->progress) {
            uint32_t pct = (uint32_t)((uint64_t)done * 100 / (j->n ? j->n : 1));
            if (pct > j->reported) {
                j->reported = pct;
                j->progress(j->progress_user, j->stage, pct / 100.0);
            }
        }
        if (i >= j->n)
            break;
        j->fn(j->user, w->index, i);
        pthread_mutex_lock(&j->lock);
        j->done++;
        pthread_mutex_unlock(&j->lock);
    }
    return NULL;
}

void ref_parallel_for(uint32_t n, uint32_t threads, ref_item_fn fn, void *user,
                      xrad_progress_fn progress, void *progress_user, const char *stage)
{
    job j = {.n = n, .fn = fn, .user = user, .progress = progress,
             .progress_user = progress_user, .stage = stage};
    threads = threads < n ? threads : (n ? n : 1);
    worker *workers = malloc(threads * sizeof *workers);
    pthread_t *tids = malloc(threads * sizeof *tids);
    bool parallel = workers && tids && pthread_mutex_init(&j.lock, NULL) == 0;
    if (!parallel) {
        /* No threads to be had: the caller alone, same results. */
        for (uint32_t i = 0; i < n; i++)
            fn(user, 0, i);
    } else {
        uint32_t started = 0;
        for (uint32_t t = 1; t < threads; t++) {
            workers[t] = (worker){&j, t};
            if (pthread_create(&tids[t], NULL, work, &workers[t]) != 0)
                break;
            started = t;
        }
        workers[0] = (worker){&j, 0};
        work(&workers[0]);
        for (uint32_t t = 1; t <= started; t++)
            pthread_join(tids[t], NULL);
        pthread_mutex_destroy(&j.lock);
    }
    if (progress && j.reported < 100)
        progress(progress_user, stage, 1.0);
    free(workers);
    free(tids);
}
