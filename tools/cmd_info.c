/* xrad info SCENE: what a scene holds and what it costs. */
#include <stdio.h>
#include <string.h>

#include "cli.h"

static void help(void)
{
    printf("usage: xrad info SCENE.json\n\n"
           "Prints the scene's objects, surfaces, elements (static set C, dynamic set M),\n"
           "radiosity atlas size and memory. Checks the file fully, like every command.\n");
}

static double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

int cmd_info(int argc, char **argv)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *opt;
    while ((opt = cli_next(&a))) {
        if (cli_is_help(opt)) {
            help();
            return 0;
        }
        cli_unknown(&a, opt);
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 1)
        return cli_usage_error("info", "needs one scene file (see xrad info --help)");

    xrad_error err = {0};
    xrad_scene *scene = NULL;
    if (xrad_scene_load(a.positional[0], &scene, &err))
        return cli_report(&err);
    xrad_scene_info in;
    xrad_scene_get_info(scene, &in);
    /* Per texel: B and unshot Bu, RGBA fp32 each (DESIGN.md "Data model"). */
    double atlas_bytes = (double)in.atlas_width * in.atlas_height * 16.0 * 2.0;
    printf("scene       %s\n", a.positional[0]);
    printf("objects     %u (%u dynamic)\n", in.objects, in.dynamic_objects);
    printf("surfaces    %u\n", in.surfaces);
    printf("materials   %u\n", in.materials);
    printf("elements    %u (static %u, dynamic %u)\n", in.elements, in.static_elements,
           in.dynamic_elements);
    printf("area        %.6g m^2\n", in.area);
    printf("atlas       %u x %u texels (%.1f%% used)\n", in.atlas_width, in.atlas_height,
           in.atlas_width && in.atlas_height
               ? 100.0 * in.elements / ((double)in.atlas_width * in.atlas_height)
               : 0.0);
    if (in.planarised)
        printf("planarised  %u surface(s), largest vertex move %.3g mm\n", in.planarised,
               in.planarise_max_offset * 1e3);
    printf("memory      host %.2f MiB, GPU radiosity atlas (B, Bu) %.2f MiB\n",
           mib((double)in.cpu_bytes), mib(atlas_bytes));
    xrad_scene_destroy(&scene);
    return 0;
}
