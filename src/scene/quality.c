/* The quality settings by name: one table gives every setting's field,
 * default and range; xrad_solver_create's defaults and checks, the scene
 * file's "quality" object, the command line and xrad bench --sweep all go
 * through it. */
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "scene/quality.h"

typedef enum value_rule {
    RULE_NONE,
    RULE_EVEN,       /* hemicube sizes: the centre of a face lies between texels */
    RULE_ONE_OR_FOUR, /* the sample counts the hemicube pass offers */
    RULE_ZERO_OK,    /* 0 is a value of its own ("until the threshold"), not "default" */
} value_rule;

typedef struct setting {
    xrad_setting_info info;
    size_t offset; /* of the field in xrad_quality */
    value_rule rule;
} setting;

#define SOLVER(field) offsetof(xrad_quality, solver) + offsetof(xrad_solver_desc, field)
#define ADAPTIVE(field) offsetof(xrad_quality, adaptive) + offsetof(xrad_adaptive_desc, field)

static const setting settings[] = {
    {{"hemicube_res", "pixels per hemicube face side, even (all methods)",
      XRAD_SETTING_INTEGER, 64, 8, 1024, NULL, 0},
     SOLVER(hemicube_res), RULE_EVEN},
    {{"msaa", "samples of gather's radiosity hemicubes, 1 or 4", XRAD_SETTING_INTEGER, 4, 1, 4,
      NULL, 0},
     SOLVER(msaa), RULE_ONE_OR_FOUR},
    {{"id_check", "ID hemicube visibility: the texel and its 8 neighbours, or the texel alone",
      XRAD_SETTING_CHOICE, XRAD_ID_CHECK_NEIGHBOURS, 1, 2, "neighbours|exact", 0},
     SOLVER(id_check), RULE_NONE},
    {{"subdivide_ratio",
      "exact point-to-quad form factor where shooter area / distance^2 exceeds this, else the "
      "disk approximation (thesis 4.3.3)",
      XRAD_SETTING_REAL, 0.01, 0, 1e6, NULL, 1},
     SOLVER(subdivide_ratio), RULE_NONE},
    {{"max_patches",
      "most shooting patches along a surface side (shooter subdivision); 0: 12 for "
      "progressive, 8 for incremental and cross",
      XRAD_SETTING_INTEGER, 0, 0, 64, NULL, 0},
     SOLVER(max_patches), RULE_ZERO_OK},
    {{"threshold",
      "stop when the largest unshot power (gather: the light the bounces still to come would "
      "add) relative to the emitted power is below this",
      XRAD_SETTING_REAL, 1e-4, 0, 0.5, NULL, 1},
     SOLVER(threshold), RULE_NONE},
    {{"unshot",
      "progressive (and the dynamic methods' first solve): stop also only once all unshot "
      "power is below this share of the emitted power (1: no such test)",
      XRAD_SETTING_REAL, 5e-3, 0, 1, NULL, 1},
     SOLVER(unshot), RULE_NONE},
    {{"batch", "progressive shots per submission (one host wait each)", XRAD_SETTING_INTEGER,
      32, 1, 4096, NULL, 0},
     SOLVER(batch), RULE_NONE},
    {{"frame_shots",
      "incremental, cross: progressive shots after each redistribution (0: until the "
      "threshold)",
      XRAD_SETTING_INTEGER, 0, 0, 1e7, NULL, 0},
     SOLVER(frame_shots), RULE_ZERO_OK},
    {{"cross_grid", "cross: PROJECTEDRADIOSITY rays per patch side (thesis 4.5.3 gridSize)",
      XRAD_SETTING_INTEGER, 4, 1, 16, NULL, 0},
     SOLVER(cross_grid), RULE_NONE},
    {{"cross_grid_ff",
      "cross: form factor from which a receiver gets all cross_grid rays a side over a patch; "
      "below it ceil(cross_grid sqrt(F / this)), at least 1",
      XRAD_SETTING_REAL, 0.02, 0, 1, NULL, 1},
     SOLVER(cross_grid_ff), RULE_NONE},
    {{"cross_cut",
      "cross: leave out a (receiver, patch) pair whose term F (B_s - P) can be at most this "
      "share of the largest radiosity on the patches or C's back hemicubes (0: none)",
      XRAD_SETTING_REAL, 0, 0, 0.1, NULL, 0},
     SOLVER(cross_cut), RULE_ZERO_OK},
    {{"back_res", "cross: back hemicube face side, even (thesis 4.5.2)", XRAD_SETTING_INTEGER,
      16, 8, 256, NULL, 0},
     SOLVER(back_res), RULE_EVEN},
    {{"back_msaa", "cross: back hemicube samples, 1 or 4", XRAD_SETTING_INTEGER, 4, 1, 4, NULL, 0},
     SOLVER(back_msaa), RULE_ONE_OR_FOUR},
    {{"radiosity_format", "texels of radiosity hemicubes (gather, cross)", XRAD_SETTING_CHOICE,
      XRAD_RADIOSITY_FP16, 1, 2, "fp16|fp32", 0},
     SOLVER(radiosity_format), RULE_NONE},
    {{"ambient",
      "progressive, incremental, cross: add the unshot remainder spread evenly (ambient term, "
      "Cohen et al. 1988) to what is read",
      XRAD_SETTING_CHOICE, XRAD_AMBIENT_OFF, 1, 2, "off|on", 0},
     SOLVER(ambient), RULE_NONE},
    {{"conserve",
      "progressive shots: a shooter's receivers take what it sends (form factors scaled "
      "where they would take more or less); far: only those that see it by its centre, the "
      "near blocks exact; auto: far",
      XRAD_SETTING_CHOICE, XRAD_CONSERVE_AUTO, 1, 4, "on|off|far|auto", 0},
     SOLVER(conserve), RULE_NONE},
    {{"cull",
      "leave out of a draw of hemicubes what none of them can see (clusters behind every "
      "base, closed meshes' clusters facing away); auto: shots in scenes of 8 clusters of "
      "256 triangles or more, not gather's hemicubes",
      XRAD_SETTING_CHOICE, XRAD_CULL_AUTO, 1, 3, "on|off|auto", 0},
     SOLVER(cull), RULE_NONE},
    {{"cross_pairs",
      "cross: list the (element, patch) pairs that see each other and trace the projection "
      "per listed pair, in patch order, rather than per element over every patch",
      XRAD_SETTING_CHOICE, XRAD_CROSS_PAIRS_OFF, 1, 2, "off|on", 0},
     SOLVER(cross_pairs), RULE_NONE},
    {{"back_mips",
      "cross: read the back hemicubes through mip levels chosen per ray by the width of "
      "the cone it stands for behind the patch (thesis 6.2)",
      XRAD_SETTING_CHOICE, XRAD_BACK_MIPS_OFF, 1, 2, "off|on", 0},
     SOLVER(back_mips), RULE_NONE},
    {{"cross_regather",
      "cross: when moving objects gather their light: after each frame's progressive "
      "iterations (this frame's surroundings; they shoot the last frame's gather), off "
      "(before them: a frame late), on (both: twice the gather hemicubes)",
      XRAD_SETTING_CHOICE, XRAD_CROSS_REGATHER_AFTER, 1, 3, "off|on|after", 0},
     SOLVER(cross_regather), RULE_NONE},
    {{"density_scale", "every element density of the scene file times this (at load)",
      XRAD_SETTING_REAL, 1, 0, 16, NULL, 1},
     offsetof(xrad_quality, density_scale), RULE_NONE},
    {{"adaptive_levels",
      "1 -> 4 splits at most of surfaces a shadow boundary crosses, before the first shot "
      "(at load; 0: off)",
      XRAD_SETTING_INTEGER, 0, 0, 4, NULL, 0},
     ADAPTIVE(levels), RULE_NONE},
    {{"adaptive_lower", "adaptive: least visible fraction of a surface from an emitter that splits",
      XRAD_SETTING_REAL, 0.02, 0, 1, NULL, 1},
     ADAPTIVE(lower), RULE_NONE},
    {{"adaptive_upper", "adaptive: most visible fraction of a surface from an emitter that splits",
      XRAD_SETTING_REAL, 0.98, 0, 1, NULL, 1},
     ADAPTIVE(upper), RULE_NONE},
};

#define SETTING_COUNT (sizeof(settings) / sizeof(settings[0]))

static bool is_real(const setting *st)
{
    return st->info.kind == XRAD_SETTING_REAL;
}

static double field_get(const xrad_quality *q, const setting *st)
{
    const char *p = (const char *)q + st->offset;
    if (is_real(st)) {
        double v;
        memcpy(&v, p, sizeof(v));
        return v;
    }
    uint32_t v;
    memcpy(&v, p, sizeof(v));
    return v;
}

static void field_set(xrad_quality *q, const setting *st, double v)
{
    char *p = (char *)q + st->offset;
    if (is_real(st)) {
        memcpy(p, &v, sizeof(v));
    } else {
        uint32_t u = (uint32_t)v;
        memcpy(p, &u, sizeof(u));
    }
}

static const setting *find(const char *name)
{
    for (size_t i = 0; name && i < SETTING_COUNT; i++)
        if (!strcmp(settings[i].info.name, name))
            return &settings[i];
    return NULL;
}

const xrad_setting_info *xrad_setting_get(uint32_t index)
{
    return index < SETTING_COUNT ? &settings[index].info : NULL;
}

uint32_t xrad_setting_count(void)
{
    return (uint32_t)SETTING_COUNT;
}

/* Whether v is allowed; otherwise a message "must be ..." in err. */
static xrad_status check(const setting *st, double v, xrad_error *err)
{
    const xrad_setting_info *in = &st->info;
    bool ok = isfinite(v) && v <= in->max &&
              (in->min_open ? v > in->min : v >= in->min);
    if (ok && in->kind != XRAD_SETTING_REAL)
        ok = v == floor(v);
    if (ok && st->rule == RULE_EVEN)
        ok = fmod(v, 2) == 0;
    if (ok && st->rule == RULE_ONE_OR_FOUR)
        ok = v == 1 || v == 4;
    if (ok)
        return XRAD_OK;
    if (in->min_open)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s must be in (%g, %g], got %g", in->name,
                         in->min, in->max, v);
    switch (st->rule) {
    case RULE_EVEN:
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s must be even and in [%g, %g], got %g",
                         in->name, in->min, in->max, v);
    case RULE_ONE_OR_FOUR:
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s must be 1 or 4, got %g", in->name, v);
    default:
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s must be %s in [%g, %g], got %g", in->name,
                         in->kind == XRAD_SETTING_REAL ? "a number" : "a whole number",
                         in->min, in->max, v);
    }
}

xrad_status quality_resolve(xrad_quality *q, xrad_error *err)
{
    for (size_t i = 0; i < SETTING_COUNT; i++) {
        const setting *st = &settings[i];
        double v = field_get(q, st);
        if (v == 0 && st->rule != RULE_ZERO_OK) {
            field_set(q, st, st->info.def);
            continue;
        }
        xrad_status s = check(st, v, err);
        if (s)
            return s;
    }
    return XRAD_OK;
}

xrad_status xrad_quality_resolve(xrad_quality *q, xrad_error *err)
{
    xrad_status s = quality_resolve(q, err);
    if (s)
        xrad_error_prefix(err, "quality");
    return s;
}

xrad_status xrad_quality_set(xrad_quality *q, const char *name, const char *value,
                             xrad_error *err)
{
    const setting *st = find(name);
    if (!st) {
        char list[512] = "";
        size_t len = 0;
        for (size_t i = 0; i < SETTING_COUNT; i++)
            len += (size_t)snprintf(list + len, len < sizeof(list) ? sizeof(list) - len : 0,
                                    "%s%s", i ? ", " : "", settings[i].info.name);
        return xrad_fail(err, XRAD_ERROR_INPUT, "unknown quality setting '%s' (settings: %s)",
                         name ? name : "(null)", list);
    }
    if (!value)
        return xrad_fail(err, XRAD_ERROR_INPUT, "%s: no value", st->info.name);
    double v;
    if (st->info.kind == XRAD_SETTING_CHOICE) {
        /* Choices by name, or by their position. */
        const char *c = st->info.choices;
        size_t n = strlen(value);
        v = 0;
        for (uint32_t k = 1; c && *c; k++) {
            const char *bar = strchr(c, '|');
            size_t len = bar ? (size_t)(bar - c) : strlen(c);
            if (len == n && !strncmp(c, value, n))
                v = k;
            c = bar ? bar + 1 : c + len;
        }
        if (v == 0)
            return xrad_fail(err, XRAD_ERROR_INPUT, "%s must be one of %s, got '%s'",
                             st->info.name, st->info.choices, value);
    } else {
        char *end;
        v = strtod(value, &end);
        if (end == value || *end)
            return xrad_fail(err, XRAD_ERROR_INPUT, "%s: '%s' is not a number", st->info.name,
                             value);
    }
    /* An explicit 0 is "until the threshold" only where that exists. */
    if (v == 0 && st->rule == RULE_ZERO_OK) {
        field_set(q, st, 0);
        return XRAD_OK;
    }
    xrad_status s = check(st, v, err);
    if (!s)
        field_set(q, st, v);
    return s;
}

xrad_status xrad_quality_format(const xrad_quality *q, const char *name, char *buf, size_t size,
                                xrad_error *err)
{
    const setting *st = find(name);
    if (!st)
        return xrad_fail(err, XRAD_ERROR_INPUT, "unknown quality setting '%s'",
                         name ? name : "(null)");
    double v = field_get(q, st);
    if (v == 0 && st->rule != RULE_ZERO_OK)
        v = st->info.def;
    if (st->info.kind == XRAD_SETTING_CHOICE) {
        const char *c = st->info.choices;
        for (uint32_t k = 1; k < (uint32_t)v && strchr(c, '|'); k++)
            c = strchr(c, '|') + 1;
        const char *bar = strchr(c, '|');
        int len = bar ? (int)(bar - c) : (int)strlen(c);
        snprintf(buf, size, "%.*s", len, c);
    } else {
        snprintf(buf, size, "%.6g", v);
    }
    return XRAD_OK;
}

/* Presets: name, then the settings in table order. Tuned on surface_error
 * and element p95 against the CPU reference (README "Quality"): the
 * threshold is what buys progressive's speed (draft's 1e-2 left room-4's
 * table 25% off, interactive's 1e-3 cornell-large's plinth 7.5%); 16
 * shooting patches a side made room-4's table side worse than 8, and
 * `high` has progressive's default 12 since the near blocks and the
 * shots' conservation were reworked (README "12 shooting patches a
 * side"). */
static const struct {
    const char *name;
    double v[SETTING_COUNT];
} presets[] = {
    /*        res msaa id  subdiv max  thresh unshot batch shots grid grid_ff cut back bmsaa fmt
                                                                     amb cons cull pairs mips regather density
                                                                     adaptive: levels lower upper */
    {"draft",       {32, 1, 1, 0.1, 2, 1e-3, 0.05, 64, 0, 1, 0.2, 0, 8, 1, 1, 2, 1, 0, 1, 1, 3, 0.5, 0, 0.02, 0.98}},
    {"interactive", {64, 1, 1, 0.01, 8, 3e-4, 0.02, 32, 0, 2, 0.05, 0, 16, 4, 1, 2, 1, 0, 1, 1, 3, 1, 0, 0.02, 0.98}},
    {"high",        {128, 4, 1, 0.01, 12, 1e-5, 1e-3, 32, 0, 4, 0.005, 0, 32, 4, 1, 1, 3, 0, 1, 1, 3, 1, 0, 0.02, 0.98}},
    {"reference",   {256, 4, 1, 0.001, 24, 1e-5, 1e-4, 32, 0, 8, 1e-6, 0, 64, 4, 2, 1, 3, 0, 1, 1, 3, 2, 0, 0.02, 0.98}},
};

const char *xrad_quality_preset_list(void)
{
    return "draft, interactive, high, reference";
}

xrad_status xrad_quality_preset(xrad_quality *q, const char *name, xrad_error *err)
{
    for (size_t p = 0; name && p < sizeof(presets) / sizeof(presets[0]); p++) {
        if (strcmp(presets[p].name, name))
            continue;
        for (size_t i = 0; i < SETTING_COUNT; i++)
            field_set(q, &settings[i], presets[p].v[i]);
        return XRAD_OK;
    }
    return xrad_fail(err, XRAD_ERROR_INPUT, "unknown quality preset '%s' (presets: %s)",
                     name ? name : "(null)", xrad_quality_preset_list());
}
