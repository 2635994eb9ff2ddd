/* Effects against mechanics: spring frequencies, drag's exact velocities, contact that holds a
 * body up, kinetic friction's stopping distance, static friction that holds on a slope, and
 * user callbacks. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "bodies.h"
#include "fixtures.h"
#include "near.h"
#include "span.h"
#include "tumble/tumble.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

static size_t add_sphere(tb_scene *scene, double mass, double radius, const double position[3])
{
    tb_body_def def = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, mass, radius, &def.mass, NULL),
                     TB_STATUS_OK);
    memcpy(def.position, position, 3 * sizeof(double));
    size_t id;
    assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
    return id;
}

static tb_integrator *rk4(tb_scene *scene, double dt)
{
    tb_integrator_def def = tb_integrator_def_default();
    def.dt = dt;
    tb_integrator *integrator = NULL;
    assert_int_equal(tb_scene_integrator_create(scene, &def, 0.0, &integrator), TB_STATUS_OK);
    return integrator;
}

/* A 2 kg ball on a spring (k = 200 N/m, rest 1 m) to a world anchor, released 0.1 m beyond
 * rest: x(t) = 1 + 0.1 cos(omega t), omega = sqrt(k/m) = 10 rad/s. RK4 at h = 1e-3
 * (omega h = 0.01) follows it over 20 periods to 1e-9 m. */
static void test_spring_to_anchor_oscillates_at_sqrt_k_over_m(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 2.0, 0.1, (double[]){1.1, 0, 0});
    tb_spring_def spring = tb_spring_def_default();
    spring.body_a = ball;
    spring.stiffness = 200.0;
    spring.rest_length = 1.0;
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    tb_integrator *integrator = rk4(scene, 1e-3);
    double worst = 0.0;
    for (int k = 1; k <= 200; ++k) {
        const double t = 0.02 * PI * k; /* 10 samples a period */
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        worst = fmax(worst, fabs(tb_scene_states(scene)[0] - (1.0 + 0.1 * cos(10.0 * t))));
    }
    print_message("largest deviation from 1 + 0.1 cos(10 t) over 20 periods: %.2e m\n", worst);
    assert_true(worst < 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Two balls (1 kg and 3 kg) on a spring between their surfaces: they oscillate at
 * sqrt(k / mu), mu = m1 m2 / (m1 + m2) = 0.75 kg, about their fixed centre of mass, and with
 * damping c the amplitude decays as exp(-c t / (2 mu)). k = 75 N/m, omega = 10 rad/s,
 * c = 0.3 N s/m: decay rate 0.2 1/s; the damped frequency sqrt(omega^2 - 0.04) differs by
 * 2e-4 from omega. Checked against the exact damped solution to 1e-8 m. */
static void test_two_body_spring_uses_the_reduced_mass_and_decays(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t a = add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 0});
    const size_t b = add_sphere(scene, 3.0, 0.1, (double[]){1.5, 0, 0});
    tb_spring_def spring = tb_spring_def_default();
    spring.body_a = a;
    spring.body_b = b;
    spring.point_a[0] = 0.1;  /* a's surface facing b */
    spring.point_b[0] = -0.1; /* b's surface facing a */
    spring.stiffness = 75.0;
    spring.damping = 0.3;
    spring.rest_length = 1.2; /* stretched by 0.1 m at the start */
    assert_int_equal(tb_scene_add_spring(scene, &spring), TB_STATUS_OK);
    tb_integrator *integrator = rk4(scene, 1e-3);
    const double decay = 0.3 / (2 * 0.75), omega_d = sqrt(100.0 - decay * decay);
    double worst = 0.0, P[3];
    for (int k = 1; k <= 100; ++k) {
        const double t = 0.05 * k;
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        const double *y = tb_scene_states(scene);
        const double stretch = (y[13] - 0.1) - (y[0] + 0.1) - 1.2;
        /* released from rest: s(t) = A e^{-a t} (cos w t + a/w sin w t) */
        const double exact =
            0.1 * exp(-decay * t) * (cos(omega_d * t) + decay / omega_d * sin(omega_d * t));
        worst = fmax(worst, fabs(stretch - exact));
    }
    tb_scene_linear_momentum(scene, tb_scene_states(scene), P);
    print_message("largest deviation from the damped two-body solution: %.2e m\n", worst);
    assert_true(worst < 1e-8);
    assert_near(P[0], 0.0, 1e-12); /* internal forces: momentum kept */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Falling from rest under gravity with linear drag b: v(t) = -v_T (1 - e^{-b t / m}), v_T =
 * m g / b; with quadratic drag c: v(t) = -v_T tanh(g t / v_T), v_T = sqrt(m g / c). A spinning
 * ball with angular drag: omega(t) = omega0 e^{-b_w t / I}. RK4 at h = 1e-3: 1e-9 relative. */
static void test_drag_gives_the_exact_terminal_velocity_curves(void **state)
{
    (void)state;
    const double m = 2.0, g = 9.81;
    for (int kind = 0; kind < 3; ++kind) {
        tb_scene *scene = test_empty_scene();
        const size_t ball = add_sphere(scene, m, 0.5, (double[]){0, 0, 0}); /* I = 0.2 */
        tb_scene_set_velocity(scene, ball, (double[]){0, 0, 0}, (double[]){0, 0, 4.0});
        assert_int_equal(tb_scene_add_gravity(scene, (double[]){0, 0, -g}), TB_STATUS_OK);
        tb_drag_def drag = tb_drag_def_default();
        drag.linear = kind == 0 ? 0.5 : 0.0;
        drag.quadratic = kind == 1 ? 0.3 : 0.0;
        drag.angular = kind == 2 ? 0.05 : 0.0;
        assert_int_equal(tb_scene_add_drag(scene, &drag), TB_STATUS_OK);
        tb_integrator *integrator = rk4(scene, 1e-3);
        double worst = 0.0;
        for (int k = 1; k <= 50; ++k) {
            const double t = 0.2 * k;
            assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
            double v[3], w[3];
            tb_scene_body_velocity(scene, tb_scene_states(scene), ball, v);
            tb_scene_body_angular_velocity(scene, tb_scene_states(scene), ball, w);
            double value, exact;
            if (kind == 0) {
                const double terminal = m * g / 0.5;
                value = v[2];
                exact = -terminal * (1.0 - exp(-0.5 * t / m));
            } else if (kind == 1) {
                const double terminal = sqrt(m * g / 0.3);
                value = v[2];
                exact = -terminal * tanh(g * t / terminal);
            } else {
                value = w[2];
                exact = 4.0 * exp(-0.05 * t / 0.2);
            }
            worst = fmax(worst, fabs(value - exact) / fabs(exact));
        }
        print_message("%s drag: largest relative deviation %.2e\n",
                      kind == 0   ? "linear"
                      : kind == 1 ? "quadratic"
                                  : "angular",
                      worst);
        assert_true(worst < 1e-9);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

/* --- ground contact ------------------------------------------------------------------------ */

/* At rest on level ground the box sinks by the configured penetration (its weight shared by 4
 * corners, each with k = M g / (4 penetration)): centre at 0.05 - 0.001 m, to 1e-7 m after
 * the contact (critically damped, 99 rad/s) has settled. */
static void test_a_resting_box_sinks_by_the_configured_penetration(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    tb_scene *scene = test_box_on_slope(0.0, &ground);
    tb_integrator *integrator = rk4(scene, 0.0); /* the default step */
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_OK);
    const double *y = tb_scene_states(scene);
    print_message("resting height %.9f m (expected %.9f)\n", y[2], 0.05 - ground.penetration);
    assert_near(y[2], 0.05 - ground.penetration, 1e-7);
    assert_near(y[7] / 8.0, 0.0, 1e-6);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A body's ground force starts exactly when its lowest point dips below the plane, however it is
 * turned (the ground skips bodies whose every point is clear by more than |r| + radius, and must
 * never skip one that touches). A 0.1 x 0.2 x 0.3 m box on its 8 corners (radius 0 and 2 cm) in
 * 20 orientations, placed from its shape pose so that its lowest corner's sphere is 1 nm above
 * or below the plane: 1e-8 of the box's size, far beyond the rounding of a depth (1e-16 of it)
 * and far inside the skip's room (the centre is then nearer than |r| + radius). Below: an upward
 * push; above: none, force and torque exactly 0. */
static void test_ground_force_starts_at_the_lowest_point_in_any_orientation(void **state)
{
    (void)state;
    const double size[3] = {0.1, 0.2, 0.3}, radii[2] = {0.0, 0.02}, gaps[2] = {1e-9, -1e-9};
    tb_contact_point corners[8];
    size_t count = 0;
    assert_int_equal(tb_contact_points_box(size, corners, 8, &count), TB_STATUS_OK);
    unsigned seed = 12345u;
    for (int turn = 0; turn < 20; ++turn) {
        double q[4], norm = 0.0;
        for (int k = 0; k < 4; ++k) {
            seed = seed * 1103515245u + 12345u;
            q[k] = (double)(seed >> 8) / 16777216.0 - 0.5;
            norm += q[k] * q[k];
        }
        for (int r = 0; r < 2; ++r) {
            for (int g = 0; g < 2; ++g) {
                tb_scene_def scene_def = tb_scene_def_default();
                tb_scene *scene = NULL;
                assert_int_equal(tb_scene_create(&scene_def, &scene, NULL), TB_STATUS_OK);
                tb_body_def def = tb_body_def_default();
                assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0, size, &def.mass, NULL),
                                 TB_STATUS_OK);
                for (int k = 0; k < 4; ++k) {
                    def.orientation[k] = q[k] / sqrt(norm);
                }
                def.position[2] = 1.0;
                size_t id;
                assert_int_equal(tb_scene_add_body(scene, &def, &id), TB_STATUS_OK);
                tb_contact_point points[8];
                for (size_t c = 0; c < count; ++c) {
                    points[c] = corners[c];
                    points[c].radius = radii[r];
                }
                assert_int_equal(tb_scene_set_contact_points(scene, id, points, count, 4),
                                 TB_STATUS_OK);
                tb_ground_def ground = tb_ground_def_default();
                assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
                double *y = tb_scene_states(scene), origin[3], p[4];
                assert_int_equal(tb_scene_body_shape_pose(scene, y, id, origin, p), TB_STATUS_OK);
                double lowest = INFINITY; /* z of R c + origin, R from the shape pose */
                for (size_t c = 0; c < count; ++c) {
                    const double *v = points[c].position;
                    const double z = 2.0 * (p[1] * p[3] - p[0] * p[2]) * v[0] +
                                     2.0 * (p[2] * p[3] + p[0] * p[1]) * v[1] +
                                     (1.0 - 2.0 * (p[1] * p[1] + p[2] * p[2])) * v[2];
                    lowest = fmin(lowest, origin[2] + z - radii[r]);
                }
                y[2] += gaps[g] - lowest;
                const size_t n = tb_scene_state_size(scene);
                double dydt[64];
                assert_true(n <= 64);
                assert_int_equal(tb_scene_derivative(0.0, y, dydt, scene), 0);
                if (gaps[g] < 0.0) {
                    assert_true(dydt[9] > 0.0);
                } else {
                    for (int k = 7; k < 13; ++k) {
                        assert_true(dydt[k] == 0.0);
                    }
                }
                tb_scene_destroy(scene);
            }
        }
    }
}

/* Sliding at 2 m/s on level ground with mu_k = 0.5, a block stops after v^2 / (2 mu_k g) =
 * 0.4077 m under Coulomb friction. The stick-anchor law caps the force at mu N from the first
 * 0.1 mm of deflection, so the slide is Coulomb's (the LuGre law before it lost v / 400 s of
 * build-up and slid 5 mm further). Tolerance 0.5 mm: the cap starts at mu_s for the ~1e-5 s
 * until the slip is established, the Stribeck rise to mu_s below v_s shortens the slide by about
 * v_s^2 / g (1e-5 m), and the spring holds up to 0.1 mm at the end. At the documented
 * 240 steps per second. */
static void test_kinetic_friction_stops_a_slide_at_v2_over_2_mu_g(void **state)
{
    (void)state;
    tb_ground_def ground = tb_ground_def_default();
    ground.static_friction = 0.6;
    ground.kinetic_friction = 0.5;
    tb_scene *scene = test_box_on_slope(0.0, &ground);
    /* start at the resting height so the slide begins in steady contact */
    tb_body_state s;
    tb_scene_get_state(scene, 0, &s);
    s.x[2] = 0.05 - ground.penetration;
    s.P[0] = 8.0 * 2.0;
    tb_scene_set_state(scene, 0, &s);
    tb_integrator *integrator = rk4(scene, 0.0); /* the default step */
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    const double coulomb = 4.0 / (2 * 0.5 * 9.81), expected = coulomb;
    const double *y = tb_scene_states(scene);
    print_message("slid %.5f m (v^2 / 2 mu_k g = %.5f m), final speed %.2e m/s\n", y[0], coulomb,
                  fabs(y[7] / 8.0));
    assert_near(y[0], expected, 5e-4);
    assert_true(fabs(y[7] / 8.0) < 1e-3);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* On a 25 degree slope (tan 25 = 0.466 < mu_s = 0.6) the box holds: after settling, it moves
 * less than 1e-7 m between t = 2 s and t = 12 s (no creep). On a 35 degree slope (tan 35 =
 * 0.700 > 0.6) it slides with acceleration g (sin 35 - mu_k cos 35) = 1.608 m/s^2, to 1%. */
static void test_static_friction_holds_a_box_on_a_slope_without_creep(void **state)
{
    (void)state;
    /* under memcheck the window is 2 to 4 s: creep would show in any window after settling */
    const double until = tb_test_span(12.0, 4.0);
    const double creep = test_slope_displacement(25.0, 2.0, until);
    print_message("25 degrees: moved %.3e m down the slope between 2 s and %g s\n", creep, until);
    assert_true(fabs(creep) < 1e-7);

    const double s1 = test_slope_displacement(35.0, 0.0, 1.0),
                 s2 = test_slope_displacement(35.0, 0.0, 2.0);
    const double angle = 35.0 * PI / 180.0;
    const double expected = 9.81 * (sin(angle) - 0.5 * cos(angle));
    /* s(t) = a t^2 / 2 + b t + c for a constant acceleration after a short start: the second
     * difference over t = 1, 2, 3 s gives a exactly. */
    const double s3 = test_slope_displacement(35.0, 0.0, 3.0);
    const double measured = (s3 - 2.0 * s2 + s1) / 1.0;
    print_message("35 degrees: acceleration %.4f m/s^2 (g (sin - mu_k cos) = %.4f)\n", measured,
                  expected);
    assert_near(measured, expected, 0.01 * expected);
}

/* --- user effects ------------------------------------------------------------------------ */

typedef struct user_spring {
    double k;
    int fail_after_calls;
    int calls;
} user_spring;

/* F = -k x on body 0 through the helpers. */
static int pull_to_origin(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)t;
    user_spring *s = ctx;
    if (s->fail_after_calls > 0 && ++s->calls > s->fail_after_calls) {
        return -4;
    }
    const double *x = y;
    const double f[3] = {-s->k * x[0], -s->k * x[1], -s->k * x[2]};
    tb_effect_add_force(scene, y, dydt, 0, f, x);
    return 0;
}

static void test_user_effect_acts_like_the_force_it_computes(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    add_sphere(scene, 0.5, 0.1, (double[]){0.2, 0, 0});
    user_spring s = {50.0, 0, 0}; /* omega = 10 rad/s */
    assert_int_equal(tb_scene_add_user_effect(scene, pull_to_origin, &s), TB_STATUS_OK);
    tb_integrator *integrator = rk4(scene, 1e-3);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_near(tb_scene_states(scene)[0], 0.2 * cos(10.0), 1e-10);
    tb_integrator_destroy(integrator);

    s.fail_after_calls = 10;
    integrator = rk4(scene, 1e-3);
    assert_int_equal(tb_integrator_advance(integrator, 2.0), TB_STATUS_DERIVATIVE_FAILED);
    assert_non_null(strstr(tb_integrator_detail(integrator), "returned -4"));
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* --- refused definitions, one row each; nothing changes ----------------------------------- */

static tb_status drag_negative(tb_scene *s)
{
    tb_drag_def d = tb_drag_def_default();
    d.quadratic = -1.0;
    return tb_scene_add_drag(s, &d);
}
static tb_status drag_bad_body(tb_scene *s)
{
    tb_drag_def d = tb_drag_def_default();
    d.body = 5;
    return tb_scene_add_drag(s, &d);
}
static tb_status spring_self(tb_scene *s)
{
    tb_spring_def d = tb_spring_def_default();
    d.body_b = 0;
    return tb_scene_add_spring(s, &d);
}
static tb_status spring_nan_point(tb_scene *s)
{
    tb_spring_def d = tb_spring_def_default();
    d.point_b[1] = NAN;
    return tb_scene_add_spring(s, &d);
}
static tb_status spring_negative_rest(tb_scene *s)
{
    tb_spring_def d = tb_spring_def_default();
    d.rest_length = -0.5;
    return tb_scene_add_spring(s, &d);
}
static tb_status ground_bad_normal(tb_scene *s)
{
    tb_ground_def d = tb_ground_def_default();
    d.normal[2] = 0.0; /* (0, 0, 0): no direction */
    return tb_scene_add_ground(s, &d);
}
static tb_status ground_mu_order(tb_scene *s)
{
    tb_ground_def d = tb_ground_def_default();
    d.static_friction = 0.2;
    return tb_scene_add_ground(s, &d);
}
static tb_status ground_zero_penetration(tb_scene *s)
{
    tb_ground_def d = tb_ground_def_default();
    d.penetration = 0.0;
    return tb_scene_add_ground(s, &d);
}
static tb_status contact_negative_radius(tb_scene *s)
{
    const tb_contact_point p = {{0, 0, 0}, -1.0};
    return tb_scene_set_contact_points(s, 0, &p, 1, 1);
}
static tb_status user_null(tb_scene *s)
{
    return tb_scene_add_user_effect(s, NULL, NULL);
}

static void test_bad_effect_definitions_are_refused_and_change_nothing(void **state)
{
    (void)state;
    static const struct {
        const char *label;
        tb_status (*attempt)(tb_scene *);
        tb_status expected;
        const char *named;
    } cases[] = {
        {"negative drag", drag_negative, TB_STATUS_INVALID_ARGUMENT, "quadratic"},
        {"drag on body 5", drag_bad_body, TB_STATUS_OUT_OF_RANGE, "body id 5"},
        {"spring to itself", spring_self, TB_STATUS_INVALID_ARGUMENT, "body_b"},
        {"spring NaN point", spring_nan_point, TB_STATUS_NOT_FINITE, "point_b"},
        {"negative rest length", spring_negative_rest, TB_STATUS_INVALID_ARGUMENT, "rest_length"},
        {"ground normal zero", ground_bad_normal, TB_STATUS_INVALID_ARGUMENT, "normal"},
        {"mu_s < mu_k", ground_mu_order, TB_STATUS_INVALID_ARGUMENT, "static_friction"},
        {"zero penetration", ground_zero_penetration, TB_STATUS_INVALID_ARGUMENT, "penetration"},
        {"negative contact radius", contact_negative_radius, TB_STATUS_INVALID_ARGUMENT,
         "points[0]"},
        {"NULL user callback", user_null, TB_STATUS_NULL_POINTER, "fn"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tb_scene *scene = test_empty_scene();
        add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 1});
        const size_t size = tb_scene_state_size(scene);
        const tb_status status = cases[i].attempt(scene);
        print_message("%-24s -> %-18s %s\n", cases[i].label, tb_status_name(status),
                      tb_scene_detail(scene));
        assert_int_equal(status, cases[i].expected);
        assert_non_null(strstr(tb_scene_detail(scene), cases[i].named));
        assert_int_equal(tb_scene_effect_count(scene), 0);
        assert_int_equal(tb_scene_state_size(scene), size);
        tb_scene_destroy(scene);
    }
}

/* F31: a ground normal is a direction. (0, 0, 1e-300) and (1e300, 1e300, 1e300) were refused as
 * "|normal| = 0" or not unit, because |n|^2 under- or overflows; scaled by the largest component
 * first, each is the plane it points at: (0, 0, 1) exactly (one nonzero component, divided by
 * itself), and (1, 1, 1) / sqrt 3 within 2 ulps (one division and one square root). The scene
 * file's loader takes the same directions. */
static void test_a_ground_normal_of_any_length_is_its_direction(void **state)
{
    (void)state;
    const double third = 1.0 / sqrt(3.0);
    static const struct {
        double normal[3], expected[3], tolerance;
    } cases[] = {
        {{0, 0, 1e-300}, {0, 0, 1}, 0.0},
        {{0, 0, 5e-324}, {0, 0, 1}, 0.0},
        {{0, 0, 2}, {0, 0, 1}, 0.0},
        {{1e300, 1e300, 1e300}, {0, 0, 0}, 4.4e-16},
        {{DBL_MAX, DBL_MAX, DBL_MAX}, {0, 0, 0}, 4.4e-16},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tb_scene *scene = test_scene_one_body(1.0, (double[]){1, 1, 1}, NULL, (double[]){0, 0, 0});
        tb_ground_def ground = tb_ground_def_default();
        memcpy(ground.normal, cases[i].normal, sizeof ground.normal);
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        tb_ground_info info;
        assert_int_equal(tb_scene_get_ground(scene, 0, &info), TB_STATUS_OK);
        for (int k = 0; k < 3; ++k) {
            const double expected = cases[i].tolerance > 0.0 ? third : cases[i].expected[k];
            assert_near(info.normal[k], expected, cases[i].tolerance);
        }
        tb_scene_destroy(scene);
    }
    const char *json = "{\"bodies\": [{\"name\": \"b\", \"mass\": 1, \"shape\": {\"type\": "
                       "\"sphere\", \"radius\": 0.1}, \"position\": [0, 0, 1]}], \"effects\": "
                       "[{\"type\": \"ground\", \"normal\": [0, 0, 1e-300]}]}";
    tb_scene *loaded = NULL;
    tb_run_def run;
    tb_error error;
    assert_int_equal(tb_scene_load_string(json, "t.json", NULL, &loaded, &run, &error),
                     TB_STATUS_OK);
    tb_ground_info info;
    assert_int_equal(tb_scene_get_ground(loaded, 0, &info), TB_STATUS_OK);
    assert_true(info.normal[0] == 0.0 && info.normal[1] == 0.0 && info.normal[2] == 1.0);
    tb_scene_destroy(loaded);
}

/* The offset is the plane's distance along the unit normal, whatever the normal's length: a
 * ball of radius 0.1 m centred 1e-6 m below z = 1.1 dips 1e-6 m into the plane (0, 0, 2) . x = 1
 * made unit, z = 1 (read by the touching pairs to 1e-12 m: one subtraction near 1.1); were the
 * offset taken against the raw normal (z = 0.5) it would start 0.5 m deep and be refused. */
static void test_a_ground_offset_is_along_the_unit_normal(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t ball = add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 1.1 - 1e-6});
    const tb_contact_point point = {{0, 0, 0}, 0.1};
    assert_int_equal(tb_scene_set_contact_points(scene, ball, &point, 1, 1), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.normal[2] = 2.0;
    ground.offset = 1.0;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    tb_contact_touch touch;
    size_t count = 0;
    assert_int_equal(
        tb_scene_contact_touching(scene, tb_scene_states_const(scene), &touch, 1, &count),
        TB_STATUS_OK);
    assert_int_equal(count, 1);
    assert_near(touch.depth, 1e-6, 1e-12);
    tb_scene_destroy(scene);
}

/* A second ground plane facing the way an earlier one faces, within 1e-6 rad (a copy-pasted
 * plane, one at 1e-9 m above it, one tilted by 1e-7 rad), pushed the same contact points twice:
 * a ball dropped at 2 m/s with e = 0.5 left at 0.43 times its speed, with every event twice. It is
 * refused naming the earlier plane, nothing added; a plane tilted 1e-3 rad, a ceiling (the
 * opposite normal) and a wall are different planes and taken. */
static void test_a_second_plane_facing_the_same_way_is_refused(void **state)
{
    (void)state;
    const double tilt = 1e-7, wide = 1e-3;
    static const struct {
        double normal[3], offset;
        tb_status expected;
    } cases[] = {
        {{0, 0, 1}, 0.0, TB_STATUS_INVALID_ARGUMENT},
        {{0, 0, 7}, 1e-9, TB_STATUS_INVALID_ARGUMENT},
        {{0, 0, 1}, -5.0, TB_STATUS_INVALID_ARGUMENT}, /* buried under the first */
        {{tilt, 0, 1}, 0.0, TB_STATUS_INVALID_ARGUMENT},
        {{wide, 0, 1}, 0.0, TB_STATUS_OK},
        {{0, 0, -1}, -3.0, TB_STATUS_OK},
        {{1, 0, 0}, -2.0, TB_STATUS_OK},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        tb_scene *scene = test_empty_scene();
        add_sphere(scene, 1.0, 0.1, (double[]){0, 0, 1});
        tb_ground_def ground = tb_ground_def_default();
        assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
        const size_t size = tb_scene_state_size(scene);
        memcpy(ground.normal, cases[i].normal, sizeof ground.normal);
        ground.offset = cases[i].offset;
        const tb_status status = tb_scene_add_ground(scene, &ground);
        print_message("(%g, %g, %g) %g -> %s %s\n", cases[i].normal[0], cases[i].normal[1],
                      cases[i].normal[2], cases[i].offset, tb_status_name(status),
                      tb_scene_detail(scene));
        assert_int_equal(status, cases[i].expected);
        if (status != TB_STATUS_OK) {
            assert_non_null(strstr(tb_scene_detail(scene), "normal: "));
            assert_non_null(strstr(tb_scene_detail(scene), "effect 0 (a ground plane"));
            assert_int_equal(tb_scene_effect_count(scene), 1);
            assert_int_equal(tb_scene_state_size(scene), size);
        } else {
            assert_int_equal(tb_scene_effect_count(scene), 2);
        }
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spring_to_anchor_oscillates_at_sqrt_k_over_m),
        cmocka_unit_test(test_two_body_spring_uses_the_reduced_mass_and_decays),
        cmocka_unit_test(test_drag_gives_the_exact_terminal_velocity_curves),
        cmocka_unit_test(test_a_resting_box_sinks_by_the_configured_penetration),
        cmocka_unit_test(test_ground_force_starts_at_the_lowest_point_in_any_orientation),
        cmocka_unit_test(test_kinetic_friction_stops_a_slide_at_v2_over_2_mu_g),
        cmocka_unit_test(test_static_friction_holds_a_box_on_a_slope_without_creep),
        cmocka_unit_test(test_user_effect_acts_like_the_force_it_computes),
        cmocka_unit_test(test_bad_effect_definitions_are_refused_and_change_nothing),
        cmocka_unit_test(test_a_ground_normal_of_any_length_is_its_direction),
        cmocka_unit_test(test_a_second_plane_facing_the_same_way_is_refused),
        cmocka_unit_test(test_a_ground_offset_is_along_the_unit_normal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
