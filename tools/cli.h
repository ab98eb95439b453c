/* Shared pieces of the xrad command line: argument scanning and messages. */
#ifndef XRAD_TOOLS_CLI_H
#define XRAD_TOOLS_CLI_H

#include <stdbool.h>
#include <stdint.h>

#include "xrad.h"

/* A subcommand: argv[0] is the subcommand's name. Returns an exit status
 * (0 ok, 1 bad input, 2 system or GPU error). */
typedef int (*cli_command_fn)(int argc, char **argv);

int cmd_render(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_devices(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_view(int argc, char **argv);

/* Positional arguments a command takes at most: bench takes a scene per
 * argument, room for a shell glob's worth. */
#define CLI_POSITIONAL_MAX 256

/* Scans argv for options. Each call to cli_next returns the next option name
 * (without leading dashes) or NULL at the end; positional arguments are
 * collected in `positional`. `--name=value` and `--name value` both work. */
typedef struct cli_args {
    int argc, index;
    char **argv;
    const char *value; /* inline value from --name=value, if any */
    char opt[64];
    const char *positional[CLI_POSITIONAL_MAX];
    int positional_count;
    const char *command;
    bool failed;
} cli_args;

void cli_init(cli_args *a, int argc, char **argv);
const char *cli_next(cli_args *a);
/* The value of the current option; reports and sets failed if missing. */
const char *cli_value(cli_args *a);
bool cli_double(cli_args *a, double lo, double hi, double *out);
bool cli_uint(cli_args *a, uint32_t lo, uint32_t hi, uint32_t *out);
bool cli_is_help(const char *opt);
/* Reports an unknown option and sets failed. */
void cli_unknown(cli_args *a, const char *opt);

/* Prints "xrad: <message>" to stderr and returns the status as exit code. */
int cli_report(const xrad_error *err);
int cli_usage_error(const char *command, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Fills err like the library does and returns status. */
xrad_status cli_fail(xrad_error *err, xrad_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* xrad_context_create of `desc` with the XRAD_* environment applied to
 * what it leaves unset (xrad_context_desc_from_env): every tool's
 * context. */
xrad_status cli_context_create(xrad_context_desc desc, xrad_context **out, xrad_error *err);

double cli_now(void);
const char *cli_basename_noext(const char *path, char *buf, size_t n);
bool cli_has_ext(const char *path, const char *ext);
/* mkdir -p of the directory part of `path`. */
bool cli_make_parent_dirs(const char *path);
/* Whether `path` can be written (its directories made, the file opened for
 * appending; a file that did not exist is removed again), before a long
 * run: else XRAD_ERROR_INPUT in err naming the path and the reason. */
xrad_status cli_check_writable(const char *path, xrad_error *err);

#endif
