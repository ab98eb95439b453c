/* xrad compare A B: NRMSE of A against B (thesis table 5.1 metric), EXR or
 * PNG images. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "cli.h"

static void help(void)
{
    printf("usage: xrad compare A.exr|A.png B.exr|B.png [--diff FILE.exr|FILE.png]\n\n"
           "Prints 'nrmse <value>': the RMS over all pixels and RGB channels of (A - B),\n"
           "divided by (max - min) of B's RGB values. B is the reference. PNG values\n"
           "are compared linear (sRGB decoded), so compare PNGs of one exposure.\n\n"
           "  --diff FILE   also write |A - B| per channel (EXR linear, PNG auto-exposed)\n");
}

int cmd_compare(int argc, char **argv)
{
    cli_args a;
    cli_init(&a, argc, argv);
    const char *diff = NULL, *opt;
    while ((opt = cli_next(&a))) {
        if (cli_is_help(opt)) {
            help();
            return 0;
        } else if (!strcmp(opt, "diff")) {
            diff = cli_value(&a);
        } else {
            cli_unknown(&a, opt);
        }
    }
    if (a.failed)
        return 1;
    if (a.positional_count != 2)
        return cli_usage_error("compare", "needs two images (see xrad compare --help)");

    xrad_error err = {0};
    float *img[2] = {NULL, NULL};
    uint32_t w[2], h[2];
    int rc = 0;
    for (int i = 0; i < 2 && rc == 0; i++)
        if ((cli_has_ext(a.positional[i], ".png")
                 ? xrad_image_read_png(a.positional[i], &img[i], &w[i], &h[i], &err)
                 : xrad_image_read_exr(a.positional[i], &img[i], &w[i], &h[i], &err)))
            rc = cli_report(&err);
    if (rc == 0 && (w[0] != w[1] || h[0] != h[1])) {
        fprintf(stderr, "xrad compare: %s is %ux%u but %s is %ux%u\n", a.positional[0], w[0],
                h[0], a.positional[1], w[1], h[1]);
        rc = 1;
    }
    if (rc == 0) {
        double e = xrad_image_nrmse(img[0], img[1], w[0], h[0]);
        if (e < 0) {
            fprintf(stderr, "xrad compare: %s is constant; NRMSE is undefined\n",
                    a.positional[1]);
            rc = 1;
        } else {
            printf("nrmse %.7f\n", e);
        }
    }
    if (rc == 0 && diff) {
        size_t n = (size_t)w[0] * h[0] * 4;
        for (size_t i = 0; i < n; i++)
            img[0][i] = (i % 4 == 3) ? 1.0f : fabsf(img[0][i] - img[1][i]);
        xrad_status st = cli_has_ext(diff, ".png")
                             ? xrad_image_write_png(diff, img[0], w[0], h[0], 0, &err)
                             : xrad_image_write_exr(diff, img[0], w[0], h[0], &err);
        if (st)
            rc = cli_report(&err);
    }
    free(img[0]);
    free(img[1]);
    return rc;
}
