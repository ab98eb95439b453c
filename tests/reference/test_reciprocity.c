/*
 * Reciprocity (thesis 2.2.1: A_i F_ij = A_j F_ji) of the area-averaged form
 * factor kernel on element cells of a scene, and closure (rows of F sum to
 * 1) of the reference solver's form factor matrix in a closed box.
 */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "harness.h"
#include "reference/ff_kernel.h"
#include "reference/reference.h"

/* A room (inward box) with a tilted panel floating inside it, facing
 * roughly down towards the floor and one wall. */
static const char *scene_json =
    "{\"unit\":\"m\",\"density\":3,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5],\"emission\":[1,1,1]}],"
    "\"objects\":[{\"name\":\"room\",\"surfaces\":[{\"name\":\"walls\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1.2,0,0],\"v\":[0,1,0],\"w\":[0,0,0.8]},\"inward\":true}]},"
    "{\"name\":\"panel\",\"surfaces\":[{\"name\":\"p\",\"material\":\"m\","
    "\"quad\":{\"origin\":[0.3,0.6,0.2],\"u\":[0,-0.1,0.4],\"v\":[0.5,0.05,0]}}]}],"
    "\"camera\":{\"position\":[0.6,0.5,0.1],\"look_at\":[0.6,0.5,0.8],\"up\":[0,1,0],"
    "\"fov_degrees\":60}}";

static const char *box_json =
    "{\"unit\":\"m\",\"density\":4,"
    "\"materials\":[{\"name\":\"m\",\"albedo\":[0.5,0.5,0.5],\"emission\":[1,1,1]}],"
    "\"objects\":[{\"name\":\"box\",\"surfaces\":[{\"name\":\"b\",\"material\":\"m\","
    "\"box\":{\"origin\":[0,0,0],\"u\":[1,0,0],\"v\":[0,1,0],\"w\":[0,0,1]},\"inward\":true}]}],"
    "\"camera\":{\"position\":[0.5,0.5,0.1],\"look_at\":[0.5,0.5,1],\"up\":[0,1,0],"
    "\"fov_degrees\":60}}";

static xrad_scene *parse(const char *json, const char *name)
{
    xrad_scene *scene = NULL;
    xrad_error err = {0};
    xrad_status st = xrad_scene_parse(json, strlen(json), name, &scene, &err);
    CHECK(st == XRAD_OK, "parse %s: %s", name, err.message);
    return st ? NULL : scene;
}

static double cell_area(const vec3 c[4])
{
    return 0.5 * v3_len(ref_polygon_newell(c, 4));
}

/* Cells i and j lie on one plane: then both form factors vanish and the
 * pair says nothing. */
static int coplanar(const ref_geometry *g, uint32_t i, uint32_t j)
{
    vec3 ni = g->normal[i], nj = g->normal[j];
    double d = fabs(v3_dot(ni, v3_sub(g->cell[j][0], g->cell[i][0])));
    return fabs(fabs(v3_dot(ni, nj)) - 1) < 1e-12 && d < 1e-12;
}

static void check_pair(const ref_geometry *g, uint32_t i, uint32_t j, double *worst, int *pairs)
{
    /* Order 6 on a mesh graded 4 levels towards the edges: converged to
     * better than 1e-6 even for cells that share an edge. */
    double fij = ref_ff_area_polygon(g->cell[i], 4, g->cell[j], 4, 6, 4);
    double fji = ref_ff_area_polygon(g->cell[j], 4, g->cell[i], 4, 6, 4);
    double a = cell_area(g->cell[i]) * fij, b = cell_area(g->cell[j]) * fji;
    if (a == 0 && b == 0)
        return; /* facing away: both vanish, as reciprocity says */
    double rel = fabs(a - b) / fmax(a, b);
    *worst = rel > *worst ? rel : *worst;
    (*pairs)++;
    CHECK(rel < 1e-3, "pair (%u, %u): A_i F_ij = %.9g, A_j F_ji = %.9g", i, j, a, b);
}

static void test_reciprocity(void)
{
    xrad_scene *scene = parse(scene_json, "room.json");
    if (!scene)
        return;
    ref_geometry *g = NULL;
    xrad_error err = {0};
    xrad_status st = ref_geometry_create(scene, 0, 16, false, &g, &err);
    CHECK(st == XRAD_OK, "geometry: %s", err.message);
    if (st) {
        xrad_scene_destroy(&scene);
        return;
    }
    uint32_t n = g->element_count;
    /* Cells tile their surfaces: their areas match the scene's element
     * areas and sum to the surface areas. */
    for (uint32_t s = 0; s < g->surface_count; s++) {
        double sum = 0;
        for (uint32_t e = g->surface_first[s]; e < g->surface_first[s] + g->surface_elements[s]; e++) {
            CHECK_REL(cell_area(g->cell[e]), scene->elements[e].area, 1e-9);
            sum += cell_area(g->cell[e]);
        }
        CHECK_REL(sum, scene->surfaces[s].area, 1e-9);
    }

    /* Pairs: 200 drawn by a fixed LCG among all elements, skipping pairs on
     * one plane (F = 0 both ways, nothing to compare); these cover far,
     * oblique and panel-to-wall pairs. Then every pair of cells that touch
     * across an edge of the room (a floor cell and a wall cell meeting at
     * the seam), since there the integrand is least smooth and a poor
     * quadrature would show first. */
    double worst = 0;
    int pairs = 0;
    uint64_t x = 12345;
    for (int k = 0; k < 200;) {
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t i = (uint32_t)(x >> 33) % n;
        x = x * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t j = (uint32_t)(x >> 33) % n;
        if (g->surface_of[i] == g->surface_of[j] || coplanar(g, i, j))
            continue;
        check_pair(g, i, j, &worst, &pairs);
        k++;
    }
    int touching = 0;
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t j = i + 1; j < n; j++) {
            if (g->surface_of[i] == g->surface_of[j] || coplanar(g, i, j))
                continue;
            int shared = 0;
            for (int a = 0; a < 4; a++)
                for (int b = 0; b < 4; b++)
                    shared += v3_len(v3_sub(g->cell[i][a], g->cell[j][b])) < 1e-9;
            if (shared >= 2) {
                check_pair(g, i, j, &worst, &pairs);
                touching++;
            }
        }
    fprintf(stderr, "reciprocity: %d pairs (%d sharing an edge), worst relative difference %.3g\n",
            pairs, touching, worst);
    CHECK(pairs >= 150, "only %d pairs with a nonzero form factor", pairs);
    CHECK(touching > 0, "no edge-sharing pairs found");
    ref_geometry_destroy(&g);
    xrad_scene_destroy(&scene);
}

static void test_row_sums(void)
{
    xrad_scene *scene = parse(box_json, "box.json");
    if (!scene)
        return;
    xrad_reference_desc desc = {.threads = 2};
    xrad_reference_stats stats = {0};
    xrad_error err = {0};
    float *F = NULL;
    xrad_status st = ref_form_factor_matrix(scene, &desc, &F, &stats, &err);
    CHECK(st == XRAD_OK, "matrix: %s", err.message);
    if (!st) {
        uint32_t n = scene->element_count;
        double lo = 1e9, hi = -1e9;
        for (uint32_t i = 0; i < n; i++) {
            double sum = 0;
            for (uint32_t j = 0; j < n; j++) {
                float f = F[(size_t)i * n + j];
                CHECK(f >= 0 && f <= 1, "F[%u][%u] = %g", i, j, f);
                sum += f;
            }
            lo = sum < lo ? sum : lo;
            hi = sum > hi ? sum : hi;
        }
        fprintf(stderr, "closed box, %u elements: row sums in [%.9f, %.9f], stats max %.9f\n", n, lo,
                hi, stats.max_row_sum);
        CHECK(fabs(lo - 1) < 1e-2 && fabs(hi - 1) < 1e-2, "row sums [%g, %g]", lo, hi);
        /* In fact only float rounding of the entries separates them from 1. */
        CHECK(fabs(lo - 1) < 1e-6 && fabs(hi - 1) < 1e-6, "row sums [%.9f, %.9f]", lo, hi);
        CHECK_ABS(stats.max_row_sum, hi, 1e-12);
    }
    free(F);
    xrad_scene_destroy(&scene);
}

int main(void)
{
    test_reciprocity();
    test_row_sums();
    return test_finish();
}
