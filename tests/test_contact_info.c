/* The contact read-outs (include/tumble/contact_info.h): what a scene's contact effects and
 * ground planes were given comes back, and the pairs touching at a state have the depth their
 * geometry sets. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>

/* A 1 kg ball of radius r at (x, 0, z); no shape when r is 0. */
static size_t add_ball(tb_scene *scene, double r, double x, double z)
{
    tb_body_def def = tb_body_def_default();
    tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, r > 0 ? r : 0.1, &def.mass, NULL);
    def.position[0] = x;
    def.position[2] = z;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    if (r > 0) {
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_SPHERE;
        shape.radius = r;
        assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    }
    return id;
}

static void test_contact_effects_read_back_what_they_were_given(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    add_ball(scene, 0.1, 0.0, 1.0);
    add_ball(scene, 0.1, 0.15, 1.0); /* centres 0.15 apart: 0.05 m of overlap */
    add_ball(scene, 0.1, 5.0, 1.0);  /* far from the others */
    tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
    /* every body so far (0, 1, 2); bodies added later are not in it */
    tb_contact_def every = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &every), TB_STATUS_OK);
    add_ball(scene, 0.1, 10.0, 1.0); /* 3: far from 2 (a listed body needs a shape) */
    tb_contact_def def = tb_contact_def_default();
    def.restitution = 0.7; /* above 0.062, so the law meets it (to 1e-7) */
    def.static_friction = 0.45;
    def.kinetic_friction = 0.25;
    def.penetration = 2e-5;
    const size_t listed[2] = {2, 3}; /* shares body 2 with the first, no pair (refused if it did) */
    def.bodies = listed;
    def.body_count = 2;
    assert_int_equal(tb_scene_add_contact(scene, &def), TB_STATUS_OK);
    assert_int_equal(tb_scene_contact_count(scene), 2);
    assert_int_equal(tb_scene_ground_count(scene), 0);

    tb_contact_info info;
    assert_int_equal(tb_scene_get_contact(scene, 0, &info), TB_STATUS_OK);
    assert_int_equal(info.effect, 1); /* after gravity */
    assert_true(info.every_body);
    assert_int_equal(info.body_count, 3);
    assert_int_equal(tb_scene_get_contact(scene, 1, &info), TB_STATUS_OK);
    assert_int_equal(info.effect, 2);
    assert_false(info.every_body);
    assert_int_equal(info.body_count, 2);
    assert_int_equal(info.bodies[0], 2);
    assert_int_equal(info.bodies[1], 3);
    assert_true(fabs(info.restitution - 0.7) < 1e-6);
    assert_true(info.static_friction == 0.45 && info.kinetic_friction == 0.25);
    assert_true(fabs(info.penetration - 2e-5) < 1e-18); /* g / (sqrt(g / p))^2 */
    assert_int_equal(tb_scene_get_contact(scene, 2, &info), TB_STATUS_OUT_OF_RANGE);

    /* Each effect finds the overlapping pair (0, 1) only where it covers both: the every-body
     * effect does; the listed one (bodies 2 and 3, 5 m apart) has no pair. */
    tb_contact_touch touch[4];
    size_t count = 0;
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), touch, 4, &count),
        TB_STATUS_OK);
    assert_int_equal(count, 1);
    assert_int_equal(touch[0].effect, 1);
    assert_int_equal(touch[0].body_a, 0);
    assert_int_equal(touch[0].body_b, 1);
    assert_true(fabs(touch[0].depth - 0.05) < 1e-12); /* 0.2 - 0.15 */
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), NULL, 0, &count),
        TB_STATUS_OK);
    assert_int_equal(count, 1); /* counted without room */
    tb_scene_destroy(scene);
}

/* A ball resting 1 mm into the ground: one point, 1 mm deep; a ball 1 mm above: none. */
static void test_ground_planes_read_back_and_touch_what_dips_in(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    tb_scene_create(&scene_def, &scene, NULL);
    add_ball(scene, 0.1, 0.0, 0.099);
    add_ball(scene, 0.1, 1.0, 0.101);
    for (size_t id = 0; id < 2; ++id) {
        tb_contact_point point;
        size_t points = 0;
        tb_contact_points_sphere(0.1, &point, 1, &points);
        assert_int_equal(tb_scene_set_contact_points(scene, id, &point, points, 1), TB_STATUS_OK);
    }
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-3; /* the start 1 mm deep is allowed (10 penetrations) */
    ground.restitution = 0.5;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_ground_info info;
    assert_int_equal(tb_scene_get_ground(scene, 0, &info), TB_STATUS_OK);
    assert_true(info.normal[2] == 1.0 && info.offset == 0.0 && info.penetration == 1e-3);
    assert_true(fabs(info.restitution - 0.5) < 1e-6);
    size_t points = 0;
    assert_int_equal(tb_scene_body_contact_point_count(scene, 1, &points), TB_STATUS_OK);
    assert_int_equal(points, 1);
    assert_int_equal(tb_scene_body_contact_point_count(scene, 2, &points), TB_STATUS_OUT_OF_RANGE);
    tb_contact_touch touch[2];
    size_t count = 0;
    tb_scene_contact_touching(scene, tb_scene_states_const(scene), touch, 2, &count);
    assert_int_equal(count, 1);
    assert_int_equal(touch[0].body_a, 0);
    assert_true(touch[0].body_b == TB_WORLD);
    assert_true(fabs(touch[0].depth - 1e-3) < 1e-12);
    assert_int_equal(touch[0].points, 1);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_contact_effects_read_back_what_they_were_given),
        cmocka_unit_test(test_ground_planes_read_back_and_touch_what_dips_in),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
