/*
 * Minimal test harness: CHECK macros that count failures and a summary.
 * A test program returns test_finish(): 0 when every check held and at
 * least one ran, 1 otherwise, 77 (meson's "skip") only through
 * test_skip().
 */
#ifndef XRAD_TEST_HARNESS_H
#define XRAD_TEST_HARNESS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int test_failures;
static int test_checks;

#define CHECK(cond, ...)                                                     \
    do {                                                                     \
        test_checks++;                                                       \
        if (!(cond)) {                                                       \
            test_failures++;                                                 \
            fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                    \
            fprintf(stderr, "\n");                                           \
        }                                                                    \
    } while (0)

/* |got - want| <= rel * |want| */
#define CHECK_REL(got, want, rel)                                            \
    do {                                                                     \
        double g_ = (got), w_ = (want);                                      \
        CHECK(fabs(g_ - w_) <= (rel) * fabs(w_), "%s = %.9g, want %.9g (rel %.3g, allowed %.3g)", \
              #got, g_, w_, w_ != 0 ? fabs(g_ - w_) / fabs(w_) : fabs(g_), (double)(rel)); \
    } while (0)

#define CHECK_ABS(got, want, tol)                                            \
    do {                                                                     \
        double g_ = (got), w_ = (want);                                      \
        CHECK(fabs(g_ - w_) <= (tol), "%s = %.9g, want %.9g (abs diff %.3g, allowed %.3g)", \
              #got, g_, w_, fabs(g_ - w_), (double)(tol));                   \
    } while (0)

/* A test that ran no check fails: it proved nothing. */
static inline int test_finish(void)
{
    fprintf(stderr, "%d checks, %d failed\n", test_checks, test_failures);
    if (!test_checks)
        fprintf(stderr, "no check ran: the test fails\n");
    return test_failures || !test_checks ? 1 : 0;
}

static inline int test_skip(const char *why)
{
    fprintf(stderr, "SKIP: %s\n", why);
    return 77;
}

/* Path of a file in the source tree (XRAD_SOURCE_ROOT, set by meson). */
static inline const char *test_source_path(const char *rel, char *buf, size_t n)
{
    const char *root = getenv("XRAD_SOURCE_ROOT");
    snprintf(buf, n, "%s/%s", root ? root : ".", rel);
    return buf;
}

#endif
