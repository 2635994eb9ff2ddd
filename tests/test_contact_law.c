/* The compliant normal contact law against what mechanics says: a body hitting the ground leaves
 * at e times its approach speed whatever that speed, energy never grows through a contact with
 * e <= 1, and the die of the issue sinks no deeper than its target. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

/* A 1 kg ball of radius 0.1 m, one contact point at its centre (support 1), its lowest point
 * `gap` above the level ground plane, moving down at `speed`; with gravity or without. */
static tb_scene *ball_scene(const tb_ground_def *ground, double gap, double speed, bool gravity)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    def.position[2] = 0.1 + gap;
    def.velocity[2] = -speed;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    const tb_contact_point point = {{0.0, 0.0, 0.0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1), TB_STATUS_OK);
    if (gravity) {
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_ground(scene, ground), TB_STATUS_OK);
    return scene;
}

static tb_integrator *integrator_for(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (tb_method_is_adaptive(method)) {
        def.rtol = 1e-8;
    }
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    return integrator;
}

/* Without gravity the ball meets the plane at `speed` and, once the contact has let go, flies
 * off at a constant speed: the restitution it met. */
static double measured_restitution(double e, double speed, tb_method method)
{
    tb_ground_def ground = tb_ground_def_default();
    ground.restitution = e;
    tb_scene *scene = ball_scene(&ground, 0.01, speed, false);
    tb_integrator *integrator = integrator_for(scene, method);
    /* 1 cm to fall, a contact of at most pi / omega (0.03 s at the softest setting), then free */
    assert_int_equal(tb_integrator_advance(integrator, 0.01 / speed + 0.25), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double height = y[2] - 0.1;
    const double rebound = y[TB_STATE_P + 2] / 1.0;
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    assert_true(height > 0.0); /* it left the plane */
    return rebound / speed;
}

/* The restitution the user asks for is the one the ball meets, at 0.5 and 5 m/s alike (the
 * linear law's e does not depend on the speed). CVODE at rtol 1e-8 integrates the law closely
 * enough to check the closed form e(zeta) and its inversion: 1e-4 relative, against the 2.7e-6
 * measured (a wrong e(zeta), a clamp that pulls or a speed-dependent law are off by percents). */
static void test_a_ball_leaves_the_ground_at_e_times_its_approach_speed(void **state)
{
    (void)state;
    const double restitutions[] = {0.2, 0.5, 0.8, 1.0}, speeds[] = {0.5, 5.0};
    const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 3; ++m) {
        for (size_t i = 0; i < 4; ++i) {
            for (size_t k = 0; k < 2; ++k) {
                const double e = measured_restitution(restitutions[i], speeds[k], methods[m]);
                print_message("%-11s e = %.1f at %.1f m/s: leaves at %.5f (off by %.2e)\n",
                              tb_method_name(methods[m]), restitutions[i], speeds[k], e,
                              e / restitutions[i] - 1.0);
                if (tb_method_is_adaptive(methods[m])) {
                    assert_near(e / restitutions[i], 1.0, 1e-4);
                }
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_ball_leaves_the_ground_at_e_times_its_approach_speed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
