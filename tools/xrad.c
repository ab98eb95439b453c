/* xrad: the command line. Each subcommand lives in its own cmd_*.c. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static const struct {
    const char *name;
    cli_command_fn fn;
    const char *summary;
} commands[] = {
    {"render", cmd_render, "solve a scene and write the camera's image (PNG and/or EXR)"},
#ifdef XRAD_HAVE_VIEW
    {"view", cmd_view, "show a scene in a window while its objects move (real-time loop)"},
#endif
    {"bench", cmd_bench, "time methods on scenes and measure their error against a reference"},
    {"compare", cmd_compare, "print the NRMSE of one EXR image against another"},
    {"info", cmd_info, "print a scene's surfaces, elements, atlas and memory"},
    {"devices", cmd_devices, "list the Vulkan devices xrad can use"},
};

static void usage(FILE *f)
{
    fprintf(f, "usage: xrad COMMAND [OPTIONS]\n"
               "       xrad --version\n\n"
               "xrad computes diffuse global illumination by radiosity on Vulkan.\n\n"
               "commands:\n");
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
        fprintf(f, "  %-9s %s\n", commands[i].name, commands[i].summary);
    fprintf(f, "\n'xrad COMMAND --help' describes a command's options.\n"
               "Exit status: 0 ok, 1 bad input, 2 system or GPU error.\n"
               "Environment: XRAD_DEVICE (device name substring), XRAD_VALIDATION=1 "
               "(Khronos validation layer),\n"
               "  XRAD_GPU_MEMORY_MIB (a device memory limit), XRAD_FAULT (testing: "
               "vkFunction:N:VK_ERROR_NAME).\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 1;
    }
    const char *name = argv[1];
    if (!strcmp(name, "--version")) {
        /* The headers' and the library's: they differ only when a shared
         * libxrad of another build is loaded. */
        printf("xrad %s\n", XRAD_VERSION);
        if (strcmp(xrad_version(), XRAD_VERSION))
            printf("libxrad %s\n", xrad_version());
        return 0;
    }
    if (!strcmp(name, "--help") || !strcmp(name, "-h") || !strcmp(name, "help")) {
        if (argc > 2 && strcmp(name, "help") == 0) {
            char help[] = "--help";
            char *sub[] = {argv[2], help};
            for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
                if (!strcmp(commands[i].name, argv[2]))
                    return commands[i].fn(2, sub);
        }
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
        if (!strcmp(commands[i].name, name))
            return commands[i].fn(argc - 1, argv + 1);
    fprintf(stderr, "xrad: unknown command '%s'\n\n", name);
    usage(stderr);
    return 1;
}
