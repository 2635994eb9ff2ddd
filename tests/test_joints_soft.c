/* Soft joints' springs keep energy (issue 21, src/constraints/joint_soft.c): an undamped soft
 * joint is a conservative, isotropic spring whose energy tb_scene_potential_energy counts, so
 * kinetic plus potential energy is constant up to the integrator's error, which converges at
 * RK4's order; between two free bodies momentum and angular momentum are kept too. A damped one
 * only loses energy. Tolerances stated with their reasons. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <string.h>

/* A 1 kg, 1 m rod hung by its top end from the world on a soft ball joint (frequency hz,
 * damping ratio zeta), released at rest at 1 rad from straight down, under gravity. */
static tb_scene *soft_pendulum(double hz, double zeta, size_t *rod)
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double theta = 1.0, center[3] = {0.5 * sin(theta), 0.0, -0.5 * cos(theta)};
    *rod = test_add_rod(scene, 1.0, 1.0, theta, center);
    tb_joint_def def = tb_joint_def_default();
    def.body_a = *rod;
    def.soft_frequency = hz;
    def.soft_damping_ratio = zeta;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

typedef struct swing {
    double drift;  /* largest |E - E0|, J */
    double spring; /* largest spring energy seen, J */
    double rise;   /* largest E(t) - E(t - frame), J (damped: should not be positive) */
} swing;

/* The pendulum for 5 s under RK4 at dt, energy read at 100 Hz. The spring's energy is the
 * potential less gravity's, m g z of the rod's centre. */
static swing run_pendulum(double hz, double zeta, double dt)
{
    size_t rod = 0;
    tb_scene *scene = soft_pendulum(hz, zeta, &rod);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, dt, 0.0);
    const double e0 = test_total_energy(scene);
    swing out = {0.0, 0.0, -INFINITY};
    double last = e0;
    for (int frame = 1; frame <= 500; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 100.0), TB_STATUS_OK);
        const double *y = tb_scene_states_const(scene);
        double potential = 0.0, x[3];
        assert_int_equal(tb_scene_potential_energy(scene, y, &potential), TB_STATUS_OK);
        assert_int_equal(tb_scene_body_point(scene, y, rod, (double[]){0.0, 0.0, 0.0}, x, NULL),
                         TB_STATUS_OK); /* the rod's centre: its shape origin */
        const double e = test_total_energy(scene);
        out.drift = fmax(out.drift, fabs(e - e0));
        out.spring = fmax(out.spring, potential - 1.0 * TEST_G * x[2]);
        out.rise = fmax(out.rise, e - last);
        last = e;
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* An undamped 5 Hz soft ball joint: the rod swings and its top bobs on the spring (the spring's
 * energy reaches 0.071 m g l, so a model that left it out, or whose stiffness turned with the
 * rod, would miss the bounds by orders). RK4 keeps the total energy to its own error, which on
 * an oscillation is an amplitude error of (h w)^6 / 144 a step, order 5 over a run: 4.5e-9 m g l
 * at 1/480 s, 1.5e-10 at 1/960 s over 5 s (measured, ratio 30), bounds 2e-8 and 1e-9 m g l and a
 * ratio of at least 12. tb_scene_conserved says energy is kept (not momentum: the world holds
 * the joint). */
static void test_undamped_soft_pendulum_keeps_its_energy(void **state)
{
    (void)state;
    const double mgl = 1.0 * TEST_G * 1.0;
    const swing coarse = run_pendulum(5.0, 0.0, 1.0 / 480.0);
    const swing fine = run_pendulum(5.0, 0.0, 1.0 / 960.0);
    print_message("soft pendulum rk4: spring energy up to %.3g m g l; drift %.3g m g l at 1/480 s, "
                  "%.3g at 1/960 s (ratio %.3g)\n",
                  coarse.spring / mgl, coarse.drift / mgl, fine.drift / mgl,
                  coarse.drift / fine.drift);
    assert_true(coarse.spring >= 1e-2 * mgl);
    assert_true(coarse.drift <= 2e-8 * mgl);
    assert_true(fine.drift <= 1e-9 * mgl);
    assert_true(coarse.drift / fine.drift >= 12.0);
    size_t rod = 0;
    tb_scene *scene = soft_pendulum(5.0, 0.0, &rod);
    tb_conserved c;
    assert_int_equal(tb_scene_conserved(scene, &c), TB_STATUS_OK);
    assert_true(c.energy && !c.linear_momentum);
    tb_scene_destroy(scene);
}

/* With damping ratio 0.1 the same pendulum loses energy, never gaining any between frames
 * beyond RK4's error (bound 1e-9 m g l), and tb_scene_conserved says energy is not kept. */
static void test_damped_soft_pendulum_only_loses_energy(void **state)
{
    (void)state;
    const double mgl = 1.0 * TEST_G * 1.0;
    const swing damped = run_pendulum(5.0, 0.1, 1.0 / 240.0);
    print_message("damped soft pendulum: largest rise between frames %.3g m g l, lost %.3g m g l\n",
                  damped.rise / mgl, damped.drift / mgl);
    assert_true(damped.rise <= 1e-9 * mgl);
    assert_true(damped.drift >= 1e-3 * mgl);
    size_t rod = 0;
    tb_scene *scene = soft_pendulum(5.0, 0.1, &rod);
    tb_conserved c;
    assert_int_equal(tb_scene_conserved(scene, &c), TB_STATUS_OK);
    assert_false(c.energy);
    tb_scene_destroy(scene);
}

typedef struct pair_run {
    double twist, drift, dp, dl; /* largest row error; drift of E, of P, of L (relative) */
} pair_run;

/* The pair for 5 s of RK4 at dt, read at 100 Hz. */
static pair_run run_pair(double dt)
{
    tb_scene *scene = test_empty_scene();
    const size_t a = test_add_box(scene, 2.0, (double[]){0.4, 0.2, 0.1}, (double[]){0.0, 0, 0});
    const size_t b = test_add_box(scene, 1.0, (double[]){0.1, 0.3, 0.2}, (double[]){0.5, 0, 0});
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_FIXED;
    def.body_a = a;
    def.body_b = b;
    def.anchor[0] = 0.3;
    def.soft_frequency = 2.0;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    assert_int_equal(
        tb_scene_set_velocity(scene, a, (double[]){0.1, 0.2, 0.0}, (double[]){1.0, 0.5, 2.0}),
        TB_STATUS_OK);
    assert_int_equal(
        tb_scene_set_velocity(scene, b, (double[]){0.0, -0.3, 0.1}, (double[]){-1.5, 2.0, -1.0}),
        TB_STATUS_OK);
    tb_conserved c;
    assert_int_equal(tb_scene_conserved(scene, &c), TB_STATUS_OK);
    assert_true(c.energy && c.linear_momentum && c.angular_momentum);
    const double origin[3] = {0.0, 0.0, 0.0};
    double p0[3], l0[3], p[3], l[3], k0 = 0.0;
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_linear_momentum(scene, y, p0), TB_STATUS_OK);
    assert_int_equal(tb_scene_angular_momentum(scene, y, origin, l0), TB_STATUS_OK);
    assert_int_equal(tb_scene_kinetic_energy(scene, y, &k0), TB_STATUS_OK);
    const double e0 = test_total_energy(scene);
    const double l_size = sqrt(l0[0] * l0[0] + l0[1] * l0[1] + l0[2] * l0[2]);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, dt, 0.0);
    pair_run out = {0.0, 0.0, 0.0, 0.0};
    for (int frame = 1; frame <= 500; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 100.0), TB_STATUS_OK);
        y = tb_scene_states_const(scene);
        assert_int_equal(tb_scene_linear_momentum(scene, y, p), TB_STATUS_OK);
        assert_int_equal(tb_scene_angular_momentum(scene, y, origin, l), TB_STATUS_OK);
        double error = 0.0;
        assert_int_equal(tb_scene_joint_error(scene, y, 0, &error, NULL), TB_STATUS_OK);
        out.twist = fmax(out.twist, error);
        out.drift = fmax(out.drift, fabs(test_total_energy(scene) - e0) / k0);
        for (int k = 0; k < 3; ++k) {
            out.dp = fmax(out.dp, fabs(p[k] - p0[k]));
            out.dl = fmax(out.dl, fabs(l[k] - l0[k]) / l_size);
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* Two boxes (2 kg and 1 kg, different shapes) on an undamped 2 Hz soft fixed joint, no gravity,
 * started with different spins and velocities so that the spring twists and stretches (its rows'
 * error reaches 0.58): the rotation rows' spring is exact only with its factor e0 = cos(theta / 2)
 * (joint_soft.c; without it the energy is off by 1.6e-2 at every step size), and the pair's
 * momentum and angular momentum are kept only if the spring is isotropic. RK4 over 5 s: energy to
 * RK4's error, 1.2e-8 of the kinetic energy at the start at 1/480 s and 3.7e-10 at 1/960 s
 * (measured, ratio 32: order 5, as above), bounds 1e-7 and 1e-8 and a ratio of at least 12;
 * linear momentum to 1e-13 kg m/s (the forces are equal and opposite at every stage: round-off,
 * 2.2e-15 measured), angular momentum about the origin to 1e-9 of its size (RK4 does not keep
 * x x P exactly: 1.2e-10 measured). */
static void test_soft_fixed_joint_between_free_bodies_keeps_energy_and_momenta(void **state)
{
    (void)state;
    const pair_run coarse = run_pair(1.0 / 480.0), fine = run_pair(1.0 / 960.0);
    print_message("soft fixed joint: largest row error %.3g (m or sin), energy drift %.3g of the "
                  "start's kinetic energy at 1/480 s, %.3g at 1/960 s (ratio %.3g), momentum %.3g "
                  "kg m/s, angular momentum %.3g of its size\n",
                  coarse.twist, coarse.drift, fine.drift, coarse.drift / fine.drift, coarse.dp,
                  coarse.dl);
    assert_true(coarse.twist >= 0.1);
    assert_true(coarse.drift <= 1e-7 && fine.drift <= 1e-8);
    assert_true(coarse.drift / fine.drift >= 12.0);
    assert_true(coarse.dp <= 1e-13 && fine.dp <= 1e-13);
    assert_true(coarse.dl <= 1e-9 && fine.dl <= 1e-9);
}

/* Limits and a motor on soft joints: the axial row (a hinge's angle, a slider's travel) is an
 * exact row of the solve while a stop holds it or the motor drives it, the springs beside it.
 * A soft vertical slider (4 Hz, damping ratio 0.5) with limits [-0.5, 0.3] m lifts a 2 kg block
 * at its motor's 30 N cap into its upper stop (restitution 0) and rests there: on the stop to
 * 1e-12 m (the projection of its axial row), the motor at its cap and the stop pushing back
 * -(30 - m g), to 1e-12 of the cap (statics along the axis: the springs are across it and
 * unloaded). Reversed at 3 s, it follows the servo's exponential as the rigid slider does,
 * 0.3 - 0.5 s + (0.5 / 20)(1 - e^(-20 s)), to 1e-7 m (RK4 at 1/240 s, CVODE BDF at rtol
 * 1e-10). A soft joint made without limits or a motor is refused one later (its rows have no
 * axial row), and the scene is unchanged. */
static void test_soft_slider_motor_rests_on_its_stop_and_leaves_when_reversed(void **state)
{
    (void)state;
    const double m = 2.0, cap = 30.0;
    const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (int k = 0; k < 2; ++k) {
        tb_scene *scene = test_empty_scene();
        const size_t block =
            test_add_box(scene, m, (double[]){0.2, 0.2, 0.2}, (double[]){0.0, 0.0, 0.0});
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_SLIDER;
        def.body_a = block;
        def.has_limits = 1;
        def.limits[0] = -0.5;
        def.limits[1] = 0.3;
        def.motor = TB_MOTOR_VELOCITY;
        def.motor_speed = 0.5;
        def.motor_max_force = cap;
        def.soft_frequency = 4.0;
        def.soft_damping_ratio = 0.5;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        tb_integrator *integrator =
            test_integrator_for(scene, methods[k], k == 0 ? 1.0 / 240.0 : 0.0, 1e-10);
        assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_OK);
        const double *y = tb_scene_states_const(scene);
        double q[3];
        assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], &q[1], &q[2]), TB_STATUS_OK);
        print_message("soft lift %s at its stop: travel %.17g m, motor %.17g N, stop %.17g N\n",
                      tb_method_name(methods[k]), q[0], q[1], q[2]);
        assert_true(fabs(q[0] - 0.3) <= 1e-12);
        assert_true(fabs(q[1] - cap) <= 1e-12 * cap);
        assert_true(fabs(q[2] + (cap - m * TEST_G)) <= 1e-12 * cap);
        assert_int_equal(tb_scene_set_joint_motor(scene, 0, TB_MOTOR_VELOCITY, -0.5, cap),
                         TB_STATUS_OK);
        double worst = 0.0;
        for (int frame = 1; frame <= 100; ++frame) {
            const double t = frame / 100.0;
            assert_int_equal(tb_integrator_advance(integrator, 3.0 + t), TB_STATUS_OK);
            y = tb_scene_states_const(scene);
            assert_int_equal(tb_scene_joint_axial(scene, y, 0, &q[0], NULL, NULL), TB_STATUS_OK);
            worst = fmax(worst, fabs(q[0] - (0.3 - 0.5 * t + 0.5 / 20.0 * (1.0 - exp(-20.0 * t)))));
        }
        print_message("soft lift %s reversed: travel error %.3g m over 1 s\n",
                      tb_method_name(methods[k]), worst);
        assert_true(worst <= 1e-7);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    tb_scene *scene = test_empty_scene();
    const size_t ball = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, 0.0}, NULL);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = ball;
    def.soft_frequency = 4.0;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_joint_motor(scene, 0, TB_MOTOR_VELOCITY, 1.0, 1.0),
                     TB_STATUS_UNSUPPORTED);
    assert_non_null(strstr(tb_scene_detail(scene), "soft joint"));
    tb_joint_def after;
    assert_int_equal(tb_scene_joint_def(scene, 0, &after), TB_STATUS_OK);
    assert_int_equal(after.motor, TB_MOTOR_OFF);
    tb_scene_destroy(scene);
}

/* A 20 kg door (1 x 0.05 x 2 m) on an undamped 3 Hz soft hinge with limits [0, 90 deg] and a
 * perfectly elastic stop (restitution 1), no gravity, pushed open at 2 rad/s: it bounces
 * between its stops, its hinge's springs taking up the door's centre, which a stop's torque
 * does not stop. An elastic impulse along one row keeps kinetic energy, and the springs are
 * conservative, so kinetic plus spring energy is kept: CVODE BDF (rtol 1e-10) locates each
 * impact at its root and keeps it to 1e-6 of the start's (the tolerance's growth over 3 s of
 * bounces); the angle never passes a stop by more than the projection's 1e-12 rad. */
static void test_soft_door_bounces_between_elastic_stops_keeping_its_energy(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    tb_joint_def def;
    test_add_swinging_door(scene, 2.0, &def);
    def.restitution = 1.0;
    def.soft_frequency = 3.0;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    tb_conserved c;
    assert_int_equal(tb_scene_conserved(scene, &c), TB_STATUS_OK);
    assert_true(c.energy);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_CVODE_BDF, 0.0, 1e-10);
    const double e0 = test_total_energy(scene);
    double drift = 0.0, past = 0.0, low = INFINITY, high = -INFINITY;
    for (int frame = 1; frame <= 300; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 100.0), TB_STATUS_OK);
        double angle = 0.0;
        assert_int_equal(
            tb_scene_joint_axial(scene, tb_scene_states_const(scene), 0, &angle, NULL, NULL),
            TB_STATUS_OK);
        past = fmax(past, fmax(-angle, angle - TEST_PI / 2.0));
        low = fmin(low, angle);
        high = fmax(high, angle);
        drift = fmax(drift, fabs(test_total_energy(scene) - e0));
    }
    print_message("soft door cvode-bdf: angles [%.3g, %.3g] rad, past a stop %.3g rad, energy "
                  "drift %.3g of the start's\n",
                  low, high, past, drift / e0);
    assert_true(low < 0.1 && high > TEST_PI / 2.0 - 0.1); /* it reaches both stops */
    assert_true(past <= 1e-12);
    assert_true(drift <= 1e-6 * e0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_undamped_soft_pendulum_keeps_its_energy),
        cmocka_unit_test(test_damped_soft_pendulum_only_loses_energy),
        cmocka_unit_test(test_soft_fixed_joint_between_free_bodies_keeps_energy_and_momenta),
        cmocka_unit_test(test_soft_slider_motor_rests_on_its_stop_and_leaves_when_reversed),
        cmocka_unit_test(test_soft_door_bounces_between_elastic_stops_keeping_its_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
