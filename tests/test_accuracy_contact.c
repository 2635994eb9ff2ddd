/* The accuracy sweep on contact scenes (issue 12): a reference that does not fail where CVODE
 * BDF does, errors that fall with the step on a bounce, and a horizon on chaotic dice. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static tb_scene *load(const char *name, tb_run_def *run)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", TUMBLE_TEST_SCENES_DIR, name);
    tb_scene *scene = NULL;
    tb_error error;
    assert_int_equal(tb_scene_load_file(path, &scene, run, &error), TB_STATUS_OK);
    return scene;
}

static double order(const tb_accuracy_result *coarse, const tb_accuracy_result *fine)
{
    return log(coarse->error / fine->error) / log(fine->setting / coarse->setting);
}

/* The sweep fitted to a stiff scene: each explicit fixed-step method at 1, 2 and 4 times the rate
 * of its default step, which the scene accepts (the table's 60 to 4000 steps/s are all unstable);
 * rosenbrock, which has no stability limit, at the table's user steps, 240 and 1000 per second. */
static void test_a_stiff_scene_sweeps_its_own_stable_steps(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load("bouncing_ball.json", &run);
    tb_accuracy_setting settings[32];
    size_t count = 0;
    assert_int_equal(tb_accuracy_scene_sweep(scene, settings, 32, &count), TB_STATUS_OK);
    /* 3 Euler, 3 midpoint, 3 RK4, 4 Adams, 4 BDF, 4 ark-imex, 2 rosenbrock */
    assert_int_equal(count, 23);
    assert_int_equal(settings[21].method, TB_METHOD_ROSENBROCK);
    assert_int_equal(settings[22].method, TB_METHOD_ROSENBROCK);
    assert_true(settings[21].setting == 240.0 && settings[22].setting == 1000.0);
    for (size_t k = 0; k < 9; ++k) {
        double dt = 0.0;
        tb_scene_default_step(scene, settings[k].method, &dt);
        assert_false(tb_method_is_adaptive(settings[k].method));
        assert_true(fabs(settings[k].setting * dt - (double)(1 << (k % 3))) < 1e-12);
    }
    tb_scene_destroy(scene);
}

/* A ball dropped on the ground: nothing chaotic, so the CVODE reference holds, the references
 * agree over every frame (no horizon), and the errors fall with the step. Euler's error is its
 * own first-order term (observed order within 0.15 of 1 over each doubling); the law's kink at
 * touchdown (its force is continuous, its slope jumps) adds an error of second order per crossing
 * whose constant depends on where the step falls against touchdown, so midpoint and RK4 do not
 * fall monotonically: they are held to a bound instead, a tenth of Euler's finest error. Fixed
 * steps now end at the touchdowns (src/ode/fixed_onset.c), so RK4's error from its default step
 * to twice its rate falls at an observed order of at least 2 (measured 2.3: 1.05e-6 to 2.1e-7;
 * before the onsets 9.0e-6 to 1.5e-6), and at four times the rate it meets a floor of 2.1e-7
 * (not explained: the reference's own error is the first suspect), held to not growing. CVODE
 * Adams: 100 times tighter rtol, at least 10 times smaller error. */
static void test_a_bounce_converges_with_the_step(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load("bouncing_ball.json", &run);
    tb_accuracy_setting settings[32];
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = settings;
    tb_accuracy_scene_sweep(scene, settings, 32, &def.setting_count);
    tb_accuracy_result r[32];
    tb_accuracy_reference reference;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, &reference, NULL),
                     TB_STATUS_OK);
    assert_int_equal(reference.method, TB_METHOD_CVODE_BDF);
    assert_string_equal(reference.cvode_detail, "");
    assert_int_equal(reference.horizon_frames, reference.frames);
    assert_true(fabs(reference.horizon - run.duration) < 1e-12);
    for (size_t k = 0; k < def.setting_count; ++k) {
        assert_int_equal(r[k].status, TB_STATUS_OK);
        assert_true(r[k].error > 10 * reference.error); /* resolved */
    }
    assert_true(fabs(order(&r[0], &r[1]) - 1.0) < 0.15);
    assert_true(fabs(order(&r[1], &r[2]) - 1.0) < 0.15);
    for (size_t k = 3; k < 9; ++k) {
        assert_true(r[k].error < 0.1 * r[2].error);
    }
    assert_true(order(&r[6], &r[7]) >= 2.0 && r[8].error <= 1.01 * r[7].error);
    assert_true(r[10].error < 0.1 * r[9].error && r[12].error < r[10].error);
    tb_scene_destroy(scene);
}

/* Three dice thrown at each other: CVODE BDF at rtol 1e-11 fails near the landing (its error test
 * meets the jumps of the box-box manifold), so the reference is RK4 at an eighth of the default
 * step, checked at a quarter; the two differ past some time by more than the tolerance, which is
 * reported as the horizon, and the sweep still gives every setting a result. */
static void test_chaotic_dice_get_an_rk4_reference_and_a_horizon(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load("three_dice.json", &run);
    run.duration = 0.5; /* they meet at about 0.1 s and land at 0.2 to 0.3 s */
    tb_accuracy_setting fitted[32];
    size_t count = 0;
    tb_accuracy_scene_sweep(scene, fitted, 32, &count);
    tb_accuracy_setting sweep[2] = {fitted[6],
                                    {TB_METHOD_CVODE_ADAMS, 1e-5}}; /* RK4 at its default step */
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = sweep;
    def.setting_count = 2;
    def.horizon_tolerance = 1e-6;
    tb_accuracy_result r[2];
    tb_accuracy_reference reference;
    tb_error error;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, &reference, &error),
                     TB_STATUS_OK);
    assert_int_equal(reference.method, TB_METHOD_RK4);
    assert_non_null(strstr(reference.cvode_detail, "reference run (cvode-bdf at rtol 1e-11)"));
    assert_true(fabs(reference.check_setting - 0.5 * reference.setting) < 1e-9);
    assert_true(fabs(reference.setting - 8.0 * fitted[6].setting) < 1e-6 * reference.setting);
    /* a horizon inside the run, and the reference known to the tolerance up to it */
    assert_true(reference.horizon_frames < reference.frames);
    assert_true(reference.horizon < run.duration);
    assert_true(reference.error <= def.horizon_tolerance);
    assert_int_equal(r[0].status, TB_STATUS_OK);
    assert_int_equal(r[1].status, TB_STATUS_OK);
    tb_scene_destroy(scene);
}

static void test_bad_reference_settings_are_refused(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load("bouncing_ball.json", &run);
    tb_accuracy_result r[18];
    tb_error error;
    tb_accuracy_def def = tb_accuracy_def_default();
    def.reference_step_fraction = 0.75;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.reference_step_fraction"));
    def = tb_accuracy_def_default();
    def.horizon_tolerance = NAN;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(error.message, "def.horizon_tolerance"));
    def = tb_accuracy_def_default();
    def.reference = (tb_accuracy_reference_kind)7;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, r, NULL, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    tb_scene_destroy(scene);
}

/* Reports of the sweep's progress: how many fell strictly between two frames. */
typedef struct inside_frames {
    double frame_interval; /* s */
    int count;
} inside_frames;

static void count_inside(const tb_accuracy_progress *p, void *ctx)
{
    inside_frames *w = ctx;
    const double frames = p->t / w->frame_interval;
    w->count += fabs(frames - round(frames)) > 1e-9;
}

/* A setting that costs far more than the RK4 reference is stopped where it is, inside a frame,
 * not at the frame's end: three dice, frames 0.1 s apart; the reference at half the default step
 * (checked at the default), the setting RK4 at a hundredth of it, about 50 times the reference's
 * work a frame, so it passes the budget (1.5 times the reference's CPU) within about 3 % of the
 * first frame. Checked at frames only, it ran the whole frame (this test's run took 50 times the
 * reference) and said "stopped at t = 0.1 s"; on the example stack ark-imex spent over 7
 * minutes in its first frame. The stop time is asserted inside the frame (a bound of 0.1 s, far
 * from the measured 0.003-0.01 s whatever the machine's load: the budget is process CPU), and
 * progress reports come from inside the frames. */
static void test_a_setting_past_its_budget_stops_inside_a_frame(void **state)
{
    (void)state;
    tb_run_def run;
    tb_scene *scene = load("three_dice.json", &run);
    run.duration = 0.1;
    run.fps = 10.0;
    double dt = 0.0;
    assert_int_equal(tb_scene_default_step(scene, TB_METHOD_RK4, &dt), TB_STATUS_OK);
    tb_accuracy_setting slow = {TB_METHOD_RK4, 100.0 / dt};
    tb_accuracy_def def = tb_accuracy_def_default();
    def.settings = &slow;
    def.setting_count = 1;
    def.reference = TB_ACCURACY_REFERENCE_RK4;
    def.reference_step_fraction = 0.5;
    inside_frames inside = {1.0 / run.fps, 0};
    def.progress = count_inside;
    def.progress_ctx = &inside;
    tb_accuracy_result r;
    tb_accuracy_reference reference;
    assert_int_equal(tb_scene_accuracy_sweep(scene, &run, &def, NULL, NULL, &r, &reference, NULL),
                     TB_STATUS_OK);
    assert_int_equal(r.status, TB_STATUS_TOO_MANY_STEPS);
    const char *at = strstr(r.detail, "stopped at t = ");
    assert_non_null(at);
    double stopped = -1.0;
    assert_int_equal(sscanf(at, "stopped at t = %lf", &stopped), 1);
    assert_true(stopped > 0.0 && stopped < 0.1);
    assert_true(inside.count > 0);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_stiff_scene_sweeps_its_own_stable_steps),
        cmocka_unit_test(test_a_bounce_converges_with_the_step),
        cmocka_unit_test(test_chaotic_dice_get_an_rk4_reference_and_a_horizon),
        cmocka_unit_test(test_bad_reference_settings_are_refused),
        cmocka_unit_test(test_a_setting_past_its_budget_stops_inside_a_frame),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
