/* Scene files: JSON (cJSON) -> validated scene description -> built scene.
 * The format is specified in scenes/README.md; every check here is listed
 * there. Every message names the file, the object (or material, or camera)
 * and the field. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"

#define PI 3.14159265358979323846

typedef struct ctx {
    const char *file;
    xrad_error *err;
    /* "object 'room': surface 'floor': " or "" at the top level. */
    char where[3 * SCENE_NAME_MAX + 64];
    double unit;         /* m per file unit */
    double density;      /* scene default, per m */
    double density_scale; /* every density read times this (quality.density_scale) */
    uint64_t elements;   /* so far, for the limit */
    uint32_t surface_cap;
    struct name_ref *material_index; /* materials sorted by name, for lookups */
} ctx;

/* Names are checked for duplicates and looked up through sorted indexes, so
 * that large scenes cost n log n, not n^2. */
typedef struct name_ref {
    const char *name;
    uint32_t index;
} name_ref;

static int name_ref_cmp(const void *pa, const void *pb)
{
    const name_ref *a = pa, *b = pb;
    int c = strcmp(a->name, b->name);
    if (c)
        return c;
    return a->index < b->index ? -1 : a->index > b->index;
}

/* Sorts refs; returns the position in refs of the second of the first
 * duplicate pair (by index order of the pairs found), or n if none. */
static uint32_t sort_find_duplicate(name_ref *refs, uint32_t n)
{
    qsort(refs, n, sizeof(*refs), name_ref_cmp);
    uint32_t dup = n;
    for (uint32_t k = 1; k < n; k++)
        if (!strcmp(refs[k - 1].name, refs[k].name) && (dup == n || refs[k].index < refs[dup].index))
            dup = k;
    return dup;
}

XRAD_PRINTF(3, 4)
static xrad_status fail(ctx *c, const char *field, const char *fmt, ...)
{
    char msg[640];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    if (field)
        return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %sfield '%.80s': %s", c->file, c->where,
                         field, msg);
    return xrad_fail(c->err, XRAD_ERROR_INPUT, "%s: %s%s", c->file, c->where, msg);
}

static const char *type_name(const cJSON *j)
{
    if (cJSON_IsString(j))
        return "a string";
    if (cJSON_IsNumber(j))
        return "a number";
    if (cJSON_IsBool(j))
        return "a boolean";
    if (cJSON_IsNull(j))
        return "null";
    if (cJSON_IsArray(j))
        return "an array";
    if (cJSON_IsObject(j))
        return "an object";
    return "invalid";
}

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(obj, key);
}

/* Rejects keys outside `allowed` (NULL-terminated; at most 16) and keys
 * given twice; `prefix` is prepended to the key in the message. */
static xrad_status check_keys(ctx *c, const cJSON *obj, const char *prefix,
                              const char *const *allowed)
{
    unsigned seen[16] = {0};
    char field[160];
    for (const cJSON *it = obj->child; it; it = it->next) {
        const char *key = it->string ? it->string : "";
        int k = 0;
        while (allowed[k] && strcmp(allowed[k], key) != 0)
            k++;
        snprintf(field, sizeof(field), "%s%.64s", prefix, key);
        if (!allowed[k]) {
            char list[256] = "";
            size_t len = 0;
            for (int a = 0; allowed[a]; a++)
                len += (size_t)snprintf(list + len, len < sizeof(list) ? sizeof(list) - len : 0,
                                        "%s%s", a ? ", " : "", allowed[a]);
            return fail(c, field, "unknown key (expected one of: %s)", list);
        }
        if (seen[k]++)
            return fail(c, field, "given twice");
    }
    return XRAD_OK;
}

static xrad_status get_number(ctx *c, const cJSON *obj, const char *key, const char *field,
                              bool required, double *out, bool *present)
{
    const cJSON *j = member(obj, key);
    if (present)
        *present = j != NULL;
    if (!j)
        return required ? fail(c, field, "missing (required)") : XRAD_OK;
    if (!cJSON_IsNumber(j))
        return fail(c, field, "must be a number, got %s", type_name(j));
    if (!isfinite(j->valuedouble))
        return fail(c, field, "must be a finite number, got %g", j->valuedouble);
    *out = j->valuedouble;
    return XRAD_OK;
}

static xrad_status get_uint(ctx *c, const cJSON *j, const char *field, double lo, double hi,
                            uint32_t *out)
{
    if (!cJSON_IsNumber(j))
        return fail(c, field, "must be an integer, got %s", type_name(j));
    double v = j->valuedouble;
    if (!isfinite(v) || v != floor(v))
        return fail(c, field, "must be an integer, got %g", v);
    if (v < lo || v > hi)
        return fail(c, field, "must be in [%g, %g], got %g", lo, hi, v);
    *out = (uint32_t)v;
    return XRAD_OK;
}

static xrad_status get_bool(ctx *c, const cJSON *obj, const char *key, const char *field,
                            bool *out)
{
    const cJSON *j = member(obj, key);
    if (!j)
        return XRAD_OK;
    if (!cJSON_IsBool(j))
        return fail(c, field, "must be true or false, got %s", type_name(j));
    *out = cJSON_IsTrue(j);
    return XRAD_OK;
}

/* A name: non-empty, shorter than SCENE_NAME_MAX - reserve bytes, printable. */
static xrad_status get_name(ctx *c, const cJSON *obj, const char *key, const char *field,
                            size_t reserve, char out[SCENE_NAME_MAX])
{
    const cJSON *j = member(obj, key);
    if (!j)
        return fail(c, field, "missing (required)");
    if (!cJSON_IsString(j))
        return fail(c, field, "must be a string, got %s", type_name(j));
    size_t len = strlen(j->valuestring);
    if (len == 0)
        return fail(c, field, "must not be empty");
    if (len >= SCENE_NAME_MAX - reserve)
        return fail(c, field, "longer than %zu characters", SCENE_NAME_MAX - reserve - 1);
    for (size_t i = 0; i < len; i++)
        if ((unsigned char)j->valuestring[i] < 0x20 || j->valuestring[i] == 0x7f)
            return fail(c, field, "contains a control character");
    memcpy(out, j->valuestring, len + 1);
    return XRAD_OK;
}

static xrad_status check_coord(ctx *c, const char *field, vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (m > SCENE_MAX_COORD)
        return fail(c, field, "%g m is out of range (at most %g m)", m, SCENE_MAX_COORD);
    return XRAD_OK;
}

static xrad_status json_vec3(ctx *c, const cJSON *j, const char *field, vec3 *out)
{
    if (!cJSON_IsArray(j))
        return fail(c, field, "must be an array of 3 numbers, got %s", type_name(j));
    if (cJSON_GetArraySize(j) != 3)
        return fail(c, field, "must have 3 numbers, got %d", cJSON_GetArraySize(j));
    double v[3];
    int k = 0;
    for (const cJSON *it = j->child; it; it = it->next, k++) {
        if (!cJSON_IsNumber(it))
            return fail(c, field, "element %d must be a number, got %s", k, type_name(it));
        if (!isfinite(it->valuedouble))
            return fail(c, field, "element %d must be finite, got %g", k, it->valuedouble);
        v[k] = it->valuedouble;
    }
    *out = v3(v[0], v[1], v[2]);
    return XRAD_OK;
}

static xrad_status get_vec3(ctx *c, const cJSON *obj, const char *key, const char *field,
                            bool required, vec3 *out, bool *present)
{
    const cJSON *j = member(obj, key);
    if (present)
        *present = j != NULL;
    if (!j)
        return required ? fail(c, field, "missing (required)") : XRAD_OK;
    return json_vec3(c, j, field, out);
}

/* A position or length in file units, converted to metres. */
static xrad_status get_length3(ctx *c, const cJSON *obj, const char *key, const char *field,
                               bool required, vec3 *out, bool *present)
{
    xrad_status st = get_vec3(c, obj, key, field, required, out, present);
    if (st)
        return st;
    *out = v3_scale(*out, c->unit);
    return check_coord(c, field, *out);
}

static xrad_status get_axis(ctx *c, const cJSON *obj, const char *field, vec3 *axis)
{
    xrad_status st = get_vec3(c, obj, "axis", field, true, axis, NULL);
    if (st)
        return st;
    double len = v3_len(*axis);
    if (!(len > 0) || !isfinite(len))
        return fail(c, field, "must be a non-zero vector of finite length");
    *axis = v3_scale(*axis, 1.0 / len);
    return XRAD_OK;
}

static xrad_status get_density(ctx *c, const cJSON *obj, const char *key, double *out,
                               bool *present)
{
    xrad_status st = get_number(c, obj, key, key, false, out, present);
    if (st || !*present)
        return st;
    if (!(*out > 0) || *out > SCENE_MAX_DENSITY)
        return fail(c, key, "must be in (0, %g] elements per metre, got %g", SCENE_MAX_DENSITY,
                    *out);
    *out *= c->density_scale;
    if (*out > SCENE_MAX_DENSITY)
        return fail(c, key, "%g x the density scale %g is more than %g elements per metre",
                    *out / c->density_scale, c->density_scale, SCENE_MAX_DENSITY);
    return XRAD_OK;
}

/* ------------------------------------------------------------- materials */

static xrad_status parse_material(ctx *c, const cJSON *j, uint32_t index, xrad_scene *sc)
{
    static const char *const keys[] = {"name", "albedo", "emission", NULL};
    snprintf(c->where, sizeof(c->where), "material #%u: ", index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    material *m = &sc->materials[index];
    xrad_status st = get_name(c, j, "name", "name", 0, m->name);
    if (st)
        return st;
    snprintf(c->where, sizeof(c->where), "material '%s': ", m->name);
    if ((st = check_keys(c, j, "", keys)))
        return st;
    if ((st = get_vec3(c, j, "albedo", "albedo", true, &m->albedo, NULL)))
        return st;
    double a[3] = {m->albedo.x, m->albedo.y, m->albedo.z};
    for (int k = 0; k < 3; k++)
        if (!(a[k] >= 0 && a[k] < 1))
            return fail(c, "albedo", "must be in [0, 1), got %g", a[k]);
    m->emission = v3(0, 0, 0);
    if ((st = get_vec3(c, j, "emission", "emission", false, &m->emission, NULL)))
        return st;
    double e[3] = {m->emission.x, m->emission.y, m->emission.z};
    for (int k = 0; k < 3; k++)
        if (!(e[k] >= 0 && e[k] <= SCENE_MAX_EMISSION))
            return fail(c, "emission", "must be in [0, %g] W/m^2, got %g", SCENE_MAX_EMISSION,
                        e[k]);
    return XRAD_OK;
}

/* -------------------------------------------------------------- surfaces */

typedef struct surface_opts {
    double density;   /* the surface's, else the object's, else the scene's */
    const char *density_field;
    bool explicit_counts;
    uint32_t counts[3];
} surface_opts;

static xrad_status grow_surfaces(ctx *c, xrad_scene *sc, uint32_t add)
{
    if (sc->surface_count + (uint64_t)add > SCENE_MAX_SURFACES)
        return fail(c, NULL, "more than %u surfaces in the scene", SCENE_MAX_SURFACES);
    if (sc->surface_count + add <= c->surface_cap)
        return XRAD_OK;
    uint32_t cap = c->surface_cap ? c->surface_cap * 2 : 64;
    while (cap < sc->surface_count + add)
        cap *= 2;
    surface *s = realloc(sc->surfaces, cap * sizeof(surface));
    if (!s)
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory for %u surfaces", c->file,
                         cap);
    sc->surfaces = s;
    c->surface_cap = cap;
    return XRAD_OK;
}

/* Adds one quad: validates it, counts its elements, checks the limits. */
static xrad_status add_quad(ctx *c, xrad_scene *sc, uint32_t obj, uint32_t mat, const char *name,
                            const vec3 p[4], const char *geo_field, const surface_opts *o,
                            uint32_t cu, uint32_t cv)
{
    surface *s = &sc->surfaces[sc->surface_count];
    memset(s, 0, sizeof(*s));
    char why[256];
    if (!scene_quad_setup(s, p, why, sizeof(why)))
        return fail(c, geo_field, "%s", why);
    snprintf(s->name, sizeof(s->name), "%s", name);
    s->object = obj;
    s->material = mat;
    const char *count_field = "elements";
    if (o->explicit_counts) {
        s->nu = cu;
        s->nv = cv;
    } else {
        double lu, lv;
        scene_quad_edge_lengths(s, &lu, &lv);
        double nu = scene_samples_along(lu, o->density);
        double nv = scene_samples_along(lv, o->density);
        count_field = o->density_field;
        if (nu > SCENE_MAX_SAMPLES || nv > SCENE_MAX_SAMPLES)
            return fail(c, count_field,
                        "gives %.0f x %.0f elements on surface '%s', more than %u along an edge",
                        nu, nv, name, SCENE_MAX_SAMPLES);
        s->nu = (uint32_t)nu;
        s->nv = (uint32_t)nv;
    }
    c->elements += (uint64_t)s->nu * s->nv;
    if (c->elements > SCENE_MAX_ELEMENTS)
        return fail(c, count_field,
                    "surface '%s' (%u x %u) brings the scene to %llu elements, more than %u", name,
                    s->nu, s->nv, (unsigned long long)c->elements, SCENE_MAX_ELEMENTS);
    sc->surface_count++;
    return XRAD_OK;
}

static xrad_status parse_quad_geometry(ctx *c, const cJSON *g, vec3 p[4])
{
    static const char *const keys[] = {"origin", "u", "v", NULL};
    if (!cJSON_IsObject(g))
        return fail(c, "quad", "must be an object {origin, u, v}, got %s", type_name(g));
    xrad_status st = check_keys(c, g, "quad.", keys);
    vec3 o, u, v;
    if (st || (st = get_length3(c, g, "origin", "quad.origin", true, &o, NULL)) ||
        (st = get_length3(c, g, "u", "quad.u", true, &u, NULL)) ||
        (st = get_length3(c, g, "v", "quad.v", true, &v, NULL)))
        return st;
    if (!(v3_len(u) > 0))
        return fail(c, "quad.u", "zero-length edge (zero area)");
    if (!(v3_len(v) > 0))
        return fail(c, "quad.v", "zero-length edge (zero area)");
    if (!(v3_len(v3_cross(u, v)) > 1e-9 * v3_len(u) * v3_len(v)))
        return fail(c, "quad", "edges u and v are parallel (zero area)");
    p[0] = o;
    p[1] = v3_add(o, u);
    p[2] = v3_add(p[1], v);
    p[3] = v3_add(o, v);
    for (int k = 0; k < 4; k++)
        if ((st = check_coord(c, "quad", p[k])))
            return st;
    return XRAD_OK;
}

static xrad_status parse_vertices(ctx *c, const cJSON *g, vec3 p[4])
{
    if (!cJSON_IsArray(g))
        return fail(c, "vertices", "must be an array of 4 points, got %s", type_name(g));
    if (cJSON_GetArraySize(g) != 4)
        return fail(c, "vertices", "must have 4 points, got %d", cJSON_GetArraySize(g));
    int k = 0;
    for (const cJSON *it = g->child; it; it = it->next, k++) {
        char field[32];
        snprintf(field, sizeof(field), "vertices[%d]", k);
        xrad_status st = json_vec3(c, it, field, &p[k]);
        if (st)
            return st;
        p[k] = v3_scale(p[k], c->unit);
        if ((st = check_coord(c, field, p[k])))
            return st;
    }
    return XRAD_OK;
}

/* A box expands into six faces named <name>.-u, <name>.+u, ...; each face's
 * vertex order is chosen so that its normal points away from the box's
 * centre (towards it with "inward"). */
static xrad_status add_box(ctx *c, xrad_scene *sc, uint32_t obj, uint32_t mat, const char *name,
                           const cJSON *g, bool inward, const surface_opts *o)
{
    static const char *const keys[] = {"origin", "u", "v", "w", NULL};
    if (!cJSON_IsObject(g))
        return fail(c, "box", "must be an object {origin, u, v, w}, got %s", type_name(g));
    xrad_status st = check_keys(c, g, "box.", keys);
    vec3 org, e[3];
    if (st || (st = get_length3(c, g, "origin", "box.origin", true, &org, NULL)) ||
        (st = get_length3(c, g, "u", "box.u", true, &e[0], NULL)) ||
        (st = get_length3(c, g, "v", "box.v", true, &e[1], NULL)) ||
        (st = get_length3(c, g, "w", "box.w", true, &e[2], NULL)))
        return st;
    static const char *const edge_field[3] = {"box.u", "box.v", "box.w"};
    for (int k = 0; k < 3; k++)
        if (!(v3_len(e[k]) > 0))
            return fail(c, edge_field[k], "zero-length edge (zero volume)");
    double vol = fabs(v3_dot(e[0], v3_cross(e[1], e[2])));
    if (!(vol > 1e-9 * v3_len(e[0]) * v3_len(e[1]) * v3_len(e[2])))
        return fail(c, "box", "edges u, v and w are coplanar (zero volume)");
    vec3 centre = v3_add(org, v3_scale(v3_add(e[0], v3_add(e[1], e[2])), 0.5));
    if ((st = check_coord(c, "box", v3_add(org, v3_add(e[0], v3_add(e[1], e[2]))))))
        return st;
    static const char axis_name[3] = {'u', 'v', 'w'};
    for (int a = 0; a < 3; a++) {
        int ia = (a + 1) % 3, ib = (a + 2) % 3;
        for (int side = 0; side < 2; side++) {
            vec3 corner = side ? v3_add(org, e[a]) : org;
            vec3 ea = e[ia], eb = e[ib];
            uint32_t ca = o->counts[ia], cb = o->counts[ib];
            vec3 mid = v3_add(corner, v3_scale(v3_add(ea, eb), 0.5));
            double out = v3_dot(v3_cross(ea, eb), v3_sub(mid, centre));
            if ((out < 0) != inward) {
                vec3 t = ea;
                ea = eb;
                eb = t;
                uint32_t tc = ca;
                ca = cb;
                cb = tc;
            }
            vec3 p[4] = {corner, v3_add(corner, ea), v3_add(v3_add(corner, ea), eb),
                         v3_add(corner, eb)};
            char face[SCENE_NAME_MAX];
            snprintf(face, sizeof(face), "%s.%c%c", name, side ? '+' : '-', axis_name[a]);
            if ((st = grow_surfaces(c, sc, 1)) ||
                (st = add_quad(c, sc, obj, mat, face, p, "box", o, ca, cb)))
                return st;
        }
    }
    return XRAD_OK;
}

static xrad_status parse_surface(ctx *c, const cJSON *j, uint32_t index, xrad_scene *sc,
                                 uint32_t obj, double object_density, const char *object_where)
{
    static const char *const keys[] = {"name", "material", "quad", "vertices", "box",
                                       "inward", "density", "elements", NULL};
    snprintf(c->where, sizeof(c->where), "%ssurface #%u: ", object_where, index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    const cJSON *box = member(j, "box");
    char name[SCENE_NAME_MAX];
    /* Box faces append ".-u" to the name. */
    xrad_status st = get_name(c, j, "name", "name", box ? 3 : 0, name);
    if (st)
        return st;
    snprintf(c->where, sizeof(c->where), "%ssurface '%s': ", object_where, name);
    if ((st = check_keys(c, j, "", keys)))
        return st;

    char mat_name[SCENE_NAME_MAX];
    if ((st = get_name(c, j, "material", "material", 0, mat_name)))
        return st;
    name_ref key = {mat_name, 0};
    const name_ref *found = NULL;
    /* Any entry with the name will do: duplicates were rejected. */
    for (uint32_t lo = 0, hi = sc->material_count; lo < hi && !found;) {
        uint32_t mid = lo + (hi - lo) / 2;
        int cmp = strcmp(key.name, c->material_index[mid].name);
        if (cmp == 0)
            found = &c->material_index[mid];
        else if (cmp < 0)
            hi = mid;
        else
            lo = mid + 1;
    }
    if (!found)
        return fail(c, "material", "unknown material '%s'", mat_name);
    uint32_t mat = found->index;

    const cJSON *quad = member(j, "quad"), *verts = member(j, "vertices");
    int kinds = (quad != NULL) + (verts != NULL) + (box != NULL);
    if (kinds == 0)
        return fail(c, "quad", "missing: a surface needs one of 'quad', 'vertices' or 'box'");
    if (kinds > 1)
        return fail(c, quad ? "quad" : "vertices",
                    "a surface has exactly one of 'quad', 'vertices' or 'box'");
    bool inward = false;
    if ((st = get_bool(c, j, "inward", "inward", &inward)))
        return st;
    if (member(j, "inward") && !box)
        return fail(c, "inward", "only allowed with 'box'");

    surface_opts o = {object_density, "density", false, {0, 0, 0}};
    bool has_density;
    double density;
    if ((st = get_density(c, j, "density", &density, &has_density)))
        return st;
    if (has_density)
        o.density = density;
    const cJSON *el = member(j, "elements");
    if (el) {
        int want = box ? 3 : 2;
        if (!cJSON_IsArray(el) || cJSON_GetArraySize(el) != want)
            return fail(c, "elements", "must be an array of %d integers (samples along %s)", want,
                        box ? "u, v, w" : "u, v");
        int k = 0;
        for (const cJSON *it = el->child; it; it = it->next, k++)
            if ((st = get_uint(c, it, "elements", 2, SCENE_MAX_SAMPLES, &o.counts[k])))
                return st;
        o.explicit_counts = true;
    }

    if (box)
        return add_box(c, sc, obj, mat, name, box, inward, &o);
    vec3 p[4];
    if ((st = quad ? parse_quad_geometry(c, quad, p) : parse_vertices(c, verts, p)) ||
        (st = grow_surfaces(c, sc, 1)))
        return st;
    return add_quad(c, sc, obj, mat, name, p, quad ? "quad" : "vertices", &o, o.counts[0],
                    o.counts[1]);
}

/* --------------------------------------------------------------- objects */

static xrad_status parse_animation(ctx *c, const cJSON *j, animation *a)
{
    static const char *const keys[] = {"rotate", "keyframes", "loop", NULL};
    static const char *const rot_keys[] = {"axis", "pivot", "degrees_per_second", NULL};
    static const char *const key_keys[] = {"time", "translate", NULL};
    if (!cJSON_IsObject(j))
        return fail(c, "animation", "must be an object, got %s", type_name(j));
    xrad_status st = check_keys(c, j, "animation.", keys);
    if (st)
        return st;
    a->loop = true;
    if ((st = get_bool(c, j, "loop", "animation.loop", &a->loop)))
        return st;
    const cJSON *rot = member(j, "rotate");
    if (rot) {
        if (!cJSON_IsObject(rot))
            return fail(c, "animation.rotate", "must be an object, got %s", type_name(rot));
        double dps;
        if ((st = check_keys(c, rot, "animation.rotate.", rot_keys)) ||
            (st = get_axis(c, rot, "animation.rotate.axis", &a->axis)) ||
            (st = get_length3(c, rot, "pivot", "animation.rotate.pivot", false, &a->pivot,
                              NULL)) ||
            (st = get_number(c, rot, "degrees_per_second", "animation.rotate.degrees_per_second",
                             true, &dps, NULL)))
            return st;
        a->rotates = true;
        a->rate = dps * PI / 180.0;
    }
    const cJSON *keysj = member(j, "keyframes");
    if (!keysj)
        return XRAD_OK;
    if (!cJSON_IsArray(keysj))
        return fail(c, "animation.keyframes", "must be an array, got %s", type_name(keysj));
    int n = cJSON_GetArraySize(keysj);
    if (n < 1 || (uint32_t)n > SCENE_MAX_KEYFRAMES)
        return fail(c, "animation.keyframes", "must have 1 to %u keys, got %d",
                    SCENE_MAX_KEYFRAMES, n);
    a->keyframes = calloc((size_t)n, sizeof(keyframe));
    if (!a->keyframes)
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    a->keyframe_count = (uint32_t)n;
    int k = 0;
    for (const cJSON *it = keysj->child; it; it = it->next, k++) {
        char prefix[64], ftime[64], ftrans[64];
        snprintf(prefix, sizeof(prefix), "animation.keyframes[%d].", k);
        snprintf(ftime, sizeof(ftime), "%stime", prefix);
        snprintf(ftrans, sizeof(ftrans), "%stranslate", prefix);
        if (!cJSON_IsObject(it))
            return fail(c, ftime, "a key must be an object {time, translate}, got %s",
                        type_name(it));
        keyframe *kf = &a->keyframes[k];
        if ((st = check_keys(c, it, prefix, key_keys)) ||
            (st = get_number(c, it, "time", ftime, true, &kf->time, NULL)) ||
            (st = get_length3(c, it, "translate", ftrans, true, &kf->translation, NULL)))
            return st;
        if (kf->time < 0)
            return fail(c, ftime, "must be >= 0 s, got %g", kf->time);
        if (k > 0 && !(kf->time > a->keyframes[k - 1].time))
            return fail(c, ftime, "times must increase strictly: %g after %g", kf->time,
                        a->keyframes[k - 1].time);
    }
    return XRAD_OK;
}

static xrad_status parse_object(ctx *c, const cJSON *j, uint32_t index, xrad_scene *sc)
{
    static const char *const keys[] = {"name",   "dynamic",       "translate", "rotate",
                                       "density", "cross_density", "animation", "surfaces",
                                       NULL};
    static const char *const rot_keys[] = {"axis", "degrees", NULL};
    snprintf(c->where, sizeof(c->where), "object #%u: ", index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    object *ob = &sc->objects[index];
    xrad_status st = get_name(c, j, "name", "name", 0, ob->name);
    if (st)
        return st;
    char where[SCENE_NAME_MAX + 16];
    snprintf(where, sizeof(where), "object '%s': ", ob->name);
    snprintf(c->where, sizeof(c->where), "%s", where);
    if ((st = check_keys(c, j, "", keys)))
        return st;
    if ((st = get_bool(c, j, "dynamic", "dynamic", &ob->dynamic)))
        return st;

    vec3 translate = v3(0, 0, 0);
    mat3 rot = m3_identity();
    if ((st = get_length3(c, j, "translate", "translate", false, &translate, NULL)))
        return st;
    const cJSON *r = member(j, "rotate");
    if (r) {
        if (!cJSON_IsObject(r))
            return fail(c, "rotate", "must be an object {axis, degrees}, got %s", type_name(r));
        vec3 axis;
        double deg;
        if ((st = check_keys(c, r, "rotate.", rot_keys)) ||
            (st = get_axis(c, r, "rotate.axis", &axis)) ||
            (st = get_number(c, r, "degrees", "rotate.degrees", true, &deg, NULL)))
            return st;
        rot = m3_rotation(axis, deg * PI / 180.0);
    }
    ob->base = (xform){rot, translate};

    bool has;
    double density = c->density;
    if ((st = get_density(c, j, "density", &density, &has)))
        return st;
    if (!has)
        density = c->density;
    if ((st = get_density(c, j, "cross_density", &ob->cross_density, &has)))
        return st;
    if (has && !ob->dynamic)
        return fail(c, "cross_density", "only allowed on dynamic objects (\"dynamic\": true)");
    const cJSON *anim = member(j, "animation");
    if (anim) {
        if (!ob->dynamic)
            return fail(c, "animation", "only allowed on dynamic objects (\"dynamic\": true)");
        if ((st = parse_animation(c, anim, &ob->anim)))
            return st;
    }

    const cJSON *surfs = member(j, "surfaces");
    if (!surfs)
        return fail(c, "surfaces", "missing (required)");
    if (!cJSON_IsArray(surfs) || cJSON_GetArraySize(surfs) < 1)
        return fail(c, "surfaces", "must be a non-empty array, got %s", type_name(surfs));
    ob->first_surface = sc->surface_count;
    uint32_t k = 0;
    for (const cJSON *it = surfs->child; it; it = it->next, k++)
        if ((st = parse_surface(c, it, k, sc, index, density, where)))
            return st;
    ob->surface_count = sc->surface_count - ob->first_surface;
    name_ref *refs = malloc(ob->surface_count * sizeof(*refs));
    if (!refs)
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    for (uint32_t s = 0; s < ob->surface_count; s++)
        refs[s] = (name_ref){sc->surfaces[ob->first_surface + s].name, s};
    uint32_t dup = sort_find_duplicate(refs, ob->surface_count);
    if (dup < ob->surface_count) {
        snprintf(c->where, sizeof(c->where), "%ssurface '%s': ", where, refs[dup].name);
        st = fail(c, "name", "duplicate surface name '%s' in this object (box faces are named "
                  "<box>.-u, <box>.+u, ...)", refs[dup].name);
    }
    free(refs);
    if (st)
        return st;

    if (ob->cross_density > 0) {
        /* In double: a long edge at a high density overflows any integer. */
        double n = 0;
        for (uint32_t s = ob->first_surface; s < sc->surface_count; s++) {
            double lu, lv;
            scene_quad_edge_lengths(&sc->surfaces[s], &lu, &lv);
            n += scene_samples_along(lu, ob->cross_density) *
                 scene_samples_along(lv, ob->cross_density);
            if (n > SCENE_MAX_ELEMENTS) {
                snprintf(c->where, sizeof(c->where), "%s", where);
                return fail(c, "cross_density", "gives more than %u elements",
                            SCENE_MAX_ELEMENTS);
            }
        }
        ob->cross_element_count = (uint32_t)n;
    }
    return XRAD_OK;
}

/* ---------------------------------------------------------------- camera */

static xrad_status parse_camera(ctx *c, const cJSON *j, camera *cam)
{
    static const char *const keys[] = {"position", "look_at", "up", "fov_degrees",
                                       "width",    "height",  NULL};
    snprintf(c->where, sizeof(c->where), "camera: ");
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    xrad_status st = check_keys(c, j, "", keys);
    double fov = 45;
    if (st || (st = get_length3(c, j, "position", "position", true, &cam->position, NULL)) ||
        (st = get_length3(c, j, "look_at", "look_at", true, &cam->look_at, NULL)) ||
        (st = get_vec3(c, j, "up", "up", false, &cam->up, NULL)) ||
        (st = get_number(c, j, "fov_degrees", "fov_degrees", false, &fov, NULL)))
        return st;
    if (!(fov > 0 && fov < 180))
        return fail(c, "fov_degrees", "must be in (0, 180), got %g", fov);
    cam->fov_y = fov * PI / 180.0;
    vec3 dir = v3_sub(cam->look_at, cam->position);
    if (!(v3_len(dir) > 0))
        return fail(c, "look_at", "must differ from position");
    if (!(v3_len(v3_cross(v3_norm(dir), v3_norm(cam->up))) > 1e-6))
        return fail(c, "up", "must be non-zero and not parallel to the view direction");
    const cJSON *w = member(j, "width"), *h = member(j, "height");
    if ((w && (st = get_uint(c, w, "width", 1, 16384, &cam->width))) ||
        (h && (st = get_uint(c, h, "height", 1, 16384, &cam->height))))
        return st;
    return XRAD_OK;
}

/* Without a camera: look along +z at the centre of the scene's bounds from
 * far enough back that a sphere around them fits the 45 degree view. */
static void default_camera(xrad_scene *sc)
{
    vec3 lo, hi;
    scene_bounds(sc, 0.0, &lo, &hi);
    vec3 centre = v3_scale(v3_add(lo, hi), 0.5);
    double radius = 0.5 * v3_len(v3_sub(hi, lo));
    camera *cam = &sc->cam;
    cam->fov_y = 45.0 * PI / 180.0;
    cam->look_at = centre;
    cam->position = v3_sub(centre, v3(0, 0, radius / sin(0.5 * cam->fov_y) + radius));
}

/* ------------------------------------------------------------------ root */

/* "quality": {"preset": NAME, SETTING: VALUE, ...}: checked by applying it
 * to `q`, kept as text for xrad_scene_get_quality. */
static xrad_status parse_quality(ctx *c, const cJSON *j, xrad_scene *sc, xrad_quality *q)
{
    if (!cJSON_IsObject(j))
        return fail(c, "quality", "must be an object, got %s", type_name(j));
    xrad_error e;
    const cJSON *preset = member(j, "preset");
    if (preset) {
        if (!cJSON_IsString(preset))
            return fail(c, "quality.preset", "must be a string, got %s", type_name(preset));
        if (xrad_quality_preset(q, preset->valuestring, &e))
            return fail(c, "quality.preset", "%s", e.message);
        snprintf(sc->quality_preset, sizeof(sc->quality_preset), "%s", preset->valuestring);
    }
    for (const cJSON *it = j->child; it; it = it->next) {
        if (!strcmp(it->string, "preset"))
            continue;
        char field[80], value[64];
        snprintf(field, sizeof(field), "quality.%.60s", it->string);
        if (cJSON_IsNumber(it))
            snprintf(value, sizeof(value), "%.17g", it->valuedouble);
        else if (cJSON_IsString(it))
            snprintf(value, sizeof(value), "%.63s", it->valuestring);
        else
            return fail(c, field, "must be a number or a string, got %s", type_name(it));
        if (xrad_quality_set(q, it->string, value, &e))
            return fail(c, field, "%s", e.message);
        if (sc->quality_count == SCENE_MAX_QUALITY)
            return fail(c, "quality", "more than %d settings", SCENE_MAX_QUALITY);
        uint32_t k = sc->quality_count++;
        snprintf(sc->quality_name[k], sizeof(sc->quality_name[k]), "%s", it->string);
        snprintf(sc->quality_value[k], sizeof(sc->quality_value[k]), "%s", value);
    }
    return XRAD_OK;
}

static xrad_status parse_root(ctx *c, const cJSON *root, xrad_scene *sc)
{
    static const char *const keys[] = {"name",    "unit",   "density", "materials",
                                       "objects", "camera", "quality", NULL};
    c->where[0] = '\0';
    if (!cJSON_IsObject(root))
        return fail(c, NULL, "the top level must be a JSON object, got %s", type_name(root));
    xrad_status st = check_keys(c, root, "", keys);
    if (st)
        return st;
    if (member(root, "name") && (st = get_name(c, root, "name", "name", 0, sc->name)))
        return st;

    c->unit = 1.0;
    const cJSON *unit = member(root, "unit");
    if (unit) {
        if (!cJSON_IsString(unit))
            return fail(c, "unit", "must be a string, got %s", type_name(unit));
        if (!strcmp(unit->valuestring, "m"))
            c->unit = 1.0;
        else if (!strcmp(unit->valuestring, "cm"))
            c->unit = 0.01;
        else if (!strcmp(unit->valuestring, "mm"))
            c->unit = 0.001;
        else
            return fail(c, "unit", "must be \"m\", \"cm\" or \"mm\", got \"%.32s\"",
                        unit->valuestring);
    }
    sc->unit = c->unit;
    /* Quality first: its density scale applies to every density below,
     * unless the loader gave one. */
    xrad_quality q = {0};
    const cJSON *quality = member(root, "quality");
    if (quality && (st = parse_quality(c, quality, sc, &q)))
        return st;
    if (!(c->density_scale > 0))
        c->density_scale = q.density_scale > 0 ? q.density_scale : 1;
    sc->density_scale = c->density_scale;
    bool has;
    c->density = 20;
    if ((st = get_density(c, root, "density", &c->density, &has)))
        return st;
    if (!has)
        c->density = 20 * c->density_scale;
    sc->density = c->density;

    const cJSON *mats = member(root, "materials");
    if (!mats)
        return fail(c, "materials", "missing (required)");
    int nm = cJSON_IsArray(mats) ? cJSON_GetArraySize(mats) : 0;
    if (nm < 1)
        return fail(c, "materials", "must be a non-empty array, got %s", type_name(mats));
    if ((uint32_t)nm > SCENE_MAX_MATERIALS)
        return fail(c, "materials", "more than %u materials", SCENE_MAX_MATERIALS);
    if (!(sc->materials = calloc((size_t)nm, sizeof(material))))
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    uint32_t k = 0;
    for (const cJSON *it = mats->child; it; it = it->next, k++) {
        if ((st = parse_material(c, it, k, sc)))
            return st;
        sc->material_count = k + 1;
    }
    if (!(c->material_index = malloc(sc->material_count * sizeof(name_ref))))
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    for (k = 0; k < sc->material_count; k++)
        c->material_index[k] = (name_ref){sc->materials[k].name, k};
    uint32_t dup = sort_find_duplicate(c->material_index, sc->material_count);
    if (dup < sc->material_count) {
        snprintf(c->where, sizeof(c->where), "material '%s': ", c->material_index[dup].name);
        return fail(c, "name", "duplicate material name '%s'", c->material_index[dup].name);
    }

    c->where[0] = '\0';
    const cJSON *objs = member(root, "objects");
    if (!objs)
        return fail(c, "objects", "missing (required)");
    int no = cJSON_IsArray(objs) ? cJSON_GetArraySize(objs) : 0;
    if (no < 1)
        return fail(c, "objects", "must be a non-empty array, got %s", type_name(objs));
    if ((uint32_t)no > SCENE_MAX_OBJECTS)
        return fail(c, "objects", "more than %u objects", SCENE_MAX_OBJECTS);
    if (!(sc->objects = calloc((size_t)no, sizeof(object))))
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    k = 0;
    for (const cJSON *it = objs->child; it; it = it->next, k++) {
        /* Count it first so that destroy frees its keyframes on failure. */
        sc->object_count = k + 1;
        if ((st = parse_object(c, it, k, sc)))
            return st;
    }
    name_ref *refs = malloc(sc->object_count * sizeof(*refs));
    if (!refs)
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    for (k = 0; k < sc->object_count; k++)
        refs[k] = (name_ref){sc->objects[k].name, k};
    dup = sort_find_duplicate(refs, sc->object_count);
    if (dup < sc->object_count) {
        snprintf(c->where, sizeof(c->where), "object '%s': ", refs[dup].name);
        st = fail(c, "name", "duplicate object name '%s'", refs[dup].name);
    }
    free(refs);
    if (st)
        return st;

    sc->cam = (camera){.up = v3(0, 1, 0), .width = 512, .height = 512};
    const cJSON *cam = member(root, "camera");
    if (cam)
        return parse_camera(c, cam, &sc->cam);
    default_camera(sc);
    return XRAD_OK;
}

/* 1-based line and column of byte `offset`. */
static void line_col(const char *text, size_t offset, unsigned *line, unsigned *col)
{
    *line = 1;
    *col = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n') {
            (*line)++;
            *col = 1;
        } else {
            (*col)++;
        }
    }
}

xrad_status xrad_scene_parse(const char *json, size_t len, const char *name, xrad_scene **out,
                             xrad_error *err)
{
    return xrad_scene_parse_with(json, len, name, NULL, out, err);
}

xrad_status xrad_scene_parse_with(const char *json, size_t len, const char *name,
                                  const xrad_scene_load_desc *desc, xrad_scene **out,
                                  xrad_error *err)
{
    *out = NULL;
    if (!name)
        name = "<memory>";
    if (!json)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: no scene text", name);
    if (len > SCENE_MAX_FILE_BYTES)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %zu bytes, larger than the %u byte limit",
                         name, len, SCENE_MAX_FILE_BYTES);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(json, len, &end, 0);
    size_t at = end && end >= json ? (size_t)(end - json) : 0;
    if (at > len)
        at = len;
    if (root) {
        /* cJSON stops after the first value; anything but white space after
         * it is an error too. */
        while (at < len && (json[at] == ' ' || json[at] == '\t' || json[at] == '\n' ||
                            json[at] == '\r'))
            at++;
        if (at < len) {
            cJSON_Delete(root);
            root = NULL;
        }
    }
    if (!root) {
        unsigned line, col;
        line_col(json, at, &line, &col);
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: line %u, column %u: malformed JSON", name,
                         line, col);
    }

    xrad_scene *sc = calloc(1, sizeof(*sc));
    if (!sc) {
        cJSON_Delete(root);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
    }
    snprintf(sc->path, sizeof(sc->path), "%s", name);
    double scale = desc ? desc->density_scale : 0;
    if (scale != 0 && !(scale > 0 && scale <= 16))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: density scale %g is outside (0, 16]", name,
                         scale);
    ctx c = {.file = name, .err = err, .density_scale = scale};
    xrad_status st = parse_root(&c, root, sc);
    free(c.material_index);
    cJSON_Delete(root);
    if (!st)
        st = scene_build_elements(sc, err);
    if (st) {
        xrad_scene_destroy(&sc);
        return st;
    }
    *out = sc;
    return XRAD_OK;
}

xrad_status xrad_scene_load(const char *path, xrad_scene **out, xrad_error *err)
{
    return xrad_scene_load_with(path, NULL, out, err);
}

xrad_status xrad_scene_load_with(const char *path, const xrad_scene_load_desc *desc,
                                 xrad_scene **out, xrad_error *err)
{
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        /* A file that is not there or not ours to read is the caller's bad
         * input; anything else (EIO, EMFILE, ...) is the system's. */
        return xrad_fail(err,
                         errno == ENOENT || errno == ENOTDIR || errno == EACCES ||
                                 errno == EISDIR || errno == ENAMETOOLONG || errno == ELOOP
                             ? XRAD_ERROR_INPUT
                             : XRAD_ERROR_SYSTEM,
                         "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    char *buf = malloc(cap);
    xrad_status st = XRAD_OK;
    while (buf) {
        if (len == cap) {
            if (cap >= SCENE_MAX_FILE_BYTES) {
                st = xrad_fail(err, XRAD_ERROR_INPUT, "%s: larger than the %u byte limit", path,
                               SCENE_MAX_FILE_BYTES);
                break;
            }
            char *grown = realloc(buf, cap * 2);
            if (!grown) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = grown;
            cap *= 2;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) {
            if (ferror(f))
                st = xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: cannot read: %s", path,
                               strerror(errno));
            break;
        }
    }
    fclose(f);
    if (!buf)
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory reading it", path);
    if (!st)
        st = xrad_scene_parse_with(buf, len, path, desc, out, err);
    free(buf);
    return st;
}

void xrad_scene_destroy(xrad_scene **scene)
{
    if (!scene || !*scene)
        return;
    xrad_scene *sc = *scene;
    for (uint32_t o = 0; o < sc->object_count; o++)
        free(sc->objects[o].anim.keyframes);
    free(sc->objects);
    free(sc->materials);
    free(sc->surfaces);
    free(sc->elements);
    free(sc);
    *scene = NULL;
}

void xrad_scene_get_quality(const xrad_scene *scene, xrad_quality *q)
{
    xrad_error ignored;
    /* Checked when the file was parsed. */
    if (scene->quality_preset[0])
        xrad_quality_preset(q, scene->quality_preset, &ignored);
    for (uint32_t k = 0; k < scene->quality_count; k++)
        xrad_quality_set(q, scene->quality_name[k], scene->quality_value[k], &ignored);
}
