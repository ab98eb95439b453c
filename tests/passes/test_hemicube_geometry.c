/* Hemicube conventions: the delta form factor table partitions the
 * hemisphere (sums to 1), agrees with the classic pixel-centre formulas of
 * Cohen and Greenberg (1985) as the pixels shrink, and the lookup inverts
 * the face projection. */
#include "harness.h"
#include "passes/hemicube_geometry.h"

static double table_sum(const float *t, uint32_t res)
{
    double s = 0;
    for (size_t i = 0; i < (size_t)HEMICUBE_FACES * res * res; i++)
        s += t[i];
    return s;
}

static void test_sum_and_closed_forms(uint32_t res)
{
    float *t = malloc(sizeof(float) * HEMICUBE_FACES * res * res);
    if (!t) {
        CHECK(0, "out of memory");
        return;
    }
    hemicube_delta_form_factors(res, t);
    CHECK_ABS(table_sum(t, res), 1.0, 1e-4);

    /* Pixel-centre formulas (DESIGN.md "Integrate"): top pixel at (x, y, 1):
     * dA / (pi (x^2 + y^2 + 1)^2); side pixel at (x, 1, z): z dA / (pi (x^2
     * + z^2 + 1)^2). They are midpoint rules of the exact values, so they
     * agree to O(dA) relative. */
    double da = (2.0 / res) * (2.0 / res), worst = 0;
    for (int f = 0; f < HEMICUBE_FACES; f++) {
        for (uint32_t row = res / 2 + 1; row < res; row++) {
            for (uint32_t col = 0; col < res; col++) {
                double a = -1 + (col + 0.5) * 2.0 / res, b = -1 + (row + 0.5) * 2.0 / res;
                double want = f == 0 ? da / (M_PI * pow(a * a + b * b + 1, 2))
                                     : b * da / (M_PI * pow(a * a + b * b + 1, 2));
                double got = t[(size_t)f * res * res + (size_t)row * res + col];
                worst = fmax(worst, fabs(got - want) / want);
            }
        }
    }
    CHECK(worst < 4.0 / res, "res %u: worst relative gap to the pixel-centre formula %.3g", res,
          worst);

    /* Below the horizon, side faces weigh nothing. */
    double below = 0;
    for (int f = 1; f < HEMICUBE_FACES; f++)
        for (uint32_t row = 0; row < res / 2; row++)
            for (uint32_t col = 0; col < res; col++)
                below += t[(size_t)f * res * res + (size_t)row * res + col];
    CHECK(below == 0, "side faces below the horizon sum to %g", below);
    free(t);
}

static void test_lookup_inverts_projection(uint32_t res)
{
    int bad = 0;
    for (int f = 0; f < HEMICUBE_FACES; f++) {
        vec3 r, u, fw;
        hemicube_face_axes(f, &r, &u, &fw);
        for (uint32_t row = f == 0 ? 0 : res / 2; row < res; row++) {
            for (uint32_t col = 0; col < res; col++) {
                double a = -1 + (col + 0.5) * 2.0 / res, b = -1 + (row + 0.5) * 2.0 / res;
                /* any positive scale of the direction lands in the same pixel */
                vec3 d = v3_scale(v3_add(fw, v3_add(v3_scale(r, a), v3_scale(u, b))), 3.7);
                uint32_t px, py;
                int face = hemicube_lookup(d, res, &px, &py);
                bad += face != f || px != col || py != row;
            }
        }
    }
    CHECK(bad == 0, "res %u: %d pixel centres map elsewhere", res, bad);

    /* The normal is the centre of the top face. */
    uint32_t px, py;
    CHECK(hemicube_lookup(v3(0, 0, 1), res, &px, &py) == 0 && px == res / 2 && py == res / 2,
          "normal -> top face centre, got %u %u", px, py);
}

static void test_rotation_spread(void)
{
    /* Angles cover the circle: 10k seeds fill each of 16 sectors. */
    int sectors[16] = {0};
    for (uint32_t s = 0; s < 10000; s++) {
        double a = hemicube_rotation(s);
        CHECK(a >= 0 && a < 2 * M_PI, "angle %g", a);
        sectors[(int)(a / (2 * M_PI) * 16)]++;
    }
    for (int i = 0; i < 16; i++)
        CHECK(sectors[i] > 500 && sectors[i] < 750, "sector %d has %d of 10000", i, sectors[i]);
}

int main(void)
{
    test_sum_and_closed_forms(16);
    test_sum_and_closed_forms(64);
    test_sum_and_closed_forms(128);
    test_lookup_inverts_projection(16);
    test_lookup_inverts_projection(64);
    test_rotation_spread();
    return test_finish();
}
