/*
 * libFuzzer harness for the photometric readers (src/scene/ldt.c, ies.c):
 * every byte string goes through both. A file either reads into a table
 * that keeps photometry.h's invariants (angles ascending in range,
 * intensities finite and not negative, every lookup and the flux finite)
 * or ends in an input error naming the file (fuzz_check.h). Linked with
 * replay.c, every build replays the seeds: the shipped test files
 * (tests/data/photometry) and regressions/photometry/.
 */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "scene/photometry.h"

/* check_error() alone of the shared checks: the scene ones go unused. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include "fuzz_check.h"
#pragma GCC diagnostic pop

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check_table(const photometry *p)
{
    REQUIRE(p->nc >= 1 && p->ng >= 2, p->nc, p->ng);
    for (uint32_t k = 0; k < p->nc; k++)
        REQUIRE(p->c[k] >= 0 && p->c[k] < 360 && (k == 0 || p->c[k] > p->c[k - 1]), k, p->nc);
    for (uint32_t j = 0; j < p->ng; j++)
        REQUIRE(p->g[j] >= 0 && p->g[j] <= 180 && (j == 0 || p->g[j] > p->g[j - 1]), j, p->ng);
    for (size_t i = 0; i < (size_t)p->nc * p->ng; i++)
        REQUIRE(isfinite(p->cd[i]) && p->cd[i] >= 0, (unsigned)i, 0);
    REQUIRE(isfinite(p->flux) && p->flux >= 0, 0, 0);
    double f = photometry_flux(p);
    REQUIRE(isfinite(f) && f >= 0, 0, 0);
    for (int c = -30; c <= 390; c += 37)
        for (int g = -10; g <= 190; g += 23) {
            double v = photometry_intensity(p, c, g);
            REQUIRE(isfinite(v) && v >= 0, (unsigned)(c + 30), (unsigned)(g + 10));
        }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static const char *const names[2] = {"fuzz.ldt", "fuzz.ies"};
    for (int k = 0; k < 2; k++) {
        photometry p;
        xrad_error err;
        memset(&err, 0, sizeof(err));
        xrad_status st = k == 0 ? photometry_parse_ldt(names[k], (const char *)data, size, &p, &err)
                                : photometry_parse_ies(names[k], (const char *)data, size, &p, &err);
        if (st != XRAD_OK) {
            check_error(st, &err, names[k]);
            REQUIRE(p.c == NULL && p.g == NULL && p.cd == NULL, k, 0);
            continue;
        }
        check_table(&p);
        photometry_free(&p);
    }
    return 0;
}
