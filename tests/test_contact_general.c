/* The shapes without closed forms (cylinder, convex hull, points) resting on a box: their base
 * comes from their own features met with the box in closed form, so a hull cube on a box
 * touches where the box-box closed form says, a cylinder standing on a box at 4 rim points,
 * three balls of a points shape at their three lowest points. */
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

/* A point of a among b's (within 1e-12 m). */
static bool has_point(const tb__contact_manifold *m, const double p[3], double depth)
{
    for (int k = 0; k < m->count; ++k) {
        const double *q = m->points[k].position;
        if (fabs(q[0] - p[0]) < EXACT && fabs(q[1] - p[1]) < EXACT && fabs(q[2] - p[2]) < EXACT &&
            fabs(m->points[k].depth - depth) < EXACT) {
            return true;
        }
    }
    return false;
}

/* A 0.4 m cube given as the hull of its 8 corners, sunk 1 mm into a slab and turned about the
 * vertical, against the same cube as a box: the same 4 points, 1 mm deep, either order. */
static void test_a_hull_cube_on_a_box_touches_where_a_box_does(void **state)
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
    tb__collision_shape *hull = test_shape(&s), *cube = test_box(0.4, 0.4, 0.4);
    tb__collision_shape *slab = test_box(3, 3, 0.2);
    double ps[7], pc[7];
    test_pose(ps, 0, 0, -0.1, z_axis, 0.0);
    test_pose(pc, 0.3, 0.1, 0.2 - 1e-3, z_axis, 0.6);
    tb__contact_manifold as_hull, as_box, swapped;
    assert_int_equal(tb__collide(slab, ps, hull, pc, 0.0, &as_hull), 4);
    assert_int_equal(tb__collide(slab, ps, cube, pc, 0.0, &as_box), 4);
    assert_int_equal(tb__collide(hull, pc, slab, ps, 0.0, &swapped), 4);
    assert_near(as_hull.normal[2], 1.0, 1e-9);
    assert_near(swapped.normal[2], -1.0, 1e-9);
    for (int k = 0; k < 4; ++k) {
        assert_true(has_point(&as_hull, as_box.points[k].position, as_box.points[k].depth));
        assert_true(has_point(&swapped, as_box.points[k].position, as_box.points[k].depth));
    }
    free(hull);
    free(cube);
    free(slab);
}

/* A cylinder (radius 0.1 m) standing on a box, sunk 1 mm: 4 rim points 0.1 m from its axis,
 * each 1 mm deep. */
static void test_a_cylinder_standing_on_a_box_rests_on_its_rim(void **state)
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
    for (int k = 0; k < 4; ++k) {
        assert_near(m.points[k].depth, 1e-3, EXACT);
        assert_near(hypot(m.points[k].position[0] - 0.5, m.points[k].position[1] + 0.4), 0.1,
                    EXACT);
    }
    free(cylinder);
    free(slab);
}

/* Three balls (radius 0.05 m) of a points shape, two of them 2 mm into the box and one 1 cm
 * above it: within a 2 cm margin three points, depths 2 mm, 2 mm and -1 cm. */
static void test_a_points_shape_on_a_box_rests_on_its_balls(void **state)
{
    (void)state;
    const double centres[] = {0, 0, 0, 0.3, 0, 0, 0, 0.3, 0.012};
    const double radii[] = {0.05, 0.05, 0.05};
    tb_shape s = tb_shape_default();
    s.type = TB_SHAPE_POINTS;
    s.vertices = centres;
    s.vertex_count = 3;
    s.radii = radii;
    tb__collision_shape *balls = test_shape(&s), *slab = test_box(3, 3, 0.2);
    double ps[7], pb[7];
    test_pose(ps, 0, 0, -0.1, z_axis, 0.0);
    test_pose(pb, 0.1, 0.1, 0.05 - 2e-3, z_axis, 0.0);
    tb__contact_manifold m;
    assert_int_equal(tb__collide(slab, ps, balls, pb, 0.02, &m), 3);
    double depths[3] = {m.points[0].depth, m.points[1].depth, m.points[2].depth};
    double sum = depths[0] + depths[1] + depths[2];
    assert_near(sum, 2e-3 + 2e-3 - 1e-2, EXACT);
    assert_near(fmax(fmax(depths[0], depths[1]), depths[2]), 2e-3, EXACT);
    free(balls);
    free(slab);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_hull_cube_on_a_box_touches_where_a_box_does),
        cmocka_unit_test(test_a_cylinder_standing_on_a_box_rests_on_its_rim),
        cmocka_unit_test(test_a_points_shape_on_a_box_rests_on_its_balls),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
