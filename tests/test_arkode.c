/* ark-imex (SUNDIALS ARKODE's ARKStep) against exact solutions, on a stiff spring beside
 * cvode-adams, at a contact onset's analytic time, on resting boxes, and beside cvode-bdf on a
 * contact trajectory. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* --- a generic system: the harmonic oscillator x'' = -x --------------------------------- */

static int oscillator(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = y[1];
    dydt[1] = -y[0];
    return 0;
}

static tb_integrator_def ark_def(double rtol)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_ARK_IMEX;
    def.rtol = rtol;
    return def;
}

/* |y(t) - (cos t, -sin t)| after integrating from (1, 0) to t = 10 (a bit over 1.5 periods). */
static double oscillator_error(double rtol, long *steps)
{
    tb_ode_system system = {.n = 2, .derivative = oscillator};
    double y[2] = {1.0, 0.0};
    const tb_integrator_def def = ark_def(rtol);
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 10.0), TB_STATUS_OK);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    *steps = stats.steps;
    tb_integrator_destroy(integrator);
    return hypot(y[0] - cos(10.0), y[1] + sin(10.0));
}

/* Local error control bounds each step's error by about rtol |y| (|y| = 1 here), and the errors
 * of N steps add up, so the global error must stay below 10 N rtol (the 10 leaves room for
 * their growth along the orbit); and asking for 100x less must give at least 10x less (an order
 * 4 method with error per unit step h^4 gains 100^(4/5) = 40x; measured 39x, 54x, 128x). */
static void test_oscillator_error_follows_rtol(void **state)
{
    (void)state;
    double previous = INFINITY;
    for (double rtol = 1e-4; rtol >= 1e-10; rtol *= 1e-2) {
        long steps = 0;
        const double error = oscillator_error(rtol, &steps);
        print_message("ark-imex rtol %.0e: error %.2e, %ld steps, error / (N rtol) %.3f\n", rtol,
                      error, steps, error / ((double)steps * rtol));
        assert_true(error <= 10.0 * (double)steps * rtol);
        assert_true(error * 10.0 <= previous);
        previous = error;
    }
}

/* --- a stiff spring: a slow decay beside a fast, heavily damped spring ------------------ */

/* y0' = -y0 (slow, taken explicitly with the split); x'' = -K x - C x' with K = 1e6 s^-2 and
 * C = 2.02e3 s^-1 (overdamped: modes -868 and -1152 s^-1, decayed in a few milliseconds). After
 * them the fast spring is at rest and only its stability limits an explicit method's step:
 * Adams' stable |h lambda| is below about 2 at every order, so h < 2e-3 s and thousands of steps
 * over 10 s, where an implicit method's step follows the slow decay. */
#define STIFF_K 1e6
#define STIFF_C 2.02e3

static int stiff(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = -y[0];
    dydt[1] = y[2];
    dydt[2] = -STIFF_K * y[1] - STIFF_C * y[2];
    return 0;
}

static int stiff_explicit(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = -y[0];
    dydt[1] = dydt[2] = 0.0;
    return 0;
}

static long stiff_steps(tb_method method, bool split, double *slow_error)
{
    tb_ode_system system = {.n = 3, .derivative = stiff};
    system.split.explicit_part = split ? stiff_explicit : NULL;
    double y[3] = {1.0, 1e-3, 0.0};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.rtol = 1e-6;
    def.atol = 1e-9;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 10.0), TB_STATUS_OK);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    tb_integrator_destroy(integrator);
    *slow_error = fabs(y[0] - exp(-10.0)) / exp(-10.0);
    print_message("%-11s%s: %6ld steps, %7ld derivatives, slow part's relative error %.1e\n",
                  tb_method_name(method), split ? " (split)" : "        ", stats.steps,
                  stats.derivative_evals, *slow_error);
    return stats.steps;
}

/* ark-imex must take at least 10x fewer steps than cvode-adams (measured: 50x, 114x with the
 * split), with the split (the slow decay explicit) and without, and keep the slow part's relative
 * error at t = 10 (where y0 = e^-10) within 1e-3: the global error of about 100 steps at rtol 1e-6
 * relative to a component that shrank by e^10 while atol stayed 1e-9 = 2e-5 y0(10). */
static void test_a_stiff_spring_costs_ark_imex_far_fewer_steps_than_adams(void **state)
{
    (void)state;
    double error = 0.0;
    const long adams = stiff_steps(TB_METHOD_CVODE_ADAMS, false, &error);
    for (int split = 0; split < 2; ++split) {
        const long ark = stiff_steps(TB_METHOD_ARK_IMEX, split != 0, &error);
        assert_true(10 * ark <= adams);
        assert_true(error < 1e-3);
    }
}

/* --- scenes --------------------------------------------------------------------------- */

static tb_scene *load(const char *json)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    const tb_status status = tb_scene_load_string(json, "test", NULL, &scene, &run, &error);
    if (status != TB_STATUS_OK) {
        print_error("%s\n", error.message);
    }
    assert_int_equal(status, TB_STATUS_OK);
    return scene;
}

static tb_integrator *scene_integrator(tb_scene *scene, tb_method method, double rtol,
                                       tb_linear_solver solver)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.rtol = rtol;
    def.linear_solver = method == TB_METHOD_CVODE_ADAMS ? TB_LINEAR_SOLVER_AUTO : solver;
    tb_integrator *integrator = NULL;
    const tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    if (status == TB_STATUS_UNSUPPORTED && solver == TB_LINEAR_SOLVER_SPARSE) {
        tb_scene_destroy(scene);
        skip(); /* built without KLU, as test_contact_jacobian skips */
    }
    if (status != TB_STATUS_OK) {
        print_error("%s\n", tb_scene_detail(scene));
    }
    assert_int_equal(status, TB_STATUS_OK);
    return integrator;
}

/* A ball of radius 0.1 m dropped from rest with its centre at 1.1 m under g = 9.81 m/s^2 (the
 * gravity effect's default) touches the ground when z - r = 0: t = sqrt(2 * 1 m / g). The gap
 * is a root function; ARKStep locates its sign change on its interpolant, whose error at
 * rtol 1e-8 is about 1e-8 of the state: the onset time must be within 1e-6 s. The call is
 * advanced to 0.2 s, restarted there (tb_integrator_reset) and stepped until the first event
 * (measured: 2e-16 s off). */
static void test_a_dropped_ball_touches_the_ground_at_the_analytic_time(void **state)
{
    (void)state;
    tb_scene *scene = load("{\"bodies\": [{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", "
                           "\"radius\": 0.1}, \"mass\": 1, \"position\": [0, 0, 1.1]}],"
                           " \"effects\": [{\"type\": \"gravity\"}, {\"type\": \"ground\"}]}");
    const double exact = sqrt(2.0 / 9.81);
    tb_integrator_events events;
    tb_integrator *integrator =
        scene_integrator(scene, TB_METHOD_ARK_IMEX, 1e-8, TB_LINEAR_SOLVER_AUTO);
    /* a restart on the way keeps the roots and the counts (ARKStepReInit zeroes ARKStep's) */
    assert_int_equal(tb_integrator_advance(integrator, 0.2), TB_STATUS_OK);
    tb_integrator_stats before, after;
    tb_integrator_get_stats(integrator, &before);
    assert_int_equal(tb_integrator_reset(integrator, 0.2), TB_STATUS_OK);
    tb_integrator_get_stats(integrator, &after);
    assert_int_equal(after.steps, before.steps);
    assert_int_equal(after.reinitializations, before.reinitializations + 1);
    while (tb_integrator_get_events(integrator, &events) == TB_STATUS_OK && events.count == 0) {
        assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
    }
    print_message("first event at %.12f s (%+.1e s)\n", events.last_time, events.last_time - exact);
    assert_true(fabs(events.last_time - exact) < 1e-6);
    assert_int_equal(events.last_direction, -1); /* the gap fell through zero */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* count boxes of 0.1 m and 1 kg in a column on the ground, each resting on the one below (the
 * static deflection of the contacts left out: they settle by a few micrometres). Sleeping off,
 * so the bodies are stepped to the end. */
static tb_scene *column(int count)
{
    char json[4096];
    size_t used = (size_t)snprintf(json, sizeof json, "{\"sleeping\": false, \"bodies\": [");
    for (int i = 0; i < count; ++i) {
        used += (size_t)snprintf(json + used, sizeof json - used,
                                 "%s{\"name\": \"box%d\", \"shape\": {\"type\": \"box\", \"size\": "
                                 "[0.1, 0.1, 0.1]}, \"mass\": 1, \"position\": [0, 0, %.17g]}",
                                 i > 0 ? ", " : "", i, 0.05 + 0.1 * i);
    }
    snprintf(json + used, sizeof json - used,
             "], \"effects\": [{\"type\": \"gravity\"}, {\"type\": \"ground\"}%s]}",
             count > 1 ? ", {\"type\": \"contact\"}" : "");
    return load(json);
}

/* The fastest body's speed (m/s; 1 kg bodies: momentum is velocity). */
static double fastest(tb_scene *scene, size_t count)
{
    const double *y = tb_scene_states(scene);
    double fastest = 0.0;
    for (size_t i = 0; i < count; ++i) {
        const double *P = y + TB_STATE_SIZE * i + TB_STATE_P;
        fastest = fmax(fastest, sqrt(P[0] * P[0] + P[1] * P[1] + P[2] * P[2]));
    }
    return fastest;
}

/* A box and a column of ten on the ground, at rest, stepped for 2 s (sleeping off) with the
 * contacts' sparse Jacobian: they must settle to speeds under 1e-6 m/s over the last second
 * (creep: the contact's damping takes out the settling of the first milliseconds, and nothing
 * drives a motion after; measured 5.2e-9 and 4.1e-7 m/s) and an implicit method must not pay the
 * contact's 3500 rad/s mode: fewer than 2000 steps (RK4's stable step for it is 0.8 ms, 2500
 * steps in 2 s; measured 80 and 722). */
static void test_resting_boxes_stay_still_in_few_steps(void **state)
{
    (void)state;
    const int counts[2] = {1, 10};
    for (int c = 0; c < 2; ++c) {
        tb_scene *scene = column(counts[c]);
        tb_integrator *integrator =
            scene_integrator(scene, TB_METHOD_ARK_IMEX, 1e-6, TB_LINEAR_SOLVER_SPARSE);
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
        double creep = 0.0;
        for (int k = 1; k <= 10; ++k) {
            assert_int_equal(tb_integrator_advance(integrator, 1.0 + 0.1 * k), TB_STATUS_OK);
            creep = fmax(creep, fastest(scene, (size_t)counts[c]));
        }
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        print_message("%2d box%s: %5ld steps (%ld failed), %ld Jacobians, creep %.1e m/s\n",
                      counts[c], counts[c] > 1 ? "es" : "  ", stats.steps, stats.failed_steps,
                      stats.jacobian_evals, creep);
        assert_true(creep < 1e-6);
        assert_true(stats.steps < 2000);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* ark-imex and cvode-bdf, both at rtol 1e-8 with the sparse Jacobian, on a contact trajectory
 * of duration seconds: the largest difference of the bodies' positions (m). */
static double apart_from_bdf(const char *json, double duration)
{
    double end[2][2 * TB_STATE_SIZE];
    const tb_method methods[2] = {TB_METHOD_ARK_IMEX, TB_METHOD_CVODE_BDF};
    for (int m = 0; m < 2; ++m) {
        tb_scene *scene = load(json);
        tb_integrator *integrator =
            scene_integrator(scene, methods[m], 1e-8, TB_LINEAR_SOLVER_SPARSE);
        const tb_status status = tb_integrator_advance(integrator, duration);
        if (status != TB_STATUS_OK) {
            print_error("%s\n", tb_integrator_detail(integrator));
        }
        assert_int_equal(status, TB_STATUS_OK);
        tb_integrator_stats stats;
        tb_integrator_get_stats(integrator, &stats);
        print_message("%-9s: %5ld steps, %5ld failed\n", tb_method_name(methods[m]), stats.steps,
                      stats.failed_steps);
        memcpy(end[m], tb_scene_states(scene), sizeof end[m]);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
    double apart = 0.0;
    for (int b = 0; b < 2; ++b) {
        for (int k = 0; k < 3; ++k) {
            const int i = TB_STATE_SIZE * b + TB_STATE_X + k;
            apart = fmax(apart, fabs(end[0][i] - end[1][i]));
        }
    }
    print_message("positions apart by %.2e m\n", apart);
    return apart;
}

/* Two contact trajectories: a ball (radius 0.1 m) dropped from 0.3 m onto the ground, spinning
 * about a horizontal axis (0.5 s: fall, impact, bounce with friction), and a box dropped 2 cm
 * onto another resting on the ground, tilted 2 degrees (0.3 s: impact, bounce, settling).
 * ark-imex and cvode-bdf must agree within 1e-5 m on every position: each method's global error
 * is of order steps x rtol x |x| (a few thousand steps, 1e-8, 0.3 m: about 1e-5 m at worst), the
 * impacts magnifying a difference; measured 6.7e-9 and 1.0e-9 m. */
static void test_ark_imex_agrees_with_bdf_on_contact_trajectories(void **state)
{
    (void)state;
    const char *ball =
        "{\"bodies\": [{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, "
        "\"mass\": 1, \"position\": [0, 0, 0.3], \"angular_velocity\": [5, 0, 0]}, {\"name\": "
        "\"other\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1, "
        "\"position\": [1, 0, 0.1]}], \"effects\": [{\"type\": \"gravity\"}, {\"type\": "
        "\"ground\"}, {\"type\": \"contact\"}]}";
    const char *boxes =
        "{\"bodies\": [{\"name\": \"lower\", \"shape\": {\"type\": \"box\", \"size\": [0.1, "
        "0.1, 0.1]}, \"mass\": 1, \"position\": [0, 0, 0.05]}, {\"name\": \"upper\", \"shape\": "
        "{\"type\": \"box\", \"size\": [0.1, 0.1, 0.1]}, \"mass\": 1, \"position\": [0.01, 0, "
        "0.17], \"orientation\": [0.9998476951563913, 0.01745240643728351, 0, 0]}], "
        "\"effects\": [{\"type\": \"gravity\"}, {\"type\": \"ground\"}, {\"type\": "
        "\"contact\"}]}";
    assert_true(apart_from_bdf(ball, 0.5) < 1e-5);
    assert_true(apart_from_bdf(boxes, 0.3) < 1e-5);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_oscillator_error_follows_rtol),
        cmocka_unit_test(test_a_stiff_spring_costs_ark_imex_far_fewer_steps_than_adams),
        cmocka_unit_test(test_a_dropped_ball_touches_the_ground_at_the_analytic_time),
        cmocka_unit_test(test_resting_boxes_stay_still_in_few_steps),
        cmocka_unit_test(test_ark_imex_agrees_with_bdf_on_contact_trajectories),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
