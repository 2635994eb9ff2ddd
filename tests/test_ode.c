/* The generic ODE layer on problems with known solutions, and its failure behaviour. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "tumble/ode.h"

/* Euler, midpoint and RK4: the fixed-step methods come first in tb_method. */
#define FIXED_STEP_METHODS (TB_METHOD_RK4 + 1)

#include <limits.h>
#include <math.h>
#include <string.h>

/* x' = v, v' = -x: x = cos t, v = -sin t from (1, 0). */
static int harmonic(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = y[1];
    dydt[1] = -y[0];
    return 0;
}

static double harmonic_error(tb_method method, double dt, double T)
{
    double y[2] = {1.0, 0.0};
    tb_ode_system system = {.n = 2, .derivative = harmonic};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = dt;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, T), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    return fmax(fabs(y[0] - cos(T)), fabs(y[1] + sin(T)));
}

/* Halving h divides the global error by 2^p. Measured over two halvings in the asymptotic
 * range (errors 1e-2 .. 1e-11, far above round-off); 10% slack covers the higher-order terms
 * still present at these step sizes. */
static void test_steppers_converge_at_their_classical_orders(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        const int order = tb_method_order((tb_method)m);
        double previous = harmonic_error((tb_method)m, 0.05, 2.0);
        for (int k = 1; k <= 2; ++k) {
            const double error = harmonic_error((tb_method)m, 0.05 / (1 << k), 2.0);
            const double measured = log2(previous / error);
            print_message("%-8s h = %-8g error %.3e  order %.3f\n", tb_method_name((tb_method)m),
                          0.05 / (1 << k), error, measured);
            assert_true(fabs(measured - order) <= 0.1 * order);
            previous = error;
        }
    }
}

/* y' = 1: y equals t exactly at every step, so landing is checked to the last bit. */
static int unit_slope(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)y;
    (void)ctx;
    dydt[0] = 1.0;
    return 0;
}

static void test_advance_lands_exactly_on_the_target_without_a_sliver_step(void **state)
{
    (void)state;
    double y[1] = {0.0};
    tb_ode_system system = {.n = 1, .derivative = unit_slope};
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.1; /* 0.1 is not a binary fraction: ten steps do not sum to 1.0 exactly */
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    assert_int_equal(stats.steps, 10);
    assert_true(tb_integrator_time(integrator) == 1.0);
    assert_near(y[0], 1.0, 1e-15);

    assert_int_equal(tb_integrator_advance(integrator, 1.25), TB_STATUS_OK);
    tb_integrator_get_stats(integrator, &stats);
    assert_int_equal(stats.steps, 13); /* 0.1, 0.1, then a shortened 0.05 */
    assert_near(stats.last_step, 0.05, 1e-15);
    assert_true(tb_integrator_time(integrator) == 1.25);
    assert_int_equal(stats.derivative_evals, 13 * 4);

    /* Advancing to the current time is a no-op; going back is an error. */
    assert_int_equal(tb_integrator_advance(integrator, 1.25), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_integrator_detail(integrator), "t_target"));
    tb_integrator_destroy(integrator);
}

/* A derivative that refuses to be evaluated past t = 0.35. */
static int fails_after(double t, const double *y, double *dydt, void *ctx)
{
    (void)y;
    (void)ctx;
    dydt[0] = 1.0;
    return t > 0.35 ? 7 : 0;
}

static void test_derivative_error_keeps_the_last_good_state(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        double y[1] = {0.0};
        tb_ode_system system = {.n = 1, .derivative = fails_after};
        tb_integrator_def def = tb_integrator_def_default();
        def.method = (tb_method)m;
        def.dt = 0.1;
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_DERIVATIVE_FAILED);
        /* Euler evaluates at step starts only, so it fails in the step from 0.4; midpoint and
         * RK4 evaluate at t + h/2 and fail in the step from 0.3. */
        const double last_good = m == TB_METHOD_EULER ? 0.4 : 0.3;
        assert_near(tb_integrator_time(integrator), last_good, 1e-15);
        assert_near(y[0], last_good, 1e-15);
        assert_non_null(strstr(tb_integrator_detail(integrator), "returned 7"));
        tb_integrator_destroy(integrator);
    }
}

typedef struct hook_log {
    int calls;
    int fail_on_call;
} hook_log;

/* Counts calls; fails on the requested call. */
static int counting_hook(double t, double *y, void *ctx)
{
    (void)t;
    (void)y;
    hook_log *log = ctx;
    return ++log->calls == log->fail_on_call ? 5 : 0;
}

static void test_post_step_hook_runs_once_per_step_and_can_stop_the_run(void **state)
{
    (void)state;
    hook_log log = {0, 0};
    double y[1] = {0.0};
    tb_ode_system system = {
        .n = 1, .derivative = unit_slope, .post_step = counting_hook, .ctx = &log};
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.25;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(log.calls, 4);

    log.fail_on_call = 6;
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_HOOK_FAILED);
    assert_near(tb_integrator_time(integrator), 1.25, 1e-15);
    assert_near(y[0], 1.25, 1e-15);
    tb_integrator_destroy(integrator);
}

/* y' = 1 except on (1, 2), where y' = 0 and the system says it rests until 2 (from where it
 * is, whatever y): the fixed-step methods take the steps up to 1 and from 2, jump over the rest
 * with one post-step call at its end, and land on y = 2 at t = 3 exactly (the slope is constant on
 * every step). A hook that fails at the jump's end leaves time and state where the rest began;
 * max_steps does not count a rest (a call at rest all the way is not refused). */
static int slope_but_rest(double t, const double *y, double *dydt, void *ctx)
{
    (void)y;
    (void)ctx;
    dydt[0] = t > 1.0 && t < 2.0 ? 0.0 : 1.0; /* stages at 1 and 2 see the slope */
    return 0;
}

static double rests_until_two(double t, const double *y, void *ctx)
{
    (void)y;
    (void)ctx;
    return t >= 1.0 && t < 2.0 ? 2.0 : t;
}

/* The resting system with the counting hook, stepped by method at dt 0.25 from y at t = 0. */
static tb_integrator *resting_integrator(tb_method method, hook_log *log, long max_steps, double *y)
{
    tb_ode_system system = {.n = 1,
                            .derivative = slope_but_rest,
                            .post_step = counting_hook,
                            .ctx = log,
                            .events.rest_until = rests_until_two};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = 0.25;
    def.max_steps = max_steps > 0 ? max_steps : def.max_steps;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    return integrator;
}

/* y' = 1 with a break one ulp after every time (next_break): each fixed step was cut at the
 * break and only steps on the grid counted against max_steps, so an advance of 10 steps of 0.1
 * under max_steps = 1000 stepped an ulp at a time for ever. Steps cut short have a budget of
 * max_steps as well: the advance stops with TB_STATUS_TOO_MANY_STEPS after exactly max_steps of
 * them, at t = max_steps ulps, y that of the last good step. A derivative that counts past 1e6
 * calls fails the call instead, so the test fails rather than hangs without the budget. */
static long ulp_break_calls;

static int unit_rate(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)y;
    (void)ctx;
    dydt[0] = 1.0;
    return ++ulp_break_calls > 1000000 ? -1 : 0;
}

static double break_an_ulp_later(double t, void *ctx)
{
    (void)ctx;
    return nextafter(t, INFINITY);
}

static void test_steps_cut_at_breaks_are_held_to_max_steps(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                 TB_METHOD_ROSENBROCK};
    for (size_t m = 0; m < sizeof methods / sizeof methods[0]; ++m) {
        double y[1] = {0.0};
        tb_ode_system system = {.n = 1, .derivative = unit_rate};
        system.events.next_break = break_an_ulp_later;
        tb_integrator_def def = tb_integrator_def_default();
        def.method = methods[m];
        def.dt = 0.1;
        def.max_steps = 1000;
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL),
                         TB_STATUS_OK);
        ulp_break_calls = 0;
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_TOO_MANY_STEPS);
        assert_non_null(strstr(tb_integrator_detail(integrator), "1000 cut short at breaks"));
        tb_integrator_stats stats;
        assert_int_equal(tb_integrator_get_stats(integrator, &stats), TB_STATUS_OK);
        assert_int_equal(stats.steps, 1000);
        assert_true(tb_integrator_time(integrator) == 1000 * nextafter(0.0, 1.0));
        /* y' = 1 over steps one subnormal ulp long: y is t to their rounding (RK4's h / 6
         * rounds to 0 there), a finite state between 0 and 2 t */
        assert_true(y[0] >= 0.0 && y[0] <= 2.0 * tb_integrator_time(integrator));
        tb_integrator_destroy(integrator);
    }
}

/* A system's check_break or check_reset that refuses without writing a detail (the contract asks
 * for one) left the call's detail empty: a refusal that said nothing. The integrator now names the
 * check, the time and the status. y' = 1 with a break at 0.25 s refused: RK4 at dt 0.1 stops on
 * it, at 0.25 s exactly (the step cut there), y = 0.25 to round-off. */
static double break_at_a_quarter(double t, void *ctx)
{
    (void)ctx;
    return t < 0.25 ? 0.25 : INFINITY;
}

static tb_status refuse_silently(double t, const double *y, void *ctx, char *detail)
{
    (void)y;
    (void)ctx;
    (void)detail;
    return t >= 0.25 ? TB_STATUS_INVALID_ARGUMENT : TB_STATUS_OK;
}

static void test_a_check_that_refuses_without_a_detail_is_named(void **state)
{
    (void)state;
    double y[1] = {0.0};
    tb_ode_system system = {.n = 1, .derivative = unit_rate};
    system.events.next_break = break_at_a_quarter;
    system.events.check_break = refuse_silently;
    system.lifetime.check_reset = refuse_silently;
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_RK4;
    def.dt = 0.1;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    ulp_break_calls = 0;
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_INVALID_ARGUMENT);
    assert_true(tb_integrator_time(integrator) == 0.25);
    assert_true(fabs(y[0] - 0.25) <= 1e-15);
    assert_non_null(
        strstr(tb_integrator_detail(integrator), "events.check_break refused t = 0.25"));
    assert_int_equal(tb_integrator_reset(integrator, 0.5), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(
        strstr(tb_integrator_detail(integrator), "lifetime.check_reset refused t = 0.5"));
    tb_integrator_destroy(integrator);
}

static void test_a_rest_is_jumped_over_without_steps(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        hook_log log = {0, 0};
        double y[1] = {0.0};
        tb_integrator *integrator = resting_integrator((tb_method)m, &log, 0, y);
        assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_OK);
        tb_integrator_stats stats;
        assert_int_equal(tb_integrator_get_stats(integrator, &stats), TB_STATUS_OK);
        assert_true(y[0] == 2.0 && tb_integrator_time(integrator) == 3.0);
        assert_int_equal(stats.steps, 8);
        assert_int_equal(log.calls, 9);
        assert_true(stats.rest_time == 1.0);
        tb_integrator_destroy(integrator);
    }
    /* max_steps bounds the steps a call takes: a call at rest all the way takes none */
    hook_log quiet = {0, 0};
    double z[1] = {0.0};
    tb_integrator *bounded = resting_integrator(TB_METHOD_RK4, &quiet, 2, z);
    assert_int_equal(tb_integrator_advance(bounded, 0.5), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(bounded, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(bounded, 2.0), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(bounded, 3.0), TB_STATUS_TOO_MANY_STEPS);
    assert_true(z[0] == 1.0 && tb_integrator_time(bounded) == 2.0);
    tb_integrator_destroy(bounded);

    hook_log log = {0, 5}; /* the fifth call: the jump's end */
    double y[1] = {0.0};
    tb_integrator *integrator = resting_integrator(TB_METHOD_RK4, &log, 0, y);
    assert_int_equal(tb_integrator_advance(integrator, 3.0), TB_STATUS_HOOK_FAILED);
    assert_true(y[0] == 1.0 && tb_integrator_time(integrator) == 1.0);
    tb_integrator_destroy(integrator);
}

/* y' = y^2 from 1e100: Euler's second step overflows to infinity. */
static int quadratic(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    (void)ctx;
    dydt[0] = y[0] * y[0];
    return 0;
}

static void test_a_state_that_overflows_is_reported_and_not_kept(void **state)
{
    (void)state;
    double y[1] = {1e100};
    tb_ode_system system = {.n = 1, .derivative = quadratic};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_EULER;
    def.dt = 1.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 5.0), TB_STATUS_STATE_NOT_FINITE);
    assert_near(y[0], 1e100 + 1e200, 1e185);
    assert_near(tb_integrator_time(integrator), 1.0, 0.0);
    assert_non_null(strstr(tb_integrator_detail(integrator), "y[0]"));
    tb_integrator_destroy(integrator);
}

typedef struct bad_case {
    const char *label;
    void (*spoil)(tb_ode_system *system, tb_integrator_def *def);
    tb_status expected;
    const char *named;
} bad_case;

static void zero_n(tb_ode_system *s, tb_integrator_def *d)
{
    (void)d, s->n = 0;
}
static void no_derivative(tb_ode_system *s, tb_integrator_def *d)
{
    (void)d, s->derivative = NULL;
}
static void zero_dt(tb_ode_system *s, tb_integrator_def *d)
{
    (void)s, d->dt = 0.0;
}
static void nan_dt(tb_ode_system *s, tb_integrator_def *d)
{
    (void)s, d->dt = NAN;
}
static void bad_method(tb_ode_system *s, tb_integrator_def *d)
{
    (void)s, d->method = 99;
}
static void no_cookie(tb_ode_system *s, tb_integrator_def *d)
{
    (void)s, d->internal_cookie = 0;
}

static int no_block_derivative(double t, const double *y, double *dydt, size_t first, size_t count,
                               void *ctx)
{
    (void)t, (void)y, (void)dydt, (void)first, (void)count, (void)ctx;
    return -1;
}
static int no_hook(double t, double *y, void *ctx)
{
    (void)t, (void)y, (void)ctx;
    return -1;
}
static void block_size_not_dividing_n(tb_ode_system *s, tb_integrator_def *d)
{
    (void)d, s->blocks.size = 3, s->blocks.derivative = no_block_derivative;
}
static void blocks_without_block_derivative(tb_ode_system *s, tb_integrator_def *d)
{
    (void)d, s->blocks.size = 1;
}
static void hook_without_block_hook(tb_ode_system *s, tb_integrator_def *d)
{
    (void)d, s->blocks.size = 1, s->blocks.derivative = no_block_derivative, s->post_step = no_hook;
}

static void test_invalid_definitions_are_rejected_with_the_field_named(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"n = 0", zero_n, TB_STATUS_INVALID_ARGUMENT, "system.n"},
        {"no derivative", no_derivative, TB_STATUS_NULL_POINTER, "system.derivative"},
        {"dt = 0", zero_dt, TB_STATUS_INVALID_ARGUMENT, "def.dt"},
        {"dt = NaN", nan_dt, TB_STATUS_NOT_FINITE, "def.dt"},
        {"method 99", bad_method, TB_STATUS_INVALID_ARGUMENT, "def.method"},
        {"no cookie", no_cookie, TB_STATUS_INVALID_ARGUMENT, "tb_integrator_def_default"},
        {"block of 3", block_size_not_dividing_n, TB_STATUS_INVALID_ARGUMENT, "system.blocks.size"},
        {"no block f", blocks_without_block_derivative, TB_STATUS_NULL_POINTER,
         "system.blocks.derivative"},
        {"no block hook", hook_without_block_hook, TB_STATUS_NULL_POINTER,
         "system.blocks.post_step"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        double y[2] = {1, 0};
        tb_ode_system system = {.n = 2, .derivative = harmonic};
        tb_integrator_def def = tb_integrator_def_default();
        cases[i].spoil(&system, &def);
        tb_integrator *integrator = (tb_integrator *)&y; /* must be overwritten with NULL */
        tb_error error;
        tb_status status = tb_integrator_create(&system, &def, 0.0, y, &integrator, &error);
        print_message("%-14s -> %s: %s\n", cases[i].label, tb_status_name(status), error.message);
        assert_int_equal(status, cases[i].expected);
        assert_null(integrator);
        assert_non_null(strstr(error.message, cases[i].named));
        assert_near(y[0], 1.0, 0.0);
    }
}

static void test_method_names_round_trip_in_any_case(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        tb_method parsed = TB_METHOD_COUNT;
        assert_int_equal(tb_method_from_name(tb_method_name((tb_method)m), &parsed), TB_STATUS_OK);
        assert_int_equal(parsed, m);
    }
    tb_method parsed = TB_METHOD_COUNT;
    assert_int_equal(tb_method_from_name("RK4", &parsed), TB_STATUS_OK);
    assert_int_equal(parsed, TB_METHOD_RK4);
    assert_int_equal(tb_method_from_name("Cvode-BDF", &parsed), TB_STATUS_OK);
    assert_int_equal(parsed, TB_METHOD_CVODE_BDF);
    assert_int_equal(tb_method_from_name("rk45", &parsed), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_method_from_name("rk", &parsed), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(parsed, TB_METHOD_CVODE_BDF); /* untouched by the failures */
    assert_null(tb_method_name(TB_METHOD_COUNT));
}

static void test_an_unknown_method_name_is_named_with_the_list_of_methods(void **state)
{
    (void)state;
    tb_method parsed = TB_METHOD_COUNT;
    tb_error error;
    assert_int_equal(tb_method_parse("rk5", &parsed, &error), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(error.status, TB_STATUS_INVALID_ARGUMENT);
    assert_string_equal(error.message,
                        "unknown method \"rk5\"; methods: euler, midpoint, rk4, cvode-adams, "
                        "cvode-bdf, rosenbrock, ark-imex");
    assert_int_equal(parsed, TB_METHOD_COUNT);
    /* a NULL argument after that failure leaves no stale message */
    assert_int_equal(tb_method_parse(NULL, &parsed, &error), TB_STATUS_NULL_POINTER);
    assert_non_null(strstr(error.message, "name is NULL"));
    assert_int_equal(tb_method_parse("rk4", NULL, &error), TB_STATUS_NULL_POINTER);
    assert_non_null(strstr(error.message, "out_method is NULL"));
    assert_int_equal(tb_method_parse("euler", &parsed, &error), TB_STATUS_OK);
    assert_string_equal(error.message, "");
}

/* The table's facts that are not stability limits, against the methods' definitions. */
static void test_the_method_table_states_each_methods_kind_and_cost(void **state)
{
    (void)state;
    static const struct {
        int order, adaptive, multistep, evals;
    } expected[TB_METHOD_COUNT] = {
        [TB_METHOD_EULER] = {1, 0, 0, 1},     [TB_METHOD_MIDPOINT] = {2, 0, 0, 2},
        [TB_METHOD_RK4] = {4, 0, 0, 4},       [TB_METHOD_CVODE_ADAMS] = {12, 1, 1, 0},
        [TB_METHOD_CVODE_BDF] = {5, 1, 1, 0}, [TB_METHOD_ROSENBROCK] = {2, 0, 0, 2},
        [TB_METHOD_ARK_IMEX] = {5, 1, 0, 0},
    };
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        tb_method_info info;
        assert_int_equal(tb_method_get_info((tb_method)m, &info), TB_STATUS_OK);
        assert_string_equal(info.name, tb_method_name((tb_method)m));
        assert_int_equal(info.order, expected[m].order);
        assert_int_equal(info.adaptive, expected[m].adaptive);
        assert_int_equal(tb_method_is_adaptive((tb_method)m), expected[m].adaptive);
        assert_int_equal(info.multistep, expected[m].multistep);
        assert_int_equal(info.derivative_evals_per_step, expected[m].evals);
        if (info.adaptive) {
            assert_true(isinf(info.imaginary_limit) && isinf(info.real_limit));
        }
    }
    tb_method_info info = {0};
    assert_int_equal(tb_method_get_info(TB_METHOD_COUNT, &info), TB_STATUS_INVALID_ARGUMENT);
    assert_null(info.name);
    assert_int_equal(tb_method_get_info(TB_METHOD_RK4, NULL), TB_STATUS_NULL_POINTER);
}

/* x' = -w v, v' = w x: an undamped oscillation, the mode lambda = i w. */
static int rotation(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    const double w = *(const double *)ctx;
    dydt[0] = -w * y[1];
    dydt[1] = w * y[0];
    return 0;
}

/* x' = -k x: pure decay, the mode lambda = -k. */
static int decay(double t, const double *y, double *dydt, void *ctx)
{
    (void)t;
    dydt[0] = -*(const double *)ctx * y[0];
    return 0;
}

/* |R(h lambda)| measured as one step of the real stepper with h = 1 on a unit state. */
static double one_step_gain(tb_method method, tb_ode_derivative f, size_t n, double rate)
{
    double y[2] = {1.0, 0.0};
    tb_ode_system system = {.n = n, .derivative = f, .ctx = &rate};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = 1.0;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
    return hypot(y[0], n == 2 ? y[1] : 0.0);
}

/* Each stated limit is where the stepper's gain crosses the stated |R|: at the limit the gain
 * equals it (to 1e-12: the limits are given to 16-17 digits, and a step is a handful of
 * roundings), and 1% past it the gain exceeds it. */
static void
test_stability_limits_are_where_the_steppers_gain_crosses_the_stated_growth(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        tb_method_info info;
        assert_int_equal(tb_method_get_info((tb_method)m, &info), TB_STATUS_OK);
        const double on_imaginary = one_step_gain((tb_method)m, rotation, 2, info.imaginary_limit);
        const double past_imaginary =
            one_step_gain((tb_method)m, rotation, 2, 1.01 * info.imaginary_limit);
        const double on_real = one_step_gain((tb_method)m, decay, 1, info.real_limit);
        const double past_real = one_step_gain((tb_method)m, decay, 1, 1.01 * info.real_limit);
        print_message("%-8s imaginary %.4f gain %.12f, real %.4f gain %.12f\n", info.name,
                      info.imaginary_limit, on_imaginary, info.real_limit, on_real);
        assert_near(on_imaginary, info.imaginary_growth, 1e-12);
        assert_true(past_imaginary > info.imaginary_growth);
        assert_near(on_real, 1.0, 1e-12);
        assert_true(past_real > 1.0);
    }
    tb_method_info euler, rk4;
    tb_method_get_info(TB_METHOD_EULER, &euler);
    tb_method_get_info(TB_METHOD_RK4, &rk4);
    assert_near(euler.imaginary_growth, 1.01, 0.0); /* unstable on the axis: 1% a step */
    assert_near(rk4.imaginary_growth, 1.0, 0.0);    /* stable on a segment of it */
}

/* y' = 1, counting derivative calls: to show a refused advance computed nothing. */
static int counted_slope(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)y;
    ++*(long *)ctx;
    dydt[0] = 1.0;
    return 0;
}

typedef struct slope_run {
    double y[1];
    long calls;
    tb_ode_system system;
    tb_integrator *integrator;
} slope_run;

static void start_slope(slope_run *run, double dt, long max_steps, double t0)
{
    run->y[0] = 0.0;
    run->calls = 0;
    run->system = (tb_ode_system){.n = 1, .derivative = counted_slope, .ctx = &run->calls};
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = dt;
    def.max_steps = max_steps;
    run->integrator = NULL;
    assert_int_equal(tb_integrator_create(&run->system, &def, t0, run->y, &run->integrator, NULL),
                     TB_STATUS_OK);
}

/* Before the budget, dt = 1e-300 to the first frame and one frame 1e9 s away ran for ever. */
static void
test_a_fixed_step_advance_needing_more_than_max_steps_is_refused_before_stepping(void **state)
{
    (void)state;
    slope_run run;
    start_slope(&run, 1e-300, 100000, 0.0);
    assert_int_equal(tb_integrator_advance(run.integrator, 1.0 / 60.0), TB_STATUS_TOO_MANY_STEPS);
    print_message("%s\n", tb_integrator_detail(run.integrator));
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "max_steps = 100000"));
    assert_int_equal(run.calls, 0);
    assert_near(run.y[0], 0.0, 0.0);
    assert_near(tb_integrator_time(run.integrator), 0.0, 0.0);
    tb_integrator_destroy(run.integrator);

    start_slope(&run, 1.0 / 240.0, 100000, 0.0);
    assert_int_equal(tb_integrator_advance(run.integrator, 1e9), TB_STATUS_TOO_MANY_STEPS);
    assert_int_equal(run.calls, 0);
    assert_near(tb_integrator_time(run.integrator), 0.0, 0.0);
    tb_integrator_destroy(run.integrator);

    /* the budget counts steps per call: 10 steps of 0.1 to 1.0 fit in 10, 11 to 2.05 do not */
    start_slope(&run, 0.1, 10, 0.0);
    assert_int_equal(tb_integrator_advance(run.integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(run.integrator, 2.0), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(run.integrator, 3.05), TB_STATUS_TOO_MANY_STEPS);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "max_steps = 10"));
    assert_near(tb_integrator_time(run.integrator), 2.0, 0.0);
    assert_near(run.y[0], 2.0, 1e-14);
    tb_integrator_destroy(run.integrator);
}

/* Near t = 1e15 doubles are 0.125 apart: steps of 1/240 s would not move time. Refused at
 * creation, reset and advance, naming dt and the time; at 1e9 (spacing 1.2e-7) steps work. */
static void test_a_step_that_times_near_t_cannot_resolve_is_refused(void **state)
{
    (void)state;
    double y[1] = {0.0};
    long calls = 0;
    tb_ode_system system = {.n = 1, .derivative = counted_slope, .ctx = &calls};
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    tb_error error;
    assert_int_equal(tb_integrator_create(&system, &def, 1e15, y, &integrator, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    print_message("%s\n", error.message);
    assert_non_null(strstr(error.message, "def.dt: 0.00416667"));
    assert_non_null(strstr(error.message, "t0 = 1000000000000000"));
    assert_null(integrator);

    slope_run run;
    start_slope(&run, 1.0 / 240.0, 100000, 1e9);
    assert_int_equal(tb_integrator_advance(run.integrator, 1e9 + 1.0), TB_STATUS_OK);
    assert_near(run.y[0], 1.0, 1e-6); /* 240 steps; each h is exact to 1.2e-7 s, and so y */
    assert_int_equal(tb_integrator_reset(run.integrator, 1e15), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "t = 1000000000000000"));
    assert_near(tb_integrator_time(run.integrator), 1e9 + 1.0, 0.0);
    tb_integrator_destroy(run.integrator);

    /* dt = 1/8 just below 2^40, where doubles are 2^-13 = dt / 1024 apart: a step may start
     * there but not end past 2^40, where they are twice as far apart */
    start_slope(&run, 0.125, 100000, 0x1p40 - 0.0625);
    assert_int_equal(tb_integrator_step(run.integrator), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "t + dt"));
    assert_int_equal(run.calls, 0);
    assert_true(tb_integrator_time(run.integrator) == 0x1p40 - 0.0625);
    tb_integrator_destroy(run.integrator);

    start_slope(&run, 1.0 / 240.0, LONG_MAX, 0.0);
    assert_int_equal(tb_integrator_advance(run.integrator, 1e15), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "t_target = 1000000000000000"));
    assert_int_equal(run.calls, 0);
    tb_integrator_destroy(run.integrator);
}

/* x' = 1, q' = 1e308 q: from q = 1, Euler at h = 0.5 gives 5e307, then infinity. */
static int overflowing(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = 1.0;
    dydt[1] = 1e308 * y[1];
    return 0;
}

/* Like a scene's renormalisation: fails (1) on a component it cannot normalise. */
static int normalising_hook(double t, double *y, void *ctx)
{
    (void)t, (void)ctx;
    return isfinite(y[1]) ? 0 : 1;
}

/* The step made the state non-finite, and the hook failed on it: the cause is the state
 * (before: HOOK_FAILED, "post-step hook returned 1"). */
static void test_a_hook_failing_on_a_non_finite_state_reports_the_state(void **state)
{
    (void)state;
    double y[2] = {0.0, 1.0};
    tb_ode_system system = {.n = 2, .derivative = overflowing, .post_step = normalising_hook};
    tb_integrator_def def = tb_integrator_def_default();
    def.method = TB_METHOD_EULER;
    def.dt = 0.5;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_STATE_NOT_FINITE);
    const char *detail = tb_integrator_detail(integrator);
    print_message("%s\n", detail);
    assert_non_null(strstr(detail, "y[1] became inf in the euler step from t = 0.5"));
    assert_non_null(strstr(detail, "hook returned 1"));
    assert_near(y[1], 1.0 + 0.5e308, 0.0); /* the last good step's */
    assert_near(tb_integrator_time(integrator), 0.5, 0.0);
    tb_integrator_destroy(integrator);
}

/* A NULL argument after a failure: the message is about the NULL, not the earlier failure. */
static void test_a_null_argument_after_a_failure_leaves_no_stale_detail(void **state)
{
    (void)state;
    slope_run run;
    start_slope(&run, 0.1, 100000, 0.0);
    assert_int_equal(tb_integrator_advance(run.integrator, -1.0), TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "t_target"));
    assert_int_equal(tb_integrator_get_stats(run.integrator, NULL), TB_STATUS_NULL_POINTER);
    assert_string_equal(tb_integrator_detail(run.integrator), "out_stats is NULL");
    tb_integrator_stats stats;
    assert_int_equal(tb_integrator_get_stats(run.integrator, &stats), TB_STATUS_OK);
    assert_string_equal(tb_integrator_detail(run.integrator), "");

    assert_int_equal(tb_integrator_advance(run.integrator, NAN), TB_STATUS_NOT_FINITE);
    assert_int_equal(tb_integrator_step(run.integrator), TB_STATUS_OK);
    assert_string_equal(tb_integrator_detail(run.integrator), "");
    assert_int_equal(tb_integrator_reset(run.integrator, INFINITY), TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(tb_integrator_detail(run.integrator), "t: must be finite"));
    assert_int_equal(tb_integrator_reset(run.integrator, 0.0), TB_STATUS_OK);
    assert_string_equal(tb_integrator_detail(run.integrator), "");

    tb_error error;
    tb_integrator *other = NULL;
    assert_int_equal(tb_integrator_create(NULL, NULL, 0.0, run.y, &other, &error),
                     TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_integrator_create(&run.system, NULL, 0.0, run.y, NULL, &error),
                     TB_STATUS_NULL_POINTER);
    assert_string_equal(error.message, "out_integrator is NULL");
    tb_integrator_destroy(run.integrator);

    assert_int_equal(tb_integrator_advance(NULL, 1.0), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_integrator_step(NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_integrator_reset(NULL, 1.0), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_integrator_get_stats(NULL, &stats), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_integrator_method(NULL), TB_METHOD_COUNT);
    assert_true(isnan(tb_integrator_time(NULL)));
    assert_string_equal(tb_integrator_detail(NULL), "integrator is NULL");
}

/* Which settings each method reads, as include/tumble/ode.h states it: fixed steps read dt,
 * threads and the scene's allow_unstable; CVODE the tolerances, the step bounds and max_order;
 * BDF and ark-imex the linear solver's; every method max_steps. The loader, the CLI and the
 * bindings ask this one rule (before, the loader refused max_steps for rk4, which the library
 * reads). */
static void test_each_method_reads_the_settings_its_header_names(void **state)
{
    (void)state;
    static const char *const fixed[] = {"dt", "threads", "allow_unstable"};
    static const char *const adaptive[] = {"rtol",     "atol",      "atol_vector",
                                           "max_step", "max_order", "initial_step"};
    static const char *const bdf[] = {"linear_solver", "preconditioner_half_bandwidth"};
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        const int is_adaptive = tb_method_is_adaptive((tb_method)m);
        tb_error error;
        assert_int_equal(tb_method_check_setting((tb_method)m, "max_steps", &error), TB_STATUS_OK);
        for (size_t k = 0; k < 3; ++k) {
            assert_int_equal(tb_method_check_setting((tb_method)m, fixed[k], &error),
                             is_adaptive ? TB_STATUS_UNSUPPORTED : TB_STATUS_OK);
        }
        for (size_t k = 0; k < 6; ++k) {
            assert_int_equal(tb_method_check_setting((tb_method)m, adaptive[k], &error),
                             is_adaptive ? TB_STATUS_OK : TB_STATUS_UNSUPPORTED);
        }
        for (size_t k = 0; k < 2; ++k) {
            assert_int_equal(tb_method_check_setting((tb_method)m, bdf[k], &error),
                             m == TB_METHOD_CVODE_BDF || m == TB_METHOD_ARK_IMEX
                                 ? TB_STATUS_OK
                                 : TB_STATUS_UNSUPPORTED);
        }
    }
    tb_error error;
    assert_int_equal(tb_method_check_setting(TB_METHOD_RK4, "rtol", &error), TB_STATUS_UNSUPPORTED);
    assert_string_equal(
        error.message,
        "applies to adaptive methods (cvode-adams, cvode-bdf, ark-imex), not to rk4");
    assert_int_equal(tb_method_check_setting(TB_METHOD_RK4, "step", &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "unknown setting \"step\"; settings: dt,"));
    assert_int_equal(tb_method_check_setting(TB_METHOD_COUNT, "dt", &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_method_check_setting(TB_METHOD_RK4, NULL, NULL), TB_STATUS_NULL_POINTER);
}

/* Before: rtol given to rk4 or dt to cvode-bdf was silently ignored. */
static void test_a_field_the_method_does_not_read_is_refused_by_name(void **state)
{
    (void)state;
    static const struct {
        tb_method method;
        const char *field;
    } cases[] = {{TB_METHOD_RK4, "def.rtol: rk4 does not read it"},
                 {TB_METHOD_EULER, "def.max_order: euler"},
                 {TB_METHOD_CVODE_BDF, "def.dt: cvode-bdf does not read it"},
                 {TB_METHOD_CVODE_ADAMS, "def.linear_solver: cvode-adams"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        double y[2] = {1.0, 0.0};
        tb_ode_system system = {.n = 2, .derivative = harmonic};
        tb_integrator_def def = tb_integrator_def_default();
        def.method = cases[i].method;
        switch (i) {
        case 0:
            def.rtol = 1e-8;
            break;
        case 1:
            def.max_order = 2;
            break;
        case 2:
            def.dt = 0.01;
            break;
        default:
            def.linear_solver = TB_LINEAR_SOLVER_KRYLOV;
        }
        tb_integrator *integrator = NULL;
        tb_error error;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, &error),
                         TB_STATUS_INVALID_ARGUMENT);
        print_message("%s\n", error.message);
        assert_non_null(strstr(error.message, cases[i].field));
        assert_null(integrator);
        /* switching with tb_integrator_def_set_method puts the unread field back */
        const tb_method wanted = cases[i].method;
        def.method = TB_METHOD_RK4;
        assert_int_equal(tb_integrator_def_set_method(&def, wanted), TB_STATUS_OK);
        assert_int_equal(def.method, wanted);
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, y, &integrator, &error),
                         TB_STATUS_OK);
        tb_integrator_destroy(integrator);
    }
    /* what the new method reads is kept */
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.01;
    def.rtol = 1e-9;
    def.linear_solver = TB_LINEAR_SOLVER_DENSE;
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_CVODE_BDF), TB_STATUS_OK);
    assert_near(def.rtol, 1e-9, 0.0);
    assert_int_equal(def.linear_solver, TB_LINEAR_SOLVER_DENSE);
    assert_near(def.dt, tb_integrator_def_default().dt, 0.0);
    assert_int_equal(tb_integrator_def_set_method(&def, TB_METHOD_COUNT),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(def.method, TB_METHOD_CVODE_BDF);
    assert_int_equal(tb_integrator_def_set_method(NULL, TB_METHOD_RK4), TB_STATUS_NULL_POINTER);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_steppers_converge_at_their_classical_orders),
        cmocka_unit_test(test_advance_lands_exactly_on_the_target_without_a_sliver_step),
        cmocka_unit_test(test_derivative_error_keeps_the_last_good_state),
        cmocka_unit_test(test_post_step_hook_runs_once_per_step_and_can_stop_the_run),
        cmocka_unit_test(test_a_rest_is_jumped_over_without_steps),
        cmocka_unit_test(test_steps_cut_at_breaks_are_held_to_max_steps),
        cmocka_unit_test(test_a_check_that_refuses_without_a_detail_is_named),
        cmocka_unit_test(test_a_state_that_overflows_is_reported_and_not_kept),
        cmocka_unit_test(test_invalid_definitions_are_rejected_with_the_field_named),
        cmocka_unit_test(test_method_names_round_trip_in_any_case),
        cmocka_unit_test(test_an_unknown_method_name_is_named_with_the_list_of_methods),
        cmocka_unit_test(test_the_method_table_states_each_methods_kind_and_cost),
        cmocka_unit_test(
            test_stability_limits_are_where_the_steppers_gain_crosses_the_stated_growth),
        cmocka_unit_test(
            test_a_fixed_step_advance_needing_more_than_max_steps_is_refused_before_stepping),
        cmocka_unit_test(test_a_step_that_times_near_t_cannot_resolve_is_refused),
        cmocka_unit_test(test_a_hook_failing_on_a_non_finite_state_reports_the_state),
        cmocka_unit_test(test_a_null_argument_after_a_failure_leaves_no_stale_detail),
        cmocka_unit_test(test_each_method_reads_the_settings_its_header_names),
        cmocka_unit_test(test_a_field_the_method_does_not_read_is_refused_by_name),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
