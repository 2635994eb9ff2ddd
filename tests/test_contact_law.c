/* The compliant normal contact law against what mechanics says: a body hitting the ground leaves
 * at e times its approach speed whatever that speed, energy never grows through a contact with
 * e <= 1, and the die of the issue sinks no deeper than its target. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "fixtures.h"
#include "near.h"
#include "tumble/tumble.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

/* A 1 kg ball of radius 0.1 m, one contact point at its centre (support 1), its lowest point
 * `gap` above the level ground plane, moving down at `speed`; with gravity or without. */
static tb_scene *ball_scene(const tb_ground_def *ground, double gap, double speed, bool gravity)
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &def.mass, NULL), TB_STATUS_OK);
    def.position[2] = 0.1 + gap;
    def.velocity[2] = -speed;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    const tb_contact_point point = {{0.0, 0.0, 0.0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, 0, &point, 1, 1), TB_STATUS_OK);
    if (gravity) {
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    }
    assert_int_equal(tb_scene_add_ground(scene, ground), TB_STATUS_OK);
    return scene;
}

/* The default contact (8e-7 m: stiff enough for impacts, docs/effects.md). */
#define DEFAULT_PENETRATION (tb_ground_def_default().penetration)

/* def.dt 0: the scene's default step (tb_scene_default_step). */
/* Without gravity the ball meets the plane at `speed` and, once the contact has let go, flies
 * off at a constant speed: the restitution it met. */
static double measured_restitution(double e, double speed, tb_method method, double penetration)
{
    tb_ground_def ground = tb_ground_def_default();
    ground.restitution = e;
    ground.penetration = penetration;
    tb_scene *scene = ball_scene(&ground, 0.01, speed, false);
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, 1e-8);
    /* 1 cm to fall, a contact of at most pi / omega (0.03 s at the softest setting), then free */
    assert_int_equal(tb_integrator_advance(integrator, 0.01 / speed + 0.25), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double height = y[2] - 0.1;
    const double rebound = y[TB_STATE_P + 2] / 1.0;
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    assert_true(height > 0.0); /* it left the plane */
    return rebound / speed;
}

/* The restitution the user asks for is the one the ball meets, at 0.5 and 5 m/s alike (the
 * linear law's e does not depend on the speed). CVODE at rtol 1e-8 integrates the law closely
 * enough to check the closed form e(zeta) and its inversion: 1e-4 relative, against the 2.7e-6
 * measured (a wrong e(zeta), a clamp that pulls or a speed-dependent law are off by percents). */
static void test_a_ball_leaves_the_ground_at_e_times_its_approach_speed(void **state)
{
    (void)state;
    const double restitutions[] = {0.2, 0.5, 0.8, 1.0}, speeds[] = {0.5, 5.0};
    const tb_method methods[] = {TB_METHOD_RK4, TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    for (size_t m = 0; m < 3; ++m) {
        for (size_t i = 0; i < 4; ++i) {
            for (size_t k = 0; k < 2; ++k) {
                const double e = measured_restitution(restitutions[i], speeds[k], methods[m], 1e-3);
                print_message("%-11s e = %.1f at %.1f m/s: leaves at %.5f (off by %.2e)\n",
                              tb_method_name(methods[m]), restitutions[i], speeds[k], e,
                              e / restitutions[i] - 1.0);
                if (tb_method_is_adaptive(methods[m])) {
                    assert_near(e / restitutions[i], 1.0, 1e-4);
                }
            }
        }
    }
}

/* RK4 at the scene's default step on the default contact (omega = 3500 rad/s, which 1/240 s cannot
 * hold: the default step is then 1/(240 n) with h omega <= 0.5). The law is continuous at
 * touchdown, so a fixed step's error in e falls as h^2: 2.1 % measured at h omega = 0.41 against
 * the 5 %, the tolerance here (the plain spring-dashpot misses it by 14 % for e = 0.2). */
static void test_rk4_at_the_default_step_meets_the_restitution_within_5_percent(void **state)
{
    (void)state;
    const double restitutions[] = {0.2, 0.5, 0.8, 1.0}, speeds[] = {0.5, 1.5, 4.5};
    double worst = 0.0;
    for (size_t i = 0; i < 4; ++i) {
        for (size_t k = 0; k < 3; ++k) {
            const double e = measured_restitution(restitutions[i], speeds[k], TB_METHOD_RK4,
                                                  DEFAULT_PENETRATION);
            worst = fmax(worst, fabs(e / restitutions[i] - 1.0));
        }
    }
    print_message("rk4 at the default step: worst relative error in e %.4f\n", worst);
    assert_true(worst < 0.05);
}

/* The default step of a scene whose contact 1/240 s cannot hold is 1/(240 n), within half the
 * stability limit and at most 0.5 / omega of the bounce (the guard's fastest oscillation, which
 * this test does not re-derive, is at least that); 1/240 s where it is stable. */
static void test_the_default_step_divides_1_240_and_resolves_the_contact(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4};
    tb_ground_def ground = tb_ground_def_default();
    ground.penetration = 1e-3; /* the soft contact of old: 99 rad/s */
    ground.presliding = 1e-4;
    tb_scene *soft = ball_scene(&ground, 0.01, 1.0, true);
    double dt;
    assert_int_equal(tb_scene_default_step(soft, TB_METHOD_RK4, &dt), TB_STATUS_OK);
    assert_true(dt == 1.0 / 240.0); /* stable at 99 rad/s: h omega = 0.41 */
    ground = tb_ground_def_default();
    tb_scene *stiff = ball_scene(&ground, 0.01, 1.0, true);
    const double omega = sqrt(9.81 / DEFAULT_PENETRATION);
    for (size_t m = 0; m < 3; ++m) {
        double stable;
        assert_int_equal(tb_scene_default_step(stiff, methods[m], &dt), TB_STATUS_OK);
        assert_int_equal(tb_scene_max_stable_step(stiff, methods[m], &stable, NULL), TB_STATUS_OK);
        const double n = 1.0 / (240.0 * dt);
        print_message("%-8s default step 1/%.0f s (stable up to %.3g s)\n",
                      tb_method_name(methods[m]), 1.0 / dt, stable);
        assert_near(n, round(n), 1e-9 * n);
        assert_true(dt <= 0.5 * stable && dt * omega <= 0.5);
        assert_true(n >= 2.0); /* 1/240 s would be refused */
    }
    tb_scene_destroy(soft);
    tb_scene_destroy(stiff);
}

/* Energy never grows through a bounce: with e = 1 the ball leaves with its kinetic energy to
 * RK4's error at the default step (measured below 1 %; tolerance 2 %), with e < 1 with e^2 of
 * it, less (the law dissipates: the dashpot's power c g d'^2 >= 0, and the clamp only removes
 * force). */
static void test_energy_never_grows_through_a_bounce(void **state)
{
    (void)state;
    const double restitutions[] = {0.2, 0.5, 0.8, 1.0};
    for (size_t i = 0; i < 4; ++i) {
        const double e =
            measured_restitution(restitutions[i], 3.0, TB_METHOD_RK4, DEFAULT_PENETRATION);
        print_message("e = %.1f: kinetic energy out / in %.5f\n", restitutions[i], e * e);
        assert_true(e * e <= 1.0 + 0.02);
        assert_true(e * e < restitutions[i] * restitutions[i] * 1.1);
    }
}

/* The die: 5 cm, 100 g, its 8 corners as contact points (support 4), dropped from 1 m
 * (4.43 m/s at impact) face, edge or corner first. Deepest corner over the bounce, RK4 at the
 * default step and the default contact: at most 2 mm, the target (CVODE measures
 * 0.84 / 1.25 / 1.88 mm; one corner carries the whole impact on a spring sized for a quarter
 * of the weight, so corner first sinks deepest). A softer contact (the 1 mm default) sinks
 * 26 / 40 / 47 mm. */
static double deepest_corner(const double q[4])
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *scene = NULL;
    assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    const double size[3] = {0.05, 0.05, 0.05};
    assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 0.1, size, &def.mass, NULL), TB_STATUS_OK);
    memcpy(def.orientation, q, 4 * sizeof(double));
    def.position[2] = 1.05;
    assert_int_equal(tb_scene_add_body(scene, &def, NULL), TB_STATUS_OK);
    tb_contact_point corners[8];
    size_t count;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, 0, corners, count, 4), TB_STATUS_OK);
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -9.81}), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 1e-8);
    double deepest = 0.0;
    for (int frame = 1; frame <= 3000; ++frame) { /* 0.6 s: the fall and the first bounce */
        assert_int_equal(tb_integrator_advance(integrator, 0.6 * frame / 3000.0), TB_STATUS_OK);
        tb_body_state s;
        tb_scene_get_state(scene, 0, &s);
        const double w = s.q[0], x = s.q[1], y = s.q[2], z = s.q[3];
        for (size_t j = 0; j < 8; ++j) { /* the world z of R p */
            const double *p = corners[j].position;
            const double height = s.x[2] + 2.0 * (x * z - w * y) * p[0] +
                                  2.0 * (y * z + w * x) * p[1] +
                                  (1.0 - 2.0 * (x * x + y * y)) * p[2];
            deepest = fmax(deepest, -height);
        }
    }
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return deepest;
}

static void test_a_die_dropped_from_1_m_sinks_at_most_2_mm(void **state)
{
    (void)state;
    const double edge = PI / 8.0, corner = 0.5 * acos(1.0 / sqrt(3.0));
    const double orientations[3][4] = {
        {1, 0, 0, 0},                 /* face first */
        {cos(edge), sin(edge), 0, 0}, /* 45 degrees about x: edge first */
        {cos(corner), sin(corner) / sqrt(2.0), -sin(corner) / sqrt(2.0), 0}, /* (1,1,1) down */
    };
    for (int k = 0; k < 3; ++k) {
        const double depth = deepest_corner(orientations[k]);
        print_message("orientation %d: deepest corner %.3f mm\n", k, 1e3 * depth);
        assert_true(depth > 0.0 && depth <= 2e-3);
    }
}

/* The static-friction band (mu_s 0.6, mu_k 0.4: atan mu_k = 21.8, atan mu_s = 30.96
 * degrees): the box of test_box_on_slope released at rest with its bottom on the plane, how far
 * it has moved down the slope after `seconds` under `method` (fixed steps at the scene's default
 * step, CVODE at rtol 1e-6). */
static double band_slide(double degrees, tb_method method, double seconds)
{
    const double a = degrees * PI / 180.0;
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = 0.6;
    ground.kinetic_friction = 0.4;
    tb_scene *scene = test_box_on_slope(degrees, &ground);
    tb_integrator_def def = tb_integrator_def_default();
    assert_int_equal(tb_integrator_def_set_method(&def, method), TB_STATUS_OK);
    def.dt = tb_method_is_adaptive(method) ? def.dt : 0.0;
    def.max_steps = 100000000;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    const double start = -cos(a) * y[0] - sin(a) * y[2];
    assert_int_equal(tb_integrator_advance(integrator, seconds), TB_STATUS_OK);
    const double moved = -cos(a) * y[0] - sin(a) * y[2] - start;
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
    return moved;
}

/* Between atan mu_k and atan mu_s a box released at rest stays: within 1 mm over 10 s (the
 * issue's bound; what it moves is the spring taking up the load, at most the 0.1 mm presliding
 * plus the release's slip) at every slope from 5 degrees up to atan mu_s - 0.5 degrees, under
 * every method. Above atan mu_s it slides at g (sin - mu_k cos): s(2) - 2 s(1.5) + s(1) =
 * a (0.5 s)^2, to 2 % (the slide starts within the first 0.1 s; the Stribeck term has faded by
 * then). The LuGre law before slid 55 m in 8 s at 28 degrees: the release transient's velocity
 * lowered mu to mu_k. */
static void test_static_friction_holds_across_the_band_under_every_method(void **state)
{
    (void)state;
    const tb_method methods[] = {TB_METHOD_EULER, TB_METHOD_MIDPOINT, TB_METHOD_RK4,
                                 TB_METHOD_CVODE_ADAMS, TB_METHOD_CVODE_BDF};
    const double holds[] = {5.0, 21.0, 22.5, 25.0, 28.0, 29.5, 30.46};
    for (size_t m = 0; m < 5; ++m) {
        double worst = 0.0;
        /* Euler and midpoint take 4 to 8 times RK4's steps: at the band's edges only */
        const bool cheap = methods[m] == TB_METHOD_EULER || methods[m] == TB_METHOD_MIDPOINT;
        for (size_t k = cheap ? 2 : 0; k < sizeof holds / sizeof holds[0]; k += cheap ? 4 : 1) {
            const double moved = band_slide(holds[k], methods[m], 10.0);
            worst = fmax(worst, fabs(moved));
            if (!(fabs(moved) < 1e-3)) {
                print_error("%s at %.2f degrees: moved %.3e m\n", tb_method_name(methods[m]),
                            holds[k], moved);
            }
            assert_true(fabs(moved) < 1e-3);
        }
        const double degrees = 33.0, angle = degrees * PI / 180.0;
        const double expected = 9.81 * (sin(angle) - 0.4 * cos(angle));
        const double s1 = band_slide(degrees, methods[m], 1.0),
                     s15 = band_slide(degrees, methods[m], 1.5),
                     s2 = band_slide(degrees, methods[m], 2.0);
        const double measured = (s2 - 2.0 * s15 + s1) / 0.25;
        print_message("%-11s holds: worst %.2e m in 10 s; 33 degrees: %.4f m/s^2 (expected %.4f)\n",
                      tb_method_name(methods[m]), worst, measured, expected);
        assert_near(measured, expected, 0.02 * expected);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_ball_leaves_the_ground_at_e_times_its_approach_speed),
        cmocka_unit_test(test_rk4_at_the_default_step_meets_the_restitution_within_5_percent),
        cmocka_unit_test(test_the_default_step_divides_1_240_and_resolves_the_contact),
        cmocka_unit_test(test_energy_never_grows_through_a_bounce),
        cmocka_unit_test(test_a_die_dropped_from_1_m_sinks_at_most_2_mm),
        cmocka_unit_test(test_static_friction_holds_across_the_band_under_every_method),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
