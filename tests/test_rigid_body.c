/* Rigid-body motion against what mechanics knows: the projectile parabola, the torque-free
 * top in Jacobi elliptic functions, conservation of angular momentum and energy, and the
 * growth or decay of |q| that linear stability theory predicts for each stepper. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "near.h"
#include "torque_free_top.h"
#include "tumble/tumble.h"

/* Euler, midpoint and RK4: the fixed-step methods come first in tb_method. */
#define FIXED_STEP_METHODS (TB_METHOD_RK4 + 1)

#include <math.h>
#include <string.h>

static tb_integrator *make_integrator(tb_scene *scene, tb_method method, double dt)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = dt;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    return integrator;
}

/* Under constant gravity x(t) = x0 + v0 t + g t^2 / 2. Midpoint and RK4 are exact on a
 * quadratic (round-off only: 1e-12 m on metres). Euler's position lags by exactly
 * g T h / 2, since x_N = x0 + v0 T + g h^2 N (N - 1) / 2. The spin does not matter: gravity
 * exerts no torque about the centre of mass, so L stays exactly as it was. */
static void test_projectile_follows_the_exact_parabola(void **state)
{
    (void)state;
    const double g[3] = {0.0, 0.0, -9.81}, v0[3] = {3.0, -1.0, 12.0}, T = 2.0, h = 0.01;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        tb_scene *scene =
            test_scene_one_body(2.0, (double[]){0.1, 0.2, 0.25}, NULL, (double[]){1.0, 5.0, 0.5});
        assert_int_equal(tb_scene_set_velocity(scene, 0, v0, (double[]){1.0, 5.0, 0.5}),
                         TB_STATUS_OK);
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        tb_body_state before;
        tb_scene_get_state(scene, 0, &before);
        tb_integrator *integrator = make_integrator(scene, (tb_method)m, h);
        assert_int_equal(tb_integrator_advance(integrator, T), TB_STATUS_OK);
        tb_body_state after;
        tb_scene_get_state(scene, 0, &after);
        for (int i = 0; i < 3; ++i) {
            const double exact = v0[i] * T + 0.5 * g[i] * T * T;
            const double lag = m == TB_METHOD_EULER ? 0.5 * g[i] * T * h : 0.0;
            assert_near(after.x[i], exact - lag, 1e-12);
            assert_near(after.P[i], 2.0 * (v0[i] + g[i] * T), 1e-12);
            assert_true(after.L[i] == before.L[i]);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* top_error: the shared Jacobi-top measurement with a fixed-step method. */
static double top_error(tb_method method, double dt, double T, int frames)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = dt;
    return test_top_error(&def, T, frames, NULL);
}

/* RK4 at 240 steps per second follows Jacobi's solution over three periods of the body-frame
 * motion to 1e-9 rad/s: the global error bound C (omega h)^4 omega T with omega ~ 2 rad/s is
 * of order 1e-10, and round-off of the elliptic functions is 1e-15. */
static void test_torque_free_top_matches_the_jacobi_elliptic_solution(void **state)
{
    (void)state;
    torque_free_top exact;
    torque_free_top_init(&exact, test_top_moments, test_top_omega[0], test_top_omega[2]);
    const double T = 3.0 * torque_free_top_period(&exact);
    const double error = top_error(TB_METHOD_RK4, 1.0 / 240.0, T, 60);
    print_message("period %.6f s, RK4 error over 3 periods %.3e rad/s\n",
                  torque_free_top_period(&exact), error);
    assert_true(error < 1e-9);
}

/* Measured order on the free body: error ratios under halving h, in the asymptotic range.
 * The issue asks RK4 to measure 4 within 10%; Euler and midpoint are held to the same 10%. */
static void test_free_body_converges_at_each_steppers_order(void **state)
{
    (void)state;
    const double T = 10.0;
    const double base[FIXED_STEP_METHODS] = {0.002, 0.01, 0.05};
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        const double e1 = top_error((tb_method)m, base[m], T, 10);
        const double e2 = top_error((tb_method)m, base[m] / 2, T, 10);
        const double e3 = top_error((tb_method)m, base[m] / 4, T, 10);
        const double p1 = log2(e1 / e2), p2 = log2(e2 / e3);
        const int order = tb_method_order((tb_method)m);
        print_message("%-8s errors %.3e %.3e %.3e  measured order %.3f %.3f\n",
                      tb_method_name((tb_method)m), e1, e2, e3, p1, p2);
        assert_true(fabs(p1 - order) <= 0.1 * order);
        assert_true(fabs(p2 - order) <= 0.1 * order);
    }
}

/* With no torque dL/dt = 0 exactly, so every Runge-Kutta stage adds h * 0 to L: world L is
 * kept bit for bit, for every stepper, however long the run. Energy is not a linear
 * invariant: RK4's drift over 60 s at 240 Hz scales as (omega h)^4 omega T ~ 1e-6 times a
 * method constant well below 1e-2 (measured: 5.5e-12); we require 1e-9, which any loss of
 * fourth order (drift ~ (omega h)^3 or worse) would exceed. Euler's drift is printed, not
 * hidden: it gains about 9% in 60 s. */
static void test_torque_free_body_keeps_angular_momentum_exactly(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        tb_scene *scene = test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
        tb_body_state start;
        tb_scene_get_state(scene, 0, &start);
        double E0, E1;
        tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E0);
        tb_integrator *integrator = make_integrator(scene, (tb_method)m, 1.0 / 240.0);
        assert_int_equal(tb_integrator_advance(integrator, 60.0), TB_STATUS_OK);
        tb_body_state end;
        tb_scene_get_state(scene, 0, &end);
        assert_memory_equal(end.L, start.L, sizeof start.L);
        tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E1);
        print_message("%-8s relative energy drift over 60 s: %+.3e\n", tb_method_name((tb_method)m),
                      (E1 - E0) / E0);
        if (m == TB_METHOD_RK4) {
            assert_true(fabs(E1 - E0) < 1e-9 * E0);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* For an isotropic body omega is constant, so dq/dt = A q is linear with A skew-symmetric
 * (eigenvalues +-i omega/2). One step multiplies |q|^2 by |R(iz)|^2, z = omega h / 2, where R
 * is the stepper's stability polynomial: Euler 1 + z^2, midpoint 1 + z^4/4, RK4
 * 1 - z^6/72 + z^8/576. Without the hook |q| must follow that prediction to 1e-9 relative
 * (round-off over 1e5 steps is ~1e-11); with the hook it stays within 1e-15 of 1. */
static double predicted_norm_factor(tb_method method, double z)
{
    const double z2 = z * z;
    switch (method) {
    case TB_METHOD_EULER:
        return 1.0 + z2;
    case TB_METHOD_MIDPOINT:
        return 1.0 + z2 * z2 / 4.0;
    default:
        return 1.0 - z2 * z2 * z2 / 72.0 + z2 * z2 * z2 * z2 / 576.0;
    }
}

static void
test_quaternion_norm_drifts_as_stability_theory_predicts_unless_renormalised(void **state)
{
    (void)state;
    const long steps = 100000;
    const double h = 0.01, omega[FIXED_STEP_METHODS] = {2.0, 20.0, 20.0};
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        const double w_body[3] = {0.0, 0.6 * omega[m], 0.8 * omega[m]};
        tb_scene *scene = test_scene_one_body(1.0, (double[]){0.4, 0.4, 0.4}, test_top_q0, w_body);
        tb_scene_set_renormalize(scene, false);
        tb_integrator *integrator = make_integrator(scene, (tb_method)m, h);
        assert_int_equal(tb_integrator_advance(integrator, h * steps), TB_STATUS_OK);
        tb_body_state s;
        tb_scene_get_state(scene, 0, &s);
        const double norm =
            sqrt(s.q[0] * s.q[0] + s.q[1] * s.q[1] + s.q[2] * s.q[2] + s.q[3] * s.q[3]);
        const double z = 0.5 * omega[m] * h;
        const double predicted = pow(predicted_norm_factor((tb_method)m, z), 0.5 * steps);
        print_message("%-8s |q| after 1e5 steps without hook %.15f, predicted %.15f\n",
                      tb_method_name((tb_method)m), norm, predicted);
        assert_near(norm / predicted, 1.0, 1e-9);
        assert_true(fabs(norm - 1.0) > 1e-4); /* the drift is real, not round-off */
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);

        scene = test_scene_one_body(1.0, (double[]){0.4, 0.4, 0.4}, test_top_q0, w_body);
        integrator = make_integrator(scene, (tb_method)m, h);
        double worst = 0.0;
        for (long k = 0; k < steps; ++k) {
            assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
            const double *q = tb_scene_states(scene) + 3;
            worst = fmax(worst,
                         fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1.0));
        }
        print_message("%-8s with hook: largest | |q| - 1 | over 1e5 steps %.2e\n",
                      tb_method_name((tb_method)m), worst);
        assert_true(worst < 1e-15);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A force f at a body point r (shape frame) on a body turned by q: dP/dt = f and
 * dL/dt = (R r) x f, read straight from the derivative. A body-frame force turns with the
 * body: dP/dt = R f. Here R is 90 degrees about z: R (1, 0, 0) = (0, 1, 0). Tolerance 1e-14:
 * a few ulps of the values, from rounding sqrt(1/2) in q. */
static void test_off_centre_force_exerts_the_lever_arm_torque(void **state)
{
    (void)state;
    const double s = sqrt(0.5);
    const double quarter_turn_z[4] = {s, 0.0, 0.0, s};
    tb_scene *scene =
        test_scene_one_body(2.0, (double[]){1, 1, 1}, quarter_turn_z, (double[]){0, 0, 0});
    const double r[3] = {1.0, 0.0, 0.0}, f[3] = {0.0, 0.0, 5.0};
    assert_int_equal(tb_scene_add_force(scene, 0, f, r, TB_FRAME_WORLD), TB_STATUS_OK);
    double dydt[TB_STATE_SIZE];
    assert_int_equal(tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene), 0);
    /* lever arm (0, 1, 0) x (0, 0, 5) = (5, 0, 0) */
    const double expected_P[3] = {0, 0, 5}, expected_L[3] = {5, 0, 0};
    for (int i = 0; i < 3; ++i) {
        assert_near(dydt[7 + i], expected_P[i], 1e-15);
        assert_near(dydt[10 + i], expected_L[i], 1e-14);
    }
    tb_scene_destroy(scene);

    scene = test_scene_one_body(2.0, (double[]){1, 1, 1}, quarter_turn_z, (double[]){0, 0, 0});
    assert_int_equal(
        tb_scene_add_force(scene, 0, (double[]){1, 0, 0}, (double[]){0, 0, 0}, TB_FRAME_BODY),
        TB_STATUS_OK);
    assert_int_equal(tb_scene_add_torque(scene, 0, (double[]){0, 2, 0}, TB_FRAME_BODY),
                     TB_STATUS_OK);
    assert_int_equal(tb_scene_derivative(0.0, tb_scene_states(scene), dydt, scene), 0);
    assert_near(dydt[7], 0.0, 1e-14);
    assert_near(dydt[8], 1.0, 1e-14);
    assert_near(dydt[10], -2.0, 1e-14); /* R (0, 2, 0) = (-2, 0, 0) */
    assert_near(dydt[11], 0.0, 1e-14);
    tb_scene_destroy(scene);
}

/* One body with principal moments (3, 2, 1) kg m^2 about its shape axes (descending, as
 * tb_mass_from_box gives a box longest along z) and rotation the identity. */
static tb_scene *descending_body(const tb_mass_properties *mass, const double omega[3])
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    def.mass = *mass;
    memcpy(def.angular_velocity, omega, sizeof def.angular_velocity);
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    return scene;
}

/* F29: the order of principal moments is any order (include/tumble/mass.h: the primitives keep
 * their shape axes, so a box's moments may descend); tb_mass_validate accepts (3, 2, 1), and a
 * body given them moves exactly as the same body given (1, 2, 3) with the principal frame turned
 * onto the shape axes (principal x along shape z, y along -y, z along x: half a turn about
 * (1, 0, 1) / sqrt 2, proper). Both tumble torque-free for 2 s under RK4 at 1 ms; the shape
 * frames' poses agree to 1e-12: the same physics rounded differently, at rates below 0.5
 * rad/s that amplify round-off by at most e^(0.5 * 2). */
static void test_descending_moments_are_a_body_in_another_frame(void **state)
{
    (void)state;
    tb_mass_properties descending = {.mass = 2.0, .moments = {3, 2, 1}, .rotation = {1, 0, 0, 0}};
    assert_int_equal(tb_mass_validate(&descending, NULL), TB_STATUS_OK);
    tb_mass_properties ascending = descending;
    const double s = sqrt(0.5);
    const double half_turn[4] = {0.0, s, 0.0, s};
    memcpy(ascending.moments, (double[]){1, 2, 3}, sizeof ascending.moments);
    memcpy(ascending.rotation, half_turn, sizeof ascending.rotation);
    assert_int_equal(tb_mass_validate(&ascending, NULL), TB_STATUS_OK);
    const double omega[3] = {0.3, 0.2, 0.1};
    tb_scene *scenes[2] = {descending_body(&descending, omega), descending_body(&ascending, omega)};
    double position[2][3], orientation[2][4];
    for (int k = 0; k < 2; ++k) {
        tb_integrator *integrator = make_integrator(scenes[k], TB_METHOD_RK4, 1e-3);
        assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
        assert_int_equal(tb_scene_body_shape_pose(scenes[k], tb_scene_states(scenes[k]), 0,
                                                  position[k], orientation[k]),
                         TB_STATUS_OK);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scenes[k]);
    }
    const double sign = orientation[0][0] * orientation[1][0] < 0.0 ? -1.0 : 1.0; /* q ~ -q */
    for (int i = 0; i < 4; ++i) {
        assert_near(orientation[1][i], sign * orientation[0][i], 1e-12);
    }
    assert_true(fabs(orientation[0][0]) < 0.999); /* it turned: the check is not vacuous */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_projectile_follows_the_exact_parabola),
        cmocka_unit_test(test_torque_free_top_matches_the_jacobi_elliptic_solution),
        cmocka_unit_test(test_free_body_converges_at_each_steppers_order),
        cmocka_unit_test(test_torque_free_body_keeps_angular_momentum_exactly),
        cmocka_unit_test(
            test_quaternion_norm_drifts_as_stability_theory_predicts_unless_renormalised),
        cmocka_unit_test(test_off_centre_force_exerts_the_lever_arm_torque),
        cmocka_unit_test(test_descending_moments_are_a_body_in_another_frame),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
