#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

xrad_status xrad_fail(xrad_error *err, xrad_status status, const char *fmt, ...)
{
    if (!err)
        return status;
    err->status = status;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof(err->message), fmt, ap);
    va_end(ap);
    return status;
}

void xrad_error_prefix(xrad_error *err, const char *fmt, ...)
{
    if (!err)
        return;
    char prefix[512], old[sizeof(err->message)];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof(prefix), fmt, ap);
    va_end(ap);
    memcpy(old, err->message, sizeof(old));
    snprintf(err->message, sizeof(err->message), "%s: %s", prefix, old);
}
