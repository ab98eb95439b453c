/* The scene builder (xrad.h): materials, objects, quads and triangle meshes
 * from arrays -> a validated scene -> elements and atlas. The scene-file
 * loader (scene_parse.c) is written on top of it; every check on values
 * lives here, every check on the JSON's shape there. Messages name the
 * builder (the file), the object or material, the surface and the field,
 * as scenes/README.md lists them. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_internal.h"
#include "scene/scene_luminaire.h"
#include "scene/scene_texture.h"

#define PI 3.14159265358979323846

/* Two triangles join into a quad when the fourth vertex lies within this
 * fraction of the pair's longest edge from the first triangle's plane. */
#define MESH_COPLANAR 1e-6

struct xrad_scene_builder {
    xrad_scene *sc;
    char file[512];
    double density;       /* scene default, per m, scaled */
    double density_scale; /* every density given times this */
    xrad_adaptive_desc adaptive; /* defaults filled in */
    uint64_t elements;    /* so far, for the limit */
    uint32_t material_cap, object_cap, surface_cap, mesh_cap, luminaire_cap;
    /* Albedo and normal maps (scene_texture.h): per material once one has
     * a map (width 0: none), and the texture coordinates of the surfaces
     * with one; NULL in a scene without. The elements' albedos and
     * normals come from them at finish, and they go. */
    scene_material_maps *maps;
    uint32_t map_cap;
    scene_uv *uv;
    uint32_t uv_cap;
    bool in_object;   /* objects[object_count - 1] takes surfaces */
    bool has_camera;
    bool failed;      /* a call failed: only destroy is left */
};

static int name_ref_cmp(const void *pa, const void *pb)
{
    const name_ref *a = pa, *b = pb;
    int c = strcmp(a->name, b->name);
    if (c)
        return c;
    return a->index < b->index ? -1 : a->index > b->index;
}

uint32_t scene_find_duplicate(name_ref *r, uint32_t n)
{
    qsort(r, n, sizeof(*r), name_ref_cmp);
    uint32_t dup = n;
    for (uint32_t k = 1; k < n; k++)
        if (!strcmp(r[k - 1].name, r[k].name) && (dup == n || r[k].index < r[dup].index))
            dup = k;
    return dup;
}

/* "FILE: WHERE field 'FIELD': MESSAGE", WHERE as "object 'room': surface
 * 'floor': "; the builder is failed from then on. */
XRAD_PRINTF(5, 6)
static xrad_status fail(xrad_scene_builder *b, xrad_error *err, const char *where,
                        const char *field, const char *fmt, ...)
{
    char msg[640];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    b->failed = true;
    if (field)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %sfield '%.80s': %s", b->file, where, field,
                         msg);
    return xrad_fail(err, XRAD_ERROR_INPUT, "%s: %s%s", b->file, where, msg);
}

static xrad_status out_of_memory(xrad_scene_builder *b, xrad_error *err)
{
    b->failed = true;
    return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", b->file);
}

static xrad_status check_usable(xrad_scene_builder *b, xrad_error *err)
{
    if (!b)
        return xrad_fail(err, XRAD_ERROR_INPUT, "scene builder: NULL");
    if (b->failed || !b->sc)
        return xrad_fail(err, XRAD_ERROR_INPUT,
                         "%s: the builder failed or finished before; destroy it", b->file);
    return XRAD_OK;
}

/* A name: non-empty, shorter than SCENE_NAME_MAX - reserve bytes, printable. */
static xrad_status check_name(xrad_scene_builder *b, xrad_error *err, const char *where,
                              const char *name, size_t reserve)
{
    if (!name || !name[0])
        return fail(b, err, where, "name", name ? "must not be empty" : "missing (required)");
    size_t len = strlen(name);
    if (len >= SCENE_NAME_MAX - reserve)
        return fail(b, err, where, "name", "longer than %zu characters",
                    SCENE_NAME_MAX - reserve - 1);
    for (size_t i = 0; i < len; i++)
        if ((unsigned char)name[i] < 0x20 || name[i] == 0x7f)
            return fail(b, err, where, "name", "contains a control character");
    return XRAD_OK;
}

static bool finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static xrad_status check_coord(xrad_scene_builder *b, xrad_error *err, const char *where,
                               const char *field, vec3 v)
{
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!(m <= SCENE_MAX_COORD))
        return fail(b, err, where, field, "%g m is out of range (at most %g m)", m,
                    SCENE_MAX_COORD);
    return XRAD_OK;
}

/* A density as given (0: inherit `fallback`) -> elements per metre, scaled. */
static xrad_status check_density(xrad_scene_builder *b, xrad_error *err, const char *where,
                                 const char *field, double given, double fallback, double *out)
{
    if (given == 0) {
        *out = fallback;
        return XRAD_OK;
    }
    if (!(given > 0) || given > SCENE_MAX_DENSITY)
        return fail(b, err, where, field, "must be in (0, %g] elements per metre, got %g",
                    SCENE_MAX_DENSITY, given);
    *out = given * b->density_scale;
    if (*out > SCENE_MAX_DENSITY)
        return fail(b, err, where, field,
                    "%g x the density scale %g is more than %g elements per metre", given,
                    b->density_scale, SCENE_MAX_DENSITY);
    return XRAD_OK;
}

xrad_status xrad_scene_builder_create(const xrad_scene_builder_desc *desc,
                                      xrad_scene_builder **out, xrad_error *err)
{
    *out = NULL;
    xrad_scene_builder_desc d = desc ? *desc : (xrad_scene_builder_desc){0};
    const char *name = d.name ? d.name : "<builder>";
    if (d.density_scale != 0 && !(d.density_scale > 0 && d.density_scale <= 16))
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: density_scale %g is outside (0, 16]", name,
                         d.density_scale);
    xrad_adaptive_desc ad;
    xrad_status st = scene_adaptive_check(&d.adaptive, name, &ad, err);
    if (st)
        return st;
    xrad_scene_builder *b = calloc(1, sizeof(*b));
    if (!b || !(b->sc = calloc(1, sizeof(xrad_scene)))) {
        free(b);
        return xrad_fail(err, XRAD_ERROR_SYSTEM, "%s: out of memory", name);
    }
    snprintf(b->file, sizeof(b->file), "%s", name);
    snprintf(b->sc->path, sizeof(b->sc->path), "%s", name);
    b->sc->unit = 1.0;
    b->density_scale = d.density_scale > 0 ? d.density_scale : 1.0;
    b->sc->density_scale = b->density_scale;
    b->adaptive = ad;
    st = check_density(b, err, "", "density", d.density, 20 * b->density_scale, &b->density);
    if (st) {
        xrad_scene_builder_destroy(&b);
        return st;
    }
    b->sc->density = b->density;
    b->sc->cam = (camera){.up = v3(0, 1, 0), .width = 512, .height = 512};
    *out = b;
    return XRAD_OK;
}

static void free_maps(xrad_scene_builder *b)
{
    for (uint32_t k = 0; k < b->map_cap; k++) {
        free(b->maps[k].albedo.rgb);
        free(b->maps[k].normal.rgb);
    }
    free(b->maps);
    free(b->uv);
    b->maps = NULL;
    b->uv = NULL;
    b->map_cap = b->uv_cap = 0;
}

void xrad_scene_builder_destroy(xrad_scene_builder **builder)
{
    if (!builder || !*builder)
        return;
    free_maps(*builder);
    xrad_scene_destroy(&(*builder)->sc);
    free(*builder);
    *builder = NULL;
}

xrad_scene *scene_builder_scene(xrad_scene_builder *b)
{
    return b->sc;
}

xrad_status scene_builder_set_adaptive(xrad_scene_builder *b, const xrad_adaptive_desc *d,
                                       xrad_error *err)
{
    return scene_adaptive_check(d, b->file, &b->adaptive, err);
}

xrad_status scene_builder_set_density(xrad_scene_builder *b, double scale, double density,
                                      xrad_error *err)
{
    b->density_scale = scale;
    b->sc->density_scale = scale;
    xrad_status st = check_density(b, err, "", "density", density, 20 * scale, &b->density);
    b->sc->density = b->density;
    return st;
}

#define SCENE_MAX_WARNINGS 64

void scene_builder_warn(xrad_scene_builder *b, const char *fmt, ...)
{
    xrad_scene *sc = b->sc;
    if (!sc || sc->warning_count >= SCENE_MAX_WARNINGS)
        return;
    char **w = realloc(sc->warnings, (sc->warning_count + 1) * sizeof(char *));
    if (!w)
        return;
    sc->warnings = w;
    char line[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(line, sizeof(line), fmt, ap);
    va_end(ap);
    if ((w[sc->warning_count] = strdup(line)))
        sc->warning_count++;
}

/* Grows *array (elements of `size` bytes, capacity *cap) to hold n. */
static bool grow(void **array, uint32_t *cap, uint32_t n, size_t size)
{
    if (n <= *cap)
        return true;
    uint32_t c = *cap ? *cap : 16;
    while (c < n)
        c = c > UINT32_MAX / 2 ? n : c * 2;
    void *p = realloc(*array, (size_t)c * size);
    if (!p)
        return false;
    *array = p;
    *cap = c;
    return true;
}

/* grow, the new entries zeroed. */
static bool grow_zeroed(void **array, uint32_t *cap, uint32_t n, size_t size)
{
    uint32_t old = *cap;
    if (!grow(array, cap, n, size))
        return false;
    memset((char *)*array + (size_t)old * size, 0, (size_t)(*cap - old) * size);
    return true;
}

static bool mapped(const xrad_scene_builder *b, uint32_t mat)
{
    return mat < b->map_cap && (b->maps[mat].albedo.width || b->maps[mat].normal.width);
}

xrad_status xrad_scene_builder_add_material(xrad_scene_builder *b, const xrad_material_desc *m,
                                            uint32_t *index, xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st)
        return st;
    xrad_scene *sc = b->sc;
    char where[SCENE_NAME_MAX + 32];
    snprintf(where, sizeof(where), "material #%u: ", sc->material_count);
    if (!m)
        return fail(b, err, where, NULL, "no description (NULL)");
    if ((st = check_name(b, err, where, m->name, 0)))
        return st;
    snprintf(where, sizeof(where), "material '%s': ", m->name);
    if (sc->material_count >= SCENE_MAX_MATERIALS)
        return fail(b, err, "", "materials", "more than %u materials", SCENE_MAX_MATERIALS);
    for (int k = 0; k < 3; k++)
        if (!(m->albedo[k] >= 0 && m->albedo[k] < 1))
            return fail(b, err, where, "albedo", "must be in [0, 1), got %g", m->albedo[k]);
    for (int k = 0; k < 3; k++)
        if (!(m->emission[k] >= 0 && m->emission[k] <= SCENE_MAX_EMISSION))
            return fail(b, err, where, "emission", "must be in [0, %g] W/m^2, got %g",
                        SCENE_MAX_EMISSION, m->emission[k]);
    if (m->normal_map_levels < XRAD_NORMAL_MAP_LEVELS_NONE ||
        m->normal_map_levels > XRAD_NORMAL_MAP_LEVELS_MAX)
        return fail(b, err, where, "normal_map_levels", "must be %d (none) to %d, got %d",
                    XRAD_NORMAL_MAP_LEVELS_NONE, XRAD_NORMAL_MAP_LEVELS_MAX, m->normal_map_levels);
    if (!grow((void **)&sc->materials, &b->material_cap, sc->material_count + 1,
              sizeof(material)))
        return out_of_memory(b, err);
    if (m->albedo_map || m->normal_map) {
        if (!grow_zeroed((void **)&b->maps, &b->map_cap, sc->material_count + 1,
                         sizeof(scene_material_maps)))
            return out_of_memory(b, err);
        char w[sizeof(b->file) + SCENE_NAME_MAX + 32];
        snprintf(w, sizeof(w), "%s: %s", b->file, where);
        scene_material_maps *mm = &b->maps[sc->material_count];
        mm->normal_levels = m->normal_map_levels == 0  ? 1
                            : m->normal_map_levels < 0 ? 0
                                                       : (uint32_t)m->normal_map_levels;
        if ((m->albedo_map &&
             (st = scene_texture_copy(m->albedo_map, &mm->albedo, w, "albedo_map", err))) ||
            (m->normal_map &&
             (st = scene_texture_copy(m->normal_map, &mm->normal, w, "normal_map", err)))) {
            b->failed = true;
            return st;
        }
    }
    material *mt = &sc->materials[sc->material_count];
    memset(mt, 0, sizeof(*mt));
    snprintf(mt->name, sizeof(mt->name), "%s", m->name);
    mt->albedo = v3(m->albedo[0], m->albedo[1], m->albedo[2]);
    mt->emission = v3(m->emission[0], m->emission[1], m->emission[2]);
    if (index)
        *index = sc->material_count;
    sc->material_count++;
    return XRAD_OK;
}

xrad_status scene_builder_check_materials(xrad_scene_builder *b, xrad_error *err)
{
    xrad_scene *sc = b->sc;
    name_ref *refs = malloc((sc->material_count + 1) * sizeof(*refs));
    if (!refs)
        return out_of_memory(b, err);
    for (uint32_t k = 0; k < sc->material_count; k++)
        refs[k] = (name_ref){sc->materials[k].name, k};
    uint32_t dup = scene_find_duplicate(refs, sc->material_count);
    xrad_status st = XRAD_OK;
    if (dup < sc->material_count) {
        char where[SCENE_NAME_MAX + 32];
        snprintf(where, sizeof(where), "material '%s': ", refs[dup].name);
        st = fail(b, err, where, "name", "duplicate material name '%s'", refs[dup].name);
    }
    free(refs);
    return st;
}

/* ---------------------------------------------------------------- objects */

static void object_where(const xrad_scene_builder *b, char *where, size_t size)
{
    snprintf(where, size, "object '%s': ", b->sc->objects[b->sc->object_count - 1].name);
}

/* Closes the current object: it has surfaces, their names are unique, and
 * its cross density gives a sane element count. */
static xrad_status end_object(xrad_scene_builder *b, xrad_error *err)
{
    if (!b->in_object)
        return XRAD_OK;
    b->in_object = false;
    xrad_scene *sc = b->sc;
    object *ob = &sc->objects[sc->object_count - 1];
    char where[SCENE_NAME_MAX + 16];
    object_where(b, where, sizeof(where));
    ob->surface_count = sc->surface_count - ob->first_surface;
    if (ob->surface_count == 0)
        return fail(b, err, where, "surfaces", "the object has no surfaces");
    name_ref *refs = malloc(ob->surface_count * sizeof(*refs));
    if (!refs)
        return out_of_memory(b, err);
    for (uint32_t s = 0; s < ob->surface_count; s++)
        refs[s] = (name_ref){sc->surfaces[ob->first_surface + s].name, s};
    uint32_t dup = scene_find_duplicate(refs, ob->surface_count);
    xrad_status st = XRAD_OK;
    if (dup < ob->surface_count) {
        char sw[2 * SCENE_NAME_MAX + 32];
        snprintf(sw, sizeof(sw), "%ssurface '%s': ", where, refs[dup].name);
        st = fail(b, err, sw, "name",
                  "duplicate surface name '%s' in this object (box faces are named "
                  "<box>.-u, <box>.+u, ...; mesh surfaces <mesh>.0, <mesh>.1, ...)",
                  refs[dup].name);
    }
    free(refs);
    if (st || !(ob->cross_density > 0))
        return st;
    /* In double: a long edge at a high density overflows any integer. */
    double n = 0;
    for (uint32_t s = ob->first_surface; s < sc->surface_count; s++) {
        double lu, lv;
        scene_quad_edge_lengths(&sc->surfaces[s], &lu, &lv);
        n += scene_samples_along(lu, ob->cross_density) *
             scene_samples_along(lv, ob->cross_density);
        if (n > SCENE_MAX_ELEMENTS)
            return fail(b, err, where, "cross_density", "gives more than %u elements",
                        SCENE_MAX_ELEMENTS);
    }
    ob->cross_element_count = (uint32_t)n;
    return XRAD_OK;
}

static xrad_status check_animation(xrad_scene_builder *b, xrad_error *err, const char *where,
                                   const xrad_animation_desc *a, animation *out)
{
    out->loop = !a->once;
    if (a->rotates) {
        vec3 axis = v3(a->axis[0], a->axis[1], a->axis[2]);
        double len = v3_len(axis);
        if (!(len > 0) || !isfinite(len))
            return fail(b, err, where, "animation.rotate.axis",
                        "must be a non-zero vector of finite length");
        vec3 pivot = v3(a->pivot[0], a->pivot[1], a->pivot[2]);
        xrad_status st = check_coord(b, err, where, "animation.rotate.pivot", pivot);
        if (st)
            return st;
        if (!isfinite(a->degrees_per_second))
            return fail(b, err, where, "animation.rotate.degrees_per_second",
                        "must be a finite number, got %g", a->degrees_per_second);
        out->rotates = true;
        out->axis = v3_scale(axis, 1.0 / len);
        out->pivot = pivot;
        out->rate = a->degrees_per_second * PI / 180.0;
    }
    if (a->keyframe_count == 0)
        return XRAD_OK;
    if (!a->keyframes || a->keyframe_count > SCENE_MAX_KEYFRAMES)
        return fail(b, err, where, "animation.keyframes", "must have 1 to %u keys, got %u",
                    SCENE_MAX_KEYFRAMES, a->keyframes ? a->keyframe_count : 0);
    out->keyframes = calloc(a->keyframe_count, sizeof(keyframe));
    if (!out->keyframes)
        return out_of_memory(b, err);
    out->keyframe_count = a->keyframe_count;
    for (uint32_t k = 0; k < a->keyframe_count; k++) {
        const xrad_keyframe *in = &a->keyframes[k];
        char ftime[64], ftrans[64];
        snprintf(ftime, sizeof(ftime), "animation.keyframes[%u].time", k);
        snprintf(ftrans, sizeof(ftrans), "animation.keyframes[%u].translate", k);
        if (!isfinite(in->time))
            return fail(b, err, where, ftime, "must be a finite number, got %g", in->time);
        if (in->time < 0)
            return fail(b, err, where, ftime, "must be >= 0 s, got %g", in->time);
        if (k > 0 && !(in->time > a->keyframes[k - 1].time))
            return fail(b, err, where, ftime, "times must increase strictly: %g after %g",
                        in->time, a->keyframes[k - 1].time);
        if (!finite3(in->translate))
            return fail(b, err, where, ftrans, "must be finite");
        vec3 t = v3(in->translate[0], in->translate[1], in->translate[2]);
        xrad_status st = check_coord(b, err, where, ftrans, t);
        if (st)
            return st;
        out->keyframes[k] = (keyframe){in->time, t};
    }
    return XRAD_OK;
}

xrad_status xrad_scene_builder_begin_object(xrad_scene_builder *b, const xrad_object_desc *o,
                                            xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st || (st = end_object(b, err)))
        return st;
    xrad_scene *sc = b->sc;
    char where[SCENE_NAME_MAX + 32];
    snprintf(where, sizeof(where), "object #%u: ", sc->object_count);
    if (!o)
        return fail(b, err, where, NULL, "no description (NULL)");
    if ((st = check_name(b, err, where, o->name, 0)))
        return st;
    snprintf(where, sizeof(where), "object '%s': ", o->name);
    if (sc->object_count >= SCENE_MAX_OBJECTS)
        return fail(b, err, "", "objects", "more than %u objects", SCENE_MAX_OBJECTS);
    if (!grow((void **)&sc->objects, &b->object_cap, sc->object_count + 1, sizeof(object)))
        return out_of_memory(b, err);
    object *ob = &sc->objects[sc->object_count++];
    memset(ob, 0, sizeof(*ob));
    snprintf(ob->name, sizeof(ob->name), "%s", o->name);
    ob->dynamic = o->dynamic != 0;
    ob->first_surface = sc->surface_count;
    b->in_object = true;

    if (!finite3(o->translate))
        return fail(b, err, where, "translate", "must be finite");
    vec3 translate = v3(o->translate[0], o->translate[1], o->translate[2]);
    if ((st = check_coord(b, err, where, "translate", translate)))
        return st;
    mat3 rot = m3_identity();
    if (o->rotate_degrees != 0) {
        vec3 axis = v3(o->rotate_axis[0], o->rotate_axis[1], o->rotate_axis[2]);
        double len = v3_len(axis);
        if (!(len > 0) || !isfinite(len))
            return fail(b, err, where, "rotate.axis", "must be a non-zero vector of finite length");
        if (!isfinite(o->rotate_degrees))
            return fail(b, err, where, "rotate.degrees", "must be a finite number, got %g",
                        o->rotate_degrees);
        rot = m3_rotation(v3_scale(axis, 1.0 / len), o->rotate_degrees * PI / 180.0);
    }
    ob->base = (xform){rot, translate};
    double density;
    if ((st = check_density(b, err, where, "density", o->density, b->density, &density)))
        return st;
    ob->density = density;
    if (o->cross_density != 0) {
        if (!ob->dynamic)
            return fail(b, err, where, "cross_density",
                        "only allowed on dynamic objects (\"dynamic\": true)");
        if ((st = check_density(b, err, where, "cross_density", o->cross_density, 0,
                                &ob->cross_density)))
            return st;
    }
    if (o->animation) {
        if (!ob->dynamic)
            return fail(b, err, where, "animation",
                        "only allowed on dynamic objects (\"dynamic\": true)");
        if ((st = check_animation(b, err, where, o->animation, &ob->anim)))
            return st;
    }
    return XRAD_OK;
}

/* --------------------------------------------------------------- surfaces */

static xrad_status begin_surface(xrad_scene_builder *b, xrad_error *err, surface **out)
{
    xrad_scene *sc = b->sc;
    if (!b->in_object)
        return fail(b, err, "", NULL, "a surface comes after xrad_scene_builder_begin_object");
    if (sc->surface_count >= SCENE_MAX_SURFACES)
        return fail(b, err, "", NULL, "more than %u surfaces in the scene", SCENE_MAX_SURFACES);
    if (!grow((void **)&sc->surfaces, &b->surface_cap, sc->surface_count + 1, sizeof(surface)))
        return out_of_memory(b, err);
    *out = &sc->surfaces[sc->surface_count];
    memset(*out, 0, sizeof(**out));
    (*out)->object = sc->object_count - 1;
    return XRAD_OK;
}

/* Counts the elements of the surface being added (its p, name set), checks
 * the limits and appends it. counts: explicit samples, or NULL. */
static xrad_status finish_surface(xrad_scene_builder *b, xrad_error *err, const char *where,
                                  const char *density_field, double density,
                                  const uint32_t counts[2])
{
    xrad_scene *sc = b->sc;
    surface *s = &sc->surfaces[sc->surface_count];
    const char *count_field = "elements";
    if (counts && counts[0]) {
        s->nu = counts[0];
        s->nv = counts[1];
    } else {
        double lu, lv;
        scene_quad_edge_lengths(s, &lu, &lv);
        double nu = scene_samples_along(lu, density);
        double nv = scene_samples_along(lv, density);
        count_field = density_field;
        if (nu > SCENE_MAX_SAMPLES || nv > SCENE_MAX_SAMPLES)
            return fail(b, err, where, count_field,
                        "gives %.0f x %.0f elements on surface '%s', more than %u along an edge",
                        nu, nv, s->name, SCENE_MAX_SAMPLES);
        s->nu = (uint32_t)nu;
        s->nv = (uint32_t)nv;
        /* A triangle within one spacing either way is one element at its
         * centroid (scene.h): its 2 x 2 samples would sit on its corners,
         * four values for what the density resolves as one. */
        if (s->triangle && nu <= 2 && nv <= 2)
            s->nu = s->nv = 1;
    }
    b->elements += (uint64_t)s->nu * s->nv;
    if (b->elements > SCENE_MAX_ELEMENTS)
        return fail(b, err, where, count_field,
                    "surface '%s' (%u x %u) brings the scene to %llu elements, more than %u",
                    s->name, s->nu, s->nv, (unsigned long long)b->elements, SCENE_MAX_ELEMENTS);
    if (mapped(b, s->material)) {
        /* A quad's map lies on its parameters (xrad.h); a mesh's
         * triangles set theirs after. */
        if (!grow_zeroed((void **)&b->uv, &b->uv_cap, sc->surface_count + 1, sizeof(scene_uv)))
            return out_of_memory(b, err);
        b->uv[sc->surface_count] = (scene_uv){{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
    }
    sc->surface_count++;
    return XRAD_OK;
}

xrad_status scene_builder_quad(xrad_scene_builder *b, const xrad_quad_desc *q, const char *where,
                               const char *field, double density, xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    surface *s;
    if (st || (st = begin_surface(b, err, &s)))
        return st;
    vec3 p[4];
    for (int k = 0; k < 4; k++) {
        if (!finite3(q->p[k]))
            return fail(b, err, where, field, "vertex %d is not finite", k);
        p[k] = v3(q->p[k][0], q->p[k][1], q->p[k][2]);
        if ((st = check_coord(b, err, where, field, p[k])))
            return st;
    }
    if (q->material >= b->sc->material_count)
        return fail(b, err, where, "material", "material %u does not exist (%u materials)",
                    q->material, b->sc->material_count);
    for (int k = 0; k < 2; k++)
        if ((q->samples[0] || q->samples[1]) &&
            !(q->samples[k] >= 2 && q->samples[k] <= SCENE_MAX_SAMPLES))
            return fail(b, err, where, "elements", "must be in [2, %u], got %u",
                        SCENE_MAX_SAMPLES, q->samples[k]);
    char why[256];
    if (!scene_quad_setup(s, p, why, sizeof(why)))
        return fail(b, err, where, field, "%s", why);
    snprintf(s->name, sizeof(s->name), "%s", q->name);
    s->object = b->sc->object_count - 1;
    s->material = q->material;
    return finish_surface(b, err, where, "density", density, q->samples);
}

xrad_status scene_builder_surface_density(xrad_scene_builder *b, const char *where,
                                          double given, double *out, xrad_error *err)
{
    const object *ob = &b->sc->objects[b->sc->object_count - 1];
    return check_density(b, err, where, "density", given, ob->density, out);
}

xrad_status xrad_scene_builder_add_quad(xrad_scene_builder *b, const xrad_quad_desc *q,
                                        xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st)
        return st;
    if (!b->in_object)
        return fail(b, err, "", NULL, "a surface comes after xrad_scene_builder_begin_object");
    char where[3 * SCENE_NAME_MAX + 32];
    object_where(b, where, sizeof(where));
    size_t len = strlen(where);
    snprintf(where + len, sizeof(where) - len, "surface #%u: ",
             b->sc->surface_count - b->sc->objects[b->sc->object_count - 1].first_surface);
    if (!q)
        return fail(b, err, where, NULL, "no description (NULL)");
    if ((st = check_name(b, err, where, q->name, 0)))
        return st;
    snprintf(where + len, sizeof(where) - len, "surface '%s': ", q->name);
    double density;
    if ((st = scene_builder_surface_density(b, where, q->density, &density, err)))
        return st;
    return scene_builder_quad(b, q, where, "p", density, err);
}

/* ----------------------------------------------------------------- meshes */

/* Vertices welded by position: weld[v] is the smallest index with the same
 * coordinates, so that triangles of a mesh exported with split vertices
 * still find their neighbours. */
typedef struct weld_key {
    float p[3];
    uint32_t index;
} weld_key;

static int weld_cmp(const void *pa, const void *pb)
{
    const weld_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->p[k] != b->p[k])
            return a->p[k] < b->p[k] ? -1 : 1;
    return a->index < b->index ? -1 : a->index > b->index;
}

typedef struct mesh_edge {
    uint32_t lo, hi; /* welded vertex ids, lo < hi */
    uint32_t tri;
    uint8_t slot;    /* edge slot: from corner slot to corner (slot + 1) % 3 */
} mesh_edge;

static int edge_cmp(const void *pa, const void *pb)
{
    const mesh_edge *a = pa, *b = pb;
    if (a->lo != b->lo)
        return a->lo < b->lo ? -1 : 1;
    if (a->hi != b->hi)
        return a->hi < b->hi ? -1 : 1;
    return a->tri < b->tri ? -1 : a->tri > b->tri;
}

static vec3 mesh_point(const xrad_mesh_desc *m, uint32_t v)
{
    return v3(m->positions[3 * v], m->positions[3 * v + 1], m->positions[3 * v + 2]);
}

/* The quad of triangles t (a b c, the shared edge b c) and u (c b d): a b d c,
 * when coplanar and convex (scene_quad_setup says). Written q = a c d b:
 * join_slots gives the slot each triangle's corner lands on. */
static bool join_pair(const xrad_mesh_desc *m, uint32_t t, int slot_t, uint32_t u, int slot_u,
                      vec3 q[4])
{
    const uint32_t *it = &m->indices[3 * t], *iu = &m->indices[3 * u];
    vec3 a = mesh_point(m, it[(slot_t + 2) % 3]), pb = mesh_point(m, it[(slot_t + 1) % 3]);
    vec3 c = mesh_point(m, it[slot_t]), d = mesh_point(m, iu[(slot_u + 2) % 3]);
    /* Edge slot s runs from corner s to corner s + 1: t's edge c -> b is
     * slot_t (c = it[slot_t]); written a b d c, counter-clockwise. */
    vec3 n = v3_cross(v3_sub(pb, a), v3_sub(c, a));
    double nl = v3_len(n);
    double size = fmax(v3_len(v3_sub(pb, c)), fmax(v3_len(v3_sub(a, d)), v3_len(v3_sub(pb, a))));
    if (!(nl > 0) || fabs(v3_dot(v3_scale(n, 1.0 / nl), v3_sub(d, a))) > MESH_COPLANAR * size)
        return false;
    q[0] = a;
    q[1] = c;
    q[2] = d;
    q[3] = pb;
    surface probe;
    char why[256];
    return scene_quad_setup(&probe, q, why, sizeof(why));
}

static void mesh_uv(const xrad_mesh_desc *m, uint32_t v, double out[2])
{
    out[0] = m->uvs[2 * v];
    out[1] = m->uvs[2 * v + 1];
}

/* Whether triangles t and u (join_pair's) map the texture by one affine
 * map of the plane: then the quad's bilinear coordinates are exact
 * (scene_texture.h), else the pair stays two triangles. u's corners are
 * predicted from t's map (barycentric coordinates in t's plane). */
static bool uv_affine(const xrad_mesh_desc *m, uint32_t t, uint32_t u)
{
    const uint32_t *it = &m->indices[3 * t], *iu = &m->indices[3 * u];
    vec3 p0 = mesh_point(m, it[0]);
    vec3 e1 = v3_sub(mesh_point(m, it[1]), p0), e2 = v3_sub(mesh_point(m, it[2]), p0);
    double d11 = v3_dot(e1, e1), d12 = v3_dot(e1, e2), d22 = v3_dot(e2, e2);
    double det = d11 * d22 - d12 * d12;
    if (!(det > 0))
        return false;
    double w[3][2];
    for (int k = 0; k < 3; k++)
        mesh_uv(m, it[k], w[k]);
    double extent = 0;
    for (int k = 0; k < 3; k++)
        for (int c = 0; c < 2; c++)
            extent = fmax(extent, fabs(w[k][c] - w[0][c]));
    for (int k = 0; k < 3; k++) {
        vec3 d = v3_sub(mesh_point(m, iu[k]), p0);
        double r1 = v3_dot(d, e1), r2 = v3_dot(d, e2);
        double b1 = (d22 * r1 - d12 * r2) / det, b2 = (d11 * r2 - d12 * r1) / det;
        double have[2];
        mesh_uv(m, iu[k], have);
        for (int c = 0; c < 2; c++) {
            double want = w[0][c] + b1 * (w[1][c] - w[0][c]) + b2 * (w[2][c] - w[0][c]);
            if (!(fabs(have[c] - want) <= 1e-5 * fmax(extent, 1e-3)))
                return false;
        }
    }
    return true;
}

/* The quad slots of join_pair's corners: t's corner slot_t is c (q[1]),
 * slot_t + 1 is b (q[3]), slot_t + 2 is a (q[0]); u's corner slot_u is b
 * (its edge b -> c), slot_u + 1 is c, slot_u + 2 is d (q[2]). The quad
 * keeps this order (scene_quad_setup neither rotates nor reorders). */
static void join_slots(int slot_t, int slot_u, uint8_t st[3], uint8_t su[3])
{
    st[slot_t] = 1;
    st[(slot_t + 1) % 3] = 3;
    st[(slot_t + 2) % 3] = 0;
    su[slot_u] = 3;
    su[(slot_u + 1) % 3] = 1;
    su[(slot_u + 2) % 3] = 2;
}

/* Surface si's corner `slot` has mesh vertex v's texture coordinates. */
static void set_uv(xrad_scene_builder *b, const xrad_mesh_desc *m, uint32_t si, int slot,
                   uint32_t v)
{
    b->uv[si].uv[slot][0] = m->uvs[2 * v];
    b->uv[si].uv[slot][1] = m->uvs[2 * v + 1];
}

/* The corner k of a triangle that became the apex, slot 2 (= slot 3). */
static int went_apex(const mesh_triangle *w)
{
    return w->slot[0] == 2 ? 0 : w->slot[1] == 2 ? 1 : 2;
}

xrad_status xrad_scene_builder_add_mesh(xrad_scene_builder *b, const xrad_mesh_desc *m,
                                        xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st)
        return st;
    if (!b->in_object)
        return fail(b, err, "", NULL, "a mesh comes after xrad_scene_builder_begin_object");
    char where[3 * SCENE_NAME_MAX + 32];
    object_where(b, where, sizeof(where));
    size_t len = strlen(where);
    if (!m)
        return fail(b, err, where, NULL, "mesh: no description (NULL)");
    snprintf(where + len, sizeof(where) - len, "mesh: ");
    /* Room for ".99999999" after the name. */
    if ((st = check_name(b, err, where, m->name, 10)))
        return st;
    snprintf(where + len, sizeof(where) - len, "mesh '%s': ", m->name);
    if (!m->positions || !m->indices || m->vertex_count == 0 || m->triangle_count == 0)
        return fail(b, err, where, m->positions ? "indices" : "positions",
                    "missing or empty (%u vertices, %u triangles)", m->vertex_count,
                    m->triangle_count);
    if (m->triangle_count > SCENE_MAX_SURFACES)
        return fail(b, err, where, "indices", "%u triangles, more than %u", m->triangle_count,
                    SCENE_MAX_SURFACES);
    for (uint32_t v = 0; v < m->vertex_count; v++) {
        char field[48];
        snprintf(field, sizeof(field), "positions[%u]", v);
        vec3 p = mesh_point(m, v);
        if (!(isfinite(p.x) && isfinite(p.y) && isfinite(p.z)))
            return fail(b, err, where, field, "is not finite");
        if ((st = check_coord(b, err, where, field, p)))
            return st;
    }
    bool any_mapped = false;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        for (int k = 0; k < 3; k++)
            if (m->indices[3 * t + k] >= m->vertex_count)
                return fail(b, err, where, "indices",
                            "triangle %u: vertex index %u is out of range (%u vertices)", t,
                            m->indices[3 * t + k], m->vertex_count);
        uint32_t mat = m->materials ? m->materials[t] : m->material;
        if (mat >= b->sc->material_count)
            return fail(b, err, where, m->materials ? "materials" : "material",
                        "triangle %u: material %u does not exist (%u materials)", t, mat,
                        b->sc->material_count);
        if (mapped(b, mat) && !m->uvs)
            return fail(b, err, where, "uvs",
                        "missing: triangle %u's material '%s' has an albedo or normal map", t,
                        b->sc->materials[mat].name);
        any_mapped = any_mapped || mapped(b, mat);
    }
    /* Read (and so checked) only for a mapped material's triangles. */
    for (uint32_t v = 0; any_mapped && v < m->vertex_count; v++)
        if (!(isfinite(m->uvs[2 * v]) && isfinite(m->uvs[2 * v + 1]) &&
              fabs(m->uvs[2 * v]) <= 1e6 && fabs(m->uvs[2 * v + 1]) <= 1e6)) {
            char field[48];
            snprintf(field, sizeof(field), "uvs[%u]", v);
            return fail(b, err, where, field, "(%g, %g) is not finite or beyond 1e6",
                        m->uvs[2 * v], m->uvs[2 * v + 1]);
        }
    double density;
    if ((st = scene_builder_surface_density(b, where, m->density, &density, err)))
        return st;

    uint32_t nt = m->triangle_count;
    uint32_t *weld = malloc(m->vertex_count * sizeof(uint32_t));
    weld_key *order = malloc(m->vertex_count * sizeof(weld_key));
    mesh_edge *edges = malloc(3ull * nt * sizeof(mesh_edge));
    uint32_t *partner = malloc(nt * sizeof(uint32_t)); /* joined triangle, or UINT32_MAX */
    int8_t *partner_slot = malloc(nt);
    uint8_t *degenerate = calloc(nt, 1);
    /* Where each triangle went (xrad_scene_get_mesh_corners). */
    mesh_triangle *went = malloc(nt * sizeof(mesh_triangle));
    if (!weld || !order || !edges || !partner || !partner_slot || !degenerate || !went) {
        st = out_of_memory(b, err);
        goto done;
    }
    for (uint32_t v = 0; v < m->vertex_count; v++)
        order[v] = (weld_key){{m->positions[3 * v], m->positions[3 * v + 1],
                               m->positions[3 * v + 2]},
                              v};
    qsort(order, m->vertex_count, sizeof(weld_key), weld_cmp);
    for (uint32_t k = 0; k < m->vertex_count; k++) {
        bool same = k > 0 && !memcmp(order[k].p, order[k - 1].p, sizeof(order[k].p));
        weld[order[k].index] = same ? weld[order[k - 1].index] : order[k].index;
    }
    for (uint32_t t = 0; t < nt; t++) {
        partner[t] = UINT32_MAX;
        partner_slot[t] = -1;
        vec3 p[3];
        for (int k = 0; k < 3; k++)
            p[k] = mesh_point(m, m->indices[3 * t + k]);
        double l = fmax(v3_len(v3_sub(p[1], p[0])),
                        fmax(v3_len(v3_sub(p[2], p[1])), v3_len(v3_sub(p[0], p[2]))));
        double a2 = v3_len(v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0])));
        degenerate[t] = !(a2 > 1e-9 * l * l);
        for (int k = 0; k < 3; k++) {
            uint32_t v0 = weld[m->indices[3 * t + k]], v1 = weld[m->indices[3 * t + (k + 1) % 3]];
            edges[3 * t + k] = (mesh_edge){v0 < v1 ? v0 : v1, v0 < v1 ? v1 : v0, t, (uint8_t)k};
        }
    }
    qsort(edges, 3ull * nt, sizeof(mesh_edge), edge_cmp);
    /* Closed with its fronts outside: every edge in exactly two triangles,
     * walked opposite ways, and a positive volume (divergence theorem). */
    bool closed = true;
    for (uint64_t e = 0; closed && e < 3ull * nt; e += 2) {
        const mesh_edge *x = &edges[e], *y = &edges[e + 1];
        closed = e + 1 < 3ull * nt && x->lo == y->lo && x->hi == y->hi &&
                 (e + 2 >= 3ull * nt || edges[e + 2].lo != x->lo || edges[e + 2].hi != x->hi) &&
                 (weld[m->indices[3 * x->tri + x->slot]] == x->lo) !=
                     (weld[m->indices[3 * y->tri + y->slot]] == y->lo);
    }
    double volume = 0;
    for (uint32_t t = 0; closed && t < nt; t++)
        volume += v3_dot(mesh_point(m, m->indices[3 * t]),
                         v3_cross(mesh_point(m, m->indices[3 * t + 1]),
                                  mesh_point(m, m->indices[3 * t + 2])));
    closed = closed && volume > 0;
    if (!m->keep_triangles) {
        /* An edge two triangles share (and no third), walked in opposite
         * directions, same material: join greedily in edge order. */
        for (uint64_t e = 0; e + 1 < 3ull * nt; e++) {
            const mesh_edge *x = &edges[e], *y = &edges[e + 1];
            if (x->lo != y->lo || x->hi != y->hi)
                continue;
            if (e + 2 < 3ull * nt && edges[e + 2].lo == x->lo && edges[e + 2].hi == x->hi)
                continue;
            if (e > 0 && edges[e - 1].lo == x->lo && edges[e - 1].hi == x->hi)
                continue;
            uint32_t t = x->tri, u = y->tri;
            if (t == u || partner[t] != UINT32_MAX || partner[u] != UINT32_MAX ||
                degenerate[t] || degenerate[u])
                continue;
            if ((m->materials ? m->materials[t] != m->materials[u] : false))
                continue;
            if (weld[m->indices[3 * t + x->slot]] != weld[m->indices[3 * u + (y->slot + 1) % 3]])
                continue; /* same direction: opposite faces */
            vec3 q[4];
            if (!join_pair(m, t, x->slot, u, y->slot, q))
                continue;
            if (mapped(b, m->materials ? m->materials[t] : m->material) && !uv_affine(m, t, u))
                continue;
            partner[t] = u;
            partner[u] = t;
            partner_slot[t] = (int8_t)x->slot;
            partner_slot[u] = (int8_t)y->slot;
        }
    }

    uint32_t named = 0, skipped = 0;
    for (uint32_t t = 0; t < nt && !st; t++) {
        if (degenerate[t]) {
            b->sc->skipped_triangles++;
            skipped++;
            went[t] = (mesh_triangle){.surface = UINT32_MAX};
            continue;
        }
        if (partner[t] != UINT32_MAX && partner[t] < t)
            continue; /* added with its partner */
        char sw[4 * SCENE_NAME_MAX + 32];
        char sname[SCENE_NAME_MAX];
        snprintf(sname, sizeof(sname), "%s.%u", m->name, named++);
        snprintf(sw, sizeof(sw), "%ssurface '%s': ", where, sname);
        uint32_t mat = m->materials ? m->materials[t] : m->material;
        if (partner[t] != UINT32_MAX) {
            xrad_quad_desc qd = {.name = sname, .material = mat};
            vec3 q[4];
            join_pair(m, t, partner_slot[t], partner[t], partner_slot[partner[t]], q);
            for (int k = 0; k < 4; k++) {
                qd.p[k][0] = q[k].x;
                qd.p[k][1] = q[k].y;
                qd.p[k][2] = q[k].z;
            }
            st = scene_builder_quad(b, &qd, sw, "indices", density, err);
            if (!st) {
                uint32_t si = b->sc->surface_count - 1, u = partner[t];
                b->sc->surfaces[si].mesh = true;
                b->sc->surfaces[si].closed = closed;
                went[t].surface = went[u].surface = si;
                join_slots(partner_slot[t], partner_slot[u], went[t].slot, went[u].slot);
                if (mapped(b, mat))
                    for (int k = 0; k < 3; k++) {
                        set_uv(b, m, si, went[t].slot[k], m->indices[3 * t + k]);
                        set_uv(b, m, si, went[u].slot[k], m->indices[3 * u + k]);
                    }
            }
            continue;
        }
        surface *s;
        if ((st = begin_surface(b, err, &s)))
            break;
        vec3 p[3];
        for (int k = 0; k < 3; k++)
            p[k] = mesh_point(m, m->indices[3 * t + k]);
        char why[256];
        if (!scene_triangle_setup(s, p, why, sizeof(why))) {
            st = fail(b, err, sw, "indices", "triangle %u: %s", t, why);
            break;
        }
        snprintf(s->name, sizeof(s->name), "%s", sname);
        s->object = b->sc->object_count - 1;
        s->material = mat;
        s->mesh = true;
        s->closed = closed;
        /* scene_triangle_setup turns the corners (the longest edge first):
         * each is found among p0 p1 p2, which are distinct. */
        went[t] = (mesh_triangle){.surface = b->sc->surface_count};
        for (int k = 0; k < 3; k++)
            for (uint8_t j = 0; j < 3; j++)
                if (!memcmp(&s->p[j], &p[k], sizeof(vec3)))
                    went[t].slot[k] = j;
        st = finish_surface(b, err, sw, "density", density, NULL);
        if (!st && mapped(b, mat)) {
            for (int k = 0; k < 3; k++)
                set_uv(b, m, went[t].surface, went[t].slot[k], m->indices[3 * t + k]);
            set_uv(b, m, went[t].surface, 3, m->indices[3 * t + went_apex(&went[t])]);
        }
    }
    if (!st && !grow((void **)&b->sc->meshes, &b->mesh_cap, b->sc->mesh_count + 1,
                     sizeof(scene_mesh)))
        st = out_of_memory(b, err);
    if (!st) {
        scene_mesh *sm = &b->sc->meshes[b->sc->mesh_count++];
        memset(sm, 0, sizeof(*sm));
        snprintf(sm->name, sizeof(sm->name), "%s", m->name);
        sm->object = b->sc->object_count - 1;
        sm->triangle_count = nt;
        sm->skipped_triangles = skipped;
        sm->triangles = went;
        went = NULL;
    }
done:
    free(weld);
    free(order);
    free(edges);
    free(partner);
    free(partner_slot);
    free(degenerate);
    free(went);
    return st;
}

/* ----------------------------------------------------------------- camera */

xrad_status xrad_scene_builder_add_luminaire(xrad_scene_builder *b, const xrad_luminaire_desc *l,
                                            xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st)
        return st;
    xrad_scene *sc = b->sc;
    char where[SCENE_NAME_MAX + 32];
    snprintf(where, sizeof(where), "luminaire #%u: ", sc->luminaire_count);
    if (!l)
        return fail(b, err, where, NULL, "no description (NULL)");
    if ((st = check_name(b, err, where, l->name, 0)))
        return st;
    snprintf(where, sizeof(where), "luminaire '%s': ", l->name);
    for (uint32_t k = 0; k < sc->luminaire_count; k++)
        if (!strcmp(sc->luminaires[k].name, l->name))
            return fail(b, err, where, "name", "duplicate luminaire name '%s'", l->name);
    if (sc->luminaire_count >= SCENE_MAX_LUMINAIRES)
        return fail(b, err, "", "luminaires", "more than %u luminaires", SCENE_MAX_LUMINAIRES);
    if (!grow((void **)&sc->luminaires, &b->luminaire_cap, sc->luminaire_count + 1,
              sizeof(luminaire)))
        return out_of_memory(b, err);
    char w[sizeof(where) + 600];
    snprintf(w, sizeof(w), "%s: %s", b->file, where);
    if ((st = scene_luminaire_setup(l, w, &sc->luminaires[sc->luminaire_count], err))) {
        b->failed = true;
        return st;
    }
    sc->luminaire_count++;
    return XRAD_OK;
}

xrad_status xrad_scene_builder_set_camera(xrad_scene_builder *b, const xrad_camera_desc *c,
                                          xrad_error *err)
{
    xrad_status st = check_usable(b, err);
    if (st)
        return st;
    const char *where = "camera: ";
    if (!c)
        return fail(b, err, where, NULL, "no description (NULL)");
    camera cam = {.up = v3(0, 1, 0), .width = 512, .height = 512};
    if (!finite3(c->position) || !finite3(c->look_at) || !finite3(c->up))
        return fail(b, err, where, !finite3(c->position) ? "position"
                                   : !finite3(c->look_at) ? "look_at"
                                                          : "up",
                    "must be finite");
    cam.position = v3(c->position[0], c->position[1], c->position[2]);
    cam.look_at = v3(c->look_at[0], c->look_at[1], c->look_at[2]);
    if ((st = check_coord(b, err, where, "position", cam.position)) ||
        (st = check_coord(b, err, where, "look_at", cam.look_at)))
        return st;
    if (c->up[0] || c->up[1] || c->up[2])
        cam.up = v3(c->up[0], c->up[1], c->up[2]);
    double fov = c->fov_degrees ? c->fov_degrees : 45;
    if (!(fov > 0 && fov < 180))
        return fail(b, err, where, "fov_degrees", "must be in (0, 180), got %g", fov);
    cam.fov_y = fov * PI / 180.0;
    vec3 dir = v3_sub(cam.look_at, cam.position);
    if (!(v3_len(dir) > 0))
        return fail(b, err, where, "look_at", "must differ from position");
    if (!(v3_len(v3_cross(v3_norm(dir), v3_norm(cam.up))) > 1e-6))
        return fail(b, err, where, "up", "must be non-zero and not parallel to the view direction");
    if (c->width > 16384 || c->height > 16384)
        return fail(b, err, where, c->width > 16384 ? "width" : "height",
                    "must be in [1, 16384], got %u", c->width > 16384 ? c->width : c->height);
    if (c->width)
        cam.width = c->width;
    if (c->height)
        cam.height = c->height;
    b->sc->cam = cam;
    b->has_camera = true;
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

/* What solves but is likely not what was meant: no surface emits (every
 * method gives black), a material no surface uses (a typo in a name). */
static void warn_unlit(xrad_scene_builder *b)
{
    const xrad_scene *sc = b->sc;
    bool *used = calloc(sc->material_count, sizeof(*used));
    if (!used)
        return;
    bool lit = false;
    for (uint32_t k = 0; k < sc->surface_count; k++) {
        const material *m = &sc->materials[sc->surfaces[k].material];
        used[sc->surfaces[k].material] = true;
        lit = lit || m->emission.x > 0 || m->emission.y > 0 || m->emission.z > 0;
    }
    /* Warnings name the file (tests/fuzz/fuzz_import.c holds them to it). */
    if (!lit && !sc->luminaire_count)
        scene_builder_warn(b, "%s: no surface emits light and no luminaire: every method "
                              "solves to black (a material's \"emission\", \"luminaires\")",
                           sc->path);
    for (uint32_t k = 0; k < sc->material_count; k++)
        if (!used[k])
            scene_builder_warn(b, "%s: material '%s' is used by no surface", sc->path,
                               sc->materials[k].name);
    free(used);
}

/* Surfaces back to back in one plane (scene_find_flat_slabs), at the
 * scene's start: the GPU methods leave both dark where they meet. */
static xrad_status warn_flat_slabs(xrad_scene_builder *b, xrad_error *err)
{
    const xrad_scene *sc = b->sc;
    uint32_t *pairs = NULL, count = 0;
    xrad_status st = scene_find_flat_slabs(sc, 0, &pairs, &count, err);
    for (uint32_t k = 0; !st && k < count && k < 3; k++) {
        const surface *s0 = &sc->surfaces[pairs[2 * k]], *s1 = &sc->surfaces[pairs[2 * k + 1]];
        scene_builder_warn(b,
                           "%s: surfaces '%s' (object '%s') and '%s' (object '%s') lie back to "
                           "back in one plane with nothing closed behind either: a slab of zero "
                           "thickness. The GPU methods take them as in contact (a box standing "
                           "on a floor) and leave both dark where they meet; the CPU reference "
                           "lights both. Give the slab a thickness%s",
                           sc->path, s0->name, sc->objects[s0->object].name, s1->name,
                           sc->objects[s1->object].name,
                           k == 2 && count > 3 ? " (and more such pairs)" : "");
    }
    free(pairs);
    return st;
}

/* Splits the elements of each normal-mapped surface 1 -> 4 while the
 * split elements' normals differ by more than SCENE_NORMAL_DETAIL_DEGREES
 * between neighbours, at most its material's normal_levels times (xrad.h
 * normal_map_levels), within the scene's element limits. */
static xrad_status refine_normal_mapped(xrad_scene_builder *b, xrad_error *err)
{
    xrad_scene *sc = b->sc;
    uint32_t capped = 0;
    for (uint32_t si = 0; si < sc->surface_count; si++) {
        surface *sf = &sc->surfaces[si];
        if (sf->material >= b->map_cap || !b->maps[sf->material].normal.width)
            continue;
        const scene_material_maps *mm = &b->maps[sf->material];
        uint32_t level = 0;
        for (; level < mm->normal_levels; level++) {
            uint32_t nu, nv;
            if (!scene_split_fits(sf, b->elements, &nu, &nv)) {
                capped++;
                break;
            }
            int vary = scene_texture_normals_vary(&mm->normal, sf, &b->uv[si], nu, nv);
            if (vary < 0)
                return out_of_memory(b, err);
            if (!vary)
                break;
            scene_split_take(sf, nu, nv, &b->elements);
        }
        sc->normal_refined_surfaces += level > 0;
    }
    if (capped)
        scene_builder_warn(b,
                           "%s: %u normal-mapped surface(s) split less than their map's "
                           "detail asks: the scene's element limits (%u, %u along an edge)",
                           sc->path, capped, SCENE_MAX_ELEMENTS, SCENE_MAX_SAMPLES);
    return XRAD_OK;
}

xrad_status xrad_scene_builder_finish(xrad_scene_builder *b, xrad_scene **out, xrad_error *err)
{
    *out = NULL;
    xrad_status st = check_usable(b, err);
    if (st || (st = end_object(b, err)) || (st = scene_builder_check_materials(b, err)))
        return st;
    xrad_scene *sc = b->sc;
    if (sc->material_count == 0)
        return fail(b, err, "", "materials", "no materials");
    if (sc->object_count == 0)
        return fail(b, err, "", "objects", "no objects");
    name_ref *refs = malloc(sc->object_count * sizeof(*refs));
    if (!refs)
        return out_of_memory(b, err);
    for (uint32_t k = 0; k < sc->object_count; k++)
        refs[k] = (name_ref){sc->objects[k].name, k};
    uint32_t dup = scene_find_duplicate(refs, sc->object_count);
    if (dup < sc->object_count) {
        char where[SCENE_NAME_MAX + 16];
        snprintf(where, sizeof(where), "object '%s': ", refs[dup].name);
        st = fail(b, err, where, "name", "duplicate object name '%s'", refs[dup].name);
    }
    free(refs);
    if (st)
        return st;
    if (!b->has_camera)
        default_camera(sc);
    warn_unlit(b);
    if ((b->uv && (st = refine_normal_mapped(b, err))) ||
        (b->adaptive.levels && (st = scene_adaptive_refine(b, &b->adaptive, &b->elements, err))) ||
        (st = scene_build_elements(sc, err)) ||
        (b->uv && (st = scene_texture_apply(sc, b->maps, b->map_cap, b->uv, err))) ||
        (st = warn_flat_slabs(b, err))) {
        b->failed = true;
        return st;
    }
    free_maps(b);
    *out = sc;
    b->sc = NULL;
    return XRAD_OK;
}

uint32_t xrad_scene_warning_count(const xrad_scene *scene)
{
    return scene ? scene->warning_count : 0;
}

const char *xrad_scene_warning(const xrad_scene *scene, uint32_t index)
{
    return scene && index < scene->warning_count ? scene->warnings[index] : NULL;
}
