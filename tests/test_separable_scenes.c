/* Scenes whose bodies do not interact are separable ODE systems: the fixed-step integrators
 * step them a chunk of bodies at a time, and must give what stepping the whole state array
 * gives, with every per-body effect. Effects that couple bodies or own states make the scene
 * one block. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "near.h"
#include "span.h"
#include "tumble/tumble.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* Euler, midpoint and RK4: the fixed-step methods come first in tb_method. */
#define FIXED_STEP_METHODS (TB_METHOD_RK4 + 1)

#define BODIES 40 /* 520 states: several chunks, the last one partial */

/* 40 boxes of different sizes, each moving and spinning its own way, under gravity, drag on
 * all of them and on one, a spring to a world anchor, constant forces and torques in both
 * frames: every effect that acts on bodies one by one (36 of them). */
static tb_scene *every_per_body_effect(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    for (size_t i = 0; i < BODIES; ++i) {
        tb_body_def body = tb_body_def_default();
        const double k = (double)i;
        assert_int_equal(tb_mass_from_box(TB_MASS_DENSITY, 500.0,
                                          (double[]){0.1 + 0.01 * k, 0.2, 0.3 - 0.005 * k},
                                          &body.mass, NULL),
                         TB_STATUS_OK);
        body.position[0] = k;
        body.velocity[1] = 0.1 * k;
        body.velocity[2] = 3.0;
        body.angular_velocity[0] = 1.0 + 0.3 * k;
        body.angular_velocity[1] = 2.0 - 0.1 * k;
        body.angular_velocity[2] = 0.5;
        assert_int_equal(tb_scene_add_body(scene, &body, NULL), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_drag_def drag = tb_drag_def_default();
    drag.linear = 0.3;
    drag.quadratic = 0.05;
    drag.angular = 0.01;
    drag.angular_quadratic = 0.002;
    assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
    drag.body = 3;
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
    assert_int_equal(tb_scene_add_force(scene, 7, push, at, TB_FRAME_WORLD), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_force(scene, 11, push, at, TB_FRAME_BODY), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_torque(scene, 13, push, TB_FRAME_WORLD), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_torque(scene, 39, push, TB_FRAME_BODY), TB_STATUS_OK);
    /* and many more single-body effects, added out of body order, some bodies holding several */
    for (size_t i = BODIES; i-- > 0;) {
        if (i % 3 == 0) {
            const double turn[3] = {0.1 * (double)i, 0.0, -0.2};
            assert_int_equal(tb_scene_add_torque(scene, i, turn, TB_FRAME_BODY), TB_STATUS_OK);
            assert_int_equal(tb_scene_add_force(scene, (7 * i) % BODIES, push, at, TB_FRAME_WORLD),
                             TB_STATUS_OK);
        }
    }
    return scene;
}

static size_t block_size(tb_scene *scene)
{
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    return system.blocks.size;
}

/* Both paths do the same arithmetic on every state in the same order (the same effects in the
 * same order, then the renormalisation), so they agree to the last bit; the tolerance
 * (2 DBL_EPSILON, relative above 1) only allows a compiler to contract a * b + c into one
 * rounding in one loop and not in the other. */
static void test_bodies_that_do_not_interact_step_chunkwise_as_the_whole_array(void **state)
{
    (void)state;
    for (int m = 0; m < FIXED_STEP_METHODS; ++m) {
        tb_scene *chunked = every_per_body_effect(), *whole = every_per_body_effect();
        assert_int_equal(block_size(chunked), TB_STATE_SIZE);
        tb_integrator_def def = tb_integrator_def_default();
        def.method = (tb_method)m;
        def.dt = 1.0 / 960;
        tb_integrator *a = NULL, *b = NULL;
        assert_int_equal(tb_scene_integrator_create(chunked, &def, 0.0, &a), TB_STATUS_OK);
        tb_ode_system system;
        assert_int_equal(tb_scene_ode_system(whole, &system), TB_STATUS_OK);
        system.blocks.size = 0;
        assert_int_equal(tb_integrator_create(&system, &def, 0.0, tb_scene_states(whole), &b, NULL),
                         TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(a, 2.0), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(b, 2.0), TB_STATUS_OK);
        const double *ya = tb_scene_states_const(chunked), *yb = tb_scene_states_const(whole);
        double largest = 0.0;
        for (size_t i = 0; i < TB_STATE_SIZE * BODIES; ++i) {
            largest = fmax(largest, fabs(ya[i] - yb[i]));
            assert_near(ya[i], yb[i], 2 * DBL_EPSILON * fmax(1.0, fabs(yb[i])));
        }
        print_message("%-8s largest difference %.3g\n", tb_method_name((tb_method)m), largest);
        assert_near(tb_scene_quaternion_drift(chunked), tb_scene_quaternion_drift(whole), 0.0);
        tb_integrator_destroy(a);
        tb_integrator_destroy(b);
        tb_scene_destroy(chunked);
        tb_scene_destroy(whole);
    }
}

static int nothing(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)scene, (void)y, (void)dydt, (void)ctx;
    return 0;
}

/* A spring between two bodies, a ground plane (friction states of its own) and a user callback
 * (which may read any body) couple the bodies: the scene is then one block. */
static void test_coupling_effects_make_the_scene_one_block(void **state)
{
    (void)state;
    for (int coupling = 0; coupling < 3; ++coupling) {
        tb_scene *scene = every_per_body_effect();
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = 1;
        spring.body_b = 2;
        spring.stiffness = 10.0;
        tb_ground_def ground = tb_ground_def_default();
        switch (coupling) {
        case 0:
            assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
            break;
        case 1:
            assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
            break;
        default:
            assert_int_equal(tb_scene_add_user_effect(scene, nothing, NULL), TB_STATUS_OK);
        }
        assert_int_equal(block_size(scene), 0);
        tb_scene_destroy(scene);
    }
}

/* The integrator steps the scene it was made from. A coupling effect added afterwards would be
 * ignored by chunks of independent bodies; the step refuses instead, and loses nothing. */
static void test_coupling_added_after_the_integrator_stops_the_run_unchanged(void **state)
{
    (void)state;
    tb_scene *scene = every_per_body_effect();
    tb_integrator_def def = tb_integrator_def_default();
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
    tb_spring_def spring = tb_spring_def_default();
    spring.body_a = 1;
    spring.body_b = 30;
    spring.stiffness = 10.0;
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    static double before[TB_STATE_SIZE * BODIES];
    memcpy(before, tb_scene_states_const(scene), sizeof before);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_LAYOUT_CHANGED);
    assert_memory_equal(tb_scene_states_const(scene), before, sizeof before);
    assert_near(tb_integrator_time(integrator), 0.5, 0.0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* 30 balls, each on its own stiff damped spring to a world anchor above it (k/m from 1e4 to
 * 3e5 s^-2, up to 550 rad/s), under gravity, released 5 cm from rest length. */
static tb_scene *balls_on_stiff_springs(void)
{
    tb_scene_def def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&def, &scene, NULL), TB_STATUS_OK);
    for (size_t i = 0; i < 30; ++i) {
        tb_body_def body = tb_body_def_default();
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &body.mass, NULL),
                         TB_STATUS_OK);
        body.position[0] = (double)i;
        body.position[2] = -1.05;
        size_t id;
        assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = id;
        spring.point_b[0] = (double)i;
        spring.stiffness = 1e4 * (double)(i + 1);
        spring.damping = 2.0;
        spring.rest_length = 1.0;
        assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    return scene;
}

/* Largest |z_a - z_b| over the balls at the end. */
static double largest_height_difference(const tb_scene *a, const tb_scene *b)
{
    double largest = 0.0;
    for (size_t i = 0; i < tb_scene_body_count(a); ++i) {
        const double za = tb_scene_states_const(a)[TB_STATE_SIZE * i + 2];
        const double zb = tb_scene_states_const(b)[TB_STATE_SIZE * i + 2];
        largest = fmax(largest, fabs(za - zb));
    }
    return largest;
}

static void run(tb_scene *scene, const tb_integrator_def *def, int whole_array, double T,
                tb_integrator_stats *stats)
{
    tb_ode_system system;
    assert_int_equal(tb_scene_ode_system(scene, &system), TB_STATUS_OK);
    if (whole_array) {
        system.blocks.size = 0;
    }
    tb_integrator_def scene_def = *def;
    double atol[30 * TB_STATE_SIZE];
    if (tb_method_is_adaptive(def->method)) {
        assert_int_equal(tb_scene_absolute_tolerances(scene, 1e-2 * def->rtol, atol), TB_STATUS_OK);
        scene_def.atol_vector = atol;
    }
    tb_integrator *integrator = NULL;
    assert_int_equal(
        tb_integrator_create(&system, &scene_def, 0.0, tb_scene_states(scene), &integrator, NULL),
        TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, T), TB_STATUS_OK);
    if (stats != NULL) {
        tb_integrator_get_stats(integrator, stats);
    }
    tb_integrator_destroy(integrator);
}

/* For independent bodies BDF's Krylov solver is preconditioned block by block: J is block
 * diagonal, so P = I - gamma J is the Newton matrix itself and GMRES converges in one
 * iteration per Newton iteration (here about one a step: measured 1.004, we allow 1.1; a
 * preconditioner with gamma 20% off needs 1.3), as with the banded
 * preconditioner covering each body's block (also exact here). Both follow RK4 at h = 1e-5 s
 * (omega h <= 0.0055: its error ~1e-12 m) to 1e-6 m at rtol 1e-9 (CVODE's global error ~
 * steps x rtol x |z|, here ~1e-7 m). */
static void test_bdf_preconditions_independent_bodies_block_by_block(void **state)
{
    (void)state;
    /* under memcheck 0.02 s: the error bound holds a fortiori (CVODE's global error grows with
     * the steps taken) and the Krylov iterations per step are a per-step property */
    const double T = tb_test_span(0.2, 0.02);
    tb_scene *reference = balls_on_stiff_springs(), *block = balls_on_stiff_springs(),
             *band = balls_on_stiff_springs();
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 1e-5;
    run(reference, &def, 0, T, NULL);
    tb_integrator_def_set_method(&def, TB_METHOD_CVODE_BDF); /* dt back to its default */
    def.rtol = 1e-9;
    def.linear_solver = TB_LINEAR_SOLVER_KRYLOV;
    def.preconditioner_half_bandwidth = TB_STATE_SIZE - 1;
    tb_integrator_stats with_blocks, with_band;
    run(block, &def, 0, T, &with_blocks);
    run(band, &def, 1, T, &with_band);
    const double block_error = largest_height_difference(block, reference);
    const double band_error = largest_height_difference(band, reference);
    const tb_integrator_stats *s[2] = {&with_blocks, &with_band};
    for (int k = 0; k < 2; ++k) {
        print_message("%-6s error %.3g m, %ld steps, %ld Krylov iterations, %ld derivatives "
                      "(%ld for preconditioners)\n",
                      k == 0 ? "blocks" : "band", k == 0 ? block_error : band_error, s[k]->steps,
                      s[k]->linear_iterations, s[k]->derivative_evals,
                      s[k]->jacobian_derivative_evals);
    }
    assert_true(block_error <= 1e-6);
    assert_true(band_error <= 1e-6);
    assert_true((double)with_blocks.linear_iterations <= 1.1 * (double)with_blocks.steps);
    assert_true((double)with_band.linear_iterations <= 1.1 * (double)with_band.steps);
    tb_scene_destroy(reference);
    tb_scene_destroy(block);
    tb_scene_destroy(band);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bodies_that_do_not_interact_step_chunkwise_as_the_whole_array),
        cmocka_unit_test(test_coupling_effects_make_the_scene_one_block),
        cmocka_unit_test(test_coupling_added_after_the_integrator_stops_the_run_unchanged),
        cmocka_unit_test(test_bdf_preconditions_independent_bodies_block_by_block),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
