/* Adaptive stepping with CVODE (Adams and BDF) against exact solutions, against RK4, on a
 * stiff spring, across frame rates, and on its failure paths. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "near.h"
#include "torque_free_top.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const tb_method adaptive[2] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};

static tb_integrator_def adaptive_def(tb_method method, double rtol)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.rtol = rtol;
    return def;
}

static double top_period(void)
{
    torque_free_top exact;
    torque_free_top_init(&exact, test_top_moments, test_top_omega[0], test_top_omega[2]);
    return torque_free_top_period(&exact);
}

/* CVODE bounds the local error of each step (weighted RMS <= 1 with weights rtol |y| + atol),
 * not the global error: on a conservative system the step errors add up, so the global error
 * after N steps is about N rtol |y|. Over one period of the top we require
 * error <= 10 N rtol |omega0| (measured: 0.75 for Adams and 0.5 for BDF of N rtol |omega0|;
 * the factor 10 leaves room for the growth of errors along the orbit). */
static const double omega0_norm = 1.8027756377319946; /* |(1.5, 0, 1)| rad/s */

static void test_torque_free_top_matches_jacobi_with_adams_and_bdf(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        for (double rtol = 1e-6; rtol >= 1e-10; rtol *= 1e-2) {
            tb_integrator_def def = adaptive_def(adaptive[m], rtol);
            tb_integrator_stats stats;
            const double error = test_top_error(&def, top_period(), 40, &stats);
            const double bound = (double)stats.steps * rtol * omega0_norm;
            print_message("%-11s rtol %.0e: error %.2e rad/s = %.2f N rtol |omega0|, %ld steps, "
                          "%ld derivatives, order %d\n",
                          tb_method_name(adaptive[m]), rtol, error, error / bound, stats.steps,
                          stats.derivative_evals, stats.last_order);
            assert_true(error <= 10.0 * bound);
            assert_true(stats.steps > 0 && stats.derivative_evals >= stats.steps);
            assert_true(stats.last_order >= 1 && stats.last_order <= tb_method_order(adaptive[m]));
            assert_true(stats.current_step > 0);
        }
    }
}

/* Tolerance proportionality: asking for 100x less error must give at least 10x less, over the
 * range where each method is meant to be used on this oscillatory problem: Adams 1e-5 .. 1e-11,
 * BDF 1e-5 .. 1e-9. (Local error control does not promise proportionality; BDF, whose orders
 * 3-5 are weakly damped near the imaginary axis, gains only 9.9x from 1e-9 to 1e-11 here, so
 * that step is measured in the benchmark, not asserted.) */
static void test_tightening_rtol_100x_cuts_the_error_at_least_10x(void **state)
{
    (void)state;
    const double tightest[2] = {1e-11, 1e-9};
    for (int m = 0; m < 2; ++m) {
        double previous = 0.0;
        for (double rtol = 1e-5; rtol >= 0.5 * tightest[m]; rtol *= 1e-2) {
            tb_integrator_def def = adaptive_def(adaptive[m], rtol);
            tb_integrator_stats stats;
            const double error = test_top_error(&def, top_period(), 40, &stats);
            print_message("%-11s rtol %.0e: error %.2e rad/s, %5ld steps, %6ld derivatives%s\n",
                          tb_method_name(adaptive[m]), rtol, error, stats.steps,
                          stats.derivative_evals, previous > 0 ? "" : " (first)");
            if (previous > 0.0) {
                print_message("            gain %.1fx\n", previous / error);
                assert_true(error <= previous / 10.0);
            }
            previous = error;
        }
    }
}

/* A scene with forces and torques and no closed form: gravity, an off-centre body-frame force
 * and a world torque on an asymmetric body. RK4 at h = 1e-3 s has error ~1e-12 here; CVODE
 * at rtol 1e-10 must agree with it within 1e-7 in every state component (scaled by the
 * component's own size, at least 1). */
static void test_adams_and_bdf_agree_with_small_step_rk4(void **state)
{
    (void)state;
    double reference[TB_STATE_SIZE];
    for (int run = 0; run < 3; ++run) {
        tb_scene *scene = test_scene_one_body(2.0, (double[]){0.5, 1.0, 1.2}, test_top_q0,
                                              (double[]){1.0, 2.0, -0.5});
        tb_scene_set_velocity(scene, 0, (double[]){1, 0, 5}, (double[]){1.0, 2.0, -0.5});
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
        tb_scene_add_force(scene, 0, (double[]){0, 3, 0}, (double[]){0.2, 0, 0.1}, TB_FRAME_BODY);
        tb_scene_add_torque(scene, 0, (double[]){0.1, 0, 0.3}, TB_FRAME_WORLD);
        tb_integrator_def def = tb_integrator_def_default();
        if (run == 0) {
            def.dt = 1e-3;
        } else {
            def = adaptive_def(adaptive[run - 1], 1e-10);
        }
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_OK);
        const double *y = tb_scene_states(scene);
        if (run == 0) {
            memcpy(reference, y, sizeof reference);
        } else {
            double worst = 0.0;
            for (int k = 0; k < TB_STATE_SIZE; ++k) {
                worst = fmax(worst, fabs(y[k] - reference[k]) / fmax(1.0, fabs(reference[k])));
            }
            print_message("%-11s largest scaled difference from RK4: %.2e\n",
                          tb_method_name(def.method), worst);
            assert_true(worst < 1e-7);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* --- a stiff spring ------------------------------------------------------------------------
 * A 1 kg mass on a spring of rest length 1 m with k = 10^6 N/m (k/m = 10^6, omega = 1000
 * rad/s) and light damping (c = 100 N s/m, damping ratio 0.05), swinging under gravity as a
 * pendulum from 0.5 rad. The pendulum motion is slow (period ~2 s); the spring's own mode is
 * fast and hardly excited. State (x, y, vx, vy), anchor at the origin, gravity -y. */
typedef struct spring {
    double k, c, rest, g;
} spring;

static int spring_pendulum(double t, const double *s, double *ds, void *ctx)
{
    (void)t;
    const spring *p = ctx;
    const double length = sqrt(s[0] * s[0] + s[1] * s[1]);
    const double ux = s[0] / length, uy = s[1] / length;
    const double radial_speed = s[2] * ux + s[3] * uy;
    const double tension = p->k * (length - p->rest) + p->c * radial_speed;
    ds[0] = s[2];
    ds[1] = s[3];
    ds[2] = -tension * ux;
    ds[3] = -tension * uy - p->g;
    return 0;
}

static tb_status run_spring(const tb_integrator_def *def, double T, double out[4],
                            tb_integrator_stats *stats)
{
    static spring p = {1e6, 100.0, 1.0, 9.81};
    /* at rest along the spring at 0.5 rad: stretched by m g cos(0.5) / k */
    const double length = p.rest + p.g * cos(0.5) / p.k;
    double s[4] = {length * sin(0.5), -length * cos(0.5), 0.0, 0.0};
    tb_ode_system system = {.n = 4, .derivative = spring_pendulum, .ctx = &p};
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, def, 0.0, s, &integrator, NULL), TB_STATUS_OK);
    const tb_status status = tb_integrator_advance(integrator, T);
    tb_integrator_get_stats(integrator, stats);
    memcpy(out, s, sizeof s);
    tb_integrator_destroy(integrator);
    return status;
}

/* BDF limited to order 2 at rtol 1e-4 follows the reference (RK4 at h = 1e-5 s, 1% of the
 * fast period) within 1e-2 m, 2% of the 0.48 m swing (measured 2.7e-3 m; local error control
 * gives no tighter a priori bound than N rtol |x| ~ 0.03 m). RK4 given the same number of
 * derivative evaluations takes steps beyond its stability limit (h omega > 2.83) and does not
 * survive. Order 2 because the spring's modes, -50 +- 1000i, lie near the imaginary axis:
 * BDF2 is A-stable there at any step, orders 3-5 are not, and unrestricted BDF needs 2.5x
 * the work (see docs/integrators.md). */
static void test_bdf_integrates_a_stiff_spring_that_rk4_at_equal_cost_cannot(void **state)
{
    (void)state;
    const double T = 2.0;
    double reference[4], bdf[4], rk4[4];
    tb_integrator_stats stats;
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 1e-5;
    def.max_steps = 300000; /* 200000 steps in one advance: past the default budget */
    assert_int_equal(run_spring(&def, T, reference, &stats), TB_STATUS_OK);

    def = adaptive_def(TB_METHOD_CVODE_BDF, 1e-4);
    def.atol = 1e-6;
    def.max_order = 2;
    assert_int_equal(run_spring(&def, T, bdf, &stats), TB_STATUS_OK);
    const double error = hypot(bdf[0] - reference[0], bdf[1] - reference[1]);
    const long budget = stats.derivative_evals;
    print_message("BDF: %ld steps, %ld derivatives, position error %.2e m\n", stats.steps, budget,
                  error);
    assert_true(error < 1e-2);

    def = tb_integrator_def_default();
    def.dt = 4.0 * T / (double)budget; /* RK4 spends 4 derivatives a step */
    const tb_status status = run_spring(&def, T, rk4, &stats);
    const double rk4_error = hypot(rk4[0] - reference[0], rk4[1] - reference[1]);
    print_message("RK4 at equal cost: h = %.2e s (h omega = %.1f), status %s, error %.2e m\n",
                  def.dt, def.dt * 1000.0, tb_status_name(status), rk4_error);
    assert_true(def.dt * 1000.0 > 2.83);
    assert_true(status == TB_STATUS_STATE_NOT_FINITE || rk4_error > 1.0);
}

/* Frames come from CVODE's interpolant: the frame rate must not change the solution. Output
 * at 24 and at 240 fps over 5 s: step counts within 5% (only CVODE's first-step estimate,
 * which looks at the first output time, differs), and final states within N rtol of each
 * other (scaled), the global error either run may have after N steps. Measured: Adams 2e-8,
 * BDF 2e-6 (BDF's projection moves each step by up to its local error). */
static void test_frame_rate_does_not_change_the_solution(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        double final[2][TB_STATE_SIZE];
        long steps[2];
        const double fps[2] = {24.0, 240.0};
        for (int r = 0; r < 2; ++r) {
            tb_scene *scene =
                test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
            tb_integrator_def def = adaptive_def(adaptive[m], 1e-7);
            tb_integrator *integrator = NULL;
            assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                             TB_STATUS_OK);
            for (int f = 1; f <= (int)(5.0 * fps[r]); ++f) {
                assert_int_equal(tb_integrator_advance(integrator, f / fps[r]), TB_STATUS_OK);
            }
            tb_integrator_stats stats;
            tb_integrator_get_stats(integrator, &stats);
            steps[r] = stats.steps;
            memcpy(final[r], tb_scene_states(scene), sizeof final[r]);
            tb_integrator_destroy(integrator);
            tb_scene_destroy(scene);
        }
        double worst = 0.0;
        for (int k = 0; k < TB_STATE_SIZE; ++k) {
            worst = fmax(worst, fabs(final[0][k] - final[1][k]) / fmax(1.0, fabs(final[0][k])));
        }
        print_message("%-11s 24 fps: %ld steps, 240 fps: %ld steps, states differ by %.2e\n",
                      tb_method_name(adaptive[m]), steps[0], steps[1], worst);
        assert_true(worst <= (double)steps[0] * 1e-7);
        assert_true(labs(steps[0] - steps[1]) <= 0.05 * (double)steps[0]);
    }
}

/* Renormalisation under CVODE: outputs always carry unit quaternions (1e-15); the drift the
 * hook removes is of the order of the tolerance (BDF: projection after each step; Adams:
 * only outputs are normalised, CVODE's internal q drifts by its error), below 100 rtol. */
static void test_quaternions_are_unit_on_output_and_drift_stays_within_tolerance(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        tb_scene *scene = test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
        tb_integrator_def def = adaptive_def(adaptive[m], 1e-6);
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        double worst_output = 0.0;
        for (int f = 1; f <= 600; ++f) {
            assert_int_equal(tb_integrator_advance(integrator, f / 60.0), TB_STATUS_OK);
            const double *q = tb_scene_states(scene) + 3;
            worst_output =
                fmax(worst_output,
                     fabs(sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]) - 1.0));
        }
        const double drift = tb_scene_quaternion_drift(scene);
        print_message("%-11s rtol 1e-6 over 10 s: largest |q| - 1 removed %.2e, on output %.1e\n",
                      tb_method_name(adaptive[m]), drift, worst_output);
        assert_true(worst_output < 1e-15);
        assert_true(drift > 0.0 && drift < 100.0 * def.rtol);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* Changing the state from outside between advances restarts CVODE from the new state: the
 * continued run equals a fresh run from that state (to 10 rtol), and the restart is counted. */
static void test_changing_the_state_between_frames_restarts_cvode(void **state)
{
    (void)state;
    tb_scene *scene = test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
    tb_integrator_def def = adaptive_def(TB_METHOD_CVODE_ADAMS, 1e-9);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_velocity(scene, 0, (double[]){0, 0, 0}, (double[]){0, 3, 0}),
                     TB_STATUS_OK);
    tb_body_state kicked;
    tb_scene_get_state(scene, 0, &kicked);
    assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_OK);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    assert_int_equal(stats.reinitializations, 1);

    tb_scene *fresh = test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
    tb_scene_set_state(fresh, 0, &kicked);
    tb_integrator *second = NULL;
    assert_int_equal(tb_scene_integrator_create(fresh, &def, 1.0, &second), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(second, 3.0), TB_STATUS_OK);
    for (int k = 0; k < TB_STATE_SIZE; ++k) {
        assert_near(tb_scene_states(scene)[k], tb_scene_states(fresh)[k], 1e-8);
    }
    tb_integrator_destroy(second);
    tb_scene_destroy(fresh);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* --- failures: a status with CVODE's flag name, the state at the last good step ----------- */

typedef struct failing {
    double after; /* the derivative misbehaves for t > after */
    int mode;     /* 0: return -1; 1: return +1; 2: produce NaN */
} failing;

/* y' = -y, misbehaving after a time. */
static int decay_until(double t, const double *y, double *dydt, void *ctx)
{
    const failing *f = ctx;
    dydt[0] = -y[0];
    dydt[1] = -2.0 * y[1];
    if (t > f->after) {
        if (f->mode == 2) {
            dydt[0] = NAN;
            return 0;
        }
        return f->mode == 0 ? -1 : 1;
    }
    return 0;
}

static void expect_failure(tb_method method, failing how, long max_steps, tb_status expected,
                           const char *flag)
{
    double y[2] = {1.0, 1.0};
    tb_ode_system system = {.n = 2, .derivative = decay_until, .ctx = &how};
    tb_integrator_def def = adaptive_def(method, 1e-8);
    def.max_steps = max_steps;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    const tb_status status = tb_integrator_advance(integrator, 2.0);
    const double t = tb_integrator_time(integrator);
    print_message("%-11s %-20s -> %s at t = %.4f: %s\n", tb_method_name(method), flag,
                  tb_status_name(status), t, tb_integrator_detail(integrator));
    assert_int_equal(status, expected);
    assert_non_null(strstr(tb_integrator_detail(integrator), flag));
    /* The state is the solution at the integrator's (last good) time, to the tolerance. */
    assert_true(t < 2.0 && t <= how.after + 1e-12);
    assert_near(y[0], exp(-t), 1e-6);
    assert_near(y[1], exp(-2.0 * t), 1e-6);
    tb_integrator_destroy(integrator);
}

static void test_failures_name_the_cvode_flag_and_keep_the_last_good_state(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        expect_failure(adaptive[m], (failing){1e9, 0}, 5, TB_STATUS_TOO_MANY_STEPS,
                       "CV_TOO_MUCH_WORK");
        expect_failure(adaptive[m], (failing){0.5, 0}, 100000, TB_STATUS_DERIVATIVE_FAILED,
                       "derivative returned -1");
        /* A recoverable failure makes CVODE retry with smaller steps; one that persists past a
         * time makes it crawl towards that time until max_steps. */
        expect_failure(adaptive[m], (failing){0.5, 1}, 5000, TB_STATUS_DERIVATIVE_FAILED,
                       "derivative returned 1");
        /* NaN derivatives: CVODE shrinks the step until its budget, and the cause is named
         * (was SOLVER_FAILED, then TOO_MANY_STEPS without the cause) */
        expect_failure(adaptive[m], (failing){0.5, 2}, 5000, TB_STATUS_STATE_NOT_FINITE,
                       "derivative gave dydt[0] = nan");
    }
}

static void test_invalid_adaptive_settings_are_rejected(void **state)
{
    (void)state;
    static const struct {
        const char *label;
        const char *field;
        tb_status expected; /* NaN and infinity: NOT_FINITE; finite out of domain: INVALID */
    } cases[] = {{"rtol 0", "def.rtol", TB_STATUS_INVALID_ARGUMENT},
                 {"atol -1", "def.atol", TB_STATUS_INVALID_ARGUMENT},
                 {"atol_vector NaN", "def.atol_vector[1]", TB_STATUS_NOT_FINITE},
                 {"max_order 6", "def.max_order", TB_STATUS_INVALID_ARGUMENT},
                 {"max_steps 0", "def.max_steps", TB_STATUS_INVALID_ARGUMENT},
                 {"solver 7", "def.linear_solver", TB_STATUS_INVALID_ARGUMENT},
                 {"bandwidth 2", "def.preconditioner_half_bandwidth", TB_STATUS_INVALID_ARGUMENT},
                 {"max_step -1", "def.max_step", TB_STATUS_INVALID_ARGUMENT},
                 {"rtol NaN", "def.rtol", TB_STATUS_NOT_FINITE},
                 {"atol inf", "def.atol", TB_STATUS_NOT_FINITE},
                 {"initial_step NaN", "def.initial_step", TB_STATUS_NOT_FINITE}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        double y[2] = {1, 1}, atol[2] = {1e-8, NAN};
        failing how = {1e9, 0};
        tb_ode_system system = {.n = 2, .derivative = decay_until, .ctx = &how};
        tb_integrator_def def = adaptive_def(TB_METHOD_CVODE_BDF, 1e-6);
        switch (i) {
        case 0:
            def.rtol = 0.0;
            break;
        case 1:
            def.atol = -1.0;
            break;
        case 2:
            def.atol_vector = atol;
            break;
        case 3:
            def.max_order = 6;
            break;
        case 4:
            def.max_steps = 0;
            break;
        case 5:
            def.linear_solver = (tb_linear_solver)7;
            break;
        case 6:
            def.preconditioner_half_bandwidth = 2;
            break;
        case 7:
            def.max_step = -1.0;
            break;
        case 8:
            def.rtol = NAN;
            break;
        case 9:
            def.atol = INFINITY;
            break;
        default:
            def.initial_step = NAN;
            break;
        }
        tb_integrator *integrator = NULL;
        tb_error error;
        const tb_status status = tb_integrator_create(&system, &def, 0.0, y, &integrator, &error);
        print_message("%-16s -> %s: %s\n", cases[i].label, tb_status_name(status), error.message);
        assert_int_equal(status, cases[i].expected);
        assert_null(integrator);
        assert_non_null(strstr(error.message, cases[i].field));
    }
}

/* BDF on a scene of 20 bodies (260 unknowns) with the Krylov solver and the banded
 * preconditioner, and with the dense solver: every body is a torque-free top with its own
 * spin, so each must follow its own Jacobi solution to the bound of the single-top test,
 * 10 N rtol |omega0|. Gravity moves the centres of mass but exerts no torque. */
static void test_krylov_and_dense_bdf_follow_twenty_jacobi_tops(void **state)
{
    (void)state;
    enum { BODIES = 20 };
    torque_free_top exact[BODIES];
    for (int solver = 0; solver < 2; ++solver) {
        tb_scene_def scene_def = tb_scene_def_default();
        tb_scene *scene = NULL;
        assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
        for (int k = 0; k < BODIES; ++k) {
            const double spin = 1.0 + 0.05 * k;
            const double omega[3] = {1.5 * spin, 0.0, spin};
            torque_free_top_init(&exact[k], test_top_moments, omega[0], omega[2]);
            tb_body_def def = tb_body_def_default();
            const double I[9] = {1, 0, 0, 0, 2, 0, 0, 0, 3};
            assert_int_equal(tb_mass_from_tensor(1.0, (double[]){0, 0, 0}, I, &def.mass, NULL),
                             TB_STATUS_OK);
            def.position[0] = k;
            def.velocity[2] = 5.0;
            memcpy(def.angular_velocity, omega, sizeof omega); /* identity orientation */
            assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
        }
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
        const double rtol = 1e-8, T = 5.0;
        tb_integrator_def def = adaptive_def(TB_METHOD_CVODE_BDF, rtol);
        def.linear_solver = solver == 0 ? TB_LINEAR_SOLVER_DENSE : TB_LINEAR_SOLVER_KRYLOV;
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, T), TB_STATUS_OK);
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        double worst = 0.0;
        for (int k = 0; k < BODIES; ++k) {
            double w[3], w_exact[3];
            test_body_omega(scene, (size_t)k, w);
            torque_free_top_omega(&exact[k], T, w_exact);
            for (int i = 0; i < 3; ++i) {
                worst = fmax(worst, fabs(w[i] - w_exact[i]) / (1.0 + 0.05 * k));
            }
        }
        const double bound = (double)stats.steps * rtol * omega0_norm;
        print_message("%s: %ld steps, %ld derivatives (%ld for the Jacobian), %ld Krylov "
                      "iterations; worst error %.2e = %.2f N rtol |omega0|\n",
                      solver == 0 ? "dense " : "Krylov", stats.steps, stats.derivative_evals,
                      stats.jacobian_derivative_evals, stats.linear_iterations, worst,
                      worst / bound);
        assert_true(worst <= 10.0 * bound);
        if (solver == 1) {
            assert_true(stats.linear_iterations > 0);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* x' = v, v' = -x, recording the range of times the derivative is called at. */
typedef struct clock_range {
    double first, last;
} clock_range;

static int harmonic_clocked(double t, const double *y, double *dydt, void *ctx)
{
    clock_range *range = ctx;
    range->first = fmin(range->first, t);
    range->last = fmax(range->last, t);
    dydt[0] = y[1];
    dydt[1] = -y[0];
    return 0;
}

/* Near t = 1e17 doubles are 16 apart, and CVODE's first step from there did not move t
 * (SOLVER_FAILED "tout too close to t0"). CVODE now counts time from the start; the solution
 * is cos and -sin of the elapsed time (64 s: 1e-5 is 10x the N rtol bound at rtol 1e-9), and
 * the derivative still sees the system's own times. */
static void test_cvode_starts_at_any_finite_time(void **state)
{
    (void)state;
    const double t0 = 1e17;
    for (int m = 0; m < 2; ++m) {
        double y[2] = {1.0, 0.0};
        clock_range range = {INFINITY, -INFINITY};
        tb_ode_system system = {.n = 2, .derivative = harmonic_clocked, .ctx = &range};
        tb_integrator_def def = adaptive_def(adaptive[m], 1e-9);
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_integrator_create(&system, &def, t0, y, &integrator, NULL),
                         TB_STATUS_OK);
        for (int k = 1; k <= 4; ++k) { /* t0 + 16 k is exact */
            const tb_status status = tb_integrator_advance(integrator, t0 + 16.0 * k);
            assert_int_equal(status, TB_STATUS_OK);
            assert_true(tb_integrator_time(integrator) == t0 + 16.0 * k);
        }
        print_message("%s from t0 = 1e17: x %.9f (cos 64 = %.9f)\n", tb_method_name(adaptive[m]),
                      y[0], cos(64.0));
        assert_near(y[0], cos(64.0), 1e-5);
        assert_near(y[1], -sin(64.0), 1e-5);
        assert_true(range.first >= t0 && range.last <= t0 + 16.0 * 5);
        tb_integrator_destroy(integrator);
    }
}

/* A hook that spoils the output (NaN) on a chosen call, like a renormalisation of a zero
 * quaternion. */
static int spoiling_hook(double t, double *y, void *ctx)
{
    (void)t;
    int *calls_left = ctx;
    if (--*calls_left == 0) {
        y[1] = NAN;
    }
    return 0;
}

static int harmonic_plain(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = y[1];
    dydt[1] = -y[0];
    return 0;
}

/* Before: OK with y[1] = NaN. Now STATE_NOT_FINITE, y and time at the last good output, and
 * the next advance restarts from there to the right answer (tolerance as above). */
static void test_a_non_finite_output_is_refused_and_the_last_good_one_kept(void **state)
{
    (void)state;
    int calls_left = 3;
    double y[2] = {1.0, 0.0};
    tb_ode_system system = {
        .n = 2, .derivative = harmonic_plain, .post_step = spoiling_hook, .ctx = &calls_left};
    tb_integrator_def def = adaptive_def(TB_METHOD_CVODE_ADAMS, 1e-9);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double kept[2] = {y[0], y[1]};
    assert_int_equal(tb_integrator_advance(integrator, 1.5), TB_STATUS_STATE_NOT_FINITE);
    print_message("%s\n", tb_integrator_detail(integrator));
    assert_non_null(strstr(tb_integrator_detail(integrator), "y[1] became nan"));
    assert_true(tb_integrator_time(integrator) == 1.0);
    assert_memory_equal(y, kept, sizeof kept);
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
    assert_near(y[0], cos(2.0), 1e-6);
    assert_near(y[1], -sin(2.0), 1e-6);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    assert_int_equal(stats.reinitializations, 1);
    tb_integrator_destroy(integrator);
}

/* y' = slope, with a generation that moves when the slope is changed. */
typedef struct changing_slope {
    double slope;
    unsigned long long generation;
} changing_slope;

static int slope_derivative(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)y;
    dydt[0] = ((const changing_slope *)ctx)->slope;
    return 0;
}

static unsigned long long slope_generation(void *ctx)
{
    return ((const changing_slope *)ctx)->generation;
}

/* CVODE steps past the output time and interpolates, so after the slope changes at t = 1 the
 * next output came from the old right-hand side (y(2) = 2 instead of 1 + 3 = 4). With
 * rhs_generation it restarts; y is linear, so both methods are exact to round-off (1e-9 covers
 * rtol 1e-10 on |y| <= 4). */
static void test_a_changed_right_hand_side_restarts_cvode(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        changing_slope ctx = {1.0, 0};
        double y[1] = {0.0};
        tb_ode_system system = {.n = 1,
                                .derivative = slope_derivative,
                                .ctx = &ctx,
                                .lifetime.rhs_generation = slope_generation};
        tb_integrator_def def = adaptive_def(adaptive[m], 1e-10);
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
        assert_near(y[0], 1.0, 1e-9);
        ctx.slope = 3.0;
        ctx.generation++;
        assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
        assert_near(y[0], 4.0, 1e-9);
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        assert_int_equal(stats.reinitializations, 1);
        tb_integrator_destroy(integrator);
    }
}

/* y0' = -1000 y0, y1' = 1000 y0 - y1 from (1, 0): y0 = e^-1000t, y1 = 1000/999 (e^-t -
 * e^-1000t). Its Jacobian, given as a sparse matrix whose pattern alternates between the lower
 * triangle and the full 2 x 2 (an explicit zero at (0, 1)), so that KLU analyses anew. */
static int two_rates(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = -1000.0 * y[0];
    dydt[1] = 1000.0 * y[0] - y[1];
    return 0;
}

static size_t two_rates_capacity(double t, const double *y, void *ctx)
{
    (void)t, (void)y, (void)ctx;
    return 4;
}

static int two_rates_jacobian(double t, const double *y, const double *fy, tb_ode_sparse *J,
                              void *ctx)
{
    (void)t, (void)y, (void)fy;
    long *evaluations = ctx;
    const int full = (int)(++*evaluations % 2);
    const size_t starts[3] = {0, full ? 2 : 1, full ? 4 : 3};
    const size_t columns[4] = {0, 1, 0, 1};
    const double values[4] = {-1000.0, 0.0, 1000.0, -1.0};
    memcpy(J->row_starts, starts, sizeof starts);
    J->columns[0] = 0, J->values[0] = -1000.0;
    for (size_t e = 1; e < starts[2]; ++e) {
        J->columns[e] = columns[e + !full];
        J->values[e] = values[e + !full];
    }
    return 0;
}

/* With rtol 1e-8 each step's error is below 1e-8 of the solution; on these decaying modes the
 * errors do not grow, and 1e-5 of y1 leaves room for their sum over the ~1e3 steps. */
static void test_bdf_with_a_sparse_jacobian_follows_two_decay_rates(void **state)
{
    (void)state;
    long evaluations = 0;
    double y[2] = {1.0, 0.0};
    tb_ode_system system = {.n = 2, .derivative = two_rates, .ctx = &evaluations};
    system.jacobian.capacity = two_rates_capacity;
    system.jacobian.evaluate = two_rates_jacobian;
    tb_integrator_def def = adaptive_def(TB_METHOD_CVODE_BDF, 1e-8);
    def.linear_solver = TB_LINEAR_SOLVER_SPARSE;
    tb_integrator *integrator = NULL;
    tb_error error;
    const tb_status created = tb_integrator_create(&system, &def, 0.0, y, &integrator, &error);
    if (created == TB_STATUS_UNSUPPORTED) { /* built without KLU: the refusal names it */
        assert_non_null(strstr(error.message, "KLU"));
        return;
    }
    assert_int_equal(created, TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double y1 = 1000.0 / 999.0 * (exp(-1.0) - exp(-1000.0));
    assert_true(fabs(y[1] - y1) <= 1e-5 * y1);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    assert_true(stats.jacobian_evals >= 2 && evaluations == stats.jacobian_evals);
    tb_integrator_destroy(integrator);
    /* without the system's Jacobian the sparse solver is refused, naming the setting */
    system.jacobian = (tb_ode_jacobian){0};
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.linear_solver"));
    assert_null(integrator);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_torque_free_top_matches_jacobi_with_adams_and_bdf),
        cmocka_unit_test(test_tightening_rtol_100x_cuts_the_error_at_least_10x),
        cmocka_unit_test(test_adams_and_bdf_agree_with_small_step_rk4),
        cmocka_unit_test(test_bdf_integrates_a_stiff_spring_that_rk4_at_equal_cost_cannot),
        cmocka_unit_test(test_frame_rate_does_not_change_the_solution),
        cmocka_unit_test(test_quaternions_are_unit_on_output_and_drift_stays_within_tolerance),
        cmocka_unit_test(test_changing_the_state_between_frames_restarts_cvode),
        cmocka_unit_test(test_failures_name_the_cvode_flag_and_keep_the_last_good_state),
        cmocka_unit_test(test_invalid_adaptive_settings_are_rejected),
        cmocka_unit_test(test_krylov_and_dense_bdf_follow_twenty_jacobi_tops),
        cmocka_unit_test(test_cvode_starts_at_any_finite_time),
        cmocka_unit_test(test_a_non_finite_output_is_refused_and_the_last_good_one_kept),
        cmocka_unit_test(test_a_changed_right_hand_side_restarts_cvode),
        cmocka_unit_test(test_bdf_with_a_sparse_jacobian_follows_two_decay_rates),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
