/* xrad info SCENE: what a scene holds and what it costs, on the host and,
 * for one method, on the GPU by category; xrad info LUMINAIRE: what a
 * photometric file holds. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "method.h"

static void help(void)
{
    printf("usage: xrad info SCENE.json [--method NAME] [--no-gpu] [options]\n"
           "       xrad info LUMINAIRE.ldt|.ies\n\n"
           "A luminaire file (EULUMDAT or IES LM-63): its C-planes, gamma range, largest\n"
           "intensity and luminous flux, the integral of its intensities beside what the\n"
           "file states.\n\n"
           "Prints the scene's objects, surfaces, elements (static set C, dynamic set M),\n"
           "radiosity atlas size and host memory, then the GPU memory a solver of --method\n"
           "allocates, by category (created, not solved). Checks the file fully, like\n"
           "every command.\n\n"
           "  --method NAME     gather, progressive, incremental or cross [cross where the\n"
           "                    scene has dynamic objects, else progressive]\n"
           "  --no-gpu          host figures only\n"
           "  --surfaces        also each surface's element grid\n"
           "  --device NAME     Vulkan device\n");
    method_print_options();
}

static double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

/* The solver's GPU memory by category: what creating it allocates. */
static int gpu_memory(const xrad_scene *scene, const char *method, const char *device,
                      const method_settings *m)
{
    xrad_error err = {0};
    xrad_context *ctx = NULL;
    xrad_status cs = cli_context_create((xrad_context_desc){.device = device}, &ctx, &err);
    /* No device is an answer (the host figures stand); bad input, such as
     * an XRAD_HEMICUBE_PATH that names no path, is an error. */
    if (cs == XRAD_ERROR_INPUT)
        return cli_report(&err);
    if (cs) {
        printf("GPU memory  unavailable: %s\n", err.message);
        return 0;
    }
    xrad_solver_desc d = m->solver;
    d.method = xrad_method_from_name(method);
    xrad_solver *s = NULL;
    int rc = 0;
    if (xrad_solver_create(ctx, scene, &d, &s, &err)) {
        rc = cli_report(&err);
    } else {
        xrad_memory_stats ms;
        xrad_context_get_memory(ctx, &ms);
        printf("GPU memory  %.2f MiB for %s on %s (peak while creating %.2f MiB):\n",
               mib((double)ms.total), method, xrad_context_device_name(ctx),
               mib((double)ms.total_peak));
        for (uint32_t c = 0; c < ms.count; c++)
            printf("  %-15s %10.3f MiB\n", ms.names[c], mib((double)ms.bytes[c]));
        if (d.method == XRAD_METHOD_CROSS) {
            xrad_solver_stats st;
            xrad_solver_get_stats(s, &st);
            printf("cross       %u patches on the dynamic objects, %u on the lights (a frame "
                   "draws hemicubes of each; an object's cross_density sets its own)\n",
                   st.cross_patches, st.cross_light_patches);
        }
    }
    xrad_solver_destroy(&s);
    xrad_context_destroy(&ctx);
    return rc;
}

static bool is_photometry(const char *path)
{
    return cli_has_ext(path, ".ldt") || cli_has_ext(path, ".ies");
}

/* A luminaire file: what it holds and the flux it states against the
 * integral of its intensities (a file whose two differ by more than its
 * sampling is inconsistent, or states the lamps' flux, not its own). */
static int photometry_info(const char *path)
{
    xrad_error err = {0};
    xrad_photometry *p = NULL;
    if (xrad_photometry_load(path, &p, &err))
        return cli_report(&err);
    xrad_photometry_info in;
    xrad_photometry_get_info(p, &in);
    printf("luminaire   %s\n", path);
    printf("C-planes    %u%s\n", in.c_planes,
           in.c_planes == 1 ? " (rotationally symmetric)" : " over the circle");
    printf("gamma       %u angles, %g to %g degrees from straight down\n", in.gamma_angles,
           in.gamma_min, in.gamma_max);
    printf("intensity   max %.6g cd at C %g, gamma %g\n", in.max_intensity, in.max_c,
           in.max_gamma);
    printf("flux        %.6g lm integrated (%.6g W at 683 lm/W)", in.flux, in.flux / 683.0);
    if (in.flux_stated > 0)
        printf(", the file states %.6g lm (ratio %.4f)", in.flux_stated,
               in.flux / in.flux_stated);
    printf("\n");
    if (in.tilt_ignored)
        printf("note        TILT=INCLUDE: the lamp tilt factors are not applied\n");
    xrad_photometry_destroy(&p);
    return 0;
}

int cmd_info(int argc, char **argv)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *opt, *method = NULL, *device = NULL;
    int no_gpu = 0, surfaces = 0;
    method_settings m = {0};
    while ((opt = cli_next(&a)) && !a.failed) {
        if (cli_is_help(opt)) {
            help();
            return 0;
        } else if (!strcmp(opt, "method")) {
            method = cli_value(&a);
        } else if (!strcmp(opt, "no-gpu")) {
            no_gpu = 1;
        } else if (!strcmp(opt, "surfaces")) {
            surfaces = 1;
        } else if (!strcmp(opt, "device")) {
            device = cli_value(&a);
        } else if (!method_solver_option(&a, opt, &m)) {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 1)
        return cli_usage_error("info", "needs one scene file (see xrad info --help)");
    if (method && !xrad_method_from_name(method))
        return cli_usage_error("info", "--method: '%s' is not a GPU method", method);

    xrad_error err = {0};
    if (is_photometry(a.positional[0]))
        return photometry_info(a.positional[0]);
    xrad_scene *scene = NULL;
    if (method_load_scene(a.positional[0], &m, &scene, &err))
        return cli_report(&err);
    xrad_scene_info in;
    xrad_scene_get_info(scene, &in);
    /* Per texel: B and unshot Bu, RGBA fp32 each (DESIGN.md "Data model"). */
    double atlas_bytes = (double)in.atlas_width * in.atlas_height * 16.0 * 2.0;
    printf("scene       %s\n", a.positional[0]);
    printf("objects     %u (%u dynamic)\n", in.objects, in.dynamic_objects);
    if (in.triangles || in.skipped_triangles)
        printf("surfaces    %u (%u quads, %u triangles; %u zero-area triangles left out)\n",
               in.surfaces, in.surfaces - in.triangles, in.triangles, in.skipped_triangles);
    else
        printf("surfaces    %u\n", in.surfaces);
    printf("materials   %u", in.materials);
    if (in.albedo_maps)
        printf(" (%u with an albedo map, over %u elements)", in.albedo_maps, in.mapped_elements);
    if (in.normal_maps)
        printf(" (%u with a normal map, over %u elements; %u surfaces split for its detail)",
               in.normal_maps, in.normal_mapped_elements, in.normal_refined_surfaces);
    printf("\n");
    if (in.luminaires)
        printf("luminaires  %u\n", in.luminaires);
    if (in.adaptive_refined_surfaces)
        printf("adaptive    %u surfaces split (%u with a shadow boundary, the rest their "
               "neighbours)\n",
               in.adaptive_refined_surfaces, in.adaptive_partial_surfaces);
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
    printf("memory      host %.2f MiB, radiosity atlas (B, Bu) %.2f MiB\n",
           mib((double)in.cpu_bytes), mib(atlas_bytes));
    for (uint32_t i = 0; surfaces && i < in.surfaces; i++) {
        xrad_surface_info si;
        if (!xrad_scene_get_surface(scene, i, &si, &err))
            printf("  surface %-28s %3u x %-3u elements, %.4g x %.4g m\n", si.name, si.nu,
                   si.nv, si.length_u, si.length_v);
    }
    int rc = 0;
    if (!no_gpu)
        rc = gpu_memory(scene, method ? method : in.dynamic_objects ? "cross" : "progressive",
                        device, &m);
    xrad_scene_destroy(&scene);
    return rc;
}
