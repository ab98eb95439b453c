#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>

void cli_init(cli_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof(*a));
    a->argc = argc;
    a->argv = argv;
    a->index = 1;
    a->command = argv[0];
}

const char *cli_next(cli_args *a)
{
    while (a->index < a->argc) {
        const char *s = a->argv[a->index++];
        if (s[0] == '-' && s[1] != '\0') {
            while (*s == '-')
                s++;
            const char *eq = strchr(s, '=');
            size_t n = eq ? (size_t)(eq - s) : strlen(s);
            if (n >= sizeof(a->opt))
                n = sizeof(a->opt) - 1;
            memcpy(a->opt, s, n);
            a->opt[n] = '\0';
            a->value = eq ? eq + 1 : NULL;
            return a->opt;
        }
        if (a->positional_count < (int)(sizeof(a->positional) / sizeof(a->positional[0]))) {
            a->positional[a->positional_count++] = s;
        } else {
            cli_usage_error(a->command, "too many arguments at '%s'", s);
            a->failed = true;
        }
    }
    return NULL;
}

const char *cli_value(cli_args *a)
{
    if (a->value)
        return a->value;
    if (a->index < a->argc)
        return a->argv[a->index++];
    cli_usage_error(a->command, "option --%s needs a value", a->opt);
    a->failed = true;
    return NULL;
}

bool cli_double(cli_args *a, double lo, double hi, double *out)
{
    const char *v = cli_value(a);
    if (!v)
        return false;
    char *end;
    errno = 0;
    double d = strtod(v, &end);
    if (end == v || *end || errno || !isfinite(d) || d < lo || d > hi) {
        cli_usage_error(a->command, "--%s: '%s' is not a number in [%g, %g]", a->opt, v, lo, hi);
        a->failed = true;
        return false;
    }
    *out = d;
    return true;
}

bool cli_uint(cli_args *a, uint32_t lo, uint32_t hi, uint32_t *out)
{
    const char *v = cli_value(a);
    if (!v)
        return false;
    char *end;
    errno = 0;
    unsigned long long u = strtoull(v, &end, 10);
    if (end == v || *end || errno || v[0] == '-' || u < lo || u > hi) {
        cli_usage_error(a->command, "--%s: '%s' is not an integer in [%u, %u]", a->opt, v, lo, hi);
        a->failed = true;
        return false;
    }
    *out = (uint32_t)u;
    return true;
}

bool cli_is_help(const char *opt) { return !strcmp(opt, "help") || !strcmp(opt, "h"); }

void cli_unknown(cli_args *a, const char *opt)
{
    /* Named as written: "-o" said back as "--o" reads as a typo of ours. */
    const char *raw = a->index > 0 && a->index <= a->argc ? a->argv[a->index - 1] : opt;
    const char *eq = strchr(raw, '=');
    int n = eq ? (int)(eq - raw) : (int)strlen(raw);
    cli_usage_error(a->command, "unknown option %.*s (see xrad %s --help)", n, raw, a->command);
    a->failed = true;
}

int cli_report(const xrad_error *err)
{
    fprintf(stderr, "xrad: %s\n", err->message[0] ? err->message : "unknown error");
    return err->status ? (int)err->status : 2;
}

int cli_usage_error(const char *command, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "xrad %s: ", command);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    return 1;
}

xrad_status cli_fail(xrad_error *err, xrad_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof(err->message), fmt, ap);
    va_end(ap);
    err->status = status;
    return status;
}

double cli_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

const char *cli_basename_noext(const char *path, char *buf, size_t n)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    snprintf(buf, n, "%s", base);
    char *dot = strrchr(buf, '.');
    if (dot && dot != buf)
        *dot = '\0';
    return buf;
}

bool cli_has_ext(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    return n > m && !strcasecmp(path + n - m, ext);
}

bool cli_make_parent_dirs(const char *path)
{
    char buf[1024];
    snprintf(buf, sizeof(buf), "%s", path);
    for (char *p = buf + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = '\0';
        if (mkdir(buf, 0777) != 0 && errno != EEXIST)
            return false;
        *p = '/';
    }
    return true;
}

xrad_status cli_check_writable(const char *path, xrad_error *err)
{
    if (!cli_make_parent_dirs(path))
        return cli_fail(err, XRAD_ERROR_INPUT, "%s: cannot create its directory: %s", path,
                        strerror(errno));
    struct stat st;
    bool existed = stat(path, &st) == 0;
    if (existed && S_ISDIR(st.st_mode))
        return cli_fail(err, XRAD_ERROR_INPUT, "%s: cannot write: Is a directory", path);
    FILE *f = fopen(path, "ab");
    if (!f)
        return cli_fail(err, XRAD_ERROR_INPUT, "%s: cannot write: %s", path, strerror(errno));
    fclose(f);
    if (!existed)
        remove(path);
    return XRAD_OK;
}

xrad_status cli_context_create(xrad_context_desc desc, xrad_context **out, xrad_error *err)
{
    *out = NULL;
    xrad_status st = xrad_context_desc_from_env(&desc, err);
    return st ? st : xrad_context_create(&desc, out, err);
}
