/* xrad devices: the Vulkan physical devices, and which one xrad picks. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static void help(void)
{
    printf("usage: xrad devices [--device NAME]\n\n"
           "Lists the Vulkan devices and marks with '*' the one xrad would use\n"
           "(--device NAME or $XRAD_DEVICE picks by name substring; otherwise the first\n"
           "discrete or integrated GPU, else the first device, e.g. lavapipe).\n");
}

static void print_device(void *user, const xrad_device_info *info)
{
    const char *chosen = user;
    printf("%s %-40s %-10s Vulkan %u.%u.%u  %.0f MiB device-local\n",
           chosen && !strcmp(chosen, info->name) ? "*" : " ", info->name, info->type,
           info->api_version >> 22, (info->api_version >> 12) & 0x3ff, info->api_version & 0xfff,
           (double)info->device_local_bytes / (1024.0 * 1024.0));
}

int cmd_devices(int argc, char **argv)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *device = NULL, *opt;
    while ((opt = cli_next(&a))) {
        if (cli_is_help(opt)) {
            help();
            return 0;
        } else if (!strcmp(opt, "device")) {
            device = cli_value(&a);
        } else {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    xrad_error err = {0};
    xrad_context *ctx = NULL;
    char chosen[256] = "";
    if (cli_context_create((xrad_context_desc){.device = device}, &ctx, &err) == XRAD_OK) {
        snprintf(chosen, sizeof(chosen), "%s", xrad_context_device_name(ctx));
        xrad_context_destroy(&ctx);
    } else {
        fprintf(stderr, "xrad: %s\n", err.message);
    }
    if (xrad_devices_list(print_device, chosen, &err))
        return cli_report(&err);
    return chosen[0] ? 0 : (int)err.status;
}
