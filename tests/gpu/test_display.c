/*
 * The display pass against independent truths computed here with a pinhole
 * camera and ray-quad intersection:
 *  (a) a constant atlas renders to exactly that constant wherever a surface
 *      is and to 0 elsewhere, for every filter path; coverage matches the
 *      ray cast, which (the scene being asymmetric) also fixes the image
 *      orientation (row 0 at the top); a surface seen from behind is drawn;
 *  (b) two coplanar adjacent quads with element values linear in world x
 *      render that linear function across their shared edge (no seam), and
 *      nearest filtering shows the value of the nearest element sample;
 *  (d) the nearest surface along each ray is the one shown (depth);
 *  (e) a closed room shows a surface in every pixel: no background through
 *      cracks where walls meet, also where a wall was planarised (its file
 *      vertices not coplanar: the Cornell box's red wall, and a room written
 *      here with two warped walls seen from inside), and with a triangle
 *      mesh in it; with a constant atlas every pixel is that constant
 *      within 1e-3 (no seam between surfaces or mesh faces);
 *  and every test ends with zero validation messages (gpu_test.h).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/timer.h"
#include "gpu_test.h"
#include "render/view.h"
#include "scene/scene.h"

#define PI 3.14159265358979323846

/* ----------------------------------------------------------- pinhole */

typedef struct pinhole {
    double pos[3], fwd[3], right[3], up[3];
    double tan_half; /* tan(fov_y / 2) */
    uint32_t w, h;
} pinhole;

/* Camera at `pos` looking along -z with +y up (so +x is right), as every
 * scene below declares it. */
static pinhole make_pinhole(double z, double fov_deg, uint32_t w, uint32_t h)
{
    pinhole p = {
        .pos = {0, 0, z},
        .fwd = {0, 0, -1},
        .right = {1, 0, 0},
        .up = {0, 1, 0},
        .tan_half = tan(0.5 * fov_deg * PI / 180.0),
        .w = w,
        .h = h,
    };
    return p;
}

/* Ray direction through the centre of pixel (px, py), row 0 at the top. */
static void pixel_ray(const pinhole *c, uint32_t px, uint32_t py, double d[3])
{
    double aspect = (double)c->w / c->h;
    double x = ((px + 0.5) / c->w * 2 - 1) * c->tan_half * aspect;
    double y = (1 - (py + 0.5) / c->h * 2) * c->tan_half;
    for (int k = 0; k < 3; k++)
        d[k] = c->fwd[k] + x * c->right[k] + y * c->up[k];
}

typedef struct rect {
    double o[3], u[3], v[3]; /* origin and perpendicular edges */
} rect;

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Ray hit with a rectangle: distance t (< 0 for a miss), the rectangle
 * parameters (s, q) and how far inside it is, in units of its own edges'
 * lengths (m). */
static double hit_rect(const pinhole *c, const double d[3], const rect *r, double *s,
                       double *q, double *inside_m)
{
    double n[3] = {r->u[1] * r->v[2] - r->u[2] * r->v[1], r->u[2] * r->v[0] - r->u[0] * r->v[2],
                   r->u[0] * r->v[1] - r->u[1] * r->v[0]};
    double den = dot3(d, n);
    if (fabs(den) < 1e-12)
        return -1;
    double oc[3] = {r->o[0] - c->pos[0], r->o[1] - c->pos[1], r->o[2] - c->pos[2]};
    double t = dot3(oc, n) / den;
    if (t <= 0)
        return -1;
    double p[3];
    for (int k = 0; k < 3; k++)
        p[k] = c->pos[k] + t * d[k] - r->o[k];
    double lu = sqrt(dot3(r->u, r->u)), lv = sqrt(dot3(r->v, r->v));
    *s = dot3(p, r->u) / (lu * lu);
    *q = dot3(p, r->v) / (lv * lv);
    *inside_m = fmin(fmin(*s * lu, (1 - *s) * lu), fmin(*q * lv, (1 - *q) * lv));
    return t;
}

/* World size of one pixel at distance t along a ray (roughly). */
static double pixel_size(const pinhole *c, double t)
{
    return 2.0 * c->tan_half * t / c->h;
}

/* ------------------------------------------------------------ helpers */

static xrad_scene *parse(const char *json)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status s = xrad_scene_parse(json, strlen(json), "test scene", &scene, &err);
    CHECK(s == XRAD_OK, "xrad_scene_parse: %s", err.message);
    return scene;
}

static const char *filter_name(display_filter f)
{
    return f == DISPLAY_FILTER_NEAREST ? "nearest" : f == DISPLAY_FILTER_LINEAR ? "linear"
                                                                                : "linear-shader";
}

static float *render(xrad_context *ctx, const xrad_scene *scene, const xrad_atlas *atlas,
                     display_filter filter, uint32_t w, uint32_t h, gpu_timer *timer)
{
    render_view_options opt = {.filter = filter, .timer = timer};
    xrad_view_desc desc = {.width = w, .height = h};
    float *img = NULL;
    uint32_t gw = 0, gh = 0;
    xrad_error err = {0};
    xrad_status s = render_view(ctx, scene, atlas, &desc, &opt, &img, &gw, &gh, &err);
    CHECK(s == XRAD_OK, "render_view (%s): %s", filter_name(filter), err.message);
    CHECK(s != XRAD_OK || (gw == w && gh == h), "image %u x %u, want %u x %u", gw, gh, w, h);
    return s == XRAD_OK ? img : NULL;
}

/* Fills the tile of every element of surface `s` with `value(i, j)`. */
static void fill_surface(const xrad_scene *scene, xrad_atlas *atlas, uint32_t s,
                         void (*value)(const surface *sf, uint32_t i, uint32_t j, float rgb[3]))
{
    const surface *sf = &scene->surfaces[s];
    for (uint32_t e = 0; e < sf->nu * sf->nv; e++) {
        const element *el = &scene->elements[sf->first_element + e];
        float *t = &atlas->rgba[4 * ((size_t)el->texel_y * atlas->width + el->texel_x)];
        value(sf, el->i, el->j, t);
        t[3] = 1;
    }
}

/* ---------------------------------------------- (a) constant atlas */

static const float constant_rgb[3] = {0.25f, 3.5f, 1234.5f};

static void constant_value(const surface *sf, uint32_t i, uint32_t j, float rgb[3])
{
    memcpy(rgb, constant_rgb, sizeof(constant_rgb));
}

/* A frontal quad in the upper left, and one on the right whose front faces
 * away from the camera (u x v along -z): it must be drawn all the same. */
static const char *constant_scene =
    "{\"unit\": \"m\","
    " \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": [{\"name\": \"o\", \"surfaces\": ["
    "  {\"name\": \"front\", \"material\": \"grey\", \"elements\": [5, 4],"
    "   \"quad\": {\"origin\": [-1.6, -0.4, 0], \"u\": [2, 0, 0], \"v\": [0, 1.6, 0]}},"
    "  {\"name\": \"back\", \"material\": \"grey\", \"elements\": [3, 7],"
    "   \"quad\": {\"origin\": [0.6, -1.2, -0.5], \"u\": [0, 1.5, 0], \"v\": [0.9, 0, 0]}}]}],"
    " \"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0],"
    "  \"fov_degrees\": 40, \"width\": 80, \"height\": 60}}";

static const rect constant_rects[2] = {
    {{-1.6, -0.4, 0}, {2, 0, 0}, {0, 1.6, 0}},
    {{0.6, -1.2, -0.5}, {0, 1.5, 0}, {0.9, 0, 0}},
};

static void check_constant(const float *img, const pinhole *cam, const char *what)
{
    uint32_t covered = 0, wrong_value = 0, wrong_cover = 0;
    for (uint32_t py = 0; py < cam->h; py++) {
        for (uint32_t px = 0; px < cam->w; px++) {
            const float *p = &img[4 * ((size_t)py * cam->w + px)];
            double d[3];
            pixel_ray(cam, px, py, d);
            /* +1: clearly inside a quad; -1: clearly outside all; 0: edge. */
            int truth = -1;
            for (int r = 0; r < 2; r++) {
                double s, q, in;
                double t = hit_rect(cam, d, &constant_rects[r], &s, &q, &in);
                if (t < 0)
                    continue;
                double margin = 1.5 * pixel_size(cam, t);
                if (in > margin)
                    truth = 1;
                else if (in > -margin && truth < 0)
                    truth = 0;
            }
            if (p[3] == 1.0f) {
                covered++;
                for (int k = 0; k < 3; k++)
                    if (fabs(p[k] - constant_rgb[k]) > 1e-6 * constant_rgb[k])
                        wrong_value++;
            } else {
                if (p[0] != 0 || p[1] != 0 || p[2] != 0 || p[3] != 0)
                    wrong_value++;
            }
            if ((truth == 1 && p[3] != 1.0f) || (truth == -1 && p[3] != 0.0f))
                wrong_cover++;
        }
    }
    CHECK(wrong_value == 0, "%s: %u pixel channels differ from the constant (or from 0)", what,
          wrong_value);
    CHECK(wrong_cover == 0, "%s: %u pixels covered where no surface is, or the reverse", what,
          wrong_cover);
    CHECK(covered > cam->w * cam->h / 10, "%s: only %u pixels covered", what, covered);
    fprintf(stderr, "%s: %u pixels covered\n", what, covered);
}

static void test_constant(xrad_context *ctx)
{
    xrad_scene *scene = parse(constant_scene);
    if (!scene)
        return;
    xrad_atlas atlas;
    xrad_error err = {0};
    CHECK(xrad_atlas_create(scene, &atlas, &err) == XRAD_OK, "atlas: %s", err.message);
    for (uint32_t s = 0; s < scene->surface_count; s++)
        fill_surface(scene, &atlas, s, constant_value);
    pinhole cam = make_pinhole(5, 40, 80, 60);
    const display_filter filters[3] = {DISPLAY_FILTER_NEAREST, DISPLAY_FILTER_LINEAR,
                                       DISPLAY_FILTER_LINEAR_SHADER};
    for (int f = 0; f < 3; f++) {
        float *img = render(ctx, scene, &atlas, filters[f], 80, 60, NULL);
        if (img)
            check_constant(img, &cam, filter_name(filters[f]));
        free(img);
    }
    /* The public entry point, with the camera's own size. */
    float *img = NULL;
    uint32_t w = 0, h = 0;
    CHECK(xrad_render_view(ctx, scene, &atlas, &(xrad_view_desc){0}, &img, &w, &h, &err) ==
              XRAD_OK,
          "xrad_render_view: %s", err.message);
    CHECK(w == 80 && h == 60, "default size %u x %u, want the camera's 80 x 60", w, h);
    if (img && w == 80 && h == 60)
        check_constant(img, &cam, "xrad_render_view");
    free(img);

    /* A wrong-sized atlas is an input error. */
    xrad_atlas small = {atlas.width - 1, atlas.height, atlas.rgba};
    img = NULL;
    CHECK(xrad_render_view(ctx, scene, &small, NULL, &img, &w, &h, &err) == XRAD_ERROR_INPUT &&
              !img,
          "mismatched atlas accepted");
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

/* ------------------------------------------------ (b) seamless edge */

/* f(x) = 10 + 3 x per channel with different scales. */
static double linear_f(double x, int k)
{
    return (10.0 + 3.0 * x) * (k + 1);
}

/* Quads A = [-2, 0] x [-1, 1] and B = [0, 2] x [-1, 1] at z = 0, with
 * different element counts; their samples on x = 0 coincide. */
static const char *seam_scene =
    "{\"unit\": \"m\","
    " \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": [{\"name\": \"o\", \"surfaces\": ["
    "  {\"name\": \"a\", \"material\": \"grey\", \"elements\": [5, 3],"
    "   \"quad\": {\"origin\": [-2, -1, 0], \"u\": [2, 0, 0], \"v\": [0, 2, 0]}},"
    "  {\"name\": \"b\", \"material\": \"grey\", \"elements\": [9, 4],"
    "   \"quad\": {\"origin\": [0, -1, 0], \"u\": [2, 0, 0], \"v\": [0, 2, 0]}}]}],"
    " \"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0],"
    "  \"fov_degrees\": 22, \"width\": 128, \"height\": 48}}";

/* Sample x of element (i, j): origin.x + u.x * i / (nu - 1), from the
 * geometry above (not from the scene module). */
static void seam_value(const surface *sf, uint32_t i, uint32_t j, float rgb[3])
{
    double x0 = sf->nu == 5 ? -2.0 : 0.0;
    double x = x0 + 2.0 * i / (sf->nu - 1);
    for (int k = 0; k < 3; k++)
        rgb[k] = (float)linear_f(x, k);
}

static void test_seam(xrad_context *ctx)
{
    xrad_scene *scene = parse(seam_scene);
    if (!scene)
        return;
    CHECK(scene->surface_count == 2 && scene->surfaces[0].nu == 5 && scene->surfaces[1].nu == 9,
          "scene layout");
    xrad_atlas atlas;
    xrad_error err = {0};
    CHECK(xrad_atlas_create(scene, &atlas, &err) == XRAD_OK, "atlas: %s", err.message);
    for (uint32_t s = 0; s < scene->surface_count; s++)
        fill_surface(scene, &atlas, s, seam_value);
    const uint32_t W = 128, H = 48;
    pinhole cam = make_pinhole(6, 22, W, H);
    const rect both = {{-2, -1, 0}, {4, 0, 0}, {0, 2, 0}};
    const double range = linear_f(2, 0) - linear_f(-2, 0);

    const display_filter linear[2] = {DISPLAY_FILTER_LINEAR, DISPLAY_FILTER_LINEAR_SHADER};
    for (int f = 0; f < 2; f++) {
        float *img = render(ctx, scene, &atlas, linear[f], W, H, NULL);
        if (!img)
            continue;
        /* Every covered pixel, not only one row: B at the pixel's surface
         * point is f(x) exactly, bilinear interpolation of a linear
         * function being exact. */
        double worst = 0, jump = 0;
        uint32_t n = 0;
        for (uint32_t py = 0; py < H; py++) {
            for (uint32_t px = 0; px < W; px++) {
                const float *p = &img[4 * ((size_t)py * W + px)];
                double d[3], s, q, in;
                pixel_ray(&cam, px, py, d);
                double t = hit_rect(&cam, d, &both, &s, &q, &in);
                if (t < 0 || in < 0.25 * pixel_size(&cam, t) || p[3] != 1.0f)
                    continue;
                double x = -2 + 4 * s;
                for (int k = 0; k < 3; k++)
                    worst = fmax(worst, fabs(p[k] - linear_f(x, k)) / ((k + 1) * range));
                n++;
            }
        }
        /* The middle row across the shared edge: consecutive pixels differ
         * by the slope times the pixel pitch, also at the edge. */
        uint32_t py = H / 2;
        double pitch = 3.0 * pixel_size(&cam, 6.0);
        for (uint32_t px = W / 2 - 4; px < W / 2 + 4; px++) {
            const float *a = &img[4 * ((size_t)py * W + px)], *b = a + 4;
            jump = fmax(jump, fabs((b[0] - a[0]) - pitch) / range);
        }
        fprintf(stderr, "%s: %u pixels, max |B - f(x)| / range = %.3g, edge step error %.3g\n",
                filter_name(linear[f]), n, worst, jump);
        CHECK(n > W * H / 3, "%s: only %u pixels checked", filter_name(linear[f]), n);
        CHECK(worst < 1e-3, "%s: max deviation from the linear function %.3g of the range",
              filter_name(linear[f]), worst);
        CHECK(jump < 1e-3, "%s: step across the shared edge off by %.3g of the range",
              filter_name(linear[f]), jump);
        free(img);
    }

    /* Nearest: element squares; a pixel well inside one shows the value of
     * the nearest sample. */
    float *img = render(ctx, scene, &atlas, DISPLAY_FILTER_NEAREST, W, H, NULL);
    if (img) {
        uint32_t n = 0, wrong = 0;
        for (uint32_t py = 0; py < H; py++) {
            for (uint32_t px = 0; px < W; px++) {
                const float *p = &img[4 * ((size_t)py * W + px)];
                double d[3], s, q, in;
                pixel_ray(&cam, px, py, d);
                double t = hit_rect(&cam, d, &both, &s, &q, &in);
                if (t < 0 || in < 0.25 * pixel_size(&cam, t))
                    continue;
                double x = -2 + 4 * s;
                double spacing = x < 0 ? 0.5 : 0.25; /* 2 m over 4 and over 8 intervals */
                double xs = round(x / spacing) * spacing;
                /* Skip pixels near a boundary between two element squares. */
                if (fabs(fabs(x - xs) - 0.5 * spacing) < 0.25 * pixel_size(&cam, t) ||
                    fabs(x) < 0.25 * pixel_size(&cam, t))
                    continue;
                n++;
                wrong += fabs(p[0] - linear_f(xs, 0)) > 1e-5 * linear_f(xs, 0);
            }
        }
        CHECK(n > W * H / 4 && wrong == 0,
              "nearest: %u of %u pixels do not show their nearest sample", wrong, n);
        free(img);
    }
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

/* ------------------------------------------------------- (d) depth */

static void depth_value(const surface *sf, uint32_t i, uint32_t j, float rgb[3])
{
    float v = sf->nu == 4 ? 7.0f : 2.0f; /* near quad 7, far quad 2 */
    rgb[0] = rgb[1] = rgb[2] = v;
}

/* The far quad is listed first so that draw order cannot explain a pass. */
static const char *depth_scene =
    "{\"unit\": \"m\","
    " \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": [{\"name\": \"o\", \"surfaces\": ["
    "  {\"name\": \"far\", \"material\": \"grey\", \"elements\": [3, 3],"
    "   \"quad\": {\"origin\": [-1.5, -1, -1], \"u\": [2.5, 0, 0], \"v\": [0, 2, 0]}},"
    "  {\"name\": \"near\", \"material\": \"grey\", \"elements\": [4, 4],"
    "   \"quad\": {\"origin\": [-0.5, -0.5, 0.5], \"u\": [2, 0, 0], \"v\": [0, 1.2, 0]}}]}],"
    " \"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0],"
    "  \"fov_degrees\": 50, \"width\": 64, \"height\": 64}}";

static void test_depth(xrad_context *ctx, gpu_timer *timer)
{
    xrad_scene *scene = parse(depth_scene);
    if (!scene)
        return;
    xrad_atlas atlas;
    xrad_error err = {0};
    CHECK(xrad_atlas_create(scene, &atlas, &err) == XRAD_OK, "atlas: %s", err.message);
    for (uint32_t s = 0; s < scene->surface_count; s++)
        fill_surface(scene, &atlas, s, depth_value);
    const rect rects[2] = {{{-1.5, -1, -1}, {2.5, 0, 0}, {0, 2, 0}},
                           {{-0.5, -0.5, 0.5}, {2, 0, 0}, {0, 1.2, 0}}};
    const float values[2] = {2.0f, 7.0f};
    pinhole cam = make_pinhole(5, 50, 64, 64);
    float *img = render(ctx, scene, &atlas, DISPLAY_FILTER_LINEAR_SHADER, 64, 64, timer);
    if (img) {
        uint32_t n[2] = {0, 0}, wrong = 0;
        for (uint32_t py = 0; py < 64; py++) {
            for (uint32_t px = 0; px < 64; px++) {
                double d[3], best = INFINITY, s, q, in;
                int which = -1, ambiguous = 0;
                pixel_ray(&cam, px, py, d);
                for (int r = 0; r < 2; r++) {
                    double t = hit_rect(&cam, d, &rects[r], &s, &q, &in);
                    if (t < 0)
                        continue;
                    double margin = 1.5 * pixel_size(&cam, t);
                    ambiguous |= fabs(in) < margin;
                    if (in >= margin && t < best) {
                        best = t;
                        which = r;
                    }
                }
                if (ambiguous || which < 0)
                    continue;
                n[which]++;
                wrong += img[4 * (py * 64 + px)] != values[which];
            }
        }
        CHECK(n[0] > 100 && n[1] > 100 && wrong == 0,
              "depth: %u of %u + %u pixels show the wrong surface", wrong, n[0], n[1]);
        free(img);
    }
    xrad_atlas_destroy(&atlas);
    xrad_scene_destroy(&scene);
}

/* ------------------------------------------------- (e) closed rooms */

/* The pinhole of a scene's camera, with display_camera_from's basis
 * (right = fwd x up, up = right x fwd); positions in m, world. */
static pinhole scene_pinhole(const camera *c, uint32_t w, uint32_t h)
{
    double f[3] = {c->look_at.x - c->position.x, c->look_at.y - c->position.y,
                   c->look_at.z - c->position.z};
    double fl = sqrt(dot3(f, f));
    pinhole p = {.pos = {c->position.x, c->position.y, c->position.z},
                 .tan_half = tan(0.5 * c->fov_y),
                 .w = w,
                 .h = h};
    for (int k = 0; k < 3; k++)
        p.fwd[k] = f[k] / fl;
    const double u[3] = {c->up.x, c->up.y, c->up.z};
    double r[3] = {p.fwd[1] * u[2] - p.fwd[2] * u[1], p.fwd[2] * u[0] - p.fwd[0] * u[2],
                   p.fwd[0] * u[1] - p.fwd[1] * u[0]};
    double rl = sqrt(dot3(r, r));
    for (int k = 0; k < 3; k++)
        p.right[k] = r[k] / rl;
    p.up[0] = p.right[1] * p.fwd[2] - p.right[2] * p.fwd[1];
    p.up[1] = p.right[2] * p.fwd[0] - p.right[0] * p.fwd[2];
    p.up[2] = p.right[0] * p.fwd[1] - p.right[1] * p.fwd[0];
    return p;
}

/* Pixel coordinates (x right, y down, pixel centres at + 0.5) of world
 * point x (m), the inverse of pixel_ray; the point is in front. */
static void project(const pinhole *c, const double x[3], double *px, double *py)
{
    double d[3] = {x[0] - c->pos[0], x[1] - c->pos[1], x[2] - c->pos[2]};
    double z = dot3(d, c->fwd);
    double aspect = (double)c->w / c->h;
    *px = (dot3(d, c->right) / (z * c->tan_half * aspect) + 1) * 0.5 * c->w;
    *py = (1 - dot3(d, c->up) / (z * c->tan_half)) * 0.5 * c->h;
}

/* Renders `scene` from its camera at w x h with a constant atlas (linear
 * filtering, the default image's) and counts uncovered pixels (alpha not
 * 1): with `opening` (four world corners, m, of the room's open side, in
 * order) only pixels whose centre is inside its projection by more than
 * 1.5 pixels, where the room must be seen; without it, every pixel (a
 * camera inside a closed room). Returns the count, *checked the pixels
 * looked at; checks that every covered pixel shows the constant within
 * 1e-3. */
static uint32_t count_holes(xrad_context *ctx, const xrad_scene *scene, uint32_t w, uint32_t h,
                            const double (*opening)[3], uint32_t *checked, const char *what)
{
    *checked = 0;
    xrad_atlas atlas;
    xrad_error err = {0};
    if (xrad_atlas_create(scene, &atlas, &err) != XRAD_OK) {
        CHECK(0, "%s: atlas: %s", what, err.message);
        return UINT32_MAX;
    }
    for (uint32_t s = 0; s < scene->surface_count; s++)
        fill_surface(scene, &atlas, s, constant_value);
    float *img = render(ctx, scene, &atlas, DISPLAY_FILTER_LINEAR_SHADER, w, h, NULL);
    xrad_atlas_destroy(&atlas);
    if (!img)
        return UINT32_MAX;
    pinhole cam = scene_pinhole(&scene->cam, w, h);
    double corner[4][2];
    for (int k = 0; opening && k < 4; k++)
        project(&cam, opening[k], &corner[k][0], &corner[k][1]);
    uint32_t holes = 0, off = 0;
    for (uint32_t py = 0; py < h; py++) {
        for (uint32_t px = 0; px < w; px++) {
            if (opening) {
                /* Signed distances (pixels) from the four projected edges,
                 * all of one sign inside. */
                double x = px + 0.5, y = py + 0.5, lo = INFINITY, hi = -INFINITY;
                for (int k = 0; k < 4; k++) {
                    const double *a = corner[k], *b = corner[(k + 1) % 4];
                    double ex = b[0] - a[0], ey = b[1] - a[1];
                    double dist = (ex * (y - a[1]) - ey * (x - a[0])) / sqrt(ex * ex + ey * ey);
                    lo = fmin(lo, dist);
                    hi = fmax(hi, dist);
                }
                if (!(lo > 1.5 || hi < -1.5))
                    continue;
            }
            (*checked)++;
            const float *p = &img[4 * ((size_t)py * w + px)];
            holes += p[3] != 1.0f;
            /* Where a surface is, the constant: no seam between surfaces
             * or mesh faces, no unfilled texel blended in. */
            for (int k = 0; p[3] == 1.0f && k < 3; k++)
                if (!(fabs(p[k] - constant_rgb[k]) <= 1e-3 * constant_rgb[k])) {
                    if (off++ == 0)
                        fprintf(stderr, "%s: pixel (%u, %u) channel %d is %.6g, want %.6g\n",
                                what, px, py, k, p[k], constant_rgb[k]);
                    break;
                }
        }
    }
    free(img);
    fprintf(stderr, "%s: %u of %u pixels uncovered, %u off the constant\n", what, holes,
            *checked, off);
    CHECK(off == 0, "%s: %u of %u pixels differ from the constant by more than 1e-3", what,
          off, *checked);
    return holes;
}

/* A 4 x 3 x 3 m room, every wall facing in, with two corners moved off
 * the box so that two walls are warped and planarised on load (as the
 * Cornell box's red wall is): (4, 3, 3) by 0.12 m along x warps the wall
 * x = 4 (vertices ~3 cm from their best-fit plane), (0, 0, 0) by 0.1 m
 * down warps the floor; the walls sharing those corners stay planar. */
#define ROOM_C000 "[0, -0.1, 0]"
#define ROOM_C100 "[4, 0, 0]"
#define ROOM_C010 "[0, 3, 0]"
#define ROOM_C110 "[4, 3, 0]"
#define ROOM_C001 "[0, 0, 3]"
#define ROOM_C101 "[4, 0, 3]"
#define ROOM_C011 "[0, 3, 3]"
#define ROOM_C111 "[4.12, 3, 3]"
#define ROOM_WALL(name, a, b, c, d)                                                             \
    "{\"name\": \"" name "\", \"material\": \"grey\", \"vertices\": [" a ", " b ", " c ", " d  \
    "]}"
static const char *warped_room_scene =
    "{\"unit\": \"m\", \"density\": 3,"
    " \"materials\": [{\"name\": \"grey\", \"albedo\": [0.5, 0.5, 0.5]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    ROOM_WALL("floor", ROOM_C000, ROOM_C001, ROOM_C101, ROOM_C100) ", "
    ROOM_WALL("ceiling", ROOM_C010, ROOM_C110, ROOM_C111, ROOM_C011) ", "
    ROOM_WALL("left", ROOM_C000, ROOM_C010, ROOM_C011, ROOM_C001) ", "
    ROOM_WALL("right", ROOM_C100, ROOM_C101, ROOM_C111, ROOM_C110) ", "
    ROOM_WALL("front", ROOM_C000, ROOM_C100, ROOM_C110, ROOM_C010) ", "
    ROOM_WALL("back", ROOM_C001, ROOM_C011, ROOM_C111, ROOM_C101) "]}],"
    " \"camera\": {\"position\": [1.5, 1.2, 1], \"look_at\": [4, 2, 3], \"up\": [0, 1, 0],"
    "  \"fov_degrees\": 75, \"width\": 160, \"height\": 120}}";

/* A closed 3 x 2.4 x 2.8 m box as one triangle mesh facing in, each wall
 * a grid of 3 x 2 cells cut into triangles along alternating diagonals,
 * so that a wall is many faces meeting at interior vertices: with
 * keep_triangles each face its own tile, else the cells' pairs as quads. */
static xrad_scene *grid_room(int keep_triangles)
{
    enum { NU = 3, NV = 2, WALLS = 6 };
    static const double size[3] = {3, 2.4, 2.8};
    float pos[WALLS * (NU + 1) * (NV + 1) * 3];
    uint32_t idx[WALLS * NU * NV * 6], nv = 0, nt = 0;
    for (int w = 0; w < WALLS; w++) {
        /* Wall w: axis a = w / 2 at 0 or size, spanned by axes b and c,
         * wound so that its front faces in. */
        int a = w / 2, b = (a + 1) % 3, c = (a + 2) % 3;
        bool far = w % 2;
        uint32_t base = nv;
        for (int j = 0; j <= NV; j++)
            for (int i = 0; i <= NU; i++) {
                float *v = &pos[3 * nv++];
                v[a] = far ? (float)size[a] : 0.0f;
                v[b] = (float)(size[b] * i / NU);
                v[c] = (float)(size[c] * j / NV);
            }
        for (int j = 0; j < NV; j++)
            for (int i = 0; i < NU; i++) {
                uint32_t q[4] = {base + j * (NU + 1) + i, base + j * (NU + 1) + i + 1,
                                 base + (j + 1) * (NU + 1) + i + 1, base + (j + 1) * (NU + 1) + i};
                /* b x c is +a: counter-clockwise seen from +a, the near
                 * wall's inside; the far wall turns round. */
                if (far) {
                    uint32_t t = q[1];
                    q[1] = q[3];
                    q[3] = t;
                }
                uint32_t *t = &idx[3 * nt];
                bool flip = (i + j) % 2;
                uint32_t tri[6] = {q[0], q[1], q[flip ? 3 : 2], q[flip ? 1 : 0], q[2], q[3]};
                memcpy(t, tri, sizeof tri);
                nt += 2;
            }
    }
    xrad_scene_builder *b = NULL;
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    uint32_t grey;
    xrad_status st;
    if (!(st = xrad_scene_builder_create(&(xrad_scene_builder_desc){.density = 4}, &b, &err)) &&
        !(st = xrad_scene_builder_add_material(
              b, &(xrad_material_desc){.name = "grey", .albedo = {0.5, 0.5, 0.5}}, &grey, &err)) &&
        !(st = xrad_scene_builder_begin_object(b, &(xrad_object_desc){.name = "room"}, &err)) &&
        !(st = xrad_scene_builder_add_mesh(
              b,
              &(xrad_mesh_desc){.name = "walls", .positions = pos, .vertex_count = nv,
                                .indices = idx, .triangle_count = nt, .material = grey,
                                .keep_triangles = keep_triangles},
              &err)) &&
        !(st = xrad_scene_builder_set_camera(
              b,
              &(xrad_camera_desc){.position = {0.4, 1.9, 2.5}, .look_at = {2.6, 0.4, 0.3},
                                  .fov_degrees = 80},
              &err)))
        st = xrad_scene_builder_finish(b, &scene, &err);
    xrad_scene_builder_destroy(&b);
    CHECK(st == XRAD_OK, "grid room: %s", err.message);
    return scene;
}

static void test_closed_rooms(xrad_context *ctx)
{
    /* The Cornell boxes' open fronts (z = 0, m), from the scene files. */
    static const double box_opening[4][3] = {
        {0.5528, 0, 0}, {0, 0, 0}, {0, 0.5488, 0}, {0.556, 0.5488, 0}};
    static const double large_opening[4][3] = {
        {0.556, 0, 0}, {0, 0, 0}, {0, 0.5488, 0}, {0.556, 0.5488, 0}};
    static const struct {
        const char *file;
        const double (*opening)[3];
        uint32_t size;
    } files[] = {
        {"scenes/cornell-box.json", box_opening, 512}, /* the headline image's size */
        {"scenes/cornell-large.json", large_opening, 256},
    };
    for (size_t f = 0; f < sizeof(files) / sizeof(files[0]); f++) {
        char path[1024];
        xrad_scene *scene = NULL;
        xrad_error err = {0};
        CHECK(xrad_scene_load(test_source_path(files[f].file, path, sizeof path), &scene,
                              &err) == XRAD_OK,
              "%s: %s", files[f].file, err.message);
        if (!scene)
            continue;
        uint32_t checked = 0;
        uint32_t holes = count_holes(ctx, scene, files[f].size, files[f].size, files[f].opening,
                                     &checked, files[f].file);
        CHECK(holes == 0 && checked > files[f].size * files[f].size / 2,
              "%s: %u of %u pixels inside the room show no surface", files[f].file, holes,
              checked);
        xrad_scene_destroy(&scene);
    }

    xrad_scene *scene = parse(warped_room_scene);
    if (!scene)
        return;
    uint32_t warped = 0;
    for (uint32_t s = 0; s < scene->surface_count; s++)
        warped += scene->surfaces[s].planarise_offset > 0.01;
    CHECK(warped == 2, "the test room has %u walls planarised by more than 1 cm, want 2", warped);
    /* From inside, towards each warped corner and along the room. */
    static const double views[3][2][3] = {
        {{1.5, 1.2, 1}, {4, 2, 3}},
        {{2.5, 2, 2}, {0, 0, 0}},
        {{0.5, 1.5, 0.5}, {4, 1.5, 3}},
    };
    for (int v = 0; v < 3; v++) {
        scene->cam.position = v3(views[v][0][0], views[v][0][1], views[v][0][2]);
        scene->cam.look_at = v3(views[v][1][0], views[v][1][1], views[v][1][2]);
        char what[64];
        snprintf(what, sizeof what, "warped room, view %d", v);
        uint32_t checked = 0;
        uint32_t holes = count_holes(ctx, scene, 160, 120, NULL, &checked, what);
        CHECK(holes == 0, "%s: %u of %u pixels show no surface", what, holes, checked);
    }
    xrad_scene_destroy(&scene);

    /* A triangle mesh (a 320-face geodesic ball, one atlas tile per face)
     * in a closed room, from the scene's camera and from close by, where a
     * face spans tens of pixels: every pixel a surface, every surface the
     * constant (issue 15: no seam between faces, no gap). */
    char path[1024];
    xrad_error err = {0};
    CHECK(xrad_scene_load(test_source_path("tests/data/ball-room-320.json", path, sizeof path),
                          &scene, &err) == XRAD_OK,
          "ball-room-320: %s", err.message);
    if (!scene)
        return;
    uint32_t mesh_faces = 0;
    for (uint32_t s = 0; s < scene->surface_count; s++)
        mesh_faces += scene->surfaces[s].triangle;
    CHECK(mesh_faces == 320, "ball-room-320 has %u triangles, want 320", mesh_faces);
    static const double ball_views[2][2][3] = {
        {{1.5, 1.2, 3.6}, {1.5, 0.8, 0}},     /* the scene's camera */
        {{1.5, 0.75, 2.45}, {1.5, 0.6, 1.8}}, /* 0.35 m from the ball's surface */
    };
    for (int v = 0; v < 2; v++) {
        scene->cam.position = v3(ball_views[v][0][0], ball_views[v][0][1], ball_views[v][0][2]);
        scene->cam.look_at = v3(ball_views[v][1][0], ball_views[v][1][1], ball_views[v][1][2]);
        char what[64];
        snprintf(what, sizeof what, "mesh ball in a room, view %d", v);
        uint32_t checked = 0;
        uint32_t holes = count_holes(ctx, scene, 200, 150, NULL, &checked, what);
        CHECK(holes == 0, "%s: %u of %u pixels show no surface", what, holes, checked);
    }
    xrad_scene_destroy(&scene);

    /* Flat walls of many mesh faces: every face its own tile, or the
     * cells' pairs joined into quads (the builder's charts). */
    for (int keep = 0; keep < 2; keep++) {
        scene = grid_room(keep);
        if (!scene)
            continue;
        uint32_t tris = 0;
        for (uint32_t s = 0; s < scene->surface_count; s++)
            tris += scene->surfaces[s].triangle;
        CHECK(keep ? tris == 72 && scene->surface_count == 72 : tris == 0 &&
                                                                    scene->surface_count == 36,
              "grid room: %u surfaces, %u triangles", scene->surface_count, tris);
        char what[64];
        snprintf(what, sizeof what, "grid room, %s", keep ? "a tile a face" : "quads");
        uint32_t checked = 0;
        uint32_t holes = count_holes(ctx, scene, 200, 150, NULL, &checked, what);
        CHECK(holes == 0, "%s: %u of %u pixels show no surface", what, holes, checked);
        xrad_scene_destroy(&scene);
    }
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    if (!ctx)
        return test_finish();
    gpu_timer *timer = NULL;
    xrad_error err = {0};
    CHECK(gpu_timer_create(ctx, 4, &timer, &err) == XRAD_OK, "timer: %s", err.message);
    test_constant(ctx);
    test_seam(ctx);
    test_closed_rooms(ctx);
    if (timer) {
        test_depth(ctx, timer);
        if (timer->supported) {
            CHECK(timer->totals[0].count == 1 && gpu_timer_total_ms(timer, "display") > 0,
                  "display pass timed %u times, %.3g ms", timer->totals[0].count,
                  gpu_timer_total_ms(timer, "display"));
            fprintf(stderr, "display pass, 64 x 64: %.3f ms\n",
                    gpu_timer_total_ms(timer, "display"));
        }
    }
    gpu_timer_destroy(ctx, &timer);
    gpu_test_end(&ctx);
    return test_finish();
}
