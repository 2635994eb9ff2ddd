/* tb_scene_frame_values: every body's frame (shape-origin position, shape orientation,
 * shape-origin velocity, angular velocity) in one call, against hand-computed mechanics. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "near.h"
#include "math/tb_math.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

static tb_scene *two_bodies(void)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def a = tb_body_def_default();
    a.mass = test_tilted_mass();
    a.position[0] = 1, a.position[1] = 2, a.position[2] = 3;
    a.velocity[0] = 0.5;
    a.angular_velocity[2] = 2.0;
    assert_int_equal(tb_scene_add_body(scene, &a, NULL), TB_STATUS_OK);
    tb_body_def b = tb_body_def_default();
    b.mass = test_tilted_mass();
    b.orientation[0] = sqrt(0.5), b.orientation[3] = sqrt(0.5); /* 90 degrees about z */
    b.angular_velocity[0] = 1.0;
    assert_int_equal(tb_scene_add_body(scene, &b, NULL), TB_STATUS_OK);
    return scene;
}

/* Body a, unturned at x = (1, 2, 3): its shape origin is at x - c = (0.9, 1.8, 2.7) and moves
 * at v + omega x (-c) = (0.5, 0, 0) + (0, 0, 2) x (-0.1, -0.2, -0.3) = (0.9, -0.2, 0). Body b,
 * turned 90 degrees about z at the origin: c maps to (-0.2, 0.1, 0.3), so the origin is at
 * (0.2, -0.1, -0.3), and moves at (1, 0, 0) x (0.2, -0.1, -0.3) = (0, 0.3, -0.1). Tolerance
 * 1e-12: a few roundings of numbers of order 1 (the principal rotation in and out). */
static void test_frame_values_read_as_by_hand(void **state)
{
    (void)state;
    tb_scene *scene = two_bodies();
    double values[2 * TB_FRAME_VALUES];
    assert_int_equal(tb_scene_frame_values(scene, tb_scene_states_const(scene), values),
                     TB_STATUS_OK);
    const double h = sqrt(0.5);
    const double expected[2 * TB_FRAME_VALUES] = {
        0.9, 1.8,  2.7,  1, 0, 0, 0, 0.9, -0.2, 0.0,  0, 0, 2,
        0.2, -0.1, -0.3, h, 0, 0, h, 0,   0.3,  -0.1, 1, 0, 0,
    };
    for (int k = 0; k < 2 * TB_FRAME_VALUES; ++k) {
        assert_near(values[k], expected[k], 1e-12);
    }
    tb_scene_destroy(scene);
}

/* The one call holds what the per-body read-outs give, to the last bit for the pose and the
 * angular velocity (the same arithmetic) and to 1e-15 m/s for the velocity (the point helper
 * rounds the arm differently), for the scene's current state and for another state array. */
static void test_frame_values_agree_with_the_per_body_read_outs(void **state)
{
    (void)state;
    tb_scene *scene = two_bodies();
    double y[2 * TB_STATE_SIZE];
    memcpy(y, tb_scene_states_const(scene), sizeof y);
    y[TB_STATE_SIZE + TB_STATE_L] = 3.0; /* another spin for b, in a caller's array */
    double values[2 * TB_FRAME_VALUES];
    assert_int_equal(tb_scene_frame_values(scene, y, values), TB_STATUS_OK);
    for (size_t id = 0; id < 2; ++id) {
        double position[3], q[4], v[3], omega[3];
        tb_scene_body_shape_pose(scene, y, id, position, q);
        tb_scene_body_shape_velocity(scene, y, id, v);
        tb_scene_body_angular_velocity(scene, y, id, omega);
        const double *got = values + TB_FRAME_VALUES * id;
        assert_memory_equal(got, position, sizeof position);
        assert_memory_equal(got + 3, q, sizeof q);
        assert_memory_equal(got + 10, omega, sizeof omega);
        for (int k = 0; k < 3; ++k) {
            assert_near(got[7 + k], v[k], 1e-15);
        }
    }
    tb_scene_destroy(scene);
}

/* A NULL scene, state or output is refused, the output left as it was; an empty scene fills
 * nothing. */
static void test_frame_values_refuse_null_and_write_nothing(void **state)
{
    (void)state;
    tb_scene *scene = two_bodies();
    double values[2 * TB_FRAME_VALUES] = {0};
    assert_int_equal(tb_scene_frame_values(NULL, tb_scene_states_const(scene), values),
                     TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_frame_values(scene, NULL, values), TB_STATUS_NULL_POINTER);
    assert_non_null(strstr(tb_scene_detail(scene), "y is NULL"));
    assert_int_equal(tb_scene_frame_values(scene, tb_scene_states_const(scene), NULL),
                     TB_STATUS_NULL_POINTER);
    for (int k = 0; k < 2 * TB_FRAME_VALUES; ++k) {
        assert_true(values[k] == 0.0);
    }
    tb_scene_destroy(scene);

    tb_scene_def scene_def = tb_scene_def_default();
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    assert_int_equal(tb_scene_frame_values(scene, tb_scene_states_const(scene), values),
                     TB_STATUS_OK);
    tb_scene_destroy(scene);
}

/* The frames a front end keeps: 5 s at 60 fps is frames 0..300, 301 of them; a body-frame
 * count is refused past TB_RUN_MAX_BODY_FRAMES (1e8) exactly, and a body count near SIZE_MAX
 * does not wrap the product into a small one. Before, 1e9 frames passed (95 GB of CSV, and the
 * Python bindings allocated 104 GB before anything refused). The output is untouched on
 * refusal. */
static void test_output_frames_are_bounded_by_body_frames(void **state)
{
    (void)state;
    size_t frames = 7;
    tb_error error;
    assert_int_equal(tb_run_output_frames(1, 5.0, 60.0, &frames, &error), TB_STATUS_OK);
    assert_int_equal(frames, 301);
    /* 1000 bodies at 1 fps: 99 999 s is 100 000 frames, 1e8 body-frames; one second more is
     * 1e8 + 1000 */
    assert_int_equal(tb_run_output_frames(1000, 99999.0, 1.0, &frames, &error), TB_STATUS_OK);
    assert_int_equal(frames, 100000);
    frames = 7;
    assert_int_equal(tb_run_output_frames(1000, 100000.0, 1.0, &frames, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(frames, 7);
    assert_non_null(strstr(error.message, "TB_RUN_MAX_BODY_FRAMES"));
    assert_int_equal(tb_run_output_frames(SIZE_MAX, 1.0, 1.0, &frames, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_run_output_frames(1, 1e8, 10.0, &frames, &error),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(frames, 7);
    assert_int_equal(tb_run_output_frames(1, 1.0, 1.0, NULL, &error), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_run_output_frames(1, NAN, 1.0, &frames, &error), TB_STATUS_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_frame_values_read_as_by_hand),
        cmocka_unit_test(test_frame_values_agree_with_the_per_body_read_outs),
        cmocka_unit_test(test_frame_values_refuse_null_and_write_nothing),
        cmocka_unit_test(test_output_frames_are_bounded_by_body_frames),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
