/* A column of boxes at rest, against statics: each contact carries the weight of the boxes above
 * it, and the contact law is a linear spring sized so that one body's weight sinks it by
 * `penetration` (docs/effects.md: on the ground k = M g / (support penetration) per corner, four
 * corners carrying; between bodies k = M_min g / (points penetration) per manifold point, the
 * four points of a face on a face). So the bottom of a column of n equal boxes sinks
 * n penetrations into the floor and box l + 1 sinks n - 1 - l penetrations into box l: the
 * sinking bench_peer_contact reports for its pile (docs/accuracy.md). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>

#define HEIGHT 8
#define EDGE 0.1           /* m */
#define PENETRATION 8e-7   /* m, the default of both contacts */
#define SETTLE_SECONDS 0.1 /* the column rings at a few hundred rad/s, damped by e = 0.3 */

/* HEIGHT cubes of 0.5 kg stacked exactly touching, the lowest on the floor, under gravity. */
static tb_scene *column(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    const double size[3] = {EDGE, EDGE, EDGE};
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    shape.size[0] = shape.size[1] = shape.size[2] = EDGE;
    tb_contact_point corners[8];
    size_t count = 0;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    for (size_t i = 0; i < HEIGHT; ++i) {
        tb_body_def body = tb_body_def_default();
        assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 0.5, size, &body.mass, NULL),
                         TB_STATUS_OK);
        body.position[2] = EDGE * (0.5 + (double)i);
        assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_body_shape(scene, i, &shape), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, i, corners, count, 4), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    tb_contact_def contact = tb_contact_def_default();
    assert_true(ground.penetration == PENETRATION && contact.penetration == PENETRATION);
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

/* Settles the column under method and checks every contact's sinking against statics, to 1%
 * of a penetration (what is left of the ringing after 0.1 s is far below that: the slowest mode
 * decays at about zeta omega / HEIGHT, some 60 per second) and that the column stays upright
 * (its boxes within 1e-9 m of the axis: nothing pushes sideways). */
static void check_column(tb_method method)
{
    tb_scene *scene = column();
    tb_integrator_def def = test_integrator_def(method, 0.0, 1e-6); /* dt 0: the default step */
    def.max_steps = 1000000;
    tb_integrator *integrator = test_integrator(scene, &def);
    assert_int_equal(tb_integrator_advance(integrator, SETTLE_SECONDS), TB_STATUS_OK);
    double below_top = 0.0; /* the floor */
    for (size_t i = 0; i < HEIGHT; ++i) {
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, i, &s), TB_STATUS_OK);
        const double depth = below_top - (s.x[2] - 0.5 * EDGE);
        const double expected = (double)(HEIGHT - i) * PENETRATION;
        print_message("%s: box %zu sinks %.4g um (statics %.4g)\n", tb_method_name(method), i,
                      1e6 * depth, 1e6 * expected);
        assert_true(fabs(depth - expected) <= 0.01 * PENETRATION);
        assert_true(fabs(s.x[0]) <= 1e-9 && fabs(s.x[1]) <= 1e-9);
        below_top = s.x[2] + 0.5 * EDGE;
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_a_column_of_boxes_sinks_as_statics_says_under_rk4(void **state)
{
    (void)state;
    check_column(TB_METHOD_RK4);
}

static void test_a_column_of_boxes_sinks_as_statics_says_under_cvode_adams(void **state)
{
    (void)state;
    check_column(TB_METHOD_CVODE_ADAMS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_column_of_boxes_sinks_as_statics_says_under_rk4),
        cmocka_unit_test(test_a_column_of_boxes_sinks_as_statics_says_under_cvode_adams),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
