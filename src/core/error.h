/* Error values: fill an xrad_error and return its status in one step. */
#ifndef XRAD_CORE_ERROR_H
#define XRAD_CORE_ERROR_H

#include "xrad.h"

#if defined(__GNUC__)
#define XRAD_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define XRAD_PRINTF(f, a)
#endif

/* Sets err (may be NULL) and returns status, so that callers can write
 * `return xrad_fail(err, XRAD_ERROR_INPUT, "%s: ...", path);`. */
xrad_status xrad_fail(xrad_error *err, xrad_status status, const char *fmt, ...)
    XRAD_PRINTF(3, 4);

/* Prefixes err->message with context ("loading x: " + old message). */
void xrad_error_prefix(xrad_error *err, const char *fmt, ...) XRAD_PRINTF(2, 3);

#endif
