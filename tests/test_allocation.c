/* Memory is allocated when objects are created, never per step or per derivative. This test
 * replaces malloc and friends for the whole process (the executable's definitions take
 * precedence over libc's for every caller, the shared libtumble included) and counts calls
 * while scenes are stepped. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "counting_malloc.h"
#include "fixtures.h"
#include "joint_scenes.h"
#include "tumble/tumble.h"

#include <stdlib.h>
#include <string.h>

/* The counter is live: creating a scene is seen to allocate, so a zero below means
 * something. */
static void test_the_counter_sees_allocations(void **state)
{
    (void)state;
    const long before = counted_allocations;
    tb_scene *scene = test_scene_one_body(1.0, (double[]){1, 2, 3}, NULL, (double[]){1, 0, 1});
    assert_true(counted_allocations > before);
    tb_scene_destroy(scene);
}

/* Every method, and BDF with both linear solvers (one body: dense; six bodies, 78 unknowns:
 * Krylov). CVODE completes its set-up inside its first CVode call, so the adaptive methods
 * get one warm-up advance; after it, long runs (including Jacobian re-evaluations, which
 * BDF makes at least every 50 steps) must allocate nothing. */
static void run_without_allocating(tb_method method, int bodies)
{
    tb_scene *scene = test_scene_one_body(1.0, (double[]){1, 2, 3}, NULL, (double[]){1, 0, 1});
    for (int k = 1; k < bodies; ++k) {
        tb_body_def def = tb_body_def_default();
        assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.5, &def.mass, NULL),
                         TB_STATUS_OK);
        def.position[0] = k;
        def.angular_velocity[2] = k;
        assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    assert_int_equal(
        tb_scene_add_force(scene, 0, (double[]){1, 0, 0}, (double[]){0, 1, 0}, TB_FRAME_BODY),
        TB_STATUS_OK);
    tb_integrator_def def = tb_integrator_def_default();
    def.method = method;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    if (tb_method_is_adaptive(method)) {
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK);
    }
    const long before = counted_allocations;
    for (int frame = 1; frame <= 300; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
    }
    for (int k = 0; k < 100; ++k) {
        assert_int_equal(tb_integrator_step(integrator), TB_STATUS_OK);
    }
    double energy, P[3], L[3], y_dot[6 * TB_STATE_SIZE];
    const double *y = tb_scene_states(scene);
    tb_scene_kinetic_energy(scene, y, &energy);
    tb_scene_linear_momentum(scene, y, P);
    tb_scene_angular_momentum(scene, y, (double[]){0, 0, 0}, L);
    tb_scene_derivative(0.0, y, y_dot, scene);
    tb_integrator_stats stats;
    tb_integrator_get_stats(integrator, &stats);
    const long during = counted_allocations - before;
    print_message("%-12s %d bodies: %6ld steps, %6ld derivatives (%ld for Jacobians), %ld "
                  "allocations\n",
                  tb_method_name(method), bodies, stats.steps, stats.derivative_evals,
                  stats.jacobian_derivative_evals, during);
    assert_int_equal(during, 0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_stepping_allocates_nothing(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        run_without_allocating((tb_method)m, 1);
    }
    run_without_allocating(TB_METHOD_CVODE_BDF, 6);
}

/* Every kind of effect at once: drag, a spring between bodies, a ground plane with friction
 * state, a user callback, on boxes resting on the ground. */
static int user_push(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    tb_effect_add_torque(scene, dydt, 0, (double[]){0, 0, 0.1});
    (void)y;
    return 0;
}

static void test_stepping_with_every_effect_allocates_nothing(void **state)
{
    (void)state;
    for (int m = TB_METHOD_RK4; m < TB_METHOD_COUNT; ++m) {
        tb_scene_def scene_def = tb_scene_def_default();
        tb_scene *scene = NULL;
        assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
        const double size[3] = {0.2, 0.3, 0.4};
        tb_contact_point corners[8];
        size_t count;
        tb_contact_points_box(size, corners, 8, &count);
        for (int k = 0; k < 2; ++k) {
            tb_body_def def = tb_body_def_default();
            tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &def.mass, NULL);
            def.position[0] = k;
            def.position[2] = 0.2;
            def.velocity[0] = 1.0;
            assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
            assert_int_equal(tb_scene_set_contact_points(scene, (size_t)k, corners, count, 4),
                             TB_STATUS_OK);
        }
        tb_scene_add_gravity(scene, (double[]){0, 0, -9.81});
        tb_drag_def drag = tb_drag_def_default();
        drag.linear = 0.1;
        drag.angular = 0.1;
        tb_scene_add_drag(scene, &drag);
        tb_spring_def spring = tb_spring_def_default();
        spring.body_a = 1;
        spring.body_b = 0;
        spring.stiffness = 10.0;
        spring.rest_length = 1.0;
        tb_scene_add_spring(scene, &spring);
        tb_ground_def ground = tb_ground_def_default();
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        tb_scene_add_user_effect(scene, user_push, NULL);
        tb_integrator_def def = tb_integrator_def_default();
        def.method = (tb_method)m;
        def.dt = tb_method_is_adaptive(def.method) ? def.dt : 0.0; /* the stiff contact's step */
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK); /* warm-up */
        const long before = counted_allocations;
        /* rosenbrock factors a dense matrix at each of its ~60 000 default steps a second: a
         * quarter second (15 frames, past the warm-up's first contacts) keeps the test's CPU
         * far under its budget; the others run 2 s */
        const int frames = m == TB_METHOD_ROSENBROCK ? 15 : 120;
        for (int frame = 1; frame <= frames; ++frame) {
            assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        }
        assert_int_equal(counted_allocations - before, 0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* Building a scene body by body, each with its contact point (what the scene loader does),
 * grows every array by doubling: 10000 bodies cost a few allocations per doubling, not one or
 * more per body. Setting the points copied every body's points at every body (O(n^2): 100000
 * bodies took minutes to load); 200 allows ~14 doublings of each of a dozen arrays. */
static void test_building_a_scene_allocates_per_doubling_not_per_body(void **state)
{
    (void)state;
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    const tb_contact_point centre = {{0, 0, 0}, 0.1};
    const long before = counted_allocations;
    for (int k = 0; k < 10000; ++k) {
        def.position[0] = 0.5 * k;
        size_t id;
        assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
        assert_int_equal(tb_scene_set_contact_points(scene, id, &centre, 1, 1), TB_STATUS_OK);
    }
    print_message("10000 bodies with a contact point each: %ld allocations\n",
                  counted_allocations - before);
    assert_true(counted_allocations - before < 200);
    tb_scene_destroy(scene);
}

/* Contact between bodies: a row of boxes and balls with shapes, pushed into each other on the
 * ground, under every method. The pairs hook is made when the effect is added; stepping through
 * the collisions allocates nothing. */
static void test_contact_between_bodies_allocates_nothing(void **state)
{
    (void)state;
    /* rosenbrock is left out: its default step is taken where nothing touches yet (1/240 s), and
     * there the box-sphere collisions of this row blow up (docs/integrators.md, "rosenbrock"); its
     * first contacts also grow the scene's Jacobian pattern, which allocates by design */
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        if (m == TB_METHOD_ROSENBROCK) {
            continue;
        }
        tb_scene_def scene_def = tb_scene_def_default();
        tb_scene *scene = NULL;
        assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
        for (int k = 0; k < 6; ++k) {
            tb_body_def def = tb_body_def_default();
            tb_shape shape = tb_shape_default();
            if (k % 2 == 0) {
                shape.type = TB_SHAPE_BOX;
                shape.size[0] = shape.size[1] = shape.size[2] = 0.1;
                tb_mass_from_box(TB_MASS_GIVEN, 1.0, shape.size, &def.mass, NULL);
            } else {
                shape.type = TB_SHAPE_SPHERE;
                shape.radius = 0.05;
                tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.05, &def.mass, NULL);
            }
            def.position[0] = 0.12 * k;
            def.position[2] = 0.05;
            def.velocity[0] = k == 0 ? 1.0 : 0.0;
            size_t id = 0;
            assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
            assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
        }
        tb_contact_def contact = tb_contact_def_default();
        assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
        tb_integrator_def def = tb_integrator_def_default();
        assert_int_equal(tb_integrator_def_set_method(&def, (tb_method)m), TB_STATUS_OK);
        if (!tb_method_is_adaptive((tb_method)m)) {
            def.dt = 0.0; /* the scene's default step */
        }
        tb_integrator *integrator = NULL;
        assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(integrator, 0.01), TB_STATUS_OK); /* warm-up */
        const long before = counted_allocations;
        for (int frame = 1; frame <= 60; ++frame) { /* frame by frame: the step budget */
            assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        }
        print_message("%s: %ld allocations while colliding\n", tb_method_name((tb_method)m),
                      counted_allocations - before);
        assert_int_equal(counted_allocations - before, 0);
        const double *y = tb_scene_states(scene);
        assert_true(y[TB_STATE_SIZE * 5 + TB_STATE_P] > 0.1); /* the push reached the last body */
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* The joints' stage and projection (a double pendulum on hinges): no allocation per step or
 * derivative under any method, after a first advance (CVODE's own first-call set-up). */
static void test_stepping_jointed_bodies_allocates_nothing(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        tb_scene *scene = test_double_pendulum(1.0, 0.5, NULL);
        tb_integrator *integrator = test_integrator_for(scene, (tb_method)m, 1.0 / 960.0, 1e-8);
        assert_int_equal(tb_integrator_advance(integrator, 0.1), TB_STATUS_OK);
        const long before = counted_allocations;
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
        assert_int_equal(counted_allocations, before);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A block resting on a slider's stop (held: the stop's row in the solve, its push checked at
 * every boundary or root) and a wheel driven by a capped motor: once the stop holds (by 0.5 s),
 * stepping allocates nothing under any method. */
static void test_stepping_stops_and_motors_allocates_nothing(void **state)
{
    (void)state;
    for (int m = 0; m < TB_METHOD_COUNT; ++m) {
        tb_scene *scene = test_empty_scene();
        const double size[3] = {0.2, 0.2, 0.2}, x[3] = {0.0, 0.0, 0.0}, far[3] = {3.0, 0.0, 0.0};
        const size_t block = test_add_box(scene, 2.0, size, x);
        const size_t wheel = test_add_box(scene, 6.0, size, far);
        const double g[3] = {0.0, 0.0, -9.81};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_SLIDER;
        def.body_a = block;
        def.axis[2] = -1.0;
        def.has_limits = 1;
        def.limits[0] = -1.0;
        def.limits[1] = 0.1;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        def = tb_joint_def_default();
        def.type = TB_JOINT_HINGE;
        def.body_a = wheel;
        memcpy(def.anchor, far, sizeof far);
        def.motor = TB_MOTOR_VELOCITY;
        def.motor_speed = 100.0; /* capped all along */
        def.motor_max_force = 0.1;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, (tb_method)m, 1.0 / 960.0, 1e-8);
        assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
        const long before = counted_allocations;
        assert_int_equal(tb_integrator_advance(integrator, 1.5), TB_STATUS_OK);
        assert_int_equal(counted_allocations, before);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_counter_sees_allocations),
        cmocka_unit_test(test_stepping_allocates_nothing),
        cmocka_unit_test(test_stepping_with_every_effect_allocates_nothing),
        cmocka_unit_test(test_building_a_scene_allocates_per_doubling_not_per_body),
        cmocka_unit_test(test_contact_between_bodies_allocates_nothing),
        cmocka_unit_test(test_stepping_jointed_bodies_allocates_nothing),
        cmocka_unit_test(test_stepping_stops_and_motors_allocates_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
