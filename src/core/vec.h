/* Double-precision vector and rigid-transform helpers for host code. The
 * GPU side converts to float at upload. */
#ifndef XRAD_CORE_VEC_H
#define XRAD_CORE_VEC_H

#include <math.h>

typedef struct vec3 {
    double x, y, z;
} vec3;

/* Row-major 3x3 matrix: m[row][col]. */
typedef struct mat3 {
    double m[3][3];
} mat3;

/* x -> r x + t */
typedef struct xform {
    mat3 r;
    vec3 t;
} xform;

static inline vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_mad(vec3 a, vec3 b, double s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_len(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline vec3 v3_norm(vec3 a)
{
    double l = v3_len(a);
    return l > 0 ? v3_scale(a, 1.0 / l) : a;
}
static inline vec3 v3_lerp(vec3 a, vec3 b, double t) { return v3_mad(a, v3_sub(b, a), t); }
static inline int v3_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

static inline mat3 m3_identity(void)
{
    return (mat3){{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
}

static inline vec3 m3_apply(const mat3 *m, vec3 v)
{
    return v3(m->m[0][0] * v.x + m->m[0][1] * v.y + m->m[0][2] * v.z,
              m->m[1][0] * v.x + m->m[1][1] * v.y + m->m[1][2] * v.z,
              m->m[2][0] * v.x + m->m[2][1] * v.y + m->m[2][2] * v.z);
}

static inline mat3 m3_mul(const mat3 *a, const mat3 *b)
{
    mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j];
    return r;
}

/* Rotation by `angle` radians about the unit `axis` (Rodrigues). */
static inline mat3 m3_rotation(vec3 axis, double angle)
{
    double c = cos(angle), s = sin(angle), k = 1 - c;
    double x = axis.x, y = axis.y, z = axis.z;
    return (mat3){{{c + x * x * k, x * y * k - z * s, x * z * k + y * s},
                   {y * x * k + z * s, c + y * y * k, y * z * k - x * s},
                   {z * x * k - y * s, z * y * k + x * s, c + z * z * k}}};
}

static inline xform xf_identity(void) { return (xform){m3_identity(), v3(0, 0, 0)}; }
static inline vec3 xf_point(const xform *x, vec3 p) { return v3_add(m3_apply(&x->r, p), x->t); }
static inline vec3 xf_dir(const xform *x, vec3 d) { return m3_apply(&x->r, d); }
/* a after b: x -> a(b(x)) */
static inline xform xf_compose(const xform *a, const xform *b)
{
    return (xform){m3_mul(&a->r, &b->r), v3_add(m3_apply(&a->r, b->t), a->t)};
}

#endif
