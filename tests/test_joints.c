/* Joints held exactly (issue 21): each test checks physics known without the code (energy
 * conservation, a pendulum in generalised coordinates, closed forms) or the joint's own
 * definition (its error stays at round-off). Tolerances are stated with their reasons. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fixtures.h"
#include "joint_scenes.h"
#include "span.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The double pendulum of two 1 kg, 1 m rods on hinges, RK4 at 1/240 s for 10 s, released
 * from (1.0, 0.5) rad: hinges do no work, so the energy is conserved up to RK4's error (the
 * issue's bound: 1e-5 m g l), and the projection keeps the joints at round-off (1e-12 m). */
static void test_double_pendulum_rk4_conserves_energy_on_its_hinges(void **state)
{
    (void)state;
    tb_scene *scene = test_double_pendulum(1.0, 0.5, NULL);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    const double e0 = test_total_energy(scene);
    double drift = 0.0, error = 0.0;
    for (int frame = 1; frame <= 600; ++frame) {
        assert_int_equal(tb_integrator_advance(integrator, frame / 60.0), TB_STATUS_OK);
        drift = fmax(drift, fabs(test_total_energy(scene) - e0));
        error = fmax(error, test_largest_joint_error(scene));
    }
    print_message("double pendulum rk4: energy drift %.3g m g l, joint error %.3g m\n",
                  drift / (1.0 * TEST_G * 1.0), error);
    assert_true(drift <= 1e-5 * TEST_G);
    assert_true(error <= 1e-12);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Runs the scene's integrator to each of frames frames at fps, calling observe after each. */
typedef void (*observer)(const tb_scene *scene, double t, void *ctx);

static void run_frames(tb_scene *scene, tb_integrator *integrator, int frames, double fps,
                       observer observe, void *ctx)
{
    for (int frame = 1; frame <= frames; ++frame) {
        const tb_status status = tb_integrator_advance(integrator, frame / fps);
        if (status != TB_STATUS_OK) {
            print_message("%s\n", tb_integrator_detail(integrator));
        }
        assert_int_equal(status, TB_STATUS_OK);
        observe(scene, frame / fps, ctx);
    }
}

typedef struct drift {
    double e0, energy, joint;
} drift;

static void watch_drift(const tb_scene *scene, double t, void *ctx)
{
    (void)t;
    drift *d = ctx;
    d->energy = fmax(d->energy, fabs(test_total_energy(scene) - d->e0));
    d->joint = fmax(d->joint, test_largest_joint_error(scene));
}

/* A 10-link chain of ball joints (1 kg, 1 m rods) released horizontally, RK4 at 1/240 s for
 * 2 s: ball joints do no work, so the energy is kept up to RK4's error; the bound is
 * 1e-5 m g l N (measured: 1.6e-6). A chain of 0.2 m links whips its end much faster within the
 * 2 s and RK4 at 240 Hz then loses 1.3e-2 m g l N, 4.1e-4 at 480 Hz, 1.6e-5 at 960 Hz: the
 * method's error (order 5 per step), not the joints' (docs/joints.md, "Tolerances"). */
static void test_ball_chain_released_horizontally_keeps_its_energy(void **state)
{
    (void)state;
    const size_t n = 10;
    const double m = 1.0, l = 1.0;
    tb_scene *scene = test_ball_chain(n, m, l);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    drift d = {test_total_energy(scene), 0.0, 0.0};
    run_frames(scene, integrator, 480, 240.0, watch_drift, &d);
    const double scale = m * TEST_G * l * (double)n;
    print_message("10-link chain rk4: energy drift %.3g m g l N, joint error %.3g m\n",
                  d.energy / scale, d.joint);
    assert_true(d.energy <= 1e-5 * scale);
    assert_true(d.joint <= 1e-12);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

typedef struct hanging {
    size_t heavy;
    double length;  /* m: pivot to the heavy body's anchor, straight */
    double stretch; /* m: the largest |pivot-to-anchor distance| beyond length */
    double joint;
} hanging;

static void watch_hanging(const tb_scene *scene, double t, void *ctx)
{
    (void)t;
    hanging *h = ctx;
    double p[3], v[3];
    assert_int_equal(tb_scene_body_point(scene, tb_scene_states_const(scene), h->heavy,
                                         (double[]){0.0, 0.0, 0.2}, p, v),
                     TB_STATUS_OK);
    h->stretch = fmax(h->stretch, sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) - h->length);
    h->joint = fmax(h->joint, test_largest_joint_error(scene));
}

/* A 1000 kg ball hung from five 1 kg links of 0.2 m (ball joints), swinging: the exact solve
 * does not stretch the chain as an iterative solver does under a mass ratio of 1000; the
 * pivot-to-ball distance stays within the chain's length plus 1e-9 m (the bound). RK4
 * at 1/480 s: the links sway under the weight's tension at up to about 700 rad/s, beyond
 * RK4's limit at 1/240 s, which the guard refuses (test_joints_guard.c). */
static void test_heavy_body_on_light_chain_does_not_stretch_it(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const size_t links = 5;
    const double l = 0.2;
    size_t previous = TB_WORLD;
    for (size_t i = 0; i < links; ++i) {
        const size_t id = test_add_rod(scene, 1.0, l, 0.0, (double[]){0.0, 0.0, -(i + 0.5) * l});
        tb_joint_def def = tb_joint_def_default();
        def.body_a = id;
        def.body_b = previous;
        def.anchor[2] = -(double)i * l;
        assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
        previous = id;
    }
    const double bottom = -(double)links * l;
    const size_t heavy = test_add_ball(scene, NULL, 1000.0, 0.2, (double[]){0.0, 0.0, bottom - 0.2},
                                       (double[]){1.0, 0.5, 0.0});
    tb_joint_def def = tb_joint_def_default();
    def.body_a = heavy;
    def.body_b = previous;
    def.anchor[2] = bottom;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    /* the links start at rest under a moving ball: the first step's projection makes the
     * velocities agree */
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 480.0, 0.0);
    hanging h = {heavy, -bottom, 0.0, 0.0};
    run_frames(scene, integrator, 480, 240.0, watch_hanging, &h);
    print_message("1000 kg on 1 kg links: stretch %.3g m, joint error %.3g m\n", h.stretch,
                  h.joint);
    assert_true(h.stretch <= 1e-9);
    assert_true(h.joint <= 1e-9);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A rod from p to q (in the x-z plane): its id. */
static size_t rod_between(tb_scene *scene, const double p[3], const double q[3])
{
    const double d[3] = {q[0] - p[0], 0.0, q[2] - p[2]};
    const double length = sqrt(d[0] * d[0] + d[2] * d[2]);
    const double center[3] = {0.5 * (p[0] + q[0]), 0.0, 0.5 * (p[2] + q[2])};
    return test_add_bar(scene, 1.0, length, 0.05, atan2(d[0] / length, -d[2] / length), center);
}

static void join(tb_scene *scene, tb_joint_type type, size_t a, size_t b, const double anchor[3])
{
    tb_joint_def def = tb_joint_def_default();
    def.type = type;
    def.body_a = a;
    def.body_b = b;
    memcpy(def.anchor, anchor, sizeof def.anchor);
    def.axis[1] = 1.0;
    def.axis[2] = 0.0;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
}

/* A four-bar linkage (a loop: crank, coupler, rocker, the world as the fourth bar), RK4 at
 * 1/240 s for 60 s under gravity: hinges at the world pivots, ball joints at the coupler's ends
 * (an RSSR linkage; four planar hinges repeat rows: test_joints_redundant.c). The joint error
 * stays at round-off however long it runs (no drift: 1e-12 m) and the energy is kept to RK4's
 * error: measured 7.6e-5 m g l over 60 s (2.6e-6 at 480 Hz, 9.9e-8 at 960 Hz: the method's
 * order, not a leak of the joints); bound 2.5e-4. */
static void test_four_bar_linkage_does_not_drift_off_its_joints(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double A[3] = {0.0, 0.0, 0.0}, B[3] = {0.5, 0.0, 0.8660254037844386};
    const double C[3] = {2.0, 0.0, 1.2}, D[3] = {2.0, 0.0, 0.0};
    const size_t crank = rod_between(scene, A, B), coupler = rod_between(scene, B, C);
    const size_t rocker = rod_between(scene, D, C);
    join(scene, TB_JOINT_HINGE, crank, TB_WORLD, A);
    join(scene, TB_JOINT_BALL, coupler, crank, B);
    join(scene, TB_JOINT_BALL, coupler, rocker, C);
    join(scene, TB_JOINT_HINGE, rocker, TB_WORLD, D);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    drift d = {test_total_energy(scene), 0.0, 0.0};
    /* under memcheck 5 s: the joint error has as many steps to drift, at every one */
    const int seconds = (int)tb_test_span(60.0, 5.0);
    run_frames(scene, integrator, seconds * 60, 60.0, watch_drift, &d);
    print_message("four-bar %d s rk4: energy drift %.3g m g l, joint error %.3g m\n", seconds,
                  d.energy / TEST_G, d.joint);
    assert_true(d.joint <= 1e-12);
    assert_true(d.energy <= 2.5e-4 * TEST_G);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Two boxes held by a fixed joint, tumbling in free space, against one body of their combined
 * mass properties (tb_mass_combine, the parallel-axis theorem) started with the same motion:
 * a material point of the first box follows the combined body's to RK4's error at 1/240 s
 * over 3 s (measured 2e-10 m; bound 1e-8 m). */
static void test_fixed_joint_moves_as_one_body_of_combined_mass(void **state)
{
    (void)state;
    tb_mass_part parts[2];
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 2.0, (double[]){0.4, 0.2, 0.1}, &parts[0].props, NULL),
        TB_STATUS_OK);
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 1.0, (double[]){0.2, 0.3, 0.2}, &parts[1].props, NULL),
        TB_STATUS_OK);
    const double offset[3] = {0.3, 0.1, 0.05}, omega[3] = {1.0, 2.0, 0.5};
    for (int k = 0; k < 2; ++k) {
        const double identity[4] = {1.0, 0.0, 0.0, 0.0};
        memcpy(parts[k].orientation, identity, sizeof identity);
        for (int i = 0; i < 3; ++i) {
            parts[k].position[i] = k == 0 ? 0.0 : offset[i];
        }
    }
    tb_mass_properties combined;
    assert_int_equal(tb_mass_combine(parts, 2, &combined, NULL), TB_STATUS_OK);
    tb_scene *jointed = test_empty_scene(), *whole = test_empty_scene();
    size_t ids[2];
    for (int k = 0; k < 2; ++k) {
        tb_body_def def = tb_body_def_default();
        def.mass = parts[k].props;
        double r[3];
        for (int i = 0; i < 3; ++i) {
            def.position[i] = parts[k].position[i];
            r[i] = def.position[i] - combined.center[i];
        }
        memcpy(def.angular_velocity, omega, sizeof omega);
        def.velocity[0] = omega[1] * r[2] - omega[2] * r[1]; /* omega x r about the centre */
        def.velocity[1] = omega[2] * r[0] - omega[0] * r[2];
        def.velocity[2] = omega[0] * r[1] - omega[1] * r[0];
        assert_int_equal(tb_scene_add_body(jointed, &def, &ids[k]), TB_STATUS_OK);
    }
    join(jointed, TB_JOINT_FIXED, ids[1], ids[0], (double[]){0.15, 0.05, 0.0});
    tb_body_def def = tb_body_def_default();
    def.mass = combined;
    memcpy(def.position, combined.center, sizeof def.position);
    memcpy(def.angular_velocity, omega, sizeof omega);
    size_t one = 0;
    assert_int_equal(tb_scene_add_body(whole, &def, &one), TB_STATUS_OK);
    tb_integrator *a = test_integrator_for(jointed, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    tb_integrator *b = test_integrator_for(whole, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(a, 3.0), TB_STATUS_OK);
    assert_int_equal(tb_integrator_advance(b, 3.0), TB_STATUS_OK);
    const double point[3] = {0.2, -0.1, 0.05};
    double pa[3], pb[3], v[3];
    assert_int_equal(
        tb_scene_body_point(jointed, tb_scene_states_const(jointed), ids[0], point, pa, v),
        TB_STATUS_OK);
    assert_int_equal(tb_scene_body_point(whole, tb_scene_states_const(whole), one, point, pb, v),
                     TB_STATUS_OK);
    const double gap = sqrt((pa[0] - pb[0]) * (pa[0] - pb[0]) + (pa[1] - pb[1]) * (pa[1] - pb[1]) +
                            (pa[2] - pb[2]) * (pa[2] - pb[2]));
    print_message("fixed joint vs combined body: %.3g m after 3 s\n", gap);
    assert_true(gap <= 1e-8);
    tb_integrator_destroy(a);
    tb_integrator_destroy(b);
    tb_scene_destroy(jointed);
    tb_scene_destroy(whole);
}

/* A box on a slider to the world along an incline of 30 degrees, released at rest: only the
 * component of gravity along the axis acts, a = g sin(30 deg), so after 1 s it has moved
 * g sin(30 deg) / 2 along the axis and has not turned. RK4 is exact on the quadratic; the
 * bound 1e-10 m is round-off over 240 steps with their projections. */
static void test_slider_on_incline_accelerates_at_g_sin_angle(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double angle = TEST_PI / 6.0, axis[3] = {cos(angle), 0.0, -sin(angle)};
    tb_body_def body = tb_body_def_default();
    assert_int_equal(
        tb_mass_from_box(TB_MASS_GIVEN, 3.0, (double[]){0.3, 0.2, 0.1}, &body.mass, NULL),
        TB_STATUS_OK);
    const double q[4] = {cos(0.2), 0.3 * sin(0.2), 0.4 * sin(0.2), sqrt(0.75) * sin(0.2)};
    memcpy(body.orientation, q, sizeof q);
    body.position[2] = 1.0;
    size_t id = 0;
    assert_int_equal(tb_scene_add_body(scene, &body, &id), TB_STATUS_OK);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_SLIDER;
    def.body_a = id;
    memcpy(def.anchor, (double[]){0.1, 0.05, 1.02}, sizeof def.anchor);
    memcpy(def.axis, axis, sizeof def.axis);
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    tb_body_state s0, s;
    assert_int_equal(tb_scene_get_state(scene, id, &s0), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 1.0), TB_STATUS_OK);
    assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
    const double travel = 0.5 * TEST_G * sin(angle);
    double worst = 0.0;
    for (int k = 0; k < 3; ++k) {
        const double expected = (k == 2 ? 1.0 : 0.0) + travel * axis[k];
        worst = fmax(worst, fabs(s.x[k] - expected));
        worst = fmax(worst, fabs(s.q[k + 1] - s0.q[k + 1]));
    }
    print_message("slider on incline: %.3g m off g sin(a) t^2 / 2\n", worst);
    assert_true(worst <= 1e-10);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A ball (1 kg, r 0.1 m) on a ball joint 1 m below the world's pivot, released 0.005 rad off
 * the vertical: a compound pendulum of period 2 pi sqrt(I_p / (m g L)), I_p = 2/5 m r^2 +
 * m L^2, longer by theta0^2 / 16 = 1.6e-6 at this amplitude. Five periods by the crossings
 * of x = 0 (RK4 at 1/240 s, crossings interpolated linearly where the motion is straight):
 * within 1e-8 of the period (measured 1.5e-10; the next amplitude term is 1e-12). */
static void test_ball_pendulum_small_angle_period(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double L = 1.0, r = 0.1, theta0 = 0.005;
    const size_t id = test_add_ball(scene, NULL, 1.0, r,
                                    (double[]){L * sin(theta0), 0.0, -L * cos(theta0)}, NULL);
    join(scene, TB_JOINT_BALL, id, TB_WORLD, (double[]){0.0, 0.0, 0.0});
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    const double period = 2.0 * TEST_PI * sqrt((0.4 * r * r + L * L) / (TEST_G * L));
    double last_x = L * sin(theta0), first = -1.0, crossing = -1.0;
    int crossings = 0;
    for (int k = 1; k <= (int)(5.6 * period * 240.0); ++k) {
        assert_int_equal(tb_integrator_advance(integrator, k / 240.0), TB_STATUS_OK);
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
        if (last_x > 0.0 && s.x[0] <= 0.0) { /* downward crossing, linearly between steps */
            crossing = (k - s.x[0] / (s.x[0] - last_x)) / 240.0;
            first = crossings++ == 0 ? crossing : first;
        }
        last_x = s.x[0];
    }
    const double measured = (crossing - first) / (crossings - 1);
    const double expected = period * (1.0 + theta0 * theta0 / 16.0);
    print_message("ball pendulum: period %.9f s, expected %.9f s (%.2g)\n", measured, expected,
                  measured / expected - 1.0);
    assert_int_equal(crossings, 6);
    assert_true(fabs(measured / expected - 1.0) <= 1e-8);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

#define SUPPORT_ACCELERATION (0.5 * TEST_G) /* m/s^2 along +x */

/* The support's motion: x = a t^2 / 2 along x, not turning. */
static int accelerating_support(double t, void *ctx, tb_body_motion_sample *out)
{
    (void)ctx;
    memset(out, 0, sizeof *out);
    out->orientation[0] = 1.0;
    out->position[0] = 0.5 * SUPPORT_ACCELERATION * t * t;
    out->velocity[0] = SUPPORT_ACCELERATION * t;
    out->acceleration[0] = SUPPORT_ACCELERATION;
    return 0;
}

/* phi'' = -(m L |g_eff| / I_p) sin(phi - phi0), RK4 with steps of h. */
static void swing(double s[2], double h, double rate2, double phi0)
{
    double k[4][2], t[2];
    for (int stage = 0; stage < 4; ++stage) {
        const double c = stage == 0 ? 0.0 : stage == 3 ? h : 0.5 * h;
        t[0] = s[0] + (stage == 0 ? 0.0 : c * k[stage - 1][0]);
        t[1] = s[1] + (stage == 0 ? 0.0 : c * k[stage - 1][1]);
        k[stage][0] = t[1];
        k[stage][1] = -rate2 * sin(t[0] - phi0);
    }
    for (int i = 0; i < 2; ++i) {
        s[i] += h / 6.0 * (k[0][i] + 2.0 * k[1][i] + 2.0 * k[2][i] + k[3][i]);
    }
}

/* A ball pendulum hung from a keyframed support that accelerates uniformly along x from
 * rest: in the support's frame gravity is g_eff = (-a, 0, -g), so the pendulum swings about
 * phi0 = atan(-a / g) from rest at phi = 0 exactly as the plain pendulum under |g_eff|, whose
 * equation (integrated by RK4 at 1e-4 s) is the reference. The keyframed body's acceleration
 * enters the joint's solve. Over 3 s at RK4 1/240 s: within 1e-7 rad (measured 1.1e-9). */
static void test_pendulum_on_accelerating_keyframed_support(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    tb_body_def support = tb_body_def_default();
    support.motion = TB_MOTION_KEYFRAMED;
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.05, &support.mass, NULL),
                     TB_STATUS_OK);
    size_t base = 0;
    assert_int_equal(tb_scene_add_body(scene, &support, &base), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_body_motion_fn(scene, base, accelerating_support, NULL),
                     TB_STATUS_OK);
    const double L = 1.0, r = 0.1;
    const size_t id = test_add_ball(scene, NULL, 1.0, r, (double[]){0.0, 0.0, -L}, NULL);
    join(scene, TB_JOINT_BALL, id, base, (double[]){0.0, 0.0, 0.0});
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    const double a = SUPPORT_ACCELERATION, g_eff = sqrt(a * a + TEST_G * TEST_G);
    const double rate2 = L * g_eff / (0.4 * r * r + L * L), phi0 = atan2(-a, TEST_G);
    double reference[2] = {0.0, 0.0}, worst = 0.0;
    for (int k = 1; k <= 180; ++k) {
        assert_int_equal(tb_integrator_advance(integrator, k / 60.0), TB_STATUS_OK);
        for (int i = 0; i < 1000 / 6; ++i) {
            swing(reference, 1.0 / 60.0 / (1000 / 6), rate2, phi0);
        }
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
        const double t = k / 60.0, x = s.x[0] - 0.5 * a * t * t;
        worst = fmax(worst, fabs(atan2(x, -s.x[2]) - reference[0]));
    }
    print_message("pendulum on accelerating support: %.3g rad off\n", worst);
    assert_true(worst <= 1e-7);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A cantilever: a 2 kg bar held level by a fixed joint to the world at its end, at rest. Statics:
 * the joint pushes up with m g and turns it back with the torque -d x (-m g z) about the
 * anchor (d the arm to the centre of mass), and the state is on the joint (0 error). To
 * round-off: 1e-12 of m g. */
static void test_cantilever_reaction_is_statics(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double m = 2.0, length = 0.8;
    const size_t id =
        test_add_bar(scene, m, length, 0.05, 0.5 * TEST_PI, (double[]){0.5 * length, 0.0, 0.0});
    join(scene, TB_JOINT_FIXED, id, TB_WORLD, (double[]){0.0, 0.0, 0.0});
    double force[3], torque[3], position = 1.0, velocity = 1.0;
    const double *y = tb_scene_states_const(scene);
    assert_int_equal(tb_scene_joint_reaction(scene, y, 0, force, torque), TB_STATUS_OK);
    assert_int_equal(tb_scene_joint_error(scene, y, 0, &position, &velocity), TB_STATUS_OK);
    const double weight = m * TEST_G, tol = 1e-12 * weight;
    assert_true(fabs(force[0]) <= tol && fabs(force[1]) <= tol);
    assert_true(fabs(force[2] - weight) <= tol);
    /* gravity's torque about the anchor: (L/2) x x (-m g z) = m g L / 2 y; the joint's cancels */
    assert_true(fabs(torque[0]) <= tol && fabs(torque[2]) <= tol);
    assert_true(fabs(torque[1] + 0.5 * length * weight) <= tol);
    assert_true(position <= 1e-15 && velocity == 0.0);
    tb_scene_destroy(scene);
}

/* Sleeping: a still ball joined to a spinning one (the joint at the spinning ball's centre,
 * so it carries no force and the still ball stays still) must not fall asleep apart from it:
 * the joint links the two into one island. A lone still ball beside them does sleep after
 * TB_SLEEP_TIME (the control). */
static void test_jointed_bodies_do_not_fall_asleep_apart(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const size_t still = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, 0.0}, NULL);
    tb_body_def spinning = tb_body_def_default();
    assert_int_equal(tb_mass_from_sphere(TB_MASS_GIVEN, 1.0, 0.1, &spinning.mass, NULL),
                     TB_STATUS_OK);
    spinning.position[0] = 1.0;
    spinning.angular_velocity[2] = 5.0;
    size_t spinner = 0;
    assert_int_equal(tb_scene_add_body(scene, &spinning, &spinner), TB_STATUS_OK);
    const size_t lone = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){5.0, 0.0, 0.0}, NULL);
    join(scene, TB_JOINT_BALL, still, spinner, (double[]){1.0, 0.0, 0.0});
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    assert_int_equal(tb_integrator_advance(integrator, 4.0 * TB_SLEEP_TIME), TB_STATUS_OK);
    bool asleep[3];
    const size_t ids[3] = {still, spinner, lone};
    for (int k = 0; k < 3; ++k) {
        assert_int_equal(tb_scene_body_asleep(scene, ids[k], &asleep[k]), TB_STATUS_OK);
    }
    assert_false(asleep[0]);
    assert_false(asleep[1]);
    assert_true(asleep[2]);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Contact and joints together: a ball pendulum (1 kg, r 0.1 m, 1 m arm) released level swings
 * down into a ground plane 1.05 m below its pivot (contact forces are applied loads, and the
 * joint's stage runs after them). It bounces back up the way it came, never sinks more than
 * 1 mm into the ground, loses energy at the impact (restitution 0.3) and never gains any, and
 * stays on its joint (1e-12 m). RK4 at the scene's default step. */
static void test_pendulum_bounces_off_the_ground_on_its_joint(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const double r = 0.1, floor_z = -1.05;
    const size_t id = test_add_ball(scene, NULL, 1.0, r, (double[]){1.0, 0.0, 0.0}, NULL);
    tb_contact_point point;
    size_t count = 0;
    assert_int_equal(tb_contact_points_sphere(r, &point, 1, &count), TB_STATUS_OK);
    assert_int_equal(tb_scene_set_contact_points(scene, id, &point, count, 1), TB_STATUS_OK);
    tb_ground_def ground = tb_ground_def_default();
    ground.offset = floor_z;
    assert_int_equal(tb_scene_add_ground(scene, &ground), TB_STATUS_OK);
    join(scene, TB_JOINT_BALL, id, TB_WORLD, (double[]){0.0, 0.0, 0.0});
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 0.0, 0.0);
    const double e0 = test_total_energy(scene);
    double deepest = 0.0, gained = -INFINITY, joint = 0.0, last_vx = 0.0;
    bool swung_in = false, bounced = false;
    for (int k = 1; k <= 120; ++k) {
        assert_int_equal(tb_integrator_advance(integrator, k / 120.0), TB_STATUS_OK);
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
        deepest = fmax(deepest, floor_z - (s.x[2] - r));
        gained = fmax(gained, test_total_energy(scene) - e0);
        joint = fmax(joint, test_largest_joint_error(scene));
        swung_in = swung_in || s.P[0] < 0.0;
        bounced = bounced || (swung_in && last_vx < 0.0 && s.P[0] > 0.0 && s.x[0] > 0.0);
        last_vx = s.P[0];
    }
    print_message("pendulum on the ground: deepest %.3g m, energy gained %.3g J, joint %.3g m\n",
                  deepest, gained, joint);
    assert_true(bounced);
    assert_true(deepest <= 1e-3);
    assert_true(gained <= 1e-9 * e0 + 1e-9);
    assert_true(test_total_energy(scene) < e0 - 0.1);
    assert_true(joint <= 1e-12);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* A soft ball joint (2 Hz, damping ratio 0.1) holding a 2 kg ball at its centre, the ball
 * kicked at 1 m/s, no gravity: each row is a spring-damper at the ball's mass, so the ball
 * follows the damped oscillator x = v0 / w_d e^(-zeta w t) sin(w_d t), w = 2 pi f,
 * w_d = w sqrt(1 - zeta^2). RK4 at 1/240 s over 2 s: within 1e-6 m (measured 1.8e-8 m; the
 * step's w dt = 0.05 gives RK4 an error of order (w dt)^4 / 120 of the amplitude). */
static void test_soft_joint_is_a_damped_spring_at_the_body_mass(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const double f = 2.0, zeta = 0.1, v0 = 1.0;
    const size_t id =
        test_add_ball(scene, NULL, 2.0, 0.1, (double[]){0.0, 0.0, 0.0}, (double[]){v0, 0.0, 0.0});
    tb_joint_def def = tb_joint_def_default();
    def.body_a = id;
    def.soft_frequency = f;
    def.soft_damping_ratio = zeta;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    const double w = 2.0 * TEST_PI * f, wd = w * sqrt(1.0 - zeta * zeta);
    double worst = 0.0;
    for (int k = 1; k <= 120; ++k) {
        const double t = k / 60.0;
        assert_int_equal(tb_integrator_advance(integrator, t), TB_STATUS_OK);
        tb_body_state s;
        assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
        const double exact = v0 / wd * exp(-zeta * w * t) * sin(wd * t);
        worst = fmax(worst, fmax(fabs(s.x[0] - exact), fmax(fabs(s.x[1]), fabs(s.x[2]))));
    }
    print_message("soft joint: %.3g m off the damped oscillator\n", worst);
    assert_true(worst <= 1e-6);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

#define PULL_RATE 10.0 /* N/s: the pull's growth */

/* A pull down on body 0's centre growing as PULL_RATE t. */
static int growing_pull(double t, const tb_scene *scene, const double *y, double *dydt, void *ctx)
{
    (void)ctx;
    const double force[3] = {0.0, 0.0, -PULL_RATE * t};
    return tb_effect_add_force(scene, y, dydt, 0, force, y + TB_STATE_X) == TB_STATUS_OK ? 0 : -1;
}

/* A 1 kg ball hanging at rest from a ball joint with break_force 30 N, pulled down by a force
 * growing at 10 N/s: statics puts the joint's reaction at m g + 10 t, which passes 30 N at
 * t* = (30 - m g) / 10 = 2.019 s. The joint breaks at the first step boundary past t* (within
 * the 1/240 s between reads), its reaction is 0 from then on, and the ball falls. */
static void break_under(tb_method method)
{
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    const size_t id = test_add_ball(scene, NULL, 1.0, 0.1, (double[]){0.0, 0.0, -0.1}, NULL);
    assert_int_equal(tb_scene_add_user_effect(scene, growing_pull, NULL), TB_STATUS_OK);
    tb_joint_def def = tb_joint_def_default();
    def.body_a = id;
    def.break_force = 30.0;
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, method, 1.0 / 240.0, 1e-8);
    const double t_star = (30.0 - TEST_G) / PULL_RATE;
    double broke_at = -1.0;
    for (int k = 1; k <= 600 && broke_at < 0.0; ++k) {
        assert_int_equal(tb_integrator_advance(integrator, k / 240.0), TB_STATUS_OK);
        bool broken = false;
        assert_int_equal(tb_scene_joint_broken(scene, 0, &broken), TB_STATUS_OK);
        broke_at = broken ? k / 240.0 : -1.0;
    }
    print_message("%s: joint broke at %.6f s, statics %.6f s\n", tb_method_name(method), broke_at,
                  t_star);
    /* CVODE's check runs as the next advance starts, on the last output: one read later */
    const double reads = tb_method_is_adaptive(method) ? 2.0 : 1.0;
    assert_true(broke_at > t_star && broke_at <= t_star + reads / 240.0);
    double force[3], torque[3];
    assert_int_equal(tb_scene_joint_reaction(scene, tb_scene_states_const(scene), 0, force, torque),
                     TB_STATUS_OK);
    assert_true(force[0] == 0.0 && force[1] == 0.0 && force[2] == 0.0);
    assert_int_equal(tb_integrator_advance(integrator, broke_at + 0.5), TB_STATUS_OK);
    tb_body_state s;
    assert_int_equal(tb_scene_get_state(scene, id, &s), TB_STATUS_OK);
    assert_true(s.x[2] < -0.1 - 0.5 * TEST_G * 0.25 * 0.9); /* at least free fall's 1.2 m */
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* Under RK4 at 1/240 s, and under CVODE BDF read every 1/240 s (its boundaries are its
 * outputs: its projections run on trial steps too). */
static void test_joint_breaks_when_its_reaction_passes_the_limit(void **state)
{
    (void)state;
    break_under(TB_METHOD_RK4);
    break_under(TB_METHOD_CVODE_BDF);
}

typedef struct ring_watch {
    double P0[3], L0[3], e0;
    double momentum, angular, energy, joint;
} ring_watch;

static void watch_ring(const tb_scene *scene, double t, void *ctx)
{
    (void)t;
    ring_watch *w = ctx;
    const double *y = tb_scene_states_const(scene), origin[3] = {0.0, 0.0, 0.0};
    double P[3], L[3];
    assert_int_equal(tb_scene_linear_momentum(scene, y, P), TB_STATUS_OK);
    assert_int_equal(tb_scene_angular_momentum(scene, y, origin, L), TB_STATUS_OK);
    for (int k = 0; k < 3; ++k) {
        w->momentum = fmax(w->momentum, fabs(P[k] - w->P0[k]));
        w->angular = fmax(w->angular, fabs(L[k] - w->L0[k]));
    }
    w->energy = fmax(w->energy, fabs(test_total_energy(scene) - w->e0));
    w->joint = fmax(w->joint, test_largest_joint_error(scene));
}

/* A closed ring of four bars on ball joints (a loop: the factor fills in) tumbling freely,
 * started as one rigid rotation with one bar spinning about its own axis through its two
 * joints as well (a start on the joints), so that the ring flexes: the joints' forces are internal,
 * so the total momentum is kept to round-off (1e-12 kg m/s: the solve and the projection's impulses
 * are equal and opposite) and the angular momentum and energy to RK4's error at 1/240 s over 5 s
 * (measured 6.8e-10 and 3.2e-11 of their sizes; bounds 1e-8), the joints at round-off. */
static void test_free_ring_keeps_momentum_angular_momentum_and_energy(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    const double corner[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}};
    const double omega[3] = {0.3, 0.2, 1.0}, c[3] = {0.5, 0.5, 0.0};
    size_t ids[4];
    for (int i = 0; i < 4; ++i) {
        tb_body_def def = tb_body_def_default();
        const double size[3] = {1.0, 0.1, 0.1};
        assert_int_equal(tb_mass_from_box(TB_MASS_GIVEN, 1.0 + 0.5 * i, size, &def.mass, NULL),
                         TB_STATUS_OK);
        const double q[4] = {cos(0.25 * TEST_PI * i), 0.0, 0.0, sin(0.25 * TEST_PI * i)};
        memcpy(def.orientation, q, sizeof q);
        double r[3];
        for (int k = 0; k < 3; ++k) {
            def.position[k] = 0.5 * (corner[i][k] + corner[i + 1][k]);
            r[k] = def.position[k] - c[k];
        }
        def.velocity[0] = omega[1] * r[2] - omega[2] * r[1];
        def.velocity[1] = omega[2] * r[0] - omega[0] * r[2];
        def.velocity[2] = omega[0] * r[1] - omega[1] * r[0];
        memcpy(def.angular_velocity, omega, sizeof omega);
        def.angular_velocity[0] += i == 0 ? 5.0 : 0.0; /* bar 0 spins about its own axis too */
        assert_int_equal(tb_scene_add_body(scene, &def, &ids[i]), TB_STATUS_OK);
    }
    for (int i = 0; i < 4; ++i) {
        join(scene, TB_JOINT_BALL, ids[(i + 1) % 4], ids[i], corner[i + 1]);
    }
    tb_conserved claimed;
    assert_int_equal(tb_scene_conserved(scene, &claimed), TB_STATUS_OK);
    assert_true(claimed.energy && claimed.linear_momentum && claimed.angular_momentum &&
                claimed.angular_momentum_about_center_of_mass);
    ring_watch w = {.e0 = test_total_energy(scene)};
    const double *y = tb_scene_states_const(scene), origin[3] = {0.0, 0.0, 0.0};
    assert_int_equal(tb_scene_linear_momentum(scene, y, w.P0), TB_STATUS_OK);
    assert_int_equal(tb_scene_angular_momentum(scene, y, origin, w.L0), TB_STATUS_OK);
    tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
    run_frames(scene, integrator, 300, 60.0, watch_ring, &w);
    const double size_L = sqrt(w.L0[0] * w.L0[0] + w.L0[1] * w.L0[1] + w.L0[2] * w.L0[2]);
    print_message("free ring: momentum %.3g, angular momentum %.3g, energy %.3g (relative), joint "
                  "%.3g m\n",
                  w.momentum, w.angular / size_L, w.energy / w.e0, w.joint);
    assert_true(w.momentum <= 1e-12);
    assert_true(w.angular <= 1e-8 * size_L);
    assert_true(w.energy <= 1e-8 * w.e0);
    assert_true(w.joint <= 1e-12);
    tb_integrator_destroy(integrator);
    tb_scene_destroy(scene);
}

/* The same cantilever fixed to a static wall body (its shape origin at the anchor) instead of
 * the world: the wall's reaction read-out (tb_scene_body_reaction) is the joint's load on it,
 * the opposite of the bar's: m g down and the bar's weight's torque m g L / 2 about y. */
static void test_static_wall_feels_the_cantilever_it_holds(void **state)
{
    (void)state;
    tb_scene *scene = test_empty_scene();
    assert_int_equal(tb_scene_add_gravity(scene, (double[]){0.0, 0.0, -TEST_G}), TB_STATUS_OK);
    tb_body_def wall = tb_body_def_default();
    wall.motion = TB_MOTION_STATIC;
    size_t holder = 0;
    assert_int_equal(tb_scene_add_body(scene, &wall, &holder), TB_STATUS_OK);
    const double m = 2.0, length = 0.8;
    const size_t id =
        test_add_bar(scene, m, length, 0.05, 0.5 * TEST_PI, (double[]){0.5 * length, 0.0, 0.0});
    join(scene, TB_JOINT_FIXED, id, holder, (double[]){0.0, 0.0, 0.0});
    double force[3], torque[3];
    assert_int_equal(
        tb_scene_body_reaction(scene, tb_scene_states_const(scene), holder, force, torque),
        TB_STATUS_OK);
    const double weight = m * TEST_G, tol = 1e-12 * weight;
    assert_true(fabs(force[0]) <= tol && fabs(force[1]) <= tol);
    assert_true(fabs(force[2] + weight) <= tol);
    assert_true(fabs(torque[0]) <= tol && fabs(torque[2]) <= tol);
    assert_true(fabs(torque[1] - 0.5 * length * weight) <= tol);
    tb_scene_destroy(scene);
}

/* What tb_scene_conserved claims for joints, each claim checked against the motion (RK4 at
 * 1/240 s, 0.5 s). Case 0, the double pendulum from horizontal: its hinge to the world does no
 * work (energy kept to RK4's error: bound 1e-6 of m g l). Case 1, a 1 kg, 1 m rod spinning at
 * 2 rad/s about a world hinge at its end, no gravity: the hinge pushes (the rod's momentum, 1 kg
 * m/s, turns by 1 rad: it changes by about 1 kg m/s, bound 0.5), so momentum is not claimed.
 * Case 2, the rod with a motor driving its hinge at 4 rad/s under a 50 N m cap: the motor does
 * work (the energy moves by more than 1 J), so energy is not claimed. */
static tb_scene *conserved_case(int which)
{
    if (which == 0) {
        return test_double_pendulum(0.5 * TEST_PI, 0.5 * TEST_PI, NULL);
    }
    tb_scene *scene = test_empty_scene();
    const double center[3] = {0.5, 0.0, 0.0};
    const size_t rod = test_add_rod(scene, 1.0, 1.0, 0.5 * TEST_PI, center);
    const double omega[3] = {0.0, 0.0, 2.0}, zero[3] = {0.0, 0.0, 0.0};
    const double v[3] = {0.0, 1.0, 0.0};
    assert_int_equal(
        tb_scene_set_velocity(scene, rod, which == 1 ? v : zero, which == 1 ? omega : zero),
        TB_STATUS_OK);
    tb_joint_def def = tb_joint_def_default();
    def.type = TB_JOINT_HINGE;
    def.body_a = rod;
    if (which == 2) {
        def.motor = TB_MOTOR_VELOCITY;
        def.motor_speed = 4.0;
        def.motor_max_force = 50.0;
    }
    assert_int_equal(tb_scene_add_joint(scene, &def, NULL), TB_STATUS_OK); /* axis z */
    return scene;
}

static void test_conserved_says_what_joints_keep(void **state)
{
    (void)state;
    for (int which = 0; which < 3; ++which) {
        tb_scene *scene = conserved_case(which);
        tb_conserved claimed;
        assert_int_equal(tb_scene_conserved(scene, &claimed), TB_STATUS_OK);
        assert_int_equal(claimed.energy, which != 2);
        assert_false(claimed.linear_momentum || claimed.angular_momentum ||
                     claimed.angular_momentum_about_center_of_mass);
        const double e0 = test_total_energy(scene);
        double P0[3], P[3];
        assert_int_equal(tb_scene_linear_momentum(scene, tb_scene_states_const(scene), P0),
                         TB_STATUS_OK);
        tb_integrator *integrator = test_integrator_for(scene, TB_METHOD_RK4, 1.0 / 240.0, 0.0);
        assert_int_equal(tb_integrator_advance(integrator, 0.5), TB_STATUS_OK);
        assert_int_equal(tb_scene_linear_momentum(scene, tb_scene_states_const(scene), P),
                         TB_STATUS_OK);
        const double moved =
            sqrt((P[0] - P0[0]) * (P[0] - P0[0]) + (P[1] - P0[1]) * (P[1] - P0[1]) +
                 (P[2] - P0[2]) * (P[2] - P0[2]));
        const double change = fabs(test_total_energy(scene) - e0);
        print_message("case %d: momentum moved %.3g kg m/s, energy %.3g J\n", which, moved, change);
        assert_true(moved > 0.5);
        assert_true(which == 2 ? change > 1.0 : change <= 1e-6 * TEST_G);
        tb_integrator_destroy(integrator);
        tb_scene_destroy(scene);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_double_pendulum_rk4_conserves_energy_on_its_hinges),
        cmocka_unit_test(test_ball_chain_released_horizontally_keeps_its_energy),
        cmocka_unit_test(test_heavy_body_on_light_chain_does_not_stretch_it),
        cmocka_unit_test(test_four_bar_linkage_does_not_drift_off_its_joints),
        cmocka_unit_test(test_fixed_joint_moves_as_one_body_of_combined_mass),
        cmocka_unit_test(test_slider_on_incline_accelerates_at_g_sin_angle),
        cmocka_unit_test(test_ball_pendulum_small_angle_period),
        cmocka_unit_test(test_pendulum_on_accelerating_keyframed_support),
        cmocka_unit_test(test_cantilever_reaction_is_statics),
        cmocka_unit_test(test_static_wall_feels_the_cantilever_it_holds),
        cmocka_unit_test(test_jointed_bodies_do_not_fall_asleep_apart),
        cmocka_unit_test(test_pendulum_bounces_off_the_ground_on_its_joint),
        cmocka_unit_test(test_soft_joint_is_a_damped_spring_at_the_body_mass),
        cmocka_unit_test(test_joint_breaks_when_its_reaction_passes_the_limit),
        cmocka_unit_test(test_free_ring_keeps_momentum_angular_momentum_and_energy),
        cmocka_unit_test(test_conserved_says_what_joints_keep),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
