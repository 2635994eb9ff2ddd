/* Joints whose rows repeat one another (issue 21): a door on two coaxial hinges, a planar
 * four-bar of four hinges. J M^-1 J^T is singular there; the solve drops the repeated rows
 * (joint_solver.c), so the motion is the one of the independent rows. Each test checks physics
 * known without the code: the same motion as with one hinge, conservation of energy, statics. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"
#include "span.h"

#include <math.h>
#include <string.h>

static void hinge(tb_scene *scene, size_t body, const double anchor[3], const double axis[3])
{
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = body;
    memcpy(def.anchor, anchor, sizeof def.anchor);
    memcpy(def.axis, axis, sizeof def.axis);
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
}

/* A 1 kg flap 1 m long, 0.05 m square, level along +x from a hinge line along y through the
 * origin, under gravity; hinged there once (hinges 1) or at y = -0.4 and y = +0.4 (hinges 2). */
static tb_scene *flap(int hinges)
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const size_t id = test_add_bar(scene, 1.0, 1.0, 0.05, 0.5 * TEST_PI, (double[]){0.5, 0, 0});
    const double axis[3] = {0.0, 1.0, 0.0};
    if (hinges == 1) {
        hinge(scene, id, (double[]){0.0, 0.0, 0.0}, axis);
    } else {
        hinge(scene, id, (double[]){0.0, -0.4, 0.0}, axis);
        hinge(scene, id, (double[]){0.0, 0.4, 0.0}, axis);
    }
    return scene;
}

/* The flap released level swings through the hinge line and back, RK4 at 1/240 s for 5 s. On
 * two hinges the second's five rows repeat the first's: the manifold, and so the motion, is the
 * one hinge's. The two runs differ only by round-off (the rows are summed in another order and
 * the projection's Newton step meets the same manifold), which a pendulum's neutral phase
 * error lets grow about linearly: 1e-16 m per step over 1200 steps, at most about 1e-13 m
 * (measured 6e-15 m); bound 1e-12 m on the positions, and the joint errors at round-off
 * (1e-12 m). */
static void test_flap_on_two_coaxial_hinges_swings_as_on_one(void **state)
{
    (void)state;
    tb_scene *one = flap(1), *two = flap(2);
    tb_integrator *a = test_integrator_for(one, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    tb_integrator *b = test_integrator_for(two, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    double apart = 0.0, error = 0.0;
    for (int frame = 1; frame <= 300; ++frame) {
        assert_int_equal(tb_integrator_advance(a, frame / 60.0), TB_STATUS_OK);
        assert_int_equal(tb_integrator_advance(b, frame / 60.0), TB_STATUS_OK);
        const double *ya = tb_scene_states_const(one), *yb = tb_scene_states_const(two);
        for (int k = 0; k < 3; ++k) {
            apart = fmax(apart, fabs(ya[k] - yb[k]));
        }
        error = fmax(error, test_largest_joint_error(two));
    }
    print_message("flap on two hinges: %.3g m from one hinge's, joint error %.3g m\n", apart,
                  error);
    assert_true(apart <= 1e-12);
    assert_true(error <= 1e-12);
    tb_integrator_destroy(a);
    tb_integrator_destroy(b);
    tb_scene_destroy(one);
    tb_scene_destroy(two);
}

/* A door (2 kg, 1 m wide along +x, 1 m tall) on two hinges with a vertical axis at heights 0
 * and 1, at rest: statics gives the sum of the hinges' forces, the weight m g up, and the sum
 * of their moments about the lower hinge, the door's weight moment: r_cm x (m g z) with r_cm =
 * (0.5, 0, 0.5), i.e. (0, -m g / 2, 0). How the two share it is statically indeterminate; the
 * solve drops the repeated rows of the hinge eliminated second, so the other carries it all
 * (printed). To round-off: 1e-12 of m g. */
static void test_door_on_two_hinges_carries_its_weight_and_moment(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double m = 2.0;
    const size_t door = test_add_box(scene, m, (double[]){1.0, 0.04, 1.0}, (double[]){0.5, 0, 0.5});
    const double axis[3] = {0.0, 0.0, 1.0}, low[3] = {0.0, 0.0, 0.0}, high[3] = {0.0, 0.0, 1.0};
    hinge(scene, door, low, axis);
    hinge(scene, door, high, axis);
    const double *y = tb_scene_states_const(scene);
    double force[2][3], torque[2][3], total_force[3], total_moment[3];
    for (size_t j = 0; j < 2; ++j) {
        assert_int_equal(tb_scene_joint_reaction(scene, y, j, force[j], torque[j]), TB_STATUS_OK);
    }
    for (int k = 0; k < 3; ++k) {
        total_force[k] = force[0][k] + force[1][k];
        total_moment[k] = torque[0][k] + torque[1][k];
    }
    /* the upper hinge's force about the lower one: (0, 0, 1) x F */
    total_moment[0] -= force[1][1];
    total_moment[1] += force[1][0];
    print_message("door hinges: lower force (%.4g %.4g %.4g) torque (%.4g %.4g %.4g), upper "
                  "force (%.4g %.4g %.4g) torque (%.4g %.4g %.4g)\n",
                  force[0][0], force[0][1], force[0][2], torque[0][0], torque[0][1], torque[0][2],
                  force[1][0], force[1][1], force[1][2], torque[1][0], torque[1][1], torque[1][2]);
    const double weight = m * TEST_G, tol = 1e-12 * weight;
    assert_true(fabs(total_force[0]) <= tol && fabs(total_force[1]) <= tol);
    assert_true(fabs(total_force[2] - weight) <= tol);
    assert_true(fabs(total_moment[0]) <= tol && fabs(total_moment[2]) <= tol);
    assert_true(fabs(total_moment[1] + 0.5 * weight) <= tol);
    tb_scene_destroy(scene);
}

/* A rod from p to q in the x-z plane: its id. */
static size_t rod_between(tb_scene *scene, const double p[3], const double q[3])
{
    const double d[3] = {q[0] - p[0], 0.0, q[2] - p[2]};
    const double length = sqrt(d[0] * d[0] + d[2] * d[2]);
    const double center[3] = {0.5 * (p[0] + q[0]), 0.0, 0.5 * (p[2] + q[2])};
    return test_add_bar(scene, 1.0, length, 0.05, atan2(d[0] / length, -d[2] / length), center);
}

static void hinge_between(tb_scene *scene, size_t a, size_t b, const double anchor[3])
{
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = a;
    def.body_b = b;
    memcpy(def.anchor, anchor, sizeof def.anchor);
    memcpy(def.axis, (double[]){0.0, 1.0, 0.0}, sizeof def.axis);
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
}

typedef struct drift {
    double e0, energy, joint;
} drift;

/* A planar four-bar of four hinges (crank, coupler, rocker and the world), RK4 at 1/240 s for
 * 60 s under gravity: 20 rows on 18 coordinates with one degree of freedom, so 3 rows repeat
 * (the loop's out-of-plane ones). The joint error stays at round-off (1e-12 m) and the energy
 * is kept to RK4's error (the RSSR linkage of test_joints.c, the same bars, loses 7.6e-5 m g l
 * over 60 s at 240 Hz; bound 2.5e-4, the same). */
static void test_planar_four_bar_of_hinges_keeps_its_joints_and_energy(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double A[3] = {0.0, 0.0, 0.0}, B[3] = {0.5, 0.0, 0.8660254037844386};
    const double C[3] = {2.0, 0.0, 1.2}, D[3] = {2.0, 0.0, 0.0};
    const size_t crank = rod_between(scene, A, B), coupler = rod_between(scene, B, C);
    const size_t rocker = rod_between(scene, D, C);
    hinge_between(scene, crank, TB_WORLD, A);
    hinge_between(scene, coupler, crank, B);
    hinge_between(scene, coupler, rocker, C);
    hinge_between(scene, rocker, TB_WORLD, D);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    drift d = {test_total_energy(scene), 0.0, 0.0};
    const int frames = (int)tb_test_span(60.0, 5.0) * 60;
    for (int frame = 1; frame <= frames; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        d.energy = fmax(d.energy, fabs(test_total_energy(scene) - d.e0));
        d.joint = fmax(d.joint, test_largest_joint_error(scene));
    }
    print_message("planar four-bar %d s rk4: energy drift %.3g m g l, joint error %.3g m\n",
                  frames / 60, d.energy / TEST_G, d.joint);
    assert_true(d.joint <= 1e-12);
    assert_true(d.energy <= 2.5e-4 * TEST_G);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flap_on_two_coaxial_hinges_swings_as_on_one),
        cmocka_unit_test(test_door_on_two_hinges_carries_its_weight_and_moment),
        cmocka_unit_test(test_planar_four_bar_of_hinges_keeps_its_joints_and_energy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
