/* The double pendulum on hinges under every method, against the same pendulum integrated in
 * generalised coordinates (its Lagrange equations, tests/support/joint_scenes.c, RK4 at 1e-4 s,
 * whose own error is below 1e-12 rad): the angles' largest error over the run, the energy
 * drift and the joints' error. Each bound is the method's measured figure (docs/joints.md,
 * "Tolerances") with a margin of about 3 for other compilers and processors. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define THETA1 1.0
#define THETA2 0.5
#define FPS 60

typedef struct run_figures {
    double angle;  /* rad: largest |theta - theta_reference| over the frames */
    double energy; /* J: largest |E - E0| */
    double joint;  /* m: largest joint position error at the frames */
} run_figures;

static run_figures run(tb_method method, double dt, double rtol, double seconds)
{
    size_t ids[2];
    tb_scene *scene = test_double_pendulum(THETA1, THETA2, ids);
    tb_integrator *integrator = test_integrator_for(scene, method, dt, rtol);
    const size_t frames = (size_t)lround(seconds * FPS);
    double *reference = malloc(2 * (frames + 1) * sizeof(double));
    assert_non_null(reference);
    test_double_pendulum_reference(THETA1, THETA2, 1.0 / FPS, frames + 1, reference);
    const double e0 = test_total_energy(scene);
    run_figures out = {0.0, 0.0, 0.0};
    for (size_t k = 1; k <= frames; ++k) {
        const tb_status status = tb_integrator_advance(integrator, (double)k / FPS);
        if (status != TB_STATUS_OK) {
            print_message("%s\n", tb_integrator_detail(integrator));
        }
        assert_int_equal(status, TB_STATUS_OK);
        const double *y = tb_scene_states_const(scene);
        for (int i = 0; i < 2; ++i) {
            const double error = test_rod_angle(scene, y, ids[i]) - reference[2 * k + i];
            out.angle = fmax(out.angle, fabs(remainder(error, 2.0 * TEST_PI)));
        }
        out.energy = fmax(out.energy, fabs(test_total_energy(scene) - e0));
        out.joint = fmax(out.joint, test_largest_joint_error(scene));
    }
    print_message("%-10s %s %-8g %4.0f s: angle error %.3g rad, energy drift %.3g m g l, joint "
                  "error %.3g m\n",
                  tb_method_name(method), tb_method_is_adaptive(method) ? "rtol" : "dt  ",
                  tb_method_is_adaptive(method) ? rtol : dt, seconds, out.angle,
                  out.energy / TEST_G, out.joint);
    free(reference);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* The bounds: angle (rad) and energy drift (in m g l, m = 1 kg, l = 1 m); every method's
 * outputs are projected, so the joints stay at round-off (1e-12 m, the bound). */
static void check(run_figures f, double angle, double energy)
{
    assert_true(f.angle <= angle);
    assert_true(f.energy <= energy * TEST_G);
    assert_true(f.joint <= 1e-12);
}

static void test_euler_follows_the_pendulum_to_first_order(void **state)
{
    (void)state;
    /* measured 0.011 rad and 8.0e-3 m g l over 2 s: first order */
    const run_figures f = run(TB_METHOD_EULER, 1.0 / 2400.0, 0.0, 2.0);
    check(f, 0.03, 0.02);
}

static void test_midpoint_follows_the_pendulum(void **state)
{
    (void)state;
    /* measured 1.2e-3 rad and 2.4e-5 m g l (dt 1/480 s: at 1/240 s the
     * stability guard refuses the thin rods spinning at 4 rad/s) */
    const run_figures f = run(TB_METHOD_MIDPOINT, 1.0 / 480.0, 0.0, 10.0);
    check(f, 4e-3, 1e-4);
}

static void test_rk4_follows_the_pendulum(void **state)
{
    (void)state;
    /* measured 2.5e-7 rad and 1.3e-8 m g l; the issue asks 1e-5 m g l */
    const run_figures f = run(TB_METHOD_RK4, 1.0 / 240.0, 0.0, 10.0);
    check(f, 1e-6, 1e-5);
}

static void test_cvode_adams_follows_the_pendulum(void **state)
{
    (void)state;
    /* measured 6.3e-7 rad and 7.7e-8 m g l, with Baumgarte terms in the
     * steps */
    const run_figures f = run(TB_METHOD_CVODE_ADAMS, 0.0, 1e-8, 10.0);
    check(f, 3e-6, 3e-7);
}

static void test_cvode_bdf_follows_the_pendulum(void **state)
{
    (void)state;
    /* measured 6.7e-7 rad and 1.6e-7 m g l, projected by CVODE */
    const run_figures f = run(TB_METHOD_CVODE_BDF, 0.0, 1e-8, 10.0);
    check(f, 2e-6, 5e-7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_euler_follows_the_pendulum_to_first_order),
        cmocka_unit_test(test_midpoint_follows_the_pendulum),
        cmocka_unit_test(test_rk4_follows_the_pendulum),
        cmocka_unit_test(test_cvode_adams_follows_the_pendulum),
        cmocka_unit_test(test_cvode_bdf_follows_the_pendulum),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
