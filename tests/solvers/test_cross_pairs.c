/* Cross's pair list (cross_pairs on; spirv/cross_reconstruct.comp): the
 * (element of C, patch) pairs that see each other, listed on the GPU, then
 * traced per pair in patch order.
 *
 * 1. No visible pair missing: every pair that plainly sees each other on
 *    the CPU (element and patch face each other at cosines above 0.1, and
 *    the segments from the element's sample point to the patch's centre
 *    and to four points near its corners cross no other surface) is in
 *    the element's range of the list.
 * 2. The list is a list: each pair in its element's range names that
 *    element, a patch at most once, a positive form factor; the ranges do
 *    not overlap; fewer pairs than elements x patches.
 * 3. The same solution as the loop over every patch per element, after a
 *    solve and after a frame (the old pose's terms removed), to 1e-5 of
 *    the largest radiosity.
 * 4. The contribution bound (cross_cut, xrad.h): with a cut, every listed
 *    pair's bound F max(B_s, Pmax) is at least cut x Rmax (the totals and
 *    the peak read back); every plainly visible pair whose bound by the
 *    exact unoccluded form factor (Lambert's contour formula on the CPU) is
 *    twice that is listed; and some plainly visible pair below half of it
 *    is left out (the cut did something). */
#include "gpu/gpu_test.h"
#include "solver_test.h"
#include "reference/ff_kernel.h"
#include "reference/raycast.h"
#include "scene/scene.h"
#include "solvers/cross.h"
#include "solvers/solver.h"

/* A room with a ceiling light and a box floating in it, moving 0.2 m. */
static const char *scene_json =
    "{\"unit\": \"m\", \"density\": 8,"
    " \"materials\": [{\"name\": \"white\", \"albedo\": [0.6, 0.6, 0.6]},"
    "   {\"name\": \"red\", \"albedo\": [0.7, 0.2, 0.2]},"
    "   {\"name\": \"lamp\", \"albedo\": [0, 0, 0], \"emission\": [20, 20, 20]}],"
    " \"objects\": [{\"name\": \"room\", \"surfaces\": ["
    "   {\"name\": \"walls\", \"material\": \"white\", \"box\": {\"origin\": [0, 0, 0],"
    "     \"u\": [1, 0, 0], \"v\": [0, 1, 0], \"w\": [0, 0, 1]}, \"inward\": true},"
    "   {\"name\": \"light\", \"material\": \"lamp\", \"quad\": {\"origin\": [0.4, 0.99, 0.4],"
    "     \"u\": [0.2, 0, 0], \"v\": [0, 0, 0.2]}}]},"
    "  {\"name\": \"box\", \"dynamic\": true, \"cross_density\": 8, \"surfaces\": ["
    "   {\"name\": \"b\", \"material\": \"red\", \"box\": {\"origin\": [0.3, 0.3, 0.35],"
    "     \"u\": [0.25, 0, 0], \"v\": [0, 0.25, 0], \"w\": [0, 0, 0.25]}}],"
    "   \"animation\": {\"keyframes\": [{\"time\": 0, \"translate\": [0, 0, 0]},"
    "     {\"time\": 1, \"translate\": [0.2, 0, 0]}], \"loop\": false}}],"
    " \"camera\": {\"position\": [0.5, 0.5, 0.02], \"look_at\": [0.5, 0.5, 1],"
    "   \"fov_degrees\": 70, \"width\": 32, \"height\": 32}}";

/* Part 4's cut: on this room it keeps about 900 of 11,000 pairs. */
#define CUT 0.003

static xrad_solver *make(xrad_context *ctx, const xrad_scene *scene, uint32_t pairs, double cut,
                         xrad_error *err)
{
    xrad_solver_desc d = {.method = XRAD_METHOD_CROSS, .hemicube_res = 32, .msaa = 1,
                          .cross_pairs = pairs, .cross_cut = cut};
    xrad_solver *s = NULL;
    if (xrad_solver_create(ctx, scene, &d, &s, err) || xrad_solver_solve(s, err))
        xrad_solver_destroy(&s);
    return s;
}

static vec3 v3f(const vec4 v) { return (vec3){v.x, v.y, v.z}; }

/* Whether the segment a -> b crosses a static surface other than `skip`
 * or a patch other than `skip_patch`. */
static bool blocked(const xrad_scene *scene, const cross_pair_readback *r, vec3 a, vec3 b,
                    uint32_t skip, uint32_t skip_patch)
{
    for (uint32_t s = 0; s < scene->surface_count; s++) {
        if (s == skip || scene->objects[scene->surfaces[s].object].dynamic)
            continue;
        ref_quad q;
        if (ref_quad_init(&q, scene->surfaces[s].p) && ref_segment_hits_quad(&q, a, b))
            return true;
    }
    for (uint32_t p = 0; p < r->patch_count; p++) {
        if (p == skip_patch)
            continue;
        vec3 c[4];
        for (int k = 0; k < 4; k++)
            c[k] = v3f(r->quads[p].corner[k]);
        ref_quad q;
        if (ref_quad_init(&q, c) && ref_segment_hits_quad(&q, a, b))
            return true;
    }
    return false;
}

/* Element e and patch p plainly see each other (the comment at the top). */
static bool plainly_visible(const xrad_scene *scene, const cross_pair_readback *r, uint32_t e,
                            uint32_t p)
{
    const element *el = &scene->elements[e];
    const surface *sf = &scene->surfaces[el->surface];
    vec3 x = el->pos, ne = sf->normal;
    vec3 c = v3f(r->fronts[p].pos_area), np = v3f(r->fronts[p].normal);
    vec3 points[5] = {c};
    for (int k = 0; k < 4; k++)
        points[k + 1] = v3_add(c, v3_scale(v3_sub(v3f(r->quads[p].corner[k]), c), 0.9));
    for (int k = 0; k < 5; k++) {
        vec3 d = v3_sub(x, points[k]);
        double len = v3_len(d);
        if (len < 0.02 || v3_dot(d, np) < 0.1 * len || -v3_dot(d, ne) < 0.1 * len ||
            blocked(scene, r, x, points[k], el->surface, p))
            return false;
    }
    return true;
}

static void check_list(const xrad_scene *scene, const cross_pair_readback *r, const char *when)
{
    uint32_t checked = 0, missing = 0, listed_total = 0, elements = 0;
    uint8_t *seen = calloc(r->patch_count, 1);
    uint8_t *used = calloc(r->pair_count ? r->pair_count : 1, 1);
    CHECK(seen && used, "out of memory");
    for (uint32_t e = 0; seen && used && e < scene->element_count; e++) {
        const surface *sf = &scene->surfaces[scene->elements[e].surface];
        if (scene->objects[sf->object].dynamic)
            continue;
        uint32_t first = r->ranges[2 * e], n = r->ranges[2 * e + 1];
        CHECK(n != CROSS_RANGE_INLINE, "%s: element %u left out of the list", when, e);
        if (n == CROSS_RANGE_SKIP || n == CROSS_RANGE_HIDDEN || n == CROSS_RANGE_INLINE)
            continue;
        elements++;
        CHECK(first <= r->pair_count && n <= r->pair_count - first,
              "%s: element %u's range %u + %u passes the %u pairs", when, e, first, n,
              r->pair_count);
        if (first > r->pair_count || n > r->pair_count - first)
            continue;
        memset(seen, 0, r->patch_count);
        for (uint32_t k = first; k < first + n; k++) {
            const struct cross_pair *q = &r->pairs[k];
            CHECK(!used[k], "%s: pair %u in two ranges", when, k);
            used[k] = 1;
            CHECK(q->element == e && q->patch_index < r->patch_count && q->ff > 0,
                  "%s: pair %u of element %u names element %u, patch %u, ff %g", when, k, e,
                  q->element, q->patch_index, q->ff);
            if (q->patch_index < r->patch_count) {
                CHECK(!seen[q->patch_index], "%s: element %u lists patch %u twice", when, e,
                      q->patch_index);
                seen[q->patch_index] = 1;
            }
        }
        listed_total += n;
        for (uint32_t p = 0; p < r->patch_count; p++) {
            if (!plainly_visible(scene, r, e, p))
                continue;
            checked++;
            if (!seen[p]) {
                if (missing < 5)
                    CHECK(seen[p], "%s: element %u (%s) plainly sees patch %u, not listed",
                          when, e, sf->name, p);
                missing++;
            }
        }
    }
    printf("%s: %u pairs listed for %u elements x %u patches; %u plainly visible pairs "
           "checked, %u missing\n",
           when, listed_total, elements, r->patch_count, checked, missing);
    CHECK(missing == 0, "%s: %u plainly visible pairs missing from the list", when, missing);
    CHECK(checked > 1000, "%s: only %u pairs plainly visible: the check tested little", when,
          checked);
    CHECK(listed_total == r->pair_count, "%s: ranges cover %u of %u pairs", when, listed_total,
          r->pair_count);
    CHECK(listed_total < (uint64_t)elements * r->patch_count,
          "%s: every pair listed (%u): the list left nothing out", when, listed_total);
    free(seen);
    free(used);
}

static double largest(const vec4 v)
{
    return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
}

/* Part 4, on a list made with cross_cut = CUT. */
static void check_cut(const xrad_scene *scene, const cross_pair_readback *r)
{
    double peak = r->peak > 0 && isfinite(r->peak) ? r->peak : 0, top = peak;
    for (uint32_t p = 0; p < r->patch_count; p++)
        top = fmax(top, largest(r->values[p].total));
    double level = CUT * top;
    CHECK(level > 0, "cut: no radiosity to cut against (peak %g)", peak);
    uint32_t low = 0, kept_low = 0, checked = 0, missing = 0;
    for (uint32_t k = 0; k < r->pair_count; k++) {
        const struct cross_pair *q = &r->pairs[k];
        if (q->patch_index >= r->patch_count)
            continue;
        double bound = q->ff * fmax(largest(r->values[q->patch_index].total), peak);
        if (bound < level * (1 - 1e-5) && kept_low++ < 5)
            CHECK(0, "cut: pair %u (element %u, patch %u) listed with bound %g < %g", k,
                  q->element, q->patch_index, bound, level);
    }
    for (uint32_t e = 0; e < scene->element_count; e++) {
        const element *el = &scene->elements[e];
        const surface *sf = &scene->surfaces[el->surface];
        uint32_t first = r->ranges[2 * e], n = r->ranges[2 * e + 1];
        if (scene->objects[sf->object].dynamic || n == CROSS_RANGE_SKIP ||
            n == CROSS_RANGE_HIDDEN || n == CROSS_RANGE_INLINE || first > r->pair_count ||
            n > r->pair_count - first)
            continue;
        for (uint32_t p = 0; p < r->patch_count; p++) {
            if (!plainly_visible(scene, r, e, p))
                continue;
            vec3 c[4];
            for (int k = 0; k < 4; k++)
                c[k] = v3f(r->quads[p].corner[k]);
            double bound = ref_ff_point_polygon(el->pos, sf->normal, c, 4) *
                           fmax(largest(r->values[p].total), peak);
            bool listed = false;
            for (uint32_t k = first; k < first + n; k++)
                listed |= r->pairs[k].patch_index == p;
            if (bound >= 2 * level) {
                checked++;
                if (!listed && missing++ < 5)
                    CHECK(0, "cut: element %u (%s) and patch %u, bound %g >= 2 x %g, not listed",
                          e, sf->name, p, bound, level);
            } else if (bound < 0.5 * level && !listed) {
                low++;
            }
        }
    }
    printf("cut %g: level %.3g (Rmax %.3g); %u pairs listed, %u plainly visible pairs above "
           "twice the level checked, %u missing; %u below half of it left out\n",
           CUT, level, top, r->pair_count, checked, missing, low);
    CHECK(kept_low == 0, "cut: %u listed pairs below the level", kept_low);
    CHECK(missing == 0, "cut: %u pairs above twice the level missing", missing);
    CHECK(checked > 100, "cut: only %u pairs above twice the level: tested little", checked);
    CHECK(low > 100, "cut: only %u pairs below half the level left out: the cut did little",
          low);
}

int main(void)
{
    xrad_context *ctx = gpu_test_context();
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    CHECK(xrad_scene_parse(scene_json, strlen(scene_json), "cross_pairs.json", &scene, &err) ==
              XRAD_OK,
          "%s", err.message);
    if (!ctx || !scene)
        return test_finish();
    xrad_solver *listed = make(ctx, scene, XRAD_CROSS_PAIRS_ON, 0, &err);
    CHECK(listed, "cross, pairs listed: %s", err.message);
    xrad_solver *looped = make(ctx, scene, XRAD_CROSS_PAIRS_OFF, 0, &err);
    CHECK(looped, "cross, a loop per element: %s", err.message);
    xrad_atlas a = {0}, b = {0};
    CHECK(xrad_atlas_create(scene, &a, &err) == XRAD_OK &&
              xrad_atlas_create(scene, &b, &err) == XRAD_OK,
          "%s", err.message);
    const double times[2] = {-1, 0.6};
    for (int f = 0; listed && looped && f < 2; f++) {
        const char *when = f ? "after a frame" : "after the solve";
        if (times[f] >= 0) {
            CHECK(xrad_solver_advance(listed, times[f], &err) == XRAD_OK, "%s", err.message);
            CHECK(xrad_solver_advance(looped, times[f], &err) == XRAD_OK, "%s", err.message);
        }
        xrad_solver_stats st;
        xrad_solver_get_stats(listed, &st);
        CHECK(st.cross_pairs > 0 && st.cross_pairs_unlisted == 0,
              "%s: %llu pairs traced, %llu unlisted", when, (unsigned long long)st.cross_pairs,
              (unsigned long long)st.cross_pairs_unlisted);
        cross_pair_readback r;
        CHECK(cross_read_pairs(listed, &r, &err) == XRAD_OK, "%s", err.message);
        check_list(scene, &r, when);
        cross_pair_readback_free(&r);
        CHECK(xrad_solver_read(listed, &a, &err) == XRAD_OK &&
                  xrad_solver_read(looped, &b, &err) == XRAD_OK,
              "%s", err.message);
        double d = solver_test_atlas_diff(&a, &b);
        printf("%s: listed against looped, largest difference %.2e of the largest value\n",
               when, d);
        CHECK(d < 1e-5, "%s: listed and looped differ by %.2e of the largest value", when, d);
    }
    xrad_solver_destroy(&listed);
    xrad_solver_destroy(&looped);
    xrad_solver *cut = make(ctx, scene, XRAD_CROSS_PAIRS_ON, CUT, &err);
    CHECK(cut, "cross, pairs listed with a cut: %s", err.message);
    if (cut) {
        cross_pair_readback r;
        CHECK(cross_read_pairs(cut, &r, &err) == XRAD_OK, "%s", err.message);
        check_cut(scene, &r);
        cross_pair_readback_free(&r);
    }
    xrad_solver_destroy(&cut);
    xrad_atlas_destroy(&a);
    xrad_atlas_destroy(&b);
    xrad_scene_destroy(&scene);
    gpu_test_end(&ctx);
    return test_finish();
}
