/* The accuracy sweep (tb_scene_accuracy_sweep): errors that converge at each method's order,
 * a scene left as it was, the reference's failure named, bad input refused with the status
 * of its kind. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

/* The asymmetric top of the tests (I = 1, 2, 3 kg m^2), free of torque: 1 s at 5 fps (every
 * step rate below is a whole number of steps a frame, so no step is shortened to land on a
 * frame and the errors are the methods' own). */
static tb_scene *top(tb_run_def *run)
{
    *run = tb_run_def_default();
    run->fps = 5.0;
    run->duration = 1.0;
    return test_scene_one_body(1.0, test_top_moments, test_top_q0, test_top_omega);
}

static double order(const tb_accuracy_result *coarse, const tb_accuracy_result *fine)
{
    return log(coarse->error / fine->error) / log(fine->setting / coarse->setting);
}

static void test_errors_fall_at_each_methods_order(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    const tb_accuracy_setting settings[] = {{TB_METHOD_EULER, 1000},   {TB_METHOD_EULER, 4000},
                                            {TB_METHOD_MIDPOINT, 240}, {TB_METHOD_MIDPOINT, 960},
                                            {TB_METHOD_RK4, 15},       {TB_METHOD_RK4, 60}};
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = settings;
    def.setting_count = 6;
    def.reference_rtol = 1e-12; /* a reference tight enough for RK4 at 60 steps/s (2e-8 m) */
    def.check_rtol = 1e-11;
    tb_accuracy_result results[6];
    tb_accuracy_reference reference;
    tb_error error;
    assert_int_equal(
        tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, &reference, &error),
        TB_STATUS_OK);
    for (int k = 0; k < 6; ++k) {
        assert_int_equal(results[k].status, TB_STATUS_OK);
        /* resolved: the reference's own error is about a tenth of reference.error (the check
         * run's rtol is 10x looser), so below 1% of these */
        assert_true(results[k].error > 10 * reference.error);
    }
    /* Step rates 4x apart: the observed order within 0.3 of the method's (1, 2, 4): at the
     * coarser rate the error is not yet purely its leading term. */
    assert_true(fabs(order(&results[0], &results[1]) - 1.0) < 0.3);
    assert_true(fabs(order(&results[2], &results[3]) - 2.0) < 0.3);
    assert_true(fabs(order(&results[4], &results[5]) - 4.0) < 0.3);
    /* The cheapest within a budget only RK4 at 60 and midpoint at 960 meet. */
    const size_t best = tb_accuracy_cheapest(results, 6, results[5].error * 1.0001);
    assert_true(best == 5 || best == 3);
    assert_int_equal(tb_accuracy_cheapest(results, 6, 0.0), 6);
    tb_scene_destroy(scene);
}

static void test_the_scene_is_left_as_it_was(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    double before[TB_STATE_SIZE];
    memcpy(before, tb_scene_states_const(scene), sizeof before);
    const tb_accuracy_setting settings[] = {{TB_METHOD_RK4, 240}, {TB_METHOD_CVODE_ADAMS, 1e-6}};
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = settings;
    def.setting_count = 2;
    tb_accuracy_result results[2];
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, NULL, NULL),
                     TB_STATUS_OK);
    assert_memory_equal(before, tb_scene_states_const(scene), sizeof before);
    run.fps = -1.0; /* the reference run is refused: still unchanged */
    assert_int_not_equal(
        tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, NULL, NULL), TB_STATUS_OK);
    assert_memory_equal(before, tb_scene_states_const(scene), sizeof before);
    tb_scene_destroy(scene);
}

static void test_a_failed_reference_says_which_run_and_why(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    run.duration = 1e300; /* more frames than a run takes */
    tb_accuracy_result results[18];
    tb_error error;
    const tb_status status =
        tb_scene_accuracy_sweep(scene, &run, NULL, NULL, NULL, results, NULL, &error);
    assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(error.status, status);
    assert_non_null(strstr(error.message, "reference run (cvode-bdf at rtol 1e-11) failed: "));
    assert_non_null(strstr(error.message, "duration"));
    tb_scene_destroy(scene);
}

static int stop_after_first(size_t index, const tb_accuracy_result *result, void *ctx)
{
    (void)result;
    *(size_t *)ctx = index;
    return 1;
}

static void test_the_callback_can_stop_the_sweep(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    run.duration = 0.1;
    tb_accuracy_result results[18];
    size_t seen = 99;
    assert_int_equal(
        tb_scene_accuracy_sweep(scene, &run, NULL, stop_after_first, &seen, results, NULL, NULL),
        TB_STATUS_CANCELLED);
    assert_int_equal(seen, 0);
    tb_scene_destroy(scene);
}

/* Progress reports: every run (reference, check, each setting in order) reported from t = 0 to
 * its end at each of its frames (1 s at 5 fps: 6 frames, t = 0 to 1 s exactly). */
typedef struct progress_log {
    size_t reports, starts, ends;
    tb_accuracy_run_kind kinds[8];
    size_t indices[8];
} progress_log;

static void log_progress(const tb_accuracy_progress *p, void *ctx)
{
    progress_log *log = ctx;
    log->reports += 1;
    assert_true(p->t >= 0.0 && p->t <= p->duration);
    assert_int_equal(p->count, 2);
    if (p->t == 0.0 && log->starts < 8) {
        log->kinds[log->starts] = p->kind;
        log->indices[log->starts] = p->index;
        log->starts += 1;
    }
    log->ends += p->t == p->duration;
}

static void test_progress_is_reported_for_every_run(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    const tb_accuracy_setting settings[] = {{TB_METHOD_RK4, 60}, {TB_METHOD_CVODE_ADAMS, 1e-6}};
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = settings;
    def.setting_count = 2;
    progress_log log = {0};
    def.progress = log_progress;
    def.progress_ctx = &log;
    tb_accuracy_result r[2];
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, NULL, NULL),
                     TB_STATUS_OK);
    assert_int_equal(log.starts, 4);
    assert_int_equal(log.ends, 4);
    assert_int_equal(log.reports, 4 * 6);
    const tb_accuracy_run_kind kinds[4] = {TB_ACCURACY_RUN_REFERENCE, TB_ACCURACY_RUN_CHECK,
                                           TB_ACCURACY_RUN_SETTING, TB_ACCURACY_RUN_SETTING};
    for (int k = 0; k < 4; ++k) {
        assert_int_equal(log.kinds[k], kinds[k]);
    }
    assert_int_equal(log.indices[2], 0);
    assert_int_equal(log.indices[3], 1);
    tb_scene_destroy(scene);
}

static void test_bad_input_is_refused_by_kind(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = top(&run);
    tb_accuracy_result results[2];
    tb_error error;
    assert_int_equal(tb_scene_accuracy_sweep(NULL, &run, NULL, NULL, NULL, results, NULL, &error),
                     TB_STATUS_NULL_POINTER);
    assert_string_equal(error.message, "scene is NULL");
    tb_accuracy_setting settings[2] = {{TB_METHOD_RK4, 240}, {TB_METHOD_RK4, NAN}};
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = settings;
    def.setting_count = 2;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, NULL, &error),
                     TB_STATUS_NOT_FINITE);
    assert_non_null(strstr(error.message, "def.settings[1].setting"));
    settings[1].setting = -60;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.settings[1].setting: must be > 0, got -60"));
    settings[1] = (tb_accuracy_setting){(tb_method)99, 60};
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, results, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.settings[1].method"));
    tb_accuracy_def uninitialised;
    memset(&uninitialised, 0, sizeof uninitialised);
    assert_int_equal(
        tb_scene_accuracy_sweep(scene, &run, &uninitialised, NULL, NULL, results, NULL, &error),
        TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "tb_accuracy_def_default"));
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_errors_fall_at_each_methods_order),
        cmocka_unit_test(test_the_scene_is_left_as_it_was),
        cmocka_unit_test(test_a_failed_reference_says_which_run_and_why),
        cmocka_unit_test(test_the_callback_can_stop_the_sweep),
        cmocka_unit_test(test_progress_is_reported_for_every_run),
        cmocka_unit_test(test_bad_input_is_refused_by_kind),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
