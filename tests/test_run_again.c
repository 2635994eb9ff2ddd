/* A run from a start state is the same run whatever ran on the scene before it: nothing a run
 * leaves outside y changes the next run from a state (src/scene/effect_list.c,
 * tb__scene_restart). Two such memories were found:
 *   - which touching point holds which slot of the friction pools (the contact effect's and the
 *     ground's; the anchors themselves live in y) is kept beside y, at step boundaries. A second
 *     run from the start found the slots claimed, keyed and queued as the first had left them, so
 *     its points took other slots, its anchors sat elsewhere in y, and CVODE's error norms summed
 *     them in another order: the dice under CVODE BDF took 18 642 steps over 0.3 s fresh, 18 465
 *     and 18 440 after other runs;
 *   - a joint that broke stayed broken, and a run again from the start fell free from t = 0.
 * Every comparison here is bit for bit, over the whole state (the anchors too): the runs are the
 * same arithmetic on the same numbers, so any difference is remembered history. */
#include "fixtures.h"
#include "joint_scenes.h"
#include "span.h"
#include "tumble/tumble.h"

#include <setjmp.h> /* cmocka needs these first */
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

/* s: the top box slides 2.3 mm and sticks by 31 ms (mu_k g = 4.9 m/s^2), then rests on its
 * anchors; the runs end with slots claimed, keyed, and some freed and queued again. Under
 * valgrind (span.h) a shorter span, still sliding, with slots held. */
static double span(void)
{
    return tb_test_span(0.08, 0.02);
}

/* A 1 kg, 10 cm box on the ground, a 0.5 kg, 8 cm box on it sliding at 0.15 m/s and turning
 * at 2 rad/s, and a 0.5 kg box beside them sliding the other way: friction between bodies (the
 * contact effect's pool) and on the ground (the ground's pool), sliding and sticking. */
static tb_scene *sliding_boxes(void)
{
    tb_scene *scene = test_empty_scene();
    const double base[3] = {0.1, 0.1, 0.1}, small[3] = {0.08, 0.08, 0.08};
    test_add_box(scene, 1.0, base, (double[]){0.0, 0.0, 0.05});
    const size_t top = test_add_box(scene, 0.5, small, (double[]){0.0, 0.0, 0.14});
    const size_t side = test_add_box(scene, 0.5, small, (double[]){0.2, 0.0, 0.04});
    assert_int_equal(
        tb_scene_set_velocity(scene, top, (double[]){0.15, 0.0, 0.0}, (double[]){0.0, 0.0, 2.0}),
        TB_STATUS_OK);
    assert_int_equal(
        tb_scene_set_velocity(scene, side, (double[]){-0.1, 0.05, 0.0}, (double[]){0.0, 0.0, 0.0}),
        TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -9.81}), TB_STATUS_OK);
    const tb_ground_def ground = tb_ground_def_default();
    const tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    return scene;
}

static const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};

/* RK4 at the scene's default step; BDF with the contact's sparse Jacobian (KLU), 30 times
 * cheaper here than the dense difference quotients, as on the dice (bench_bdf_contact). */
static tb_integrator_def method_def(tb_method method)
{
    tb_integrator_def def = test_integrator_def(method, 0.0, 1e-6);
    if (method == TB_METHOD_CVODE_BDF) {
        def.linear_solver = TB_LINEAR_SOLVER_SPARSE;
    }
    return def;
}

/* Whether this build has the method (BDF's sparse solver needs KLU); prints a skip if not. */
static bool built(tb_method method)
{
    tb_scene *scene = sliding_boxes();
    const tb_integrator_def def = method_def(method);
    tb_integrator *integrator = NULL;
    const tb_status status = tb_scene_integrator_create(scene, &def, 0.0, &integrator);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    if (status == TB_STATUS_UNSUPPORTED) {
        print_message("%s skipped: built without KLU\n", tb_method_name(method));
        return false;
    }
    assert_int_equal(status, TB_STATUS_OK);
    return true;
}

static double *copy_states(const tb_scene *scene)
{
    const size_t bytes = tb_scene_state_size(scene) * sizeof(double);
    double *copy = malloc(bytes);
    assert_non_null(copy);
    memcpy(copy, tb_scene_states_const(scene), bytes);
    return copy;
}

/* The scene's states set to start, then run by tb_scene_run (from t = 0): a copy of the state it
 * ends in (the caller frees it). */
static double *run_from(tb_scene *scene, const double *start, const tb_run_def *run)
{
    memcpy(tb_scene_states(scene), start, tb_scene_state_size(scene) * sizeof(double));
    tb_error error;
    const tb_status status = tb_scene_run(scene, run, NULL, NULL, NULL, &error);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", error.message);
    }
    assert_int_equal(status, TB_STATUS_OK);
    return copy_states(scene);
}

/* The run of the front ends (tb_scene_run, from t = 0, as `tumble run` and the accuracy sweep's
 * rows make it) three times from the start: each ends as the first, while friction slots were in
 * use (checked: the contact effect's pool holds some at the end). */
static void test_runs_again_from_the_start_end_as_the_first(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        if (!built(methods[m])) {
            continue;
        }
        tb_scene *scene = sliding_boxes();
        double *start = copy_states(scene);
        tb_run_def run = tb_run_def_default();
        run.integrator = method_def(methods[m]);
        run.duration = span();
        run.fps = 50.0;
        double *first = run_from(scene, start, &run);
        for (int k = 1; k < 3; ++k) {
            double *again = run_from(scene, start, &run);
            assert_memory_equal(first, again, tb_scene_state_size(scene) * sizeof(double));
            free(again);
        }
        tb_contact_friction_stats stats;
        assert_int_equal(tb_scene_contact_friction_stats(scene, 2, &stats), TB_STATUS_OK);
        print_message("%s: %zu friction slots in use at the end\n", tb_method_name(methods[m]),
                      stats.in_use);
        assert_true(stats.in_use > 0);
        free(start);
        free(first);
        tb_scene_destroy(scene);
    }
}

/* One integrator, run over the span, its scene's states put back to the start and the
 * integrator reset to t = 0, run over the span again: it ends as a fresh scene's fresh integrator
 * does. */
static void test_a_reset_to_the_start_runs_as_a_fresh_scene(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        if (!built(methods[m])) {
            continue;
        }
        const tb_integrator_def def = method_def(methods[m]);
        tb_scene *fresh = sliding_boxes();
        tb_integrator *integrator = test_integrator(fresh, &def);
        assert_int_equal(tb_integrator_advance(integrator, span()), TB_STATUS_OK);
        tb_integrator_destroy(integrator);

        tb_scene *scene = sliding_boxes();
        const size_t bytes = tb_scene_state_size(scene) * sizeof(double);
        double *start = copy_states(scene);
        integrator = test_integrator(scene, &def);
        assert_int_equal(tb_integrator_advance(integrator, span()), TB_STATUS_OK);
        memcpy(tb_scene_states(scene), start, bytes);
        assert_int_equal(tb_integrator_reset(integrator, 0.0), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, span()), TB_STATUS_OK);
        assert_memory_equal(tb_scene_states_const(fresh), tb_scene_states_const(scene), bytes);
        tb_integrator_destroy(integrator);
        free(start);
        tb_scene_destroy(scene);
        tb_scene_destroy(fresh);
    }
}

/* A reset where the run stopped (the bindings' restart after a change of a body's state, or a
 * user force added) continues the run: the loaded anchors keep their points, and RK4 ends as
 * the run that was never reset. Starting the pools afresh there would free every slot, and the
 * resting top box would lose the grip its anchors hold. */
static void test_a_reset_where_the_run_stopped_continues_it(void **state)
{
    (void)state;
    const tb_integrator_def def = method_def(TB_METHOD_RK4);
    tb_scene *through = sliding_boxes();
    tb_integrator *integrator = test_integrator(through, &def);
    assert_int_equal(tb_integrator_advance(integrator, 0.5 * span()), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, span()), TB_STATUS_OK);
    tb_integrator_destroy(integrator);

    tb_scene *scene = sliding_boxes();
    integrator = test_integrator(scene, &def);
    assert_int_equal(tb_integrator_advance(integrator, 0.5 * span()), TB_STATUS_OK);
    assert_int_equal(tb_integrator_reset(integrator, 0.5 * span()), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, span()), TB_STATUS_OK);
    assert_memory_equal(tb_scene_states_const(through), tb_scene_states_const(scene),
                        tb_scene_state_size(scene) * sizeof(double));
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    tb_scene_destroy(through);
}

/* A 2 kg ball on a 1 m string (a ball joint at the origin) released level with it: the string's
 * pull grows as 3 m g sin(phi) with the angle phi swung below the level, and a break_force of
 * 30 N breaks it at phi = 30.6 deg, about 0.26 s in. Run over 0.6 s, then again from the start
 * by tb_scene_run: the second breaks as the first and ends as it, bit for bit. Before, the joint
 * stayed broken and the second run's ball fell free from t = 0 (z = -g/2 T^2). An integrator
 * made and reset where the run stopped, after the break, keeps it broken. */
static void test_a_joint_broken_in_a_run_is_whole_in_a_run_again(void **state)
{
    (void)state;
    for (int m = 0; m < 2; ++m) {
        tb_scene *scene = test_empty_scene();
        const size_t ball =
            test_add_ball(scene, "ball", 2.0, 0.05, (double[]){1.0, 0.0, 0.0}, NULL);
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
        tb_joint_def string = tb_joint_def_default();
        string.type = TB_JOINT_BALL;
        string.body_a = ball;
        string.break_force = 30.0;
        assert_int_equal(tb_scene_add_joint(scene, &string, NULL), TB_STATUS_OK);
        double *start = copy_states(scene), *ends[2];
        tb_run_def run = tb_run_def_default();
        run.integrator = methods[m] == TB_METHOD_RK4 ? test_integrator_def(methods[m], 1e-3, 0.0)
                                                     : test_integrator_def(methods[m], 0.0, 1e-8);
        run.duration = 0.6;
        run.fps = 100.0;
        for (int k = 0; k < 2; ++k) {
            ends[k] = run_from(scene, start, &run);
            bool broken = false;
            assert_int_equal(tb_scene_joint_broken(scene, 0, &broken), TB_STATUS_OK);
            assert_true(broken);
        }
        print_message("%s: the ball at z = %.6f m, then %.6f m (free fall: %.6f m)\n",
                      tb_method_name(methods[m]), ends[0][2], ends[1][2], -0.5 * TEST_G * 0.36);
        assert_memory_equal(ends[0], ends[1], tb_scene_state_size(scene) * sizeof(double));
        tb_integrator *integrator = NULL; /* where the run stopped: the break stays */
        assert_int_equal(tb_scene_integrator_create(scene, &run.integrator, 0.6, &integrator),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_reset(integrator, 0.6), TB_STATUS_OK);
        bool broken = false;
        assert_int_equal(tb_scene_joint_broken(scene, 0, &broken), TB_STATUS_OK);
        assert_true(broken);
        tb_integrator_destroy(integrator);
        free(start);
        free(ends[0]);
        free(ends[1]);
        tb_scene_destroy(scene);
    }
}

int main(int argc, char **argv)
{
    if (argc > 1) { /* a pattern of test names to run (cmocka's filter) */
        cmocka_set_test_filter(argv[1]);
    }
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_runs_again_from_the_start_end_as_the_first),
        cmocka_unit_test(test_a_reset_to_the_start_runs_as_a_fresh_scene),
        cmocka_unit_test(test_a_reset_where_the_run_stopped_continues_it),
        cmocka_unit_test(test_a_joint_broken_in_a_run_is_whole_in_a_run_again),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
