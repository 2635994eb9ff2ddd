/* Joint limits (issue 21): a stop reverses the axial rate times its restitution at the impact
 * and then holds the joint while it pushes. Each test checks physics known without the code (a
 * free rotation at constant speed, statics on an incline); tolerances are stated with their
 * reasons. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#define DOOR_SPEED 2.0 /* rad/s, the push that opens it */
#define DOOR_E 0.5     /* the stop's restitution */
#define DOOR_OPEN (TEST_PI / 2.0)

/* A 20 kg door (1 m wide along x, 2 m tall, 5 cm thick) on one hinge about the vertical axis
 * through its edge at the origin, limits [0, 90 degrees] with restitution DOOR_E, pushed open
 * at DOOR_SPEED; gravity acts along the axis, so nothing turns it but the stops. */
static tb_scene *door_scene(size_t *door)
{
    tb_scene *scene = test_empty_scene();
    tb_body_def def = tb_body_def_default();
    const double size[3] = {1.0, 0.05, 2.0};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 20.0, size, &def.mass, NULL), TB_STATUS_OK);
    def.position[0] = 0.5;
    def.angular_velocity[2] = DOOR_SPEED;
    def.velocity[1] = 0.5 * DOOR_SPEED; /* omega x (centre - hinge): the hinge at rest */
    assert_int_equal(tb_scene_add_body(scene, &def, door), TB_STATUS_OK);
    const double g[3] = {0.0, 0.0, -TEST_G};
    assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
    tb_joint_def joint = tb_joint_def_default();
    joint.type = TB_JOINT_HINGE;
    joint.body_a = *door;
    joint.has_limits = 1;
    joint.limits[1] = DOOR_OPEN;
    joint.restitution = DOOR_E;
    assert_int_equal(tb_scene_add_joint(scene, &joint, NULL), TB_STATUS_OK);
    return scene;
}

/* The door's angle about z from its start (its free edge's direction). */
static double door_angle(tb_scene *scene, size_t door)
{
    const double edge[3] = {0.5, 0.0, 0.0};
    double p[3];
    assert_int_equal(tb_scene_body_point(scene, tb_scene_states(scene), door, edge, p, NULL),
                     TB_STATUS_OK);
    return atan2(p[1], p[0]);
}

static double door_speed(tb_scene *scene, size_t door)
{
    double omega[3];
    assert_int_equal(tb_scene_body_angular_velocity(scene, tb_scene_states(scene), door, omega),
                     TB_STATUS_OK);
    return omega[2];
}

typedef struct door_run {
    double speed_error; /* largest |omega - exact| away from the impact, rad/s */
    double angle_error; /* largest |angle - exact| after the impact, rad */
    double overshoot;   /* largest angle past the stop at a frame, rad */
} door_run;

/* Runs the door for 1.5 s (frames at 100 Hz): it swings at DOOR_SPEED to the stop at
 * t1 = DOOR_OPEN / DOOR_SPEED = 0.785 s, and comes back at DOOR_E DOOR_SPEED (it reaches the
 * other stop at 2.36 s, after the run). */
static door_run run_door(tb_method method, double dt, double rtol)
{
    size_t door = 0;
    tb_scene *scene = door_scene(&door);
    tb_integrator *integrator = test_integrator_for(scene, method, dt, rtol);
    const double t1 = DOOR_OPEN / DOOR_SPEED, back = DOOR_E * DOOR_SPEED;
    door_run out = {0.0, 0.0, 0.0};
    for (int frame = 1; frame <= 150; ++frame) {
        const double t = frame / 100.0;
        const tb_status status = tb_integrator_advance(integrator, t);
        if (status != TB_STATUS_OK) {
            print_message("%s\n", tb_integrator_detail(integrator));
        }
        assert_int_equal(status, TB_STATUS_OK);
        const double angle = door_angle(scene, door), speed = door_speed(scene, door);
        out.overshoot = fmax(out.overshoot, angle - DOOR_OPEN);
        if (t < t1 - 0.02 || t > t1 + 0.02) { /* a frame's width clear of the impact */
            const double exact = t < t1 ? DOOR_SPEED : -back;
            out.speed_error = fmax(out.speed_error, fabs(speed - exact));
        }
        if (t > t1 + 0.02) {
            out.angle_error = fmax(out.angle_error, fabs(angle - (DOOR_OPEN - back * (t - t1))));
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return out;
}

/* The door pushed open stops at 90 degrees and comes back at e times its speed, under every
 * method. A free rotation about a fixed axis keeps its speed exactly (no torque about the
 * axis), so the speed after the impact is e DOOR_SPEED up to each method's own error on a
 * constant rotation: RK4's round-off (bound 1e-12 rad/s), midpoint's (omega dt)^3 per step
 * (bound 1e-7), Euler's growth of the speed on a circle by (omega dt)^2 / 2 a step, 0.65% over
 * the 188 steps to the stop (bound 1.5e-2 rad/s), CVODE's tolerance (rtol 1e-8, bound 1e-6).
 * A fixed step finds the impact at the end of the step that crosses the stop, d past it, and
 * puts the door e d short of the stop, where it would be at its speed: exact for a constant
 * speed, so the angle after the impact is the exact swing's up to the method's own error:
 * RK4 round-off (bound 1e-10 rad), midpoint's phase error (bound 1e-4 rad), Euler's speed
 * error over the swing (bound 1e-2 rad); CVODE locates the impact by its root, to its
 * tolerance (bound 1e-6 rad).
 * No frame is past the stop by more than the projection's 1e-12 rad. */
static void test_door_stops_at_its_limit_and_bounces_back_at_e_times_its_speed(void **state)
{
    (void)state;
    static const struct {
        tb_method method;
        double dt, rtol, speed_bound, angle_bound;
    } runs[] = {
        {TB_METHOD_EULER, 1.0 / 240.0, 0.0, 1.5e-2, 1e-2},
        {TB_METHOD_MIDPOINT, 1.0 / 240.0, 0.0, 1e-7, 1e-4},
        {TB_METHOD_RK4, 1.0 / 240.0, 0.0, 1e-12, 1e-10},
        {TB_METHOD_CVODE_ADAMS, 0.0, 1e-8, 1e-6, 1e-6},
        {TB_METHOD_CVODE_BDF, 0.0, 1e-8, 1e-6, 1e-6},
    };
    for (size_t k = 0; k < sizeof runs / sizeof runs[0]; ++k) {
        const door_run r = run_door(runs[k].method, runs[k].dt, runs[k].rtol);
        print_message("door %s: speed error %.3g rad/s, angle error %.3g rad, overshoot %.3g "
                      "rad\n",
                      tb_method_name(runs[k].method), r.speed_error, r.angle_error, r.overshoot);
        assert_true(r.speed_error <= runs[k].speed_bound);
        assert_true(r.angle_error <= runs[k].angle_bound);
        assert_true(r.overshoot <= 1e-12);
    }
}

/* A 2 kg block on a slider down a 30 degree incline (gravity only), stopped after 0.2 m by
 * its upper limit (restitution 0): it slides g sin 30 t^2 / 2 to the stop, then rests on it,
 * and the joint's reaction is then statics': minus its weight, (0, 0, m g), whose component
 * along the incline, m g sin 30, is the stop's push. RK4 at 1/240 s and CVODE BDF: the block
 * rests at 0.2 m to the projection's 1e-12 m, the reaction to 1e-9 of m g (round-off of the
 * solve; the block does not move). */
static void test_slider_stop_holds_a_block_with_its_weight_component(void **state)
{
    (void)state;
    const double m = 2.0, s30 = 0.5, c30 = sqrt(3.0) / 2.0, travel = 0.2;
    const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (int k = 0; k < 2; ++k) {
        tb_scene *scene = test_empty_scene();
        const double size[3] = {0.2, 0.2, 0.2}, x[3] = {0.0, 0.0, 0.0};
        const size_t block = test_add_box(scene, m, size, x);
        const double g[3] = {0.0, 0.0, -TEST_G};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_SLIDER;
        def.body_a = block;
        const double axis[3] = {c30, 0.0, -s30}; /* downhill */
        memcpy(def.axis, axis, sizeof axis);
        def.has_limits = 1;
        def.limits[0] = -1.0;
        def.limits[1] = travel;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        tb_integrator *integrator =
            test_integrator_for(scene, methods[k], k == 0 ? 1.0 / 240.0 : 0.0, 1e-8);
        const double t_stop = sqrt(2.0 * travel / (TEST_G * s30));
        assert_int_equal(tb_integrator_advance(integrator, 0.5 * t_stop), TB_STATUS_OK);
        double v[3], p[3], f[3], tau[3];
        const double *y = tb_scene_states(scene);
        assert_int_equal(tb_scene_body_velocity(scene, y, block, v), TB_STATUS_OK);
        const double half = TEST_G * s30 * 0.5 * t_stop; /* speed at half the time */
        assert_true(fabs(v[0] * c30 - v[2] * s30 - half) <= 1e-6 * half);
        assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
        y = tb_scene_states(scene);
        assert_int_equal(tb_scene_body_point(scene, y, block, x, p, NULL), TB_STATUS_OK);
        assert_int_equal(tb_scene_body_velocity(scene, y, block, v), TB_STATUS_OK);
        assert_int_equal(tb_scene_joint_reaction(scene, tb_scene_states(scene), 0, f, tau),
                         TB_STATUS_OK);
        const double along = f[0] * c30 - f[2] * s30; /* N, downhill */
        print_message("slider stop %s: travel %.17g m, speed %.3g m/s, reaction (%.17g, %.3g, "
                      "%.17g) N, along the incline %.17g N\n",
                      tb_method_name(methods[k]), p[0] * c30 - p[2] * s30,
                      sqrt(v[0] * v[0] + v[2] * v[2]), f[0], f[1], f[2], along);
        assert_true(fabs(p[0] * c30 - p[2] * s30 - travel) <= 1e-12);
        assert_true(sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) <= 1e-9);
        assert_true(fabs(f[2] - m * TEST_G) <= 1e-9 * m * TEST_G);
        assert_true(fabs(f[0]) <= 1e-9 * m * TEST_G && fabs(f[1]) <= 1e-9 * m * TEST_G);
        assert_true(fabs(along + m * TEST_G * s30) <= 1e-9 * m * TEST_G);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A 2 kg weight falls along a vertical slider onto its stop 0.3 m down (restitution 0); the
 * slider breaks above break_force. In free fall along the axis the joint carries nothing;
 * from the landing, t = sqrt(2 0.3 / g) = 0.2473 s, the stop holds the weight and statics
 * says the reaction is m g = 19.62 N. With a 15 N limit the joint breaks there: at the end of
 * the step that lands (RK4 at 1/240 s: within one step after the landing), or the first output
 * after it (CVODE BDF read every 1/240 s: breaking is checked as an advance starts, so the read
 * after that one shows it: within two reads); then the weight falls freely. With a 25 N limit it
 * holds, the weight resting on the stop. */
static void test_slider_breaks_when_a_falling_weight_lands_on_its_stop(void **state)
{
    (void)state;
    const double m = 2.0, drop = 0.3, t_land = sqrt(2.0 * drop / TEST_G), dt = 1.0 / 240.0;
    const tb_method methods[2] = {TB_METHOD_RK4, TB_METHOD_CVODE_BDF};
    for (int k = 0; k < 4; ++k) {
        tb_scene *scene = test_empty_scene();
        const double size[3] = {0.1, 0.1, 0.1}, x[3] = {0.0, 0.0, 0.0};
        const size_t weight = test_add_box(scene, m, size, x);
        const double g[3] = {0.0, 0.0, -TEST_G};
        assert_int_equal(tb_scene_add_gravity(scene, g), TB_STATUS_OK);
        tb_joint_def def = tb_joint_def_default();
        def.type = TB_JOINT_SLIDER;
        def.body_a = weight;
        def.axis[2] = -1.0;
        def.has_limits = 1;
        def.limits[0] = -1.0;
        def.limits[1] = drop;
        def.break_force = k < 2 ? 15.0 : 25.0;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        const tb_method method = methods[k % 2];
        tb_integrator *integrator =
            test_integrator_for(scene, method, method == TB_METHOD_RK4 ? dt : 0.0, 1e-8);
        double broke = -1.0;
        for (int frame = 1; frame <= 120; ++frame) {
            assert_int_equal(tb_integrator_advance(integrator, frame * dt), TB_STATUS_OK);
            bool broken = false;
            assert_int_equal(tb_scene_joint_broken(scene, 0, &broken), TB_STATUS_OK);
            broke = broken && broke < 0.0 ? frame * dt : broke;
        }
        double p[3];
        assert_int_equal(tb_scene_body_point(scene, tb_scene_states(scene), weight, x, p, NULL),
                         TB_STATUS_OK);
        print_message("falling weight %s, break_force %g N: broke at %.6g s (lands at %.6g s), "
                      "at z = %.6g m after 0.5 s\n",
                      tb_method_name(method), def.break_force, broke, t_land, p[2]);
        if (k < 2) {
            /* CVODE breaks it at the output after the landing, the advance after that says so */
            const double late = (method == TB_METHOD_RK4 ? 1.0 : 2.0) * dt * (1 + 1e-9);
            assert_true(broke >= t_land && broke <= t_land + late);
            assert_true(p[2] < -drop - 0.1); /* falling freely after */
        } else {
            assert_true(broke < 0.0);
            assert_true(fabs(p[2] + drop) <= 1e-12);
        }
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_door_stops_at_its_limit_and_bounces_back_at_e_times_its_speed),
        cmocka_unit_test(test_slider_stop_holds_a_block_with_its_weight_component),
        cmocka_unit_test(test_slider_breaks_when_a_falling_weight_lands_on_its_stop),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
