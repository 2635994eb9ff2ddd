/* Static friction between bodies against Coulomb's law: a box resting on a box on a slope within
 * the static cone stays where it is (no creep) under every method, above atan mu_s it slides at
 * g (sin - mu_k cos), and the friction state survives pairs meeting and parting under CVODE with
 * the state's length fixed and no slot lost. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "near.h"
#include "tumble/tumble.h"

/* How long the holds run (s): 10, as the issue asks; the sanitizer builds, where a step costs about
 * ten times the CPU, set 1 (tests/CMakeLists.txt) and check the same bounds over it. */
#ifndef TB_TEST_HOLD_SECONDS
#define TB_TEST_HOLD_SECONDS 10.0
#endif

#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The materials between the boxes; the ground grips the lower box harder, so that it
 * holds at every slope here and the top box's motion is its motion over the lower box. */
#define MU_S 0.6
#define MU_K 0.4
#define GROUND_MU_S 1.0
#define GROUND_MU_K 0.9

static const double lower_size[3] = {0.4, 0.4, 0.1}, upper_size[3] = {0.2, 0.2, 0.1};

static size_t add_box(tb_scene *scene, double mass, const double size[3], double degrees,
                      const double position[3])
{
    const double a = degrees * PI / 180.0;
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, mass, size, &def.mass, NULL), TB_STATUS_OK);
    const double q[4] = {cos(-a / 2), 0.0, sin(-a / 2), 0.0}; /* turns z onto the normal */
    memcpy(def.orientation, q, sizeof q);
    memcpy(def.position, position, 3 * sizeof(double));
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_BOX;
    memcpy(shape.size, size, 3 * sizeof(double));
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

/* A point `up` along the slope (up-hill, m) and `out` along the normal from the origin. */
static void on_slope(double degrees, double up, double out, double p[3])
{
    const double a = degrees * PI / 180.0;
    p[0] = up * cos(a) - out * sin(a);
    p[1] = 0.0;
    p[2] = up * sin(a) + out * cos(a);
}

/* An 8 kg box (0.4 x 0.4 x 0.1 m) with its bottom on a ground plane through the origin tilted by
 * `degrees` about y (its 8 corners as ground contact points), and a 2 kg box (0.2 x 0.2 x 0.1 m)
 * on it, `up` m up-hill of its centre and `gap` m above it, at rest; gravity -9.81 z; contact
 * between the boxes with `def` (mu_s 0.6, mu_k 0.4 and restitution e). */
static tb_scene *stacked_boxes(double degrees, double up, double gap, double e, tb_contact_def *def)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    double p[3];
    on_slope(degrees, 0.0, 0.05, p);
    add_box(scene, 8.0, lower_size, degrees, p);
    on_slope(degrees, up, 0.15 + gap, p);
    add_box(scene, 2.0, upper_size, degrees, p);
    tb_contact_point corners[8];
    size_t count;
    assert_int_equal(tb_contact_points_box(lower_size, corners, 8, &count), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    const double a = degrees * PI / 180.0;
    const double normal[3] = {-sin(a), 0.0, cos(a)};
    memcpy(ground.normal, normal, sizeof normal);
    ground.static_friction = GROUND_MU_S;
    ground.kinetic_friction = GROUND_MU_K;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    def->static_friction = MU_S;
    def->kinetic_friction = MU_K;
    def->restitution = e;
    assert_int_equal(tb_scene_add_contact(scene, def), TB_STATUS_OK);
    return scene;
}

/* How far the top box is down-hill of the lower one (m), along the slope. */
static double downhill(const tb_scene *scene, double degrees)
{
    const double a = degrees * PI / 180.0;
    const double *y = tb_scene_states_const(scene);
    const double d[3] = {y[TB_STATE_SIZE] - y[0], 0.0, y[TB_STATE_SIZE + 2] - y[2]};
    return -cos(a) * d[0] - sin(a) * d[2];
}

/* Fixed steps at the scene's default step, CVODE at its default tolerances. */
static tb_integrator *integrator_for(tb_scene *scene, tb_method method)
{
    tb_integrator_def def = test_integrator_def(method, 0.0, tb_integrator_def_default().rtol);
    def.max_steps = 100000000;
    return test_integrator(scene, &def);
}

static tb_contact_friction_stats friction_stats(const tb_scene *scene)
{
    tb_contact_friction_stats stats;
    const size_t contact = tb_scene_effect_count(scene) - 1; /* added last */
    assert_int_equal(tb_scene_contact_friction_stats(scene, contact, &stats), TB_STATUS_OK);
    return stats;
}

/* The top box released at rest on the lower one, how far it moves over it in `seconds`. */
static double hold(double degrees, tb_method method, double seconds)
{
    tb_contact_def def = tb_contact_def_default();
    tb_scene *scene = stacked_boxes(degrees, 0.0, 0.0, 0.3, &def);
    tb_integrator *integrator = integrator_for(scene, method);
    const double start = downhill(scene, degrees);
    assert_int_equal(tb_integrator_advance(integrator, seconds), TB_STATUS_OK);
    const double moved = downhill(scene, degrees) - start;
    const tb_contact_friction_stats stats = friction_stats(scene);
    assert_int_equal(stats.in_use, 4); /* the face-on-face manifold's 4 points */
    assert_int_equal(stats.overflows, 0);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return moved;
}

/* Within the static cone (tan theta < mu_s) Coulomb's law holds the top box still: the issue's
 * bound is 1 mm in 10 s (what it moves is its spring taking up the load, mu_s g / (g s0) ~ the
 * 0.5 um presliding). The memoryless law of before crept at v_reg tan theta / mu_s = 0.78 mm/s
 * at 25 degrees: 7.8 mm in 10 s. At 25 degrees and at atan mu_s - 0.5 = 30.46 degrees, under
 * every method at its default step. */
static void test_a_box_on_a_box_on_a_slope_holds_under_every_method(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                 TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    const double slopes[] = {25.0, 30.46};
    for (size_t m = 0; m < 5; ++m) {
        for (size_t k = 0; k < 2; ++k) {
            const double moved = hold(slopes[k], methods[m], TB_TEST_HOLD_SECONDS);
            print_message("%-11s %.2f degrees: moved %.3e m in %g s\n", tb_method_name(methods[m]),
                          slopes[k], moved, TB_TEST_HOLD_SECONDS);
            assert_true(fabs(moved) < 1e-3);
        }
    }
}

/* Above atan mu_s (33 degrees) the top box slides over the lower one, which the ground holds, at
 * g (sin - mu_k cos) = 2.054 m/s^2: s(0.4) - 2 s(0.3) + s(0.2) = a (0.1 s)^2, to 2 % (by 0.2 s
 * it slips at 0.4 m/s, 40 Stribeck velocities: mu is mu_k to e^-1600). It starts 0.1 m up-hill
 * of the centre, so it stays on the lower box until 0.54 s. */
static void test_above_atan_mu_s_the_top_box_slides_at_g_sin_minus_mu_k_cos(void **state)
{
    (void)state;
    const double degrees = 33.0, a = degrees * PI / 180.0;
    const double expected = 9.81 * (sin(a) - MU_K * cos(a));
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                 TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 5; ++m) {
        tb_contact_def def = tb_contact_def_default();
        tb_scene *scene = stacked_boxes(degrees, 0.1, 0.0, 0.3, &def);
        tb_integrator *integrator = integrator_for(scene, methods[m]);
        const double start = downhill(scene, degrees);
        double s[3];
        for (int k = 0; k < 3; ++k) {
            assert_int_equal(tb_integrator_advance(integrator, 0.2 + 0.1 * k), TB_STATUS_OK);
            s[k] = downhill(scene, degrees) - start;
        }
        const double measured = (s[2] - 2.0 * s[1] + s[0]) / 0.01;
        print_message("%-11s 33 degrees: slides at %.4f m/s^2 (expected %.4f)\n",
                      tb_method_name(methods[m]), measured, expected);
        assert_near(measured, expected, 0.02 * expected);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* How far apart the boxes' facing faces are along the normal (m; < 0 overlapping). */
static double face_gap(const tb_scene *scene, double degrees)
{
    const double a = degrees * PI / 180.0;
    const double *y = tb_scene_states_const(scene);
    const double d[3] = {y[TB_STATE_SIZE] - y[0], 0.0, y[TB_STATE_SIZE + 2] - y[2]};
    return -sin(a) * d[0] + cos(a) * d[2] - 0.1;
}

/* Pairs meeting and parting under CVODE: the 2 kg box dropped 5 mm onto the lower one on a 15
 * degree slope (below atan mu_k, so the landing's slide stops), e = 0.5, bounces (each bounce
 * parts the pair and meets it again) and comes to rest; from 1 s to 10 s it must then hold
 * within the 1 mm (the memoryless law crept at v_reg tan 15 / mu_s = 0.45 mm/s: 4 mm).
 * The state's length never changes (the integrator would refuse to step), the pair never holds
 * more than its 4 points' slots (a slot taken anew at each re-contact, or never given back,
 * would show as more) and no point went without one. */
static void test_a_bouncing_box_keeps_the_layout_and_holds_after_recontact(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    const double degrees = 15.0;
    for (size_t m = 0; m < 2; ++m) {
        tb_contact_def def = tb_contact_def_default();
        tb_scene *scene = stacked_boxes(degrees, 0.0, 0.005, 0.5, &def);
        const size_t length = tb_scene_state_size(scene);
        tb_integrator *integrator = integrator_for(scene, methods[m]);
        int partings = 0;
        bool touching = false;
        for (int k = 1; k <= 1000; ++k) { /* 1 kHz: a 5 mm drop's bounces last ms or more */
            assert_int_equal(tb_integrator_advance(integrator, k * 1e-3), TB_STATUS_OK);
            const double gap = face_gap(scene, degrees);
            partings += touching && gap > 1e-6;
            touching = gap < 0.0 ? true : (gap > 1e-6 ? false : touching);
        }
        const double start = downhill(scene, degrees);
        assert_int_equal(tb_integrator_advance(integrator, 1.0 + 0.9 * TB_TEST_HOLD_SECONDS),
                         TB_STATUS_OK);
        const double moved = downhill(scene, degrees) - start;
        const tb_contact_friction_stats stats = friction_stats(scene);
        print_message("%-11s %d partings; 1 s to %g s moved %.3e m; slots in use %zu, peak %zu, "
                      "overflows %llu, state length %zu\n",
                      tb_method_name(methods[m]), partings, 1.0 + 0.9 * TB_TEST_HOLD_SECONDS, moved,
                      stats.in_use, stats.peak_in_use, stats.overflows, tb_scene_state_size(scene));
        assert_true(partings >= 2);
        assert_true(fabs(moved) < 1e-3);
        assert_int_equal(tb_scene_state_size(scene), length);
        assert_int_equal(stats.in_use, 4);
        assert_int_equal(stats.peak_in_use, 4);
        assert_int_equal(stats.overflows, 0);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A pair that parts for good gives its slots back: at 33 degrees the top box slides off the
 * lower one (by 0.6 s) and falls away (it has no ground contact); by 2 s its deflections have
 * relaxed (at 100/s) and every slot is free again, the state's length unchanged. */
static void test_boxes_sliding_apart_free_their_slots_under_cvode(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 2; ++m) {
        tb_contact_def def = tb_contact_def_default();
        tb_scene *scene = stacked_boxes(33.0, 0.1, 0.0, 0.3, &def);
        const size_t length = tb_scene_state_size(scene);
        tb_integrator *integrator = integrator_for(scene, methods[m]);
        for (int frame = 1; frame <= 120; ++frame) {
            assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        }
        const tb_contact_friction_stats stats = friction_stats(scene);
        print_message("%-11s slid %.3f m down-hill of the lower box; slots in use %zu, peak %zu\n",
                      tb_method_name(methods[m]), downhill(scene, 33.0), stats.in_use,
                      stats.peak_in_use);
        assert_true(downhill(scene, 33.0) > 0.5); /* gone past the lower box's edge */
        assert_int_equal(stats.in_use, 0);
        assert_int_equal(stats.peak_in_use, 4);
        assert_int_equal(tb_scene_state_size(scene), length);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* A pool too small for the contact (1 slot for 4 points) neither fails nor allocates: one point
 * keeps the stick anchor, the other three get the memoryless law, counted at every step
 * boundary (3 each). The box then creeps, as that law does (more than 10 um in 1 s, where the
 * anchor alone holds it to 0.5 um), but no faster than the law's steady creep with the whole
 * load, v_reg tan 25 / sqrt(mu_s^2 - tan^2 25) = 2.11 mm/s with v_reg = sqrt(mu_s g presliding)
 * = 1.7155 mm/s at the defaults (mu stays within 1 % of mu_s at that speed), plus 5 % for the
 * Stribeck drop. */
static void test_a_full_pool_falls_back_to_the_memoryless_law_and_counts_it(void **state)
{
    (void)state;
    tb_contact_def def = tb_contact_def_default();
    def.friction_points = 1;
    tb_scene *scene = stacked_boxes(25.0, 0.0, 0.0, 0.3, &def);
    tb_integrator *integrator = integrator_for(scene, TB_METHOD_RK4);
    const double start = downhill(scene, 25.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double moved = downhill(scene, 25.0) - start;
    const tb_contact_friction_stats stats = friction_stats(scene);
    tb_integrator_stats steps;
    assert_int_equal(tb_integrator_get_stats(integrator, &steps), TB_STATUS_OK);
    print_message("1 slot: moved %.3e m in 1 s; overflows %llu over %llu boundaries (%ld steps)\n",
                  moved, stats.overflows, stats.boundaries, steps.steps);
    assert_int_equal(stats.slots, 1);
    assert_int_equal(stats.in_use, 1);
    assert_true(stats.boundaries == (unsigned long long)steps.steps);
    assert_true(stats.overflows > 2 * stats.boundaries && stats.overflows <= 3 * stats.boundaries);
    assert_true(moved > 1e-5 && moved < 2.22e-3);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void expect_refused(const tb_contact_def *def, const char *field)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    add_box(scene, 1.0, upper_size, 0.0, (double[]){0, 0, 0});
    const size_t length = tb_scene_state_size(scene);
    assert_int_not_equal(tb_scene_add_contact(scene, def), TB_STATUS_OK);
    assert_non_null(strstr(tb_scene_detail(scene), field));
    assert_int_equal(tb_scene_effect_count(scene), 0);
    assert_int_equal(tb_scene_state_size(scene), length);
    tb_scene_destroy(scene);
}

/* The friction's inputs are checked and a refusal changes nothing; the stats of an effect that
 * is not a contact are refused. */
static void test_bad_friction_inputs_are_refused(void **state)
{
    (void)state;
    const double bad_presliding[] = {0.0, -1e-6, NAN, INFINITY, 1e-310};
    for (size_t k = 0; k < 5; ++k) {
        tb_contact_def def = tb_contact_def_default();
        def.presliding = bad_presliding[k];
        expect_refused(&def, "presliding");
    }
    tb_contact_def def = tb_contact_def_default();
    def.friction_points = (size_t)-1 / 2;
    expect_refused(&def, "friction_points");
    def = tb_contact_def_default();
    tb_scene *scene = stacked_boxes(0.0, 0.0, 0.0, 0.3, &def);
    tb_contact_friction_stats stats;
    assert_int_equal(tb_scene_contact_friction_stats(scene, 0, &stats),
                     TB_STATUS_INVALID_ARGUMENT); /* effect 0 is gravity */
    assert_int_equal(tb_scene_contact_friction_stats(scene, 99, &stats),
                     TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_scene_contact_friction_stats(scene, 2, NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_contact_friction_stats(scene, 2, &stats), TB_STATUS_OK);
    assert_int_equal(stats.slots, 12); /* 6 per body */
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_box_on_a_box_on_a_slope_holds_under_every_method),
        cmocka_unit_test(test_above_atan_mu_s_the_top_box_slides_at_g_sin_minus_mu_k_cos),
        cmocka_unit_test(test_a_bouncing_box_keeps_the_layout_and_holds_after_recontact),
        cmocka_unit_test(test_boxes_sliding_apart_free_their_slots_under_cvode),
        cmocka_unit_test(test_a_full_pool_falls_back_to_the_memoryless_law_and_counts_it),
        cmocka_unit_test(test_bad_friction_inputs_are_refused),
    };
    const char *filter = getenv("TB_TEST_FILTER"); /* e.g. "*bouncing*": one test alone */
    if (filter != NULL) {
        cmocka_set_test_filter(filter);
    }
    return cmocka_run_group_tests(tests, NULL, NULL);
}
