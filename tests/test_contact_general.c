/* The shapes without closed forms (cylinder, convex hull, points) resting on a box: the part
 * of their base that presses on the box's face is a region (a hull's face, the octagon of a
 * cylinder's 8 rim points, the polygon of a point set's lowest balls), and the manifold is the
 * 4-point rule that integrates a depth linear over it: its points' mean depth is the region's
 * mean depth and their centroid and second moments (each point of weight 1/4) are the region's,
 * so the force and torque are those of the face pressed by its depth. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "geometry.h"
#include "near.h"
#include "contact/narrow_phase.h"
#include "math/tb_math.h"

#include <stdlib.h>

#define EXACT 1e-12
static const double z_axis[3] = {0, 0, 1};

/* Centroid c (x, y) and second moments per weight M = (xx, xy, yy) of the manifold's points,
 * each of weight 1 / count. */
static void rule_moments(const tb__contact_manifold *m, double c[2], double M[3])
{
    c[0] = c[1] = M[0] = M[1] = M[2] = 0.0;
    for (int k = 0; k < m->count; ++k) {
        c[0] += m->points[k].position[0] / m->count;
        c[1] += m->points[k].position[1] / m->count;
    }
    for (int k = 0; k < m->count; ++k) {
        const double x = m->points[k].position[0] - c[0], y = m->points[k].position[1] - c[1];
        M[0] += x * x / m->count;
        M[1] += x * y / m->count;
        M[2] += y * y / m->count;
    }
}

/* The manifold's points all depth deep, centroid (cx, cy), second moments (xx, xy, yy). */
static void assert_pressed_region(const tb__contact_manifold *m, double depth, double cx, double cy,
                                  const double M[3])
{
    assert_int_equal(m->count, 4);
    double c[2], got[3];
    rule_moments(m, c, got);
    for (int k = 0; k < 4; ++k) {
        assert_near(m->points[k].depth, depth, EXACT);
    }
    assert_near(c[0], cx, EXACT);
    assert_near(c[1], cy, EXACT);
    for (int i = 0; i < 3; ++i) {
        assert_near(got[i], M[i], EXACT);
    }
}

/* A 0.4 m cube given as the hull of its 8 corners, sunk 1 mm into a slab and turned about the
 * vertical: its whole bottom face presses, 1 mm deep, centred under the cube, with a square's
 * second moments (side^2 / 12 along every axis, whatever the turn); either order, the same
 * points. */
static void test_a_hull_cube_on_a_box_presses_its_whole_face(void **state)
{
    (void)state;
    double corners[24];
    for (int c = 0; c < 8; ++c) {
        for (int k = 0; k < 3; ++k) {
            corners[3 * c + k] = c >> k & 1 ? 0.2 : -0.2;
        }
    }
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CONVEX;
    s.vertices = corners;
    s.vertex_count = 8;
    tb__collision_shape *hull = test_shape(&s), *slab = test_box(3, 3, 0.2);
    double ps[7], pc[7];
    test_pose(ps, 0, 0, -0.1, z_axis, 0.0);
    test_pose(pc, 0.3, 0.1, 0.2 - 1e-3, z_axis, 0.6);
    tb__contact_manifold m, swapped;
    assert_int_equal(tb__collide(slab, ps, hull, pc, 0.0, &m), 4);
    assert_int_equal(tb__collide(hull, pc, slab, ps, 0.0, &swapped), 4);
    assert_near(m.normal[2], 1.0, 1e-9);
    assert_near(swapped.normal[2], -1.0, 1e-9);
    const double square[3] = {0.4 * 0.4 / 12.0, 0.0, 0.4 * 0.4 / 12.0};
    assert_pressed_region(&m, 1e-3, 0.3, 0.1, square);
    assert_pressed_region(&swapped, 1e-3, 0.3, 0.1, square);
    free(hull);
    free(slab);
}

/* A cylinder (radius 0.1 m) standing on a box, sunk 1 mm: its end presses as the regular
 * octagon of its rim points, 1 mm deep, centred on its axis, with the octagon's second moments
 * R^2 (2 + cos 45 deg) / 12 along every axis (half the polar moment per area of a regular n-gon
 * of circumradius R, R^2 (2 + cos(2 pi / n)) / 6). */
static void test_a_cylinder_standing_on_a_box_presses_its_end(void **state)
{
    (void)state;
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CYLINDER;
    s.radius = 0.1;
    s.length = 0.3;
    tb__collision_shape *cylinder = test_shape(&s), *slab = test_box(3, 3, 0.2);
    double ps[7], pc[7];
    test_pose(ps, 0, 0, -0.1, z_axis, 0.0);
    test_pose(pc, 0.5, -0.4, 0.15 - 1e-3, z_axis, 1.1);
    tb__contact_manifold m;
    assert_int_equal(tb__collide(cylinder, pc, slab, ps, 0.0, &m), 4);
    assert_near(m.normal[2], -1.0, 1e-9);
    const double per_axis = 0.01 * (2.0 + sqrt(0.5)) / 12.0;
    assert_pressed_region(&m, 1e-3, 0.5, -0.4, (const double[]){per_axis, 0.0, per_axis});
    free(cylinder);
    free(slab);
}

/* Three balls (radius 0.05 m) of a points shape 2 mm into the box press as the triangle of
 * their lowest points: 2 mm deep, its centroid, its second moments sum (p_i - c)(p_i - c)^T / 12.
 * With the third ball 1 cm above the box (within a 2 cm margin) only the part of the triangle
 * below the box's face presses: every point inside the triangle, none deeper than 2 mm. */
static void test_a_points_shape_on_a_box_presses_the_triangle_of_its_balls(void **state)
{
    (void)state;
    const double flat[] = {0, 0, 0, 0.3, 0, 0, 0, 0.3, 0},
                 lifted[] = {0, 0, 0, 0.3, 0, 0, 0, 0.3, 0.012};
    const double radii[] = {0.05, 0.05, 0.05};
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_POINTS;
    s.vertex_count = 3;
    s.radii = radii;
    s.vertices = flat;
    tb__collision_shape *balls = test_shape(&s), *slab = test_box(3, 3, 0.2);
    s.vertices = lifted;
    tb__collision_shape *tilted = test_shape(&s);
    double ps[7], pb[7];
    test_pose(ps, 0, 0, -0.1, z_axis, 0.0);
    tb__contact_manifold m;
    test_pose(pb, 0.1, 0.1, 0.05 - 2e-3, z_axis, 0.0);
    assert_int_equal(tb__collide(slab, ps, balls, pb, 0.02, &m), 4);
    const double x[3] = {0.1, 0.4, 0.1}, y[3] = {0.1, 0.1, 0.4}; /* lowest points */
    const double cx = (x[0] + x[1] + x[2]) / 3.0, cy = (y[0] + y[1] + y[2]) / 3.0;
    double M[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; ++k) {
        M[0] += (x[k] - cx) * (x[k] - cx) / 12.0;
        M[1] += (x[k] - cx) * (y[k] - cy) / 12.0;
        M[2] += (y[k] - cy) * (y[k] - cy) / 12.0;
    }
    assert_pressed_region(&m, 2e-3, cx, cy, M);
    assert_int_equal(tb__collide(slab, ps, tilted, pb, 0.02, &m), 4);
    for (int k = 0; k < 4; ++k) {
        const double *p = m.points[k].position;
        assert_true(m.points[k].depth <= 2e-3 + EXACT);
        assert_true(p[0] >= 0.1 - EXACT && p[1] >= 0.1 - EXACT && p[0] + p[1] <= 0.5 + EXACT);
    }
    free(balls);
    free(tilted);
    free(slab);
}

/* A hull cube (0.2 m) meeting a slab or another hull cube at random tilts up to 0.02 rad, from
 * 1 mm apart to 1 mm in, so that the part of its face that presses ranges from nothing through
 * slivers to the whole face: every point of the manifold lies within both shapes' bounds grown
 * by the margin (the rule's points are inside the pressed region), and every depth is finite and
 * below 2 mm plus the tilt's drop across the cube (0.2 m times the tilt). MPR's normal, up to 10
 * degrees off between two hull cubes, gave single points 18 and 39 mm deep (trials 6193, 6527)
 * before a face's normal replaced it wherever one overlaps less. */
static void test_pressed_slivers_keep_their_points_inside(void **state)
{
    (void)state;
    double corners[24];
    for (int c = 0; c < 8; ++c) {
        for (int k = 0; k < 3; ++k) {
            corners[3 * c + k] = c >> k & 1 ? 0.1 : -0.1;
        }
    }
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_CONVEX;
    s.vertices = corners;
    s.vertex_count = 8;
    tb__collision_shape *hull = test_shape(&s), *lower = test_shape(&s);
    tb__collision_shape *slab = test_box(3, 3, 0.2);
    uint64_t seed = 0x5eed5eedULL;
    int pressed = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double axis[3] = {test_uniform(&seed, -1, 1), test_uniform(&seed, -1, 1), 0.0};
        const double tilt = test_uniform(&seed, 0.0, 0.02), sink = test_uniform(&seed, -1e-3, 1e-3);
        const bool on_slab = trial % 2 == 0;
        double pl[7], pc[7];
        test_pose(pl, 0, 0, on_slab ? -0.1 : 0.0, z_axis, on_slab ? 0.0 : 0.3);
        test_pose(pc, test_uniform(&seed, -0.05, 0.05), test_uniform(&seed, -0.05, 0.05),
                  (on_slab ? 0.0 : 0.1) + 0.1 * cos(tilt) + 0.1 * sin(tilt) - sink, axis, tilt);
        tb__contact_manifold m;
        const int count = tb__collide(on_slab ? slab : lower, pl, hull, pc, 1e-3, &m);
        assert_true(count >= 0 && count <= TB__MANIFOLD_POINTS);
        for (int k = 0; k < count; ++k) {
            const double *p = m.points[k].position;
            assert_true(isfinite(m.points[k].depth) && m.points[k].depth < 2e-3 + 0.2 * tilt);
            assert_true(fabs(p[0] - pc[0]) < 0.15 && fabs(p[1] - pc[1]) < 0.15 &&
                        fabs(p[2] - (on_slab ? 0.0 : 0.1)) < 0.01);
            pressed += m.points[k].depth > 0.0;
        }
    }
    print_message("points pressed in over 20 000 trials: %d\n", pressed);
    assert_true(pressed > 0);
    free(hull);
    free(lower);
    free(slab);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_hull_cube_on_a_box_presses_its_whole_face),
        cmocka_unit_test(test_a_cylinder_standing_on_a_box_presses_its_end),
        cmocka_unit_test(test_a_points_shape_on_a_box_presses_the_triangle_of_its_balls),
        cmocka_unit_test(test_pressed_slivers_keep_their_points_inside),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
