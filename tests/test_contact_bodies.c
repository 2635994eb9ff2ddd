/* Contact between bodies against mechanics: two balls meeting head-on part at e times their
 * approach speed, and a crowd of bodies colliding keeps its total linear and angular momentum to
 * round-off (the forces act at the same world point with opposite signs). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "near.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static size_t add_ball(tb_scene *scene, double mass, double radius, const double x[3],
                       const double v[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, mass, radius, &def.mass, NULL),
                     TB_STATUS_OK);
    memcpy(def.position, x, 3 * sizeof(double));
    memcpy(def.velocity, v, 3 * sizeof(double));
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = radius;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    return id;
}

/* Balls of 1 kg and 3 kg (radius 0.1 m) 1 cm apart, closing at `speed` along x, no gravity:
 * the separation speed after the contact over the approach speed. */
static double head_on(double e, double speed, tb_method method)
{
    tb_scene *scene = test_empty_scene();
    add_ball(scene, 1.0, 0.1, (double[]){-0.105, 0, 0}, (double[]){0.75 * speed, 0, 0});
    add_ball(scene, 3.0, 0.1, (double[]){0.105, 0, 0}, (double[]){-0.25 * speed, 0, 0});
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = e;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, 1e-8);
    assert_int_equal(tb_integrator_advance(integrator, 0.01 / speed + 0.05), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double v0 = y[TB_STATE_P] / 1.0, v1 = y[TB_STATE_SIZE + TB_STATE_P] / 3.0;
    const double total = y[TB_STATE_P] + y[TB_STATE_SIZE + TB_STATE_P];
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    assert_near(total, 0.0, 1e-12 * speed); /* the centre of mass stays at rest */
    return (v1 - v0) / speed;
}

/* The restitution the user asks for is what two free balls meet: the law at the reduced mass.
 * CVODE (rtol 1e-8) to 1e-4 relative, as for the ground (the law's own e(zeta)); RK4 at the
 * default step within the 5 %. Speeds 0.5 and 5 m/s: e does not depend on speed. */
static void test_balls_meeting_head_on_part_at_e_times_their_approach_speed(void **state)
{
    (void)state;
    const double restitutions[] = {0.2, 0.5, 0.8, 1.0}, speeds[] = {0.5, 5.0};
    const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS};
    for (size_t m = 0; m < 2; ++m) {
        for (size_t i = 0; i < 4; ++i) {
            for (size_t k = 0; k < 2; ++k) {
                const double e = head_on(restitutions[i], speeds[k], methods[m]);
                print_message("%-11s e = %.1f at %.1f m/s: parts at %.5f\n",
                              tb_method_name(methods[m]), restitutions[i], speeds[k], e);
                const double tolerance = tb_method_is_adaptive(methods[m]) ? 1e-4 : 0.05;
                assert_near(e / restitutions[i], 1.0, tolerance);
            }
        }
    }
}

/* 8 balls of different masses and sizes thrown at each other in free space (no ground, gravity
 * or drag) collide; the contact's forces are equal and opposite at one world point, so:
 *   - total P, a linear invariant that RK4 keeps exactly, stays what it was to round-off
 *     (1e-12 of the largest body's momentum; a missing reaction is off by its whole impulse);
 *   - at every frame the derivative's net torque about the origin, sum x_i x F_i + tau_i, is zero
 *     to round-off (1e-12 of sum |x_i| |F_i|; a reaction applied at another point, or a torque
 *     about the wrong arm, leaves a torque of the order of the force times the contact's radius);
 *   - L about the origin, quadratic (x x P) and so kept by RK4 only to its own error, to 1e-5.
 * Energy falls (e = 0.5). */
static void test_colliding_bodies_keep_momentum_and_angular_momentum(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    for (int k = 0; k < 8; ++k) {
        const double a = 0.785398 * k;
        const double x[3] = {0.4 * cos(a), 0.4 * sin(a), 0.05 * (k % 3)};
        const double v[3] = {-2.0 * cos(a + 0.1 * k), -2.0 * sin(a + 0.1 * k), 0.3 * (k % 2)};
        add_ball(scene, 0.5 + 0.3 * k, 0.06 + 0.01 * (k % 4), x, v);
    }
    tb_contact_def contact = tb_contact_def_default();
    contact.restitution = 0.5;
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_conserved conserved;
    assert_int_equal(tb_scene_conserved(scene, &conserved), TB_STATUS_OK);
    assert_true(conserved.linear_momentum && conserved.angular_momentum);
    const double origin[3] = {0, 0, 0};
    double P0[3], L0[3], P1[3], L1[3], E0, E1;
    assert_int_equal(tb_scene_linear_momentum(scene, tb_scene_states(scene), P0), TB_STATUS_OK);
    assert_int_equal(tb_scene_angular_momentum(scene, tb_scene_states(scene), origin, L0),
                     TB_STATUS_OK);
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E0), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 1e-8);
    double worst_torque = 0.0; /* |sum x_i x dP_i + dL_i| / sum |x_i| |dP_i| over the frames */
    int touching = 0;
    /* the bodies' states, then the contact's friction slots */
    double *dydt = malloc(tb_scene_state_size(scene) * sizeof(double));
    assert_non_null(dydt);
    for (int frame = 1; frame <= 4800; ++frame) { /* contacts last ~1 ms: sample finely */
        assert_int_equal(tb_integrator_advance(integrator, frame / 4800.0), TB_STATUS_OK);
        const double *y = tb_scene_states(scene);
        assert_int_equal(tb_scene_derivative(frame / 4800.0, y, dydt, scene), 0);
        double total[3] = {0, 0, 0}, size = 0.0;
        for (int i = 0; i < 8; ++i) {
            const double *x = y + TB_STATE_SIZE * i, *F = dydt + TB_STATE_SIZE * i + TB_STATE_P,
                         *tau = dydt + TB_STATE_SIZE * i + TB_STATE_L;
            total[0] += x[1] * F[2] - x[2] * F[1] + tau[0];
            total[1] += x[2] * F[0] - x[0] * F[2] + tau[1];
            total[2] += x[0] * F[1] - x[1] * F[0] + tau[2];
            size += sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2] + 0.01) *
                    sqrt(F[0] * F[0] + F[1] * F[1] + F[2] * F[2]);
        }
        if (size > 0.0) {
            ++touching;
            worst_torque =
                fmax(worst_torque,
                     sqrt(total[0] * total[0] + total[1] * total[1] + total[2] * total[2]) / size);
        }
    }
    assert_int_equal(tb_scene_linear_momentum(scene, tb_scene_states(scene), P1), TB_STATUS_OK);
    assert_int_equal(tb_scene_angular_momentum(scene, tb_scene_states(scene), origin, L1),
                     TB_STATUS_OK);
    assert_int_equal(tb_scene_kinetic_energy(scene, tb_scene_states(scene), &E1), TB_STATUS_OK);
    const double scale = 2.0 * (0.5 + 0.3 * 7) * 2.1; /* the largest |P_i| */
    print_message("frames in contact %d; largest net torque about the origin / sum |x| |F|: %.2e\n",
                  touching, worst_torque);
    assert_true(touching > 0);
    assert_true(worst_torque < 1e-12);
    for (int i = 0; i < 3; ++i) {
        print_message("P[%d] %.3e -> %.3e, L[%d] %.3e -> %.3e\n", i, P0[i], P1[i], i, L0[i], L1[i]);
        assert_near(P1[i], P0[i], 1e-12 * scale);
        assert_near(L1[i], L0[i], 1e-5 * scale); /* RK4's error on the quadratic x x P */
    }
    print_message("kinetic energy %.6f -> %.6f J\n", E0, E1);
    assert_true(E1 < E0);
    free(dydt);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A scene file's {"type": "contact"}: equal balls, e = 1, one at rest: the moving one stops and
 * the other leaves at its speed (momentum and energy together say so), to 1e-3 m/s (0.1% of the
 * speed) at the default step: RK4's error through the contact, whose touchdown a fixed step
 * straddles, at h omega = 0.27 (the default step since the guard bounds the balls' contact at
 * their centres, where the normal acts, 2.3 times the old; 3e-6 at the old step). */
static void test_a_scene_files_contact_passes_the_momentum_on(void **state)
{
    (void)state;
    const char *json =
        "{\"bodies\": ["
        "{\"name\": \"a\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1,"
        " \"position\": [-0.2, 0, 0], \"velocity\": [1, 0, 0]},"
        "{\"name\": \"b\", \"shape\": {\"type\": \"sphere\", \"radius\": 0.1}, \"mass\": 1,"
        " \"position\": [0.2, 0, 0]}],"
        " \"effects\": [{\"type\": \"contact\", \"bodies\": [\"a\", \"b\"], \"restitution\": 1}]}";
    tb_scene *scene = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "cradle", NULL, &scene, &run, &error),
                     TB_STATUS_OK);
    run.duration = 1.0;
    assert_int_equal(tb_scene_run(scene, &run, NULL, NULL, NULL, &error), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    print_message("after: v_a = %.2e, v_b = %.6f m/s\n", y[TB_STATE_P],
                  y[TB_STATE_SIZE + TB_STATE_P]);
    assert_near(y[TB_STATE_P], 0.0, 1e-3);
    assert_near(y[TB_STATE_SIZE + TB_STATE_P], 1.0, 1e-3);
    tb_scene_destroy(scene);
}

/* Two equal boxes (0.2 x 0.2 x 0.1 m, 1 kg) stacked on the ground: the box-box manifold is
 * their overlap's 4 corners with k = M omega^2 / 4 each, so the upper box sinks into the lower
 * by M g / (M omega^2) = penetration, and the lower into the ground by 2 penetrations (twice the
 * weight on the ground's k = M g / penetration). After 1 s of settling, to 1e-8 m (the
 * friction's regularised creep is sideways and nothing pushes sideways here). */
static void test_a_box_resting_on_a_box_sinks_by_the_penetration(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const double size[3] = {0.2, 0.2, 0.1};
    tb_contact_point corners[8];
    size_t count;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    for (int k = 0; k < 2; ++k) {
        tb_body_def def = tb_body_def_default();
        assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &def.mass, NULL), TB_STATUS_OK);
        def.position[2] = 0.05 + 0.1 * k;
        size_t id;
        assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_BOX;
        memcpy(shape.size, size, sizeof size);
        assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_def contact = tb_contact_def_default();
    assert_int_equal(tb_scene_add_contact(scene, &contact), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 1e-8);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double pen = contact.penetration;
    print_message("lower box sinks %.4e m (2 penetrations %.4e), upper into it %.4e m\n",
                  0.05 - y[2], 2 * pen, 0.1 - (y[TB_STATE_SIZE + 2] - y[2]));
    assert_near(0.05 - y[2], 2.0 * pen, 1e-8);
    assert_near(0.1 - (y[TB_STATE_SIZE + 2] - y[2]), pen, 1e-8);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Bad definitions are refused with a detail naming the field, and add nothing. */
static void test_bad_contact_definitions_are_refused_and_change_nothing(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, 1.0, 0.1, (double[]){0, 0, 0}, (double[]){0, 0, 0});
    const size_t missing[1] = {7}, twice[2] = {0, 0};
    for (int k = 0; k < 6; ++k) {
        tb_contact_def def = tb_contact_def_default();
        const char *field = NULL;
        switch (k) {
        case 0:
            def.restitution = 1.5;
            field = "restitution";
            break;
        case 1:
            def.static_friction = 0.1;
            field = "static_friction";
            break;
        case 2:
            def.penetration = 0.0;
            field = "penetration";
            break;
        case 3:
            def.body_count = 2;
            field = "bodies";
            break;
        case 4:
            def.bodies = missing;
            def.body_count = 1;
            field = "7";
            break;
        default:
            def.bodies = twice;
            def.body_count = 2;
            field = "0";
            break;
        }
        const tb_status status = tb_scene_add_contact(scene, &def);
        print_message("%s -> %s: %s\n", field, tb_status_string(status), tb_scene_detail(scene));
        assert_true(status != TB_STATUS_OK);
        assert_non_null(strstr(tb_scene_detail(scene), field));
        assert_int_equal(tb_scene_effect_count(scene), 0);
    }
    tb_contact_def def;
    memset(&def, 0, sizeof def);
    assert_int_equal(tb_scene_add_contact(scene, &def), TB_STATUS_INVALID_ARGUMENT);
    assert_int_equal(tb_scene_add_contact(scene, NULL), TB_STATUS_NULL_POINTER);
    assert_int_equal(tb_scene_effect_count(scene), 0);
    tb_scene_destroy(scene);
}

/* A red-team find: a list with no pair the effect could push (one body; two static walls) was
 * taken, and the scene file's `"bodies": ["ball"]` with it: an effect that pushed nothing, with
 * no word. Both are refused naming what is missing, nothing added; a wall with the ball is a
 * pair, and taken. */
static void test_a_list_with_no_pair_to_push_is_refused(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_ball(scene, 1.0, 0.1, (double[]){0, 0, 0}, (double[]){0, 0, 0});
    for (int k = 0; k < 2; ++k) {
        tb_body_def wall = tb_body_def_default();
        wall.motion = TB_MOTION_STATIC;
        wall.position[0] = k == 0 ? -1.0 : 1.0;
        size_t id;
        assert_int_equal(tb_scene_add_body(scene, &wall, &id), TB_STATUS_OK);
        tb_shape shape = tb_shape_default();
        shape.type = TB_SHAPE_BOX;
        shape.size[0] = 0.1;
        shape.size[1] = shape.size[2] = 1.0;
        assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    }
    static const struct {
        size_t ids[2], count;
        const char *named; /* NULL: taken */
    } lists[] = {
        {{0, 0}, 1, "bodies: only 1 listed"},
        {{1, 2}, 2, "bodies: none of the 2 listed is dynamic"},
        {{1, 0}, 2, NULL},
    };
    for (size_t i = 0; i < sizeof lists / sizeof lists[0]; ++i) {
        tb_contact_def def = tb_contact_def_default();
        def.bodies = lists[i].ids;
        def.body_count = lists[i].count;
        const size_t size = tb_scene_state_size(scene), effects = tb_scene_effect_count(scene);
        const tb_status status = tb_scene_add_contact(scene, &def);
        print_message("%zu bodies -> %s: %s\n", lists[i].count, tb_status_name(status),
                      tb_scene_detail(scene));
        if (lists[i].named == NULL) {
            assert_int_equal(status, TB_STATUS_OK);
            continue;
        }
        assert_int_equal(status, TB_STATUS_INVALID_ARGUMENT);
        assert_non_null(strstr(tb_scene_detail(scene), lists[i].named));
        assert_int_equal(tb_scene_effect_count(scene), effects);
        assert_int_equal(tb_scene_state_size(scene), size);
    }
    tb_scene_destroy(scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_balls_meeting_head_on_part_at_e_times_their_approach_speed),
        cmocka_unit_test(test_colliding_bodies_keep_momentum_and_angular_momentum),
        cmocka_unit_test(test_a_scene_files_contact_passes_the_momentum_on),
        cmocka_unit_test(test_a_box_resting_on_a_box_sinks_by_the_penetration),
        cmocka_unit_test(test_bad_contact_definitions_are_refused_and_change_nothing),
        cmocka_unit_test(test_a_list_with_no_pair_to_push_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
