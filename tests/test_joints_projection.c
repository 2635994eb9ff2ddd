/* tb_scene_project_joints (issue 21): a start off the joints brought onto them, positions then
 * velocities, and its refusals, each changing nothing. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <string.h>

static double largest_velocity_error(const tb_scene *scene)
{
    double worst = 0.0;
    for (size_t j = 0; j < tb_scene_joint_count(scene); ++j) {
        double velocity = 0.0;
        assert_int_equal(
            tb_scene_joint_error(scene, tb_scene_states_const(scene), j, NULL, &velocity),
            TB_STATUS_OK);
        worst = fmax(worst, velocity);
    }
    return worst;
}

/* The double pendulum with its lower rod moved 1 mm along x and pushed at 0.1 m/s along z, off
 * both hinges. */
static tb_scene *pendulum_off_its_joints(size_t ids[2])
{
    tb_scene *scene = test_double_pendulum(1.0, 0.5, ids);
    double *y = tb_scene_states(scene);
    y[TB_STATE_SIZE * ids[1] + TB_STATE_X] += 1e-3;
    y[TB_STATE_SIZE * ids[1] + TB_STATE_P + 2] += 0.1; /* 1 kg: 0.1 m/s */
    return scene;
}

/* After the projection the start is on the joints to round-off (1e-12 m, 1e-12 m/s: Newton's
 * iterations converge quadratically from 1 mm, and the velocities' projection is one linear
 * solve), and the mass-weighted least change moves the bodies by about the 1 mm they were off,
 * not more (bound 2 mm). RK4 then steps from it with the joints held (1e-12 m). */
static void test_start_one_millimetre_off_is_projected_onto_the_joints(void **state)
{
    (void)state;
    size_t ids[2];
    tb_scene *scene = pendulum_off_its_joints(ids);
    assert_true(test_largest_joint_error(scene) >= 0.5e-3);
    double before[2 * TB_STATE_SIZE], left = 1.0;
    memcpy(before, tb_scene_states_const(scene), sizeof before);
    assert_int_equal(tb_scene_project_joints(scene, 0.0, &left), TB_STATUS_OK);
    const double *y = tb_scene_states_const(scene);
    double moved = 0.0;
    for (size_t b = 0; b < 2; ++b) {
        const double *x = y + TB_STATE_SIZE * b + TB_STATE_X;
        const double *x0 = before + TB_STATE_SIZE * b + TB_STATE_X;
        moved =
            fmax(moved, sqrt((x[0] - x0[0]) * (x[0] - x0[0]) + (x[2] - x0[2]) * (x[2] - x0[2])));
    }
    print_message("projected: joint error %.3g m, velocity error %.3g m/s, moved %.3g m\n",
                  test_largest_joint_error(scene), largest_velocity_error(scene), moved);
    assert_true(left <= TB_JOINT_PROJECTION_TOLERANCE);
    assert_true(test_largest_joint_error(scene) <= 1e-12);
    assert_true(largest_velocity_error(scene) <= 1e-12);
    assert_true(moved <= 2e-3);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_true(test_largest_joint_error(scene) <= 1e-12);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A tolerance below round-off (1e-300) cannot be met: refused with TB_STATUS_SOLVER_FAILED,
 * the detail naming the joint, the states unchanged to the bit. */
static void test_projection_that_cannot_meet_its_tolerance_changes_nothing(void **state)
{
    (void)state;
    size_t ids[2];
    tb_scene *scene = pendulum_off_its_joints(ids);
    double before[2 * TB_STATE_SIZE], left = -1.0;
    memcpy(before, tb_scene_states_const(scene), sizeof before);
    assert_int_equal(tb_scene_project_joints(scene, 1e-300, &left), TB_STATUS_SOLVER_FAILED);
    assert_non_null(strstr(tb_scene_detail(scene), "joints["));
    assert_memory_equal(before, tb_scene_states_const(scene), sizeof before);
    assert_true(left == -1.0);
    tb_scene_destroy(scene);
}

/* A scene without joints: nothing to project, the states unchanged, no error left. */
static void test_scene_without_joints_is_left_as_it_is(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, 1.0}, NULL);
    double before[TB_STATE_SIZE], left = -1.0;
    memcpy(before, tb_scene_states_const(scene), sizeof before);
    assert_int_equal(tb_scene_project_joints(scene, 0.0, &left), TB_STATUS_OK);
    assert_memory_equal(before, tb_scene_states_const(scene), sizeof before);
    assert_true(left == 0.0);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_start_one_millimetre_off_is_projected_onto_the_joints),
        cmocka_unit_test(test_projection_that_cannot_meet_its_tolerance_changes_nothing),
        cmocka_unit_test(test_scene_without_joints_is_left_as_it_is),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
