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
#include "scene/scene_luminaire.h"
#include "scene/scene_texture.h"

#define PI 3.14159265358979323846

typedef struct ctx {
    const char *file;
    xrad_error *err;
    xrad_scene_builder *b; /* what the file's values go to (scene_builder.c) */
    /* "object 'room': surface 'floor': " or "" at the top level. */
    char where[3 * SCENE_NAME_MAX + 64];
    double unit;         /* m per file unit */
    double density_scale; /* every density read times this (quality.density_scale) */
    xrad_adaptive_desc adaptive; /* the loader's; a zero field: quality's */
    name_ref *material_index; /* materials sorted by name, for lookups */
} ctx;

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

/* A density as the file gives it: (0, SCENE_MAX_DENSITY] per metre. The
 * builder scales it (and checks the product). */
static xrad_status get_density(ctx *c, const cJSON *obj, const char *key, double *out,
                               bool *present)
{
    xrad_status st = get_number(c, obj, key, key, false, out, present);
    if (st || !*present)
        return st;
    if (!(*out > 0) || *out > SCENE_MAX_DENSITY)
        return fail(c, key, "must be in (0, %g] elements per metre, got %g", SCENE_MAX_DENSITY,
                    *out);
    return XRAD_OK;
}

/* A file the scene names (a model, a luminaire's, an albedo map), relative to the scene
 * file's folder unless absolute. */
static void beside_scene(const ctx *c, const char *file, char *out, size_t n)
{
    const char *slash = strrchr(c->file, '/');
    if (file[0] != '/' && slash)
        snprintf(out, n, "%.*s/%s", (int)(slash - c->file), c->file, file);
    else
        snprintf(out, n, "%s", file);
}

static void put3(double out[3], vec3 v)
{
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
}

/* ------------------------------------------------------------- materials */

/* Material field `key`, if there, names an image beside the scene file:
 * *image gets its texels (malloc'd; rgb NULL where the field is absent). */
static xrad_status read_map(ctx *c, const cJSON *j, const char *key, bool srgb,
                            xrad_image_desc *image)
{
    const cJSON *map = member(j, key);
    if (!map)
        return XRAD_OK;
    if (!cJSON_IsString(map) || !map->valuestring[0])
        return fail(c, key, "must be a non-empty string (an image file), got %s", type_name(map));
    char path[1024], what[1200];
    beside_scene(c, map->valuestring, path, sizeof(path));
    snprintf(what, sizeof(what), "%s: %sfield '%s'", c->file, c->where, key);
    char *data = NULL;
    size_t size = 0;
    float *texels = NULL;
    xrad_status st = scene_read_file(path, 256u << 20, &data, &size, c->err);
    if (st)
        xrad_error_prefix(c->err, "%s", what);
    else
        st = scene_texture_decode(data, size, srgb, what, &texels, &image->width, &image->height,
                                  c->err);
    free(data);
    image->rgb = texels;
    return st;
}

static xrad_status parse_material(ctx *c, const cJSON *j, uint32_t index)
{
    static const char *const keys[] = {
        "name", "albedo", "emission", "albedo_map", "normal_map", "normal_map_levels", NULL};
    snprintf(c->where, sizeof(c->where), "material #%u: ", index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    char name[SCENE_NAME_MAX];
    xrad_status st = get_name(c, j, "name", "name", 0, name);
    if (st)
        return st;
    snprintf(c->where, sizeof(c->where), "material '%s': ", name);
    vec3 albedo, emission = v3(0, 0, 0);
    if ((st = check_keys(c, j, "", keys)) ||
        (st = get_vec3(c, j, "albedo", "albedo", true, &albedo, NULL)) ||
        (st = get_vec3(c, j, "emission", "emission", false, &emission, NULL)))
        return st;
    xrad_material_desc m = {.name = name};
    put3(m.albedo, albedo);
    put3(m.emission, emission);
    /* Images beside the scene file: the albedo map sRGB, the normal map
     * linear (scene_texture.h). */
    xrad_image_desc albedo_map = {0}, normal_map = {0};
    if ((st = read_map(c, j, "albedo_map", true, &albedo_map)) ||
        (st = read_map(c, j, "normal_map", false, &normal_map))) {
        free((void *)albedo_map.rgb);
        return st;
    }
    m.albedo_map = albedo_map.rgb ? &albedo_map : NULL;
    m.normal_map = normal_map.rgb ? &normal_map : NULL;
    /* 0 here is none; absent, the library's default (xrad.h). */
    const cJSON *levels = member(j, "normal_map_levels");
    uint32_t nl = 0;
    if (levels &&
        (st = get_uint(c, levels, "normal_map_levels", 0, XRAD_NORMAL_MAP_LEVELS_MAX, &nl))) {
        free((void *)albedo_map.rgb);
        free((void *)normal_map.rgb);
        return st;
    }
    if (levels)
        m.normal_map_levels = nl ? (int)nl : XRAD_NORMAL_MAP_LEVELS_NONE;
    st = xrad_scene_builder_add_material(c->b, &m, NULL, c->err);
    free((void *)albedo_map.rgb);
    free((void *)normal_map.rgb);
    return st;
}

/* -------------------------------------------------------------- surfaces */

typedef struct surface_opts {
    double density; /* resolved: the surface's, else the object's */
    bool explicit_counts;
    uint32_t counts[3];
} surface_opts;

/* One quad through the builder, its messages at this surface and `field`. */
static xrad_status add_quad(ctx *c, uint32_t mat, const char *name, const vec3 p[4],
                            const char *field, const surface_opts *o, uint32_t cu, uint32_t cv)
{
    xrad_quad_desc q = {.name = name, .material = mat};
    for (int k = 0; k < 4; k++)
        put3(q.p[k], p[k]);
    if (o->explicit_counts) {
        q.samples[0] = cu;
        q.samples[1] = cv;
    }
    return scene_builder_quad(c->b, &q, c->where, field, o->density, c->err);
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
static xrad_status add_box(ctx *c, uint32_t mat, const char *name, const cJSON *g, bool inward,
                           const surface_opts *o)
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
            if ((st = add_quad(c, mat, face, p, "box", o, ca, cb)))
                return st;
        }
    }
    return XRAD_OK;
}

/* "mesh.scale" range: micrometres to metres and back, with room to spare.
 * The bound below keeps a model's areas from underflowing to zero; the
 * coordinates a scale gives are checked against SCENE_MAX_COORD. */
#define MESH_MIN_SCALE 1e-6
#define MESH_MAX_SCALE 1e6

/* Scales the surfaces [first, sc->surface_count) about the object's origin
 * by `scale`: their corners, areas and planarisation offsets. Their sample
 * counts were already made for the scaled size (parse_mesh). Every test the
 * builder made on them (degenerate, coplanar, convex, joined pairs) is
 * relative to their size, so it holds at any scale. */
static xrad_status scale_surfaces(ctx *c, uint32_t first, double scale)
{
    xrad_scene *sc = scene_builder_scene(c->b);
    for (uint32_t i = first; i < sc->surface_count; i++) {
        surface *s = &sc->surfaces[i];
        for (int k = 0; k < 4; k++) {
            s->p[k] = v3_scale(s->p[k], scale);
            s->planarise_dist[k] *= scale;
            xrad_status st = check_coord(c, "mesh.scale", s->p[k]);
            if (st)
                return st;
        }
        s->area *= scale * scale;
        s->planarise_offset *= scale;
    }
    return XRAD_OK;
}

/* "mesh": {"file": PATH, "node": NAME, "scale": S}: a model file's
 * triangles (scene_import.c), PATH relative to the scene file's directory
 * (or absolute), all of them or one node's subtree, times S, in this
 * object's space; `mat` for every triangle, or UINT32_MAX for the file's
 * own materials. */
static xrad_status parse_mesh(ctx *c, const cJSON *j, const cJSON *mesh, uint32_t mat,
                              const char *object_where)
{
    static const char *const keys[] = {"file", "node", "scale", NULL};
    static const char *const surface_keys[] = {"name", "material", "mesh", "density", NULL};
    xrad_status st = check_keys(c, j, "", surface_keys);
    if (st)
        return st;
    if (!cJSON_IsObject(mesh))
        return fail(c, "mesh", "must be an object {file, node, scale}, got %s",
                    type_name(mesh));
    if ((st = check_keys(c, mesh, "mesh.", keys)))
        return st;
    const cJSON *file = member(mesh, "file"), *node = member(mesh, "node");
    if (!file)
        return fail(c, "mesh.file", "missing (required)");
    if (!cJSON_IsString(file) || !file->valuestring[0])
        return fail(c, "mesh.file", "must be a non-empty string, got %s", type_name(file));
    if (node && !cJSON_IsString(node))
        return fail(c, "mesh.node", "must be a string, got %s", type_name(node));
    if (!scene_import_supported(file->valuestring))
        return fail(c, "mesh.file", "'%.200s' is not a model file xrad reads (.gltf, .glb, "
                    ".obj, .ply)", file->valuestring);
    char path[1024];
    beside_scene(c, file->valuestring, path, sizeof(path));
    double density = 0, scale = 1;
    bool has;
    if ((st = get_density(c, j, "density", &density, &has)) ||
        (st = get_number(c, mesh, "scale", "mesh.scale", false, &scale, &has)))
        return st;
    if (!(scale >= MESH_MIN_SCALE) || scale > MESH_MAX_SCALE)
        return fail(c, "mesh.scale", "must be in [%g, %g] (a factor on the model's metres), "
                    "got %g", MESH_MIN_SCALE, MESH_MAX_SCALE, scale);
    /* scene_import.c takes no scale: the model comes in at its own size
     * and is scaled here once it is in. Its sample counts are made then, so
     * the density it gets is the one meant for the scaled model times the
     * scale (an edge L long in the file is L x scale in the scene), divided
     * by the density scale the builder applies to it again. */
    if (scale != 1) {
        double d;
        if ((st = scene_builder_surface_density(c->b, c->where, density, &d, c->err)))
            return st;
        density = d * scale / c->density_scale;
        if (d * scale > SCENE_MAX_DENSITY || density > SCENE_MAX_DENSITY)
            return fail(c, "mesh.scale", "%g elements per metre at scale %g is %g per metre "
                        "of the model file, more than %g", d, scale, d * scale,
                        SCENE_MAX_DENSITY);
    }
    /* Material names: OBJECT.SURFACE/NAME, unique per placement. */
    char prefix[SCENE_NAME_MAX], name[SCENE_NAME_MAX];
    const cJSON *nm = member(j, "name");
    snprintf(name, sizeof(name), "%s", cJSON_IsString(nm) ? nm->valuestring : "mesh");
    /* object_where is "object 'NAME': ". */
    const char *obj = object_where + strlen("object '");
    int olen = (int)strlen(obj) - (int)strlen("': ");
    snprintf(prefix, sizeof(prefix), "%.*s.%.10s", olen < 10 ? olen : 10, obj, name);
    scene_import_desc d = {.prefix = prefix,
                           .name = name,
                           .node = node ? node->valuestring : NULL,
                           .material = mat,
                           .density = density};
    uint32_t first = scene_builder_scene(c->b)->surface_count;
    if ((st = scene_import_model(c->b, path, &d, c->err))) {
        /* c->where ends in ": ", which xrad_error_prefix adds itself. */
        size_t wl = strlen(c->where);
        xrad_error_prefix(c->err, "%s: %.*s", c->file, (int)(wl >= 2 ? wl - 2 : wl), c->where);
        return st;
    }
    return scale != 1 ? scale_surfaces(c, first, scale) : XRAD_OK;
}

static xrad_status parse_surface(ctx *c, const cJSON *j, uint32_t index, uint32_t material_count,
                                 const char *object_where)
{
    static const char *const keys[] = {"name",   "material", "quad",    "vertices", "box",
                                       "inward", "density",  "elements", "mesh",    NULL};
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

    const cJSON *mesh = member(j, "mesh");
    char mat_name[SCENE_NAME_MAX];
    /* A model file brings its own materials; "material" overrides them. */
    if (mesh && !member(j, "material"))
        return parse_mesh(c, j, mesh, UINT32_MAX, object_where);
    if ((st = get_name(c, j, "material", "material", 0, mat_name)))
        return st;
    name_ref key = {mat_name, 0};
    const name_ref *found = NULL;
    /* Any entry with the name will do: duplicates were rejected. */
    for (uint32_t lo = 0, hi = material_count; lo < hi && !found;) {
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
    if (mesh)
        return parse_mesh(c, j, mesh, mat, object_where);

    const cJSON *quad = member(j, "quad"), *verts = member(j, "vertices");
    int kinds = (quad != NULL) + (verts != NULL) + (box != NULL);
    if (kinds == 0)
        return fail(c, "quad",
                    "missing: a surface needs one of 'quad', 'vertices', 'box' or 'mesh'");
    if (kinds > 1)
        return fail(c, quad ? "quad" : "vertices",
                    "a surface has exactly one of 'quad', 'vertices', 'box' or 'mesh'");
    bool inward = false;
    if ((st = get_bool(c, j, "inward", "inward", &inward)))
        return st;
    if (member(j, "inward") && !box)
        return fail(c, "inward", "only allowed with 'box'");

    surface_opts o = {0};
    bool has_density;
    double density = 0;
    if ((st = get_density(c, j, "density", &density, &has_density)) ||
        (st = scene_builder_surface_density(c->b, c->where, density, &o.density, c->err)))
        return st;
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
        return add_box(c, mat, name, box, inward, &o);
    vec3 p[4];
    if ((st = quad ? parse_quad_geometry(c, quad, p) : parse_vertices(c, verts, p)))
        return st;
    return add_quad(c, mat, name, p, quad ? "quad" : "vertices", &o, o.counts[0], o.counts[1]);
}

/* --------------------------------------------------------------- objects */

/* The file's animation into `a`; the keyframes go to *keys (the caller
 * frees them). The builder checks the values. */
static xrad_status parse_animation(ctx *c, const cJSON *j, xrad_animation_desc *a,
                                   xrad_keyframe **keys_out)
{
    static const char *const keys[] = {"rotate", "keyframes", "loop", NULL};
    static const char *const rot_keys[] = {"axis", "pivot", "degrees_per_second", NULL};
    static const char *const key_keys[] = {"time", "translate", NULL};
    if (!cJSON_IsObject(j))
        return fail(c, "animation", "must be an object, got %s", type_name(j));
    xrad_status st = check_keys(c, j, "animation.", keys);
    if (st)
        return st;
    bool loop = true;
    if ((st = get_bool(c, j, "loop", "animation.loop", &loop)))
        return st;
    a->once = !loop;
    const cJSON *rot = member(j, "rotate");
    if (rot) {
        if (!cJSON_IsObject(rot))
            return fail(c, "animation.rotate", "must be an object, got %s", type_name(rot));
        vec3 axis, pivot = v3(0, 0, 0);
        if ((st = check_keys(c, rot, "animation.rotate.", rot_keys)) ||
            (st = get_axis(c, rot, "animation.rotate.axis", &axis)) ||
            (st = get_length3(c, rot, "pivot", "animation.rotate.pivot", false, &pivot, NULL)) ||
            (st = get_number(c, rot, "degrees_per_second", "animation.rotate.degrees_per_second",
                             true, &a->degrees_per_second, NULL)))
            return st;
        a->rotates = 1;
        put3(a->axis, axis);
        put3(a->pivot, pivot);
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
    xrad_keyframe *kf = calloc((size_t)n, sizeof(xrad_keyframe));
    if (!kf)
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    *keys_out = kf;
    a->keyframes = kf;
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
        vec3 t;
        if ((st = check_keys(c, it, prefix, key_keys)) ||
            (st = get_number(c, it, "time", ftime, true, &kf[k].time, NULL)) ||
            (st = get_length3(c, it, "translate", ftrans, true, &t, NULL)))
            return st;
        put3(kf[k].translate, t);
    }
    return XRAD_OK;
}

static xrad_status parse_object(ctx *c, const cJSON *j, uint32_t index, uint32_t material_count)
{
    static const char *const keys[] = {"name",   "dynamic",       "translate", "rotate",
                                       "density", "cross_density", "animation", "surfaces",
                                       NULL};
    static const char *const rot_keys[] = {"axis", "degrees", NULL};
    snprintf(c->where, sizeof(c->where), "object #%u: ", index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    char name[SCENE_NAME_MAX];
    xrad_status st = get_name(c, j, "name", "name", 0, name);
    if (st)
        return st;
    char where[SCENE_NAME_MAX + 16];
    snprintf(where, sizeof(where), "object '%s': ", name);
    snprintf(c->where, sizeof(c->where), "%s", where);
    xrad_object_desc o = {.name = name};
    bool dynamic = false;
    if ((st = check_keys(c, j, "", keys)) || (st = get_bool(c, j, "dynamic", "dynamic", &dynamic)))
        return st;
    o.dynamic = dynamic;

    vec3 translate = v3(0, 0, 0);
    if ((st = get_length3(c, j, "translate", "translate", false, &translate, NULL)))
        return st;
    put3(o.translate, translate);
    const cJSON *r = member(j, "rotate");
    if (r) {
        if (!cJSON_IsObject(r))
            return fail(c, "rotate", "must be an object {axis, degrees}, got %s", type_name(r));
        vec3 axis;
        if ((st = check_keys(c, r, "rotate.", rot_keys)) ||
            (st = get_axis(c, r, "rotate.axis", &axis)) ||
            (st = get_number(c, r, "degrees", "rotate.degrees", true, &o.rotate_degrees, NULL)))
            return st;
        put3(o.rotate_axis, axis);
    }
    bool has;
    if ((st = get_density(c, j, "density", &o.density, &has)) ||
        (st = get_density(c, j, "cross_density", &o.cross_density, &has)))
        return st;
    const cJSON *anim = member(j, "animation");
    xrad_animation_desc a = {0};
    xrad_keyframe *keys_given = NULL;
    if (anim && !(st = parse_animation(c, anim, &a, &keys_given)))
        o.animation = &a;
    if (!st)
        st = xrad_scene_builder_begin_object(c->b, &o, c->err);
    free(keys_given);
    if (st)
        return st;

    const cJSON *surfs = member(j, "surfaces");
    if (!surfs)
        return fail(c, "surfaces", "missing (required)");
    if (!cJSON_IsArray(surfs) || cJSON_GetArraySize(surfs) < 1)
        return fail(c, "surfaces", "must be a non-empty array, got %s", type_name(surfs));
    uint32_t k = 0;
    for (const cJSON *it = surfs->child; it; it = it->next, k++)
        if ((st = parse_surface(c, it, k, material_count, where)))
            return st;
    return XRAD_OK;
}

/* ---------------------------------------------------------------- camera */

static xrad_status parse_camera(ctx *c, const cJSON *j)
{
    static const char *const keys[] = {"position", "look_at", "up", "fov_degrees",
                                       "width",    "height",  NULL};
    snprintf(c->where, sizeof(c->where), "camera: ");
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    xrad_status st = check_keys(c, j, "", keys);
    vec3 position, look_at, up = v3(0, 1, 0);
    xrad_camera_desc cam = {.fov_degrees = 45};
    bool has_up = false;
    if (st || (st = get_length3(c, j, "position", "position", true, &position, NULL)) ||
        (st = get_length3(c, j, "look_at", "look_at", true, &look_at, NULL)) ||
        (st = get_vec3(c, j, "up", "up", false, &up, &has_up)) ||
        (st = get_number(c, j, "fov_degrees", "fov_degrees", false, &cam.fov_degrees, NULL)))
        return st;
    /* The builder reads a zero `up` as "default". */
    if (has_up && !(v3_len(up) > 0))
        return fail(c, "up", "must be non-zero and not parallel to the view direction");
    if (!(cam.fov_degrees > 0 && cam.fov_degrees < 180))
        return fail(c, "fov_degrees", "must be in (0, 180), got %g", cam.fov_degrees);
    put3(cam.position, position);
    put3(cam.look_at, look_at);
    put3(cam.up, up);
    const cJSON *w = member(j, "width"), *h = member(j, "height");
    if ((w && (st = get_uint(c, w, "width", 1, 16384, &cam.width))) ||
        (h && (st = get_uint(c, h, "height", 1, 16384, &cam.height))))
        return st;
    return xrad_scene_builder_set_camera(c->b, &cam, c->err);
}

/* ------------------------------------------------------------ luminaires */

/* {"name", "file" | "intensity", "scale", "position", "aim", "up", "cone",
 * "falloff"} (scenes/README.md "Luminaires"). */
static xrad_status parse_luminaire(ctx *c, const cJSON *j, uint32_t index)
{
    static const char *const keys[] = {"name", "file", "intensity", "scale",   "position",
                                       "aim",  "up",   "cone",      "falloff", NULL};
    snprintf(c->where, sizeof(c->where), "luminaires[%u]: ", index);
    if (!cJSON_IsObject(j))
        return fail(c, NULL, "must be an object, got %s", type_name(j));
    char name[SCENE_NAME_MAX];
    xrad_status st = check_keys(c, j, "", keys);
    if (st || (st = get_name(c, j, "name", "name", 0, name)))
        return st;
    snprintf(c->where, sizeof(c->where), "luminaire '%s': ", name);
    xrad_luminaire_desc d = {.name = name};
    vec3 position, aim = v3(0, 0, 0), up = v3(0, 0, 0), intensity = v3(0, 0, 0);
    bool has_intensity = false, has;
    if ((st = get_length3(c, j, "position", "position", true, &position, NULL)) ||
        (st = get_vec3(c, j, "aim", "aim", false, &aim, &has)) ||
        (has && !(v3_len(aim) > 0) && (st = fail(c, "aim", "must be non-zero"))) ||
        (st = get_vec3(c, j, "up", "up", false, &up, &has)) ||
        (has && !(v3_len(up) > 0) && (st = fail(c, "up", "must be non-zero"))) ||
        (st = get_vec3(c, j, "intensity", "intensity", false, &intensity, &has_intensity)) ||
        (st = get_number(c, j, "scale", "scale", false, &d.scale, &has)) ||
        (has && !(d.scale > 0) && (st = fail(c, "scale", "must be positive, got %g", d.scale))) ||
        (st = get_number(c, j, "cone", "cone", false, &d.cone_degrees, &has)) ||
        (has && !(d.cone_degrees > 0) &&
         (st = fail(c, "cone", "must be in (0, 180] degrees, got %g", d.cone_degrees))) ||
        (st = get_number(c, j, "falloff", "falloff", false, &d.falloff_degrees, NULL)))
        return st;
    const cJSON *file = member(j, "file");
    char path[1024];
    if (file) {
        if (!cJSON_IsString(file) || !file->valuestring[0])
            return fail(c, "file", "must be a non-empty string, got %s", type_name(file));
        if (has_intensity || d.cone_degrees != 0 || d.falloff_degrees != 0)
            return fail(c, has_intensity ? "intensity" : "cone",
                        "a luminaire's file gives its distribution: no intensity, cone or "
                        "falloff beside it");
        beside_scene(c, file->valuestring, path, sizeof(path));
        d.file = path;
    } else if (!has_intensity) {
        return fail(c, "file", "missing: a luminaire has a photometric file (.ldt, .ies) or "
                    "an intensity (W/sr, a point or spot light)");
    }
    put3(d.position, position);
    put3(d.aim, aim);
    put3(d.up, up);
    put3(d.intensity, intensity);
    return xrad_scene_builder_add_luminaire(c->b, &d, c->err);
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

static xrad_status parse_root(ctx *c, const cJSON *root)
{
    static const char *const keys[] = {"name",    "unit",   "density", "materials",
                                       "objects", "camera", "quality", "luminaires", NULL};
    xrad_scene *sc = scene_builder_scene(c->b);
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
    bool has;
    double density = 0;
    if ((st = get_density(c, root, "density", &density, &has)) ||
        (st = scene_builder_set_density(c->b, c->density_scale, density, c->err)))
        return st;
    xrad_adaptive_desc ad = q.adaptive;
    ad.levels = c->adaptive.levels ? c->adaptive.levels : ad.levels;
    ad.lower = c->adaptive.lower > 0 ? c->adaptive.lower : ad.lower;
    ad.upper = c->adaptive.upper > 0 ? c->adaptive.upper : ad.upper;
    if ((st = scene_builder_set_adaptive(c->b, &ad, c->err)))
        return st;

    const cJSON *mats = member(root, "materials");
    if (!mats)
        return fail(c, "materials", "missing (required)");
    int nm = cJSON_IsArray(mats) ? cJSON_GetArraySize(mats) : 0;
    if (nm < 1)
        return fail(c, "materials", "must be a non-empty array, got %s", type_name(mats));
    if ((uint32_t)nm > SCENE_MAX_MATERIALS)
        return fail(c, "materials", "more than %u materials", SCENE_MAX_MATERIALS);
    uint32_t k = 0;
    for (const cJSON *it = mats->child; it; it = it->next, k++)
        if ((st = parse_material(c, it, k)))
            return st;
    if ((st = scene_builder_check_materials(c->b, c->err)))
        return st;
    uint32_t material_count = sc->material_count;
    if (!(c->material_index = malloc(material_count * sizeof(name_ref))))
        return xrad_fail(c->err, XRAD_ERROR_SYSTEM, "%s: out of memory", c->file);
    for (k = 0; k < material_count; k++)
        c->material_index[k] = (name_ref){sc->materials[k].name, k};
    /* Sorted by name for the lookups (no duplicates: checked above). */
    scene_find_duplicate(c->material_index, material_count);

    c->where[0] = '\0';
    const cJSON *objs = member(root, "objects");
    if (!objs)
        return fail(c, "objects", "missing (required)");
    int no = cJSON_IsArray(objs) ? cJSON_GetArraySize(objs) : 0;
    if (no < 1)
        return fail(c, "objects", "must be a non-empty array, got %s", type_name(objs));
    if ((uint32_t)no > SCENE_MAX_OBJECTS)
        return fail(c, "objects", "more than %u objects", SCENE_MAX_OBJECTS);
    k = 0;
    for (const cJSON *it = objs->child; it; it = it->next, k++)
        if ((st = parse_object(c, it, k, material_count)))
            return st;

    const cJSON *lums = member(root, "luminaires");
    if (lums && !cJSON_IsArray(lums)) {
        c->where[0] = '\0';
        return fail(c, "luminaires", "must be an array, got %s", type_name(lums));
    }
    k = 0;
    for (const cJSON *it = lums ? lums->child : NULL; it; it = it->next, k++)
        if ((st = parse_luminaire(c, it, k)))
            return st;

    c->where[0] = '\0';
    const cJSON *cam = member(root, "camera");
    return cam ? parse_camera(c, cam) : XRAD_OK;
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

    double scale = desc ? desc->density_scale : 0;
    xrad_scene_builder *b = NULL;
    xrad_status st = xrad_scene_builder_create(
        &(xrad_scene_builder_desc){.name = name,
                                   .density_scale = scale,
                                   .adaptive = desc ? desc->adaptive : (xrad_adaptive_desc){0}},
        &b, err);
    if (st) {
        cJSON_Delete(root);
        return st;
    }
    ctx c = {.file = name, .err = err, .b = b, .density_scale = scale};
    if (desc)
        c.adaptive = desc->adaptive;
    st = parse_root(&c, root);
    free(c.material_index);
    cJSON_Delete(root);
    if (!st)
        st = xrad_scene_builder_finish(b, out, err);
    xrad_scene_builder_destroy(&b);
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
    free(sc->element_albedo);
    free(sc->element_normal);
    for (uint32_t k = 0; k < sc->luminaire_count; k++)
        scene_luminaire_free(&sc->luminaires[k]);
    free(sc->luminaires);
    for (uint32_t k = 0; k < sc->mesh_count; k++)
        free(sc->meshes[k].triangles);
    free(sc->meshes);
    for (uint32_t k = 0; k < sc->warning_count; k++)
        free(sc->warnings[k]);
    free(sc->warnings);
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
