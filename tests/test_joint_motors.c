/* Joint motors (issue 21): a velocity motor spins a wheel up at its torque cap's constant
 * angular acceleration, then holds the speed; a position motor holds a lever against gravity
 * when its cap suffices and sags to where statics says when it does not. Tolerances are stated
 * with their reasons. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* A 6 kg wheel (a 1 x 1 x 0.2 m box: I = m (1 + 1) / 12 = 1 kg m^2 about its axis z) on a hinge
 * about z through its centre, at rest, its velocity motor asking speed under a cap of
 * max_torque. */
static tb_scene *wheel_scene(double speed, double max_torque, size_t *wheel)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {1.0, 1.0, 0.2}, x[3] = {0.0, 0.0, 0.0};
    *wheel = test_add_box(scene, 6.0, size, x);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = *wheel;
    def.motor = TB_MOTOR_VELOCITY;
    def.motor_speed = speed;
    def.motor_max_force = max_torque;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

static double spin(tb_scene *scene, size_t body)
{
    double omega[3];
    assert_int_equal(tb_scene_body_angular_velocity(scene, tb_scene_states(scene), body, omega),
                     TB_STATUS_OK);
    return omega[2];
}

/* Spin-up to 10 rad/s under a 2 N m cap: the motor asks 20/s times the speed error, more
 * than the cap gives (2 rad/s^2) until the error is 0.1 rad/s, so the speed is 2 t exactly
 * (a constant torque on a free rotation: every method integrates it to round-off) until
 * 4.95 s; then the error decays as 0.1 e^(-20 (t - 4.95)), below 1e-9 rad/s from 6 s. Checked
 * to 1e-9 rad/s before 4.9 s and from 6.5 s on to 8 s, for RK4 at 1/240 s and CVODE BDF at
 * rtol 1e-10 (its error on a constant acceleration is round-off too; the decay it tracks to
 * its tolerance, far below the bound). */
static void test_velocity_motor_spins_a_wheel_up_at_its_cap_then_holds_the_speed(void **state)
{
    (void)state;
    const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (int k = 0; k < 2; ++k) {
        size_t wheel = 0;
        tb_scene *scene = wheel_scene(10.0, 2.0, &wheel);
        tb_integrator *integrator =
            test_integrator_for(scene, methods[k], k == 0 ? 1.0 / 240.0 : 0.0, 1e-10);
        double ramp = 0.0, hold = 0.0;
        for (int frame = 1; frame <= 80; ++frame) {
            const double t = frame / 10.0;
            assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
            const double omega = spin(scene, wheel);
            if (t <= 4.9 + 1e-9) {
                ramp = fmax(ramp, fabs(omega - 2.0 * t));
            } else if (t >= 6.5 - 1e-9) {
                hold = fmax(hold, fabs(omega - 10.0));
            }
        }
        double f[3], tau[3];
        assert_int_equal(tb_scene_joint_reaction(scene, tb_scene_states(scene), 0, f, tau),
                         TB_STATUS_OK);
        print_message("wheel motor %s: spin-up error %.3g rad/s, hold error %.3g rad/s, torque "
                      "at speed %.3g N m\n",
                      tb_method_name(methods[k]), ramp, hold, tau[2]);
        assert_true(ramp <= 1e-9);
        assert_true(hold <= 1e-9);
        assert_true(fabs(tau[2]) <= 1e-6); /* at speed a free wheel needs no torque */
        /* the motor is no constraint: the wheel is on its hinge, whatever its speed */
        double position = 1.0, velocity = 1.0;
        assert_int_equal(
            tb_scene_joint_error(scene, tb_scene_states(scene), 0, &position, &velocity),
            TB_STATUS_OK);
        assert_true(position <= 1e-12 && velocity <= 1e-12);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* While spinning up, the motor's torque is its cap, read out as the joint's reaction torque
 * on the wheel about the axis: 2 N m. */
static void test_capped_motor_reads_out_its_cap(void **state)
{
    (void)state;
    size_t wheel = 0;
    tb_scene *scene = wheel_scene(10.0, 2.0, &wheel);
    double f[3], tau[3];
    assert_int_equal(tb_scene_joint_reaction(scene, tb_scene_states(scene), 0, f, tau),
                     TB_STATUS_OK);
    assert_true(fabs(tau[2] - 2.0) <= 1e-12);
    tb_scene_destroy(scene);
}

/* A 1 kg, 1 m rod hinged at one end about y, horizontal along +x at the start (its weight's
 * torque about the hinge m g L / 2 = 4.905 N m, turning it down: +angle about y), under gravity,
 * with a position motor toward target (rad from the start) capped at max_torque. */
static tb_scene *lever_scene(double theta, double target, double max_torque, size_t *rod)
{
    tb_scene *scene = test_empty_scene();
    const double c[3] = {0.5 * sin(theta), 0.0, -0.5 * cos(theta)};
    *rod = test_add_rod(scene, 1.0, 1.0, theta, c);
    const double g[3] = {0.0, 0.0, -TEST_G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = *rod;
    const double axis[3] = {0.0, 1.0, 0.0};
    memcpy(def.axis, axis, sizeof axis);
    def.motor = TB_MOTOR_POSITION;
    def.motor_target = target;
    def.motor_max_force = max_torque;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

/* Its angle below the horizontal. */
static double droop(tb_scene *scene, size_t rod)
{
    return 0.5 * TEST_PI - test_rod_angle(scene, tb_scene_states(scene), rod);
}

/* A cap of 10 N m holds the lever level: the motor's row asks zero acceleration at the
 * target, so the lever stays at rest there exactly (to 1e-12 rad over 2 s, RK4 at 1/240 s)
 * and the reaction torque about y is minus the weight's, -m g L / 2 (to 1e-9 N m). */
static void test_position_motor_holds_a_lever_when_its_cap_suffices(void **state)
{
    (void)state;
    size_t rod = 0;
    tb_scene *scene = lever_scene(0.5 * TEST_PI, 0.0, 10.0, &rod);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
    double f[3], tau[3];
    assert_int_equal(tb_scene_joint_reaction(scene, tb_scene_states(scene), 0, f, tau),
                     TB_STATUS_OK);
    print_message("lever held: droop %.3g rad, torque %.17g N m\n", droop(scene, rod), tau[1]);
    assert_true(fabs(droop(scene, rod)) <= 1e-12);
    assert_true(fabs(tau[1] + 0.5 * TEST_G) <= 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A cap of 3 N m cannot hold it (4.905 N m needed): statics puts the lever where the weight's
 * torque m g L / 2 cos(droop) equals the cap, droop* = acos(3 / 4.905) = 0.9128 rad. Started
 * there at rest (the motor still asking for level), it stays there: to 1e-9 rad over 2 s. Let
 * go from level, it swings down, the cap's constant torque against the weight, to the turning
 * point where their work balances, m g L / 2 sin(d) = 3 d (by bisection here), to 1e-5
 * rad: RK4 at 1/480 s (its energy error over the swing is far below), frames at 1 kHz, which
 * sample the turning point within (1 ms)^2 |d''| / 8 ~ 1e-6 rad. */
static void test_position_motor_sags_to_where_statics_says_when_its_cap_is_short(void **state)
{
    (void)state;
    const double cap = 3.0, weight = 0.5 * TEST_G, star = acos(cap / weight);
    size_t rod = 0;
    tb_scene *scene = lever_scene(0.5 * TEST_PI - star, -star, cap, &rod);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
    print_message("lever at statics: droop %.17g rad (statics %.17g)\n", droop(scene, rod), star);
    assert_true(fabs(droop(scene, rod) - star) <= 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);

    scene = lever_scene(0.5 * TEST_PI, 0.0, cap, &rod);
    integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 480.0, 0.0);
    double lo = 0.1, hi = TEST_PI; /* weight sin d - cap d: > 0 at lo, < 0 at hi */
    for (int k = 0; k < 200; ++k) {
        const double mid = 0.5 * (lo + hi);
        *(weight * sin(mid) - cap * mid > 0.0 ? &lo : &hi) = mid;
    }
    double deepest = 0.0;
    for (int frame = 1; frame <= 1500; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 1000.0), TB_STATUS_OK);
        deepest = fmax(deepest, droop(scene, rod));
    }
    print_message("lever let go: deepest %.17g rad (energy says %.17g)\n", deepest, lo);
    assert_true(deepest > star);
    assert_true(fabs(deepest - lo) <= 1e-5);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_velocity_motor_spins_a_wheel_up_at_its_cap_then_holds_the_speed),
        cmocka_unit_test(test_capped_motor_reads_out_its_cap),
        cmocka_unit_test(test_position_motor_holds_a_lever_when_its_cap_suffices),
        cmocka_unit_test(test_position_motor_sags_to_where_statics_says_when_its_cap_is_short),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
