/* The contact's dashpot sized where it acts (issue 23, item 6): an off-centre hit is one
 * oscillator of the effective mass at the contact point, 1/m = sum 1/M + (r x n) . I^-1 (r x n),
 * so the law's e(zeta) is what the point does whatever its lever arm: the end of a rod landing
 * on the ground or on a heavy box leaves at e times its impact speed (the dashpot sized at the
 * rod's whole mass, or the reduced mass, let it leave at 0.451 and 0.382 for e = 0.5). Elastic
 * contact (e = 1, no damping) keeps the energy of spinning boxes, and a glancing box-on-ball hit
 * runs at the step a user would pick (RK4 at 1e-4 s), agreeing with CVODE. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "tumble/tumble.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The rod: 1 m x 2 cm x 2 cm (0.4 kg), its +x end lowered by turning it THETA about y. */
#define ROD_LENGTH 1.0
#define ROD_HALF_THICKNESS 0.01
#define THETA 0.52359877559829887 /* 30 degrees */

static tb_scene *load(const char *json)
{
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    const tb_status status = tb_scene_load_string(json, "damping", NULL, &scene, &run, &error);
    if (status != TB_STATUS_OK) {
        print_message("%s\n", error.message);
    }
    assert_int_equal(status, TB_STATUS_OK);
    return scene;
}

/* dt 0: the scene's default step; adaptive methods at rtol 1e-9. Advances frame by frame
 * (1/1000 s) to t, so that a fixed step's max_steps is a budget per frame. */
static void advance(tb_scene *scene, tb_method method, double dt, double t)
{
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    if (tb_method_is_adaptive(method)) {
        def.rtol = 1e-9;
        def.atol = 1e-12;
    } else {
        def.dt = dt;
    }
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    for (int frame = 1; frame <= (int)ceil(t * 1000.0 - 1e-9); ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, fmin(frame / 1000.0, t)), TB_STATUS_OK);
    }
    tb_integrator_destroy(integrator);
}

/* Body id's lever arm (world, from its centre of mass) to its material point at `local` (its
 * shape frame). */
static void lever_arm(const tb_scene *scene, size_t id, const double local[3], double arm[3])
{
    const double *y = tb_scene_states_const(scene);
    double origin[3], q[4];
    assert_int_equal(tb_scene_body_shape_pose(scene, y, id, origin, q), TB_STATUS_OK);
    /* R(q) local = local + w t + u x t, t = 2 u x local */
    const double *u = q + 1, w = q[0];
    const double t[3] = {2.0 * (u[1] * local[2] - u[2] * local[1]),
                         2.0 * (u[2] * local[0] - u[0] * local[2]),
                         2.0 * (u[0] * local[1] - u[1] * local[0])};
    const double *x = y + TB_STATE_SIZE * id + TB_STATE_X;
    arm[0] = origin[0] + local[0] + w * t[0] + u[1] * t[2] - u[2] * t[1] - x[0];
    arm[1] = origin[1] + local[1] + w * t[1] + u[2] * t[0] - u[0] * t[2] - x[1];
    arm[2] = origin[2] + local[2] + w * t[2] + u[0] * t[1] - u[1] * t[0] - x[2];
}

/* The velocity v + omega x arm (world) body id gives a point at lever arm `arm`. */
static void point_velocity(const tb_scene *scene, size_t id, const double arm[3], double out[3])
{
    const double *y = tb_scene_states_const(scene);
    double v[3], w[3];
    tb_scene_body_velocity(scene, y, id, v);
    tb_scene_body_angular_velocity(scene, y, id, w);
    out[0] = v[0] + w[1] * arm[2] - w[2] * arm[1];
    out[1] = v[1] + w[2] * arm[0] - w[0] * arm[2];
    out[2] = v[2] + w[0] * arm[1] - w[1] * arm[0];
}

/* The rod's body entry, its lowest edge's middle (the contact point) at (x, 0, z + 1 mm),
 * falling at 1 m/s. */
static void rod_json(char *out, size_t size, double x, double z)
{
    const double c = cos(THETA), s = sin(THETA);
    const double half = 0.5 * ROD_LENGTH;
    snprintf(out, size,
             "{\"name\": \"rod\", \"shape\": {\"type\": \"box\", \"size\": [%.17g, %.17g, %.17g]},"
             " \"density\": 1000, \"position\": [%.17g, 0, %.17g],"
             " \"orientation\": [%.17g, 0, %.17g, 0], \"velocity\": [0, 0, -1]}",
             ROD_LENGTH, 2.0 * ROD_HALF_THICKNESS, 2.0 * ROD_HALF_THICKNESS,
             x - (half * c - ROD_HALF_THICKNESS * s), z + half * s + ROD_HALF_THICKNESS * c + 1e-3,
             cos(0.5 * THETA), sin(0.5 * THETA));
}

/* The normal speed of the rod's end after its first hit over the speed before (1 m/s), relative
 * to body `other` (SIZE_MAX: the ground), 3 ms after the release (the hit lasts from 1 to 1.7
 * ms). Rigid-body restitution compares the velocities the point has through the impact, at the
 * configuration of the hit: the velocities after, at the arm the end had when it landed (the
 * rod, turning at 3 rad/s after, would otherwise move its end's velocity by 1% in 8 ms). */
static double rod_end_restitution(const char *json, tb_method method, size_t other)
{
    tb_scene *scene = load(json);
    const double end[3] = {0.5 * ROD_LENGTH, 0.0, -ROD_HALF_THICKNESS};
    double arm[3], v[3], w[3] = {0.0, 0.0, 0.0};
    lever_arm(scene, 0, end, arm); /* the rod does not turn before the hit */
    advance(scene, method, 0.0, 0.003);
    point_velocity(scene, 0, arm, v);
    if (other != SIZE_MAX) { /* hit above its centre of mass, the box only translates */
        tb_scene_body_velocity(scene, tb_scene_states_const(scene), other, w);
    }
    tb_scene_destroy(scene);
    return v[2] - w[2];
}

/* A frictionless rod (e = 0.5) lands on one end, the two corners of its lower edge together, 30
 * degrees from the ground: the end's effective mass is 0.4 kg / (1 + 12 (0.5 cos 30)^2) = 0.13
 * kg, a third of the rod's. The law's e within 1% (the target) under RK4 at its default
 * step and CVODE Adams at rtol 1e-9; the dashpot sized at the rod's whole mass gave 0.454. */
static void test_a_rod_landing_on_its_end_leaves_at_e(void **state)
{
    (void)state;
    char rod[512], json[1024];
    rod_json(rod, sizeof rod, 0.0, 0.0);
    snprintf(json, sizeof json,
             "{\"bodies\": [%s], \"effects\": [{\"type\": \"ground\", \"restitution\": 0.5,"
             " \"static_friction\": 0, \"kinetic_friction\": 0}]}",
             rod);
    const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS};
    for (int m = 0; m < 2; ++m) {
        const double e = rod_end_restitution(json, methods[m], SIZE_MAX);
        print_message("%s: the end leaves at %.5f of its impact speed\n",
                      tb_method_name(methods[m]), e);
        assert_true(fabs(e - 0.5) < 0.01 * 0.5);
    }
}

/* The same rod's end hits the middle of a heavy free box (0.4 x 0.4 x 0.1 m, 16 kg, no gravity):
 * the effective mass at the point adds both bodies' inverse masses; their relative normal speed
 * after over before is e within 1%. */
static void test_a_rod_end_hitting_a_heavy_box_leaves_at_e(void **state)
{
    (void)state;
    char rod[512], json[1400];
    rod_json(rod, sizeof rod, 0.0, 0.05);
    snprintf(json, sizeof json,
             "{\"bodies\": [%s, {\"name\": \"box\", \"shape\": {\"type\": \"box\", \"size\":"
             " [0.4, 0.4, 0.1]}, \"density\": 1000, \"position\": [0, 0, 0]}],"
             " \"effects\": [{\"type\": \"contact\", \"restitution\": 0.5, \"static_friction\": 0,"
             " \"kinetic_friction\": 0}]}",
             rod);
    const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS};
    for (int m = 0; m < 2; ++m) {
        const double e = rod_end_restitution(json, methods[m], 1);
        print_message("%s: the end leaves the box at %.5f of its impact speed\n",
                      tb_method_name(methods[m]), e);
        assert_true(fabs(e - 0.5) < 0.01 * 0.5);
    }
}

static double kinetic_energy(const tb_scene *scene)
{
    double energy = 0.0;
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states_const(scene), &energy),
                     TB_STATUS_OK);
    return energy;
}

/* Two spinning 1 kg cubes (10 cm) meet off-centre, frictionless, e = 1: the law is a spring with
 * no dashpot, which stores and gives back the same energy along any path, so the kinetic energy
 * after is the energy before but for the integrator's error and for what the manifold's jumps do
 * (a point's stiffness is shared among the manifold's points and changes when their count
 * does). The bound is 0.5% (STATED_BOUND) under CVODE Adams at rtol 1e-9 and under RK4 at its
 * default step, which resolves the fastest contact mode with 12 steps a period or more (RK4
 * changes an oscillator's energy by (h omega)^6 / 72 a step, 2e-4 at h omega = 0.5, for the
 * few steps an impact lasts). At e = 1 there is no dashpot, so its sizing does not enter: this
 * holds the elastic end of the law to what the manifold allows. */
#define STATED_BOUND 0.005
static double spinning_boxes_energy_ratio(tb_method method)
{
    const char *json =
        "{\"bodies\": ["
        "{\"name\": \"a\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.1, 0.1]},"
        " \"mass\": 1, \"position\": [-0.12, 0, 0], \"velocity\": [1, 0, 0],"
        " \"angular_velocity\": [2, 3, 20]},"
        "{\"name\": \"b\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.1, 0.1]},"
        " \"mass\": 1, \"position\": [0.12, 0.03, 0.02], \"velocity\": [-1, 0, 0],"
        " \"orientation\": [0.9238795325112867, 0.3826834323650898, 0, 0],"
        " \"angular_velocity\": [3, -5, -10]}],"
        " \"effects\": [{\"type\": \"contact\", \"restitution\": 1, \"static_friction\": 0,"
        " \"kinetic_friction\": 0}]}";
    tb_scene *scene = load(json);
    const double before = kinetic_energy(scene);
    advance(scene, method, 0.0, 0.2);
    const double *y = tb_scene_states_const(scene);
    assert_true(y[TB_STATE_P] < 0.5); /* they did collide: a's x momentum fell from 1 */
    const double ratio = kinetic_energy(scene) / before;
    tb_scene_destroy(scene);
    return ratio;
}

static void test_spinning_elastic_boxes_keep_their_energy(void **state)
{
    (void)state;
    const double cvode = spinning_boxes_energy_ratio(TB_METHOD_CVODE_ADAMS);
    const double rk4 = spinning_boxes_energy_ratio(TB_METHOD_RK4);
    print_message("energy after / before - 1: %.3g (CVODE Adams), %.3g (RK4, default step)\n",
                  cvode - 1.0, rk4 - 1.0);
    assert_true(fabs(cvode - 1.0) < STATED_BOUND);
    assert_true(fabs(rk4 - 1.0) < STATED_BOUND);
}

/* A 2 kg box (10 cm) glancing off a 1 kg ball (5 cm radius) on its edge, at the defaults
 * (e = 0.3, friction 0.6 / 0.5), no gravity. RK4 at dt = 1e-4 s, a step a user would pick, is
 * within the stability guard (it was refused: "use dt <= 2.76e-05 s"), keeps the linear
 * momentum to round-off (1e-12 kg m/s: the loads are equal and opposite at one point) and
 * lands where CVODE Adams at rtol 1e-9 does within 5% of the approach speed in every velocity
 * (the law's fixed-step error is 3% at h omega = 0.4 and grows as h^2; here the edge's
 * effective mass makes h omega about 0.5). */
static void glancing_velocities(tb_method method, double dt, double v[6])
{
    const char *json =
        "{\"bodies\": ["
        "{\"name\": \"box\", \"shape\": {\"type\": \"box\", \"size\": [0.1, 0.1, 0.1]},"
        " \"mass\": 2, \"position\": [-0.12, 0.06, 0], \"velocity\": [2, 0, 0]},"
        "{\"name\": \"ball\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.05},"
        " \"mass\": 1, \"position\": [0.12, 0, 0]}],"
        " \"effects\": [{\"type\": \"contact\"}]}";
    tb_scene *scene = load(json);
    if (!tb_method_is_adaptive(method)) {
        double stable = 0.0;
        assert_int_equal(tb_scene_max_stable_step(scene, method, &stable, NULL), TB_STATUS_OK);
        print_message("%s: stable up to %.3g s\n", tb_method_name(method), stable);
        assert_true(stable >= dt);
    }
    advance(scene, method, dt, 0.15);
    const double *y = tb_scene_states_const(scene);
    const double P = y[TB_STATE_P] + y[TB_STATE_SIZE + TB_STATE_P];
    assert_true(fabs(P - 4.0) < 1e-12);
    assert_true(fabs(y[TB_STATE_P + 1] + y[TB_STATE_SIZE + TB_STATE_P + 1]) < 1e-12);
    tb_scene_body_velocity(scene, y, 0, v);
    tb_scene_body_velocity(scene, y, 1, v + 3);
    tb_scene_destroy(scene);
}

static void test_a_glancing_box_on_ball_runs_at_a_users_step(void **state)
{
    (void)state;
    double rk4[6], cvode[6];
    glancing_velocities(TB_METHOD_RK4, 1e-4, rk4);
    glancing_velocities(TB_METHOD_CVODE_ADAMS, 0.0, cvode);
    for (int k = 0; k < 6; ++k) {
        print_message("v[%d]: RK4 at 1e-4 s %.5f, CVODE %.5f m/s\n", k, rk4[k], cvode[k]);
        assert_true(fabs(rk4[k] - cvode[k]) < 0.05 * 2.0);
    }
    assert_true(cvode[4] < -0.05); /* a glancing hit: the ball is pushed sideways */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_rod_landing_on_its_end_leaves_at_e),
        cmocka_unit_test(test_a_rod_end_hitting_a_heavy_box_leaves_at_e),
        cmocka_unit_test(test_spinning_elastic_boxes_keep_their_energy),
        cmocka_unit_test(test_a_glancing_box_on_ball_runs_at_a_users_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
