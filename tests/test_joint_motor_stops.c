/* A motor and limits on one joint (issue 21): a hinge's motor drives a door into its stop, a
 * slider's motor a block into its end of travel. The stop wins: the joint rests on it, the
 * motor pushing at its cap and the stop taking exactly that (statics), and the joint leaves the
 * stop when the motor is reversed. Checked against closed forms (a constant torque's uniform
 * acceleration, the velocity servo's exponential approach); tolerances stated with reasons. */
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

#define MOTOR_RATE 20.0 /* 1/s: the motor's servo rate (docs/joints.md, Motors) */

static const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};

static tb_integrator *integrator_for(tb_scene *scene, int k)
{
    return test_integrator_for(scene, methods[k], k == 0 ? 1.0 / 240.0 : 0.0, 1e-10);
}

static void advance(tb_integrator *integrator, double t)
{
    const tb_status status = tb_integrator_advance(integrator, t);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", tb_integrator_detail(integrator));
    }
    assert_int_equal(status, TB_STATUS_OK);
}

/* A 20 kg door (1 m wide, 5 cm thick, 2 m tall) at rest on a vertical hinge through its edge,
 * limits [0, 90 deg] (restitution 0), its velocity motor toward 1 rad/s under a 2 N m cap.
 * Gravity along the axis turns nothing. I about the hinge = m (w^2 + t^2) / 12 + m (w / 2)^2. */
#define DOOR_CAP 2.0
#define DOOR_OPEN (TEST_PI / 2.0)
static tb_scene *door_scene(size_t *door, double *inertia)
{
    tb_scene *scene = test_empty_scene();
    tb_joint_def def;
    *door = test_add_swinging_door(scene, 0.0, &def);
    *inertia = 20.0 * (1.0 + 0.05 * 0.05) / 12.0 + 20.0 * 0.25;
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    def.motor = TB_MOTOR_VELOCITY;
    def.motor_speed = 1.0;
    def.motor_max_force = DOOR_CAP;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

/* The door under its capped motor: the motor asks 20/s (1 - omega) I, more than the cap until
 * omega = 1 - 2 / (20 I) = 0.985 rad/s, and the door reaches its stop before (at 0.971 rad/s), so
 * the angle is alpha t^2 / 2, alpha = cap / I, until t1 = sqrt(pi / alpha) = 3.24 s: a constant
 * torque about a fixed axis, which RK4 integrates to round-off and CVODE (rtol 1e-10) to its
 * tolerance: bound 1e-8 rad. From then on it rests on the stop (restitution 0): at 90 deg to
 * the projection's 1e-12 rad, still (bound 1e-9 rad/s), the motor pushing at its cap, 2 N m,
 * and the stop pushing back -2 N m: statics about the axis, where nothing else acts (the
 * solve's round-off: bound 1e-12 of the cap); the joint's torque about z, their sum, is 0.
 * Reversed at 5 s (toward -1 rad/s), the motor pulls the door off at its cap: pi/2 - alpha
 * (t - 5)^2 / 2 to 1e-8 rad until 7 s, the stop's push 0. */
static void test_door_motor_rests_on_its_stop_at_its_cap_and_leaves_when_reversed(void **state)
{
    (void)state;
    for (int k = 0; k < 2; ++k) {
        size_t door = 0;
        double inertia = 0.0, q[3], f[3], tau[3];
        tb_scene *scene = door_scene(&door, &inertia);
        tb_integrator *integrator = integrator_for(scene, k);
        const double alpha = DOOR_CAP / inertia, t1 = sqrt(TEST_PI / alpha);
        double swing = 0.0, rest = 0.0, still = 0.0, back = 0.0;
        for (int frame = 1; frame <= 700; ++frame) {
            const double t = frame / 100.0;
            if (frame == 501) {
                assert_int_equal(
                    tb_scene_set_joint_motor(scene, 0, TB_MOTOR_VELOCITY, -1.0, DOOR_CAP),
                    TB_STATUS_OK);
            }
            advance(integrator, t);
            const double *y = tb_scene_states(scene);
            assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], &q[1], &q[2]), TB_STATUS_OK);
            double omega[3];
            assert_int_equal(tb_scene_body_angular_velocity(scene, y, door, omega), TB_STATUS_OK);
            if (t < t1 - 1e-9) {
                swing = fmax(swing, fabs(q[0] - 0.5 * alpha * t * t));
            } else if (t >= t1 + 0.1 && t <= 5.0 + 1e-9) {
                rest = fmax(rest, fabs(q[0] - DOOR_OPEN));
                still = fmax(still, fabs(omega[2]));
                assert_true(fabs(q[1] - DOOR_CAP) <= 1e-12 * DOOR_CAP);
                assert_true(fabs(q[2] + DOOR_CAP) <= 1e-12 * DOOR_CAP);
            } else if (t > 5.0) {
                back = fmax(back, fabs(q[0] - (DOOR_OPEN - 0.5 * alpha * (t - 5.0) * (t - 5.0))));
                assert_true(fabs(q[1] + DOOR_CAP) <= 1e-12 * DOOR_CAP && q[2] == 0.0);
            }
            if (frame == 500) {
                assert_int_equal(tb_scene_joint_reaction(scene, y, 0, f, tau), TB_STATUS_OK);
            }
        }
        print_message("door motor %s: swing error %.3g rad, rest error %.3g rad (speed %.3g "
                      "rad/s), torque about the axis at rest %.3g N m, back error %.3g rad\n",
                      tb_method_name(methods[k]), swing, rest, still, tau[2], back);
        assert_true(swing <= 1e-8);
        assert_true(rest <= 1e-12 && still <= 1e-9);
        assert_true(fabs(tau[2]) <= 1e-12 * DOOR_CAP);
        assert_true(back <= 1e-8);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A 2 kg block on a vertical slider, limits [-0.5, 0.3] m, its velocity motor toward +0.5 m/s
 * under a cap of max_force (N). */
static tb_scene *lift_scene(size_t *block, double max_force)
{
    tb_scene *scene = test_empty_scene();
    const double size[3] = {0.2, 0.2, 0.2}, x[3] = {0.0, 0.0, 0.0};
    *block = test_add_box(scene, 2.0, size, x);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_SLIDER;
    def.body_a = *block;
    def.has_limits = 1;
    def.limits[0] = -0.5;
    def.limits[1] = 0.3;
    def.motor = TB_MOTOR_VELOCITY;
    def.motor_speed = 0.5;
    def.motor_max_force = max_force;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

/* The lift with a 30 N cap (its weight is 19.62 N) rises into its upper stop (restitution 0)
 * and rests there: at 0.3 m to the projection's 1e-12 m, the motor at its cap, +30 N, the stop
 * pushing back -(30 - m g) = -10.38 N, the joint's force on the block (0, 0, m g): statics, to
 * 1e-12 of the cap (the solve's round-off). Reversed at 3 s toward -0.5 m/s, the motor needs
 * m (20/s (-0.5 - v) + g), -0.38 N at most, within its cap, so the block leaves the stop on the
 * servo's exponential: z = 0.3 - 0.5 s + (0.5 / 20) (1 - e^(-20 s)), s = t - 3, checked to
 * 1e-7 m until 4 s (RK4's error on e^(-20 s) at h 20 = 1/12: 3.3e-9 m measured; CVODE's at rtol
 * 1e-10 below it). */
static void test_slider_motor_holds_its_block_on_the_stop_and_lowers_it_when_reversed(void **state)
{
    (void)state;
    const double m = 2.0, cap = 30.0;
    for (int k = 0; k < 2; ++k) {
        size_t block = 0;
        tb_scene *scene = lift_scene(&block, cap);
        tb_integrator *integrator = integrator_for(scene, k);
        advance(integrator, 3.0);
        const double *y = tb_scene_states(scene);
        double q[3], f[3], tau[3];
        assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], &q[1], &q[2]), TB_STATUS_OK);
        assert_int_equal(tb_scene_joint_reaction(scene, y, 0, f, tau), TB_STATUS_OK);
        print_message("lift %s at its stop: travel %.17g m, motor %.17g N, stop %.17g N, "
                      "reaction (%.3g, %.3g, %.17g) N\n",
                      tb_method_name(methods[k]), q[0], q[1], q[2], f[0], f[1], f[2]);
        assert_true(fabs(q[0] - 0.3) <= 1e-12);
        assert_true(fabs(q[1] - cap) <= 1e-12 * cap);
        assert_true(fabs(q[2] + (cap - m * TEST_G)) <= 1e-12 * cap);
        assert_true(fabs(f[2] - m * TEST_G) <= 1e-12 * cap);
        assert_true(fabs(f[0]) <= 1e-12 * cap && fabs(f[1]) <= 1e-12 * cap);
        assert_int_equal(tb_scene_set_joint_motor(scene, 0, TB_MOTOR_VELOCITY, -0.5, cap),
                         TB_STATUS_OK);
        double worst = 0.0;
        for (int frame = 1; frame <= 100; ++frame) {
            const double s = frame / 100.0;
            advance(integrator, 3.0 + s);
            y = tb_scene_states(scene);
            assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], &q[1], &q[2]), TB_STATUS_OK);
            const double exact = 0.3 - 0.5 * s + 0.5 / MOTOR_RATE * (1.0 - exp(-MOTOR_RATE * s));
            worst = fmax(worst, fabs(q[0] - exact));
            assert_true(q[2] == 0.0);
        }
        print_message("lift %s reversed: travel error %.3g m over 1 s\n",
                      tb_method_name(methods[k]), worst);
        assert_true(worst <= 1e-7);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The lift at its lower stop with a cap below its weight (10 N < 19.62 N): the motor drives
 * away from the stop but cannot lift the block, so the stop holds it with the motor at its cap
 * beside it: the block stays at -0.5 m (the projection's 1e-12 m), the motor +10 N, the stop
 * m g - 10 = 9.62 N, to 1e-12 of m g (statics). It starts 1 mm above the stop, so it falls onto
 * it first (restitution 0). */
static void test_short_motor_cannot_lift_its_block_off_the_stop(void **state)
{
    (void)state;
    const double m = 2.0, cap = 10.0;
    for (int k = 0; k < 2; ++k) {
        size_t block = 0;
        tb_scene *scene = lift_scene(&block, cap);
        tb_joint_def def;
        assert_int_equal(tb_scene_joint_def(scene, 0, &def), TB_STATUS_OK);
        tb_scene_destroy(scene);
        scene = test_empty_scene();
        const double size[3] = {0.2, 0.2, 0.2}, x[3] = {0.0, 0.0, 0.0};
        block = test_add_box(scene, m, size, x);
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
        def.limits[0] = -0.001;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        tb_integrator *integrator = integrator_for(scene, k);
        double worst = 0.0, q[3];
        for (int frame = 1; frame <= 100; ++frame) {
            advance(integrator, frame / 50.0);
            const double *y = tb_scene_states(scene);
            assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], &q[1], &q[2]), TB_STATUS_OK);
            if (frame >= 25) {
                worst = fmax(worst, fabs(q[0] + 0.001));
                assert_true(fabs(q[1] - cap) <= 1e-12 * m * TEST_G);
                assert_true(fabs(q[2] - (m * TEST_G - cap)) <= 1e-12 * m * TEST_G);
            }
        }
        print_message("short lift %s: off the stop by %.3g m, motor %.17g N, stop %.17g N\n",
                      tb_method_name(methods[k]), worst, q[1], q[2]);
        assert_true(worst <= 1e-12);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The door pushed open at 2 rad/s into its stop with restitution 0.3 while its motor (toward
 * 1 rad/s, 5 N m cap) keeps pushing: it bounces back at 0.3 times its speed again and again, each
 * bounce shorter (a ball bouncing under gravity), until one leaves it slower than resting contact
 * and the stop holds it. Under CVODE (BDF and Adams, rtol 1e-8) every bounce is an event, the
 * last ones microseconds and 1e-12 rad long; the door never passes its stop by more than the
 * projection's 1e-12 rad, and from 3 s it rests on it with the motor at +5 N m and the stop at
 * -5 N m (statics, to 1e-12 of the cap). (An event's root may lie a rounding past the bound:
 * left there, the door went through the stop on its next approach, its root function negative
 * from the start.) */
static void test_door_motor_bouncing_into_its_stop_comes_to_rest_on_it(void **state)
{
    (void)state;
    const tb_method adaptive[2] = {TB_METHOD_CVODE_BDF, TB_METHOD_CVODE_ADAMS};
    for (int k = 0; k < 2; ++k) {
        tb_scene *scene = test_empty_scene();
        tb_joint_def def;
        test_add_swinging_door(scene, 2.0, &def);
        def.restitution = 0.3;
        def.motor = TB_MOTOR_VELOCITY;
        def.motor_speed = 1.0;
        def.motor_max_force = 5.0;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, adaptive[k], 0.0, 1e-8);
        double past = 0.0, q[3] = {0.0, 0.0, 0.0};
        for (int frame = 1; frame <= 400; ++frame) {
            advance(integrator, frame / 100.0);
            assert_int_equal(
                tb_scene_joint_axial(scene, tb_scene_states(scene), 0, &q[0], &q[1], &q[2]),
                TB_STATUS_OK);
            past = fmax(past, q[0] - DOOR_OPEN);
            if (frame >= 300) {
                assert_true(fabs(q[1] - 5.0) <= 1e-12 * 5.0 && fabs(q[2] + 5.0) <= 1e-12 * 5.0);
            }
        }
        print_message("bouncing door %s: past its stop by %.3g rad; at 4 s motor %.17g, stop %.17g "
                      "N m\n",
                      tb_method_name(adaptive[k]), past, q[1], q[2]);
        assert_true(past <= 1e-12);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_door_motor_rests_on_its_stop_at_its_cap_and_leaves_when_reversed),
        cmocka_unit_test(test_slider_motor_holds_its_block_on_the_stop_and_lowers_it_when_reversed),
        cmocka_unit_test(test_short_motor_cannot_lift_its_block_off_the_stop),
        cmocka_unit_test(test_door_motor_bouncing_into_its_stop_comes_to_rest_on_it),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
