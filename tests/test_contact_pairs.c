/* The rest of contact geometry: shapes against planes, world bounds against support points,
 * convex hulls, the contact-pairs hook against the narrow phase run on every pair (the broad
 * phase alone: test_broad_phase.c), tb_scene_set_body_shape's refusals, and the
 * scene file's shapes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geometry.h"
#include "near.h"
#include "contact/contact_pairs.h"
#include "contact/convex_hull.h"
#include "contact/narrow_phase.h"
#include "math/tb_math.h"
#include "tumble/tumble.h"

#include <stdlib.h>
#include <string.h>

#define EXACT 1e-12
static const double z_axis[3] = {0, 0, 1};
static const double up[3] = {0, 0, 1};

/* A box on the plane z = 0, sunk 1 mm and turned about z: its 4 bottom corners, 1 mm deep,
 * halfway between corner and plane. Tilted 0.2 rad about x, only the two lowest corners
 * touch, the lower edge's depth 1 mm. */
static void test_box_on_a_plane_touches_at_its_lowest_corners(void **state)
{
    (void)state;
    tb__collision_shape *box = test_box(0.4, 0.2, 0.1);
    double pose[7];
    test_pose(pose, 1, 2, 0.05 - 1e-3, z_axis, 0.7);
    tb__contact_manifold m;
    assert_int_equal(tb__collide_plane(up, 0.0, box, pose, 0.0, &m), 4);
    for (int k = 0; k < 4; ++k) {
        assert_near(m.points[k].depth, 1e-3, EXACT);
        assert_near(m.points[k].position[2], -0.5e-3, EXACT);
    }
    const double x_axis[3] = {1, 0, 0}, angle = 0.2;
    const double low = 0.05 * cos(angle) + 0.1 * sin(angle); /* the lower edge's drop */
    test_pose(pose, 0, 0, low - 1e-3, x_axis, angle);
    assert_int_equal(tb__collide_plane(up, 0.0, box, pose, 0.0, &m), 2);
    assert_near(m.points[0].depth, 1e-3, EXACT);
    assert_near(m.points[1].depth, 1e-3, EXACT);
    /* within a 5 cm margin the two upper-side corners of the bottom come too */
    assert_int_equal(tb__collide_plane(up, 0.0, box, pose, 0.05, &m), 4);
    free(box);
}

/* A capsule lying on the plane rests on its two end spheres; a cylinder standing on it on 4
 * rim points 90 degrees apart, lying on it on its two lowest rim points; all equally deep. */
static void test_capsules_and_cylinders_rest_on_a_plane_along_their_length(void **state)
{
    (void)state;
    const double x_axis[3] = {1, 0, 0}, half_turn = 0.5 * 3.141592653589793;
    tb_shape s = tb_shape_default();
    s.radius = 0.1;
    s.length = 0.6;
    s.type = TB_SHAPE_CAPSULE;
    tb__collision_shape *capsule = test_shape(&s);
    s.type = TB_SHAPE_CYLINDER;
    tb__collision_shape *cylinder = test_shape(&s);
    double pose[7];
    tb__contact_manifold m;
    test_pose(pose, 0, 0, 0.1 - 1e-3, x_axis, half_turn);
    assert_int_equal(tb__collide_plane(up, 0.0, capsule, pose, 0.0, &m), 2);
    assert_near(m.points[0].depth, 1e-3, EXACT);
    assert_near(m.points[1].depth, 1e-3, EXACT);
    assert_near(fabs(m.points[0].position[1] - m.points[1].position[1]), 0.6, EXACT);
    assert_int_equal(tb__collide_plane(up, 0.0, cylinder, pose, 0.0, &m), 2);
    assert_near(fabs(m.points[0].position[1] - m.points[1].position[1]), 0.6, EXACT);
    test_pose(pose, 0, 0, 0.3 - 1e-3, z_axis, 0.4);
    assert_int_equal(tb__collide_plane(up, 0.0, cylinder, pose, 0.0, &m), 4);
    for (int k = 0; k < 4; ++k) {
        assert_near(m.points[k].depth, 1e-3, EXACT);
        assert_near(hypot(m.points[k].position[0], m.points[k].position[1]), 0.1, EXACT);
    }
    free(capsule);
    free(cylinder);
}

/* Every shape on a tilted plane n . x = d: the depth of its lowest point from the support
 * function's closed form (sphere r, capsule r + h |n . a|, cylinder h |n . a| + r sqrt(1 -
 * (n . a)^2), ellipsoid |A R^T n|) below the centre's height. */
static void test_every_shape_on_a_plane_is_as_deep_as_its_lowest_point(void **state)
{
    (void)state;
    const double n[3] = {0.36, 0.48, 0.8}, offset = 0.3;
    double pose[7];
    const double axis[3] = {1, 2, 3};
    test_pose(pose, 0.5, -0.2, 0.4, axis, 0.9);
    double a[3]; /* the shape's z axis in the world */
    tb__q_rotate(a, pose + 3, z_axis);
    const double na = tb__v3_dot(n, a);
    const double height = tb__v3_dot(n, pose) - offset;
    tb_shape s = tb_shape_default();
    struct {
        tb_shape_type type;
        double reach; /* how far below the centre along -n the shape reaches */
    } cases[4] = {{TB_SHAPE_SPHERE, 0.25},
                  {TB_SHAPE_CAPSULE, 0.25 + 0.3 * fabs(na)},
                  {TB_SHAPE_CYLINDER, 0.3 * fabs(na) + 0.25 * sqrt(1 - na * na)},
                  {TB_SHAPE_ELLIPSOID, 0.0}};
    double local_n[3];
    tb__q_rotate_inverse(local_n, pose + 3, n);
    cases[3].reach = sqrt(0.01 * local_n[0] * local_n[0] + 0.04 * local_n[1] * local_n[1] +
                          0.09 * local_n[2] * local_n[2]);
    for (int k = 0; k < 4; ++k) {
        s.type = cases[k].type;
        s.radius = 0.25;
        s.length = 0.6;
        tb__v3_set(s.semi_axes, 0.1, 0.2, 0.3);
        tb__collision_shape *shape = test_shape(&s);
        tb__contact_manifold m;
        assert_true(tb__collide_plane(n, offset, shape, pose, 0.0, &m) >= 1);
        double deepest = -INFINITY;
        for (int p = 0; p < m.count; ++p) {
            deepest = fmax(deepest, m.points[p].depth);
        }
        assert_near(deepest, cases[k].reach - height, 1e-12);
        free(shape);
    }
}

/* World bounds are exactly the support points along the axes for the primitives (so the
 * broad phase pads nothing it need not), and contain every vertex of a convex shape. */
static void test_bounds_are_the_support_points_along_the_axes(void **state)
{
    (void)state;
    uint64_t rng = 99;
    tb_shape s = tb_shape_default();
    s.radius = 0.3;
    s.length = 0.8;
    tb__v3_set(s.size, 0.2, 0.5, 1.1);
    tb__v3_set(s.semi_axes, 0.2, 0.5, 1.1);
    const tb_shape_type types[] = {TB_SHAPE_SPHERE, TB_SHAPE_BOX, TB_SHAPE_CAPSULE,
                                   TB_SHAPE_CYLINDER, TB_SHAPE_ELLIPSOID};
    for (int trial = 0; trial < 50; ++trial) {
        double pose[7];
        tb__v3_set(pose, test_uniform(&rng, -3, 3), test_uniform(&rng, -3, 3), 1.0);
        test_random_quaternion(&rng, pose + 3);
        for (size_t t = 0; t < sizeof types / sizeof types[0]; ++t) {
            s.type = types[t];
            tb__collision_shape *shape = test_shape(&s);
            double low[3], high[3];
            tb__collision_shape_bounds(shape, pose, low, high);
            for (int i = 0; i < 3; ++i) {
                double e[3] = {0, 0, 0}, p[3];
                e[i] = 1.0;
                tb__collision_shape_support(shape, pose, e, p);
                assert_near(high[i], p[i], 1e-12);
                e[i] = -1.0;
                tb__collision_shape_support(shape, pose, e, p);
                assert_near(low[i], p[i], 1e-12);
            }
            free(shape);
        }
    }
}

/* The hull of a cube's corners with points inside and on its faces is the 8 corners; points
 * on a sphere are all on their hull; a flat set is refused. */
static void test_convex_hull_keeps_exactly_the_extreme_points(void **state)
{
    (void)state;
    uint64_t rng = 5;
    enum { N = 208 };
    double points[3 * N];
    for (int c = 0; c < 8; ++c) {
        for (int k = 0; k < 3; ++k) {
            points[3 * c + k] = c >> k & 1 ? 1.0 : -1.0;
        }
    }
    for (int i = 8; i < N; ++i) {
        for (int k = 0; k < 3; ++k) {
            points[3 * i + k] = test_uniform(&rng, -1, 1);
        }
        if (i % 2 == 0) {
            points[3 * i + i % 3] = 1.0; /* on a face */
        }
    }
    unsigned char on_hull[N];
    char detail[256];
    assert_int_equal(tb__convex_hull(points, N, on_hull, detail), TB_STATUS_OK);
    for (int i = 0; i < N; ++i) {
        assert_int_equal(on_hull[i], i < 8);
    }
    for (int i = 0; i < N; ++i) { /* on the unit sphere */
        double q[4];
        test_random_quaternion(&rng, q);
        tb__v3_set(points + 3 * i, q[1], q[2], q[3]);
        const double r = tb__v3_norm(points + 3 * i);
        tb__v3_set(points + 3 * i, q[1] / r, q[2] / r, q[3] / r);
    }
    assert_int_equal(tb__convex_hull(points, N, on_hull, detail), TB_STATUS_OK);
    for (int i = 0; i < N; ++i) {
        assert_int_equal(on_hull[i], 1);
    }
    for (int i = 0; i < N; ++i) {
        points[3 * i + 2] = 0.5; /* all in the plane z = 0.5 */
    }
    assert_int_equal(tb__convex_hull(points, N, on_hull, detail), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(detail, "all in one plane"));
}

/* --- the scene's shapes and the contact-pairs hook -------------------------------------- */

static tb_scene *scene_of_shapes(uint64_t *rng, size_t count, double spread)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    for (size_t i = 0; i < count; ++i) {
        tb_body_def body = tb_body_def_default();
        assert_int_equal(
            tb_mass_from_box(TB_MASS_GIVEN, 1.0, (double[]){0.3, 0.2, 0.1}, &body.mass, NULL),
            TB_STATUS_OK);
        body.mass.center[0] = 0.05; /* the shape origin off the centre of mass */
        tb__v3_set(body.position, test_uniform(rng, -spread, spread),
                   test_uniform(rng, -spread, spread), test_uniform(rng, 0, 0.3 * spread));
        test_random_quaternion(rng, body.orientation);
        assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
        tb_shape s = tb_shape_default();
        s.type = (tb_shape_type)(TB_SHAPE_SPHERE + i % 5);
        s.radius = 0.1;
        s.length = 0.2;
        tb__v3_set(s.size, 0.3, 0.2, 0.1);
        tb__v3_set(s.semi_axes, 0.15, 0.1, 0.05);
        if (i % 7 != 3) { /* some bodies have no shape */
            assert_int_equal(tb_scene_set_body_shape(scene, i, &s), TB_STATUS_OK);
        }
    }
    return scene;
}

/* Bit for bit: the normal and the points in use. */
static void same_manifold(const tb__contact_manifold *a, const tb__contact_manifold *b)
{
    assert_int_equal(a->count, b->count);
    assert_memory_equal(a->normal, b->normal, sizeof a->normal);
    assert_memory_equal(a->points, b->points, (size_t)a->count * sizeof a->points[0]);
}

/* The hook gives exactly the touching pairs the narrow phase finds on all N (N - 1) / 2
 * pairs, with the same manifolds bit for bit, in any batch size, and the same order on a
 * second pass. */
static void test_contact_pairs_are_the_narrow_phase_on_every_pair(void **state)
{
    (void)state;
    uint64_t rng = 31;
    enum { N = 150 };
    tb_scene *scene = scene_of_shapes(&rng, N, 1.5);
    const double *y = tb_scene_states(scene);
    tb__contact_pairs *pairs = NULL;
    char detail[256];
    const double margin = 0.02;
    assert_int_equal(tb__contact_pairs_create(scene, NULL, N, margin, &pairs, detail),
                     TB_STATUS_OK);
    static tb__pair_contact found[N * N / 2], again[N * N / 2];
    size_t count[2] = {0, 0};
    for (int pass = 0; pass < 2; ++pass) {
        tb__contact_pairs_begin(pairs, scene, tb_scene_time(scene), y);
        size_t n;
        tb__pair_contact *out = pass == 0 ? found : again;
        while ((n = tb__contact_pairs_next(pairs, scene, y, out + count[pass],
                                           pass == 0 ? 3 : 1000)) > 0) {
            count[pass] += n;
        }
    }
    assert_int_equal(count[0], count[1]);
    for (size_t k = 0; k < count[0]; ++k) {
        assert_true(found[k].body_a == again[k].body_a && found[k].body_b == again[k].body_b);
        same_manifold(&found[k].manifold, &again[k].manifold);
    }
    size_t expected = 0;
    for (size_t a = 0; a < N; ++a) {
        for (size_t b = a + 1; b < N; ++b) {
            const tb__collision_shape *sa = tb__scene_body_collision_shape(scene, a);
            const tb__collision_shape *sb = tb__scene_body_collision_shape(scene, b);
            double pa[7], pb[7];
            tb__contact_manifold m;
            if (sa == NULL || sb == NULL) {
                continue;
            }
            tb__shape_pose(scene, tb_scene_time(scene), y, a, pa);
            tb__shape_pose(scene, tb_scene_time(scene), y, b, pb);
            if (tb__collide(sa, pa, sb, pb, margin, &m) == 0) {
                continue;
            }
            ++expected;
            size_t k = 0;
            while (k < count[0] && !(found[k].body_a == a && found[k].body_b == b)) {
                ++k;
            }
            assert_true(k < count[0]);
            same_manifold(&found[k].manifold, &m);
        }
    }
    assert_int_equal(count[0], expected);
    assert_true(expected > 20);
    tb__contact_pairs_destroy(pairs);
    tb_scene_destroy(scene);
}

/* A shape's pose follows the body: the shape frame, not the principal frame, and the shape
 * origin, not the centre of mass. */
static void test_shape_pose_is_the_body_shape_pose(void **state)
{
    (void)state;
    uint64_t rng = 8;
    tb_scene *scene = scene_of_shapes(&rng, 4, 1.0);
    for (size_t id = 0; id < 4; ++id) {
        double pose[7], position[3], orientation[4];
        tb__shape_pose(scene, tb_scene_time(scene), tb_scene_states(scene), id, pose);
        assert_int_equal(
            tb_scene_body_shape_pose(scene, tb_scene_states(scene), id, position, orientation),
            TB_STATUS_OK);
        for (int k = 0; k < 3; ++k) {
            assert_near(pose[k], position[k], EXACT);
        }
        for (int k = 0; k < 4; ++k) {
            assert_near(pose[3 + k], orientation[k], EXACT);
        }
    }
    tb_scene_destroy(scene);
}

static void refused(tb_scene *scene, size_t id, const tb_shape *s, tb_status status,
                    const char *words)
{
    tb_shape_type before, after;
    assert_int_equal(tb_scene_body_shape_type(scene, 0, &before), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_shape(scene, id, s), status);
    if (strstr(tb_scene_detail(scene), words) == NULL) {
        fail_msg("detail \"%s\" lacks \"%s\"", tb_scene_detail(scene), words);
    }
    assert_int_equal(tb_scene_body_shape_type(scene, 0, &after), TB_STATUS_OK);
    assert_int_equal(after, before); /* nothing changed */
}

static void test_bad_shapes_are_refused_naming_the_field(void **state)
{
    (void)state;
    uint64_t rng = 1;
    tb_scene *scene = scene_of_shapes(&rng, 1, 1.0);
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_SPHERE;
    s.radius = -1.0;
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "radius: must be > 0");
    s.radius = NAN;
    refused(scene, 0, &s, TB_STATUS_NOT_FINITE, "radius: must be finite");
    s.radius = 1e101;
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "<= 1e100 m");
    s.radius = 1.0;
    refused(scene, 5, &s, TB_STATUS_OUT_OF_RANGE, "id");
    s.type = TB_SHAPE_BOX;
    tb__v3_set(s.size, 1, 0, 1);
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "size[1]: must be > 0");
    s.type = TB_SHAPE_CAPSULE;
    s.length = INFINITY;
    refused(scene, 0, &s, TB_STATUS_NOT_FINITE, "length");
    s.type = TB_SHAPE_CONVEX;
    refused(scene, 0, &s, TB_STATUS_NULL_POINTER, "vertices is NULL");
    const double flat[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0, 0.5, 0.5, 0};
    s.vertices = flat;
    s.vertex_count = 3;
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "vertex_count");
    s.vertex_count = 5;
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "all in one plane");
    const double nan_vertex[] = {0, 0, 0, 1, 0, 0, 0, NAN, 0, 0, 0, 1};
    s.vertices = nan_vertex;
    s.vertex_count = 4;
    refused(scene, 0, &s, TB_STATUS_NOT_FINITE, "vertices[2][1]");
    s.type = TB_SHAPE_POINTS;
    s.vertices = flat;
    s.vertex_count = 2;
    s.radii = (const double[]){0.1, -0.1};
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "radii[1]");
    s.type = (tb_shape_type)42;
    refused(scene, 0, &s, TB_STATUS_INVALID_ARGUMENT, "type: 42");
    /* NULL removes the shape */
    tb_shape_type type;
    assert_int_equal(tb_scene_set_body_shape(scene, 0, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_shape_type(scene, 0, &type), TB_STATUS_OK);
    assert_int_equal(type, TB_SHAPE_NONE);
    double low[3], high[3];
    assert_int_equal(tb_scene_body_shape_bounds(scene, tb_scene_states(scene), 0, low, high),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "has no shape"));
    char detail[256];
    tb__contact_pairs *pairs = NULL;
    assert_int_equal(
        tb__contact_pairs_create(scene, (const size_t[]){0, 0}, 2, 0.0, &pairs, detail),
        TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(detail, "listed twice"));
    assert_int_equal(tb__contact_pairs_create(scene, NULL, 0, NAN, &pairs, detail),
                     TB_STATUS_NOT_FINITE);
    assert_null(pairs);
    tb_scene_destroy(scene);
}

/* The scene file's shapes become collision shapes: the example scenes load with theirs. */
static void test_scene_file_shapes_collide(void **state)
{
    (void)state;
    const char *text =
        "{\"bodies\": ["
        "{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1},"
        "{\"name\": \"die\", \"shape\": {\"type\": \"box\", \"size\": [0.05, 0.05, 0.05]},"
        " \"density\": 1000, \"position\": [0.12, 0, 0]},"
        "{\"name\": \"tet\", \"shape\": {\"type\": \"mesh\", \"vertices\": [[0,0,0],[1,0,0],"
        "[0,1,0],[0,0,1]], \"triangles\": [[0,2,1],[0,1,3],[0,3,2],[1,2,3]]}, \"mass\": 1,"
        " \"position\": [5, 0, 0]},"
        "{\"name\": \"dumbbell\", \"shape\": {\"type\": \"points\", \"points\": ["
        "{\"position\": [0, 0, 0], \"mass\": 1}, {\"position\": [1, 0, 0], \"mass\": 1},"
        "{\"position\": [0, 1, 0], \"mass\": 1}]}, \"position\": [9, 0, 0]},"
        "{\"name\": \"plain\", \"mass\": 1, \"inertia\": [1, 1, 1]}]}";
    tb_scene *scene = NULL;
    tb_error error;
    tb_run_def run;
    tb_status status = tb_scene_load_string(text, "inline", NULL, &scene, &run, &error);
    if (status != TB_STATUS_OK) {
        fail_msg("%s", error.message);
    }
    const tb_shape_type expected[] = {TB_SHAPE_SPHERE, TB_SHAPE_BOX, TB_SHAPE_CONVEX,
                                      TB_SHAPE_POINTS, TB_SHAPE_NONE};
    for (size_t id = 0; id < 5; ++id) {
        tb_shape_type type;
        assert_int_equal(tb_scene_body_shape_type(scene, id, &type), TB_STATUS_OK);
        assert_int_equal(type, expected[id]);
    }
    /* ball (r 0.1 at 0) and die (half 0.025 at 0.12): 5 mm deep */
    const double *y = tb_scene_states(scene);
    double pa[7], pb[7];
    tb__shape_pose(scene, tb_scene_time(scene), y, 0, pa);
    tb__shape_pose(scene, tb_scene_time(scene), y, 1, pb);
    tb__contact_manifold m;
    assert_int_equal(tb__collide(tb__scene_body_collision_shape(scene, 0), pa,
                                 tb__scene_body_collision_shape(scene, 1), pb, 0.0, &m),
                     1);
    assert_near(m.points[0].depth, 0.005, EXACT);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_box_on_a_plane_touches_at_its_lowest_corners),
        cmocka_unit_test(test_capsules_and_cylinders_rest_on_a_plane_along_their_length),
        cmocka_unit_test(test_every_shape_on_a_plane_is_as_deep_as_its_lowest_point),
        cmocka_unit_test(test_bounds_are_the_support_points_along_the_axes),
        cmocka_unit_test(test_convex_hull_keeps_exactly_the_extreme_points),
        cmocka_unit_test(test_contact_pairs_are_the_narrow_phase_on_every_pair),
        cmocka_unit_test(test_shape_pose_is_the_body_shape_pose),
        cmocka_unit_test(test_bad_shapes_are_refused_naming_the_field),
        cmocka_unit_test(test_scene_file_shapes_collide),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
