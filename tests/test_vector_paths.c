/* The vector paths (tb_vector_path) and threads (tb_integrator_def.threads) of a separable scene:
 * every path this processor supports and every thread count give the bits the body-by-body path
 * on one thread gives, whatever the scene's size and wherever a body falls in a lane group or
 * chunk; and the lanes carry the physics (a free top keeps its world angular momentum to the
 * bit and follows Euler's equations' exact solution). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "near.h"
#include "torque_free_top.h"
#include "tumble/tumble.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Euler, midpoint and RK4: the fixed-step methods come first in tb_method. */
#define FIXED_STEP_METHODS (TB_METHOD_RK4 + 1)

/* Lane paths after TB_VECTOR_PATH_NONE, the reference. */
#define FIRST_LANE_PATH TB_VECTOR_PATH_BASELINE

/* Body with seed k: its own motion and spin (and one of 50 sizes), so a body computed in another's
 * place (a lane or chunk mixed up) gives another answer. */
static void add_seeded_body(tb_scene *scene, double k)
{
    tb_body_def body = tb_body_def_default();
    const double shape = fmod(k, 50.0);
    assert_int_equal(tb_mass_from_box(TB_MASS_DENSITY, 500.0,
                                      (double[]){0.1 + 0.003 * shape, 0.2, 0.3 - 0.002 * shape},
                                      &body.mass, NULL),
                     TB_STATUS_OK);
    body.position[0] = k;
    body.velocity[1] = 0.1 * k;
    body.velocity[2] = 3.0;
    body.angular_velocity[0] = 1.0 + 0.03 * k;
    body.angular_velocity[1] = 2.0 - 0.01 * k;
    body.angular_velocity[2] = 0.5;
    assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
}

static tb_scene *new_scene(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    return scene;
}

/* Gravity and drag (linear, quadratic, angular) on every body: the effects with lane forms. */
static void add_all_body_effects(tb_scene *scene)
{
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_drag_def drag = tb_drag_def_default();
    drag.linear = 0.3;
    drag.quadratic = 0.05;
    drag.angular = 0.01;
    drag.angular_quadratic = 0.002;
    assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
}

/* `bodies` seeded bodies under every per-body effect: gravity and drag on all; drag on one, a
 * spring to a world anchor, forces and torques in both frames on single bodies (applied lane
 * by lane), one of them on the last body, whose lane group is padded. */
static tb_scene *every_per_body_effect(size_t bodies)
{
    tb_scene *scene = new_scene();
    for (size_t i = 0; i < bodies; ++i) {
        add_seeded_body(scene, (double)i);
    }
    add_all_body_effects(scene);
    tb_drag_def drag = tb_drag_def_default();
    drag.body = 3;
    drag.linear = 0.2;
    drag.angular = 0.05;
    assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
    tb_spring_def spring = tb_spring_def_default();
    spring.body_a = 5;
    spring.point_a[0] = 0.05;
    spring.point_b[0] = 5.0;
    spring.point_b[2] = 1.0;
    spring.stiffness = 50.0;
    spring.damping = 0.5;
    spring.rest_length = 0.5;
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    const double push[3] = {1.0, -2.0, 0.5}, at[3] = {0.05, 0.0, 0.1};
    assert_int_equal(tb_scene_add_force(scene, 7 % bodies, push, at, TB_FRAME_WORLD), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_force(scene, bodies - 1, push, at, TB_FRAME_BODY), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_torque(scene, 2, push, TB_FRAME_WORLD), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_torque(scene, bodies / 2, push, TB_FRAME_BODY), TB_STATUS_OK);
    return scene;
}

/* Advances scene to T with method on path and threads; the integrator's stats into *stats. */
static void run(tb_scene *scene, tb_method method, tb_vector_path path, int threads, double T,
                tb_integrator_stats *stats)
{
    assert_int_equal(tb_scene_set_vector_path(scene, path), TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    def.dt = 1.0 / 480;
    def.threads = threads;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, T), TB_STATUS_OK);
    assert_int_equal(tb_integrator_get_stats(integrator, stats), TB_STATUS_OK);
    tb_integrator_destroy(integrator);
}

/* The lanes do each body's operations in the body-by-body order, with no contraction into FMA
 * (the library is built with -ffp-contract=off), threads share out the same chunks, so every
 * path and thread count must agree to the last bit; so must the renormalisation's drift. 12
 * bodies: one lane group of 8 and a padded one; 77: two groups of 32 and a padded one; 780: 25
 * groups, which a step shares among up to 3 threads (8 groups a thread at least). */
static void test_every_path_and_thread_count_gives_the_body_by_body_bits(void **state)
{
    (void)state;
    static const size_t sizes[] = {12, 77, 780};
    static const int thread_counts[] = {1, 2, 3};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s) {
        for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
            tb_scene *reference = every_per_body_effect(sizes[s]);
            tb_integrator_stats expected, got;
            const double T = sizes[s] > 100 ? 0.05 : 0.5; /* 24 steps of the big scene */
            run(reference, (tb_method)m, TB_VECTOR_PATH_NONE, 1, T, &expected);
            const size_t bytes = TB_STATE_SIZE * sizes[s] * sizeof(double);
            for (int p = TB_VECTOR_PATH_NONE; p < TB_VECTOR_PATH_COUNT; ++p) {
                if (!tb_vector_path_supported((tb_vector_path)p)) {
                    print_message("%s: not supported here, skipped\n",
                                  tb_vector_path_name((tb_vector_path)p));
                    continue;
                }
                for (size_t k = 0; k < sizeof thread_counts / sizeof thread_counts[0]; ++k) {
                    tb_scene *scene = every_per_body_effect(sizes[s]);
                    run(scene, (tb_method)m, (tb_vector_path)p, thread_counts[k], T, &got);
                    assert_memory_equal(tb_scene_states_const(scene),
                                        tb_scene_states_const(reference), bytes);
                    assert_true(tb_scene_quaternion_drift(scene) ==
                                tb_scene_quaternion_drift(reference));
                    assert_int_equal(got.steps, expected.steps);
                    assert_int_equal(got.derivative_evals, expected.derivative_evals);
                    tb_scene_destroy(scene);
                }
            }
            print_message("%zu bodies, %s: every path and thread count the same bits\n", sizes[s],
                          tb_method_name((tb_method)m));
            tb_scene_destroy(reference);
        }
    }
}

/* Body seed k alone in its scene (stepped body by body: no lanes below 8 bodies) and the same
 * body at index k + shift of a scene of 45 on the widest path: the same bits, wherever its lane
 * and chunk. */
static void test_a_body_moves_the_same_in_any_lane_of_any_scene(void **state)
{
    (void)state;
    enum { BODIES = 40, SHIFT = 5 };
    tb_scene *shifted = new_scene();
    for (size_t i = 0; i < SHIFT; ++i) {
        add_seeded_body(shifted, 100.0 + (double)i);
    }
    for (size_t i = 0; i < BODIES; ++i) {
        add_seeded_body(shifted, (double)i);
    }
    add_all_body_effects(shifted);
    tb_integrator_stats stats;
    run(shifted, TB_METHOD_RK4, TB_VECTOR_PATH_AUTO, 2, 1.0, &stats);
    static const size_t seeds[] = {0, 17, 26, 31, 39};
    for (size_t s = 0; s < sizeof seeds / sizeof seeds[0]; ++s) {
        tb_scene *alone = new_scene();
        add_seeded_body(alone, (double)seeds[s]);
        add_all_body_effects(alone);
        run(alone, TB_METHOD_RK4, TB_VECTOR_PATH_AUTO, 1, 1.0, &stats);
        assert_memory_equal(tb_scene_states_const(alone),
                            tb_scene_states_const(shifted) + TB_STATE_SIZE * (SHIFT + seeds[s]),
                            TB_STATE_SIZE * sizeof(double));
        tb_scene_destroy(alone);
    }
    tb_scene_destroy(shifted);
}

/* 40 copies of the asymmetric top (I = (1, 2, 3) kg m^2), each spun at its own rate
 * omega_body(0) = s (1.5, 0, 1), s from 0.5 to 1.28, on every lane path: no torque acts, so each
 * world L stays what it was to the bit (the state holds L, and dL/dt is exactly 0); and each
 * body-frame angular velocity follows the Jacobi elliptic solution of Euler's equations
 * (tests/support/torque_free_top.c) to 1e-8 rad/s after 4 s at 480 steps/s (RK4's error there
 * is at most (omega h)^4 omega T ~ 6e-9; measured 1e-11), which a lane computed with another's
 * rate or moments would miss by ~1e-1. */
static void test_free_tops_in_lanes_keep_their_momentum_and_follow_euler(void **state)
{
    (void)state;
    enum { TOPS = 40 };
    for (int p = FIRST_LANE_PATH; p < TB_VECTOR_PATH_COUNT; ++p) {
        if (!tb_vector_path_supported((tb_vector_path)p)) {
            continue;
        }
        tb_scene *scene = new_scene();
        for (size_t i = 0; i < TOPS; ++i) {
            const double s = 0.5 + 0.02 * (double)i;
            tb_body_def body = tb_body_def_default();
            body.mass = (tb_mass_properties){1.0, {0, 0, 0}, {1.0, 2.0, 3.0}, {1, 0, 0, 0}};
            memcpy(body.orientation, test_top_q0, sizeof body.orientation);
            /* world angular velocity R omega_body */
            const double *q = test_top_q0;
            const double w_body[3] = {1.5 * s, 0.0, 1.0 * s};
            tb_scene *one = test_scene_one_body(1.0, test_top_moments, q, w_body);
            assert_int_equal(tb_scene_body_angular_velocity(one, tb_scene_states_const(one), 0,
                                                            body.angular_velocity),
                             TB_STATUS_OK);
            tb_scene_destroy(one);
            assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
        }
        static double L0[TOPS][3];
        for (size_t i = 0; i < TOPS; ++i) {
            memcpy(L0[i], tb_scene_states_const(scene) + TB_STATE_SIZE * i + TB_STATE_L,
                   sizeof L0[i]);
        }
        tb_integrator_stats stats;
        run(scene, TB_METHOD_RK4, (tb_vector_path)p, 1, 4.0, &stats);
        double worst = 0.0;
        for (size_t i = 0; i < TOPS; ++i) {
            const double s = 0.5 + 0.02 * (double)i;
            assert_memory_equal(tb_scene_states_const(scene) + TB_STATE_SIZE * i + TB_STATE_L,
                                L0[i], sizeof L0[i]);
            torque_free_top exact;
            assert_int_equal(torque_free_top_init(&exact, test_top_moments, 1.5 * s, 1.0 * s), 0);
            double expected[3], got[3];
            torque_free_top_omega(&exact, 4.0, expected);
            test_body_omega(scene, i, got);
            for (int k = 0; k < 3; ++k) {
                worst = fmax(worst, fabs(got[k] - expected[k]));
            }
        }
        print_message("%s: largest body-rate error %.2g rad/s\n",
                      tb_vector_path_name((tb_vector_path)p), worst);
        assert_true(worst < 1e-8);
        tb_scene_destroy(scene);
    }
}

/* An unknown path is refused, and a refused path leaves the choice as it was; threads < 0 and
 * threads for an adaptive method are refused, naming the field. */
static void test_bad_paths_and_thread_counts_are_refused(void **state)
{
    (void)state;
    tb_scene *scene = every_per_body_effect(12);
    assert_int_equal(tb_scene_set_vector_path(scene, TB_VECTOR_PATH_NONE), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_vector_path(scene, TB_VECTOR_PATH_COUNT),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_scene_set_vector_path(scene, (tb_vector_path)-1),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "path"));
    assert_int_equal(tb_scene_vector_path(scene), TB_VECTOR_PATH_NONE);
    for (int p = 0; p < TB_VECTOR_PATH_COUNT; ++p) {
        const tb_status status = tb_scene_set_vector_path(scene, (tb_vector_path)p);
        assert_int_equal(status, tb_vector_path_supported((tb_vector_path)p)
                                     ? TB_STATUS_OK
                                     : TB_STATUS_UNSUPPORTED);
        tb_vector_path parsed;
        assert_int_equal(tb_vector_path_parse(tb_vector_path_name((tb_vector_path)p), &parsed),
                         TB_STATUS_OK);
        assert_int_equal(parsed, p);
    }
    tb_vector_path parsed = TB_VECTOR_PATH_NONE;
    assert_int_equal(tb_vector_path_parse("sse9", &parsed), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(parsed, TB_VECTOR_PATH_NONE);
    assert_true(tb_vector_path_supported(tb_vector_path_best()));
    assert_null(tb_vector_path_name(TB_VECTOR_PATH_COUNT));
    tb_integrator_def def = tb_integrator_def_default();
    def.threads = -1;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "def.threads"));
    assert_null(integrator);
    def = tb_integrator_def_default();
    def.method = TB_METHOD_CVODE_ADAMS;
    def.threads = 2;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_non_null(strstr(tb_scene_detail(scene), "def.threads"));
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_path_and_thread_count_gives_the_body_by_body_bits),
        cmocka_unit_test(test_a_body_moves_the_same_in_any_lane_of_any_scene),
        cmocka_unit_test(test_free_tops_in_lanes_keep_their_momentum_and_follow_euler),
        cmocka_unit_test(test_bad_paths_and_thread_counts_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
