/* Large convex hulls against what a convex polytope must be: points on a sphere are all its
 * vertices and points well inside are none; the triangles close an oriented surface (every
 * directed edge once, its reverse once), which gives V - E + F = 2; every edge is convex (the
 * far corner of the neighbouring triangle lies below the plane); and no input point lies above
 * any triangle's plane. The scene loader loads a 500 000-vertex mesh sphere (every mesh body
 * gets a hull at load), with the mass of the inscribed polyhedron. No timing here: the hull's
 * cost is printed by bench_contact_geometry. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "contact/convex_hull.h"
#include "math/tb_math.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TB_TEST_PI 3.14159265358979323846

enum { SPHERE_POINTS = 500000, INSIDE_POINTS = 100 };

/* Point i of n spread evenly over the unit sphere (the Fibonacci lattice). */
static void fibonacci_point(size_t i, size_t n, double out[3])
{
    const double z = 1.0 - (2.0 * (double)i + 1.0) / (double)n, r = sqrt(1.0 - z * z);
    const double angle = 2.399963229728653 * (double)i; /* the golden angle, rad */
    tb__v3_set(out, r * cos(angle), r * sin(angle), z);
}

static uint64_t edge_key(uint32_t from, uint32_t to)
{
    return (uint64_t)from << 32 | to;
}

static int by_value(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Which triangle holds directed edge key (sorted keys, owner of each), or -1. */
static long owner_of(const uint64_t *keys, const uint32_t *owner, size_t count, uint64_t key)
{
    size_t low = 0, high = count;
    while (low < high) {
        const size_t middle = low + (high - low) / 2;
        if (keys[middle] < key) {
            low = middle + 1;
        } else {
            high = middle;
        }
    }
    return low < count && keys[low] == key ? (long)owner[low] : -1;
}

static double plane_height(const double *points, const uint32_t *t, const double *x)
{
    double ab[3], ac[3], n[3], ax[3];
    for (int k = 0; k < 3; ++k) {
        ab[k] = points[3 * t[1] + k] - points[3 * t[0] + k];
        ac[k] = points[3 * t[2] + k] - points[3 * t[0] + k];
        ax[k] = x[k] - points[3 * t[0] + k];
    }
    tb__v3_cross(n, ab, ac);
    return tb__v3_dot(n, ax) / tb__v3_norm(n);
}

/* Every directed edge once and its reverse once (a closed oriented surface), and every edge
 * convex: the neighbour's far corner at most tolerance above the plane. */
static void assert_closed_and_convex(const double *points, const uint32_t *tri, size_t faces,
                                     double tolerance)
{
    const size_t edges = 3 * faces;
    uint64_t *keys = malloc(edges * sizeof *keys);
    uint32_t *owner = malloc(edges * sizeof *owner);
    assert_non_null(keys);
    assert_non_null(owner);
    for (size_t f = 0; f < faces; ++f) {
        for (int k = 0; k < 3; ++k) {
            keys[3 * f + k] = edge_key(tri[3 * f + k], tri[3 * f + (k + 1) % 3]);
        }
    }
    qsort(keys, edges, sizeof *keys, by_value);
    for (size_t e = 1; e < edges; ++e) {
        assert_true(keys[e - 1] < keys[e]); /* no directed edge twice */
    }
    for (size_t f = 0; f < faces; ++f) { /* each sorted edge's triangle */
        for (int k = 0; k < 3; ++k) {
            const uint64_t key = edge_key(tri[3 * f + k], tri[3 * f + (k + 1) % 3]);
            size_t low = 0, high = edges;
            while (low < high) {
                const size_t middle = low + (high - low) / 2;
                if (keys[middle] < key) {
                    low = middle + 1;
                } else {
                    high = middle;
                }
            }
            owner[low] = (uint32_t)f;
        }
    }
    double highest = -INFINITY;
    for (size_t f = 0; f < faces; ++f) {
        const uint32_t *t = tri + 3 * f;
        for (int k = 0; k < 3; ++k) {
            const long g = owner_of(keys, owner, edges, edge_key(t[(k + 1) % 3], t[k]));
            assert_true(g >= 0); /* the reverse edge exists: closed */
            for (int j = 0; j < 3; ++j) {
                highest = fmax(highest, plane_height(points, t, points + 3 * tri[3 * g + j]));
            }
        }
    }
    print_message("highest neighbour corner above a face: %.3g\n", highest);
    assert_true(highest <= tolerance);
    free(keys);
    free(owner);
}

/* 500 000 points on the unit sphere and 100 inside (radius 0.5 to 0.9, all well inside the
 * inscribed polytope, whose faces are within 3e-6 of the sphere). Tolerance 1e-9: the hull
 * treats points within 1e-10 of the extent (2) as on it; a wrong hull is off by the spacing's
 * sagitta, about 1e-6. */
static void test_the_hull_of_half_a_million_points_on_a_sphere_is_their_polytope(void **unused)
{
    (void)unused;
    const size_t n = SPHERE_POINTS + INSIDE_POINTS;
    double *points = malloc(3 * n * sizeof *points);
    unsigned char *on_hull = malloc(n);
    assert_non_null(points);
    assert_non_null(on_hull);
    for (size_t i = 0; i < SPHERE_POINTS; ++i) {
        fibonacci_point(i, SPHERE_POINTS, points + 3 * i);
    }
    for (size_t i = 0; i < INSIDE_POINTS; ++i) { /* interleaved with the sphere's */
        double *x = points + 3 * (SPHERE_POINTS + i);
        fibonacci_point(i * 4999, SPHERE_POINTS, x);
        const double r = 0.5 + 0.4 * (double)i / INSIDE_POINTS;
        tb__v3_set(x, r * x[0], r * x[1], r * x[2]);
    }
    uint32_t *tri = NULL;
    size_t faces = 0;
    char detail[TB_DETAIL_SIZE];
    assert_int_equal(tb__convex_hull_triangles(points, n, on_hull, &tri, &faces, detail),
                     TB_STATUS_OK);
    size_t vertices = 0;
    for (size_t i = 0; i < n; ++i) {
        assert_int_equal(on_hull[i], i < SPHERE_POINTS);
        vertices += on_hull[i];
    }
    for (size_t j = 0; j < 3 * faces; ++j) {
        assert_true(tri[j] < SPHERE_POINTS); /* hull corners are input points, on the sphere */
    }
    /* closed and triangulated: E = 3F / 2, so V - E + F = 2 is F = 2 V - 4 */
    assert_int_equal((long)vertices - (long)(3 * faces / 2) + (long)faces, 2);
    assert_closed_and_convex(points, tri, faces, 1e-9);
    double highest = -INFINITY; /* no point above any face: 10 inside points against each */
    for (size_t i = SPHERE_POINTS; i < SPHERE_POINTS + 10; ++i) {
        for (size_t f = 0; f < faces; ++f) {
            highest = fmax(highest, plane_height(points, tri + 3 * f, points + 3 * i));
        }
    }
    assert_true(highest <= 1e-9);
    free(tri);
    free(on_hull);
    free(points);
}

/* A mesh sphere of 1 + 500 x 1000 + 1 vertices (rings of latitude, quads between them, triangle
 * fans at the poles) written as OBJ and loaded as a body: its hull is made at load. The mass at
 * density 1 is the inscribed polyhedron's, below 4/3 pi by at most the rings' and segments'
 * sagitta (relative 1 - cos(pi / 501) + 1 - cos(pi / 1000), 2.5e-5): 1e-4 relative. */
static void test_the_scene_loader_loads_a_half_million_vertex_mesh_sphere(void **unused)
{
    (void)unused;
    enum { RINGS = 500, SEGMENTS = 1000 };
    const char *folder = TUMBLE_TEST_BUILD_DIR "/";
    char path[512];
    snprintf(path, sizeof path, "%sbig_sphere.obj", folder);
    FILE *obj = fopen(path, "w");
    assert_non_null(obj);
    fprintf(obj, "v 0 0 1\n");
    for (int i = 0; i < RINGS; ++i) {
        const double theta = TB_TEST_PI * (i + 1) / (RINGS + 1);
        for (int j = 0; j < SEGMENTS; ++j) {
            const double phi = 2.0 * TB_TEST_PI * j / SEGMENTS;
            fprintf(obj, "v %.12g %.12g %.12g\n", sin(theta) * cos(phi), sin(theta) * sin(phi),
                    cos(theta));
        }
    }
    fprintf(obj, "v 0 0 -1\n");
    const int bottom = 2 + RINGS * SEGMENTS;
    for (int j = 0; j < SEGMENTS; ++j) {
        const int next = (j + 1) % SEGMENTS;
        fprintf(obj, "f 1 %d %d\n", 2 + j, 2 + next);
        for (int i = 0; i + 1 < RINGS; ++i) {
            fprintf(obj, "f %d %d %d %d\n", 2 + i * SEGMENTS + j, 2 + (i + 1) * SEGMENTS + j,
                    2 + (i + 1) * SEGMENTS + next, 2 + i * SEGMENTS + next);
        }
        fprintf(obj, "f %d %d %d\n", bottom, 2 + (RINGS - 1) * SEGMENTS + next,
                2 + (RINGS - 1) * SEGMENTS + j);
    }
    assert_int_equal(fclose(obj), 0);
    const char *json = "{\"bodies\": [{\"name\": \"ball\", \"shape\": {\"type\": \"mesh\", "
                       "\"file\": \"big_sphere.obj\"}, \"density\": 1}]}";
    tb_scene *scene = NULL;
    tb_error error;
    const tb_status status = tb_scene_load_string(json, "m.json", folder, &scene, NULL, &error);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", error.message);
    }
    assert_int_equal(status, TB_STATUS_OK);
    tb_mass_properties mass;
    assert_int_equal(tb_scene_get_mass(scene, 0, &mass), TB_STATUS_OK);
    const double exact = 4.0 / 3.0 * TB_TEST_PI;
    print_message("mass %.9g, the ball's %.9g\n", mass.mass, exact);
    assert_true(mass.mass < exact && mass.mass > exact * (1.0 - 1e-4));
    tb_scene_destroy(scene);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_hull_of_half_a_million_points_on_a_sphere_is_their_polytope),
        cmocka_unit_test(test_the_scene_loader_loads_a_half_million_vertex_mesh_sphere),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
