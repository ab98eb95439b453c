#include "passes/hemicube_geometry.h"

#include <math.h>
#include <stddef.h>

static const double face_axes[HEMICUBE_FACES][3][3] = {
    /* right        up          forward */
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
    {{0, -1, 0}, {0, 0, 1}, {-1, 0, 0}},
    {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
    {{1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
};

void hemicube_face_axes(int face, vec3 *right, vec3 *up, vec3 *forward)
{
    const double(*a)[3] = face_axes[face];
    *right = v3(a[0][0], a[0][1], a[0][2]);
    *up = v3(a[1][0], a[1][1], a[1][2]);
    *forward = v3(a[2][0], a[2][1], a[2][2]);
}

static uint32_t to_pixel(double c, uint32_t res)
{
    double p = floor((c + 1.0) * 0.5 * res);
    return p < 0 ? 0 : p >= res ? res - 1 : (uint32_t)p;
}

int hemicube_lookup(vec3 d, uint32_t res, uint32_t *px, uint32_t *py)
{
    int best = 0;
    double best_dot = -INFINITY;
    for (int f = 0; f < HEMICUBE_FACES; f++) {
        vec3 r, u, fw;
        hemicube_face_axes(f, &r, &u, &fw);
        double k = v3_dot(d, fw);
        if (k > best_dot) {
            best_dot = k;
            best = f;
        }
    }
    vec3 r, u, fw;
    hemicube_face_axes(best, &r, &u, &fw);
    *px = to_pixel(v3_dot(d, r) / best_dot, res);
    *py = to_pixel(v3_dot(d, u) / best_dot, res);
    return best;
}

/* Form factor from a differential area at the origin with normal +z to a
 * convex polygon lying entirely in z >= 0 (Lambert; see
 * ../shared/reference/ground-truth.md). Vertices counter-clockwise seen from
 * the origin give a positive value. */
static double point_to_polygon(const vec3 *v, int n)
{
    double sum = 0;
    for (int k = 0; k < n; k++) {
        vec3 a = v[k], b = v[(k + 1) % n];
        vec3 c = v3_cross(a, b);
        double cl = v3_len(c);
        if (cl <= 0)
            continue;
        double gamma = atan2(cl, v3_dot(a, b));
        sum += gamma * c.z / cl;
    }
    return fabs(sum) / (2.0 * M_PI);
}

void hemicube_delta_form_factors(uint32_t res, float *table)
{
    double step = 2.0 / res;
    for (int f = 0; f < HEMICUBE_FACES; f++) {
        vec3 r, u, fw;
        hemicube_face_axes(f, &r, &u, &fw);
        for (uint32_t row = 0; row < res; row++) {
            double b0 = -1 + row * step, b1 = b0 + step;
            for (uint32_t col = 0; col < res; col++) {
                double a0 = -1 + col * step, a1 = a0 + step;
                float *out = &table[(size_t)f * res * res + (size_t)row * res + col];
                if (f != 0 && b1 <= 0) {
                    *out = 0;
                    continue;
                }
                /* The pixel square on the unit-distance face plane. */
                vec3 q[4] = {
                    v3_add(fw, v3_add(v3_scale(r, a0), v3_scale(u, b0))),
                    v3_add(fw, v3_add(v3_scale(r, a1), v3_scale(u, b0))),
                    v3_add(fw, v3_add(v3_scale(r, a1), v3_scale(u, b1))),
                    v3_add(fw, v3_add(v3_scale(r, a0), v3_scale(u, b1))),
                };
                *out = (float)point_to_polygon(q, 4);
            }
        }
    }
}

double patch_rotation(uint32_t seed, uint32_t index)
{
    return hemicube_rotation(seed * 0x9e3779b9u + 0x7f4a7c15u + index);
}

double hemicube_rotation(uint32_t seed)
{
    /* A 32-bit integer hash (Wellons' lowbias32) spread over the circle. */
    uint32_t x = seed;
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return (double)x * (2.0 * M_PI / 4294967296.0);
}
